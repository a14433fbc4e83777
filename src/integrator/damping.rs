//! Kelvin-Voigt rod damping in an implicit step: the strains at the step's start (and the one
//! before, for BDF2), and the blended rest strains and stiffness factor the energy terms take
//! (the derivation is in [`crate::energy`], "Rod damping").

use crate::model::Model;
use crate::rod::frames;
use crate::rod::vec3::V3;
use crate::state::{edge_vec, State};

/// Strains of a configuration: integrated curvature and twist per node (ends unused), length
/// per edge.
#[derive(Clone, Default)]
struct Strains {
    kappa: Vec<[f64; 2]>,
    twist: Vec<f64>,
    len: Vec<f64>,
}

impl Strains {
    fn new(m: &Model) -> Self {
        Strains {
            kappa: vec![[0.0; 2]; m.nodes],
            twist: vec![0.0; m.nodes],
            len: vec![0.0; m.nodes - 1],
        }
    }

    /// The strains of `s.q` in its frozen frames (those of the energy terms at `s.q`).
    fn measure(&mut self, m: &Model, s: &State) {
        for j in 0..m.nodes - 1 {
            let e = edge_vec(&s.q, j);
            self.len[j] = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
        }
        for i in 1..m.nodes - 1 {
            let (e0, e1) = (edge_vec(&s.q, i - 1), edge_vec(&s.q, i));
            let th0 = s.q[crate::rod::dof::edge(i - 1)];
            let th1 = s.q[crate::rod::dof::edge(i)];
            let st = frames::strains::<f64>(&V3(e0), &V3(e1), &th0, &th1, &s.frames[i - 1]);
            self.kappa[i] = st.kappa;
            self.twist[i] = st.twist;
        }
    }
}

/// The damping state of an integrator: strains at the last two step starts, and the step's
/// blended rest strains.
pub(crate) struct RodDamping {
    now: Strains,
    prev: Strains,
    /// Blended natural curvature, twist and rest lengths of the step being solved.
    pub(crate) kappa0: Vec<[f64; 2]>,
    pub(crate) m0: Vec<f64>,
    pub(crate) rest_len: Vec<f64>,
    /// `1 + tau/h'` of the step being solved.
    pub(crate) scale: f64,
}

impl RodDamping {
    /// The damping of `m`, or `None` when its damping time is 0.
    pub(crate) fn of(m: &Model) -> Option<Self> {
        (m.damping_time > 0.0).then(|| RodDamping {
            now: Strains::new(m),
            prev: Strains::new(m),
            kappa0: vec![[0.0; 2]; m.nodes],
            m0: vec![0.0; m.nodes],
            rest_len: m.rest_len.clone(),
            scale: 1.0,
        })
    }

    /// Blend the rest strains `kappa0`, `m0` (at the step's end time) and the model's rest
    /// lengths with the strain origin `c_n e(q_n) + c_p e(q_{n-1})` of a step of effective
    /// size `h_eff`, `s` being the state at the step's start.
    pub(crate) fn begin_step(
        &mut self,
        m: &Model,
        s: &State,
        (c_n, c_p, h_eff): (f64, f64, f64),
        kappa0: &[[f64; 2]],
        m0: &[f64],
    ) {
        self.now.measure(m, s);
        let r = m.damping_time / h_eff;
        let w = 1.0 / (1.0 + r);
        self.scale = 1.0 + r;
        let (now, prev) = (&self.now, &self.prev);
        // Implicit Euler's (1, 0): exactly `a` (the previous strains are finite, zeros at first).
        let origin = |a: f64, b: f64| c_n * a + c_p * b;
        for i in 0..m.nodes {
            for a in 0..2 {
                let o = origin(now.kappa[i][a], prev.kappa[i][a]);
                self.kappa0[i][a] = (kappa0[i][a] + r * o) * w;
            }
            let o = origin(now.twist[i], prev.twist[i]);
            self.m0[i] = (m0[i] + r * o) * w;
        }
        for j in 0..m.nodes - 1 {
            let o = origin(now.len[j], prev.len[j]);
            self.rest_len[j] = (m.rest_len[j] + r * o) * w;
        }
    }

    /// The step is accepted: its start's strains become the previous ones.
    pub(crate) fn commit(&mut self) {
        std::mem::swap(&mut self.now, &mut self.prev);
    }
}
