//! Explicit symplectic reference integrator (MODEL section 8): velocity Verlet on the same
//! discrete rod as the implicit step — the same coordinates `q = (x, theta)`, the same lumped
//! masses `rho A l_i` and twist inertias `rho J l_j` ([`Model::mass`]), the same energy terms
//! (stretch, bend, twist, gravity) and the same time-parallel reference frames:
//!
//! ```text
//! v_{n+1/2} = v_n + h/2 M^{-1} F(q_n, t_n)
//! q_{n+1}   = q_n + h v_{n+1/2}                  (then frames transported to q_{n+1})
//! v_{n+1}   = v_{n+1/2} + h/2 M^{-1} F(q_{n+1}, t_{n+1}),      F = -dE/dq
//! ```
//!
//! Why velocity Verlet and not symplectic Euler: both are symplectic and cost one force
//! evaluation per step (the force at the end of a step is reused at the start of the next),
//! but Verlet is second order and time-reversible, so its energy error is bounded and shrinks
//! like `h^2` (symplectic Euler's like `h`), and its positions and velocities live at the same
//! instants, so `E(q_n, v_n)` is the energy of the run. It is the Stormer-Verlet family that
//! the peer simulators use (PyElastica's default `PositionVerlet` is the same method with the
//! half steps on positions instead of velocities). The velocity form evaluates the force only
//! at full steps, right after the reference frames have been transported to `q_{n+1}`, so the
//! gradient is always taken with frames at the current tangents (the DER gradient of Bergou et
//! al. 2010) and the frames are updated once per step.
//!
//! Forces come from a gradient-only path through the same energy-term list as the implicit
//! step ([`crate::energy::rod_terms`], [`Term::gradient`]): stretching and gravity assemble
//! into a scratch assembly (their Hessians are a few closed-form 3x3 blocks per edge,
//! negligible); bending and twist take their gradient from the stencil derivatives
//! ([`crate::energy::stencil`]): the closed-form DER gradient (Bergou et al. 2010), exact
//! when the reference frames sit at the current tangents, as they do where the forces are
//! evaluated; anywhere else (a state whose frames are stale) first-order dual numbers
//! ([`num_dual::gradient`]). Both are checked against the implicit path's gradient and finite
//! differences in `tests/explicit.rs`. No Hessian, no eigenvalue projection, no linear solve.
//!
//! Clamped coordinates ([`Model::fixed`]) are held, as in the implicit step: their velocity
//! is zero and their force ignored. Ground contact is not supported: explicit peers model it
//! with penalty springs, which would make this a different model, so a model with a ground is
//! rejected ([`Unsupported`]); so is static mode.
//!
//! Instability is an error, never silent: after every step the coordinates, velocities and
//! energies must be finite and the energy error
//! `|E(t) - E(0) - W_muscle(t)|` (`W_muscle`: the work of the time-dependent rest strains,
//! `integral dE/dt|_q dt`, by the trapezoid rule per step:
//! `[E(q_n, t_{n+1}) - E(q_n, t_n) + E(q_{n+1}, t_{n+1}) - E(q_{n+1}, t_n)] / 2`, two extra
//! energy evaluations per step while muscles act) must stay below
//! [`BLOWUP_FACTOR`] times the energy scale
//! `KE(0) + E_elastic(0) + m g L + B/L + max_t E_rest(t)` (`m g L`: the weight over the rod's
//! length; `B/L`: a floor so a rod at rest still has a scale; `E_rest`: the elastic energy of
//! the straight rod against the muscles' rest strains). A stable Verlet run keeps this error
//! orders of magnitude below the scale; past the stability limit it grows exponentially, so
//! the exact factor only moves the reported instant by a few steps. The failed step is undone
//! and reported as [`StepError::Unstable`] with its start time and step.

use super::{Actuation, Energies, RunStats, StepError};
use crate::band::Assembly;
use crate::energy::local::intrinsic;
use crate::energy::stencil::frames_current;
use crate::energy::{Ctx, Term};
use crate::model::Model;
use crate::problem::Mode;
use crate::state::State;
use std::time::Instant;

