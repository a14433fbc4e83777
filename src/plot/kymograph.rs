//! The kymograph: a heat map over arc length and `t/T` with a colour bar.
//!
//! [`KymographStyle`] sets how values become colours: a robust scale (the colour range ends
//! at a quantile of the finite values, e.g. the 99th percentile, so one extreme cell does not
//! wash out the rest; the colour bar's label says where it clips and what the maximum was),
//! a legend entry for the grey NaN cells (e.g. "in the air"), and a floor drawn in its own
//! colour (e.g. zero slip, "stuck", distinguishable from slow slip).

use super::axes::{canvas, edges, finite_range, frame_plot, pad, tick_label};
use super::{colormap, draw_err, PlotError, DESC_PX, FONT, SIZE, TICK_PX};
use plotters::prelude::*;
use std::path::Path;

/// Colour of the cells at or below [`KymographStyle::floor`] (red: not in either colour map).
pub const FLOOR_COLOR: RGBColor = RGBColor(215, 25, 28);
/// Colour of NaN cells.
pub const NAN_COLOR: RGBColor = RGBColor(200, 200, 200);

/// How a kymograph draws its values (the default: the whole finite range, nothing special).
#[derive(Clone, Debug, Default)]
pub struct KymographStyle<'a> {
    /// Blue-white-red symmetric about 0, else viridis-like from the lower to the upper end.
    pub diverging: bool,
    /// Sequential scale from 0 (not from the smallest value).
    pub from_zero: bool,
    /// End the colour range at this quantile of the finite magnitudes (e.g. 0.99); larger
    /// values are drawn in the end colour and the colour bar label notes the clip.
    pub clip_quantile: Option<f64>,
    /// Legend entry for the grey NaN cells (e.g. "in the air").
    pub nan_label: Option<&'a str>,
    /// Values at or below this threshold are drawn in [`FLOOR_COLOR`], with this legend entry.
    pub floor: Option<(f64, &'a str)>,
    /// Horizontal axis description (default "arc length s (m)").
    pub s_desc: Option<&'a str>,
    /// Vertical axis description (default "t/T").
    pub t_desc: Option<&'a str>,
}

/// The colour range a kymograph used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KymographScale {
    /// Value at the low end of the colour bar.
    pub lo: f64,
    /// Value at the high end of the colour bar.
    pub hi: f64,
    /// Largest finite value (beyond `hi` when clipped).
    pub max: f64,
    /// Finite cells beyond the colour range (drawn in the end colour).
    pub clipped: usize,
}

/// The `q` quantile (0..1, nearest rank) of the finite values (`None` if there is none).
pub fn quantile(values: impl Iterator<Item = f64>, q: f64) -> Option<f64> {
    let mut v: Vec<f64> = values.filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(|a, b| a.total_cmp(b));
    let k = ((q.clamp(0.0, 1.0) * v.len() as f64).ceil() as usize).clamp(1, v.len()) - 1;
    Some(v[k])
}

/// Kymograph: a heat map of `values[frame][node]` over arc length `s` (m, horizontal axis, head
/// `s[0]` at the left) and `t_over_t` = t/T (dimensionless, vertical axis, time increasing upward),
/// with a colour bar labelled `label` (include the unit, e.g. "curvature (1/m)") and title `title`
/// (may be empty). Colour map: blue-white-red symmetric about 0 when `diverging`, else
/// viridis-like from the minimum to the maximum value. Cells are centred on the given `s` and
/// `t/T` (both must be finite and strictly increasing); NaN values are drawn light grey.
/// Writes a 1000x700 px PNG.
///
/// Errors: [`PlotError::Mismatch`] if `values.len() != t_over_t.len()` or any
/// `values[j].len() != s.len()`; [`PlotError::Invalid`] for empty or non-increasing axes.
pub fn kymograph(
    path: &Path,
    title: &str,
    label: &str,
    s: &[f64],
    t_over_t: &[f64],
    values: &[Vec<f64>],
    diverging: bool,
) -> Result<(), PlotError> {
    let style = KymographStyle {
        diverging,
        ..Default::default()
    };
    kymograph_styled(path, title, label, s, t_over_t, values, &style).map(|_| ())
}

