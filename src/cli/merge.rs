//! `slither merge`: combine the output directories of sharded `slither phase` runs.
use super::lock_out;
use super::phase::{growth_failed, growth_line, growth_summary, refine_line, refine_summary};
use slither::studies;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// Shard output directories.
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// Output directory (created if absent).
    #[arg(long)]
    pub out: PathBuf,
}

pub fn merge(args: &Args) -> ExitCode {
    let (dirs, out) = (args.dirs.as_slice(), args.out.as_path());
    if let Err(code) = super::guard::check_merge_out(dirs, out) {
        return code;
    }
    let _lock = match lock_out(out) {
        Ok(l) => l,
        Err(code) => return code,
    };
    if let Err(code) = super::guard::check_writer(out, super::guard::Writer::Phase) {
        return code;
    }
    let t0 = Instant::now();
    let report = |done: usize, c: &studies::phase::Cell| eprintln!("{}", refine_line(done, c));
    let growth_report =
        |done: usize, c: &studies::phase::Cell| eprintln!("{}", growth_line(done, c));
    match studies::phase::merge(dirs, out, &report, &growth_report) {
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
            if let Some((g, simulated)) = &m.growth {
                eprintln!("{}", growth_summary(g, *simulated));
                if let Err(code) = growth_failed(g, &out.join("growth.csv")) {
                    return code;
                }
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(match e {
                studies::phase::PhaseError::Io { .. } | studies::phase::PhaseError::Plot { .. } => {
                    1
                }
                _ => 2,
            })
        }
    }
}
