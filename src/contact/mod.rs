//! Ground contact with anisotropic Coulomb friction (MODEL section 3). The default model is
//! the semi-smooth Newton ([`semismooth`], `[solver] contact = "semi-smooth"`); the conic
//! program described below is its fallback and certificate, and a model of its own
//! (`"conic"`); the active set ([`active`]) is the older default, kept for comparison (it has no
//! self-contact). Self-contact (the body against itself) is not a contact model: it is a
//! barrier in the step's potential ([`crate::energy::self_contact`]) that every model sees.
//!
//! Contact candidates are the real nodes, with the exact gap `z_i - a/2 >= 0` against the
//! plane `z = 0` (an incline tilts gravity, not the plane, so gaps stay linear and exact: a
//! sliding body cannot rise, there is no Anitescu drift to correct).
//!
//! At each contact the local frame is: forward `f` = the body tangent at the node projected
//! on the ground, toward the head (s decreasing), taken at the start of the step; sideways
//! `s = e_z x f`; normal `e_z`. With the node's slip velocity `v = (x - x_n)/h`, the friction
//! dissipation potential is `D = N sqrt((mu(v_f) v_f)^2 + (mu_s v_s)^2)`, `mu = mu_f` for
//! forward sliding and `mu_b` backward: the support function of the admissible force set (a
//! union of two half-ellipses). It is second-order-cone representable with
//! `v_f = u - w`, `u, w >= 0`, `sigma >= ||(mu_f u, mu_b w, mu_s v_s)||`, cost `h N sigma`.
//!
//! Each Newton iterate solves the convex SOCP
//! `min 1/2 dq^T H dq + g^T dq + h sum_c N_c sigma_c` subject to the gaps at `q + dq`, the
//! cone constraints and the linear slip definitions. The duals of the gap rows are the normal
//! forces `N_c`; they enter the next iterate's dissipation (a fixed point on the normal
//! forces, converged together with Newton), so at convergence the contact forces satisfy
//! exact Coulomb complementarity: stiction inside the cone, sliding on its boundary.
//!
//! The program of one iterate is formulated in [`conic`]. The semi-smooth Newton solves most
//! steps without it. The older [`active`] keeps every contact's status (free, sticking, sliding) and solves
//! the then smooth step problem by Newton, changing statuses that violate the Coulomb
//! conditions and verifying them at convergence; the conic program runs only when that fails
//! (and its solution resets the statuses).
//!
//! A contact model owns its outcomes: its statistics ([`ContactStats`]) and its failures
//! ([`ContactFailure`], which wraps Newton's own).

pub mod active;
pub mod conic;
mod deferred;
#[cfg(test)]
mod dissipation_tests;
pub mod reactions;
pub mod semismooth;
pub mod status;

pub use active::ActiveSet;
pub use conic::{Conic, ConicError, ConicStep};
pub use semismooth::SemiSmooth;
pub use status::{Mode, Statuses};

pub use crate::model::Ground;

use crate::model::Model;
use crate::newton::{self, Newton, Potential};
use crate::rod::{dof, vec3::f};

/// A contact model: what a time step needs of ground contact. The integrator calls
/// [`ContactModel::begin_step`] once per step, [`ContactModel::solve`] to solve the step problem
/// (the incremental potential plus friction, subject to the contact constraints) with Newton's
/// building blocks, then [`ContactModel::accept`] or [`ContactModel::reject`]; the run loop reads
/// the normal forces. Implementations: [`Conic`] (one conic program per Newton iterate) and
/// [`ActiveSet`] (contact statuses held and verified, the conic program as the fallback).
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
    /// no; the active set takes more iterations from there: 3.05 against 2.82 per step on the
    /// S-start at 200 elements and 5e-4 s).
    fn extrapolated_start(&self) -> bool {
        false
    }
    /// The step's solution `q` was accepted.
    fn accept(&mut self, m: &Model, q: &[f64]);
    /// The step was rejected: restore what `begin_step` saved.
    fn reject(&mut self);
    /// Normal force on every real node (N; zero off the ground), into `out`.
    fn normal_forces(&self, m: &Model, out: &mut [f64]);
    /// The model's statistics so far (none by default).
    fn stats(&self) -> &ContactStats {
        &NO_STATS
    }
}

