//! Exact value, gradient and Hessian of a stencil energy by `num-dual` hyper-dual numbers:
//! the energy written once, generically over the scalar ([`StencilEnergy`]), differentiated
//! without any hand-written derivative. Every other derivative of the bending and twist
//! stencils is checked against this.

use crate::energy::stencil::StencilEnergy;
use nalgebra::{SMatrix, SVector};
use num_dual::{hessian, Dual2SVec64};

/// Value, gradient and Hessian of a stencil energy in its intrinsic coordinates, by
/// hyper-dual numbers.
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
