//! The kymograph: a heat map over arc length and `t/T` with a colour bar.

use super::axes::{canvas, edges, finite_range, frame_plot, pad, tick_label};
use super::{colormap, draw_err, PlotError, DESC_PX, FONT, SIZE, TICK_PX};
use plotters::prelude::*;
use std::path::Path;

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
    let xe = edges("s", s)?;
    let ye = edges("t_over_t", t_over_t)?;
    let vr = finite_range(values.iter().flatten().copied());
    let (lo, hi) = if diverging {
        let m = vr.map(|(a, b)| a.abs().max(b.abs())).unwrap_or(0.0);
        let m = if m > 0.0 { m } else { 1.0 };
        (-m, m)
    } else {
        match vr {
            Some((a, b)) if b > a => (a, b),
            r => pad(r, 0.0),
        }
    };
    let cmap = |u: f64| {
        if diverging {
            colormap::diverging(u)
        } else {
            colormap::sequential(u)
        }
    };
    let color = |v: f64| {
        if v.is_finite() {
            cmap((v - lo) / (hi - lo))
        } else {
            RGBColor(200, 200, 200)
        }
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
        .x_desc("arc length s (m)")
        .y_desc("t/T")
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
    root.present().map_err(draw_err)
}
