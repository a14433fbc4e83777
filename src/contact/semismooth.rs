//! Semi-smooth Newton contact: every contact's status follows from the current iterate at
//! every iteration, all at once, and one linear system per iteration moves positions and
//! contact forces together.
//!
//! Unknowns: the coordinates `q`, and per contact its normal force `lambda` and its friction
//! force `G` (in the dissipation-gradient convention of [`super::status`]: `grad_t Phi + G = 0`
//! at the node, `G` along the slip when sliding). In the scaled variables
//! `p = (G_f / mu(G_f), G_s / mu_s)` (`mu = mu_f` for `G_f > 0`, `mu_b` otherwise) the
//! anisotropic friction set is the disc `|p| <= lambda`, and exact Coulomb friction with the
//! gap condition is the root of the Alart-Curnier function
//!
//! ```text
//! phi_n = lambda - max(0, lambda - rho gap)
//! phi_t = p - Proj_{|.| <= N}(p + rho u),   N = max(0, lambda - rho gap),
//! ```
//!
//! with `u = (mu(s_f) s_f, mu_s s_s)` the scaled slip `s` of the step (`mu(s_f) = mu_f` for
//! forward slip) and `rho = P m_node w`: `P` (`[solver] semi_smooth_penalty`, 10 by default)
//! times the node's inertia stiffness. Any positive value gives the same roots; on the S-start
//! `P = 10` takes 10 to 20 % fewer iterations than `P = 1`, and `P` of order 100 (the node's
//! whole stiffness, elasticity included) four times as many. Together with the force balance `grad Phi(q) - lambda e_z + G = 0` at every
//! contact node this is one semi-smooth system `F(q, lambda, G) = 0`.
//!
//! Each iteration takes the element of the generalized Jacobian on the branch the current
//! iterate lies in, per contact:
//! * **free** (`lambda - rho gap <= 0`): `lambda, G -> 0`, the node moves freely;
//! * **stick** (touching, `|p + rho u| <= N`): the node goes to its start position and height
//!   (held coordinates with a target), the forces are the reactions there after the step;
//! * **slide** (touching, `|p + rho u| > N`, `w = p + rho u`): the height is held; with
//!   `c = N/|w|` and `k = c rho/(1 - c)` the friction force after the step is
//!   `p' = lambda' w/|w| + k (I - w w^T/|w|^2) u'`: a constant force along `w` scaled by the
//!   new normal force (the height's reaction, coupled into the system as in
//!   [`super::reactions`]) and a spring across it, both exact to first order.
//!
//! The statuses change wherever the iterate says, every contact in the same iteration: a
//! contact at the edge of the cone is on one branch or the other and the function is
//! continuous across the edge, so there is no slip to invent when a contact starts sliding and
//! no cap on status changes. The eliminated system keeps the banded symmetric Hessian (plus the
//! sliding contacts' normal-force coupling, solved by GMRES: [`super::reactions`]). GMRES
//! solves to `1e-2 normal_force_tolerance` (times the mean weight per contact), a hundredth of
//! what the convergence test resolves, so the convergence stays quadratic down to the
//! tolerance; far from the solution (`r > 0.1`, `r` the largest relative force-balance
//! residual) after the first two iterates, to `1e-2 r` only, an inexact Newton direction in the
//! sense of Eisenstat and Walker. Measured while `r` still counted the touching contacts'
//! bare reactions (the residual's sum, fixed since: `balance_residual`), so that `r` stayed
//! above 0.1 and the loose tolerance held at every iterate from the third: on the S-start at
//! 200 elements (BDF2, 5e-3 s) 14.98 instead of 15.13 iterations per step in 0.87 of the wall
//! time (medians of 5 alternating runs); with implicit Euler at 5e-4 s 3.32 instead of 3.31
//! (first 1.5 s) at 200 elements and 6.09 instead of 6.06 (whole scene) at 400. From the first
//! iterate on it cost implicit Euler iterations (3.66, and 3.91 at `0.1 r`, at 200 elements):
//! the first direction decides the statuses. With the true `r`, the tolerance near the
//! solution was `min(1e-2 normal_force_tolerance, r^2)` at first: tighter than the test can
//! see, and the solves' share of the time rose from 14 to 19 % (implicit Euler, 200 and 400
//! elements, record semismooth-residual). Without the `r^2` term, in single runs (whole scene,
//! implicit Euler at 5e-4 s; seconds in the solves): 200 elements 3.913 instead of 3.949
//! iterations per step, 0.88 instead of 1.11 s; 400 elements 5.889 instead of 5.855, 2.52
//! instead of 3.28 s; the superlinear tests of `tests/semismooth.rs` unchanged.
//!
//! Globalisation: the merit `theta = 1/2 |F|^2` (forces relative to the mean weight per
//! contact, torques over `a`), evaluated with each assembly; a full step is taken and its
//! sufficient decrease `theta(alpha) <= (1 - 2 sigma alpha) theta_ref` checked at the next
//! assembly, backtracking from the saved iterate otherwise (each try one assembly, no
//! factorisation). The test is non-monotone: `theta_ref` is the largest merit of the last `M`
//! accepted iterates (`[solver] semi_smooth_merit_memory`), because on the S-start the
//! monotone test (`M = 1`) refuses full steps near the solution, where contacts on the edge of
//! the cone change branch between iterates, and then creeps at a quarter step per iterate
//! until the iteration cap. A watchdog keeps it from cycling: after `M` accepted iterates
//! without a new lowest merit (by the same sufficient decrease) the test is against the last
//! iterate again. The bending and twist Hessian is kept within a step
//! (`[solver] hessian_reuse`). Convergence: a full step below the Newton tolerance on positions and
//! angles, contact forces that change by less than `[solver] normal_force_tolerance`, and at
//! the new iterate every contact on the same branch or, having changed branch, with its
//! Alart-Curnier residual below that force tolerance (a contact on the cone's edge, where
//! both branches have the same root: requiring the same branch there cost up to 8 more
//! iterations on BDF2 steps of 5e-3 s). Or, by the residual: every equation of `F` at the
//! iterate within the force tolerance (the largest force-balance entry and the largest
//! Alart-Curnier residual, relative to the mean weight per contact) and a full step below the
//! Newton tolerance on positions and angles, while that step would still move the force
//! variables by more than the tolerance; that step is taken (`semismooth_residual_stops`).
//! On a stiff rod lying on the ground the contact forces are ill-determined: positions
//! settled to 1e-13 m moved them by 1e-2 of a node's weight from iterate to iterate, and
//! contacts on the cone's edge switched branch in cycles of 17 iterates whose merit never
//! fell below that of their best iterate. On the S-start at 800
//! elements (implicit Euler at 2.5e-4 s) such a cycle failed one step at t = 2.01975 s at
//! every halving down to 1e-6 s, with contact on the curve and at the nodes; the semi-smooth
//! Newton had reached residuals of 3.4e-4 after 168 iterations and cycled there until the cap.
//! By the residual (whole runs, the bundled S-start and its step, against the test before),
//! iterations per step go from 10.37 to 6.20 at 100 elements and from 16.14 to 12.00 at 200
//! (curve: 8.11 to 6.67 and 17.71 to 12.58); with implicit Euler at 5e-4 s and 200 elements
//! from 7.80 to 3.90 (curve 8.44 to 3.89). The 1 to 12 conic fallbacks per run are gone and
//! `v_s/v_m` moves by at most 2.2e-7 of itself. At 100 elements a run at a thousandth of the
//! tolerances gives 0.32350322, the test before 0.32350318 and this one 0.32350325; keeping
//! the iterate instead of taking the step gave 0.32350337.
//!
//! Start: the force variables extrapolated linearly over the last two steps (where the
//! contact touched at both), and with implicit Euler the positions from the velocities
//! extrapolated likewise ([`super::ContactModel::extrapolated_start`]): on the S-start at 200
//! elements and 5e-4 s the first 1.5 s take 3.31 instead of 3.96 iterations per step.
//!
//! The solver takes the dispatcher's contact set ([`super::ContactSet`]) and holds each
//! contact's node coordinates; a contact between nodes has none to hold, and its held
//! components enter the system as an augmented Lagrangian instead (`between.rs`). A failure
//! falls back to the conic program ([`super::Dispatcher`]).

