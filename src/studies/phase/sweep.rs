//! The sweep over the grid (whole or one shard): cells in parallel, each appended to
//! `phase.csv` when done, then the boundaries and the figures.
use super::boundaries::{boundaries, fit_boundaries, Boundary};
use super::cell::{simulate_verified, Cell};
use super::csv::{append_rows, read_phase_csv, simulate_appending};
use super::file::{Phase, Protocol, Verify};
use super::growth::{self, Growth, GrowthLine};
use super::refine::{self, Refinement};
use super::PhaseError;
use crate::observe::Regime;
use crate::plot::{self, phase as figs};
use crate::problem::Problem;
use crate::studies::accuracy::StudyAccuracy;
use crate::studies::optimize::Status;
use std::path::{Path, PathBuf};

/// What a sweep produced.
#[derive(Debug)]
pub struct Sweep {
    /// Every cell, weight-major (`cells[i * torque.len() + j]` is `(weight[i], torque[j])`).
    pub cells: Vec<Cell>,
    /// Cells simulated in this call.
    pub simulated: usize,
    /// Cells reused from an existing `phase.csv`.
    pub reused: usize,
    /// An incomplete last line of `phase.csv` (a write cut short by a crash) was dropped.
    pub dropped_partial_row: bool,
    /// The bisection of the boundaries, when the phase file asked for it and the run holds the
    /// whole grid.
    pub refinement: Option<Refinement>,
    /// The growth line (`growth = { ... }`) and how many of its sizes were simulated now,
    /// when the run holds the whole grid.
    pub growth: Option<(GrowthLine, usize)>,
}

/// One share of a sweep's cells: `index` of `count` (1-based), for spreading a study over a
/// job array. Cell `k` of the grid (weight-major) belongs to shard `k % count + 1`: a
/// deterministic split in which every cell is in exactly one shard.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Shard {
    /// This shard, 1..=count.
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

impl Shard {
    /// Whether grid cell `k` (weight-major) is in this shard.
    pub fn owns(&self, k: usize) -> bool {
        k % self.count == self.index - 1
    }
}

impl std::str::FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || format!("`{s}`: a shard is I/N with integers 1 <= I <= N (e.g. 2/4)");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count) = (
            i.trim().parse::<usize>().map_err(|_| bad())?,
            n.trim().parse::<usize>().map_err(|_| bad())?,
        );
        if index == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

/// `phase.json`: what a sweep directory holds, so shards can be checked before merging.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunInfo {
    /// The phase file.
    pub phase_file: String,
    /// The base problem file.
    pub base_file: String,
    /// Hash of the effective base problem ([`crate::studies::problem_hash`], hex; with
    /// `[accuracy]` the chosen model's key).
    pub base_hash: String,
    /// Scaled weights of the grid.
    pub weight: Vec<f64>,
    /// Scaled torques of the grid.
    pub torque: Vec<f64>,
    /// The shard this directory holds (`null`: every cell).
    pub shard: Option<Shard>,
    /// Bisection steps of `refine = true` (`null`: no refinement); [`super::merge()`] refines with it.
    #[serde(default)]
    pub refine_steps: Option<usize>,
    /// The model chosen for the phase file's `[accuracy]` (absent without one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accuracy: Option<StudyAccuracy>,
    /// The cells' verification (`verify = { ... }`; `null` without one).
    #[serde(default)]
    pub verify: Option<Verify>,
    /// How the cells are made (`weight_via`, `similar`; absent: the default).
    #[serde(default, skip_serializing_if = "Protocol::is_default")]
    pub protocol: Protocol,
    /// The growth line (`growth = { ... }`; absent without one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub growth: Option<Growth>,
    /// The rows carry the periodic columns: the base gait has a launch period (absent: no).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub periodic: bool,
    /// The command-line settings the phase file was read with (`--set KEY=VALUE`, as
    /// `KEY=VALUE`; absent: none): `merge` reads the file again with them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub settings: Vec<String>,
}

impl RunInfo {
    /// The recorded settings, parsed again (`Err`: one that no longer parses).
    pub fn parsed_settings(&self) -> Result<Vec<crate::problem::set::Setting>, String> {
        self.settings.iter().map(|s| s.parse()).collect()
    }
}

