//! The growth law of a phase study's growth line (`[phase] growth = { ... }`,
//! [`super::growth`]): the sizes, their muscle stress, their scaled weight and torque, and the
//! grown snake itself in SI units.
use crate::problem::Problem;
use serde::{Deserialize, Serialize};

/// Moon (2007): a snake's muscle stress at [`MOON_REFERENCE`], in Pa (7.72 kPa).
pub const MOON_STRESS: f64 = 7720.0;
/// The diameter (m) at which [`MOON_STRESS`] holds: 1 cm.
pub const MOON_REFERENCE: f64 = 0.01;
/// Moon (2007): the exponent of the muscle stress in the diameter.
pub const MOON_EXPONENT: f64 = 1.39;
/// Most sizes on a growth line.
pub const MAX_SIZES: usize = 200;

/// `[phase] growth = { diameters, stress, reference_diameter, exponent }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Growth {
    /// The diameters `a` (m), increasing.
    pub diameters: Vec<f64>,
    /// Muscle stress (Pa) at `reference_diameter`.
    pub stress: f64,
    /// The diameter (m) at which `stress` holds.
    pub reference_diameter: f64,
    /// `Gamma(a) = stress (a / reference_diameter)^exponent`.
    pub exponent: f64,
}

/// The table as written (checked by [`parse`]).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct GrowthTable {
    diameters: toml::Value,
    stress: Option<f64>,
    reference_diameter: Option<f64>,
    exponent: Option<f64>,
}

/// Validate a `growth` table: `Err((value, allowed))` for the message of `phase.growth`.
pub(super) fn parse(
    t: &GrowthTable,
    axis: impl Fn(&toml::Value) -> Result<Vec<f64>, String>,
) -> Result<Growth, (String, String)> {
    let diameters = axis(&t.diameters).map_err(|why| {
        (
            format!("{{ diameters = {} }}", t.diameters),
            format!("diameters (m) a list or {{ from, to, count, spacing }}: {why}"),
        )
    })?;
    let ok = !diameters.is_empty()
        && diameters.len() <= MAX_SIZES
        && diameters.iter().all(|&a| a.is_finite() && a > 0.0)
        && diameters.windows(2).all(|w| w[1] > w[0]);
    if !ok {
        return Err((
            format!("{{ diameters = {diameters:?} }}"),
            format!("diameters (m): 1 to {MAX_SIZES} values > 0, strictly increasing"),
        ));
    }
    let g = Growth {
        diameters,
        stress: t.stress.unwrap_or(MOON_STRESS),
        reference_diameter: t.reference_diameter.unwrap_or(MOON_REFERENCE),
        exponent: t.exponent.unwrap_or(MOON_EXPONENT),
    };
    let checks = [
        (
            "stress",
            g.stress,
            g.stress > 0.0,
            "stress (Pa) finite and > 0",
        ),
        (
            "reference_diameter",
            g.reference_diameter,
            g.reference_diameter > 0.0,
            "reference_diameter (m) finite and > 0",
        ),
        (
            "exponent",
            g.exponent,
            g.exponent.abs() <= 10.0,
            "exponent in [-10, 10]",
        ),
    ];
    for (key, v, fine, allowed) in checks {
        if !(v.is_finite() && fine) {
            return Err((format!("{{ {key} = {v} }}"), allowed.to_string()));
        }
    }
    Ok(g)
}

/// One size on the line.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct GrowthPoint {
    /// Diameter `a` (m).
    pub diameter: f64,
    /// Length `L` (m): the base's `L/a` times `a`.
    pub length: f64,
    /// Muscle stress `Gamma(a)` (Pa).
    pub stress: f64,
    /// Scaled weight `W`.
    pub weight: f64,
    /// Scaled torque `G`.
    pub torque: f64,
}

impl Growth {
    /// The muscle stress `Gamma(a)` (Pa) of diameter `a` (m).
    pub fn muscle_stress(&self, a: f64) -> f64 {
        self.stress * (a / self.reference_diameter).powf(self.exponent)
    }

    /// Young's modulus (Pa) of the base: `E = 64 B / (pi a^4)` (a solid circular section).
    pub fn young_modulus(base: &Problem) -> f64 {
        64.0 * base.rod.bending_stiffness / (std::f64::consts::PI * base.rod.diameter.powi(4))
    }

    /// The line's sizes with their `W` and `G` (`W` grows like `a`, `G` like `Gamma(a)`).
    pub fn points(&self, base: &Problem) -> Vec<GrowthPoint> {
        let r = &base.rod;
        let w0 = r.density * base.gravity.g * r.diameter.powi(2) * r.length.powi(3)
            / r.bending_stiffness;
        let g0 = base.gait.stress * r.diameter.powi(3) * r.length / r.bending_stiffness;
        self.diameters
            .iter()
            .map(|&a| {
                let s = a / r.diameter;
                let stress = self.muscle_stress(a);
                GrowthPoint {
                    diameter: a,
                    length: r.length * s,
                    stress,
                    weight: w0 * s,
                    torque: g0 * stress / base.gait.stress,
                }
            })
            .collect()
    }
}

/// The snake of diameter `a` itself, in SI units: the base grown by `s = a / a0` (length,
/// diameter; `B`, `C` like `s^4`, `EA` like `s^2`; the step, duration, output interval and
/// step bounds like `s`, the pulse time `L / v_m`), muscle stress `Gamma(a)`, everything else
/// the base's. Simulating it gives the same dimensionless motion as the line's cell
/// ([`PROTOCOL`]); the line is simulated through the cell.
pub fn grown_problem(base: &Problem, growth: &Growth, a: f64) -> Problem {
    let s = a / base.rod.diameter;
    let mut p = base.clone();
    p.rod.length *= s;
    p.rod.diameter = a;
    p.rod.bending_stiffness *= s.powi(4);
    p.rod.twist_stiffness = p.rod.twist_stiffness.map(|c| c * s.powi(4));
    p.rod.stretch_stiffness = p.rod.stretch_stiffness.map(|ea| ea * s * s);
    p.gait.stress = growth.muscle_stress(a);
    scale_times(&mut p, s);
    p
}

/// Multiply a problem's times by `k`: the duration, the step and its adaptive bounds, and the
/// output interval (a run that follows a pulse time scaled by `k`).
pub fn scale_times(p: &mut Problem, k: f64) {
    let t = &mut p.time;
    t.duration = t.duration.map(|d| d * k);
    t.dt = t.dt.map(|d| d * k);
    t.dt_max = t.dt_max.map(|d| d * k);
    t.dt_min = t.dt_min.map(|d| d * k);
    p.output.interval = p.output.interval.map(|i| i * k);
}
