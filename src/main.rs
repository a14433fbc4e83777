//! The `slither` command line.
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use slither::model::Model;
use slither::{gait, observe, output, problem, sim, topology};
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
    },
    /// Twist, writhe and link of a framed curve given as CSV (x,y,z,d1x,d1y,d1z).
    Topology {
        /// CSV file with a header row.
        curve: PathBuf,
        /// The curve is closed (its last edge returns to the first node); adds `lk_gauss`.
        #[arg(long)]
        closed: bool,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.cmd {
        Cmd::Run {
            problem,
            out,
            quiet,
            no_plots,
        } => run(&problem, &out, quiet, no_plots),
        Cmd::Topology { curve, closed } => topo(&curve, closed),
    }
}

fn topo(path: &Path, closed: bool) -> ExitCode {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {}: cannot read: {e}", path.display());
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

fn run(path: &Path, out: &Path, quiet: bool, no_plots: bool) -> ExitCode {
    let p = match problem::load(path) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let model = Model::new(&p);
    if let Err(e) = std::fs::create_dir_all(out) {
        eprintln!(
            "error: {}: cannot create output directory: {e}",
            out.display()
        );
        return ExitCode::from(1);
    }
    // Remove a previous run's summary first so a crash never leaves a stale "finished" run.
    let _ = std::fs::remove_file(out.join("summary.json"));
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
    let o = sim::run(
        &model,
        Box::new(gait::Muscles {
            gait: model.gait.clone(),
        }),
        &mut progress,
        &mut |_| {},
    );
    if let Some(b) = bar.take() {
        b.finish_and_clear();
    }
    let mut summary = output::Summary::new(path, &model, &o);
    let fields = observe::fields(&model, &o.frames);
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
