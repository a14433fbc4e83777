//! Paper-style PNG figures: kymographs, body snapshots, time series and x-y charts.
//!
//! Every function takes plain data and writes one PNG file (the path should end in `.png`; the
//! encoder is chosen from the extension). Text is drawn with the DejaVu Sans font embedded in the
//! binary (registered with plotters on first use), so figures render on a machine without any
//! system fonts, fontconfig or freetype.
//!
//! Conventions: lengths in metres (m), times in seconds (s); `t/T` is time over the gait period
//! (dimensionless). Non-finite values (NaN, ±inf) in the plotted data are skipped (lines break
//! there; kymograph cells are drawn light grey); non-finite coordinates that define an axis
//! (`s`, `t/T`, `t`) are an error.

pub mod colormap;

use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use std::sync::OnceLock;

/// Errors of the plotting functions.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// Input arrays whose lengths do not agree; the message names the arrays and their lengths.
    #[error("dimension mismatch: {0}")]
    Mismatch(String),
    /// Input that cannot be plotted (empty, non-finite or non-increasing axis coordinates).
    #[error("invalid plot input: {0}")]
    Invalid(String),
    /// The embedded font could not be registered.
    #[error("font registration failed: {0}")]
    Font(String),
    /// Drawing or encoding/writing the image failed (includes I/O errors from the PNG encoder).
    #[error("drawing failed: {0}")]
    Draw(String),
}

fn draw_err<E: std::fmt::Display>(e: E) -> PlotError {
    PlotError::Draw(e.to_string())
}

/// Figure size of the single-panel charts (pixels).
const SIZE: (u32, u32) = (1000, 700);
/// Figure size of the two-panel snapshot figure (pixels).
const SIZE_WIDE: (u32, u32) = (1400, 700);
const FONT: &str = "sans-serif";
const TITLE_PX: u32 = 30;
const DESC_PX: u32 = 22;
const TICK_PX: u32 = 18;
const LEGEND_PX: u32 = 17;

/// Registers the embedded DejaVu fonts with plotters under the names "sans-serif", "serif" and
/// "monospace" (idempotent; called by every plot function). Public so that callers drawing their
/// own plotters figures can rely on the same fonts.
pub fn register_fonts() -> Result<(), PlotError> {
    static DONE: OnceLock<Result<(), String>> = OnceLock::new();
    DONE.get_or_init(|| {
        let reg = |name: &str, style: FontStyle, bytes: &'static [u8]| {
            plotters::style::register_font(name, style, bytes)
                .map_err(|_| format!("invalid embedded font for {name} {}", style.as_str()))
        };
        for fam in ["sans-serif", "serif"] {
            reg(fam, FontStyle::Normal, dejavu::sans::regular())?;
            reg(fam, FontStyle::Bold, dejavu::sans::bold())?;
            reg(fam, FontStyle::Italic, dejavu::sans::oblique())?;
            reg(fam, FontStyle::Oblique, dejavu::sans::oblique())?;
        }
        reg("monospace", FontStyle::Normal, dejavu::sans_mono::regular())?;
        Ok(())
    })
    .clone()
    .map_err(PlotError::Font)
}

/// Formats `v` with about `sig` significant digits, without trailing zeros; scientific notation
/// outside 1e-3 <= |v| < 1e5.
fn fmt_num(v: f64, sig: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { format!("{v}") };
    }
    let mag = v.abs().log10().floor() as i32;
    if (-3..5).contains(&mag) {
        let dec = (sig as i32 - 1 - mag).max(0) as usize;
        let s = format!("{v:.dec$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        let p = sig.saturating_sub(1);
        let s = format!("{v:.p$e}");
        // 1.500e-4 -> 1.5e-4
        match s.split_once('e') {
            Some((m, e)) if m.contains('.') => {
                format!("{}e{}", m.trim_end_matches('0').trim_end_matches('.'), e)
            }
            _ => s,
        }
    }
}

