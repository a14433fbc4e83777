//! The `slither` command line.
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use slither::model::Model;
use slither::{design, observe, output, problem, sim, topology};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

#[derive(Parser)]
#[command(
    name = "slither",
    version,
    about = "Snake locomotion: discrete elastic rods, implicit Euler, conic friction"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Simulate a problem file and write summary.json, final.csv and trajectory.npz.
    Run {
        /// Problem file (TOML, SI units).
        problem: PathBuf,
        /// Output directory (created if absent).
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
        /// Skip the PNG figures and the ParaView export.
        #[arg(long)]
        no_plots: bool,
        /// Run even above the size limits (steps, stored frames, post-processing; see the
        /// README's "Limits").
        #[arg(long)]
        force: bool,
        /// Run the cheapest model (adaptive BDF2 tolerance and mesh) whose estimated relative
        /// error of v_s/v_m is below this, e.g. 0.01 (overrides `[accuracy] target`; scenes
        /// with ground and gait; in [1e-4, 0.5]).
        #[arg(long)]
        accuracy: Option<f64>,
    },
    /// Twist, writhe and link of a framed curve given as CSV (x,y,z,d1x,d1y,d1z).
    Topology {
        /// CSV file with a header row.
        curve: PathBuf,
        /// The curve is closed (its last edge returns to the first node); adds `lk_gauss`.
        #[arg(long)]
        closed: bool,
    },
    /// Speed against accuracy of the implicit and the explicit (velocity Verlet) integrator:
    /// work-precision chart or stability map (CSV, JSON and PNG).
    Chart {
        #[command(subcommand)]
        which: ChartCmd,
    },
    /// Gait design: maximise the forward speed v_s over muscle stress, width and speed
    /// (argmin Nelder-Mead, one simulation per evaluation, or particle swarm, a generation
    /// in parallel); writes history.csv, optimum.json
    /// and figures. Rerunning with the same --out reuses the evaluations in history.csv.
    Optimize {
        /// Study file (TOML): the base problem, the bounds and the budget.
        study: PathBuf,
        /// Output directory (created if absent).
        #[arg(long, default_value = "out_optimize")]
        out: PathBuf,
        /// No progress bar and no log lines.
        #[arg(long)]
        quiet: bool,
    },
    /// Regime phase diagram over scaled weight W and scaled torque G (one simulation per
    /// cell, in parallel); writes phase.csv, boundaries.json and the regime map and Fig. 3
    /// charts (PNG and SVG), and with `refine = true` the boundary bisection's refine.csv.
    /// Rerunning with the same --out reuses the finished cells and refinement simulations.
    Phase {
        /// Phase file (TOML): the base problem and the W and G grids.
        file: PathBuf,
        /// Output directory (created if absent).
        #[arg(long, default_value = "out_phase")]
        out: PathBuf,
        /// No progress bar and no per-cell lines.
        #[arg(long)]
        quiet: bool,
        /// Run only shard I of N (cell k of the weight-major grid belongs to shard k % N + 1):
        /// for a job array; `slither merge` combines the shard directories. No figures.
        #[arg(long, value_name = "I/N")]
        shard: Option<design::phase::Shard>,
    },
    /// Combine the output directories of `slither phase --shard I/N` runs (one phase file and
    /// base problem) into one: the same phase.csv, phase.json and figures as an unsharded run,
    /// bisecting the boundaries into refine.csv when the phase file has `refine = true`.
    /// Refuses directories of another grid or base file and reports missing cells.
    Merge {
        /// Shard output directories.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Output directory (created if absent).
        #[arg(long)]
        out: PathBuf,
    },
}

/// Diagnostics of the library (`log` crate) on stderr, at debug level when `SLITHER_DEBUG` is
/// set (every Newton iteration), else warnings only.
struct StderrLog;

impl log::Log for StderrLog {
    fn enabled(&self, meta: &log::Metadata) -> bool {
        meta.level() <= log::max_level()
    }
    fn log(&self, record: &log::Record) {
        if self.enabled(record.metadata()) {
            eprintln!("{}", record.args());
        }
    }
    fn flush(&self) {}
}