use super::reactions::{Reactions, UNCOUPLED};
use super::status::ContactStatus;
use super::{ContactFailure, ContactSet, ContactStats};
use crate::model::Model;
use crate::newton::{HessianCache, Newton, NewtonFailure, Objective, Path, Potential};
use crate::rod::dof;
use std::collections::VecDeque;
use std::time::Instant;

mod between;
mod branches;
mod forces;
mod step;
mod system;
mod watchdog;
use branches::{norm, status_line};
use system::SlideLin;
use watchdog::{MeritTest, Watch};

/// The penalty factors of the retries of a failed step (`[solver] semi_smooth_retries`): on
/// the S-start at 800 elements (the first 1.5 s at 5e-4 s) the first two turned 8 conic
/// fallbacks and 2 step halvings into 1 fallback and none.
const RETRY_PENALTIES: [f64; 4] = [3.0, 0.3, 10.0, 0.1];

/// Inexact coupled directions far from the solution (module doc): from iterate
/// `FORCING_AFTER + 1` on, while the largest force-balance residual exceeds `FAR_RESIDUAL`
/// (relative to the mean weight per contact), GMRES stops at `FAR_FORCING` times that residual
/// instead of at `min(1e-2 normal_force_tolerance, r^2)`.
const FORCING_AFTER: usize = 2;
const FAR_RESIDUAL: f64 = 0.1;
const FAR_FORCING: f64 = 1e-2;

