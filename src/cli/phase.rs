//! `slither phase`: the regime phase diagram over scaled weight and torque (whole or one
//! shard), with its boundary refinement.
use super::{lock_out, selection_log, study_accuracy};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use slither::studies;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// Phase file (TOML): the base problem and the W and G grids.
    pub file: PathBuf,
    /// Output directory (created if absent).
    #[arg(long, default_value = "out_phase")]
    pub out: PathBuf,
    /// No progress bar and no per-cell lines.
    #[arg(long)]
    pub quiet: bool,
    /// Run only shard I of N (cell k of the weight-major grid belongs to shard k % N + 1):
    /// for a job array; `slither merge` combines the shard directories. No figures.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<studies::phase::Shard>,
    /// Run even above the size limits (10 000 cells, 2e7 time steps in all).
    #[arg(long)]
    pub force: bool,
    /// Re-run one cell of the grid, W,G (values of phase.weight and phase.torque, each within
    /// 1e-3 relative of exactly one grid value), into the run directory --out, as `slither
    /// run` would: the model the study builds for that cell, with trajectory, summary,
    /// figures, tracks and movie.
    #[arg(long, value_name = "W,G", conflicts_with_all = ["shard", "cell_index", "growth_size"])]
    pub cell: Option<String>,
    /// As --cell, the cell given by its indices i,j in phase.weight and phase.torque (from 0).
    #[arg(long, value_name = "i,j", conflicts_with_all = ["shard", "growth_size"])]
    pub cell_index: Option<String>,
    /// As --cell, one size of the growth line (`growth = { ... }`): its diameter D (m), within
    /// 1e-3 relative of exactly one of the line's diameters.
    #[arg(long, value_name = "D", conflicts_with = "shard")]
    pub growth_size: Option<String>,
    /// With --cell, --cell-index or --growth-size: write the results without the figures,
    /// tracks and movie.
    #[arg(long)]
    pub no_plots: bool,
    /// Also write phase_gallery.png: each cell simulated again to picture the body at its
    /// writhe snapshot (top and side views on the W, G grid; about one more sweep's time).
    #[arg(long, conflicts_with_all = ["shard", "cell", "cell_index", "growth_size"])]
    pub gallery: bool,
    /// Change a key for this study, validated like the file: keys of `[phase]` and
    /// `[accuracy]` edit the phase file (`--set phase.refine=false`), every other key its base
    /// problem (`--set rod.elements=100`). Repeatable; recorded in `phase.json`, so `merge`
    /// reads the file with them.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<slither::problem::set::Setting>,
    /// With --cell, --cell-index or --growth-size: write that cell's problem (the model the
    /// study builds for it, every default filled in) to FILE as a problem file.
    #[arg(long, value_name = "FILE")]
    pub dump_problem: Option<PathBuf>,
}

/// What `--cell`, `--cell-index` or `--growth-size` selects: the cell's `(W, G)` and protocol,
/// and its name for messages.
fn selected(
    args: &Args,
    ph: &studies::phase::Phase,
) -> Option<Result<(f64, f64, studies::phase::Protocol, String), String>> {
    use studies::phase::select;
    let grid = |(i, j): (usize, usize)| {
        let (w, g) = (ph.weight[i], ph.torque[j]);
        (
            w,
            g,
            ph.protocol,
            format!("cell W = {w}, G = {g} (index {i},{j})"),
        )
    };
    if let Some(text) = &args.cell {
        return Some(select::cell(&ph.weight, &ph.torque, text).map(grid));
    }
    if let Some(text) = &args.cell_index {
        return Some(select::cell_index(&ph.weight, &ph.torque, text).map(grid));
    }
    let text = args.growth_size.as_ref()?;
    let Some(growth) = &ph.growth else {
        return Some(Err(format!(
            "--growth-size {text}: {} has no growth line (phase.growth)",
            ph.file.display()
        )));
    };
    Some(select::growth_size(&growth.diameters, text).map(|k| {
        let p = growth.points(&ph.base)[k];
        (
            p.weight,
            p.torque,
            studies::phase::growth::PROTOCOL,
            format!(
                "growth size {} m (W = {}, G = {})",
                p.diameter, p.weight, p.torque
            ),
        )
    }))
}

