//! Time stepping: variational implicit Euler (MODEL section 2) and the static solve.
//!
//! One dynamic step minimises the incremental potential
//! `Phi(q) = 1/(2h^2) (q - qhat)^T M (q - qhat) + E(q, t_{n+1})`, `qhat = q_n + h v_n`,
//! by Newton's method: the Hessian (every stencil projected to positive semi-definite) is
//! assembled into a fixed banded pattern and factorised by faer's sparse Cholesky
//! ([`linsolve`]); a backtracking (Armijo) line search on `Phi` guards each update; the step
//! has converged when the last full Newton correction is below `tol * a` on every position
//! and below `tol` rad on every twist angle (the gradient scaled by the inverse Hessian).
//! Then `v_{n+1} = (q_{n+1} - q_n)/h` and the reference frames are transported in time.
//! A step that fails (iteration cap, failed line search, non-finite value) is retried as
//! two steps of `h/2`, up to `max_halvings` times, then reported with time, step and reason.
//!
//! The static mode minimises `E(q)` with the same Newton machinery, ramping gravity and the
//! natural strains over `load_steps` increments.
//!
//! Extension points: the rest strains at `t_{n+1}` come from an [`Actuation`] (muscles), and
//! the linear solve of each Newton iterate is one call that a contact solver may replace.
//!
//! With ground contact a step first tries the active-set path (contact statuses held, exact
//! Hessians, Coulomb conditions verified at convergence; `newton_active`); if its checks
//! fail the step restarts from the same iterate with one conic program per Newton iterate
//! (`newton`), whose failure rejects the step as above.
//!
//! [`explicit`] is the explicit symplectic reference (velocity Verlet on the same discrete
//! model, no contact) for the speed-against-accuracy charts.

pub mod explicit;
pub mod linsolve;

use crate::energy::{self, Assembly, Ctx, Term};
use crate::model::Model;
use crate::rod::dof;
use crate::state::State;
use linsolve::LinSolver;
use std::time::Instant;

/// Time-dependent natural strains (muscle activation enters here, MODEL 1.2).
pub trait Actuation: Send + Sync {
    /// Fill the integrated natural curvature `kappa0[i]` and twist `m0[i]` of every interior
    /// node `i` at time `t`.
    fn rest_strains(&self, t: f64, m: &Model, kappa0: &mut [[f64; 2]], m0: &mut [f64]);
}

/// The rod's own uniform natural curvature and twist from the problem file.
pub struct Natural;

impl Actuation for Natural {
    fn rest_strains(&self, _t: f64, m: &Model, kappa0: &mut [[f64; 2]], m0: &mut [f64]) {
        for i in 1..m.nodes - 1 {
            let l = m.voronoi[i];
            kappa0[i] = [m.natural_curvature[0] * l, m.natural_curvature[1] * l];
            m0[i] = m.natural_twist * l;
        }
    }
}

/// Newton iterations allowed to the conic path started where a failed active-set attempt
/// stopped (close to the solution: a few suffice; beyond that it starts over from the step's
/// start).
const WARM_CONIC_CAP: usize = 8;

/// Cumulative solver statistics.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct Stats {
    /// Accepted steps (dynamic) or load increments (static).
    pub steps: usize,
    /// Newton iterations over all accepted steps.
    pub newton_iterations: usize,
    /// Step halvings (each failed attempt that was retried with h/2).
    pub step_halvings: usize,
    /// Line-search backtracks.
    pub backtracks: usize,
    /// Times a factorisation needed a diagonal shift.
    pub shifted_factorizations: usize,
    /// Seconds in energy, gradient and Hessian assembly.
    pub assembly_s: f64,
    /// Seconds in numeric factorisation.
    pub factor_s: f64,
    /// Seconds in triangular solves.
    pub solve_s: f64,
    /// Seconds in line-search energy evaluations.
    pub line_search_s: f64,
    /// Conic (Clarabel) solves.
    pub conic_solves: usize,
    /// Clarabel interior-point iterations over all solves.
    pub conic_iterations: usize,
    /// Seconds in Clarabel (set-up and solve).
    pub conic_s: f64,
    /// Contact steps solved by the active-set path (no conic solve).
    pub active_set_steps: usize,
    /// Contact steps where the active-set path failed its checks and the conic path ran.
    pub active_set_fallbacks: usize,
    /// Fallbacks whose conic path, started where the active set stopped, failed and was rerun
    /// from the step's start.
    pub warm_conic_restarts: usize,
}

