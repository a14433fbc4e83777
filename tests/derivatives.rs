//! Every energy term's analytic gradient and Hessian against central finite differences on
//! random non-degenerate rods (relative error < 1e-6), and invariance of every energy under
//! rigid translations and rotations.
// Index loops over dof indices read as the math does.
#![allow(clippy::needless_range_loop)]
mod common;
use common::{model, Rng};
use slither::energy::{self, Assembly, Ctx, Term};
use slither::fd;
use slither::model::Model;
use slither::rod::dof;
use slither::state::State;

const ROD: &str = r#"
[rod]
length = 0.5
diameter = 0.02
elements = 6
bending_stiffness = 2e-3
twist_stiffness = 1.5e-3
[time]
dt = 1e-3
duration = 1e-2
"#;

/// A random curved, twisted rod whose frozen frames belong to a different (earlier) shape,
/// with random rest strains.
fn random_setup(seed: u64) -> (Model, State, Vec<f64>, Vec<[f64; 2]>, Vec<f64>) {
    let m = model(ROD);
    let mut r = Rng(seed.wrapping_mul(0x9E3779B97F4A7C15) | 1);
    let mut s = State::initial(&m);
    let l0 = m.rest_len[0];
    for k in 0..m.ndof {
        s.q[k] += 0.3 * l0 * r.sym();
    }
    s.update_frames();
    let mut q = s.q.clone();
    for k in 0..m.ndof {
        q[k] += 0.15 * l0 * r.sym();
    }
    for j in 0..m.nodes - 1 {
        q[dof::edge(j)] = 2.0 * r.sym();
    }
    let kappa0 = (0..m.nodes)
        .map(|_| [0.3 * r.sym(), 0.3 * r.sym()])
        .collect();
    let m0 = (0..m.nodes).map(|_| 0.3 * r.sym()).collect();
    (m, s, q, kappa0, m0)
}

/// Rest lengths off the model's by up to 4 % (as rod damping blends them with the strains at
/// the step's start), so that the derivative checks cover a damped step's terms.
fn blended_rest_lengths(m: &Model, seed: u64) -> Vec<f64> {
    let mut r = Rng(seed.wrapping_mul(7) | 1);
    m.rest_len
        .iter()
        .map(|l| l * (1.0 + 0.04 * r.sym()))
        .collect()
}

fn check_term(term: &dyn Term, seed: u64) {
    let (m, s, q, kappa0, m0) = random_setup(seed);
    let rest_len = blended_rest_lengths(&m, seed);
    // Odd seeds: an undamped step; even seeds: a damped one (stiffness factor 1 + tau/h').
    let (rest_len, elastic_scale) = if seed % 2 == 1 {
        (m.rest_len.clone(), 1.0)
    } else {
        (rest_len, 1.0 + 0.9 * seed as f64)
    };
    let ctx = Ctx {
        model: &m,
        frames: &s.frames,
        kappa0: &kappa0,
        m0: &m0,
        gravity: [0.3, -0.2, -9.81],
        rest_len: &rest_len,
        elastic_scale,
    };
    let mut asm = Assembly::new(m.ndof);
    let e = term.eval(&ctx, &q, Some(&mut asm), false);
    let e_plain = term.eval(&ctx, &q, None, false);
    assert!(
        (e - e_plain).abs() <= 1e-12 * e.abs().max(1e-30),
        "{}: value paths differ",
        term.name()
    );
    let (err_g, err_h, g_fd) = fd_errors(
        &q,
        &asm,
        &mut |x| term.eval(&ctx, x, None, false),
        &mut |x| {
            let mut a = Assembly::new(m.ndof);
            term.eval(&ctx, x, Some(&mut a), false);
            a.grad
        },
    );
    assert!(
        err_g < 1e-6,
        "{} gradient: relative error {err_g:e} (seed {seed})",
        term.name()
    );
    // The comparison can fail: the gradient is far from zero (a term that returned zeros
    // would pass a relative check only against a zero numerical gradient), and an error of
    // 1e-4 in the largest entry would exceed the tolerance.
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    assert!(
        norm(&g_fd) > 1e-6 * e.abs().max(1e-12) / m.rest_len[0],
        "{}: numerical gradient {:e} too small to check (energy {e:e}, seed {seed})",
        term.name(),
        norm(&g_fd)
    );
    let big = (0..g_fd.len())
        .max_by(|&i, &j| g_fd[i].abs().total_cmp(&g_fd[j].abs()))
        .unwrap();
    let mut wrong = asm.grad.clone();
    wrong[big] *= 1.0 + 1e-4;
    assert!(
        fd::rel_error(&wrong, &g_fd, 1e-12) > 1e-6,
        "{}: the check would not see a 1e-4 error (seed {seed})",
        term.name()
    );
    assert!(
        err_h < 1e-6,
        "{} Hessian: relative error {err_h:e} (seed {seed})",
        term.name()
    );
}

