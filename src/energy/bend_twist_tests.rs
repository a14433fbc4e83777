//! Tests of `node.rs`.
use super::*;
use crate::energy::reference::testing::{assert_matches, stencil};

/// The fused closed form equals the sum of the staged jets' bending and twist (themselves
/// checked against hyper-dual numbers and finite differences) on random, strongly bent
/// stencils with frozen frames away from the current tangents.
#[test]
fn node_stencil_matches_the_jets() {
    for seed in 1..=300 {
        let (frame, y, mut r) = stencil(seed);
        let st = NodeStencil {
            frame: &frame,
            kappa0: [0.5 * r.sym(), 0.5 * r.sym()],
            bend: 1.0 + r.sym(),
            m0: 0.5 * r.sym(),
            twist: 1.0 + r.sym(),
        };
        let edges = [
            EdgeFrame::new([y[0], y[1], y[2]], frame.t_old[0], frame.a1_old[0], y[6]),
            EdgeFrame::new([y[3], y[4], y[5]], frame.t_old[1], frame.a1_old[1], y[7]),
        ];
        let (b, t) = split(&st);
        let (vb, gb, hb) = b.derivatives(y);
        let (vt, gt, ht) = t.derivatives(y);
        assert_matches(
            node_local(&st, [&edges[0], &edges[1]]),
            (vb + vt, gb + gt, hb + ht),
            seed,
        );
    }
}

/// The gradient-only stencil (used at iterates that keep an earlier Hessian) equals the
/// value and gradient of the full one, which the test above checks against the jets, on
/// the same random stencils; and its gradient matches central differences of its own
/// value.
#[test]
fn gradient_only_stencil_matches_the_full_one_and_finite_differences() {
    for seed in 1..=300 {
        let (frame, y, mut r) = stencil(seed);
        let st = NodeStencil {
            frame: &frame,
            kappa0: [0.5 * r.sym(), 0.5 * r.sym()],
            bend: 1.0 + r.sym(),
            m0: 0.5 * r.sym(),
            twist: 1.0 + r.sym(),
        };
        let at = |y: &[f64; 8]| {
            let edges = [
                EdgeFrame::new([y[0], y[1], y[2]], frame.t_old[0], frame.a1_old[0], y[6]),
                EdgeFrame::new([y[3], y[4], y[5]], frame.t_old[1], frame.a1_old[1], y[7]),
            ];
            (
                node_local_gradient(&st, [&edges[0], &edges[1]]),
                node_local(&st, [&edges[0], &edges[1]]),
            )
        };
        let ((v, g), (vf, gf, _)) = at(&y);
        let scale = 1.0 + vf.abs() + gf.amax();
        assert!(
            (v - vf).abs() <= 1e-12 * scale,
            "seed {seed}: value {v} vs {vf}"
        );
        for k in 0..8 {
            assert!(
                (g[k] - gf[k]).abs() <= 1e-11 * scale,
                "seed {seed}: gradient {k}: {} vs {}",
                g[k],
                gf[k]
            );
            let h = 1e-6;
            let (mut yp, mut ym) = (y, y);
            yp[k] += h;
            ym[k] -= h;
            let fd = (at(&yp).0 .0 - at(&ym).0 .0) / (2.0 * h);
            assert!(
                (fd - g[k]).abs() <= 1e-6 * scale,
                "seed {seed}: gradient {k}: {} vs central difference {fd}",
                g[k]
            );
        }
    }
}

/// The contracted frame Hessians against central differences of `w . a1` and `w . a2`
/// along two directions `u`, `v` orthogonal to `t` at a unit edge `e = t`: there the
/// second derivative of `G(e / |e|)` is `u^T H v - (g . t)(u . v)` with `g` the gradient
/// in `t` (the tangent's own curvature).
#[test]
fn contracted_frame_hessians_match_finite_differences() {
    let unit = |v: [f64; 3]| f::scale(v, 1.0 / f::norm(v));
    let to = unit([0.2, -0.9, 0.4]);
    let ao = unit(f::cross(to, [0.3, 0.1, 0.8]));
    let t = unit([0.5, -0.6, 0.7]);
    let w = [0.3, -1.1, 0.6];
    let fr = EdgeFrame::new(t, to, ao, 0.0);
    let (h1, h2) = (fr.hess_a1(w), fr.hess_a2(w));
    let (g1, g2) = (mul_t(&fr.ja1, w), mul_t(&fr.ja2, w));
    let val = |x: [f64; 3]| {
        let fr = EdgeFrame::new(x, to, ao, 0.0);
        [f::dot(w, fr.a1), f::dot(w, fr.a2)]
    };
    let u = unit(f::cross(t, [1.0, 0.0, 0.0]));
    let v = f::cross(t, u);
    let h = 1e-4;
    for (da, db) in [(u, u), (u, v), (v, v)] {
        let p = |a: f64, b: f64| val(f::add(t, f::add(f::scale(da, a), f::scale(db, b))));
        let (pp, pm, mp, mm) = (p(h, h), p(h, -h), p(-h, h), p(-h, -h));
        let quad = |hm: &M3| -> f64 {
            (0..3)
                .map(|i| (0..3).map(|j| da[i] * hm[i][j] * db[j]).sum::<f64>())
                .sum()
        };
        let uv = f::dot(da, db);
        let an = [
            quad(&h1) - f::dot(g1, t) * uv,
            quad(&h2) - f::dot(g2, t) * uv,
        ];
        for k in 0..2 {
            let fd = (pp[k] - pm[k] - mp[k] + mm[k]) / (4.0 * h * h);
            assert!((fd - an[k]).abs() < 1e-6, "director {k}: {fd} vs {}", an[k]);
        }
    }
}
