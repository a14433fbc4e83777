//! The compiled gait: muscle couples `m(s, t)` in SI units (MODEL 4). The problem-file schema is
//! [`crate::problem::GaitSpec`]; the couples become natural strains in [`crate::gait`].

use crate::problem::{GaitSpec, Kind};

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
