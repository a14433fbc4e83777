//! Exact value, gradient and Hessian of a node stencil energy written once, generically, in
//! the 8 intrinsic coordinates `y = (e^{i-1}, e^i, theta^{i-1}, theta^i)`, and their chain rule
//! to the 11 node coordinates `(x_{i-1}, x_i, x_{i+1}, theta^{i-1}, theta^i)`.

use nalgebra::{SMatrix, SVector};
use num_dual::{hessian, Dual2SVec64, DualNum};

/// A scalar function of the 8 stencil coordinates, generic over the number type.
pub trait StencilEnergy {
    /// Evaluate.
    fn eval<T: DualNum<Primitive = f64>>(&self, y: &[T; 8]) -> T;
}

/// Add node `i`'s stencil value, gradient and Hessian in intrinsic coordinates (`local`),
/// the Hessian projected to positive semi-definite when `project`, to `asm` at the node
/// coordinates. Returns the value.
#[inline(always)]
pub fn add_local(
    asm: &mut crate::energy::Assembly,
    i: usize,
    local: (f64, SVector<f64, 8>, SMatrix<f64, 8, 8>),
    project: bool,
) -> f64 {
    let (v, g, mut h) = local;
    if project {
        project_psd(&mut h);
    }
    asm.add_node_stencil(i, &g, &h);
    v
}

/// Add node `i`'s stencil gradient in intrinsic coordinates to `grad` at the node coordinates
/// (chain rule: `e0 = x_i - x_{i-1}`, `e1 = x_{i+1} - x_i`).
pub fn add_gradient(grad: &mut [f64], i: usize, g: &[f64; 8]) {
    use crate::rod::dof;
    let [a, b, c] = [dof::node(i - 1), dof::node(i), dof::node(i + 1)];
    for r in 0..3 {
        grad[a + r] -= g[r];
        grad[b + r] += g[r] - g[3 + r];
        grad[c + r] += g[3 + r];
    }
    grad[dof::edge(i - 1)] += g[6];
    grad[dof::edge(i)] += g[7];
}

/// Intrinsic coordinates of node `i`'s stencil from `q`.
pub fn intrinsic(q: &[f64], i: usize) -> [f64; 8] {
    use crate::rod::dof;
    let a = dof::node(i - 1);
    let b = dof::node(i);
    let c = dof::node(i + 1);
    [
        q[b] - q[a],
        q[b + 1] - q[a + 1],
        q[b + 2] - q[a + 2],
        q[c] - q[b],
        q[c + 1] - q[b + 1],
        q[c + 2] - q[b + 2],
        q[dof::edge(i - 1)],
        q[dof::edge(i)],
    ]
}

/// Value, gradient and Hessian in intrinsic coordinates.
pub fn derivatives<E: StencilEnergy>(
    e: &E,
    y: [f64; 8],
) -> (f64, SVector<f64, 8>, SMatrix<f64, 8, 8>) {
    hessian(
        |v: SVector<Dual2SVec64<8>, 8>| {
            let arr: [Dual2SVec64<8>; 8] = std::array::from_fn(|k| v[k]);
            e.eval(&arr)
        },
        &SVector::from(y),
    )
}

/// Replace negative eigenvalues by zero: `H - sum_{lambda < 0} lambda v v^T`, with the
/// eigen-decomposition of [`sym_eigen8`] (nalgebra's as a fallback if it does not converge).
pub fn project_psd(h: &mut SMatrix<f64, 8, 8>) {
    let a: [[f64; 8]; 8] = std::array::from_fn(|i| std::array::from_fn(|j| h[(i, j)]));
    let Some((lam, v)) = sym_eigen8(&a) else {
        project_psd_nalgebra(h);
        return;
    };
    for k in 0..8 {
        if lam[k] < 0.0 {
            for i in 0..8 {
                let li = lam[k] * v[k][i];
                for j in 0..8 {
                    h[(i, j)] -= li * v[k][j];
                }
            }
        }
    }
}