/// A step that could not be completed.
#[derive(Debug, thiserror::Error)]
pub enum StepError {
    /// Rejected after all allowed halvings.
    #[error("step rejected at t = {t} s with dt = {dt} s after {halvings} halvings: {reason}")]
    Rejected {
        /// Time at the start of the failed step (s).
        t: f64,
        /// Smallest step tried (s).
        dt: f64,
        /// Halvings tried.
        halvings: usize,
        /// Why the last attempt failed.
        reason: String,
    },
    /// The explicit integrator became unstable ([`explicit`]): non-finite state or energy
    /// blow-up. The state is that of the start of the failed step.
    #[error("explicit integrator unstable at t = {t} s with dt = {dt} s: {reason}")]
    Unstable {
        /// Time at the start of the failed step (s).
        t: f64,
        /// Step (s).
        dt: f64,
        /// What was detected.
        reason: String,
    },
}

/// Energies of a state (J).
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct Energies {
    /// Kinetic energy.
    pub kinetic: f64,
    /// Elastic energy (stretch, bend, twist).
    pub elastic: f64,
    /// Gravitational potential energy.
    pub gravity: f64,
    /// Sum.
    pub total: f64,
}

/// The stepper: model, terms, preallocated workspace and statistics.
pub struct Integrator<'m> {
    /// The model.
    pub model: &'m Model,
    terms: Vec<Box<dyn Term>>,
    actuation: Box<dyn Actuation>,
    asm: Assembly,
    lin: LinSolver,
    qhat: Vec<f64>,
    dq: Vec<f64>,
    trial: Vec<f64>,
    q_prev: Vec<f64>,
    v_prev: Vec<f64>,
    kappa0: Vec<[f64; 2]>,
    m0: Vec<f64>,
    load: f64,
    /// Solve contact steps by the active-set path first ([`crate::contact::active`]), the
    /// conic program only when its checks fail; off: a conic program every Newton iterate
    /// (environment variable `SLITHER_CONTACT=conic`).
    pub active_set: bool,
    /// Ground contacts, when the model has a ground.
    pub contacts: Option<crate::contact::Contacts>,
    normal_saved: Vec<f64>,
    pred_grad: Vec<f64>,
    q_init: Vec<f64>,
    held: Vec<bool>,
    /// Print every Newton iteration to stderr (environment variable `SLITHER_DEBUG`).
    trace: bool,
    /// Statistics so far.
    pub stats: Stats,
}

impl<'m> Integrator<'m> {
    /// A stepper for `model` driven by `actuation`.
    pub fn new(model: &'m Model, actuation: Box<dyn Actuation>) -> Self {
        let asm = Assembly::new(model.ndof);
        let lin = LinSolver::new(&asm);
        let n = model.ndof;
        Integrator {
            model,
            terms: energy::rod_terms(),
            actuation,
            asm,
            lin,
            qhat: vec![0.0; n],
            dq: vec![0.0; n],
            trial: vec![0.0; n],
            q_prev: vec![0.0; n],
            v_prev: vec![0.0; n],
            kappa0: vec![[0.0; 2]; model.nodes],
            m0: vec![0.0; model.nodes],
            load: 1.0,
            active_set: std::env::var("SLITHER_CONTACT").map_or(true, |v| v != "conic"),
            contacts: model
                .ground
                .as_ref()
                .map(|_| crate::contact::Contacts::new(model, &model.q0)),
            normal_saved: Vec::new(),
            pred_grad: vec![0.0; n],
            q_init: vec![0.0; n],
            held: vec![false; n],
            trace: std::env::var_os("SLITHER_DEBUG").is_some(),
            stats: Stats::default(),
        }
    }

    fn set_time(&mut self, t: f64) {
        self.actuation
            .rest_strains(t, self.model, &mut self.kappa0, &mut self.m0);
        if self.load != 1.0 {
            for k in self.kappa0.iter_mut() {
                k[0] *= self.load;
                k[1] *= self.load;
            }
            for m in self.m0.iter_mut() {
                *m *= self.load;
            }
        }
    }

    fn gravity(&self) -> [f64; 3] {
        let g = self.model.gravity;
        [g[0] * self.load, g[1] * self.load, g[2] * self.load]
    }

