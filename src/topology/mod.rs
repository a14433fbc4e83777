//! Topology of framed curves: twist, writhe and linking number of a discrete
//! ribbon (a polygon `r_0 .. r_{n-1}` carrying one unit director `d1` per edge).
//!
//! # Equations
//!
//! **Edges and tangents.** Edge `i` runs from `r_i` to `r_{i+1}` (for closed
//! curves indices are taken mod `n`, so the last edge runs from `r_{n-1}` back
//! to `r_0`); `t_i = (r_{i+1} - r_i) / |r_{i+1} - r_i|`.
//!
//! **Twist** (discrete, vertex based). At every vertex joining edges `i-1`
//! and `i` (and, for closed curves, also the wrap-around pair `n-1, 0`) the
//! director of edge `i-1` is parallel-transported onto edge `i` by the
//! rotation about `t_{i-1} x t_i` that takes `t_{i-1}` to `t_i`:
//!
//! ```text
//! P u = c u + v x u + (v . u) / (1 + c) v,     c = t_{i-1} . t_i,  v = t_{i-1} x t_i
//! phi_i = atan2( t_i . (p x q), p . q ),      p = (P d1_{i-1})_perp,  q = (d1_i)_perp
//! Tw = (1 / 2 pi) sum_i phi_i                 [turns]
//! ```
//!
//! where `_perp` is the component perpendicular to `t_i` (so directors need only
//! be approximately perpendicular to their edges).
//!
//! **Writhe** (exact for polygons, Klenin & Langowski 2000). For two segments
//! `(r_1 -> r_2)` and `(r_3 -> r_4)` let `r_ab = r_b - r_a` and
//!
//! ```text
//! n_1 = r_13 x r_14 / |.|,  n_2 = r_14 x r_24 / |.|,  n_3 = r_24 x r_23 / |.|,  n_4 = r_23 x r_13 / |.|
//! Omega* = asin(n_1.n_2) + asin(n_2.n_3) + asin(n_3.n_4) + asin(n_4.n_1)
//! Omega  = Omega* sign( (r_34 x r_12) . r_13 )
//! ```
//!
//! `Omega / 4 pi` is exactly the Gauss double integral
//! `(1/4 pi) \int\int (x - y) . (dx x dy) / |x - y|^3` over the two segments.
//! Then
//!
//! ```text
//! Wr = (1 / 4 pi) sum_{i != j, non-adjacent} Omega_ij = 2 sum_{i < j} Omega_ij / (4 pi)
//! ```
//!
//! (adjacent segments are coplanar and contribute nothing; for open curves all
//! pairs of edges sharing no node are summed).
//!
//! *Numerical evaluation.* `Omega` is the solid angle, seen from the origin, of
//! the quadrilateral `r_13, r_14, r_24, r_23`, which is the planar
//! parallelogram `{y - x}`. The arcsine sum above is ill-conditioned for nearly
//! collinear segment pairs (a straight rod away from the origin gets
//! `|Wr| ~ 1e-2` from round-off), so the code evaluates the *same* `Omega` as
//! the sum of the two triangles `(r_13, r_14, r_24)`, `(r_13, r_24, r_23)`
//! with the Van Oosterom–Strackee formula
//! `tan(W/2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|)`,
//! with K-L's sign convention. The tests check it against the literal
//! Klenin–Langowski formula and against quadrature of the Gauss integral.
//! Degenerate (parallel / coplanar) pairs contribute 0.
//!
//! **Linking number.** For closed curves `Lk` is the Gauss linking number of
//! the polygon `r` and its push-off polygon `r + eps w`, computed with the same
//! exact solid-angle formula summed over *all* pairs (edge of `r`, edge of the
//! push-off): `Lk = (1 / 4 pi) sum_{i,j} Omega(r-edge i, push-off edge j)`.
//! Being an exact sum of solid angles of two disjoint closed polygons, it is an
//! integer up to round-off.
//!
//! **White's theorem** (Călugăreanu–White–Fuller): `Lk = Tw + Wr`.
//! For closed polygons with the twist above and the exact polygon writhe,
//! `Tw + Wr` is an integer up to round-off (the parallel-transport holonomy
//! around the closed polygon is exactly compensated by the polygon writhe,
//! Fuller's relation applied to the geodesic tangent indicatrix), and it equals
//! the Gauss linking number with a sufficiently small push-off.
//!
//! # References
//!
//! * K. Klenin and J. Langowski, "Computation of writhe in modeling of
//!   supercoiled DNA", *Biopolymers* **54**, 307–317 (2000), eqs. 13–16.
//! * J. H. White, "Self-linking and the Gauss integral in higher dimensions",
//!   *Am. J. Math.* **91**, 693–728 (1969): `Lk = Tw + Wr`.
//! * F. B. Fuller, "The writhing number of a space curve", *PNAS* **68**,
//!   815–819 (1971).
//! * A. van Oosterom and J. Strackee, "The solid angle of a plane triangle",
//!   *IEEE Trans. Biomed. Eng.* **30**, 125–126 (1983).

use std::f64::consts::PI;
use std::fmt;

type V3 = [f64; 3];

// ---------------------------------------------------------------------------
// small vector helpers
// ---------------------------------------------------------------------------

