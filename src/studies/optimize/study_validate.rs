//! The checks of a study file that go beyond its schema (see [`super::study`]): the base
//! problem, the optimised parameters' bounds and starting point, the durations, the search
//! settings, the objective and the method's sizes, and that the shortest run holds a step.
//! Each error names the key, its line and what is allowed.

use super::*;
use crate::problem::keys::Key;

/// Where a study file's errors point: its text (for line numbers) and path.
pub(super) struct At<'a> {
    pub(super) text: &'a str,
    pub(super) path: &'a Path,
}

impl At<'_> {
    /// `table.key = value` is not allowed: `allowed` says what is.
    pub(super) fn fail(
        &self,
        table: &str,
        key: &str,
        value: String,
        allowed: String,
    ) -> StudyError {
        let top = key.split('.').next().unwrap_or(key);
        StudyError::from(ProblemError::Invalid {
            file: self.path.into(),
            line: key_line(self.text, table, top),
            key: format!("{table}.{key}"),
            value,
            allowed,
        })
    }

    /// A number outside its key's range ([`study_keys`]): the message states the key's
    /// allowed values.
    pub(super) fn real(&self, key: &Key, v: f64) -> Result<f64, StudyError> {
        if key.check_real(v) {
            return Ok(v);
        }
        let (table, name) = key.key.split_once('.').expect("dotted key");
        Err(self.fail(table, name, format!("{v}"), key.allowed()))
    }

    /// The `[optimize]` table is missing or gives no bounds (`value` says which).
    pub(super) fn no_bounds(&self, line: usize, value: &str) -> StudyError {
        StudyError::from(ProblemError::Invalid {
            file: self.path.into(),
            line,
            key: "optimize".into(),
            value: value.into(),
            allowed: OPTIMIZE_ONE_OF.into(),
        })
    }
}

/// The base problem `[study] base` names (relative to the study file, with the command
/// line's settings), which must have a gait and run in dynamic mode; and its path.
pub(super) fn base_problem(
    at: &At,
    s: &StudyTable,
    base_settings: &[&problem::set::Setting],
) -> Result<(PathBuf, Problem), StudyError> {
    let (text, path) = (at.text, at.path);
    let base_path = path.parent().unwrap_or_else(|| Path::new("")).join(&s.base);
    let base = problem::read(&base_path)
        .and_then(|t| problem::parse_with(&t, &base_path, base_settings).map(|(_, p)| p));
    let base = base.map_err(|source| StudyError::Base {
        file: path.into(),
        line: key_line(text, "study", "base"),
        value: s.base.clone(),
        source: Box::new(source),
    })?;
    let base_fail = |allowed: &str| {
        StudyError::from(ProblemError::Invalid {
            file: path.into(),
            line: key_line(text, "study", "base"),
            key: "study.base".into(),
            value: format!("{:?}", s.base),
            allowed: allowed.into(),
        })
    };
    if base.gait.kind == gait::Kind::None {
        return Err(base_fail(
            "a problem whose [gait] kind is \"s-start\", \"sidewinding\" or \"serpenoid\" (there is no gait to optimise)",
        ));
    }
    if base.time.mode != problem::Mode::Dynamic {
        return Err(base_fail("a problem in dynamic mode (a gait needs time)"));
    }
    Ok((base_path, base))
}