/// Reference projection with nalgebra's `SymmetricEigen` (the original implementation).
pub fn project_psd_nalgebra(h: &mut SMatrix<f64, 8, 8>) {
    let eig = nalgebra::SymmetricEigen::new(*h);
    if eig.eigenvalues.iter().all(|&l| l >= 0.0) {
        return;
    }
    let mut lam = eig.eigenvalues;
    for l in lam.iter_mut() {
        *l = l.max(0.0);
    }
    *h =
        eig.eigenvectors * SMatrix::<f64, 8, 8>::from_diagonal(&lam) * eig.eigenvectors.transpose();
}

/// Eigenvalues and eigenvectors (rows of the second array) of a symmetric 8x8 matrix by
/// Householder tridiagonalisation and the implicit QL algorithm (EISPACK `tred2`/`tql2`, as
/// in JAMA), on fixed-size arrays. `None` if the iteration does not converge.
pub fn sym_eigen8(a: &[[f64; 8]; 8]) -> Option<([f64; 8], [[f64; 8]; 8])> {
    const N: usize = 8;
    let mut v = *a;
    let mut d = [0.0f64; N];
    let mut e = [0.0f64; N];
    // tred2
    d.copy_from_slice(&v[N - 1]);
    for i in (1..N).rev() {
        let mut scale = 0.0;
        let mut h = 0.0;
        for k in 0..i {
            scale += d[k].abs();
        }
        if scale == 0.0 {
            e[i] = d[i - 1];
            for j in 0..i {
                d[j] = v[i - 1][j];
                v[i][j] = 0.0;
                v[j][i] = 0.0;
            }
        } else {
            for k in 0..i {
                d[k] /= scale;
                h += d[k] * d[k];
            }
            let mut f = d[i - 1];
            let mut g = h.sqrt();
            if f > 0.0 {
                g = -g;
            }
            e[i] = scale * g;
            h -= f * g;
            d[i - 1] = f - g;
            for j in 0..i {
                e[j] = 0.0;
            }
            for j in 0..i {
                f = d[j];
                v[j][i] = f;
                g = e[j] + v[j][j] * f;
                for k in j + 1..i {
                    g += v[k][j] * d[k];
                    e[k] += v[k][j] * f;
                }
                e[j] = g;
            }
            f = 0.0;
            for j in 0..i {
                e[j] /= h;
                f += e[j] * d[j];
            }
            let hh = f / (h + h);
            for j in 0..i {
                e[j] -= hh * d[j];
            }
            for j in 0..i {
                f = d[j];
                g = e[j];
                for k in j..i {
                    v[k][j] -= f * e[k] + g * d[k];
                }
                d[j] = v[i - 1][j];
                v[i][j] = 0.0;
            }
        }
        d[i] = h;
    }
    for i in 0..N - 1 {
        v[N - 1][i] = v[i][i];
        v[i][i] = 1.0;
        let h = d[i + 1];
        if h != 0.0 {
            for k in 0..=i {
                d[k] = v[k][i + 1] / h;
            }
            for j in 0..=i {
                let mut g = 0.0;
                for k in 0..=i {
                    g += v[k][i + 1] * v[k][j];
                }
                for k in 0..=i {
                    v[k][j] -= g * d[k];
                }
            }
        }
        for k in 0..=i {
            v[k][i + 1] = 0.0;
        }
    }
    for j in 0..N {
        d[j] = v[N - 1][j];
        v[N - 1][j] = 0.0;
    }
    v[N - 1][N - 1] = 1.0;
    e[0] = 0.0;
    // tql2, accumulating the rotations into the transposed (row = eigenvector) matrix.
    let mut vt = [[0.0f64; N]; N];
    for i in 0..N {
        for j in 0..N {
            vt[j][i] = v[i][j];
        }
    }
    for i in 1..N {
        e[i - 1] = e[i];
    }
    e[N - 1] = 0.0;
    let mut f = 0.0f64;
    let mut tst1 = 0.0f64;
    let eps = f64::EPSILON;
    for l in 0..N {
        tst1 = tst1.max(d[l].abs() + e[l].abs());
        let mut m = l;
        while m < N - 1 && e[m].abs() > eps * tst1 {
            m += 1;
        }
        if m > l {
            let mut iter = 0;
            loop {
                iter += 1;
                if iter > 60 {
                    return None;
                }
                let mut g = d[l];
                let mut p = (d[l + 1] - g) / (2.0 * e[l]);
                let mut r = (p * p + 1.0).sqrt();
                if p < 0.0 {
                    r = -r;
                }
                d[l] = e[l] / (p + r);
                d[l + 1] = e[l] * (p + r);
                let dl1 = d[l + 1];
                let mut h = g - d[l];
                for di in d.iter_mut().skip(l + 2) {
                    *di -= h;
                }
                f += h;
                p = d[m];
                let mut c = 1.0;
                let mut c2 = c;
                let mut c3 = c;
                let el1 = e[l + 1];
                let mut s = 0.0;
                let mut s2 = 0.0;
                for i in (l..m).rev() {
                    c3 = c2;
                    c2 = c;
                    s2 = s;
                    g = c * e[i];
                    h = c * p;
                    r = (p * p + e[i] * e[i]).sqrt();
                    e[i + 1] = s * r;
                    s = e[i] / r;
                    c = p / r;
                    p = c * d[i] - s * g;
                    d[i + 1] = h + s * (c * g + s * d[i]);
                    let (lo, hi) = vt.split_at_mut(i + 1);
                    let (vi, vi1) = (&mut lo[i], &mut hi[0]);
                    for k in 0..N {
                        let hk = vi1[k];
                        vi1[k] = s * vi[k] + c * hk;
                        vi[k] = c * vi[k] - s * hk;
                    }
                }
                p = -s * s2 * c3 * el1 * e[l] / dl1;
                e[l] = s * p;
                d[l] = c * p;
                if !(e[l].abs() > eps * tst1) {
                    break;
                }
            }
        }
        d[l] += f;
        e[l] = 0.0;
    }
    if d.iter().all(|x| x.is_finite()) {
        Some((d, vt))
    } else {
        None
    }
}

