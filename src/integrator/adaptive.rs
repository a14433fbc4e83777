//! Error-controlled step sizes (`[time] adaptive = true`).
//!
//! **Estimate.** After a step of size `h` is solved, the [`super::Scheme`] gives an explicit
//! predictor `q^P` of the same order as the step and Milne's factor `c`
//! ([`super::Scheme::error_predictor`]); the local error estimate is `e = c (q_{n+1} - q^P)`.
//! Implicit Euler: `q^P = q_n + h v_n`, `c = 1/2`, since the implicit step errs by
//! `+h^2/2 q''` and the predictor by `-h^2/2 q''`. BDF2 with step ratio `w = h_n / h_{n-1}`:
//! `q^P = q_n + h v_n + h^2/2 (v_n - v_{n-1}) / h_{n-1}` errs by `-(1/6 + 1/(4w)) h^3 q'''`,
//! the step by `+(1 + w)^2 / (6 w (1 + 2w)) h^3 q'''` (2/9 at `w = 1`), so
//! `c = C_bdf / (C_bdf + C_pred)` (8/23 at `w = 1`).
//!
//! **Contact events.** A node landing or lifting off changes its velocity by an impulse (the
//! normal stop and the friction it switches on or off): no smooth predictor follows that, and a
//! smaller step does not shrink the difference at the method's order, so it would only drive
//! the step toward `dt_min` (measured on the S-start at tolerance 1e-6: steps down to 3e-6 s,
//! 15274 steps). Two rules leave such events out of the estimate: the predictor's heights are
//! raised to `z = a/2` (the ground), and a node whose contact state (normal force above
//! [`Model::in_contact`]'s threshold) differs between the start and the end of the step is
//! left out of the norm for that step, as are the nodes of a contact on the curve whose point
//! starts the step below the ground by more than the Newton tolerance (a point where the
//! parabola through a bend that lifts off dips below its nodes: the step
//! lifts it by that depth whatever its size; counted in, the 20-element S-start stopped with
//! its step below `dt_min`, `tests/contact_between.rs`). The neighbours of such a node, the sticking and sliding
//! nodes and every lifted node still count: a contact event shrinks the step through the
//! motion it causes. On the S-start this took `v_s/v_m` at tolerance 1e-5 from 0.3156 (3149
//! steps) to 0.3078 (2718 steps), against the fixed-step BDF2 reference 0.3056. With BDF2's
//! landings inelastic ([`super::bdf2`]) the rules still pay: counting the event nodes, with the
//! predictor's heights not raised, took 1651 instead of 1323 steps at tolerance 3e-5 for the
//! same `v_s/v_m` (0.31748 against 0.31743).
//!
//! **Norm.** `err = max_i |e_i| / (tol L)` over the free nodes `i` (3-vectors) and the free
//! twist angles `(a/2) |e_theta| / (tol L)` (the surface displacement): the largest local error
//! of any point of the body as a fraction of its length, against `tol = error_tolerance`. A
//! max norm keeps the meaning of `tol` independent of the mesh (a contact event at one node is
//! not averaged away by the others).
//!
//! **Controller.** A step with `err <= 1` is accepted; the next step is
//! `h * min(GROWTH_MAX, max(SHRINK_MIN, SAFETY * err^(-1/(p+1))))`, `p` the step's order (1 for
//! implicit Euler and BDF2's Euler start, 2 for BDF2), clipped to `[dt_min, dt_max]`. A step with
//! `err > 1` is rejected and retried at `h * max(SHRINK_MIN, min(SAFETY, SAFETY *
//! err^(-1/(p+1))))`; a step whose Newton or contact solve fails is retried at `h *
//! FAILURE_SHRINK`. A retry below `dt_min` stops the run ([`super::StepError::BelowMinimum`]).
//! A rejected step leaves the state, the BDF2 history and the contact model as they were.
//! The growth limit 2 also keeps variable-step BDF2 zero-stable (it needs ratios below
//! `1 + sqrt 2`).

use crate::model::Model;
use crate::problem::Adaptive;
use crate::rod::dof;

/// Safety factor on the optimal step `h err^(-1/(p+1))`.
pub const SAFETY: f64 = 0.9;
/// Largest growth of the step from one step to the next.
pub const GROWTH_MAX: f64 = 2.0;
/// Largest shrink of the step on one rejection (or after an accepted step).
pub const SHRINK_MIN: f64 = 0.2;
/// Shrink of the step after a failed Newton or contact solve.
pub const FAILURE_SHRINK: f64 = 0.5;

