//! Derivatives against finite differences, the closest distance against brute force, and
//! conservative advancement against a sampled path.

use super::*;
use crate::fd;

/// A free 24-element rod of 0.24 m (`a` = 0.02 m, edges of half a diameter) without
/// gravity, with its coordinates folded so that the head half lies across the tail half
/// at `gap` (m) beyond contact, plus a random jitter of up to `jitter / 2` (m) per
/// coordinate. The activation gap is 2e-4 m.
fn folded(gap: f64, jitter: f64, seed: u64) -> (Model, Vec<f64>) {
    let toml = "[rod]\nlength = 0.24\ndiameter = 0.02\nelements = 24\nbending_stiffness = 0.01\n\
                [gravity]\ng = 0.0\n[time]\ndt = 1e-3\nduration = 0.01\n";
    let p = crate::problem::parse(toml, std::path::Path::new("<test>")).unwrap();
    let m = Model::new(&p);
    let a = m.diameter;
    let mut q = m.q0.clone();
    let mut x = seed;
    let mut next = || fd::uniform(&mut x);
    // Nodes 0..=10 along -y at x = 0.05 (node 7 at y = 0), a + gap above nodes 13..=24
    // along -x at y = 0 (node 19 at x = 0.05); nodes 11 and 12 fold the rod well apart.
    for i in 0..m.nodes {
        let k = dof::node(i);
        let xyz = match i {
            0..=10 => [
                0.05 + 0.3 * a * next(),
                0.07 - 0.01 * i as f64,
                a / 2.0 + a + gap,
            ],
            11 => [0.09, -0.03, 1.5 * a],
            12 => [0.12, -0.01, a],
            _ => [0.24 - 0.01 * i as f64, 0.0, a / 2.0],
        };
        for c in 0..3 {
            q[k + c] = xyz[c] + jitter * next();
        }
    }
    (m, q)
}

/// The barrier's gradient is that of its value (central differences), with pairs across
/// the activation gap; `b'` and `b''` are those of `b`.
#[test]
fn barrier_derivatives_match_finite_differences() {
    for (gap, seed) in [(1.6e-4, 3u64), (1e-4, 5), (4e-5, 7), (6e-6, 11)] {
        let (m, q) = folded(gap, 2e-7, seed);
        let sc = SelfContact::of(&m).unwrap();
        let mut asm = Assembly::new(m.ndof);
        let e = sc.assemble(&q, &mut asm);
        assert!(e > 0.0, "gap {gap}: no active pair");
        assert!(!asm.low_rank.is_empty());
        let mut value = |x: &[f64]| sc.value(x);
        let num = fd::gradient(&mut value, &q, 1e-9);
        let err = fd::rel_error(&asm.grad, &num, 1e-12);
        assert!(err < 1e-5, "gap {gap}: gradient error {err:.2e}");
        // b' and b'' against differences of b and b'.
        for g in [0.1, 0.5, 0.9].map(|f| f * sc.activation()) {
            let hstep = 1e-6 * sc.activation();
            let (b, db, ddb) = sc.barrier(g);
            let (bp, dbp, _) = sc.barrier(g + hstep);
            let (bm, dbm, _) = sc.barrier(g - hstep);
            assert!(b > 0.0);
            assert!(((bp - bm) / (2.0 * hstep) - db).abs() <= 1e-6 * db.abs());
            assert!(((dbp - dbm) / (2.0 * hstep) - ddb).abs() <= 1e-6 * ddb.abs());
        }
        // The low-rank part is positive semi-definite (it is the projection of
        // b'' grad d grad d^T + b' grad^2 d, whose parts the tests here check).
        let mut v = vec![0.0; m.ndof];
        for (k, x) in v.iter_mut().enumerate() {
            *x = ((k * 7919) % 13) as f64 - 6.0;
        }
        let form: f64 = asm.low_rank.iter().map(|u| u.dot(&v).powi(2)).sum();
        assert!(form > 0.0);
    }
}

