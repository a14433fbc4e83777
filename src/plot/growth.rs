//! The growth line's figure (`growth.png` / `growth.svg`): the sizes of a growing snake placed
//! on the regime map over `(W, G)` and on the chart of `v_s/v_m` against `W/G`, over the
//! study's own cells.
//!
//! A size's diameter is written beside its circle, a fixed number of pixels away
//! ([`LABEL_OFFSET`]) whatever the axes' ranges. The speed chart spans the line's `W/G`; the
//! grid's cells outside it are left out, not drawn on the axis's edge ([`in_speed_range`]). The
//! map's ticks are the grid's own values ([`super::phase::grid_ticks`]): plotters labels a log
//! axis only at its powers of ten.
use super::phase::{grid_ticks, regime_color};
use super::{draw_err, PlotError, FONT, LEGEND_PX, TICK_PX};
use crate::observe::Regime;
use plotters::coord::combinators::BindKeyPoints;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// A point of the figure: a cell of the grid (`diameter` `None`) or a size of the line.
#[derive(Clone, Debug)]
pub struct Mark {
    /// Scaled weight `W`.
    pub weight: f64,
    /// Scaled torque `G`.
    pub torque: f64,
    /// Label (`None`: failed).
    pub regime: Option<Regime>,
    /// `v_s / v_m`.
    pub v_s_over_v_m: f64,
    /// The runs of a verified cell disagree (drawn hollow).
    pub uncertain: bool,
    /// The snake's diameter (m), for a size of the line.
    pub diameter: Option<f64>,
}

/// Where a size's diameter label starts (its top-left corner), in pixels from the size's
/// point: just right of the 8 px circle and a little below its centre, on the side the line
/// (which rises to the right) leaves free.
pub const LABEL_OFFSET: (i32, i32) = (11, 1);

/// Radius (px) of a size's circle.
const SIZE_RADIUS: u32 = 8;

/// Whether a grid cell belongs on the speed chart, whose x axis spans `range` of `W/G` (the
/// line's span with a margin): cells outside it are left out rather than drawn at the edge.
pub fn in_speed_range(m: &Mark, range: &std::ops::Range<f64>) -> bool {
    range.contains(&(m.weight / m.torque))
}

/// The distinct positive values of `v`, sorted, thinned to at most `max` (first and last kept):
/// the ticks of one axis of the map.
fn grid_values(v: impl Iterator<Item = f64>, max: usize) -> Vec<f64> {
    let mut v: Vec<f64> = v.filter(|x| x.is_finite() && *x > 0.0).collect();
    v.sort_by(f64::total_cmp);
    v.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * b.abs());
    grid_ticks(v.len(), max).into_iter().map(|i| v[i]).collect()
}

