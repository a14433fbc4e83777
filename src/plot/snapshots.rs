//! Body snapshots: top and side views of the centreline at several times.

use super::axes::{
    best_corner, canvas, finite_range, finite_runs, fmt_num, frame_plot, legend, pad, tick_label,
    Area,
};
use super::{colormap, draw_err, PlotError, DESC_PX, FONT, SIZE_WIDE, TICK_PX};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::path::Path;

/// Chart of one snapshot panel with the given data ranges.
fn snapshot_chart<'a, 'b>(
    area: &'a Area<'b>,
    x: (f64, f64),
    y: (f64, f64),
) -> Result<
    ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    PlotError,
> {
    ChartBuilder::on(area)
        .margin_left(15)
        .margin_right(25)
        .margin_top(5)
        .margin_bottom(15)
        .x_label_area_size(65)
        .y_label_area_size(95)
        .build_cartesian_2d(x.0..x.1, y.0..y.1)
        .map_err(draw_err)
}

/// Snapshots of the body: two panels side by side, a top view (x-y, equal aspect) and a side view
/// (x-z, the same x scale; z stretched to fill the panel, with the stretch factor stated in the
/// panel caption and the z tick labels in true metres). `frames` holds `(t, positions)` pairs:
/// time t (s) and node positions (m) with node 0 the head. One polyline per frame, coloured by
/// time (viridis-like, early dark to late bright), legend entries "t = ... s"; the head is marked
/// with a dot. Writes a 1400x700 px PNG.
///
/// Errors: [`PlotError::Invalid`] if `frames` is empty or holds no finite point.
pub fn snapshots(
    path: &Path,
    title: &str,
    frames: &[(f64, Vec<[f64; 3]>)],
) -> Result<(), PlotError> {
    if frames.is_empty() {
        return Err(PlotError::Invalid("snapshots: no frames".into()));
    }
    let all = || frames.iter().flat_map(|(_, p)| p.iter());
    let finite = |p: &&[f64; 3]| p.iter().all(|v| v.is_finite());
    let xr = finite_range(all().filter(finite).map(|p| p[0]));
    let yr = finite_range(all().filter(finite).map(|p| p[1]));
    let zr = finite_range(all().filter(finite).map(|p| p[2]));
    if xr.is_none() {
        return Err(PlotError::Invalid(
            "snapshots: no finite node position".into(),
        ));
    }
    let tr = finite_range(frames.iter().map(|f| f.0));
    let tcolor = |t: f64| match tr {
        Some((a, b)) if b > a && t.is_finite() => colormap::sequential(0.85 * (t - a) / (b - a)),
        _ => colormap::sequential(0.0),
    };

    let (root, body) = canvas(path, SIZE_WIDE, title)?;
    let (w, _) = body.dim_in_pixel();
    let (left, right) = body.split_horizontally(w / 2);
    let cap_px = 36;
    let (lcap, larea) = left.split_vertically(cap_px);
    let (rcap, rarea) = right.split_vertically(cap_px);

    // Measure the plotting area, then choose ranges with equal metres per pixel in x and y.
    let (pw, ph) = snapshot_chart(&larea, (0.0, 1.0), (0.0, 1.0))?
        .plotting_area()
        .dim_in_pixel();
    let (pw, ph) = (pw.max(1) as f64, ph.max(1) as f64);
    let (xa, xb) = pad(xr, 0.06);
    let (ya, yb) = pad(yr, 0.06);
    let scale = ((xb - xa) / pw).max((yb - ya) / ph);
    let (cx, cy) = (0.5 * (xa + xb), 0.5 * (ya + yb));
    let xrange = (cx - 0.5 * scale * pw, cx + 0.5 * scale * pw);
    let yrange = (cy - 0.5 * scale * ph, cy + 0.5 * scale * ph);
    // Side view: same x range; z padded, with a floor on its span so that a planar body is shown
    // as a flat line rather than amplified round-off.
    let (pw2, ph2) = snapshot_chart(&rarea, (0.0, 1.0), (0.0, 1.0))?
        .plotting_area()
        .dim_in_pixel();
    let (pw2, ph2) = (pw2.max(1) as f64, ph2.max(1) as f64);
    let xspan = xrange.1 - xrange.0;
    let zmin_span = 1e-3 * xspan;
    let zr = zr.map(|(a, b)| {
        if b - a < 1e-6 * xspan {
            // Planar (to round-off): a flat line in a window 1/10 of the x extent tall.
            let c = 0.5 * (a + b);
            (c - 0.05 * xspan, c + 0.05 * xspan)
        } else if b - a < zmin_span {
            let c = 0.5 * (a + b);
            (c - 0.5 * zmin_span, c + 0.5 * zmin_span)
        } else {
            (a, b)
        }
    });
    let zrange = pad(zr, 0.1);
    let stretch = ((ph2 / (zrange.1 - zrange.0)) / (pw2 / (xrange.1 - xrange.0))).max(0.0);

    let cap_style =
        TextStyle::from((FONT, DESC_PX).into_font()).pos(plotters::style::text_anchor::Pos::new(
            plotters::style::text_anchor::HPos::Center,
            plotters::style::text_anchor::VPos::Center,
        ));
    let (cw, ch) = lcap.dim_in_pixel();
    lcap.draw_text(
        "top view (x-y, equal scales)",
        &cap_style,
        (cw as i32 / 2, ch as i32 / 2),
    )
    .map_err(draw_err)?;
    let side_caption = if stretch > 1.5 {
        format!("side view (x-z, z stretched ×{})", fmt_num(stretch, 2))
    } else if stretch < 1.0 / 1.5 {
        format!(
            "side view (x-z, z compressed ×{})",
            fmt_num(1.0 / stretch, 2)
        )
    } else {
        "side view (x-z)".to_string()
    };
    rcap.draw_text(&side_caption, &cap_style, (cw as i32 / 2, ch as i32 / 2))
        .map_err(draw_err)?;

    let mut head_pts = vec![];
    for (panel, (area, (ya_, yb_), comp, ydesc)) in [
        (&larea, yrange, 1usize, "y (m)"),
        (&rarea, zrange, 2usize, "z (m)"),
    ]
    .into_iter()
    .enumerate()
    {
        let mut chart = snapshot_chart(area, xrange, (ya_, yb_))?;
        let xfmt = |v: &f64| tick_label(*v, xrange.1 - xrange.0);
        let yfmt = |v: &f64| tick_label(*v, yb_ - ya_);
        chart
            .configure_mesh()
            .light_line_style(WHITE.mix(0.0))
            .bold_line_style(BLACK.mix(0.08))
            .x_desc("x (m)")
            .y_desc(ydesc)
            .x_label_formatter(&xfmt)
            .y_label_formatter(&yfmt)
            .axis_desc_style((FONT, DESC_PX))
            .label_style((FONT, TICK_PX))
            .x_labels(7)
            .y_labels(7)
            .draw()
            .map_err(draw_err)?;
        for (t, pos) in frames {
            let c = tcolor(*t);
            let runs = finite_runs(pos.iter().map(|p| (p[0], p[comp])));
            for (k, run) in runs.into_iter().enumerate() {
                let series = chart
                    .draw_series(LineSeries::new(run, c.stroke_width(2)))
                    .map_err(draw_err)?;
                if panel == 0 && k == 0 {
                    series
                        .label(format!("t = {} s", fmt_num(*t, 4)))
                        .legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 24, y)], c.stroke_width(3))
                        });
                }
            }
            if let Some(h) = pos.first().filter(|p| finite(p)) {
                chart
                    .draw_series(std::iter::once(Circle::new((h[0], h[comp]), 5, c.filled())))
                    .map_err(draw_err)?;
                chart
                    .draw_series(std::iter::once(Circle::new(
                        (h[0], h[comp]),
                        5,
                        BLACK.stroke_width(1),
                    )))
                    .map_err(draw_err)?;
                if panel == 0 {
                    head_pts.push((h[0], h[1]));
                }
            }
        }
        if panel == 0 {
            let pts = frames
                .iter()
                .flat_map(|(_, p)| p.iter().map(|q| (q[0], q[1])))
                .chain(head_pts.iter().copied());
            let corner = best_corner(pts, xrange, yrange, false, false);
            legend(&mut chart, corner, 10)?;
        }
        frame_plot(&mut chart)?;
    }
    root.present().map_err(draw_err)
}
