//! Ground tracks from contact data: where stationary contacts lie on the ground over time, and
//! at what angle to the body axis those tracks run.
//!
//! A node is **stuck** at a frame when it is in contact and its horizontal speed is at most
//! [`super::periodic::STATIONARY_SLIP_OVER_V_M`]` v_m` (the tracks figure's and the periodic
//! observables' test). At each frame the stuck nodes form patches (runs of consecutive stuck
//! nodes). A **track** chains patches of consecutive frames that share a node stuck in both (a
//! stuck node holds its place on the ground, so the chained patches are one footprint that
//! grows at its front as the body lays down and shrinks at its back as it peels off). Its
//! points are the ground positions `(x, y)` of all its stuck samples; its direction is their
//! principal axis (the eigenvector of the larger eigenvalue of their 2x2 covariance) and its
//! length their extent along it.
//!
//! The angle of a track to the body axis is the angle between its direction and the mean unit
//! tail-to-head direction over the frames of the track (0 to 90 degrees, a direction having no
//! sign).

use crate::sim::Frame;

/// One ground track (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Track {
    /// First and last frame time (s).
    pub t: [f64; 2],
    /// Stuck samples (node-frames) in it.
    pub samples: usize,
    /// Unit direction of the principal axis in the ground plane.
    pub direction: [f64; 2],
    /// Extent of its points along that axis (m).
    pub length: f64,
    /// Angle between its direction and the mean tail-to-head direction over its frames
    /// (degrees, 0 to 90).
    pub angle_to_axis_deg: f64,
}

struct Open {
    nodes: Vec<usize>,
    points: Vec<[f64; 2]>,
    axis: [f64; 2],
    t: [f64; 2],
}

fn close(o: Open) -> Track {
    let n = o.points.len() as f64;
    let (mx, my) = o
        .points
        .iter()
        .fold((0.0, 0.0), |(a, b), p| (a + p[0] / n, b + p[1] / n));
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for p in &o.points {
        let (dx, dy) = (p[0] - mx, p[1] - my);
        sxx += dx * dx;
        sxy += dx * dy;
        syy += dy * dy;
    }
    // Principal axis of [[sxx, sxy], [sxy, syy]]: angle 0.5 atan2(2 sxy, sxx - syy).
    let phi = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let d = [phi.cos(), phi.sin()];
    let along = o.points.iter().map(|p| d[0] * p[0] + d[1] * p[1]);
    let (lo, hi) = along.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), s| {
        (a.min(s), b.max(s))
    });
    let r = o.axis[0].hypot(o.axis[1]);
    let c = ((d[0] * o.axis[0] + d[1] * o.axis[1]) / r).abs().min(1.0);
    Track {
        t: o.t,
        samples: o.points.len(),
        direction: d,
        length: hi - lo,
        angle_to_axis_deg: c.acos().to_degrees(),
    }
}

