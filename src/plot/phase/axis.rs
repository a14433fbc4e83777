//! The regime map's axes: cell edges on a log axis, a grid value of zero drawn as its own row
//! (or column) beyond a break, ticks at the grid's own values, and the fitted boundary lines
//! cut to the cells that support them.
//!
//! Both axes of the map are logarithmic. plotters labels a log axis only at its powers of ten,
//! so a grid such as `G = 10, 15` would carry the single tick "10"; the map's ticks are
//! therefore the grid values themselves ([`grid_ticks`]), thinned evenly when there are more
//! than fit, the first and last always kept.
//!
//! Zero (no gravity, or no muscles) has no place on a log axis. We draw it as one more row
//! below the smallest positive value, one grid step further down (the log step between the
//! first two positive values, a decade when there is one positive value), labelled "0" and
//! set off from the positive values by a break ([`GridAxis::zero_break`]). A linear axis was
//! the alternative, and the old map's choice: it squeezes the small values of a log-spaced grid
//! into a sliver beside the large ones, and with cell edges at the midpoints it ran below zero
//! with negative ticks.

use crate::plot::PlotError;

/// One axis of the regime map: where its cells are drawn, their edges and its ticks, on a log
/// scale.
#[derive(Clone, Debug, PartialEq)]
pub struct GridAxis {
    /// Where each grid value is drawn: the value itself, or for a zero its stand-in one grid
    /// step below the smallest positive value.
    pub at: Vec<f64>,
    /// Cell edges (one more than the values): geometric midpoints, the ends mirrored.
    pub edges: Vec<f64>,
    /// Tick positions (values of `at`) and their labels (the grid values; "0" for zero).
    pub ticks: Vec<(f64, String)>,
    /// The edge between the zero row and the positive values, when the grid has a zero.
    pub zero_break: Option<f64>,
}

impl GridAxis {
    /// The axis of grid `values` (finite, >= 0, strictly increasing), with at most `max_ticks`
    /// ticks (at least two when there are two values).
    pub fn new(name: &str, values: &[f64], max_ticks: usize) -> Result<GridAxis, PlotError> {
        if values.is_empty() {
            return Err(PlotError::Invalid(format!("`{name}` is empty")));
        }
        if let Some(v) = values.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
            return Err(PlotError::Invalid(format!(
                "`{name}` holds {v}: the regime map needs finite values >= 0"
            )));
        }
        if values.windows(2).any(|w| w[1] <= w[0]) {
            return Err(PlotError::Invalid(format!(
                "`{name}` must be strictly increasing: {values:?}"
            )));
        }
        let zero = values[0] == 0.0;
        let pos = &values[zero as usize..];
        let mut at = Vec::with_capacity(values.len());
        if zero {
            at.push(match pos {
                [] => 1.0,
                [p] => p / 10.0,
                [p, q, ..] => p * p / q,
            });
        }
        at.extend_from_slice(pos);
        let edges = log_edges(&at);
        let ticks = grid_ticks(values.len(), max_ticks)
            .into_iter()
            .map(|i| (at[i], short(values[i])))
            .collect();
        let zero_break = (zero && !pos.is_empty()).then(|| edges[1]);
        Ok(GridAxis {
            at,
            edges,
            ticks,
            zero_break,
        })
    }

    /// The axis's extent, from the first edge to the last.
    pub fn range(&self) -> std::ops::Range<f64> {
        self.edges[0]..self.edges[self.edges.len() - 1]
    }

    /// The extent of the positive values in log10 (the zero row left out): where boundary
    /// lines, fitted in log space, may run.
    pub fn log_span(&self) -> (f64, f64) {
        let lo = self.zero_break.unwrap_or(self.edges[0]);
        (lo.log10(), self.edges[self.edges.len() - 1].log10())
    }

    /// The label of the tick at `v` (the nearest tick).
    pub fn label(&self, v: f64) -> String {
        self.ticks
            .iter()
            .min_by(|a, b| (a.0 - v).abs().total_cmp(&(b.0 - v).abs()))
            .map_or_else(String::new, |t| t.1.clone())
    }
}

/// The indices of the grid values that get a tick, out of `n`: all when `n <= max`, else about
/// `max` spread evenly (the first and last always; at least two when `n >= 2`).
pub fn grid_ticks(n: usize, max: usize) -> Vec<usize> {
    let max = max.max(2);
    if n <= max {
        return (0..n).collect();
    }
    let stride = (n - 1).div_ceil(max - 1);
    let mut v: Vec<usize> = (0..n - 1).step_by(stride).collect();
    // The last value always; its neighbour dropped when closer than half a stride or two
    // values (labels of neighbouring cells could touch).
    if v.len() > 1 && n - 1 - v[v.len() - 1] < stride.div_ceil(2).max(2) {
        v.pop();
    }
    v.push(n - 1);
    v
}

