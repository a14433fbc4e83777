//! The growth line's figure (`growth.png` / `growth.svg`): the sizes of a growing snake placed
//! on the regime map over `(W, G)` and on the chart of `v_s/v_m` against `W/G`, over the
//! study's own cells.
use super::phase::regime_color;
use super::{PlotError, FONT, LEGEND_PX, TICK_PX};
use crate::observe::Regime;
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
    let err = |e: &dyn std::fmt::Display| PlotError::Draw(e.to_string());
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
    let shown = |m: &&Mark| rr.contains(&(m.weight / m.torque));
    let speeds: Vec<f64> = grid
        .iter()
        .filter(shown)
        .chain(line)
        .map(|m| m.v_s_over_v_m)
        .filter(|v| v.is_finite())
        .collect();
    let (vlo, vhi) = speeds
        .iter()
        .fold((0.0f64, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
    let vpad = 0.08 * (vhi - vlo).max(0.1);
    let vr = (vlo - vpad)..(vhi + vpad);
    let tick = |v: &f64| {
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
    };
    let cm = |a: f64| {
        format!("{:.3}", a * 100.0)
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
            + " cm"
    };
    crate::on_backend!(path, (1500, 720), |root| {
        root.fill(&WHITE).map_err(|e| err(&e))?;
        let root = root.titled(verdict, (FONT, 24)).map_err(|e| err(&e))?;
        let (charts, strip) = root.split_vertically(640);
        let (left, right) = charts.split_horizontally(750);
        // The point's style: filled in its regime's colour, hollow when not confident.
        let style = |m: &Mark| {
            let c = regime_color(m.regime);
            if m.uncertain {
                c.stroke_width(2)
            } else {
                c.filled()
            }
        };
        // Left: the (W, G) plane.
        let mut chart = ChartBuilder::on(&left)
            .caption("Sizes on the regime map", (FONT, 22))
            .margin(15)
            .x_label_area_size(55)
            .y_label_area_size(70)
            .build_cartesian_2d(wr.clone().log_scale(), gr.clone().log_scale())
            .map_err(|e| err(&e))?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("scaled weight W (log)")
            .y_desc("scaled torque G (log)")
            .x_labels(10)
            .y_labels(10)
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .label_style((FONT, TICK_PX))
            .draw()
            .map_err(|e| err(&e))?;
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
            .map_err(|e| err(&e))?;
        chart
            .draw_series(LineSeries::new(
                line.iter().map(|m| (m.weight, m.torque)),
                BLACK.stroke_width(2),
            ))
            .map_err(|e| err(&e))?;
        chart
            .draw_series(
                line.iter()
                    .map(|m| Circle::new((m.weight, m.torque), 8, style(m))),
            )
            .map_err(|e| err(&e))?;
        chart
            .draw_series(
                line.iter()
                    .map(|m| Circle::new((m.weight, m.torque), 8, BLACK.stroke_width(1))),
            )
            .map_err(|e| err(&e))?;
        chart
            .draw_series(line.iter().map(|m| {
                Text::new(
                    m.diameter.map_or(String::new(), cm),
                    (m.weight * 1.06, m.torque / 1.25),
                    (FONT, LEGEND_PX),
                )
            }))
            .map_err(|e| err(&e))?;
        // Right: speed against W/G.
        let mut chart = ChartBuilder::on(&right)
            .caption("Forward speed against W / G", (FONT, 22))
            .margin(15)
            .x_label_area_size(55)
            .y_label_area_size(70)
            .build_cartesian_2d(rr.clone(), vr)
            .map_err(|e| err(&e))?;
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
            .map_err(|e| err(&e))?;
        let at = |m: &Mark| (m.weight / m.torque, m.v_s_over_v_m);
        let finite = |m: &&Mark| m.v_s_over_v_m.is_finite();
        chart
            .draw_series(
                grid.iter()
                    .filter(finite)
                    .map(|m| Circle::new(at(m), 3, style(m))),
            )
            .map_err(|e| err(&e))?;
        chart
            .draw_series(LineSeries::new(
                line.iter().filter(finite).map(at),
                BLACK.stroke_width(2),
            ))
            .map_err(|e| err(&e))?;
        chart
            .draw_series(
                line.iter()
                    .filter(finite)
                    .map(|m| Circle::new(at(m), 8, style(m))),
            )
            .map_err(|e| err(&e))?;
        chart
            .draw_series(
                line.iter()
                    .filter(finite)
                    .map(|m| Circle::new(at(m), 8, BLACK.stroke_width(1))),
            )
            .map_err(|e| err(&e))?;
        chart
            .draw_series(line.iter().filter(finite).map(|m| {
                let (x, y) = at(m);
                Text::new(
                    m.diameter.map_or(String::new(), cm),
                    (
                        x + 0.01 * (rr.end - rr.start),
                        y + 0.02 * (vhi - vlo).max(0.1),
                    ),
                    (FONT, LEGEND_PX),
                )
            }))
            .map_err(|e| err(&e))?;
        // The regimes' colours.
        let legend: Vec<(String, RGBColor)> =
            [Regime::S, Regime::M, Regime::F, Regime::N, Regime::U]
                .into_iter()
                .map(|r| (r.to_string(), regime_color(Some(r))))
                .chain(std::iter::once(("failed".to_string(), regime_color(None))))
                .collect();
        for (k, (name, c)) in legend.iter().enumerate() {
            let x = 60 + 90 * k as i32;
            strip
                .draw(&Circle::new((x, 25), 7, c.filled()))
                .map_err(|e| err(&e))?;
            strip
                .draw(&Text::new(name.clone(), (x + 14, 16), (FONT, LEGEND_PX)))
                .map_err(|e| err(&e))?;
        }
        strip
            .draw(&Text::new(
                "circles: the sizes, labelled with their diameter; squares and dots: the grid's cells; hollow: the runs disagree on the label",
                (620, 16),
                (FONT, LEGEND_PX),
            ))
            .map_err(|e| err(&e))?;
        root.present().map_err(|e| err(&e))
    })
}
