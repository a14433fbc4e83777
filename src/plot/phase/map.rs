//! The regime map (`phase.png` / `phase.svg`): one coloured rectangle per cell on log-log axes
//! ([`super::GridAxis`]: ticks at the grid values, a zero beyond a break), each labelled
//! with its regime, the fitted boundary lines, and the legend on the right.
//!
//! A cell's label is a stack of one or two centred lines placed in pixels from the cell's
//! centre ([`label_stack`]); an uncertain cell is hatched, and its label sits on a white box
//! drawn over the hatching so the hatch never runs through the text.

use super::axis::{boundary_segment, short, supported_box, GridAxis};
use super::{regime_color, regime_counts, MapCell, MapLine, FULL_LABEL_MAX_COLUMNS};
use crate::observe::Regime;
use crate::plot::PlotError;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;
use std::path::Path;

/// Colours of the fitted boundary lines on the map, in `boundaries.json` order.
/// (Ten: the five regimes have at most ten neighbouring pairs, so no two lines share one.)
const BOUNDARY_COLORS: [RGBColor; 10] = [
    RGBColor(0, 0, 0),
    RGBColor(150, 30, 150),
    RGBColor(20, 70, 170),
    RGBColor(160, 60, 0),
    RGBColor(0, 120, 120),
    RGBColor(110, 110, 0),
    RGBColor(230, 0, 120),
    RGBColor(0, 170, 230),
    RGBColor(120, 70, 30),
    RGBColor(90, 90, 90),
];

/// Most ticks on the weight axis (labels of up to 4 digits across the 1000 px wide map) and on
/// the torque axis.
const MAX_W_TICKS: usize = 12;
const MAX_G_TICKS: usize = 16;

/// The layout of a cell label of lines of pixel sizes `sizes` (width, height), centred on the
/// cell's centre: each line's vertical offset (px, from the centre to the line's centre), the
/// lines `gap` px apart, and the box (px, corners relative to the centre) that holds them with
/// `pad` px around.
pub fn label_stack(sizes: &[(u32, u32)], gap: i32, pad: i32) -> (Vec<i32>, [(i32, i32); 2]) {
    let total: i32 =
        sizes.iter().map(|s| s.1 as i32).sum::<i32>() + gap * (sizes.len() as i32 - 1).max(0);
    let top = -total / 2;
    let mut y = top;
    let offsets = sizes
        .iter()
        .map(|&(_, h)| {
            let c = y + h as i32 / 2;
            y += h as i32 + gap;
            c
        })
        .collect();
    let half_w = sizes.iter().map(|s| s.0 as i32).max().unwrap_or(0) / 2 + 1;
    (
        offsets,
        [
            (-half_w - pad, top - pad),
            (half_w + pad, top + total + pad),
        ],
    )
}

/// The regime map (`phase.png` / `phase.svg`, by the extension of `path`): one coloured
/// rectangle per cell on log-log axes (log W across, log G up; a zero in either grid drawn as
/// its own row or column beyond a break, see [`GridAxis`]), ticks at the grid values, each
/// cell labelled with the regime and `v_s / v_m` (and, for `M`, the S criteria it missed; only
/// the regime letter on grids wider than [`FULL_LABEL_MAX_COLUMNS`]), the fitted regime
/// boundaries (`bounds`, in `boundaries.json` order) drawn as lines, and on the right a legend
/// of the regimes with their cell counts and of the boundary lines with slope and `W/G` at
/// `G = 10`. The cells of a gait with a launch period that sidewind ([`MapCell::sidewinding`])
/// say so under their label, and the legend counts them.
pub fn regime_map(
    path: &Path,
    weight: &[f64],
    torque: &[f64],
    cells: &[MapCell],
    bounds: &[MapLine],
) -> Result<(), PlotError> {
    crate::plot::register_fonts()?;
    let err = |e: &dyn std::fmt::Display| PlotError::Draw(e.to_string());
    let xa = GridAxis::new("weight", weight, MAX_W_TICKS)?;
    let ya = GridAxis::new("torque", torque, MAX_G_TICKS)?;
    crate::on_backend!(path, (1400, 800), |root| {
        root.fill(&WHITE).map_err(|e| err(&e))?;
        let (left, right) = root.split_horizontally(1000);
        map_body(&left, &xa, &ya, cells, bounds)?;
        map_legend(&right, cells, bounds)?;
        root.present().map_err(|e| err(&e))
    })
}