/// The step controller of a run: the problem's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Controller {
    /// Settings (tolerance, first, smallest and largest step).
    pub settings: Adaptive,
}

impl Controller {
    /// The step after an accepted step of size `h` with scaled error `err` and order `p`.
    pub fn next_after_accept(&self, h: f64, err: f64, p: usize) -> f64 {
        let f = if err > 0.0 {
            SAFETY * err.powf(-1.0 / (p as f64 + 1.0))
        } else {
            GROWTH_MAX
        };
        (h * f.clamp(SHRINK_MIN, GROWTH_MAX)).clamp(self.settings.dt_min, self.settings.dt_max)
    }

    /// The retry after a rejected step of size `h` with scaled error `err > 1` and order `p`.
    pub fn retry_after_reject(&self, h: f64, err: f64, p: usize) -> f64 {
        let f = SAFETY * err.powf(-1.0 / (p as f64 + 1.0));
        h * if f.is_finite() {
            f.clamp(SHRINK_MIN, SAFETY)
        } else {
            SHRINK_MIN
        }
    }
}

/// The result of one adaptive step (after any rejected tries).
#[derive(Clone, Copy, Debug, Default)]
pub struct Adapted {
    /// Size of the accepted step (s).
    pub h: f64,
    /// Proposed size of the next step (s).
    pub next: f64,
    /// Scaled error of the accepted step (<= 1).
    pub error: f64,
    /// Tries rejected by the error test.
    pub rejected_error: usize,
    /// Tries rejected because the Newton or contact solve failed.
    pub rejected_solve: usize,
}

/// Step statistics of a run (fixed or adaptive steps).
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct StepStats {
    /// Whether the steps were error controlled.
    pub adaptive: bool,
    /// Accepted steps.
    pub accepted: usize,
    /// Rejected tries: error test and failed solves (fixed steps: halvings).
    pub rejected: usize,
    /// Rejected tries whose error estimate was above the tolerance.
    pub rejected_error: usize,
    /// Rejected tries whose Newton or contact solve failed.
    pub rejected_solve: usize,
    /// Smallest accepted step (s).
    pub dt_min: f64,
    /// Largest accepted step (s).
    pub dt_max: f64,
    /// Largest scaled error estimate of an accepted step (adaptive; 0 for fixed steps).
    pub error_max: f64,
}

impl Default for StepStats {
    fn default() -> Self {
        StepStats {
            adaptive: false,
            accepted: 0,
            rejected: 0,
            rejected_error: 0,
            rejected_solve: 0,
            dt_min: f64::INFINITY,
            dt_max: 0.0,
            error_max: 0.0,
        }
    }
}

impl StepStats {
    /// Count an accepted step.
    pub fn add(&mut self, a: &Adapted) {
        self.accepted += 1;
        self.rejected_error += a.rejected_error;
        self.rejected_solve += a.rejected_solve;
        self.rejected = self.rejected_error + self.rejected_solve;
        self.dt_min = self.dt_min.min(a.h);
        self.dt_max = self.dt_max.max(a.h);
        self.error_max = self.error_max.max(a.error);
    }
}

/// Scaled error norm of `q - q^P` times `c` (see the module doc): `max |e| / (tol L)` over the
/// free nodes and twist angles. `pred` has its heights raised to `a/2` when there is a ground.
/// Nodes with `skip[i]` set (real node index `i - m.real.start`; a contact event this step)
/// are left out.
pub fn error_norm(m: &Model, q: &[f64], pred: &[f64], c: f64, tol: f64, skip: &[bool]) -> f64 {
    let scale = 1.0 / (tol * m.length);
    let floor = m.ground.as_ref().map(|_| 0.5 * m.diameter);
    let mut worst: f64 = 0.0;
    for i in 0..m.nodes {
        let k = dof::node(i);
        if m.fixed[k] && m.fixed[k + 1] && m.fixed[k + 2] {
            continue;
        }
        if m.real.contains(&i) && skip.get(i - m.real.start).copied().unwrap_or(false) {
            continue;
        }
        let mut zp = pred[k + 2];
        if let Some(z0) = floor {
            zp = zp.max(z0);
        }
        let e = [q[k] - pred[k], q[k + 1] - pred[k + 1], q[k + 2] - zp];
        worst = worst.max((e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt());
    }
    for j in 0..m.nodes - 1 {
        let k = dof::edge(j);
        if !m.fixed[k] {
            worst = worst.max(0.5 * m.diameter * (q[k] - pred[k]).abs());
        }
    }
    let err = c * worst * scale;
    if err.is_finite() {
        err
    } else {
        f64::INFINITY
    }
}