/// Tick label on a linear axis of extent `span`: values within 1e-9 span of zero (round-off of
/// the tick generator) print as "0"; otherwise up to 4 significant digits.
fn tick_label(v: f64, span: f64) -> String {
    if span > 0.0 && v.abs() < 1e-9 * span {
        "0".into()
    } else {
        fmt_num(v, 4)
    }
}

/// Min and max of the finite values, or None.
fn finite_range(vals: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let mut r: Option<(f64, f64)> = None;
    for v in vals.filter(|v| v.is_finite()) {
        r = Some(match r {
            None => (v, v),
            Some((a, b)) => (a.min(v), b.max(v)),
        });
    }
    r
}

/// Pads a range by `frac` of its span on both sides; a degenerate range gets a small width.
fn pad(r: Option<(f64, f64)>, frac: f64) -> (f64, f64) {
    match r {
        None => (0.0, 1.0),
        Some((a, b)) if b > a => {
            let d = (b - a) * frac;
            (a - d, b + d)
        }
        Some((a, _)) => {
            let d = if a == 0.0 { 1.0 } else { 0.1 * a.abs() };
            (a - d, a + d)
        }
    }
}

/// Padded range on a log axis (positive values only), widened by `frac` decades... in log space.
fn pad_log(r: Option<(f64, f64)>, frac: f64) -> (f64, f64) {
    match r {
        None => (1.0, 10.0),
        Some((a, b)) => {
            let (la, lb) = (a.log10(), b.log10());
            let d = if lb > la { (lb - la) * frac } else { 0.5 };
            (10f64.powf(la - d), 10f64.powf(lb + d))
        }
    }
}

/// Cell edges around strictly increasing, finite centres (midpoints; the ends extend by half
/// the neighbouring spacing; a single centre gets a unit-width cell).
fn edges(name: &str, c: &[f64]) -> Result<Vec<f64>, PlotError> {
    if c.is_empty() {
        return Err(PlotError::Invalid(format!("`{name}` is empty")));
    }
    if let Some(i) = c.iter().position(|v| !v.is_finite()) {
        return Err(PlotError::Invalid(format!("`{name}[{i}]` is not finite")));
    }
    if let Some(i) = c.windows(2).position(|w| w[1] <= w[0]) {
        return Err(PlotError::Invalid(format!(
            "`{name}` must be strictly increasing, but {name}[{}] = {} >= {name}[{}] = {}",
            i,
            c[i],
            i + 1,
            c[i + 1]
        )));
    }
    let n = c.len();
    if n == 1 {
        let h = if c[0] == 0.0 { 0.5 } else { 0.5 * c[0].abs() };
        return Ok(vec![c[0] - h, c[0] + h]);
    }
    let mut e = Vec::with_capacity(n + 1);
    e.push(c[0] - 0.5 * (c[1] - c[0]));
    for w in c.windows(2) {
        e.push(0.5 * (w[0] + w[1]));
    }
    e.push(c[n - 1] + 0.5 * (c[n - 1] - c[n - 2]));
    Ok(e)
}

/// The legend corner with the fewest data points near it (each corner region covers 40 % of the
/// width and height of the plotting range).
fn best_corner(
    pts: impl Iterator<Item = (f64, f64)>,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    log_x: bool,
    log_y: bool,
) -> SeriesLabelPosition {
    let map = |v: f64, a: f64, b: f64, log: bool| {
        if log {
            (v.log10() - a.log10()) / (b.log10() - a.log10())
        } else {
            (v - a) / (b - a)
        }
    };
    // Order of preference on ties: upper right, upper left, lower right, lower left.
    let mut count = [0usize; 4];
    for (x, y) in pts {
        let u = map(x, x0, x1, log_x);
        let v = map(y, y0, y1, log_y);
        if !(u.is_finite() && v.is_finite()) {
            continue;
        }
        let (r, l, t, b) = (u > 0.6, u < 0.4, v > 0.6, v < 0.4);
        count[0] += (r && t) as usize;
        count[1] += (l && t) as usize;
        count[2] += (r && b) as usize;
        count[3] += (l && b) as usize;
    }
    let best = (0..4).min_by_key(|&i| (count[i], i)).unwrap_or(0);
    [
        SeriesLabelPosition::UpperRight,
        SeriesLabelPosition::UpperLeft,
        SeriesLabelPosition::LowerRight,
        SeriesLabelPosition::LowerLeft,
    ][best]
        .clone()
}

