//! The run loop: steps a [`Model`] from its initial state to the end of the run (dynamic) or
//! through its load increments (static), records frames at the output interval and keeps
//! everything computed so far when a step fails.
//!
//! Two series of frames are kept. [`Outcome::frames`] are the frames the user asked for
//! (`[output] interval`): the trajectory, the kymographs and the figures. [`Outcome::observed`]
//! are the frames every observable and the regime are measured on ([`crate::observe`]): a
//! grid set by the physics, independent of the output interval, so that asking for fewer
//! frames never changes a measured value. Its spacing is [`observation_interval`]: the pulse
//! time `T = L / v_m` (or the duration, if shorter or without a gait; a gait with a launch
//! period always `T`, so its per-cycle values do not depend on the run's length) over
//! [`OBSERVATIONS_PER_PULSE`]; with fixed steps it is rounded to a whole number of steps
//! (the bundled S-start: 9 steps of 2 ms, 0.018 s); with adaptive steps a frame is taken at
//! the first accepted step that reaches each grid time. Both series start at t = 0 and end
//! with the last step of a finished run. Every time stepper ([`Stepper`]: implicit,
//! explicit) runs through [`drive`]; the charts run it with their own [`Schedule`].

use crate::integrator::adaptive::{Adapted, Controller, StepStats};
use crate::integrator::explicit::{Explicit, Unsupported};
use crate::integrator::statics::Static;
use crate::integrator::{Actuation, Energies, Integrator, RunStats, StepError, Stepper};
use crate::model::Model;
use crate::problem::Mode;
use crate::rod::dof;
use crate::state::State;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Set (by the command line's SIGINT handler, or any caller) to stop the running simulations
/// after their current step: [`drive`] then returns what it computed with
/// [`Outcome::interrupted`] set. A single atomic store, safe inside a signal handler.
pub static INTERRUPT: AtomicBool = AtomicBool::new(false);

/// Whether [`INTERRUPT`] is set.
pub fn interrupt_requested() -> bool {
    INTERRUPT.load(Ordering::Relaxed)
}

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
    /// Recorded frames, at the output interval (what the user asked for).
    pub frames: Vec<Frame>,
    /// Frames on the observation grid ([`observation_interval`], module doc): every measured
    /// observable and the regime come from these, never from [`Outcome::frames`].
    pub observed: Vec<Frame>,
    /// Solver statistics.
    pub stats: RunStats,
    /// Wall-clock time of the integration (s).
    pub wall_time_s: f64,
    /// Largest |strain| over all accepted steps.
    pub max_strain: f64,
    /// Energies of the final state.
    pub energies: Energies,
    /// The failure that stopped the run, if any.
    pub error: Option<StepError>,
    /// Stopped early by [`INTERRUPT`] (Ctrl-C) after the last accepted step.
    pub interrupted: bool,
    /// Largest penetration of a node below `z = a/2` over all accepted steps (m).
    pub max_penetration: f64,
    /// Largest slip speed of a node in contact over all accepted steps (m/s).
    pub slip_speed_max: f64,
    /// Accepted and rejected steps and the range of step sizes.
    pub steps: StepStats,
}

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum RunStatus {
    /// Every step accepted to the end.
    Completed,
    /// Stopped by a failed step ([`Outcome::error`]).
    Failed,
    /// Stopped by the user (Ctrl-C, [`INTERRUPT`]) before the end.
    Interrupted,
}

impl Outcome {
    /// How the run ended.
    pub fn status(&self) -> RunStatus {
        if self.error.is_some() {
            RunStatus::Failed
        } else if self.interrupted {
            RunStatus::Interrupted
        } else {
            RunStatus::Completed
        }
    }
}

/// Observation frames per pulse time `T = L / v_m` (module doc): 200, so a travelling pulse
/// is seen at 200 positions along the body and the peak of a lift that lasts a tenth of `T`
/// at 20 instants.
pub const OBSERVATIONS_PER_PULSE: f64 = 200.0;

/// Spacing of the observation grid (s): `min(T, duration) / OBSERVATIONS_PER_PULSE`, with the
/// pulse time `T = L / v_m` of a gait, or the duration without one (static mode: every load
/// increment is observed). A gait with a launch period (sidewinding) is observed every
/// `T / OBSERVATIONS_PER_PULSE` whatever the duration, so its per-cycle values do not change
/// with the run's length (in a run shorter than `T` the cycles' end frames would otherwise
/// move with the duration). It depends on the physics (rod, gait, duration), never on
/// `[output] interval`.
pub fn observation_interval(model: &Model) -> f64 {
    let g = &model.gait;
    let pulse = if g.kind != crate::gait::Kind::None && g.speed > 0.0 {
        g.pulse_time(model.length)
    } else {
        f64::INFINITY
    };
    if g.kind.has_launch_period() && pulse.is_finite() {
        return pulse / OBSERVATIONS_PER_PULSE;
    }
    pulse.min(model.duration) / OBSERVATIONS_PER_PULSE
}

