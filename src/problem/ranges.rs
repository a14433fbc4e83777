//! The allowed range of every input-file key, as written in error messages, and the fixed
//! lengths of array keys.
//!
//! TOML type errors (a string for a number, `elements = -5` for an unsigned integer) come from
//! the deserializer, which knows only the Rust type; [`allowed`] adds the key's range so every
//! error says what would be accepted. [`FIXED_LENGTHS`] lists the arrays whose length is
//! fixed: the deserializer reads the first `n` elements of a longer array and ignores the
//! rest, so `check_lengths` rejects any other length.

use super::{key_line, ProblemError};
use std::path::Path;

/// `(dotted key, allowed values)` of problem, study and phase files. (Enumerations such as
/// `solver.integrator` are left out where serde's message already lists the variants; a new
/// key without an entry gets toml's message alone.)
const ALLOWED: &[(&str, &str)] = &[
    ("rod.length", "a finite number > 0 (m)"),
    ("rod.diameter", "a finite number > 0 and < rod.length (m)"),
    ("rod.elements", "an integer in [2, 100000]"),
    ("rod.density", "a finite number > 0 (kg/m^3)"),
    ("rod.bending_stiffness", "a finite number > 0 (N m^2)"),
    ("rod.twist_stiffness", "a finite number > 0 (N m^2)"),
    ("rod.stretch_stiffness", "a finite number > 0 (N)"),
    ("rod.clamp", "\"none\", \"head\" or \"tail\""),
    (
        "rod.natural_curvature",
        "an array of 2 finite numbers (1/m)",
    ),
    ("rod.natural_twist", "a finite number (rad/m)"),
    ("initial.shape", "\"straight\""),
    ("initial.velocity", "an array of 3 finite numbers (m/s)"),
    (
        "initial.angular_velocity",
        "an array of 3 finite numbers (rad/s)",
    ),
    ("initial.heading_deg", "a finite number (degrees)"),
    ("initial.height", "a finite number >= 0 (m)"),
    ("gravity.g", "a finite number >= 0 (m/s^2)"),
    ("time.mode", "\"dynamic\" or \"static\""),
    ("time.dt", "a finite number > 0, at most time.duration (s)"),
    ("time.duration", "a finite number > 0 (s)"),
    ("time.load_steps", "an integer in [1, 10000]"),
    ("time.adaptive", "true or false (false in static mode)"),
    (
        "time.error_tolerance",
        "a number in [1e-12, 0.1] (fraction of rod.length per step), with time.adaptive = true",
    ),
    ("time.dt_max", "a number in [time.dt, time.duration] (s), with time.adaptive = true"),
    ("time.dt_min", "a number in (0, time.dt] (s), with time.adaptive = true"),
    ("output.interval", "a finite number > 0 (s)"),
    ("accuracy.target", "a number in [1e-4, 0.5] (relative error of v_s/v_m)"),
    ("accuracy.max_elements", "an integer in [rod.elements, 100000]"),
    ("solver.tolerance", "a number in (0, 0.001]"),
    ("solver.max_iterations", "an integer in [1, 10000]"),
    ("solver.max_halvings", "an integer in [0, 30]"),
    ("solver.contact", "\"active-set\" or \"conic\""),
    ("solver.max_backtracks", "an integer in [1, 200]"),
    ("solver.armijo", "a number in (0, 0.5)"),
    ("solver.line_search_noise", "a number in [0, 1e-6]"),
    ("solver.shift", "a number in (0, 1e-2]"),
    ("solver.shift_tries", "an integer in [1, 30]"),
    ("solver.active_set_max_iterations", "an integer in [1, 10000]"),
    ("solver.active_set_extra_switches", "an integer in [0, 10000]"),
    ("solver.warm_conic_iterations", "an integer in [1, 10000]"),
    ("solver.normal_force_tolerance", "a number in (0, 1] (fraction of W / n_c)"),
    ("solver.contact_tolerance", "a number in (0, 1e-3] (fraction of a)"),
    ("solver.contact_force_tolerance", "a number in (0, 1e-3] (fraction of W / n_c)"),
    ("solver.conic_tolerance", "a number in (0, 1e-4]"),
    ("solver.conic_max_iterations", "an integer in [1, 10000]"),
    ("solver.clarabel_method", "\"qdldl\" or \"faer\""),
    ("ground.mu_forward", "a finite number >= 0"),
    ("ground.mu_backward", "a finite number >= 0"),
    ("ground.mu_sideways", "a finite number >= 0"),
    ("ground.incline_deg", "a number in (-90, 90) (degrees)"),
    (
        "gait.kind",
        "\"none\", \"s-start\", \"sidewinding\" or \"serpenoid\"",
    ),
    ("gait.stress", "a finite number >= 0 (Pa)"),
    (
        "gait.sigma",
        "a number in (0, 1], for s-start and sidewinding at least one element length 1/rod.elements (fraction of rod.length)",
    ),
    ("gait.speed", "a finite number > 0 (m/s)"),
    (
        "gait.centers",
        "an array of 3 numbers in [0, 1] (fractions of rod.length)",
    ),
    ("gait.scales", "an array of 3 finite numbers"),
    ("gait.period", "a finite number > 0 (s)"),
    ("gait.ramp", "a number in [0, 1] (fraction of L / v_m)"),
    (
        "gait.wavelength",
        "a finite number > 0 (fraction of rod.length)",
    ),
    (
        "study.base",
        "a path (string) to a problem file, relative to the study file",
    ),
    (
        "study.max_evaluations",
        "an integer in [n + 1, 100000] for n optimised parameters",
    ),
    (
        "study.duration_pulses",
        "a number in (0, 1000] (pulse times L / v_m)",
    ),
    (
        "study.initial_step",
        "a number in (0, 1] (fraction of each bound's width)",
    ),
    ("study.tolerance", "a finite number >= 0 (m/s)"),
    ("study.penalty", "a finite number >= 0 (m/s)"),
    ("study.max_heading_deg", "a number in (0, 180] (degrees)"),
    ("optimize.stress", "[lo, hi] with 0 <= lo < hi, finite (Pa)"),
    (
        "optimize.sigma",
        "[lo, hi] with 0 < lo < hi <= 1, lo >= 1/rod.elements for s-start and sidewinding (fraction of rod.length)",
    ),
    ("optimize.speed", "[lo, hi] with 0 < lo < hi, finite (m/s)"),
    (
        "optimize.initial.stress",
        "a number within optimize.stress (Pa)",
    ),
    (
        "optimize.initial.sigma",
        "a number within optimize.sigma (fraction of rod.length)",
    ),
    (
        "optimize.initial.speed",
        "a number within optimize.speed (m/s)",
    ),
    (
        "phase.base",
        "a path (string) to a problem file, relative to the phase file",
    ),
    (
        "phase.weight",
        "a non-empty array of scaled weights W > 0, strictly increasing, or { from, to, count, spacing }",
    ),
    (
        "phase.torque",
        "a non-empty array of scaled torques G >= 0, strictly increasing, or { from, to, count, spacing }",
    ),
];

