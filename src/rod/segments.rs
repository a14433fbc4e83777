//! Geometry of pairs of edges (segments): closest points and a sort-and-sweep broad phase.
//!
//! The self-contact of [`crate::energy::self_contact`] needs, for two edges of the body, the
//! closest points `p(s) = x_i + s (x_{i+1} - x_i)` and `r(t) = x_j + t (x_{j+1} - x_j)`
//! (`s, t` in `[0, 1]`) and their distance, and, for a whole rod, the pairs of edges whose
//! bounding boxes overlap.
//!
//! * [`closest`]: the minimiser of `|p(s) - r(t)|` over the unit square, by the usual clamped
//!   line-line solution (the unconstrained minimiser, clamped to an edge of the square and
//!   re-minimised along it). Where the two edges are parallel the minimiser is not unique; the
//!   distance is, and `s` is then taken at the middle of the overlap of the two edges'
//!   projections (continuous as the edges slide along each other).
//! * [`SortAndSweep`]: boxes sorted by their lower `x`, swept once; the order is kept between
//!   calls, and Rust's stable sort finds an almost sorted order in one pass, so a broad phase
//!   over a body that moved a little costs about one pass over the edges plus the pairs.
//!   The edges of a rod are boxes of one size, which sort-and-sweep handles as well as a tree
//!   would; the self-contact's cost on scenes that never come close is measured in the guide
//!   (chapter "Self-contact").

use super::vec3::f;

/// The closest points of two segments.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closest {
    /// Parameter of the closest point on the first segment, in `[0, 1]`.
    pub s: f64,
    /// Parameter of the closest point on the second segment, in `[0, 1]`.
    pub t: f64,
    /// `p(s) - r(t)`.
    pub delta: [f64; 3],
    /// `|p(s) - r(t)|`.
    pub dist: f64,
}

fn clamp01(x: f64) -> f64 {
    x.clamp(0.0, 1.0)
}

/// Closest points of the segments `p0 p1` and `q0 q1` (both of positive length).
pub fn closest(p0: [f64; 3], p1: [f64; 3], q0: [f64; 3], q1: [f64; 3]) -> Closest {
    let d1 = f::sub(p1, p0);
    let d2 = f::sub(q1, q0);
    let r = f::sub(p0, q0);
    let a = f::dot(d1, d1);
    let e = f::dot(d2, d2);
    let b = f::dot(d1, d2);
    let c = f::dot(d1, r);
    let g = f::dot(d2, r);
    let denom = a * e - b * b;
    let s0 = if denom > 1e-12 * a * e {
        clamp01((b * g - c * e) / denom)
    } else {
        // Parallel: the middle of the overlap of q's projection onto p's line with [0, 1].
        let lo = clamp01(-c / a);
        let hi = clamp01((b - c) / a);
        0.5 * (lo.min(hi) + lo.max(hi))
    };
    // The best t for s0, clamped; if clamped, the best s for that t.
    let mut s = s0;
    let mut t = (b * s + g) / e;
    if t < 0.0 {
        t = 0.0;
        s = clamp01(-c / a);
    } else if t > 1.0 {
        t = 1.0;
        s = clamp01((b - c) / a);
    }
    let p = f::add(p0, f::scale(d1, s));
    let q = f::add(q0, f::scale(d2, t));
    let delta = f::sub(p, q);
    Closest {
        s,
        t,
        delta,
        dist: f::norm(delta),
    }
}

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub lo: [f64; 3],
    /// Upper corner.
    pub hi: [f64; 3],
}

