//! Scatter charts: markers only, a single-point series drawn larger and outlined.

use super::axes::{best_corner, canvas_on, finite_range, frame_plot, legend, pad, tick_label};
use super::{colormap, draw_err, PlotError, DESC_PX, FONT, SIZE, TICK_PX};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// Scatter chart on linear axes: each named series of (x, y) points drawn as markers only (no
/// joining line), with a legend, axis labels `x_label` and `y_label` (include units) and title
/// `title` (may be empty). A series of a single point is drawn as a larger, outlined marker, to
/// mark one point (e.g. an optimum) on top of the others. Non-finite points are skipped.
/// Writes a 1000x700 px PNG, or SVG when `path` ends in `.svg`.
///
/// Errors: [`PlotError::Invalid`] if no finite point remains.
pub fn scatter(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[(&str, Vec<(f64, f64)>)],
) -> Result<(), PlotError> {
    scatter_colored(path, title, x_label, y_label, series, None)
}

/// [`scatter`] with the series' colours given (one per series; the palette without).
pub fn scatter_colored(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[(&str, Vec<(f64, f64)>)],
    colors: Option<&[RGBColor]>,
) -> Result<(), PlotError> {
    let pts = || {
        series
            .iter()
            .flat_map(|(_, p)| p.iter().copied())
            .filter(|p| p.0.is_finite() && p.1.is_finite())
    };
    if pts().next().is_none() {
        return Err(PlotError::Invalid("scatter: no finite point".into()));
    }
    let xr = pad(finite_range(pts().map(|p| p.0)), 0.08);
    let yr = pad(finite_range(pts().map(|p| p.1)), 0.08);
    crate::on_backend!(path, SIZE, |area| {
        let (root, body) = canvas_on(area, title)?;
        scatter_body(&body, xr, yr, x_label, y_label, series, colors)?;
        root.present().map_err(draw_err)
    })
}

/// The axes and markers of [`scatter`] on any backend.
fn scatter_body<DB: DrawingBackend>(
    body: &DrawingArea<DB, Shift>,
    xr: (f64, f64),
    yr: (f64, f64),
    x_label: &str,
    y_label: &str,
    series: &[(&str, Vec<(f64, f64)>)],
    colors: Option<&[RGBColor]>,
) -> Result<(), PlotError> {
    let pts = || {
        series
            .iter()
            .flat_map(|(_, p)| p.iter().copied())
            .filter(|p| p.0.is_finite() && p.1.is_finite())
    };
    let mut chart = ChartBuilder::on(body)
        .margin_left(20)
        .margin_right(35)
        .margin_top(15)
        .margin_bottom(20)
        .x_label_area_size(65)
        .y_label_area_size(100)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
        .map_err(draw_err)?;
    let xfmt = |v: &f64| tick_label(*v, xr.1 - xr.0);
    let yfmt = |v: &f64| tick_label(*v, yr.1 - yr.0);
    chart
        .configure_mesh()
        .light_line_style(BLACK.mix(0.04))
        .bold_line_style(BLACK.mix(0.12))
        .x_desc(x_label)
        .y_desc(y_label)
        .axis_desc_style((FONT, DESC_PX))
        .label_style((FONT, TICK_PX))
        .x_labels(9)
        .y_labels(9)
        .x_label_formatter(&xfmt)
        .y_label_formatter(&yfmt)
        .draw()
        .map_err(draw_err)?;
    if yr.0 < 0.0 && yr.1 > 0.0 {
        chart
            .draw_series(LineSeries::new(
                vec![(xr.0, 0.0), (xr.1, 0.0)],
                BLACK.mix(0.5).stroke_width(1),
            ))
            .map_err(draw_err)?;
    }
    for (k, (name, p)) in series.iter().enumerate() {
        let c = colors
            .and_then(|cs| cs.get(k).copied())
            .unwrap_or_else(|| colormap::palette(k));
        let finite: Vec<(f64, f64)> = p
            .iter()
            .copied()
            .filter(|q| q.0.is_finite() && q.1.is_finite())
            .collect();
        if finite.is_empty() {
            continue;
        }
        let r = if p.len() == 1 { 10 } else { 5 };
        let ann = chart
            .draw_series(finite.iter().map(|&q| {
                EmptyElement::at(q)
                    + Circle::new((0, 0), r, c.filled())
                    + Circle::new(
                        (0, 0),
                        r,
                        if r > 5 {
                            BLACK.stroke_width(2)
                        } else {
                            c.stroke_width(1)
                        },
                    )
            }))
            .map_err(draw_err)?;
        if !name.is_empty() {
            ann.label(name.to_string()).legend(move |(x, y)| {
                EmptyElement::at((x + 10, y))
                    + Circle::new((0, 0), r.min(7), c.filled())
                    + Circle::new(
                        (0, 0),
                        r.min(7),
                        if r > 5 {
                            BLACK.stroke_width(2)
                        } else {
                            c.stroke_width(1)
                        },
                    )
            });
        }
    }
    if series.iter().any(|(n, _)| !n.is_empty()) {
        let corner = best_corner(pts(), xr, yr, false, false);
        legend(&mut chart, corner, 12)?;
    }
    frame_plot(&mut chart)
}