/// Read the environment once: the logger and the solver overrides.
fn configure_from_env() {
    static LOGGER: StderrLog = StderrLog;
    if log::set_logger(&LOGGER).is_ok() {
        log::set_max_level(if std::env::var_os("SLITHER_DEBUG").is_some() {
            log::LevelFilter::Debug
        } else {
            log::LevelFilter::Warn
        });
    }
    problem::set_overrides(problem::Overrides {
        contact: std::env::var("SLITHER_CONTACT")
            .ok()
            .map(|v| match v.as_str() {
                "conic" => problem::ContactKind::Conic,
                _ => problem::ContactKind::ActiveSet,
            }),
        clarabel_method: std::env::var("SLITHER_CLARABEL_METHOD").ok(),
    });
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    configure_from_env();
    match cli.cmd {
        Cmd::Run {
            problem,
            out,
            quiet,
            no_plots,
            force,
            accuracy,
        } => run(&problem, &out, quiet, no_plots, force, accuracy),
        Cmd::Topology { curve, closed } => topo(&curve, closed),
        Cmd::Chart { which } => chart_cmd(which),
        Cmd::Optimize { study, out, quiet } => optimize(&study, &out, quiet),
        Cmd::Phase {
            file,
            out,
            quiet,
            shard,
        } => phase(&file, &out, quiet, shard),
        Cmd::Merge { dirs, out } => merge(&dirs, &out),
    }
}

fn topo(path: &Path, closed: bool) -> ExitCode {
    let text = match problem::read(path) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let c = match topology::parse_curve_csv(&text, closed) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {}:{}: {}", path.display(), e.line, e.message);
            return ExitCode::from(2);
        }
    };
    let t = topology::topology(&c);
    let mut v = serde_json::json!({ "tw": t.tw, "wr": t.wr, "lk": t.lk });
    if closed {
        let len: f64 = (0..c.nodes.len())
            .map(|i| {
                let a = c.nodes[i];
                let b = c.nodes[(i + 1) % c.nodes.len()];
                ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
            })
            .fold(f64::INFINITY, f64::min);
        v["lk_gauss"] = serde_json::json!(topology::gauss_link(&c, 1e-3 * len));
    }
    println!("{v}");
    ExitCode::SUCCESS
}

/// Create `out` and lock it for this process: exit 2 if another live run holds it, 1 if it
/// cannot be created or written (found before any simulation).
fn lock_out(out: &Path) -> Result<output::lock::OutLock, ExitCode> {
    if let Err(e) = std::fs::create_dir_all(out) {
        eprintln!(
            "error: {}: cannot create output directory: {e}",
            out.display()
        );
        return Err(ExitCode::from(1));
    }
    output::lock::OutLock::acquire(out).map_err(|e| {
        eprintln!("error: {e}");
        ExitCode::from(match e {
            output::lock::LockError::Busy { .. } => 2,
            output::lock::LockError::Io { .. } => 1,
        })
    })
}

