//! Line charts: time series ([`series`]) and x-y charts with markers on linear or log axes
//! ([`xy`]), both drawn by one shared body.

use super::axes::{
    best_corner, canvas, canvas_on, finite_range, finite_runs, fmt_num, frame_plot, legend, pad,
    pad_log, spans_decades, tick_label,
};
use super::{colormap, draw_err, PlotError, DESC_PX, FONT, SIZE, TICK_PX};
use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// Time series: the named `curves` (each with one value per entry of `t`) against time `t` (s),
/// with a legend and the y-axis label `y_label` (include the unit, e.g. "turns"). Title `title`
/// (may be empty). NaN values break a curve. Writes a 1000x700 px PNG.
///
/// Errors: [`PlotError::Mismatch`] if a curve's length differs from `t.len()`;
/// [`PlotError::Invalid`] if `t` is empty or has a non-finite entry.
pub fn series(
    path: &Path,
    title: &str,
    y_label: &str,
    t: &[f64],
    curves: &[(&str, Vec<f64>)],
) -> Result<(), PlotError> {
    if t.is_empty() {
        return Err(PlotError::Invalid("series: t is empty".into()));
    }
    if let Some(i) = t.iter().position(|v| !v.is_finite()) {
        return Err(PlotError::Invalid(format!("series: t[{i}] is not finite")));
    }
    if let Some((name, c)) = curves.iter().find(|(_, c)| c.len() != t.len()) {
        return Err(PlotError::Mismatch(format!(
            "series: curve \"{name}\" has {} values but t has {} entries",
            c.len(),
            t.len()
        )));
    }
    let data: Vec<(&str, Vec<(f64, f64)>)> = curves
        .iter()
        .map(|(n, c)| (*n, t.iter().copied().zip(c.iter().copied()).collect()))
        .collect();
    let (root, body) = canvas(path, SIZE, title)?;
    let xr = finite_range(t.iter().copied()).map(|(a, b)| {
        if b > a {
            (a, b)
        } else {
            pad(Some((a, b)), 0.0)
        }
    });
    let yr = pad(
        finite_range(curves.iter().flat_map(|(_, c)| c.iter().copied())),
        0.05,
    );
    let x: RangedCoordf64 = (xr.unwrap().0..xr.unwrap().1).into();
    let y: RangedCoordf64 = (yr.0..yr.1).into();
    line_chart(
        &body,
        x,
        y,
        xr.unwrap(),
        yr,
        "time t (s)",
        y_label,
        &data,
        None,
        (false, false),
    )?;
    root.present().map_err(draw_err)
}

/// Scatter/line chart: each named series of (x, y) points is drawn as markers joined by a thin
/// line in the given order (sort the points if the line should be monotone in x), with a legend,
/// axis labels `x_label` and `y_label` (include units) and title `title` (may be empty).
/// `log_x` / `log_y` select base-10 logarithmic axes (drawn linear when the data on that axis
/// contain fewer than two powers of ten, where a log axis would carry one tick label or
/// none); points with a non-positive coordinate on a log axis, and non-finite points, are
/// skipped. Writes a 1000x700 px PNG, or SVG when `path` ends in `.svg`.
///
/// Errors: [`PlotError::Invalid`] if no plottable point remains.
pub fn xy(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[(&str, Vec<(f64, f64)>)],
    log_x: bool,
    log_y: bool,
) -> Result<(), PlotError> {
    xy_axes(
        path,
        title,
        x_label,
        y_label,
        series,
        &[],
        (log_x, log_y),
        false,
    )
}

/// The marker of a series in [`xy_marked`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Marker {
    /// A filled circle (the marker of [`xy`]).
    #[default]
    Circle,
    /// A filled triangle, point up: another code's points beside circles.
    Triangle,
}

/// A named series of (x, y) points with its marker, for [`xy_marked`].
pub type MarkedSeries<'a> = (&'a str, Vec<(f64, f64)>, Marker);

/// [`xy`] with a marker per series: each entry of `series` is (name, points, marker).
///
/// Errors: [`PlotError::Invalid`] if no plottable point remains.
pub fn xy_marked(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[MarkedSeries],
    log_x: bool,
    log_y: bool,
) -> Result<(), PlotError> {
    let data: Vec<(&str, Vec<(f64, f64)>)> =
        series.iter().map(|(n, p, _)| (*n, p.clone())).collect();
    let shapes: Vec<Marker> = series.iter().map(|s| s.2).collect();
    xy_axes(
        path,
        title,
        x_label,
        y_label,
        &data,
        &shapes,
        (log_x, log_y),
        false,
    )
}

