//! The adaptive part of `[time]`: error-controlled steps ([`Adaptive`]) and its validation.
//!
//! ```toml
//! [time]
//! dt = 2e-3               # the first step (s)
//! duration = 3.572
//! adaptive = true         # default false: fixed steps of dt
//! error_tolerance = 5e-6  # local error per step, fraction of rod.length; default DEFAULT_TOLERANCE
//! dt_max = 0.02           # largest step (s); default: duration / 50 (at least dt)
//! dt_min = 1e-7           # smallest step before the run stops (s); default dt * 1e-4
//! ```
//!
//! The step controller and the meaning of the tolerance are in [`crate::integrator::adaptive`].

use super::{Checker, IntegratorKind, Mode, Problem, ProblemError};

/// Default `[time] error_tolerance` ([`super::keys::TIME_ERROR_TOLERANCE`]): allowed local
/// (one-step) error of any node position, as a fraction of the rod length. Chosen so that the
/// bundled S-start (50 elements, BDF2) lands within 1 % of its converged `v_s/v_m`; the guide's
/// chapter "Speed against accuracy" gives the measurements behind it.
pub const DEFAULT_TOLERANCE: f64 = super::keys::TIME_ERROR_TOLERANCE.real();

/// Smallest allowed step by default, as a fraction of the first step `dt`.
pub const DEFAULT_DT_MIN_FRACTION: f64 = 1e-4;

/// Default `[time] dt_max`: `duration / 50`, at least `dt`. It used to be the output interval,
/// which made the physics of an adaptive run depend on how often frames are stored; it is now
/// set by the duration alone. Adaptive steps also land on the frame times, so no step exceeds
/// the output interval either: wherever the interval is at most `duration / 50` (the bundled
/// S-start, 0.036 s against 0.071 s; the cantilever swing, 0.01 s against 0.01 s) the steps
/// are exactly those of the old default.
pub fn default_dt_max(dt: f64, duration: f64) -> f64 {
    (duration / 50.0).max(dt)
}

/// The error-controlled step settings of a problem (`[time] adaptive = true`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Adaptive {
    /// Allowed local error per step, fraction of the rod length (`error_tolerance`).
    pub tolerance: f64,
    /// First step (s) (`dt`).
    pub dt_first: f64,
    /// Smallest step (s): a step that must shrink below it stops the run (`dt_min`).
    pub dt_min: f64,
    /// Largest step (s) (`dt_max`).
    pub dt_max: f64,
}

impl Adaptive {
    /// The settings of a validated problem, `None` for fixed steps.
    pub fn of(p: &Problem) -> Option<Self> {
        let t = &p.time;
        if !t.adaptive || t.mode != Mode::Dynamic {
            return None;
        }
        let dt = t.dt?;
        let duration = t.duration?;
        Some(Adaptive {
            tolerance: t.error_tolerance.unwrap_or(DEFAULT_TOLERANCE),
            dt_first: dt,
            dt_min: t.dt_min.unwrap_or(dt * DEFAULT_DT_MIN_FRACTION),
            dt_max: t.dt_max.unwrap_or_else(|| default_dt_max(dt, duration)),
        })
    }
}

/// Range checks of the adaptive keys (after `dt` and `duration` are checked).
pub(super) fn check(p: &Problem, c: &Checker) -> Result<(), ProblemError> {
    let t = &p.time;
    if !t.adaptive {
        for (key, v) in [
            ("error_tolerance", t.error_tolerance),
            ("dt_max", t.dt_max),
            ("dt_min", t.dt_min),
        ] {
            if let Some(v) = v {
                return Err(c.fail(
                    "time",
                    key,
                    super::num(v),
                    "given only with time.adaptive = true (fixed steps use time.dt)",
                ));
            }
        }
        return Ok(());
    }
    if t.mode == Mode::Static {
        return Err(c.fail(
            "time",
            "adaptive",
            "true".into(),
            "false in static mode (adaptive steps are a time integration setting)",
        ));
    }
    if p.solver.integrator == IntegratorKind::VelocityVerlet {
        return Err(c.fail(
            "solver",
            "integrator",
            "\"explicit\"".into(),
            "\"implicit\" or \"bdf2\" with time.adaptive = true (the explicit reference has no error estimate)",
        ));
    }
    if let Some(tol) = t.error_tolerance {
        c.key(&super::keys::TIME_ERROR_TOLERANCE, tol)?;
    }
    let (dt, duration) = (t.dt.unwrap_or(f64::NAN), t.duration.unwrap_or(f64::NAN));
    if let Some(v) = t.dt_max {
        if !(v.is_finite() && v >= dt && v <= duration) {
            return Err(c.fail(
                "time",
                "dt_max",
                super::num(v),
                &format!("in [time.dt, time.duration] = [{dt}, {duration}] (s)"),
            ));
        }
    }
    if let Some(v) = t.dt_min {
        if !(v.is_finite() && v > 0.0 && v <= dt) {
            return Err(c.fail(
                "time",
                "dt_min",
                super::num(v),
                &format!("in (0, time.dt] = (0, {dt}] (s)"),
            ));
        }
    }
    Ok(())
}