/// A log axis over `a`'s range with ticks at its grid values.
fn log_axis(a: &GridAxis) -> impl AsRangedCoord<Value = f64, CoordDescType: ValueFormatter<f64>> {
    use plotters::coord::combinators::BindKeyPoints;
    a.range()
        .log_scale()
        .with_key_points(a.ticks.iter().map(|t| t.0).collect())
}

/// Cells, labels, breaks and boundary lines of [`regime_map`] on any backend.
fn map_body<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    xa: &GridAxis,
    ya: &GridAxis,
    cells: &[MapCell],
    bounds: &[MapLine],
) -> Result<(), PlotError> {
    use plotters::style::text_anchor::{HPos, Pos, VPos};
    let err = |e: &dyn std::fmt::Display| PlotError::Draw(e.to_string());
    let mut chart = ChartBuilder::on(area)
        .caption(
            "Regime over scaled weight and scaled torque",
            ("sans-serif", 24),
        )
        .margin(20)
        .x_label_area_size(60)
        .y_label_area_size(80)
        .build_cartesian_2d(log_axis(xa), log_axis(ya))
        .map_err(|e| err(&e))?;
    let desc = |name: &str, a: &GridAxis| match a.zero_break {
        Some(_) => format!("{name} (log; 0 beyond the break)"),
        None => format!("{name} (log)"),
    };
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(desc("scaled weight W = rho g a^2 L^3 / B", xa))
        .y_desc(desc("scaled torque G = Gamma a^3 L / B", ya))
        .x_label_formatter(&|v: &f64| xa.label(*v))
        .y_label_formatter(&|v: &f64| ya.label(*v))
        .label_style(("sans-serif", 18))
        .axis_desc_style(("sans-serif", 22))
        .draw()
        .map_err(|e| err(&e))?;
    let centred = |px: u32| {
        ("sans-serif", px)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Center))
    };
    let (xe, ye) = (&xa.edges, &ya.edges);
    let nt = ya.at.len();
    let full = xe.len() - 1 <= FULL_LABEL_MAX_COLUMNS;
    for (k, c) in cells.iter().enumerate() {
        let (i, j) = (k / nt, k % nt);
        if i + 1 >= xe.len() {
            break;
        }
        let rect = [(xe[i], ye[j]), (xe[i + 1], ye[j + 1])];
        chart
            .draw_series([
                Rectangle::new(rect, regime_color(c.regime).filled()),
                Rectangle::new(rect, WHITE.stroke_width(if full { 2 } else { 1 })),
            ])
            .map_err(|e| err(&e))?;
        // A point a fraction (fx, fy) across the cell, in log space.
        let at = |fx: f64, fy: f64| {
            (
                xe[i] * (xe[i + 1] / xe[i]).powf(fx),
                ye[j] * (ye[j + 1] / ye[j]).powf(fy),
            )
        };
        if c.uncertain {
            // Hatched with three diagonals and outlined in black, inset from the white grid.
            let hatch = [
                (0.06, 0.5, 0.5, 0.94),
                (0.06, 0.06, 0.94, 0.94),
                (0.5, 0.06, 0.94, 0.5),
            ];
            chart
                .draw_series(hatch.iter().map(|&(x0, y0, x1, y1)| {
                    PathElement::new(vec![at(x0, y0), at(x1, y1)], BLACK.stroke_width(2))
                }))
                .map_err(|e| err(&e))?;
            let outline = vec![
                at(0.06, 0.06),
                at(0.94, 0.06),
                at(0.94, 0.94),
                at(0.06, 0.94),
                at(0.06, 0.06),
            ];
            chart
                .draw_series(std::iter::once(PathElement::new(
                    outline,
                    BLACK.stroke_width(3),
                )))
                .map_err(|e| err(&e))?;
        }
        let lines = cell_lines(c, full);
        let sizes: Vec<(u32, u32)> = lines
            .iter()
            .map(|(t, px)| {
                ("sans-serif", *px)
                    .into_font()
                    .box_size(t)
                    .unwrap_or((0, *px))
            })
            .collect();
        let (offsets, bx) = label_stack(&sizes, 3, 3);
        let centre = at(0.5, 0.5);
        if c.uncertain {
            chart
                .draw_series(std::iter::once(
                    EmptyElement::at(centre) + Rectangle::new(bx, WHITE.mix(0.9).filled()),
                ))
                .map_err(|e| err(&e))?;
        }
        for ((text, px), dy) in lines.into_iter().zip(offsets) {
            chart
                .draw_series(std::iter::once(
                    EmptyElement::at(centre) + Text::new(text, (0, dy), centred(px)),
                ))
                .map_err(|e| err(&e))?;
        }
    }
    draw_breaks(&mut chart, xa, ya)?;
    draw_bounds(&mut chart, xa, ya, bounds)
}

