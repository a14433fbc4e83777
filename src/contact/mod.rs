//! Ground contact with anisotropic Coulomb friction (MODEL section 3). The default solver is
//! the semi-smooth Newton ([`semismooth`], `[solver] contact = "semi-smooth"`); the conic
//! program ([`conic`], Clarabel) is its fallback and its certificate, and a solver of its own
//! (`"conic"`). Self-contact (the body against itself) is not a contact of this module: it is
//! a barrier in the step's potential ([`crate::energy::self_contact`]) that every solver sees.
//!
//! The room, by what its parts share:
//! * [`point`]: a contact is a point anywhere on the body ([`Contact`]): a stencil of a few
//!   nodes with weights ([`Stencil`]; a ground contact at a node is one node of weight 1), its
//!   gap, its frame and its friction law ([`Ground`], whose coefficient `mu_along` decides
//!   forward against backward in one place);
//! * [`set`]: the contact set ([`ContactSet`]) with its normal forces, frames frozen per step;
//! * [`dispatch`]: the dispatcher ([`Dispatcher`]) owns the set and the statistics and hands
//!   the set to the solvers, which are peers: [`semismooth`] (with [`reactions`] and
//!   [`status`]) and [`conic`].
//!
//! The ground's contacts are the real nodes (`[solver] ground_points = "nodes"`, the default),
//! with the exact gap `z_i - a/2 >= 0` against the plane `z = 0` (an incline tilts gravity,
//! not the plane, so gaps stay linear and exact: a sliding body cannot rise, there is no
//! Anitescu drift to correct), or one contact per node at the lowest point of a parabola
//! through it and its neighbours (`"curve"`, [`set::lowest_point`]): a stencil of three nodes
//! chosen at the start of every step, whose gap is linear and exact within the step.
//!
//! At each contact the local frame is: forward `f` = the body tangent at the contact projected
//! on the ground, toward the head (s decreasing), taken at the start of the step; sideways
//! `s = e_z x f`; normal `e_z`. With the contact's slip velocity `v = (x - x_n)/h`, the friction
//! dissipation potential is `D = N sqrt((mu(v_f) v_f)^2 + (mu_s v_s)^2)`, `mu = mu_f` for
//! forward sliding and `mu_b` backward: the support function of the admissible force set (a
//! union of two half-ellipses). It is second-order-cone representable with
//! `v_f = u - w`, `u, w >= 0`, `sigma >= ||(mu_f u, mu_b w, mu_s v_s)||`, cost `h N sigma`.
//!
//! The semi-smooth Newton solves the exact Coulomb conditions (Alart-Curnier) with positions
//! and contact forces together. The conic program solves, at each Newton iterate, the convex
//! SOCP `min 1/2 dq^T H dq + g^T dq + h sum_c N_c sigma_c` subject to the gaps at `q + dq`,
//! the cone constraints and the linear slip definitions. The duals of the gap rows are the
//! normal forces `N_c`; they enter the next iterate's dissipation (a fixed point on the normal
//! forces, converged together with Newton), so at convergence the contact forces satisfy
//! exact Coulomb complementarity: stiction inside the cone, sliding on its boundary.
//!
//! There is no active-set solver (contact statuses held from one iterate and verified): no
//! bundled scene needs one (record `active-set-need`).
//!
//! The dispatcher owns its outcomes: its statistics ([`ContactStats`]) and its failures
//! ([`ContactFailure`], which wraps Newton's own).

pub mod conic;
pub mod dispatch;
pub mod point;
pub mod reactions;
pub mod semismooth;
pub mod set;
pub mod status;

pub use conic::{Conic, ConicError, ConicStep};
pub use dispatch::Dispatcher;
pub use point::{Contact, Frame, Stencil, StencilError, MAX_STENCIL};
pub use semismooth::SemiSmooth;
pub use set::ContactSet;
pub use status::ContactStatus;

pub use crate::model::Ground;

use crate::model::Model;
use crate::newton::{self, Newton, Potential};

/// A contact model: what a time step needs of ground contact. The integrator calls
/// [`ContactModel::begin_step`] once per step, [`ContactModel::solve`] to solve the step problem
/// (the incremental potential plus friction, subject to the contact constraints) with Newton's
/// building blocks, then [`ContactModel::accept`] or [`ContactModel::reject`]; the run loop reads
/// the normal forces. Implemented by the [`Dispatcher`], which hands its contact set to the
/// solvers.
pub trait ContactModel: Send {
    /// Freeze the contact frames at `q_start` and the slip origin `slip_origin` (slip is
    /// `x - x_origin`: the time integrator's velocity times its effective step), and put the
    /// iterate `q` on the feasible side of the ground. `v_start`, `h`: the state and step.
    fn begin_step(
        &mut self,
        m: &Model,
        q_start: &[f64],
        slip_origin: &[f64],
        v_start: &[f64],
        h: f64,
        q: &mut [f64],
    );
    /// Solve the step problem `min obj + friction` from the iterate `q` (overwritten with the
    /// solution). Returns the Newton iteration count.
    fn solve(
        &mut self,
        newton: &mut Newton,
        obj: &Potential,
        q: &mut Vec<f64>,
    ) -> Result<usize, ContactFailure>;
    /// Whether the step's Newton should start from the velocities extrapolated over the last
    /// two steps rather than from the scheme's predictor, where the scheme allows it (default:
    /// no).
    fn extrapolated_start(&self) -> bool {
        false
    }
    /// The step's solution `q` was accepted.
    fn accept(&mut self, m: &Model, q: &[f64]);
    /// The step was rejected: restore what `begin_step` saved.
    fn reject(&mut self);
    /// Normal force on every real node (N; zero off the ground), into `out`.
    fn normal_forces(&self, m: &Model, out: &mut [f64]);
    /// From the next step on, ground contacts between nodes (`[solver] ground_points =
    /// "curve"`) at their nodes (`true`) or on the curve again (`false`); returns whether the
    /// model has such contacts (default: none, and nothing changes).
    fn points_at_nodes(&mut self, _on: bool) -> bool {
        false
    }
    /// Set `out[r]` (real node `r`) for the nodes of every contact whose point started the
    /// step below the ground by more than the Newton tolerance (default: none).
    fn started_below(&self, _m: &Model, _out: &mut [bool]) {}
    /// The model's statistics so far (none by default).
    fn stats(&self) -> &ContactStats {
        &NO_STATS
    }
}

