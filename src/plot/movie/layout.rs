//! The movie's text layout, from the picture's size alone, so that the text fits the picture
//! and the scene never runs under it: fonts scaled to the width (17 and 14 px on a wide
//! picture, down to 8 px), the clock on two lines when one does not fit at 13 px, and the
//! bottom band's legend and scale wrapped onto more rows when a narrow picture cannot hold
//! them on one. The bands are sized for the widest legend of any colouring and view, so the
//! scene's rows ([`super::scene_rows`]) depend on the size alone.

use crate::plot::FONT;
use plotters::prelude::IntoFont;

/// Sizes (px) of the movie's text and bands.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Font size of the clock (px).
    pub big: u32,
    /// Font size of the title, legend and scale (px).
    pub small: u32,
    /// The clock on two lines (time and `t/T`; speed) instead of one.
    pub split_clock: bool,
    /// Height of the top band (px).
    pub top: u32,
    /// Height of one row of the bottom band (px).
    pub row: u32,
    /// Height of the bottom band (px).
    pub bottom: u32,
}

/// Margin (px) at the picture's left and right edges.
pub const EDGE: i32 = 8;
/// Gap (px) between two items of the legend.
pub const GAP: i32 = 14;
/// Width (px) of a colour swatch and the space after it.
pub const SWATCH: i32 = 18;

/// The widest clock lines drawn (one line; the two halves of a split one).
const CLOCK: &str = "t = 10.00 s   t/T = 10.00   v_s = -0.123 m/s (-0.45 v_m)";
const CLOCK_HALVES: [&str; 2] = ["t = 10.00 s   t/T = 10.00", "v_s = -0.123 m/s (-0.45 v_m)"];

/// Width (px) of `s` in the movie's font at `px`.
pub fn text_width(s: &str, px: u32) -> i32 {
    // The embedded font (registered once; without it the width is a guess of 8 px a letter).
    let _ = crate::plot::register_fonts();
    (FONT, px)
        .into_font()
        .box_size(s)
        .map_or(8 * s.len() as i32, |(w, _)| w as i32)
}

/// Width (px) of the colour bar of the elevation and lambda legends.
pub fn bar_width(w: u32) -> i32 {
    if w >= 640 {
        120
    } else {
        80
    }
}

/// Places items of widths `items` from the left edge of a picture `w` px wide, `GAP` apart,
/// wrapping onto a new row when one does not fit, then the `scale` item right-aligned on the
/// last row, or on a row of its own when it does not fit there. Returns each item's `(x,
/// row)`, the scale's last.
pub fn flow(items: &[i32], scale: i32, w: u32) -> Vec<(i32, u32)> {
    let right = w as i32 - EDGE;
    let (mut x, mut row) = (EDGE, 0u32);
    let mut out = Vec::with_capacity(items.len() + 1);
    for &iw in items {
        if x > EDGE && x + iw > right {
            x = EDGE;
            row += 1;
        }
        out.push((x, row));
        x += iw + GAP;
    }
    let sx = right - scale;
    if x > EDGE && sx < x {
        row += 1;
    }
    out.push((sx.max(EDGE), row));
    out
}

/// The legend items' widths (px) of each colouring at font `px`, and the widest scale item.
fn worst_legends(w: u32, px: u32) -> (Vec<Vec<i32>>, i32) {
    let t = |s: &str| text_width(s, px);
    let contact = ["stuck", "sliding", "in the air", "on itself"]
        .iter()
        .map(|s| SWATCH + t(s))
        .collect();
    let bar = |name: &str| vec![t(name), t("-00.00") + 6 + bar_width(w) + 6 + t("-00.00")];
    let scale = (w as i32 / 4 + 8 + t("0.25 L")).max(t("grid 0.1 L"));
    (
        vec![
            contact,
            bar("elevation (z - a/2)/a"),
            bar("lambda (turns/m)"),
        ],
        scale,
    )
}