/// Progress callback: fraction done in [0, 1].
pub type Progress<'a> = &'a mut dyn FnMut(f64);

/// The steps of a dynamic run: `steps` steps of `dt`, the last one of `last` (so the run ends
/// exactly at its duration), a frame recorded every `every` steps (and after the last).
///
/// With `adaptive` set, the steps are error controlled instead: the first is `dt`, the run
/// ends at `duration`, and a frame is recorded at every multiple of `interval` (and at the
/// end). Steps are sized to land on the frame times: a step that would pass the next frame
/// time ends on it, and one that would leave less than a step before it is split into two
/// equal steps, so no step is shorter than half the controller's proposal because of a frame.
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
    /// Steps between observation frames ([`observation_interval`] in steps, at least 1).
    pub observe_every: usize,
    /// Observation grid spacing of an adaptive run (s).
    pub observe_interval: f64,
    /// Error-controlled steps (`[time] adaptive`), else `None`.
    pub adaptive: Option<Controller>,
    /// End time of an adaptive run (s).
    pub duration: f64,
    /// Frame interval of an adaptive run (s).
    pub interval: f64,
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
            observe_every: ((observation_interval(model) / dt).round() as usize).max(1),
            observe_interval: observation_interval(model),
            adaptive: model.adaptive.map(|settings| Controller { settings }),
            duration,
            interval: model.output_interval,
        }
    }

    /// `steps` steps of `dt`, recording (and observing) only the first and last frames.
    pub fn fixed(dt: f64, steps: usize) -> Self {
        Schedule {
            dt,
            steps,
            last: dt,
            every: steps.max(1),
            observe_every: steps.max(1),
            observe_interval: dt * steps as f64,
            adaptive: None,
            duration: dt * steps as f64,
            interval: dt * steps as f64,
        }
    }

    /// Error-controlled steps with `control` from t = 0 to `duration`, frames every `interval`,
    /// observed every `duration / OBSERVATIONS_PER_PULSE`.
    pub fn adaptive(control: Controller, duration: f64, interval: f64) -> Self {
        Schedule {
            dt: control.settings.dt_first,
            steps: 0,
            last: control.settings.dt_first,
            every: 1,
            observe_every: 1,
            observe_interval: duration / OBSERVATIONS_PER_PULSE,
            adaptive: Some(control),
            duration,
            interval,
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
        observed: frames.clone(),
        frames,
        stats: integ.stats().clone(),
        wall_time_s: start.elapsed().as_secs_f64(),
        max_strain,
        energies,
        error,
        interrupted: false,
        max_penetration: 0.0,
        slip_speed_max: 0.0,
        steps: StepStats::default(),
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
    let mut watch = Watch::new(model, integ, &s);
    let mut error = None;
    let mut interrupted = false;
    let mut steps = StepStats::default();
    match schedule.adaptive {
        None => {
            let n_steps = schedule.steps;
            for k in 1..=n_steps {
                if interrupt_requested() {
                    interrupted = true;
                    break;
                }
                let h = if k == n_steps {
                    schedule.last
                } else {
                    schedule.dt
                };
                let (t0, halvings) = (s.t, integ.stats().step_halvings);
                if let Err(e) = integ.step(&mut s, h) {
                    error = Some(e);
                    break;
                }
                steps.add(&Adapted {
                    h: s.t - t0,
                    rejected_solve: integ.stats().step_halvings - halvings,
                    ..Default::default()
                });
                let frame = k % schedule.every == 0 || k == n_steps;
                let observed = k % schedule.observe_every == 0 || k == n_steps;
                watch.after_step(model, integ, &s, frame, observed);
                on_step(&s);
                progress(k as f64 / n_steps as f64);
            }
        }
        Some(control) => {
            steps.adaptive = true;
            let t_end = schedule.duration;
            let interval = schedule.interval.max(f64::MIN_POSITIVE);
            // Relative slack for landing on a frame time (rounding of t).
            let slack = 1e-9;
            let mut next = control.settings.dt_first;
            let mut frame_index = 1usize;
            let grid = schedule.observe_interval.max(f64::MIN_POSITIVE);
            let mut observe_index = 1usize;
            while s.t < t_end * (1.0 - 1e-12) {
                if interrupt_requested() {
                    interrupted = true;
                    break;
                }
                let target = (frame_index as f64 * interval).min(t_end);
                let left = target - s.t;
                let proposal = next.min(control.settings.dt_max);
                let h = if left <= proposal * (1.0 + slack) {
                    left
                } else if left < 2.0 * proposal {
                    0.5 * left
                } else {
                    proposal
                };
                let r = match integ.adaptive_step(&mut s, h, &control) {
                    Ok(r) => r,
                    Err(e) => {
                        error = Some(e);
                        break;
                    }
                };
                steps.add(&r);
                next = r.next;
                let landed = (s.t - target).abs() <= slack * target.max(h);
                if landed {
                    s.t = target;
                    // Skip frame times already passed (an interval below the smallest step).
                    while frame_index as f64 * interval <= s.t * (1.0 + slack) {
                        frame_index += 1;
                    }
                }
                // An observation at the first step reaching the next grid time (the grid is
                // not landed on: the steps do not depend on it).
                let end = s.t >= t_end * (1.0 - 1e-12);
                let observed = end || s.t >= observe_index as f64 * grid * (1.0 - slack);
                while observe_index as f64 * grid <= s.t * (1.0 + slack) {
                    observe_index += 1;
                }
                watch.after_step(model, integ, &s, landed, observed);
                on_step(&s);
                progress((s.t / t_end).min(1.0));
            }
        }
    }
    if interrupted {
        // The last accepted step, so the saved results end where the run stopped.
        let last = Frame::of(model, &s, s.t, watch.normal.clone());
        if watch.observed.last().is_some_and(|f| f.t < s.t) {
            watch.observed.push(last.clone());
        }
        if watch.frames.last().is_some_and(|f| f.t < s.t) {
            watch.frames.push(last);
        }
    }
    let energies = integ.energies(&s);
    Outcome {
        state: s,
        frames: watch.frames,
        observed: watch.observed,
        stats: integ.stats().clone(),
        wall_time_s: start.elapsed().as_secs_f64(),
        max_strain: watch.max_strain,
        energies,
        error,
        interrupted,
        max_penetration: watch.max_penetration,
        slip_speed_max: watch.slip_speed_max,
        steps,
    }
}

/// What the run loop records after every accepted step: frames, observation frames and the
/// contact statistics.
struct Watch {
    normal: Vec<f64>,
    frames: Vec<Frame>,
    observed: Vec<Frame>,
    max_strain: f64,
    max_penetration: f64,
    slip_speed_max: f64,
}

impl Watch {
    fn new(model: &Model, integ: &dyn Stepper, s: &State) -> Self {
        let mut normal = vec![0.0; model.real.len()];
        integ.normal_forces_into(&mut normal);
        let first = Frame::of(model, s, 0.0, normal.clone());
        Watch {
            observed: vec![first.clone()],
            frames: vec![first],
            normal,
            max_strain: s.max_strain(model),
            max_penetration: 0.0,
            slip_speed_max: 0.0,
        }
    }

    fn after_step(
        &mut self,
        model: &Model,
        integ: &dyn Stepper,
        s: &State,
        frame: bool,
        observed: bool,
    ) {
        self.max_strain = self.max_strain.max(s.max_strain(model));
        integ.normal_forces_into(&mut self.normal);
        if integ.has_contact() {
            for (r, i) in model.real.clone().enumerate() {
                self.max_penetration = self
                    .max_penetration
                    .max(0.5 * model.diameter - s.node(i)[2]);
                if model.in_contact(self.normal[r]) {
                    let v = s.node_velocity(i);
                    self.slip_speed_max =
                        self.slip_speed_max.max((v[0] * v[0] + v[1] * v[1]).sqrt());
                }
            }
        }
        if frame || observed {
            let fr = Frame::of(model, s, s.t, self.normal.clone());
            if observed {
                self.observed.push(fr.clone());
            }
            if frame {
                self.frames.push(fr);
            }
        }
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
        crate::problem::IntegratorKind::ImplicitEuler | crate::problem::IntegratorKind::Bdf2 => {
            Ok(run(model, muscles, progress, on_step))
        }
        crate::problem::IntegratorKind::VelocityVerlet => {
            run_explicit(model, muscles, progress, on_step)
        }
    }
}