fn run(
    path: &Path,
    out: &Path,
    quiet: bool,
    no_plots: bool,
    force: bool,
    accuracy: Option<f64>,
) -> ExitCode {
    let p = match problem::load_for_run(path, force) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    if let Some(a) = accuracy {
        if !(a.is_finite() && (1e-4..=0.5).contains(&a)) {
            eprintln!("error: --accuracy {a} is not allowed: must be in [1e-4, 0.5] (relative error of v_s/v_m)");
            return ExitCode::from(2);
        }
        if p.time.mode != problem::Mode::Dynamic
            || p.ground.is_none()
            || p.gait.kind == problem::Kind::None
        {
            eprintln!(
                "error: {}: --accuracy needs a dynamic scene with [ground] and a [gait] (it controls the error of v_s/v_m)",
                path.display()
            );
            return ExitCode::from(2);
        }
    }
    let target = accuracy
        .map(|t| (t, p.accuracy.as_ref().map_or(400, |a| a.max_elements)))
        .or(p.accuracy.as_ref().map(|a| (a.target, a.max_elements)));
    let mut model = Model::new(&p);
    let _lock = match lock_out(out) {
        Ok(l) => l,
        Err(code) => return code,
    };
    // A previous run's outputs go first, so none is left beside this run's (and a crash never
    // leaves a stale "finished" summary).
    if let Err(e) = output::remove_previous(out) {
        eprintln!(
            "error: {}: cannot remove the previous run's outputs: {e}",
            out.display()
        );
        return ExitCode::from(1);
    }
    let show = !quiet && std::io::stderr().is_terminal();
    let start = Instant::now();
    let mut bar: Option<ProgressBar> = None;
    let mut progress = |frac: f64| {
        if !show {
            return;
        }
        if bar.is_none() && start.elapsed() > Duration::from_secs(1) {
            let b = ProgressBar::with_draw_target(Some(1000), ProgressDrawTarget::stderr());
            b.set_style(
                ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {percent}% eta {eta}")
                    .unwrap(),
            );
            bar = Some(b);
        }
        if let Some(b) = &bar {
            b.set_position((frac * 1000.0) as u64);
        }
    };
    let mut report = None;
    let o = if let Some((target, max_elements)) = target {
        let mut log = |line: &str| {
            if !quiet {
                eprintln!("{line}")
            }
        };
        let sel = slither::chart::accuracy::select(&p, target, max_elements, &mut log);
        model = sel.model;
        report = Some(sel.report);
        sel.outcome
    } else {
        match sim::run_gait(&model, p.solver.integrator, &mut progress, &mut |_| {}) {
            Ok(o) => o,
            Err(e) => {
                eprintln!("error: {}: {e}", path.display());
                return ExitCode::from(2);
            }
        }
    };
    if let Some(b) = bar.take() {
        b.finish_and_clear();
    }
    let mut summary = output::Summary::new(path, &model, &o);
    if let Some(r) = &report {
        if !quiet {
            eprintln!(
                "accuracy {}: chose {} elements, {}: estimated error {:.2e} (time {:.2e}, mesh {:.2e}){}; {} runs in {:.1} s",
                r.target,
                r.elements,
                model_label(r.dt, r.error_tolerance),
                r.estimated_error,
                r.time_error,
                r.mesh_error,
                if r.met { "" } else { ", ABOVE the target (refinement limits reached)" },
                r.runs.len(),
                r.wall_time_total_s
            );
        }
    }
    summary.accuracy = report;
    // Post-processing (topology of every frame) shows its own bar when it takes over a second.
    let post_start = Instant::now();
    let mut post_bar: Option<ProgressBar> = None;
    let fields = observe::fields_with_progress(&model, &o.frames, &mut |frac| {
        if !show {
            return;
        }
        if post_bar.is_none() && post_start.elapsed() > Duration::from_secs(1) {
            let b = ProgressBar::with_draw_target(Some(1000), ProgressDrawTarget::stderr());
            b.set_style(
                ProgressStyle::with_template(
                    "{elapsed_precise} [{bar:40}] {percent}% post-processing (topology of every frame) eta {eta}",
                )
                .unwrap(),
            );
            post_bar = Some(b);
        }
        if let Some(b) = &post_bar {
            b.set_position((frac * 1000.0) as u64);
        }
    });
    if let Some(b) = post_bar.take() {
        b.finish_and_clear();
    }
    summary.observables = Some(observe::observe(&model, &o.frames, &fields));
    let extra = [
        ("elevation", fields.elevation.clone()),
        ("slip_speed", fields.slip.clone()),
        ("lambda", fields.lambda.clone()),
    ];
    let written = output::write_final_csv(out, &model, &o)
        .and_then(|_| output::write_trajectory(out, &model, &o.frames, &extra))
        .and_then(|_| output::write_summary(out, &summary));
    if let Err(e) = written {
        eprintln!("error: {}: cannot write results: {e}", out.display());
        return ExitCode::from(1);
    }
    if !no_plots {
        if let Err(e) = output::write_figures(out, &model, &o.frames, &fields) {
            eprintln!("error: {}: cannot write figures: {e}", out.display());
            return ExitCode::from(1);
        }
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
    if !quiet {
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
    }
    ExitCode::SUCCESS
}

/// Progress of a study: an indicatif bar over evaluations on a terminal, else one line per
/// evaluation on stderr (nothing with --quiet).
struct StudyProgress {
    bar: Option<ProgressBar>,
    lines: bool,
    max: usize,
    done: usize,
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

impl design::EvaluationObserver for StudyProgress {
    fn started(&mut self, count: usize, p: &design::Point, cached: bool) {
        if let Some(b) = &self.bar {
            b.set_message(format!(
                "eval {count}/{}: stress {} Pa, sigma {}, speed {} m/s{}",
                self.max,
                p.stress,
                p.sigma,
                p.speed,
                if cached { " (cached)" } else { "" }
            ));
        }
    }

    fn progress(&mut self, fraction: f64) {
        if let Some(b) = &self.bar {
            b.set_position((self.done as f64 * 100.0 + fraction * 100.0) as u64);
        }
    }

    fn finished(&mut self, count: usize, e: &design::Evaluation, reused: bool) {
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
            design::Status::Ok => format!(
                "v_s = {:.5} m/s, v_s/v_m = {:.4}, {:.1} deg, Wr_max = {:.3}, regime {}",
                e.v_s, e.v_s_over_v_m, e.displacement_angle_deg, e.writhe_max, e.regime
            ),
            design::Status::Failed => format!("FAILED: {}", e.reason),
        };
        self.say(format!(
            "eval {count}/{} (row {}): stress {} Pa, sigma {}, speed {} m/s (G = {:.3}) -> {result} [{source}]",
            self.max, e.eval, e.point.stress, e.point.sigma, e.point.speed, e.g
        ));
    }
}

/// A study's `[accuracy]` after [`design::accuracy::prepare_study`] or `prepare_phase`
/// (`prepared`: whether a recorded choice was reused): prints the choice. `Err` is the exit
/// code (1: `accuracy.json` could not be written).
fn study_accuracy(
    out: &Path,
    quiet: bool,
    prepared: std::io::Result<bool>,
    chosen: Option<&design::accuracy::StudyAccuracy>,
) -> Result<(), ExitCode> {
    match prepared {
        Ok(reused) => {
            if let (Some(c), false) = (chosen, quiet) {
                eprintln!(
                    "accuracy {}: {} {} elements, {} for every run{}",
                    c.target,
                    if reused {
                        "reusing the recorded choice of"
                    } else {
                        "chose"
                    },
                    c.elements,
                    model_label(c.dt, c.error_tolerance),
                    match c.selection["estimated_error"].as_f64() {
                        Some(e) => format!(" (estimated error {e:.2e})"),
                        None => String::new(),
                    }
                );
            }
            Ok(())
        }
        Err(e) => {
            eprintln!(
                "error: {}: {e}",
                out.join(design::accuracy::ACCURACY_FILE).display()
            );
            Err(ExitCode::from(1))
        }
    }
}

/// One line per run of an accuracy selection (nothing with `--quiet`).
fn selection_log(quiet: bool) -> impl FnMut(&str) {
    move |line: &str| {
        if !quiet {
            eprintln!("{line}")
        }
    }
}

fn optimize(path: &Path, out: &Path, quiet: bool) -> ExitCode {
    let mut study = match design::load_study(path) {
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
    let prepared = design::accuracy::prepare_study(&mut study, out, &mut selection_log(quiet));
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
    };
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
    let history = out.join(design::HISTORY_FILE);
    if history.exists() {
        progress.say(format!(
            "{}: resuming with {}: evaluations already in it are reused, not simulated again",
            path.display(),
            history.display()
        ));
    }
    let method = match study.method {
        design::Method::NelderMead if study.starts > 1 => {
            format!("Nelder-Mead ({} starts)", study.starts)
        }
        design::Method::NelderMead => "Nelder-Mead".to_string(),
        design::Method::ParticleSwarm => format!(
            "particle swarm ({} particles per generation, in parallel)",
            study.particles
        ),
    };
    progress.say(format!(
        "{}: {method} over {}; at most {} evaluations of {} ({} pulse times L/v_m each)",
        path.display(),
        names.join(", "),
        study.max_evaluations,
        study.base_path.display(),
        study.duration_pulses
    ));
    let result = design::optimize(&study, out, &mut progress);
    if let Some(b) = progress.bar.take() {
        b.finish_and_clear();
    }
    let r = match result {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(match e {
                design::DesignError::History { .. } => 2,
                _ => 1,
            });
        }
    };
    let Some(best) = &r.best else {
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
        return ExitCode::from(3);
    };
    if !quiet {
        if r.dropped_partial_row {
            eprintln!(
                "note: an incomplete last row of {} was dropped",
                history.display()
            );
        }
        if r.rows_other_base > 0 {
            eprintln!(
                "note: {} rows of {} were written for another version of the base file and were not reused",
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
            "start: stress {} Pa, sigma {}, speed {} m/s: v_s = {:.5} m/s (v_s/v_m = {:.4}), regime {}",
            i.point.stress, i.point.sigma, i.point.speed, i.v_s, i.v_s_over_v_m, i.regime
        );
        eprintln!(
            "best:  stress {} Pa, sigma {}, speed {} m/s (G = {:.3}, W = {:.1}): v_s = {:.5} m/s (v_s/v_m = {:.4}), {:.1} deg off the head direction, writhe max {:.3} mean {:.3} turns, regime {}; wrote {}",
            best.point.stress,
            best.point.sigma,
            best.point.speed,
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
        for (param, side) in design::on_bound(&study, &r) {
            eprintln!(
                "note: the optimum lies on the {side} bound of {param} (within {} of the range): widen optimize.{param} to follow it",
                design::ON_BOUND_FRACTION
            );
        }
    }
    ExitCode::SUCCESS
}

#[derive(Subcommand)]
enum ChartCmd {
    /// Final-centreline error against wall time for both integrators at several steps, against
    /// a Richardson-checked velocity Verlet reference (a scene without [ground]).
    WorkPrecision {
        /// Problem file: without [ground] (e.g. problems/cantilever_swing.toml) implicit Euler
        /// against velocity Verlet; with [ground] and a gait (e.g. problems/s_start.toml)
        /// implicit Euler, BDF2 and adaptive BDF2 against a cached fine implicit Euler reference.
        problem: PathBuf,
        /// Output directory (created if absent).
        #[arg(long, default_value = "out/work_precision")]
        out: PathBuf,
    },
    /// Largest stable step of each integrator over scaled weight W and element count, by
    /// bisection, for the cantilever swing (or --problem).
    Stability {
        /// Base scene without [ground] (default: the bundled problems/cantilever_swing.toml).
        #[arg(long)]
        problem: Option<PathBuf>,
        /// Output directory (created if absent).
        #[arg(long, default_value = "out/stability")]
        out: PathBuf,
    },
}

fn chart_cmd(which: ChartCmd) -> ExitCode {
    use slither::chart;
    const SWING: &str = include_str!("../problems/cantilever_swing.toml");
    let load = |path: &Path| problem::load(path);
    let (p, scene, out) = match &which {
        ChartCmd::WorkPrecision { problem, out } => (load(problem), problem.clone(), out.clone()),
        ChartCmd::Stability {
            problem: Some(f),
            out,
        } => (load(f), f.clone(), out.clone()),
        ChartCmd::Stability { problem: None, out } => {
            let name = PathBuf::from("problems/cantilever_swing.toml");
            (problem::parse(SWING, &name), name, out.clone())
        }
    };
    let p = match p {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let name = scene.file_name().map_or(scene.display().to_string(), |n| {
        n.to_string_lossy().into_owned()
    });
    let mut log = |line: &str| eprintln!("{line}");
    let gait_scene = p.ground.is_some() && p.time.mode == problem::Mode::Dynamic;
    if gait_scene && matches!(which, ChartCmd::WorkPrecision { .. }) {
        // A scene with ground: implicit Euler, BDF2 and adaptive BDF2 against a fine implicit
        // Euler reference.
        let model = Model::new(&p);
        let cache = out.join("reference.json");
        if let Err(e) = std::fs::create_dir_all(&out) {
            eprintln!("error: {}: {e}", out.display());
            return ExitCode::from(1);
        }
        let r = chart::gait_precision(
            &name,
            &p,
            &model,
            &Default::default(),
            Some(&cache),
            &mut log,
        )
        .and_then(|g| {
            eprint!("{}", g.summary());
            chart::write_gait_precision(&out, &g)
        });
        return match r {
            Ok(()) => {
                eprintln!("wrote {}", out.display());
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {}: {e}", scene.display());
                ExitCode::from(1)
            }
        };
    }
    if p.ground.is_some() || p.time.mode == problem::Mode::Static {
        eprintln!(
            "error: {}: the stability chart (and the work-precision chart of a scene without ground) needs a dynamic scene without [ground] (the explicit integrator has no contact)",
            scene.display()
        );
        return ExitCode::from(2);
    }
    let r = match which {
        ChartCmd::WorkPrecision { .. } => {
            let model = Model::new(&p);
            chart::work_precision(&name, &model, &Default::default(), &mut log).and_then(|wp| {
                eprint!("{}", wp.summary());
                chart::write_work_precision(&out, &wp)
            })
        }
        ChartCmd::Stability { .. } => {
            chart::stability_map(&name, &p, &Default::default(), &mut log).and_then(|map| {
                eprint!("{}", map.summary());
                chart::write_stability(&out, &map)
            })
        }
    };
    match r {
        Ok(()) => {
            eprintln!("wrote {}", out.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {}: {e}", scene.display());
            ExitCode::from(1)
        }
    }
}

fn merge(dirs: &[PathBuf], out: &Path) -> ExitCode {
    let _lock = match lock_out(out) {
        Ok(l) => l,
        Err(code) => return code,
    };
    let t0 = Instant::now();
    let report = |done: usize, c: &design::phase::Cell| eprintln!("{}", refine_line(done, c));
    match design::phase::merge(dirs, out, &report) {
        Ok(m) => {
            eprintln!(
                "merged {} cells from {} directories ({} found twice with identical results); wrote {}",
                m.cells.len(),
                dirs.len(),
                m.duplicates,
                out.display()
            );
            if let Some(r) = &m.refinement {
                eprintln!("{}", refine_summary(r, t0.elapsed().as_secs_f64()));
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(match e {
                design::phase::PhaseError::Io { .. } | design::phase::PhaseError::Plot { .. } => 1,
                _ => 2,
            })
        }
    }
}

fn phase(path: &Path, out: &Path, quiet: bool, shard: Option<design::phase::Shard>) -> ExitCode {
    let mut ph = match design::phase::load(path) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let _lock = match lock_out(out) {
        Ok(l) => l,
        Err(code) => return code,
    };
    let prepared = design::accuracy::prepare_phase(&mut ph, out, &mut selection_log(quiet));
    if let Err(code) = study_accuracy(out, quiet, prepared, ph.chosen.as_ref()) {
        return code;
    }
    let grid = ph.weight.len() * ph.torque.len();
    let total = match shard {
        Some(s) => (0..grid).filter(|&k| s.owns(k)).count(),
        None => grid,
    };
    if !quiet {
        eprintln!(
            "{}: {} cells (W in {:?} x G in {:?}) of {}; finished cells in {} are reused",
            path.display(),
            total,
            ph.weight,
            ph.torque,
            ph.base_path.display(),
            out.join("phase.csv").display()
        );
    }
    let bar = (!quiet && std::io::stderr().is_terminal()).then(|| {
        let b = ProgressBar::with_draw_target(Some(total as u64), ProgressDrawTarget::stderr());
        b.set_style(
            ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {pos}/{len} cells {msg}")
                .unwrap(),
        );
        b
    });
    let report = |done: usize, todo: usize, c: &design::phase::Cell| {
        let line = if c.status == design::Status::Ok {
            format!(
                "cell {done}/{todo}: W = {} G = {}: regime {}, v_s/v_m = {:.4}, {:.1} deg, max elevation {:.2} a, {:.1} s",
                c.weight,
                c.torque,
                c.regime.map_or("-", |r| r.as_str()),
                c.v_s_over_v_m,
                c.displacement_angle_deg,
                c.max_elevation_over_a,
                c.wall_time_s
            )
        } else {
            format!(
                "cell {done}/{todo}: W = {} G = {}: failed: {}",
                c.weight, c.torque, c.reason
            )
        };
        match &bar {
            Some(b) => {
                b.inc(1);
                b.println(line);
            }
            None if !quiet => eprintln!("{line}"),
            None => {}
        }
    };
    let refine_report = |done: usize, c: &design::phase::Cell| {
        let line = refine_line(done, c);
        match &bar {
            Some(b) => b.println(line),
            None if !quiet || c.status != design::Status::Ok => eprintln!("{line}"),
            None => {}
        }
    };
    let t0 = Instant::now();
    let result = design::phase::sweep_shard(&ph, out, shard, &report, &refine_report);
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let sw = match result {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(match e {
                design::phase::PhaseError::Csv { .. } => 2,
                _ => 1,
            });
        }
    };
    if sw.dropped_partial_row && !quiet {
        eprintln!(
            "note: an incomplete last row of {} (a write cut short) was dropped; its cell was simulated again",
            out.join("phase.csv").display()
        );
    }
    let failed = sw
        .cells
        .iter()
        .filter(|c| c.status != design::Status::Ok)
        .count();
    eprintln!(
        "{}: {} cells ({} simulated, {} reused, {} failed) in {:.1} s; wrote {}",
        path.display(),
        sw.cells.len(),
        sw.simulated,
        sw.reused,
        failed,
        t0.elapsed().as_secs_f64(),
        out.display()
    );
    if let Some(r) = &sw.refinement {
        eprintln!("{}", refine_summary(r, t0.elapsed().as_secs_f64()));
    }
    if failed == sw.cells.len() && !sw.cells.is_empty() {
        eprintln!(
            "error: {}: every cell failed; see {}",
            path.display(),
            out.join("phase.csv").display()
        );
        return ExitCode::from(3);
    }
    ExitCode::SUCCESS
}

/// One refinement simulation, for the log.
fn refine_line(done: usize, c: &design::phase::Cell) -> String {
    if c.status == design::Status::Ok {
        format!(
            "refine {done}: W = {} G = {}: regime {}, v_s/v_m = {:.4}, {:.1} s",
            c.weight,
            c.torque,
            c.regime.map_or("-", |r| r.as_str()),
            c.v_s_over_v_m,
            c.wall_time_s
        )
    } else {
        format!(
            "refine {done}: W = {} G = {}: failed (its pair keeps the interval reached): {}",
            c.weight, c.torque, c.reason
        )
    }
}

/// The refinement's counts, for the last lines of `phase` and `merge`.
fn refine_summary(r: &design::refine::Refinement, elapsed_s: f64) -> String {
    let stopped = r.points.iter().filter(|p| p.failed.is_some()).count();
    format!(
        "refinement ({} bisection steps): {} neighbour pairs, {} boundary points ({} stopped early by a failed simulation); {} simulated, {} reused, {} failed; {:.1} s since start; wrote refine.csv",
        r.steps,
        r.pairs,
        r.points.len(),
        stopped,
        r.simulated,
        r.reused,
        r.failed,
        elapsed_s
    )
}

/// The time resolution of an accuracy choice, for messages.
fn model_label(dt: Option<f64>, tolerance: Option<f64>) -> String {
    slither::chart::accuracy::Resolution::from_parts(dt, tolerance)
        .map_or("no time resolution".into(), |r| r.to_string())
}
