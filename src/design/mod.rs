//! Gait design, the outer loop (MODEL section 7): maximise the averaged forward speed `v_s` over
//! the muscle stress `Gamma` (`gait.stress`, Pa), the couple width `sigma` (`gait.sigma`,
//! fraction of L) and the travelling speed `v_m` (`gait.speed`, m/s), every evaluation one full
//! simulation of a base problem with those values substituted.
//!
//! The loop is argmin's: a [`CostFunction`] (the simulator, [`Evaluator`]), a solver
//! (Nelder-Mead, wrapped to stop at the evaluation budget) and an [`Executor`] that owns
//! termination; an argmin observer records the simplex's best vertex after every iteration.
//! The history must survive an interrupted study, so it is written by the evaluator itself,
//! one flushed CSV row per simulation, rather than by an argmin observer (which sees iterations,
//! not evaluations); progress goes to an [`EvaluationObserver`].
//!
//! # The search space
//!
//! Each optimised parameter `x_i` with bounds `[lo_i, hi_i]` is mapped to `u_i = (x_i - lo_i) /
//! (hi_i - lo_i)`, so Nelder-Mead works on the unit cube. A vertex outside the cube is
//! **clamped and penalised**: the simulation runs at the nearest point of the cube (the clamped
//! physical values, so no parameter ever leaves its bounds) and the cost is
//!
//! ```text
//! f(u) = -v_s(clamp(u)) + penalty * |u - clamp(u)|        (m/s)
//! ```
//!
//! which keeps the simplex from drifting out along a flat plateau. With `max_heading_deg`, a
//! finished run whose net displacement lies further than that off the initial head direction
//! adds `penalty * (angle - max_heading_deg) / 90` and is never reported as the optimum. A simulation that fails
//! (a rejected step, an unstable integrator, a non-finite speed, a panic) is recorded with
//! status `failed` and costs [`FAILED_COST`], worse than any finished run. Parameters without
//! bounds keep the base problem's value.
//!
//! The duration follows the pulse time: every evaluation runs `duration_pulses * L / v_m`
//! seconds (default: the base file's `time.duration` over its own `L / v_m`, so at the base
//! speed the base duration is kept).
//!
//! # Resume
//!
//! Every simulation is appended to `history.csv` (and flushed) as soon as it ends. A rerun with
//! the same output directory reads the file and answers any evaluation whose exact parameter
//! values (bit for bit, as written), duration and base file (an FNV-1a hash of its text) match a
//! row from the row instead of simulating. Nelder-Mead is deterministic, so a rerun replays the
//! interrupted study from the rows and continues where it stopped.

pub mod phase;

use crate::model::Model;
use crate::problem::{self, key_line, Problem, ProblemError};
use crate::{gait, observe, plot, sim};
use argmin::core::observers::{Observe, ObserverMode};
use argmin::core::{
    CostFunction, Error as ArgminError, Executor, IterState, Problem as ArgminProblem, Solver,
    State, TerminationReason, TerminationStatus, KV,
};
use argmin::solver::neldermead::NelderMead;
use serde::{Deserialize, Serialize};
use std::cell::{Cell, RefCell};
use std::collections::HashMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// Cost (m/s) of a failed simulation: far worse than `-v_s` of any finished run (no snake moves
/// backward at 1000 m/s), and finite so the simplex statistics stay finite.
pub const FAILED_COST: f64 = 1.0e3;

/// Name of the history file in the output directory.
pub const HISTORY_FILE: &str = "history.csv";

/// Header of `history.csv` (the column order is fixed; units in the README).
pub const HISTORY_HEADER: &str = "eval,stress,sigma,speed,duration,G,W,v_s,v_s_over_v_m,writhe_max,writhe_mean,displacement_angle_deg,regime,status,wall_time_s,objective,base_hash,reason";

// ---------------------------------------------------------------------------------------------
// The study file
// ---------------------------------------------------------------------------------------------

/// A whole study file (TOML).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudySpec {
    /// `[study]`: the base problem and the budget (required table).
    pub study: StudyTable,
    /// `[optimize]`: bounds of the optimised parameters (required table).
    pub optimize: Option<OptimizeTable>,
}

/// `[study]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudyTable {
    /// Problem file, relative to the study file. Required. Its gait must have a kind other
    /// than "none" and its time mode must be "dynamic".
    pub base: String,
    /// Evaluations (cost-function calls: simulations plus answers from `history.csv`) before the
    /// search stops. Default 30, an integer in [n + 1, 100000] for n optimised parameters.
    #[serde(default = "d_max_evaluations")]
    pub max_evaluations: usize,
    /// Simulated duration in pulse times `L / v_m`: every evaluation runs
    /// `duration_pulses * L / v_m` seconds. Default: the base file's `time.duration * v_m / L`.
    /// In (0, 1000].
    pub duration_pulses: Option<f64>,
    /// Edge of the initial simplex in normalised coordinates (fraction of each bound's width).
    /// Default 0.25, in (0, 1].
    #[serde(default = "d_initial_step")]
    pub initial_step: f64,
    /// Nelder-Mead stops when the standard deviation of the cost over the simplex falls below
    /// this (m/s). Default 1e-5, >= 0.
    #[serde(default = "d_tolerance")]
    pub tolerance: f64,
    /// Penalty on a vertex outside the bounds (m/s per unit of normalised distance outside the
    /// unit cube). Default 1.0, >= 0.
    #[serde(default = "d_penalty")]
    pub penalty: f64,
    /// Heading limit (degrees): a finished run whose net displacement lies more than this off
    /// the initial head direction costs `penalty * (angle - max_heading_deg) / 90` extra (m/s)
    /// and cannot be the optimum. Default: no limit; in (0, 180].
    pub max_heading_deg: Option<f64>,
}
fn d_max_evaluations() -> usize {
    30
}
fn d_initial_step() -> f64 {
    0.25
}
fn d_tolerance() -> f64 {
    1e-5
}
fn d_penalty() -> f64 {
    1.0
}

