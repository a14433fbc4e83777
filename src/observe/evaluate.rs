//! The one evaluation pipeline: simulate a model with its own gait and integrator, then
//! measure the run. Every caller that runs a scene for its observables goes through here: `slither
//! run`, an optimisation's evaluation ([`crate::studies::optimize`]), a phase cell
//! ([`crate::studies::phase`]) and the speed-against-accuracy charts ([`crate::charts`]).
//!
//! [`evaluate`] = [`crate::sim::run_gait`] with the model's `[solver] integrator`, then
//! [`measure`]. A failed step is not an `Err`: the outcome keeps its error and everything up to
//! it, measured like a finished run (the callers decide what a cut-short run means); `Err` is
//! only an integrator that cannot run the model ([`Unsupported`]). Panics are not caught here:
//! the studies catch them per evaluation, `slither run` lets them end the process.

use super::{fields_with_progress, observe, of_outcome, Fields, Observables};
use crate::integrator::explicit::Unsupported;
use crate::model::Model;
use crate::sim::{self, Frame, Outcome};

/// What [`measure`] computes from a run's frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Measure {
    /// Every frame: the kymograph fields (topology of every frame) and all observables.
    Full,
    /// The first and the last frame only: the displacement observables (`v_s`, `v_s/v_m`,
    /// heading) at a fraction of the cost; the fields and the time-resolved observables
    /// (writhe over time, lifts, the `lambda` pulse) are those of two frames.
    Ends,
}

/// A simulated and measured run.
pub struct Observed {
    /// The run (finished or cut short by a failed step: `outcome.error`).
    pub outcome: Outcome,
    /// Kymograph fields of the measured frames.
    pub fields: Fields,
    /// Observables of the measured frames.
    pub observables: Observables,
}

/// Simulate `model` driven by its own gait with its own integrator (`progress` gets the
/// fraction of the run done), then [`measure`] it (`post` gets the fraction of the frames
/// measured).
pub fn evaluate(
    model: &Model,
    what: Measure,
    progress: &mut dyn FnMut(f64),
    post: &mut dyn FnMut(f64),
) -> Result<Observed, Unsupported> {
    let outcome = sim::run_gait(model, model.solver.integrator, progress, &mut |_| {})?;
    let (fields, observables) = measure(model, &outcome, what, post);
    Ok(Observed {
        outcome,
        fields,
        observables,
    })
}

/// The fields and observables of a run. [`Measure::Full`]: the fields of the output frames
/// (`outcome.frames`, for the kymographs and figures) and the observables of the observation
/// frames (`outcome.observed`, set by the physics: [`super::of_outcome`]). [`Measure::Ends`]:
/// both from the first and the last observation frame. `post` gets the fraction of the output
/// frames done.
pub fn measure(
    model: &Model,
    outcome: &Outcome,
    what: Measure,
    post: &mut dyn FnMut(f64),
) -> (Fields, Observables) {
    match what {
        Measure::Full => {
            let fields = fields_with_progress(model, &outcome.frames, post);
            (fields, of_outcome(model, outcome))
        }
        Measure::Ends => {
            let frames: Vec<Frame> = match (outcome.observed.first(), outcome.observed.last()) {
                (Some(a), Some(b)) => vec![a.clone(), b.clone()],
                _ => Vec::new(),
            };
            let fields = fields_with_progress(model, &frames, post);
            let observables = observe(model, &frames, &fields);
            (fields, observables)
        }
    }
}
