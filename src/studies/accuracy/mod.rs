//! `[accuracy]` in study files (`slither optimize`, `slither phase`): the model (mesh and
//! time resolution: implicit Euler's step, or adaptive BDF2's error tolerance when the base
//! file asks for `integrator = "bdf2"`) is chosen once, on the study's base scene, by the selection
//! of `slither run --accuracy` ([`selection::select`]), and every evaluation or
//! cell then runs at that model.
//!
//! ```toml
//! [accuracy]
//! target = 0.01          # relative error of v_s/v_m, in [1e-4, 0.5]
//! max_elements = 400     # in [base rod.elements, 100000]; default 400
//! ```
//!
//! The keys and ranges are a problem file's `[accuracy]` table's
//! ([`crate::problem::check_accuracy`], checked against the base problem).
//!
//! **The base scene** is the base problem file as written (its gait values, its duration),
//! not an evaluation's or a cell's variant of it: the selection estimates the error there and
//! the choice is applied to every run of the study.
//!
//! **Record and resume.** The choice, with the selection's estimates and runs, is written to
//! `DIR/accuracy.json` ([`ACCURACY_FILE`]) before the study starts, and copied into
//! `phase.json` / `optimum.json` (`accuracy`). A rerun into the same directory reads
//! `accuracy.json` and reuses its choice, without selecting again, when the base file's hash,
//! `target` and `max_elements` are the recorded ones; otherwise it selects again and
//! overwrites it. The resume key of the study's rows (`base_hash` in `history.csv`,
//! `phase.csv`, `phase.json`, `optimum.json`) is then a hash of the base file's hash and the
//! chosen model, so rows of a run at another model (or without `[accuracy]`) are never reused.

pub mod selection;

use crate::problem::{AccuracySpec, Problem};
use selection::{accuracy_problem, select, Resolution};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The file in a study's output directory that records the chosen model.
pub const ACCURACY_FILE: &str = "accuracy.json";

/// A study's chosen model (`accuracy.json`, and `accuracy` in `phase.json` / `optimum.json`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StudyAccuracy {
    /// FNV-1a hash of the base file's text (hex) the choice was made on.
    pub base_file_hash: String,
    /// `[accuracy] target`.
    pub target: f64,
    /// `[accuracy] max_elements`.
    pub max_elements: usize,
    /// Chosen mesh (elements).
    pub elements: usize,
    /// Chosen fixed step of implicit Euler (s); absent for adaptive BDF2 (and in records
    /// written before implicit Euler could be chosen).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
    /// Chosen error tolerance of adaptive BDF2 (fraction of L per step); absent for implicit
    /// Euler.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error_tolerance: Option<f64>,
    /// The selection's report (estimates and every run, as `summary.json`'s `accuracy` of
    /// `slither run --accuracy`).
    pub selection: serde_json::Value,
}

impl StudyAccuracy {
    /// The chosen time resolution (a record with neither `dt` nor `error_tolerance` is not
    /// one this version wrote: `None`).
    pub fn resolution(&self) -> Option<Resolution> {
        Resolution::from_parts(self.dt, self.error_tolerance)
    }

    /// `base` at the chosen model: the chosen mesh and time resolution.
    pub fn apply(&self, base: &Problem) -> Problem {
        let res = self
            .resolution()
            .expect("a chosen model has a step or a tolerance");
        accuracy_problem(base, self.elements, res)
    }

    /// Resume key of the study's rows at this model, from the base file's hash (`u64`). The
    /// adaptive BDF2 key is the one of records written before implicit Euler could be chosen.
    pub fn row_hash(&self) -> u64 {
        let model = match self.resolution() {
            Some(Resolution::Tolerance(t)) => format!("error_tolerance {t:e}"),
            Some(Resolution::Step(h)) => format!("implicit dt {h:e}"),
            None => "unknown".into(),
        };
        crate::studies::fnv1a(
            format!("{} elements {} {model}", self.base_file_hash, self.elements).as_bytes(),
        )
    }
}

/// The model for `spec` on `base` (whose text hashes to `base_file_hash`, hex): the one
/// recorded in `out/accuracy.json` when it was chosen for the same base file, target and
/// `max_elements` (returned with `true`), else a new selection (returned with `false`), written
/// to `out/accuracy.json`. `log` gets one line per selection run.
pub fn choose(
    base: &Problem,
    base_file_hash: &str,
    spec: &AccuracySpec,
    out: &Path,
    log: &mut dyn FnMut(&str),
) -> std::io::Result<(StudyAccuracy, bool)> {
    let file = out.join(ACCURACY_FILE);
    if let Ok(text) = std::fs::read_to_string(&file) {
        if let Ok(old) = serde_json::from_str::<StudyAccuracy>(&text) {
            if old.base_file_hash == base_file_hash
                && old.resolution().is_some()
                && old.target == spec.target
                && old.max_elements == spec.max_elements
            {
                return Ok((old, true));
            }
        }
    }
    let sel = select(base, spec.target, spec.max_elements, log);
    let r = &sel.report;
    let chosen = StudyAccuracy {
        base_file_hash: base_file_hash.to_string(),
        target: spec.target,
        max_elements: spec.max_elements,
        elements: r.elements,
        dt: r.dt,
        error_tolerance: r.error_tolerance,
        selection: serde_json::to_value(r).map_err(std::io::Error::other)?,
    };
    std::fs::create_dir_all(out)?;
    let text = serde_json::to_string_pretty(&chosen).map_err(std::io::Error::other)?;
    crate::output::write_atomic(&file, (text + "\n").as_bytes())?;
    Ok((chosen, false))
}

/// Remove a previous run's `accuracy.json` from `out` (a study without `[accuracy]`), so no
/// record of another model is left beside its results.
pub fn forget(out: &Path) -> std::io::Result<()> {
    match std::fs::remove_file(out.join(ACCURACY_FILE)) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(e),
        _ => Ok(()),
    }
}