/// `[optimize]`: `[lo, hi]` bounds of each optimised parameter; a parameter without bounds
/// keeps the base problem's value.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OptimizeTable {
    /// Bounds of the muscle stress `Gamma` (Pa), `0 <= lo < hi`.
    pub stress: Option<[f64; 2]>,
    /// Bounds of the couple width `sigma` (fraction of L), `0 < lo < hi <= 1`; for the
    /// Gaussian gaits (s-start, sidewinding) also `lo >= 1/N`, one element of the base file's
    /// `N = rod.elements`.
    pub sigma: Option<[f64; 2]>,
    /// Bounds of the travelling speed `v_m` (m/s), `0 < lo < hi`.
    pub speed: Option<[f64; 2]>,
    /// Starting point; each value must lie in its bounds. Default: the base problem's values.
    #[serde(default)]
    pub initial: InitialTable,
}

/// `[optimize] initial = { ... }`: the starting point (only optimised parameters).
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialTable {
    /// Muscle stress (Pa).
    pub stress: Option<f64>,
    /// Couple width (fraction of L).
    pub sigma: Option<f64>,
    /// Travelling speed (m/s).
    pub speed: Option<f64>,
}

/// One of the three gait parameters the optimiser may vary.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Param {
    /// `gait.stress`, the muscle stress `Gamma` (Pa).
    Stress,
    /// `gait.sigma`, the couple width (fraction of L).
    Sigma,
    /// `gait.speed`, the travelling speed `v_m` (m/s).
    Speed,
}

impl Param {
    /// All three, in column order.
    pub const ALL: [Param; 3] = [Param::Stress, Param::Sigma, Param::Speed];

    /// Key in `[optimize]` and `[gait]`.
    pub fn key(self) -> &'static str {
        match self {
            Param::Stress => "stress",
            Param::Sigma => "sigma",
            Param::Speed => "speed",
        }
    }

    /// Unit, as written in messages.
    pub fn unit(self) -> &'static str {
        match self {
            Param::Stress => "Pa",
            Param::Sigma => "fraction of rod.length",
            Param::Speed => "m/s",
        }
    }

    fn get(self, p: &Point) -> f64 {
        match self {
            Param::Stress => p.stress,
            Param::Sigma => p.sigma,
            Param::Speed => p.speed,
        }
    }

    fn set(self, p: &mut Point, v: f64) {
        match self {
            Param::Stress => p.stress = v,
            Param::Sigma => p.sigma = v,
            Param::Speed => p.speed = v,
        }
    }
}

/// Gait parameters of one evaluation (physical units).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Point {
    /// Muscle stress `Gamma` (Pa).
    pub stress: f64,
    /// Couple width `sigma` (fraction of L).
    pub sigma: f64,
    /// Travelling speed `v_m` (m/s).
    pub speed: f64,
}

/// One optimised dimension: bounds and starting value (physical units).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Dim {
    /// Which parameter.
    pub param: Param,
    /// Lower bound.
    pub lo: f64,
    /// Upper bound (> `lo`).
    pub hi: f64,
    /// Starting value, in `[lo, hi]`.
    pub initial: f64,
}

/// The search space: the optimised dimensions and the fixed values of the others.
#[derive(Clone, Debug)]
pub struct Space {
    /// Optimised dimensions, in the order stress, sigma, speed (those present).
    pub dims: Vec<Dim>,
    /// Values of every parameter when not optimised (the base problem's).
    pub fixed: Point,
}

impl Space {
    /// Normalised coordinates `u_i = (x_i - lo_i) / (hi_i - lo_i)` of a physical point.
    pub fn to_unit(&self, p: &Point) -> Vec<f64> {
        self.dims
            .iter()
            .map(|d| (d.param.get(p) - d.lo) / (d.hi - d.lo))
            .collect()
    }

    /// The physical point of normalised coordinates `u`, clamped to the bounds, and the
    /// Euclidean distance of `u` from the unit cube (0 inside). Non-finite coordinates clamp
    /// to the lower bound at infinite distance.
    pub fn point(&self, u: &[f64]) -> (Point, f64) {
        let mut p = self.fixed;
        let mut d2 = 0.0;
        for (d, &ui) in self.dims.iter().zip(u) {
            let (c, out) = if ui.is_nan() {
                (0.0, f64::INFINITY)
            } else {
                let c = ui.clamp(0.0, 1.0);
                (c, ui - c)
            };
            d2 += out * out;
            // Exact bounds at the cube's faces (no round-off past lo or hi).
            let x = if c <= 0.0 {
                d.lo
            } else if c >= 1.0 {
                d.hi
            } else {
                (d.lo + c * (d.hi - d.lo)).clamp(d.lo, d.hi)
            };
            d.param.set(&mut p, x);
        }
        (p, d2.sqrt())
    }

    /// The starting point (physical).
    pub fn initial(&self) -> Point {
        let mut p = self.fixed;
        for d in &self.dims {
            d.param.set(&mut p, d.initial);
        }
        p
    }

    /// The initial simplex in normalised coordinates: the starting point and, for each
    /// dimension, the starting point moved by `step` along it (backward where forward would
    /// leave the unit cube).
    pub fn initial_simplex(&self, step: f64) -> Vec<Vec<f64>> {
        let u0 = self.to_unit(&self.initial());
        let mut simplex = vec![u0.clone()];
        for i in 0..u0.len() {
            let mut v = u0.clone();
            v[i] = if u0[i] + step <= 1.0 {
                u0[i] + step
            } else {
                u0[i] - step
            };
            simplex.push(v);
        }
        simplex
    }
}

/// A validated study.
#[derive(Clone, Debug)]
pub struct Study {
    /// The study file.
    pub path: PathBuf,
    /// The base problem file (resolved against the study file's directory).
    pub base_path: PathBuf,
    /// The base problem.
    pub base: Problem,
    /// FNV-1a 64 hash of the base file's text (16 hex digits): resume only reuses rows whose
    /// hash matches.
    pub base_hash: String,
    /// Evaluation budget.
    pub max_evaluations: usize,
    /// Duration of every evaluation in pulse times `L / v_m`.
    pub duration_pulses: f64,
    /// Initial simplex edge (normalised).
    pub initial_step: f64,
    /// Nelder-Mead cost standard-deviation tolerance (m/s).
    pub tolerance: f64,
    /// Out-of-bounds penalty (m/s per unit normalised distance).
    pub penalty: f64,
    /// Heading limit (degrees), if any.
    pub max_heading_deg: Option<f64>,
    /// The search space.
    pub space: Space,
}

impl Study {
    /// Whether a run's heading is within `max_heading_deg` (always, without a limit).
    pub fn meets_heading(&self, e: &Evaluation) -> bool {
        self.max_heading_deg
            .is_none_or(|max| !(e.displacement_angle_deg > max))
    }