/// The allowed values of a dotted key, if it is one of the documented keys.
pub fn allowed(key: &str) -> Option<&'static str> {
    ALLOWED.iter().find(|(k, _)| *k == key).map(|(_, a)| *a)
}

/// `(table, key, length)` of every fixed-length array in problem and study files.
pub const FIXED_LENGTHS: &[(&str, &str, usize)] = &[
    ("rod", "natural_curvature", 2),
    ("initial", "velocity", 3),
    ("initial", "angular_velocity", 3),
    ("gait", "centers", 3),
    ("gait", "scales", 3),
    ("optimize", "stress", 2),
    ("optimize", "sigma", 2),
    ("optimize", "speed", 2),
];

/// Reject an array key of [`FIXED_LENGTHS`] whose length differs (the text has already
/// deserialized, so it is valid TOML).
pub(crate) fn check_lengths(text: &str, path: &Path) -> Result<(), ProblemError> {
    let Ok(doc) = text.parse::<toml::Table>() else {
        return Ok(());
    };
    for &(table, key, n) in FIXED_LENGTHS {
        let Some(toml::Value::Array(a)) = doc
            .get(table)
            .and_then(|t| t.as_table())
            .and_then(|t| t.get(key))
        else {
            continue;
        };
        if a.len() != n {
            let dotted = format!("{table}.{key}");
            let what = allowed(&dotted).unwrap_or("an array of the documented length");
            return Err(ProblemError::Invalid {
                file: path.into(),
                line: key_line(text, table, key),
                key: dotted,
                value: format!("an array of {} elements", a.len()),
                allowed: format!("{what}: exactly {n} elements"),
            });
        }
    }
    Ok(())
}