/// Splits a sequence of points into runs of finite points (a NaN breaks the line).
fn finite_runs(pts: impl Iterator<Item = (f64, f64)>) -> Vec<Vec<(f64, f64)>> {
    let mut runs = vec![];
    let mut cur = vec![];
    for (x, y) in pts {
        if x.is_finite() && y.is_finite() {
            cur.push((x, y));
        } else if !cur.is_empty() {
            runs.push(std::mem::take(&mut cur));
        }
    }
    if !cur.is_empty() {
        runs.push(cur);
    }
    runs
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

/// White canvas with the title (if non-empty) drawn at the top; returns the root (to present)
/// and the area below the title.
fn canvas<'a>(
    path: &'a Path,
    size: (u32, u32),
    title: &str,
) -> Result<(Area<'a>, Area<'a>), PlotError> {
    register_fonts()?;
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(draw_err)?;
    let body = if title.is_empty() {
        root.clone().margin(TITLE_PX / 2, 0, 0, 0)
    } else {
        root.titled(title, (FONT, TITLE_PX).into_font().style(FontStyle::Bold))
            .map_err(draw_err)?
    };
    Ok((root, body))
}

/// The series legend, in the house style, at `corner`.
fn legend<'a, 'b: 'a, X, Y>(
    chart: &mut ChartContext<'a, BitMapBackend<'b>, Cartesian2d<X, Y>>,
    corner: SeriesLabelPosition,
    margin: u32,
) -> Result<(), PlotError>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    chart
        .configure_series_labels()
        .position(corner)
        .margin(margin)
        .label_font((FONT, LEGEND_PX))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.5))
        .draw()
        .map_err(draw_err)
}

fn frame_plot<X, Y>(
    chart: &mut ChartContext<'_, BitMapBackend<'_>, Cartesian2d<X, Y>>,
) -> Result<(), PlotError>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    // Box around the plotting area (drawn in pixel coordinates of the plotting area).
    let area = chart.plotting_area().strip_coord_spec();
    let (w, h) = area.dim_in_pixel();
    area.draw(&Rectangle::new(
        [(0, 0), (w as i32 - 1, h as i32 - 1)],
        BLACK.stroke_width(1),
    ))
    .map_err(draw_err)
}

