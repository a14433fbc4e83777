//! `slither run`: simulate a problem file and write its results, figures and summary.
use super::{lock_out, model_label};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use slither::model::Model;
use slither::{observe, output, problem, sim};
use std::io::IsTerminal;
use std::path::PathBuf;
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
    /// Skip the PNG figures, the movie, the tracks and the ParaView export.
    #[arg(long)]
    pub no_plots: bool,
    /// Write movie.gif even when the problem file says `[output] movie = false`.
    #[arg(long)]
    pub movie: bool,
    /// Run even above the size limits (steps, stored frames, post-processing; see the
    /// README's "Limits").
    #[arg(long)]
    pub force: bool,
    /// Run the cheapest model (adaptive BDF2 tolerance and mesh) whose estimated relative
    /// error of v_s/v_m is below this, e.g. 0.01 (overrides `[accuracy] target`; scenes
    /// with ground and gait; in [1e-4, 0.5]).
    #[arg(long)]
    pub accuracy: Option<f64>,
}

pub fn run(args: &Args) -> ExitCode {
    let (path, out) = (args.problem.as_path(), args.out.as_path());
    let (quiet, no_plots, force, accuracy) = (args.quiet, args.no_plots, args.force, args.accuracy);
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
        // Ground tracks always; the movie unless the problem file turns it off.
        let want_movie = args.movie || p.output.movie;
        let title = path
            .file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned());
        let regime = summary
            .observables
            .as_ref()
            .filter(|_| o.error.is_none())
            .map(|ob| ob.regime.to_string());
        let clip = output::movie::clip_from_run(&model, &o.frames, &fields, &title, regime);
        let made = output::movie::write_tracks(out, &clip).and_then(|_| {
            if want_movie {
                output::movie::write_movie(out, "movie.gif", &clip, &Default::default()).map(|_| ())
            } else {
                Ok(())
            }
        });
        if let Err(e) = made {
            eprintln!(
                "error: {}: cannot write the movie or the tracks: {e}",
                out.display()
            );
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