#[inline(always)]
fn sub(a: &V3, b: &V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline(always)]
fn add(a: &V3, b: &V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

#[inline(always)]
fn scale(a: &V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

#[inline(always)]
fn dot(a: &V3, b: &V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
fn cross(a: &V3, b: &V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[inline(always)]
fn norm(a: &V3) -> f64 {
    dot(a, a).sqrt()
}

/// Unit vector along `a`, or `None` if `a` is zero (or not finite).
#[inline(always)]
fn unit(a: &V3) -> Option<V3> {
    let l = norm(a);
    if l > 0.0 && l.is_finite() {
        Some(scale(a, 1.0 / l))
    } else {
        None
    }
}

/// Unit vector along `a`, or the zero vector if `a` is zero.
#[inline(always)]
fn unit_or_zero(a: &V3) -> V3 {
    unit(a).unwrap_or([0.0; 3])
}

/// Component of `u` perpendicular to the unit vector `t`.
#[inline(always)]
fn reject(u: &V3, t: &V3) -> V3 {
    sub(u, &scale(t, dot(u, t)))
}

/// Some unit vector perpendicular to the unit vector `t` (deterministic).
fn any_perpendicular(t: &V3) -> V3 {
    let (ax, ay, az) = (t[0].abs(), t[1].abs(), t[2].abs());
    let e = if ax <= ay && ax <= az {
        [1.0, 0.0, 0.0]
    } else if ay <= az {
        [0.0, 1.0, 0.0]
    } else {
        [0.0, 0.0, 1.0]
    };
    unit(&cross(t, &e)).unwrap_or([1.0, 0.0, 0.0])
}

// ---------------------------------------------------------------------------
// public types
// ---------------------------------------------------------------------------

/// A framed curve: nodes `r_0..r_{n-1}` and one unit director `d1` per edge
/// (perpendicular to the edge, approximately).
///
/// * open (`closed == false`): edges `i = 0..n-2` run from node `i` to node
///   `i+1`, and `d1.len() == n - 1`;
/// * closed (`closed == true`): edges `i = 0..n-1`, the last one from node
///   `n-1` back to node 0, and `d1.len() == n`.
///
/// Edges must have nonzero length; directors need not be exactly unit or
/// exactly perpendicular (only their component perpendicular to the edge is
/// used).
#[derive(Debug, Clone, PartialEq)]
pub struct FramedCurve {
    /// Node positions `r_i`.
    pub nodes: Vec<[f64; 3]>,
    /// Director `d1` of each edge (edge `i` starts at node `i`).
    pub d1: Vec<[f64; 3]>,
    /// Whether the curve is closed (last edge joins node `n-1` to node 0).
    pub closed: bool,
}

/// Twist, writhe and linking number of a framed curve (all in turns).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Topology {
    /// Total twist `Tw` of the ribbon `(r, d1)`, see [`twist`].
    pub tw: f64,
    /// Writhe `Wr` of the node polygon, see [`writhe`].
    pub wr: f64,
    /// `Lk = Tw + Wr` (White's theorem); an integer for closed curves.
    pub lk: f64,
}

/// Local densities over windows `[s, s+delta]` of arc length: `tau` = twist of
/// the sub-ribbon in the window, `omega` = writhe of the sub-curve in the
/// window (treated as an open curve), `lambda = tau + omega`; all per unit
/// length (turns per unit length, i.e. divided by `delta`). `s` = arc length of
/// the window start; one window starts at each node whose window fits inside
/// the curve (open curves) or at every node, wrapping around (closed curves).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Densities {
    /// Arc length of each window's start node.
    pub s: Vec<f64>,
    /// Local linking density `tau + omega` [turns / length].
    pub lambda: Vec<f64>,
    /// Local twist density [turns / length].
    pub tau: Vec<f64>,
    /// Local writhe density [turns / length].
    pub omega: Vec<f64>,
}

/// Error from [`parse_curve_csv`]: 1-based line number and a description.
#[derive(Debug)]
pub struct CsvError {
    /// 1-based line number of the offending line in the input text.
    pub line: usize,
    /// What is wrong with that line (or with the input as a whole).
    pub message: String,
}

impl fmt::Display for CsvError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}

impl std::error::Error for CsvError {}

// ---------------------------------------------------------------------------
// internals
// ---------------------------------------------------------------------------

/// Number of edges of a polygon with `n` nodes.
#[inline]
fn edge_count(n: usize, closed: bool) -> usize {
    if n < 2 {
        0
    } else if closed {
        n
    } else {
        n - 1
    }
}

/// Panics unless the director count matches the edge convention.
fn check_curve(c: &FramedCurve) {
    let n = c.nodes.len();
    let expected = if c.closed { n } else { n.saturating_sub(1) };
    assert!(
        c.d1.len() == expected,
        "FramedCurve: {} nodes ({}) need {} directors, got {}",
        n,
        if c.closed { "closed" } else { "open" },
        expected,
        c.d1.len()
    );
}

/// Unit tangents of all edges (zero vector for zero-length edges).
fn tangents(nodes: &[V3], closed: bool) -> Vec<V3> {
    let n = nodes.len();
    (0..edge_count(n, closed))
        .map(|e| unit_or_zero(&sub(&nodes[(e + 1) % n], &nodes[e])))
        .collect()
}

/// Parallel transport of `u` from unit tangent `t1` to unit tangent `t2`
/// (rotation about `t1 x t2` taking `t1` to `t2`).
#[inline]
fn transport(t1: &V3, t2: &V3, u: &V3) -> V3 {
    let c = dot(t1, t2);
    if 1.0 + c <= 1e-12 {
        // Cusp (edges antiparallel): the transport is ill-defined; use the
        // rotation by pi about a fixed axis perpendicular to t1.
        let a = any_perpendicular(t1);
        return sub(&scale(&a, 2.0 * dot(&a, u)), u);
    }
    let v = cross(t1, t2);
    let vxu = cross(&v, u);
    let k = dot(&v, u) / (1.0 + c);
    [
        c * u[0] + vxu[0] + k * v[0],
        c * u[1] + vxu[1] + k * v[1],
        c * u[2] + vxu[2] + k * v[2],
    ]
}

/// Signed twist angle (radians, in (-pi, pi]) at the vertex joining the edge
/// (`t_prev`, `d_prev`) to the edge (`t`, `d`).
#[inline]
fn vertex_angle(t_prev: &V3, d_prev: &V3, t: &V3, d: &V3) -> f64 {
    let p = reject(&transport(t_prev, t, d_prev), t);
    let q = reject(d, t);
    dot(t, &cross(&p, &q)).atan2(dot(&p, &q))
}

/// Relative tolerance below which a segment pair counts as coplanar in
/// [`pair_solid_angle`]: `|r_13 . (r_12 x r_34)| <= 1e-12 |r_12| |r_34| max|r_ij|`, i.e. the
/// two segments lie in one plane to about 1e-12 of their size (round-off of coordinates that
/// are coplanar by construction, such as a planar curve rotated in space).
pub const COPLANAR_TOL: f64 = 1e-12;

/// Signed solid angle of the triangle `(a, b, c)` seen from the origin
/// (Van Oosterom & Strackee 1983): `tan(W/2) = a.(b x c) / (|a||b||c| +
/// (a.b)|c| + (a.c)|b| + (b.c)|a|)`; result in `(-2 pi, 2 pi)`.
#[inline(always)]
fn triangle_solid_angle(a: &V3, b: &V3, c: &V3) -> f64 {
    let (la, lb, lc) = (norm(a), norm(b), norm(c));
    let num = dot(a, &cross(b, c));
    let den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
    2.0 * num.atan2(den)
}

/// Signed solid angle `Omega` of the segment pair `(p1 -> p2)`, `(p3 -> p4)`
/// (Klenin & Langowski 2000, eqs. 13-16); the Gauss integral over the pair
/// equals `Omega / (4 pi)`. No allocation.
///
/// `Omega` is the solid angle, seen from the origin, of the quadrilateral
/// `r_13, r_14, r_24, r_23`, which is the planar parallelogram
/// `{y - x : x in [p1,p2], y in [p3,p4]}`. Instead of Klenin–Langowski's
/// arcsine sum over face normals (which is ill-conditioned for nearly
/// collinear segments: a straight rod away from the origin can get a writhe
/// of order 1e-2 from round-off), the same `Omega` is evaluated as the sum of
/// the two triangles `(r_13, r_14, r_24)` and `(r_13, r_24, r_23)` with the
/// atan2 triangle formula, accurate to round-off in every configuration.
/// The sign convention is K-L's: `sign(Omega) = sign((r_34 x r_12) . r_13)`.
/// Degenerate (coplanar, parallel, collinear) pairs give 0 (to round-off).
#[inline]
fn pair_solid_angle(p1: &V3, p2: &V3, p3: &V3, p4: &V3) -> f64 {
    let r13 = sub(p3, p1);
    let r14 = sub(p4, p1);
    let r23 = sub(p3, p2);
    let r24 = sub(p4, p2);
    // Coplanar pairs (to round-off, `COPLANAR_TOL` relative) contribute their principal
    // value 0: the integrand `(x - y) . (dx x dy)` vanishes on the plane, and for segments that
    // cross each other the two one-sided limits (+2 pi, -2 pi, the curve passing just above or
    // just below) average to 0. Without this a crossing gives +-2 pi from the sign of a
    // rounded zero (a planar figure eight got writhe 1).
    let r12 = sub(p2, p1);
    let r34 = sub(p4, p3);
    let scale_ = norm(&r12) * norm(&r34) * norm(&r13).max(norm(&r14)).max(norm(&r23));
    if dot(&r13, &cross(&r12, &r34)).abs() <= COPLANAR_TOL * scale_ {
        return 0.0;
    }
    // The parallelogram r_13 -> r_14 -> r_24 -> r_23 is traversed clockwise as
    // seen from the origin when K-L's sign is positive, hence the minus sign.
    let w = -(triangle_solid_angle(&r13, &r14, &r24) + triangle_solid_angle(&r13, &r24, &r23));
    if w.is_finite() {
        w
    } else {
        0.0
    }
}

/// Push-off direction at each node of a closed curve: the average of the two
/// adjacent edges' directors, each made perpendicular to the vertex tangent
/// `T = unit(t_{j-1} + t_j)` and normalised, then renormalised.
fn push_off_directions(c: &FramedCurve, t: &[V3]) -> Vec<V3> {
    let n = c.nodes.len();
    (0..n)
        .map(|j| {
            let prev = (j + n - 1) % n;
            let tv = unit(&add(&t[prev], &t[j])).unwrap_or(t[j]);
            let a = unit_or_zero(&reject(&c.d1[prev], &tv));
            let b = unit_or_zero(&reject(&c.d1[j], &tv));
            unit(&add(&a, &b))
                .or_else(|| unit(&b))
                .or_else(|| unit(&a))
                .unwrap_or_else(|| any_perpendicular(&tv))
        })
        .collect()
}

// ---------------------------------------------------------------------------
// public functions
// ---------------------------------------------------------------------------

/// Total twist of the ribbon `(r, d1)`, in turns: the sum over vertices of the
/// signed angle between the parallel-transported director of the previous edge
/// and the director of the next edge, divided by `2 pi` (see module docs).
/// Closed curves include the wrap-around vertex (edge `n-1` to edge 0).
///
/// # Panics
/// If `c.d1.len()` does not match the edge count (`n-1` open, `n` closed).
pub fn twist(c: &FramedCurve) -> f64 {
    check_curve(c);
    let m = edge_count(c.nodes.len(), c.closed);
    if m < 2 {
        return 0.0;
    }
    let t = tangents(&c.nodes, c.closed);
    let mut sum = 0.0;
    for e in 1..m {
        sum += vertex_angle(&t[e - 1], &c.d1[e - 1], &t[e], &c.d1[e]);
    }
    if c.closed {
        sum += vertex_angle(&t[m - 1], &c.d1[m - 1], &t[0], &c.d1[0]);
    }
    sum / (2.0 * PI)
}

/// Exact writhe of the polygon through `nodes` (closing edge from the last
/// node back to the first if `closed`), by the Klenin–Langowski solid-angle
/// formula: `Wr = 2 sum_{i<j} Omega_ij / (4 pi)` over all pairs of edges that
/// share no node. O(n^2) with no allocation.
pub fn writhe(nodes: &[[f64; 3]], closed: bool) -> f64 {
    let n = nodes.len();
    let m = edge_count(n, closed);
    let mut sum = 0.0;
    for i in 0..m {
        let a0 = &nodes[i];
        let a1 = &nodes[(i + 1) % n];
        // closed: edge 0 and edge m-1 share node 0
        let j_end = if closed && i == 0 {
            m.saturating_sub(1)
        } else {
            m
        };
        for j in (i + 2)..j_end {
            sum += pair_solid_angle(a0, a1, &nodes[j], &nodes[(j + 1) % n]);
        }
    }
    sum / (2.0 * PI)
}

/// Twist, writhe and `lk = tw + wr` of a framed curve.
///
/// # Panics
/// If `c.d1.len()` does not match the edge count.
pub fn topology(c: &FramedCurve) -> Topology {
    let tw = twist(c);
    let wr = writhe(&c.nodes, c.closed);
    Topology {
        tw,
        wr,
        lk: tw + wr,
    }
}

/// Gauss linking number of the closed polygon `r` and its push-off polygon
/// `r_j + eps w_j`, computed exactly with the Klenin–Langowski solid angle over
/// all pairs (edge of `r`, edge of the push-off).
///
/// Push-off direction `w_j` at node `j`: the directors of the two edges
/// meeting at `j` are each projected perpendicular to the vertex tangent
/// `unit(t_{j-1} + t_j)` and normalised; `w_j` is their normalised average.
/// `eps` should be small compared with the edge lengths and with the distance
/// of closest approach of non-adjacent parts of the curve; the result is then
/// an integer (up to round-off) equal to `twist(c) + writhe(..)`.
///
/// # Panics
/// If the curve is not closed or `c.d1.len() != c.nodes.len()`.
pub fn gauss_link(c: &FramedCurve, eps: f64) -> f64 {
    assert!(c.closed, "gauss_link is defined for closed curves only");
    check_curve(c);
    let n = c.nodes.len();
    if n < 3 {
        return 0.0;
    }
    let t = tangents(&c.nodes, true);
    let w = push_off_directions(c, &t);
    let q: Vec<V3> = c
        .nodes
        .iter()
        .zip(&w)
        .map(|(r, w)| add(r, &scale(w, eps)))
        .collect();
    let mut sum = 0.0;
    for i in 0..n {
        let a0 = &c.nodes[i];
        let a1 = &c.nodes[(i + 1) % n];
        for j in 0..n {
            sum += pair_solid_angle(a0, a1, &q[j], &q[(j + 1) % n]);
        }
    }
    sum / (4.0 * PI)
}

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
struct SlidingWrithe<'a> {
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

fn densities_windows(c: &FramedCurve, delta: f64, count: Option<usize>) -> Densities {
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
        if !c.closed && b > total + tol {
            if count.is_none() {
                break;
            }
            b = total;
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
        let len = b - a;
        let tau = twist_rad / (2.0 * PI) / len;
        let omega = w / (2.0 * PI) / len;
        out.s.push(a);
        out.tau.push(tau);
        out.omega.push(omega);
        out.lambda.push(tau + omega);
    }
    out
}

/// A closed curve's last row repeats its first node when they are closer than this fraction of
/// the mean edge length (such a row is dropped by [`parse_curve_csv`]).
pub const REPEAT_TOL: f64 = 1e-9;

/// [`parse_curve_csv`] rejects a director whose component perpendicular to its edge is at most
/// this fraction of its length (within about 1e-6 rad of the tangent): twist is measured from
/// that component, so it would be round-off.
pub const ALONG_TANGENT_TOL: f64 = 1e-6;

/// Parse CSV text: a header row, then rows `x,y,z,d1x,d1y,d1z` (row `i`'s
/// `d1` is the director of the edge starting at node `i`; for an open curve
/// the last row's `d1` is ignored). Blank lines are skipped; fields may be
/// surrounded by whitespace. A header `s,x,y,z,d1x,d1y,d1z` (the `final.csv` of
/// `slither run`) marks a leading arc-length column, which is skipped.
///
/// Errors carry the 1-based line number and say what is wrong: wrong field
/// count, a field that is not a number, a non-finite value, a zero director
/// (for rows whose director is used), a first line that looks like data
/// instead of a header, fewer than 3 data rows, a zero-length edge (a node repeated), or a
/// director along its edge's tangent (see [`ALONG_TANGENT_TOL`]).
///
/// With `closed`, a last row that repeats the first node (within [`REPEAT_TOL`] of the mean
/// edge length) is dropped: the closing edge is implied and must not be written twice.
pub fn parse_curve_csv(text: &str, closed: bool) -> Result<FramedCurve, CsvError> {
    const NAMES: [&str; 6] = ["x", "y", "z", "d1x", "d1y", "d1z"];
    let mut nodes: Vec<V3> = Vec::new();
    let mut d1: Vec<V3> = Vec::new();
    let mut row_lines: Vec<usize> = Vec::new();
    let mut last_line = 0;
    // A leading `s` column (as in `slither run`'s final.csv: s,x,y,z,d1x,d1y,d1z) is skipped.
    let mut skip = 0;
    for (idx, raw) in text.lines().enumerate() {
        let line_no = idx + 1;
        last_line = line_no;
        let line = raw.trim();
        if idx == 0 {
            let fields: Vec<&str> = line.split(',').map(str::trim).collect();
            if fields.len() == 6 && fields.iter().all(|f| f.parse::<f64>().is_ok()) {
                return Err(CsvError {
                    line: 1,
                    message: "first line looks like data; a header row \
                              (e.g. x,y,z,d1x,d1y,d1z) is required"
                        .to_string(),
                });
            }
            if fields.len() == 7 && fields[0] == "s" {
                skip = 1;
            }
            continue;
        }
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).skip(skip).collect();
        if fields.len() != 6 {
            return Err(CsvError {
                line: line_no,
                message: format!(
                    "expected 6 fields (x,y,z,d1x,d1y,d1z), found {}",
                    fields.len()
                ),
            });
        }
        let mut v = [0.0; 6];
        for (k, f) in fields.iter().enumerate() {
            let x: f64 = f.parse().map_err(|_| CsvError {
                line: line_no,
                message: format!("field {} ({}) is not a number: {:?}", k + 1, NAMES[k], f),
            })?;
            if !x.is_finite() {
                return Err(CsvError {
                    line: line_no,
                    message: format!("field {} ({}) is not finite: {:?}", k + 1, NAMES[k], f),
                });
            }
            v[k] = x;
        }
        nodes.push([v[0], v[1], v[2]]);
        d1.push([v[3], v[4], v[5]]);
        row_lines.push(line_no);
    }
    if last_line == 0 {
        return Err(CsvError {
            line: 1,
            message: "empty input: missing header row".to_string(),
        });
    }
    if nodes.len() < 3 {
        return Err(CsvError {
            line: last_line,
            message: format!("fewer than 3 data rows (found {})", nodes.len()),
        });
    }
    if closed && nodes.len() > 3 {
        // A closed curve written with its first node repeated at the end: the repeated node
        // (and the director of the zero-length edge it would start) is dropped.
        let n = nodes.len();
        let mean_edge = (0..n - 1)
            .map(|i| norm(&sub(&nodes[i + 1], &nodes[i])))
            .sum::<f64>()
            / (n - 1) as f64;
        if norm(&sub(&nodes[n - 1], &nodes[0])) <= REPEAT_TOL * mean_edge {
            nodes.pop();
            d1.pop();
            row_lines.pop();
        }
    }
    if !closed {
        d1.pop();
    }
    let n = nodes.len();
    for (k, d) in d1.iter().enumerate() {
        if norm(d) == 0.0 {
            return Err(CsvError {
                line: row_lines[k],
                message: "director d1 is the zero vector".to_string(),
            });
        }
        let e = sub(&nodes[(k + 1) % n], &nodes[k]);
        let Some(t) = unit(&e) else {
            return Err(CsvError {
                line: row_lines[k],
                message: format!(
                    "the edge from this row's node to the node of line {} has zero length (a repeated node)",
                    row_lines[(k + 1) % n]
                ),
            });
        };
        if norm(&reject(d, &t)) <= ALONG_TANGENT_TOL * norm(d) {
            return Err(CsvError {
                line: row_lines[k],
                message: format!(
                    "director d1 = {d:?} lies along its edge's tangent {t:?}; it must have a component perpendicular to the edge (more than {ALONG_TANGENT_TOL} of its length)"
                ),
            });
        }
    }
    Ok(FramedCurve { nodes, d1, closed })
}