    /// Extra cost (m/s) of a finished run that heads more than `max_heading_deg` off the
    /// initial head direction: `penalty * (angle - max_heading_deg) / 90`; zero otherwise.
    pub fn heading_penalty(&self, e: &Evaluation) -> f64 {
        match (self.max_heading_deg, e.status) {
            (Some(max), Status::Ok) if e.displacement_angle_deg > max => {
                self.penalty * (e.displacement_angle_deg - max) / 90.0
            }
            _ => 0.0,
        }
    }

    /// Duration of a run at travelling speed `speed` (s).
    pub fn duration(&self, speed: f64) -> f64 {
        self.duration_pulses * self.base.rod.length / speed
    }

    /// The base problem with the point's gait values and the matching duration.
    pub fn problem_at(&self, p: &Point) -> Problem {
        let mut pr = self.base.clone();
        pr.gait.stress = p.stress;
        pr.gait.sigma = p.sigma;
        pr.gait.speed = p.speed;
        pr.time.duration = Some(self.duration(p.speed));
        pr
    }
}

/// A study-file error: names the file, the dotted key, its line and what is allowed.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// The study file could not be read, is not valid TOML of the study's shape, or has a value
    /// outside its allowed range (the same errors as a problem file's).
    #[error(transparent)]
    File(#[from] ProblemError),
    /// The base problem file is missing or invalid.
    #[error("{file}:{line}: `study.base` = {value:?}: {source}; must be a valid problem file (path relative to the study file)")]
    Base {
        /// The study file.
        file: PathBuf,
        /// Line of `base`.
        line: usize,
        /// The value as written.
        value: String,
        /// The problem-file error (names the base file, its key and line).
        source: ProblemError,
    },
}

/// Read, parse and validate a study file (and its base problem).
pub fn load_study(path: &Path) -> Result<Study, StudyError> {
    parse_study(&problem::read(path)?, path)
}

