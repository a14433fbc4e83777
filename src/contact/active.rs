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
//!   the reaction at the current iterate and its change along the step inside the Newton
//!   system ([`super::reactions`]; `[solver] contact_coupling = false` lags it one iterate);
//! * a free contact has no force and must keep a positive gap.
//!
//! The converged point is the exact solution of the conic step problem (the same KKT system)
//! when every normal force is non-negative, every sticking contact's friction force lies in
//! the anisotropic friction set, every sliding contact still slides and no free contact
//! reached the ground. Otherwise the integrator falls back to the conic program.
//!
//! Within a step, statuses change as the iteration goes: at a converged point whose exact
//! conditions fail, and earlier when a contact pulls, or leaves the cone, both now and after
//! the step. After an early lift-off or slide the Newton step is still taken (it held fixed
//! only the coordinates the change releases). A sliding contact whose slip vanished sticks
//! before the iterate is assembled. An exact repeat of iterate, statuses and early changes
//! is a cycle and goes to the conic program at once; so does a stall (the correction not
//! falling tenfold in [`STALL_WINDOW`] iterations with unchanged statuses), and an iteration
//! or status change cap. The iterations of a failed attempt count in the step's total.

use super::reactions::{Reactions, UNCOUPLED};
use super::{Conic, ContactModel, Contacts, Ground};
use crate::model::Model;
use crate::newton::{Failure, Newton, Objective, Path, Potential, STALL_WINDOW};
use crate::rod::{dof, vec3::f};
use std::time::Instant;

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

/// Slip, relative to the rod diameter, given to a contact that starts sliding from a stick,
/// along the direction its friction force drives (so the dissipation is differentiable).
/// Ten times the sticking threshold `[solver] contact_tolerance` (1e-9). It must stay below
/// the slips the solution takes: contacts on the edge of the friction cone often slide by
/// less than 1e-6 a within a step, and started at 1e-6 a the Newton step reversed them, they
/// stuck, exceeded the cone and slid again, so whole stretches of the body cycled between
/// sticking and sliding until the conic program took over. Measured on the S-start: at 1e-6
/// 10, 397 and 1265 fallbacks at 50, 100 and 200 elements; at 1e-8 7, 3 and 126.
const SLIDE_START: f64 = 1e-8;

/// Converged points in a row, each with a contact leaving the friction cone, that mark a slip
/// front running along the body ([`FRONT_MARGIN`]). On the 200-element S-start such fronts
/// moved one contact per Newton iteration (38 in a row in one step, each contact 1.5 to 2 %
/// outside the cone once its neighbour slid, the whole stretch within 2 % of the cone) into
/// the 40-iteration cap. Measured (S-start it/step at 50, 100 and 200 elements; fallbacks at
/// 200; the sidewinding scene's change under a 100x tighter solve): without 3.81, 3.95, 8.10,
/// 122, 9.9e-5; 2 rounds 4.13, 4.04, 5.85, 104; 3 rounds 3.85, 3.64, 6.19, 109, 1.5e-4;
/// 4 rounds 3.82, 3.90, 6.38, 114, 1.01e-4; **6 rounds 3.81, 3.77, 6.88, 101, 9.9e-5**;
/// 8 rounds 3.81, 3.75, 7.39, 129. Fewer rounds also switch contacts of short stick-slip
/// episodes, which costs iterations at 50 elements and moves sidewinding's default-tolerance
/// result away from the tight one (the tight results agree to 1e-7).
const FRONT_ROUNDS: usize = 6;

/// Sticking contacts within this fraction of the friction cone, contiguous with a contact that
/// left it at a slip front, slide with it. 0.01, 0.02, 0.03, 0.05 at 200 elements (2 rounds):
/// 5.78, 5.85, 5.87, 5.86 it/step with 133, 104, 114, 142 fallbacks (8.10 and 122 without).
/// At 6 rounds, two runs each (the file, `mu_forward` + 1e-7): 0.005 gives 6.87 and 6.88 it/step
/// with 88 and 111 fallbacks, 0.01 6.99 and 6.91 with 96 and 98, 0.02 6.88 and 6.86 with 101
/// and 133, 0.03 6.91 and 6.87 with 138 and 128: below 0.03 the differences are within the
/// trajectory's own spread.
const FRONT_MARGIN: f64 = 0.02;

