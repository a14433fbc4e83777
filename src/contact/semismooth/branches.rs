//! Each contact's branch of the Alart-Curnier function at an iterate (free, stick or slide,
//! with its residual), every contact's status from it, and the sliding contacts'
//! linearisation: the part of the semi-smooth Newton ([`super::SemiSmooth`]) that reads the
//! iterate, per contact.

use super::{SemiSmooth, SlideLin};
use crate::contact::status::ContactStatus;
use crate::contact::ContactSet;
use crate::model::Model;

/// `|v|` of a force or slip: `sqrt` of the sum of squares, not `hypot`, whose overflow
/// guard these magnitudes (forces of order the weight, slips of order the step) never need
/// and which cost 3 % of the S-start's run time at 200 elements in contact statuses.
#[inline]
pub(super) fn norm(v: [f64; 2]) -> f64 {
    (v[0] * v[0] + v[1] * v[1]).sqrt()
}

/// The contacts' statuses as one character each, head first (`.` free, `#` stick, `~`
/// slide): the debug trace's line per iterate, read by `lab/status_anatomy/status_trace.py`.
pub(super) fn status_line(mode: &[ContactStatus]) -> String {
    mode.iter()
        .map(|m| match m {
            ContactStatus::Free => '.',
            ContactStatus::Stick => '#',
            ContactStatus::Slide => '~',
        })
        .collect()
}

/// One contact's branch and residual at an iterate.
struct Branch {
    mode: ContactStatus,
    /// `max(0, lambda - rho gap)`.
    n_hat: f64,
    /// `p + rho u`.
    w: [f64; 2],
    /// The Alart-Curnier residuals `phi_n` and `phi_t` (N).
    phi_n: f64,
    phi_t: [f64; 2],
}

impl SemiSmooth {
    /// Contact `c`'s branch at `q` with its current force variables.
    fn branch(&self, ct: &ContactSet, m: &Model, c: usize, q: &[f64], rho: f64) -> Branch {
        let g = &ct.contacts[c].law;
        let gap = ct.contacts[c].gap(q, m.diameter);
        let lam = self.lambda[c];
        let n_hat = (lam - rho * gap).max(0.0);
        let phi_n = lam - n_hat;
        let p = g.scaled_force(ct.to_local(c, self.force[c]));
        let u = g.scaled_slip(ct.slip(c, q));
        let w = [p[0] + rho * u[0], p[1] + rho * u[1]];
        let wn = norm(w);
        let (proj, mode) = if lam - rho * gap <= 0.0 {
            ([0.0; 2], ContactStatus::Free)
        } else if wn <= n_hat {
            (w, ContactStatus::Stick)
        } else {
            ([n_hat * w[0] / wn, n_hat * w[1] / wn], ContactStatus::Slide)
        };
        Branch {
            mode,
            n_hat,
            w,
            phi_n,
            phi_t: [p[0] - proj[0], p[1] - proj[1]],
        }
    }

    /// Every contact's branch at `q`: its status and, sliding, its linearisation. Returns
    /// the contacts' part of `2 theta` and their largest Alart-Curnier residual `|phi|` (both
    /// relative to `scale`). `within`: a later iterate of the
    /// step, where a contact that slid at the last iterate and would now slide the other way
    /// is held stuck for this iterate instead: a contact whose true state is stuck otherwise
    /// slides back and forth, its slip overshooting by more than twice the cone's radius
    /// (`rho |u| > 2 N`) at every iterate (on the 50-element S-start with adaptive BDF2, 4.89
    /// instead of 6.94 iterations per step).
    pub(super) fn branches(
        &mut self,
        ct: &ContactSet,
        m: &Model,
        q: &[f64],
        scale: f64,
        within: bool,
    ) -> (f64, f64) {
        let mut sum = 0.0;
        let mut worst: f64 = 0.0;
        let trace = log::log_enabled!(log::Level::Trace);
        self.scratch.edge.clear();
        for c in 0..ct.len() {
            let g = &ct.contacts[c].law;
            let rho = self.scratch.rho[c];
            let b = self.branch(ct, m, c, q, rho);
            let mut mode = b.mode;
            if within && mode == ContactStatus::Slide && self.mode[c] == ContactStatus::Slide {
                let d = self.scratch.slide[c].dir;
                if d[0] * b.w[0] + d[1] * b.w[1] < 0.0 {
                    mode = ContactStatus::Stick;
                }
            }
            self.mode[c] = mode;
            if trace {
                // How close each stuck contact is to its cone's edge, `|w| / N`: a digit per
                // tenth, `X` from 0.999.
                let r = norm(b.w) / b.n_hat.max(1e-300);
                self.scratch.edge.push(match mode {
                    ContactStatus::Free => '.',
                    ContactStatus::Slide => '~',
                    ContactStatus::Stick if r >= 0.999 => 'X',
                    ContactStatus::Stick => char::from(b'0' + (10.0 * r).floor().min(9.0) as u8),
                });
            }
            let e = (b.phi_n * b.phi_n + b.phi_t[0] * b.phi_t[0] + b.phi_t[1] * b.phi_t[1])
                / (scale * scale);
            sum += e;
            worst = worst.max(e);
            if mode == ContactStatus::Slide {
                let wn = norm(b.w);
                let cc = b.n_hat / wn;
                let mu_w = g.mu_along(b.w[0]);
                self.scratch.slide[c] = SlideLin {
                    dir: [b.w[0] / wn, b.w[1] / wn],
                    k: cc * rho / (1.0 - cc),
                    mu: [mu_w, g.mu_s],
                };
            }
        }
        (sum, worst.sqrt())
    }

    /// Whether every contact at `q` is on the branch the last direction was computed with, or
    /// has changed branch with its Alart-Curnier residual below `tol` (N): a contact on the
    /// cone's edge, where both branches give the same root.
    pub(super) fn branches_settled(
        &mut self,
        ct: &ContactSet,
        m: &Model,
        q: &[f64],
        tol: f64,
    ) -> bool {
        (0..ct.len()).all(|c| {
            let g = &ct.contacts[c].law;
            let mu_x = g.mu_f.max(g.mu_b);
            let rho = self.scratch.rho[c];
            let b = self.branch(ct, m, c, q, rho);
            b.mode == self.mode[c]
                || b.phi_n.hypot(mu_x * b.phi_t[0]).hypot(g.mu_s * b.phi_t[1]) <= tol
        })
    }
}
