//! Shared pieces of the figures: number and tick formatting, finite and padded axis ranges,
//! cell edges, the legend corner, NaN-broken lines, the titled canvas, the legend and the box
//! around a plotting area.

use super::{draw_err, register_fonts, PlotError, FONT, LEGEND_PX, TITLE_PX};
use plotters::coord::ranged1d::Ranged;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// Formats `v` with about `sig` significant digits, without trailing zeros; scientific notation
/// outside 1e-3 <= |v| < 1e5.
pub(super) fn fmt_num(v: f64, sig: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { format!("{v}") };
    }
    let mag = v.abs().log10().floor() as i32;
    if (-3..5).contains(&mag) {
        let dec = (sig as i32 - 1 - mag).max(0) as usize;
        let s = format!("{v:.dec$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        let p = sig.saturating_sub(1);
        let s = format!("{v:.p$e}");
        // 1.500e-4 -> 1.5e-4
        match s.split_once('e') {
            Some((m, e)) if m.contains('.') => {
                format!("{}e{}", m.trim_end_matches('0').trim_end_matches('.'), e)
            }
            _ => s,
        }
    }
}

/// Tick label on a linear axis of extent `span`: values within 1e-9 span of zero (round-off of
/// the tick generator) print as "0"; otherwise up to 4 significant digits.
pub(super) fn tick_label(v: f64, span: f64) -> String {
    if span > 0.0 && v.abs() < 1e-9 * span {
        "0".into()
    } else {
        fmt_num(v, 4)
    }
}

/// Min and max of the finite values, or None.
pub(super) fn finite_range(vals: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let mut r: Option<(f64, f64)> = None;
    for v in vals.filter(|v| v.is_finite()) {
        r = Some(match r {
            None => (v, v),
            Some((a, b)) => (a.min(v), b.max(v)),
        });
    }
    r
}

/// Pads a range by `frac` of its span on both sides; a degenerate range gets a small width.
pub(super) fn pad(r: Option<(f64, f64)>, frac: f64) -> (f64, f64) {
    match r {
        None => (0.0, 1.0),
        Some((a, b)) if b > a => {
            let d = (b - a) * frac;
            (a - d, b + d)
        }
        Some((a, _)) => {
            let d = if a == 0.0 { 1.0 } else { 0.1 * a.abs() };
            (a - d, a + d)
        }
    }
}

/// Whether a positive data range contains two powers of ten. plotters labels a log axis only
/// at the powers of ten inside its range (over less than two decades it adds no labels in
/// between), so an axis with fewer would carry one number or none; such an axis is drawn
/// linear ([`super::xy`]).
pub(super) fn spans_decades(r: Option<(f64, f64)>) -> bool {
    r.is_none_or(|(a, b)| a.log10().ceil() + 1.0 <= b.log10().floor())
}

/// Padded range on a log axis (positive values only), widened by `frac` decades... in log space.
pub(super) fn pad_log(r: Option<(f64, f64)>, frac: f64) -> (f64, f64) {
    match r {
        None => (1.0, 10.0),
        Some((a, b)) => {
            let (la, lb) = (a.log10(), b.log10());
            let d = if lb > la { (lb - la) * frac } else { 0.5 };
            (10f64.powf(la - d), 10f64.powf(lb + d))
        }
    }
}

/// Cell edges around strictly increasing, finite centres (midpoints; the ends extend by half
/// the neighbouring spacing; a single centre gets a unit-width cell).
pub(super) fn edges(name: &str, c: &[f64]) -> Result<Vec<f64>, PlotError> {
    if c.is_empty() {
        return Err(PlotError::Invalid(format!("`{name}` is empty")));
    }
    if let Some(i) = c.iter().position(|v| !v.is_finite()) {
        return Err(PlotError::Invalid(format!("`{name}[{i}]` is not finite")));
    }
    if let Some(i) = c.windows(2).position(|w| w[1] <= w[0]) {
        return Err(PlotError::Invalid(format!(
            "`{name}` must be strictly increasing, but {name}[{}] = {} >= {name}[{}] = {}",
            i,
            c[i],
            i + 1,
            c[i + 1]
        )));
    }
    let n = c.len();
    if n == 1 {
        let h = if c[0] == 0.0 { 0.5 } else { 0.5 * c[0].abs() };
        return Ok(vec![c[0] - h, c[0] + h]);
    }
    let mut e = Vec::with_capacity(n + 1);
    e.push(c[0] - 0.5 * (c[1] - c[0]));
    for w in c.windows(2) {
        e.push(0.5 * (w[0] + w[1]));
    }
    e.push(c[n - 1] + 0.5 * (c[n - 1] - c[n - 2]));
    Ok(e)
}