// ---------------------------------------------------------------------------
// tests
// ---------------------------------------------------------------------------

#[cfg(test)]
mod tests {
    use super::*;

    /// Small deterministic PRNG (xorshift64*), uniform in [0, 1).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
        }
        fn sym(&mut self) -> f64 {
            2.0 * self.next() - 1.0
        }
    }

    /// Director for edge (a -> b): `u` made perpendicular to the edge, then
    /// rotated by `alpha` about the edge tangent.
    fn director(a: &V3, b: &V3, u: &V3, alpha: f64) -> V3 {
        let t = unit(&sub(b, a)).unwrap();
        let u = unit(&reject(u, &t)).unwrap();
        let w = cross(&t, &u);
        add(&scale(&u, alpha.cos()), &scale(&w, alpha.sin()))
    }

    /// Circle of radius 1 in the xy-plane, d1 rotating `k` turns about the tangent.
    fn twisted_ring(n: usize, k: i32) -> FramedCurve {
        let nodes: Vec<V3> = (0..n)
            .map(|i| {
                let th = 2.0 * PI * i as f64 / n as f64;
                [th.cos(), th.sin(), 0.0]
            })
            .collect();
        let d1 = (0..n)
            .map(|i| {
                let thm = 2.0 * PI * (i as f64 + 0.5) / n as f64;
                let radial = [thm.cos(), thm.sin(), 0.0];
                director(&nodes[i], &nodes[(i + 1) % n], &radial, k as f64 * thm)
            })
            .collect();
        FramedCurve {
            nodes,
            d1,
            closed: true,
        }
    }

    /// (p,q) torus knot on the torus (R, a); d1 = direction away from the tube
    /// core, plus `extra` full turns about the tangent.
    fn torus_knot(p: f64, q: f64, n: usize, extra: i32) -> FramedCurve {
        let (rr, a) = (2.0, 0.8);
        let pos = |phi: f64| {
            let rad = rr + a * (q * phi).cos();
            [
                rad * (p * phi).cos(),
                rad * (p * phi).sin(),
                a * (q * phi).sin(),
            ]
        };
        let core = |phi: f64| [rr * (p * phi).cos(), rr * (p * phi).sin(), 0.0];
        let nodes: Vec<V3> = (0..n)
            .map(|i| pos(2.0 * PI * i as f64 / n as f64))
            .collect();
        let d1 = (0..n)
            .map(|i| {
                let phm = 2.0 * PI * (i as f64 + 0.5) / n as f64;
                let (r0, r1) = (&nodes[i], &nodes[(i + 1) % n]);
                let mid = scale(&add(r0, r1), 0.5);
                let u = sub(&mid, &core(phm));
                director(r0, r1, &u, extra as f64 * phm)
            })
            .collect();
        FramedCurve {
            nodes,
            d1,
            closed: true,
        }
    }

    fn is_integer(x: f64, tol: f64) -> bool {
        (x - x.round()).abs() < tol
    }

    /// Literal Klenin-Langowski eqs. 13-16 (arcsine sum over face normals),
    /// used as an independent oracle for well-conditioned pairs.
    fn kl_literal(p1: &V3, p2: &V3, p3: &V3, p4: &V3) -> f64 {
        let (r12, r34) = (sub(p2, p1), sub(p4, p3));
        let (r13, r14, r23, r24) = (sub(p3, p1), sub(p4, p1), sub(p3, p2), sub(p4, p2));
        let n1 = unit(&cross(&r13, &r14)).unwrap();
        let n2 = unit(&cross(&r14, &r24)).unwrap();
        let n3 = unit(&cross(&r24, &r23)).unwrap();
        let n4 = unit(&cross(&r23, &r13)).unwrap();
        let asin = |a: &V3, b: &V3| dot(a, b).clamp(-1.0, 1.0).asin();
        let omega_star = asin(&n1, &n2) + asin(&n2, &n3) + asin(&n3, &n4) + asin(&n4, &n1);
        omega_star * dot(&cross(&r34, &r12), &r13).signum()
    }

    #[test]
    fn stable_solid_angle_agrees_with_literal_klenin_langowski() {
        let mut rng = Rng(7);
        for _ in 0..2000 {
            let p: Vec<V3> = (0..4).map(|_| [rng.sym(), rng.sym(), rng.sym()]).collect();
            let a = pair_solid_angle(&p[0], &p[1], &p[2], &p[3]);
            let b = kl_literal(&p[0], &p[1], &p[2], &p[3]);
            assert!((a - b).abs() < 1e-9, "{a} vs {b} for {p:?}");
        }
    }

    // (nearly) straight rods far from the origin have (nearly) zero writhe;
    // the literal arcsine formula fails this (|Wr| ~ 5e-2 at offset 10).
    #[test]
    fn near_straight_rod_writhe_is_tiny() {
        let d = unit(&[1.0, 2.0, -0.5]).unwrap();
        let e1 = any_perpendicular(&d);
        let e2 = cross(&d, &e1);
        for &off in &[0.0, 10.0, 1000.0] {
            for &amp in &[0.0, 1e-10, 1e-7] {
                let nodes: Vec<V3> = (0..200)
                    .map(|i| {
                        let s = i as f64 * 0.01;
                        let wig = add(
                            &scale(&e1, amp * (7.0 * s).sin()),
                            &scale(&e2, amp * (5.0 * s).cos()),
                        );
                        add(&add(&[off, -off, off], &scale(&d, s)), &wig)
                    })
                    .collect();
                let wr = writhe(&nodes, false);
                assert!(wr.abs() < 1e-9, "offset {off}, wiggle {amp}: wr = {wr:e}");
            }
        }
    }

    // 0. the segment-pair solid angle equals the Gauss double integral
    #[test]
    fn segment_pair_matches_gauss_quadrature() {
        let mut rng = Rng(0x1234_5678_9abc_def1);
        for _ in 0..5 {
            let p1 = [rng.sym(), rng.sym(), rng.sym()];
            let p2 = [rng.sym(), rng.sym(), rng.sym()];
            let p3 = [rng.sym(), rng.sym(), 2.0 + rng.sym()];
            let p4 = [rng.sym(), 0.5 * rng.sym(), 2.5 + rng.sym()];
            let da = sub(&p2, &p1);
            let db = sub(&p4, &p3);
            let dadb = cross(&da, &db);
            // composite Simpson on [0,1]^2
            let m = 200;
            let w = |k: usize| {
                if k == 0 || k == m {
                    1.0
                } else if k % 2 == 1 {
                    4.0
                } else {
                    2.0
                }
            };
            let mut sum = 0.0;
            for i in 0..=m {
                let x = add(&p1, &scale(&da, i as f64 / m as f64));
                for j in 0..=m {
                    let y = add(&p3, &scale(&db, j as f64 / m as f64));
                    let d = sub(&x, &y);
                    let r = norm(&d);
                    sum += w(i) * w(j) * dot(&d, &dadb) / (r * r * r);
                }
            }
            let h = 1.0 / m as f64;
            let quad = sum * h * h / 9.0 / (4.0 * PI);
            let exact = pair_solid_angle(&p1, &p2, &p3, &p4) / (4.0 * PI);
            assert!((quad - exact).abs() < 1e-8, "quad {quad} vs exact {exact}");
            assert!(exact.abs() > 1e-4, "test pair too degenerate");
        }
    }

    // 1. twisted rings
    #[test]
    fn twisted_ring_link_equals_twist_plus_writhe() {
        for &k in &[0, 1, 3, -2] {
            let c = twisted_ring(100, k);
            let topo = topology(&c);
            let lk = gauss_link(&c, 0.01);
            assert!(is_integer(lk, 1e-6), "k={k}: lk={lk} not integer");
            assert!((lk - k as f64).abs() < 1e-6, "k={k}: lk={lk}");
            assert!(
                (lk - (topo.tw + topo.wr)).abs() < 1e-6,
                "k={k}: {lk} vs {topo:?}"
            );
            assert!((topo.lk - topo.tw - topo.wr).abs() == 0.0);
            assert!(topo.wr.abs() < 1e-12, "planar writhe {}", topo.wr);
            assert!((topo.tw - k as f64).abs() < 1e-9, "tw={}", topo.tw);
        }
    }

    // 2. torus knots
    #[test]
    fn torus_trefoils_link_equals_twist_plus_writhe() {
        for &(p, q) in &[(2.0, 3.0), (3.0, 2.0)] {
            let mut lk0 = None;
            for &extra in &[0, 2, -1] {
                let c = torus_knot(p, q, 200, extra);
                let topo = topology(&c);
                let lk = gauss_link(&c, 1e-3);
                let lk2 = gauss_link(&c, 1e-2);
                assert!(is_integer(lk, 1e-6), "({p},{q}) lk={lk}");
                assert!((lk - lk2).abs() < 1e-6, "eps dependence {lk} {lk2}");
                assert!(
                    (lk - (topo.tw + topo.wr)).abs() < 1e-6,
                    "({p},{q}) extra={extra}: lk={lk} topo={topo:?}"
                );
                assert!(topo.wr.abs() > 1.0, "trefoil writhe {}", topo.wr);
                match lk0 {
                    None => {
                        // torus-surface framing of T(p,q) has |Lk| = p q
                        assert_eq!(lk.round().abs(), p * q, "({p},{q}) lk={lk}");
                        lk0 = Some(lk.round());
                    }
                    Some(l0) => assert_eq!(lk.round(), l0 + extra as f64),
                }
            }
        }
    }

    fn random_rotation(rng: &mut Rng) -> [[f64; 3]; 3] {
        let mut q = [rng.sym(), rng.sym(), rng.sym(), rng.sym()];
        let l = (q.iter().map(|x| x * x).sum::<f64>()).sqrt();
        q.iter_mut().for_each(|x| *x /= l);
        let [w, x, y, z] = q;
        [
            [
                1.0 - 2.0 * (y * y + z * z),
                2.0 * (x * y - w * z),
                2.0 * (x * z + w * y),
            ],
            [
                2.0 * (x * y + w * z),
                1.0 - 2.0 * (x * x + z * z),
                2.0 * (y * z - w * x),
            ],
            [
                2.0 * (x * z - w * y),
                2.0 * (y * z + w * x),
                1.0 - 2.0 * (x * x + y * y),
            ],
        ]
    }

    // 3. invariances
    #[test]
    fn writhe_invariances() {
        let mut rng = Rng(42);
        // open random walk, 101 nodes
        let mut walk = vec![[0.0; 3]];
        for _ in 0..100 {
            let last = *walk.last().unwrap();
            let step = unit(&[rng.sym(), rng.sym(), rng.sym()]).unwrap();
            walk.push(add(&last, &step));
        }
        let trefoil = torus_knot(2.0, 3.0, 120, 0).nodes;
        for (nodes, closed) in [(walk, false), (trefoil, true)] {
            let wr = writhe(&nodes, closed);
            assert!(wr.abs() > 1e-3, "test curve should have nonzero writhe");
            for _ in 0..3 {
                let rot = random_rotation(&mut rng);
                let shift = [10.0 * rng.sym(), 10.0 * rng.sym(), 10.0 * rng.sym()];
                let s = 0.1 + 5.0 * rng.next();
                let moved: Vec<V3> = nodes
                    .iter()
                    .map(|r| {
                        let rr = [dot(&rot[0], r), dot(&rot[1], r), dot(&rot[2], r)];
                        add(&scale(&rr, s), &shift)
                    })
                    .collect();
                let wr2 = writhe(&moved, closed);
                assert!((wr - wr2).abs() < 1e-10, "rigid/scale: {wr} vs {wr2}");
            }
            let reversed: Vec<V3> = nodes.iter().rev().copied().collect();
            assert!((writhe(&reversed, closed) - wr).abs() < 1e-10);
            let mirror: Vec<V3> = nodes.iter().map(|r| [-r[0], r[1], r[2]]).collect();
            assert!((writhe(&mirror, closed) + wr).abs() < 1e-10);
        }
        // no non-adjacent pairs
        assert_eq!(
            writhe(&[[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.3]], false),
            0.0
        );
        assert_eq!(
            writhe(&[[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.3]], true),
            0.0
        );
    }

    // 4a. uniformly twisted straight rod (non-uniform spacing, tilted axis)
    #[test]
    fn densities_straight_rod_uniform_twist() {
        let tau0 = 2.0; // rad per metre
        let dir = unit(&[1.0, 2.0, -0.5]).unwrap();
        let e1 = any_perpendicular(&dir);
        let e2 = cross(&dir, &e1);
        let mut s = vec![0.0];
        for i in 0..60 {
            let last = *s.last().unwrap();
            s.push(last + 0.05 * (1.0 + 0.3 * (1.7 * i as f64).sin()));
        }
        let nodes: Vec<V3> = s
            .iter()
            .map(|&si| add(&[0.3, -1.0, 2.0], &scale(&dir, si)))
            .collect();
        let d1: Vec<V3> = (0..s.len() - 1)
            .map(|e| {
                let a = tau0 * 0.5 * (s[e] + s[e + 1]);
                add(&scale(&e1, a.cos()), &scale(&e2, a.sin()))
            })
            .collect();
        let c = FramedCurve {
            nodes,
            d1,
            closed: false,
        };
        let delta = 0.37;
        let d = densities(&c, delta);
        assert!(d.s.len() > 10);
        for k in 0..d.s.len() {
            assert!((d.s[k] - s[k]).abs() < 1e-12);
            assert!(d.s[k] + delta <= s[s.len() - 1] + 1e-9);
            assert!(
                (d.tau[k] - tau0 / (2.0 * PI)).abs() < 1e-9,
                "tau[{k}]={}",
                d.tau[k]
            );
            assert!(d.omega[k].abs() < 1e-12, "omega[{k}]={}", d.omega[k]);
            assert_eq!(d.lambda[k], d.tau[k] + d.omega[k]);
        }
        // the last fitting window is present
        let last_start = *d.s.last().unwrap();
        assert!(s
            .iter()
            .any(|&si| si > last_start && si + delta > s[s.len() - 1] + 1e-9));
    }

    // 4b. helix writhe density has the helix's sign
    #[test]
    fn densities_helix_sign() {
        let helix = |pitch: f64| {
            let n = 401;
            let nodes: Vec<V3> = (0..n)
                .map(|i| {
                    let t = 8.0 * PI * i as f64 / (n - 1) as f64;
                    [t.cos(), t.sin(), pitch * t]
                })
                .collect();
            let d1 = (0..n - 1)
                .map(|i| {
                    let m = scale(&add(&nodes[i], &nodes[i + 1]), 0.5);
                    director(&nodes[i], &nodes[i + 1], &[-m[0], -m[1], 0.0], 0.0)
                })
                .collect();
            FramedCurve {
                nodes,
                d1,
                closed: false,
            }
        };
        let right = densities(&helix(0.2), 7.0);
        let left = densities(&helix(-0.2), 7.0);
        assert!(!right.s.is_empty());
        assert_eq!(right.s.len(), left.s.len());
        for k in 0..right.s.len() {
            assert!(
                right.omega[k] > 1e-3,
                "right-handed omega[{k}]={}",
                right.omega[k]
            );
            assert!(
                left.omega[k] < -1e-3,
                "left-handed omega[{k}]={}",
                left.omega[k]
            );
            assert!((right.omega[k] + left.omega[k]).abs() < 1e-12);
        }
        // a window covering the whole curve reproduces the curve's writhe
        let c = helix(0.2);
        let total: f64 = (0..c.nodes.len() - 1)
            .map(|i| norm(&sub(&c.nodes[i + 1], &c.nodes[i])))
            .sum();
        let whole = densities(&c, total);
        assert_eq!(whole.s.len(), 1);
        assert!((whole.omega[0] * total - writhe(&c.nodes, false)).abs() < 1e-10);
    }

    // 4c. closed curves: a full-length window integrates the total twist
    #[test]
    fn densities_closed_full_window_gives_total_twist() {
        let c = torus_knot(2.0, 3.0, 150, 1);
        let n = c.nodes.len();
        let total: f64 = (0..n)
            .map(|i| norm(&sub(&c.nodes[(i + 1) % n], &c.nodes[i])))
            .sum();
        let d = densities(&c, total);
        assert_eq!(d.s.len(), n);
        let tw = twist(&c);
        for k in 0..n {
            assert!(
                (d.tau[k] * total - tw).abs() < 1e-9,
                "{} vs {tw}",
                d.tau[k] * total
            );
        }
        assert!(densities(&c, 1.01 * total).s.is_empty());
        assert!(densities(&c, -1.0).s.is_empty());
    }

    // 5. CSV
    fn to_csv(c: &FramedCurve) -> String {
        let mut s = String::from("x,y,z,d1x,d1y,d1z\n");
        for (i, r) in c.nodes.iter().enumerate() {
            let d = c.d1.get(i).copied().unwrap_or([0.0, 0.0, 1.0]);
            s += &format!("{},{},{},{},{},{}\n", r[0], r[1], r[2], d[0], d[1], d[2]);
        }
        s
    }

    #[test]
    fn csv_round_trip() {
        let closed = torus_knot(3.0, 2.0, 50, 1);
        assert_eq!(parse_curve_csv(&to_csv(&closed), true).unwrap(), closed);
        let mut open = twisted_ring(20, 2);
        open.closed = false;
        open.d1.pop();
        assert_eq!(parse_curve_csv(&to_csv(&open), false).unwrap(), open);
        // whitespace, CRLF and blank lines are tolerated
        let text =
            "x, y, z, d1x, d1y, d1z\r\n0, 0, 0, 0, 1, 0\r\n\r\n1,0,0, 0,1,0\r\n2,0,0,0,1,0\r\n";
        let c = parse_curve_csv(text, false).unwrap();
        assert_eq!(c.nodes.len(), 3);
        assert_eq!(c.d1.len(), 2);
    }

    #[test]
    fn csv_errors_report_line_numbers() {
        let h = "x,y,z,d1x,d1y,d1z\n";
        let ok = "0,0,0,0,1,0\n";
        let cases: Vec<(String, usize, &str)> = vec![
            (
                format!("{h}{ok}{ok}1,2,3,4,5\n{ok}"),
                4,
                "expected 6 fields",
            ),
            (format!("{h}{ok}{ok}{ok}1,2,abc,0,1,0\n"), 5, "not a number"),
            (format!("{h}{ok}1,2,inf,0,1,0\n{ok}"), 3, "not finite"),
            (format!("{h}{ok}1,2,3,0,NaN,0\n{ok}"), 3, "not finite"),
            (format!("{h}{ok}{ok}"), 3, "fewer than 3"),
            (format!("{ok}{ok}{ok}{ok}"), 1, "header"),
            (String::new(), 1, "empty"),
            (format!("{h}{ok}1,0,0,0,0,0\n{ok}"), 3, "zero"),
        ];
        for (text, line, what) in cases {
            let err = parse_curve_csv(&text, true).unwrap_err();
            assert_eq!(err.line, line, "{text:?}: {err}");
            assert!(err.message.contains(what), "{err}");
            assert!(err.to_string().starts_with(&format!("line {line}:")));
        }
        // the last row's director is ignored for open curves
        let text = format!("{h}{ok}1,0,0,0,1,0\n2,0,0,0,0,0\n");
        assert!(parse_curve_csv(&text, false).is_ok());
        let e: Box<dyn std::error::Error> = Box::new(parse_curve_csv("", true).unwrap_err());
        assert!(!e.to_string().is_empty());
    }

    // twist is unchanged by a constant rotation of all directors
    #[test]
    fn twist_invariant_under_constant_director_rotation() {
        let c = torus_knot(2.0, 3.0, 100, 1);
        let n = c.nodes.len();
        let mut c2 = c.clone();
        for i in 0..n {
            let (r0, r1) = (&c.nodes[i], &c.nodes[(i + 1) % n]);
            c2.d1[i] = director(r0, r1, &c.d1[i], 0.7);
        }
        assert!((twist(&c) - twist(&c2)).abs() < 1e-10);
    }

    /// The windows' writhe computed directly: the sub-polygon of each window (its whole edges
    /// and the interpolated last point), summed pair by pair with [`writhe`].
    fn direct_window_writhe(c: &FramedCurve, d: &Densities, delta: f64) -> Vec<f64> {
        let n = c.nodes.len();
        let m = edge_count(n, c.closed);
        let lens: Vec<f64> = (0..m)
            .map(|e| norm(&sub(&c.nodes[(e + 1) % n], &c.nodes[e])))
            .collect();
        let total: f64 = lens.iter().sum();
        d.s.iter()
            .enumerate()
            .map(|(w, &a)| {
                let i = (0..n)
                    .position(|k| lens[..k].iter().sum::<f64>() == a)
                    .unwrap();
                let b = (a + delta).min(if c.closed { f64::INFINITY } else { total });
                let mut pts = vec![c.nodes[i]];
                let mut pos = a;
                for k in i..i + m {
                    let e = k % m;
                    let (p, q) = (c.nodes[e], c.nodes[(e + 1) % n]);
                    if pos + lens[e] >= b - 1e-12 * total.max(delta) {
                        let f = ((b - pos) / lens[e]).clamp(0.0, 1.0);
                        pts.push(add(&p, &scale(&sub(&q, &p), f)));
                        break;
                    }
                    pts.push(q);
                    pos += lens[e];
                }
                let _ = w;
                writhe(&pts, false)
            })
            .collect()
    }

    #[test]
    fn sliding_window_writhe_equals_the_direct_sum() {
        // A random walk (open) and a trefoil (closed), windows of several sizes, some ending
        // inside an edge and one exactly at nodes.
        let mut rng = Rng(99);
        let mut walk = vec![[0.0; 3]];
        for _ in 0..80 {
            let last = *walk.last().unwrap();
            let step = scale(
                &unit(&[rng.sym(), rng.sym(), rng.sym()]).unwrap(),
                0.5 + rng.next(),
            );
            walk.push(add(&last, &step));
        }
        let d1: Vec<V3> = (0..walk.len() - 1)
            .map(|i| director(&walk[i], &walk[i + 1], &[0.3, -0.2, 1.0], 0.1 * i as f64))
            .collect();
        let open = FramedCurve {
            nodes: walk,
            d1,
            closed: false,
        };
        let knot = torus_knot(2.0, 3.0, 90, 1);
        for (c, deltas) in [(&open, [3.3, 10.0, 25.7]), (&knot, [1.1, 4.0, 9.5])] {
            for delta in deltas {
                let d = densities(c, delta);
                assert!(d.s.len() > 10, "{delta}: {} windows", d.s.len());
                let direct = direct_window_writhe(c, &d, delta);
                let mut largest: f64 = 0.0;
                for (k, wr) in direct.iter().enumerate() {
                    largest = largest.max(wr.abs());
                    let got = d.omega[k] * delta;
                    assert!((got - wr).abs() < 1e-12, "window {k}: {got} vs {wr}");
                }
                assert!(largest > 1e-4, "windows should writhe: {largest}");
            }
        }
    }

    #[test]
    fn shortened_last_window_keeps_the_count_and_divides_by_its_length() {
        // A uniformly twisted straight rod of 10 unit edges, windows of 3: at rest 8 windows
        // fit; compressed by 1e-4 only 7 do, and the 8th is shortened, not NaN or missing.
        let rod = |scale_: f64| {
            let nodes: Vec<V3> = (0..=10).map(|i| [scale_ * i as f64, 0.0, 0.0]).collect();
            let d1 = (0..10)
                .map(|e| {
                    let a = 0.5 * (e as f64 + 0.5);
                    [0.0, a.cos(), a.sin()]
                })
                .collect();
            FramedCurve {
                nodes,
                d1,
                closed: false,
            }
        };
        assert_eq!(densities(&rod(1.0), 3.0).s.len(), 8);
        let squeezed = rod(1.0 - 1e-4);
        assert_eq!(densities(&squeezed, 3.0).s.len(), 7);
        let d = densities_shortened(&squeezed, 3.0, 8);
        assert_eq!(d.s.len(), 8);
        let rate = 0.5 / (1.0 - 1e-4) / (2.0 * PI);
        for k in 0..8 {
            assert!((d.tau[k] - rate).abs() < 1e-9, "tau[{k}] = {}", d.tau[k]);
            assert!(d.lambda[k].is_finite());
        }
    }

    #[test]
    fn planar_figure_eight_has_zero_writhe() {
        // A lemniscate in the plane z = 0 crosses itself once: its writhe is 0 (the crossing
        // pair's principal value), also after a rotation in space.
        let n = 120;
        let eight: Vec<V3> = (0..n)
            .map(|i| {
                let t = 2.0 * PI * (i as f64 + 0.25) / n as f64;
                [t.sin(), t.sin() * t.cos(), 0.0]
            })
            .collect();
        assert!(
            writhe(&eight, true).abs() < 1e-12,
            "{}",
            writhe(&eight, true)
        );
        let mut rng = Rng(5);
        let rot = random_rotation(&mut rng);
        let moved: Vec<V3> = eight
            .iter()
            .map(|r| [dot(&rot[0], r), dot(&rot[1], r), dot(&rot[2], r)])
            .collect();
        assert!(
            writhe(&moved, true).abs() < 1e-9,
            "{}",
            writhe(&moved, true)
        );
        // Lifting the crossing by +-h gives writhe of opposite signs, symmetric about 0.
        let lift = |h: f64| -> Vec<V3> {
            eight
                .iter()
                .enumerate()
                .map(|(i, r)| {
                    let t = 2.0 * PI * (i as f64 + 0.25) / n as f64;
                    [r[0], r[1], h * t.cos()]
                })
                .collect()
        };
        let (up, down) = (writhe(&lift(1e-3), true), writhe(&lift(-1e-3), true));
        assert!(up.abs() > 1e-3 && (up + down).abs() < 1e-9, "{up} {down}");
    }

    #[test]
    fn csv_closed_repeated_closing_node_is_dropped() {
        let ring = twisted_ring(40, -1);
        let mut text = to_csv(&ring);
        let r = ring.nodes[0];
        let d = ring.d1[0];
        text += &format!("{},{},{},{},{},{}\n", r[0], r[1], r[2], d[0], d[1], d[2]);
        let c = parse_curve_csv(&text, true).unwrap();
        assert_eq!(c, ring);
        assert!((gauss_link(&c, 1e-3) + 1.0).abs() < 1e-6);
    }

    #[test]
    fn csv_rejects_a_director_along_the_tangent_and_a_zero_edge() {
        let h = "x,y,z,d1x,d1y,d1z\n";
        let text = format!("{h}0,0,0,0,0,1\n1,0,0,0,0,1\n1,1,0,0,0,1\n0,1,0,0,-3,0\n");
        let e = parse_curve_csv(&text, true).unwrap_err();
        assert_eq!(e.line, 5, "{e}");
        assert!(e.message.contains("along its edge's tangent"), "{e}");
        let text = format!("{h}0,0,0,0,1,0\n1,0,0,0,1,0\n1,0,0,0,1,0\n0,1,0,1,0,0\n");
        let e = parse_curve_csv(&text, false).unwrap_err();
        assert_eq!(e.line, 3, "{e}");
        assert!(e.message.contains("zero length"), "{e}");
    }

    #[test]
    #[should_panic(expected = "closed curves only")]
    fn gauss_link_rejects_open_curves() {
        let mut c = twisted_ring(10, 0);
        c.closed = false;
        c.d1.pop();
        gauss_link(&c, 0.01);
    }
}