/// Chain rule from intrinsic to node coordinates: `e0 = x_i - x_{i-1}`, `e1 = x_{i+1} - x_i`,
/// so `g_x = J^T g` and `H_x = J^T H J` with the constant 8x11 Jacobian `J` (entries 0, +-1).
/// Returns the 11-gradient and the row-major 11x11 Hessian. Written out per block (`M = H J`,
/// then `J^T M`), without multiplying by the zeros of `J`, in the order of [`dof::stencil`]:
/// the reference that [`crate::energy::Assembly::add_node_stencil`] (the same chain rule written
/// straight into the band) is tested against.
///
/// [`dof::stencil`]: crate::rod::dof::stencil
pub fn to_nodes(g: &SVector<f64, 8>, h: &SMatrix<f64, 8, 8>) -> ([f64; 11], [f64; 121]) {
    // Column b of `y J` for a row y of 8 intrinsic values.
    let cols = |y: &dyn Fn(usize) -> f64| -> [f64; 11] {
        let mut out = [0.0; 11];
        for r in 0..3 {
            out[r] = -y(r);
            out[3 + r] = y(r) - y(3 + r);
            out[6 + r] = y(3 + r);
        }
        out[9] = y(6);
        out[10] = y(7);
        out
    };
    let gx = cols(&|k| g[k]);
    // M = H J (8 x 11), then H_x = J^T M: the same pattern applied down each column.
    let m: [[f64; 11]; 8] = std::array::from_fn(|k| cols(&|l| h[(k, l)]));
    let mut hx = [0.0; 121];
    for b in 0..11 {
        let col = cols(&|k| m[k][b]);
        for a in 0..11 {
            hx[a * 11 + b] = col[a];
        }
    }
    (gx, hx)
}

/// Second-order forward-mode numbers ("jets") with a fixed number `N` of variables: value,
/// gradient and full (symmetric) Hessian in plain arrays, so that the stencils can be
/// differentiated in stages over only the variables each intermediate depends on (an edge's
/// frame over its 3 edge coordinates, the curvature binormal and reference twist over the 6
/// positional coordinates, and the final strains over all 8).
pub mod jet {
    use std::ops::{Add, Mul, Neg, Sub};