/// Kymograph: a heat map of `values[frame][node]` over arc length `s` (m, horizontal axis, head
/// `s[0]` at the left) and `t_over_t` = t/T (dimensionless, vertical axis, time increasing upward),
/// with a colour bar labelled `label` (include the unit, e.g. "curvature (1/m)") and title `title`
/// (may be empty). Colour map: blue-white-red symmetric about 0 when `diverging`, else
/// viridis-like from the minimum to the maximum value. Cells are centred on the given `s` and
/// `t/T` (both must be finite and strictly increasing); NaN values are drawn light grey.
/// Writes a 1000x700 px PNG.
///
/// Errors: [`PlotError::Mismatch`] if `values.len() != t_over_t.len()` or any
/// `values[j].len() != s.len()`; [`PlotError::Invalid`] for empty or non-increasing axes.
pub fn kymograph(
    path: &Path,
    title: &str,
    label: &str,
    s: &[f64],
    t_over_t: &[f64],
    values: &[Vec<f64>],
    diverging: bool,
) -> Result<(), PlotError> {
    if values.len() != t_over_t.len() {
        return Err(PlotError::Mismatch(format!(
            "kymograph: values has {} frames (rows) but t_over_t has {} entries",
            values.len(),
            t_over_t.len()
        )));
    }
    if let Some((j, row)) = values.iter().enumerate().find(|(_, r)| r.len() != s.len()) {
        return Err(PlotError::Mismatch(format!(
            "kymograph: values[{j}] has {} nodes but s has {} entries",
            row.len(),
            s.len()
        )));
    }
    let xe = edges("s", s)?;
    let ye = edges("t_over_t", t_over_t)?;
    let vr = finite_range(values.iter().flatten().copied());
    let (lo, hi) = if diverging {
        let m = vr.map(|(a, b)| a.abs().max(b.abs())).unwrap_or(0.0);
        let m = if m > 0.0 { m } else { 1.0 };
        (-m, m)
    } else {
        match vr {
            Some((a, b)) if b > a => (a, b),
            r => pad(r, 0.0),
        }
    };
    let cmap = |u: f64| {
        if diverging {
            colormap::diverging(u)
        } else {
            colormap::sequential(u)
        }
    };
    let color = |v: f64| {
        if v.is_finite() {
            cmap((v - lo) / (hi - lo))
        } else {
            RGBColor(200, 200, 200)
        }
    };

    let (root, body) = canvas(path, SIZE, title)?;
    let (w, _) = body.dim_in_pixel();
    let (main, bar) = body.split_horizontally(w - 190);
    let (ml, mt, mb, xl) = (20, 15, 20, 65);

    let (xspan, yspan) = (xe[xe.len() - 1] - xe[0], ye[ye.len() - 1] - ye[0]);
    let xfmt = |v: &f64| tick_label(*v, xspan);
    let yfmt = |v: &f64| tick_label(*v, yspan);
    let mut chart = ChartBuilder::on(&main)
        .margin_left(ml)
        .margin_top(mt)
        .margin_bottom(mb)
        .margin_right(10)
        .x_label_area_size(xl)
        .y_label_area_size(90)
        .build_cartesian_2d(xe[0]..xe[xe.len() - 1], ye[0]..ye[ye.len() - 1])
        .map_err(draw_err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("arc length s (m)")
        .y_desc("t/T")
        .x_label_formatter(&xfmt)
        .y_label_formatter(&yfmt)
        .axis_desc_style((FONT, DESC_PX))
        .label_style((FONT, TICK_PX))
        .x_labels(8)
        .y_labels(8)
        .draw()
        .map_err(draw_err)?;
    let mut cells = Vec::with_capacity(values.len() * s.len());
    for (j, row) in values.iter().enumerate() {
        for (i, &v) in row.iter().enumerate() {
            cells.push(Rectangle::new(
                [(xe[i], ye[j]), (xe[i + 1], ye[j + 1])],
                color(v).filled(),
            ));
        }
    }
    chart.draw_series(cells).map_err(draw_err)?;
    frame_plot(&mut chart)?;

    // Colour bar, vertically aligned with the plotting area.
    let nbar = 256;
    let mut cbar = ChartBuilder::on(&bar)
        .margin_top(mt)
        .margin_bottom(mb)
        .margin_left(15)
        .margin_right(10)
        .x_label_area_size(xl)
        .set_label_area_size(LabelAreaPosition::Right, 120)
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(draw_err)?;
    // The bar first, then the axis and tick labels, so no label is painted over.
    cbar.draw_series((0..nbar).map(|k| {
        let a = lo + (hi - lo) * k as f64 / nbar as f64;
        let b = lo + (hi - lo) * (k + 1) as f64 / nbar as f64;
        Rectangle::new(
            [(0.0, a), (1.0, b)],
            cmap((k as f64 + 0.5) / nbar as f64).filled(),
        )
    }))
    .map_err(draw_err)?;
    let fmt = |v: &f64| tick_label(*v, hi - lo);
    cbar.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .x_labels(0)
        .y_labels(9)
        .y_label_formatter(&fmt)
        .set_tick_mark_size(LabelAreaPosition::Right, 6)
        .y_label_offset(0)
        .y_desc(label)
        .axis_desc_style((FONT, DESC_PX))
        .label_style((FONT, TICK_PX))
        .draw()
        .map_err(draw_err)?;
    frame_plot(&mut cbar)?;
    root.present().map_err(draw_err)
}

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
        false,
        (false, false),
    )?;
    root.present().map_err(draw_err)
}

