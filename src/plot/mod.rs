//! Paper-style PNG figures: kymographs, body snapshots, time series and x-y charts.
//!
//! Every function takes plain data and writes one image file. The study charts ([`xy`],
//! [`scatter`]) write SVG when the path ends in `.svg` (any case) and a bitmap otherwise (the
//! encoder chosen from the extension, e.g. `.png`); their bodies are written once, generic over
//! the plotters backend, and instantiated for both by `on_backend!`. Kymographs and snapshots
//! are PNG only. Text is drawn with the DejaVu Sans font embedded in the
//! binary (registered with plotters on first use), so figures render on a machine without any
//! system fonts, fontconfig or freetype.
//!
//! Conventions: lengths in metres (m), times in seconds (s); `t/T` is time over the gait period
//! (dimensionless). Non-finite values (NaN, ±inf) in the plotted data are skipped (lines break
//! there; kymograph cells are drawn light grey); non-finite coordinates that define an axis
//! (`s`, `t/T`, `t`) are an error.
//!
//! One file per kind of figure: [`kymograph()`] (`kymograph.rs`), [`snapshots()`]
//! (`snapshots.rs`), [`series()`] and [`xy()`] (line charts, `charts.rs`), [`scatter()`]
//! (`scatter.rs`), [`tracks()`] (ground tracks, `tracks.rs`, PNG or SVG), and the animated GIF
//! of a run, [`movie`] (`movie/`); axis ranges, tick labels, cell edges, legends and the canvas are shared in
//! `axes.rs`, colour maps in [`colormap`]; the phase diagram's map and charts in [`phase`]
//! (`phase.rs`), its gallery of thumbnails in [`gallery`] (`gallery.rs`).

mod axes;
mod charts;
pub mod colormap;
pub mod gallery;
pub mod growth;
mod kymograph;
pub mod movie;
pub mod phase;
mod scatter;
mod snapshots;
mod tracks;

pub use charts::{series, xy, xy_log_log, xy_marked, MarkedSeries, Marker};
pub use kymograph::{kymograph, kymograph_styled, quantile, KymographScale, KymographStyle};
pub use scatter::scatter;
pub use snapshots::snapshots;
pub use tracks::tracks;

use plotters::prelude::*;
use std::path::Path;
use std::sync::OnceLock;

/// Whether `path` names an SVG file (extension `svg`, any case): the study figures are then
/// drawn with plotters' SVG backend instead of the bitmap one.
pub fn is_svg(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"))
}

/// `on_backend!(path, size, |root| { ... })`: run the block with `root` the drawing area of an
/// SVG backend (path ending in `.svg`) or of a bitmap backend (otherwise). The block is
/// compiled once per backend, so code in it (and the generic helpers it calls) serves both.
#[macro_export]
#[doc(hidden)]
macro_rules! on_backend {
    ($path:expr, $size:expr, |$root:ident| $body:block) => {{
        let path: &::std::path::Path = $path;
        if $crate::plot::is_svg(path) {
            let $root = ::plotters::prelude::IntoDrawingArea::into_drawing_area(
                ::plotters::prelude::SVGBackend::new(path, $size),
            );
            $body
        } else {
            let $root = ::plotters::prelude::IntoDrawingArea::into_drawing_area(
                ::plotters::prelude::BitMapBackend::new(path, $size),
            );
            $body
        }
    }};
}

/// The `.svg` twin of a `.png` path (the same name with extension `svg`).
pub fn svg_twin(path: &Path) -> std::path::PathBuf {
    path.with_extension("svg")
}

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

pub(super) fn draw_err<E: std::fmt::Display>(e: E) -> PlotError {
    PlotError::Draw(e.to_string())
}

/// Figure size of the single-panel charts (pixels).
pub(super) const SIZE: (u32, u32) = (1000, 700);
/// Figure size of the two-panel snapshot figure (pixels).
pub(super) const SIZE_WIDE: (u32, u32) = (1400, 700);
pub(super) const FONT: &str = "sans-serif";
pub(super) const TITLE_PX: u32 = 30;
pub(super) const DESC_PX: u32 = 22;
pub(super) const TICK_PX: u32 = 18;
pub(super) const LEGEND_PX: u32 = 17;

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
