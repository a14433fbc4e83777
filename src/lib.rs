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
//! by Newton's method on a band Cholesky (checked against faer's sparse one), with
//! anisotropic Coulomb friction `D` as a second-order-cone program (Clarabel) or, when the
//! contact modes are settled, as an active-set Newton iteration checked against the Coulomb
//! conditions.
//!
//! Module map, in layers: a module uses only modules of its own or lower layers, so the
//! top-level modules import each other without cycles.
//!
//! 0. [`rod`] (dof layout, vectors, frames) and [`fd`] (the finite-difference checker of the
//!    tests): leaves.
//! 1. [`problem`]: problem files (TOML schema with defaults, validation, the `[gait]` and
//!    `[solver]` tables).
//! 2. [`model`] (the immutable model: geometry, masses, ground, the compiled gait) and
//!    [`state`] (positions, velocities, reference frames).
//! 3. Physics: [`energy`] (stretch, bend, twist, gravity; the per-node stencil and its
//!    derivatives), [`gait`] (muscles as time-dependent rest strains: [`gait::Actuation`]).
//! 4. [`newton`]: Newton's method on an objective (assembly, band Cholesky, line search,
//!    statistics, typed failures), and the incremental potential of a step.
//! 5. [`contact`]: contact models behind [`contact::ContactModel`] (conic program by Clarabel,
//!    active set), solving a step's problem with Newton's building blocks.
//! 6. [`integrator`]: time steppers behind [`integrator::Stepper`]: the implicit stepper with
//!    a time integration [`integrator::Scheme`] (implicit Euler), static equilibrium, and the
//!    explicit velocity Verlet reference.
//! 7. [`sim`]: the one run loop.
//! 8. Observables and output: [`topology`] (twist, writhe, link, densities), [`observe`]
//!    (speeds, kymograph fields, regimes), [`output`] (files), [`plot`] (figures).
//! 9. Studies: [`design`] (gait optimiser, phase diagram) and [`chart`] (speed against
//!    accuracy).
//! 10. The command line (`main.rs` and `cli/`, one file per subcommand; a module of the binary,
//!     not of this library), the only place that reads the environment and prints.
//!
//! Where to add things: a time integrator is a [`integrator::Scheme`] in one new file under
//! `integrator/` plus a variant of [`problem::IntegratorKind`] (mapped in
//! [`integrator::scheme_for`]); an energy term is a [`energy::Term`] in one new file under
//! `energy/` plus a line in [`energy::rod_terms`] (the implicit and the explicit integrator
//! both use that list); a contact model is a [`contact::ContactModel`] in one new file under
//! `contact/` plus a variant of [`problem::ContactKind`] (mapped in [`contact::model_for`]).
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