/// The legend corner with the fewest data points near it (each corner region covers 40 % of the
/// width and height of the plotting range).
pub(super) fn best_corner(
    pts: impl Iterator<Item = (f64, f64)>,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    log_x: bool,
    log_y: bool,
) -> SeriesLabelPosition {
    let map = |v: f64, a: f64, b: f64, log: bool| {
        if log {
            (v.log10() - a.log10()) / (b.log10() - a.log10())
        } else {
            (v - a) / (b - a)
        }
    };
    // Order of preference on ties: upper right, upper left, lower right, lower left.
    let mut count = [0usize; 4];
    for (x, y) in pts {
        let u = map(x, x0, x1, log_x);
        let v = map(y, y0, y1, log_y);
        if !(u.is_finite() && v.is_finite()) {
            continue;
        }
        let (r, l, t, b) = (u > 0.6, u < 0.4, v > 0.6, v < 0.4);
        count[0] += (r && t) as usize;
        count[1] += (l && t) as usize;
        count[2] += (r && b) as usize;
        count[3] += (l && b) as usize;
    }
    let best = (0..4).min_by_key(|&i| (count[i], i)).unwrap_or(0);
    [
        SeriesLabelPosition::UpperRight,
        SeriesLabelPosition::UpperLeft,
        SeriesLabelPosition::LowerRight,
        SeriesLabelPosition::LowerLeft,
    ][best]
        .clone()
}

/// Splits a sequence of points into runs of finite points (a NaN breaks the line).
pub(super) fn finite_runs(pts: impl Iterator<Item = (f64, f64)>) -> Vec<Vec<(f64, f64)>> {
    let mut runs = vec![];
    let mut cur = vec![];
    for (x, y) in pts {
        if x.is_finite() && y.is_finite() {
            cur.push((x, y));
        } else if !cur.is_empty() {
            runs.push(std::mem::take(&mut cur));
        }
    }
    if !cur.is_empty() {
        runs.push(cur);
    }
    runs
}

pub(super) type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;
/// A drawing area of any backend (PNG or SVG).
pub(super) type AnyArea<DB> = DrawingArea<DB, Shift>;

/// White canvas with the title (if non-empty) drawn at the top; returns the root (to present)
/// and the area below the title. A PNG bitmap; [`canvas_on`] for any backend.
pub(super) fn canvas<'a>(
    path: &'a Path,
    size: (u32, u32),
    title: &str,
) -> Result<(Area<'a>, Area<'a>), PlotError> {
    canvas_on(BitMapBackend::new(path, size).into_drawing_area(), title)
}

/// [`canvas`] on the drawing area of any backend (PNG or SVG, see `on_backend!`).
pub(super) fn canvas_on<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
) -> Result<(AnyArea<DB>, AnyArea<DB>), PlotError> {
    register_fonts()?;
    root.fill(&WHITE).map_err(draw_err)?;
    let body = if title.is_empty() {
        root.clone().margin(TITLE_PX / 2, 0, 0, 0)
    } else {
        root.titled(title, (FONT, TITLE_PX).into_font().style(FontStyle::Bold))
            .map_err(draw_err)?
    };
    Ok((root, body))
}

/// The series legend, in the house style, at `corner`.
pub(super) fn legend<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    corner: SeriesLabelPosition,
    margin: u32,
) -> Result<(), PlotError>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    chart
        .configure_series_labels()
        .position(corner)
        .margin(margin)
        .label_font((FONT, LEGEND_PX))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.5))
        .draw()
        .map_err(draw_err)
}

pub(super) fn frame_plot<DB, X, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
) -> Result<(), PlotError>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    // Box around the plotting area (drawn in pixel coordinates of the plotting area).
    let area = chart.plotting_area().strip_coord_spec();
    let (w, h) = area.dim_in_pixel();
    area.draw(&Rectangle::new(
        [(0, 0), (w as i32 - 1, h as i32 - 1)],
        BLACK.stroke_width(1),
    ))
    .map_err(draw_err)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A log axis needs two powers of ten inside the data (plotters' only labels there).
    #[test]
    fn log_axes_need_two_powers_of_ten() {
        assert!(!spans_decades(Some((1.09, 3.03))));
        assert!(!spans_decades(Some((0.9, 3.0))));
        assert!(!spans_decades(Some((2.0, 25.0))));
        assert!(spans_decades(Some((1.0, 10.0))));
        assert!(spans_decades(Some((6.5e-4, 4.5e-2))));
        assert!(spans_decades(None));
    }

    #[test]
    fn number_format() {
        assert_eq!(fmt_num(0.0, 3), "0");
        assert_eq!(fmt_num(1.5, 3), "1.5");
        assert_eq!(fmt_num(0.126, 2), "0.13");
        assert_eq!(fmt_num(2.0, 4), "2");
        assert_eq!(fmt_num(1.5e-4, 3), "1.5e-4");
        assert_eq!(fmt_num(-123456.0, 3), "-1.23e5");
    }

    #[test]
    fn cell_edges() {
        assert_eq!(
            edges("s", &[0.0, 1.0, 3.0]).unwrap(),
            vec![-0.5, 0.5, 2.0, 4.0]
        );
        assert!(edges("s", &[0.0, 0.0]).is_err());
        assert!(edges("s", &[]).is_err());
    }
}
