//! The Newton system of one iterate of the semi-smooth Newton ([`super::SemiSmooth`]): the
//! sliding contacts' friction linearised on their branch ([`SlideLin`]), the touching and
//! sticking contacts' held coordinates with their targets, and the direction solved with the
//! sliding contacts' normal-force coupling ([`crate::contact::reactions`]).

use super::{SemiSmooth, FAR_FORCING, FAR_RESIDUAL};
use crate::contact::point::Frame;
use crate::contact::status::ContactStatus;
use crate::contact::ContactSet;
use crate::model::Model;
use crate::newton::Newton;
use crate::rod::dof::HALF_BANDWIDTH as W;

/// Per-contact linearisation of a sliding contact: the branch's scaled direction `w/|w|`,
/// the spring `k` across it and the friction coefficients `(mu_w, mu_s)` of the branch.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct SlideLin {
    pub(super) dir: [f64; 2],
    pub(super) k: f64,
    pub(super) mu: [f64; 2],
}

impl SlideLin {
    /// The friction force (dissipation gradient, world `(x, y)`) of the branch at the slip
    /// `sl` (forward, sideways) with normal force `n`: `T (n dir + k P u)`, `u` the scaled slip
    /// and `P` the projection across `dir`.
    pub(super) fn force(&self, frame: &Frame, sl: [f64; 2], n: f64) -> [f64; 2] {
        let SlideLin { dir, k, mu } = *self;
        let u = [mu[0] * sl[0], mu[1] * sl[1]];
        let along = u[0] * dir[0] + u[1] * dir[1];
        let pu = [u[0] - along * dir[0], u[1] - along * dir[1]];
        frame.to_world([
            mu[0] * (n * dir[0] + k * pu[0]),
            mu[1] * (n * dir[1] + k * pu[1]),
        ])
    }

    /// The force's Hessian in the slip, `k T P T` in (forward, sideways), as world `(x, y)`.
    pub(super) fn hessian(&self, frame: &Frame) -> [[f64; 2]; 2] {
        let SlideLin { dir, k, mu } = *self;
        let hff = k * mu[0] * mu[0] * (1.0 - dir[0] * dir[0]);
        let hfs = -k * mu[0] * mu[1] * dir[0] * dir[1];
        let hss = k * mu[1] * mu[1] * (1.0 - dir[1] * dir[1]);
        let (fw, sd) = (frame.forward, frame.side);
        let hx = |i: usize, j: usize| {
            hff * fw[i] * fw[j] + hfs * (fw[i] * sd[j] + sd[i] * fw[j]) + hss * sd[i] * sd[j]
        };
        [[hx(0, 0), hx(0, 1)], [hx(1, 0), hx(1, 1)]]
    }
}

impl SemiSmooth {
    /// Sliding contacts' friction, linearised on their branch: gradient and Hessian at their
    /// `(x, y)`, and their normal-force coupling.
    pub(super) fn add_sliding(&mut self, ct: &ContactSet, nw: &mut Newton, q: &[f64]) {
        let s = &mut self.scratch;
        // (The reactions were begun by `add_between`.)
        for c in 0..ct.len() {
            if s.node_mode[c] != ContactStatus::Slide {
                continue;
            }
            let lin = s.slide[c];
            let frame = &ct.contacts[c].frame;
            // Force in (f, s) = T (N dir + k P u), N the reaction.
            let gxy = lin.force(frame, ct.slip(c, q), s.grad[c][2]);
            let unit = frame.to_world([lin.mu[0] * lin.dir[0], lin.mu[1] * lin.dir[1]]);
            let h = lin.hessian(frame);
            let kk = ct.node_dof(c);
            nw.asm.grad[kk] += gxy[0];
            nw.asm.grad[kk + 1] += gxy[1];
            nw.asm.add_h(kk, kk, h[0][0]);
            nw.asm.add_h(kk, kk + 1, h[0][1]);
            nw.asm.add_h(kk + 1, kk + 1, h[1][1]);
            s.reactions.set_slide(c, unit, 1.0);
        }
    }

    /// Hold the touching heights at the ground and the sticking positions at their start
    /// (targets of the step); the reaction rows captured first.
    pub(super) fn hold_targets(&mut self, ct: &ContactSet, m: &Model, nw: &mut Newton, q: &[f64]) {
        let s = &mut self.scratch;
        s.reactions.capture(ct, &s.node_mode, &nw.asm);
        s.held.copy_from_slice(&m.fixed);
        s.target.fill(0.0);
        for c in 0..ct.len() {
            if s.node_mode[c] == ContactStatus::Free {
                continue;
            }
            let k = ct.node_dof(c);
            s.held[k + 2] = true;
            s.target[k + 2] = 0.5 * m.diameter - q[k + 2];
            if s.node_mode[c] == ContactStatus::Stick {
                for j in 0..2 {
                    s.held[k + j] = true;
                    s.target[k + j] = ct.contacts[c].origin[j] - q[k + j];
                }
            }
        }
        // Free rows see the held coordinates' moves: g_i += H_ik d_k. Only the contacts'
        // coordinates have targets, and their rows are the ones just captured.
        let n = m.ndof;
        for c in 0..ct.len() {
            if s.node_mode[c] == ContactStatus::Free {
                continue;
            }
            let k0 = ct.node_dof(c);
            for r in s.node_mode[c].held() {
                let (k, d) = (k0 + r, s.target[k0 + r]);
                if d == 0.0 {
                    continue;
                }
                for (t, v) in s.reactions.row(c, r).iter().enumerate() {
                    let i = (k + t).wrapping_sub(W);
                    if i < n && !s.held[i] {
                        nw.asm.grad[i] += v * d;
                    }
                }
            }
        }
        // The same for the low-rank part (self-contact pairs far along the body).
        nw.asm.low_rank_held_moves(&s.held, &s.target);
        for k in 0..n {
            if s.held[k] {
                nw.asm.fix(k);
            }
        }
    }

    /// The Newton direction with the held coordinates' moves and the sliding contacts'
    /// normal forces inside the system; returns the GMRES iterations ([`UNCOUPLED`]: the
    /// coupling did not converge and the symmetric direction is kept).
    pub(super) fn direction(
        &mut self,
        ct: &ContactSet,
        m: &Model,
        nw: &mut Newton,
        scale: f64,
        residual: f64,
        far: bool,
    ) -> usize {
        let set = &m.solver;
        nw.solve_direction();
        let s = &mut self.scratch;
        for k in 0..m.ndof {
            if s.held[k] {
                nw.dq[k] = s.target[k];
            }
        }
        if set.contact_coupling && s.reactions.coupled() {
            // A hundredth of the force tolerance near the solution (what the convergence test
            // resolves), a fixed fraction of the residual far from it after the first
            // iterates (module doc).
            let forcing = if far && residual > FAR_RESIDUAL {
                FAR_FORCING * residual
            } else {
                1e-2 * set.normal_force_tolerance
            };
            let tol = scale * forcing;
            s.reactions.couple(ct, nw, &s.held, tol)
        } else {
            0
        }
    }
}