/// Energy error, in units of the run's energy scale (see the module doc), beyond which a run
/// is declared unstable.
pub const BLOWUP_FACTOR: f64 = 1.0;

/// A model the explicit integrator does not handle.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Unsupported {
    /// The model has a ground (contact would need penalty springs: a different model).
    #[error("the explicit integrator has no ground contact: use the implicit integrator for problems with a [ground]")]
    Ground,
    /// Static mode has no time stepping.
    #[error("the explicit integrator only steps in time: static mode needs the implicit solver")]
    Static,
}

/// Rod energy split as the energy monitor needs it.
#[derive(Clone, Copy, Debug, Default)]
struct Potential {
    elastic: f64,
    gravity: f64,
}

impl Potential {
    fn total(&self) -> f64 {
        self.elastic + self.gravity
    }
}

/// The velocity Verlet stepper: model, actuation, force cache and energy monitor.
pub struct Explicit<'m> {
    /// The model.
    pub model: &'m Model,
    actuation: Box<dyn Actuation>,
    kappa0: Vec<[f64; 2]>,
    m0: Vec<f64>,
    kappa0_prev: Vec<[f64; 2]>,
    m0_prev: Vec<f64>,
    terms: Vec<Box<dyn Term>>,
    scratch: Assembly,
    /// `dE/dq` at (`cached_q`, `cached_t`).
    grad: Vec<f64>,
    potential: Potential,
    cached_q: Vec<f64>,
    cached_t: f64,
    have_grad: bool,
    prev: Option<State>,
    monitor: Option<Monitor>,
    /// Statistics (`steps`; `assembly_s` is the time in force evaluations).
    pub stats: RunStats,
    /// Stencil gradients computed in closed form and by dual numbers (stale frames).
    pub stencil_paths: [usize; 2],
    /// The self-contact's broad phase and distances (this integrator applies no barrier: it
    /// stops when a pair comes within the activation gap).
    self_contact: Option<crate::energy::self_contact::SelfContact>,
}

/// Energy bookkeeping of a run.
#[derive(Clone, Copy, Debug)]
struct Monitor {
    e0: f64,
    base_scale: f64,
    rest_max: f64,
    work: f64,
    max_error: f64,
}

impl Monitor {
    fn scale(&self) -> f64 {
        self.base_scale + self.rest_max
    }
}

impl<'m> Explicit<'m> {
    /// A stepper for `model` driven by `actuation`; models with a ground or in static mode
    /// are rejected.
    pub fn new(model: &'m Model, actuation: Box<dyn Actuation>) -> Result<Self, Unsupported> {
        if model.ground.is_some() {
            return Err(Unsupported::Ground);
        }
        if model.mode == Mode::Static {
            return Err(Unsupported::Static);
        }
        let n = model.ndof;
        Ok(Explicit {
            model,
            actuation,
            kappa0: vec![[0.0; 2]; model.nodes],
            m0: vec![0.0; model.nodes],
            kappa0_prev: vec![[0.0; 2]; model.nodes],
            m0_prev: vec![0.0; model.nodes],
            terms: crate::energy::rod_terms(),
            scratch: Assembly::new(n),
            grad: vec![0.0; n],
            potential: Potential::default(),
            cached_q: vec![0.0; n],
            cached_t: f64::NAN,
            have_grad: false,
            prev: None,
            monitor: None,
            stats: RunStats::default(),
            stencil_paths: [0; 2],
            self_contact: crate::energy::self_contact::SelfContact::of(model),
        })
    }

    fn set_time(&mut self, t: f64) {
        self.actuation
            .rest_strains(t, self.model, &mut self.kappa0, &mut self.m0);
    }

    /// Elastic energy of the straight rod against the current rest strains (J).
    fn rest_energy(&self) -> f64 {
        let m = self.model;
        (1..m.nodes - 1)
            .filter(|&i| m.voronoi[i] > 0.0)
            .map(|i| {
                let l = m.voronoi[i];
                let k = self.kappa0[i];
                m.bend / (2.0 * l) * (k[0] * k[0] + k[1] * k[1])
                    + m.twist / (2.0 * l) * self.m0[i] * self.m0[i]
            })
            .sum()
    }