/// Parse and validate study text; `path` locates the base file and names the study in messages.
pub fn parse_study(text: &str, path: &Path) -> Result<Study, StudyError> {
    let spec: StudySpec = problem::from_toml(text, path)?;
    problem::ranges::check_lengths(text, path)?;
    let fail = |table: &str, key: &str, value: String, allowed: String| {
        let top = key.split('.').next().unwrap_or(key);
        StudyError::from(ProblemError::Invalid {
            file: path.into(),
            line: key_line(text, table, top),
            key: format!("{table}.{key}"),
            value,
            allowed,
        })
    };
    let s = &spec.study;
    let base_path = path.parent().unwrap_or_else(|| Path::new("")).join(&s.base);
    let base_text =
        problem::read(&base_path).and_then(|t| problem::parse(&t, &base_path).map(|p| (t, p)));
    let (base_text, base) = base_text.map_err(|source| StudyError::Base {
        file: path.into(),
        line: key_line(text, "study", "base"),
        value: s.base.clone(),
        source,
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
    let fixed = Point {
        stress: base.gait.stress,
        sigma: base.gait.sigma,
        speed: base.gait.speed,
    };
    let Some(opt) = &spec.optimize else {
        return Err(ProblemError::Invalid {
            file: path.into(),
            line: text.lines().count().max(1),
            key: "optimize".into(),
            value: "(missing)".into(),
            allowed: "a table with at least one of optimize.stress (Pa), optimize.sigma (fraction of L), optimize.speed (m/s)".into(),
        }
        .into());
    };
    let mut dims = Vec::new();
    for param in Param::ALL {
        let (bounds, initial) = match param {
            Param::Stress => (opt.stress, opt.initial.stress),
            Param::Sigma => (opt.sigma, opt.initial.sigma),
            Param::Speed => (opt.speed, opt.initial.speed),
        };
        let key = param.key();
        let unit = param.unit();
        let Some([lo, hi]) = bounds else {
            if let Some(v) = initial {
                return Err(fail(
                    "optimize",
                    &format!("initial.{key}"),
                    format!("{v}"),
                    format!("absent unless optimize.{key} gives bounds ({unit})"),
                ));
            }
            continue;
        };
        let (ok, allowed) = match param {
            Param::Stress => (
                lo.is_finite() && hi.is_finite() && lo >= 0.0 && lo < hi,
                format!("[lo, hi] with 0 <= lo < hi, finite ({unit})"),
            ),
            Param::Sigma => {
                // The Gaussian gaits need at least one element of the base mesh (a narrower
                // Gaussian falls between the nodes and the muscles do nothing).
                let gaussian =
                    matches!(base.gait.kind, gait::Kind::SStart | gait::Kind::Sidewinding);
                let min = 1.0 / base.rod.elements as f64;
                (
                    lo > 0.0 && lo < hi && hi <= 1.0 && (!gaussian || lo >= min),
                    if gaussian {
                        format!(
                            "[lo, hi] with 0 < lo < hi <= 1 and lo at least one element, 1/rod.elements = {min} ({unit})"
                        )
                    } else {
                        format!("[lo, hi] with 0 < lo < hi <= 1 ({unit})")
                    },
                )
            }
            Param::Speed => (
                lo.is_finite() && hi.is_finite() && lo > 0.0 && lo < hi,
                format!("[lo, hi] with 0 < lo < hi, finite ({unit})"),
            ),
        };
        if !ok {
            return Err(fail("optimize", key, format!("[{lo}, {hi}]"), allowed));
        }
        let x0 = initial.unwrap_or(param.get(&fixed));
        if !(x0 >= lo && x0 <= hi) {
            return Err(match initial {
                Some(v) => fail(
                    "optimize",
                    &format!("initial.{key}"),
                    format!("{v}"),
                    format!("in [{lo}, {hi}] ({unit}), the bounds optimize.{key}"),
                ),
                None => fail(
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
        return Err(ProblemError::Invalid {
            file: path.into(),
            line: key_line(text, "optimize", "stress"),
            key: "optimize".into(),
            value: "(no bounds)".into(),
            allowed: "at least one of optimize.stress (Pa), optimize.sigma (fraction of L), optimize.speed (m/s)".into(),
        }
        .into());
    }
    let n = dims.len();
    if !(n + 1..=100_000).contains(&s.max_evaluations) {
        return Err(fail(
            "study",
            "max_evaluations",
            format!("{}", s.max_evaluations),
            format!(
                "an integer in [{}, 100000] (the initial simplex of {n} optimised parameters needs {} evaluations)",
                n + 1,
                n + 1
            ),
        ));
    }
    let base_duration = base.time.duration.unwrap_or(0.0);
    let duration_pulses = match s.duration_pulses {
        Some(v) => {
            if !(v.is_finite() && v > 0.0 && v <= 1000.0) {
                return Err(fail(
                    "study",
                    "duration_pulses",
                    format!("{v}"),
                    "in (0, 1000] (pulse times L / v_m)".into(),
                ));
            }
            v
        }
        None => base_duration * base.gait.speed / base.rod.length,
    };
    if !(s.initial_step.is_finite() && s.initial_step > 0.0 && s.initial_step <= 1.0) {
        return Err(fail(
            "study",
            "initial_step",
            format!("{}", s.initial_step),
            "in (0, 1] (fraction of each bound's width)".into(),
        ));
    }
    if !(s.tolerance.is_finite() && s.tolerance >= 0.0) {
        return Err(fail(
            "study",
            "tolerance",
            format!("{}", s.tolerance),
            "a finite number >= 0 (m/s)".into(),
        ));
    }
    if !(s.penalty.is_finite() && s.penalty >= 0.0) {
        return Err(fail(
            "study",
            "penalty",
            format!("{}", s.penalty),
            "a finite number >= 0 (m/s per unit normalised distance)".into(),
        ));
    }
    if let Some(h) = s.max_heading_deg {
        if !(h.is_finite() && h > 0.0 && h <= 180.0) {
            return Err(fail(
                "study",
                "max_heading_deg",
                format!("{h}"),
                "a number in (0, 180] (degrees)".into(),
            ));
        }
    }
    let space = Space { dims, fixed };
    let study = Study {
        path: path.into(),
        base_path,
        base_hash: format!("{:016x}", fnv1a(base_text.as_bytes())),
        base,
        max_evaluations: s.max_evaluations,
        duration_pulses,
        initial_step: s.initial_step,
        tolerance: s.tolerance,
        penalty: s.penalty,
        max_heading_deg: s.max_heading_deg,
        space,
    };
    // The shortest run (at the fastest speed) must hold at least one time step.
    let v_max = study
        .space
        .dims
        .iter()
        .find(|d| d.param == Param::Speed)
        .map_or(fixed.speed, |d| d.hi);
    let dt = study.base.time.dt.unwrap_or(0.0);
    let shortest = study.duration(v_max);
    if shortest < dt {
        let (table, key) = if s.duration_pulses.is_some() {
            ("study", "duration_pulses")
        } else {
            ("optimize", "speed")
        };
        return Err(fail(
            table,
            key,
            if key == "speed" {
                format!("{v_max}")
            } else {
                format!("{duration_pulses}")
            },
            format!(
                "such that the shortest run, duration_pulses * L / v_m = {shortest} s at v_m = {v_max} m/s, is at least the base file's time.dt = {dt} s"
            ),
        ));
    }
    Ok(study)
}

/// FNV-1a, 64 bit (stable across Rust versions, unlike `DefaultHasher`).
pub(crate) fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

// ---------------------------------------------------------------------------------------------
// Evaluations and the history file
// ---------------------------------------------------------------------------------------------

/// Outcome of one simulation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// The run finished and `v_s` is finite.
    Ok,
    /// The run stopped early (or `v_s` was not finite): cost [`FAILED_COST`].
    Failed,
}

impl Status {
    fn as_str(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Failed => "failed",
        }
    }
}

/// One simulated point: a row of `history.csv`.
#[derive(Clone, Debug, Serialize)]
pub struct Evaluation {
    /// Row number in `history.csv` (1-based, continues across resumed runs).
    pub eval: usize,
    /// Gait values.
    #[serde(flatten)]
    pub point: Point,
    /// Simulated duration (s).
    pub duration: f64,
    /// Scaled torque `G = Gamma a^3 L / B`.
    #[serde(rename = "G")]
    pub g: f64,
    /// Scaled weight `W = rho g a^2 L^3 / B`.
    #[serde(rename = "W")]
    pub w: f64,
    /// Mean forward speed of the centroid (m/s); NaN for a failed run (its observables are
    /// not measured: NaN, regime "-").
    pub v_s: f64,
    /// `v_s / v_m`.
    pub v_s_over_v_m: f64,
    /// Largest |writhe| over the frames (turns).
    pub writhe_max: f64,
    /// Mean writhe over the frames (turns).
    pub writhe_mean: f64,
    /// Angle of the net displacement from the initial head direction (degrees).
    pub displacement_angle_deg: f64,
    /// Regime "S", "F", "N" or "U" ([`crate::observe`]).
    pub regime: String,
    /// Finished or failed.
    pub status: Status,
    /// Wall time of the simulation (s).
    pub wall_time_s: f64,
    /// Why a failed run failed (empty when it finished).
    pub reason: String,
}

impl Evaluation {
    /// The objective at this point, without any out-of-bounds penalty: `-v_s` (m/s), or
    /// [`FAILED_COST`] for a failed run.
    pub fn objective(&self) -> f64 {
        match self.status {
            Status::Ok => -self.v_s,
            Status::Failed => FAILED_COST,
        }
    }

    fn csv_row(&self, base_hash: &str) -> String {
        let reason: String = self
            .reason
            .chars()
            .map(|c| {
                if c == ',' {
                    ';'
                } else if c.is_control() {
                    ' '
                } else {
                    c
                }
            })
            .collect();
        format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            self.eval,
            self.point.stress,
            self.point.sigma,
            self.point.speed,
            self.duration,
            self.g,
            self.w,
            self.v_s,
            self.v_s_over_v_m,
            self.writhe_max,
            self.writhe_mean,
            self.displacement_angle_deg,
            self.regime,
            self.status.as_str(),
            self.wall_time_s,
            self.objective(),
            base_hash,
            reason
        )
    }
}

/// Cache key: exact bits of stress, sigma, speed and duration.
type Key = [u64; 4];

fn key(p: &Point, duration: f64) -> Key {
    [
        p.stress.to_bits(),
        p.sigma.to_bits(),
        p.speed.to_bits(),
        duration.to_bits(),
    ]
}

/// Rows of an existing `history.csv`.
#[derive(Debug, Default)]
pub struct History {
    /// Every row, in file order, with its base hash.
    pub rows: Vec<(Evaluation, String)>,
    /// An incomplete last line (an interrupted write) was dropped from the file.
    pub dropped_partial: bool,
}

/// Read `path` if it exists (a missing file is an empty history). A last line without its
/// newline (a write cut short) is removed from the file; any other malformed line is an error
/// naming its line.
pub fn read_history(path: &Path) -> Result<History, DesignError> {
    let mut h = History::default();
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(h),
        Err(source) => {
            return Err(DesignError::Io {
                path: path.into(),
                source,
            })
        }
    };
    let mut complete = text.as_str();
    if !text.is_empty() && !text.ends_with('\n') {
        let keep = text.rfind('\n').map_or(0, |i| i + 1);
        complete = &text[..keep];
        let f = std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .and_then(|f| f.set_len(keep as u64));
        f.map_err(|source| DesignError::Io {
            path: path.into(),
            source,
        })?;
        h.dropped_partial = true;
    }
    let bad = |line: usize, message: String| DesignError::History {
        file: path.into(),
        line,
        message,
    };
    for (n, line) in complete.lines().enumerate() {
        let line_no = n + 1;
        if n == 0 {
            if line.trim_end() != HISTORY_HEADER {
                return Err(bad(
                    1,
                    format!("the header must be `{HISTORY_HEADER}` (written by this version of slither); move the file away to start afresh"),
                ));
            }
            continue;
        }
        if line.trim().is_empty() {
            continue;
        }
        let f: Vec<&str> = line.splitn(18, ',').collect();
        if f.len() != 18 {
            return Err(bad(
                line_no,
                format!("expected 18 comma-separated fields, found {}", f.len()),
            ));
        }
        let num = |i: usize| -> Result<f64, DesignError> {
            f[i].trim().parse::<f64>().map_err(|_| {
                bad(
                    line_no,
                    format!(
                        "column `{}` = {:?} is not a number",
                        HISTORY_HEADER.split(',').nth(i).unwrap_or("?"),
                        f[i]
                    ),
                )
            })
        };
        let eval = f[0].trim().parse::<usize>().map_err(|_| {
            bad(
                line_no,
                format!("column `eval` = {:?} is not an integer", f[0]),
            )
        })?;
        let status = match f[13].trim() {
            "ok" => Status::Ok,
            "failed" => Status::Failed,
            other => {
                return Err(bad(
                    line_no,
                    format!("column `status` = {other:?} must be \"ok\" or \"failed\""),
                ))
            }
        };
        let e = Evaluation {
            eval,
            point: Point {
                stress: num(1)?,
                sigma: num(2)?,
                speed: num(3)?,
            },
            duration: num(4)?,
            g: num(5)?,
            w: num(6)?,
            v_s: num(7)?,
            v_s_over_v_m: num(8)?,
            writhe_max: num(9)?,
            writhe_mean: num(10)?,
            displacement_angle_deg: num(11)?,
            regime: f[12].trim().to_string(),
            status,
            wall_time_s: num(14)?,
            reason: f[17].to_string(),
        };
        h.rows.push((e, f[16].trim().to_string()));
    }
    Ok(h)
}

// ---------------------------------------------------------------------------------------------
// One evaluation: a simulation
// ---------------------------------------------------------------------------------------------

/// Simulate the study's base problem at `p` (the evaluation index is set by the caller) and
/// measure it. Never panics: a failed step, an unsupported integrator, a non-finite speed or a
/// panic inside the simulator gives status [`Status::Failed`] with the reason.
pub fn simulate(study: &Study, p: &Point, progress: &mut dyn FnMut(f64)) -> Evaluation {
    let start = Instant::now();
    let pr = study.problem_at(p);
    let duration = pr.time.duration.unwrap_or(0.0);
    let model = Model::new(&pr);
    let b = model.bend;
    let g = model.gait.couple * model.length / b;
    let w = model.dimensionless().scaled_weight;
    let mut e = Evaluation {
        eval: 0,
        point: *p,
        duration,
        g,
        w,
        v_s: f64::NAN,
        v_s_over_v_m: f64::NAN,
        writhe_max: f64::NAN,
        writhe_mean: f64::NAN,
        displacement_angle_deg: f64::NAN,
        regime: "-".into(),
        status: Status::Failed,
        wall_time_s: 0.0,
        reason: String::new(),
    };
    let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let outcome = sim::run_gait(&model, pr.solver.integrator, progress, &mut |_| {})
            .map_err(|err| err.to_string())?;
        let fields = observe::fields(&model, &outcome.frames);
        let ob = observe::observe(&model, &outcome.frames, &fields);
        Ok::<_, String>((ob, outcome.error.map(|err| err.to_string())))
    }));
    match run {
        // A run cut short has not measured the gait: its observables stay NaN (regime "-").
        Ok(Ok((_, Some(reason)))) => {
            e.reason = reason;
            e.regime = "-".into();
        }
        Ok(Ok((ob, None))) => {
            e.v_s = ob.v_s;
            e.v_s_over_v_m = ob.v_s_over_v_m;
            e.writhe_max = ob.writhe_max;
            e.writhe_mean = ob.writhe_mean;
            e.displacement_angle_deg = ob.displacement_angle_deg;
            e.regime = ob.regime;
            if ob.v_s.is_finite() {
                e.status = Status::Ok;
            } else {
                e.reason = "v_s is not finite".into();
            }
        }
        Ok(Err(reason)) => e.reason = reason,
        Err(panic) => {
            let msg = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            e.reason = format!("the simulator panicked: {msg}");
        }
    }
    e.wall_time_s = start.elapsed().as_secs_f64();
    e
}

