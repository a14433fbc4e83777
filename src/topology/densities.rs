//! Local twist, writhe and link densities over arc-length windows, the writhe by sliding
//! windows.

use super::*;

/// Local twist, writhe and link densities over arc-length windows
/// `[s, s + delta]` (see [`Densities`]).
///
/// * `tau`: the twist angle of each vertex is spread uniformly over its
///   Voronoi cell (half of each adjacent edge), giving a piecewise-constant
///   twist density `phi_j / ((l_{j-1} + l_j) / 2)`; `tau` is its integral over
///   the window, in turns, divided by `delta`. For open curves the end
///   half-edges (which have no vertex) carry the density of the nearest
///   vertex, so a uniformly twisted rod has uniform `tau` everywhere.
/// * `omega`: exact writhe (see [`writhe`]) of the open sub-polygon from the
///   window's start node to the point at arc length `s + delta` (interpolated
///   on its edge), divided by `delta`.
/// * `lambda = tau + omega`.
///
/// Windows start at each node; for open curves only windows ending inside the
/// curve are kept, for closed curves windows wrap around (requires
/// `delta <= total length`). Returns empty vectors if `delta` is not positive
/// and finite or no window fits.
///
/// *Cost.* The writhe of consecutive windows is computed by sliding: the sum
/// over the window's whole edges is updated by adding the pairs of the edge
/// entering the window and removing those of the edge leaving it, and only the
/// pairs of the interpolated last (partial) edge are summed afresh. With `w`
/// edges per window this is `O(n w)` pair evaluations for all windows
/// (`O(n^2)` at most), not `O(n w^2)`. The result equals [`writhe`] of each
/// window's sub-polygon up to round-off (the sliding sum adds and subtracts
/// the same terms; `tests` checks it against the direct sum to 1e-12).
///
/// # Panics
/// If `c.d1.len()` does not match the edge count.
pub fn densities(c: &FramedCurve, delta: f64) -> Densities {
    densities_windows(c, delta, None)
}

/// Like [`densities`] for an open curve, but with exactly `count` windows, starting at nodes
/// `0 .. count` (at most one per node but the last): a window that would run past the
/// curve's end is **shortened** to end there, and its densities are divided by its actual
/// length `total - s` instead of `delta`. A run's kymographs use this so that every frame has
/// the same windows even when the body is compressed slightly and the last window no longer
/// fits (the windows are laid out once, on the rest length). Closed curves: as [`densities`].
///
/// # Panics
/// If `c.d1.len()` does not match the edge count.
pub fn densities_shortened(c: &FramedCurve, delta: f64, count: usize) -> Densities {
    if c.closed {
        return densities(c, delta);
    }
    densities_windows(c, delta, Some(count))
}

/// Sliding sum of the solid angles of all non-adjacent pairs of the whole edges
/// `lo .. hi` (unwrapped edge indices, edge `k` = edge `k mod m`) of a polygon.
pub(super) struct SlidingWrithe<'a> {
    nodes: &'a [V3],
    m: usize,
    lo: usize,
    hi: usize,
    sum: f64,
}

impl SlidingWrithe<'_> {
    fn edge(&self, k: usize) -> (V3, V3) {
        let n = self.nodes.len();
        let e = k % self.m;
        (self.nodes[e], self.nodes[(e + 1) % n])
    }

    /// Grow the window to the whole edges `lo .. hi`, then drop edges below `lo`.
    fn slide_to(&mut self, lo: usize, hi: usize) {
        while self.hi < hi {
            let (b0, b1) = self.edge(self.hi);
            for a in self.lo..self.hi.saturating_sub(1) {
                let (a0, a1) = self.edge(a);
                self.sum += pair_solid_angle(&a0, &a1, &b0, &b1);
            }
            self.hi += 1;
        }
        while self.lo < lo {
            let (a0, a1) = self.edge(self.lo);
            for b in self.lo + 2..self.hi {
                let (b0, b1) = self.edge(b);
                self.sum -= pair_solid_angle(&a0, &a1, &b0, &b1);
            }
            self.lo += 1;
        }
    }
}