/// [`xy`] on log-log axes even when the data span less than two powers of ten (a cost
/// against a size, where the slope is the message): the ticks then fall between powers of
/// ten. Points with a non-positive coordinate are skipped.
///
/// Errors: [`PlotError::Invalid`] if no plottable point remains.
pub fn xy_log_log(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[(&str, Vec<(f64, f64)>)],
) -> Result<(), PlotError> {
    xy_axes(
        path,
        title,
        x_label,
        y_label,
        series,
        &[],
        (true, true),
        true,
    )
}

/// The body of [`xy`], [`xy_marked`] and [`xy_log_log`]; `force` keeps the log axes of
/// narrow data.
#[allow(clippy::too_many_arguments)] // the public functions' arguments, passed through
fn xy_axes(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[(&str, Vec<(f64, f64)>)],
    shapes: &[Marker],
    (log_x, log_y): (bool, bool),
    force: bool,
) -> Result<(), PlotError> {
    let keep = |&(x, y): &(f64, f64)| {
        x.is_finite() && y.is_finite() && (!log_x || x > 0.0) && (!log_y || y > 0.0)
    };
    let data: Vec<(&str, Vec<(f64, f64)>)> = series
        .iter()
        .map(|(n, p)| {
            (
                *n,
                p.iter()
                    .map(|&q| if keep(&q) { q } else { (f64::NAN, f64::NAN) })
                    .collect(),
            )
        })
        .collect();
    let pts = || {
        data.iter()
            .flat_map(|(_, p)| p.iter().copied())
            .filter(|p| p.0.is_finite())
    };
    if pts().next().is_none() {
        return Err(PlotError::Invalid(
            "xy: no plottable point (finite, and positive on log axes)".into(),
        ));
    }
    let (x_data, y_data) = (
        finite_range(pts().map(|p| p.0)),
        finite_range(pts().map(|p| p.1)),
    );
    let log_x = log_x && (force || spans_decades(x_data));
    let log_y = log_y && (force || spans_decades(y_data));
    let xr = if log_x {
        pad_log(x_data, 0.05)
    } else {
        pad(x_data, 0.05)
    };
    let yr = if log_y {
        pad_log(y_data, 0.05)
    } else {
        pad(y_data, 0.05)
    };
    crate::on_backend!(path, SIZE, |area| {
        let (root, body) = canvas_on(area, title)?;
        if force && log_x && log_y {
            // Ticks at 1, 2 and 5 times the powers of ten (plotters' own log ticks are the
            // powers of ten alone: one or none on narrow data).
            let ticks = |r: (f64, f64)| -> Vec<f64> {
                let mut t = Vec::new();
                for k in (r.0.log10().floor() as i32 - 1)..=(r.1.log10().ceil() as i32) {
                    for m in [1.0, 2.0, 5.0] {
                        let v = m * 10f64.powi(k);
                        if v >= r.0 && v <= r.1 {
                            t.push(v);
                        }
                    }
                }
                t
            };
            let x = (xr.0..xr.1).log_scale().with_key_points(ticks(xr));
            let y = (yr.0..yr.1).log_scale().with_key_points(ticks(yr));
            line_chart(
                &body,
                x,
                y,
                xr,
                yr,
                x_label,
                y_label,
                &data,
                Some(shapes),
                (true, true),
            )?;
        } else {
            xy_body(&body, xr, yr, x_label, y_label, &data, shapes, log_x, log_y)?;
        }
        root.present().map_err(draw_err)
    })
}

/// The axes and curves of [`xy`] on any backend.
#[allow(clippy::too_many_arguments)]
fn xy_body<DB: DrawingBackend>(
    body: &DrawingArea<DB, Shift>,
    xr: (f64, f64),
    yr: (f64, f64),
    x_label: &str,
    y_label: &str,
    data: &[(&str, Vec<(f64, f64)>)],
    shapes: &[Marker],
    log_x: bool,
    log_y: bool,
) -> Result<(), PlotError> {
    let lin = |r: (f64, f64)| -> RangedCoordf64 { (r.0..r.1).into() };
    let log = |r: (f64, f64)| -> LogCoord<f64> { (r.0..r.1).log_scale().into() };
    let logs = (log_x, log_y);
    match logs {
        (false, false) => line_chart(
            body,
            lin(xr),
            lin(yr),
            xr,
            yr,
            x_label,
            y_label,
            data,
            Some(shapes),
            logs,
        )?,
        (true, false) => line_chart(
            body,
            log(xr),
            lin(yr),
            xr,
            yr,
            x_label,
            y_label,
            data,
            Some(shapes),
            logs,
        )?,
        (false, true) => line_chart(
            body,
            lin(xr),
            log(yr),
            xr,
            yr,
            x_label,
            y_label,
            data,
            Some(shapes),
            logs,
        )?,
        (true, true) => line_chart(
            body,
            log(xr),
            log(yr),
            xr,
            yr,
            x_label,
            y_label,
            data,
            Some(shapes),
            logs,
        )?,
    }
    Ok(())
}