/// `slither phase FILE --cell W,G --out DIR` (or `--cell-index`, `--growth-size`): the
/// selected cell's problem (after the file's `[accuracy]`, as the study does) run into the run
/// directory `out`.
fn rerun_cell(
    args: &Args,
    mut ph: studies::phase::Phase,
    chosen: Result<(f64, f64, studies::phase::Protocol, String), String>,
) -> ExitCode {
    let (w, g, protocol, name) = match chosen {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {}: {e}", ph.file.display());
            return ExitCode::from(2);
        }
    };
    let out = args.out.as_path();
    // Refused before `[accuracy]` could record its choice in a study's directory.
    if let Err(code) = super::guard::check_writer(out, super::guard::Writer::Run) {
        return code;
    }
    if ph.accuracy.is_some() {
        let prepared =
            studies::phase::prepare_accuracy(&mut ph, out, &mut selection_log(args.quiet));
        if let Err(code) = study_accuracy(out, args.quiet, prepared, ph.chosen.as_ref()) {
            return code;
        }
    }
    let p = studies::phase::cell_problem_with(&ph.base, w, g, protocol);
    let what = format!("{}: {name}", args.file.display());
    if let Some(file) = &args.dump_problem {
        let from = format!("{what}{}", super::run::settings_label(&args.set));
        if let Err(code) = super::run::dump_problem(file, &p, &from) {
            return code;
        }
    }
    match super::run::rerun_into(&p, &args.file, out, args.quiet, !args.no_plots, &what) {
        Ok(_) => ExitCode::SUCCESS,
        Err(code) => code,
    }
}

pub fn phase(args: &Args) -> ExitCode {
    let (path, out, quiet, shard) = (
        args.file.as_path(),
        args.out.as_path(),
        args.quiet,
        args.shard,
    );
    let settings: Vec<&slither::problem::set::Setting> = args.set.iter().collect();
    let mut ph = match studies::phase::load_with(path, &settings) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    if let Some(chosen) = selected(args, &ph) {
        return rerun_cell(args, ph, chosen);
    }
    if args.dump_problem.is_some() {
        eprintln!("error: --dump-problem is for one cell (--cell, --cell-index, --growth-size): a study has a problem per cell");
        return ExitCode::from(2);
    }
    if args.no_plots {
        eprintln!("error: --no-plots is for rerunning one cell (--cell, --cell-index, --growth-size); a study's figures are its results");
        return ExitCode::from(2);
    }
    let cells = ph.weight.len() * ph.torque.len();
    let steps = slither::problem::limits::run_size(&ph.base).steps;
    let (total_steps, too_big) = super::guard::phase_size(path, cells, steps);
    if let (Some(why), false) = (too_big, args.force) {
        eprintln!("error: {why}");
        return ExitCode::from(2);
    }
    let _lock = match lock_out(out) {
        Ok(l) => l,
        Err(code) => return code,
    };
    if let Err(code) = super::guard::check_writer(out, super::guard::Writer::Phase)
        .and_then(|_| super::guard::check_phase_grid(out, &ph))
    {
        return code;
    }
    let prepared = studies::phase::prepare_accuracy(&mut ph, out, &mut selection_log(quiet));
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
            "{}: {} cells (W in {:?} x G in {:?}) of {}, about {:.2e} time steps in all; finished cells in {} are reused",
            path.display(),
            total,
            ph.weight,
            ph.torque,
            ph.base_path.display(),
            total_steps * total as f64 / grid.max(1) as f64,
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
    if let (Some(v), false) = (&ph.verify, quiet) {
        eprintln!("{}", verify_line(v));
    }
    let report = |done: usize, todo: usize, c: &studies::phase::Cell| {
        let line = cell_line(done, todo, c);
        match &bar {
            Some(b) => {
                b.inc(1);
                b.println(line);
            }
            None if !quiet => eprintln!("{line}"),
            None => {}
        }
    };
    let refine_report = |done: usize, c: &studies::phase::Cell| {
        let line = refine_line(done, c);
        match &bar {
            Some(b) => b.println(line),
            None if !quiet || c.status != studies::optimize::Status::Ok => eprintln!("{line}"),
            None => {}
        }
    };
    let growth_report = |done: usize, c: &studies::phase::Cell| {
        let line = growth_line(done, c);
        match &bar {
            Some(b) => b.println(line),
            None if !quiet || c.status != studies::optimize::Status::Ok => eprintln!("{line}"),
            None => {}
        }
    };
    let t0 = Instant::now();
    let result =
        studies::phase::sweep_shard(&ph, out, shard, &report, &refine_report, &growth_report);
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let sw = match result {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(match e {
                studies::phase::PhaseError::Csv { .. }
                | studies::phase::PhaseError::Header { .. } => 2,
                _ => 1,
            });
        }
    };
    finish(args, &ph, &sw, t0)
}

