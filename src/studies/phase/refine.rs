//! Regime boundaries located by bisection between neighbouring cells (`[phase] refine = true`).
//!
//! A grid cell pair whose regimes differ says only that a boundary crosses the segment between
//! the two cell centres; the midpoint fit of [`super::boundaries()`] puts the crossing at
//! the segment's log-midpoint, so each point is uncertain by half a grid spacing. With
//! `refine = true` every such pair is bisected along its segment, in log scale: for two
//! neighbours in the same `G` row (a ray of constant `G`) the base scene is simulated at the
//! geometric midpoint `W_m = sqrt(W_lo W_hi)` (the same `G`, set the way the grid sets it,
//! [`super::cell_problem`]), labelled by the same regime test, and the half whose ends
//! still differ is kept; `refine_steps = K` times. Neighbours in the same `W` column are
//! bisected the same way in `G` (a ray of constant `W`): the boundaries slither finds are
//! flatter than the paper's (slopes well below 1), and a nearly flat line is crossed mostly by
//! such pairs.
//!
//! The boundary point is the last interval's geometric midpoint; its uncertainty, the interval's
//! half-width in decades along the pair's axis, is `h_K = log10(hi / lo) / 2^(K + 1)`, a factor
//! `2^K` below the midpoint fit's. If a midpoint shows a third regime, both halves have ends of
//! different regimes and both are bisected further with the steps left (each then yields a point
//! of its own pair of regimes, e.g. `F/M` and `M/N` from an `F/N` pair). If a simulation fails,
//! that interval stops: its point is the midpoint of the interval reached so far (the grid
//! pair's own midpoint when the first simulation fails), marked with the failure and the steps
//! done, never dropped.
//!
//! The lines are then fitted through these points exactly as through the midpoints
//! ([`super::fit_boundaries`]). Every refinement simulation is appended to `refine.csv`
//! (the columns of `phase.csv`) as it finishes, and a rerun answers every midpoint already in
//! the file for the same base file (hash) from its row; at the end the file is rewritten in a
//! fixed order (by `G`, then `W`), so its content does not depend on which simulation finished
//! first. Pairs are bisected in parallel (rayon, one pair per core; the steps of one pair run one
//! after another, as each depends on the last).

use super::cell::{simulate_verified, Cell};
use super::csv::{append_rows, read_rows, Format};
use super::file::{Protocol, Verify};
use super::PhaseError;
use crate::observe::Regime;
use crate::problem::Problem;
use rayon::prelude::*;
use serde::Serialize;
use std::collections::HashMap;
use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// The grid axis along which two neighbouring cells (and their bisection) lie.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Axis {
    /// Same `G`, neighbouring `W` (a ray of constant `G`).
    W,
    /// Same `W`, neighbouring `G`.
    G,
}

/// Two neighbouring grid cells of different regimes, `lo` before `hi` along `axis`.
#[derive(Clone, Debug, PartialEq)]
pub struct Neighbours {
    /// The axis they differ in.
    pub axis: Axis,
    /// `(W, G)` of the cell lower along `axis`, and its regime.
    pub lo: ((f64, f64), Regime),
    /// `(W, G)` of the other cell, and its regime.
    pub hi: ((f64, f64), Regime),
}

/// Every pair of neighbouring cells (along `W` and along `G`, both with `G > 0`) of a
/// weight-major grid of labels whose regimes differ (`None`: a failed cell, not used), in grid
/// order: for each cell, its `W` neighbour, then its `G` neighbour.
pub fn neighbour_pairs(
    weight: &[f64],
    torque: &[f64],
    labels: &[Option<Regime>],
) -> Vec<Neighbours> {
    let nt = torque.len();
    let mut out = Vec::new();
    let mut add = |axis: Axis, a: (usize, usize), b: (usize, usize)| {
        if let (Some(ra), Some(rb)) = (labels[a.0 * nt + a.1], labels[b.0 * nt + b.1]) {
            if ra != rb && torque[a.1] > 0.0 && torque[b.1] > 0.0 {
                out.push(Neighbours {
                    axis,
                    lo: ((weight[a.0], torque[a.1]), ra),
                    hi: ((weight[b.0], torque[b.1]), rb),
                });
            }
        }
    };
    for i in 0..weight.len() {
        for j in 0..nt {
            if i + 1 < weight.len() {
                add(Axis::W, (i, j), (i + 1, j));
            }
            if j + 1 < nt {
                add(Axis::G, (i, j), (i, j + 1));
            }
        }
    }
    out
}