/// Scatter/line chart: each named series of (x, y) points is drawn as markers joined by a thin
/// line in the given order (sort the points if the line should be monotone in x), with a legend,
/// axis labels `x_label` and `y_label` (include units) and title `title` (may be empty).
/// `log_x` / `log_y` select base-10 logarithmic axes; points with a non-positive coordinate on a
/// log axis, and non-finite points, are skipped. Writes a 1000x700 px PNG.
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
    let xr = if log_x {
        pad_log(finite_range(pts().map(|p| p.0)), 0.05)
    } else {
        pad(finite_range(pts().map(|p| p.0)), 0.05)
    };
    let yr = if log_y {
        pad_log(finite_range(pts().map(|p| p.1)), 0.05)
    } else {
        pad(finite_range(pts().map(|p| p.1)), 0.05)
    };
    let (root, body) = canvas(path, SIZE, title)?;
    let lin = |r: (f64, f64)| -> RangedCoordf64 { (r.0..r.1).into() };
    let log = |r: (f64, f64)| -> LogCoord<f64> { (r.0..r.1).log_scale().into() };
    let logs = (log_x, log_y);
    match logs {
        (false, false) => line_chart(
            &body,
            lin(xr),
            lin(yr),
            xr,
            yr,
            x_label,
            y_label,
            &data,
            true,
            logs,
        )?,
        (true, false) => line_chart(
            &body,
            log(xr),
            lin(yr),
            xr,
            yr,
            x_label,
            y_label,
            &data,
            true,
            logs,
        )?,
        (false, true) => line_chart(
            &body,
            lin(xr),
            log(yr),
            xr,
            yr,
            x_label,
            y_label,
            &data,
            true,
            logs,
        )?,
        (true, true) => line_chart(
            &body,
            log(xr),
            log(yr),
            xr,
            yr,
            x_label,
            y_label,
            &data,
            true,
            logs,
        )?,
    }
    root.present().map_err(draw_err)
}

