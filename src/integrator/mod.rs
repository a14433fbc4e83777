//! Time stepping: the implicit steppers and the explicit reference, behind one [`Stepper`]
//! trait that the run loop ([`crate::sim`]) drives.
//!
//! * [`Integrator`] (dynamic, implicit): every step minimises the incremental potential
//!   `Phi(q) = w/2 (q - qhat)^T M (q - qhat) + E(q, t_{n+1})` (+ friction, subject to the
//!   contact constraints) by Newton's method ([`crate::newton`]), with the contact model of
//!   the problem ([`crate::contact::ContactModel`]). What distinguishes one implicit time
//!   integrator from another is only its predictor `qhat`, its inertia weight `w` and its
//!   velocity update: a [`Scheme`] (implicit Euler: [`euler::ImplicitEuler`]). A step that
//!   fails (iteration cap, failed line search, non-finite value, unsolved conic program) is
//!   retried as two steps of `h/2`, up to `max_halvings` times, then reported with time, step
//!   and reason ([`StepError`]). Adding a time integrator: one file with a [`Scheme`] and one
//!   variant of [`crate::problem::IntegratorKind`] (see [`scheme_for`]).
//! * [`statics::Static`]: static equilibrium `min E(q)` by the same Newton machinery, ramping
//!   gravity and the natural strains over `load_steps` increments.
//! * [`explicit::Explicit`]: velocity Verlet on the same discrete model and the same energy
//!   terms (no contact), the reference of the speed-against-accuracy charts.
//!
//! With `[time] adaptive = true` the implicit stepper sizes its steps by a local error
//! estimate ([`adaptive`]): [`Stepper::adaptive_step`] solves a step, estimates its error
//! against the scheme's explicit predictor, and accepts it or retries it smaller, leaving
//! the state, the scheme's history and the contact model untouched by a rejected try.
//!
//! The rest strains at a time come from an [`Actuation`] ([`crate::gait`]).
//!
//! # Names
//!
//! Four names, one concept each:
//! * [`Stepper`] (trait): anything the run loop can advance by a step (`step`, normal forces,
//!   energies, statistics). Implemented by [`Integrator`], [`statics::Static`] and
//!   [`explicit::Explicit`].
//! * [`Integrator`] (struct): the implicit dynamic stepper, i.e. Newton on the incremental
//!   potential with contact, halvings and adaptive steps. One struct for every implicit
//!   integrator.
//! * [`Scheme`] (trait): what one implicit integrator changes in [`Integrator`]: predictor,
//!   inertia weight, velocity update, error predictor ([`euler::ImplicitEuler`],
//!   [`bdf2::Bdf2`]).
//! * [`crate::problem::IntegratorKind`] (enum): the problem file's `[solver] integrator`
//!   choice, mapped to a [`Scheme`] by [`scheme_for`] (or to [`explicit::Explicit`] by
//!   [`crate::sim::run_gait`]). The charts and the summary name integrators by it too.

/// The fraction of the velocity's change over the last step that the extrapolated start
/// ([`Scheme::extrapolated_start`]) carries into the next at the nodes that touched the
/// ground at the step's start (1 elsewhere): their velocities change by stick-slip and
/// impacts, not smoothly. On the S-start with implicit Euler at 5e-4 s (whole run) Newton
/// iterations per step go from 3.127, 3.977 and 6.056 (full extrapolation) to 3.048, 3.949
/// and 5.855 at 100, 200 and 400 elements, and over the first 1.5 s at 800 elements from 7.48
/// to 7.22 (conic fallbacks 1 and 2 of 3000 steps); the heavy S-start at 200 elements takes
/// 2.148 instead of 2.134. Other fractions, measured on the ground only at 200 and 400
/// elements with an earlier build (full extrapolation there: 3.972 and 6.106): 0.25 gave
/// 4.015 and 5.882, 0.5 3.927 and 5.870, 0.75 3.932 and 5.949, 0 (no extrapolation on the
/// ground) 4.091 and 5.973; half at every node instead 3.948 and 5.908 (heavy 2.217 against
/// 2.136). The answers stay the same to the solver's tolerance (v_s/v_m to 1e-8).
const ON_GROUND_EXTRAPOLATION: f64 = 0.5;

