//! `slither optimize`: the gait design study (Nelder-Mead or particle swarm over stress, width
//! and speed).
use super::{lock_out, selection_log, study_accuracy};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use slither::studies;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Study file (TOML): the base problem, the bounds and the budget.
    pub study: PathBuf,
    /// Output directory (created if absent).
    #[arg(long, default_value = "out_optimize")]
    pub out: PathBuf,
    /// No progress bar and no log lines.
    #[arg(long)]
    pub quiet: bool,
    /// At the end, re-run the best point and the runner-up K times each with small
    /// perturbations (as `slither run --ensemble K`) and report in optimum.json (`ensemble`)
    /// whether the improvement is larger than the spread; K in [2, 1000].
    #[arg(long, value_name = "K")]
    pub ensemble: Option<usize>,
    /// Seed of `--ensemble` (the runner-up's ensemble uses seed + 1).
    #[arg(long, default_value_t = slither::studies::ensemble::SEED, requires = "ensemble")]
    pub ensemble_seed: u64,
    /// Change a key for this study, validated like the file: keys of `[study]`,
    /// `[optimize]` and `[accuracy]` edit the study file (`--set study.max_evaluations=60`),
    /// every other key its base problem (`--set rod.elements=100`). Repeatable. Rows of
    /// `history.csv` simulated under other settings are simulated again.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<slither::problem::set::Setting>,
}

/// Progress of a study: an indicatif bar over evaluations on a terminal, else one line per
/// evaluation on stderr (nothing with --quiet).
struct StudyProgress {
    bar: Option<ProgressBar>,
    lines: bool,
    max: usize,
    done: usize,
    /// The search space (which parameters the log lines name).
    space: studies::optimize::Space,
}

impl StudyProgress {
    fn say(&self, line: String) {
        match &self.bar {
            Some(b) => b.println(line),
            None if self.lines => eprintln!("{line}"),
            None => {}
        }
    }
}

impl studies::optimize::EvaluationObserver for StudyProgress {
    fn started(&mut self, count: usize, p: &studies::optimize::GaitParams, cached: bool) {
        if let Some(b) = &self.bar {
            b.set_message(format!(
                "eval {count}/{}: {}{}",
                self.max,
                self.space.describe(p),
                if cached { " (cached)" } else { "" }
            ));
        }
    }

    fn progress(&mut self, fraction: f64) {
        if let Some(b) = &self.bar {
            b.set_position((self.done as f64 * 100.0 + fraction * 100.0) as u64);
        }
    }

    fn finished(&mut self, count: usize, e: &studies::optimize::Evaluation, reused: bool) {
        self.done = count;
        if let Some(b) = &self.bar {
            b.set_position(self.done as u64 * 100);
        }
        let source = if reused {
            "reused from history.csv".to_string()
        } else {
            format!("{:.1} s", e.wall_time_s)
        };
        let result = match e.status {
            studies::optimize::Status::Ok => format!(
                "v_s = {:.5} m/s, v_s/v_m = {:.4}, {:.1} deg, Wr_max = {:.3}, regime {}{}",
                e.v_s,
                e.v_s_over_v_m,
                e.displacement_angle_deg,
                e.writhe_max,
                e.regime,
                e.periodic
                    .map_or(String::new(), |c| format!("; {}", c.describe()))
            ),
            studies::optimize::Status::Failed => format!("FAILED: {}", e.reason),
        };
        self.say(format!(
            "eval {count}/{} (row {}): {} (G = {:.3}) -> {result} [{source}]",
            self.max,
            e.eval,
            self.space.describe(&e.point),
            e.g
        ));
    }
}