/// Cumulative statistics of a contact model (written to `summary.json` beside Newton's).
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct ContactStats {
    /// Active-set fallbacks that were stalls ([`ContactFailure::Stalled`]).
    pub active_set_stalls: usize,
    /// Conic (Clarabel) solves.
    pub conic_solves: usize,
    /// Clarabel interior-point iterations over all solves.
    pub conic_iterations: usize,
    /// Seconds in Clarabel (set-up and solve).
    pub conic_s: f64,
    /// Contact steps solved by the active-set path (no conic solve).
    pub active_set_steps: usize,
    /// Contact steps where the active-set path failed its checks and the conic path ran.
    pub active_set_fallbacks: usize,
    /// Fallbacks whose conic path, started where the active set stopped, failed and was rerun
    /// from the step's start.
    pub warm_conic_restarts: usize,
    /// Fallbacks that first tried one conic solve and resumed the active set from its
    /// statuses.
    pub conic_handoffs: usize,
    /// Handoffs whose resumed active set converged (the rest went on down the conic path).
    pub handoff_steps: usize,
    /// Contact steps solved by the semi-smooth Newton ([`semismooth`]; no conic solve).
    pub semismooth_steps: usize,
    /// Contact steps where the semi-smooth Newton failed and the conic path ran.
    pub semismooth_fallbacks: usize,
    /// Semi-smooth attempts that failed and started again from the step's start with another
    /// penalty (`[solver] semi_smooth_retries`; a step solved by a retry is no fallback).
    pub semismooth_retries: usize,
    /// Fallbacks because the active-set iterates cycled (an exact repeat of iterate and
    /// statuses), sent to the conic path before the iteration cap.
    pub contact_cycles: usize,
    /// Semi-smooth or active-set steps certified by the conic program (`[solver] conic_certificate`).
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
    /// The active set's status changes by kind, over all steps (failed attempts included).
    pub switches: SwitchCounts,
    /// The last active-set solve's residual at each iterate (largest force on a free
    /// position coordinate, or torque on a free angle over `a`, relative to the mean weight
    /// per contact; NaN marks a change of contact statuses, -1 a step that was not a full
    /// step of the exact linearisation: damped, projected or with unconverged coupling), for
    /// convergence tests; not written to `summary.json`.
    #[serde(skip)]
    pub residuals: Vec<f64>,
}

static NO_STATS: ContactStats = ContactStats {
    active_set_stalls: 0,
    conic_solves: 0,
    conic_iterations: 0,
    conic_s: 0.0,
    active_set_steps: 0,
    active_set_fallbacks: 0,
    warm_conic_restarts: 0,
    conic_handoffs: 0,
    handoff_steps: 0,
    contact_cycles: 0,
    semismooth_steps: 0,
    semismooth_fallbacks: 0,
    semismooth_retries: 0,
    certificates: 0,
    certificate_failures: 0,
    certificate_max_correction: 0.0,
    certificate_max_normal_change: 0.0,
    switches: SwitchCounts {
        converged_lifts: 0,
        converged_slides: 0,
        front_slides: 0,
        early_lifts: 0,
        early_slides: 0,
        reversals: 0,
        landings: 0,
        zero_slip_sticks: 0,
    },
    residuals: Vec::new(),
};

/// The active set's contact status changes by kind ([`active`]; `stats.switches` in
/// `summary.json`): where its iterations go when a step needs many.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct SwitchCounts {
    /// A touching contact pulling at a converged point lifts off.
    pub converged_lifts: usize,
    /// A sticking contact outside the friction cone at a converged point slides.
    pub converged_slides: usize,
    /// A sticking neighbour within the front margin of a contact that slid slides with it.
    pub front_slides: usize,
    /// A contact pulling now and after the Newton step lifts off before convergence.
    pub early_lifts: usize,
    /// A sticking contact outside the cone now and after the Newton step slides before
    /// convergence.
    pub early_slides: usize,
    /// A sliding contact whose full Newton step reverses its slip sticks.
    pub reversals: usize,
    /// A free contact that the full Newton step takes below the ground lands.
    pub landings: usize,
    /// A sliding contact whose slip vanished sticks.
    pub zero_slip_sticks: usize,
}

