//! Exact polygon writhe and the Gauss linking number by segment-pair solid angles (module
//! doc of [`crate::topology`], "Writhe" and "Linking number").

use super::*;

/// Relative tolerance below which a segment pair counts as coplanar in
/// `pair_solid_angle`: `|r_13 . (r_12 x r_34)| <= 1e-12 |r_12| |r_34| max|r_ij|`, i.e. the
/// two segments lie in one plane to about 1e-12 of their size (round-off of coordinates that
/// are coplanar by construction, such as a planar curve rotated in space).
pub const COPLANAR_TOL: f64 = 1e-12;

/// Signed solid angle of the triangle `(a, b, c)` seen from the origin
/// (Van Oosterom & Strackee 1983): `tan(W/2) = a.(b x c) / (|a||b||c| +
/// (a.b)|c| + (a.c)|b| + (b.c)|a|)`; result in `(-2 pi, 2 pi)`.
#[inline(always)]
pub(super) fn triangle_solid_angle(a: &V3, b: &V3, c: &V3) -> f64 {
    let (la, lb, lc) = (norm(a), norm(b), norm(c));
    let num = dot(a, &cross(b, c));
    let den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
    2.0 * num.atan2(den)
}

#[cfg(test)]
thread_local! {
    // Pair evaluations on this thread (test builds only): the tests count work, not seconds.
    pub(super) static PAIRS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
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
pub(super) fn pair_solid_angle(p1: &V3, p2: &V3, p3: &V3, p4: &V3) -> f64 {
    #[cfg(test)]
    PAIRS.with(|n| n.set(n.get() + 1));
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
pub(super) fn push_off_directions(c: &FramedCurve, t: &[V3]) -> Vec<V3> {
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