/// The ground tracks of `frames` (module doc): a node is stuck when `in_contact(normal)` and
/// its horizontal speed is at most `stuck_speed` (m/s). Tracks in the order they end.
pub fn tracks(frames: &[Frame], stuck_speed: f64, in_contact: &dyn Fn(f64) -> bool) -> Vec<Track> {
    let mut done = Vec::new();
    let mut open: Vec<Open> = Vec::new();
    for fr in frames {
        let stuck: Vec<bool> =
            fr.v.iter()
                .zip(&fr.normal)
                .map(|(v, &n)| in_contact(n) && v[0].hypot(v[1]) <= stuck_speed)
                .collect();
        let ax = {
            let (h, t) = (fr.x[0], fr.x[fr.x.len() - 1]);
            let (dx, dy) = (h[0] - t[0], h[1] - t[1]);
            let r = dx.hypot(dy);
            [dx / r, dy / r]
        };
        // Patches of this frame.
        let mut patches: Vec<Vec<usize>> = Vec::new();
        for (i, &s) in stuck.iter().enumerate() {
            if s {
                match patches.last_mut() {
                    Some(p) if *p.last().unwrap() + 1 == i => p.push(i),
                    _ => patches.push(vec![i]),
                }
            }
        }
        let mut next: Vec<Open> = Vec::new();
        for p in patches {
            // Every open track sharing a node with this patch joins it.
            let mut joined: Option<Open> = None;
            let mut k = 0;
            while k < open.len() {
                if open[k].nodes.iter().any(|i| p.contains(i)) {
                    let o = open.swap_remove(k);
                    joined = Some(match joined {
                        None => o,
                        Some(mut j) => {
                            j.points.extend(o.points);
                            j.axis = [j.axis[0] + o.axis[0], j.axis[1] + o.axis[1]];
                            j.t = [j.t[0].min(o.t[0]), j.t[1].max(o.t[1])];
                            j
                        }
                    });
                } else {
                    k += 1;
                }
            }
            let mut o = joined.unwrap_or(Open {
                nodes: Vec::new(),
                points: Vec::new(),
                axis: [0.0, 0.0],
                t: [fr.t, fr.t],
            });
            o.points.extend(p.iter().map(|&i| [fr.x[i][0], fr.x[i][1]]));
            o.axis = [o.axis[0] + ax[0], o.axis[1] + ax[1]];
            o.t[1] = fr.t;
            o.nodes = p;
            next.push(o);
        }
        // Tracks no patch continued have ended.
        done.extend(open.drain(..).map(close));
        open = next;
    }
    done.extend(open.into_iter().map(close));
    done
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A straight body along x (head at +x) whose nodes `lo..hi` are stuck, the others in
    /// contact and sliding at 1 m/s.
    fn frame(t: f64, n: usize, shift: [f64; 2], lo: usize, hi: usize) -> Frame {
        Frame {
            t,
            x: (0..n)
                .map(|i| [shift[0] - i as f64 * 0.01, shift[1], 0.01])
                .collect(),
            theta: vec![0.0; n - 1],
            v: (0..n)
                .map(|i| {
                    if (lo..hi).contains(&i) {
                        [0.0; 3]
                    } else {
                        [0.0, 1.0, 0.0]
                    }
                })
                .collect(),
            normal: vec![1.0; n],
            d1: vec![[0.0, 0.0, 1.0]; n - 1],
        }
    }

    #[test]
    fn a_patch_that_travels_along_the_body_lays_a_track_along_it() {
        // The stuck window moves one node per frame toward the tail: one track along x.
        let fr: Vec<Frame> = (0..10)
            .map(|k| frame(k as f64, 30, [0.0, 0.0], k, k + 5))
            .collect();
        let tr = tracks(&fr, 0.1, &|n| n > 0.5);
        assert_eq!(tr.len(), 1, "{tr:?}");
        assert_eq!(tr[0].samples, 50);
        assert!((tr[0].length - 0.13).abs() < 1e-12, "{tr:?}");
        assert!(tr[0].angle_to_axis_deg < 1e-6);
        // Patches that share no node with the last frame's start new tracks.
        let fr: Vec<Frame> = (0..4)
            .map(|k| frame(k as f64, 30, [0.0, 0.0], 6 * k, 6 * k + 3))
            .collect();
        assert_eq!(tracks(&fr, 0.1, &|n| n > 0.5).len(), 4);
    }

    #[test]
    fn a_stuck_point_swept_across_the_body_lays_a_track_across_it() {
        // The body (along x) moves +y by 0.01 per frame; nodes 3 and 4 are stuck in every
        // frame, node 3 held at y = 0, node 4 laid down a little further each frame: the
        // stuck points spread along y (0.075) far more than along x (0.01).
        let fr: Vec<Frame> = (0..8)
            .map(|k| {
                let mut f = frame(k as f64, 10, [0.0, 0.01 * k as f64], 3, 5);
                f.x[3][1] = 0.0;
                f.x[4][1] = 0.01 * k as f64 + 0.005;
                f
            })
            .collect();
        let tr = tracks(&fr, 0.1, &|n| n > 0.5);
        assert_eq!(tr.len(), 1);
        // Points: node 3 at (-0.03, 0), node 4 at (-0.04, 0.005 .. 0.075): mostly along y.
        assert!(tr[0].angle_to_axis_deg > 60.0, "{tr:?}");
    }
}
