//! Active-set contact: the conic program's solution fixes, per contact, whether it is free,
//! sticking or sliding; the following steps keep that status and are solved by plain Newton
//! iterations on a smooth problem, with the exact Coulomb conditions verified at convergence.
//!
//! With the status fixed, the step problem of MODEL section 3 is smooth:
//! * a touching contact (sticking or sliding) holds its gap at zero: `z = a/2` is an exact
//!   linear constraint, and the reaction at the held coordinate (the objective's gradient
//!   there) is its normal force `N`;
//! * a sticking contact also holds its tangential position at the start of the step (zero
//!   slip); the reaction there is its friction force;
//! * a sliding contact carries the dissipation `N sqrt((mu(v_f) v_f)^2 + (mu_s v_s)^2)`,
//!   smooth away from zero slip (gradient and positive semi-definite Hessian below), with `N`
//!   lagged and updated each Newton iterate (the same fixed point as the conic path);
//! * a free contact has no force and must keep a positive gap.
//!
//! The converged point is the exact solution of the conic step problem (the same KKT system)
//! when every normal force is non-negative, every sticking contact's friction force lies in
//! the anisotropic friction set, every sliding contact still slides and no free contact
//! reached the ground. Otherwise the integrator falls back to the conic program.

use super::{Contacts, Ground};
use crate::model::Model;
use crate::rod::{dof, vec3::f};

/// Status of a contact candidate in the active-set mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Off the ground, no force.
    Free,
    /// On the ground, no slip.
    Stick,
    /// On the ground, sliding.
    Slide,
}

/// Slip below which a contact counts as sticking, relative to the rod diameter.
const STICK_SLIP: f64 = 1e-9;
/// Gap below which a contact counts as touching, relative to the rod diameter.
const TOUCH_GAP: f64 = 1e-9;

impl Contacts {
    /// Tangential slip `(dx . f, dx . s)` of contact `c` at `q` since the start of the step.
    pub(crate) fn slip(&self, c: usize, q: &[f64]) -> [f64; 2] {
        let k = dof::node(self.nodes[c]);
        let dx = f::sub([q[k], q[k + 1], q[k + 2]], self.x_start[c]);
        [f::dot(dx, self.forward[c]), f::dot(dx, self.side[c])]
    }

    /// Classify every contact from a converged step at `q` (after a conic solve).
    pub fn classify(&mut self, m: &Model, q: &[f64]) {
        let a = m.diameter;
        for c in 0..self.nodes.len() {
            let k = dof::node(self.nodes[c]);
            let gap = q[k + 2] - 0.5 * a;
            self.mode[c] = if gap > TOUCH_GAP * a {
                Mode::Free
            } else {
                let s = self.slip(c, q);
                if s[0].hypot(s[1]) <= STICK_SLIP * a {
                    Mode::Stick
                } else {
                    Mode::Slide
                }
            };
        }
        self.modes_valid = true;
    }

    /// Guess every contact's status from a state (positions `q`, velocities `v`) before any
    /// conic solve: touching contacts stick when at rest and slide otherwise. The active-set
    /// step verifies (and corrects) the guess.
    pub fn guess_modes(&mut self, m: &Model, q: &[f64], v: &[f64], h: f64) {
        let a = m.diameter;
        for c in 0..self.nodes.len() {
            let k = dof::node(self.nodes[c]);
            self.mode[c] = if q[k + 2] - 0.5 * a > TOUCH_GAP * a {
                Mode::Free
            } else if h * v[k].hypot(v[k + 1]) > STICK_SLIP * a {
                Mode::Slide
            } else {
                Mode::Stick
            };
        }
        self.modes_valid = true;
    }

    /// Put the held coordinates of `q` on their constraints: touching gaps at zero, sticking
    /// contacts at their start positions; free contacts lifted onto the ground if below.
    /// Marks the held coordinates in `held` and zeroes free contacts' normal forces.
    pub fn hold(&mut self, m: &Model, q: &mut [f64], held: &mut [bool]) {
        let a = m.diameter;
        for c in 0..self.nodes.len() {
            let k = dof::node(self.nodes[c]);
            match self.mode[c] {
                Mode::Free => {
                    q[k + 2] = q[k + 2].max(0.5 * a);
                    self.normal[c] = 0.0;
                }
                Mode::Stick => {
                    q[k] = self.x_start[c][0];
                    q[k + 1] = self.x_start[c][1];
                    q[k + 2] = 0.5 * a;
                    held[k] = true;
                    held[k + 1] = true;
                    held[k + 2] = true;
                }
                Mode::Slide => {
                    q[k + 2] = 0.5 * a;
                    held[k + 2] = true;
                }
            }
        }
    }

