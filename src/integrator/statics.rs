//! Static equilibrium: `min_q E(q)` at a load fraction (gravity and natural strains scaled),
//! by Newton's method ([`crate::newton`]) with the reference frames re-based after every
//! accepted iterate. The run loop ramps the load over `[time] load_steps` increments.

use super::AttemptFailure;
use super::{Energies, Loads, RunStats, StepError};
use crate::band::Assembly;
use crate::energy::{self, Term};
use crate::model::Model;
use crate::newton::{Newton, Objective, Potential};
use crate::state::State;

/// The static stepper.
pub struct Static<'m> {
    /// The model.
    pub model: &'m Model,
    terms: Vec<Box<dyn Term>>,
    loads: Loads,
    newton: Newton,
    stats: RunStats,
}

/// The rod energy with the frames of a state that moves with the iterate.
struct Equilibrium<'a> {
    model: &'a Model,
    terms: &'a [Box<dyn Term>],
    loads: &'a Loads,
    state: &'a mut State,
}

impl Equilibrium<'_> {
    fn potential(&self) -> Potential<'_> {
        Potential {
            model: self.model,
            terms: self.terms,
            frames: &self.state.frames,
            kappa0: &self.loads.kappa0,
            m0: &self.loads.m0,
            gravity: self.loads.gravity(self.model),
            rest_len: &self.model.rest_len,
            elastic_scale: 1.0,
            inertia: None,
            self_contact: None,
        }
    }
}

impl Objective for Equilibrium<'_> {
    fn value(&self, q: &[f64]) -> f64 {
        self.potential().value(q)
    }
    fn assemble(&self, q: &[f64], asm: &mut Assembly, project: bool) -> f64 {
        self.potential().assemble(q, asm, project)
    }
    fn accepted(&mut self, q: &[f64]) {
        self.state.q.copy_from_slice(q);
        self.state.update_frames();
    }
}

impl<'m> Static<'m> {
    /// A static stepper for `model` with the rest strains of `actuation` at `t = 0`.
    pub fn new(model: &'m Model, actuation: Box<dyn super::Actuation>) -> Self {
        Static {
            model,
            terms: energy::rod_terms(),
            loads: Loads::new(model, actuation),
            newton: Newton::new(model.ndof),
            stats: RunStats::default(),
        }
    }

    /// Statistics so far.
    pub fn stats(&self) -> &RunStats {
        &self.stats
    }

    /// Static equilibrium at load fraction `load`, from `s`. Returns the Newton iterations.
    pub fn solve(&mut self, s: &mut State, load: f64) -> Result<usize, StepError> {
        let m = self.model;
        self.loads.load = load;
        self.loads.set_time(m, s.t);
        let mut q = s.q.clone();
        let r = {
            let mut obj = Equilibrium {
                model: m,
                terms: &self.terms,
                loads: &self.loads,
                state: s,
            };
            self.newton
                .minimize(m, &mut obj, &mut q, &m.fixed, m.max_iterations)
        };
        self.loads.load = 1.0;
        self.stats.newton = self.newton.stats;
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
                reason: AttemptFailure::Static {
                    load,
                    inner: Box::new(reason.into()),
                },
            }),
        }
    }

    /// Energies of `s` at full load.
    pub fn energies(&mut self, s: &State) -> Energies {
        self.loads.energies(self.model, &self.terms, s)
    }
}
