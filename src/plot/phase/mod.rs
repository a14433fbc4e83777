//! The figures of a regime phase diagram ([`crate::studies::phase`]): the regime map over
//! scaled weight and torque with its fitted boundary lines, the speed chart, and the paper's
//! Fig. 3 (writhe against `W/G`, speed against writhe). The diagram's cells and lines come in
//! as [`MapCell`] and [`MapLine`], the values a figure shows, so this layer needs nothing of
//! the study that computed them.
//!
//! One file per job: the map and its legend (`map.rs`), the map's axes, ticks and boundary
//! segments (`axis.rs`), and the x-y charts (`charts.rs`).

mod axis;
mod charts;
mod map;

pub use axis::{boundary_segment, grid_ticks, supported_box, GridAxis};
pub use charts::{shown_torques, speed_chart, speed_vs_writhe, writhe_vs_ratio, MAX_TORQUE_SERIES};
pub use map::{label_stack, regime_map};

use crate::observe::Regime;
use plotters::prelude::RGBColor;

/// A cell of the diagram, as the figures show it.
#[derive(Clone, Debug)]
pub struct MapCell<'a> {
    /// Scaled weight `W`.
    pub weight: f64,
    /// Scaled torque `G`.
    pub torque: f64,
    /// The cell's simulation finished (else drawn as failed).
    pub ok: bool,
    /// Regime (`None` when failed).
    pub regime: Option<Regime>,
    /// For `M`: the S criteria it missed, `;`-separated; "-" otherwise.
    pub regime_detail: &'a str,
    /// `v_s / v_m`.
    pub v_s_over_v_m: f64,
    /// Largest |writhe| (turns).
    pub writhe_max: f64,
    /// Writhe at the snapshot instant (turns).
    pub writhe_snapshot: f64,
    /// The cell's verification runs disagree on its label (drawn hatched and outlined).
    pub uncertain: bool,
    /// Whether the cell sidewinds (every sidewinding criterion holds in every cycle), for a
    /// gait with a launch period; `None` otherwise (other gaits, failed runs, `G = 0`). A
    /// sidewinding cell is written "sidewinding" under its label (its label starred on a wide
    /// grid).
    pub sidewinding: Option<bool>,
}

/// A fitted boundary line, as the regime map draws it.
#[derive(Clone, Debug)]
pub struct MapLine<'a> {
    /// The two regimes, e.g. "F/N".
    pub pair: &'a str,
    /// Slope of `log10 G = slope log10 W + intercept` (`None`: not fitted, not drawn).
    pub slope: Option<f64>,
    /// Intercept of `log10 G` at `log10 W = 0`.
    pub intercept: Option<f64>,
    /// `W/G` on the line at `G = 10`.
    pub ratio_at_g10: Option<f64>,
    /// At least one point was placed by bisection (the points are then drawn as dots).
    pub bisected: bool,
    /// The fitted points `(W, G)`.
    pub points: Vec<(f64, f64)>,
}

/// Colour of a regime in the map (dark grey for a failed cell).
pub fn regime_color(r: Option<Regime>) -> RGBColor {
    match r {
        Some(Regime::S) => RGBColor(90, 180, 100),
        Some(Regime::M) => RGBColor(100, 150, 230),
        Some(Regime::F) => RGBColor(240, 170, 80),
        Some(Regime::N) => RGBColor(190, 190, 190),
        Some(Regime::U) => RGBColor(220, 80, 80),
        None => RGBColor(60, 60, 60),
    }
}

/// How many cells have each regime (in [`Regime::ALL`] order), and how many failed.
pub fn regime_counts(cells: &[MapCell]) -> ([(Regime, usize); 5], usize) {
    let count = |r: Regime| cells.iter().filter(|c| c.regime == Some(r)).count();
    (
        Regime::ALL.map(|r| (r, count(r))),
        cells.iter().filter(|c| c.regime.is_none()).count(),
    )
}

/// Grids with more weight columns than this label each cell with its regime letter only (the
/// `v_s/v_m` value and the M detail no longer fit in a cell of the 1000 px wide map).
pub const FULL_LABEL_MAX_COLUMNS: usize = 8;