/// The optimised parameters: each with bounds in `[optimize]`, its bounds checked against the
/// base and its starting point (`optimize.initial`, else the base's value) inside them.
pub(super) fn dims(
    at: &At,
    opt: &OptimizeTable,
    base: &Problem,
    fixed: &GaitParams,
) -> Result<Vec<Dim>, StudyError> {
    let mut dims = Vec::new();
    for param in Param::ALL {
        let (bounds, initial) = match param {
            Param::Stress => (opt.stress, opt.initial.stress),
            Param::Sigma => (opt.sigma, opt.initial.sigma),
            Param::Speed => (opt.speed, opt.initial.speed),
            Param::Period => (opt.period, opt.initial.period),
            Param::Spacing => (opt.spacing, opt.initial.spacing),
            Param::Lift => (opt.lift, opt.initial.lift),
        };
        let key = param.key();
        let unit = param.unit();
        let Some([lo, hi]) = bounds else {
            if let Some(v) = initial {
                return Err(at.fail(
                    "optimize",
                    &format!("initial.{key}"),
                    format!("{v}"),
                    format!("absent unless optimize.{key} gives bounds ({unit})"),
                ));
            }
            continue;
        };
        if let Err(allowed) = param.check_bounds(base, lo, hi) {
            return Err(at.fail("optimize", key, format!("[{lo}, {hi}]"), allowed));
        }
        let x0 = initial.unwrap_or(param.get(fixed));
        if !(x0 >= lo && x0 <= hi) {
            return Err(match initial {
                Some(v) => at.fail(
                    "optimize",
                    &format!("initial.{key}"),
                    format!("{v}"),
                    format!("in [{lo}, {hi}] ({unit}), the bounds optimize.{key}"),
                ),
                None => at.fail(
                    "optimize",
                    key,
                    format!("[{lo}, {hi}]"),
                    format!(
                        "bounds containing the base file's gait.{key} = {x0} ({unit}), or give optimize.initial.{key}"
                    ),
                ),
            });
        }
        dims.push(Dim {
            param,
            lo,
            hi,
            initial: x0,
        });
    }
    if dims.is_empty() {
        return Err(at.no_bounds(key_line(at.text, "optimize", "stress"), "(no bounds)"));
    }
    Ok(dims)
}

/// Every evaluation's duration: `duration_pulses` (default: the base's duration in pulse
/// times) and, for a sidewinding base, `duration_periods` instead.
pub(super) fn durations(
    at: &At,
    s: &StudyTable,
    base: &Problem,
) -> Result<(f64, Option<f64>), StudyError> {
    let base_duration = base.time.duration.unwrap_or(0.0);
    let duration_pulses = match s.duration_pulses {
        Some(v) => at.real(&study_keys::STUDY_DURATION_PULSES, v)?,
        None => base_duration * base.gait.speed / base.rod.length,
    };
    let duration_periods = match s.duration_periods {
        None => None,
        Some(v) => {
            if s.duration_pulses.is_some() {
                return Err(at.fail(
                    "study",
                    "duration_periods",
                    format!("{v}"),
                    "absent when study.duration_pulses is given (one of the two sets the duration)"
                        .into(),
                ));
            }
            if base.gait.kind != gait::Kind::Sidewinding {
                return Err(at.fail(
                    "study",
                    "duration_periods",
                    format!("{v}"),
                    "absent unless the base's gait is \"sidewinding\" (the only gait with a launch period)".into(),
                ));
            }
            Some(at.real(&study_keys::STUDY_DURATION_PERIODS, v)?)
        }
    };
    Ok((duration_pulses, duration_periods))
}

/// The simplex's settings (`initial_step`, `tolerance`, `penalty`) and the heading limit.
pub(super) fn check_search_settings(at: &At, s: &StudyTable) -> Result<(), StudyError> {
    at.real(&study_keys::STUDY_INITIAL_STEP, s.initial_step)?;
    at.real(&study_keys::STUDY_TOLERANCE, s.tolerance)?;
    at.real(&study_keys::STUDY_PENALTY, s.penalty)?;
    if let Some(h) = s.max_heading_deg {
        at.real(&study_keys::STUDY_MAX_HEADING_DEG, h)?;
    }
    Ok(())
}

/// The objective and its penalties (`turn_penalty`, `stationary_penalty`: broadside only).
pub(super) fn objective(
    at: &At,
    s: &StudyTable,
    base: &Problem,
) -> Result<(Objective, f64, f64), StudyError> {
    let objective = match s.objective.as_deref() {
        None | Some("v_s") => Objective::Vs,
        Some("broadside") => Objective::Broadside,
        Some("sidewinding") => Objective::Sidewinding,
        Some(other) => {
            return Err(at.fail(
                "study",
                "objective",
                format!("{other:?}"),
                study_keys::STUDY_OBJECTIVE.allowed(),
            ))
        }
    };
    if objective != Objective::Vs && base.gait.kind != gait::Kind::Sidewinding {
        let name = s.objective.as_deref().unwrap_or_default();
        return Err(at.fail(
            "study",
            "objective",
            format!("{name:?}"),
            format!("\"v_s\" for a base whose gait is not \"sidewinding\" (the {name} objective is measured per launch period)"),
        ));
    }
    // Both penalties: in range, and only with the broadside objective.
    let penalty = |key: &Key, v: Option<f64>| match v {
        None => Ok(key.real()),
        Some(t) if objective != Objective::Broadside => {
            let (table, name) = key.key.split_once('.').expect("dotted key");
            Err(at.fail(table, name, format!("{t}"), key.allowed()))
        }
        Some(t) => at.real(key, t),
    };
    let turn_penalty = penalty(&study_keys::STUDY_TURN_PENALTY, s.turn_penalty)?;
    let stationary_penalty = penalty(&study_keys::STUDY_STATIONARY_PENALTY, s.stationary_penalty)?;
    Ok((objective, turn_penalty, stationary_penalty))
}