/// Log range with a margin around the finite positive values of `v`.
fn log_range(v: impl Iterator<Item = f64>) -> Result<std::ops::Range<f64>, PlotError> {
    let (lo, hi) = v
        .filter(|x| x.is_finite() && *x > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
    if !lo.is_finite() {
        return Err(PlotError::Invalid("no finite positive coordinate".into()));
    }
    let pad = if hi > lo { (hi / lo).powf(0.06) } else { 2.0 };
    Ok(lo / pad..hi * pad)
}

/// Draw the figure: left the `(W, G)` plane (log-log), right `v_s/v_m` against `W/G` (log
/// across); the grid's cells as small squares coloured by regime, the line's sizes as large
/// circles joined in order and labelled with their diameter (hollow when not confident), and
/// `verdict` as the title.
pub fn growth_chart(
    path: &Path,
    grid: &[Mark],
    line: &[Mark],
    verdict: &str,
) -> Result<(), PlotError> {
    super::register_fonts()?;
    let all = || grid.iter().chain(line);
    let wr = log_range(all().map(|m| m.weight))?;
    let gr = log_range(all().map(|m| m.torque))?;
    // The speed chart spans the line's W/G (a decade or so, so a linear axis: plotters' log axis
    // labels only its decades); grid cells outside it are left out there.
    let rr = {
        let r = log_range(line.iter().map(|m| m.weight / m.torque))?;
        let pad = 0.08 * (r.end - r.start).max(0.1 * r.end);
        (r.start - pad).max(0.0)..r.end + pad
    };
    let speeds: Vec<f64> = grid
        .iter()
        .filter(|m| in_speed_range(m, &rr))
        .chain(line)
        .map(|m| m.v_s_over_v_m)
        .filter(|v| v.is_finite())
        .collect();
    let (vlo, vhi) = speeds
        .iter()
        .fold((0.0f64, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
    let vpad = 0.08 * (vhi - vlo).max(0.1);
    let vr = (vlo - vpad)..(vhi + vpad);
    crate::on_backend!(path, (1500, 720), |root| {
        root.fill(&WHITE).map_err(draw_err)?;
        let root = root.titled(verdict, (FONT, 24)).map_err(draw_err)?;
        let (charts, strip) = root.split_vertically(640);
        let (left, right) = charts.split_horizontally(750);
        draw_map(&left, grid, line, wr, gr)?;
        draw_speeds(&right, grid, line, rr, vr)?;
        draw_legend(&strip)?;
        root.present().map_err(draw_err)
    })
}

/// A tick label: whole above 10, else two decimals, trailing zeros dropped.
fn tick(v: &f64) -> String {
    let s = if *v >= 10.0 {
        format!("{v:.0}")
    } else {
        format!("{v:.2}")
    };
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// A diameter (m) as its label in cm, trailing zeros dropped.
fn cm(a: f64) -> String {
    format!("{:.3}", a * 100.0)
        .trim_end_matches('0')
        .trim_end_matches('.')
        .to_string()
        + " cm"
}

/// A point's style: filled in its regime's colour, hollow when not confident.
fn style(m: &Mark) -> ShapeStyle {
    let c = regime_color(m.regime);
    if m.uncertain {
        c.stroke_width(2)
    } else {
        c.filled()
    }
}

/// The left panel: the (W, G) plane, ticked at the grid's values (the line's when there is no
/// grid); the grid's cells as squares, the line's sizes as labelled circles joined in order.
fn draw_map<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    grid: &[Mark],
    line: &[Mark],
    wr: std::ops::Range<f64>,
    gr: std::ops::Range<f64>,
) -> Result<(), PlotError> {
    let ticks = |f: fn(&Mark) -> f64| {
        let from = if grid.is_empty() { line } else { grid };
        grid_values(from.iter().map(f), 8)
    };
    let mut chart = ChartBuilder::on(area)
        .caption("Sizes on the regime map", (FONT, 22))
        .margin(15)
        .x_label_area_size(55)
        .y_label_area_size(70)
        .build_cartesian_2d(
            wr.log_scale().with_key_points(ticks(|m| m.weight)),
            gr.log_scale().with_key_points(ticks(|m| m.torque)),
        )
        .map_err(draw_err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("scaled weight W (log)")
        .y_desc("scaled torque G (log)")
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .label_style((FONT, TICK_PX))
        .draw()
        .map_err(draw_err)?;
    chart
        .draw_series(grid.iter().map(|m| {
            Rectangle::new(
                [
                    (m.weight / 1.04, m.torque / 1.04),
                    (m.weight * 1.04, m.torque * 1.04),
                ],
                style(m),
            )
        }))
        .map_err(draw_err)?;
    let at = |m: &Mark| (m.weight, m.torque);
    draw_sizes(&mut chart, line.iter(), at)
}

/// The right panel: `v_s/v_m` against `W/G` over `rr` and `vr`, the grid's cells in range as
/// dots, the line's sizes as labelled circles joined in order.
fn draw_speeds<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    grid: &[Mark],
    line: &[Mark],
    rr: std::ops::Range<f64>,
    vr: std::ops::Range<f64>,
) -> Result<(), PlotError> {
    let shown = |m: &&Mark| in_speed_range(m, &rr);
    let mut chart = ChartBuilder::on(area)
        .caption("Forward speed against W / G", (FONT, 22))
        .margin(15)
        .x_label_area_size(55)
        .y_label_area_size(70)
        .build_cartesian_2d(rr.clone(), vr)
        .map_err(draw_err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("W / G = rho g L^2 / (Gamma a)")
        .y_desc("v_s / v_m")
        .x_labels(10)
        .x_label_formatter(&tick)
        .y_label_formatter(&|v: &f64| format!("{v:.2}"))
        .label_style((FONT, TICK_PX))
        .draw()
        .map_err(draw_err)?;
    let at = |m: &Mark| (m.weight / m.torque, m.v_s_over_v_m);
    let finite = |m: &&Mark| m.v_s_over_v_m.is_finite();
    chart
        .draw_series(
            grid.iter()
                .filter(finite)
                .filter(shown)
                .map(|m| Circle::new(at(m), 3, style(m))),
        )
        .map_err(draw_err)?;
    draw_sizes(&mut chart, line.iter().filter(finite), at)
}

/// The line's sizes on a panel at `at(m)`: joined in order, circles in their style with a black
/// rim, each labelled with its diameter.
fn draw_sizes<'a, DB, X, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    sizes: impl Iterator<Item = &'a Mark> + Clone,
    at: impl Fn(&Mark) -> (f64, f64),
) -> Result<(), PlotError>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    chart
        .draw_series(LineSeries::new(
            sizes.clone().map(&at),
            BLACK.stroke_width(2),
        ))
        .map_err(draw_err)?;
    chart
        .draw_series(
            sizes
                .clone()
                .map(|m| Circle::new(at(m), SIZE_RADIUS, style(m))),
        )
        .map_err(draw_err)?;
    chart
        .draw_series(
            sizes
                .clone()
                .map(|m| Circle::new(at(m), SIZE_RADIUS, BLACK.stroke_width(1))),
        )
        .map_err(draw_err)?;
    chart
        .draw_series(sizes.map(|m| {
            EmptyElement::at(at(m))
                + Text::new(
                    m.diameter.map_or(String::new(), cm),
                    LABEL_OFFSET,
                    (FONT, LEGEND_PX),
                )
        }))
        .map_err(draw_err)?;
    Ok(())
}

/// The strip below the panels: the regimes' colours and what the marks mean.
fn draw_legend<DB: DrawingBackend>(strip: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
    let legend: Vec<(String, RGBColor)> = [Regime::S, Regime::M, Regime::F, Regime::N, Regime::U]
        .into_iter()
        .map(|r| (r.to_string(), regime_color(Some(r))))
        .chain(std::iter::once(("failed".to_string(), regime_color(None))))
        .collect();
    for (k, (name, c)) in legend.iter().enumerate() {
        let x = 60 + 90 * k as i32;
        strip
            .draw(&Circle::new((x, 25), 7, c.filled()))
            .map_err(draw_err)?;
        strip
            .draw(&Text::new(name.clone(), (x + 14, 16), (FONT, LEGEND_PX)))
            .map_err(draw_err)?;
    }
    strip
        .draw(&Text::new(
            "circles: the sizes, labelled with their diameter; squares and dots: the grid's cells; hollow: the runs disagree on the label",
            (620, 16),
            (FONT, LEGEND_PX),
        ))
        .map_err(draw_err)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mark(weight: f64, torque: f64, diameter: Option<f64>) -> Mark {
        Mark {
            weight,
            torque,
            regime: Some(Regime::M),
            v_s_over_v_m: 0.05 + 0.01 * (weight / torque).sin(),
            uncertain: false,
            diameter,
        }
    }

    /// A growth line like the bundled study's: 19 sizes from W = 150, G = 4.7 to W = 1500,
    /// G = 120 over a 4 x 4 grid, whose cells' W/G (1.25 to 375) mostly lie outside the line's.
    fn study() -> (Vec<Mark>, Vec<Mark>) {
        let grid = [150.0, 316.0, 711.0, 1500.0]
            .iter()
            .flat_map(|&w| [4.0, 12.6, 37.9, 120.0].map(|g| mark(w, g, None)))
            .collect();
        let line = (0..19)
            .map(|k| {
                let u = k as f64 / 18.0;
                let a = 0.01 * 10f64.powf(u);
                mark(150.0 * 10f64.powf(u), 4.72 * 10f64.powf(1.39 * u), Some(a))
            })
            .collect();
        (grid, line)
    }

    /// Attribute `k` of the SVG element whose text (after its tag name) starts `elem`.
    fn attr(elem: &str, k: &str) -> f64 {
        let elem = format!(" {}", elem.split('>').next().unwrap_or(""));
        elem.split(&format!(" {k}=\""))
            .nth(1)
            .and_then(|v| v.split('"').next())
            .and_then(|v| v.parse().ok())
            .unwrap_or(f64::NAN)
    }

    /// The chart as SVG text (drawn into its own file `name`: the tests run in parallel).
    fn draw_svg(name: &str, grid: &[Mark], line: &[Mark]) -> String {
        let dir = std::env::temp_dir().join(format!("slither-growth-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join(name);
        growth_chart(&f, grid, line, "verdict").unwrap();
        let s = std::fs::read_to_string(&f).unwrap();
        let _ = std::fs::remove_file(&f);
        s
    }

    /// Every diameter label starts within 16 px of its size's circle (the old labels, placed
    /// in data units, sat some 35 px away on the map).
    #[test]
    fn diameter_labels_sit_next_to_their_points() {
        let (grid, line) = study();
        let s = draw_svg("labels.svg", &grid, &line);
        let circles: Vec<(f64, f64)> = s
            .split("<circle ")
            .skip(1)
            .filter(|c| attr(c, "r") == SIZE_RADIUS as f64)
            .map(|c| (attr(c, "cx"), attr(c, "cy")))
            .collect();
        let labels: Vec<(f64, f64)> = s
            .split("<text ")
            .skip(1)
            .filter(|t| t.contains(" cm"))
            .map(|t| (attr(t, "x"), attr(t, "y")))
            .collect();
        // Two charts, each with a label per size.
        assert_eq!(labels.len(), 2 * line.len());
        for (x, y) in labels {
            let d = circles
                .iter()
                .map(|(cx, cy)| (x - cx).hypot(y - cy))
                .fold(f64::INFINITY, f64::min);
            assert!(d <= 16.0, "label at ({x}, {y}) is {d:.0} px from its point");
        }
        let (dx, dy) = LABEL_OFFSET;
        assert!(dx > SIZE_RADIUS as i32 && (dx as f64).hypot(dy as f64) <= 16.0);
    }

    /// The speed chart leaves out the grid's cells outside its W/G range: none is drawn, and
    /// none sits on the axis's edges.
    #[test]
    fn cells_outside_the_speed_range_are_clipped() {
        let (grid, line) = study();
        let s = draw_svg("clip.svg", &grid, &line);
        let rr = 20.0..40.0;
        assert!(in_speed_range(&mark(600.0, 20.0, None), &rr));
        assert!(!in_speed_range(&mark(150.0, 120.0, None), &rr));
        assert!(!in_speed_range(&mark(1500.0, 4.0, None), &rr));
        // The line's W/G spans 31.8 down to 12.5: only the grid cells with W/G between about
        // 11 and 34 belong on the chart (the 3 px dots).
        let inside = grid
            .iter()
            .filter(|m| (11.0..34.0).contains(&(m.weight / m.torque)))
            .count();
        let dots = s
            .split("<circle ")
            .skip(1)
            .filter(|c| attr(c, "r") == 3.0)
            .count();
        assert_eq!(dots, inside, "{} grid cells in all", grid.len());
    }

    #[test]
    fn map_ticks_are_the_grid_values() {
        let v = grid_values([4.0, 12.6, 4.0, 37.9, 120.0, 0.0].into_iter(), 8);
        assert_eq!(v, vec![4.0, 12.6, 37.9, 120.0]);
        let (grid, line) = study();
        let s = draw_svg("ticks.svg", &grid, &line);
        for t in ["150", "1500", "4", "120"] {
            assert!(s.lines().any(|l| l.trim() == t), "no tick {t}");
        }
    }
}
