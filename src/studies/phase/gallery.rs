//! The phase gallery, `phase_gallery.png` (`slither phase --gallery`): every cell simulated
//! again (the study's run of the cell, [`cell_problem_with`]; cells in parallel) to picture the
//! body at its writhe snapshot, the instant the centre of the middle couple passes mid-body,
//! `t* = (L/2 - s_b0) / v_m` (as `observe` defines it; the last frame without a gait), drawn
//! on the (W, G) grid by [`crate::plot::gallery`] with the regimes of the study's cells.
//! It costs about one more sweep of the grid.

use super::{cell_problem_with, Cell, Phase};
use crate::model::Model;
use crate::plot::gallery::{gallery, Thumb};
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// The body of `m`'s run at its writhe snapshot: time and node positions (None if the run
/// could not start or recorded nothing).
fn snapshot(m: &Model) -> Option<(f64, Vec<[f64; 3]>)> {
    let o = crate::sim::run_gait(m, m.solver.integrator, &mut |_| {}, &mut |_| {}).ok()?;
    let g = &m.gait;
    let frame = if g.kind != crate::gait::Kind::None && g.couple > 0.0 && g.speed > 0.0 {
        let t_star = (0.5 * m.length - g.centers[1]) / g.speed;
        o.frames
            .iter()
            .min_by(|a, b| (a.t - t_star).abs().total_cmp(&(b.t - t_star).abs()))
    } else {
        o.frames.last()
    };
    frame.map(|f| (f.t, f.x.clone()))
}

/// One thumbnail per cell of `cells`, with the cell's regime.
pub fn thumbs(ph: &Phase, cells: &[Cell]) -> Vec<Thumb> {
    cells
        .par_iter()
        .map(|c| {
            let p = cell_problem_with(&ph.base, c.weight, c.torque, ph.protocol);
            let shot = std::panic::catch_unwind(|| snapshot(&Model::new(&p)))
                .ok()
                .flatten();
            let (t, x) = shot.unwrap_or((f64::NAN, Vec::new()));
            Thumb {
                weight: c.weight,
                torque: c.torque,
                regime: c.regime,
                t,
                x,
            }
        })
        .collect()
}

/// Simulate the thumbnails of `cells` and write `out/phase_gallery.png`; returns its path.
pub fn write_gallery(ph: &Phase, cells: &[Cell], out: &Path) -> Result<PathBuf, String> {
    let path = out.join("phase_gallery.png");
    let th = thumbs(ph, cells);
    let r = &ph.base.rod;
    gallery(&path, &ph.weight, &ph.torque, &th, r.length, r.diameter)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(path)
}