/// The search method's sizes: Nelder-Mead's `starts` (default 1) and the swarm's `particles`
/// (0 for Nelder-Mead), for `n` optimised parameters.
pub(super) fn method_sizes(
    at: &At,
    s: &StudyTable,
    opt: &OptimizeTable,
    n: usize,
) -> Result<(usize, usize), StudyError> {
    let method = opt.method;
    let starts = opt
        .starts
        .unwrap_or(study_keys::OPTIMIZE_STARTS.int() as usize);
    if let Some(k) = opt.starts {
        if method != SearchMethod::NelderMead {
            return Err(at.fail(
                "optimize",
                "starts",
                format!("{k}"),
                "absent with method = \"particle-swarm\" (multi-start is for Nelder-Mead; the swarm sets its size with optimize.particles)".into(),
            ));
        }
        let key = study_keys::OPTIMIZE_STARTS;
        if !key.check_int(k as u64) || s.max_evaluations < k * (n + 1) {
            let (lo, hi) = key.int_range();
            return Err(at.fail(
                "optimize",
                "starts",
                format!("{k}"),
                format!(
                    "an integer in [{lo}, {hi}] with study.max_evaluations = {} >= starts * {} (each start's simplex needs n + 1 = {} evaluations)",
                    s.max_evaluations,
                    n + 1,
                    n + 1
                ),
            ));
        }
    }
    let particles = match (method, opt.particles) {
        (SearchMethod::NelderMead, Some(p)) => {
            return Err(at.fail(
                "optimize",
                "particles",
                format!("{p}"),
                "absent unless method = \"particle-swarm\"".into(),
            ))
        }
        (SearchMethod::NelderMead, None) => 0,
        (SearchMethod::ParticleSwarm, p) => {
            let p = p.unwrap_or(DEFAULT_PARTICLES);
            let key = study_keys::OPTIMIZE_PARTICLES;
            if !key.check_int(p as u64) || p > s.max_evaluations {
                let (lo, hi) = key.int_range();
                return Err(at.fail(
                    "optimize",
                    "particles",
                    format!("{p}"),
                    format!(
                        "an integer in [{lo}, {hi}], at most study.max_evaluations = {} (one generation)",
                        s.max_evaluations
                    ),
                ));
            }
            p
        }
    };
    Ok((starts, particles))
}

/// The shortest run (at the fastest speed, or the shortest period) must hold at least one
/// time step of the base.
pub(super) fn check_shortest_run(at: &At, s: &StudyTable, study: &Study) -> Result<(), StudyError> {
    let fixed = study.space.fixed;
    let bound = |param: Param, upper: bool| {
        let d = study.space.dims.iter().find(|d| d.param == param);
        d.map_or(param.get(&fixed), |d| if upper { d.hi } else { d.lo })
    };
    let mut shortest_point = fixed;
    shortest_point.speed = bound(Param::Speed, true);
    shortest_point.period = bound(Param::Period, false);
    let dt = study.base.time.dt.unwrap_or(0.0);
    let shortest = study.duration(&shortest_point);
    if shortest < dt {
        let (v_max, p_min) = (shortest_point.speed, shortest_point.period);
        let (table, key, value, rule) = match study.duration_periods {
            Some(n) => (
                "study",
                "duration_periods",
                format!("{n}"),
                format!("duration_periods * period = {shortest} s at period = {p_min} s"),
            ),
            None => {
                let rule = format!("duration_pulses * L / v_m = {shortest} s at v_m = {v_max} m/s");
                if s.duration_pulses.is_some() {
                    (
                        "study",
                        "duration_pulses",
                        format!("{}", study.duration_pulses),
                        rule,
                    )
                } else {
                    ("optimize", "speed", format!("{v_max}"), rule)
                }
            }
        };
        return Err(at.fail(
            table,
            key,
            value,
            format!(
                "such that the shortest run, {rule}, is at least the base file's time.dt = {dt} s"
            ),
        ));
    }
    Ok(())
}