pub mod adaptive;
pub mod bdf2;
mod damping;
pub mod euler;
pub mod explicit;
mod failure;
mod retry;
pub mod statics;

use crate::band::Assembly;
use crate::contact::{ContactModel, ContactStats};
use crate::energy::self_contact::SelfContact;
use crate::energy::{self, Ctx, Term};
use crate::model::Model;
use crate::newton::{self, Inertia, Newton, Potential};
use crate::rod::dof;
use crate::state::State;

pub use crate::gait::{Actuation, Natural};
pub use failure::{AttemptFailure, StepError};

/// Cumulative statistics of a stepper: its own step counts, Newton's and the contact model's
/// (written to `summary.json` as one flat object).
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct RunStats {
    /// Accepted steps (dynamic) or load increments (static).
    pub steps: usize,
    /// Newton iterations over all accepted steps.
    pub newton_iterations: usize,
    /// Newton iterations of solved steps that the adaptive error control rejected (work not
    /// in `newton_iterations`).
    pub rejected_iterations: usize,
    /// Step halvings (each failed attempt that was retried with h/2).
    pub step_halvings: usize,
    /// Fixed steps that failed with ground contact on the curve after every halving and were
    /// taken again with contact at the nodes (`[solver] ground_points = "curve"`).
    pub ground_point_fallbacks: usize,
    /// Newton's own statistics.
    #[serde(flatten)]
    pub newton: newton::NewtonStats,
    /// The contact model's.
    #[serde(flatten)]
    pub contact: ContactStats,
    /// Accepted steps by their Newton iteration count: entry `k` counts the steps that took
    /// `k` iterations (for diagnostics; not in `summary.json`).
    #[serde(skip)]
    pub iteration_histogram: Vec<usize>,
    /// Self-contact over the accepted steps (`summary.json` writes it as its own block).
    #[serde(skip)]
    pub self_contact: crate::energy::self_contact::SelfContactStats,
}

impl RunStats {
    /// Count one accepted step of `it` Newton iterations.
    fn count_step(&mut self, it: usize) {
        self.steps += 1;
        self.newton_iterations += it;
        if self.iteration_histogram.len() <= it {
            self.iteration_histogram.resize(it + 1, 0);
        }
        self.iteration_histogram[it] += 1;
    }
}

/// What the run loop needs of a time stepper.
pub trait Stepper {
    /// Advance `s` by `h`.
    fn step(&mut self, s: &mut State, h: f64) -> Result<(), StepError>;
    /// Normal contact force on each real node (N), into `out` (length: real nodes).
    fn normal_forces_into(&self, out: &mut [f64]);
    /// Whether the stepper models ground contact.
    fn has_contact(&self) -> bool;
    /// Energies of `s`.
    fn energies(&mut self, s: &State) -> Energies;
    /// Statistics so far.
    fn stats(&self) -> &RunStats;
    /// Normal contact force on each real node (N).
    fn normal_forces(&self, m: &Model) -> Vec<f64> {
        let mut out = vec![0.0; m.real.len()];
        self.normal_forces_into(&mut out);
        out
    }
    /// Advance `s` by one error-controlled step, trying `h` first ([`adaptive`]). Steppers
    /// without an error estimate refuse ([`StepError::NotAdaptive`]).
    fn adaptive_step(
        &mut self,
        s: &mut State,
        _h: f64,
        _control: &adaptive::Controller,
    ) -> Result<adaptive::Adapted, StepError> {
        Err(StepError::NotAdaptive { t: s.t })
    }
}

