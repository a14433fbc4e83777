//! slither: a simulator and gait designer for snake locomotion.
//!
//! The snake is a Discrete Elastic Rod (Bergou et al. 2008, time-parallel frames of Bergou et
//! al. 2010) on the ground. Every step solves the variational implicit Euler problem
//!
//! ```text
//! q_{n+1} = argmin_q 1/(2h^2) (q - qhat)^T M (q - qhat) + E(q, t_{n+1}) + h D(v; N)
//!           subject to z_i - a/2 >= 0,          qhat = q_n + h v_n,  v_{n+1} = (q_{n+1} - q_n)/h
//! ```
//!
//! by Newton's method on faer's sparse Cholesky, with anisotropic Coulomb friction `D` as a
//! second-order-cone program (Clarabel) or, when the contact modes are settled, as an
//! active-set Newton iteration checked against the Coulomb conditions.
//!
//! Module map: [`problem`] (TOML schema and validation) -> [`model`] (immutable model) and
//! [`state`]; [`rod`] (dof layout, frames, strains); [`energy`] (stretch, bend, twist,
//! gravity); [`gait`] (muscles as moving natural curvature); [`contact`] (gaps, friction,
//! conic program, active set); [`integrator`] (the step, halving, static solve); [`sim`]
//! (the run loop); [`topology`] (twist, writhe, link, densities); [`observe`] (speeds,
//! kymograph fields, regimes); [`output`] and [`plot`] (files and figures); [`design`] (the gait
//! optimiser, argmin's Nelder-Mead over simulations); [`fd`] (the finite-difference checker
//! used by the tests).
#![warn(missing_docs)]
// Numerical kernels index several arrays (coordinates, masses, flags, predictor) with one dof
// index `k`; the index loop states that correspondence more plainly than zipped iterators.
#![allow(clippy::needless_range_loop)]
// `!(x > y)` is deliberate where a NaN must take the "not satisfied" branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
pub mod chart;
pub mod contact;
pub mod design;
pub mod energy;
pub mod fd;
pub mod gait;
pub mod integrator;
pub mod model;
pub mod newton;
pub mod observe;
pub mod output;
pub mod plot;
pub mod problem;
pub mod rod;
pub mod sim;
pub mod state;
pub mod topology;