/// Shared body of [`series`] and [`xy`]: axes, grid, curves, legend. `markers`: `None` draws
/// plain curves; `Some(shapes)` draws each point with the marker `shapes[k]` of series `k`
/// (a circle beyond its end).
#[allow(clippy::too_many_arguments)]
fn line_chart<DB, X, Y>(
    area: &DrawingArea<DB, Shift>,
    x: X,
    y: Y,
    xr: (f64, f64),
    yr: (f64, f64),
    x_label: &str,
    y_label: &str,
    data: &[(&str, Vec<(f64, f64)>)],
    markers: Option<&[Marker]>,
    logs: (bool, bool),
) -> Result<(), PlotError>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut chart = ChartBuilder::on(area)
        .margin_left(20)
        .margin_right(35)
        .margin_top(15)
        .margin_bottom(20)
        .x_label_area_size(65)
        .y_label_area_size(100)
        .build_cartesian_2d(x, y)
        .map_err(draw_err)?;
    let xfmt = |v: &f64| {
        if logs.0 {
            fmt_num(*v, 3)
        } else {
            tick_label(*v, xr.1 - xr.0)
        }
    };
    let yfmt = |v: &f64| {
        if logs.1 {
            fmt_num(*v, 3)
        } else {
            tick_label(*v, yr.1 - yr.0)
        }
    };
    let mut mesh = chart.configure_mesh();
    mesh.light_line_style(BLACK.mix(0.04))
        .bold_line_style(BLACK.mix(0.12))
        .x_desc(x_label)
        .y_desc(y_label)
        .axis_desc_style((FONT, DESC_PX))
        .label_style((FONT, TICK_PX))
        .x_labels(9)
        .y_labels(9)
        .x_label_formatter(&xfmt)
        .y_label_formatter(&yfmt);
    mesh.draw().map_err(draw_err)?;
    // A zero line on a linear y axis that spans zero.
    if !logs.1 && yr.0 < 0.0 && yr.1 > 0.0 {
        chart
            .draw_series(LineSeries::new(
                vec![(xr.0, 0.0), (xr.1, 0.0)],
                BLACK.mix(0.5).stroke_width(1),
            ))
            .map_err(draw_err)?;
    }
    for (k, (name, pts)) in data.iter().enumerate() {
        let c = colormap::palette(k);
        let runs = finite_runs(pts.iter().copied());
        let shape = markers.map(|m| m.get(k).copied().unwrap_or_default());
        let width = if shape.is_some() { 2 } else { 3 };
        let mut labelled = false;
        for run in runs {
            let ann = chart
                .draw_series(LineSeries::new(run.clone(), c.stroke_width(width)))
                .map_err(draw_err)?;
            if !labelled {
                labelled = true;
                ann.label(name.to_string()).legend(move |(x, y)| {
                    let line = PathElement::new(vec![(x - 2, y), (x + 22, y)], c.stroke_width(3));
                    // One element type for every shape: the marker not drawn is transparent.
                    let (circle, triangle) = match shape {
                        Some(Marker::Circle) => (c.filled(), c.mix(0.0).filled()),
                        Some(Marker::Triangle) => (c.mix(0.0).filled(), c.filled()),
                        None => (c.mix(0.0).filled(), c.mix(0.0).filled()),
                    };
                    EmptyElement::at((0, 0))
                        + line
                        + Circle::new((x + 10, y), 5, circle)
                        + TriangleMarker::new((x + 10, y), 7, triangle)
                });
            }
            match shape {
                Some(Marker::Circle) => {
                    chart
                        .draw_series(run.iter().map(|&p| Circle::new(p, 5, c.filled())))
                        .map_err(draw_err)?;
                }
                Some(Marker::Triangle) => {
                    chart
                        .draw_series(run.iter().map(|&p| TriangleMarker::new(p, 8, c.filled())))
                        .map_err(draw_err)?;
                }
                None => {}
            }
        }
    }
    if data.iter().any(|(n, _)| !n.is_empty()) {
        let corner = best_corner(
            data.iter().flat_map(|(_, p)| p.iter().copied()),
            xr,
            yr,
            logs.0,
            logs.1,
        );
        legend(&mut chart, corner, 12)?;
    }
    frame_plot(&mut chart)
}