/// The part of an implicit time integrator that differs between integrators: the step problem
/// is `min w/2 |q - qhat|_M^2 + E(q, t_{n+1}) + friction`, and the new velocity follows from
/// the solution.
pub trait Scheme: Send {
    /// Name in files and messages.
    fn name(&self) -> &'static str;
    /// The predictor `qhat` of a step of size `h` from `s` (fixed coordinates stay put).
    fn predictor(&mut self, m: &Model, s: &State, h: f64, qhat: &mut [f64]);
    /// Whether Newton may start from the velocities extrapolated over the last two steps
    /// (when the contact model asks for it) instead of from the predictor. Default: no.
    fn extrapolated_start(&self) -> bool {
        false
    }
    /// The inertia weight `w` of a step of size `h` (1/s^2).
    fn inertia_weight(&self, h: f64) -> f64;
    /// Coordinates that take an implicit Euler step in this step (weight `1/h^2`; their
    /// `qhat` is `q_n + h v_n`), set by [`Scheme::predictor`]. Default: none.
    fn euler_coordinates(&self) -> &[usize] {
        &[]
    }
    /// The strain origin and effective step of rod damping ([`crate::energy`], "Rod
    /// damping"): `(c_n, c_p, h')` with origin `c_n e(q_n) + c_p e(q_{n-1})`, set by
    /// [`Scheme::predictor`]. Default: implicit Euler's `(1, 0, h)`.
    fn strain_origin(&self, h: f64) -> (f64, f64, f64) {
        (1.0, 0.0, h)
    }
    /// Where contact slip is measured from: the velocity at the solution is
    /// `(x - x_origin) / (w^{-1/2})`, so friction dissipation is `N mu |x - x_origin|`.
    /// `q_prev`: coordinates at the step's start.
    fn slip_origin<'a>(&'a self, q_prev: &'a [f64]) -> &'a [f64] {
        q_prev
    }
    /// Set `s.v` from the solved `s.q`, the step's start `q_prev`, `v_prev` and `h`.
    fn update(&mut self, m: &Model, q_prev: &[f64], v_prev: &[f64], h: f64, s: &mut State);
    /// The explicit predictor `q^P` of the step just solved (called after the solve, before
    /// [`Scheme::update`]), of the same order as the step, into `pred`; returns Milne's
    /// factor `c` (local error `c (q_{n+1} - q^P)`) and the step's order ([`adaptive`]).
    /// Default: implicit Euler's, `q_n + h v_n`, `c = 1/2`, order 1.
    fn error_predictor(
        &self,
        m: &Model,
        q_prev: &[f64],
        v_prev: &[f64],
        h: f64,
        pred: &mut [f64],
    ) -> (f64, usize) {
        euler_predictor(m, q_prev, v_prev, h, pred)
    }
}

/// Implicit Euler's error predictor `q^P = q_n + h v_n` with Milne's factor 1/2, order 1 (see
/// [`adaptive`]).
pub(crate) fn euler_predictor(
    m: &Model,
    q_prev: &[f64],
    v_prev: &[f64],
    h: f64,
    pred: &mut [f64],
) -> (f64, usize) {
    for k in 0..m.ndof {
        pred[k] = q_prev[k] + h * v_prev[k];
    }
    (0.5, 1)
}