/// [`kymograph()`] drawn with `style`; returns the colour range it used.
pub fn kymograph_styled(
    path: &Path,
    title: &str,
    label: &str,
    s: &[f64],
    t_over_t: &[f64],
    values: &[Vec<f64>],
    style: &KymographStyle,
) -> Result<KymographScale, PlotError> {
    let diverging = style.diverging;
    check_shapes(s, t_over_t, values)?;
    let xe = edges("s", s)?;
    let ye = edges("t_over_t", t_over_t)?;
    let (lo, hi, max) = colour_range(values, style);
    let clipped = values
        .iter()
        .flatten()
        .filter(|v| v.is_finite() && (**v > hi || **v < lo))
        .count();
    let label = if clipped > 0 {
        format!(
            "{label}; colours clipped at {} ({} of {} cells beyond, max {})",
            tick_label(hi, hi - lo),
            clipped,
            values.iter().flatten().filter(|v| v.is_finite()).count(),
            tick_label(max, hi - lo)
        )
    } else {
        label.to_string()
    };
    let label = label.as_str();
    let cmap = |u: f64| {
        if diverging {
            colormap::diverging(u)
        } else {
            colormap::sequential(u)
        }
    };
    let color = |v: f64| match style.floor {
        _ if !v.is_finite() => NAN_COLOR,
        Some((floor, _)) if v <= floor => FLOOR_COLOR,
        _ => cmap((v - lo) / (hi - lo)),
    };

    let (root, body) = canvas(path, SIZE, title)?;
    let (w, _) = body.dim_in_pixel();
    let (main, bar) = body.split_horizontally(w - 190);
    let (ml, mt, mb, xl) = (20, 15, 20, 65);

    let (xspan, yspan) = (xe[xe.len() - 1] - xe[0], ye[ye.len() - 1] - ye[0]);
    let xfmt = |v: &f64| tick_label(*v, xspan);
    let yfmt = |v: &f64| tick_label(*v, yspan);
    let mut chart = ChartBuilder::on(&main)
        .margin_left(ml)
        .margin_top(mt)
        .margin_bottom(mb)
        .margin_right(10)
        .x_label_area_size(xl)
        .y_label_area_size(90)
        .build_cartesian_2d(xe[0]..xe[xe.len() - 1], ye[0]..ye[ye.len() - 1])
        .map_err(draw_err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(style.s_desc.unwrap_or("arc length s (m)"))
        .y_desc(style.t_desc.unwrap_or("t/T"))
        .x_label_formatter(&xfmt)
        .y_label_formatter(&yfmt)
        .axis_desc_style((FONT, DESC_PX))
        .label_style((FONT, TICK_PX))
        .x_labels(8)
        .y_labels(8)
        .draw()
        .map_err(draw_err)?;
    let mut cells = Vec::with_capacity(values.len() * s.len());
    for (j, row) in values.iter().enumerate() {
        for (i, &v) in row.iter().enumerate() {
            cells.push(Rectangle::new(
                [(xe[i], ye[j]), (xe[i + 1], ye[j + 1])],
                color(v).filled(),
            ));
        }
    }
    chart.draw_series(cells).map_err(draw_err)?;
    frame_plot(&mut chart)?;

    // Colour bar, vertically aligned with the plotting area.
    let nbar = 256;
    let mut cbar = ChartBuilder::on(&bar)
        .margin_top(mt)
        .margin_bottom(mb)
        .margin_left(15)
        .margin_right(10)
        .x_label_area_size(xl)
        .set_label_area_size(LabelAreaPosition::Right, 120)
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(draw_err)?;
    // The bar first, then the axis and tick labels, so no label is painted over.
    cbar.draw_series((0..nbar).map(|k| {
        let a = lo + (hi - lo) * k as f64 / nbar as f64;
        let b = lo + (hi - lo) * (k + 1) as f64 / nbar as f64;
        Rectangle::new(
            [(0.0, a), (1.0, b)],
            cmap((k as f64 + 0.5) / nbar as f64).filled(),
        )
    }))
    .map_err(draw_err)?;
    let fmt = |v: &f64| tick_label(*v, hi - lo);
    cbar.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .x_labels(0)
        .y_labels(9)
        .y_label_formatter(&fmt)
        .set_tick_mark_size(LabelAreaPosition::Right, 6)
        .y_label_offset(0)
        .y_desc(label)
        .axis_desc_style((FONT, DESC_PX))
        .label_style((FONT, TICK_PX))
        .draw()
        .map_err(draw_err)?;
    frame_plot(&mut cbar)?;
    draw_patches(&bar, style, mb + xl)?;
    root.present().map_err(draw_err)?;
    Ok(KymographScale {
        lo,
        hi,
        max,
        clipped,
    })
}

/// `values` has one row per entry of `t_over_t`, each with one value per entry of `s`.
fn check_shapes(s: &[f64], t_over_t: &[f64], values: &[Vec<f64>]) -> Result<(), PlotError> {
    if values.len() != t_over_t.len() {
        return Err(PlotError::Mismatch(format!(
            "kymograph: values has {} frames (rows) but t_over_t has {} entries",
            values.len(),
            t_over_t.len()
        )));
    }
    if let Some((j, row)) = values.iter().enumerate().find(|(_, r)| r.len() != s.len()) {
        return Err(PlotError::Mismatch(format!(
            "kymograph: values[{j}] has {} nodes but s has {} entries",
            row.len(),
            s.len()
        )));
    }
    Ok(())
}

/// The colour range `(lo, hi)` of [`kymograph_styled`] and the largest value: symmetric about
/// 0 when diverging, from 0 with `from_zero`, its end at the `clip_quantile` of the magnitudes
/// when that is smaller than the extreme.
fn colour_range(values: &[Vec<f64>], style: &KymographStyle) -> (f64, f64, f64) {
    let diverging = style.diverging;
    let vr = finite_range(values.iter().flatten().copied());
    let vr = match (vr, style.from_zero) {
        (Some((a, b)), true) => Some((a.min(0.0), b.max(0.0))),
        (r, _) => r,
    };
    let max = vr.map_or(f64::NAN, |r| r.1);
    // The robust end: a quantile of the magnitudes, never beyond the extreme.
    let robust = style
        .clip_quantile
        .and_then(|q| quantile(values.iter().flatten().map(|v| v.abs()), q).filter(|&x| x > 0.0));
    let (lo, hi) = if diverging {
        let m = vr.map(|(a, b)| a.abs().max(b.abs())).unwrap_or(0.0);
        let m = robust.map_or(m, |r| r.min(m));
        let m = if m > 0.0 { m } else { 1.0 };
        (-m, m)
    } else {
        match vr {
            Some((a, b)) if b > a => (a, robust.map_or(b, |r| r.min(b).max(a + 1e-12 * (b - a)))),
            r => pad(r, 0.0),
        }
    };
    (lo, hi, max)
}

/// Legend patches for the special colours (`floor`, NaN) under the colour bar, whose bottom
/// margin and label area together are `below` px.
fn draw_patches<DB: DrawingBackend>(
    bar: &DrawingArea<DB, plotters::coord::Shift>,
    style: &KymographStyle,
    below: i32,
) -> Result<(), PlotError> {
    let (_, bh) = bar.dim_in_pixel();
    let patches: Vec<(RGBColor, &str)> = [
        style.floor.map(|(_, l)| (FLOOR_COLOR, l)),
        style.nan_label.map(|l| (NAN_COLOR, l)),
    ]
    .into_iter()
    .flatten()
    .collect();
    for (k, (c, text)) in patches.iter().enumerate() {
        let y = bh as i32 - below + 12 + 26 * k as i32;
        bar.draw(&Rectangle::new([(15, y), (33, y + 18)], c.filled()))
            .map_err(draw_err)?;
        bar.draw(&Rectangle::new(
            [(15, y), (33, y + 18)],
            BLACK.stroke_width(1),
        ))
        .map_err(draw_err)?;
        bar.draw(&Text::new(text.to_string(), (39, y), (FONT, 15)))
            .map_err(draw_err)?;
    }
    Ok(())
}