/// How a boundary point was placed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Placement {
    /// The log-midpoint of the two grid cells.
    Midpoint,
    /// The log-midpoint of the interval left after one or more bisection steps.
    Bisection,
}

/// One point on a regime boundary, as written to `boundaries.json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BoundaryPoint {
    /// The two regimes on either side, alphabetical (`"F/N"`).
    #[serde(skip)]
    pub pair: String,
    /// Scaled weight `W` of the point.
    pub w: f64,
    /// Scaled torque `G` of the point.
    pub g: f64,
    /// The axis it was located along (the other coordinate is a grid value).
    pub along: Axis,
    /// Half-width, in decades of `along`, of the interval the boundary was bracketed in: the
    /// point's uncertainty.
    pub half_width: f64,
    /// Midpoint of the grid pair, or bisection.
    pub method: Placement,
    /// Bisection steps done (the `refine_steps` asked for, unless a simulation failed).
    pub steps: usize,
    /// Why a bisection simulation failed (its interval stopped there); `null` otherwise.
    pub failed: Option<String>,
    /// The grid cells `[[W, G], [W, G]]` the point lies between.
    pub cells: [[f64; 2]; 2],
}

/// The regime pair's name: the two one-letter names in alphabetical order, `/` between.
pub fn pair_name(a: Regime, b: Regime) -> String {
    let (x, y) = if a.as_str() < b.as_str() {
        (a, b)
    } else {
        (b, a)
    };
    format!("{}/{}", x.as_str(), y.as_str())
}

/// The point of the interval `[lo, hi]` (coordinates along the pair's axis) of pair `n`.
fn point(
    n: &Neighbours,
    lo: (f64, Regime),
    hi: (f64, Regime),
    steps: usize,
    failed: Option<String>,
) -> BoundaryPoint {
    let m = (lo.0 * hi.0).sqrt();
    let ((w0, g0), _) = n.lo;
    let (w, g) = match n.axis {
        Axis::W => (m, g0),
        Axis::G => (w0, m),
    };
    BoundaryPoint {
        pair: pair_name(lo.1, hi.1),
        w,
        g,
        along: n.axis,
        half_width: 0.5 * (hi.0 / lo.0).log10(),
        method: if steps > 0 {
            Placement::Bisection
        } else {
            Placement::Midpoint
        },
        steps,
        failed,
        cells: [[n.lo.0 .0, n.lo.0 .1], [n.hi.0 .0, n.hi.0 .1]],
    }
}

/// The midpoint of a grid pair (no simulation).
pub fn midpoint(n: &Neighbours) -> BoundaryPoint {
    let along = |c: (f64, f64)| match n.axis {
        Axis::W => c.0,
        Axis::G => c.1,
    };
    point(n, (along(n.lo.0), n.lo.1), (along(n.hi.0), n.hi.1), 0, None)
}

/// Bisect one grid pair `steps` times in log scale along its axis (see the module doc), with
/// `label(W, G)` the regime of a simulation there (`Err(reason)` when it failed). Returns the
/// pair's points, lowest first: one, or more when a midpoint showed a third regime.
pub fn bisect(
    n: &Neighbours,
    steps: usize,
    label: &dyn Fn(f64, f64) -> Result<Regime, String>,
) -> Vec<BoundaryPoint> {
    let ((w0, g0), _) = n.lo;
    let along = |c: (f64, f64)| match n.axis {
        Axis::W => c.0,
        Axis::G => c.1,
    };
    let at = |x: f64| match n.axis {
        Axis::W => (x, g0),
        Axis::G => (w0, x),
    };
    let mut out = Vec::new();
    // A stack of intervals (lower end, upper end, steps done); the lower half is pushed last so
    // it is taken first and the points come out in order along the axis.
    let mut work = vec![((along(n.lo.0), n.lo.1), (along(n.hi.0), n.hi.1), 0usize)];
    while let Some((lo, hi, done)) = work.pop() {
        if done == steps {
            out.push(point(n, lo, hi, done, None));
            continue;
        }
        let m = (lo.0 * hi.0).sqrt();
        let (w, g) = at(m);
        match label(w, g) {
            Err(why) => out.push(point(n, lo, hi, done, Some(why))),
            Ok(r) => {
                if r != hi.1 {
                    work.push(((m, r), hi, done + 1));
                }
                if r != lo.1 {
                    work.push((lo, (m, r), done + 1));
                }
            }
        }
    }
    out
}