    /// Energies of `s` with the rest strains at `s.t`.
    pub fn energies(&mut self, s: &State) -> Energies {
        self.set_time(s.t);
        let ctx = Ctx {
            model: self.model,
            frames: &s.frames,
            kappa0: &self.kappa0,
            m0: &self.m0,
            gravity: self.gravity(),
        };
        let mut elastic = 0.0;
        let mut gravity = 0.0;
        for t in &self.terms {
            let e = t.eval(&ctx, &s.q, None, false);
            if t.name() == "gravity" {
                gravity += e;
            } else {
                elastic += e;
            }
        }
        let kinetic = s.kinetic_energy(self.model);
        Energies {
            kinetic,
            elastic,
            gravity,
            total: kinetic + elastic + gravity,
        }
    }

    /// Objective of the step problem at `q` (no derivatives).
    fn objective(&self, s: &State, q: &[f64], h: Option<f64>) -> f64 {
        let mut f = self.phi(s, q, h);
        if h.is_some() {
            if let (Some(g), Some(c)) = (&self.model.ground, &self.contacts) {
                f += c.dissipation(g, q);
            }
        }
        f
    }

    /// Clear and assemble the step objective at `s.q`: rod energy plus, in a dynamic step,
    /// the inertial term `1/(2h^2) |q - qhat|_M^2`; gradient and Hessian into `self.asm`.
    /// Returns the objective's value.
    fn assemble(&mut self, s: &State, h: Option<f64>, project: bool) -> f64 {
        let m = self.model;
        self.asm.clear();
        let ctx = Ctx {
            model: m,
            frames: &s.frames,
            kappa0: &self.kappa0,
            m0: &self.m0,
            gravity: self.gravity(),
        };
        let mut f = energy::total(&self.terms, &ctx, &s.q, Some(&mut self.asm), project);
        if let Some(h) = h {
            let w = 1.0 / (h * h);
            for k in 0..m.ndof {
                let d = s.q[k] - self.qhat[k];
                f += 0.5 * w * m.mass[k] * d * d;
                self.asm.grad[k] += w * m.mass[k] * d;
                self.asm.add_h(k, k, w * m.mass[k]);
            }
        }
        f
    }

    /// Largest position and twist-angle components of the Newton correction `self.dq`.
    fn correction_norms(&self) -> (f64, f64) {
        let mut dx: f64 = 0.0;
        let mut dth: f64 = 0.0;
        for (k, d) in self.dq.iter().enumerate() {
            if dof::is_edge(k) {
                dth = dth.max(d.abs());
            } else {
                dx = dx.max(d.abs());
            }
        }
        (dx, dth)
    }

    /// Rod energy plus the inertial term (dynamic) at `q`, without friction.
    fn phi(&self, s: &State, q: &[f64], h: Option<f64>) -> f64 {
        let ctx = Ctx {
            model: self.model,
            frames: &s.frames,
            kappa0: &self.kappa0,
            m0: &self.m0,
            gravity: self.gravity(),
        };
        let mut f = energy::total(&self.terms, &ctx, q, None, false);
        if let Some(h) = h {
            let w = 0.5 / (h * h);
            for k in 0..q.len() {
                f += w * self.model.mass[k] * (q[k] - self.qhat[k]).powi(2);
            }
        }
        f
    }

    /// Factorise the assembled Hessian, shifting the diagonal if it is only semi-definite.
    fn factor_shifted(&mut self, it: usize) -> Result<(), String> {
        if self.lin.factor(&self.asm).is_ok() {
            return Ok(());
        }
        let n = self.model.ndof;
        self.stats.shifted_factorizations += 1;
        let dmax = (0..n)
            .map(|k| self.asm.h(k, k).abs())
            .fold(0.0, f64::max)
            .max(1e-300);
        let mut shift = 1e-10 * dmax;
        for _ in 0..12 {
            for k in 0..n {
                self.asm.add_h(k, k, shift);
            }
            if self.lin.factor(&self.asm).is_ok() {
                return Ok(());
            }
            shift *= 10.0;
        }
        Err(format!(
            "Hessian not positive definite even with a diagonal shift (iteration {it})"
        ))
    }

