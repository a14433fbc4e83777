//! A symmetric 8x8 matrix (a node stencil's Hessian in its intrinsic coordinates,
//! [`super::local`]) made positive semi-definite ([`project_psd`]: negative eigenvalues set to
//! zero) by a fixed-size eigen-decomposition ([`sym_eigen8`], EISPACK's `tred2`/`tql2`), with
//! nalgebra's `SymmetricEigen` as the fallback and the reference.

use nalgebra::SMatrix;

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
    use crate::energy::reference::testing::Rng;
    use nalgebra::SVector;

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
