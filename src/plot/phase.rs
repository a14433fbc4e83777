//! The figures of a regime phase diagram ([`crate::design::phase`]): the regime map over
//! scaled weight and torque with its fitted boundary lines, the speed chart, and the paper's
//! Fig. 3 (writhe against `W/G`, speed against writhe). The diagram's cells and lines come in
//! as [`MapCell`] and [`MapLine`], the values a figure shows, so this layer needs nothing of
//! the study that computed them.
use super::PlotError;
use crate::observe::Regime;
use plotters::prelude::*;
use std::path::Path;

/// A cell of the diagram, as the figures show it.
#[derive(Clone, Debug)]
pub struct MapCell<'a> {
    /// Scaled weight `W`.
    pub weight: f64,
    /// Scaled torque `G`.
    pub torque: f64,
    /// The cell's simulation finished (else drawn as failed).
    pub ok: bool,
    /// Regime (`None` when failed).
    pub regime: Option<Regime>,
    /// For `M`: the S criteria it missed, `;`-separated; "-" otherwise.
    pub regime_detail: &'a str,
    /// `v_s / v_m`.
    pub v_s_over_v_m: f64,
    /// Largest |writhe| (turns).
    pub writhe_max: f64,
    /// Writhe at the snapshot instant (turns).
    pub writhe_snapshot: f64,
    /// The cell's verification runs disagree on its label (drawn hatched and outlined).
    pub uncertain: bool,
    /// Whether the cell sidewinds (every sidewinding criterion holds in every cycle), for a
    /// gait with a launch period; `None` otherwise (other gaits, failed runs, `G = 0`). A
    /// sidewinding cell is written "sidewinding" under its label (its label starred on a wide
    /// grid).
    pub sidewinding: Option<bool>,
}

/// A fitted boundary line, as the regime map draws it.
#[derive(Clone, Debug)]
pub struct MapLine<'a> {
    /// The two regimes, e.g. "F/N".
    pub pair: &'a str,
    /// Slope of `log10 G = slope log10 W + intercept` (`None`: not fitted, not drawn).
    pub slope: Option<f64>,
    /// Intercept of `log10 G` at `log10 W = 0`.
    pub intercept: Option<f64>,
    /// `W/G` on the line at `G = 10`.
    pub ratio_at_g10: Option<f64>,
    /// At least one point was placed by bisection (the points are then drawn as dots).
    pub bisected: bool,
    /// The fitted points `(W, G)`.
    pub points: Vec<(f64, f64)>,
}

/// Colour of a regime in the map (dark grey for a failed cell).
pub fn regime_color(r: Option<Regime>) -> RGBColor {
    match r {
        Some(Regime::S) => RGBColor(90, 180, 100),
        Some(Regime::M) => RGBColor(100, 150, 230),
        Some(Regime::F) => RGBColor(240, 170, 80),
        Some(Regime::N) => RGBColor(190, 190, 190),
        Some(Regime::U) => RGBColor(220, 80, 80),
        None => RGBColor(60, 60, 60),
    }
}

/// How many cells have each regime (in [`Regime::ALL`] order), and how many failed.
pub fn regime_counts(cells: &[MapCell]) -> ([(Regime, usize); 5], usize) {
    let count = |r: Regime| cells.iter().filter(|c| c.regime == Some(r)).count();
    (
        Regime::ALL.map(|r| (r, count(r))),
        cells.iter().filter(|c| c.regime.is_none()).count(),
    )
}

/// Cell edges on a log axis: geometric midpoints, the ends mirrored.
fn log_edges(c: &[f64]) -> Vec<f64> {
    let n = c.len();
    if n == 1 {
        return vec![c[0] / 2.0_f64.sqrt(), c[0] * 2.0_f64.sqrt()];
    }
    let mut e = vec![c[0] * (c[0] / c[1]).sqrt()];
    e.extend(c.windows(2).map(|w| (w[0] * w[1]).sqrt()));
    e.push(c[n - 1] * (c[n - 1] / c[n - 2]).sqrt());
    e
}

