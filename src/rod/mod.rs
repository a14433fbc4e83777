//! Rod geometry: degree-of-freedom indexing, small 3-vector algebra that works on plain
//! `f64` and on `num-dual` hyper-dual numbers alike, parallel transport, and the
//! time-parallel reference frames of Bergou et al. 2010.
//!
//! Layout of the generalised coordinates `q` (interleaved so the Hessian is banded with
//! half-bandwidth 10):
//! `q = (x_0, theta^0, x_1, theta^1, ..., theta^{N-1}, x_N)`, i.e. node `i` occupies
//! `4i..4i+3` and edge `j`'s twist angle sits at `4j+3`. Always go through [`dof`].

pub mod dof;
pub mod frames;
pub mod segments;
pub mod vec3;

pub use vec3::V3;