/// [`bisect`] every pair, in parallel (rayon, one pair per task), the points in pair order.
pub fn bisect_all(
    pairs: &[Neighbours],
    steps: usize,
    label: &(dyn Fn(f64, f64) -> Result<Regime, String> + Sync),
) -> Vec<BoundaryPoint> {
    let per_pair: Vec<Vec<BoundaryPoint>> =
        pairs.par_iter().map(|n| bisect(n, steps, label)).collect();
    per_pair.into_iter().flatten().collect()
}

/// What a refinement did.
#[derive(Debug)]
pub struct Refinement {
    /// Bisection steps asked for per pair.
    pub steps: usize,
    /// Neighbour pairs of different regimes that were bisected.
    pub pairs: usize,
    /// The boundary points, in pair order.
    pub points: Vec<BoundaryPoint>,
    /// Refinement simulations run in this call (rows appended to `refine.csv`).
    pub simulated: usize,
    /// Midpoints answered from rows of an earlier run.
    pub reused: usize,
    /// Midpoints whose simulation failed (run now or earlier), each ending its interval.
    pub failed: usize,
    /// An incomplete last line of `refine.csv` (a write cut short by a crash) was dropped.
    pub dropped_partial_row: bool,
}

/// Refine the boundaries of a complete grid (`labels` weight-major over `weight` x `torque`,
/// `None` for a cell that takes no part: failed, or not unanimous in a verified study)
/// by bisection of every neighbour pair of different regimes, `steps` times, simulating
/// `base` at the midpoints and keeping the simulations in `out/refine.csv` under the rows'
/// hash `base_hash` (see the module doc). With `verify` every midpoint is verified like a grid
/// cell ([`simulate_verified`]): the bisection follows its reported (finest) label, and its
/// row in `refine.csv` has the agreement of its runs. `report(done, cell)` is called after
/// each new simulation. The midpoints are made from `base` by `protocol`, as the grid's cells.
#[allow(clippy::too_many_arguments)]
pub fn refine(
    base: &Problem,
    base_hash: u64,
    steps: usize,
    verify: Option<&Verify>,
    protocol: Protocol,
    out: &Path,
    weight: &[f64],
    torque: &[f64],
    labels: &[Option<Regime>],
    report: &(dyn Fn(usize, &Cell) + Sync),
) -> Result<Refinement, PhaseError> {
    let csv = out.join("refine.csv");
    let io = |file: &Path| {
        let file = file.to_path_buf();
        move |source| PhaseError::Io {
            file: file.clone(),
            source,
        }
    };
    let key = |w: f64, g: f64| (w.to_bits(), g.to_bits());
    let old = read_rows(&csv)?;
    let cache: HashMap<(u64, u64), Cell> = old
        .rows
        .iter()
        .filter(|(_, h)| *h == base_hash)
        .map(|(c, _)| (key(c.weight, c.torque), c.clone()))
        .collect();
    let format = Format::of(base, verify);
    let file = append_rows(&csv, old.fresh, old.format, format)?;
    let pairs = neighbour_pairs(weight, torque, labels);
    let (reused, failed) = (AtomicUsize::new(0), AtomicUsize::new(0));
    // The file, the new rows and the first write error.
    let sink = Mutex::new((file, Vec::<Cell>::new(), None::<std::io::Error>));
    let label = |w: f64, g: f64| {
        let c = match cache.get(&key(w, g)) {
            Some(c) => {
                reused.fetch_add(1, Ordering::Relaxed);
                c.clone()
            }
            None => {
                let c = simulate_verified(base, w, g, verify, protocol);
                let mut s = sink.lock().unwrap_or_else(|e| e.into_inner());
                let line = c.row(base_hash, format.periodic) + "\n";
                let r = s.0.write_all(line.as_bytes()).and_then(|_| s.0.flush());
                if let Err(e) = r {
                    s.2.get_or_insert(e);
                }
                s.1.push(c.clone());
                report(s.1.len(), &c);
                c
            }
        };
        c.regime.ok_or_else(|| {
            failed.fetch_add(1, Ordering::Relaxed);
            c.reason.clone()
        })
    };
    let points = bisect_all(&pairs, steps, &label);
    let (file, new, err) = sink.into_inner().unwrap_or_else(|e| e.into_inner());
    drop(file);
    if let Some(e) = err {
        return Err(io(&csv)(e));
    }
    let simulated = new.len();
    // Rewrite the file in a fixed order (G, then W, then base hash), through a temporary file
    // renamed over it, so an interruption leaves the old or the new file, never half of one.
    let mut rows: Vec<(Cell, u64)> = old.rows;
    rows.extend(new.into_iter().map(|c| (c, base_hash)));
    rows.sort_by(|(a, ha), (b, hb)| {
        a.torque
            .total_cmp(&b.torque)
            .then(a.weight.total_cmp(&b.weight))
            .then(ha.cmp(hb))
    });
    let mut text = format!("{}\n", format.header());
    for (c, h) in &rows {
        text += &(c.row(*h, format.periodic) + "\n");
    }
    let tmp = out.join("refine.csv.tmp");
    std::fs::write(&tmp, text).map_err(io(&tmp))?;
    std::fs::rename(&tmp, &csv).map_err(io(&csv))?;
    Ok(Refinement {
        steps,
        pairs: pairs.len(),
        points,
        simulated,
        reused: reused.into_inner(),
        failed: failed.into_inner(),
        dropped_partial_row: old.dropped_partial_row,
    })
}