// ---------------------------------------------------------------------------------------------
// The cost function, the solver wrapper and the iteration observer
// ---------------------------------------------------------------------------------------------

/// Notified before and after every evaluation (the CLI's progress bar and log lines).
pub trait EvaluationObserver {
    /// Evaluation number `count` (1-based within this run) starts at `point`; `cached` when it
    /// is answered from `history.csv` without simulating.
    fn started(&mut self, _count: usize, _point: &Point, _cached: bool) {}
    /// Fraction of the running simulation done, in [0, 1].
    fn progress(&mut self, _fraction: f64) {}
    /// Evaluation `count` ended with `e`; `reused` when it came from an earlier run's row.
    fn finished(&mut self, _count: usize, _e: &Evaluation, _reused: bool) {}
}

/// An observer that does nothing.
pub struct Silent;
impl EvaluationObserver for Silent {}

/// How an evaluation was answered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Source {
    Simulated,
    /// A row written by an earlier run.
    Reused,
    /// A point already visited in this run.
    Repeat,
}

struct Shared<'a> {
    study: &'a Study,
    cache: HashMap<Key, (Evaluation, bool)>,
    next_eval: usize,
    history: std::fs::File,
    history_path: PathBuf,
    observer: &'a mut dyn EvaluationObserver,
    /// Every answered evaluation of this run, in order.
    visited: Vec<(Evaluation, Source, f64)>,
    fatal: Option<DesignError>,
}

