//! How a step fails: one attempt's [`AttemptFailure`] (Newton's or the contact model's), and the
//! [`StepError`] that stops a run (after the halvings, below the adaptive minimum, an unstable
//! explicit step, or the explicit integrator at a self-contact).

use crate::contact::ContactFailure;
use crate::newton;

/// Why one attempt at a step (or a static load increment) failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AttemptFailure {
    /// Newton failed (no contact model, or static equilibrium).
    #[error(transparent)]
    Newton(#[from] newton::NewtonFailure),
    /// The contact model's solve failed.
    #[error(transparent)]
    Contact(#[from] ContactFailure),
    /// A static load increment failed.
    #[error("static solve at load {load}: {inner}")]
    Static {
        /// Load fraction.
        load: f64,
        /// The failure.
        inner: Box<AttemptFailure>,
    },
}

/// A step that could not be completed.
#[derive(Debug, thiserror::Error)]
pub enum StepError {
    /// Rejected after all allowed halvings.
    #[error("step rejected at t = {t} s with dt = {dt} s after {halvings} halvings: {reason}")]
    Rejected {
        /// Time at the start of the failed step (s).
        t: f64,
        /// Smallest step tried (s).
        dt: f64,
        /// Halvings tried.
        halvings: usize,
        /// Why the last attempt failed.
        reason: AttemptFailure,
    },
    /// An error-controlled step would have to be smaller than `[time] dt_min`.
    #[error("adaptive step at t = {t} s: the step would have to shrink to {dt:.3e} s, below time.dt_min = {dt_min:.3e} s (last try: {reason}; max |v| = {v_max:.3e} m/s at that time)")]
    BelowMinimum {
        /// Time at the start of the failed step (s).
        t: f64,
        /// The step that would be needed (s).
        dt: f64,
        /// The smallest allowed step (s).
        dt_min: f64,
        /// Why the last try was rejected (error estimate or solver failure).
        reason: String,
        /// Largest node speed of the state at `t` (m/s).
        v_max: f64,
    },
    /// The stepper has no error estimate (the explicit reference).
    #[error("at t = {t} s: this integrator cannot take error-controlled steps")]
    NotAdaptive {
        /// Time (s).
        t: f64,
    },
    /// The explicit integrator became unstable ([`super::explicit`]): non-finite state or energy
    /// blow-up. The state is that of the start of the failed step.
    #[error("explicit integrator unstable at t = {t} s with dt = {dt} s: {reason}")]
    Unstable {
        /// Time at the start of the failed step (s).
        t: f64,
        /// Step (s).
        dt: f64,
        /// What was detected.
        reason: String,
    },
    /// Two parts of the body came within the self-contact's activation gap under the
    /// explicit integrator, which has no self-contact. The state is that of the step's end.
    #[error("at t = {t} s two parts of the body came {distance_over_a:.4} a apart (centrelines), within the self-contact's activation gap: the explicit integrator has no self-contact; run \"implicit\" or \"bdf2\", or set self_contact.enabled = false to accept a body that passes through itself")]
    SelfContact {
        /// Time at the end of the step (s).
        t: f64,
        /// The closest centreline distance over `a`.
        distance_over_a: f64,
    },
}
