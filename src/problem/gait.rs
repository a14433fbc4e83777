//! `[gait]`: the muscle activation pattern as written in a problem file (SI units; positions
//! as fractions of L). Compiled into [`crate::model::Gait`]; the physics is in [`crate::gait`].

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