/// The text of a cell of [`regime_map`], one `(line, px)` per line stacked about the cell's
/// centre: the regime (with `v_s / v_m` on a full-label grid, `*` for a sidewinding cell
/// otherwise), and under it an M cell's missed S criteria and "sidewinding" (full labels only).
fn cell_lines(c: &MapCell, full: bool) -> Vec<(String, u32)> {
    let ok = c.ok;
    let sidewinds = c.sidewinding == Some(true);
    let label = match c.regime {
        Some(r) if ok && full => format!("{r} {:.3}", c.v_s_over_v_m),
        Some(r) if ok && sidewinds => format!("{r}*"),
        Some(r) if ok => r.to_string(),
        _ if full => "failed".into(),
        _ => "x".into(),
    };
    let missed = (full && c.regime == Some(Regime::M))
        .then(|| c.regime_detail.replace('_', " ").replace(';', ", "));
    let detail = match (missed, full && sidewinds) {
        (Some(m), true) => Some(format!("sidewinding; {m}")),
        (None, true) => Some("sidewinding".into()),
        (m, false) => m,
    };
    std::iter::once((label, if full { 17 } else { 13 }))
        .chain(detail.map(|d| (d, 14)))
        .collect()
}

/// A zero row or column of [`regime_map`]: a white gap at the break across the map and "//" on
/// the axis.
fn draw_breaks<DB, X, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    xa: &GridAxis,
    ya: &GridAxis,
) -> Result<(), PlotError>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let err = |e: &dyn std::fmt::Display| PlotError::Draw(e.to_string());
    let (xe, ye) = (&xa.edges, &ya.edges);
    let (x0, x1) = (xe[0], xe[xe.len() - 1]);
    let (y0, y1) = (ye[0], ye[ye.len() - 1]);
    let slashes = |horizontal: bool| {
        [-4, 4].map(|d| {
            let pts = if horizontal {
                vec![(-8, d + 4), (8, d - 4)]
            } else {
                vec![(d - 4, 8), (d + 4, -8)]
            };
            PathElement::new(pts, BLACK.stroke_width(2))
        })
    };
    if let Some(b) = ya.zero_break {
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(x0, b), (x1, b)],
                WHITE.stroke_width(6),
            )))
            .map_err(|e| err(&e))?;
        chart
            .draw_series(slashes(true).map(|s| EmptyElement::at((x0, b)) + s))
            .map_err(|e| err(&e))?;
    }
    if let Some(b) = xa.zero_break {
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(b, y0), (b, y1)],
                WHITE.stroke_width(6),
            )))
            .map_err(|e| err(&e))?;
        chart
            .draw_series(slashes(false).map(|s| EmptyElement::at((b, y0)) + s))
            .map_err(|e| err(&e))?;
    }
    Ok(())
}

