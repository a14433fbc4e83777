//! Ground tracks: the ground plane from above with every node's stuck contact over time.
//!
//! Each frame in which a node is stuck ([`ContactState::Stuck`]) puts a dot of 0.6 times the
//! rod's diameter (at least 3 px) where the node touches the ground, coloured by time
//! (viridis-like, early dark to late bright); a node stuck in consecutive frames draws a line
//! between the dots, so a resting patch shows as a blot and a node that sticks while the body
//! rolls over it draws a short track. The body's centreline at six instants is drawn thin in
//! the same time colours, the head marked, with a legend of the instants. Equal scales in x
//! and y. PNG or SVG by the path's extension.

use super::axes::{
    best_corner, canvas_on, finite_range, fmt_num, frame_plot, legend, pad, tick_label,
};
use super::movie::{Clip, ContactState};
use super::{colormap, draw_err, PlotError, DESC_PX, FONT, TICK_PX};
use plotters::prelude::*;
use std::path::Path;

/// Figure size (px).
const SIZE: (u32, u32) = (1000, 800);

/// Write the tracks figure of `clip` to `path` (`.svg`: SVG, else PNG).
///
/// Errors: [`PlotError::Invalid`] when the clip has no frame or no finite position.
pub fn tracks(path: &Path, clip: &Clip) -> Result<(), PlotError> {
    let nf = clip.t.len();
    if nf == 0 || clip.x.len() != nf || clip.contact.len() != nf {
        return Err(PlotError::Invalid(format!(
            "tracks: {} times, {} position frames, {} contact frames",
            nf,
            clip.x.len(),
            clip.contact.len()
        )));
    }
    let finite = |p: &[f64; 3]| p.iter().all(|v| v.is_finite());
    let all = || clip.x.iter().flatten().filter(|p| finite(p));
    let (Some(xr), Some(yr)) = (
        finite_range(all().map(|p| p[0])),
        finite_range(all().map(|p| p[1])),
    ) else {
        return Err(PlotError::Invalid("tracks: no finite node position".into()));
    };
    let (t0, t1) = (clip.t[0], clip.t[nf - 1]);
    let tcolor = |t: f64| {
        if t1 > t0 {
            colormap::sequential(0.9 * (t - t0) / (t1 - t0))
        } else {
            colormap::sequential(0.0)
        }
    };
    let stuck_frames = clip
        .contact
        .iter()
        .flatten()
        .filter(|c| **c == ContactState::Stuck)
        .count();
    let title = if clip.title.is_empty() {
        "Ground tracks: stuck contacts over time".to_string()
    } else {
        format!("Ground tracks of {}: stuck contacts over time", clip.title)
    };
    crate::on_backend!(path, SIZE, |area| {
        let (root, body) = canvas_on(area, &title)?;
        let chart_of = |xr: (f64, f64), yr: (f64, f64)| {
            ChartBuilder::on(&body)
                .margin_left(15)
                .margin_right(30)
                .margin_top(5)
                .margin_bottom(15)
                .x_label_area_size(65)
                .y_label_area_size(95)
                .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
                .map_err(draw_err)
        };
        // Equal metres per pixel in x and y.
        let (pw, ph) = chart_of((0.0, 1.0), (0.0, 1.0))?
            .plotting_area()
            .dim_in_pixel();
        let (pw, ph) = (pw.max(1) as f64, ph.max(1) as f64);
        let (xa, xb) = pad(Some(xr), 0.06);
        let (ya, yb) = pad(Some(yr), 0.06);
        let scale = ((xb - xa) / pw).max((yb - ya) / ph);
        let (cx, cy) = (0.5 * (xa + xb), 0.5 * (ya + yb));
        let xrange = (cx - 0.5 * scale * pw, cx + 0.5 * scale * pw);
        let yrange = (cy - 0.5 * scale * ph, cy + 0.5 * scale * ph);
        let mut chart = chart_of(xrange, yrange)?;
        let xfmt = |v: &f64| tick_label(*v, xrange.1 - xrange.0);
        let yfmt = |v: &f64| tick_label(*v, yrange.1 - yrange.0);
        let tfmt = format!(
            "x (m); track colour = time, {} s (dark) to {} s (bright); {} stuck node-frames",
            fmt_num(t0, 3),
            fmt_num(t1, 3),
            stuck_frames
        );
        chart
            .configure_mesh()
            .light_line_style(WHITE.mix(0.0))
            .bold_line_style(BLACK.mix(0.08))
            .x_desc(tfmt)
            .y_desc("y (m)")
            .x_label_formatter(&xfmt)
            .y_label_formatter(&yfmt)
            .axis_desc_style((FONT, DESC_PX))
            .label_style((FONT, TICK_PX))
            .x_labels(7)
            .y_labels(7)
            .draw()
            .map_err(draw_err)?;
        let dot = ((clip.diameter / scale) * 0.3).round().max(1.5) as i32;
        draw_stuck(&mut chart, clip, dot, &tcolor)?;
        // Self-contact: every node-frame touching another part of the body, in its colour.
        let purple = RGBColor(
            super::movie::SELF_CONTACT[0],
            super::movie::SELF_CONTACT[1],
            super::movie::SELF_CONTACT[2],
        );
        let touching = touching_dots(clip, dot, purple);
        if !touching.is_empty() {
            chart
                .draw_series(touching)
                .map_err(draw_err)?
                .label("touching another part of the body")
                .legend(move |(x, y)| Circle::new((x + 12, y), 4, purple.filled()));
        }
        // The body at six instants.
        let m = 6.min(nf);
        for j in 0..m {
            let k = j * (nf - 1) / (m - 1).max(1);
            let c = tcolor(clip.t[k]);
            let pts: Vec<(f64, f64)> = clip.x[k]
                .iter()
                .filter(|p| finite(p))
                .map(|p| (p[0], p[1]))
                .collect();
            chart
                .draw_series(std::iter::once(PathElement::new(
                    pts.clone(),
                    BLACK.mix(0.55).stroke_width(4),
                )))
                .map_err(draw_err)?;
            chart
                .draw_series(std::iter::once(PathElement::new(pts, c.stroke_width(2))))
                .map_err(draw_err)?
                .label(format!("body at t = {} s", fmt_num(clip.t[k], 3)))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], c.stroke_width(3))
                });
            if let Some(h) = clip.x[k].first().filter(|p| finite(p)) {
                chart
                    .draw_series(std::iter::once(Circle::new((h[0], h[1]), 5, c.filled())))
                    .map_err(draw_err)?;
                chart
                    .draw_series(std::iter::once(Circle::new(
                        (h[0], h[1]),
                        5,
                        BLACK.stroke_width(1),
                    )))
                    .map_err(draw_err)?;
            }
        }
        let corner = best_corner(all().map(|p| (p[0], p[1])), xrange, yrange, false, false);
        legend(&mut chart, corner, 10)?;
        frame_plot(&mut chart)?;
        root.present().map_err(draw_err)
    })
}

