//! Movies of a run: the body as a shaded tube of the rod's diameter over a ground grid with
//! its shadow, one frame per recorded output (or a stride that keeps the movie to
//! [`MovieOptions::max_seconds`]), written as an animated GIF.
//!
//! Three views ([`View`]): a perspective 3D view from above and behind one side of the body
//! whose camera follows the body's centroid smoothly (a centred moving average with a
//! triangular window of half-width `duration / 8`, so the camera neither jerks nor lags);
//! an orthographic top view and an orthographic side view (5 degrees above the ground), both
//! framing the whole run from a fixed camera when it fits in 3 body lengths, else following
//! the centroid the same way. Screen right is the initial heading (tail to head) in the top
//! and side views.
//!
//! Colours ([`Colouring`]): contact state of each node (stuck, sliding, in the air; stuck
//! meaning in contact and slower than [`Clip::stuck_speed`]), elevation `(z - a/2)/a`, or the
//! local link density `lambda`. On screen: time, `t/T` (T the gait period, when there is a
//! gait), the mean forward speed of the centroid so far (`v_s`, along the initial heading, and
//! `v_s/v_m`), the run's regime when known, the colour legend, and a scale in body lengths
//! (a bar of 0.25 L in the orthographic views; in the 3D view a 0.5 L ruler lying on the
//! ground near the bottom of the picture, and the grid spacing, 0.1 L). The side view's ground
//! is a panel as deep as the body needs (0.1 L beyond its farthest node along the line of sight,
//! at least 0.25 L each way), the sky colour beyond, not a plane seen edge on across the whole
//! picture. The text stays in a
//! band at the top and a band at the bottom of the picture ([`scene_rows`] gives the rows
//! between them).
//!
//! The picture is rasterised in-house (`raster.rs`: ray-cast ground, swept-sphere tube with a
//! depth buffer), the text drawn by plotters on the same buffer with the embedded font, and the
//! GIF encoded by the `gif` crate with one palette learnt by NeuQuant (`encode.rs`). Frames are
//! rendered and compressed in parallel (rayon).

mod camera;
mod encode;
pub mod layout;
mod overlay;
mod raster;

use super::{colormap, draw_err, PlotError};
use camera::Camera;
use raster::{Ball, Canvas};
use std::path::Path;

/// The contact state of a node at one instant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactState {
    /// In contact and slower than the stuck speed.
    Stuck,
    /// In contact and sliding.
    Sliding,
    /// Not in contact.
    Air,
}

/// What a movie shows: plain data, from a run in memory or from a run directory.
#[derive(Clone, Debug, Default)]
pub struct Clip {
    /// Title shown on every frame (e.g. the problem's name).
    pub title: String,
    /// Frame times (s).
    pub t: Vec<f64>,
    /// Node positions (m), frames x nodes, head first.
    pub x: Vec<Vec<[f64; 3]>>,
    /// Contact state, frames x nodes.
    pub contact: Vec<Vec<ContactState>>,
    /// Nodes touching another part of the body (self-contact), frames x nodes; may be empty.
    pub self_contact: Vec<Vec<bool>>,
    /// Local link density at the nodes (turns/m), frames x nodes (NaN where undefined); may
    /// be empty.
    pub lambda: Vec<Vec<f64>>,
    /// Rod diameter `a` (m).
    pub diameter: f64,
    /// Rod length `L` (m).
    pub length: f64,
    /// Gait period `T` (s), if there is a gait.
    pub period: Option<f64>,
    /// Gait speed `v_m` (m/s), if there is a gait.
    pub gait_speed: Option<f64>,
    /// The speed (m/s) below which a node in contact counts as stuck.
    pub stuck_speed: f64,
    /// The run's regime (one letter), when known.
    pub regime: Option<String>,
}

/// Which camera.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum View {
    /// Perspective, from above and behind one side, following the centroid.
    #[default]
    ThreeD,
    /// Orthographic, from straight above.
    Top,
    /// Orthographic, from the side, 5 degrees above the ground.
    Side,
}

/// What the body's colour shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Colouring {
    /// Stuck, sliding or in the air.
    #[default]
    Contact,
    /// Elevation `(z - a/2)/a`.
    Elevation,
    /// Local link density `lambda` (turns/m).
    Lambda,
}

