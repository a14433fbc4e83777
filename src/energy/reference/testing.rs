//! Random non-degenerate stencils and comparisons for the derivative tests.

use crate::rod::frames::StencilFrame;
use crate::rod::vec3::f;

/// Xorshift, uniform in [-1, 1).
pub struct Rng(pub u64);
impl Rng {
    pub fn sym(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
    fn v3(&mut self) -> [f64; 3] {
        [self.sym(), self.sym(), self.sym()]
    }
}

/// A frozen frame near the edges `e0`, `e1`, intrinsic coordinates and the rng.
pub fn stencil(seed: u64) -> (StencilFrame, [f64; 8], Rng) {
    let mut r = Rng(seed.wrapping_mul(0x9E3779B97F4A7C15) | 1);
    let base = f::unit(r.v3());
    let e0 = f::scale(f::add(base, f::scale(r.v3(), 0.5)), 0.1);
    let e1 = f::scale(f::add(base, f::scale(r.v3(), 0.5)), 0.1);
    let mut t_old = [[0.0; 3]; 2];
    let mut a1_old = [[0.0; 3]; 2];
    for (k, e) in [e0, e1].into_iter().enumerate() {
        t_old[k] = f::unit(f::add(f::unit(e), f::scale(r.v3(), 0.3)));
        a1_old[k] = f::unit(f::cross(t_old[k], r.v3()));
    }
    let mut p = StencilFrame {
        t_old,
        a1_old,
        ref_twist_prev: 0.0,
    };
    p.ref_twist_prev = crate::rod::frames::ref_twist(e0, e1, &p)
        + 0.1 * r.sym()
        + 2.0 * std::f64::consts::TAU * r.sym().round();
    let y = [
        e0[0],
        e0[1],
        e0[2],
        e1[0],
        e1[1],
        e1[2],
        3.0 * r.sym(),
        3.0 * r.sym(),
    ];
    (p, y, r)
}

/// A closed form's value, gradient and Hessian `got` equal the reference `want` for
/// stencil `seed`: the value to 1e-12, gradient and Hessian to 1e-9 relative.
pub fn assert_matches(
    got: crate::energy::local::Local,
    want: crate::energy::local::Local,
    seed: u64,
) {
    let ((v, g, h), (v_ref, g_ref, h_ref)) = (got, want);
    assert!(
        (v - v_ref).abs() <= 1e-12 * v_ref.abs().max(1e-12),
        "value {v} vs {v_ref} (seed {seed})"
    );
    let eg = rel_diff(g.as_slice(), g_ref.as_slice());
    let eh = rel_diff(h.as_slice(), h_ref.as_slice());
    assert!(
        eg < 1e-9 && eh < 1e-9,
        "gradient {eg:e}, Hessian {eh:e} (seed {seed})"
    );
}

/// Largest difference relative to the largest entry.
pub fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    let scale = a
        .iter()
        .chain(b)
        .fold(0.0f64, |m, x| m.max(x.abs()))
        .max(1e-300);
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}
