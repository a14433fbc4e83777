//! The regime phase diagram (MODEL section 6): the locomotion regime (S, M, F, N, U; criteria
//! in [`crate::observe::regime`]) and the forward speed over scaled weight `W = rho g a^2 L^3 / B` and
//! scaled torque `G = Gamma a^3 L / B`.
//!
//! A phase file names a base problem with a gait and the grid:
//!
//! ```toml
//! [phase]
//! base = "s_start.toml"                 # problem file, relative to the phase file
//! weight = [100.0, 300.0, 1000.0]       # scaled weights W, each > 0
//! torque = [5.0, 10.0, 15.0, 20.0]      # scaled torques G, each >= 0
//! refine = false                        # bisect the boundaries between neighbouring cells
//! refine_steps = 3                      # bisection steps per neighbour pair, 1 to 8
//! ```
//!
//! `refine` (default `false`): after the grid, bisect every pair of neighbouring cells of
//! different regimes along the line joining them (a ray of constant `G` for neighbours in `W`,
//! of constant `W` for neighbours in `G`), `refine_steps` times (default
//! [`file::DEFAULT_STEPS`], an integer in 1 to [`file::MAX_STEPS`], checked
//! even when `refine = false`, which ignores it), simulating the base scene at each log-midpoint, and fit the boundary lines
//! through the bisected points instead of the cell midpoints ([`refine`]; the
//! simulations go to `refine.csv`). A sharded run (`--shard I/N`, `N > 1`) never refines: it
//! lacks the rest of the grid; [`merge()`] refines when the shards' phase file asked for it.
//!
//! `verify = { finer = true, perturbations = K }` (optional `seed`, `step`; [`file::Verify`]):
//! each cell is also run at half the step and twice the elements and `K` times perturbed
//! ([`crate::studies::ensemble`]); the reported label is the finest run's, `phase.csv` gains
//! the agreement of the runs, the spread of `v_s/v_m` and the labels at both resolutions
//! ([`cell::simulate_verified`]), and the boundaries are fitted through unanimous cells only
//! ([`sweep::confident_labels`], [`sweep::Exclusions`] in `boundaries.json`).
//!
//! `weight_via = "stiffness" | "gravity" | "density"` (default "stiffness") names the parameter
//! that sets `W`, and `similar = true` keeps the cells dynamically similar: `v_m L sqrt(rho A /
//! B)` the base's, the times scaled with `L / v_m` ([`file::cell_problem_with`]). The rest of
//! this paragraph is the default.
//!
//! Each cell keeps the base's geometry, density, gravity, friction, gait shape, pulse speed and
//! time stepping. `W` is set through the bending stiffness, `B = rho g a^2 L^3 / W`, with the
//! twist and stretching stiffnesses scaled by the same factor (so `C/B` and `EA a^2/B` stay the
//! base's); `G` through the muscle stress, `Gamma = G B / (a^3 L)`.
//!
//! Cells run in parallel (rayon) and each finished cell is appended to `phase.csv` at once, so
//! a sweep that is interrupted keeps every finished cell; a rerun into the same directory
//! reuses the rows whose base file (hashed) and `(W, G)` match and simulates only the rest. A
//! cell whose simulation fails is recorded with status `failed` and its reason, and is not
//! retried on resume (the failure is deterministic).

//!
//! Files: [`file`] the phase file and a cell's problem; [`cell`] a cell's simulation and
//! values; [`csv`] the rows of `phase.csv` and `refine.csv`; [`sweep`](mod@sweep) the sweep (whole or a
//! shard) and its end (boundaries, figures); [`boundaries`](mod@boundaries) the fitted boundary lines;
//! [`refine`] their bisection; [`merge`](mod@merge) the shards' union. The figures are drawn by
//! [`crate::plot::phase`].
pub mod allometry;
pub mod boundaries;
pub mod cell;
pub mod csv;
pub mod file;
pub mod gallery;
pub mod growth;
pub mod merge;
pub mod refine;
pub mod select;
pub mod sweep;

pub use boundaries::{boundaries, fit_boundaries, Boundary};
pub use cell::{cell_seed, simulate, simulate_verified, Cell, Verification};
pub use csv::{
    comparable_row, read_phase_csv, read_rows, verify_header, Format, PhaseCsv, Rows, HEADER,
    PERIODIC_COLUMNS, VERIFY_COLUMNS,
};
pub use file::{
    cell_problem, cell_problem_with, finer_problem, load, load_with, prepare_accuracy, Phase,
    Protocol, Verify, WeightVia,
};
pub use merge::{merge, Merged};
pub use sweep::{confident_labels, sweep, sweep_shard, Exclusions, RunInfo, Shard, Sweep};

use crate::plot;
use std::path::PathBuf;

/// Errors of a sweep's bookkeeping (the simulations' own failures are recorded in the cells).
#[derive(Debug, thiserror::Error)]
pub enum PhaseError {
    /// Reading or writing an output file failed.
    #[error("{file}: {source}")]
    Io {
        /// The file.
        file: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// An existing `phase.csv` that is not ours.
    #[error("{file}:{line}: not a row of a phase study (expected the columns {HEADER}); move the file away or choose another --out")]
    Csv {
        /// The file.
        file: PathBuf,
        /// 1-based line.
        line: usize,
    },
    /// A directory cannot be merged with the others.
    #[error("{dir}: cannot merge: {why}")]
    Merge {
        /// The directory.
        dir: PathBuf,
        /// Why.
        why: String,
    },
    /// The merged directories do not cover the grid.
    #[error("the shards miss {count} cells of the grid: {cells}; run the missing shards (or rerun them into their directories) and merge again")]
    Missing {
        /// Number of missing cells.
        count: usize,
        /// The first ten.
        cells: String,
    },
    /// A study CSV of another [`Format`] (with or without verification, with or without the
    /// periodic columns) than the study's: its rows cannot be mixed.
    #[error("{file}: {why} (its header is `{found}`; this study's is `{expected}`); move the file away or choose another --out")]
    Header {
        /// The file.
        file: PathBuf,
        /// What was refused, and why.
        why: String,
        /// The file's header.
        found: String,
        /// The study's header.
        expected: String,
    },
    /// A figure could not be drawn.
    #[error("{file}: {source}")]
    Plot {
        /// The figure.
        file: PathBuf,
        /// The plotting error.
        source: plot::PlotError,
    },
}