/// The exact Hessian of a pair's distance is the Jacobian of its gradient (central
/// differences), for crossing edges (both closest points inside), an end against an edge
/// and two ends; and the projected barrier Hessian is positive semi-definite.
#[test]
fn distance_hessian_matches_finite_differences() {
    let (m, _) = folded(1e-4, 0.0, 1);
    let sc = SelfContact::of(&m).unwrap();
    let a = m.diameter;
    let mut q = m.q0.clone();
    let set = |q: &mut Vec<f64>, i: usize, x: [f64; 3]| {
        q[dof::node(i)..dof::node(i) + 3].copy_from_slice(&x);
    };
    let cases: [[[f64; 3]; 4]; 4] = [
        // Crossing, skew.
        [
            [0.0, 0.0, 0.0],
            [0.01, 0.001, 0.0005],
            [0.004, -0.005, 1.01 * a],
            [0.006, 0.005, 1.02 * a],
        ],
        // The second edge's end above the first edge's inside.
        [
            [0.0, 0.0, 0.0],
            [0.01, 0.0, 0.001],
            [0.005, 0.0, 1.01 * a],
            [0.007, 0.008, 1.3 * a],
        ],
        // End to end.
        [
            [0.0, 0.0, 0.0],
            [0.01, 0.002, 0.0],
            [0.0105, 0.003, 1.01 * a],
            [0.02, 0.009, 1.4 * a],
        ],
        // Nearly parallel, offset along.
        [
            [0.0, 0.0, 0.0],
            [0.01, 0.0, 0.0],
            [0.004, 0.0003, 1.01 * a],
            [0.014, 0.0, 1.0101 * a],
        ],
    ];
    let (i, j) = (2usize, 20usize);
    for (n, pts) in cases.iter().enumerate() {
        set(&mut q, i, pts[0]);
        set(&mut q, i + 1, pts[1]);
        set(&mut q, j, pts[2]);
        set(&mut q, j + 1, pts[3]);
        let p = sc.pair(&q, i, j);
        let h = sc.distance_hessian(&q, &p);
        let (idx, _) = SelfContact::distance_gradient(&p);
        let x0: Vec<f64> = idx.iter().map(|&k| q[k]).collect();
        let mut grad = |x: &[f64]| {
            let mut y = q.clone();
            for (&k, v) in idx.iter().zip(x) {
                y[k] = *v;
            }
            SelfContact::distance_gradient(&sc.pair(&y, i, j))
                .1
                .to_vec()
        };
        let jac = fd::jacobian(&mut grad, &x0, 1e-8);
        let scale = h.iter().flatten().fold(0.0f64, |a, b| a.max(b.abs()));
        for r in 0..12 {
            for c in 0..12 {
                assert!(
                    (h[r][c] - jac[r][c]).abs() <= 1e-5 * scale,
                    "case {n}: ({r}, {c}) {} vs {}",
                    h[r][c],
                    jac[r][c]
                );
            }
        }
        let mut asm = Assembly::new(m.ndof);
        let (_, db, ddb) = sc.barrier(0.5 * sc.activation());
        sc.add_pair_hessian(&q, &p, db, ddb, &mut asm);
        assert!(!asm.low_rank.is_empty());
    }
}

/// The four forces of every active pair add up to zero (equal and opposite on the two
/// edges), and push the edges apart.
#[test]
fn pair_forces_are_equal_and_opposite() {
    let (m, q) = folded(1e-4, 2e-7, 13);
    let sc = SelfContact::of(&m).unwrap();
    let pairs = sc.forces(&q);
    assert!(!pairs.is_empty());
    for (p, fs) in pairs {
        let on_i = f::add(fs[0], fs[1]);
        let on_j = f::add(fs[2], fs[3]);
        let scale = f::norm(on_i);
        assert!(scale > 0.0);
        assert!(f::norm(f::add(on_i, on_j)) <= 1e-14 * scale);
        // Along p(s) - r(t): pushes edge i away from edge j.
        assert!(f::dot(on_i, p.closest.delta) > 0.0);
    }
}