    /// How far the sticking contact `c`'s friction force (minus the objective's tangential
    /// gradient `grad`) is inside its anisotropic friction set with normal force `n`: below 1
    /// inside, 1 on the boundary. Also returns the force's magnitude and the unit slip
    /// direction in `(x, y)` that this force would drive if it left the set.
    pub(crate) fn stick_ratio(
        &self,
        g: &Ground,
        c: usize,
        grad: [f64; 2],
        n: f64,
    ) -> (f64, f64, [f64; 2]) {
        let fw = self.forward[c];
        let sd = self.side[c];
        // The dissipation's subgradient at zero slip balancing the rest of the objective.
        let sf = -(grad[0] * fw[0] + grad[1] * fw[1]);
        let ss = -(grad[0] * sd[0] + grad[1] * sd[1]);
        let mu = if sf >= 0.0 { g.mu_f } else { g.mu_b };
        let r = (sf / mu).hypot(ss / g.mu_s);
        let mag = sf.hypot(ss);
        // The dissipation's gradient N J u (J = diag(mu, mu_s), u = J v / |J v|) equals the
        // force when v is along J^-2 force.
        let (vf, vs) = (sf / (mu * mu), ss / (g.mu_s * g.mu_s));
        let d = [vf * fw[0] + vs * sd[0], vf * fw[1] + vs * sd[1]];
        let dl = d[0].hypot(d[1]);
        let dir = if dl > 0.0 {
            [d[0] / dl, d[1] / dl]
        } else {
            [0.0; 2]
        };
        (
            if n > 0.0 {
                r / n
            } else if r == 0.0 {
                0.0
            } else {
                f64::INFINITY
            },
            mag,
            dir,
        )
    }

    /// Change contact `c`'s status within the active-set iteration, moving its held
    /// coordinates of `q` onto the new constraints: sticking at the start position; sliding
    /// from a small slip along the direction of its last friction force (from a stick) or
    /// from where it is; free with no force.
    pub(crate) fn set_mode(
        &mut self,
        m: &Model,
        c: usize,
        mode: Mode,
        q: &mut [f64],
        held: &mut [bool],
    ) {
        let a = m.diameter;
        let k = dof::node(self.nodes[c]);
        let old = self.mode[c];
        self.mode[c] = mode;
        match mode {
            Mode::Free => {
                held[k] = m.fixed[k];
                held[k + 1] = m.fixed[k + 1];
                held[k + 2] = m.fixed[k + 2];
                self.normal[c] = 0.0;
            }
            Mode::Stick => {
                q[k] = self.x_start[c][0];
                q[k + 1] = self.x_start[c][1];
                q[k + 2] = 0.5 * a;
                held[k] = true;
                held[k + 1] = true;
                held[k + 2] = true;
            }
            Mode::Slide => {
                held[k] = m.fixed[k];
                held[k + 1] = m.fixed[k + 1];
                q[k + 2] = 0.5 * a;
                held[k + 2] = true;
                if old == Mode::Stick {
                    let d = self.slip_dir[c];
                    let eps = 1e-6 * a;
                    q[k] = self.x_start[c][0] + eps * d[0];
                    q[k + 1] = self.x_start[c][1] + eps * d[1];
                }
            }
        }
    }

    /// Gradient (x, y) and Hessian (xx, xy, yy) of the sliding contact `c`'s dissipation at
    /// `q` with its current normal force, and the slip magnitude (zero: not differentiable).
    pub(crate) fn slide_derivatives(
        &self,
        g: &Ground,
        c: usize,
        q: &[f64],
    ) -> ([f64; 2], [f64; 3], f64) {
        let [vf, vs] = self.slip(c, q);
        let mu = if vf > 0.0 { g.mu_f } else { g.mu_b };
        let (pa, pb) = (mu * vf, g.mu_s * vs);
        let r = pa.hypot(pb);
        if r == 0.0 {
            return ([0.0; 2], [0.0; 3], 0.0);
        }
        let n = self.normal[c];
        // In (v_f, v_s): gradient N J u, Hessian N/r J (I - u u^T) J, J = diag(mu, mu_s).
        let (ua, ub) = (pa / r, pb / r);
        let gl = [n * mu * ua, n * g.mu_s * ub];
        let w = n / r;
        let hff = w * mu * mu * (1.0 - ua * ua);
        let hfs = -w * mu * g.mu_s * ua * ub;
        let hss = w * g.mu_s * g.mu_s * (1.0 - ub * ub);
        // Chain rule to (x, y): v_f = f . dx, v_s = s . dx.
        let (fw, sd) = (self.forward[c], self.side[c]);
        let grad = [gl[0] * fw[0] + gl[1] * sd[0], gl[0] * fw[1] + gl[1] * sd[1]];
        let hx = |i: usize, j: usize| {
            hff * fw[i] * fw[j] + hfs * (fw[i] * sd[j] + sd[i] * fw[j]) + hss * sd[i] * sd[j]
        };
        (grad, [hx(0, 0), hx(0, 1), hx(1, 1)], f::norm([vf, vs, 0.0]))
    }
}
