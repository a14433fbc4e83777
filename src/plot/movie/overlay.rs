//! The movie's text and legends, drawn by plotters on the frame's RGB buffer: time, `t/T`,
//! `v_s` so far and the regime in the top band; the colour legend and the scale in the bottom
//! band; in the 3D view a 0.5 L ruler on the ground. Sizes and places come from
//! [`super::layout`]: the fonts fit the picture's width and the legend wraps onto more rows of
//! the bottom band on a narrow picture.

use super::layout::{self, bar_width, flow, text_width, SWATCH};
use super::{Clip, Colouring, Plan, View, AIR, SELF_CONTACT, SLIDING, STUCK};
use crate::plot::{colormap, draw_err, PlotError, FONT};
use plotters::coord::Shift;
use plotters::prelude::*;

fn rgb(c: [u8; 3]) -> RGBColor {
    RGBColor(c[0], c[1], c[2])
}

/// Draw the overlay of movie frame `j` onto `buf` (RGB, the plan's picture size).
pub(super) fn draw(buf: &mut [u8], plan: &Plan, j: usize) -> Result<(), PlotError> {
    let (w, h) = plan.opts.size;
    let clip = plan.clip;
    let k = plan.picks[j];
    // The bands: white at 82 % over the picture, blended here (plotters blends each pixel
    // in floating point, which cost more than the scene).
    let lay = layout::layout((w, h));
    let (wu, hu) = (w as usize, h as usize);
    for rows in [0..lay.top as usize, hu - lay.bottom as usize..hu] {
        for v in &mut buf[3 * wu * rows.start..3 * wu * rows.end] {
            *v = 209 + ((*v as u16 * 46) >> 8) as u8;
        }
    }
    let root = BitMapBackend::with_buffer(buf, (w, h)).into_drawing_area();
    let (fb, fs) = (lay.big, lay.small);
    let big = (FONT, fb).into_font().color(&BLACK);
    let small = (FONT, fs).into_font().color(&BLACK);

    // Top band: the clock and the speed so far (on two lines on a narrow picture); the title
    // and the regime.
    let lines = clock_lines(clip, k, lay.split_clock);
    let mut y = 4;
    for line in lines {
        root.draw(&Text::new(line, (layout::EDGE, y), big.clone()))
            .map_err(draw_err)?;
        y += fb as i32 + 3;
    }
    let mut second = clip.title.clone();
    if let Some(r) = &clip.regime {
        second += &format!("   regime {r}");
    }
    root.draw(&Text::new(second, (layout::EDGE, y + 1), small.clone()))
        .map_err(draw_err)?;

    // Bottom band: the legend's items and the scale, placed by `layout::flow`.
    let yb = (h - lay.bottom) as i32 + 2;
    let ym_of = |row: u32| yb + (row * lay.row + lay.row / 2) as i32;
    let sw = fs as i32 * 6 / 7;
    let swatch = |root: &DrawingArea<BitMapBackend, _>, x: i32, ym: i32, c: RGBColor| {
        root.draw(&Rectangle::new(
            [(x, ym - sw / 2), (x + sw, ym + sw / 2)],
            c.filled(),
        ))
        .map_err(draw_err)
    };
    let label = |root: &DrawingArea<BitMapBackend, _>, x: i32, ym: i32, s: &str| {
        root.draw(&Text::new(
            s.to_string(),
            (x, ym - fs as i32 * 4 / 7),
            small.clone(),
        ))
        .map_err(draw_err)
    };
    let tw = |s: &str| text_width(s, fs);
    // The scale: a bar of 0.25 L (shorter when that would take more than a quarter of the
    // width) in the top and side views, the grid's spacing in the 3D view.
    let l = clip.length;
    let cam = &plan.cams[j];
    let (bar_l, bar_px) = [0.25, 0.1, 0.05, 0.02]
        .into_iter()
        .map(|f| (f, (f * l * cam.scale).round() as i32))
        .find(|&(_, px)| px <= w as i32 / 4)
        .unwrap_or((0.02, w as i32 / 4));
    let bar_text = format!("{bar_l} L");
    let scale_w = match plan.opts.view {
        View::Top | View::Side => bar_px + 8 + tw(&bar_text),
        View::ThreeD => tw("grid 0.1 L"),
    };
    match plan.opts.colour {
        Colouring::Contact => {
            let items = [
                (STUCK, "stuck"),
                (SLIDING, "sliding"),
                (AIR, "in the air"),
                (SELF_CONTACT, "on itself"),
            ];
            let widths: Vec<i32> = items.iter().map(|(_, s)| SWATCH + tw(s)).collect();
            let placed = flow(&widths, scale_w, w);
            for ((c, s), &(x, row)) in items.iter().zip(&placed) {
                swatch(&root, x, ym_of(row), rgb(*c))?;
                label(&root, x + SWATCH, ym_of(row), s)?;
            }
            draw_scale(
                &root,
                plan,
                placed[items.len()],
                ym_of(placed[items.len()].1),
                (bar_px, &bar_text),
                &small,
            )?;
        }
        Colouring::Elevation | Colouring::Lambda => {
            let (name, lo, hi) = if plan.opts.colour == Colouring::Elevation {
                ("elevation (z - a/2)/a", 0.0, plan.elev_max)
            } else {
                ("lambda (turns/m)", -plan.lambda_max, plan.lambda_max)
            };
            let (lo, hi) = (format!("{lo:.2}"), format!("{hi:.2}"));
            let wbar = bar_width(w);
            let widths = [tw(name), tw(&lo) + 6 + wbar + 6 + tw(&hi)];
            let placed = flow(&widths, scale_w, w);
            label(&root, placed[0].0, ym_of(placed[0].1), name)?;
            let (mut x, ym) = (placed[1].0, ym_of(placed[1].1));
            label(&root, x, ym, &lo)?;
            x += tw(&lo) + 6;
            for i in 0..wbar {
                let u = i as f64 / (wbar - 1) as f64;
                let c = if plan.opts.colour == Colouring::Elevation {
                    colormap::sequential(0.1 + 0.9 * u)
                } else {
                    colormap::diverging(u)
                };
                root.draw(&Rectangle::new(
                    [(x + i, ym - sw / 2), (x + i + 1, ym + sw / 2)],
                    c.filled(),
                ))
                .map_err(draw_err)?;
            }
            x += wbar + 6;
            label(&root, x, ym, &hi)?;
            draw_scale(
                &root,
                plan,
                placed[2],
                ym_of(placed[2].1),
                (bar_px, &bar_text),
                &small,
            )?;
        }
    }
    // In the 3D view, a 0.5 L ruler on the ground below the scene's centre.
    if plan.opts.view == View::ThreeD {
        ruler(&root, plan, j, &small)?;
    }
    root.present().map_err(draw_err)?;
    Ok(())
}

