//! The run pipeline: what one run of a problem does, in order, for every caller (`slither
//! run`, the best evaluation of `slither optimize` in `best/`, `slither phase --cell` and
//! Python's `run` and `save`):
//!
//! 1. **load and validate**: the problem file is parsed and checked by [`crate::problem`]
//!    (with the size limits: [`crate::problem::check_for_run`]); the request, an accuracy
//!    target or an ensemble, by [`Request::validate`];
//! 2. **choose the accuracy**: with a target, the accuracy selection
//!    ([`crate::studies::accuracy::selection`]) refines mesh and step and keeps the chosen model's run;
//! 3. **simulate and measure**: [`crate::observe::evaluate`] (or, after a selection,
//!    [`crate::observe::measure`] of the chosen run);
//! 4. **summarise**: [`Summary`] with the observables, the periodic analysis of a finished
//!    run, the accuracy report and the ensemble ([`Run::add_ensemble`]);
//! 5. **stage and write**: [`Run::save`] (or, for a caller that stages itself, [`Run::write_data`]
//!    and [`Run::write_figures`]): `summary.json`, `final.csv`, `trajectory.npz`, the figures,
//!    the ground tracks and `movie.gif`, written by [`crate::output`] into a staging folder
//!    and swapped in when complete ([`crate::output::staging`]).
//!
//! The library never prints: progress and the selection's lines go to the callbacks of
//! [`Hooks`].

use crate::model::Model;
use crate::observe::{self, Fields, Measure, Observed};
use crate::output::{self, staging::Staging, Summary};
use crate::plot::movie::MovieStats;
use crate::problem::{self, keys, Problem};
use crate::sim::Outcome;
use crate::studies::{accuracy::selection, ensemble};
use std::path::{Path, PathBuf};

/// The range of an accuracy target (relative error of `v_s/v_m`).
pub const ACCURACY_RANGE: std::ops::RangeInclusive<f64> = 1e-4..=0.5;
/// The range of an ensemble's size (runs).
pub const ENSEMBLE_RANGE: std::ops::RangeInclusive<usize> = 1..=1000;

/// What to run: a problem (loaded and validated), the file named as its source, and what the
/// run adds to a plain simulation.
#[derive(Clone, Debug)]
pub struct Request {
    /// The problem (for an ensemble member, the member's: [`ensemble::member_problem`]).
    pub problem: Problem,
    /// The file named as the problem in `summary.json` (its stem titles the movie).
    pub label: PathBuf,
    /// An accuracy target that overrides the problem's `[accuracy] target` (`--accuracy`).
    pub accuracy: Option<f64>,
    /// An ensemble to run beside the scene (`--ensemble K`).
    pub ensemble: Option<ensemble::Spec>,
    /// The initial-shape perturbation of an ensemble member and its seed, applied to the
    /// model (`--member M`).
    pub perturbation: Option<(ensemble::Perturbation, u64)>,
}

/// Why a request cannot run, or a run cannot be written.
#[derive(Debug, thiserror::Error)]
pub enum PipelineError {
    /// The request is not allowed (a bad target, a scene without what it needs): exit code 2.
    #[error("{0}")]
    Invalid(String),
    /// The scene cannot be simulated by its integrator: exit code 2.
    #[error("{label}: {source}", label = label.display())]
    Unsupported {
        /// The problem file.
        label: PathBuf,
        /// Cause.
        source: crate::integrator::explicit::Unsupported,
    },
    /// A file or folder could not be written: exit code 1.
    #[error("{0}")]
    Write(String),
}

impl Request {
    /// A plain run of `problem`, named `label`.
    pub fn new(problem: Problem, label: &Path) -> Self {
        Request {
            problem,
            label: label.into(),
            accuracy: None,
            ensemble: None,
            perturbation: None,
        }
    }

