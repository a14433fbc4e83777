//! The `slither` command line: the clap definition and the dispatch. Each subcommand's
//! arguments and body live in its own module under `cli/`; the shared pieces (logger, output
//! lock, accuracy messages) in `cli/mod.rs`. The physics is the library's (`slither`): each
//! implicit step a Newton solve of the incremental potential with the self-contact barrier,
//! ground contact and friction by the semi-smooth Newton (the default; the conic program by
//! Clarabel as its fallback and certificate, or alone with `[solver] contact = "conic"`).
mod cli;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "slither",
    version,
    about = "Snake locomotion: discrete elastic rods, implicit steps, Coulomb friction by a semi-smooth Newton, self-contact"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Simulate a problem file and write summary.json, final.csv and trajectory.npz.
    Run(cli::run::Args),
    /// Twist, writhe and link of a framed curve given as CSV (x,y,z,d1x,d1y,d1z).
    Topology(cli::topology::Args),
    /// Speed against accuracy of the implicit and the explicit (velocity Verlet) integrator:
    /// work-precision chart or stability map (CSV, JSON and PNG).
    Chart {
        #[command(subcommand)]
        which: cli::chart::ChartCmd,
    },
    /// Gait design: maximise the forward speed v_s over muscle stress, width and speed
    /// (argmin Nelder-Mead, one simulation per evaluation, or particle swarm, a generation
    /// in parallel); writes history.csv, optimum.json
    /// and figures. Rerunning with the same --out reuses the evaluations in history.csv.
    Optimize(cli::optimize::Args),
    /// Regime phase diagram over scaled weight W and scaled torque G (one simulation per
    /// cell, in parallel); writes phase.csv, boundaries.json and the regime map and Fig. 3
    /// charts (PNG and SVG), and with `refine = true` the boundary bisection's refine.csv.
    /// Rerunning with the same --out reuses the finished cells and refinement simulations.
    Phase(cli::phase::Args),
    /// Combine the output directories of `slither phase --shard I/N` runs (one phase file and
    /// base problem) into one: the same phase.csv, phase.json and figures as an unsharded run,
    /// bisecting the boundaries into refine.csv when the phase file has `refine = true`.
    /// Refuses directories of another grid or base file and reports missing cells.
    Merge(cli::merge::Args),
    /// Print the user guide's generated references: every problem-file key with its unit,
    /// default, allowed values and meaning (--markdown), or every key of summary.json and
    /// column of phase.csv and history.csv (--outputs-markdown).
    Keys(cli::keys::Args),
    /// Render a movie (animated GIF) of a run directory from its trajectory.npz: the body as a
    /// shaded tube over the ground, in a 3d, top or side view, coloured by contact state,
    /// elevation or lambda.
    Movie(cli::movie::Args),
    /// The state of a study or run directory: cells or evaluations done, failed and missing,
    /// shards, locks (with host, process and whether it lives) and the command that resumes.
    Status(cli::status::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Err(code) = cli::configure_from_env() {
        return code;
    }
    match cli.cmd {
        Cmd::Run(a) => cli::run::run(&a),
        Cmd::Topology(a) => cli::topology::topo(&a),
        Cmd::Chart { which } => cli::chart::chart_cmd(which),
        Cmd::Optimize(a) => {
            cli::signals::end_studies();
            cli::optimize::optimize(&a)
        }
        Cmd::Phase(a) => {
            cli::signals::end_studies();
            cli::phase::phase(&a)
        }
        Cmd::Merge(a) => {
            cli::signals::end_studies();
            cli::merge::merge(&a)
        }
        Cmd::Keys(a) => cli::keys::keys(&a),
        Cmd::Movie(a) => cli::movie::movie(&a),
        Cmd::Status(a) => cli::status::status(&a),
    }
}