/// The stuck contacts of [`tracks`]: per node, a dot of radius `dot` (px) at every stuck frame
/// in the frame's time colour, joined to the previous one when that frame was stuck too.
fn draw_stuck<DB, X, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    clip: &Clip,
    dot: i32,
    tcolor: &dyn Fn(f64) -> RGBColor,
) -> Result<(), PlotError>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let finite = |p: &[f64; 3]| p.iter().all(|v| v.is_finite());
    let nn = clip.x[0].len();
    for i in 0..nn {
        let mut prev: Option<(f64, f64)> = None;
        for ((xk, ck), &tk) in clip.x.iter().zip(&clip.contact).zip(&clip.t) {
            let p = xk.get(i).copied().unwrap_or([f64::NAN; 3]);
            let stuck = ck.get(i) == Some(&ContactState::Stuck) && finite(&p);
            if !stuck {
                prev = None;
                continue;
            }
            let c = tcolor(tk);
            let q = (p[0], p[1]);
            if let Some(a) = prev {
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        vec![a, q],
                        c.stroke_width((2 * dot) as u32),
                    )))
                    .map_err(draw_err)?;
            }
            chart
                .draw_series(std::iter::once(Circle::new(q, dot, c.filled())))
                .map_err(draw_err)?;
            prev = Some(q);
        }
    }
    Ok(())
}

/// The self-contacts of [`tracks`]: a dot of half the stuck dots' radius at every node-frame
/// touching another part of the body.
fn touching_dots(clip: &Clip, dot: i32, purple: RGBColor) -> Vec<Circle<(f64, f64), i32>> {
    let finite = |p: &[f64; 3]| p.iter().all(|v| v.is_finite());
    clip.x
        .iter()
        .zip(&clip.self_contact)
        .flat_map(|(xk, sk)| {
            xk.iter()
                .zip(sk)
                .filter(|(p, &on)| on && finite(p))
                .map(|(p, _)| Circle::new((p[0], p[1]), (dot / 2).max(1), purple.filled()))
                .collect::<Vec<_>>()
        })
        .collect()
}
