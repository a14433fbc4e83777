//! The mutable [`State`] of a rod: time, coordinates, velocities and the time-parallel
//! reference frames (one tangent and reference director per edge, one reference twist per
//! interior node), kept apart from the immutable [`Model`].

use crate::model::Model;
use crate::rod::frames::{self, StencilFrame};
use crate::rod::{dof, vec3::f, V3};

/// Rod state at one instant.
#[derive(Clone, Debug)]
pub struct State {
    /// Time (s).
    pub t: f64,
    /// Coordinates `q` (see [`crate::rod::dof`]).
    pub q: Vec<f64>,
    /// Velocities `dq/dt`.
    pub v: Vec<f64>,
    /// Unit tangent of each edge for the current `q`.
    pub tangent: Vec<[f64; 3]>,
    /// Reference director `a1` of each edge, perpendicular to its tangent.
    pub a1: Vec<[f64; 3]>,
    /// Frozen stencil frames, node `i` at index `i - 1`.
    pub frames: Vec<StencilFrame>,
}

impl State {
    /// Initial state of a model.
    pub fn initial(m: &Model) -> Self {
        let ne = m.nodes - 1;
        let tangent: Vec<[f64; 3]> = (0..ne).map(|j| f::unit(edge_vec(&m.q0, j))).collect();
        let a1 = m.a1_0.clone();
        let mut s = State {
            t: 0.0,
            q: m.q0.clone(),
            v: m.v0.clone(),
            tangent,
            a1,
            frames: Vec::new(),
        };
        s.frames = (1..ne).map(|i| s.stencil(i, 0.0)).collect();
        let tw: Vec<f64> = (1..ne)
            .map(|i| frames::ref_twist(edge_vec(&s.q, i - 1), edge_vec(&s.q, i), &s.frames[i - 1]))
            .collect();
        for (k, r) in tw.into_iter().enumerate() {
            s.frames[k].ref_twist_prev = r;
        }
        s
    }

    fn stencil(&self, i: usize, ref_twist_prev: f64) -> StencilFrame {
        StencilFrame {
            t_old: [self.tangent[i - 1], self.tangent[i]],
            a1_old: [self.a1[i - 1], self.a1[i]],
            ref_twist_prev,
        }
    }

    /// Carry the reference frames to the current `q` (parallel transport in time) and store
    /// the new reference twists. The material frames are unchanged by this re-basing.
    pub fn update_frames(&mut self) {
        let ne = self.tangent.len();
        let tw: Vec<f64> = (1..ne)
            .map(|i| {
                frames::ref_twist(
                    edge_vec(&self.q, i - 1),
                    edge_vec(&self.q, i),
                    &self.frames[i - 1],
                )
            })
            .collect();
        for j in 0..ne {
            let t = f::unit(edge_vec(&self.q, j));
            let a = f::transport(self.tangent[j], t, self.a1[j]);
            let a = f::unit(f::sub(a, f::scale(t, f::dot(a, t))));
            self.tangent[j] = t;
            self.a1[j] = a;
        }
        for i in 1..ne {
            self.frames[i - 1] = self.stencil(i, tw[i - 1]);
        }
    }

    /// Position of node `i`.
    pub fn node(&self, i: usize) -> [f64; 3] {
        let k = dof::node(i);
        [self.q[k], self.q[k + 1], self.q[k + 2]]
    }

    /// Velocity of node `i`.
    pub fn node_velocity(&self, i: usize) -> [f64; 3] {
        let k = dof::node(i);
        [self.v[k], self.v[k + 1], self.v[k + 2]]
    }

    /// Material directors `(d1, d2)` of edge `j` at the current `q` (reference frame carried
    /// to the current tangent, then rotated by `theta^j`).
    pub fn directors(&self, j: usize) -> ([f64; 3], [f64; 3]) {
        let t = f::unit(edge_vec(&self.q, j));
        let a = f::transport(self.tangent[j], t, self.a1[j]);
        let (d1, d2) = frames::material(&V3(t), &V3(a), &self.q[dof::edge(j)]);
        (d1.0, d2.0)
    }

    /// Largest |strain| `|e|/l0 - 1` over the real edges.
    pub fn max_strain(&self, m: &Model) -> f64 {
        m.real_edges()
            .map(|j| (f::norm(edge_vec(&self.q, j)) / m.rest_len[j] - 1.0).abs())
            .fold(0.0, f64::max)
    }

    /// Kinetic energy `1/2 v^T M v` (J).
    pub fn kinetic_energy(&self, m: &Model) -> f64 {
        0.5 * self
            .v
            .iter()
            .zip(&m.mass)
            .map(|(v, mm)| mm * v * v)
            .sum::<f64>()
    }

    /// Linear momentum of the nodes (kg m/s).
    pub fn momentum(&self, m: &Model) -> [f64; 3] {
        let mut p = [0.0; 3];
        for i in 0..m.nodes {
            for c in 0..3 {
                p[c] += m.mass[dof::node(i) + c] * self.v[dof::node(i) + c];
            }
        }
        p
    }

    /// Centroid of the real nodes (m), mass-weighted.
    pub fn centroid(&self, m: &Model) -> [f64; 3] {
        let mut c = [0.0; 3];
        let mut tot = 0.0;
        for i in m.real.clone() {
            let w = m.mass[dof::node(i)].max(1e-300);
            c = f::add(c, f::scale(self.node(i), w));
            tot += w;
        }
        f::scale(c, 1.0 / tot)
    }
}

/// Edge vector `e^j = x_{j+1} - x_j` from coordinates.
pub fn edge_vec(q: &[f64], j: usize) -> [f64; 3] {
    let a = dof::node(j);
    let b = dof::node(j + 1);
    [q[b] - q[a], q[b + 1] - q[a + 1], q[b + 2] - q[a + 2]]
}
