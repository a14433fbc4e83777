//! The run loop: steps a [`Model`] from its initial state to the end of the run (dynamic) or
//! through its load increments (static), records frames at the output interval and keeps
//! everything computed so far when a step fails.

use crate::contact::Contacts;
use crate::integrator::{Actuation, Energies, Integrator, Stats, StepError};
use crate::model::Model;
use crate::problem::Mode;
use crate::rod::dof;
use crate::state::State;
use std::time::Instant;

/// One recorded instant of the real rod.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Time (s); static mode: load fraction.
    pub t: f64,
    /// Real node positions (m), head first.
    pub x: Vec<[f64; 3]>,
    /// Real edge twist angles (rad).
    pub theta: Vec<f64>,
    /// Real node velocities (m/s).
    pub v: Vec<[f64; 3]>,
    /// Normal contact force on each real node (N).
    pub normal: Vec<f64>,
    /// Material director `d1` of each real edge.
    pub d1: Vec<[f64; 3]>,
}

impl Frame {
    /// Record the real rod of `s`.
    pub fn of(m: &Model, s: &State, t: f64, normal: Vec<f64>) -> Self {
        Frame {
            t,
            x: m.real.clone().map(|i| s.node(i)).collect(),
            theta: m.real_edges().map(|j| s.q[dof::edge(j)]).collect(),
            v: m.real.clone().map(|i| s.node_velocity(i)).collect(),
            normal,
            d1: m.real_edges().map(|j| s.directors(j).0).collect(),
        }
    }
}

/// Everything a run produced, finished or not.
pub struct Outcome {
    /// Final (or last good) state.
    pub state: State,
    /// Recorded frames.
    pub frames: Vec<Frame>,
    /// Solver statistics.
    pub stats: Stats,
    /// Wall-clock time of the integration (s).
    pub wall_time_s: f64,
    /// Largest |strain| over all accepted steps.
    pub max_strain: f64,
    /// Energies of the final state.
    pub energies: Energies,
    /// The failure that stopped the run, if any.
    pub error: Option<StepError>,
    /// Largest penetration of a node below `z = a/2` over all accepted steps (m).
    pub max_penetration: f64,
    /// Largest slip speed of a node in contact over all accepted steps (m/s).
    pub slip_speed_max: f64,
}

/// Progress callback: fraction done in [0, 1].
pub type Progress<'a> = &'a mut dyn FnMut(f64);

/// What the run loop needs of an integrator (the implicit [`Integrator`] and the explicit
/// [`crate::integrator::explicit::Explicit`]).
pub trait Stepper {
    /// Advance `s` by `h`.
    fn step(&mut self, s: &mut State, h: f64) -> Result<(), StepError>;
    /// Normal contact force on each real node (N).
    fn normal_forces(&self) -> Vec<f64>;
    /// Energies of `s`.
    fn energies(&mut self, s: &State) -> Energies;
    /// Statistics so far.
    fn stats(&self) -> &Stats;
    /// Ground contacts, if the integrator has any.
    fn contacts(&self) -> Option<&Contacts> {
        None
    }
}

impl Stepper for Integrator<'_> {
    fn step(&mut self, s: &mut State, h: f64) -> Result<(), StepError> {
        Integrator::step(self, s, h)
    }
    fn normal_forces(&self) -> Vec<f64> {
        Integrator::normal_forces(self)
    }
    fn energies(&mut self, s: &State) -> Energies {
        Integrator::energies(self, s)
    }
    fn stats(&self) -> &Stats {
        &self.stats
    }
    fn contacts(&self) -> Option<&Contacts> {
        self.contacts.as_ref()
    }
}

/// Run a model to the end (or to the first unrecoverable failure) with the implicit integrator.
pub fn run(
    model: &Model,
    actuation: Box<dyn Actuation>,
    progress: Progress,
    on_step: &mut dyn FnMut(&State),
) -> Outcome {
    let start = Instant::now();
    let mut integ = Integrator::new(model, actuation);
    match model.mode {
        Mode::Dynamic => drive(model, &mut integ, start, progress, on_step),
        Mode::Static => {
            let mut s = State::initial(model);
            let mut frames = vec![Frame::of(model, &s, 0.0, integ.normal_forces())];
            let mut max_strain = s.max_strain(model);
            let mut error = None;
            let n = model.load_steps;
            for k in 1..=n {
                let load = k as f64 / n as f64;
                if let Err(e) = integ.solve_static(&mut s, load) {
                    error = Some(e);
                    break;
                }
                max_strain = max_strain.max(s.max_strain(model));
                on_step(&s);
                frames.push(Frame::of(model, &s, load, integ.normal_forces()));
                progress(load);
            }
            let energies = integ.energies(&s);
            Outcome {
                state: s,
                frames,
                stats: integ.stats.clone(),
                wall_time_s: start.elapsed().as_secs_f64(),
                max_strain,
                energies,
                error,
                max_penetration: 0.0,
                slip_speed_max: 0.0,
            }
        }
    }
}

/// The time-stepping loop shared by both integrators: steps to the end of the run (or the first
/// unrecoverable failure), records frames at the output interval and watches the contacts.
pub fn drive(
    model: &Model,
    integ: &mut dyn Stepper,
    start: Instant,
    progress: Progress,
    on_step: &mut dyn FnMut(&State),
) -> Outcome {
    let mut s = State::initial(model);
    let mut frames = vec![Frame::of(model, &s, 0.0, integ.normal_forces())];
    let mut max_strain = s.max_strain(model);
    let mut error = None;
    let mut max_penetration: f64 = 0.0;
    let mut slip_speed_max: f64 = 0.0;
    let n_steps = (model.duration / model.dt).round().max(1.0) as usize;
    let every = ((model.output_interval / model.dt).round() as usize).max(1);
    for k in 1..=n_steps {
        if let Err(e) = integ.step(&mut s, model.dt) {
            error = Some(e);
            break;
        }
        max_strain = max_strain.max(s.max_strain(model));
        if let Some(ct) = integ.contacts() {
            for i in model.real.clone() {
                max_penetration = max_penetration.max(0.5 * model.diameter - s.node(i)[2]);
            }
            for (&i, &n) in ct.nodes.iter().zip(&ct.normal) {
                if n > 0.0 {
                    let v = s.node_velocity(i);
                    slip_speed_max = slip_speed_max.max((v[0] * v[0] + v[1] * v[1]).sqrt());
                }
            }
        }
        on_step(&s);
        if k % every == 0 || k == n_steps {
            frames.push(Frame::of(model, &s, s.t, integ.normal_forces()));
        }
        progress(k as f64 / n_steps as f64);
    }
    let energies = integ.energies(&s);
    Outcome {
        state: s,
        frames,
        stats: integ.stats().clone(),
        wall_time_s: start.elapsed().as_secs_f64(),
        max_strain,
        energies,
        error,
        max_penetration,
        slip_speed_max,
    }
}

/// Run a problem's model driven by its own gait ([`crate::gait::Muscles`]) with the integrator
/// the problem asks for (`[solver] integrator`).
pub fn run_gait(
    model: &Model,
    integrator: crate::problem::IntegratorKind,
    progress: Progress,
    on_step: &mut dyn FnMut(&State),
) -> Result<Outcome, crate::integrator::explicit::Unsupported> {
    let muscles = Box::new(crate::gait::Muscles {
        gait: model.gait.clone(),
    });
    match integrator {
        crate::problem::IntegratorKind::Implicit => Ok(run(model, muscles, progress, on_step)),
        crate::problem::IntegratorKind::Explicit => {
            crate::integrator::explicit::run(model, muscles, progress, on_step)
        }
    }
}
