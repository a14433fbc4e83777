//! Reference implementations of the bending and twist derivatives, compiled for tests and
//! benches only (cargo feature `reference`, which the crate's tests and benches turn on
//! through its dev-dependency on itself; real runs never call them).
//!
//! Real runs take a node's bending and twist value, gradient and Hessian from one fused
//! closed form ([`super::bend_twist`]). Its correctness rests on independent computations of the
//! same derivatives, kept here, each tested against the one before:
//!
//! 1. [`autodiff`]: the energies written once, generically over the scalar
//!    ([`super::stencil::StencilEnergy`]), differentiated by `num-dual` hyper-dual numbers;
//! 2. [`jets`]: staged second-order jets, against the hyper-dual numbers;
//! 3. [`closed`]: per-term closed forms, against the jets;
//! 4. [`terms`]: bending and twist as two separate energy terms over either of these (the
//!    [`terms::StencilDerivatives`] seam), for whole-rod comparisons and benches;
//! 5. [`local`]: the chain rule to the node coordinates as an 11x11 product, against which
//!    the band scatter of [`super::local::add_node_stencil`] is tested.
//!
//! The fused stencil is then tested against the jets (`energy/bend_twist.rs`), and every term of
//! [`super::rod_terms`] against finite differences (`tests/derivatives.rs`).

pub mod autodiff;
pub mod closed;
pub mod jets;
pub mod local;
pub mod terms;
#[cfg(test)]
pub(crate) mod testing;