/// The boundary lines of [`regime_map`], over the positive values only (they are fitted in
/// log space), with the points bisection placed.
fn draw_bounds<DB, X, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    xa: &GridAxis,
    ya: &GridAxis,
    bounds: &[MapLine],
) -> Result<(), PlotError>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let err = |e: &dyn std::fmt::Display| PlotError::Draw(e.to_string());
    let (lw, lg) = (xa.log_span(), ya.log_span());
    for (k, b) in bounds.iter().enumerate() {
        let (Some(s), Some(c)) = (b.slope, b.intercept) else {
            continue;
        };
        let col = BOUNDARY_COLORS[k % BOUNDARY_COLORS.len()];
        // Drawn only across the cells that support it: the span of its fitted points.
        let (sw, sg) = supported_box(&b.points, lw, lg);
        if let Some(seg) = boundary_segment(s, c, sw, sg) {
            chart
                .draw_series(LineSeries::new(seg, col.stroke_width(4)))
                .map_err(|e| err(&e))?;
        }
        // Bisected points: where the boundary was found, as dots of the line's colour.
        if b.bisected {
            chart
                .draw_series(
                    b.points
                        .iter()
                        .filter(|(w, g)| *w > 0.0 && *g > 0.0)
                        .map(|&(w, g)| Circle::new((w, g), 5, col.filled())),
                )
                .map_err(|e| err(&e))?;
        }
    }
    Ok(())
}

