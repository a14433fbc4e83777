//! `phase_gallery.png`: one thumbnail per cell of a phase study, the body at one instant seen
//! from above and from the side, laid out on the (W, G) grid (W increasing to the right, G
//! upwards, as in `phase.png`), each on its regime's colour.

use super::phase::regime_color;
use super::{draw_err, PlotError, FONT};
use crate::observe::Regime;
use plotters::prelude::*;
use std::path::Path;

/// One cell's picture: the body at one instant.
#[derive(Clone, Debug)]
pub struct Thumb {
    /// Scaled weight `W` of the cell.
    pub weight: f64,
    /// Scaled torque `G` of the cell.
    pub torque: f64,
    /// The cell's regime (None: failed).
    pub regime: Option<Regime>,
    /// Time of the picture (s).
    pub t: f64,
    /// Node positions (m), head first; empty when the cell has no picture.
    pub x: Vec<[f64; 3]>,
}

/// Thumbnail size (px): the top view above the side view.
const CELL: (i32, i32) = (180, 150);
const TOP_H: i32 = 104;
/// Margins (px): left for the G labels, top for the title, bottom for the W labels.
const LEFT: i32 = 80;
const TOP: i32 = 50;
const BOTTOM: i32 = 50;
/// Height exaggeration of the side views.
pub const SIDE_ZOOM: f64 = 2.0;

/// The picture size (px) of a gallery of `nw` weights by `ng` torques.
pub fn gallery_size(nw: usize, ng: usize) -> (u32, u32) {
    (
        (LEFT + CELL.0 * nw as i32 + 10) as u32,
        (TOP + CELL.1 * ng as i32 + BOTTOM) as u32,
    )
}

/// Draw the gallery of `thumbs` (any order; each on its `(weight, torque)` of the grids) for a
/// rod of `length` and `diameter` (m) to a PNG or SVG at `path`.
pub fn gallery(
    path: &Path,
    weight: &[f64],
    torque: &[f64],
    thumbs: &[Thumb],
    length: f64,
    diameter: f64,
) -> Result<(), PlotError> {
    super::register_fonts()?;
    if weight.is_empty() || torque.is_empty() {
        return Err(PlotError::Invalid("gallery: an empty grid".into()));
    }
    if !(length > 0.0 && diameter > 0.0) {
        return Err(PlotError::Invalid(format!(
            "gallery: length {length} m and diameter {diameter} m must be > 0"
        )));
    }
    let size = gallery_size(weight.len(), torque.len());
    let svg = path.extension().is_some_and(|e| e == "svg");
    if svg {
        let root = SVGBackend::new(path, size).into_drawing_area();
        draw(&root, weight, torque, thumbs, length, diameter)?;
        root.present().map_err(draw_err)
    } else {
        let root = BitMapBackend::new(path, size).into_drawing_area();
        draw(&root, weight, torque, thumbs, length, diameter)?;
        root.present().map_err(draw_err)
    }
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    weight: &[f64],
    torque: &[f64],
    thumbs: &[Thumb],
    length: f64,
    diameter: f64,
) -> Result<(), PlotError> {
    root.fill(&WHITE).map_err(draw_err)?;
    let ng = torque.len() as i32;
    let text = |s: String, at: (i32, i32), px: u32| {
        root.draw(&Text::new(s, at, (FONT, px).into_font().color(&BLACK)))
            .map_err(draw_err)
    };
    text(
        "Phase gallery: the body at the writhe snapshot".to_string(),
        (LEFT, 6),
        17,
    )?;
    text(
        format!("top view above, side view below (height x{SIDE_ZOOM}); red: the head"),
        (LEFT, 27),
        14,
    )?;
    // Column j: weight j; row i from the top: torque ng - 1 - i.
    let origin = |wi: usize, gi: usize| {
        (
            LEFT + CELL.0 * wi as i32,
            TOP + CELL.1 * (ng - 1 - gi as i32),
        )
    };
    for (wi, w) in weight.iter().enumerate() {
        let (x0, _) = origin(wi, 0);
        text(format!("W = {w}"), (x0 + 50, TOP + CELL.1 * ng + 12), 16)?;
    }
    for (gi, g) in torque.iter().enumerate() {
        let (_, y0) = origin(0, gi);
        text(format!("G = {g}"), (8, y0 + CELL.1 / 2 - 8), 16)?;
    }
    let scale = 0.9 * CELL.0 as f64 / length;
    let stroke = ((diameter * scale).round() as u32).max(2);
    for th in thumbs {
        let (Some(wi), Some(gi)) = (
            weight
                .iter()
                .position(|w| w.to_bits() == th.weight.to_bits()),
            torque
                .iter()
                .position(|g| g.to_bits() == th.torque.to_bits()),
        ) else {
            continue;
        };
        let (x0, y0) = origin(wi, gi);
        let c = regime_color(th.regime);
        let tint = RGBColor(
            (255.0 - 0.35 * (255.0 - c.0 as f64)) as u8,
            (255.0 - 0.35 * (255.0 - c.1 as f64)) as u8,
            (255.0 - 0.35 * (255.0 - c.2 as f64)) as u8,
        );
        let inner = [(x0 + 2, y0 + 2), (x0 + CELL.0 - 2, y0 + CELL.1 - 2)];
        root.draw(&Rectangle::new(inner, tint.filled()))
            .map_err(draw_err)?;
        root.draw(&Rectangle::new(inner, c.stroke_width(2)))
            .map_err(draw_err)?;
        // The side view's ground line.
        let ground = y0 + CELL.1 - 10;
        root.draw(&PathElement::new(
            vec![(x0 + 6, ground), (x0 + CELL.0 - 6, ground)],
            RGBColor(120, 120, 120).stroke_width(1),
        ))
        .map_err(draw_err)?;
        let label = th.regime.map_or("failed", |r| r.as_str());
        text(label.to_string(), (x0 + 7, y0 + 5), 15)?;
        let pts: Vec<[f64; 3]> =
            th.x.iter()
                .copied()
                .filter(|p| p.iter().all(|v| v.is_finite()))
                .collect();
        if pts.len() < 2 {
            continue;
        }
        let n = pts.len() as f64;
        let (cx, cy) = (
            pts.iter().map(|p| p[0]).sum::<f64>() / n,
            pts.iter().map(|p| p[1]).sum::<f64>() / n,
        );
        let (mx, my) = (x0 + CELL.0 / 2, y0 + TOP_H / 2 + 4);
        let top: Vec<(i32, i32)> = pts
            .iter()
            .map(|p| {
                (
                    mx + ((p[0] - cx) * scale).round() as i32,
                    my - ((p[1] - cy) * scale).round() as i32,
                )
            })
            .collect();
        let side: Vec<(i32, i32)> = pts
            .iter()
            .map(|p| {
                (
                    mx + ((p[0] - cx) * scale).round() as i32,
                    ground
                        - ((p[2] - 0.5 * diameter).max(0.0) * scale * SIDE_ZOOM).round() as i32
                        - (stroke as i32 + 1) / 2,
                )
            })
            .collect();
        let body = RGBColor(40, 40, 40);
        for line in [top, side] {
            root.draw(&PathElement::new(line.clone(), body.stroke_width(stroke)))
                .map_err(draw_err)?;
            // The head.
            root.draw(&Circle::new(line[0], stroke as i32 + 1, RED.filled()))
                .map_err(draw_err)?;
        }
    }
    Ok(())
}