pub(super) fn write_info(out: &Path, info: &RunInfo) -> Result<(), PhaseError> {
    let file = out.join("phase.json");
    let text = serde_json::to_string_pretty(info).expect("serialisable");
    std::fs::write(&file, text + "\n").map_err(|source| PhaseError::Io { file, source })
}

/// Run the diagram into `out` (`phase.csv`, `phase.json`, `boundaries.json` and the figures,
/// each as PNG and SVG, and with `refine = true` `refine.csv`), reusing finished rows.
/// `report(done, total, cell)` is called after each newly simulated cell of the grid,
/// `refine_report(done, cell)` after each new refinement simulation, `growth_report(done,
/// cell)` after each new simulation of the growth line.
pub fn sweep(
    ph: &Phase,
    out: &Path,
    report: &(dyn Fn(usize, usize, &Cell) + Sync),
    refine_report: &(dyn Fn(usize, &Cell) + Sync),
    growth_report: &(dyn Fn(usize, &Cell) + Sync),
) -> Result<Sweep, PhaseError> {
    sweep_shard(ph, out, None, report, refine_report, growth_report)
}

/// [`sweep`] of one shard's cells only (all with `None`). A shard's directory gets
/// `phase.csv` and `phase.json` but no figures and no refinement (unless it is the only shard,
/// `1/1`); [`super::merge()`] combines the shards.
pub fn sweep_shard(
    ph: &Phase,
    out: &Path,
    shard: Option<Shard>,
    report: &(dyn Fn(usize, usize, &Cell) + Sync),
    refine_report: &(dyn Fn(usize, &Cell) + Sync),
    growth_report: &(dyn Fn(usize, &Cell) + Sync),
) -> Result<Sweep, PhaseError> {
    let io = |file: &Path| {
        let file = file.to_path_buf();
        move |source| PhaseError::Io {
            file: file.clone(),
            source,
        }
    };
    std::fs::create_dir_all(out).map_err(io(out))?;
    let csv = out.join("phase.csv");
    let key = |w: f64, g: f64| (w.to_bits(), g.to_bits());
    let hash = ph.row_hash();
    let old = read_phase_csv(&csv, hash)?;
    let mut done = old.cells;
    let format = ph.format();
    let file = append_rows(&csv, old.fresh, old.format, format)?;
    write_info(
        out,
        &RunInfo {
            phase_file: ph.file.display().to_string(),
            base_file: ph.base_path.display().to_string(),
            base_hash: format!("{:016x}", ph.base_hash),
            weight: ph.weight.clone(),
            torque: ph.torque.clone(),
            shard,
            refine_steps: ph.refine,
            accuracy: ph.chosen.clone(),
            verify: ph.verify,
            protocol: ph.protocol,
            growth: ph.growth.clone(),
            periodic: format.periodic,
            settings: ph.settings.clone(),
        },
    )?;
    let grid: Vec<(f64, f64)> = ph
        .weight
        .iter()
        .flat_map(|&w| ph.torque.iter().map(move |&g| (w, g)))
        .enumerate()
        .filter(|(k, _)| shard.is_none_or(|s| s.owns(*k)))
        .map(|(_, c)| c)
        .collect();
    let todo: Vec<(f64, f64)> = grid
        .iter()
        .copied()
        .filter(|&(w, g)| !done.contains_key(&key(w, g)))
        .collect();
    let reused = grid.len() - todo.len();
    let new = simulate_appending(
        &todo,
        &|w, g| simulate_verified(&ph.base, w, g, ph.verify.as_ref(), ph.protocol),
        file,
        &csv,
        hash,
        format.periodic,
        &|done, c| report(done, todo.len(), c),
    )?;
    let simulated = new.len();
    for c in new {
        done.insert(key(c.weight, c.torque), c);
    }
    let cells: Vec<Cell> = grid
        .iter()
        .map(|&(w, g)| done[&key(w, g)].clone())
        .collect();
    let whole = shard.is_none_or(|s| s.count == 1);
    let refinement = if whole {
        let refine = ph
            .refine
            .map(|k| (&ph.base, hash, k, ph.verify, ph.protocol));
        finish(out, &ph.weight, &ph.torque, &cells, refine, refine_report)?
    } else {
        None
    };
    let growth = match (&ph.growth, whole) {
        (Some(g), true) => Some(grow(
            out,
            &ph.base,
            ph.base_hash,
            g,
            ph.verify.as_ref(),
            &cells,
            growth_report,
        )?),
        _ => None,
    };
    Ok(Sweep {
        cells,
        simulated,
        reused,
        dropped_partial_row: old.dropped_partial_row,
        refinement,
        growth,
    })
}

