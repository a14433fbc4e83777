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

use crate::integrator::Actuation;
use crate::model::Model;
use serde::Deserialize;

/// Gait kinds.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Kind {
    /// No muscles.
    #[default]
    None,
    /// One travelling triplet.
    SStart,
    /// Triplets launched periodically.
    Sidewinding,
    /// Travelling in-plane sine wave.
    Serpenoid,
}

/// `[gait]`: muscle activation pattern (SI units; positions as fractions of L).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GaitSpec {
    /// "none" (default), "s-start", "sidewinding" or "serpenoid".
    #[serde(default)]
    pub kind: Kind,
    /// Peak muscular stress `Gamma` (Pa); couple magnitude `Gamma a^3`. Default 0, >= 0.
    #[serde(default)]
    pub stress: f64,
    /// Gaussian width `sigma` as a fraction of L. Default 0.05, in (0, 1].
    #[serde(default = "d_sigma")]
    pub sigma: f64,
    /// Travelling speed `v_m` (m/s), head to tail relative to the body. Default 0.5, > 0.
    #[serde(default = "d_speed")]
    pub speed: f64,
    /// Initial positions `s0` of the couples a, b, c as fractions of L. Default [0.15, 0.25, 0.35].
    #[serde(default = "d_centers")]
    pub centers: [f64; 3],
    /// Multipliers of `Gamma a^3` for a, b, c (sign included; a positive b presses the middle
    /// down). Default [1, 1, 1].
    #[serde(default = "d_scales")]
    pub scales: [f64; 3],
    /// Sidewinding: seconds between launched triplets. Default 0.5, > 0.
    #[serde(default = "d_period")]
    pub period: f64,
    /// Linear ramp-in of every couple over `ramp * T`, `T = L / v_m`. Default 0.05, in [0, 1].
    #[serde(default = "d_ramp")]
    pub ramp: f64,
    /// Serpenoid wavelength as a fraction of L. Default 0.5, > 0.
    #[serde(default = "d_wavelength")]
    pub wavelength: f64,
}
fn d_sigma() -> f64 {
    0.05
}
fn d_speed() -> f64 {
    0.5
}
fn d_centers() -> [f64; 3] {
    [0.15, 0.25, 0.35]
}
fn d_scales() -> [f64; 3] {
    [1.0, 1.0, 1.0]
}
fn d_period() -> f64 {
    0.5
}
fn d_ramp() -> f64 {
    0.05
}
fn d_wavelength() -> f64 {
    0.5
}
impl Default for GaitSpec {
    fn default() -> Self {
        GaitSpec {
            kind: Kind::None,
            stress: 0.0,
            sigma: d_sigma(),
            speed: d_speed(),
            centers: d_centers(),
            scales: d_scales(),
            period: d_period(),
            ramp: d_ramp(),
            wavelength: d_wavelength(),
        }
    }
}

/// A compiled gait (SI lengths).
#[derive(Clone, Debug)]
pub struct Gait {
    /// Kind.
    pub kind: Kind,
    /// Couple magnitude `Gamma a^3` (N m).
    pub couple: f64,
    /// Width (m).
    pub sigma: f64,
    /// Speed (m/s).
    pub speed: f64,
    /// Initial centres (m).
    pub centers: [f64; 3],
    /// Scales of a, b, c.
    pub scales: [f64; 3],
    /// Launch period (s).
    pub period: f64,
    /// Ramp time (s).
    pub ramp_time: f64,
    /// Serpenoid wavelength (m).
    pub wavelength: f64,
}

impl Gait {
    /// Compile from a spec and the rod's length and diameter.
    pub fn new(g: &GaitSpec, length: f64, diameter: f64) -> Self {
        Gait {
            kind: g.kind,
            couple: g.stress * diameter.powi(3),
            sigma: g.sigma * length,
            speed: g.speed,
            centers: g.centers.map(|c| c * length),
            scales: g.scales,
            period: g.period,
            ramp_time: g.ramp * length / g.speed,
            wavelength: g.wavelength * length,
        }
    }

    /// Duration of one pulse over the body, `T = L / v_m` (s).
    pub fn pulse_time(&self, length: f64) -> f64 {
        length / self.speed
    }

    fn ramp(&self, t: f64) -> f64 {
        if self.ramp_time <= 0.0 {
            1.0
        } else {
            (t / self.ramp_time).clamp(0.0, 1.0)
        }
    }

    /// Muscle couple `[about d1, about d2]` (N m) at arc length `s` (m) and time `t` (s).
    pub fn couple_at(&self, s: f64, t: f64) -> [f64; 2] {
        let gauss = |c: f64| (-(s - c).powi(2) / (2.0 * self.sigma * self.sigma)).exp();
        let triplet = |shift: f64| -> [f64; 2] {
            let [a, b, c] = self.centers;
            let [ka, kb, kc] = self.scales;
            [
                kb * gauss(b + shift),
                ka * gauss(a + shift) - kc * gauss(c + shift),
            ]
        };
        let m = match self.kind {
            Kind::None => [0.0, 0.0],
            Kind::SStart => {
                let r = self.ramp(t);
                let [m1, m2] = triplet(self.speed * t);
                [r * m1, r * m2]
            }
            Kind::Sidewinding => {
                let mut acc = [0.0, 0.0];
                let launched = (t / self.period).floor().max(0.0) as usize;
                for k in 0..=launched {
                    let tk = t - k as f64 * self.period;
                    let r = self.ramp(tk);
                    let [m1, m2] = triplet(self.speed * tk);
                    acc[0] += r * m1;
                    acc[1] += r * m2;
                }
                acc
            }
            Kind::Serpenoid => {
                let r = self.ramp(t);
                let phase = std::f64::consts::TAU * (s - self.speed * t) / self.wavelength;
                [0.0, r * phase.sin()]
            }
        };
        [self.couple * m[0], self.couple * m[1]]
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
