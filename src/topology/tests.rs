//! Tests of the topology module: the identities (link = twist + writhe, the solid angle
//! against its oracles) and invariances. Densities and CSV are in `density_tests.rs`, which
//! shares the curves built here.

use super::*;

/// Small deterministic PRNG (xorshift64*), uniform in [0, 1).
pub(super) struct Rng(pub(super) u64);
impl Rng {
    pub(super) fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    pub(super) fn sym(&mut self) -> f64 {
        2.0 * self.next() - 1.0
    }
}

/// Director for edge (a -> b): `u` made perpendicular to the edge, then
/// rotated by `alpha` about the edge tangent.
pub(super) fn director(a: &V3, b: &V3, u: &V3, alpha: f64) -> V3 {
    let t = unit(&sub(b, a)).unwrap();
    let u = unit(&reject(u, &t)).unwrap();
    let w = cross(&t, &u);
    add(&scale(&u, alpha.cos()), &scale(&w, alpha.sin()))
}

/// Circle of radius 1 in the xy-plane, d1 rotating `k` turns about the tangent.
pub(super) fn twisted_ring(n: usize, k: i32) -> FramedCurve {
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
pub(super) fn torus_knot(p: f64, q: f64, n: usize, extra: i32) -> FramedCurve {
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
        // The reported link against the independent Gauss linking integral of the curve and
        // its push-off (not against `tw + wr`, from which it is summed).
        assert!(
            (topo.lk - lk).abs() < 1e-6,
            "k={k}: lk {} vs Gauss {lk}",
            topo.lk
        );
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
#[should_panic(expected = "closed curves only")]
fn gauss_link_rejects_open_curves() {
    let mut c = twisted_ring(10, 0);
    c.closed = false;
    c.d1.pop();
    gauss_link(&c, 0.01);
}