impl Contacts {
    /// Tangential slip `(dx . f, dx . s)` of contact `c` at `q` since the start of the step.
    pub(crate) fn slip(&self, c: usize, q: &[f64]) -> [f64; 2] {
        let k = dof::node(self.nodes[c]);
        let dx = f::sub([q[k], q[k + 1], q[k + 2]], self.x_start[c]);
        [f::dot(dx, self.forward[c]), f::dot(dx, self.side[c])]
    }

    /// Whether contact `c` slides with a slip that vanished (at most `tol`, m): it sticks.
    fn slip_vanished(&self, c: usize, q: &[f64], tol: f64) -> bool {
        self.mode[c] == Mode::Slide && {
            let s = self.slip(c, q);
            s[0].hypot(s[1]) <= tol
        }
    }

    /// Classify every contact from a converged step at `q` (after a conic solve).
    pub fn classify(&mut self, m: &Model, q: &[f64]) {
        let a = m.diameter;
        let tol = m.solver.contact_tolerance;
        for c in 0..self.nodes.len() {
            let k = dof::node(self.nodes[c]);
            let gap = q[k + 2] - 0.5 * a;
            self.mode[c] = if gap > tol * a {
                Mode::Free
            } else {
                let s = self.slip(c, q);
                if s[0].hypot(s[1]) <= tol * a {
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
        let tol = m.solver.contact_tolerance;
        for c in 0..self.nodes.len() {
            let k = dof::node(self.nodes[c]);
            self.mode[c] = if q[k + 2] - 0.5 * a > tol * a {
                Mode::Free
            } else if h * v[k].hypot(v[k + 1]) > tol * a {
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
                    let eps = SLIDE_START * a;
                    q[k] = self.x_start[c][0] + eps * d[0];
                    q[k + 1] = self.x_start[c][1] + eps * d[1];
                }
            }
        }
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
        let mu = if vf > 0.0 { g.mu_f } else { g.mu_b };
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

/// The active-set contact model: each step first runs [`ActiveSet::iterate`] with the
/// statuses of the last step (guessed from the state before any conic solve); if its checks
/// fail, the conic path continues from where it stopped (at most
/// `[solver] warm_conic_iterations`), then from the step's start.
pub struct ActiveSet {
    /// The conic model: contact data and the fallback.
    pub conic: Conic,
    held: Vec<bool>,
    q_init: Vec<f64>,
    last_conic: bool,
    reactions: Reactions,
    /// Objective gradient at `(x, y)` of every sticking contact (its friction force).
    tangential: Vec<[f64; 2]>,
    /// Contacts that already changed status before convergence in this step (once each, so
    /// that a contact at the edge of the friction cone cannot cycle).
    early: Vec<bool>,
    /// Iterations of the last [`ActiveSet::iterate`] (counted in the step's total also when
    /// it fails and the conic path finishes the step).
    spent: usize,
    /// Fingerprints of the iterates within the step (reused storage).
    seen: Vec<(u64, usize)>,
    /// Corrections `max(dx / a, dtheta)` since the last status change (reused storage).
    progress: Vec<f64>,
    /// Contacts that left the cone at the current converged point (reused storage).
    slid: Vec<usize>,
    /// The iterate and direction of a full step whose sufficient decrease is checked at the
    /// next assembly ([`Deferred`]; reused storage).
    saved: Saved,
}

/// Iterate and direction saved for a [`Deferred`] test.
#[derive(Default)]
struct Saved {
    q: Vec<f64>,
    dq: Vec<f64>,
}

impl Saved {
    fn save(&mut self, q: &[f64], dq: &[f64]) {
        self.q.clear();
        self.q.extend_from_slice(q);
        self.dq.clear();
        self.dq.extend_from_slice(dq);
    }

    /// A deferred full step failed its sufficient-decrease test (or could not be tested):
    /// back to the saved iterate and direction, and the backtracking line search from there,
    /// with its accepted point in `q`.
    fn backtrack(
        &self,
        nw: &mut Newton,
        m: &Model,
        q: &mut [f64],
        d: Deferred,
        iteration: usize,
        merit: &dyn Fn(&[f64]) -> f64,
    ) -> Result<(), Failure> {
        nw.dq.copy_from_slice(&self.dq);
        let alpha = nw.backtrack(m, &self.q, d.f0, d.slope, false, merit);
        let Some(alpha) = alpha else {
            return Err(Failure::LineSearch {
                path: Path::ActiveSet,
                iteration,
                slope: d.slope,
            });
        };
        if alpha < 1.0 {
            nw.stats.residuals.push(-1.0);
        }
        q.copy_from_slice(&nw.trial);
        Ok(())
    }
}

/// A full Newton step taken before its sufficient-decrease (Armijo) test: the merit at the
/// new iterate comes with that iterate's assembly (its objective value, plus the sliding
/// dissipation with the normal forces the step was computed with), so the test costs no
/// separate energy evaluation. If it fails, the step is backtracked from the saved iterate
/// exactly as an immediate test would have, and that assembly is redone.
#[derive(Clone, Copy)]
struct Deferred {
    /// Merit at the saved iterate.
    f0: f64,
    /// Directional derivative of the merit along the saved direction.
    slope: f64,
}

impl ActiveSet {
    /// The active-set model of `m`.
    pub fn new(m: &Model) -> Self {
        ActiveSet {
            conic: Conic::new(m),
            held: vec![false; m.ndof],
            q_init: vec![0.0; m.ndof],
            last_conic: false,
            reactions: Reactions::default(),
            tangential: Vec::new(),
            early: Vec::new(),
            spent: 0,
            seen: Vec::new(),
            progress: Vec::new(),
            slid: Vec::new(),
            saved: Saved::default(),
        }
    }

    /// Newton iterations with every contact's status held (touching gaps and sticking
    /// positions eliminated, their reactions the contact forces, sliding dissipation with
    /// exact derivatives). `Err`: the statuses no longer fit (or Newton failed); the caller
    /// then falls back to the conic program.
    pub fn iterate(
        &mut self,
        nw: &mut Newton,
        obj: &Potential,
        q: &mut Vec<f64>,
    ) -> Result<usize, Failure> {
        let m = obj.model;
        let set = &m.solver;
        let ct = &mut self.conic.ct;
        let held = &mut self.held;
        let reactions = &mut self.reactions;
        let tangential = &mut self.tangential;
        let early = &mut self.early;
        let slid = &mut self.slid;
        let saved = &mut self.saved;
        let mut deferred: Option<Deferred> = None;
        early.clear();
        early.resize(ct.nodes.len(), false);
        let path = Path::ActiveSet;
        let n = m.ndof;
        let a = m.diameter;
        let nc = ct.nodes.len();
        let ground = m.ground.as_ref().expect("a contact model needs a ground");
        let scale = ct.weight_scale(m);
        let force_tol = set.contact_force_tolerance;
        held.copy_from_slice(&m.fixed);
        ct.hold(m, q, held);
        nw.stats.residuals.clear();
        // Iterations (each one assembly) and status changes allowed before the conic
        // program takes over.
        let cap = m.max_iterations.min(set.active_set_max_iterations);
        let switch_cap = nc + set.active_set_extra_switches;
        let mut switches = 0;
        let mut conv_slide_rounds = 0usize;
        // Exact (unprojected) Hessians converge quadratically; the projected one is the
        // fallback when the exact one is not positive definite.
        let mut project = false;
        tangential.resize(nc, [0.0; 2]);
        let mut it = 0;
        // Fingerprints of the iterates (coordinates, statuses, early changes) after status
        // changes: an exact repeat is a cycle the iteration cannot leave (stick -> slide ->
        // stick of one contact whose force sits on the cone's edge), for the conic program at
        // once. Near cycles without status changes (full coupled steps while the normal forces
        // change sign from one iterate to the next; not bitwise repeats, so fingerprinting
        // every iterate caught none) are left to the stall test below.
        let seen = &mut self.seen;
        seen.clear();
        let mut fingerprinted = usize::MAX;
        let progress = &mut self.progress;
        progress.clear();
        let mut progress_switches = 0;
        log::debug!("  active step");
        while it < cap {
            it += 1;
            self.spent = it;
            // A pending step's merit needs this iterate's statuses: resolve it now if a
            // zero-slip stick below would change them.
            if let Some(d) = deferred {
                if (0..nc).any(|c| ct.slip_vanished(c, q, set.contact_tolerance * a)) {
                    deferred = None;
                    let ct: &Contacts = ct;
                    saved.backtrack(nw, m, q, d, it, &|x| {
                        obj.value(x) + ct.dissipation(ground, x)
                    })?;
                }
            }
            // A sliding contact whose slip vanished sticks (before the assembly it changes).
            let mut switched = 0;
            for c in 0..nc {
                if ct.slip_vanished(c, q, set.contact_tolerance * a) {
                    log::debug!("  switch zero-slip {c}");
                    ct.set_mode(m, c, Mode::Stick, q, held);
                    switched += 1;
                }
            }
            if switched > 0 {
                switches += switched;
                nw.stats.residuals.push(f64::NAN);
                if switches > switch_cap {
                    return Err(Failure::ContactSwitches { iteration: it });
                }
            }
            if switches != fingerprinted {
                fingerprinted = switches;
                let key = fingerprint(q, &ct.mode, early);
                if let Some(&(_, first)) = seen.iter().find(|(k, _)| *k == key) {
                    return Err(Failure::ContactCycle {
                        iteration: it,
                        first,
                    });
                }
                seen.push((key, it));
            }
            let t0 = Instant::now();
            let mut f0 = obj.assemble(q, &mut nw.asm, project);
            if project {
                nw.stats.projected_iterations += 1;
            }
            if let Some(d) = deferred.take() {
                // The merit here, with the normal forces of the step's direction (not yet
                // updated from this assembly).
                let ft = f0 + ct.dissipation(ground, q);
                let noise = set.line_search_noise * d.f0.abs().max(1e-300);
                if !(ft.is_finite() && ft <= d.f0 + set.armijo * d.slope + noise) {
                    let ct: &Contacts = ct;
                    saved.backtrack(nw, m, q, d, it, &|x| {
                        obj.value(x) + ct.dissipation(ground, x)
                    })?;
                    nw.stats.assembly_s += t0.elapsed().as_secs_f64();
                    continue;
                }
            }
            if !f0.is_finite() || nw.asm.grad.iter().any(|g| !g.is_finite()) {
                return Err(Failure::NonFiniteObjective {
                    path,
                    iteration: it,
                });
            }
            // Reactions at the held coordinates: normal forces (those of the sliding
            // dissipation below) and sticking friction forces.
            let mut n_min = f64::INFINITY;
            let mut worst_ratio: f64 = 0.0;
            for c in 0..nc {
                ct.react[c] = 0.0;
                ct.ratio[c] = 0.0;
                if ct.mode[c] == Mode::Free {
                    continue;
                }
                let k = dof::node(ct.nodes[c]);
                let nn = nw.asm.grad[k + 2];
                n_min = n_min.min(nn);
                ct.react[c] = nn;
                ct.normal[c] = nn.max(0.0);
                if ct.mode[c] == Mode::Stick {
                    tangential[c] = [nw.asm.grad[k], nw.asm.grad[k + 1]];
                    let (r, mag, dir) = ct.stick_ratio(ground, c, tangential[c], ct.normal[c]);
                    if mag > force_tol * scale {
                        ct.ratio[c] = r;
                        ct.slip_dir[c] = dir;
                        worst_ratio = worst_ratio.max(r);
                    }
                }
            }
            // Sliding dissipation.
            reactions.begin(nc);
            for c in 0..nc {
                if ct.mode[c] != Mode::Slide {
                    continue;
                }
                let (g2, h3) = ct.slide_derivatives(ground, c, q);
                let k = dof::node(ct.nodes[c]);
                nw.asm.grad[k] += g2[0];
                nw.asm.grad[k + 1] += g2[1];
                nw.asm.add_h(k, k, h3[0]);
                nw.asm.add_h(k, k + 1, h3[1]);
                nw.asm.add_h(k + 1, k + 1, h3[2]);
                reactions.set_slide(c, g2, ct.normal[c]);
            }
            f0 += ct.dissipation(ground, q);
            reactions.capture(ct, &nw.asm);
            let mut residual: f64 = 0.0;
            for k in 0..n {
                if held[k] {
                    nw.asm.fix(k);
                } else {
                    let r = nw.asm.grad[k].abs() / if dof::is_edge(k) { a } else { 1.0 };
                    residual = residual.max(r / scale);
                }
            }
            nw.stats.residuals.push(residual);
            let t1 = Instant::now();
            nw.stats.assembly_s += (t1 - t0).as_secs_f64();
            if project {
                nw.factor_shifted(m, it)?;
            } else if nw.lin.factor(&nw.asm).is_err() {
                // Indefinite: redo this iterate with the projected Hessian.
                project = true;
                it -= 1;
                nw.stats.factor_s += t1.elapsed().as_secs_f64();
                continue;
            }
            let t2 = Instant::now();
            nw.stats.factor_s += (t2 - t1).as_secs_f64();
            nw.solve_direction();
            // The sliding contacts' normal forces inside the Newton system, then the
            // predicted change of every reaction over the step.
            let force_step = set.normal_force_tolerance * scale;
            let mut krylov = if set.contact_coupling && reactions.coupled() {
                // GMRES until the coupling's residual is below the square of this
                // iterate's residual (so the iteration keeps its quadratic rate).
                let krylov_tol =
                    scale * (1e-2 * set.normal_force_tolerance).min(residual * residual);
                reactions.couple(ct, nw, held, krylov_tol)
            } else {
                0
            };
            let dn_step = reactions.predict(ct, &nw.dq);
            let t3 = Instant::now();
            nw.stats.solve_s += (t3 - t2).as_secs_f64();
            if nw.dq.iter().any(|d| !d.is_finite()) {
                return Err(Failure::NonFiniteStep {
                    path,
                    iteration: it,
                });
            }
            let (dx, dth) = nw.correction_norms();
            if switches != progress_switches {
                progress.clear();
                progress_switches = switches;
            }
            progress.push((dx / a).max(dth));
            if let Some(&before) = progress.iter().rev().nth(STALL_WINDOW) {
                let now = *progress.last().unwrap();
                if now > 0.1 * before {
                    return Err(Failure::Stalled {
                        iteration: it,
                        now,
                        before,
                    });
                }
            }
            let small = dx <= m.tolerance * a && dth <= m.tolerance;
            let settled = dn_step <= force_step;
            log::debug!("  active it {it}: dx {dx:.3e} dth {dth:.3e} dN(step) {dn_step:.3e} krylov {krylov} N_min {n_min:.3e} stick ratio {worst_ratio:.6} switches {switches}");
            if small && settled {
                // Exact Coulomb conditions at the converged point; a contact that violates
                // them changes status (pulling: lifts off; friction outside the cone: slides
                // in the direction its force dictates) and Newton continues.
                let mut switched = 0;
                slid.clear();
                for c in 0..nc {
                    if ct.mode[c] != Mode::Free && ct.react[c] < -force_tol * scale {
                        log::debug!("  switch conv-lift {c}");
                        ct.set_mode(m, c, Mode::Free, q, held);
                        switched += 1;
                    } else if ct.mode[c] == Mode::Stick && ct.ratio[c] > 1.0 + force_tol {
                        log::debug!("  switch conv-slide {c}");
                        ct.set_mode(m, c, Mode::Slide, q, held);
                        slid.push(c);
                        switched += 1;
                    }
                }
                // A slip front: FRONT_ROUNDS converged points in a row where a contact left
                // the cone. Sticking neighbours of the contacts that slid, contiguous with them
                // and within FRONT_MARGIN of the cone, slide too (a wrong guess reverses and
                // sticks again in the next iterate; the exact conditions are still verified at
                // the converged point).
                if slid.is_empty() {
                    conv_slide_rounds = 0;
                } else {
                    conv_slide_rounds += 1;
                }
                if conv_slide_rounds >= FRONT_ROUNDS {
                    for &c0 in slid.iter() {
                        // Walk to either side along neighbouring nodes.
                        for step in [usize::checked_sub, usize::checked_add] {
                            let mut prev = c0;
                            while let Some(c) = step(prev, 1).filter(|&c| c < nc) {
                                if ct.nodes[c].abs_diff(ct.nodes[prev]) != 1
                                    || ct.mode[c] != Mode::Stick
                                    || ct.ratio[c] <= 1.0 - FRONT_MARGIN
                                {
                                    break;
                                }
                                log::debug!("  switch front-slide {c}");
                                ct.set_mode(m, c, Mode::Slide, q, held);
                                switched += 1;
                                prev = c;
                            }
                        }
                    }
                }
                if switched == 0 {
                    for k in 0..n {
                        q[k] += nw.dq[k];
                    }
                    nw.stats.line_search_s += t3.elapsed().as_secs_f64();
                    return Ok(it);
                }
                switches += switched;
                nw.stats.residuals.push(f64::NAN);
                if switches > switch_cap {
                    return Err(Failure::ContactSwitches { iteration: it });
                }
                continue;
            }
            // A contact pulling now and after the step lifts off; a sticking force outside the
            // cone now and after the step slides (see [`super::reactions`]). A sliding contact
            // whose full step reverses its slip stops (sticks); a free contact that the full
            // step takes below the ground lands.
            let mut switched = 0;
            let pull = -force_tol * scale;
            for c in 0..nc {
                let ch = reactions.change[c];
                if early[c] {
                    continue;
                }
                if ct.mode[c] != Mode::Free && ct.react[c] < pull && ct.react[c] + ch[2] < pull {
                    log::debug!("  switch early-lift {c}");
                    ct.set_mode(m, c, Mode::Free, q, held);
                    early[c] = true;
                    switched += 1;
                } else if ct.mode[c] == Mode::Stick && ct.ratio[c] > 1.0 + force_tol {
                    let t = tangential[c];
                    let after = [t[0] + ch[0], t[1] + ch[1]];
                    let n_after = (ct.react[c] + ch[2]).max(0.0);
                    let (r, _, _) = ct.stick_ratio(ground, c, after, n_after);
                    if r > 1.0 + force_tol {
                        log::debug!("  switch early-slide {c}");
                        ct.set_mode(m, c, Mode::Slide, q, held);
                        early[c] = true;
                        switched += 1;
                    }
                }
            }
            // Those early changes release coordinates the direction held fixed (a lift-off its
            // height, a new slide its ground position), so the direction is still one of
            // descent with the new statuses: it is taken below rather than thrown away.
            let released = switched;
            for c in 0..nc {
                let k = dof::node(ct.nodes[c]);
                match ct.mode[c] {
                    Mode::Slide => {
                        let s0 = ct.slip(c, q);
                        for kk in 0..3 {
                            nw.trial[k + kk] = q[k + kk] + nw.dq[k + kk];
                        }
                        let s1 = ct.slip(c, &nw.trial);
                        if s0[0] * s1[0] + s0[1] * s1[1] <= 0.0 {
                            log::debug!("  switch reversal {c}");
                            ct.set_mode(m, c, Mode::Stick, q, held);
                            switched += 1;
                        }
                    }
                    Mode::Free => {
                        if q[k + 2] + nw.dq[k + 2] < 0.5 * a {
                            let sl = ct.slip(c, q);
                            let mode = if sl[0].hypot(sl[1]) > set.contact_tolerance * a {
                                Mode::Slide
                            } else {
                                Mode::Stick
                            };
                            log::debug!("  switch landing {c}");
                            ct.set_mode(m, c, mode, q, held);
                            switched += 1;
                        }
                    }
                    Mode::Stick => {}
                }
            }
            if switched > 0 {
                switches += switched;
                nw.stats.residuals.push(f64::NAN);
                if switches > switch_cap {
                    return Err(Failure::ContactSwitches { iteration: it });
                }
                if switched > released {
                    nw.stats.line_search_s += t3.elapsed().as_secs_f64();
                    continue;
                }
                // The merit with the new statuses at the (slightly moved) start point.
                f0 = obj.value(q) + ct.dissipation(ground, q);
            }
            let mut slope: f64 = nw.asm.grad.iter().zip(&nw.dq).map(|(g, d)| g * d).sum();
            if slope >= 0.0 && krylov > 0 && krylov != UNCOUPLED {
                // The coupled direction need not descend on the merit (whose normal forces are
                // frozen at this iterate); the symmetric direction does.
                reactions.restore_symmetric(&mut nw.dq);
                krylov = UNCOUPLED;
                slope = nw.asm.grad.iter().zip(&nw.dq).map(|(g, d)| g * d).sum();
            }
            let alpha = {
                let ct: &Contacts = ct;
                // Near the solution (correction within 100 tolerances) a converged coupled
                // direction is the Newton direction of the system with the normal forces
                // moving, not of the merit below (normal forces frozen at this iterate), which
                // can refuse it: at 200 elements the line search then cut every step to a
                // quarter and Newton crawled (contraction 0.75) into the iteration cap. Such
                // steps are taken in full; convergence is still judged by the correction and
                // the predicted force change.
                let near = dx <= 100.0 * m.tolerance * a && dth <= 100.0 * m.tolerance;
                let full = small || (krylov > 0 && krylov < UNCOUPLED && near);
                if !full && slope < 0.0 {
                    // The full step now, its test at the next assembly.
                    deferred = Some(Deferred { f0, slope });
                    saved.save(q, &nw.dq);
                }
                nw.backtrack(m, q, f0, slope, full || deferred.is_some(), &|x| {
                    obj.value(x) + ct.dissipation(ground, x)
                })
            };
            nw.stats.line_search_s += t3.elapsed().as_secs_f64();
            let Some(alpha) = alpha else {
                return Err(Failure::LineSearch {
                    path,
                    iteration: it,
                    slope,
                });
            };
            if alpha < 1.0 || project || krylov == UNCOUPLED {
                // Not a full Newton step of the exact linearisation (damped, projected Hessian
                // or the coupled direction not found): marked for the convergence tests.
                nw.stats.residuals.push(-1.0);
            }
            std::mem::swap(q, &mut nw.trial);
        }
        Err(Failure::NotConverged {
            path,
            iterations: cap,
        })
    }
}

impl ContactModel for ActiveSet {
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
        let ct = &mut self.conic.ct;
        if !ct.modes_valid {
            ct.guess_modes(m, q_start, v_start, h);
        }
    }

    fn solve(
        &mut self,
        nw: &mut Newton,
        obj: &Potential,
        q: &mut Vec<f64>,
    ) -> Result<usize, Failure> {
        let m = obj.model;
        if self.conic.ct.modes_valid {
            self.q_init.copy_from_slice(q);
            match self.iterate(nw, obj, q) {
                Ok(it) => {
                    nw.stats.active_set_steps += 1;
                    self.last_conic = false;
                    log::debug!("  step total {it}");
                    return Ok(it);
                }
                Err(why) => {
                    log::debug!("  active set rejected: {why}");
                    nw.stats.active_set_fallbacks += 1;
                    match why {
                        Failure::ContactCycle { .. } => nw.stats.contact_cycles += 1,
                        Failure::Stalled { .. } => nw.stats.active_set_stalls += 1,
                        _ => {}
                    }
                    let spent = self.spent;
                    if q.iter().all(|x| x.is_finite()) {
                        // Start the conic path from where the active set stopped (lifted onto
                        // the ground), with its normal forces: usually a few conic solves from
                        // the solution. Should that start fail, the conic path runs again from
                        // the step's start before the step is rejected.
                        self.conic.ct.lift(m, q);
                        let cap = m.max_iterations.min(m.solver.warm_conic_iterations);
                        match self.conic.iterate(nw, obj, q, cap) {
                            Ok(it) => {
                                self.last_conic = true;
                                log::debug!("  step total {} (warm conic)", spent + it);
                                return Ok(spent + it);
                            }
                            Err(why) => {
                                log::debug!("  warm conic start failed: {why}");
                                nw.stats.warm_conic_restarts += 1;
                            }
                        }
                    }
                    q.copy_from_slice(&self.q_init);
                    self.conic.restore_normals();
                    let it = self.conic.iterate(nw, obj, q, m.max_iterations)?;
                    self.last_conic = true;
                    log::debug!("  step total {} (conic)", spent + it);
                    return Ok(spent + it);
                }
            }
        }
        let it = self.conic.iterate(nw, obj, q, m.max_iterations)?;
        self.last_conic = true;
        Ok(it)
    }

    fn accept(&mut self, m: &Model, q: &[f64]) {
        if self.last_conic {
            self.conic.ct.classify(m, q);
        }
    }

    fn reject(&mut self) {
        self.conic.reject();
    }

    fn normal_forces(&self, m: &Model, out: &mut [f64]) {
        self.conic.ct.normal_forces(m, out);
    }
}

/// A hash of the coordinates' bits, the contacts' statuses and which contacts already
/// changed status early (the state the rest of the iteration depends on).
fn fingerprint(q: &[f64], mode: &[Mode], early: &[bool]) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for x in q {
        x.to_bits().hash(&mut h);
    }
    for (m, e) in mode.iter().zip(early) {
        (*m as u8, *e).hash(&mut h);
    }
    h.finish()
}
