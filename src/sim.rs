//! The run loop: steps a [`Model`] from its initial state to the end of the run (dynamic) or
//! through its load increments (static), records frames at the output interval and keeps
//! everything computed so far when a step fails. Every time stepper ([`Stepper`]: implicit,
//! explicit) runs through [`drive`]; the charts run it with their own [`Schedule`].

use crate::integrator::explicit::{Explicit, Unsupported};
use crate::integrator::statics::Static;
use crate::integrator::{Actuation, Energies, Integrator, Stats, StepError, Stepper};
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

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum RunStatus {
    /// Every step accepted to the end.
    Completed,
    /// Stopped by a failed step ([`Outcome::error`]).
    Failed,
}

impl Outcome {
    /// How the run ended.
    pub fn status(&self) -> RunStatus {
        if self.error.is_some() {
            RunStatus::Failed
        } else {
            RunStatus::Completed
        }
    }
}

/// Progress callback: fraction done in [0, 1].
pub type Progress<'a> = &'a mut dyn FnMut(f64);

/// The steps of a dynamic run: `steps` steps of `dt`, the last one of `last` (so the run ends
/// exactly at its duration), a frame recorded every `every` steps (and after the last).
#[derive(Clone, Copy, Debug)]
pub struct Schedule {
    /// Step (s).
    pub dt: f64,
    /// Number of steps.
    pub steps: usize,
    /// Size of the last step (s), `dt` unless the duration is not a whole number of steps.
    pub last: f64,
    /// Steps between recorded frames.
    pub every: usize,
}

impl Schedule {
    /// The model's own schedule: steps of `dt` to the duration, the last step shortened to
    /// land on it when the duration is not a whole number of steps (to 1e-9 of a step);
    /// frames at the output interval.
    pub fn of(model: &Model) -> Self {
        let (dt, duration) = (model.dt, model.duration);
        let whole = (duration / dt).round();
        let (steps, last) = if (whole * dt - duration).abs() <= 1e-9 * dt {
            (whole.max(1.0) as usize, dt)
        } else {
            let n = (duration / dt).ceil().max(1.0);
            (n as usize, duration - (n - 1.0) * dt)
        };
        Schedule {
            dt,
            steps,
            last,
            every: ((model.output_interval / dt).round() as usize).max(1),
        }
    }

    /// `steps` steps of `dt`, recording only the first and last frames.
    pub fn fixed(dt: f64, steps: usize) -> Self {
        Schedule {
            dt,
            steps,
            last: dt,
            every: steps.max(1),
        }
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
    match model.mode {
        Mode::Dynamic => {
            let mut integ = Integrator::new(model, actuation);
            drive(
                model,
                &mut integ,
                Schedule::of(model),
                start,
                progress,
                on_step,
            )
        }
        Mode::Static => run_static(model, actuation, start, progress, on_step),
    }
}

/// Static mode: the load ramped over `load_steps` increments, one frame per increment.
fn run_static(
    model: &Model,
    actuation: Box<dyn Actuation>,
    start: Instant,
    progress: Progress,
    on_step: &mut dyn FnMut(&State),
) -> Outcome {
    let mut integ = Static::new(model, actuation);
    let mut s = State::initial(model);
    let zeros = vec![0.0; model.real.len()];
    let mut frames = vec![Frame::of(model, &s, 0.0, zeros.clone())];
    let mut max_strain = s.max_strain(model);
    let mut error = None;
    let n = model.load_steps;
    for k in 1..=n {
        let load = k as f64 / n as f64;
        if let Err(e) = integ.solve(&mut s, load) {
            error = Some(e);
            break;
        }
        max_strain = max_strain.max(s.max_strain(model));
        on_step(&s);
        frames.push(Frame::of(model, &s, load, zeros.clone()));
        progress(load);
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
        max_penetration: 0.0,
        slip_speed_max: 0.0,
    }
}

/// The time-stepping loop shared by every stepper: steps by `schedule` (or to the first
/// unrecoverable failure), records frames and watches the contacts.
pub fn drive(
    model: &Model,
    integ: &mut dyn Stepper,
    schedule: Schedule,
    start: Instant,
    progress: Progress,
    on_step: &mut dyn FnMut(&State),
) -> Outcome {
    let mut s = State::initial(model);
    let mut normal = vec![0.0; model.real.len()];
    integ.normal_forces_into(&mut normal);
    let mut frames = vec![Frame::of(model, &s, 0.0, normal.clone())];
    let mut max_strain = s.max_strain(model);
    let mut error = None;
    let mut max_penetration: f64 = 0.0;
    let mut slip_speed_max: f64 = 0.0;
    let n_steps = schedule.steps;
    for k in 1..=n_steps {
        let h = if k == n_steps {
            schedule.last
        } else {
            schedule.dt
        };
        if let Err(e) = integ.step(&mut s, h) {
            error = Some(e);
            break;
        }
        max_strain = max_strain.max(s.max_strain(model));
        integ.normal_forces_into(&mut normal);
        if integ.has_contact() {
            for (r, i) in model.real.clone().enumerate() {
                max_penetration = max_penetration.max(0.5 * model.diameter - s.node(i)[2]);
                if model.in_contact(normal[r]) {
                    let v = s.node_velocity(i);
                    slip_speed_max = slip_speed_max.max((v[0] * v[0] + v[1] * v[1]).sqrt());
                }
            }
        }
        on_step(&s);
        if k % schedule.every == 0 || k == n_steps {
            frames.push(Frame::of(model, &s, s.t, normal.clone()));
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

/// Run a model with the explicit integrator (or to the first instability, which is kept in
/// [`Outcome::error`] with everything computed before it).
pub fn run_explicit(
    model: &Model,
    actuation: Box<dyn Actuation>,
    progress: Progress,
    on_step: &mut dyn FnMut(&State),
) -> Result<Outcome, Unsupported> {
    let start = Instant::now();
    let mut integ = Explicit::new(model, actuation)?;
    Ok(drive(
        model,
        &mut integ,
        Schedule::of(model),
        start,
        progress,
        on_step,
    ))
}

/// Run a problem's model driven by its own gait ([`crate::gait::Muscles`]) with the integrator
/// the problem asks for (`[solver] integrator`).
pub fn run_gait(
    model: &Model,
    integrator: crate::problem::IntegratorKind,
    progress: Progress,
    on_step: &mut dyn FnMut(&State),
) -> Result<Outcome, Unsupported> {
    let muscles = Box::new(crate::gait::Muscles {
        gait: model.gait.clone(),
    });
    match integrator {
        crate::problem::IntegratorKind::Implicit | crate::problem::IntegratorKind::Bdf2 => {
            Ok(run(model, muscles, progress, on_step))
        }
        crate::problem::IntegratorKind::Explicit => run_explicit(model, muscles, progress, on_step),
    }
}