/// The legend of [`regime_map`]: regimes with cell counts, then the boundary lines.
fn map_legend<DB: DrawingBackend>(
    right: &DrawingArea<DB, plotters::coord::Shift>,
    cells: &[MapCell],
    bounds: &[MapLine],
) -> Result<(), PlotError> {
    use plotters::style::text_anchor::{HPos, Pos, VPos};
    let err = |e: &dyn std::fmt::Display| PlotError::Draw(e.to_string());
    let (counts, failed) = regime_counts(cells);
    let left_style = |px: u32| {
        ("sans-serif", px)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Left, VPos::Center))
    };
    let mut y = 60;
    let nw = cells.len()
        / cells
            .iter()
            .filter(|c| c.weight == cells[0].weight)
            .count()
            .max(1);
    let what = if nw <= FULL_LABEL_MAX_COLUMNS {
        "cell label: regime and v_s/v_m"
    } else {
        "cell label: regime"
    };
    right
        .draw(&Text::new(what, (10, y), left_style(16)))
        .map_err(|e| err(&e))?;
    y += 30;
    right
        .draw(&Text::new("regime (cells)", (10, y), left_style(18)))
        .map_err(|e| err(&e))?;
    let rows = counts
        .iter()
        .map(|&(r, n)| (Some(r), format!("{r}: {} ({n})", r.description())))
        .chain((failed > 0).then(|| (None, format!("failed ({failed})"))));
    for (r, text) in rows {
        y += 34;
        right
            .draw(&Rectangle::new(
                [(10, y - 11), (34, y + 11)],
                regime_color(r).filled(),
            ))
            .map_err(|e| err(&e))?;
        right
            .draw(&Text::new(text, (44, y), left_style(18)))
            .map_err(|e| err(&e))?;
    }
    let uncertain = cells.iter().filter(|c| c.uncertain).count();
    if uncertain > 0 {
        y += 34;
        right
            .draw(&Rectangle::new(
                [(10, y - 11), (34, y + 11)],
                WHITE.filled(),
            ))
            .map_err(|e| err(&e))?;
        for (a, b) in [
            ((10, y), (22, y + 11)),
            ((10, y - 11), (34, y + 11)),
            ((22, y - 11), (34, y)),
        ] {
            right
                .draw(&PathElement::new(vec![a, b], BLACK.stroke_width(2)))
                .map_err(|e| err(&e))?;
        }
        right
            .draw(&Rectangle::new(
                [(10, y - 11), (34, y + 11)],
                BLACK.stroke_width(2),
            ))
            .map_err(|e| err(&e))?;
        right
            .draw(&Text::new(
                format!("uncertain ({uncertain}): runs disagree on the label"),
                (44, y),
                left_style(18),
            ))
            .map_err(|e| err(&e))?;
    }
    let periodic = cells.iter().filter(|c| c.sidewinding.is_some()).count();
    if periodic > 0 {
        let n = cells.iter().filter(|c| c.sidewinding == Some(true)).count();
        let mark = if nw <= FULL_LABEL_MAX_COLUMNS {
            "(written under the label)"
        } else {
            "(the label starred)"
        };
        y += 34;
        right
            .draw(&Text::new(
                format!("sidewinding: {n} of {periodic} measured cells"),
                (10, y),
                left_style(18),
            ))
            .map_err(|e| err(&e))?;
        y += 24;
        right
            .draw(&Text::new(mark, (10, y), left_style(16)))
            .map_err(|e| err(&e))?;
    }
    let fitted: Vec<(usize, &MapLine)> = bounds
        .iter()
        .enumerate()
        .filter(|(_, b)| b.slope.is_some())
        .collect();
    if fitted.is_empty() {
        return Ok(());
    }
    y += 60;
    right
        .draw(&Text::new(
            "fitted boundaries (log G = s log W + c)",
            (10, y),
            left_style(16),
        ))
        .map_err(|e| err(&e))?;
    for (k, b) in fitted {
        y += 30;
        let col = BOUNDARY_COLORS[k % BOUNDARY_COLORS.len()];
        right
            .draw(&PathElement::new(
                vec![(10, y), (34, y)],
                col.stroke_width(4),
            ))
            .map_err(|e| err(&e))?;
        let ratio = b.ratio_at_g10.map_or("-".to_string(), |r| {
            if (0.01..1e5).contains(&r.abs()) {
                short(r)
            } else {
                format!("{r:.1e}")
            }
        });
        let text = format!(
            "{}: s = {:.2}, W/G {} at G = 10 ({} {})",
            b.pair,
            b.slope.unwrap_or(f64::NAN),
            ratio,
            b.points.len(),
            if b.bisected { "bisected" } else { "pairs" }
        );
        right
            .draw(&Text::new(text, (44, y), left_style(15)))
            .map_err(|e| err(&e))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cell(weight: f64, torque: f64, sidewinding: Option<bool>) -> MapCell<'static> {
        MapCell {
            weight,
            torque,
            ok: true,
            regime: Some(Regime::U),
            regime_detail: "-",
            v_s_over_v_m: -0.02,
            writhe_max: 0.1,
            writhe_snapshot: 0.0,
            uncertain: false,
            sidewinding,
        }
    }

    /// Draws the map as SVG into a fresh file and returns its text.
    fn svg(name: &str, w: &[f64], g: &[f64], cells: &[MapCell]) -> String {
        let dir = std::env::temp_dir().join(format!("slither-map-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join(name);
        regime_map(&f, w, g, cells, &[]).unwrap();
        let s = std::fs::read_to_string(&f).unwrap();
        let _ = std::fs::remove_file(&f);
        s
    }

    /// The texts of an SVG, in drawing order, with their anchor (x, y).
    fn texts(svg: &str) -> Vec<(String, f64, f64)> {
        svg.split("<text ")
            .skip(1)
            .map(|t| {
                let tag = format!(" {}", t.split('>').next().unwrap_or(""));
                let attr = |k: &str| -> f64 {
                    let s = tag.split(&format!(" {k}=\"")).nth(1).unwrap_or("");
                    s.split('"')
                        .next()
                        .unwrap_or("")
                        .parse()
                        .unwrap_or(f64::NAN)
                };
                let body = t.split_once('>').map_or("", |p| p.1);
                let body = body.split("</text>").next().unwrap_or("").trim();
                (body.to_string(), attr("x"), attr("y"))
            })
            .collect()
    }

    fn grid_cells(w: &[f64], g: &[f64]) -> Vec<MapCell<'static>> {
        w.iter()
            .flat_map(|&wi| g.iter().map(move |&gj| cell(wi, gj, None)))
            .collect()
    }

    /// The 10/15 torque grid is labelled at 10 and 15; a grid with G = 0 at 0 and its
    /// positive values, and no tick is negative.
    #[test]
    fn the_map_labels_every_grid_value_of_a_small_grid() {
        let w = [100.0, 300.0, 1000.0];
        let has = |s: &str, t: &str| texts(s).iter().any(|x| x.0 == t);
        let s = svg(
            "g1015.svg",
            &w,
            &[10.0, 15.0],
            &grid_cells(&w, &[10.0, 15.0]),
        );
        for t in ["10", "15", "100", "300", "1000"] {
            assert!(has(&s, t), "no tick {t}");
        }
        let g = [0.0, 10.0, 30.0, 100.0];
        let s = svg("g0.svg", &w, &g, &grid_cells(&w, &g));
        for t in ["0", "10", "30", "100"] {
            assert!(has(&s, t), "no tick {t}");
        }
        let negative = texts(&s)
            .into_iter()
            .filter(|t| t.0.starts_with('-') && t.0[1..].parse::<f64>().is_ok())
            .collect::<Vec<_>>();
        assert!(negative.is_empty(), "{negative:?}");
        // The "0" tick sits below the "10" tick (screen y grows down).
        let y = |t: &str| texts(&s).into_iter().find(|x| x.0 == t).unwrap().2;
        assert!(y("0") > y("10"));
    }

    #[test]
    fn label_lines_stack_inside_their_box() {
        let sizes = [(80, 17), (120, 14)];
        let (dy, bx) = label_stack(&sizes, 3, 3);
        assert!(dy[0] < 0 && dy[1] > 0, "{dy:?}");
        for (d, s) in dy.iter().zip(sizes) {
            let h = s.1 as i32 / 2;
            assert!(bx[0].1 <= d - h && d + h <= bx[1].1, "{d} {bx:?}");
            assert!(bx[0].0 <= -(s.0 as i32) / 2 && s.0 as i32 / 2 <= bx[1].0);
        }
        let (dy, _) = label_stack(&[(50, 17)], 3, 3);
        assert!(dy[0].abs() <= 1);
    }

    /// An uncertain cell's hatching is covered by a white box under its label: after the last
    /// hatch line and before the label comes a white rectangle holding the label's anchor
    /// and text width.
    #[test]
    fn the_hatching_stays_out_of_the_label() {
        let mut c = cell(300.0, 10.0, None);
        c.uncertain = true;
        let s = svg("hatch.svg", &[300.0], &[10.0], &[c]);
        let label = s.find("U -0.020").expect("label drawn");
        let hatch = s[..label].rfind("stroke-width=\"2\"").expect("hatch drawn");
        let between = &s[hatch..label];
        let rect = between
            .split("<rect ")
            .nth(1)
            .expect("a box between hatch and label");
        let rect = format!(" {}", rect.split('>').next().unwrap());
        let attr = |k: &str| -> f64 {
            rect.split(&format!(" {k}=\""))
                .nth(1)
                .and_then(|v| v.split('"').next())
                .and_then(|v| v.parse().ok())
                .unwrap_or_else(|| panic!("no {k} in {rect}"))
        };
        assert!(rect.contains("fill=\"#FFFFFF\""), "{rect}");
        let (_, tx, ty) = texts(&s).into_iter().find(|t| t.0 == "U -0.020").unwrap();
        let (tw, _) = ("sans-serif", 17).into_font().box_size("U -0.020").unwrap();
        let (x, y, w, h) = (attr("x"), attr("y"), attr("width"), attr("height"));
        assert!(
            x <= tx - tw as f64 / 2.0 && tx + tw as f64 / 2.0 <= x + w,
            "{rect}"
        );
        assert!(y < ty && ty < y + h, "{rect} {ty}");
    }

    #[test]
    fn the_map_marks_sidewinding_cells_of_a_periodic_study_only() {
        let g = [10.0, 15.0, 22.5];
        let periodic = svg(
            "periodic.svg",
            &[300.0],
            &g,
            &[
                cell(300.0, 10.0, Some(false)),
                cell(300.0, 15.0, Some(true)),
                cell(300.0, 22.5, None),
            ],
        );
        // One cell says so, and the legend counts it among the measured ones.
        let alone = |svg: &str| svg.lines().filter(|l| l.trim() == "sidewinding").count();
        assert_eq!(alone(&periodic), 1, "{periodic}");
        assert!(periodic.contains("sidewinding: 1 of 2 measured cells"));
        let plain = svg("plain.svg", &[300.0], &g, &grid_cells(&[300.0], &g));
        assert!(!plain.contains("sidewinding"));
    }
}
