//! `[gait]`: the muscle activation pattern as written in a problem file (SI units; positions
//! as fractions of L). Compiled into [`crate::model::Gait`]; the physics is in [`crate::gait`].

use super::keys;
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

impl Kind {
    /// Whether the gait repeats with a launch period (`gait.period`): sidewinding. Its runs
    /// are measured cycle by cycle ([`crate::observe::periodic`]).
    pub fn has_launch_period(self) -> bool {
        self == Kind::Sidewinding
    }
}

/// `[gait]`: muscle activation pattern (SI units; positions as fractions of L). Defaults and
/// ranges of every field: the `GAIT_*` keys of [`keys`].
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct GaitSpec {
    /// "none" (default), "s-start", "sidewinding" or "serpenoid".
    #[serde(default)]
    pub kind: Kind,
    /// Peak muscular stress `Gamma` (Pa); couple magnitude `Gamma a^3` ([`keys::GAIT_STRESS`]).
    #[serde(default = "d_stress")]
    pub stress: f64,
    /// Gaussian width `sigma` as a fraction of L ([`keys::GAIT_SIGMA`]).
    #[serde(default = "d_sigma")]
    pub sigma: f64,
    /// Travelling speed `v_m` (m/s), head to tail relative to the body ([`keys::GAIT_SPEED`]).
    #[serde(default = "d_speed")]
    pub speed: f64,
    /// Initial positions `s0` of the couples a, b, c as fractions of L ([`keys::GAIT_CENTERS`]).
    #[serde(default = "d_centers")]
    pub centers: [f64; 3],
    /// Multipliers of `Gamma a^3` for a, b, c (sign included; a positive b presses the middle
    /// down) ([`keys::GAIT_SCALES`]).
    #[serde(default = "d_scales")]
    pub scales: [f64; 3],
    /// Sidewinding: seconds between launched triplets ([`keys::GAIT_PERIOD`]).
    #[serde(default = "d_period")]
    pub period: f64,
    /// Linear ramp-in of every couple over `ramp * T`, `T = L / v_m` ([`keys::GAIT_RAMP`]).
    #[serde(default = "d_ramp")]
    pub ramp: f64,
    /// Serpenoid wavelength as a fraction of L ([`keys::GAIT_WAVELENGTH`]).
    #[serde(default = "d_wavelength")]
    pub wavelength: f64,
}
fn d_stress() -> f64 {
    keys::GAIT_STRESS.real()
}
fn d_sigma() -> f64 {
    keys::GAIT_SIGMA.real()
}
fn d_speed() -> f64 {
    keys::GAIT_SPEED.real()
}
fn d_centers() -> [f64; 3] {
    keys::GAIT_CENTERS.reals3()
}
fn d_scales() -> [f64; 3] {
    keys::GAIT_SCALES.reals3()
}
fn d_period() -> f64 {
    keys::GAIT_PERIOD.real()
}
fn d_ramp() -> f64 {
    keys::GAIT_RAMP.real()
}
fn d_wavelength() -> f64 {
    keys::GAIT_WAVELENGTH.real()
}
impl Default for GaitSpec {
    fn default() -> Self {
        GaitSpec {
            kind: Kind::None,
            stress: d_stress(),
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