    /// Rod energy of `q` with the frames of `s` and the current rest strains; with
    /// `grad`, also `dE/dq` (overwritten).
    /// `previous`: with the rest strains saved by the last step for its start time.
    fn evaluate(
        &mut self,
        s: &State,
        q: &[f64],
        grad: Option<&mut [f64]>,
        previous: bool,
    ) -> Potential {
        let m = self.model;
        let (kappa0, m0) = if previous {
            (&self.kappa0_prev, &self.m0_prev)
        } else {
            (&self.kappa0, &self.m0)
        };
        let ctx = Ctx {
            model: m,
            frames: &s.frames,
            kappa0,
            m0,
            gravity: m.gravity,
            rest_len: &m.rest_len,
            elastic_scale: 1.0,
        };
        let mut p = Potential::default();
        let mut add = |name: &str, e: f64| {
            if name == "gravity" {
                p.gravity += e;
            } else {
                p.elastic += e;
            }
        };
        let Some(grad) = grad else {
            for t in &self.terms {
                add(t.name(), t.eval(&ctx, q, None, false));
            }
            return p;
        };
        for i in 1..m.nodes - 1 {
            let current = frames_current(&ctx.frames[i - 1], &intrinsic(q, i));
            self.stencil_paths[usize::from(!current)] += 1;
        }
        grad.fill(0.0);
        for t in &self.terms {
            add(t.name(), t.gradient(&ctx, q, grad, &mut self.scratch));
        }
        p
    }

    /// Make `self.grad` the energy gradient at `s` (rest strains at `s.t`).
    fn ensure_gradient(&mut self, s: &State) {
        if self.have_grad && self.cached_t == s.t && self.cached_q == s.q {
            return;
        }
        let t0 = Instant::now();
        self.set_time(s.t);
        let mut grad = std::mem::take(&mut self.grad);
        self.potential = self.evaluate(s, &s.q, Some(&mut grad), false);
        self.grad = grad;
        self.cached_q.copy_from_slice(&s.q);
        self.cached_t = s.t;
        self.have_grad = true;
        self.stats.newton.assembly_s += t0.elapsed().as_secs_f64();
    }

    /// Energy gradient `dE/dq` at `s` (rest strains at `s.t`), by the gradient-only path.
    pub fn gradient(&mut self, s: &State) -> &[f64] {
        self.ensure_gradient(s);
        &self.grad
    }

    /// Rod energy (elastic plus gravity) at `s` as computed with the forces (J).
    pub fn potential(&mut self, s: &State) -> f64 {
        self.ensure_gradient(s);
        self.potential.total()
    }

    /// Energies of `s` with the rest strains at `s.t`.
    pub fn energies(&mut self, s: &State) -> Energies {
        self.set_time(s.t);
        let p = self.evaluate(s, &s.q, None, false);
        let kinetic = s.kinetic_energy(self.model);
        Energies {
            kinetic,
            elastic: p.elastic,
            gravity: p.gravity,
            total: kinetic + p.total(),
        }
    }

    /// Largest energy error `|E(t) - E(0) - W_muscle(t)|` (J) over the steps so far.
    pub fn max_energy_error(&self) -> f64 {
        self.monitor.map_or(0.0, |mo| mo.max_error)
    }

    /// The energy scale the blow-up threshold is relative to (J); 0 before the first step.
    pub fn energy_scale(&self) -> f64 {
        self.monitor.map_or(0.0, |mo| mo.scale())
    }

    fn start_monitor(&mut self, s: &State) {
        self.ensure_gradient(s);
        let m = self.model;
        let kinetic = s.kinetic_energy(m);
        let g = crate::rod::vec3::f::norm(m.gravity);
        let base_scale = kinetic
            + self.potential.elastic.abs()
            + m.total_mass() * g * m.length
            + m.bend / m.length;
        self.set_time(s.t);
        self.monitor = Some(Monitor {
            e0: kinetic + self.potential.total(),
            base_scale,
            rest_max: self.rest_energy(),
            work: 0.0,
            max_error: 0.0,
        });
    }