/// The simulator as an argmin cost function over normalised coordinates. Cost calls beyond
/// the budget, or after a fatal error, are answered with `+inf` without simulating and the
/// solver wrapper stops at the end of that iteration (argmin's Nelder-Mead unwraps cost errors
/// during its initialisation, so this function never returns an error).
pub struct Evaluator<'a> {
    shared: Rc<RefCell<Shared<'a>>>,
    calls: Rc<Cell<usize>>,
    max: usize,
    fatal: Rc<Cell<bool>>,
}

impl CostFunction for Evaluator<'_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, u: &Self::Param) -> Result<f64, ArgminError> {
        let mut sh = self.shared.borrow_mut();
        if self.calls.get() >= self.max || sh.fatal.is_some() {
            return Ok(f64::INFINITY);
        }
        self.calls.set(self.calls.get() + 1);
        let count = self.calls.get();
        let study = sh.study;
        let (p, dist) = study.space.point(u);
        let duration = study.duration(p.speed);
        let k = key(&p, duration);
        let (e, source) = if let Some((e, from_file)) = sh.cache.get(&k) {
            let e = e.clone();
            let source = if *from_file {
                Source::Reused
            } else {
                Source::Repeat
            };
            sh.observer.started(count, &p, true);
            (e, source)
        } else {
            sh.observer.started(count, &p, false);
            let mut e = {
                let obs = &mut *sh.observer;
                simulate(study, &p, &mut |f| obs.progress(f))
            };
            e.eval = sh.next_eval;
            sh.next_eval += 1;
            let row = e.csv_row(&study.base_hash) + "\n";
            let written = sh
                .history
                .write_all(row.as_bytes())
                .and_then(|_| sh.history.flush())
                .and_then(|_| sh.history.sync_data());
            if let Err(source) = written {
                self.fatal.set(true);
                sh.fatal = Some(DesignError::Io {
                    path: sh.history_path.clone(),
                    source,
                });
            }
            sh.cache.insert(k, (e.clone(), false));
            (e, Source::Simulated)
        };
        sh.observer.finished(count, &e, source == Source::Reused);
        let cost = e.objective() + study.penalty * dist + study.heading_penalty(&e);
        sh.visited.push((e, source, cost));
        Ok(cost)
    }
}

type NmState = IterState<Vec<f64>, (), (), (), (), f64>;

/// Nelder-Mead that also stops when the evaluation budget is spent (or a fatal error occurred).
struct Budgeted {
    inner: NelderMead<Vec<f64>, f64>,
    calls: Rc<Cell<usize>>,
    max: usize,
    fatal: Rc<Cell<bool>>,
}

impl<O> Solver<O, NmState> for Budgeted
where
    O: CostFunction<Param = Vec<f64>, Output = f64>,
{
    fn name(&self) -> &str {
        "Nelder-Mead"
    }

    fn init(
        &mut self,
        problem: &mut ArgminProblem<O>,
        state: NmState,
    ) -> Result<(NmState, Option<KV>), ArgminError> {
        Solver::<O, NmState>::init(&mut self.inner, problem, state)
    }

    fn next_iter(
        &mut self,
        problem: &mut ArgminProblem<O>,
        state: NmState,
    ) -> Result<(NmState, Option<KV>), ArgminError> {
        Solver::<O, NmState>::next_iter(&mut self.inner, problem, state)
    }

    fn terminate(&mut self, state: &NmState) -> TerminationStatus {
        if self.fatal.get() {
            return TerminationStatus::Terminated(TerminationReason::SolverExit(
                "aborted: the history could not be written".into(),
            ));
        }
        if self.calls.get() >= self.max {
            return TerminationStatus::Terminated(TerminationReason::SolverExit(
                "max_evaluations reached".into(),
            ));
        }
        Solver::<O, NmState>::terminate(&mut self.inner, state)
    }
}

/// One Nelder-Mead iteration as seen by the iteration observer.
#[derive(Clone, Debug, Serialize)]
pub struct Iteration {
    /// Iteration number (0: after the initial simplex).
    pub iteration: u64,
    /// Best cost of the simplex (m/s, penalty included).
    pub best_cost: f64,
    /// Nelder-Mead action ("Reflection", "Expansion", ...), empty after initialisation.
    pub action: String,
}

/// argmin observer recording the simplex's best cost after every iteration.
struct IterationLog(Arc<Mutex<Vec<Iteration>>>);

impl Observe<NmState> for IterationLog {
    fn observe_init(&mut self, _name: &str, state: &NmState, _kv: &KV) -> Result<(), ArgminError> {
        if let Ok(mut v) = self.0.lock() {
            v.push(Iteration {
                iteration: 0,
                best_cost: state.get_best_cost(),
                action: String::new(),
            });
        }
        Ok(())
    }

