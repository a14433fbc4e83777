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
//!
//! # Layout
//!
//! `mod.rs` the types and [`topology`]; `twist.rs` tangents, transport and [`twist`];
//! `writhe.rs` the segment-pair solid angle, [`writhe`] and [`gauss_link`]; `densities.rs`
//! the sliding-window local densities; `csv.rs` the CSV reader; `vec.rs` vector helpers;
//! `tests.rs` the tests of the identities and invariances, `density_tests.rs` those of the
//! densities and the CSV reader.

mod csv;
mod densities;
mod twist;
mod vec;
mod writhe;

#[cfg(test)]
mod density_tests;
#[cfg(test)]
mod tests;

pub use csv::{parse_curve_csv, ALONG_TANGENT_TOL, MAX_ABS, REPEAT_TOL};
pub use densities::{densities, densities_shortened};
pub use twist::twist;
pub use writhe::{gauss_link, writhe, COPLANAR_TOL};

use std::f64::consts::PI;
use std::fmt;
use twist::*;
use vec::*;
use writhe::*;

type V3 = [f64; 3];

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
// shared by the submodules
// ---------------------------------------------------------------------------

/// Number of edges of a polygon with `n` nodes.
#[inline]
pub(super) fn edge_count(n: usize, closed: bool) -> usize {
    if n < 2 {
        0
    } else if closed {
        n
    } else {
        n - 1
    }
}

/// Panics unless the director count matches the edge convention.
pub(super) fn check_curve(c: &FramedCurve) {
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