/// The iterations of a step's first attempt in which sliding contacts between nodes couple
/// their normal forces into the direction ([`SemiSmooth::couple_between`]); the attempt goes
/// on with the lagged normal force. Coupled, such a contact beside a touching node contact now
/// and then cycles between stick and slide until the cap (then 100). On the damped S-start (BDF2,
/// the mean over steps of 3.4e-3 to 3.8e-3 s, iterations per step; nodes 16.34 and 10.26):
/// at 200 elements 16.68 with 40, 17.34 with 30, 16.75 with 20 and 18.05 without a limit; at
/// 100 elements 9.04 with 40, 9.53 with 30 and 9.41 without.
const COUPLED_BETWEEN_ITERATIONS: usize = 40;

/// The semi-smooth Newton contact solver (`[solver] contact = "semi-smooth"`, the default).
pub struct SemiSmooth {
    /// Status of every contact at the current iterate.
    mode: Vec<ContactStatus>,
    /// Normal force variable of every contact (N).
    lambda: Vec<f64>,
    /// Friction force variable of every contact in world `(x, y)` (N).
    force: Vec<[f64; 2]>,
    /// The variables at the step's start (restored by a rejected step).
    lambda_saved: Vec<f64>,
    force_saved: Vec<[f64; 2]>,
    /// The variables at the last step's start (the older point of the extrapolation).
    lambda_older: Vec<f64>,
    force_older: Vec<[f64; 2]>,
    /// Whether the variables hold a previous step's solution (or a guess).
    valid: bool,
    /// The size of the last step begun (s; 0: none).
    step_last: f64,
    q_init: Vec<f64>,
    /// Iterations of the last [`SemiSmooth::iterate`] (counted also when it fails).
    spent: usize,
    /// Whether sliding contacts between nodes couple their normal forces into the direction
    /// (`between.rs`): in a step's first attempt, for its first
    /// [`COUPLED_BETWEEN_ITERATIONS`], not later nor in its retries, which lag the normal
    /// force of the iterate (clamped at zero) as before the coupling. With the coupling in
    /// whole attempts and in the retries as well, 5 to 8 steps in 1000 fell back to the conic
    /// program instead of 1 to 3 (the damped S-start at 200 elements, BDF2 at 3.4e-3 to
    /// 3.8e-3 s).
    couple_between: bool,
    scratch: Scratch,
}