impl std::str::FromStr for View {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "3d" => Ok(View::ThreeD),
            "top" => Ok(View::Top),
            "side" => Ok(View::Side),
            _ => Err(format!("unknown view {s:?} (allowed: 3d, top, side)")),
        }
    }
}

impl std::str::FromStr for Colouring {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "contact" => Ok(Colouring::Contact),
            "elevation" => Ok(Colouring::Elevation),
            "lambda" => Ok(Colouring::Lambda),
            _ => Err(format!(
                "unknown colouring {s:?} (allowed: contact, elevation, lambda)"
            )),
        }
    }
}

/// How to render.
#[derive(Clone, Copy, Debug)]
pub struct MovieOptions {
    /// Camera. Default 3D.
    pub view: View,
    /// Body colour. Default contact state.
    pub colour: Colouring,
    /// Frames per second of the movie. Default 10; in (0, 100].
    pub fps: f64,
    /// Longest movie (s) before frames are skipped at a stride. Default 15.
    pub max_seconds: f64,
    /// Picture size (px). Default 480 x 300 (the size that keeps a run's movie cheap: its
    /// LZW compression and rasterising both cost in proportion to the pixels).
    pub size: (u32, u32),
}

impl Default for MovieOptions {
    fn default() -> Self {
        MovieOptions {
            view: View::ThreeD,
            colour: Colouring::Contact,
            fps: 10.0,
            max_seconds: 15.0,
            size: (480, 300),
        }
    }
}

/// What a movie took.
#[derive(Clone, Copy, Debug)]
pub struct MovieStats {
    /// Frames in the movie.
    pub frames: usize,
    /// File size (bytes).
    pub bytes: usize,
    /// Wall time (s).
    pub seconds: f64,
}

/// Stuck colour (blue), sliding (orange), in the air (green): the Tableau colours.
pub const STUCK: [u8; 3] = [31, 119, 180];
/// Sliding colour.
pub const SLIDING: [u8; 3] = [255, 127, 14];
/// In-the-air colour.
pub const AIR: [u8; 3] = [44, 160, 44];
/// Colour of a node touching another part of the body (self-contact; Tableau purple).
pub const SELF_CONTACT: [u8; 3] = [148, 103, 189];

/// The rows `[y0, y1)` of a picture of `size` between the text bands: the scene alone. The
/// bands' heights come from [`layout::layout`], scaled with the picture, so the text fits a
/// small picture and the scene (framed within these rows) stays clear of it.
pub fn scene_rows(size: (u32, u32)) -> (u32, u32) {
    let l = layout::layout(size);
    (l.top, size.1.saturating_sub(l.bottom))
}

/// The clip frames a movie shows: every frame while `n / fps <= max_seconds`, else every
/// `k`-th frame with `k` the smallest stride giving at most 12 s (a little under the limit, so
/// the stride does not change with one more frame), the last frame always included.
pub fn frame_picks(n: usize, fps: f64, max_seconds: f64) -> Vec<usize> {
    if n == 0 {
        return Vec::new();
    }
    if n as f64 <= fps * max_seconds {
        return (0..n).collect();
    }
    let target = (fps * max_seconds.min(12.0)).max(2.0);
    let stride = (n as f64 / target).ceil().max(1.0) as usize;
    let mut v: Vec<usize> = (0..n).step_by(stride).collect();
    if *v.last().unwrap() != n - 1 {
        v.push(n - 1);
    }
    v
}

impl Clip {
    /// Check shapes and values.
    fn validate(&self) -> Result<(), PlotError> {
        let nf = self.t.len();
        if nf == 0 {
            return Err(PlotError::Invalid("movie: no frames".into()));
        }
        if self.x.len() != nf || self.contact.len() != nf {
            return Err(PlotError::Mismatch(format!(
                "movie: {} times, {} position frames, {} contact frames",
                nf,
                self.x.len(),
                self.contact.len()
            )));
        }
        if !self.lambda.is_empty() && self.lambda.len() != nf {
            return Err(PlotError::Mismatch(format!(
                "movie: {} times, {} lambda frames",
                nf,
                self.lambda.len()
            )));
        }
        let nn = self.x[0].len();
        if nn < 2 {
            return Err(PlotError::Invalid("movie: fewer than two nodes".into()));
        }
        for (k, fr) in self.x.iter().enumerate() {
            if fr.len() != nn || self.contact[k].len() != nn {
                return Err(PlotError::Mismatch(format!(
                    "movie: frame {k} has {} nodes and {} contact states, frame 0 {nn} nodes",
                    fr.len(),
                    self.contact[k].len()
                )));
            }
        }
        let positive = |v: f64| v > 0.0 && v.is_finite();
        if !positive(self.diameter) || !positive(self.length) {
            return Err(PlotError::Invalid(format!(
                "movie: diameter {} m and length {} m must be finite and > 0",
                self.diameter, self.length
            )));
        }
        Ok(())
    }