pub fn optimize(args: &Args) -> ExitCode {
    let (path, out, quiet) = (args.study.as_path(), args.out.as_path(), args.quiet);
    let settings: Vec<&slither::problem::set::Setting> = args.set.iter().collect();
    let mut study = match studies::optimize::load_study_with(path, &settings) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let _lock = match lock_out(out) {
        Ok(l) => l,
        Err(code) => return code,
    };
    if let Err(code) = super::guard::check_writer(out, super::guard::Writer::Optimize) {
        return code;
    }
    if let Some(k) = args.ensemble {
        if !(2..=1000).contains(&k) {
            eprintln!("error: --ensemble {k} is not allowed: must be an integer in [2, 1000] (runs per point)");
            return ExitCode::from(2);
        }
        study.ensemble = Some(studies::ensemble::Spec {
            seed: args.ensemble_seed,
            ..studies::ensemble::Spec::new(k)
        });
    }
    let prepared = studies::optimize::prepare_accuracy(&mut study, out, &mut selection_log(quiet));
    if let Err(code) = study_accuracy(out, quiet, prepared, study.chosen.as_ref()) {
        return code;
    }
    let show_bar = !quiet && std::io::stderr().is_terminal();
    let bar = show_bar.then(|| {
        let b = ProgressBar::with_draw_target(
            Some(study.max_evaluations as u64 * 100),
            ProgressDrawTarget::stderr(),
        );
        b.set_style(
            ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {percent}% {msg}").unwrap(),
        );
        b
    });
    let mut progress = StudyProgress {
        bar,
        lines: !quiet,
        max: study.max_evaluations,
        done: 0,
        space: study.space.clone(),
    };
    let history = out.join(studies::optimize::HISTORY_FILE);
    announce(path, &study, &history, &mut progress);
    let result = studies::optimize::optimize(&study, out, &mut progress);
    if let Some(b) = progress.bar.take() {
        b.finish_and_clear();
    }
    let r = match result {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(match e {
                studies::optimize::OptimizeError::History { .. } => 2,
                _ => 1,
            });
        }
    };
    let Some(best) = &r.best else {
        no_best(path, &study, &r, &history);
        return ExitCode::from(3);
    };
    // The best evaluation again as a run directory (figures, tracks, movie) in best/.
    let best_run = super::run::rerun_into(
        &study.problem_at(&best.point),
        path,
        &out.join("best"),
        quiet,
        true,
        "best evaluation",
    );
    if let Err(code) = best_run {
        return code;
    }
    if !quiet {
        report(path, out, &study, &r, best, &history);
    }
    ExitCode::SUCCESS
}

/// The lines that open a study: resuming, the method, the space and the budget.
fn announce(
    path: &Path,
    study: &studies::optimize::Study,
    history: &Path,
    progress: &mut StudyProgress,
) {
    let names: Vec<String> = study
        .space
        .dims
        .iter()
        .map(|d| {
            format!(
                "{} in [{}, {}] {}",
                d.param.key(),
                d.lo,
                d.hi,
                d.param.unit()
            )
        })
        .collect();
    if history.exists() {
        progress.say(format!(
            "{}: resuming with {}: evaluations already in it are reused, not simulated again",
            path.display(),
            history.display()
        ));
    }
    let method = match study.method {
        studies::optimize::SearchMethod::NelderMead if study.starts > 1 => {
            format!("Nelder-Mead ({} starts)", study.starts)
        }
        studies::optimize::SearchMethod::NelderMead => "Nelder-Mead".to_string(),
        studies::optimize::SearchMethod::ParticleSwarm => format!(
            "particle swarm ({} particles per generation, in parallel)",
            study.particles
        ),
    };
    progress.say(format!(
        "{}: {method} over {}; at most {} evaluations of {} ({} each)",
        path.display(),
        names.join(", "),
        study.max_evaluations,
        study.base_path.display(),
        match study.duration_periods {
            Some(n) => format!("{n} launch periods"),
            None => format!("{} pulse times L/v_m", study.duration_pulses),
        }
    ));
}

