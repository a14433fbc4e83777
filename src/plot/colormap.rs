//! Colour maps for the figures: a sequential viridis-like map and a diverging blue-white-red map.

use plotters::style::RGBColor;

/// Viridis anchors (matplotlib's viridis sampled at 9 evenly spaced points), dark to bright.
const VIRIDIS: [[u8; 3]; 9] = [
    [68, 1, 84],
    [71, 44, 122],
    [59, 81, 139],
    [44, 113, 142],
    [33, 144, 141],
    [39, 173, 129],
    [92, 200, 99],
    [170, 220, 50],
    [253, 231, 37],
];

/// Blue-white-red anchors (ColorBrewer RdBu, reversed so that negative is blue), 11 points.
const BWR: [[u8; 3]; 11] = [
    [5, 48, 97],
    [33, 102, 172],
    [67, 147, 195],
    [146, 197, 222],
    [209, 229, 240],
    [247, 247, 247],
    [253, 219, 199],
    [244, 165, 130],
    [214, 96, 77],
    [178, 24, 43],
    [103, 0, 31],
];

fn interp(anchors: &[[u8; 3]], u: f64) -> RGBColor {
    let u = if u.is_finite() {
        u.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let n = anchors.len() - 1;
    let x = u * n as f64;
    let i = (x.floor() as usize).min(n - 1);
    let f = x - i as f64;
    let a = anchors[i];
    let b = anchors[i + 1];
    let mix = |p: u8, q: u8| -> u8 { (p as f64 + (q as f64 - p as f64) * f).round() as u8 };
    RGBColor(mix(a[0], b[0]), mix(a[1], b[1]), mix(a[2], b[2]))
}

/// Sequential map: `u` in [0, 1] (dimensionless; clamped) to a viridis-like colour.
pub fn sequential(u: f64) -> RGBColor {
    interp(&VIRIDIS, u)
}

/// Diverging map: `u` in [0, 1] (dimensionless; clamped), 0 = dark blue, 0.5 = white, 1 = dark red.
pub fn diverging(u: f64) -> RGBColor {
    interp(&BWR, u)
}

/// Ten distinguishable line colours (the Tableau-10 palette), indexed cyclically.
pub fn palette(i: usize) -> RGBColor {
    const TAB10: [[u8; 3]; 10] = [
        [31, 119, 180],
        [255, 127, 14],
        [44, 160, 44],
        [214, 39, 40],
        [148, 103, 189],
        [140, 86, 75],
        [227, 119, 194],
        [127, 127, 127],
        [188, 189, 34],
        [23, 190, 207],
    ];
    let c = TAB10[i % TAB10.len()];
    RGBColor(c[0], c[1], c[2])
}