/// The scheme of `[solver] integrator` (implicit integrators only).
pub fn scheme_for(kind: crate::problem::IntegratorKind) -> Option<Box<dyn Scheme>> {
    match kind {
        crate::problem::IntegratorKind::ImplicitEuler => Some(Box::new(euler::ImplicitEuler)),
        crate::problem::IntegratorKind::Bdf2 => Some(Box::new(bdf2::Bdf2::default())),
        crate::problem::IntegratorKind::VelocityVerlet => None,
    }
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

/// The loads of a step: rest strains from the actuation at a time, gravity, and the load
/// fraction of static load stepping.
pub(crate) struct Loads {
    actuation: Box<dyn Actuation>,
    pub(crate) kappa0: Vec<[f64; 2]>,
    pub(crate) m0: Vec<f64>,
    pub(crate) load: f64,
}

impl Loads {
    pub(crate) fn new(m: &Model, actuation: Box<dyn Actuation>) -> Self {
        Loads {
            actuation,
            kappa0: vec![[0.0; 2]; m.nodes],
            m0: vec![0.0; m.nodes],
            load: 1.0,
        }
    }

    /// Rest strains at `t`, scaled by the load fraction.
    pub(crate) fn set_time(&mut self, m: &Model, t: f64) {
        self.actuation
            .rest_strains(t, m, &mut self.kappa0, &mut self.m0);
        if self.load != 1.0 {
            for k in self.kappa0.iter_mut() {
                k[0] *= self.load;
                k[1] *= self.load;
            }
            for x in self.m0.iter_mut() {
                *x *= self.load;
            }
        }
    }

    pub(crate) fn gravity(&self, m: &Model) -> [f64; 3] {
        let g = m.gravity;
        [g[0] * self.load, g[1] * self.load, g[2] * self.load]
    }

    pub(crate) fn ctx<'a>(&'a self, m: &'a Model, s: &'a State) -> Ctx<'a> {
        Ctx {
            model: m,
            frames: &s.frames,
            kappa0: &self.kappa0,
            m0: &self.m0,
            gravity: self.gravity(m),
            rest_len: &m.rest_len,
            elastic_scale: 1.0,
        }
    }

    /// Energies of `s` with the rest strains at `s.t`.
    pub(crate) fn energies(&mut self, m: &Model, terms: &[Box<dyn Term>], s: &State) -> Energies {
        self.set_time(m, s.t);
        let ctx = self.ctx(m, s);
        let mut elastic = 0.0;
        let mut gravity = 0.0;
        for t in terms {
            let e = t.eval(&ctx, &s.q, None, false);
            if t.name() == "gravity" {
                gravity += e;
            } else {
                elastic += e;
            }
        }
        let kinetic = s.kinetic_energy(m);
        Energies {
            kinetic,
            elastic,
            gravity,
            total: kinetic + elastic + gravity,
        }
    }
}

/// The implicit dynamic stepper: model, energy terms, loads, scheme, Newton workspace and
/// contact model.
pub struct Integrator<'m> {
    /// The model.
    pub model: &'m Model,
    terms: Vec<Box<dyn Term>>,
    loads: Loads,
    scheme: Box<dyn Scheme>,
    /// Newton's workspace and statistics.
    pub newton: Newton,
    /// Statistics so far (Newton's and the contact model's copied after every attempt).
    stats: RunStats,
    /// The contact model, when the model has a ground.
    pub contact: Option<Box<dyn ContactModel>>,
    qhat: Vec<f64>,
    q_prev: Vec<f64>,
    v_prev: Vec<f64>,
    /// Velocities at the start of the last accepted step and its size (0: none yet).
    v_older: Vec<f64>,
    h_older: f64,
    pred: Vec<f64>,
    /// Normal forces at the start and the end of an adaptive try, and the nodes whose contact
    /// state changed (left out of the error estimate).
    normal_start: Vec<f64>,
    normal_end: Vec<f64>,
    events: Vec<bool>,
    /// The self-contact barrier, when the model has it on.
    pub self_contact: Option<SelfContact>,
    /// The start's move from the last solution, `q - q_n` (scratch).
    start_move: Vec<f64>,
    /// Rod damping, when the model has a damping time.
    damping: Option<damping::RodDamping>,
}

impl<'m> Integrator<'m> {
    /// An implicit stepper for `model` driven by `actuation`, with the problem's time
    /// integrator (`[solver] integrator`: implicit Euler, or BDF2; implicit Euler when the
    /// problem asks for the explicit one) and contact model.
    pub fn new(model: &'m Model, actuation: Box<dyn Actuation>) -> Self {
        let scheme =
            scheme_for(model.solver.integrator).unwrap_or_else(|| Box::new(euler::ImplicitEuler));
        Self::with_scheme(model, actuation, scheme)
    }

    /// A stepper with the given time integration scheme.
    pub fn with_scheme(
        model: &'m Model,
        actuation: Box<dyn Actuation>,
        scheme: Box<dyn Scheme>,
    ) -> Self {
        let n = model.ndof;
        Integrator {
            model,
            terms: energy::rod_terms(),
            loads: Loads::new(model, actuation),
            scheme,
            newton: Newton::new(n),
            stats: RunStats::default(),
            contact: crate::contact::model_for(model),
            qhat: vec![0.0; n],
            q_prev: vec![0.0; n],
            v_prev: vec![0.0; n],
            v_older: vec![0.0; n],
            h_older: 0.0,
            pred: vec![0.0; n],
            normal_start: vec![0.0; model.real.len()],
            normal_end: vec![0.0; model.real.len()],
            events: vec![false; model.real.len()],
            self_contact: SelfContact::of(model),
            start_move: vec![0.0; n],
            damping: damping::RodDamping::of(model),
        }
    }

