//! The movie's camera: a pinhole (perspective) or orthographic projection from world
//! coordinates (m) to pixels, and the inverse ray through a pixel.
//!
//! Camera frame: `right` (screen x grows along it), `up` (screen y grows against it) and `fwd`
//! (the viewing direction, depth grows along it), orthonormal with `right = fwd x up`.

use crate::rod::vec3::f;

/// A camera over the scene.
#[derive(Clone, Copy, Debug)]
pub(super) struct Camera {
    /// Eye position (m); for an orthographic camera, a point on the image plane's centre ray.
    pub eye: [f64; 3],
    pub right: [f64; 3],
    pub up: [f64; 3],
    pub fwd: [f64; 3],
    /// Perspective: focal length (px). Orthographic: None.
    pub focal: Option<f64>,
    /// Orthographic scale (px per m); unused in perspective.
    pub scale: f64,
    /// Image centre (px).
    pub cx: f64,
    pub cy: f64,
}

/// Nearest depth drawn by a perspective camera (m).
const NEAR: f64 = 1e-3;

impl Camera {
    /// A camera looking at `target` along the horizontal direction `h` (unit, horizontal)
    /// tilted down by `elevation` (rad; pi/2 looks straight down, then `h` is the screen's up
    /// direction), from `distance` (m).
    pub fn looking_at(
        target: [f64; 3],
        h: [f64; 3],
        elevation: f64,
        distance: f64,
        focal: Option<f64>,
        scale: f64,
        size: (u32, u32),
    ) -> Camera {
        let (se, ce) = elevation.sin_cos();
        let z = [0.0, 0.0, 1.0];
        let fwd = f::add(f::scale(h, ce), f::scale(z, -se));
        // Screen up: the component of world up (or of `h` when looking straight down) normal
        // to the viewing direction.
        let up = f::unit(f::add(f::scale(z, ce), f::scale(h, se)));
        let right = f::cross(fwd, up);
        Camera {
            eye: f::sub(target, f::scale(fwd, distance)),
            right,
            up,
            fwd,
            focal,
            scale,
            cx: 0.5 * size.0 as f64,
            cy: 0.5 * size.1 as f64,
        }
    }

    /// Pixel coordinates and depth (m) of a world point; None behind a perspective camera.
    pub fn project(&self, p: [f64; 3]) -> Option<(f64, f64, f64)> {
        let d = f::sub(p, self.eye);
        let (x, y, z) = (
            f::dot(d, self.right),
            f::dot(d, self.up),
            f::dot(d, self.fwd),
        );
        match self.focal {
            Some(fl) => {
                if z < NEAR {
                    return None;
                }
                Some((self.cx + fl * x / z, self.cy - fl * y / z, z))
            }
            None => Some((self.cx + self.scale * x, self.cy - self.scale * y, z)),
        }
    }

    /// Pixels per metre at depth `z` (m), across the line of sight.
    pub fn px_per_m(&self, z: f64) -> f64 {
        match self.focal {
            Some(fl) => fl / z.max(NEAR),
            None => self.scale,
        }
    }

    /// The ray through pixel (px, py): origin and (not normalised) direction.
    pub fn ray(&self, px: f64, py: f64) -> ([f64; 3], [f64; 3]) {
        match self.focal {
            Some(fl) => {
                let d = f::add(
                    self.fwd,
                    f::add(
                        f::scale(self.right, (px - self.cx) / fl),
                        f::scale(self.up, -(py - self.cy) / fl),
                    ),
                );
                (self.eye, d)
            }
            None => {
                let o = f::add(
                    self.eye,
                    f::add(
                        f::scale(self.right, (px - self.cx) / self.scale),
                        f::scale(self.up, -(py - self.cy) / self.scale),
                    ),
                );
                (o, self.fwd)
            }
        }
    }

    /// Where the ray through pixel (px, py) meets the ground plane z = 0: ground point and
    /// ray parameter; None if it does not (looking level or up).
    pub fn ground_hit(&self, px: f64, py: f64) -> Option<([f64; 2], f64)> {
        let (o, d) = self.ray(px, py);
        if d[2] > -1e-9 {
            return None;
        }
        let t = -o[2] / d[2];
        Some(([o[0] + t * d[0], o[1] + t * d[1]], t))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_and_projection_agree() {
        for focal in [Some(500.0), None] {
            let c = Camera::looking_at(
                [0.3, -0.2, 0.0],
                f::unit([0.6, 0.8, 0.0]),
                0.6,
                2.0,
                focal,
                300.0,
                (640, 400),
            );
            // The target sits at the image centre.
            let (x, y, z) = c.project([0.3, -0.2, 0.0]).unwrap();
            assert!((x - 320.0).abs() < 1e-9 && (y - 200.0).abs() < 1e-9);
            assert!((z - 2.0).abs() < 1e-12);
            // A ground point maps to a pixel whose ray hits it again.
            let g = [0.5, 0.1, 0.0];
            let (px, py, _) = c.project(g).unwrap();
            let (h, _) = c.ground_hit(px, py).unwrap();
            assert!((h[0] - g[0]).abs() < 1e-9 && (h[1] - g[1]).abs() < 1e-9);
            // Screen up points to world up (or forward when looking down), right-handed frame.
            assert!(c.up[2] > 0.0);
            let r = f::cross(c.fwd, c.up);
            assert!(f::norm(f::sub(r, c.right)) < 1e-12);
        }
    }
}
