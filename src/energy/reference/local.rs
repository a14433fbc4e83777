//! References of the chain rule from a stencil's intrinsic coordinates to the node
//! coordinates ([`crate::energy::local`]): the 11x11 product written per block.

use nalgebra::{SMatrix, SVector};

/// Chain rule from intrinsic to node coordinates: `e0 = x_i - x_{i-1}`, `e1 = x_{i+1} - x_i`,
/// so `g_x = J^T g` and `H_x = J^T H J` with the constant 8x11 Jacobian `J` (entries 0, +-1).
/// Returns the 11-gradient and the row-major 11x11 Hessian. Written out per block (`M = H J`,
/// then `J^T M`), without multiplying by the zeros of `J`, in the order of [`dof::stencil`]:
/// the reference that [`crate::energy::local::add_node_stencil`] (the same chain rule written
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::reference::testing::Rng;

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
}
