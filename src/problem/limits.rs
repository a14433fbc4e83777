//! Size limits of a run, checked before it starts (`slither run` refuses a larger run with exit
//! code 2 unless `--force`).
//!
//! The step count and the stored frames are fixed by the problem file, so a run that would take
//! days or fill the memory (`dt = 1e-9`, `[output] interval = 1e-9`) is caught up front instead
//! of being killed. The limits are far above every bundled problem (the S-start: 1786 steps,
//! 101 frames of 51 nodes, 0.3 M topology pairs):
//!
//! * [`MAX_STEPS`] time steps (`ceil(duration / dt)`): about 3 hours at the S-start's
//!   6 ms per step;
//! * [`MAX_FRAMES`] stored frames, and [`MAX_FRAME_VALUES`] frames x nodes (every stored
//!   node carries 12 numbers, its kymograph values and its share of the npz, assembled in
//!   memory: about 1 GB at the limit);
//! * [`MAX_TOPOLOGY_PAIRS`] segment pairs of the post-processing (the writhe of every frame
//!   and its local densities cost about `frames x 0.6 N^2` pair evaluations at `N` elements;
//!   roughly 50 ns each: about 15 minutes at the limit).

use super::{key_line, Kind, Mode, Problem, ProblemError};
use std::path::Path;

/// Most time steps a run may take without `--force`.
pub const MAX_STEPS: f64 = 2.0e6;
/// Most stored frames (including the initial one) without `--force`.
pub const MAX_FRAMES: f64 = 1.0e5;
/// Most stored frames x nodes without `--force`.
pub const MAX_FRAME_VALUES: f64 = 5.0e6;
/// Most segment-pair evaluations of the post-processing (`frames x 0.6 N^2`) without `--force`.
pub const MAX_TOPOLOGY_PAIRS: f64 = 2.0e10;

/// Range of the scaled weight `W` and the scaled torque `G` when they are not zero (zero stays
/// valid: no gravity, or no muscles). Outside it the scene is no snake on the ground: at
/// `W = 1e-30` a "phase cell" ran 110 s and reported `v_s/v_m = 5.2e8`. `--force` runs it
/// anyway. The bundled scenes and studies span `W` 0.3 to 1e5 and `G` 1 to 1e3.
pub const SCALED_GROUP_RANGE: (f64, f64) = (1e-6, 1e9);

/// The scaled weight `W = rho g a^2 L^3 / B` and scaled torque `G = Gamma a^3 L / B` (0 without
/// gravity or muscles).
pub fn scaled_groups(p: &Problem) -> (f64, f64) {
    let r = &p.rod;
    let w = r.density * p.gravity.g * r.diameter.powi(2) * r.length.powi(3) / r.bending_stiffness;
    let g = if p.gait.kind == Kind::None {
        0.0
    } else {
        p.gait.stress * r.diameter.powi(3) * r.length / r.bending_stiffness
    };
    (w, g)
}

/// Refuse a scaled weight or torque that is neither zero nor within [`SCALED_GROUP_RANGE`]: the
/// error names the key that sets it (`gravity.g`, `gait.stress`) and says that `--force` runs
/// it anyway.
pub fn check_scaled_groups(p: &Problem, text: &str, path: &Path) -> Result<(), ProblemError> {
    let (lo, hi) = SCALED_GROUP_RANGE;
    let (w, g) = scaled_groups(p);
    for (what, v, table, key, value) in [
        (
            "scaled weight W = rho g a^2 L^3 / B",
            w,
            "gravity",
            "g",
            p.gravity.g,
        ),
        (
            "scaled torque G = Gamma a^3 L / B",
            g,
            "gait",
            "stress",
            p.gait.stress,
        ),
    ] {
        if v != 0.0 && !(lo..=hi).contains(&v) {
            return Err(ProblemError::Invalid {
                file: path.into(),
                line: key_line(text, table, key),
                key: format!("{table}.{key}"),
                value: super::num(value),
                allowed: format!(
                    "a value for which the {what} is 0 or in [{lo:e}, {hi:e}]; it is {:.3e} (or run with --force)",
                    v
                ),
            });
        }
    }
    Ok(())
}

/// Estimated size of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunSize {
    /// Time steps (static: load increments).
    pub steps: f64,
    /// Stored frames, the initial one included.
    pub frames: f64,
    /// Nodes.
    pub nodes: f64,
    /// Segment-pair evaluations of the post-processing.
    pub topology_pairs: f64,
}

/// The size of a validated problem's run: `steps = ceil(duration / dt)` (static mode: the load
/// steps), one frame every `round(interval / dt)` steps plus the first and the last.
pub fn run_size(p: &Problem) -> RunSize {
    let nodes = p.rod.elements as f64 + 1.0;
    let (steps, frames) = match p.time.mode {
        Mode::Static => (p.time.load_steps as f64, p.time.load_steps as f64 + 1.0),
        Mode::Dynamic => {
            let dt = p.time.dt.unwrap_or(f64::NAN);
            let d = p.time.duration.unwrap_or(f64::NAN);
            let steps = (d / dt * (1.0 - 1e-12)).ceil().max(1.0);
            let interval = p.output.interval_for(d);
            let every = (interval / dt).round().max(1.0);
            // The first frame, one every `every` steps, and the last step's.
            let last = if steps % every == 0.0 { 0.0 } else { 1.0 };
            (steps, 1.0 + (steps / every).floor() + last)
        }
    };
    RunSize {
        steps,
        frames,
        nodes,
        topology_pairs: frames * 0.6 * nodes * nodes,
    }
}

/// Refuse a run above one of the limits (see the module doc); the error names the key to change
/// and says that `--force` runs it anyway.
pub fn check_run_size(p: &Problem, text: &str, path: &Path) -> Result<(), ProblemError> {
    let z = run_size(p);
    let fail = |table: &str, key: &str, value: String, what: String| ProblemError::Invalid {
        file: path.into(),
        line: key_line(text, table, key),
        key: format!("{table}.{key}"),
        value,
        allowed: format!("{what} (or run with --force)"),
    };
    let dt = p.time.dt.map_or("(none)".into(), super::num);
    if z.steps > MAX_STEPS {
        return Err(fail(
            "time",
            "dt",
            dt,
            format!(
                "large enough that duration / dt is at most {MAX_STEPS:e} steps; this run would take {:e}",
                z.steps
            ),
        ));
    }
    let interval = p
        .output
        .interval
        .map_or("(default duration/100)".into(), super::num);
    if z.frames > MAX_FRAMES {
        return Err(fail(
            "output",
            "interval",
            interval,
            format!(
                "large enough to store at most {MAX_FRAMES:e} frames; this run would store {:e}",
                z.frames
            ),
        ));
    }
    if z.frames * z.nodes > MAX_FRAME_VALUES {
        return Err(fail(
            "output",
            "interval",
            interval,
            format!(
                "large enough that frames x nodes is at most {MAX_FRAME_VALUES:e}; this run would store {:e} frames of {} nodes",
                z.frames, z.nodes
            ),
        ));
    }
    if z.topology_pairs > MAX_TOPOLOGY_PAIRS {
        return Err(fail(
            "output",
            "interval",
            interval,
            format!(
                "large enough that the post-processing (frames x 0.6 x nodes^2 = {:.2e} segment pairs for {:e} frames of {} nodes) stays below {MAX_TOPOLOGY_PAIRS:e}; raise the interval or lower rod.elements",
                z.topology_pairs, z.frames, z.nodes
            ),
        ));
    }
    Ok(())
}
