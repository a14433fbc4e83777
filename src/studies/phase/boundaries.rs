//! The regime boundaries: straight lines in log-log fitted through the crossing points
//! between neighbouring cells of different regimes (midpoints, or bisected by [`super::refine`]).
use super::refine::{self, BoundaryPoint};
use crate::observe::Regime;

/// A fitted boundary between two regimes: the line `log10 G = slope log10 W + intercept`
/// (least squares in `log10 G`) through the points where it crosses the segments between
/// neighbouring cells with these two labels: their log-midpoints, or with `[phase] refine =
/// true` the points bisection placed ([`super::refine`]). The paper's boundaries are lines of
/// constant `W/G`: slope 1.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Boundary {
    /// The two regimes, e.g. "F/N" (alphabetical).
    pub pair: String,
    /// How the points were placed: `"bisection"` when at least one point was bisected,
    /// `"midpoints"` otherwise (no refinement, or every bisection failed at its first step).
    pub method: &'static str,
    /// Slope in log-log (`None` with fewer than two distinct weights among the points).
    pub slope: Option<f64>,
    /// Intercept of `log10 G` at `log10 W = 0`.
    pub intercept: Option<f64>,
    /// `W/G` on the line at `G = 10`.
    pub ratio_at_g10: Option<f64>,
    /// Root-mean-square residual of `log10 G` (decades).
    pub residual: Option<f64>,
    /// The neighbouring cells `[[W, G], [W, G]]` whose crossings were fitted.
    pub cells: Vec<[[f64; 2]; 2]>,
    /// The fitted points: `W`, `G`, the axis each was located along, its half-width (decades
    /// along that axis), method, bisection steps and failure (see [`BoundaryPoint`]).
    pub points: Vec<BoundaryPoint>,
}

/// Fit every boundary between neighbouring cells (along W and along G, cells with `G > 0`) of
/// a weight-major grid of labels (`None`: failed cell, not used), through the cell pairs'
/// log-midpoints.
pub fn boundaries(weight: &[f64], torque: &[f64], labels: &[Option<Regime>]) -> Vec<Boundary> {
    fit_boundaries(&refine::midpoint_points(weight, torque, labels))
}

/// Fit one line per regime pair through its points (midpoints or bisected), by least squares in
/// `log10 G` against `log10 W`; the lines in alphabetical order of their pairs.
pub fn fit_boundaries(points: &[BoundaryPoint]) -> Vec<Boundary> {
    let mut pairs: std::collections::BTreeMap<&str, Vec<BoundaryPoint>> = Default::default();
    for p in points {
        pairs.entry(p.pair.as_str()).or_default().push(p.clone());
    }
    pairs
        .into_iter()
        .map(|(pair, points)| {
            let pts: Vec<(f64, f64)> = points.iter().map(|p| (p.w.log10(), p.g.log10())).collect();
            let n = pts.len() as f64;
            let (mx, my) = (
                pts.iter().map(|p| p.0).sum::<f64>() / n,
                pts.iter().map(|p| p.1).sum::<f64>() / n,
            );
            let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
            let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
            let fit = (sxx > 1e-12).then(|| {
                let slope = sxy / sxx;
                let intercept = my - slope * mx;
                let rms = (pts
                    .iter()
                    .map(|p| (p.1 - slope * p.0 - intercept).powi(2))
                    .sum::<f64>()
                    / n)
                    .sqrt();
                (slope, intercept, rms)
            });
            let bisected = points
                .iter()
                .any(|p| p.method == refine::Placement::Bisection);
            Boundary {
                pair: pair.to_string(),
                method: if bisected { "bisection" } else { "midpoints" },
                slope: fit.map(|f| f.0),
                intercept: fit.map(|f| f.1),
                ratio_at_g10: fit
                    .filter(|f| f.0.abs() > 1e-12)
                    .map(|(s, c, _)| 10f64.powf((1.0 - c) / s) / 10.0),
                residual: fit.map(|f| f.2),
                cells: points.iter().map(|p| p.cells).collect(),
                points,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn boundaries_of_labels_set_by_w_over_g_have_slope_one() {
        // Labels set by W/G alone (S below 20, F up to 60, N beyond): straight boundaries of
        // slope 1 in log-log, at W/G 20 and 60 (to the grid's resolution).
        let weight: Vec<f64> = (0..12).map(|k| 10f64.powf(1.0 + k as f64 / 4.0)).collect();
        let torque: Vec<f64> = (0..8).map(|k| 10f64.powf(0.5 + k as f64 / 8.0)).collect();
        let labels: Vec<Option<Regime>> = weight
            .iter()
            .flat_map(|&w| {
                torque.iter().map(move |&g| {
                    Some(match w / g {
                        r if r < 20.0 => Regime::S,
                        r if r < 60.0 => Regime::F,
                        _ => Regime::N,
                    })
                })
            })
            .collect();
        let b = boundaries(&weight, &torque, &labels);
        let names: Vec<&str> = b.iter().map(|b| b.pair.as_str()).collect();
        assert_eq!(names, ["F/N", "F/S"]);
        for (bd, ratio) in b.iter().zip([60.0, 20.0]) {
            let s = bd.slope.unwrap();
            let r = bd.ratio_at_g10.unwrap();
            assert!((s - 1.0).abs() < 0.1, "{}: slope {s}", bd.pair);
            assert!((r / ratio).log10().abs() < 0.15, "{}: W/G {r}", bd.pair);
        }
        // A boundary that is not of constant W/G (labels by W alone) has slope far from 1.
        let by_w: Vec<Option<Regime>> = weight
            .iter()
            .flat_map(|&w| {
                torque
                    .iter()
                    .map(move |_| Some(if w < 300.0 { Regime::S } else { Regime::N }))
            })
            .collect();
        let b = boundaries(&weight, &torque, &by_w);
        assert!(b[0].slope.is_none_or(|s| s.abs() > 5.0), "{:?}", b[0].slope);
    }
}
