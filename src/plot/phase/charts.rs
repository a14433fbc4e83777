//! The phase study's x-y charts: `v_s/v_m` against `W/G` (one series per shown torque) and the
//! paper's Fig. 3 (writhe against `W/G`, speed against writhe).

use super::axis::short;
use super::{regime_color, MapCell};
use crate::observe::Regime;
use crate::plot::PlotError;
use plotters::prelude::RGBColor;
use std::path::Path;

/// Most torques drawn as separate series in the speed and writhe charts: a finer grid shows
/// this many, evenly spread over the grid's indices (first and last included), so the legend
/// stays readable; the regime map and `phase.csv` keep every cell.
pub const MAX_TORQUE_SERIES: usize = 6;

/// The torques drawn as series: all when at most [`MAX_TORQUE_SERIES`], else that many spread
/// evenly over the indices.
pub fn shown_torques(torque: &[f64]) -> Vec<f64> {
    let n = torque.len();
    if n <= MAX_TORQUE_SERIES {
        return torque.to_vec();
    }
    let m = MAX_TORQUE_SERIES;
    (0..m)
        .map(|i| torque[(i * (n - 1) + (m - 1) / 2) / (m - 1)])
        .collect()
}

/// `v_s / v_m` against `W / G` (the paper's speed chart), one series per torque (at most
/// [`MAX_TORQUE_SERIES`], see [`shown_torques`]).
pub fn speed_chart(path: &Path, torque: &[f64], cells: &[MapCell]) -> Result<(), PlotError> {
    let torque = shown_torques(torque);
    let names: Vec<String> = torque
        .iter()
        .map(|&g| format!("G = {}", short(g)))
        .collect();
    let series: Vec<(&str, Vec<(f64, f64)>)> = torque
        .iter()
        .zip(&names)
        .map(|(&g, name)| {
            let mut pts: Vec<(f64, f64)> = cells
                .iter()
                .filter(|c| c.torque == g && c.ok)
                .map(|c| (c.weight / c.torque, c.v_s_over_v_m))
                .collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            (name.as_str(), pts)
        })
        .collect();
    crate::plot::xy(
        path,
        "Forward speed against weight over torque",
        "W / G = rho g L^2 / (Gamma a)",
        "v_s / v_m",
        &series,
        true,
        false,
    )
}

/// Fig. 3a of the paper (`writhe_vs_ratio.png`): the largest writhe and the writhe at the
/// snapshot instant against `W/G`, one pair of series per shown torque ([`shown_torques`],
/// `G > 0`), from the finished cells with `G > 0`. [`PlotError::Invalid`] when no point is
/// finite.
pub fn writhe_vs_ratio(path: &Path, torque: &[f64], cells: &[MapCell]) -> Result<(), PlotError> {
    let ok: Vec<&MapCell> = cells.iter().filter(|c| c.ok && c.torque > 0.0).collect();
    let mut names = Vec::new();
    let mut pts = Vec::new();
    for g in shown_torques(torque).into_iter().filter(|&g| g > 0.0) {
        let mut max: Vec<(f64, f64)> = Vec::new();
        let mut snap: Vec<(f64, f64)> = Vec::new();
        for c in ok.iter().filter(|c| c.torque == g) {
            max.push((c.weight / c.torque, c.writhe_max));
            snap.push((c.weight / c.torque, c.writhe_snapshot));
        }
        max.sort_by(|a, b| a.0.total_cmp(&b.0));
        snap.sort_by(|a, b| a.0.total_cmp(&b.0));
        names.push(format!("G = {}: |Wr| max", short(g)));
        pts.push(max);
        names.push(format!("G = {}: Wr at snapshot (signed)", short(g)));
        pts.push(snap);
    }
    let series: Vec<(&str, Vec<(f64, f64)>)> = names.iter().map(String::as_str).zip(pts).collect();
    crate::plot::xy(
        path,
        "Writhe against W/G (Fig. 3a)",
        "W / G",
        "writhe (turns): largest |Wr|, signed Wr at the snapshot",
        &series,
        true,
        false,
    )
}

/// Fig. 3b of the paper (`speed_vs_writhe.png`): `v_s/v_m` against the largest writhe, one
/// series per regime, from the finished cells with `G > 0`. [`PlotError::Invalid`] when no
/// point is finite.
pub fn speed_vs_writhe(path: &Path, cells: &[MapCell]) -> Result<(), PlotError> {
    let ok: Vec<&MapCell> = cells.iter().filter(|c| c.ok && c.torque > 0.0).collect();
    let regimes = [Regime::S, Regime::M, Regime::F, Regime::N, Regime::U];
    let by_regime: Vec<(String, Vec<(f64, f64)>)> = regimes
        .iter()
        .map(|&r| {
            (
                r.as_str().to_string(),
                ok.iter()
                    .filter(|c| c.regime == Some(r))
                    .map(|c| (c.writhe_max, c.v_s_over_v_m))
                    .collect(),
            )
        })
        .filter(|(_, p): &(String, Vec<(f64, f64)>)| !p.is_empty())
        .collect();
    let series: Vec<(&str, Vec<(f64, f64)>)> = by_regime
        .iter()
        .map(|(n, p)| (n.as_str(), p.clone()))
        .collect();
    // The regime map's colours (one palette for both figures).
    let colors: Vec<RGBColor> = by_regime
        .iter()
        .map(|(n, _)| regime_color(regimes.iter().copied().find(|r| r.as_str() == n)))
        .collect();
    crate::plot::scatter::scatter_colored(
        path,
        "Speed against writhe, by regime (Fig. 3b)",
        "largest |writhe|, |Wr| max (turns)",
        "v_s / v_m",
        &series,
        Some(&colors),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fine_grid_shows_six_torques_spread_over_it() {
        let g: Vec<f64> = (0..20).map(|i| i as f64).collect();
        let shown = shown_torques(&g);
        assert_eq!(shown.len(), MAX_TORQUE_SERIES);
        assert_eq!(shown[0], 0.0);
        assert_eq!(shown[5], 19.0);
        assert!(shown.windows(2).all(|w| w[1] - w[0] >= 3.0), "{shown:?}");
        assert_eq!(shown_torques(&g[..4]), g[..4].to_vec());
    }
}