    /// Centroid of frame `k` (m); non-finite nodes skipped.
    pub fn centroid(&self, k: usize) -> [f64; 3] {
        let mut c = [0.0; 3];
        let mut n = 0.0;
        for p in &self.x[k] {
            if p.iter().all(|v| v.is_finite()) {
                for (cd, pd) in c.iter_mut().zip(p) {
                    *cd += pd;
                }
                n += 1.0;
            }
        }
        if n > 0.0 {
            c.map(|v| v / n)
        } else {
            c
        }
    }

    /// The initial heading: the horizontal tail-to-head direction of frame 0 (x if degenerate).
    pub fn heading(&self) -> [f64; 3] {
        let (h, t) = (self.x[0][0], *self.x[0].last().unwrap());
        let d = [h[0] - t[0], h[1] - t[1], 0.0];
        let n = (d[0] * d[0] + d[1] * d[1]).sqrt();
        if n > 1e-12 && n.is_finite() {
            [d[0] / n, d[1] / n, 0.0]
        } else {
            [1.0, 0.0, 0.0]
        }
    }

    /// Mean forward speed of the centroid from frame 0 to frame `k` along the initial heading
    /// (m/s); NaN at frame 0.
    pub fn v_s_so_far(&self, k: usize) -> f64 {
        let dt = self.t[k] - self.t[0];
        if dt <= 0.0 {
            return f64::NAN;
        }
        let (a, b) = (self.centroid(0), self.centroid(k));
        let h = self.heading();
        ((b[0] - a[0]) * h[0] + (b[1] - a[1]) * h[1]) / dt
    }
}

/// Everything fixed over a movie: the picked frames, the cameras and the colour scales.
struct Plan<'a> {
    clip: &'a Clip,
    opts: MovieOptions,
    picks: Vec<usize>,
    cams: Vec<Camera>,
    elev_max: f64,
    lambda_max: f64,
    /// The side view's ground panel: half its depth (m) before and behind the point the
    /// camera looks at (`None`: the whole plane, in the 3D and top views).
    panel: Option<f64>,
}

/// Centred moving average with a triangular window of half-width `tau` (s) of the points `c`
/// at times `t`.
fn smooth(t: &[f64], c: &[[f64; 3]], tau: f64) -> Vec<[f64; 3]> {
    t.iter()
        .map(|&tk| {
            let mut s = [0.0; 3];
            let mut wsum = 0.0;
            for (&tj, cj) in t.iter().zip(c) {
                let w = 1.0 - (tj - tk).abs() / tau.max(1e-12);
                if w > 0.0 || tj == tk {
                    let w = w.max(1e-9);
                    for (sd, cd) in s.iter_mut().zip(cj) {
                        *sd += w * cd;
                    }
                    wsum += w;
                }
            }
            s.map(|v| v / wsum)
        })
        .collect()
}

/// The movie's options in range: `fps` in (0, 100], the size within 160x120 to 4000x4000 px.
fn check_options(opts: &MovieOptions) -> Result<(), PlotError> {
    if !(opts.fps > 0.0 && opts.fps <= 100.0) {
        return Err(PlotError::Invalid(format!(
            "movie: fps {} is not allowed: must be in (0, 100]",
            opts.fps
        )));
    }
    if opts.size.0 < 160 || opts.size.1 < 120 || opts.size.0 > 4000 || opts.size.1 > 4000 {
        return Err(PlotError::Invalid(format!(
            "movie: size {}x{} px is not allowed: 160x120 to 4000x4000",
            opts.size.0, opts.size.1
        )));
    }
    Ok(())
}