    /// The active-set step (see [`crate::contact::active`]): Newton iterations with every
    /// contact's status held from the last conic solve. `Err` means the status no longer
    /// fits (or Newton failed); the caller then restores the iterate and solves the step
    /// with the conic program.
    fn newton_active(&mut self, s: &mut State, h: f64) -> Result<usize, String> {
        let mut ct = self.contacts.take().expect("contacts");
        let r = self.newton_active_with(s, h, &mut ct);
        self.contacts = Some(ct);
        r
    }

    fn newton_active_with(
        &mut self,
        s: &mut State,
        h: f64,
        ct: &mut crate::contact::Contacts,
    ) -> Result<usize, String> {
        use crate::contact::Mode;
        let m = self.model;
        let n = m.ndof;
        let a = m.diameter;
        let nc = ct.nodes.len();
        let ground = m.ground.as_ref().expect("ground");
        let scale = ct.weight_scale(m);
        self.held.copy_from_slice(&m.fixed);
        ct.hold(m, &mut s.q, &mut self.held);
        // Iterations (each one assembly) and status changes allowed before the conic
        // program takes over.
        let cap = m.max_iterations.min(40);
        let switch_cap = nc + 8;
        let mut switches = 0;
        // Exact (unprojected) Hessians converge quadratically; the projected one is the
        // fallback when the exact one is not positive definite.
        let mut project = false;
        let mut it = 0;
        while it < cap {
            it += 1;
            let t0 = Instant::now();
            let mut f0 = self.assemble(s, Some(h), project);
            if !f0.is_finite() || self.asm.grad.iter().any(|g| !g.is_finite()) {
                return Err(format!(
                    "non-finite objective or gradient at active-set iteration {it}"
                ));
            }
            // Reactions at the held coordinates: normal forces (updating the lagged values
            // of the sliding dissipation) and sticking friction forces.
            let mut dn: f64 = 0.0;
            let mut n_min = f64::INFINITY;
            let mut worst_ratio: f64 = 0.0;
            for c in 0..nc {
                ct.react[c] = 0.0;
                ct.ratio[c] = 0.0;
                if ct.mode[c] == Mode::Free {
                    continue;
                }
                let k = dof::node(ct.nodes[c]);
                let nn = self.asm.grad[k + 2];
                // Against the clamped value: a pulling contact (nn < 0) keeps N = 0 and must
                // count as settled, so that the Coulomb check below can free it.
                dn = dn.max((nn.max(0.0) - ct.normal[c]).abs());
                n_min = n_min.min(nn);
                ct.react[c] = nn;
                ct.normal[c] = nn.max(0.0);
                if ct.mode[c] == Mode::Stick {
                    let (r, mag, dir) = ct.stick_ratio(
                        ground,
                        c,
                        [self.asm.grad[k], self.asm.grad[k + 1]],
                        ct.normal[c],
                    );
                    if mag > 1e-9 * scale {
                        ct.ratio[c] = r;
                        ct.slip_dir[c] = dir;
                        worst_ratio = worst_ratio.max(r);
                    }
                }
            }
            // Sliding dissipation; a contact whose slip vanished sticks.
            let mut switched = 0;
            for c in 0..nc {
                if ct.mode[c] != Mode::Slide {
                    continue;
                }
                let (g2, h3, slip) = ct.slide_derivatives(ground, c, &s.q);
                let k = dof::node(ct.nodes[c]);
                if slip <= 1e-9 * a {
                    ct.set_mode(m, c, Mode::Stick, &mut s.q, &mut self.held);
                    switched += 1;
                    continue;
                }
                self.asm.grad[k] += g2[0];
                self.asm.grad[k + 1] += g2[1];
                self.asm.add_h(k, k, h3[0]);
                self.asm.add_h(k, k + 1, h3[1]);
                self.asm.add_h(k + 1, k + 1, h3[2]);
            }
            if switched > 0 {
                switches += switched;
                self.stats.assembly_s += t0.elapsed().as_secs_f64();
                if switches > switch_cap {
                    return Err(format!(
                        "too many contact status changes (active-set iteration {it})"
                    ));
                }
                continue;
            }
            f0 += ct.dissipation(ground, &s.q);
            for k in 0..n {
                if self.held[k] {
                    self.asm.fix(k);
                }
            }
            let t1 = Instant::now();
            self.stats.assembly_s += (t1 - t0).as_secs_f64();
            if project {
                self.factor_shifted(it)?;
            } else if self.lin.factor(&self.asm).is_err() {
                // Indefinite: redo this iterate with the projected Hessian.
                project = true;
                it -= 1;
                self.stats.factor_s += t1.elapsed().as_secs_f64();
                continue;
            }
            let t2 = Instant::now();
            self.stats.factor_s += (t2 - t1).as_secs_f64();
            for k in 0..n {
                self.dq[k] = -self.asm.grad[k];
            }
            self.lin.solve(&mut self.dq);
            let t3 = Instant::now();
            self.stats.solve_s += (t3 - t2).as_secs_f64();
            if self.dq.iter().any(|d| !d.is_finite()) {
                return Err(format!(
                    "non-finite Newton direction at active-set iteration {it}"
                ));
            }
            let (dx, dth) = self.correction_norms();
            let small = dx <= m.tolerance * a && dth <= m.tolerance;
            let settled = dn <= 1e-6 * scale;
            if self.trace {
                eprintln!("  active it {it}: dx {dx:.3e} dth {dth:.3e} dN {dn:.3e} N_min {n_min:.3e} stick ratio {worst_ratio:.6} switches {switches}");
            }
            if small && settled {
                // Exact Coulomb conditions at the converged point; a contact that violates
                // them changes status (pulling: lifts off; friction outside the cone: slides
                // in the direction its force dictates) and Newton continues.
                let mut switched = 0;
                for c in 0..nc {
                    if ct.mode[c] != Mode::Free && ct.react[c] < -1e-9 * scale {
                        ct.set_mode(m, c, Mode::Free, &mut s.q, &mut self.held);
                        switched += 1;
                    } else if ct.mode[c] == Mode::Stick && ct.ratio[c] > 1.0 + 1e-9 {
                        ct.set_mode(m, c, Mode::Slide, &mut s.q, &mut self.held);
                        switched += 1;
                    }
                }
                if switched == 0 {
                    for k in 0..n {
                        s.q[k] += self.dq[k];
                    }
                    self.stats.line_search_s += t3.elapsed().as_secs_f64();
                    return Ok(it);
                }
                switches += switched;
                if switches > switch_cap {
                    return Err(format!(
                        "too many contact status changes (active-set iteration {it})"
                    ));
                }
                continue;
            }
            // A sliding contact whose full step reverses its slip stops (sticks); a free
            // contact that the full step takes below the ground lands.
            let mut switched = 0;
            for c in 0..nc {
                let k = dof::node(ct.nodes[c]);
                match ct.mode[c] {
                    Mode::Slide => {
                        let s0 = ct.slip(c, &s.q);
                        for kk in 0..3 {
                            self.trial[k + kk] = s.q[k + kk] + self.dq[k + kk];
                        }
                        let s1 = ct.slip(c, &self.trial);
                        if s0[0] * s1[0] + s0[1] * s1[1] <= 0.0 {
                            ct.set_mode(m, c, Mode::Stick, &mut s.q, &mut self.held);
                            switched += 1;
                        }
                    }
                    Mode::Free => {
                        if s.q[k + 2] + self.dq[k + 2] < 0.5 * a {
                            let sl = ct.slip(c, &s.q);
                            let mode = if sl[0].hypot(sl[1]) > 1e-9 * a {
                                Mode::Slide
                            } else {
                                Mode::Stick
                            };
                            ct.set_mode(m, c, mode, &mut s.q, &mut self.held);
                            switched += 1;
                        }
                    }
                    Mode::Stick => {}
                }
            }
            if switched > 0 {
                switches += switched;
                self.stats.line_search_s += t3.elapsed().as_secs_f64();
                if switches > switch_cap {
                    return Err(format!(
                        "too many contact status changes (active-set iteration {it})"
                    ));
                }
                continue;
            }
            let slope: f64 = self.asm.grad.iter().zip(&self.dq).map(|(g, d)| g * d).sum();
            let mut alpha = 1.0;
            let noise = 1e-13 * f0.abs().max(1e-300);
            let mut accepted = false;
            for _ in 0..40 {
                for k in 0..n {
                    self.trial[k] = s.q[k] + alpha * self.dq[k];
                }
                if small {
                    accepted = true;
                    break;
                }
                let ft = self.phi(s, &self.trial, Some(h)) + ct.dissipation(ground, &self.trial);
                if ft.is_finite() && ft <= f0 + 1e-4 * alpha * slope + noise {
                    accepted = true;
                    break;
                }
                alpha *= 0.5;
                self.stats.backtracks += 1;
            }
            self.stats.line_search_s += t3.elapsed().as_secs_f64();
            if !accepted {
                return Err(format!(
                    "line search failed at active-set iteration {it} (slope {slope:.3e})"
                ));
            }
            std::mem::swap(&mut s.q, &mut self.trial);
        }
        Err(format!(
            "active-set Newton did not converge in {cap} iterations"
        ))
    }