    /// One velocity Verlet step of size `h`. On instability the state is restored to the
    /// start of the step and [`StepError::Unstable`] names that time and `h`.
    pub fn step(&mut self, s: &mut State, h: f64) -> Result<(), StepError> {
        if self.monitor.is_none() {
            self.start_monitor(s);
        }
        self.ensure_gradient(s);
        match &mut self.prev {
            Some(p) => copy_state(p, s),
            None => self.prev = Some(s.clone()),
        }
        let m = self.model;
        let t_start = s.t;
        let potential_start = self.potential.total();
        for k in 0..m.ndof {
            if m.fixed[k] {
                s.v[k] = 0.0;
                continue;
            }
            s.v[k] -= 0.5 * h * self.grad[k] / m.mass[k];
            s.q[k] += h * s.v[k];
        }
        s.update_frames();
        s.t += h;
        self.ensure_gradient(s);
        // Work of the rest strains over the step (trapezoid in q): the change of E from t_n
        // to t_{n+1} at fixed q_n and at fixed q_{n+1}, averaged.
        self.actuation
            .rest_strains(t_start, m, &mut self.kappa0_prev, &mut self.m0_prev);
        let mut work = 0.0;
        if self.kappa0 != self.kappa0_prev || self.m0 != self.m0_prev {
            let new_before = self.evaluate(s, &s.q, None, true).total();
            let prev = self.prev.take().expect("saved state");
            let old_after = self.evaluate(&prev, &prev.q, None, false).total();
            self.prev = Some(prev);
            work = 0.5 * ((old_after - potential_start) + (self.potential.total() - new_before));
        }
        for k in 0..m.ndof {
            if !m.fixed[k] {
                s.v[k] -= 0.5 * h * self.grad[k] / m.mass[k];
            }
        }
        self.stats.steps += 1;
        let kinetic = s.kinetic_energy(m);
        let rest = self.rest_energy();
        let mo = self.monitor.as_mut().expect("monitor");
        mo.work += work;
        mo.rest_max = mo.rest_max.max(rest);
        let err = (kinetic + self.potential.total() - mo.e0 - mo.work).abs();
        let scale = mo.scale();
        let finite = err.is_finite()
            && s.q.iter().all(|x| x.is_finite())
            && s.v.iter().all(|x| x.is_finite());
        let reason = if !finite {
            Some("non-finite coordinates, velocities or energy".to_string())
        } else if err > BLOWUP_FACTOR * scale {
            Some(format!(
                "energy error {err:.3e} J exceeds {BLOWUP_FACTOR} x the energy scale {scale:.3e} J"
            ))
        } else {
            mo.max_error = mo.max_error.max(err);
            None
        };
        match reason {
            None => {
                if let Some(sc) = &self.self_contact {
                    let d = sc.measure(&s.q).closest;
                    if d < m.diameter + sc.activation() {
                        return Err(StepError::SelfContact {
                            t: s.t,
                            distance_over_a: d / m.diameter,
                        });
                    }
                }
                Ok(())
            }
            Some(reason) => {
                copy_state(s, self.prev.as_ref().expect("saved state"));
                self.have_grad = false;
                self.stats.steps -= 1;
                Err(StepError::Unstable {
                    t: s.t,
                    dt: h,
                    reason,
                })
            }
        }
    }
}

/// Copy `src` into `dst` without allocating (same model).
fn copy_state(dst: &mut State, src: &State) {
    dst.t = src.t;
    dst.q.copy_from_slice(&src.q);
    dst.v.copy_from_slice(&src.v);
    dst.tangent.copy_from_slice(&src.tangent);
    dst.a1.copy_from_slice(&src.a1);
    dst.frames.copy_from_slice(&src.frames);
}

impl super::Stepper for Explicit<'_> {
    fn step(&mut self, s: &mut State, h: f64) -> Result<(), StepError> {
        Explicit::step(self, s, h)
    }
    fn normal_forces_into(&self, out: &mut [f64]) {
        out.fill(0.0);
    }
    fn has_contact(&self) -> bool {
        false
    }
    fn energies(&mut self, s: &State) -> Energies {
        Explicit::energies(self, s)
    }
    fn stats(&self) -> &RunStats {
        &self.stats
    }
}
