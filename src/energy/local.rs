//! The chain from a node stencil's intrinsic coordinates to the rod's: the intrinsic
//! coordinates `y = (e^{i-1}, e^i, theta^{i-1}, theta^i)` of node `i` from `q`
//! ([`intrinsic`]), and a stencil's value, gradient and Hessian in them ([`Local`]) added to
//! the band at the 11 node coordinates `(x_{i-1}, theta^{i-1}, x_i, theta^i, x_{i+1})`
//! ([`add_local`], [`add_node_stencil`]; the gradient alone: [`add_gradient`]). The chain
//! rule is linear (`e0 = x_i - x_{i-1}`, `e1 = x_{i+1} - x_i`). On request the stencil's
//! Hessian is first made positive semi-definite ([`super::psd::project_psd`]).

use super::psd::project_psd;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::reference::local::to_nodes;

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