    /// Newton iterations on `s.q` (the iterate) for the dynamic step (`h = Some`) or the
    /// static problem. Returns the iteration count.
    fn newton(&mut self, s: &mut State, h: Option<f64>, cap: usize) -> Result<usize, String> {
        let m = self.model;
        let n = m.ndof;
        let a = m.diameter;
        // With contact: whether the last conic step was taken in full with settled normal
        // forces, so that the gradient it predicted (`pred_grad`) can certify convergence
        // without another conic solve.
        let mut have_pred = false;
        for it in 1..=cap {
            let t0 = Instant::now();
            let f0 = self.assemble(s, h, true);
            for k in 0..n {
                if m.fixed[k] {
                    self.asm.fix(k);
                }
            }
            if !f0.is_finite() || self.asm.grad.iter().any(|g| !g.is_finite()) {
                return Err(format!(
                    "non-finite objective or gradient at Newton iteration {it}"
                ));
            }
            if have_pred {
                // The conic model was exact up to the tolerance: the true gradient at the new
                // iterate equals the predicted one, so the conic optimality conditions hold
                // for the true step problem (the constraints are linear).
                let mut worst: f64 = 0.0;
                for k in 0..n {
                    if m.fixed[k] {
                        continue;
                    }
                    let corr = (self.asm.grad[k] - self.pred_grad[k]).abs() / self.asm.h(k, k);
                    let scale = if dof::is_edge(k) { 1.0 } else { a };
                    worst = worst.max(corr / scale);
                }
                if worst <= m.tolerance {
                    self.stats.assembly_s += t0.elapsed().as_secs_f64();
                    return Ok(it - 1);
                }
            }
            let t1 = Instant::now();
            self.stats.assembly_s += (t1 - t0).as_secs_f64();
            let mut conic: Option<crate::contact::ConicStep> = None;
            if let (Some(hh), Some(ground), Some(ct)) = (h, &m.ground, self.contacts.as_mut()) {
                let r = ct
                    .solve(m, ground, &self.asm, &s.q, hh, &mut self.dq)
                    .map_err(|e| format!("{e} (Newton iteration {it})"))?;
                self.stats.conic_solves += 1;
                self.stats.conic_iterations += ct.last_iterations as usize;
                let t2 = Instant::now();
                self.stats.conic_s += (t2 - t1).as_secs_f64();
                conic = Some(r);
            } else {
                // Factorise; shift the diagonal if the projected Hessian is only semi-definite.
                self.factor_shifted(it)?;
                let t2 = Instant::now();
                self.stats.factor_s += (t2 - t1).as_secs_f64();
                for k in 0..n {
                    self.dq[k] = -self.asm.grad[k];
                }
                self.lin.solve(&mut self.dq);
                let t3 = Instant::now();
                self.stats.solve_s += (t3 - t2).as_secs_f64();
            }
            let t3 = Instant::now();
            if self.dq.iter().any(|d| !d.is_finite()) {
                return Err(format!("non-finite step at Newton iteration {it}"));
            }
            // Merit: the step objective (plus friction dissipation with the lagged normal
            // forces); the model decrease is the conic optimum's when contact is on.
            let f0 = match &conic {
                Some(_) => self.objective(s, &s.q, h),
                None => f0,
            };
            let slope: f64 = match &conic {
                Some(c) => c.predicted_decrease.min(0.0),
                None => self.asm.grad.iter().zip(&self.dq).map(|(g, d)| g * d).sum(),
            };
            let (dx, dth) = self.correction_norms();
            let mut normals_settled = true;
            if let (Some(c), Some(ct)) = (&conic, self.contacts.as_ref()) {
                normals_settled = c.max_normal_change <= 1e-6 * ct.weight_scale(m);
            }
            // With contact, a step whose predicted decrease is at round-off level is an
            // accuracy-level correction of the conic solve: take it in full.
            let negligible = conic.is_some() && -slope <= 1e-12 * f0.abs();
            let small = dx <= m.tolerance * a && dth <= m.tolerance;
            // Backtracking line search on the objective, tolerant of round-off near the minimum.
            let mut alpha = 1.0;
            let noise = 1e-13 * f0.abs().max(1e-300);
            let mut accepted = false;
            for _ in 0..40 {
                for k in 0..n {
                    self.trial[k] = s.q[k] + alpha * self.dq[k];
                }
                if small || negligible {
                    // The correction is below the tolerance: round-off (or the conic
                    // solver's accuracy) decides the merit, not the step.
                    accepted = true;
                    break;
                }
                let ft = self.objective(s, &self.trial, h);
                if ft.is_finite() && ft <= f0 + 1e-4 * alpha * slope + noise {
                    accepted = true;
                    break;
                }
                alpha *= 0.5;
                self.stats.backtracks += 1;
            }
            self.stats.line_search_s += t3.elapsed().as_secs_f64();
            if !accepted {
                return Err(format!(
                    "line search failed at Newton iteration {it} (slope {slope:.3e})"
                ));
            }
            std::mem::swap(&mut s.q, &mut self.trial);
            if h.is_none() {
                s.update_frames();
            }
            if let Some(ct) = self.contacts.as_mut() {
                if conic.is_some() {
                    std::mem::swap(&mut ct.normal, &mut ct.pending);
                }
            }
            if self.trace {
                eprintln!("  it {it}: alpha {alpha:.3e} dx {dx:.3e} dth {dth:.3e} normals_settled {normals_settled} slope {slope:.3e}");
            }
            if alpha == 1.0 && small && normals_settled {
                return Ok(it);
            }
            have_pred = false;
            if conic.is_some() && alpha == 1.0 && normals_settled {
                self.asm.mul(&self.dq, &mut self.pred_grad);
                for k in 0..n {
                    self.pred_grad[k] += self.asm.grad[k];
                }
                have_pred = true;
            }
        }
        Err(format!("Newton did not converge in {cap} iterations"))
    }

