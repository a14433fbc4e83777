//! Contacts between nodes in the semi-smooth Newton: a contact whose point is a stencil of
//! several nodes (`[solver] ground_points = "curve"`, [`crate::contact::set`]) has no node
//! coordinates to hold, so its held components (the height when touching, all three when
//! sticking) enter the Newton system as an augmented Lagrangian instead: with the reaction
//! `R = (-G_x, -G_y, lambda)` (the force variables as the force on the body) and the
//! constraint residual `r = x_c(q) - target`, the step's objective gains
//! `-R . r + rho_al/2 |r|^2` per held component, whose Hessian `rho_al J^T J` (`J` the
//! stencil's weights) stays in the band (a stencil spans at most three nodes), and the force
//! after the step is `R' = R - rho_al (r + J dq)`. The reaction converges with the iterates by
//! a factor of about the body's local stiffness over `rho_al` per iteration, so at
//! convergence the constraint holds to the force tolerance over `rho_al` and Coulomb's law is
//! as exact as at a node. A sliding contact's friction is linearised as at a node (a force
//! along the branch's direction scaled by the normal force, and a spring across it), the
//! normal force's change along the step coupled into the direction by the reactions' GMRES
//! ([`crate::contact::reactions`]) as a node contact's is.

use super::SemiSmooth;
use crate::contact::status::ContactStatus;
use crate::contact::ContactSet;
use crate::model::Model;
use crate::newton::Newton;
use crate::rod::dof;

/// `rho_al` as a multiple of the pivot node's inertia stiffness (its mass over the step's
/// squared time scale; the Alart-Curnier penalty is 10 of them). At fine meshes the body's
/// bending stiffness per node, `B / ds^3`, grows past `1e4` of them (at 800 elements, 5e-4 s:
/// 6.7e6 against 1.6e7 N/m), and the multiplier converges slowly: on the S-start, implicit
/// Euler at 5e-4 s, `1e6` took 5.98 instead of 8.55 iterations per step at 400 elements (the
/// first 1.5 s) and 5.86 instead of 6.20 at 200 (whole scene, the same `v_s/v_m` to 7 digits);
/// at 100 elements 1e5 and 1e6 both took 3.72 against 3.79.
pub(super) const STIFFNESS: f64 = 1e6;

