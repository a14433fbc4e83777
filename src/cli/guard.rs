//! Guards of an output directory, checked before a subcommand writes anything into it: a
//! directory holds the results of one kind of subcommand (a study never overwrites a run's
//! figures, nor a run a study's), `merge` never writes into one of its own inputs, and a phase
//! directory keeps one grid.
use slither::studies;
use std::path::Path;
use std::process::ExitCode;

/// The subcommands that write an output directory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Writer {
    /// `slither run`.
    Run,
    /// `slither phase` and `slither merge` (a merged directory is a phase directory).
    Phase,
    /// `slither optimize`.
    Optimize,
}

impl Writer {
    const ALL: [Writer; 3] = [Writer::Run, Writer::Phase, Writer::Optimize];

    /// The subcommand's name.
    fn name(self) -> &'static str {
        match self {
            Writer::Run => "run",
            Writer::Phase => "phase",
            Writer::Optimize => "optimize",
        }
    }

    /// Files only this subcommand writes at the top of its output directory.
    fn marks(self) -> &'static [&'static str] {
        match self {
            Writer::Run => &["summary.json", "final.csv", "trajectory.npz"],
            Writer::Phase => &["phase.csv", "phase.json"],
            Writer::Optimize => &["history.csv", "optimum.json"],
        }
    }
}

/// The subcommand whose results `out` holds, other than `me`, with the file that shows it.
pub fn other_writer(out: &Path, me: Writer) -> Option<(Writer, &'static str)> {
    Writer::ALL.into_iter().filter(|&w| w != me).find_map(|w| {
        w.marks()
            .iter()
            .find(|f| out.join(f).exists())
            .map(|f| (w, *f))
    })
}

/// Refuse (exit 2) an output directory that holds another subcommand's results.
pub fn check_writer(out: &Path, me: Writer) -> Result<(), ExitCode> {
    match other_writer(out, me) {
        None => Ok(()),
        Some((other, file)) => {
            eprintln!(
                "error: --out {}: holds the results of `slither {}` ({file}); `slither {}` would overwrite or mix with them: choose another directory",
                out.display(),
                other.name(),
                me.name()
            );
            Err(ExitCode::from(2))
        }
    }
}

/// Refuse (exit 2) a merge whose output directory is one of its inputs.
pub fn check_merge_out(dirs: &[std::path::PathBuf], out: &Path) -> Result<(), ExitCode> {
    let Ok(target) = out.canonicalize() else {
        return Ok(()); // does not exist yet: it cannot be an input
    };
    for d in dirs {
        if d.canonicalize().is_ok_and(|c| c == target) {
            eprintln!(
                "error: --out {}: is also the input directory {}; merging into a shard would replace its cells: choose a new directory",
                out.display(),
                d.display()
            );
            return Err(ExitCode::from(2));
        }
    }
    Ok(())
}

/// Refuse (exit 2) a phase directory written for another grid that the new grid does not
/// contain: its `phase.csv` would keep the old grid's rows beside the new ones. A grid that
/// extends the old one (every old weight and torque kept) reuses its cells.
pub fn check_phase_grid(out: &Path, ph: &studies::phase::Phase) -> Result<(), ExitCode> {
    let Ok(text) = std::fs::read_to_string(out.join("phase.json")) else {
        return Ok(());
    };
    let Ok(info) = serde_json::from_str::<studies::phase::RunInfo>(&text) else {
        return Ok(()); // not ours to judge: the sweep reports an unreadable file itself
    };
    let within = |old: &[f64], new: &[f64]| {
        old.iter()
            .all(|x| new.iter().any(|y| x.to_bits() == y.to_bits()))
    };
    if within(&info.weight, &ph.weight) && within(&info.torque, &ph.torque) {
        return Ok(());
    }
    eprintln!(
        "error: --out {}: holds a phase study of another grid (W {:?} x G {:?}, now W {:?} x G {:?}, which does not contain it); its phase.csv would mix the two: choose another directory (a grid that keeps every old weight and torque reuses the cells)",
        out.display(),
        info.weight,
        info.torque,
        ph.weight,
        ph.torque
    );
    Err(ExitCode::from(2))
}

/// Most cells of a phase grid without `--force`.
pub const MAX_PHASE_CELLS: usize = 10_000;
/// Most time steps of a whole phase study (cells x steps per cell) without `--force`: about
/// 33 hours of stepping at the S-start's 6 ms per step on one core.
pub const MAX_PHASE_STEPS: f64 = 2.0e7;

/// The size of a phase study (cells, steps in all) and, above the limits, the error text
/// naming the file and the keys to change.
pub fn phase_size(file: &Path, cells: usize, steps_per_cell: f64) -> (f64, Option<String>) {
    let total = cells as f64 * steps_per_cell;
    let why = if cells > MAX_PHASE_CELLS {
        Some(format!(
            "{} cells (weight x torque) is above the limit of {MAX_PHASE_CELLS}",
            cells
        ))
    } else if total > MAX_PHASE_STEPS {
        Some(format!(
            "{cells} cells x {steps_per_cell} steps = {total:.3e} time steps is above the limit of {MAX_PHASE_STEPS:.0e}"
        ))
    } else {
        None
    };
    (
        total,
        why.map(|w| {
            format!(
                "{}: phase.weight, phase.torque: {w}; use fewer cells or a coarser base, or run with --force",
                file.display()
            )
        }),
    )
}