/// The statistics of a model that keeps none.
static NO_STATS: ContactStats = ContactStats {
    conic_solves: 0,
    conic_iterations: 0,
    conic_s: 0.0,
    warm_conic_restarts: 0,
    semismooth_steps: 0,
    semismooth_fallbacks: 0,
    semismooth_retries: 0,
    semismooth_residual_stops: 0,
    ground_point_rechoices: 0,
    ground_point_rechoice_limits: 0,
    certificates: 0,
    certificate_failures: 0,
    certificate_max_correction: 0.0,
    certificate_max_normal_change: 0.0,
    residuals: Vec::new(),
};

/// Cumulative statistics of the contact solvers (written to `summary.json` beside Newton's).
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct ContactStats {
    /// Conic (Clarabel) solves.
    pub conic_solves: usize,
    /// Clarabel interior-point iterations over all solves.
    pub conic_iterations: usize,
    /// Seconds in Clarabel (set-up and solve).
    pub conic_s: f64,
    /// Fallbacks whose conic path, started where the semi-smooth Newton stopped, failed and
    /// was rerun from the step's start.
    pub warm_conic_restarts: usize,
    /// Contact steps solved by the semi-smooth Newton ([`semismooth`]; no conic solve).
    pub semismooth_steps: usize,
    /// Contact steps where the semi-smooth Newton failed and the conic path ran.
    pub semismooth_fallbacks: usize,
    /// Semi-smooth attempts that failed and started again from the step's start with another
    /// penalty (`[solver] semi_smooth_retries`; a step solved by a retry is no fallback).
    pub semismooth_retries: usize,
    /// Semi-smooth steps that converged by their residual: every equation within the force
    /// tolerance and the positions settled while the direction still moved the force
    /// variables ([`semismooth`], convergence).
    pub semismooth_residual_stops: usize,
    /// Contact solves made again because a node with its contact on the curve sank below the
    /// ground at the solution, its point chosen again there ([`ContactSet::rechoose`]).
    pub ground_point_rechoices: usize,
    /// Steps whose points, chosen again [`dispatch::RECHOICES`] times, still left a node below
    /// the ground by more than [`set::PENETRATION_TOLERANCE`] `a` (taken as they were).
    pub ground_point_rechoice_limits: usize,
    /// Semi-smooth steps certified by the conic program (`[solver] conic_certificate`).
    pub certificates: usize,
    /// Certified steps whose conic program moved the solution by more than the Newton
    /// tolerance or changed a normal force by more than `normal_force_tolerance * W / n_c`.
    pub certificate_failures: usize,
    /// Largest correction of a certifying conic program, in units of `[solver] tolerance`
    /// (positions over `a`, angles in rad).
    pub certificate_max_correction: f64,
    /// Largest normal-force change of a certifying conic program, in units of
    /// `normal_force_tolerance * W / n_c`.
    pub certificate_max_normal_change: f64,
    /// The last semi-smooth solve's residual at each iterate (its force balance and
    /// Alart-Curnier residual relative to the mean weight per contact; NaN marks a change of
    /// contact statuses, -1 a step that was not a full step of the exact linearisation:
    /// damped, projected or with unconverged coupling), for convergence tests; not written to
    /// `summary.json`.
    #[serde(skip)]
    pub residuals: Vec<f64>,
}

/// Why a contact solve failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ContactFailure {
    /// One of Newton's own failures (its building blocks inside the contact iteration).
    #[error(transparent)]
    Newton(#[from] newton::NewtonFailure),
    /// The conic program could not be set up.
    #[error("{message} (Newton iteration {iteration})")]
    ConicSetup {
        /// Clarabel's message.
        message: String,
        /// 1-based Newton iteration.
        iteration: usize,
    },
    /// The conic program ended unsolved.
    #[error("conic solve ended with status {status} after {conic_iterations} iterations (Newton iteration {iteration})")]
    Conic {
        /// Clarabel's status.
        status: String,
        /// Interior-point iterations.
        conic_iterations: u32,
        /// 1-based Newton iteration.
        iteration: usize,
    },
}

/// The contact model a problem asks for (`[solver] contact`), or `None` without a ground.
pub fn model_for(m: &Model) -> Option<Box<dyn ContactModel>> {
    m.ground.as_ref()?;
    let semismooth = match m.solver.contact {
        crate::problem::ContactKind::Conic => false,
        crate::problem::ContactKind::SemiSmooth => true,
    };
    Some(Box::new(Dispatcher::new(m, semismooth)))
}