pub(super) fn densities_windows(c: &FramedCurve, delta: f64, count: Option<usize>) -> Densities {
    check_curve(c);
    let mut out = Densities::default();
    let n = c.nodes.len();
    let m = edge_count(n, c.closed);
    if m == 0 || !delta.is_finite() || delta <= 0.0 {
        return out;
    }
    let t = tangents(&c.nodes, c.closed);
    let lens: Vec<f64> = (0..m)
        .map(|e| norm(&sub(&c.nodes[(e + 1) % n], &c.nodes[e])))
        .collect();
    let mut s_node = vec![0.0; m + 1];
    for e in 0..m {
        s_node[e + 1] = s_node[e] + lens[e];
    }
    let total = s_node[m];
    if !total.is_finite() || total <= 0.0 {
        return out;
    }
    let tol = 1e-12 * total.max(delta);
    // Arc length of unwrapped node k (closed curves continue past the end).
    let s_u = |k: usize| {
        if k <= m {
            s_node[k]
        } else {
            total + s_node[k - m]
        }
    };

    // piecewise-constant twist density, as sorted contiguous cells (start, end, rad per
    // length) covering [0, total], with the cumulative integral at each cell start.
    let mut cells: Vec<(f64, f64, f64)> = Vec::new();
    let rho = |prev: usize, e: usize| {
        let lbar = 0.5 * (lens[prev] + lens[e]);
        if lbar > 0.0 {
            vertex_angle(&t[prev], &c.d1[prev], &t[e], &c.d1[e]) / lbar
        } else {
            0.0
        }
    };
    if c.closed {
        let r0 = rho(m - 1, 0);
        cells.push((0.0, 0.5 * lens[0], r0));
        for j in 1..m {
            cells.push((
                s_node[j] - 0.5 * lens[j - 1],
                s_node[j] + 0.5 * lens[j],
                rho(j - 1, j),
            ));
        }
        cells.push((total - 0.5 * lens[m - 1], total, r0));
    } else {
        for j in 1..m {
            let a = if j == 1 {
                0.0
            } else {
                s_node[j] - 0.5 * lens[j - 1]
            };
            let b = if j == m - 1 {
                total
            } else {
                s_node[j] + 0.5 * lens[j]
            };
            cells.push((a, b, rho(j - 1, j)));
        }
    }
    let mut cum = Vec::with_capacity(cells.len() + 1);
    cum.push(0.0);
    for &(a, b, r) in &cells {
        cum.push(cum.last().unwrap() + r * (b - a));
    }
    // Integral of the twist density from 0 to x (clamped to [0, total]).
    let upto = |x: f64| -> f64 {
        if cells.is_empty() || x <= 0.0 {
            return 0.0;
        }
        let k = cells.partition_point(|&(a, _, _)| a <= x).saturating_sub(1);
        let (a, b, r) = cells[k];
        cum[k] + r * (x.min(b) - a).max(0.0)
    };
    let integrate = |a: f64, b: f64| upto(b) - upto(a);

    if c.closed && delta > total + tol {
        return out;
    }
    let mut slide = SlidingWrithe {
        nodes: &c.nodes,
        m,
        lo: 0,
        hi: 0,
        sum: 0.0,
    };
    let last_start = match count {
        Some(k) => k.min(m),
        None => n,
    };
    let mut j = 0;
    for (i, &a) in s_node.iter().enumerate().take(last_start) {
        let mut b = a + delta;
        let mut shortened = false;
        if !c.closed && b > total + tol {
            if count.is_none() {
                break;
            }
            b = total;
            shortened = true;
        }
        let twist_rad = if b > total {
            integrate(a, total) + integrate(0.0, b - total)
        } else {
            integrate(a, b)
        };
        // The window's sub-polygon: nodes i ..= j (unwrapped), then the point at arc
        // length b on edge j if it lies beyond node j.
        j = j.max(i);
        while !(s_u(j + 1) >= b - tol || j + 1 == i + m) {
            j += 1;
        }
        slide.slide_to(i, j);
        let mut w = slide.sum;
        if b - s_u(j) > tol {
            let e = j % m;
            let start = &c.nodes[e];
            let stop = &c.nodes[(e + 1) % n];
            let frac = if lens[e] > 0.0 {
                ((b - s_u(j)) / lens[e]).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let p = add(start, &scale(&sub(stop, start), frac));
            for k in i..j.saturating_sub(1) {
                let (a0, a1) = slide.edge(k);
                w += pair_solid_angle(&a0, &a1, start, &p);
            }
        }
        // A full window is `delta` long even where `a + delta` rounds to `a` (arc lengths far
        // beyond `delta`: a curve with one node at 1e26 m gave 0 / 0).
        let len = if shortened { b - a } else { delta };
        let tau = twist_rad / (2.0 * PI) / len;
        let omega = w / (2.0 * PI) / len;
        out.s.push(a);
        out.tau.push(tau);
        out.omega.push(omega);
        out.lambda.push(tau + omega);
    }
    out
}