/// The end of a run that holds the whole grid: the boundary points (bisected when `refine`
/// gives the base problem, the rows' hash, the steps and the verification; else the cell
/// midpoints), `boundaries.json` and the figures. With verified cells only the unanimous ones
/// ([`Cell::unanimous`]) take part in the boundaries (as if failed), and `boundaries.json`
/// says how many cells and neighbour pairs were left out ([`Exclusions`]).
pub(super) fn finish(
    out: &Path,
    weight: &[f64],
    torque: &[f64],
    cells: &[Cell],
    refine: Option<(&Problem, u64, usize, Option<Verify>, Protocol)>,
    refine_report: &(dyn Fn(usize, &Cell) + Sync),
) -> Result<Option<Refinement>, PhaseError> {
    // A grid in which every cell failed has nothing to fit or draw: the command line reports
    // it (exit 3, "every cell failed") instead of a plot error.
    if cells.iter().all(|c| c.status != Status::Ok) {
        return Ok(None);
    }
    let verified = cells.iter().any(|c| c.verify.is_some());
    let labels = confident_labels(cells);
    let refinement = match refine {
        Some((base, hash, steps, verify, protocol)) => Some(refine::refine(
            base,
            hash,
            steps,
            verify.as_ref(),
            protocol,
            out,
            weight,
            torque,
            &labels,
            refine_report,
        )?),
        None => None,
    };
    let bounds = match &refinement {
        Some(r) => fit_boundaries(&r.points),
        None => boundaries(weight, torque, &labels),
    };
    let exclusions = verified.then(|| Exclusions::of(weight, torque, cells));
    figures(out, weight, torque, cells, &bounds, exclusions.as_ref())?;
    Ok(refinement)
}

/// The growth line of a whole grid: its simulations ([`growth::run`]) and its figure,
/// `growth.png` / `growth.svg`, over the grid's cells.
pub(super) fn grow(
    out: &Path,
    base: &Problem,
    base_hash: u64,
    g: &Growth,
    verify: Option<&Verify>,
    grid: &[Cell],
    report: &(dyn Fn(usize, &Cell) + Sync),
) -> Result<(GrowthLine, usize), PhaseError> {
    let (line, simulated) = growth::run(base, base_hash, g, verify, out, report)?;
    let mark = |c: &Cell| plot::growth::Mark {
        weight: c.weight,
        torque: c.torque,
        regime: c.regime,
        v_s_over_v_m: c.v_s_over_v_m,
        uncertain: c.regime.is_some() && !c.unanimous(),
        diameter: None,
    };
    let background: Vec<plot::growth::Mark> = grid.iter().map(mark).collect();
    let sizes: Vec<plot::growth::Mark> = line
        .points
        .iter()
        .map(|r| plot::growth::Mark {
            weight: r.point.weight,
            torque: r.point.torque,
            regime: r.regime.parse().ok(),
            v_s_over_v_m: r.v_s_over_v_m,
            uncertain: !r.confident,
            diameter: Some(r.point.diameter),
        })
        .collect();
    for ext in ["png", "svg"] {
        let f = out.join(format!("growth.{ext}"));
        plot::growth::growth_chart(&f, &background, &sizes, &line.verdict).map_err(|source| {
            PhaseError::Plot {
                file: f.clone(),
                source,
            }
        })?;
    }
    Ok((line, simulated))
}

/// The labels the boundaries are fitted through: each cell's, `None` for a failed cell and for
/// a verified cell whose runs disagree ([`Cell::unanimous`]).
pub fn confident_labels(cells: &[Cell]) -> Vec<Option<Regime>> {
    cells
        .iter()
        .map(|c| c.regime.filter(|_| c.unanimous()))
        .collect()
}

/// What the boundary fits of a verified study left out (`boundaries.json`).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Exclusions {
    /// Cells that finished but whose runs disagree on the label (agreement below 1).
    pub excluded_cells: usize,
    /// Neighbour pairs of different labels (the pairs a boundary is fitted through) that were
    /// left out because a cell of the pair is not unanimous.
    pub excluded_pairs: usize,
    /// The left-out cells, `[W, G, label_agreement]`.
    pub uncertain: Vec<[f64; 3]>,
}