/// Relative errors of the analytic gradient and Hessian in `asm` (assembled at `q`) against
/// central differences of `value` and of `grad`, and the numerical gradient.
fn fd_errors(
    q: &[f64],
    asm: &Assembly,
    value: &mut dyn FnMut(&[f64]) -> f64,
    grad: &mut dyn FnMut(&[f64]) -> Vec<f64>,
) -> (f64, f64, Vec<f64>) {
    let g_fd = fd::gradient(value, q, 1e-6);
    let err_g = fd::rel_error(&asm.grad, &g_fd, 1e-12);
    let h_fd = fd::jacobian(grad, q, 1e-6);
    let n = q.len();
    let h_an: Vec<f64> = (0..n * n).map(|k| asm.h(k / n, k % n)).collect();
    let h_num: Vec<f64> = h_fd.iter().flatten().copied().collect();
    let err_h = fd::rel_error(&h_an, &h_num, 1e-12);
    (err_g, err_h, g_fd)
}

#[test]
fn every_term_matches_finite_differences() {
    for term in energy::rod_terms() {
        if term.name() == "gravity" {
            // Linear: its gradient is `-m_k g_c` on every position row, its Hessian zero.
            let (m, s, q, kappa0, m0) = random_setup(3);
            let g = [0.3, -0.2, -9.81];
            let ctx = Ctx {
                model: &m,
                frames: &s.frames,
                kappa0: &kappa0,
                m0: &m0,
                gravity: g,
                rest_len: &m.rest_len,
                elastic_scale: 1.0,
            };
            let mut asm = Assembly::new(m.ndof);
            term.eval(&ctx, &q, Some(&mut asm), false);
            for i in 0..m.nodes {
                for c in 0..3 {
                    let k = dof::node(i) + c;
                    assert_eq!(asm.grad[k], -m.mass[k] * g[c], "gravity gradient at {k}");
                }
            }
            for j in 0..m.nodes - 1 {
                assert_eq!(asm.grad[dof::edge(j)], 0.0, "gravity on a twist angle");
            }
            for k in 0..m.ndof * m.ndof {
                assert_eq!(asm.h(k / m.ndof, k % m.ndof), 0.0, "gravity Hessian");
            }
        }
        for seed in 1..=12 {
            check_term(term.as_ref(), seed);
        }
    }
}

#[test]
fn projected_hessian_is_positive_semidefinite() {
    let (m, s, q, kappa0, m0) = random_setup(7);
    let ctx = Ctx {
        model: &m,
        frames: &s.frames,
        kappa0: &kappa0,
        m0: &m0,
        gravity: [0.0; 3],
        rest_len: &m.rest_len,
        elastic_scale: 1.0,
    };
    let mut asm = Assembly::new(m.ndof);
    energy::total(&energy::rod_terms(), &ctx, &q, Some(&mut asm), true);
    let n = m.ndof;
    let h = nalgebra::DMatrix::from_fn(n, n, |i, j| asm.h(i, j));
    let min = h.symmetric_eigenvalues().min();
    let max = h.symmetric_eigenvalues().max();
    assert!(
        min > -1e-9 * max,
        "projected Hessian has eigenvalue {min} (max {max})"
    );
    // Unprojected it is indefinite for this strongly perturbed rod.
    let mut raw = Assembly::new(m.ndof);
    energy::total(&energy::rod_terms(), &ctx, &q, Some(&mut raw), false);
    let hr = nalgebra::DMatrix::from_fn(n, n, |i, j| raw.h(i, j));
    assert!(hr.symmetric_eigenvalues().min() < -1e-9 * max);
}

