//! The movie's scene rasteriser: a ground plane with a grid, the body's shadow and the body as
//! a shaded tube, drawn into an RGB buffer with a depth buffer.
//!
//! The tube is a swept sphere: spheres of the rod's radius `a/2` placed along the centreline
//! at most `0.35 a` apart, each drawn as a per-pixel shaded impostor (normal from the pixel's
//! offset to the projected centre, Lambert plus a small specular term) and depth-tested
//! against the others, so crossings and the near side of a coil hide the far side correctly.
//! The ground is flat, with sky above the horizon of a perspective camera; its grid lines are
//! projected cell by cell as one-pixel lines, fading out with the distance from the scene's
//! centre and where cells shrink below a few pixels. The shadow is the body's vertical
//! projection: a ground pixel (its ray cast to the ground) is shaded when the point under it
//! lies within `a/2` of a sphere centre's foot, lighter the higher that sphere is.
//!
//! An orthographic camera that looks nearly level (the side view) sees the ground plane edge
//! on: unbounded, it would fill the whole picture with grid lines. There the ground is a panel
//! ([`panel_rows`]): a strip of the plane a given depth before and behind the scene's centre,
//! edged by two darker lines, with the sky colour beyond it.

use super::camera::Camera;

/// Ground colour.
pub(super) const GROUND: [u8; 3] = [236, 233, 224];
/// Sky colour (above the horizon).
pub(super) const SKY: [u8; 3] = [214, 222, 230];
const GRID: [u8; 3] = [196, 193, 184];
const GRID_MAJOR: [u8; 3] = [160, 157, 150];
const SHADOW_MAX: f64 = 0.45;

/// One sphere of the swept tube: centre (m) and base colour.
#[derive(Clone, Copy, Debug)]
pub(super) struct Ball {
    pub c: [f64; 3],
    pub colour: [u8; 3],
    /// Radius (m).
    pub r: f64,
}

/// An RGB image with a depth buffer (depth +inf where nothing but ground or sky is drawn).
pub(super) struct Canvas {
    pub w: usize,
    pub h: usize,
    pub rgb: Vec<u8>,
    pub depth: Vec<f32>,
}

impl Canvas {
    pub fn new(w: usize, h: usize) -> Canvas {
        Canvas {
            w,
            h,
            rgb: vec![0; 3 * w * h],
            depth: vec![f32::INFINITY; w * h],
        }
    }

    fn put(&mut self, i: usize, c: [u8; 3]) {
        self.rgb[3 * i..3 * i + 3].copy_from_slice(&c);
    }
}

/// The camera's viewing direction along the ground (unit; screen up when looking straight
/// down).
fn ground_forward(cam: &Camera) -> [f64; 2] {
    let n = (cam.fwd[0] * cam.fwd[0] + cam.fwd[1] * cam.fwd[1]).sqrt();
    if n > 1e-9 {
        [cam.fwd[0] / n, cam.fwd[1] / n]
    } else {
        [cam.up[0], cam.up[1]]
    }
}

/// The rows `[a, b)` of a picture `h` rows high that show the ground panel: the points of the
/// plane within `half_depth` (m) of `centre` along the camera's viewing direction. The
/// camera's right vector is horizontal, so a row's rays all meet the ground at the same depth.
pub(super) fn panel_rows(
    cam: &Camera,
    centre: [f64; 3],
    half_depth: f64,
    h: usize,
) -> (usize, usize) {
    let fh = ground_forward(cam);
    let inside = |py: usize| {
        cam.ground_hit(cam.cx, py as f64 + 0.5)
            .is_some_and(|(g, _)| {
                ((g[0] - centre[0]) * fh[0] + (g[1] - centre[1]) * fh[1]).abs() <= half_depth
            })
    };
    let a = (0..h).find(|&py| inside(py)).unwrap_or(h);
    let b = (a..h).find(|&py| !inside(py)).unwrap_or(h);
    (a, b)
}

