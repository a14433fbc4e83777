//! The force variables after a Newton step of the semi-smooth Newton ([`super::SemiSmooth`]):
//! every contact's predicted normal and friction force on its branch, and the iterate and its
//! force variables along the saved direction (the line search's part).

use super::{norm, ContactStatus, SemiSmooth};
use crate::contact::ContactSet;
use crate::model::Model;
use crate::newton::Newton;

impl SemiSmooth {
    /// The force variables after the full step (into the scratch), from the reactions'
    /// predicted change; returns the largest change of a force variable (N).
    pub(super) fn new_forces(&mut self, ct: &ContactSet, m: &Model, nw: &Newton, q: &[f64]) -> f64 {
        let node_mode = std::mem::take(&mut self.scratch.node_mode);
        self.scratch.reactions.predict(ct, &node_mode, &nw.dq);
        self.scratch.node_mode = node_mode;
        let mut worst: f64 = 0.0;
        for c in 0..ct.len() {
            let (lam, force) = if self.scratch.at_node[c].is_none() {
                self.between_forces(ct, m, c, q, &nw.dq)
            } else {
                self.node_forces(ct, c, q, &nw.dq)
            };
            worst = worst.max((lam - self.lambda[c]).abs()).max(norm([
                force[0] - self.force[c][0],
                force[1] - self.force[c][1],
            ]));
            self.scratch.saved.lambda_new[c] = lam;
            self.scratch.saved.force_new[c] = force;
        }
        worst
    }

    /// Contact `c`'s (at a node) force variables after the step `dq` from `q`: its reactions
    /// predicted by `Reactions::predict` on its branch.
    fn node_forces(&self, ct: &ContactSet, c: usize, q: &[f64], dq: &[f64]) -> (f64, [f64; 2]) {
        let s = &self.scratch;
        let ch = s.reactions.change[c];
        let gr = s.grad[c];
        match self.mode[c] {
            ContactStatus::Free => (0.0, [0.0; 2]),
            ContactStatus::Stick => (gr[2] + ch[2], [-(gr[0] + ch[0]), -(gr[1] + ch[1])]),
            ContactStatus::Slide => {
                let lam = gr[2] + ch[2];
                let kk = ct.node_dof(c);
                let x = [q[kk] + dq[kk], q[kk + 1] + dq[kk + 1]];
                let x0 = ct.contacts[c].origin;
                let sl = ct.to_local(c, [x[0] - x0[0], x[1] - x0[1]]);
                (lam, s.slide[c].force(&ct.contacts[c].frame, sl, lam))
            }
        }
    }

    /// Save the iterate, its force variables and the direction.
    pub(super) fn save(&mut self, q: &[f64], nw: &Newton) {
        let s = &mut self.scratch.saved;
        s.q0.clear();
        s.q0.extend_from_slice(q);
        s.dq.clear();
        s.dq.extend_from_slice(&nw.dq);
        s.lambda0.clone_from(&self.lambda);
        s.force0.clone_from(&self.force);
    }

    /// The iterate `alpha` along the saved direction (held coordinates land exactly on their
    /// targets in a full step).
    pub(super) fn step_from_saved(
        &mut self,
        ct: &ContactSet,
        m: &Model,
        q: &mut [f64],
        alpha: f64,
    ) {
        let (s, saved) = (&self.scratch, &self.scratch.saved);
        for k in 0..m.ndof {
            q[k] = saved.q0[k] + alpha * saved.dq[k];
        }
        for c in 0..ct.len() {
            if let Some(k) = s.at_node[c].filter(|_| alpha == 1.0) {
                match self.mode[c] {
                    ContactStatus::Free => {}
                    ContactStatus::Stick => {
                        q[k] = ct.contacts[c].origin[0];
                        q[k + 1] = ct.contacts[c].origin[1];
                        q[k + 2] = 0.5 * m.diameter;
                    }
                    ContactStatus::Slide => q[k + 2] = 0.5 * m.diameter,
                }
            }
            self.lambda[c] = saved.lambda0[c] + alpha * (saved.lambda_new[c] - saved.lambda0[c]);
            for j in 0..2 {
                self.force[c][j] =
                    saved.force0[c][j] + alpha * (saved.force_new[c][j] - saved.force0[c][j]);
            }
        }
    }
}