    /// One implicit Euler step of size `h`, without retries.
    pub fn try_step(&mut self, s: &mut State, h: f64) -> Result<usize, String> {
        let m = self.model;
        self.q_prev.copy_from_slice(&s.q);
        self.v_prev.copy_from_slice(&s.v);
        for k in 0..m.ndof {
            self.qhat[k] = if m.fixed[k] {
                s.q[k]
            } else {
                s.q[k] + h * s.v[k]
            };
        }
        self.set_time(s.t + h);
        s.q.copy_from_slice(&self.qhat);
        if let Some(ct) = self.contacts.as_mut() {
            ct.begin_step(m, &self.q_prev);
            self.normal_saved.clone_from(&ct.normal);
            // Start from a feasible iterate: lift predicted penetrations onto the ground.
            for &i in &ct.nodes {
                let k = dof::node(i) + 2;
                s.q[k] = s.q[k].max(0.5 * m.diameter);
            }
        }
        if let Some(ct) = self.contacts.as_mut().filter(|_| self.active_set) {
            if !ct.modes_valid {
                ct.guess_modes(m, &self.q_prev, &self.v_prev, h);
            }
        }
        if self.active_set && self.contacts.as_ref().is_some_and(|ct| ct.modes_valid) {
            self.q_init.copy_from_slice(&s.q);
            match self.newton_active(s, h) {
                Ok(it) => {
                    self.stats.active_set_steps += 1;
                    for k in 0..m.ndof {
                        s.v[k] = (s.q[k] - self.q_prev[k]) / h;
                    }
                    s.update_frames();
                    s.t += h;
                    return Ok(it);
                }
                Err(why) => {
                    if self.trace {
                        eprintln!("  active set rejected at t = {}: {why}", s.t);
                    }
                    self.stats.active_set_fallbacks += 1;
                    if s.q.iter().all(|x| x.is_finite()) {
                        // Start the conic path from where the active set stopped (lifted onto
                        // the ground), with its normal forces: usually a few conic solves from
                        // the solution. Should that start fail, the conic path runs again from
                        // the step's start before the step is rejected.
                        if let Some(ct) = self.contacts.as_mut() {
                            for &i in &ct.nodes {
                                let k = dof::node(i) + 2;
                                s.q[k] = s.q[k].max(0.5 * m.diameter);
                            }
                        }
                        match self.newton(s, Some(h), m.max_iterations.min(WARM_CONIC_CAP)) {
                            Ok(it) => return Ok(self.accept_conic(s, h, it)),
                            Err(why) => {
                                if self.trace {
                                    eprintln!("  warm conic start failed at t = {}: {why}", s.t);
                                }
                                self.stats.warm_conic_restarts += 1;
                            }
                        }
                    }
                    s.q.copy_from_slice(&self.q_init);
                    if let Some(ct) = self.contacts.as_mut() {
                        ct.normal.clone_from(&self.normal_saved);
                    }
                }
            }
        }
        match self.newton(s, Some(h), m.max_iterations) {
            Ok(it) => Ok(self.accept_conic(s, h, it)),
            Err(e) => {
                s.q.copy_from_slice(&self.q_prev);
                s.v.copy_from_slice(&self.v_prev);
                if let Some(ct) = self.contacts.as_mut() {
                    ct.normal.clone_from(&self.normal_saved);
                }
                Err(e)
            }
        }
    }