/// Cell edges on a linear axis: midpoints, the ends mirrored.
fn lin_edges(c: &[f64]) -> Vec<f64> {
    let n = c.len();
    if n == 1 {
        return vec![
            c[0] - 0.5 * c[0].abs().max(1.0),
            c[0] + 0.5 * c[0].abs().max(1.0),
        ];
    }
    let mut e = vec![c[0] - 0.5 * (c[1] - c[0])];
    e.extend(c.windows(2).map(|w| 0.5 * (w[0] + w[1])));
    e.push(c[n - 1] + 0.5 * (c[n - 1] - c[n - 2]));
    e
}

/// Grids with more weight columns than this label each cell with its regime letter only (the
/// `v_s/v_m` value and the M detail no longer fit in a cell of the 1000 px wide map).
pub const FULL_LABEL_MAX_COLUMNS: usize = 8;

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

/// The part of the line `log10 G = slope log10 W + intercept` inside the box `[lw0, lw1] x
/// [lg0, lg1]` (log10 coordinates), as 64 points `(W, G)`; `None` if it misses the box.
pub fn boundary_segment(
    slope: f64,
    intercept: f64,
    (lw0, lw1): (f64, f64),
    (lg0, lg1): (f64, f64),
) -> Option<Vec<(f64, f64)>> {
    let (mut a, mut b) = (lw0, lw1);
    if slope.abs() > 1e-12 {
        let (x0, x1) = ((lg0 - intercept) / slope, (lg1 - intercept) / slope);
        a = a.max(x0.min(x1));
        b = b.min(x0.max(x1));
    } else if !(lg0..=lg1).contains(&intercept) {
        return None;
    }
    (a < b && a.is_finite() && b.is_finite()).then(|| {
        (0..64)
            .map(|k| {
                let x = a + (b - a) * k as f64 / 63.0;
                (10f64.powf(x), 10f64.powf(slope * x + intercept))
            })
            .collect()
    })
}

/// The part of the box `lw x lg` (log10 W, log10 G) that the fitted `points` span: a
/// boundary line is drawn only where cells support it. An axis the points do not spread
/// along (one weight, or one torque) keeps the box's range.
pub fn supported_box(
    points: &[(f64, f64)],
    lw: (f64, f64),
    lg: (f64, f64),
) -> ((f64, f64), (f64, f64)) {
    let span = |v: Vec<f64>, (a, b): (f64, f64)| {
        let v: Vec<f64> = v.into_iter().filter(|x| x.is_finite()).collect();
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if hi > lo {
            (a.max(lo), b.min(hi))
        } else {
            (a, b)
        }
    };
    let logs = |f: fn(&(f64, f64)) -> f64| -> Vec<f64> {
        points
            .iter()
            .map(f)
            .filter(|x| *x > 0.0)
            .map(f64::log10)
            .collect()
    };
    (span(logs(|p| p.0), lw), span(logs(|p| p.1), lg))
}

/// The regime map (`phase.png` / `phase.svg`, by the extension of `path`): one coloured
/// rectangle per cell on log-log axes (log W across, log G up; a linear G axis when the grid
/// has `G = 0`), each labelled with the regime and `v_s / v_m` (and, for `M`, the S criteria it
/// missed; only the regime letter on grids wider than [`FULL_LABEL_MAX_COLUMNS`]), the fitted
/// regime boundaries (`bounds`, in `boundaries.json` order) drawn as lines, and on the right a legend of the
/// regimes with their cell counts and of the boundary lines with slope and `W/G` at `G = 10`.
/// The cells of a gait with a launch period that sidewind ([`MapCell::sidewinding`]) say so
/// under their label, and the legend counts them.
pub fn regime_map(
    path: &Path,
    weight: &[f64],
    torque: &[f64],
    cells: &[MapCell],
    bounds: &[MapLine],
) -> Result<(), PlotError> {
    super::register_fonts()?;
    let err = |e: &dyn std::fmt::Display| PlotError::Draw(e.to_string());
    let log_g = torque.iter().all(|&g| g > 0.0);
    let xe = log_edges(weight);
    let ye = if log_g {
        log_edges(torque)
    } else {
        lin_edges(torque)
    };
    crate::on_backend!(path, (1400, 800), |root| {
        root.fill(&WHITE).map_err(|e| err(&e))?;
        let (left, right) = root.split_horizontally(1000);
        let (xr, yr) = (xe[0]..xe[xe.len() - 1], ye[0]..ye[ye.len() - 1]);
        if log_g {
            let yr = yr.log_scale();
            map_body(&left, xr, yr, &xe, &ye, torque, cells, bounds, true)?;
        } else {
            map_body(&left, xr, yr, &xe, &ye, torque, cells, bounds, false)?;
        }
        map_legend(&right, cells, bounds)?;
        root.present().map_err(|e| err(&e))
    })
}