impl Exclusions {
    /// The exclusions of a weight-major grid of cells.
    pub fn of(weight: &[f64], torque: &[f64], cells: &[Cell]) -> Self {
        let all: Vec<Option<Regime>> = cells.iter().map(|c| c.regime).collect();
        let kept = confident_labels(cells);
        let (a, b) = (
            refine::neighbour_pairs(weight, torque, &all).len(),
            refine::neighbour_pairs(weight, torque, &kept).len(),
        );
        let uncertain: Vec<[f64; 3]> = cells
            .iter()
            .filter(|c| c.regime.is_some() && !c.unanimous())
            .map(|c| {
                let agreement = c.verify.as_ref().map_or(1.0, |v| v.label_agreement);
                [c.weight, c.torque, agreement]
            })
            .collect();
        Exclusions {
            excluded_cells: uncertain.len(),
            excluded_pairs: a - b,
            uncertain,
        }
    }
}

/// `boundaries.json` of a verified study: the lines and what their fits left out.
#[derive(serde::Serialize)]
struct VerifiedBoundaries<'a> {
    boundaries: &'a [Boundary],
    #[serde(flatten)]
    exclusions: &'a Exclusions,
}

/// The figures of a complete grid, each as PNG and SVG (`phase`, `speed`, Fig. 3a-c, drawn
/// by [`crate::plot::phase`]), and `boundaries.json` (the lines `bounds`). Fig. 3a and 3b are
/// skipped when they have no finite point.
fn figures(
    out: &Path,
    weight: &[f64],
    torque: &[f64],
    cells: &[Cell],
    bounds: &[Boundary],
    exclusions: Option<&Exclusions>,
) -> Result<(), PhaseError> {
    let file = out.join("boundaries.json");
    // Without verification the file is the array of lines, as it always was.
    let text = match exclusions {
        Some(exclusions) => serde_json::to_string_pretty(&VerifiedBoundaries {
            boundaries: bounds,
            exclusions,
        }),
        None => serde_json::to_string_pretty(bounds),
    }
    .expect("serialisable");
    std::fs::write(&file, text + "\n").map_err(|source| PhaseError::Io { file, source })?;
    let cells: Vec<figs::MapCell> = cells
        .iter()
        .map(|c| figs::MapCell {
            weight: c.weight,
            torque: c.torque,
            ok: c.status == Status::Ok,
            regime: c.regime,
            regime_detail: &c.regime_detail,
            v_s_over_v_m: c.v_s_over_v_m,
            writhe_max: c.writhe_max,
            writhe_snapshot: c.writhe_snapshot,
            uncertain: c.regime.is_some() && !c.unanimous(),
            sidewinding: c.periodic.map(|p| p.sidewinding),
        })
        .collect();
    let lines: Vec<figs::MapLine> = bounds
        .iter()
        .map(|b| figs::MapLine {
            pair: &b.pair,
            slope: b.slope,
            intercept: b.intercept,
            ratio_at_g10: b.ratio_at_g10,
            bisected: b.method == "bisection",
            points: b.points.iter().map(|p| (p.w, p.g)).collect(),
        })
        .collect();
    let plot_err = |file: PathBuf| move |source| PhaseError::Plot { file, source };
    // Fig. 3a and 3b without a finite point are left out.
    let skip_empty = |r: Result<(), PhaseError>| match r {
        Err(PhaseError::Plot {
            source: plot::PlotError::Invalid(_),
            ..
        }) => Ok(()),
        r => r,
    };
    for ext in ["png", "svg"] {
        let f = out.join(format!("phase.{ext}"));
        figs::regime_map(&f, weight, torque, &cells, &lines).map_err(plot_err(f.clone()))?;
        let f = out.join(format!("speed.{ext}"));
        figs::speed_chart(&f, torque, &cells).map_err(plot_err(f.clone()))?;
        let f = out.join(format!("writhe_vs_ratio.{ext}"));
        skip_empty(figs::writhe_vs_ratio(&f, torque, &cells).map_err(plot_err(f.clone())))?;
        let f = out.join(format!("speed_vs_writhe.{ext}"));
        skip_empty(figs::speed_vs_writhe(&f, &cells).map_err(plot_err(f.clone())))?;
        let f = out.join(format!("speed_vs_ratio.{ext}"));
        figs::speed_chart(&f, torque, &cells).map_err(plot_err(f.clone()))?;
    }
    Ok(())
}