/// One refinement simulation, for the log.
pub fn refine_line(done: usize, c: &studies::phase::Cell) -> String {
    if c.status == studies::optimize::Status::Ok {
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

/// One simulation of the growth line, for the log.
pub fn growth_line(done: usize, c: &studies::phase::Cell) -> String {
    refine_line(done, c).replacen("refine", "growth", 1)
}

/// The growth line's verdict, for the last lines of `phase` and `merge`.
pub fn growth_summary(g: &studies::phase::growth::GrowthLine, simulated: usize) -> String {
    format!(
        "growth line ({} sizes, {simulated} simulated now): {}; wrote growth.csv, growth.json, growth.png",
        g.points.len(),
        g.verdict
    )
}

/// Exit 3 (after an error line) when every size of the growth line failed: the line has no
/// verdict, and a job script must not take it for "no size S-starts".
pub fn growth_failed(
    g: &studies::phase::growth::GrowthLine,
    csv: &std::path::Path,
) -> Result<(), ExitCode> {
    if g.all_failed() {
        eprintln!(
            "error: every size of the growth line failed ({} sizes); see {}",
            g.points.len(),
            csv.display()
        );
        return Err(ExitCode::from(3));
    }
    Ok(())
}

/// The refinement's counts, for the last lines of `phase` and `merge`.
pub fn refine_summary(r: &studies::phase::refine::Refinement, elapsed_s: f64) -> String {
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

/// One cell of the grid, for the log.
pub fn cell_line(done: usize, todo: usize, c: &studies::phase::Cell) -> String {
    if c.status == studies::optimize::Status::Ok {
        let agreement = c.verify.as_ref().map_or(String::new(), |v| {
            format!(
                ", agreement {:.2} (v_s/v_m {:.4} .. {:.4})",
                v.label_agreement, v.v_s_over_v_m_min, v.v_s_over_v_m_max
            )
        });
        let periodic = c
            .periodic
            .map_or(String::new(), |p| format!(", {}", p.describe()));
        format!(
            "cell {done}/{todo}: W = {} G = {}: regime {}, v_s/v_m = {:.4}, {:.1} deg, max elevation {:.2} a{agreement}{periodic}, {:.1} s",
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
    }
}

/// How a study verifies each cell, for the log.
fn verify_line(v: &studies::phase::Verify) -> String {
    format!(
            "verification: {} runs per cell ({}{} perturbed, seed {}, steps dt/{} .. dt*{}); the reported label is the {} run's",
            v.runs(),
            if v.finer { "the study's, one at dt/2 and 2x elements, " } else { "the study's, " },
            v.perturbations,
            v.seed,
            v.step,
            v.step,
            if v.finer { "finer" } else { "study's" })
}

/// The closing lines of a sweep (counts, refinement, growth line), the gallery, and the exit
/// code.
fn finish(
    args: &Args,
    ph: &studies::phase::Phase,
    sw: &studies::phase::Sweep,
    t0: Instant,
) -> ExitCode {
    let (path, out, quiet) = (args.file.as_path(), args.out.as_path(), args.quiet);
    if sw.dropped_partial_row && !quiet {
        eprintln!(
            "note: an incomplete last row of {} (a write cut short) was dropped; its cell was simulated again",
            out.join("phase.csv").display()
        );
    }
    let failed = sw
        .cells
        .iter()
        .filter(|c| c.status != studies::optimize::Status::Ok)
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
    if let Some((g, simulated)) = &sw.growth {
        eprintln!("{}", growth_summary(g, *simulated));
        if let Err(code) = growth_failed(g, &out.join("growth.csv")) {
            return code;
        }
    }
    if args.gallery {
        match studies::phase::gallery::write_gallery(ph, &sw.cells, out) {
            Ok(p) if !quiet => eprintln!("wrote {}", p.display()),
            Ok(_) => {}
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(1);
            }
        }
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