/// Cells, labels and boundary lines of [`regime_map`] on any backend and G axis.
#[allow(clippy::too_many_arguments)]
fn map_body<DB, Y>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    xr: std::ops::Range<f64>,
    yr: Y,
    xe: &[f64],
    ye: &[f64],
    torque: &[f64],
    cells: &[MapCell],
    bounds: &[MapLine],
    log_g: bool,
) -> Result<(), PlotError>
where
    DB: DrawingBackend,
    Y: plotters::coord::ranged1d::AsRangedCoord<Value = f64>,
    Y::CoordDescType: plotters::coord::ranged1d::ValueFormatter<f64>,
{
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
        .build_cartesian_2d(xr.log_scale(), yr)
        .map_err(|e| err(&e))?;
    let tick = |v: &f64| {
        if *v >= 1.0 && *v < 1e5 && v.fract() == 0.0 {
            format!("{v}")
        } else {
            format!("{v:.3}")
                .trim_end_matches('0')
                .trim_end_matches('.')
                .to_string()
        }
    };
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("scaled weight W = rho g a^2 L^3 / B (log)")
        .y_desc(if log_g {
            "scaled torque G = Gamma a^3 L / B (log)"
        } else {
            "scaled torque G = Gamma a^3 L / B"
        })
        .x_labels(12)
        .y_labels(12)
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
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
    let nt = torque.len();
    let full = xe.len() - 1 <= FULL_LABEL_MAX_COLUMNS;
    let mid = |a: f64, b: f64| if log_g { (a * b).sqrt() } else { 0.5 * (a + b) };
    for (k, c) in cells.iter().enumerate() {
        let (i, j) = (k / nt, k % nt);
        let rect = [(xe[i], ye[j]), (xe[i + 1], ye[j + 1])];
        chart
            .draw_series([
                Rectangle::new(rect, regime_color(c.regime).filled()),
                Rectangle::new(rect, WHITE.stroke_width(if full { 2 } else { 1 })),
            ])
            .map_err(|e| err(&e))?;
        if c.uncertain {
            // Hatched with three diagonals and outlined in black, inset from the white grid.
            let at = |fx: f64, fy: f64| {
                let x = xe[i] * (xe[i + 1] / xe[i]).powf(fx);
                let y = if log_g {
                    ye[j] * (ye[j + 1] / ye[j]).powf(fy)
                } else {
                    ye[j] + (ye[j + 1] - ye[j]) * fy
                };
                (x, y)
            };
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
        let ok = c.ok;
        let sidewinds = c.sidewinding == Some(true);
        let label = match c.regime {
            Some(r) if ok && full => format!("{r} {:.3}", c.v_s_over_v_m),
            Some(r) if ok && sidewinds => format!("{r}*"),
            Some(r) if ok => r.to_string(),
            _ if full => "failed".into(),
            _ => "x".into(),
        };
        let (x, y) = ((xe[i] * xe[i + 1]).sqrt(), mid(ye[j], ye[j + 1]));
        let missed = (full && c.regime == Some(Regime::M))
            .then(|| c.regime_detail.replace('_', " ").replace(';', ", "));
        let detail = match (missed, full && sidewinds) {
            (Some(m), true) => Some(format!("sidewinding; {m}")),
            (None, true) => Some("sidewinding".into()),
            (m, false) => m,
        };
        // Two lines in an M cell: the label a sixth of the cell above the centre, the detail
        // a sixth below (in the axis's own scale).
        let (above, below) = if log_g {
            let f = (ye[j + 1] / ye[j]).powf(0.15);
            (y * f, y / f)
        } else {
            let d = 0.15 * (ye[j + 1] - ye[j]);
            (y + d, y - d)
        };
        let px = if full { 17 } else { 13 };
        let y_label = if detail.is_some() { above } else { y };
        chart
            .draw_series(std::iter::once(Text::new(label, (x, y_label), centred(px))))
            .map_err(|e| err(&e))?;
        if let Some(d) = detail {
            chart
                .draw_series(std::iter::once(Text::new(d, (x, below), centred(14))))
                .map_err(|e| err(&e))?;
        }
    }
    let (lw, lg) = (
        (xe[0].log10(), xe[xe.len() - 1].log10()),
        if log_g {
            (ye[0].log10(), ye[ye.len() - 1].log10())
        } else {
            (
                ye[0].max(1e-3 * ye[ye.len() - 1]).log10(),
                ye[ye.len() - 1].log10(),
            )
        },
    );
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

/// Most torques drawn as separate series in the speed and writhe charts: a finer grid shows
/// this many, evenly spread over the grid's indices (first and last included), so the legend
/// stays readable; the regime map and `phase.csv` keep every cell.
pub const MAX_TORQUE_SERIES: usize = 6;

/// The torques drawn as series: all when at most [`MAX_TORQUE_SERIES`], else that many spread
/// evenly over the indices.
pub fn shown_torques(torque: &[f64]) -> Vec<f64> {
    let n = torque.len();
    if n <= MAX_TORQUE_SERIES {
        return torque.to_vec();
    }
    let m = MAX_TORQUE_SERIES;
    (0..m)
        .map(|i| torque[(i * (n - 1) + (m - 1) / 2) / (m - 1)])
        .collect()
}

/// A grid value for a legend: 3 significant digits (`G = 2.64`, `G = 100`).
fn short(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let dec = (2 - v.abs().log10().floor() as i32).clamp(0, 6) as usize;
    let s = format!("{v:.dec$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// `v_s / v_m` against `W / G` (the paper's speed chart), one series per torque (at most
/// [`MAX_TORQUE_SERIES`], see [`shown_torques`]).
pub fn speed_chart(path: &Path, torque: &[f64], cells: &[MapCell]) -> Result<(), PlotError> {
    let torque = shown_torques(torque);
    let names: Vec<String> = torque
        .iter()
        .map(|&g| format!("G = {}", short(g)))
        .collect();
    let series: Vec<(&str, Vec<(f64, f64)>)> = torque
        .iter()
        .zip(&names)
        .map(|(&g, name)| {
            let mut pts: Vec<(f64, f64)> = cells
                .iter()
                .filter(|c| c.torque == g && c.ok)
                .map(|c| (c.weight / c.torque, c.v_s_over_v_m))
                .collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            (name.as_str(), pts)
        })
        .collect();
    super::xy(
        path,
        "Forward speed against weight over torque",
        "W / G = rho g L^2 / (Gamma a)",
        "v_s / v_m",
        &series,
        true,
        false,
    )
}

/// Fig. 3a of the paper (`writhe_vs_ratio.png`): the largest writhe and the writhe at the
/// snapshot instant against `W/G`, one pair of series per shown torque ([`shown_torques`],
/// `G > 0`), from the finished cells with `G > 0`. [`PlotError::Invalid`] when no point is
/// finite.
pub fn writhe_vs_ratio(path: &Path, torque: &[f64], cells: &[MapCell]) -> Result<(), PlotError> {
    let ok: Vec<&MapCell> = cells.iter().filter(|c| c.ok && c.torque > 0.0).collect();
    let mut names = Vec::new();
    let mut pts = Vec::new();
    for g in shown_torques(torque).into_iter().filter(|&g| g > 0.0) {
        let mut max: Vec<(f64, f64)> = Vec::new();
        let mut snap: Vec<(f64, f64)> = Vec::new();
        for c in ok.iter().filter(|c| c.torque == g) {
            max.push((c.weight / c.torque, c.writhe_max));
            snap.push((c.weight / c.torque, c.writhe_snapshot));
        }
        max.sort_by(|a, b| a.0.total_cmp(&b.0));
        snap.sort_by(|a, b| a.0.total_cmp(&b.0));
        names.push(format!("G = {}: |Wr| max", short(g)));
        pts.push(max);
        names.push(format!("G = {}: Wr at snapshot (signed)", short(g)));
        pts.push(snap);
    }
    let series: Vec<(&str, Vec<(f64, f64)>)> = names.iter().map(String::as_str).zip(pts).collect();
    super::xy(
        path,
        "Writhe against W/G (Fig. 3a)",
        "W / G",
        "writhe (turns): largest |Wr|, signed Wr at the snapshot",
        &series,
        true,
        false,
    )
}

/// Fig. 3b of the paper (`speed_vs_writhe.png`): `v_s/v_m` against the largest writhe, one
/// series per regime, from the finished cells with `G > 0`. [`PlotError::Invalid`] when no
/// point is finite.
pub fn speed_vs_writhe(path: &Path, cells: &[MapCell]) -> Result<(), PlotError> {
    let ok: Vec<&MapCell> = cells.iter().filter(|c| c.ok && c.torque > 0.0).collect();
    let regimes = [Regime::S, Regime::M, Regime::F, Regime::N, Regime::U];
    let by_regime: Vec<(String, Vec<(f64, f64)>)> = regimes
        .iter()
        .map(|&r| {
            (
                r.as_str().to_string(),
                ok.iter()
                    .filter(|c| c.regime == Some(r))
                    .map(|c| (c.writhe_max, c.v_s_over_v_m))
                    .collect(),
            )
        })
        .filter(|(_, p): &(String, Vec<(f64, f64)>)| !p.is_empty())
        .collect();
    let series: Vec<(&str, Vec<(f64, f64)>)> = by_regime
        .iter()
        .map(|(n, p)| (n.as_str(), p.clone()))
        .collect();
    // The regime map's colours (one palette for both figures).
    let colors: Vec<RGBColor> = by_regime
        .iter()
        .map(|(n, _)| regime_color(regimes.iter().copied().find(|r| r.as_str() == n)))
        .collect();
    super::scatter::scatter_colored(
        path,
        "Speed against writhe, by regime (Fig. 3b)",
        "largest |writhe|, |Wr| max (turns)",
        "v_s / v_m",
        &series,
        Some(&colors),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fine_grid_shows_six_torques_spread_over_it() {
        let g: Vec<f64> = (0..20).map(|i| i as f64).collect();
        let shown = shown_torques(&g);
        assert_eq!(shown.len(), MAX_TORQUE_SERIES);
        assert_eq!(shown[0], 0.0);
        assert_eq!(shown[5], 19.0);
        assert!(shown.windows(2).all(|w| w[1] - w[0] >= 3.0), "{shown:?}");
        assert_eq!(shown_torques(&g[..4]), g[..4].to_vec());
        assert_eq!(short(2.636650898730358), "2.64");
        assert_eq!(short(100.0), "100");
        assert_eq!(short(14.38449888287663), "14.4");
    }

    #[test]
    fn boundary_lines_span_only_their_supporting_points() {
        let (lw, lg) = ((0.0, 4.0), (0.0, 2.0));
        // Points from W = 100 to 1000 and G = 10 to 30: the box shrinks to them.
        let pts = [(100.0, 10.0), (300.0, 20.0), (1000.0, 30.0)];
        let (w, g) = supported_box(&pts, lw, lg);
        assert!(
            (w.0 - 2.0).abs() < 1e-12 && (w.1 - 3.0).abs() < 1e-12,
            "{w:?}"
        );
        assert!(
            (g.0 - 1.0).abs() < 1e-12 && (g.1 - 30f64.log10()).abs() < 1e-12,
            "{g:?}"
        );
        // A line through them is cut to W in [100, 1000].
        let seg = boundary_segment(0.5, 0.0, w, g).unwrap();
        assert!(
            seg.iter().all(|p| (99.999..=1000.001).contains(&p.0)),
            "{seg:?}"
        );
        // One weight only: that axis keeps the box's range.
        let (w, _) = supported_box(&[(100.0, 10.0), (100.0, 30.0)], lw, lg);
        assert_eq!(w, lw);
    }

    #[test]
    fn boundary_segments_stay_in_the_box_and_on_the_line() {
        let (lw, lg) = ((1.0, 4.0), (0.0, 2.0));
        // Slope 1 through W/G = 30: enters at G = 1 (W = 30), leaves at G = 100 (W = 3000).
        let c = -(30f64.log10());
        let seg = boundary_segment(1.0, c, lw, lg).unwrap();
        for &(w, g) in &seg {
            assert!((w.log10() + c - g.log10()).abs() < 1e-12);
            assert!(w.log10() >= lw.0 - 1e-12 && w.log10() <= lw.1 + 1e-12);
            assert!(g.log10() >= lg.0 - 1e-12 && g.log10() <= lg.1 + 1e-12);
        }
        assert!((seg[0].0 - 30.0).abs() < 1e-9 && (seg[63].0 - 3000.0).abs() < 1e-6);
        // A line above the box, and a flat line outside it, are not drawn.
        assert!(boundary_segment(1.0, 5.0, lw, lg).is_none());
        assert!(boundary_segment(0.0, 3.0, lw, lg).is_none());
        // A flat line inside spans the whole weight axis.
        let flat = boundary_segment(0.0, 1.0, lw, lg).unwrap();
        assert!((flat[0].0 - 10.0).abs() < 1e-9 && (flat[63].0 - 1e4).abs() < 1e-6);
    }

    #[test]
    fn edges_enclose_the_centres() {
        let c = [100.0, 300.0, 1000.0];
        let e = log_edges(&c);
        assert_eq!(e.len(), 4);
        for i in 0..3 {
            assert!(e[i] < c[i] && c[i] < e[i + 1]);
        }
        let e = lin_edges(&[5.0, 10.0, 20.0]);
        assert_eq!(e, vec![2.5, 7.5, 15.0, 25.0]);
    }

    #[test]
    fn the_map_marks_sidewinding_cells_of_a_periodic_study_only() {
        let cell = |torque: f64, sidewinding: Option<bool>| MapCell {
            weight: 300.0,
            torque,
            ok: true,
            regime: Some(Regime::U),
            regime_detail: "-",
            v_s_over_v_m: -0.02,
            writhe_max: 0.1,
            writhe_snapshot: 0.0,
            uncertain: false,
            sidewinding,
        };
        let dir = std::env::temp_dir().join(format!("slither-map-sw-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let draw = |name: &str, cells: &[MapCell]| {
            let f = dir.join(name);
            regime_map(&f, &[300.0], &[10.0, 15.0, 22.5], cells, &[]).unwrap();
            std::fs::read_to_string(&f).unwrap()
        };
        let periodic = draw(
            "periodic.svg",
            &[
                cell(10.0, Some(false)),
                cell(15.0, Some(true)),
                cell(22.5, None),
            ],
        );
        // One cell says so, and the legend counts it among the measured ones.
        let alone = |svg: &str| svg.lines().filter(|l| l.trim() == "sidewinding").count();
        assert_eq!(alone(&periodic), 1, "{periodic}");
        assert!(periodic.contains("sidewinding: 1 of 2 measured cells"));
        let plain = draw(
            "plain.svg",
            &[cell(10.0, None), cell(15.0, None), cell(22.5, None)],
        );
        assert!(!plain.contains("sidewinding"));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
