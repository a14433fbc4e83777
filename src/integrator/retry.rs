//! What [`Integrator`] does with a step that fails or is rejected: the adaptive stepper's
//! retries ([`Integrator::adaptive_step`]), the fixed stepper's halvings
//! ([`Integrator::step`]) and, with ground contact on the curve, the step taken again with
//! contact at the nodes.

use super::{adaptive, Integrator, StepError};
use crate::state::State;

impl Integrator<'_> {
    /// One error-controlled step trying `h` first (see [`adaptive`]).
    pub fn adaptive_step(
        &mut self,
        s: &mut State,
        h: f64,
        control: &adaptive::Controller,
    ) -> Result<adaptive::Adapted, StepError> {
        let m = self.model;
        let tol = control.settings.tolerance;
        let mut out = adaptive::Adapted::default();
        let mut h = h;
        if let Some(c) = &self.contact {
            c.normal_forces(m, &mut self.normal_start);
        }
        loop {
            let reason = match self.attempt(s, h) {
                Ok(it) => {
                    let (c, p) = self.scheme.error_predictor(
                        m,
                        &self.q_prev,
                        &self.v_prev,
                        h,
                        &mut self.pred,
                    );
                    if let Some(ct) = &self.contact {
                        ct.normal_forces(m, &mut self.normal_end);
                        for r in 0..self.events.len() {
                            self.events[r] = m.in_contact(self.normal_start[r])
                                != m.in_contact(self.normal_end[r]);
                        }
                        ct.started_below(m, &mut self.events);
                    }
                    let err = adaptive::error_norm(m, &s.q, &self.pred, c, tol, &self.events);
                    log::debug!("adaptive try t {} h {h:.4e} err {err:.4e} it {it}", s.t);
                    if err <= 1.0 {
                        self.commit(s, h);
                        self.stats.count_step(it);
                        out.h = h;
                        out.error = err;
                        out.next = control.next_after_accept(h, err, p);
                        return Ok(out);
                    }
                    self.rollback(s);
                    self.stats.rejected_iterations += it;
                    out.rejected_error += 1;
                    h = control.retry_after_reject(h, err, p);
                    format!("local error estimate {err:.3e} x the tolerance")
                }
                Err(reason) => {
                    self.rollback(s);
                    log::debug!("adaptive step of {h} s at t = {} failed: {reason}", s.t);
                    out.rejected_solve += 1;
                    self.stats.step_halvings += 1;
                    h *= adaptive::FAILURE_SHRINK;
                    reason.to_string()
                }
            };
            if h < control.settings.dt_min {
                let v_max = m
                    .real
                    .clone()
                    .map(|i| crate::rod::vec3::f::norm(s.node_velocity(i)))
                    .fold(0.0, f64::max);
                return Err(StepError::BelowMinimum {
                    t: s.t,
                    dt: h,
                    dt_min: control.settings.dt_min,
                    reason,
                    v_max,
                });
            }
        }
    }

    /// Advance by `h`, halving on failure (at most `max_halvings` levels). With ground contact
    /// on the curve (`[solver] ground_points = "curve"`), a step that still fails is taken
    /// again, from where it failed to its end, with contact at the nodes (halving likewise),
    /// counted in [`RunStats::ground_point_fallbacks`] and logged as a warning. Measured on the
    /// S-start at 400 elements and 5e-4 s: at t = 2.027 s the conic fallback's positions
    /// converged but its normal forces did not, at every step down to 1.95e-6 s, while the
    /// same scene with contact at the nodes runs through.
    pub fn step(&mut self, s: &mut State, h: f64) -> Result<(), StepError> {
        let end = s.t + h;
        match self.step_level(s, h, 0) {
            Err(e) if end - s.t > 0.0 && self.points_at_nodes(true) => {
                let rest = end - s.t;
                log::warn!(
                    "{e} (ground contact on the curve); the step's last {rest:.3e} s from t = {} s taken again with contact at the nodes",
                    s.t
                );
                self.stats.ground_point_fallbacks += 1;
                let r = self.step_level(s, rest, 0);
                self.points_at_nodes(false);
                r
            }
            r => r,
        }
    }

    /// Ground contacts between nodes at their nodes from the next step on (`true`), or on the
    /// curve again; whether the contact model has such contacts.
    fn points_at_nodes(&mut self, on: bool) -> bool {
        self.contact.as_mut().is_some_and(|c| c.points_at_nodes(on))
    }

    fn step_level(&mut self, s: &mut State, h: f64, level: usize) -> Result<(), StepError> {
        match self.try_step(s, h) {
            Ok(it) => {
                self.stats.count_step(it);
                Ok(())
            }
            Err(reason) => {
                log::debug!("step of {h} s at t = {} failed: {reason}", s.t);
                if level >= self.model.max_halvings {
                    return Err(StepError::Rejected {
                        t: s.t,
                        dt: h,
                        halvings: level,
                        reason,
                    });
                }
                self.stats.step_halvings += 1;
                self.step_level(s, 0.5 * h, level + 1)?;
                self.step_level(s, 0.5 * h, level + 1)
            }
        }
    }
}
