//! Discrete twist: tangents, parallel transport between edges and the signed vertex angle
//! (module doc of [`crate::topology`], "Twist").

use super::*;

/// Unit tangents of all edges (zero vector for zero-length edges).
pub(super) fn tangents(nodes: &[V3], closed: bool) -> Vec<V3> {
    let n = nodes.len();
    (0..edge_count(n, closed))
        .map(|e| unit_or_zero(&sub(&nodes[(e + 1) % n], &nodes[e])))
        .collect()
}

/// Parallel transport of `u` from unit tangent `t1` to unit tangent `t2`
/// (rotation about `t1 x t2` taking `t1` to `t2`).
#[inline]
pub(super) fn transport(t1: &V3, t2: &V3, u: &V3) -> V3 {
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
pub(super) fn vertex_angle(t_prev: &V3, d_prev: &V3, t: &V3, d: &V3) -> f64 {
    let p = reject(&transport(t_prev, t, d_prev), t);
    let q = reject(d, t);
    dot(t, &cross(&p, &q)).atan2(dot(&p, &q))
}

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