/// Ground and grid (spacing `cell` m, every fifth line darker, fading out between 2.5 and 4
/// body lengths `reach` from `centre`) with the shadow of `balls`; with `panel` (m), only the
/// ground within that depth of `centre` ([`panel_rows`]), the sky colour elsewhere.
pub(super) fn ground(
    cv: &mut Canvas,
    cam: &Camera,
    cell: f64,
    centre: [f64; 3],
    reach: f64,
    panel: Option<f64>,
    balls: &[Ball],
) {
    let (w, h) = (cv.w, cv.h);
    let rows = panel.map_or((0, h), |d| panel_rows(cam, centre, d, h));
    // Sky and ground by rows: the camera's right vector is horizontal, so a ray's vertical
    // component is the same along a row.
    for py in 0..h {
        let (_, d) = cam.ray(0.5 * w as f64, py as f64 + 0.5);
        let c = if (d[2] > -1e-9 && cam.focal.is_some()) || !(rows.0..rows.1).contains(&py) {
            SKY
        } else {
            GROUND
        };
        for p in cv.rgb[3 * py * w..3 * (py + 1) * w].chunks_exact_mut(3) {
            p.copy_from_slice(&c);
        }
    }
    // Grid lines: straight in any projection, drawn in pieces of one cell, each piece's colour
    // faded by its distance from the centre.
    let n = (reach / cell).ceil() as i64;
    let (ox, oy) = (
        (centre[0] / cell).round() as i64,
        (centre[1] / cell).round() as i64,
    );
    for axis in 0..2 {
        for i in -n..=n {
            let major = (if axis == 0 { ox + i } else { oy + i }).rem_euclid(5) == 0;
            let colour = if major { GRID_MAJOR } else { GRID };
            // Each vertex is projected once and shared by the two pieces that meet there.
            let at = |k: i64| -> [f64; 3] {
                if axis == 0 {
                    [(ox + i) as f64 * cell, (oy + k) as f64 * cell, 0.0]
                } else {
                    [(ox + k) as f64 * cell, (oy + i) as f64 * cell, 0.0]
                }
            };
            // Only the pieces within `reach` of the centre can show (|i| and |j| in cells).
            let half = ((n * n - i * i) as f64).max(0.0).sqrt().ceil() as i64 + 1;
            let (ja, jb) = ((-half).max(-n), half.min(n));
            let mut prev = cam.project(at(ja));
            for j in ja..jb {
                let (p, q) = (at(j), at(j + 1));
                let next = cam.project(q);
                let (a, b) = (prev, next);
                prev = next;
                let mid = [
                    0.5 * (p[0] + q[0]) - centre[0],
                    0.5 * (p[1] + q[1]) - centre[1],
                ];
                let r = (mid[0] * mid[0] + mid[1] * mid[1]).sqrt() / reach;
                let fade = ((1.0 - r) / 0.375).clamp(0.0, 1.0);
                if fade <= 0.0 {
                    continue;
                }
                let (Some(a), Some(b)) = (a, b) else {
                    continue;
                };
                // Cells below ~4 px would merge into noise: fade them too.
                let px_cell = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
                let fade = fade * ((px_cell - 4.0) / 4.0).clamp(0.0, 1.0);
                if fade > 0.0 {
                    line(cv, (a.0, a.1), (b.0, b.1), rows, mix(GROUND, colour, fade));
                }
            }
        }
    }
    // Shadow: darkest under a sphere resting on the ground, fading with height; the ground
    // point under each pixel near a sphere's foot is found by casting the pixel's ray.
    let mut shade = vec![0.0f32; w * h];
    // The ground disc under a sphere, of radius `r`, spans on screen the box of the four
    // points `r` along the camera's horizontal right and forward directions (its projection
    // is near an ellipse with those axes), widened by a pixel and a tenth.
    let fh = ground_forward(cam);
    let rh = [cam.right[0], cam.right[1]];
    for b in balls {
        let foot = [b.c[0], b.c[1], 0.0];
        let height = (b.c[2] - b.r).max(0.0);
        let alpha = (SHADOW_MAX / (1.0 + height / (4.0 * b.r))) as f32;
        let r = b.r * (1.0 + 0.15 * height / b.r).min(2.0);
        let (mut xa, mut xb, mut ya, mut yb) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        let mut seen = 0;
        for (u, v) in [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)] {
            let g = [
                foot[0] + r * (u * rh[0] + v * fh[0]),
                foot[1] + r * (u * rh[1] + v * fh[1]),
                0.0,
            ];
            if let Some((x, y, _)) = cam.project(g) {
                xa = xa.min(x);
                xb = xb.max(x);
                ya = ya.min(y);
                yb = yb.max(y);
                seen += 1;
            }
        }
        if seen < 4 {
            continue;
        }
        let (mx, my) = (0.1 * (xb - xa) + 1.0, 0.1 * (yb - ya) + 1.0);
        let (x0, x1) = clamp_span(xa - mx, xb + mx, w);
        let (y0, y1) = clamp_span(ya - my, yb + my, h);
        let (y0, y1) = (y0.max(rows.0), y1.min(rows.1));
        let r2 = r * r;
        for py in y0..y1 {
            for px in x0..x1 {
                let Some((g, _)) = cam.ground_hit(px as f64 + 0.5, py as f64 + 0.5) else {
                    continue;
                };
                let (dx, dy) = (g[0] - b.c[0], g[1] - b.c[1]);
                let d2 = dx * dx + dy * dy;
                if d2 < r2 {
                    // Soft edge over the outer part of the radius.
                    let edge = ((1.0 - d2 / r2) * 2.5).min(1.0) as f32;
                    let i = py * w + px;
                    shade[i] = shade[i].max(alpha * edge);
                }
            }
        }
    }
    for (p, &s) in cv.rgb.chunks_exact_mut(3).zip(&shade) {
        if s > 0.0 {
            let k = 1.0 - s;
            for v in p {
                *v = (*v as f32 * k + 0.5) as u8;
            }
        }
    }
    // The panel's far and near edges.
    if panel.is_some() && rows.0 < rows.1 {
        for py in [rows.0, rows.1 - 1] {
            for p in cv.rgb[3 * py * w..3 * (py + 1) * w].chunks_exact_mut(3) {
                p.copy_from_slice(&GRID_MAJOR);
            }
        }
    }
}