/// Why a contact model's step solve failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ContactFailure {
    /// One of Newton's own failures (its building blocks inside the contact iteration).
    #[error(transparent)]
    Newton(#[from] newton::Failure),
    /// The active set kept changing.
    #[error("too many contact status changes (active-set iteration {iteration})")]
    ContactSwitches {
        /// 1-based iteration.
        iteration: usize,
    },
    /// The active-set iteration stopped converging: with the statuses unchanged for
    /// [`active::STALL_WINDOW`] iterations, the correction did not fall tenfold.
    #[error("active-set Newton stalls (iteration {iteration}: correction {now:.3e}, {} iterations earlier {before:.3e})", active::STALL_WINDOW)]
    Stalled {
        /// 1-based iteration.
        iteration: usize,
        /// The correction now and `STALL_WINDOW` iterations earlier (scaled).
        now: f64,
        /// See `now`.
        before: f64,
    },
    /// The active set returned to an earlier iterate with the same statuses: it would cycle.
    #[error("contact statuses cycle (active-set iteration {iteration} repeats iteration {first})")]
    ContactCycle {
        /// 1-based iteration.
        iteration: usize,
        /// The earlier iteration it repeats.
        first: usize,
    },
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

/// The contact model a problem asks for (`[solver] contact`).
pub fn model_for(m: &Model) -> Option<Box<dyn ContactModel>> {
    m.ground.as_ref()?;
    Some(match m.solver.contact {
        crate::problem::ContactKind::ActiveSet => Box::new(ActiveSet::new(m)),
        crate::problem::ContactKind::Conic => Box::new(Conic::new(m)),
        crate::problem::ContactKind::SemiSmooth => Box::new(SemiSmooth::new(m)),
    })
}

/// Per-step contact data and the normal-force fixed point.
pub struct Contacts {
    /// Internal node index of each contact candidate.
    pub nodes: Vec<usize>,
    /// Normal force at each candidate (N), the current fixed-point value.
    pub normal: Vec<f64>,
    forward: Vec<[f64; 3]>,
    side: Vec<[f64; 3]>,
    x_start: Vec<[f64; 3]>,
    /// Normal forces from the last solve, not yet committed.
    pub pending: Vec<f64>,
    /// Clarabel iterations of the last solve.
    pub last_iterations: u32,
    /// Clarabel solve time of the last solve (s).
    pub last_time: f64,
    direct_method: String,
    conic_tolerance: f64,
    conic_max_iterations: u32,
}

impl Contacts {
    /// Contact candidates of a model (real, not clamped nodes).
    pub fn new(m: &Model, q: &[f64]) -> Self {
        let nodes: Vec<usize> = m
            .real
            .clone()
            .filter(|&i| !m.fixed[dof::node(i) + 2])
            .collect();
        let nc = nodes.len();
        // Initial normal forces: each node's weight share if it touches the ground.
        let g = f::norm(m.gravity);
        let normal: Vec<f64> = nodes
            .iter()
            .map(|&i| {
                let z = q[dof::node(i) + 2];
                if z - 0.5 * m.diameter <= 1e-9 * m.diameter {
                    m.mass[dof::node(i)] * g
                } else {
                    0.0
                }
            })
            .collect();
        Contacts {
            nodes,
            pending: normal.clone(),
            normal,
            forward: vec![[0.0; 3]; nc],
            side: vec![[0.0; 3]; nc],
            x_start: vec![[0.0; 3]; nc],
            last_iterations: 0,
            last_time: 0.0,
            direct_method: m.solver.clarabel_method.clone(),
            conic_tolerance: m.solver.conic_tolerance,
            conic_max_iterations: m.solver.conic_max_iterations,
        }
    }

    /// Mean weight per contact candidate (N): the scale of normal-force tolerances.
    pub fn weight_scale(&self, m: &Model) -> f64 {
        (m.total_mass() * f::norm(m.gravity) / self.nodes.len().max(1) as f64).max(1e-300)
    }

    /// Freeze the contact frames (from `q`) and the slip origins (from `origin`) at the
    /// beginning of a step.
    pub fn begin_step(&mut self, m: &Model, q: &[f64], origin: &[f64]) {
        for (c, &i) in self.nodes.iter().enumerate() {
            let x = |k: usize| [q[dof::node(k)], q[dof::node(k) + 1], q[dof::node(k) + 2]];
            // Toward the head: from node i+1 to node i-1 (ends one-sided), on the ground.
            let lo = if i > m.real.start { i - 1 } else { i };
            let hi = if i + 1 < m.real.end { i + 1 } else { i };
            let d = f::sub(x(lo), x(hi));
            let mut fw = [d[0], d[1], 0.0];
            if f::norm(fw) < 1e-12 {
                fw = [1.0, 0.0, 0.0];
            }
            let fw = f::unit(fw);
            self.forward[c] = fw;
            self.side[c] = f::cross([0.0, 0.0, 1.0], fw);
            let k = dof::node(i);
            self.x_start[c] = [origin[k], origin[k + 1], origin[k + 2]];
        }
    }

    /// Friction dissipation `h D` at `q` with the lagged normal forces (J).
    pub fn dissipation(&self, g: &Ground, q: &[f64]) -> f64 {
        let mut d = 0.0;
        for (c, &i) in self.nodes.iter().enumerate() {
            if self.normal[c] == 0.0 {
                continue;
            }
            let k = dof::node(i);
            let dx = f::sub([q[k], q[k + 1], q[k + 2]], self.x_start[c]);
            let vf = f::dot(dx, self.forward[c]);
            let vs = f::dot(dx, self.side[c]);
            let mu = g.mu_along(vf);
            d += self.normal[c] * ((mu * vf).powi(2) + (g.mu_s * vs).powi(2)).sqrt();
        }
        d // h D = h N mu |v| = N mu |dx|
    }

    /// Lift the iterate's predicted penetrations onto the ground (a feasible start).
    pub fn lift(&self, m: &Model, q: &mut [f64]) {
        for &i in &self.nodes {
            let k = dof::node(i) + 2;
            q[k] = q[k].max(0.5 * m.diameter);
        }
    }

    /// Normal force on every real node (N), into `out`.
    pub fn normal_forces(&self, m: &Model, out: &mut [f64]) {
        out.fill(0.0);
        for (c, &i) in self.nodes.iter().enumerate() {
            out[i - m.real.start] = self.normal[c];
        }
    }
}
