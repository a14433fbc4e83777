//! Gait design, the outer loop (MODEL section 7): maximise the averaged forward speed `v_s` over
//! the muscle stress `Gamma` (`gait.stress`, Pa), the couple width `sigma` (`gait.sigma`,
//! fraction of L) and the travelling speed `v_m` (`gait.speed`, m/s), every evaluation one full
//! simulation of a base problem with those values substituted.
//!
//! The loop is argmin's: a [`CostFunction`] (the simulator, [`Evaluator`]), a solver
//! (Nelder-Mead, optionally from several starts, or particle swarm; `[optimize] method`,
//! wrapped to stop at the evaluation budget) and an [`Executor`] that owns
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
//! values (bit for bit, as written), duration and row key match a row from the row instead of
//! simulating. The row key ([`Study::row_hash`]) is the hash of the effective base problem
//! ([`problem_hash`]: parsed, defaults filled in, so a comment does not count) mixed with the
//! objective's settings (`objective`, `turn_penalty`, `stationary_penalty`), which decide the
//! row's `objective` value: a study resumed after one of them changed **re-evaluates** (simulates
//! again) every point whose row was written under other settings, and the command line says
//! how many rows it left aside. The heading limit and the out-of-bounds penalty are applied
//! when a row is read, so changing them reuses the rows. Nelder-Mead is deterministic, and the particle
//! swarm and the extra starts draw their random numbers from a generator seeded by
//! `[optimize] seed` (xoshiro256++), so a rerun replays the interrupted study from the rows and
//! continues where it stopped.
//!
//! # Methods
//!
//! * `method = "nelder-mead"` (default): argmin's simplex, one simulation per evaluation;
//!   `starts = K` runs it K times one after the other, each with an equal share of
//!   `max_evaluations`, the first from the study's start, the others from uniform random
//!   points in the bounds.
//! * `method = "particle-swarm"`: argmin's `ParticleSwarm`, its positions mapped into the unit
//!   cube by [`reflect`] (a triangle wave of period 2 per coordinate, so a particle that
//!   overshoots a bound is evaluated as far inside and can come back, where argmin's own clamp
//!   kept it on the face; no penalty applies; see `search.rs`), `particles` per generation
//!   (default [`DEFAULT_PARTICLES`]). The first generation is the start plus uniform random points;
//!   each generation's costs come in one `bulk_cost` call, whose new points are simulated in
//!   parallel (rayon, one simulation per core) and then recorded in generation order.
//!
//! An optimum within [`ON_BOUND_FRACTION`] of a bound (in normalised coordinates) is reported
//! in `optimum.json` (`on_bound`) and on the chart.
//!
//! # Layout
//!
//! `objective.rs` what a study minimises and its rows' key; `study.rs` the study file
//! (schema, validation in `study_validate.rs`, the search space in `space.rs`); `history.rs`
//! the evaluations and `history.csv`; `simulate.rs` one evaluation (a simulation);
//! `search.rs` the argmin glue (cost function, budgeted solvers, iteration observer) and
//! [`optimize`]; `report.rs` `optimum.json` and the figures. A study's `[accuracy]` table is
//! [`crate::studies::accuracy`]'s, applied by [`prepare_accuracy`]; the resume keys' hashes
//! are [`crate::studies::problem_hash`]'s.

mod history;
mod objective;
mod report;
mod search;
mod simulate;
mod space;
mod study;
mod study_validate;

use history::{key, rewrite_history, Key};
pub use history::{
    read_history, Evaluation, History, PeriodicColumns, Status, HISTORY_FILE, HISTORY_HEADER,
    LEGACY_HISTORY_HEADER, PERIODIC_COLUMNS,
};
pub use objective::{Objective, ObjectiveInputs, DEFAULT_TURN_PENALTY};
pub use report::{check_optimum, on_bound, EnsembleOf, OptimumCheck};
use report::{write_figures, write_optimum};
pub use search::{
    optimize, reflect, EvaluationObserver, Evaluator, Iteration, Reflected, Silent, SWARM_WINDOW,
};
pub use simulate::simulate;
pub use space::{Dim, GaitParams, Param, Space};
use study::OPTIMIZE_ONE_OF;
pub use study::{
    load_study, load_study_with, parse_study, parse_study_with, prepare_accuracy, InitialTable,
    OptimizeTable, SearchMethod, Study, StudyError, StudySpec, StudyTable, DEFAULT_PARTICLES,
    ON_BOUND_FRACTION, STUDY_TABLES,
};
use study_validate::{
    base_problem, check_search_settings, check_shortest_run, dims, durations, method_sizes,
    objective, At,
};

use crate::model::Model;
use crate::problem::{self, key_line, study_keys, Problem, ProblemError};
use crate::studies::{accuracy, fnv1a, problem_hash};
use crate::{gait, observe, plot};
use argmin::core::observers::{Observe, ObserverMode};
use argmin::core::PopulationState;
use argmin::core::{
    CostFunction, Error as ArgminError, Executor, Problem as ArgminProblem, Solver, State,
    TerminationReason, TerminationStatus, KV,
};
use argmin::solver::neldermead::NelderMead;
use argmin::solver::particleswarm::{Particle, ParticleSwarm};
use rand_xoshiro::rand_core::{RngCore, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;
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

// ---------------------------------------------------------------------------------------------
// The driver
// ---------------------------------------------------------------------------------------------

/// Errors of the optimiser (study-file errors are [`StudyError`]).
#[derive(Debug, thiserror::Error)]
pub enum OptimizeError {
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
    /// Rows before this run written under another key ([`Study::row_hash`]: another base
    /// problem or objective settings; never reused).
    pub rows_other_base: usize,
    /// An incomplete last row of `history.csv` was dropped.
    pub dropped_partial_row: bool,
    /// The starting point's evaluation.
    pub initial: Evaluation,
    /// The finished evaluation within the heading limit with the lowest objective among those
    /// visited in this run, if any.
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
    /// The ensemble check of the best point against the runner-up (`Study::ensemble`).
    pub check: Option<OptimumCheck>,
}