/// The boundaries of a grid of labels with each neighbour pair's point placed at its midpoint
/// (no simulation).
pub fn midpoint_points(
    weight: &[f64],
    torque: &[f64],
    labels: &[Option<Regime>],
) -> Vec<BoundaryPoint> {
    neighbour_pairs(weight, torque, labels)
        .iter()
        .map(midpoint)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::studies::phase::{boundaries, fit_boundaries};
    use std::sync::atomic::AtomicUsize;

    /// A labeller set by `W/G` alone: S below 20, F up to 60, N beyond (the paper's kind of
    /// boundaries: lines of slope 1 at `W/G` 20 and 60).
    fn by_ratio(w: f64, g: f64) -> Regime {
        match w / g {
            r if r < 20.0 => Regime::S,
            r if r < 60.0 => Regime::F,
            _ => Regime::N,
        }
    }

    /// One point per decade of `W` and three per two decades of `G`: a coarse grid whose cell
    /// midpoints miss the lines by up to a quarter decade.
    fn coarse() -> (Vec<f64>, Vec<f64>, Vec<Option<Regime>>) {
        let weight: Vec<f64> = (1..=4).map(|k| 10f64.powi(k)).collect();
        let torque: Vec<f64> = (0..4).map(|k| 10f64.powf(2.0 * k as f64 / 3.0)).collect();
        let labels = weight
            .iter()
            .flat_map(|&w| torque.iter().map(move |&g| Some(by_ratio(w, g))))
            .collect();
        (weight, torque, labels)
    }

    /// The distance, in decades along the point's axis, from the true line `W/G = ratio`.
    fn miss(p: &BoundaryPoint, ratio: f64) -> f64 {
        match p.along {
            Axis::W => (p.w / (ratio * p.g)).log10().abs(),
            Axis::G => (p.g / (p.w / ratio)).log10().abs(),
        }
    }

    #[test]
    fn bisection_recovers_lines_of_constant_ratio_better_than_midpoints() {
        let (weight, torque, labels) = coarse();
        let pairs = neighbour_pairs(&weight, &torque, &labels);
        assert!(pairs.len() >= 6, "{} pairs", pairs.len());
        let steps = 6;
        let calls = AtomicUsize::new(0);
        let label = |w: f64, g: f64| {
            calls.fetch_add(1, Ordering::Relaxed);
            Ok(by_ratio(w, g))
        };
        let points = bisect_all(&pairs, steps, &label);
        // Every pair is bisected: at least `steps` simulations each, and no point is dropped.
        assert!(calls.into_inner() >= steps * pairs.len());
        assert!(points.len() >= pairs.len());
        let truth = |pair: &str| if pair == "F/S" { 20.0 } else { 60.0 };
        for p in &points {
            assert_eq!(p.method, Placement::Bisection);
            assert_eq!(p.steps, steps);
            assert!(p.failed.is_none());
            // The interval is 2^steps times narrower than the grid spacing it started from.
            let spacing = match p.along {
                Axis::W => 1.0,
                Axis::G => 2.0 / 3.0,
            };
            assert!((p.half_width - 0.5 * spacing / 64.0).abs() < 1e-12, "{p:?}");
            // The true boundary lies inside the bracket.
            assert!(miss(p, truth(&p.pair)) <= p.half_width + 1e-12, "{p:?}");
        }
        let bisected = fit_boundaries(&points);
        let mids = boundaries(&weight, &torque, &labels);
        let names: Vec<&str> = bisected.iter().map(|b| b.pair.as_str()).collect();
        assert_eq!(names, ["F/N", "F/S"]);
        // The coarse grid has S cells next to N cells (the F band between them falls inside
        // one spacing): the midpoint fit reports an N/S boundary that does not exist, which the
        // bisection splits into its F/S and F/N points.
        assert_eq!(
            mids.iter().map(|b| b.pair.as_str()).collect::<Vec<_>>(),
            ["F/N", "F/S", "N/S"]
        );
        for (b, m) in bisected.iter().zip(&mids) {
            assert_eq!((b.method, m.method), ("bisection", "midpoints"));
            let ratio = truth(&b.pair);
            let h = b.points.iter().map(|p| p.half_width).fold(0.0, f64::max);
            let (s, r) = (b.slope.unwrap(), b.ratio_at_g10.unwrap());
            let (sm, rm) = (m.slope.unwrap(), m.ratio_at_g10.unwrap());
            // Slope 1 and the true W/G at G = 10 within the final half-width ...
            assert!((s - 1.0).abs() < 0.01, "{}: slope {s}", b.pair);
            assert!((r / ratio).log10().abs() <= h, "{}: W/G {r}", b.pair);
            // ... and closer to both than the fit through the cell midpoints.
            assert!(
                (s - 1.0).abs() < (sm - 1.0).abs(),
                "{}: {s} vs {sm}",
                b.pair
            );
            assert!(
                (r / ratio).log10().abs() < (rm / ratio).log10().abs(),
                "{}: {r} vs {rm}",
                b.pair
            );
            // (The midpoints of this grid lie on straight lines of slope 2/3 through W/G 10 and
            // 100, so their residual says nothing about how far off the line is.)
        }
    }

    #[test]
    fn a_third_regime_inside_a_pair_splits_it() {
        // S at W = 1, N at W = 1e4 (G = 1): F between W/G 20 and 60 is found inside, and the
        // pair yields an F/S and an F/N point, in order along W.
        let n = Neighbours {
            axis: Axis::W,
            lo: ((1.0, 1.0), Regime::S),
            hi: ((1e4, 1.0), Regime::N),
        };
        let pts = bisect(&n, 8, &|w, g| Ok(by_ratio(w, g)));
        let names: Vec<&str> = pts.iter().map(|p| p.pair.as_str()).collect();
        assert_eq!(names, ["F/S", "F/N"]);
        assert!(miss(&pts[0], 20.0) <= pts[0].half_width);
        assert!(miss(&pts[1], 60.0) <= pts[1].half_width);
        assert!(pts.iter().all(|p| p.cells == [[1.0, 1.0], [1e4, 1.0]]));
    }

    #[test]
    fn a_failed_simulation_stops_its_interval_and_keeps_the_point() {
        let (weight, torque, labels) = coarse();
        let pairs = neighbour_pairs(&weight, &torque, &labels);
        // Every simulation fails: each pair keeps its grid midpoint, marked.
        let pts = bisect_all(&pairs, 3, &|_, _| Err("step rejected".into()));
        assert_eq!(pts.len(), pairs.len());
        for (p, n) in pts.iter().zip(&pairs) {
            let m = midpoint(n);
            assert_eq!((p.method, p.steps), (Placement::Midpoint, 0));
            assert_eq!(p.failed.as_deref(), Some("step rejected"));
            assert_eq!((p.w, p.g, p.half_width), (m.w, m.g, m.half_width));
        }
        assert!(fit_boundaries(&pts).iter().all(|b| b.method == "midpoints"));
        // Failing beyond W = 300 only: pairs there stop after the steps that succeeded, with
        // the bracket they reached (which still holds the true boundary).
        let pts = bisect_all(&pairs, 4, &|w, g| {
            if w > 300.0 {
                Err("failed".into())
            } else {
                Ok(by_ratio(w, g))
            }
        });
        let early: Vec<&BoundaryPoint> = pts.iter().filter(|p| p.failed.is_some()).collect();
        assert!(!early.is_empty() && early.len() < pts.len());
        for p in &pts {
            let ratio = if p.pair == "F/S" { 20.0 } else { 60.0 };
            assert!(miss(p, ratio) <= p.half_width + 1e-12, "{p:?}");
            assert_eq!(p.failed.is_some(), p.steps < 4, "{p:?}");
        }
    }
}