    /// Value, gradient and Hessian of a scalar function of `N` variables.
    #[derive(Clone, Copy, Debug)]
    pub struct Jet<const N: usize> {
        /// Value.
        pub v: f64,
        /// Gradient.
        pub g: [f64; N],
        /// Hessian (full, symmetric).
        pub h: [[f64; N]; N],
    }

    impl<const N: usize> Jet<N> {
        /// A constant.
        #[inline(always)]
        pub fn cst(v: f64) -> Self {
            Jet {
                v,
                g: [0.0; N],
                h: [[0.0; N]; N],
            }
        }
        /// Variable `k` with value `v`.
        #[inline(always)]
        pub fn var(v: f64, k: usize) -> Self {
            let mut j = Self::cst(v);
            j.g[k] = 1.0;
            j
        }
        /// `f(self)` given `f`, `f'`, `f''` at the value.
        #[inline(always)]
        pub fn chain(&self, f0: f64, f1: f64, f2: f64) -> Self {
            let mut r = Self::cst(f0);
            for i in 0..N {
                r.g[i] = f1 * self.g[i];
            }
            for i in 0..N {
                let gi = f2 * self.g[i];
                for j in 0..N {
                    r.h[i][j] = f1 * self.h[i][j] + gi * self.g[j];
                }
            }
            r
        }
        /// `1 / self`.
        #[inline(always)]
        pub fn recip(&self) -> Self {
            let r = 1.0 / self.v;
            self.chain(r, -r * r, 2.0 * r * r * r)
        }
        /// Square root.
        #[inline(always)]
        pub fn sqrt(&self) -> Self {
            let s = self.v.sqrt();
            self.chain(s, 0.5 / s, -0.25 / (s * self.v))
        }
        /// `(sin, cos)`.
        #[inline(always)]
        pub fn sin_cos(&self) -> (Self, Self) {
            let (s, c) = self.v.sin_cos();
            (self.chain(s, c, -s), self.chain(c, -s, -c))
        }
        /// `atan2(self, x)`.
        #[inline(always)]
        pub fn atan2(&self, x: &Self) -> Self {
            let mut r = self.atan2_derivatives(x);
            r.v = self.v.atan2(x.v);
            r
        }
        /// The gradient and Hessian of `atan2(self, x)` only (value left at 0: no `atan2`
        /// call), for a caller that takes the angle's value elsewhere.
        #[inline(always)]
        pub fn atan2_derivatives(&self, x: &Self) -> Self {
            let (yv, xv) = (self.v, x.v);
            let rho = 1.0 / (xv * xv + yv * yv);
            let fy = xv * rho;
            let fx = -yv * rho;
            let fyy = -2.0 * xv * yv * rho * rho;
            let fxx = -fyy;
            let fxy = (yv * yv - xv * xv) * rho * rho;
            let mut r = Self::cst(0.0);
            for i in 0..N {
                r.g[i] = fy * self.g[i] + fx * x.g[i];
            }
            for i in 0..N {
                let (ay, ax) = (self.g[i], x.g[i]);
                let cy = fyy * ay + fxy * ax;
                let cx = fxx * ax + fxy * ay;
                for j in 0..N {
                    r.h[i][j] = fy * self.h[i][j] + fx * x.h[i][j] + cy * self.g[j] + cx * x.g[j];
                }
            }
            r
        }
        /// This jet of `M <= N` variables seen as one of `N` variables, its variables at
        /// `off..off + M`.
        #[inline(always)]
        pub fn embed<const M: usize>(a: &Jet<M>, off: usize) -> Self {
            let mut r = Self::cst(a.v);
            for i in 0..M {
                r.g[off + i] = a.g[i];
                for j in 0..M {
                    r.h[off + i][off + j] = a.h[i][j];
                }
            }
            r
        }
    }

