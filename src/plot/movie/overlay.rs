//! The movie's text and legends, drawn by plotters on the frame's RGB buffer: time, `t/T`,
//! `v_s` so far and the regime in the top band; the colour legend and the scale in the bottom
//! band; in the 3D view a 0.5 L ruler on the ground.

use super::{Colouring, Plan, View, AIR, BOTTOM_BAND, SELF_CONTACT, SLIDING, STUCK, TOP_BAND};
use crate::plot::{colormap, draw_err, PlotError, FONT};
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
    let (wu, hu) = (w as usize, h as usize);
    for rows in [0..TOP_BAND as usize, hu - BOTTOM_BAND as usize..hu] {
        for v in &mut buf[3 * wu * rows.start..3 * wu * rows.end] {
            *v = 209 + ((*v as u16 * 46) >> 8) as u8;
        }
    }
    let root = BitMapBackend::with_buffer(buf, (w, h)).into_drawing_area();
    // Text sized to the picture: 17 and 14 px at 640 px wide and more, 14 and 12 below.
    let (fb, fs) = if w >= 640 { (17, 14) } else { (14, 12) };
    let big = (FONT, fb).into_font().color(&BLACK);
    let small = (FONT, fs).into_font().color(&BLACK);

    // Top band: the clock and the speed so far; the title and the regime.
    let t = clip.t[k];
    let mut line = format!("t = {t:.2} s");
    if let Some(p) = clip.period.filter(|p| *p > 0.0) {
        line += &format!("   t/T = {:.2}", t / p);
    }
    let vs = clip.v_s_so_far(k);
    if vs.is_finite() {
        line += &format!("   v_s = {vs:.3} m/s");
        if let Some(vm) = clip.gait_speed.filter(|v| *v > 0.0) {
            line += &format!(" ({:.2} v_m)", vs / vm);
        }
    } else {
        line += "   v_s = -";
    }
    root.draw(&Text::new(line, (8, 4), big.clone()))
        .map_err(draw_err)?;
    let mut second = clip.title.clone();
    if let Some(r) = &clip.regime {
        second += &format!("   regime {r}");
    }
    root.draw(&Text::new(second, (8, 8 + fb), small.clone()))
        .map_err(draw_err)?;

    // Bottom band: legend.
    let yb = (h - BOTTOM_BAND) as i32;
    let ym = yb + (BOTTOM_BAND as i32) / 2;
    let mut x = 8;
    let swatch = |root: &DrawingArea<BitMapBackend, _>, x: i32, c: RGBColor| {
        root.draw(&Rectangle::new([(x, ym - 6), (x + 14, ym + 6)], c.filled()))
            .map_err(draw_err)
    };
    // Draws a label and returns its width (px).
    let label = |root: &DrawingArea<BitMapBackend, _>, x: i32, s: &str| {
        root.draw(&Text::new(s.to_string(), (x, ym - 8), small.clone()))
            .map_err(draw_err)?;
        root.estimate_text_size(s, &small)
            .map(|(tw, _)| tw as i32)
            .map_err(draw_err)
    };
    match plan.opts.colour {
        Colouring::Contact => {
            for (c, s) in [
                (STUCK, "stuck"),
                (SLIDING, "sliding"),
                (AIR, "in the air"),
                (SELF_CONTACT, "on itself"),
            ] {
                swatch(&root, x, rgb(c))?;
                x += 18 + label(&root, x + 18, s)? + 14;
            }
        }
        Colouring::Elevation | Colouring::Lambda => {
            let (name, lo, hi) = if plan.opts.colour == Colouring::Elevation {
                ("elevation (z - a/2)/a", 0.0, plan.elev_max)
            } else {
                ("lambda (turns/m)", -plan.lambda_max, plan.lambda_max)
            };
            x += label(&root, x, name)? + 10;
            x += label(&root, x, &format!("{lo:.2}"))? + 6;
            let wbar = if w >= 640 { 120 } else { 80 };
            for i in 0..wbar {
                let u = i as f64 / (wbar - 1) as f64;
                let c = if plan.opts.colour == Colouring::Elevation {
                    colormap::sequential(0.1 + 0.9 * u)
                } else {
                    colormap::diverging(u)
                };
                root.draw(&Rectangle::new(
                    [(x + i, ym - 6), (x + i + 1, ym + 6)],
                    c.filled(),
                ))
                .map_err(draw_err)?;
            }
            x += wbar + 6;
            label(&root, x, &format!("{hi:.2}"))?;
        }
    }

    // Scale.
    let l = clip.length;
    let cam = &plan.cams[j];
    match plan.opts.view {
        View::Top | View::Side => {
            let px = (0.25 * l * cam.scale).round() as i32;
            let x1 = w as i32 - 70;
            let x0 = x1 - px;
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
            label(&root, x1 + 8, "0.25 L")?;
        }
        View::ThreeD => {
            label(&root, w as i32 - 95, "grid 0.1 L")?;
            // A 0.5 L ruler on the ground below the scene's centre, along the screen's right.
            let (y0, y1) = super::scene_rows(plan.opts.size);
            let py = y1 as f64 - 0.12 * (y1 - y0) as f64;
            if let Some((g, _)) = cam.ground_hit(0.5 * w as f64, py) {
                let r = cam.right;
                let n = (r[0] * r[0] + r[1] * r[1]).sqrt().max(1e-12);
                let (rx, ry) = (r[0] / n * 0.25 * l, r[1] / n * 0.25 * l);
                let a = cam.project([g[0] - rx, g[1] - ry, 0.0]);
                let b = cam.project([g[0] + rx, g[1] + ry, 0.0]);
                if let (Some(a), Some(b)) = (a, b) {
                    let (a, b) = ((a.0 as i32, a.1 as i32), (b.0 as i32, b.1 as i32));
                    root.draw(&PathElement::new(
                        vec![a, b],
                        RGBColor(40, 40, 40).stroke_width(3),
                    ))
                    .map_err(draw_err)?;
                    for e in [a, b] {
                        root.draw(&PathElement::new(
                            vec![(e.0, e.1 - 5), (e.0, e.1 + 5)],
                            RGBColor(40, 40, 40).stroke_width(2),
                        ))
                        .map_err(draw_err)?;
                    }
                    root.draw(&Text::new(
                        "0.5 L".to_string(),
                        (b.0 + 6, b.1 - 8),
                        small.clone(),
                    ))
                    .map_err(draw_err)?;
                }
            }
        }
    }
    root.present().map_err(draw_err)?;
    Ok(())
}