/// Per-step storage of [`SemiSmooth`].
#[derive(Default)]
struct Scratch {
    held: Vec<bool>,
    /// Target change of every held coordinate.
    target: Vec<f64>,
    reactions: Reactions,
    slide: Vec<SlideLin>,
    rho: Vec<f64>,
    /// Gradient of the objective (without contact forces) at the contacts' `(x, y, z)`.
    grad: Vec<[f64; 3]>,
    /// The force balance: the gradient with the contact force variables.
    balance: Vec<f64>,
    /// The step the deferred merit test judges ([`Saved`]).
    saved: Saved,
    /// The statuses of the last iterate (a change marks the residual history).
    modes_before: Vec<ContactStatus>,
    /// The statuses of the contacts at nodes, with every contact between nodes free: what
    /// the held coordinates and the reactions see ([`between`] takes the others).
    node_mode: Vec<ContactStatus>,
    /// The first coordinate of each contact's node (`None`: a contact between nodes).
    at_node: Vec<Option<usize>>,
    /// The augmented-Lagrangian stiffness of each contact between nodes (N/m; [`between`]).
    rho_al: Vec<f64>,
    /// The trace's line of cone-edge ratios (`SLITHER_DEBUG=trace` only).
    edge: String,
    /// The merits of the last accepted iterates (at most `[solver] semi_smooth_merit_memory`).
    recent: VecDeque<f64>,
    /// The bending and twist Hessian kept within the step (`[solver] hessian_reuse`).
    hessians: HessianCache,
    /// The watchdog's checkpoint: the saved step of a full step taken without its decrease
    /// (see [`Watch`]).
    watch: Saved,
}

/// A step as the line search moves along it: the iterate and force variables it starts from,
/// its direction, and the force variables after the full step.
#[derive(Default)]
struct Saved {
    q0: Vec<f64>,
    dq: Vec<f64>,
    lambda0: Vec<f64>,
    force0: Vec<[f64; 2]>,
    lambda_new: Vec<f64>,
    force_new: Vec<[f64; 2]>,
}

impl Saved {
    /// Copy `other` into this one, keeping the allocations.
    fn copy_from(&mut self, other: &Saved) {
        self.q0.clone_from(&other.q0);
        self.dq.clone_from(&other.dq);
        self.lambda0.clone_from(&other.lambda0);
        self.force0.clone_from(&other.force0);
        self.lambda_new.clone_from(&other.lambda_new);
        self.force_new.clone_from(&other.force_new);
    }
}

/// A pending sufficient-decrease test of the step taken from the saved iterate.
#[derive(Clone, Copy)]
struct Pending {
    theta0: f64,
    alpha: f64,
}

impl SemiSmooth {
    /// The semi-smooth Newton of `m` for the contact set `ct`.
    pub fn new(m: &Model, ct: &ContactSet) -> Self {
        let nc = ct.len();
        SemiSmooth {
            lambda: ct.normal.clone(),
            mode: vec![ContactStatus::Free; nc],
            force: vec![[0.0; 2]; nc],
            lambda_saved: Vec::new(),
            force_saved: Vec::new(),
            lambda_older: Vec::new(),
            force_older: Vec::new(),
            valid: false,
            step_last: 0.0,
            q_init: vec![0.0; m.ndof],
            spent: 0,
            couple_between: true,
            scratch: Scratch {
                held: vec![false; m.ndof],
                target: vec![0.0; m.ndof],
                hessians: HessianCache::new(m.ndof),
                ..Scratch::default()
            },
        }
    }