    impl<const N: usize> Add for Jet<N> {
        type Output = Self;
        #[inline(always)]
        fn add(mut self, o: Self) -> Self {
            self.v += o.v;
            for i in 0..N {
                self.g[i] += o.g[i];
                for j in 0..N {
                    self.h[i][j] += o.h[i][j];
                }
            }
            self
        }
    }
    impl<const N: usize> Sub for Jet<N> {
        type Output = Self;
        #[inline(always)]
        fn sub(mut self, o: Self) -> Self {
            self.v -= o.v;
            for i in 0..N {
                self.g[i] -= o.g[i];
                for j in 0..N {
                    self.h[i][j] -= o.h[i][j];
                }
            }
            self
        }
    }
    impl<const N: usize> Neg for Jet<N> {
        type Output = Self;
        #[inline(always)]
        fn neg(self) -> Self {
            self * -1.0
        }
    }
    impl<const N: usize> Add<f64> for Jet<N> {
        type Output = Self;
        #[inline(always)]
        fn add(mut self, o: f64) -> Self {
            self.v += o;
            self
        }
    }
    impl<const N: usize> Sub<f64> for Jet<N> {
        type Output = Self;
        #[inline(always)]
        fn sub(mut self, o: f64) -> Self {
            self.v -= o;
            self
        }
    }
    impl<const N: usize> Mul<f64> for Jet<N> {
        type Output = Self;
        #[inline(always)]
        fn mul(mut self, s: f64) -> Self {
            self.v *= s;
            for i in 0..N {
                self.g[i] *= s;
                for j in 0..N {
                    self.h[i][j] *= s;
                }
            }
            self
        }
    }
    impl<const N: usize> Mul for Jet<N> {
        type Output = Self;
        #[inline(always)]
        fn mul(self, o: Self) -> Self {
            let mut r = Self::cst(self.v * o.v);
            for i in 0..N {
                r.g[i] = self.v * o.g[i] + o.v * self.g[i];
            }
            for i in 0..N {
                let (a, b) = (self.g[i], o.g[i]);
                for j in 0..N {
                    r.h[i][j] =
                        self.v * o.h[i][j] + o.v * self.h[i][j] + a * o.g[j] + b * self.g[j];
                }
            }
            r
        }
    }

    /// A 3-vector of jets.
    pub type JV<const N: usize> = [Jet<N>; 3];