/// A one-pixel line from `a` to `b` (px), clipped first (Liang-Barsky) to the picture's
/// rows `[rows.0, rows.1)`.
fn line(cv: &mut Canvas, a: (f64, f64), b: (f64, f64), rows: (usize, usize), c: [u8; 3]) {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let w = cv.w as f64;
    let (top, h) = (rows.0 as f64, rows.1.min(cv.h) as f64);
    let (mut u0, mut u1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0),
        (dx, w - 1e-6 - a.0),
        (-dy, a.1 - top),
        (dy, h - 1e-6 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                u0 = u0.max(r);
            } else {
                u1 = u1.min(r);
            }
        }
    }
    if !(u0 <= u1) {
        return;
    }
    let (x0, y0) = (a.0 + u0 * dx, a.1 + u0 * dy);
    let (ex, ey) = ((u1 - u0) * dx, (u1 - u0) * dy);
    let n = ex.abs().max(ey.abs()).ceil().max(1.0) as usize;
    let (sx, sy) = (ex / n as f64, ey / n as f64);
    for k in 0..=n {
        let (x, y) = (x0 + k as f64 * sx, y0 + k as f64 * sy);
        if x >= 0.0 && y >= top && x < w && y < h {
            let i = y as usize * cv.w + x as usize;
            cv.put(i, c);
        }
    }
}

/// Draw the spheres, shaded, with the depth test.
pub(super) fn tube(cv: &mut Canvas, cam: &Camera, balls: &[Ball]) {
    let (w, h) = (cv.w, cv.h);
    // Light direction in camera coordinates (x right, y up, z toward the viewer): from the
    // upper left, in front of the scene.
    let l = unit3([-0.45, 0.65, 0.62]);
    // Half vector for the specular term (viewer along +z).
    let hv = unit3([l[0], l[1], l[2] + 1.0]);
    for b in balls {
        let Some((sx, sy, z)) = cam.project(b.c) else {
            continue;
        };
        let rpx = b.r * cam.px_per_m(z);
        if rpx < 0.3 {
            continue;
        }
        let (x0, x1) = clamp_span(sx - rpx - 1.0, sx + rpx + 1.0, w);
        let (y0, y1) = clamp_span(sy - rpx - 1.0, sy + rpx + 1.0, h);
        let inv = 1.0 / rpx;
        for py in y0..y1 {
            let dy = (sy - (py as f64 + 0.5)) * inv;
            for px in x0..x1 {
                let dx = ((px as f64 + 0.5) - sx) * inv;
                let q = dx * dx + dy * dy;
                if q >= 1.0 {
                    continue;
                }
                let nz = (1.0 - q).sqrt();
                let d = (z - nz * b.r) as f32;
                let i = py * w + px;
                if d >= cv.depth[i] {
                    continue;
                }
                cv.depth[i] = d;
                let lam = (dx * l[0] + dy * l[1] + nz * l[2]).max(0.0);
                let spec = (dx * hv[0] + dy * hv[1] + nz * hv[2]).max(0.0).powi(24);
                let k = 0.38 + 0.62 * lam;
                let s = 90.0 * spec;
                let c = b.colour;
                let px3 = [
                    (c[0] as f64 * k + s).min(255.0) as u8,
                    (c[1] as f64 * k + s).min(255.0) as u8,
                    (c[2] as f64 * k + s).min(255.0) as u8,
                ];
                cv.put(i, px3);
            }
        }
    }
}