/// Conservative advancement never lets a pair cross: along random directions large
/// enough to pass the upper half through the lower, the capped step ends with every
/// candidate gap positive, and so does every point of the way there (sampled).
#[test]
fn max_step_never_crosses() {
    for seed in 1..20u64 {
        let (m, q) = folded(3e-3, 0.0, seed);
        let sc = SelfContact::of(&m).unwrap();
        let mut dq = vec![0.0; m.ndof];
        let mut x = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        for i in 0..=10 {
            let k = dof::node(i);
            let r = fd::uniform(&mut x) + 0.5;
            // Down through the lower half, 1 to 3 diameters.
            dq[k + 2] = -(1.0 + 2.0 * r) * m.diameter;
            dq[k] = 0.5 * (r - 0.5) * m.diameter;
        }
        let alpha = sc.max_step(&q, &dq);
        assert!(alpha < 1.0 && alpha > 0.0, "seed {seed}: alpha {alpha}");
        for f in 1..=50 {
            let t = alpha * f as f64 / 50.0;
            let y: Vec<f64> = q.iter().zip(&dq).map(|(a, b)| a + t * b).collect();
            let c = sc.closest_distance(&y);
            assert!(c > m.diameter, "seed {seed}: t {t}: {c}");
        }
        // Without the cap the full step crosses.
        let y: Vec<f64> = q.iter().zip(&dq).map(|(a, b)| a + b).collect();
        let _ = sc.value(&y);
    }
}

/// The candidate set's closest distance, and the exact one by the doubling sweep, equal
/// a brute-force minimum over every eligible pair.
#[test]
fn closest_distance_matches_brute_force() {
    for (gap, jitter, seed) in [
        (1e-4, 0.0, 1u64),
        (3e-3, 0.0, 2),
        (0.02, 0.006, 3),
        (0.1, 0.01, 4),
    ] {
        let (m, q) = folded(gap, jitter, seed);
        let sc = SelfContact::of(&m).unwrap();
        let mut best = f64::INFINITY;
        for i in m.real_edges() {
            for j in i + 1..m.real_edges().end {
                if sc.eligible(i, j) {
                    best = best.min(sc.pair(&q, i, j).closest.dist);
                }
            }
        }
        assert_eq!(sc.closest_distance(&q), best, "gap {gap}");
        let measured = sc.measure(&q).closest;
        if best < m.diameter + sc.activation() {
            assert_eq!(measured, best);
        }
    }
}

/// A margin grown for one long Newton step does not outlive it: after `max_step` along a step
/// as long as the body, the next evaluation at `q` sees the candidates a fresh broad phase
/// finds there, not nearly every eligible pair (at 400 elements the grown set had made
/// self-contact three quarters of the S-start's time).
#[test]
fn a_long_step_does_not_leave_every_pair_a_candidate() {
    let (m, q) = folded(3e-3, 0.0, 1);
    let fresh = SelfContact::of(&m).unwrap();
    let baseline = fresh.with_pairs(&q, None, |p| p.len());
    let sc = SelfContact::of(&m).unwrap();
    let mut dq = vec![0.0; m.ndof];
    for i in 0..m.nodes {
        dq[dof::node(i)] = 0.3 * (i as f64 / m.nodes as f64 - 0.5);
    }
    let grown = sc.with_pairs(&q, Some(&dq), |p| p.len());
    let _ = sc.max_step(&q, &dq);
    assert!(grown > 3 * baseline, "grown {grown}, baseline {baseline}");
    let after = sc.with_pairs(&q, None, |p| p.len());
    assert_eq!(after, baseline, "grown {grown}");
    assert_eq!(sc.value(&q), fresh.value(&q));
}
