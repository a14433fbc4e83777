//! Contact statuses of the active-set path (free, sticking, sliding) and the local contact
//! quantities they are decided by: slip, the stick ratio against the anisotropic friction set,
//! the sliding dissipation's derivatives. [`super::active`] iterates with them.

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

impl Mode {
    /// The contact node's coordinates (0, 1, 2: `x, y, z`) held by this status: none when
    /// free, all three when sticking, the height when sliding.
    pub fn held(self) -> std::ops::Range<usize> {
        match self {
            Mode::Free => 0..0,
            Mode::Stick => 0..3,
            Mode::Slide => 2..3,
        }
    }
}

/// Slip, relative to the rod diameter, given to a contact that starts sliding from a stick,
/// along the direction its friction force drives (so the dissipation is differentiable).
/// Ten times the sticking threshold `[solver] contact_tolerance` (1e-9). It must stay below
/// the slips the solution takes: contacts on the edge of the friction cone often slide by
/// less than 1e-6 a within a step, and started at 1e-6 a the Newton step reversed them, they
/// stuck, exceeded the cone and slid again, so whole stretches of the body cycled between
/// sticking and sliding until the conic program took over. Measured on the S-start: at 1e-6
/// 10, 397 and 1265 fallbacks at 50, 100 and 200 elements; at 1e-8 7, 3 and 126.
const SLIDE_START: f64 = 1e-8;

/// Every contact's status, and what the iteration learns about it at each iterate.
#[derive(Clone, Debug, Default)]
pub struct Statuses {
    /// Status of every contact (valid after a converged step or a guess).
    pub mode: Vec<Mode>,
    /// Whether `mode` holds a status from a converged step or a guess.
    pub valid: bool,
    /// Reaction at the held height of every touching contact (its normal force, N).
    pub(crate) react: Vec<f64>,
    /// How far every sticking contact's friction force is inside its cone (1 on the edge).
    pub(crate) ratio: Vec<f64>,
    /// Slip direction in `(x, y)` that every sticking contact's force would drive.
    pub(crate) slip_dir: Vec<[f64; 2]>,
}

impl Contacts {
    /// Tangential slip `(dx . f, dx . s)` of contact `c` at `q` since the start of the step.
    pub(crate) fn slip(&self, c: usize, q: &[f64]) -> [f64; 2] {
        let k = dof::node(self.nodes[c]);
        let dx = f::sub([q[k], q[k + 1], q[k + 2]], self.x_start[c]);
        [f::dot(dx, self.forward[c]), f::dot(dx, self.side[c])]
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
        let mu = g.mu_along(sf);
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

    /// Gradient (x, y) and Hessian (xx, xy, yy) of the sliding contact `c`'s dissipation at
    /// `q` with its current normal force (zero at zero slip, where it is not differentiable;
    /// the active set sticks such a contact before it gets here).
    pub(crate) fn slide_derivatives(
        &self,
        g: &Ground,
        c: usize,
        q: &[f64],
    ) -> ([f64; 2], [f64; 3]) {
        let [vf, vs] = self.slip(c, q);
        let mu = g.mu_along(vf);
        let (pa, pb) = (mu * vf, g.mu_s * vs);
        let r = pa.hypot(pb);
        if r == 0.0 {
            return ([0.0; 2], [0.0; 3]);
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
        (grad, [hx(0, 0), hx(0, 1), hx(1, 1)])
    }
}

impl Statuses {
    /// Statuses for the contacts of `ct`, all free and not yet valid.
    pub fn new(ct: &Contacts) -> Self {
        let nc = ct.nodes.len();
        Statuses {
            mode: vec![Mode::Free; nc],
            valid: false,
            react: vec![0.0; nc],
            ratio: vec![0.0; nc],
            slip_dir: vec![[0.0; 2]; nc],
        }
    }

    /// Whether contact `c` slides with a slip that vanished (at most `tol`, m): it sticks.
    pub(crate) fn slip_vanished(&self, ct: &Contacts, c: usize, q: &[f64], tol: f64) -> bool {
        self.mode[c] == Mode::Slide && {
            let s = ct.slip(c, q);
            s[0].hypot(s[1]) <= tol
        }
    }

    /// Classify every contact from a converged step at `q` (after a conic solve).
    pub fn classify(&mut self, ct: &Contacts, m: &Model, q: &[f64]) {
        let a = m.diameter;
        let tol = m.solver.contact_tolerance;
        for c in 0..ct.nodes.len() {
            let k = dof::node(ct.nodes[c]);
            let gap = q[k + 2] - 0.5 * a;
            self.mode[c] = if gap > tol * a {
                Mode::Free
            } else {
                let s = ct.slip(c, q);
                if s[0].hypot(s[1]) <= tol * a {
                    Mode::Stick
                } else {
                    Mode::Slide
                }
            };
        }
        self.valid = true;
    }

    /// Guess every contact's status from a state (positions `q`, velocities `v`) before any
    /// conic solve: touching contacts stick when at rest and slide otherwise. The active-set
    /// step verifies (and corrects) the guess.
    pub fn guess(&mut self, ct: &Contacts, m: &Model, q: &[f64], v: &[f64], h: f64) {
        let a = m.diameter;
        let tol = m.solver.contact_tolerance;
        for c in 0..ct.nodes.len() {
            let k = dof::node(ct.nodes[c]);
            self.mode[c] = if q[k + 2] - 0.5 * a > tol * a {
                Mode::Free
            } else if h * v[k].hypot(v[k + 1]) > tol * a {
                Mode::Slide
            } else {
                Mode::Stick
            };
        }
        self.valid = true;
    }

    /// Put the held coordinates of `q` on their constraints: touching gaps at zero, sticking
    /// contacts at their start positions; free contacts lifted onto the ground if below.
    /// Marks the held coordinates in `held` and zeroes free contacts' normal forces.
    pub fn hold(&self, ct: &mut Contacts, m: &Model, q: &mut [f64], held: &mut [bool]) {
        let a = m.diameter;
        for c in 0..ct.nodes.len() {
            let k = dof::node(ct.nodes[c]);
            match self.mode[c] {
                Mode::Free => {
                    q[k + 2] = q[k + 2].max(0.5 * a);
                    ct.normal[c] = 0.0;
                }
                Mode::Stick => {
                    q[k] = ct.x_start[c][0];
                    q[k + 1] = ct.x_start[c][1];
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

    /// Change contact `c`'s status within the active-set iteration, moving its held
    /// coordinates of `q` onto the new constraints: sticking at the start position; sliding
    /// from a small slip along the direction of its last friction force (from a stick) or
    /// from where it is; free with no force.
    pub(crate) fn set(
        &mut self,
        ct: &mut Contacts,
        m: &Model,
        c: usize,
        mode: Mode,
        q: &mut [f64],
        held: &mut [bool],
    ) {
        let a = m.diameter;
        let k = dof::node(ct.nodes[c]);
        let old = self.mode[c];
        self.mode[c] = mode;
        match mode {
            Mode::Free => {
                held[k] = m.fixed[k];
                held[k + 1] = m.fixed[k + 1];
                held[k + 2] = m.fixed[k + 2];
                ct.normal[c] = 0.0;
            }
            Mode::Stick => {
                q[k] = ct.x_start[c][0];
                q[k + 1] = ct.x_start[c][1];
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
                    let eps = SLIDE_START * a;
                    q[k] = ct.x_start[c][0] + eps * d[0];
                    q[k + 1] = ct.x_start[c][1] + eps * d[1];
                }
            }
        }
    }
}