/// The layout of a picture of `size` px: of the clock fonts (17 px down to 7) whose text fits
/// the width and whose bands leave the scene at least half the height, the one with the fewest
/// legend rows, and of those the largest; the smallest fonts when none leaves half.
pub fn layout(size: (u32, u32)) -> Layout {
    let room = size.0 as i32 - 2 * EDGE;
    let fits = |s: &str, px: u32| text_width(s, px) <= room;
    let at = |big: u32| -> Option<Layout> {
        let split_clock = !(big >= 13 && fits(CLOCK, big));
        if split_clock && !CLOCK_HALVES.iter().all(|s| fits(s, big)) {
            return None;
        }
        let small = ((big * 14 + 8) / 17).max(7);
        let lines = if split_clock { 2 } else { 1 };
        let top = 4 + lines * (big + 3) + small + 6;
        let row = small + 8;
        let (legends, scale) = worst_legends(size.0, small);
        let rows = legends
            .iter()
            .map(|items| flow(items, scale, size.0).last().map_or(0, |p| p.1) + 1)
            .max()
            .unwrap_or(1);
        Some(Layout {
            big,
            small,
            split_clock,
            top,
            row,
            bottom: rows * row + 4,
        })
    };
    let scene = |l: &Layout| size.1 as i32 - (l.top + l.bottom) as i32;
    (7..=17u32)
        .filter_map(at)
        .filter(|l| 2 * scene(l) >= size.1 as i32)
        .min_by_key(|l| (l.bottom / l.row, std::cmp::Reverse(l.big)))
        .unwrap_or_else(|| {
            at(7).unwrap_or(Layout {
                big: 7,
                small: 7,
                split_clock: true,
                top: 4 + 2 * 10 + 7 + 6,
                row: 15,
                bottom: 3 * 15 + 4,
            })
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At every size the clock, the legends and the scale fit the width, none overlapping
    /// another, and the bands leave the scene at least a quarter of the picture (half from
    /// 320 px wide). (The old fixed 14 px text ran off a 160 px picture, and its legend into
    /// the scale.)
    #[test]
    fn the_text_fits_every_size_and_leaves_room_for_the_scene() {
        for size in [
            (160, 120),
            (200, 150),
            (240, 160),
            (320, 200),
            (480, 300),
            (640, 400),
            (1280, 720),
        ] {
            let l = layout(size);
            let room = size.0 as i32 - 2 * EDGE;
            if l.split_clock {
                assert!(
                    CLOCK_HALVES.iter().all(|s| text_width(s, l.big) <= room),
                    "{size:?}"
                );
            } else {
                assert!(text_width(CLOCK, l.big) <= room, "{size:?}");
            }
            let (legends, scale) = worst_legends(size.0, l.small);
            for items in &legends {
                let placed = flow(items, scale, size.0);
                let rows = placed.last().unwrap().1 + 1;
                assert!(rows * l.row + 4 <= l.bottom, "{size:?}");
                // Every item inside the picture, none overlapping another on its row.
                let widths: Vec<i32> = items.iter().copied().chain([scale]).collect();
                for (k, (&(x, r), &w)) in placed.iter().zip(&widths).enumerate() {
                    assert!(
                        x >= EDGE && x + w <= size.0 as i32 - EDGE,
                        "{size:?} item {k}"
                    );
                    for (&(x2, r2), &w2) in placed[..k].iter().zip(&widths) {
                        assert!(r2 != r || x2 + w2 <= x, "{size:?}: items overlap");
                    }
                }
            }
            let scene = size.1 as i32 - l.top as i32 - l.bottom as i32;
            assert!(
                4 * scene >= size.1 as i32,
                "{size:?}: scene {scene} px of {}",
                size.1
            );
            if size.0 >= 320 {
                assert!(
                    2 * scene >= size.1 as i32,
                    "{size:?}: scene {scene} px of {}",
                    size.1
                );
            }
        }
        // The default picture keeps its one-line clock and one-row legend.
        let l = layout((480, 300));
        assert!(!l.split_clock && l.bottom == l.row + 4, "{l:?}");
    }
}
