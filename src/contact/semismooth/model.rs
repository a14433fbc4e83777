//! The semi-smooth Newton as a [`ContactModel`]: the step's start (force variables
//! extrapolated), the solve with its retries and the conic fallback, and what a rejected step
//! restores.

use super::{SemiSmooth, RETRY_PENALTIES};
use crate::contact::{ContactFailure, ContactModel, ContactStats};
use crate::model::Model;
use crate::newton::{Newton, Potential};

impl ContactModel for SemiSmooth {
    fn begin_step(
        &mut self,
        m: &Model,
        q_start: &[f64],
        slip_origin: &[f64],
        v_start: &[f64],
        h: f64,
        q: &mut [f64],
    ) {
        self.conic
            .begin_step(m, q_start, slip_origin, v_start, h, q);
        if !self.valid {
            self.reset_forces(m, q);
            self.valid = true;
        }
        // The force variables extrapolated linearly over the last two steps (contacts that
        // touched at both ends of the last step); `saved` keeps the values at the step's start.
        std::mem::swap(&mut self.lambda_saved, &mut self.lambda_older);
        std::mem::swap(&mut self.force_saved, &mut self.force_older);
        self.lambda_saved.clone_from(&self.lambda);
        self.force_saved.clone_from(&self.force);
        if self.step_last > 0.0 && self.lambda_older.len() == self.lambda.len() {
            let r = h / self.step_last;
            let (older_l, older_f) = (&self.lambda_older, &self.force_older);
            for c in 0..self.lambda.len() {
                let l = self.lambda[c];
                if l > 0.0 && older_l[c] > 0.0 {
                    self.lambda[c] = (l + r * (l - older_l[c])).max(0.0);
                    for j in 0..2 {
                        let f = self.force[c][j];
                        self.force[c][j] = f + r * (f - older_f[c][j]);
                    }
                }
            }
        }
        self.step_last = h;
    }

    fn extrapolated_start(&self) -> bool {
        true
    }

    fn solve(
        &mut self,
        nw: &mut Newton,
        obj: &Potential,
        q: &mut Vec<f64>,
    ) -> Result<usize, ContactFailure> {
        let m = obj.model;
        self.q_init.copy_from_slice(q);
        // Retries from the step's start with other penalties (`[solver] semi_smooth_retries`).
        let retries = &RETRY_PENALTIES[..m.solver.semi_smooth_retries.min(RETRY_PENALTIES.len())];
        let mut spent = 0;
        let mut attempt = 0;
        let mut penalty_factor = 1.0;
        let why = loop {
            match self.iterate(nw, obj, q, penalty_factor) {
                Ok(it) => {
                    self.conic.stats.semismooth_steps += 1;
                    self.publish_normals();
                    let every = m.solver.conic_certificate;
                    if every > 0 && self.conic.stats.semismooth_steps.is_multiple_of(every) {
                        self.conic.certify_recorded(nw, obj, q)?;
                    }
                    return Ok(spent + it);
                }
                Err(why) => {
                    spent += self.spent;
                    if attempt >= retries.len() || !q.iter().all(|x| x.is_finite()) {
                        break why;
                    }
                    log::debug!("  semi-smooth Newton failed ({why}); again from the step's start");
                    self.conic.stats.semismooth_retries += 1;
                    penalty_factor = retries[attempt];
                    attempt += 1;
                    q.copy_from_slice(&self.q_init);
                    self.lambda.clone_from(&self.lambda_saved);
                    self.force.clone_from(&self.force_saved);
                }
            }
        };
        log::debug!("  semi-smooth Newton failed: {why}");
        self.conic.stats.semismooth_fallbacks += 1;
        if q.iter().all(|x| x.is_finite()) {
            // The conic path from where the iteration stopped first (as the active set's
            // fallback), then from the step's start.
            self.conic.ct.lift(m, q);
            let cap = m.max_iterations.min(m.solver.warm_conic_iterations);
            match self.conic.iterate(nw, obj, q, cap) {
                Ok(it) => {
                    self.reset_forces(m, q);
                    return Ok(spent + it);
                }
                Err(why) => {
                    log::debug!("  warm conic start failed: {why}");
                    self.conic.stats.warm_conic_restarts += 1;
                }
            }
        }
        q.copy_from_slice(&self.q_init);
        self.conic.restore_normals();
        let it = self.conic.iterate(nw, obj, q, m.max_iterations)?;
        self.reset_forces(m, q);
        Ok(spent + it)
    }

    fn accept(&mut self, _m: &Model, _q: &[f64]) {}

    fn reject(&mut self) {
        self.conic.reject();
        self.lambda.clone_from(&self.lambda_saved);
        self.force.clone_from(&self.force_saved);
    }

    fn normal_forces(&self, m: &Model, out: &mut [f64]) {
        self.conic.ct.normal_forces(m, out);
    }

    fn stats(&self) -> &ContactStats {
        &self.conic.stats
    }
}
