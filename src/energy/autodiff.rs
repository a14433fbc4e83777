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
pub fn derivatives<E: StencilEnergy>(e: &E, y: [f64; 8]) -> (f64, SVector<f64, 8>, SMatrix<f64, 8, 8>) {
    hessian(
        |v: SVector<Dual2SVec64<8>, 8>| {
            let arr: [Dual2SVec64<8>; 8] = std::array::from_fn(|k| v[k].clone());
            e.eval(&arr)
        },
        &SVector::from(y),
    )
}

/// Replace negative eigenvalues by zero.
pub fn project_psd(h: &mut SMatrix<f64, 8, 8>) {
    let eig = nalgebra::SymmetricEigen::new(*h);
    if eig.eigenvalues.iter().all(|&l| l >= 0.0) {
        return;
    }
    let mut lam = eig.eigenvalues;
    for l in lam.iter_mut() {
        *l = l.max(0.0);
    }
    *h = eig.eigenvectors * SMatrix::<f64, 8, 8>::from_diagonal(&lam) * eig.eigenvectors.transpose();
}

/// Chain rule from intrinsic to node coordinates: `e0 = x_i - x_{i-1}`, `e1 = x_{i+1} - x_i`.
/// Returns the 11-gradient and the row-major 11x11 Hessian.
pub fn to_nodes(g: &SVector<f64, 8>, h: &SMatrix<f64, 8, 8>) -> ([f64; 11], [f64; 121]) {
    // Each intrinsic coordinate k is a combination of node coordinates: list (index, sign).
    let map = |k: usize| -> [(usize, f64); 2] {
        match k {
            0..=2 => [(k, -1.0), (k + 3, 1.0)],
            3..=5 => [(k, -1.0), (k + 3, 1.0)],
            6 => [(9, 1.0), (9, 0.0)],
            _ => [(10, 1.0), (10, 0.0)],
        }
    };
    let mut gx = [0.0; 11];
    let mut hx = [0.0; 121];
    for k in 0..8 {
        for (a, sa) in map(k) {
            gx[a] += sa * g[k];
        }
        for l in 0..8 {
            let v = h[(k, l)];
            if v == 0.0 {
                continue;
            }
            for (a, sa) in map(k) {
                for (b, sb) in map(l) {
                    hx[a * 11 + b] += sa * sb * v;
                }
            }
        }
    }
    (gx, hx)
}