/// Cell edges on a log axis: geometric midpoints, the ends mirrored.
pub fn log_edges(c: &[f64]) -> Vec<f64> {
    let n = c.len();
    if n == 1 {
        return vec![c[0] / 2.0_f64.sqrt(), c[0] * 2.0_f64.sqrt()];
    }
    let mut e = vec![c[0] * (c[0] / c[1]).sqrt()];
    e.extend(c.windows(2).map(|w| (w[0] * w[1]).sqrt()));
    e.push(c[n - 1] * (c[n - 1] / c[n - 2]).sqrt());
    e
}

/// A grid value for a tick or a legend: 3 significant digits (`G = 2.64`, `G = 100`).
pub fn short(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let dec = (2 - v.abs().log10().floor() as i32).clamp(0, 6) as usize;
    let s = format!("{v:.dec$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// The part of the line `log10 G = slope log10 W + intercept` inside the box `[lw0, lw1] x
/// [lg0, lg1]` (log10 coordinates), as 64 points `(W, G)`; `None` if it misses the box.
pub fn boundary_segment(
    slope: f64,
    intercept: f64,
    (lw0, lw1): (f64, f64),
    (lg0, lg1): (f64, f64),
) -> Option<Vec<(f64, f64)>> {
    let (mut a, mut b) = (lw0, lw1);
    if slope.abs() > 1e-12 {
        let (x0, x1) = ((lg0 - intercept) / slope, (lg1 - intercept) / slope);
        a = a.max(x0.min(x1));
        b = b.min(x0.max(x1));
    } else if !(lg0..=lg1).contains(&intercept) {
        return None;
    }
    (a < b && a.is_finite() && b.is_finite()).then(|| {
        (0..64)
            .map(|k| {
                let x = a + (b - a) * k as f64 / 63.0;
                (10f64.powf(x), 10f64.powf(slope * x + intercept))
            })
            .collect()
    })
}

/// The part of the box `lw x lg` (log10 W, log10 G) that the fitted `points` span: a
/// boundary line is drawn only where cells support it. An axis the points do not spread
/// along (one weight, or one torque) keeps the box's range.
pub fn supported_box(
    points: &[(f64, f64)],
    lw: (f64, f64),
    lg: (f64, f64),
) -> ((f64, f64), (f64, f64)) {
    let span = |v: Vec<f64>, (a, b): (f64, f64)| {
        let v: Vec<f64> = v.into_iter().filter(|x| x.is_finite()).collect();
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if hi > lo {
            (a.max(lo), b.min(hi))
        } else {
            (a, b)
        }
    };
    let logs = |f: fn(&(f64, f64)) -> f64| -> Vec<f64> {
        points
            .iter()
            .map(f)
            .filter(|x| *x > 0.0)
            .map(f64::log10)
            .collect()
    };
    (span(logs(|p| p.0), lw), span(logs(|p| p.1), lg))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(a: &GridAxis) -> Vec<&str> {
        a.ticks.iter().map(|t| t.1.as_str()).collect()
    }

    /// A 10/15 torque grid is labelled at both values (plotters' log axis showed only "10").
    #[test]
    fn a_ten_fifteen_grid_labels_both_values() {
        let a = GridAxis::new("torque", &[10.0, 15.0], 16).unwrap();
        assert_eq!(labels(&a), ["10", "15"]);
        assert_eq!(a.ticks[0].0, 10.0);
        assert_eq!(a.ticks[1].0, 15.0);
        assert_eq!(a.zero_break, None);
        // Ticks lie inside the axis, each in its own cell.
        let r = a.range();
        for (k, (v, _)) in a.ticks.iter().enumerate() {
            assert!(r.contains(v));
            assert!(a.edges[k] < *v && *v < a.edges[k + 1]);
        }
        // Any grid of two values or more gets at least two ticks, first and last included.
        for n in 2..40 {
            let g: Vec<f64> = (0..n).map(|i| 3.0 * 1.2f64.powi(i)).collect();
            let a = GridAxis::new("g", &g, 12).unwrap();
            assert!(
                a.ticks.len() >= 2 && a.ticks.len() <= 12,
                "{n}: {:?}",
                a.ticks
            );
            assert_eq!(a.ticks[0].0, g[0]);
            assert_eq!(a.ticks[a.ticks.len() - 1].0, g[n as usize - 1]);
        }
    }

    /// G = 0 gets its own row labelled "0", below a break, on a log axis that stays positive
    /// (the old linear axis went below zero with negative ticks).
    #[test]
    fn a_zero_in_the_grid_gets_its_own_row_and_no_negative_tick() {
        let a = GridAxis::new("torque", &[0.0, 10.0, 30.0, 100.0], 16).unwrap();
        assert_eq!(labels(&a), ["0", "10", "30", "100"]);
        assert!(a.edges.iter().all(|e| *e > 0.0), "{:?}", a.edges);
        assert!(a.ticks.iter().all(|t| !t.1.starts_with('-')));
        // The zero row sits one grid step below 10, the break between it and 10.
        let b = a.zero_break.unwrap();
        assert!(a.at[0] < b && b < 10.0);
        assert!((a.at[0] - 10.0 / 3.0).abs() < 1e-12);
        assert_eq!(a.label(a.at[0]), "0");
        // Boundary lines run over the positive values only.
        assert!((a.log_span().0 - b.log10()).abs() < 1e-12);
        // One positive value: the zero row a decade below; zero alone: drawn at 1.
        let a = GridAxis::new("torque", &[0.0, 20.0], 16).unwrap();
        assert_eq!(labels(&a), ["0", "20"]);
        assert!((a.at[0] - 2.0).abs() < 1e-12);
        let a = GridAxis::new("torque", &[0.0], 16).unwrap();
        assert_eq!(labels(&a), ["0"]);
        assert_eq!(a.zero_break, None);
        assert!(GridAxis::new("torque", &[-1.0, 10.0], 16).is_err());
        assert!(GridAxis::new("torque", &[10.0, 10.0], 16).is_err());
    }

    #[test]
    fn thinned_ticks_are_even_and_keep_the_ends() {
        assert_eq!(grid_ticks(5, 12), vec![0, 1, 2, 3, 4]);
        assert_eq!(grid_ticks(20, 6), vec![0, 4, 8, 12, 16, 19]);
        assert_eq!(grid_ticks(2, 1), vec![0, 1]);
        assert_eq!(grid_ticks(1, 12), vec![0]);
        assert_eq!(grid_ticks(16, 12), vec![0, 2, 4, 6, 8, 10, 12, 15]);
        let t = grid_ticks(17, 8);
        assert!(t.windows(2).all(|w| w[1] - w[0] >= 2), "{t:?}");
        assert_eq!(t.last(), Some(&16));
    }

    #[test]
    fn boundary_lines_span_only_their_supporting_points() {
        let (lw, lg) = ((0.0, 4.0), (0.0, 2.0));
        // Points from W = 100 to 1000 and G = 10 to 30: the box shrinks to them.
        let pts = [(100.0, 10.0), (300.0, 20.0), (1000.0, 30.0)];
        let (w, g) = supported_box(&pts, lw, lg);
        assert!(
            (w.0 - 2.0).abs() < 1e-12 && (w.1 - 3.0).abs() < 1e-12,
            "{w:?}"
        );
        assert!(
            (g.0 - 1.0).abs() < 1e-12 && (g.1 - 30f64.log10()).abs() < 1e-12,
            "{g:?}"
        );
        // A line through them is cut to W in [100, 1000].
        let seg = boundary_segment(0.5, 0.0, w, g).unwrap();
        assert!(
            seg.iter().all(|p| (99.999..=1000.001).contains(&p.0)),
            "{seg:?}"
        );
        // One weight only: that axis keeps the box's range.
        let (w, _) = supported_box(&[(100.0, 10.0), (100.0, 30.0)], lw, lg);
        assert_eq!(w, lw);
    }

    #[test]
    fn boundary_segments_stay_in_the_box_and_on_the_line() {
        let (lw, lg) = ((1.0, 4.0), (0.0, 2.0));
        // Slope 1 through W/G = 30: enters at G = 1 (W = 30), leaves at G = 100 (W = 3000).
        let c = -(30f64.log10());
        let seg = boundary_segment(1.0, c, lw, lg).unwrap();
        for &(w, g) in &seg {
            assert!((w.log10() + c - g.log10()).abs() < 1e-12);
            assert!(w.log10() >= lw.0 - 1e-12 && w.log10() <= lw.1 + 1e-12);
            assert!(g.log10() >= lg.0 - 1e-12 && g.log10() <= lg.1 + 1e-12);
        }
        assert!((seg[0].0 - 30.0).abs() < 1e-9 && (seg[63].0 - 3000.0).abs() < 1e-6);
        // A line above the box, and a flat line outside it, are not drawn.
        assert!(boundary_segment(1.0, 5.0, lw, lg).is_none());
        assert!(boundary_segment(0.0, 3.0, lw, lg).is_none());
        // A flat line inside spans the whole weight axis.
        let flat = boundary_segment(0.0, 1.0, lw, lg).unwrap();
        assert!((flat[0].0 - 10.0).abs() < 1e-9 && (flat[63].0 - 1e4).abs() < 1e-6);
    }

    #[test]
    fn edges_enclose_the_centres() {
        let c = [100.0, 300.0, 1000.0];
        let e = log_edges(&c);
        assert_eq!(e.len(), 4);
        for i in 0..3 {
            assert!(e[i] < c[i] && c[i] < e[i + 1]);
        }
        assert_eq!(short(2.636650898730358), "2.64");
        assert_eq!(short(100.0), "100");
        assert_eq!(short(14.38449888287663), "14.4");
    }
}