    /// The friction force variables after a conic solve (or before any step): normal forces
    /// from the contact data, sliding contacts' friction from their slip, sticking ones zero.
    pub(crate) fn reset_forces(&mut self, ct: &ContactSet, m: &Model, q: &[f64]) {
        for c in 0..ct.len() {
            let g = &ct.contacts[c].law;
            self.lambda[c] = ct.normal[c];
            let s = ct.slip(c, q);
            let mu = g.mu_along(s[0]);
            let u = g.scaled_slip(s);
            let r = u[0].hypot(u[1]);
            let n = ct.normal[c];
            self.force[c] = if r > m.solver.contact_tolerance * m.diameter && n > 0.0 {
                ct.to_world(c, [n * mu * u[0] / r, n * g.mu_s * u[1] / r])
            } else {
                [0.0; 2]
            };
        }
    }
}

impl SemiSmooth {
    /// The semi-smooth Newton iterations on the contact set `ct` from `q` (at most `[solver]
    /// semi_smooth_max_iterations` assemblies) with the penalty times `penalty_factor` (1 but
    /// in a retry). `Err`: the caller retries or falls back to the conic program.
    fn iterate(
        &mut self,
        ct: &ContactSet,
        stats: &mut ContactStats,
        nw: &mut Newton,
        obj: &Potential,
        q: &mut [f64],
        penalty_factor: f64,
    ) -> Result<usize, ContactFailure> {
        let m = obj.model;
        let set = &m.solver;
        let nc = ct.len();
        let scale = ct.weight_scale(m);
        let weight = obj.inertia.map_or(1.0, |i| i.weight);
        // Rod damping stiffens the step by `elastic_scale`; the penalty shrinks by as much
        // (measured on the damped S-start: 5.8 instead of 10.0 iterations per step at 200
        // elements and 1.25e-4 s; lab/ie_bdf2/README.md). Without damping the factor is 1.
        self.prepare(ct, m, weight, penalty_factor / obj.elastic_scale);
        stats.residuals.clear();
        let cap = m.max_iterations.min(set.semi_smooth_max_iterations);
        let mut project = false;
        let mut pending: Option<Pending> = None;
        let mut watch: Option<Watch> = None;
        // The non-monotone test's memory: accepted merits, the lowest and the iterates since.
        let memory = set.semi_smooth_merit_memory;
        self.scratch.recent.clear();
        let (mut best, mut since_best) = (f64::INFINITY, 0usize);
        self.scratch.hessians.invalidate();
        let mut it = 0;
        while it < cap {
            it += 1;
            if it > COUPLED_BETWEEN_ITERATIONS {
                self.couple_between = false;
            }
            self.spent = it;
            self.scratch.modes_before.copy_from_slice(&self.mode);
            let (theta_c, contact_residual) = self.branches(ct, m, q, scale, it > 1);
            let switched = it > 1 && self.mode != self.scratch.modes_before;
            for c in 0..nc {
                self.scratch.node_mode[c] = if self.scratch.at_node[c].is_some() {
                    self.mode[c]
                } else {
                    ContactStatus::Free
                };
            }
            if log::log_enabled!(log::Level::Debug) {
                log::debug!(
                    "  semi-smooth statuses it {it}: {}",
                    status_line(&self.mode)
                );
                log::trace!("  semi-smooth edge it {it}: {}", self.scratch.edge);
            }
            let t0 = Instant::now();
            let (f0, kept) = obj.assemble_reusing(
                q,
                &mut nw.asm,
                project,
                &mut self.scratch.hessians,
                set.hessian_reuse,
            );
            if kept {
                nw.stats.hessian_reuses += 1;
            }
            if project {
                nw.stats.projected_iterations += 1;
            }
            if !f0.is_finite() || nw.asm.grad.iter().any(|g| !g.is_finite()) {
                return Err(NewtonFailure::NonFiniteObjective {
                    path: Path::SemiSmooth,
                    iteration: it,
                }
                .into());
            }
            let (theta_q, residual) = self.balance_residual(ct, m, nw, scale);
            let theta = 0.5 * (theta_q + theta_c).max(0.0);
            if let Some(p) = pending.take() {
                let test = MeritTest {
                    p,
                    theta,
                    since_best,
                    memory,
                    // Monotone while self-contact pairs act: the pair distance has kinks (edges
                    // that turn parallel move their closest points from one end to the other),
                    // on which full steps can cycle.
                    monotone: !nw.asm.low_rank.is_empty(),
                    iteration: it,
                };
                if let Some(back) = self.merit_test(test, &mut watch, ct, m, q)? {
                    nw.stats.backtracks += 1;
                    pending = Some(back);
                    stats.residuals.push(-1.0);
                    nw.stats.assembly_s += t0.elapsed().as_secs_f64();
                    continue;
                }
            }
            if switched {
                // A status change between the last iterate and this one: no Newton pair.
                stats.residuals.push(f64::NAN);
            }
            stats.residuals.push((2.0 * theta).sqrt());
            // A watchdog's iterate has not earned its merit: it stays out of the memory.
            if watch.is_none() {
                self.remember(theta, memory);
            }
            (best, since_best) = if theta < (1.0 - 2.0 * set.armijo) * best {
                (theta, 0)
            } else {
                (best, since_best + 1)
            };
            self.add_between(ct, m, nw, q);
            self.add_sliding(ct, nw, q);
            self.hold_targets(ct, m, nw, q);
            let t1 = Instant::now();
            nw.stats.assembly_s += (t1 - t0).as_secs_f64();
            // While self-contact pairs act, an indefinite Hessian is shifted rather than
            // projected stencil by stencil: on the flailing cell W 127, G 100 (50 elements)
            // 15,487 instead of 22,867 iterations, the same answer.
            if project || !nw.asm.low_rank.is_empty() {
                nw.factor_shifted(m, it)?;
            } else if nw.factor().is_err() {
                // Indefinite: redo this iterate with the projected Hessian.
                project = true;
                it -= 1;
                nw.stats.factor_s += t1.elapsed().as_secs_f64();
                continue;
            }
            let t2 = Instant::now();
            nw.stats.factor_s += (t2 - t1).as_secs_f64();
            let krylov = self.direction(ct, m, nw, scale, residual, it > FORCING_AFTER);
            if nw.dq.iter().any(|d| !d.is_finite()) {
                return Err(NewtonFailure::NonFiniteStep {
                    path: Path::SemiSmooth,
                    iteration: it,
                }
                .into());
            }
            let change = self.new_forces(ct, m, nw, q);
            let t3 = Instant::now();
            nw.stats.solve_s += (t3 - t2).as_secs_f64();
            let (dx, dth) = nw.correction_norms();
            let small = dx <= m.tolerance * m.diameter && dth <= m.tolerance;
            let settled = change <= set.normal_force_tolerance * scale;
            log::debug!("  semi-smooth it {it}: theta {theta:.3e} dx {dx:.3e} dth {dth:.3e} dF {change:.3e} krylov {krylov}");
            if project || krylov == UNCOUPLED {
                stats.residuals.push(-1.0);
            }
            // The longest step (at most 1) that keeps the self-contact's pairs apart.
            let cap = obj.max_step(q, &nw.dq).min(1.0);
            if cap < 1.0 {
                log::debug!("  semi-smooth it {it}: step capped at {cap:.3e} (self-contact)");
            }
            self.save(q, nw);
            self.step_from_saved(ct, m, q, cap);
            // Converged by the residual (module doc): every equation of `F` at the iterate
            // within the force tolerance and a full step below the Newton tolerance, taken,
            // while the step still moves the force variables.
            let within = residual.max(contact_residual) <= set.normal_force_tolerance;
            if cap == 1.0 && small && !settled && within {
                nw.stats.line_search_s += t3.elapsed().as_secs_f64();
                stats.semismooth_residual_stops += 1;
                log::debug!("  semi-smooth converged by its residual at it {it}");
                return Ok(it);
            }
            let tol_f = set.normal_force_tolerance * scale;
            if cap == 1.0 && small && settled && self.branches_settled(ct, m, q, tol_f) {
                nw.stats.line_search_s += t3.elapsed().as_secs_f64();
                log::debug!("  semi-smooth converged at it {it}");
                return Ok(it);
            }
            pending = Some(Pending {
                theta0: theta,
                alpha: cap,
            });
            nw.stats.line_search_s += t3.elapsed().as_secs_f64();
        }
        Err(NewtonFailure::NotConverged {
            path: Path::SemiSmooth,
            iterations: cap,
        }
        .into())
    }