/// Pixel index range [a, b) covering the real interval [lo, hi], clamped to [0, n).
fn clamp_span(lo: f64, hi: f64, n: usize) -> (usize, usize) {
    let a = lo.floor().max(0.0).min(n as f64) as usize;
    let b = (hi.ceil() + 1.0).max(0.0).min(n as f64) as usize;
    (a, b)
}

fn unit3(v: [f64; 3]) -> [f64; 3] {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / n, v[1] / n, v[2] / n]
}

/// Linear mix of two colours, `t` in [0, 1].
pub(super) fn mix(a: [u8; 3], b: [u8; 3], t: f64) -> [u8; 3] {
    let m = |p: u8, q: u8| (p as f64 + (q as f64 - p as f64) * t).round() as u8;
    [m(a[0], b[0]), m(a[1], b[1]), m(a[2], b[2])]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearer_sphere_hides_farther_one() {
        let cam = Camera::looking_at(
            [0.0; 3],
            [1.0, 0.0, 0.0],
            std::f64::consts::FRAC_PI_2,
            1.0,
            None,
            100.0,
            (40, 40),
        );
        let mut cv = Canvas::new(40, 40);
        // Looking down: the higher ball is nearer and must win whatever the drawing order.
        let low = Ball {
            c: [0.0, 0.0, 0.05],
            colour: [0, 0, 255],
            r: 0.05,
        };
        let high = Ball {
            c: [0.0, 0.0, 0.2],
            colour: [255, 0, 0],
            r: 0.05,
        };
        tube(&mut cv, &cam, &[high, low]);
        let i = 20 * 40 + 20;
        assert!(
            cv.rgb[3 * i] > cv.rgb[3 * i + 2],
            "{:?}",
            &cv.rgb[3 * i..3 * i + 3]
        );
        let mut cv = Canvas::new(40, 40);
        tube(&mut cv, &cam, &[low, high]);
        assert!(cv.rgb[3 * i] > cv.rgb[3 * i + 2]);
    }
}

#[cfg(test)]
mod panel_tests {
    use super::*;

    /// The side view's camera over a 120 x 80 picture: orthographic, 5 degrees above the
    /// ground, 200 px per metre.
    fn side() -> Camera {
        Camera::looking_at(
            [0.0; 3],
            [0.0, 1.0, 0.0],
            5f64.to_radians(),
            5.0,
            None,
            200.0,
            (120, 80),
        )
    }

    /// With a panel, the rows beyond it keep the sky colour (no ground, no grid line); the
    /// panel shows ground and grid. Without one, the plane seen edge on fills every row.
    #[test]
    fn the_side_views_ground_stays_in_its_panel() {
        let cam = side();
        let (a, b) = panel_rows(&cam, [0.0; 3], 0.2, 80);
        // 0.2 m each way at sin 5 deg and 200 px/m: about 7 rows.
        assert!(a > 0 && b < 80 && (5..=9).contains(&(b - a)), "{a}..{b}");
        let mut cv = Canvas::new(120, 80);
        ground(&mut cv, &cam, 0.05, [0.0; 3], 2.0, Some(0.2), &[]);
        let row = |cv: &Canvas, y: usize| cv.rgb[3 * 120 * y..3 * 120 * (y + 1)].to_vec();
        for y in (0..a).chain(b..80) {
            assert!(
                row(&cv, y).chunks(3).all(|p| p == SKY),
                "row {y} outside the panel {a}..{b} is not background"
            );
        }
        for y in a..b {
            assert!(row(&cv, y).chunks(3).all(|p| p != SKY), "row {y}");
        }
        let mut whole = Canvas::new(120, 80);
        ground(&mut whole, &cam, 0.05, [0.0; 3], 2.0, None, &[]);
        assert!(row(&whole, 0).chunks(3).all(|p| p != SKY));
    }
}
