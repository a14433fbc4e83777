//! slither: a simulator and gait designer for snake locomotion.
//!
//! The snake is a Discrete Elastic Rod (Bergou et al. 2008, time-parallel frames of Bergou et
//! al. 2010) on the ground. Every step solves the variational implicit Euler problem
//!
//! ```text
//! q_{n+1} = argmin_q 1/(2h^2) (q - qhat)^T M (q - qhat) + E(q, t_{n+1}) + B(q) + h D(v; N)
//!           subject to z_i - a/2 >= 0,          qhat = q_n + h v_n,  v_{n+1} = (q_{n+1} - q_n)/h
//! ```
//!
//! (BDF2 changes only `qhat` and the weight) by Newton's method on a band Cholesky (checked
//! against faer's sparse one). `B` is the self-contact barrier that keeps parts of the body
//! more than `2a` apart along it at a centreline distance above `a`
//! ([`energy::self_contact`]; its Hessian is a low-rank part beside the band, solved by
//! Woodbury). Ground contact with anisotropic Coulomb friction `D` is solved by default by a
//! semi-smooth Newton on the Alart-Curnier function ([`contact::semismooth`]), with the
//! second-order-cone program (Clarabel, [`contact::conic`]) as its fallback and certificate.
//! A contact is a point of the body given as a stencil of nodes ([`contact::Contact`]); the
//! contact set belongs to a dispatcher that hands it to the two solvers
//! ([`contact::Dispatcher`]).

//! Module map, in layers: a module uses only modules of its own or lower layers, so the
//! top-level modules import each other without cycles.
//!
//! 0. [`rod`] (dof layout, vectors, frames) and [`fd`] (the finite-difference checker of the
//!    tests): leaves; [`band`] (the gradient and band Hessian every term and contact model adds
//!    into, and the band Cholesky that solves with it; it knows only the bandwidth of
//!    [`rod::dof`]).
//! 1. [`problem`]: problem files (TOML schema with defaults, validation, the `[gait]` and
//!    `[solver]` tables).
//! 2. [`model`] (the immutable model: geometry, masses, ground, the compiled gait) and
//!    [`state`] (positions, velocities, reference frames).
//! 3. Physics: [`energy`] (stretch, bending and twist of each node together, gravity; the
//!    reference derivatives the node's closed form is tested against are compiled for tests
//!    and benches only), [`gait`] (muscles as time-dependent rest strains:
//!    [`gait::Actuation`]).
//! 4. [`newton`]: Newton's method on an objective (assembly, factorisation by [`band`], line
//!    search, statistics, typed failures), and the incremental potential of a step.
//! 5. [`contact`]: ground contact behind [`contact::ContactModel`]: contacts as stencils of
//!    nodes, the contact set and its dispatcher, and the solvers that take the set (the
//!    semi-smooth Newton by default; the conic program by Clarabel as its fallback and
//!    certificate), solving a step's problem with Newton's building blocks.
//! 6. [`integrator`]: time steppers behind [`integrator::Stepper`]: the implicit stepper with
//!    a time integration [`integrator::Scheme`] (implicit Euler), static equilibrium, and the
//!    explicit velocity Verlet reference.
//! 7. [`sim`]: the one run loop.
//! 8. Observables and output: [`topology`] (twist, writhe, link, densities), [`observe`]
//!    (speeds, kymograph fields, regimes; [`observe::evaluate()`], the one simulate-then-measure
//!    pipeline), [`output`] (files), [`plot`] (figures).
//! 9. Studies: [`studies`] (gait optimisation, the phase diagram, accuracy selection,
//!    ensembles) and [`charts`] (speed against accuracy).
//! 10. [`pipeline`]: one run of a problem, for every caller (load and validate, choose the
//!     accuracy, simulate, measure, summarise, stage and write).
//! 11. The command line (`main.rs` and `cli/`, one file per subcommand; a module of the binary,
//!     not of this library), the only place that reads the environment and prints.
//!
//! Where to add things:
//! * a time integrator: a [`integrator::Scheme`] in one new file under `integrator/` plus a
//!   variant of [`problem::IntegratorKind`] (mapped in [`integrator::scheme_for`]); the
//!   names [`integrator::Stepper`], [`integrator::Integrator`] and [`integrator::Scheme`] are
//!   explained together in [`integrator`];
//! * an energy term: a [`energy::Term`] (value; gradient and Hessian added into the
//!   [`band::Assembly`]) in one new file under `energy/` plus a line in
//!   [`energy::rod_terms`], the one list the implicit, static and explicit steppers use (per
//!   edge like `stretch.rs`, per node like `gravity.rs`), and its check against finite
//!   differences in `tests/derivatives.rs`. A term over a node's stencil takes its
//!   coordinates from [`energy::local::intrinsic`] and adds its derivatives with
//!   [`energy::local::add_local`]. Bending and twist run as one fused closed-form node
//!   stencil, [`energy::bend_twist::BendTwist`]; a change to the node's strains goes there and into
//!   the generic energies of [`energy::stencil`] (the value, the explicit gradient and the
//!   hyper-dual reference), and is checked against the references of `energy/reference/`
//!   (`cargo test` builds them; real runs never do);
//! * a contact model: a [`contact::ContactModel`] in one new file under `contact/` plus a
//!   variant of [`problem::ContactKind`] (mapped in [`contact::model_for`]);
//! * a study kind: a module under `studies/` (as [`studies::phase`]) that builds each run's
//!   problem and measures it with [`observe::evaluate()`], plus a file `cli/NAME.rs` with its
//!   arguments and one variant in `main.rs`.
#![warn(missing_docs)]
// Numerical kernels index several arrays (coordinates, masses, flags, predictor) with one dof
// index `k`; the index loop states that correspondence more plainly than zipped iterators.
#![allow(clippy::needless_range_loop)]
// `!(x > y)` is deliberate where a NaN must take the "not satisfied" branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
pub mod band;
pub mod charts;
pub mod contact;
pub mod energy;
pub mod fd;
pub mod gait;
pub mod integrator;
pub mod model;
pub mod newton;
pub mod observe;
pub mod output;
pub mod pipeline;
pub mod plot;
pub mod problem;
pub mod rod;
pub mod sim;
pub mod state;
pub mod studies;
pub mod topology;
