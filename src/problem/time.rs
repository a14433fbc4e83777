//! The adaptive part of `[time]`: error-controlled steps ([`Adaptive`]) and its validation.
//!
//! ```toml
//! [time]
//! dt = 2e-3               # the first step (s)
//! duration = 3.572
//! adaptive = true         # default false: fixed steps of dt
//! error_tolerance = 5e-6  # local error per step, fraction of rod.length; default DEFAULT_TOLERANCE
//! dt_max = 0.02           # largest step (s); default: the output interval
//! dt_min = 1e-7           # smallest step before the run stops (s); default dt * 1e-4
//! ```
//!
//! The step controller and the meaning of the tolerance are in [`crate::integrator::adaptive`].

use super::{Checker, IntegratorKind, Mode, Problem, ProblemError};

/// Default `[time] error_tolerance`: allowed local (one-step) error of any node position, as a
/// fraction of the rod length. Chosen so that the bundled S-start (50 elements, BDF2) lands
/// within 1 % of its converged `v_s/v_m` (0.30829, implicit Euler at 3.125e-5 s): six runs
/// with `mu_forward` perturbed by up to 5e-6 relative give -0.16 % to +0.02 % (3752 to 3802
/// steps). Looser tolerances are off by more since landings are inelastic in BDF2
/// ([`crate::integrator::bdf2`]): 7e-6 +1.1 %, 1e-5 +1.2 to +1.4 %, 3e-5 +3.0 %, 1e-4 +2.8 %;
/// 4e-6 -0.19 to +0.32 %; from 3e-6 down the runs scatter (-1.2 to +0.1 % at 3e-6) as
/// fixed-step runs do at fine steps (README, section "Time stepping").
pub const DEFAULT_TOLERANCE: f64 = 5e-6;

/// Smallest allowed step by default, as a fraction of the first step `dt`.
pub const DEFAULT_DT_MIN_FRACTION: f64 = 1e-4;

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
            dt_max: t
                .dt_max
                .unwrap_or_else(|| p.output.interval.unwrap_or(duration / 100.0).max(dt)),
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
                    format!("{v}"),
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
    if p.solver.integrator == IntegratorKind::Explicit {
        return Err(c.fail(
            "solver",
            "integrator",
            "\"explicit\"".into(),
            "\"implicit\" or \"bdf2\" with time.adaptive = true (the explicit reference has no error estimate)",
        ));
    }
    if let Some(tol) = t.error_tolerance {
        if !(tol.is_finite() && (1e-12..=0.1).contains(&tol)) {
            return Err(c.fail(
                "time",
                "error_tolerance",
                format!("{tol}"),
                "in [1e-12, 0.1] (fraction of rod.length per step)",
            ));
        }
    }
    let (dt, duration) = (t.dt.unwrap_or(f64::NAN), t.duration.unwrap_or(f64::NAN));
    if let Some(v) = t.dt_max {
        if !(v.is_finite() && v >= dt && v <= duration) {
            return Err(c.fail(
                "time",
                "dt_max",
                format!("{v}"),
                &format!("in [time.dt, time.duration] = [{dt}, {duration}] (s)"),
            ));
        }
    }
    if let Some(v) = t.dt_min {
        if !(v.is_finite() && v > 0.0 && v <= dt) {
            return Err(c.fail(
                "time",
                "dt_min",
                format!("{v}"),
                &format!("in (0, time.dt] = (0, {dt}] (s)"),
            ));
        }
    }
    Ok(())
}
