//! The chain from a node stencil's intrinsic coordinates to the rod's: the intrinsic
//! coordinates `y = (e^{i-1}, e^i, theta^{i-1}, theta^i)` of node `i` from `q`
//! ([`intrinsic`]), and a stencil's value, gradient and Hessian in them ([`Local`]) added to
//! the band at the 11 node coordinates `(x_{i-1}, theta^{i-1}, x_i, theta^i, x_{i+1})`
//! ([`add_local`], [`add_node_stencil`]; the gradient alone: [`add_gradient`]). The chain
//! rule is linear (`e0 = x_i - x_{i-1}`, `e1 = x_{i+1} - x_i`). On request the stencil's
//! Hessian is first made positive semi-definite ([`project_psd`], by the fixed-size
//! eigen-decomposition [`sym_eigen8`]).

use crate::band::Assembly;
use crate::rod::dof;
use nalgebra::{SMatrix, SVector};

/// Value, gradient and Hessian in the 8 intrinsic coordinates of a stencil.
pub type Local = (f64, SVector<f64, 8>, SMatrix<f64, 8, 8>);

/// Add node `i`'s stencil value, gradient and Hessian in intrinsic coordinates (`local`),
/// the Hessian projected to positive semi-definite when `project`, to `asm` at the node
/// coordinates. Returns the value.
#[inline(always)]
pub fn add_local(asm: &mut Assembly, i: usize, local: Local, project: bool) -> f64 {
    let (v, g, mut h) = local;
    if project {
        project_psd(&mut h);
    }
    add_node_stencil(asm, i, &g, &h);
    v
}

/// Add node `i`'s stencil gradient in intrinsic coordinates to `grad` at the node coordinates
/// (chain rule: `e0 = x_i - x_{i-1}`, `e1 = x_{i+1} - x_i`).
pub fn add_gradient(grad: &mut [f64], i: usize, g: &[f64; 8]) {
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

/// Add interior node `i`'s stencil gradient and Hessian, given in its intrinsic
/// coordinates `(e^{i-1}, e^i, theta^{i-1}, theta^i)`, to `asm` at the node coordinates: the
/// chain rule (`g_x = J^T g`, `H_x = J^T H J`, `J` the constant 8x11 Jacobian of entries 0,
/// +-1) written straight into the band. The stencil's 11 coordinates are the band's
/// `dof::node(i - 1) ..= dof::node(i + 1) + 2` in the order `x_{i-1}, theta^{i-1}, x_i,
/// theta^i, x_{i+1}`, so column `b` of the node Hessian adds its upper part to one contiguous
/// slice of column `first + b`.
pub fn add_node_stencil(asm: &mut Assembly, i: usize, g: &SVector<f64, 8>, h: &SMatrix<f64, 8, 8>) {
    /// `y J` in band order for a row `y` over the intrinsic coordinates.
    #[inline(always)]
    fn band_row(y: [f64; 8]) -> [f64; 11] {
        [
            -y[0],
            -y[1],
            -y[2],
            y[6],
            y[0] - y[3],
            y[1] - y[4],
            y[2] - y[5],
            y[7],
            y[3],
            y[4],
            y[5],
        ]
    }
    let w = asm.half_bandwidth();
    let first = dof::node(i - 1);
    debug_assert_eq!(dof::node(i + 1) + 2 - first, w);
    let gx = band_row(std::array::from_fn(|k| g[k]));
    for (d, x) in asm.grad[first..=first + w].iter_mut().zip(gx) {
        *d += x;
    }
    // M = H J (8 x 11, H symmetric so its columns are its rows), then column b of
    // J^T M is band_row of column b of M.
    let m: [[f64; 11]; 8] = std::array::from_fn(|k| band_row(std::array::from_fn(|l| h[(l, k)])));
    for b in 0..11 {
        let col = band_row(std::array::from_fn(|k| m[k][b]));
        let j = first + b;
        let start = asm.col_ptr[j] + first - j.saturating_sub(w);
        for (v, x) in asm.values[start..=start + b].iter_mut().zip(&col) {
            *v += x;
        }
    }
}

/// Replace negative eigenvalues by zero: `H - sum_{lambda < 0} lambda v v^T`, with the
/// eigen-decomposition of [`sym_eigen8`] (nalgebra's if it does not converge).
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

/// [`project_psd`] with nalgebra's `SymmetricEigen`: the fallback when [`sym_eigen8`] does not
/// converge, and the reference it is tested against.
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::reference::local::to_nodes;
    use crate::energy::reference::testing::Rng;

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

    /// A node stencil in intrinsic coordinates added straight into the band equals its chain
    /// rule to the 11 node coordinates ([`to_nodes`], the reference) added entry by entry.
    #[test]
    fn node_stencil_scatter_equals_chain_rule_then_entrywise() {
        let n = dof::count(7);
        let (mut fast, mut slow) = (Assembly::new(n), Assembly::new(n));
        for i in 1..6 {
            let g = nalgebra::SVector::<f64, 8>::from_fn(|k, _| ((k + 3 * i) as f64).cos());
            let b = nalgebra::SMatrix::<f64, 8, 8>::from_fn(|a, c| ((a * 8 + c + i) as f64).sin());
            let h = b + b.transpose();
            add_node_stencil(&mut fast, i, &g, &h);
            let (gx, hx) = to_nodes(&g, &h);
            let idx = dof::stencil(i);
            for a in 0..11 {
                slow.grad[idx[a]] += gx[a];
                for c in 0..11 {
                    if idx[a] <= idx[c] {
                        slow.add_h(idx[a], idx[c], hx[a * 11 + c]);
                    }
                }
            }
        }
        for k in 0..n {
            assert!((fast.grad[k] - slow.grad[k]).abs() < 1e-14, "gradient {k}");
        }
        for (p, (x, y)) in fast.values.iter().zip(&slow.values).enumerate() {
            assert!((x - y).abs() < 1e-13, "Hessian entry {p}: {x} vs {y}");
        }
    }
}