/// Why a study found no best evaluation.
fn no_best(
    path: &Path,
    study: &studies::optimize::Study,
    r: &studies::optimize::Report,
    history: &Path,
) {
    if let (Some(max), true) = (study.max_heading_deg, r.failed < r.simulations + r.reused) {
        eprintln!(
            "error: {}: no finished run headed within max_heading_deg = {max} degrees of the initial head direction ({} evaluations); see {}",
            path.display(),
            r.evaluations,
            history.display()
        );
    } else {
        eprintln!(
            "error: {}: every simulation failed ({} evaluations); see {}",
            path.display(),
            r.evaluations,
            history.display()
        );
    }
}

/// What a study did and found: resume notes, counts, the start, the best, the ensemble check and
/// the bounds the optimum lies on.
fn report(
    path: &Path,
    out: &Path,
    study: &studies::optimize::Study,
    r: &studies::optimize::Report,
    best: &studies::optimize::Evaluation,
    history: &Path,
) {
    if r.dropped_partial_row {
        eprintln!(
            "note: an incomplete last row of {} was dropped",
            history.display()
        );
    }
    if r.rows_other_base > 0 {
        eprintln!(
            "note: {} rows of {} were written for another base problem (its effective content) or under another objective, turn_penalty or stationary_penalty, and were not reused: those points are simulated again",
            r.rows_other_base,
            history.display()
        );
    }
    let i = &r.initial;
    eprintln!(
        "{}: {} evaluations ({} simulated, {} reused from {}, {} repeated, {} failed) in {:.1} s; {}",
        path.display(),
        r.evaluations,
        r.simulations,
        r.reused,
        history.display(),
        r.repeats,
        r.failed,
        r.wall_time_s,
        r.termination
    );
    eprintln!(
        "start: {}: v_s = {:.5} m/s (v_s/v_m = {:.4}), regime {}",
        study.space.describe(&i.point),
        i.v_s,
        i.v_s_over_v_m,
        i.regime
    );
    eprintln!(
        "best:  {} (G = {:.3}, W = {:.1}): v_s = {:.5} m/s (v_s/v_m = {:.4}), {:.1} deg off the head direction, writhe max {:.3} mean {:.3} turns, regime {}; wrote {}",
        study.space.describe(&best.point),
        best.g,
        best.w,
        best.v_s,
        best.v_s_over_v_m,
        best.displacement_angle_deg,
        best.writhe_max,
        best.writhe_mean,
        best.regime,
        out.display()
    );
    if let Some(c) = &best.periodic {
        eprintln!("       {}", c.describe());
    }
    if let Some(c) = &r.check {
        let say = |e: &studies::optimize::EnsembleOf| {
            e.ensemble_objective
                .map_or("no finished member".to_string(), |s| {
                    format!(
                        "objective {:.5} ± {} (min {:.5}, max {:.5})",
                        s.mean,
                        s.sd.map_or("undefined".into(), |sd| format!("{sd:.5}")),
                        s.min,
                        s.max
                    )
                })
        };
        eprintln!(
            "ensemble of {} (best, eval {}), objective \"{}\" (lower is better): {}",
            c.runs,
            c.best.eval,
            c.objective,
            say(&c.best)
        );
        match (&c.runner_up, c.improvement, c.ranges_separate) {
            (Some(u), Some(imp), Some(separate)) => eprintln!(
                "ensemble of {} (runner-up, eval {}): {}; improvement {:.5} against spread {}: {}; {}",
                c.runs,
                u.eval,
                say(u),
                imp,
                c.spread.map_or("undefined".into(), |s| format!("{s:.5}")),
                match c.improvement_exceeds_spread {
                    Some(true) => "the improvement exceeds the spread",
                    Some(false) => "the improvement is within the spread",
                    None => "no spread to compare with",
                },
                if separate {
                    "every perturbed run of the best scores better than every one of the runner-up"
                } else {
                    "the two ensembles overlap"
                }
            ),
            _ => eprintln!("no runner-up to compare with"),
        }
    }
    for (param, side) in studies::optimize::on_bound(study, r) {
        eprintln!(
            "note: the optimum lies on the {side} bound of {param} (within {} of the range): widen optimize.{param} to follow it",
            studies::optimize::ON_BOUND_FRACTION
        );
    }
}