    /// Check the accuracy target (in [`ACCURACY_RANGE`], only for a dynamic scene with ground
    /// and gait) and the ensemble (size in [`ENSEMBLE_RANGE`], never with an accuracy
    /// target). `flag` names the accuracy override in messages (`--accuracy`, `accuracy`).
    pub fn validate(&self, flag: &str) -> Result<(), PipelineError> {
        let p = &self.problem;
        if let Some(a) = self.accuracy {
            if !(a.is_finite() && ACCURACY_RANGE.contains(&a)) {
                return Err(PipelineError::Invalid(format!(
                    "{flag} {a} is not allowed: must be in [{:e}, {}] (relative error of v_s/v_m)",
                    ACCURACY_RANGE.start(),
                    ACCURACY_RANGE.end()
                )));
            }
            if p.time.mode != problem::Mode::Dynamic
                || p.ground.is_none()
                || p.gait.kind == problem::Kind::None
            {
                return Err(PipelineError::Invalid(format!(
                    "{}: {flag} needs a dynamic scene with [ground] and a [gait] (it controls the error of v_s/v_m)",
                    self.label.display()
                )));
            }
        }
        if let Some(e) = &self.ensemble {
            let k = e.runs;
            if !ENSEMBLE_RANGE.contains(&k) {
                return Err(PipelineError::Invalid(format!(
                    "--ensemble {k} is not allowed: must be an integer in [{}, {}] (runs)",
                    ENSEMBLE_RANGE.start(),
                    ENSEMBLE_RANGE.end()
                )));
            }
            if self.target().is_some() {
                return Err(PipelineError::Invalid(format!(
                    "{}: --ensemble cannot be combined with an accuracy target (--accuracy or [accuracy])",
                    self.label.display()
                )));
            }
        }
        Ok(())
    }

    /// The accuracy target and the most elements its refinement may use: the override, else
    /// the problem's `[accuracy]` table (`None`: no selection).
    pub fn target(&self) -> Option<(f64, usize)> {
        let table = self.problem.accuracy.as_ref();
        self.accuracy
            .map(|t| {
                let max = table.map_or(keys::ACCURACY_MAX_ELEMENTS.int() as usize, |a| {
                    a.max_elements
                });
                (t, max)
            })
            .or(table.map(|a| (a.target, a.max_elements)))
    }
}

/// Where a run reports its progress (each may do nothing).
pub struct Hooks<'a> {
    /// The fraction of the simulation done.
    pub progress: &'a mut dyn FnMut(f64),
    /// The fraction of the post-processing (the topology of every frame) done.
    pub post: &'a mut dyn FnMut(f64),
    /// A line of the accuracy selection.
    pub log: &'a mut dyn FnMut(&str),
}

/// A finished (or failed) run: the model it ran, its outcome, the post-processed fields and
/// the summary; everything a run directory holds.
pub struct Run {
    /// The model run (after an accuracy selection, the chosen one).
    pub model: Model,
    /// The simulation's outcome.
    pub outcome: Outcome,
    /// The kymograph fields of the output frames.
    pub fields: Fields,
    /// `summary.json`: observables, periodic analysis, accuracy report and ensemble included.
    pub summary: Summary,
    /// The problem's `[output] movie`.
    pub movie: bool,
}

/// Simulate a validated request: choose the accuracy (with a target; `journal` keeps and
/// reuses the selection's runs), simulate, measure and summarise. An ensemble is added by
/// [`Run::add_ensemble`].
pub fn simulate(
    req: &Request,
    journal: Option<&mut selection::Journal>,
    hooks: Hooks<'_>,
) -> Result<Run, PipelineError> {
    let p = &req.problem;
    let (model, observed, report) = if let Some((target, max_elements)) = req.target() {
        let sel = selection::select_with(p, target, max_elements, journal, hooks.log);
        let (fields, observables) =
            observe::measure(&sel.model, &sel.outcome, Measure::Full, hooks.post);
        let observed = Observed {
            outcome: sel.outcome,
            fields,
            observables,
        };
        (sel.model, observed, Some(sel.report))
    } else {
        let mut model = Model::new(p);
        if let Some((pert, seed)) = &req.perturbation {
            ensemble::perturb_model(&mut model, pert, *seed);
        }
        let observed = observe::evaluate(&model, Measure::Full, hooks.progress, hooks.post)
            .map_err(|source| PipelineError::Unsupported {
                label: req.label.clone(),
                source,
            })?;
        (model, observed, None)
    };
    let Observed {
        outcome,
        fields,
        observables,
    } = observed;
    let mut summary = Summary::new(&req.label, &model, &outcome);
    summary.accuracy = report;
    summary.observables = Some(observables);
    if outcome.error.is_none() {
        summary.periodic = observe::periodic::of_outcome(&model, &outcome);
    }
    Ok(Run {
        model,
        outcome,
        fields,
        summary,
        movie: p.output.movie,
    })
}

/// What a run directory gets beside its data (`summary.json`, `final.csv`,
/// `trajectory.npz`).
#[derive(Clone, Copy, Debug)]
pub struct Files {
    /// The figures, the ParaView series and the ground tracks (`--no-plots` turns them off).
    pub plots: bool,
    /// `movie.gif` even when the problem says `[output] movie = false`, and without `plots`
    /// (then the movie alone; `--movie`).
    pub movie: bool,
}