    /// Replace the contact model (`None`: no contact even with a ground).
    pub fn set_contact(&mut self, contact: Option<Box<dyn ContactModel>>) {
        self.contact = contact;
    }

    /// Statistics so far.
    pub fn stats(&self) -> &RunStats {
        &self.stats
    }

    /// Energies of `s` with the rest strains at `s.t`.
    pub fn energies(&mut self, s: &State) -> Energies {
        self.loads.energies(self.model, &self.terms, s)
    }

    /// One step of size `h`, without retries. Returns the Newton iteration count.
    pub fn try_step(&mut self, s: &mut State, h: f64) -> Result<usize, AttemptFailure> {
        match self.attempt(s, h) {
            Ok(it) => {
                self.commit(s, h);
                Ok(it)
            }
            Err(e) => {
                self.rollback(s);
                Err(e)
            }
        }
    }

    /// Solve a step of size `h` from `s`: on success `s.q` holds the solution and nothing else
    /// has changed yet ([`Self::commit`] or [`Self::rollback`] must follow); on failure call
    /// [`Self::rollback`].
    fn attempt(&mut self, s: &mut State, h: f64) -> Result<usize, AttemptFailure> {
        let r = self.solve(s, h);
        self.stats.newton = self.newton.stats;
        if let Some(c) = &self.contact {
            self.stats.contact.clone_from(c.stats());
        }
        r
    }

    /// The solve of [`Self::attempt`].
    fn solve(&mut self, s: &mut State, h: f64) -> Result<usize, AttemptFailure> {
        let m = self.model;
        self.q_prev.copy_from_slice(&s.q);
        self.v_prev.copy_from_slice(&s.v);
        self.scheme.predictor(m, s, h, &mut self.qhat);
        self.loads.set_time(m, s.t + h);
        if let Some(d) = self.damping.as_mut() {
            let origin = self.scheme.strain_origin(h);
            d.begin_step(m, s, origin, &self.loads.kappa0, &self.loads.m0);
        }
        s.q.copy_from_slice(&self.qhat);
        let extrapolate = self.scheme.extrapolated_start()
            && self
                .contact
                .as_ref()
                .is_some_and(|c| c.extrapolated_start());
        if extrapolate && self.h_older > 0.0 {
            // q_n + h (v_n + h (v_n - v_{n-1}) / h_{n-1}): the velocity extrapolated linearly,
            // by half on the ground (ON_GROUND_EXTRAPOLATION).
            let r = h / self.h_older;
            let (q_prev, v_prev, v_older) = (&self.q_prev, &self.v_prev, &self.v_older);
            let mut start_at = |k: usize, r: f64| {
                if !m.fixed[k] {
                    s.q[k] = q_prev[k] + h * (v_prev[k] + r * (v_prev[k] - v_older[k]));
                }
            };
            for k in 0..m.ndof {
                start_at(k, r);
            }
            for i in m.real.clone().filter(|&i| m.on_ground(q_prev, i)) {
                for k in dof::node(i)..dof::node(i) + 3 {
                    start_at(k, ON_GROUND_EXTRAPOLATION * r);
                }
            }
        }
        if let Some(c) = self.contact.as_mut() {
            let origin = self.scheme.slip_origin(&self.q_prev);
            c.begin_step(m, &self.q_prev, origin, &self.v_prev, h, &mut s.q);
        }
        if let Some(sc) = &self.self_contact {
            // The start drawn back toward the last solution where the way there could cross a
            // pair (both ends lie above the ground, so every point between does).
            for k in 0..m.ndof {
                self.start_move[k] = s.q[k] - self.q_prev[k];
            }
            let alpha = sc.max_step(&self.q_prev, &self.start_move);
            if alpha < 1.0 {
                for k in 0..m.ndof {
                    s.q[k] = self.q_prev[k] + alpha * self.start_move[k];
                }
            }
        }
        let (kappa0, m0, rest_len, elastic_scale) = match &self.damping {
            Some(d) => (&d.kappa0, &d.m0, &d.rest_len, d.scale),
            None => (&self.loads.kappa0, &self.loads.m0, &m.rest_len, 1.0),
        };
        let mut obj = Potential {
            model: m,
            terms: &self.terms,
            frames: &s.frames,
            kappa0,
            m0,
            gravity: self.loads.gravity(m),
            rest_len,
            elastic_scale,
            inertia: Some(Inertia {
                weight: self.scheme.inertia_weight(h),
                qhat: &self.qhat,
                euler: self.scheme.euler_coordinates(),
                euler_weight: 1.0 / (h * h),
            }),
            self_contact: self.self_contact.as_ref(),
        };
        let q = &mut s.q;
        Ok(match self.contact.as_mut() {
            Some(c) => c.solve(&mut self.newton, &obj, q)?,
            None => self
                .newton
                .minimize(m, &mut obj, q, &m.fixed, m.max_iterations)?,
        })
    }