    /// Finish a step solved by [`Self::newton`]: contact statuses from the solution, velocities,
    /// frames and time. Returns `it`.
    fn accept_conic(&mut self, s: &mut State, h: f64, it: usize) -> usize {
        let m = self.model;
        if let Some(ct) = self.contacts.as_mut() {
            ct.classify(m, &s.q);
        }
        for k in 0..m.ndof {
            s.v[k] = (s.q[k] - self.q_prev[k]) / h;
        }
        s.update_frames();
        s.t += h;
        it
    }

    /// Advance by `h`, halving on failure (at most `max_halvings` levels).
    pub fn step(&mut self, s: &mut State, h: f64) -> Result<(), StepError> {
        self.step_level(s, h, 0)
    }

    fn step_level(&mut self, s: &mut State, h: f64, level: usize) -> Result<(), StepError> {
        match self.try_step(s, h) {
            Ok(it) => {
                self.stats.steps += 1;
                self.stats.newton_iterations += it;
                Ok(())
            }
            Err(reason) => {
                if self.trace {
                    eprintln!("step of {h} s at t = {} failed: {reason}", s.t);
                }
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

    /// Static equilibrium at load fraction `load` (gravity and natural strains scaled).
    pub fn solve_static(&mut self, s: &mut State, load: f64) -> Result<usize, StepError> {
        self.load = load;
        self.set_time(s.t);
        let r = self.newton(s, None, self.model.max_iterations);
        self.load = 1.0;
        match r {
            Ok(it) => {
                self.stats.steps += 1;
                self.stats.newton_iterations += it;
                s.v.fill(0.0);
                Ok(it)
            }
            Err(reason) => Err(StepError::Rejected {
                t: s.t,
                dt: 0.0,
                halvings: 0,
                reason: format!("static solve at load {load}: {reason}"),
            }),
        }
    }

    /// Gradient and (unprojected) Hessian of the rod energy at `q` with the frames of `s` and
    /// rest strains at `s.t` (for tests and diagnostics).
    pub fn energy_derivatives(&mut self, s: &State, q: &[f64], project: bool) -> (f64, Assembly) {
        self.set_time(s.t);
        let mut asm = Assembly::new(self.model.ndof);
        let ctx = Ctx {
            model: self.model,
            frames: &s.frames,
            kappa0: &self.kappa0,
            m0: &self.m0,
            gravity: self.gravity(),
        };
        let e = energy::total(&self.terms, &ctx, q, Some(&mut asm), project);
        (e, asm)
    }

    /// Normal force on every real node (N; zero without ground or contact).
    pub fn normal_forces(&self) -> Vec<f64> {
        let m = self.model;
        let mut out = vec![0.0; m.real.len()];
        if let Some(ct) = &self.contacts {
            for (c, &i) in ct.nodes.iter().enumerate() {
                out[i - m.real.start] = ct.normal[c];
            }
        }
        out
    }

    /// Rod energy at `q` with the frames of `s` and rest strains at `s.t`.
    pub fn energy_at(&mut self, s: &State, q: &[f64]) -> f64 {
        self.set_time(s.t);
        let ctx = Ctx {
            model: self.model,
            frames: &s.frames,
            kappa0: &self.kappa0,
            m0: &self.m0,
            gravity: self.gravity(),
        };
        energy::total(&self.terms, &ctx, q, None, false)
    }
}
