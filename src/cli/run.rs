//! `slither run`: simulate a problem file and write its results, figures and summary.
use super::{lock_out, model_label};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use slither::studies::{accuracy::selection, ensemble};
use slither::{output, pipeline, problem};
use std::cell::RefCell;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

#[derive(clap::Args)]
pub struct Args {
    /// Problem file (TOML, SI units).
    pub problem: PathBuf,
    /// Output directory (created if absent).
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Skip the PNG figures, the movie, the tracks and the ParaView export (with --movie: all
    /// but the movie).
    #[arg(long)]
    pub no_plots: bool,
    /// Write movie.gif even when the problem file says `[output] movie = false`, and with
    /// --no-plots (then the movie alone).
    #[arg(long)]
    pub movie: bool,
    /// Run even above the size limits (steps, stored frames, post-processing; see the
    /// README's "Limits").
    #[arg(long)]
    pub force: bool,
    /// Refine the mesh and the step (or adaptive BDF2's tolerance) until the estimated
    /// relative error of v_s/v_m is below this, e.g. 0.01, and run that model (overrides
    /// `[accuracy] target`; scenes with ground and gait; in [1e-4, 0.5]).
    #[arg(long)]
    pub accuracy: Option<f64>,
    /// Also run the scene K times with small independent perturbations (friction, initial
    /// shape, step; in parallel) and write the spread of every scalar observable to
    /// `summary.json` (`ensemble`); K in [1, 1000]. Not with an accuracy target.
    #[arg(long, value_name = "K")]
    pub ensemble: Option<usize>,
    /// Seed of `--ensemble` (each member's own seed is recorded in `summary.json`).
    #[arg(long, default_value_t = ensemble::SEED, requires = "ensemble")]
    pub ensemble_seed: u64,
    /// Change a key of the problem file for this run, validated like the file:
    /// `--set rod.length=1.5`, `--set gait.centers[1]=0.3`, `--set gait.kind=s-start`.
    /// Repeatable; applied in order.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<problem::set::Setting>,
    /// Write the problem this run simulates (the file with `--set` applied, every default
    /// filled in; with an accuracy target, the model it chose) to FILE as a problem file.
    #[arg(long, value_name = "FILE")]
    pub dump_problem: Option<PathBuf>,
    /// With --ensemble K: run only member M (from 0, as `members[].index` in summary.json) of
    /// that ensemble, perturbed exactly as it was, as an ordinary run into --out (its
    /// figures, tracks and movie; --no-plots skips them).
    #[arg(long, value_name = "M", requires = "ensemble")]
    pub member: Option<usize>,
}

/// Write `p` to `file` as a problem file with a header naming where it came from.
pub fn dump_problem(file: &Path, p: &problem::Problem, from: &str) -> Result<(), ExitCode> {
    let text = format!(
        "# The effective problem of {from}, written by slither {} (every key, defaults filled in).\n{}",
        env!("CARGO_PKG_VERSION"),
        p.to_toml()
    );
    std::fs::write(file, text).map_err(|e| {
        eprintln!(
            "error: --dump-problem {}: cannot write: {e}",
            file.display()
        );
        ExitCode::from(1)
    })
}

/// How `--set` changed a file, for messages: ` with --set a=1 --set b=2`, or "".
pub fn settings_label(set: &[problem::set::Setting]) -> String {
    set.iter().map(|s| format!(" --set {}", s.arg)).collect()
}

pub fn run(args: &Args) -> ExitCode {
    let (path, out) = (args.problem.as_path(), args.out.as_path());
    let quiet = args.quiet;
    let settings: Vec<&problem::set::Setting> = args.set.iter().collect();
    let p = match problem::load_for_run_with(path, args.force, &settings) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let mut req = pipeline::Request::new(p, path);
    req.accuracy = args.accuracy;
    req.ensemble = args.ensemble.map(|k| ensemble::Spec {
        seed: args.ensemble_seed,
        ..ensemble::Spec::new(k)
    });
    if let Err(e) = req.validate("--accuracy") {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    let Some(req) = member_request(args, req) else {
        return ExitCode::from(2);
    };
    let from = run_origin(args);
    if let (Some(file), None) = (&args.dump_problem, req.target()) {
        if let Err(code) = dump_problem(file, &req.problem, &from) {
            return code;
        }
    }
    let _lock = match lock_out(out) {
        Ok(l) => l,
        Err(code) => return code,
    };
    if let Err(code) = super::guard::check_writer(out, super::guard::Writer::Run) {
        return code;
    }
    // The outputs are written into a staging folder and swapped in when complete: an
    // interrupted or killed rerun leaves the previous results as they were.
    let staging = match output::staging::Staging::new(out) {
        Ok(st) => st,
        Err(e) => {
            eprintln!(
                "error: {}: cannot create the staging folder: {e}",
                out.display()
            );
            return ExitCode::from(1);
        }
    };
    super::signals::stop_runs();
    let show = !quiet && std::io::stderr().is_terminal();
    let mut run = match simulate(args, &req, show) {
        Ok(r) => r,
        Err(code) => return code,
    };
    if let Some(r) = &run.summary.accuracy {
        if let Some(file) = &args.dump_problem {
            if let Err(code) = dump_chosen(file, &req.problem, r, &from) {
                return code;
            }
        }
        if !quiet {
            eprintln!("{}", accuracy_line(r));
        }
    }
    let interrupted = run.outcome.interrupted;
    if interrupted && staging.has_previous() {
        eprintln!(
            "{}: interrupted ({}) at t = {} s; nothing written, the previous results in {} are kept",
            path.display(),
            super::signals::name(),
            run.outcome.state.t,
            out.display()
        );
        return super::signals::exit_code();
    }
    if let (Some(spec), false, None) = (&req.ensemble, interrupted, args.member) {
        let e = run.add_ensemble(&req, spec, &|done, n| {
            if show {
                eprint!("\rensemble: {done}/{n} runs");
            }
        });
        if !quiet {
            eprintln!("{}{}", if show { "\n" } else { "" }, ensemble::describe(e));
        }
    }
    let hurry = match write(args, &run, &staging) {
        Ok(hurry) => hurry,
        Err(code) => return code,
    };
    if let Err(e) = staging.commit() {
        eprintln!(
            "error: {}: cannot move the results into place: {e}",
            out.display()
        );
        return ExitCode::from(1);
    }
    closing(args, &run, hurry)
}

/// The request of `--member M` (the member's problem, friction and step perturbed, and its
/// initial shape's perturbation for the model), or `req` itself without `--member`; `None`
/// after the message when M is not a member.
fn member_request(args: &Args, mut req: pipeline::Request) -> Option<pipeline::Request> {
    match (args.member, args.ensemble) {
        (Some(m), Some(k)) if m >= k => {
            eprintln!(
                "error: --member {m} is not a member of --ensemble {k}: members are 0 to {}",
                k - 1
            );
            None
        }
        (Some(m), Some(k)) => {
            let seed = ensemble::member_seed(args.ensemble_seed, m);
            let pert = ensemble::Perturbation::default();
            if !args.quiet {
                eprintln!(
                    "{}: member {m} of an ensemble of {k} (seed {seed}, step factor {:.4})",
                    args.problem.display(),
                    ensemble::applied_step_factor(&req.problem, &pert, m, k)
                );
            }
            req.problem = ensemble::member_problem(&req.problem, &pert, seed, m, k);
            req.perturbation = Some((pert, seed));
            Some(req)
        }
        _ => Some(req),
    }
}

/// Where the run's problem came from, for `--dump-problem`'s header: the file, its `--set`s
/// and, for `--member`, how to rerun the member.
fn run_origin(args: &Args) -> String {
    let mut from = format!("{}{}", args.problem.display(), settings_label(&args.set));
    if let (Some(m), Some(k)) = (args.member, args.ensemble) {
        // The member's friction and step are in its problem; its initial shape's perturbation
        // is drawn on the model from the seed, so the file alone is not the member.
        let seed = ensemble::member_seed(args.ensemble_seed, m);
        from += &format!(
            ", member {m} of --ensemble {k} (seed {seed}; its initial-shape perturbation is not in this file: rerun the member with --ensemble {k} --member {m} --ensemble-seed {})",
            args.ensemble_seed
        );
    }
    from
}

/// The pipeline's simulation with the progress bars (shown on a terminal) and the
/// selection's lines (unless `--quiet`), and the journal of an accuracy selection.
fn simulate(args: &Args, req: &pipeline::Request, show: bool) -> Result<pipeline::Run, ExitCode> {
    let quiet = args.quiet;
    // The stepping's bar, then the post-processing's (topology of every frame), each shown
    // once its part has taken over a second.
    let stepping = RefCell::new(LateBar::new(
        show,
        Some(Instant::now()),
        "{elapsed_precise} [{bar:40}] {percent}% eta {eta}",
    ));
    let mut post_bar = LateBar::new(
        show,
        None,
        "{elapsed_precise} [{bar:40}] {percent}% post-processing (topology of every frame) eta {eta}",
    );
    let mut log = |line: &str| {
        if !quiet {
            eprintln!("{line}")
        }
    };
    // Finished selection runs are kept in DIR/accuracy_runs.jsonl and reused by a rerun of
    // the same file with the same build.
    let mut journal = None;
    if req.target().is_some() {
        let journal_path = args.out.join(selection::JOURNAL_FILE);
        journal = accuracy_journal_key(&args.problem)
            .map(|k| selection::Journal::open(&journal_path, &k));
        if let Some(j) = journal.as_ref().filter(|j| !j.is_empty()) {
            log(&format!(
                "accuracy: {} finished runs of this file in {}",
                j.len(),
                journal_path.display()
            ));
        }
    }
    let hooks = pipeline::Hooks {
        progress: &mut |frac| stepping.borrow_mut().set(frac),
        post: &mut |frac| {
            stepping.borrow_mut().clear();
            post_bar.set(frac);
        },
        log: &mut log,
    };
    let run = pipeline::simulate(req, journal.as_mut(), hooks);
    stepping.borrow_mut().clear();
    post_bar.clear();
    run.map_err(|e| {
        eprintln!("error: {e}");
        ExitCode::from(2)
    })
}

/// The line that says which model an accuracy target chose.
fn accuracy_line(r: &output::AccuracyReport) -> String {
    format!(
        "accuracy {}: chose {} elements, {}: estimated error {:.2e} (time {:.2e}, mesh {:.2e}){}; {} runs of {:.1} s in all, {:.1} s of them probes, {:.1} s elapsed",
        r.target,
        r.elements,
        model_label(r.dt, r.error_tolerance),
        r.estimated_error,
        r.time_error,
        r.mesh_error,
        if r.met { "" } else { ", ABOVE the target (refinement limits reached)" },
        r.runs.len(),
        r.wall_time_total_s,
        r.probes_wall_time_s,
        r.elapsed_s
    )
}

/// `--dump-problem` of the model an accuracy target chose.
fn dump_chosen(
    file: &Path,
    p: &problem::Problem,
    r: &output::AccuracyReport,
    from: &str,
) -> Result<(), ExitCode> {
    use selection::Resolution;
    let res = match (r.error_tolerance, r.dt) {
        (Some(tol), _) => Resolution::Tolerance(tol),
        (None, Some(h)) => Resolution::Step(h),
        (None, None) => unreachable!("a chosen model has a step or a tolerance"),
    };
    let chosen = selection::accuracy_problem(p, r.elements, res);
    dump_problem(
        file,
        &chosen,
        &format!("{from} (the model accuracy {} chose)", r.target),
    )
}

/// Write the run into the staging folder: the data at once; after SIGTERM or SIGHUP (Slurm
/// kills the job 30 s after SIGTERM), including one that came after the simulation, without
/// figures and movie. Returns whether it hurried so.
fn write(
    args: &Args,
    run: &pipeline::Run,
    staging: &output::staging::Staging,
) -> Result<bool, ExitCode> {
    let (path, out) = (args.problem.as_path(), args.out.as_path());
    let stage = staging.dir();
    if let Err(e) = run.write_data(stage) {
        eprintln!("error: {}: cannot write results: {e}", out.display());
        return Err(ExitCode::from(1));
    }
    let files = pipeline::Files {
        plots: !args.no_plots,
        movie: args.movie,
    };
    let hurry = super::signals::hurry();
    if hurry && (files.plots || files.movie) {
        eprintln!(
            "{}: interrupted ({}): figures and movie skipped",
            path.display(),
            super::signals::name()
        );
    }
    if !hurry {
        if let Err(e) = run.write_figures(stage, files) {
            eprintln!("error: {}: {e}", out.display());
            return Err(ExitCode::from(1));
        }
    }
    Ok(hurry)
}

/// The closing lines and the exit code of a written run (`hurry`: written without figures
/// after a signal).
fn closing(args: &Args, run: &pipeline::Run, hurry: bool) -> ExitCode {
    let (path, out) = (args.problem.as_path(), args.out.as_path());
    let (o, summary) = (&run.outcome, &run.summary);
    if hurry && !o.interrupted {
        eprintln!(
            "{}: {} came after the simulation: its results are written to {}, without figures",
            path.display(),
            super::signals::name(),
            out.display()
        );
        return super::signals::exit_code();
    }
    if o.interrupted {
        eprintln!(
            "{}: interrupted ({}) at t = {} s; results up to then written to {} (status \"interrupted\")",
            path.display(),
            super::signals::name(),
            o.state.t,
            out.display()
        );
        return super::signals::exit_code();
    }
    if let Some(e) = &o.error {
        eprintln!(
            "error: {}: {e}; results up to t = {} s written to {}",
            path.display(),
            o.state.t,
            out.display()
        );
        return ExitCode::from(3);
    }
    if !args.quiet {
        report(path, out, summary);
    }
    if let Some(r) = summary.accuracy.as_ref().filter(|r| !r.met) {
        // Printed even under --quiet: the answer is written, but not to the accuracy asked.
        eprintln!(
            "{}: accuracy target {} NOT met: estimated error {:.2e} with {} elements, {} (refinement limits reached); results written to {} (exit {ACCURACY_NOT_MET})",
            path.display(),
            r.target,
            r.estimated_error,
            r.elements,
            model_label(r.dt, r.error_tolerance),
            out.display()
        );
        return ExitCode::from(ACCURACY_NOT_MET);
    }
    ExitCode::SUCCESS
}

/// What a finished run found: speed and regime, self-contact, the periodic analysis.
fn report(path: &Path, out: &Path, summary: &output::Summary) {
    let ob = summary.observables.as_ref().unwrap();
    eprintln!(
        "{}: {} steps in {:.2} s, {:.2} Newton iterations/step, max strain {:.2e}; v_s = {:.4} m/s (v_s/v_m = {:.3}), regime {}; wrote {}",
        path.display(),
        summary.steps,
        summary.wall_time_s,
        summary.newton_iterations_mean,
        summary.max_strain,
        ob.v_s,
        ob.v_s_over_v_m,
        ob.regime,
        out.display()
    );
    let sc = &summary.self_contact;
    match sc.closest_over_a {
        Some(c) if !sc.enabled && c < 1.0 => eprintln!(
            "self-contact off: parts of the body came {c:.4} a apart (centrelines), closer than a: the body passed through itself"
        ),
        Some(c) if sc.active_steps > 0 => eprintln!(
            "self-contact: closest pair {c:.4} a apart; {} steps with pairs within the activation gap, at most {} at once, largest pair force {:.3} N",
            sc.active_steps, sc.max_pairs, sc.max_force
        ),
        _ => {}
    }
    if let Some(p) = &summary.periodic {
        let miss = p.missed();
        eprintln!(
            "periodic: {} cycles after {} settling; broadside >= {:.1} deg, |turn| <= {:.1} deg/cycle, displacement >= {:.3} L/cycle, stationary contact share >= {:.2}; lateral speed {:.3} v_m; sidewinding: {}",
            p.cycles.len(),
            p.settling_cycles,
            p.broadside_deg_min,
            p.turn_deg_max_abs,
            p.displacement_over_length_min,
            p.stationary_contact_share_min,
            p.lateral_speed_over_v_m,
            if p.sidewinding { "yes".to_string() } else { format!("no ({miss})") }
        );
    }
}

/// Exit code of a run whose accuracy target was not met (its results are written, with
/// `"met": false` in `summary.json`'s `accuracy` block).
pub const ACCURACY_NOT_MET: u8 = 4;

/// A progress bar on stderr that appears once its task has run for a second (never when
/// `show` is false): the task's start is given, or taken at the first report.
struct LateBar {
    show: bool,
    start: Option<Instant>,
    template: &'static str,
    bar: Option<ProgressBar>,
}

impl LateBar {
    fn new(show: bool, start: Option<Instant>, template: &'static str) -> Self {
        LateBar {
            show,
            start,
            template,
            bar: None,
        }
    }

    /// Report the fraction done.
    fn set(&mut self, frac: f64) {
        if !self.show {
            return;
        }
        let start = *self.start.get_or_insert_with(Instant::now);
        if self.bar.is_none() && start.elapsed() > Duration::from_secs(1) {
            let b = ProgressBar::with_draw_target(Some(1000), ProgressDrawTarget::stderr());
            b.set_style(ProgressStyle::with_template(self.template).unwrap());
            self.bar = Some(b);
        }
        if let Some(b) = &self.bar {
            b.set_position((frac * 1000.0) as u64);
        }
    }

    /// Remove the bar (if it appeared).
    fn clear(&mut self) {
        if let Some(b) = self.bar.take() {
            b.finish_and_clear();
        }
    }
}

/// Simulate `p` again into the run directory `dir` with figures, tracks and movie (the best
/// evaluation of `slither optimize`, a cell of `slither phase --cell`) through the run
/// pipeline, after the guard that `dir` holds no study's results; `label` is the file named
/// as the problem, `what` says what is re-run in the closing line.
pub fn rerun_into(
    p: &problem::Problem,
    label: &Path,
    dir: &Path,
    quiet: bool,
    plots: bool,
    what: &str,
) -> Result<pipeline::Run, ExitCode> {
    let _lock = lock_out(dir)?;
    super::guard::check_writer(dir, super::guard::Writer::Run)?;
    let files = if plots {
        pipeline::Files::ALL
    } else {
        pipeline::Files::DATA
    };
    match pipeline::run_into(p, label, dir, files) {
        Ok((r, movie)) => {
            if !quiet {
                let ob = r.summary.observables.as_ref();
                eprintln!(
                    "{what}: {} steps in {:.2} s; v_s = {:.4} m/s, regime {}{}; wrote {}",
                    r.summary.steps,
                    r.summary.wall_time_s,
                    ob.map_or(f64::NAN, |o| o.v_s),
                    ob.map_or("-".to_string(), |o| o.regime.to_string()),
                    movie.map_or(String::new(), |m| format!(
                        " (movie: {} frames, {:.1} MB, {:.2} s)",
                        m.frames,
                        m.bytes as f64 / 1e6,
                        m.seconds
                    )),
                    dir.display()
                );
            }
            if let Some(e) = &r.summary.error {
                eprintln!("note: {what}: the run stopped early: {e}");
            }
            Ok(r)
        }
        Err(e) => {
            eprintln!("error: {what}: {e}");
            Err(ExitCode::from(1))
        }
    }
}

/// The key of the accuracy journal's runs of the problem file at `path` by this build (`None`
/// when the file or the executable cannot be read: the selection then keeps no journal).
fn accuracy_journal_key(path: &std::path::Path) -> Option<String> {
    let text = std::fs::read_to_string(path).ok()?;
    let exe = std::fs::read(std::env::current_exe().ok()?).ok()?;
    Some(selection::Journal::key(&text, &exe))
}
