//! The sliding dissipation's analytic gradient and Hessian ([`Contacts::slide_derivatives`])
//! against central differences ([`crate::fd`]) of its value ([`Contacts::dissipation`]), at
//! random slips in every direction and on both sides of the forward/backward switch
//! (`v_f = 0`, where `mu` jumps from `mu_b` to `mu_f`: the gradient is continuous there, the
//! Hessian jumps). Mutation: the sign of the Hessian's cross term `hfs` flipped in
//! `slide_derivatives`: Hessian errors 2.3e-2 (random slips) and 1.4e-3 (at the switch), both
//! tests fail.

use super::Contacts;
use crate::fd;
use crate::model::Model;
use crate::rod::dof;
use std::path::Path;

/// A rod lying on the ground, bent into an arc so that every contact has its own forward
/// direction.
fn bent_rod() -> (Model, Vec<f64>) {
    let text = "[rod]\nlength = 1.0\ndiameter = 0.02\nelements = 10\nbending_stiffness = 1e-2\n\
                [ground]\nmu_forward = 0.11\nmu_backward = 0.14\nmu_sideways = 0.20\n\
                [time]\ndt = 1e-3\nduration = 0.1\n";
    let p = crate::problem::parse(text, Path::new("<inline>")).unwrap();
    let m = Model::new(&p);
    let mut q = m.q0.clone();
    for i in m.real.clone() {
        let s = m.arc_length(i);
        let k = dof::node(i);
        q[k] = 0.8 * (s / 0.8).sin();
        q[k + 1] = 0.8 * (1.0 - (s / 0.8).cos());
    }
    (m, q)
}

/// Deterministic xorshift in [0, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Relative errors of contact `c`'s analytic gradient and Hessian in `(x, y)` at the slip
/// `(v_f, v_s)` (m, in the contact's frame), and the analytic Hessian.
fn errors(ct: &Contacts, m: &Model, q0: &[f64], c: usize, slip: [f64; 2]) -> (f64, f64, [f64; 3]) {
    let g = m.ground.as_ref().unwrap();
    let k = dof::node(ct.nodes[c]);
    let mut q = q0.to_vec();
    let (fw, sd) = (ct.forward[c], ct.side[c]);
    for a in 0..2 {
        q[k + a] = ct.x_start[c][a] + slip[0] * fw[a] + slip[1] * sd[a];
    }
    let x = [q[k], q[k + 1]];
    let at = |xy: &[f64]| {
        let mut y = q.clone();
        y[k] = xy[0];
        y[k + 1] = xy[1];
        y
    };
    let (grad, hess) = ct.slide_derivatives(g, c, &q);
    let eps = 1e-8;
    let g_fd = fd::gradient(&mut |xy| ct.dissipation(g, &at(xy)), &x, eps);
    let h_fd = fd::jacobian(
        &mut |xy| ct.slide_derivatives(g, c, &at(xy)).0.to_vec(),
        &x,
        eps,
    );
    let err_g = fd::rel_error(&grad, &g_fd, 1e-300);
    let h_an = [hess[0], hess[1], hess[1], hess[2]];
    let h_num = [h_fd[0][0], h_fd[0][1], h_fd[1][0], h_fd[1][1]];
    (err_g, fd::rel_error(&h_an, &h_num, 1e-300), hess)
}

#[test]
fn sliding_dissipation_matches_finite_differences_in_every_direction() {
    let (m, q) = bent_rod();
    let mut ct = Contacts::new(&m, &q);
    ct.begin_step(&m, &q, &q);
    let mut r = Rng(0x5eed_1234_abcd_ef01);
    for n in ct.normal.iter_mut() {
        *n = 0.05 + r.next();
    }
    let (mut worst_g, mut worst_h) = (0.0f64, 0.0f64);
    for c in 0..ct.nodes.len() {
        for _ in 0..24 {
            // Any direction, slips from 1e-4 to 1e-2 m (FD step 1e-8 m).
            let phi = 2.0 * std::f64::consts::PI * r.next();
            let len = 1e-4 * 100f64.powf(r.next());
            let (eg, eh, _) = errors(&ct, &m, &q, c, [len * phi.cos(), len * phi.sin()]);
            // Measured up to 5e-9 and 1e-8 (central differences with a 1e-8 m step).
            assert!(
                eg < 1e-7,
                "contact {c}, slip angle {phi}: gradient error {eg:e}"
            );
            assert!(
                eh < 1e-6,
                "contact {c}, slip angle {phi}: Hessian error {eh:e}"
            );
            worst_g = worst_g.max(eg);
            worst_h = worst_h.max(eh);
        }
    }
    println!("random slips: gradient error up to {worst_g:.1e}, Hessian up to {worst_h:.1e}");
}

#[test]
fn sliding_dissipation_derivatives_on_both_sides_of_the_forward_backward_switch() {
    let (m, q) = bent_rod();
    let mut ct = Contacts::new(&m, &q);
    ct.begin_step(&m, &q, &q);
    let g = m.ground.as_ref().unwrap();
    let c = 3;
    ct.normal[c] = 0.7;
    let vs = 2e-3;
    // v_f 1e-6 m on either side (100 FD steps away), and exactly on the switch (the gradient
    // is continuous there; only the Hessian jumps).
    let (eg_f, eh_f, h_f) = errors(&ct, &m, &q, c, [1e-6, vs]);
    let (eg_b, eh_b, h_b) = errors(&ct, &m, &q, c, [-1e-6, vs]);
    let (eg_0, _, _) = errors(&ct, &m, &q, c, [0.0, vs]);
    println!(
        "switch: gradient errors {eg_f:.1e} (forward), {eg_b:.1e} (backward), {eg_0:.1e} (on \
         it); Hessian errors {eh_f:.1e}, {eh_b:.1e}"
    );
    // Measured 2.5e-10 off the switch, 2.1e-7 on it (the difference straddles the jump of
    // the second derivative), 5e-10 for the Hessians.
    for e in [eg_f, eg_b] {
        assert!(e < 1e-8, "gradient error {e:e}");
    }
    assert!(eg_0 < 1e-6, "gradient error on the switch {eg_0:e}");
    for e in [eh_f, eh_b] {
        assert!(e < 1e-7, "Hessian error {e:e}");
    }
    // The forward-forward curvature of the Hessian jumps by (mu_b / mu_f)^2 across the
    // switch (in the contact's frame: f^T H f).
    let fw = ct.forward[c];
    let ff = |h: [f64; 3]| h[0] * fw[0] * fw[0] + 2.0 * h[1] * fw[0] * fw[1] + h[2] * fw[1] * fw[1];
    let ratio = ff(h_b) / ff(h_f);
    let expected = (g.mu_b / g.mu_f).powi(2);
    assert!(
        (ratio / expected - 1.0).abs() < 1e-3,
        "curvature ratio {ratio} vs {expected}"
    );
}
