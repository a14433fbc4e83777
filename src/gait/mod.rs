//! Muscles as time-dependent natural strains (MODEL 1.2 and 4).
//!
//! The internal moment is `M = B kappa + m` with the muscle couple `m(s, t)`; in energy form
//! this is the natural curvature `kappa0 = -m / B`, integrated over each node's Voronoi length,
//! so every step stays a minimisation with a rest shape that moves with time.
//!
//! * **S-start**: three Gaussian couples of magnitude `Gamma a^3 exp(-(s - s0 - v_m t)^2 /
//!   (2 sigma^2))` travelling head to tail at `v_m` relative to the body: about `d2`
//!   (in-plane) at `a` with sign `+` and at `c` with sign `-` (the S), about `d1`
//!   (out-of-plane) at `b` between them. A positive `b` couple bends the body concave-up
//!   about `b` (the Darboux vector gives `dt/ds = -kappa_1 d2 + kappa_2 d1`, so
//!   `kappa0_1 = -m_1/B < 0` curves the tangent toward `+d2`): the middle presses down and
//!   the parts toward `a` and `c` rise. Each couple is scaled by `scales[k]`.
//!   Couples ramp in linearly over `ramp * T`, `T = L / v_m`.
//! * **Sidewinding**: the same triplet launched at the head every `period` seconds, so
//!   several pulses travel at once.
//! * **Serpenoid** (lateral undulation, the peer simulators' continuum snake): an in-plane
//!   couple `Gamma a^3 sin(2 pi (s - v_m t) / lambda)` (wave travelling head to tail),
//!   `lambda = wavelength * L`, ramped in the same way.

use crate::model::Model;

pub use crate::model::Gait;
pub use crate::problem::{GaitSpec, Kind};

/// Time-dependent natural strains (muscle activation enters here, MODEL 1.2).
pub trait Actuation: Send + Sync {
    /// Fill the integrated natural curvature `kappa0[i]` and twist `m0[i]` of every interior
    /// node `i` at time `t`.
    fn rest_strains(&self, t: f64, m: &Model, kappa0: &mut [[f64; 2]], m0: &mut [f64]);
}

/// The rod's own uniform natural curvature and twist from the problem file.
pub struct Natural;

impl Actuation for Natural {
    fn rest_strains(&self, _t: f64, m: &Model, kappa0: &mut [[f64; 2]], m0: &mut [f64]) {
        for i in 1..m.nodes - 1 {
            let l = m.voronoi[i];
            kappa0[i] = [m.natural_curvature[0] * l, m.natural_curvature[1] * l];
            m0[i] = m.natural_twist * l;
        }
    }
}

/// The gait as an [`Actuation`]: natural strains = the rod's own plus `-m/B` from muscles.
pub struct Muscles {
    /// The gait.
    pub gait: Gait,
}

impl Actuation for Muscles {
    fn rest_strains(&self, t: f64, m: &Model, kappa0: &mut [[f64; 2]], m0: &mut [f64]) {
        for i in 1..m.nodes - 1 {
            let l = m.voronoi[i];
            let mm = self.gait.couple_at(m.arc_length(i), t);
            kappa0[i] = [
                (m.natural_curvature[0] - mm[0] / m.bend) * l,
                (m.natural_curvature[1] - mm[1] / m.bend) * l,
            ];
            m0[i] = m.natural_twist * l;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(kind: Kind) -> GaitSpec {
        GaitSpec {
            kind,
            stress: 1000.0,
            sigma: 0.05,
            speed: 0.5,
            centers: [0.2, 0.3, 0.4],
            scales: [1.0, 0.5, 2.0],
            period: 0.4,
            ramp: 0.0,
            wavelength: 0.5,
        }
    }

    #[test]
    fn s_start_couples_are_gaussians_travelling_at_v_m() {
        let g = Gait::new(&spec(Kind::SStart), 2.0, 0.02);
        let gamma = 1000.0 * 0.02f64.powi(3);
        let t = 0.3;
        // Peak of a (in-plane, +) at 0.4 m + 0.15 m; of c (in-plane, -, scale 2) at 0.8 + 0.15.
        let at_a = g.couple_at(0.55, t);
        let at_c = g.couple_at(0.95, t);
        let at_b = g.couple_at(0.75, t);
        assert!((at_a[1] / gamma - 1.0).abs() < 1e-3, "{at_a:?}");
        assert!((at_c[1] / gamma + 2.0).abs() < 1e-3, "{at_c:?}");
        assert!((at_b[0] / gamma - 0.5).abs() < 1e-12, "{at_b:?}");
        // One sigma (0.1 m) away: exp(-1/2).
        assert!((g.couple_at(0.65, t)[0] / gamma - 0.5 * (-0.5f64).exp()).abs() < 1e-12);
    }

    #[test]
    fn sidewinding_launches_a_new_triplet_every_period() {
        let g = Gait::new(&spec(Kind::Sidewinding), 2.0, 0.02);
        let one = Gait::new(&spec(Kind::SStart), 2.0, 0.02);
        // At t = 0.5 two triplets are out: the first moved 0.25 m, the second 0.05 m.
        let s = 0.45;
        let both = g.couple_at(s, 0.5);
        let sum = [
            one.couple_at(s, 0.5)[0] + one.couple_at(s, 0.1)[0],
            one.couple_at(s, 0.5)[1] + one.couple_at(s, 0.1)[1],
        ];
        assert!((both[0] - sum[0]).abs() < 1e-15 && (both[1] - sum[1]).abs() < 1e-15);
    }

    #[test]
    fn serpenoid_is_a_travelling_sine() {
        let g = Gait::new(&spec(Kind::Serpenoid), 1.0, 0.02);
        let gamma = 1000.0 * 0.02f64.powi(3);
        // lambda = 0.5 m; at t = 0.1 s the wave moved 0.05 m: peak at s = 0.125 + 0.05.
        assert!((g.couple_at(0.175, 0.1)[1] / gamma - 1.0).abs() < 1e-12);
        assert_eq!(g.couple_at(0.3, 0.2)[0], 0.0);
    }
}