    /// Constant vector.
    #[inline(always)]
    pub fn lift<const N: usize>(v: [f64; 3]) -> JV<N> {
        [Jet::cst(v[0]), Jet::cst(v[1]), Jet::cst(v[2])]
    }
    /// Dot product.
    #[inline(always)]
    pub fn dot<const N: usize>(a: &JV<N>, b: &JV<N>) -> Jet<N> {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }
    /// Cross product.
    #[inline(always)]
    pub fn cross<const N: usize>(a: &JV<N>, b: &JV<N>) -> JV<N> {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }
    /// Sum.
    #[inline(always)]
    pub fn add<const N: usize>(a: &JV<N>, b: &JV<N>) -> JV<N> {
        [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
    }
    /// Scale by a jet.
    #[inline(always)]
    pub fn scale<const N: usize>(a: &JV<N>, s: &Jet<N>) -> JV<N> {
        [a[0] * *s, a[1] * *s, a[2] * *s]
    }
    /// Embed every component (see [`Jet::embed`]).
    #[inline(always)]
    pub fn embed<const M: usize, const N: usize>(a: &JV<M>, off: usize) -> JV<N> {
        [
            Jet::embed(&a[0], off),
            Jet::embed(&a[1], off),
            Jet::embed(&a[2], off),
        ]
    }
    /// Parallel transport of `u` from `t1` to `t2` (as [`crate::rod::vec3::transport`]).
    #[inline(always)]
    pub fn transport<const N: usize>(t1: &JV<N>, t2: &JV<N>, u: &JV<N>) -> JV<N> {
        let c = dot(t1, t2);
        let v = cross(t1, t2);
        let vu = dot(&v, u);
        let k = vu * (c + 1.0).recip();
        add(&add(&scale(u, &c), &cross(&v, u)), &scale(&v, &k))
    }

    /// Frame of one edge as jets of its 3 edge-vector coordinates: length, unit tangent,
    /// reference director `a1` (transported from the frozen frame) and `a2 = t x a1`.
    #[inline(always)]
    pub fn edge_frame(
        e: [f64; 3],
        t_old: [f64; 3],
        a1_old: [f64; 3],
    ) -> (Jet<3>, JV<3>, JV<3>, JV<3>) {
        let ev: JV<3> = [Jet::var(e[0], 0), Jet::var(e[1], 1), Jet::var(e[2], 2)];
        let n = dot(&ev, &ev).sqrt();
        let t = scale(&ev, &n.recip());
        let a = transport(&lift(t_old), &t, &lift(a1_old));
        let b = cross(&t, &a);
        (n, t, a, b)
    }

    /// Value, gradient and Hessian as nalgebra types.
    pub fn to_na(j: &Jet<8>) -> (f64, nalgebra::SVector<f64, 8>, nalgebra::SMatrix<f64, 8, 8>) {
        (
            j.v,
            nalgebra::SVector::from(j.g),
            nalgebra::SMatrix::from_fn(|a, b| j.h[a][b]),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use testing::Rng;

    #[test]
    fn chain_rule_to_nodes_equals_the_dense_jacobian_product() {
        // J: d(intrinsic)/d(node coordinates), built entry by entry.
        let mut j = SMatrix::<f64, 8, 11>::zeros();
        for r in 0..3 {
            j[(r, r)] = -1.0;
            j[(r, 3 + r)] = 1.0;
            j[(3 + r, 3 + r)] = -1.0;
            j[(3 + r, 6 + r)] = 1.0;
        }
        j[(6, 9)] = 1.0;
        j[(7, 10)] = 1.0;
        let mut r = Rng(777);
        for _ in 0..50 {
            let b = SMatrix::<f64, 8, 8>::from_fn(|_, _| r.sym());
            let h = b + b.transpose();
            let g = SVector::<f64, 8>::from_fn(|_, _| r.sym());
            let (gx, hx) = to_nodes(&g, &h);
            let gd = j.transpose() * g;
            let hd = j.transpose() * h * j;
            for a in 0..11 {
                assert!((gx[a] - gd[a]).abs() < 1e-14);
                for c in 0..11 {
                    assert!((hx[a * 11 + c] - hd[(a, c)]).abs() < 1e-13, "({a},{c})");
                }
            }
        }
    }

    #[test]
    fn eigen8_and_projection_match_nalgebra() {
        let mut r = Rng(12345);
        for case in 0..500 {
            // Random symmetric matrices of varied spectra, some with repeated/zero eigenvalues.
            let b = SMatrix::<f64, 8, 8>::from_fn(|_, _| r.sym());
            let mut a = b + b.transpose();
            if case % 3 == 1 {
                let q = nalgebra::SymmetricEigen::new(a).eigenvectors;
                let lam =
                    SVector::<f64, 8>::from_fn(
                        |k, _| if k < 3 { 0.0 } else { (k as f64 - 5.0) * 1e-3 },
                    );
                a = q * SMatrix::from_diagonal(&lam) * q.transpose();
            }
            let arr: [[f64; 8]; 8] = std::array::from_fn(|i| std::array::from_fn(|j| a[(i, j)]));
            let (lam, v) = sym_eigen8(&arr).expect("converges");
            let vm = SMatrix::<f64, 8, 8>::from_fn(|i, j| v[j][i]);
            let rec = vm * SMatrix::from_diagonal(&SVector::from(lam)) * vm.transpose();
            let scale = a.abs().max();
            assert!(
                (rec - a).abs().max() < 1e-13 * scale,
                "reconstruction (case {case})"
            );
            assert!(
                (vm.transpose() * vm - SMatrix::<f64, 8, 8>::identity())
                    .abs()
                    .max()
                    < 1e-13
            );
            let (mut p1, mut p2) = (a, a);
            project_psd(&mut p1);
            project_psd_nalgebra(&mut p2);
            assert!(
                (p1 - p2).abs().max() < 1e-13 * scale,
                "projection (case {case})"
            );
        }
    }
}

/// Random non-degenerate stencils for comparing the staged jets with `num-dual`.
#[cfg(test)]
pub(crate) mod testing {
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
        got: super::super::stencil::Local,
        want: super::super::stencil::Local,
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
}