impl Aabb {
    /// The box of the points `pts`, grown by `pad` on every side.
    pub fn around(pts: &[[f64; 3]], pad: f64) -> Self {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in pts {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        for k in 0..3 {
            lo[k] -= pad;
            hi[k] += pad;
        }
        Aabb { lo, hi }
    }
    /// Whether the boxes overlap on `y` and `z` (the sweep has settled `x`).
    fn overlap_yz(&self, o: &Aabb) -> bool {
        self.lo[1] <= o.hi[1]
            && o.lo[1] <= self.hi[1]
            && self.lo[2] <= o.hi[2]
            && o.lo[2] <= self.hi[2]
    }
}

/// Sort-and-sweep over boxes along `x`, keeping the order between calls.
#[derive(Clone, Debug, Default)]
pub struct SortAndSweep {
    order: Vec<usize>,
}

impl SortAndSweep {
    /// The pairs `(i, j)`, `i < j`, of overlapping boxes for which `keep(i, j)` holds, into
    /// `out` (cleared first), sorted.
    pub fn pairs(
        &mut self,
        boxes: &[Aabb],
        keep: &dyn Fn(usize, usize) -> bool,
        out: &mut Vec<(usize, usize)>,
    ) {
        out.clear();
        if self.order.len() != boxes.len() {
            self.order = (0..boxes.len()).collect();
        }
        // Stable merge sort: one pass on an already sorted order.
        self.order
            .sort_by(|&i, &j| boxes[i].lo[0].total_cmp(&boxes[j].lo[0]));
        for (a, &i) in self.order.iter().enumerate() {
            let bi = &boxes[i];
            for &j in &self.order[a + 1..] {
                let bj = &boxes[j];
                if bj.lo[0] > bi.hi[0] {
                    break;
                }
                if bi.overlap_yz(bj) {
                    let (lo, hi) = if i < j { (i, j) } else { (j, i) };
                    if keep(lo, hi) {
                        out.push((lo, hi));
                    }
                }
            }
        }
        out.sort_unstable();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::fd::uniform as pseudo;

    /// The closest points beat a fine grid search over the unit square (and the distance is
    /// attained by the returned points), for random segments, parallel ones and crossing ones.
    #[test]
    fn closest_points_beat_a_grid_search() {
        let mut seed = 0x2545_F491_4F6C_DD1D;
        let mut cases = Vec::new();
        for _ in 0..200 {
            let mut p = || [pseudo(&mut seed), pseudo(&mut seed), pseudo(&mut seed)];
            cases.push((p(), p(), p(), p()));
        }
        // Parallel, overlapping and not; collinear; crossing.
        cases.push((
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.3, 0.5, 0.0],
            [1.6, 0.5, 0.0],
        ));
        cases.push((
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.5, 0.0],
            [3.0, 0.5, 0.0],
        ));
        cases.push((
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.5, 0.0, 0.0],
            [2.5, 0.0, 0.0],
        ));
        cases.push((
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, -0.5, 0.2],
            [0.5, 0.5, 0.2],
        ));
        for (p0, p1, q0, q1) in cases {
            let c = closest(p0, p1, q0, q1);
            let at = |s: f64, t: f64| {
                let p = f::add(p0, f::scale(f::sub(p1, p0), s));
                let q = f::add(q0, f::scale(f::sub(q1, q0), t));
                f::norm(f::sub(p, q))
            };
            assert!((at(c.s, c.t) - c.dist).abs() < 1e-12);
            let mut best = f64::INFINITY;
            for a in 0..=200 {
                for b in 0..=200 {
                    best = best.min(at(a as f64 / 200.0, b as f64 / 200.0));
                }
            }
            assert!(
                c.dist <= best + 1e-12,
                "{p0:?} {p1:?} {q0:?} {q1:?}: {} > {best}",
                c.dist
            );
            assert!(
                c.dist >= best - 1e-2,
                "grid far below: {} vs {best}",
                c.dist
            );
        }
    }

    /// The sweep finds exactly the overlapping pairs a double loop finds, on a second call
    /// with moved boxes too.
    #[test]
    fn sweep_matches_all_pairs() {
        let mut seed = 0x9E37_79B9_7F4A_7C15;
        let mut sweep = SortAndSweep::default();
        for round in 0..3 {
            let boxes: Vec<Aabb> = (0..80)
                .map(|_| {
                    let c = [pseudo(&mut seed), pseudo(&mut seed), pseudo(&mut seed)];
                    Aabb::around(&[c], 0.05 + 0.02 * round as f64)
                })
                .collect();
            let keep = |i: usize, j: usize| j > i + 2;
            let mut got = Vec::new();
            sweep.pairs(&boxes, &keep, &mut got);
            let mut want = Vec::new();
            for i in 0..boxes.len() {
                for j in i + 1..boxes.len() {
                    let (a, b) = (&boxes[i], &boxes[j]);
                    let overlap = (0..3).all(|k| a.lo[k] <= b.hi[k] && b.lo[k] <= a.hi[k]);
                    if overlap && keep(i, j) {
                        want.push((i, j));
                    }
                }
            }
            assert_eq!(got, want, "round {round}");
            assert!(!want.is_empty());
        }
    }
}