/// Scatter chart on linear axes: each named series of (x, y) points drawn as markers only (no
/// joining line), with a legend, axis labels `x_label` and `y_label` (include units) and title
/// `title` (may be empty). A series of a single point is drawn as a larger, outlined marker, to
/// mark one point (e.g. an optimum) on top of the others. Non-finite points are skipped.
/// Writes a 1000x700 px PNG.
///
/// Errors: [`PlotError::Invalid`] if no finite point remains.
pub fn scatter(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[(&str, Vec<(f64, f64)>)],
) -> Result<(), PlotError> {
    let pts = || {
        series
            .iter()
            .flat_map(|(_, p)| p.iter().copied())
            .filter(|p| p.0.is_finite() && p.1.is_finite())
    };
    if pts().next().is_none() {
        return Err(PlotError::Invalid("scatter: no finite point".into()));
    }
    let xr = pad(finite_range(pts().map(|p| p.0)), 0.08);
    let yr = pad(finite_range(pts().map(|p| p.1)), 0.08);
    let (root, body) = canvas(path, SIZE, title)?;
    let mut chart = ChartBuilder::on(&body)
        .margin_left(20)
        .margin_right(35)
        .margin_top(15)
        .margin_bottom(20)
        .x_label_area_size(65)
        .y_label_area_size(100)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
        .map_err(draw_err)?;
    let xfmt = |v: &f64| tick_label(*v, xr.1 - xr.0);
    let yfmt = |v: &f64| tick_label(*v, yr.1 - yr.0);
    chart
        .configure_mesh()
        .light_line_style(BLACK.mix(0.04))
        .bold_line_style(BLACK.mix(0.12))
        .x_desc(x_label)
        .y_desc(y_label)
        .axis_desc_style((FONT, DESC_PX))
        .label_style((FONT, TICK_PX))
        .x_labels(9)
        .y_labels(9)
        .x_label_formatter(&xfmt)
        .y_label_formatter(&yfmt)
        .draw()
        .map_err(draw_err)?;
    if yr.0 < 0.0 && yr.1 > 0.0 {
        chart
            .draw_series(LineSeries::new(
                vec![(xr.0, 0.0), (xr.1, 0.0)],
                BLACK.mix(0.5).stroke_width(1),
            ))
            .map_err(draw_err)?;
    }
    for (k, (name, p)) in series.iter().enumerate() {
        let c = colormap::palette(k);
        let finite: Vec<(f64, f64)> = p
            .iter()
            .copied()
            .filter(|q| q.0.is_finite() && q.1.is_finite())
            .collect();
        if finite.is_empty() {
            continue;
        }
        let r = if p.len() == 1 { 10 } else { 5 };
        let ann = chart
            .draw_series(finite.iter().map(|&q| {
                EmptyElement::at(q)
                    + Circle::new((0, 0), r, c.filled())
                    + Circle::new(
                        (0, 0),
                        r,
                        if r > 5 {
                            BLACK.stroke_width(2)
                        } else {
                            c.stroke_width(1)
                        },
                    )
            }))
            .map_err(draw_err)?;
        if !name.is_empty() {
            ann.label(name.to_string()).legend(move |(x, y)| {
                EmptyElement::at((x + 10, y))
                    + Circle::new((0, 0), r.min(7), c.filled())
                    + Circle::new(
                        (0, 0),
                        r.min(7),
                        if r > 5 {
                            BLACK.stroke_width(2)
                        } else {
                            c.stroke_width(1)
                        },
                    )
            });
        }
    }
    if series.iter().any(|(n, _)| !n.is_empty()) {
        let corner = best_corner(pts(), xr, yr, false, false);
        legend(&mut chart, corner, 12)?;
    }
    frame_plot(&mut chart)?;
    root.present().map_err(draw_err)
}

/// Shared body of [`series`] and [`xy`]: axes, grid, curves (optionally with markers), legend.
#[allow(clippy::too_many_arguments)]
fn line_chart<X, Y>(
    area: &Area<'_>,
    x: X,
    y: Y,
    xr: (f64, f64),
    yr: (f64, f64),
    x_label: &str,
    y_label: &str,
    data: &[(&str, Vec<(f64, f64)>)],
    markers: bool,
    logs: (bool, bool),
) -> Result<(), PlotError>
where
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
        let width = if markers { 2 } else { 3 };
        let mut labelled = false;
        for run in runs {
            let ann = chart
                .draw_series(LineSeries::new(run.clone(), c.stroke_width(width)))
                .map_err(draw_err)?;
            if !labelled {
                labelled = true;
                ann.label(name.to_string()).legend(move |(x, y)| {
                    let line = PathElement::new(vec![(x - 2, y), (x + 22, y)], c.stroke_width(3));
                    let dot = Circle::new((x + 10, y), if markers { 5 } else { 0 }, c.filled());
                    EmptyElement::at((0, 0)) + line + dot
                });
            }
            if markers {
                chart
                    .draw_series(run.iter().map(|&p| Circle::new(p, 5, c.filled())))
                    .map_err(draw_err)?;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn number_format() {
        assert_eq!(fmt_num(0.0, 3), "0");
        assert_eq!(fmt_num(1.5, 3), "1.5");
        assert_eq!(fmt_num(0.126, 2), "0.13");
        assert_eq!(fmt_num(2.0, 4), "2");
        assert_eq!(fmt_num(1.5e-4, 3), "1.5e-4");
        assert_eq!(fmt_num(-123456.0, 3), "-1.23e5");
    }

    #[test]
    fn cell_edges() {
        assert_eq!(
            edges("s", &[0.0, 1.0, 3.0]).unwrap(),
            vec![-0.5, 0.5, 2.0, 4.0]
        );
        assert!(edges("s", &[0.0, 0.0]).is_err());
        assert!(edges("s", &[]).is_err());
    }
}
