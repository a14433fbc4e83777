//! Self-contact in the outputs: the `self_contact` block of `summary.json` and the arrays of
//! `trajectory.npz`, both from the recorded frames' exact closest distances.

use crate::energy::self_contact::{closest_of_frame, touching_of_frame, SelfContact};
use crate::model::Model;
use crate::sim::{Frame, Outcome};
use serde::Serialize;

/// The closest centreline distance between parts of the body more than `2a` apart along it
/// (m), per recorded frame.
fn closest_per_frame(m: &Model, frames: &[Frame]) -> Vec<f64> {
    let geometry = SelfContact::geometry(m);
    frames
        .iter()
        .map(|fr| closest_of_frame(&geometry, m, &fr.x))
        .collect()
}

/// The `self_contact` block of `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct SelfContactSummary {
    /// Whether the run had self-contact (`[self_contact] enabled`).
    pub enabled: bool,
    /// Closest centreline distance between parts of the body more than `2a` apart along it,
    /// over `a`: over every accepted step (the broad phase's candidates, exact below
    /// `1 + activation`) and every recorded frame (exact); `null` when no pair is eligible.
    pub closest_over_a: Option<f64>,
    /// Accepted steps that ended with a pair within the activation gap.
    pub active_steps: usize,
    /// Largest force of one pair at the end of a step (N).
    pub max_force: f64,
    /// Most pairs within the activation gap at once.
    pub max_pairs: usize,
}

impl SelfContactSummary {
    /// From a run's statistics and its recorded frames.
    pub fn new(m: &Model, o: &Outcome) -> Self {
        let st = &o.stats.self_contact;
        let frames = closest_per_frame(m, &o.frames)
            .into_iter()
            .fold(f64::INFINITY, f64::min)
            / m.diameter;
        let closest = st.closest_over_a.map_or(frames, |c| c.min(frames));
        SelfContactSummary {
            enabled: m.self_contact.is_some(),
            closest_over_a: closest.is_finite().then_some(closest),
            active_steps: st.active_steps,
            max_force: st.max_force,
            max_pairs: st.max_pairs,
        }
    }
}

/// The self-contact arrays of `trajectory.npz` from recorded frames: `closest_distance`
/// (per frame, m: the closest centreline distance between parts of the body more than `2a`
/// apart along it) and `self_contact` (frames x nodes, flattened: 1 where a node touches
/// another part of the body, within the activation gap, else 0).
pub fn self_contact_arrays(m: &Model, frames: &[Frame]) -> (Vec<f64>, Vec<f64>) {
    let geometry = SelfContact::geometry(m);
    let touching = frames
        .iter()
        .flat_map(|fr| {
            touching_of_frame(&geometry, m, &fr.x)
                .into_iter()
                .map(|b| if b { 1.0 } else { 0.0 })
        })
        .collect();
    (closest_per_frame(m, frames), touching)
}