    fn observe_iter(&mut self, state: &NmState, kv: &KV) -> Result<(), ArgminError> {
        let action = kv
            .get("action")
            .and_then(|a| a.get_string())
            .unwrap_or_default();
        if let Ok(mut v) = self.0.lock() {
            v.push(Iteration {
                iteration: state.get_iter() + 1,
                best_cost: state.get_best_cost(),
                action,
            });
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------------------------
// The driver
// ---------------------------------------------------------------------------------------------

/// Errors of the optimiser (study-file errors are [`StudyError`]).
#[derive(Debug, thiserror::Error)]
pub enum DesignError {
    /// An existing `history.csv` that cannot be read back.
    #[error("{file}:{line}: {message}")]
    History {
        /// The history file.
        file: PathBuf,
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// Reading or writing an output file.
    #[error("{path}: {source}")]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// Cause.
        source: std::io::Error,
    },
    /// A figure could not be drawn.
    #[error("{path}: {source}")]
    Plot {
        /// The figure.
        path: PathBuf,
        /// Cause.
        source: plot::PlotError,
    },
    /// argmin reported an internal error.
    #[error("optimiser: {0}")]
    Solver(String),
}

/// What a study run did and found.
#[derive(Clone, Debug)]
pub struct Report {
    /// Evaluations answered in this run (simulated, reused and repeated).
    pub evaluations: usize,
    /// Simulations run (and rows appended to `history.csv`) in this run.
    pub simulations: usize,
    /// Evaluations answered from rows an earlier run wrote.
    pub reused: usize,
    /// Evaluations of a point already visited in this run (answered from the cache).
    pub repeats: usize,
    /// Distinct points visited in this run whose simulation failed.
    pub failed: usize,
    /// Rows in `history.csv` before this run (all base files).
    pub rows_before: usize,
    /// Rows before this run that were written for another base file (never reused).
    pub rows_other_base: usize,
    /// An incomplete last row of `history.csv` was dropped.
    pub dropped_partial_row: bool,
    /// The starting point's evaluation.
    pub initial: Evaluation,
    /// The finished evaluation with the largest `v_s` among those visited in this run, if any
    /// finished.
    pub best: Option<Evaluation>,
    /// Every evaluation of this run in order, with the cost the optimiser saw (penalty
    /// included).
    pub visited: Vec<(Evaluation, f64)>,
    /// Nelder-Mead iterations (simplex best after each).
    pub iterations: Vec<Iteration>,
    /// Why the search stopped.
    pub termination: String,
    /// Wall time of the whole study run (s).
    pub wall_time_s: f64,
}

/// Run a study: Nelder-Mead over the normalised bounds, every evaluation a simulation (or a
/// row of an existing `out/history.csv`), then write `optimum.json`, `speed_vs_writhe.png`
/// and `history.png` into `out` (created if absent).
pub fn optimize(
    study: &Study,
    out: &Path,
    observer: &mut dyn EvaluationObserver,
) -> Result<Report, DesignError> {
    let start = Instant::now();
    std::fs::create_dir_all(out).map_err(|source| DesignError::Io {
        path: out.into(),
        source,
    })?;
    let history_path = out.join(HISTORY_FILE);
    let old = read_history(&history_path)?;
    let rows_before = old.rows.len();
    let mut cache = HashMap::new();
    let mut rows_other_base = 0;
    let mut next_eval = 1;
    for (e, hash) in old.rows {
        next_eval = next_eval.max(e.eval + 1);
        if hash == study.base_hash {
            cache.insert(key(&e.point, e.duration), (e, true));
        } else {
            rows_other_base += 1;
        }
    }
    let mut history = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(&history_path)
        .map_err(|source| DesignError::Io {
            path: history_path.clone(),
            source,
        })?;
    if rows_before == 0 {
        let empty = history.metadata().map(|m| m.len() == 0).unwrap_or(true);
        if empty {
            writeln!(history, "{HISTORY_HEADER}")
                .and_then(|_| history.flush())
                .map_err(|source| DesignError::Io {
                    path: history_path.clone(),
                    source,
                })?;
        }
    }
    let calls = Rc::new(Cell::new(0usize));
    let fatal = Rc::new(Cell::new(false));
    let shared = Rc::new(RefCell::new(Shared {
        study,
        cache,
        next_eval,
        history,
        history_path: history_path.clone(),
        observer,
        visited: Vec::new(),
        fatal: None,
    }));
    let evaluator = Evaluator {
        shared: shared.clone(),
        calls: calls.clone(),
        max: study.max_evaluations,
        fatal: fatal.clone(),
    };
    let nm = NelderMead::new(study.space.initial_simplex(study.initial_step))
        .with_sd_tolerance(study.tolerance)
        .map_err(|e| DesignError::Solver(e.to_string()))?;
    let solver = Budgeted {
        inner: nm,
        calls: calls.clone(),
        max: study.max_evaluations,
        fatal: fatal.clone(),
    };
    let iterations = Arc::new(Mutex::new(Vec::new()));
    let run = Executor::new(evaluator, solver)
        .configure(|s| s.max_iters(study.max_evaluations as u64))
        .add_observer(IterationLog(iterations.clone()), ObserverMode::Always)
        .run();
    let termination = match run {
        Ok(res) => res
            .state()
            .get_termination_reason()
            .map_or("stopped".to_string(), |r| r.text().to_string()),
        Err(e) => return Err(DesignError::Solver(e.to_string())),
    };
    let mut sh = shared.borrow_mut();
    if let Some(e) = sh.fatal.take() {
        return Err(e);
    }
    let visited: Vec<(Evaluation, Source, f64)> = std::mem::take(&mut sh.visited);
    drop(sh);
    let count = |s: Source| visited.iter().filter(|v| v.1 == s).count();
    let mut failed_keys = std::collections::HashSet::new();
    for (e, _, _) in &visited {
        if e.status == Status::Failed {
            failed_keys.insert(key(&e.point, e.duration));
        }
    }
    let best = visited
        .iter()
        .filter(|v| v.0.status == Status::Ok && study.meets_heading(&v.0))
        .max_by(|a, b| a.0.v_s.total_cmp(&b.0.v_s))
        .map(|v| v.0.clone());
    let initial = visited
        .first()
        .map(|v| v.0.clone())
        .ok_or_else(|| DesignError::Solver("no evaluation was made".into()))?;
    let report = Report {
        evaluations: visited.len(),
        simulations: count(Source::Simulated),
        reused: count(Source::Reused),
        repeats: count(Source::Repeat),
        failed: failed_keys.len(),
        rows_before,
        rows_other_base,
        dropped_partial_row: old.dropped_partial,
        initial,
        best,
        visited: visited.into_iter().map(|(e, _, c)| (e, c)).collect(),
        iterations: iterations.lock().map(|v| v.clone()).unwrap_or_default(),
        termination,
        wall_time_s: start.elapsed().as_secs_f64(),
    };
    write_optimum(study, out, &report)?;
    write_figures(study, out, &report)?;
    Ok(report)
}

/// `optimum.json`.
#[derive(Serialize)]
struct Optimum<'a> {
    study: String,
    base: String,
    base_hash: &'a str,
    /// The optimised parameters and their bounds.
    optimized: &'a [Dim],
    /// Fastest finished evaluation within the heading limit (null if there is none).
    best: Option<Summary<'a>>,
    /// The starting point.
    initial: Summary<'a>,
    /// `best.v_s - initial.v_s` (m/s).
    v_s_gain: Option<f64>,
    evaluations: usize,
    simulations: usize,
    reused: usize,
    repeats: usize,
    failed: usize,
    max_evaluations: usize,
    iterations: usize,
    termination: &'a str,
    duration_pulses: f64,
    wall_time_s: f64,
}

#[derive(Serialize)]
struct Summary<'a> {
    eval: usize,
    /// Muscle stress (Pa).
    stress: f64,
    /// Couple width (fraction of L).
    sigma: f64,
    /// Travelling speed (m/s).
    speed: f64,
    duration_s: f64,
    dimensionless: Groups,
    v_s: f64,
    v_s_over_v_m: f64,
    writhe_max: f64,
    writhe_mean: f64,
    /// Net displacement's angle from the initial head direction (degrees).
    displacement_angle_deg: f64,
    regime: &'a str,
    status: Status,
}

#[derive(Serialize)]
struct Groups {
    /// Scaled torque `G = Gamma a^3 L / B`.
    #[serde(rename = "G")]
    g: f64,
    /// Scaled weight `W = rho g a^2 L^3 / B`.
    #[serde(rename = "W")]
    w: f64,
    /// `W / G = rho g L^2 / (Gamma a)`.
    #[serde(rename = "W_over_G")]
    w_over_g: f64,
}

fn summary(e: &Evaluation) -> Summary<'_> {
    Summary {
        eval: e.eval,
        stress: e.point.stress,
        sigma: e.point.sigma,
        speed: e.point.speed,
        duration_s: e.duration,
        dimensionless: Groups {
            g: e.g,
            w: e.w,
            w_over_g: e.w / e.g,
        },
        v_s: e.v_s,
        v_s_over_v_m: e.v_s_over_v_m,
        writhe_max: e.writhe_max,
        writhe_mean: e.writhe_mean,
        displacement_angle_deg: e.displacement_angle_deg,
        regime: &e.regime,
        status: e.status,
    }
}

