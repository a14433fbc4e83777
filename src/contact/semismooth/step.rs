//! The semi-smooth Newton's part of a time step: the step's start (force variables
//! extrapolated), the solve with its retries, and what a rejected step restores. The conic
//! fallback is the dispatcher's ([`crate::contact::Dispatcher`]).

use super::{SemiSmooth, RETRY_PENALTIES};
use crate::contact::{ContactFailure, ContactSet, ContactStats};
use crate::model::Model;
use crate::newton::{Newton, Potential};

impl SemiSmooth {
    /// Start a step of size `h` from the iterate `q` (already lifted onto the ground): the
    /// force variables extrapolated linearly over the last two steps (contacts that touched
    /// at both ends of the last step); the values at the step's start are kept for a retry or
    /// a rejected step.
    pub(crate) fn begin_step(&mut self, ct: &ContactSet, m: &Model, h: f64, q: &[f64]) {
        if !self.valid {
            self.reset_forces(ct, m, q);
            self.valid = true;
        }
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

    /// Solve the step from `q` on the contact set `ct`, retrying from the step's start with
    /// other penalties (`[solver] semi_smooth_retries`); publishes the normal forces into
    /// `ct`. Returns the iterations, or the last failure with the iterations spent on all
    /// attempts (`q` then holds where the last attempt stopped).
    pub(crate) fn solve(
        &mut self,
        ct: &mut ContactSet,
        stats: &mut ContactStats,
        nw: &mut Newton,
        obj: &Potential,
        q: &mut [f64],
    ) -> Result<usize, (ContactFailure, usize)> {
        let m = obj.model;
        self.q_init.copy_from_slice(q);
        let retries = &RETRY_PENALTIES[..m.solver.semi_smooth_retries.min(RETRY_PENALTIES.len())];
        let mut spent = 0;
        let mut attempt = 0;
        let mut penalty_factor = 1.0;
        self.couple_between = true;
        loop {
            match self.iterate(ct, stats, nw, obj, q, penalty_factor) {
                Ok(it) => {
                    stats.semismooth_steps += 1;
                    self.publish_normals(ct);
                    return Ok(spent + it);
                }
                Err(why) => {
                    spent += self.spent;
                    if attempt >= retries.len() || !q.iter().all(|x| x.is_finite()) {
                        return Err((why, spent));
                    }
                    log::debug!("  semi-smooth Newton failed ({why}); again from the step's start");
                    stats.semismooth_retries += 1;
                    penalty_factor = retries[attempt];
                    self.couple_between = false;
                    attempt += 1;
                    q.copy_from_slice(&self.q_init);
                    self.restore();
                }
            }
        }
    }

    /// Back to the force variables of the step's start.
    pub(crate) fn restore(&mut self) {
        self.lambda.clone_from(&self.lambda_saved);
        self.force.clone_from(&self.force_saved);
    }
}