impl SemiSmooth {
    /// The contacts between nodes: their augmented-Lagrangian terms and sliding friction into
    /// the gradient and Hessian; then the gradient at the contacts at nodes read again (their
    /// reactions include the forces of the contacts between nodes that share their nodes).
    pub(super) fn add_between(&mut self, ct: &ContactSet, m: &Model, nw: &mut Newton, q: &[f64]) {
        let s = &mut self.scratch;
        s.reactions.begin(ct.len());
        let mut any = false;
        for c in 0..ct.len() {
            if s.at_node[c].is_some() || self.mode[c] == ContactStatus::Free {
                continue;
            }
            any = true;
            let ctc = &ct.contacts[c];
            let st = &ctc.stencil;
            let rho = s.rho_al[c];
            let x = st.position(q);
            let f = self.force[c];
            let react = [-f[0], -f[1], self.lambda[c]];
            let target = [ctc.origin[0], ctc.origin[1], 0.5 * m.diameter];
            let held = self.mode[c].held();
            for a in held.clone() {
                let g = -react[a] + rho * (x[a] - target[a]);
                for (i, w) in st.iter() {
                    nw.asm.grad[dof::node(i) + a] += w * g;
                }
            }
            for (ij, wj) in st.iter() {
                for (ik, wk) in st.iter() {
                    // Each unordered pair once: the node with the lower index first.
                    if ij > ik {
                        continue;
                    }
                    for a in held.clone() {
                        nw.asm
                            .add_h(dof::node(ij) + a, dof::node(ik) + a, rho * wj * wk);
                    }
                }
            }
            if self.mode[c] == ContactStatus::Slide {
                // The friction scales with the normal force the step's objective holds at the
                // iterate, `n = lambda - rho_al r_z` (the multiplier with the constraint's
                // residual); its change along the step, `-rho_al J_z dq`, enters the direction
                // through the reactions' GMRES (`Reactions::couple`) as a node contact's
                // reaction does, and like that one it is not clamped at zero, so the friction
                // variable after the step (`between_forces`) is the friction the direction was
                // computed with. (Put into the Hessian instead, the coupling made the system as
                // stiff as `rho_al`: 22 instead of 4.2 iterations per step at 100 elements,
                // implicit Euler at 5e-4 s, the first 2.5 s.) A retry of a failed step
                // (`couple_between` false) lags the normal force of the iterate, clamped at
                // zero, as before the coupling: see `SemiSmooth::couple_between`.
                let lin = s.slide[c];
                let coupled = self.couple_between && m.solver.contact_coupling;
                let n = if coupled {
                    self.lambda[c] - rho * (x[2] - target[2])
                } else {
                    self.lambda[c].max(0.0)
                };
                let gxy = lin.force(&ctc.frame, ctc.slip(q), n);
                if coupled {
                    let unit = ctc
                        .frame
                        .to_world([lin.mu[0] * lin.dir[0], lin.mu[1] * lin.dir[1]]);
                    s.reactions.set_slide_between(c, unit, rho);
                }
                let h = lin.hessian(&ctc.frame);
                for (i, w) in st.iter() {
                    nw.asm.grad[dof::node(i)] += w * gxy[0];
                    nw.asm.grad[dof::node(i) + 1] += w * gxy[1];
                }
                for (ij, wj) in st.iter() {
                    for (ik, wk) in st.iter() {
                        if ij > ik {
                            continue;
                        }
                        let (kj, kk) = (dof::node(ij), dof::node(ik));
                        let ww = wj * wk;
                        if ij == ik {
                            nw.asm.add_h(kj, kj, ww * h[0][0]);
                            nw.asm.add_h(kj, kj + 1, ww * h[0][1]);
                            nw.asm.add_h(kj + 1, kj + 1, ww * h[1][1]);
                        } else {
                            for a in 0..2 {
                                for b in 0..2 {
                                    nw.asm.add_h(kj + a, kk + b, ww * h[a][b]);
                                }
                            }
                        }
                    }
                }
            }
        }
        if any {
            for c in 0..ct.len() {
                if let Some(k) = s.at_node[c] {
                    let g = &nw.asm.grad;
                    s.grad[c] = [g[k], g[k + 1], g[k + 2]];
                }
            }
        }
    }

    /// Contact `c`'s (between nodes) force variables after the step `dq` from `q`: the
    /// augmented-Lagrangian update of its held components, and a sliding contact's friction
    /// from its branch's linearisation with the new normal force.
    pub(super) fn between_forces(
        &self,
        ct: &ContactSet,
        m: &Model,
        c: usize,
        q: &[f64],
        dq: &[f64],
    ) -> (f64, [f64; 2]) {
        let s = &self.scratch;
        let ctc = &ct.contacts[c];
        let rho = s.rho_al[c];
        let x = ctc.stencil.position(q);
        let dx = ctc.stencil.position(dq);
        let lam = self.lambda[c] - rho * (x[2] + dx[2] - 0.5 * m.diameter);
        match self.mode[c] {
            ContactStatus::Free => (0.0, [0.0; 2]),
            ContactStatus::Stick => {
                let f = self.force[c];
                let o = ctc.origin;
                (
                    lam,
                    [
                        f[0] + rho * (x[0] + dx[0] - o[0]),
                        f[1] + rho * (x[1] + dx[1] - o[1]),
                    ],
                )
            }
            ContactStatus::Slide => {
                let o = ctc.origin;
                let sl = ctc
                    .frame
                    .to_local([x[0] + dx[0] - o[0], x[1] + dx[1] - o[1]]);
                // Unclamped where the direction coupled it (`add_between`).
                let n = if self.couple_between && m.solver.contact_coupling {
                    lam
                } else {
                    lam.max(0.0)
                };
                (lam, s.slide[c].force(&ctc.frame, sl, n))
            }
        }
    }
}