/// JSON numbers cannot be NaN or infinite: serde_json writes them as null.
fn write_optimum(study: &Study, out: &Path, r: &Report) -> Result<(), DesignError> {
    let o = Optimum {
        study: study.path.display().to_string(),
        base: study.base_path.display().to_string(),
        base_hash: &study.base_hash,
        optimized: &study.space.dims,
        best: r.best.as_ref().map(summary),
        initial: summary(&r.initial),
        v_s_gain: r.best.as_ref().map(|b| b.v_s - r.initial.v_s),
        evaluations: r.evaluations,
        simulations: r.simulations,
        reused: r.reused,
        repeats: r.repeats,
        failed: r.failed,
        max_evaluations: study.max_evaluations,
        iterations: r.iterations.len().saturating_sub(1),
        termination: &r.termination,
        duration_pulses: study.duration_pulses,
        wall_time_s: r.wall_time_s,
    };
    let path = out.join("optimum.json");
    let text = serde_json::to_string_pretty(&o).map_err(|e| DesignError::Io {
        path: path.clone(),
        source: std::io::Error::other(e),
    })?;
    // Through a temporary name: a full disk leaves no truncated optimum.json.
    crate::output::write_atomic(&path, (text + "\n").as_bytes())
        .map_err(|source| DesignError::Io { path, source })
}

fn write_figures(study: &Study, out: &Path, r: &Report) -> Result<(), DesignError> {
    let ok: Vec<&Evaluation> = r
        .visited
        .iter()
        .map(|v| &v.0)
        .filter(|e| e.status == Status::Ok)
        .collect();
    let path = out.join("speed_vs_writhe.png");
    let (within, beyond): (Vec<&Evaluation>, Vec<&Evaluation>) =
        ok.iter().partition(|e| study.meets_heading(e));
    let mut series: Vec<(String, Vec<(f64, f64)>)> = vec![(
        format!("finished evaluations ({})", within.len()),
        within
            .iter()
            .map(|e| (e.writhe_max, e.v_s_over_v_m))
            .collect(),
    )];
    if let (Some(max), false) = (study.max_heading_deg, beyond.is_empty()) {
        series.push((
            format!(
                "more than {max} deg off the head direction ({})",
                beyond.len()
            ),
            beyond
                .iter()
                .map(|e| (e.writhe_max, e.v_s_over_v_m))
                .collect(),
        ));
    }
    if r.initial.status == Status::Ok {
        series.push((
            "start".into(),
            vec![(r.initial.writhe_max, r.initial.v_s_over_v_m)],
        ));
    }
    if let Some(b) = &r.best {
        series.push((
            format!("optimum (eval {}, v_s = {:.4} m/s)", b.eval, b.v_s),
            vec![(b.writhe_max, b.v_s_over_v_m)],
        ));
    }
    if !ok.is_empty() {
        let s: Vec<(&str, Vec<(f64, f64)>)> = series
            .iter()
            .map(|(n, p)| (n.as_str(), p.clone()))
            .collect();
        plot::scatter(
            &path,
            "Gait design: speed against writhe",
            "largest |writhe| Wr_max (turns)",
            "v_s / v_m (dimensionless)",
            &s,
        )
        .map_err(|source| DesignError::Plot {
            path: path.clone(),
            source,
        })?;
    }
    let path = out.join("history.png");
    let mut best = f64::NEG_INFINITY;
    let mut each = Vec::new();
    let mut running = Vec::new();
    for (k, (e, _)) in r.visited.iter().enumerate() {
        let x = (k + 1) as f64;
        if e.status == Status::Ok {
            each.push((x, e.v_s));
            best = best.max(e.v_s);
        } else {
            each.push((x, f64::NAN));
        }
        running.push((x, if best.is_finite() { best } else { f64::NAN }));
    }
    if each.iter().any(|p| p.1.is_finite()) {
        plot::xy(
            &path,
            "Gait design: objective per evaluation",
            "evaluation (this run)",
            "forward speed v_s (m/s)",
            &[("v_s of the evaluation", each), ("best so far", running)],
            false,
            false,
        )
        .map_err(|source| DesignError::Plot { path, source })?;
    }
    Ok(())
}