/// The top band's first lines at clip frame `k`: the clock (with `t/T` for a gait with a
/// period) and the speed so far (with `v_s/v_m`), on two lines when `split`, else on one.
fn clock_lines(clip: &Clip, k: usize, split: bool) -> Vec<String> {
    let t = clip.t[k];
    let mut clock = format!("t = {t:.2} s");
    if let Some(p) = clip.period.filter(|p| *p > 0.0) {
        clock += &format!("   t/T = {:.2}", t / p);
    }
    let vs = clip.v_s_so_far(k);
    let mut speed = "v_s = -".to_string();
    if vs.is_finite() {
        speed = format!("v_s = {vs:.3} m/s");
        if let Some(vm) = clip.gait_speed.filter(|v| *v > 0.0) {
            speed += &format!(" ({:.2} v_m)", vs / vm);
        }
    }
    if split {
        vec![clock, speed]
    } else {
        vec![format!("{clock}   {speed}")]
    }
}

/// The scale at `(x, _)` on the row centred at `ym`: in the top and side views a bar of
/// `bar.0` px labelled `bar.1`, in the 3D view the grid's spacing.
fn draw_scale(
    root: &DrawingArea<BitMapBackend, Shift>,
    plan: &Plan,
    (x, _): (i32, u32),
    ym: i32,
    (px, text): (i32, &str),
    small: &TextStyle,
) -> Result<(), PlotError> {
    let label = |x: i32, s: &str| {
        let dy = small.font.get_size() as i32 * 4 / 7;
        root.draw(&Text::new(s.to_string(), (x, ym - dy), small.clone()))
            .map_err(draw_err)
    };
    match plan.opts.view {
        View::Top | View::Side => {
            let (x0, x1) = (x, x + px);
            let line = vec![(x0, ym), (x1, ym)];
            root.draw(&PathElement::new(line, BLACK.stroke_width(3)))
                .map_err(draw_err)?;
            for xe in [x0, x1] {
                root.draw(&PathElement::new(
                    vec![(xe, ym - 5), (xe, ym + 5)],
                    BLACK.stroke_width(2),
                ))
                .map_err(draw_err)?;
            }
            label(x1 + 8, text)
        }
        View::ThreeD => label(x, "grid 0.1 L"),
    }
}

/// The 3D view's 0.5 L ruler on the ground below the scene's centre, along the screen's right.
fn ruler(
    root: &DrawingArea<BitMapBackend, Shift>,
    plan: &Plan,
    j: usize,
    small: &TextStyle,
) -> Result<(), PlotError> {
    let (w, l, cam) = (plan.opts.size.0, plan.clip.length, &plan.cams[j]);
    let (y0, y1) = super::scene_rows(plan.opts.size);
    let py = y1 as f64 - 0.12 * (y1 - y0) as f64;
    let Some((g, _)) = cam.ground_hit(0.5 * w as f64, py) else {
        return Ok(());
    };
    let r = cam.right;
    let n = (r[0] * r[0] + r[1] * r[1]).sqrt().max(1e-12);
    let (rx, ry) = (r[0] / n * 0.25 * l, r[1] / n * 0.25 * l);
    let a = cam.project([g[0] - rx, g[1] - ry, 0.0]);
    let b = cam.project([g[0] + rx, g[1] + ry, 0.0]);
    let (Some(a), Some(b)) = (a, b) else {
        return Ok(());
    };
    let (a, b) = ((a.0 as i32, a.1 as i32), (b.0 as i32, b.1 as i32));
    let ink = RGBColor(40, 40, 40);
    root.draw(&PathElement::new(vec![a, b], ink.stroke_width(3)))
        .map_err(draw_err)?;
    for e in [a, b] {
        root.draw(&PathElement::new(
            vec![(e.0, e.1 - 5), (e.0, e.1 + 5)],
            ink.stroke_width(2),
        ))
        .map_err(draw_err)?;
    }
    root.draw(&Text::new(
        "0.5 L".to_string(),
        (b.0 + 6, b.1 - 8),
        small.clone(),
    ))
    .map_err(draw_err)
}