    /// Size the per-step storage; the penalty `rho` of every contact (`[solver]
    /// semi_smooth_penalty` times `penalty_factor` times the node's inertia stiffness).
    fn prepare(&mut self, ct: &ContactSet, m: &Model, weight: f64, penalty_factor: f64) {
        let nc = ct.len();
        let penalty = m.solver.semi_smooth_penalty * penalty_factor;
        let s = &mut self.scratch;
        s.at_node.clear();
        s.at_node.extend(
            ct.contacts
                .iter()
                .map(|c| c.stencil.single().map(dof::node)),
        );
        s.rho.clear();
        s.rho
            .extend((0..nc).map(|c| penalty * m.mass[ct.pivot_dof(c) + 2] * weight));
        s.rho_al.clear();
        s.rho_al
            .extend((0..nc).map(|c| between::STIFFNESS * m.mass[ct.pivot_dof(c) + 2] * weight));
        s.node_mode.resize(nc, ContactStatus::Free);
        s.slide.resize(nc, SlideLin::default());
        s.grad.resize(nc, [0.0; 3]);
        s.saved.lambda_new.resize(nc, 0.0);
        s.saved.force_new.resize(nc, [0.0; 2]);
        s.modes_before.resize(nc, ContactStatus::Free);
    }

    /// The force balance's part of `2 theta` with the contact force variables, from the
    /// assembled gradient (saved at the contacts for the reactions), and its largest entry
    /// (both relative to `scale`; angles' torques over `a`).
    fn balance_residual(
        &mut self,
        ct: &ContactSet,
        m: &Model,
        nw: &Newton,
        scale: f64,
    ) -> (f64, f64) {
        // Reciprocals: two divisions per coordinate were a third of this function's time.
        let (per_a, per_scale) = (1.0 / m.diameter, 1.0 / scale);
        let grad = &nw.asm.grad;
        // The force balance with the contact force variables, summed once per coordinate:
        // adding the contacts' squares and taking the bare gradient's back out left a
        // round-off floor of about 1e-7 in the relative residual (sqrt(eps) times the
        // reactions, which are of order the weight).
        let balance = &mut self.scratch.balance;
        balance.clear();
        balance.extend_from_slice(grad);
        for c in 0..ct.len() {
            let f = self.force[c];
            let Some(k) = self.scratch.at_node[c] else {
                for (i, w) in ct.contacts[c].stencil.iter() {
                    let k = dof::node(i);
                    balance[k] += w * f[0];
                    balance[k + 1] += w * f[1];
                    balance[k + 2] -= w * self.lambda[c];
                }
                continue;
            };
            self.scratch.grad[c] = [grad[k], grad[k + 1], grad[k + 2]];
            balance[k] += f[0];
            balance[k + 1] += f[1];
            balance[k + 2] -= self.lambda[c];
        }
        let mut sum = 0.0;
        let mut worst: f64 = 0.0;
        for (k, &b) in balance.iter().enumerate() {
            if !m.fixed[k] {
                let x = b * if dof::is_edge(k) { per_a } else { 1.0 } * per_scale;
                sum += x * x;
                worst = worst.max(x.abs());
            }
        }
        (sum, worst)
    }

    /// The contact data's normal forces from the variables (touching contacts only).
    pub(crate) fn publish_normals(&self, ct: &mut ContactSet) {
        for c in 0..ct.len() {
            ct.normal[c] = if self.mode[c] == ContactStatus::Free {
                0.0
            } else {
                self.lambda[c].max(0.0)
            };
        }
    }
}