/// The side view's ground panel depth (m): deep enough for every picked frame's body (0.1 L
/// beyond its farthest node along the line of sight of its camera), at least 0.25 L each way.
fn side_panel_depth(clip: &Clip, picks: &[usize], cams: &[Camera]) -> f64 {
    let l = clip.length;
    let mut depth = 0.25 * l;
    for (&k, cam) in picks.iter().zip(cams) {
        let Some((c, _)) = cam.ground_hit(cam.cx, cam.cy) else {
            continue;
        };
        let n = cam.fwd[0].hypot(cam.fwd[1]).max(1e-12);
        let fh = [cam.fwd[0] / n, cam.fwd[1] / n];
        for p in clip.x[k].iter().filter(|p| p.iter().all(|v| v.is_finite())) {
            let d = ((p[0] - c[0]) * fh[0] + (p[1] - c[1]) * fh[1]).abs();
            depth = depth.max(d + 0.1 * l);
        }
    }
    depth
}

impl<'a> Plan<'a> {
    fn new(clip: &'a Clip, opts: MovieOptions) -> Result<Plan<'a>, PlotError> {
        clip.validate()?;
        check_options(&opts)?;
        let picks = frame_picks(clip.t.len(), opts.fps, opts.max_seconds);
        let w = opts.size.0 as f64;
        let l = clip.length;
        let heading = clip.heading();
        let lateral = [-heading[1], heading[0], 0.0];
        let ts: Vec<f64> = picks.iter().map(|&k| clip.t[k]).collect();
        let cs: Vec<[f64; 3]> = picks
            .iter()
            .map(|&k| {
                let c = clip.centroid(k);
                [c[0], c[1], 0.0]
            })
            .collect();
        let duration = ts.last().unwrap() - ts[0];
        let follow = smooth(&ts, &cs, duration / 8.0);
        let (y0, y1) = scene_rows(opts.size);
        let scene_h = (y1 - y0) as f64;
        let size = opts.size;
        let cams: Vec<Camera> = match opts.view {
            View::ThreeD => {
                // Looking 60 degrees from the heading, 28 degrees down, the body about 0.55 of
                // the width across (or 1.1 times the scene's height, on a wide, short picture,
                // so that it stays between the text bands).
                let az = 60f64.to_radians();
                let hdir = [
                    heading[0] * az.cos() + lateral[0] * az.sin(),
                    heading[1] * az.cos() + lateral[1] * az.sin(),
                    0.0,
                ];
                let focal = 0.5 * w / 20f64.to_radians().tan();
                let dist = focal * l / (0.55 * w).min(1.1 * scene_h);
                follow
                    .iter()
                    .map(|&c| {
                        let mut cam = Camera::looking_at(
                            c,
                            hdir,
                            28f64.to_radians(),
                            dist,
                            Some(focal),
                            1.0,
                            size,
                        );
                        // Centre the scene band, not the whole picture.
                        cam.cy = y0 as f64 + 0.5 * scene_h;
                        cam
                    })
                    .collect()
            }
            View::Top | View::Side => {
                let (hdir, el) = match opts.view {
                    View::Top => (lateral, std::f64::consts::FRAC_PI_2),
                    _ => (lateral, 5f64.to_radians()),
                };
                let probe = Camera::looking_at([0.0; 3], hdir, el, 10.0 * l, None, 1.0, size);
                // Extent of every picked frame on the screen axes (m).
                let (mut xa, mut xb, mut ya, mut yb) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
                for &k in &picks {
                    for p in &clip.x[k] {
                        if let Some((x, y, _)) = probe.project(*p) {
                            if x.is_finite() && y.is_finite() {
                                xa = xa.min(x);
                                xb = xb.max(x);
                                ya = ya.min(y);
                                yb = yb.max(y);
                            }
                        }
                    }
                }
                let pad = clip.diameter * 2.0;
                let (ex, ey) = (xb - xa + 2.0 * pad, yb - ya + 2.0 * pad);
                if ex.max(ey) <= 3.0 * l && ex.is_finite() {
                    let scale = (0.94 * w / ex).min(0.9 * scene_h / ey.max(0.25 * l));
                    let (mx, my) = (0.5 * (xa + xb) - probe.cx, 0.5 * (ya + yb) - probe.cy);
                    // Shift the probe so the extent's centre lands at the scene's centre.
                    let centre = f_add(
                        f_add(probe.eye, f_scale(probe.right, mx)),
                        f_scale(probe.up, -my),
                    );
                    let centre = f_add(centre, f_scale(probe.fwd, 10.0 * l));
                    let mut cam = Camera::looking_at(centre, hdir, el, 10.0 * l, None, scale, size);
                    cam.cy = y0 as f64 + 0.5 * scene_h;
                    vec![cam; picks.len()]
                } else {
                    let scale = 0.6 * w / l;
                    follow
                        .iter()
                        .map(|&c| {
                            let mut cam =
                                Camera::looking_at(c, hdir, el, 10.0 * l, None, scale, size);
                            cam.cy = y0 as f64 + 0.5 * scene_h;
                            cam
                        })
                        .collect()
                }
            }
        };
        let a = clip.diameter;
        let elev_max = picks
            .iter()
            .flat_map(|&k| clip.x[k].iter().map(|p| (p[2] - 0.5 * a) / a))
            .filter(|v| v.is_finite())
            .fold(1.0f64, f64::max);
        let lambda_max = picks
            .iter()
            .filter_map(|&k| clip.lambda.get(k))
            .flatten()
            .filter(|v| v.is_finite())
            .fold(0.0f64, |m, v| m.max(v.abs()));
        if opts.colour == Colouring::Lambda && clip.lambda.is_empty() {
            return Err(PlotError::Invalid(
                "movie: colouring by lambda needs the local link density, which this run did not record".into(),
            ));
        }
        // The side view's ground panel: deep enough for every picked frame's body (0.1 L
        // beyond its farthest node along the line of sight), at least 0.25 L each way.
        let panel = (opts.view == View::Side).then(|| side_panel_depth(clip, &picks, &cams));
        Ok(Plan {
            clip,
            opts,
            picks,
            cams,
            panel,
            elev_max,
            lambda_max: if lambda_max > 0.0 { lambda_max } else { 1.0 },
        })
    }

    /// Colour of node `i` of clip frame `k`.
    fn node_colour(&self, k: usize, i: usize) -> [u8; 3] {
        let c = self.clip;
        let rgb = |c: plotters::style::RGBColor| [c.0, c.1, c.2];
        match self.opts.colour {
            Colouring::Contact if c.self_contact.get(k).and_then(|r| r.get(i)) == Some(&true) => {
                SELF_CONTACT
            }
            Colouring::Contact => match c.contact[k][i] {
                ContactState::Stuck => STUCK,
                ContactState::Sliding => SLIDING,
                ContactState::Air => AIR,
            },
            Colouring::Elevation => {
                let e = (c.x[k][i][2] - 0.5 * c.diameter) / c.diameter;
                rgb(colormap::sequential(0.1 + 0.9 * e.max(0.0) / self.elev_max))
            }
            Colouring::Lambda => {
                let l = c.lambda[k].get(i).copied().unwrap_or(f64::NAN);
                if l.is_finite() {
                    rgb(colormap::diverging(0.5 + 0.5 * l / self.lambda_max))
                } else {
                    [150, 150, 150]
                }
            }
        }
    }

    /// The swept spheres of clip frame `k`.
    fn balls(&self, k: usize) -> Vec<Ball> {
        let c = self.clip;
        let r = 0.5 * c.diameter;
        let x = &c.x[k];
        let mut out = Vec::with_capacity(4 * x.len());
        for i in 0..x.len() - 1 {
            let (p, q) = (x[i], x[i + 1]);
            if !p.iter().chain(q.iter()).all(|v| v.is_finite()) {
                continue;
            }
            let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
            let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let m = (len / (0.35 * c.diameter)).ceil().clamp(1.0, 200.0) as usize;
            let (cp, cq) = (self.node_colour(k, i), self.node_colour(k, i + 1));
            for j in 0..m {
                let u = j as f64 / m as f64;
                let colour = match self.opts.colour {
                    Colouring::Contact => {
                        if u < 0.5 {
                            cp
                        } else {
                            cq
                        }
                    }
                    _ => raster::mix(cp, cq, u),
                };
                out.push(Ball {
                    c: [p[0] + u * d[0], p[1] + u * d[1], p[2] + u * d[2]],
                    colour,
                    r,
                });
            }
        }
        if let Some(&q) = x.last() {
            if q.iter().all(|v| v.is_finite()) {
                out.push(Ball {
                    c: q,
                    colour: self.node_colour(k, x.len() - 1),
                    r,
                });
            }
        }
        // The head, a little wider.
        if x[0].iter().all(|v| v.is_finite()) {
            out.push(Ball {
                c: x[0],
                colour: self.node_colour(k, 0),
                r: 1.25 * r,
            });
        }
        out
    }

    /// Render movie frame `j` (the `j`-th pick).
    fn render(&self, j: usize) -> Result<encode::Rgb, PlotError> {
        let k = self.picks[j];
        let cam = &self.cams[j];
        let (w, h) = (self.opts.size.0 as usize, self.opts.size.1 as usize);
        let mut cv = Canvas::new(w, h);
        let balls = self.balls(k);
        let l = self.clip.length;
        // The grid around the point the camera looks at, out to 4 L (and over the whole
        // picture of an orthographic camera).
        let centre = cam
            .ground_hit(cam.cx, cam.cy)
            .map_or([0.0; 3], |(g, _)| [g[0], g[1], 0.0]);
        let reach = match cam.focal {
            Some(_) => 4.0 * l,
            None => (4.0 * l)
                .max(
                    0.65 * ((w * w + h * h) as f64).sqrt() / cam.scale / cam.fwd[2].abs().max(0.05),
                )
                .min(12.0 * l),
        };
        raster::ground(&mut cv, cam, 0.1 * l, centre, reach, self.panel, &balls);
        raster::tube(&mut cv, cam, &balls);
        let body: Vec<bool> = cv.depth.iter().map(|d| d.is_finite()).collect();
        overlay::draw(&mut cv.rgb, self, j)?;
        Ok(encode::Rgb { rgb: cv.rgb, body })
    }
}

fn f_add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn f_scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// Render the movie of `clip` to a GIF at `path` (written atomically by the caller's choice of
/// path: the bytes go to `path` directly). Errors: invalid clip or options
/// ([`PlotError::Invalid`], [`PlotError::Mismatch`]), drawing or I/O ([`PlotError::Draw`]).
pub fn movie(path: &Path, clip: &Clip, opts: &MovieOptions) -> Result<MovieStats, PlotError> {
    let start = std::time::Instant::now();
    let bytes = movie_bytes(clip, opts)?;
    std::fs::write(path, &bytes)
        .map_err(|e| PlotError::Draw(format!("{}: {e}", path.display())))?;
    Ok(MovieStats {
        frames: frame_picks(clip.t.len(), opts.fps, opts.max_seconds).len(),
        bytes: bytes.len(),
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// The GIF of `clip` in memory.
pub fn movie_bytes(clip: &Clip, opts: &MovieOptions) -> Result<Vec<u8>, PlotError> {
    super::register_fonts()?;
    let plan = Plan::new(clip, *opts)?;
    let delay = (100.0 / opts.fps).round().clamp(1.0, 65535.0) as u16;
    let last = delay.max(100);
    let mut out = Vec::new();
    let render = |j: usize| plan.render(j);
    encode::write_gif(&mut out, opts.size, plan.picks.len(), &render, delay, last)?;
    Ok(out)
}

/// One frame of the movie (clip frame nearest to time `t`, s) as a PNG still.
pub fn still(path: &Path, clip: &Clip, opts: &MovieOptions, t: f64) -> Result<(), PlotError> {
    use plotters::prelude::*;
    super::register_fonts()?;
    // Every frame is a pick for a still, so the camera path is the full one.
    let mut o = *opts;
    o.max_seconds = f64::INFINITY;
    let plan = Plan::new(clip, o)?;
    let j = (0..clip.t.len())
        .min_by(|&a, &b| (clip.t[a] - t).abs().total_cmp(&(clip.t[b] - t).abs()))
        .unwrap_or(0);
    let f = plan.render(j)?;
    let mut root = BitMapBackend::new(path, opts.size);
    root.blit_bitmap((0, 0), opts.size, &f.rgb)
        .map_err(draw_err)?;
    root.present().map_err(draw_err)?;
    Ok(())
}

#[cfg(test)]
mod tests;