impl Files {
    /// Everything `slither run` writes by default.
    pub const ALL: Files = Files {
        plots: true,
        movie: false,
    };
    /// The data alone.
    pub const DATA: Files = Files {
        plots: false,
        movie: false,
    };
}

impl Run {
    /// Run the ensemble `spec` of the request's problem beside this run and keep its spread
    /// in the summary (`report` gets the runs done and their number).
    pub fn add_ensemble(
        &mut self,
        req: &Request,
        spec: &ensemble::Spec,
        report: &(dyn Fn(usize, usize) + Sync),
    ) -> &ensemble::Ensemble {
        self.summary
            .ensemble
            .insert(ensemble::run(&req.problem, spec, report))
    }

    /// The title of the movie: the stem of the problem file.
    fn title(&self) -> String {
        Path::new(&self.summary.problem)
            .file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned())
    }

    /// The movie's label: the regime of a finished run, and whether it sidewinds.
    fn regime_label(&self) -> Option<String> {
        output::movie::movie_label(
            self.summary
                .observables
                .as_ref()
                .filter(|_| self.outcome.error.is_none())
                .map(|ob| ob.regime.to_string()),
            self.summary
                .periodic
                .as_ref()
                .map(|p| (p.sidewinding, p.lateral_speed_over_v_m)),
        )
    }

    /// Write the data files (`final.csv`, `trajectory.npz`, `summary.json`) into `dir`.
    pub fn write_data(&self, dir: &Path) -> std::io::Result<()> {
        let (m, o, fl) = (&self.model, &self.outcome, &self.fields);
        let extra = [
            ("elevation", fl.elevation.clone()),
            ("slip_speed", fl.slip.clone()),
            ("lambda", fl.lambda.clone()),
        ];
        output::write_final_csv(dir, m, o)
            .and_then(|_| output::write_trajectory(dir, m, &o.frames, &extra))
            .and_then(|_| output::write_summary(dir, &self.summary))
    }

    /// Write what `files` asks beside the data into `dir`: with `plots` the figures, ParaView
    /// series and tracks, and the movie when the problem or `files.movie` asks; without, the
    /// movie alone when `files.movie` asks. `Err` is the message. Returns what the movie took.
    pub fn write_figures(&self, dir: &Path, files: Files) -> Result<Option<MovieStats>, String> {
        let (m, o, fl) = (&self.model, &self.outcome, &self.fields);
        let (title, regime) = (self.title(), self.regime_label());
        if files.plots {
            let movie = files.movie || self.movie;
            output::rundir::write_plots(dir, m, o, fl, &title, regime, movie)
        } else if files.movie {
            let clip = output::movie::clip_from_run(m, &o.frames, fl, &title, regime);
            output::movie::write_movie(dir, "movie.gif", &clip, &Default::default())
                .map(Some)
                .map_err(|e| format!("cannot write the movie: {e}"))
        } else {
            Ok(None)
        }
    }

    /// Write the run directory `out` (which must exist; hold its lock,
    /// [`output::lock::OutLock`], and check its writer first): every file into a staging
    /// folder, swapped in when complete (a failure leaves the previous results). Returns what
    /// the movie took.
    pub fn save(&self, out: &Path, files: Files) -> Result<Option<MovieStats>, PipelineError> {
        let named =
            |e: &dyn std::fmt::Display| PipelineError::Write(format!("{}: {e}", out.display()));
        let staging = Staging::new(out)
            .map_err(|e| named(&format!("cannot create the staging folder: {e}")))?;
        self.write_data(staging.dir())
            .map_err(|e| named(&format!("cannot write results: {e}")))?;
        let movie = self
            .write_figures(staging.dir(), files)
            .map_err(|e| named(&e))?;
        staging
            .commit()
            .map_err(|e| named(&format!("cannot move the results into place: {e}")))?;
        Ok(movie)
    }
}

/// Simulate `p` and write its run directory `out` with every file (the best evaluation of
/// `slither optimize`, a cell of `slither phase --cell`): [`simulate`] then [`Run::save`],
/// silently. A run that stops early (a failed step) is written up to then; its summary says
/// so.
pub fn run_into(
    p: &Problem,
    label: &Path,
    out: &Path,
    files: Files,
) -> Result<(Run, Option<MovieStats>), PipelineError> {
    let req = Request::new(p.clone(), label);
    let hooks = Hooks {
        progress: &mut |_| {},
        post: &mut |_| {},
        log: &mut |_| {},
    };
    let run = simulate(&req, None, hooks)?;
    let movie = run.save(out, files)?;
    Ok((run, movie))
}