    /// Accept the solved step of [`Self::attempt`]: velocities, frames, time, contact state and
    /// the scheme's history.
    fn commit(&mut self, s: &mut State, h: f64) {
        let m = self.model;
        if let Some(sc) = &self.self_contact {
            self.stats.self_contact.count(&sc.measure(&s.q), m.diameter);
        }
        if let Some(c) = self.contact.as_mut() {
            c.accept(m, &s.q);
        }
        if let Some(d) = self.damping.as_mut() {
            d.commit();
        }
        self.scheme.update(m, &self.q_prev, &self.v_prev, h, s);
        self.v_older.copy_from_slice(&self.v_prev);
        self.h_older = h;
        s.update_frames();
        s.t += h;
    }

    /// Undo [`Self::attempt`]: the state and the contact model as before it.
    fn rollback(&mut self, s: &mut State) {
        s.q.copy_from_slice(&self.q_prev);
        s.v.copy_from_slice(&self.v_prev);
        if let Some(c) = self.contact.as_mut() {
            c.reject();
        }
    }

    /// Gradient and Hessian of the rod energy at `q` with the frames of `s` and rest strains
    /// at `s.t` (for tests and diagnostics).
    pub fn energy_derivatives(&mut self, s: &State, q: &[f64], project: bool) -> (f64, Assembly) {
        self.loads.set_time(self.model, s.t);
        let mut asm = Assembly::new(self.model.ndof);
        let ctx = self.loads.ctx(self.model, s);
        let e = energy::total(&self.terms, &ctx, q, Some(&mut asm), project);
        (e, asm)
    }

    /// Normal force on every real node (N; zero without ground or contact).
    pub fn normal_forces(&self) -> Vec<f64> {
        Stepper::normal_forces(self, self.model)
    }

    /// Rod energy at `q` with the frames of `s` and rest strains at `s.t`.
    pub fn energy_at(&mut self, s: &State, q: &[f64]) -> f64 {
        self.loads.set_time(self.model, s.t);
        let ctx = self.loads.ctx(self.model, s);
        energy::total(&self.terms, &ctx, q, None, false)
    }
}

impl Stepper for Integrator<'_> {
    fn step(&mut self, s: &mut State, h: f64) -> Result<(), StepError> {
        Integrator::step(self, s, h)
    }
    fn adaptive_step(
        &mut self,
        s: &mut State,
        h: f64,
        control: &adaptive::Controller,
    ) -> Result<adaptive::Adapted, StepError> {
        Integrator::adaptive_step(self, s, h, control)
    }
    fn normal_forces_into(&self, out: &mut [f64]) {
        out.fill(0.0);
        if let Some(c) = &self.contact {
            c.normal_forces(self.model, out);
        }
    }
    fn has_contact(&self) -> bool {
        self.contact.is_some()
    }
    fn energies(&mut self, s: &State) -> Energies {
        Integrator::energies(self, s)
    }
    fn stats(&self) -> &RunStats {
        &self.stats
    }
}