fn rotate(rm: &nalgebra::Matrix3<f64>, v: [f64; 3]) -> [f64; 3] {
    let r = rm * nalgebra::Vector3::from(v);
    [r[0], r[1], r[2]]
}

#[test]
fn energies_are_invariant_under_rigid_motions() {
    for seed in 1..=5 {
        let (m, s, q, kappa0, m0) = random_setup(seed);
        let rm = nalgebra::Rotation3::from_euler_angles(0.3 * seed as f64, -0.7, 1.1).into_inner();
        let shift = [0.4, -1.3, 2.2];
        let mut q2 = q.clone();
        for i in 0..m.nodes {
            let k = dof::node(i);
            let x = rotate(&rm, [q[k], q[k + 1], q[k + 2]]);
            for c in 0..3 {
                q2[k + c] = x[c] + shift[c];
            }
        }
        let mut frames2 = s.frames.clone();
        for fr in frames2.iter_mut() {
            for e in 0..2 {
                fr.t_old[e] = rotate(&rm, fr.t_old[e]);
                fr.a1_old[e] = rotate(&rm, fr.a1_old[e]);
            }
        }
        let ctx = Ctx {
            model: &m,
            frames: &s.frames,
            kappa0: &kappa0,
            m0: &m0,
            gravity: [0.0; 3],
            rest_len: &m.rest_len,
            elastic_scale: 1.0,
        };
        let ctx2 = Ctx {
            model: &m,
            frames: &frames2,
            kappa0: &kappa0,
            m0: &m0,
            gravity: [0.0; 3],
            rest_len: &m.rest_len,
            elastic_scale: 1.0,
        };
        for term in energy::rod_terms() {
            if term.name() == "gravity" {
                continue;
            }
            let e1 = term.eval(&ctx, &q, None, false);
            let e2 = term.eval(&ctx2, &q2, None, false);
            assert!(
                (e1 - e2).abs() <= 1e-10 * e1.abs(),
                "{}: {e1} vs {e2}",
                term.name()
            );
            assert!(e1 > 0.0);
        }
    }
}

/// The incremental potential of a dynamic step (every rod term plus the inertia, with some
/// coordinates at the implicit Euler weight as BDF2 gives its contact normals at an event)
/// against finite differences.
#[test]
fn incremental_potential_matches_finite_differences() {
    use slither::newton::{Inertia, Objective, Potential};
    let terms = energy::rod_terms();
    for seed in 1..=4 {
        let (m, s, q, kappa0, m0) = random_setup(seed);
        let mut r = Rng(seed | 1);
        let qhat: Vec<f64> = q.iter().map(|x| x + 1e-3 * r.sym()).collect();
        let euler = [dof::node(1) + 2, dof::node(4) + 2, dof::edge(2)];
        let obj = Potential {
            model: &m,
            terms: &terms,
            frames: &s.frames,
            kappa0: &kappa0,
            m0: &m0,
            gravity: [0.0, 0.0, -9.81],
            rest_len: &m.rest_len,
            elastic_scale: 1.0,
            inertia: Some(Inertia {
                weight: 2.25e6,
                qhat: &qhat,
                euler: &euler,
                euler_weight: 1e6,
            }),
            self_contact: None,
        };
        let mut asm = Assembly::new(m.ndof);
        let f = obj.assemble(&q, &mut asm, false);
        assert!((f - obj.value(&q)).abs() <= 1e-12 * f.abs());
        let (err_g, err_h, _) = fd_errors(&q, &asm, &mut |x| obj.value(x), &mut |x| {
            let mut a = Assembly::new(m.ndof);
            obj.assemble(x, &mut a, false);
            a.grad
        });
        assert!(
            err_g < 1e-6,
            "gradient: relative error {err_g:e} (seed {seed})"
        );
        assert!(
            err_h < 1e-6,
            "Hessian: relative error {err_h:e} (seed {seed})"
        );
        // The Euler coordinates carry their own weight: the diagonal differs from the others'.
        let k = euler[0];
        let diag_energy = {
            let mut a = Assembly::new(m.ndof);
            Potential {
                inertia: None,
                ..obj
            }
            .assemble(&q, &mut a, false);
            a.h(k, k)
        };
        let inertia = asm.h(k, k) - diag_energy;
        assert!(
            (inertia / (1e6 * m.mass[k]) - 1.0).abs() < 1e-9,
            "{inertia}"
        );
    }
}
