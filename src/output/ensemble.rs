//! What `slither run --ensemble K` writes into `summary.json` (`ensemble`): the members'
//! perturbations, their results and the statistics over them. The runs themselves are
//! [`crate::studies::ensemble`]'s; the types live here so that the summary does not depend on
//! the studies.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Default relative standard deviation of each friction coefficient's perturbation.
pub const FRICTION: f64 = 1e-3;
/// Default size of the initial-shape perturbation, in diameters (see `crate::studies::ensemble`).
pub const SHAPE: f64 = 1e-3;
/// Default step ladder: the members' steps run from `dt / STEP` to `dt * STEP`.
pub const STEP: f64 = 2.5;

/// How much each member is perturbed.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Perturbation {
    /// Relative standard deviation of each friction coefficient (>= 0).
    pub friction: f64,
    /// Size of the sideways initial bend, in diameters (>= 0).
    pub shape: f64,
    /// Step ladder factor (>= 1): members step from `dt / step` to `dt * step`.
    pub step: f64,
}

impl Default for Perturbation {
    fn default() -> Self {
        Perturbation {
            friction: FRICTION,
            shape: SHAPE,
            step: STEP,
        }
    }
}

impl Perturbation {
    /// No perturbation at all (every member is the scene as written).
    pub const NONE: Perturbation = Perturbation {
        friction: 0.0,
        shape: 0.0,
        step: 1.0,
    };
}

/// Statistics of one observable over the members.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Stat {
    /// Mean.
    pub mean: f64,
    /// Sample standard deviation (`n - 1`); `None` (`null`) for one value, where it is
    /// undefined (not zero: one run says nothing about the spread).
    pub sd: Option<f64>,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
    /// Number of members with a finite value.
    pub n: usize,
}

impl Stat {
    /// The statistics of the finite values among `values` (`None` if there is none).
    pub fn of(values: impl IntoIterator<Item = f64>) -> Option<Stat> {
        let v: Vec<f64> = values.into_iter().filter(|x| x.is_finite()).collect();
        if v.is_empty() {
            return None;
        }
        let n = v.len();
        let mean = v.iter().sum::<f64>() / n as f64;
        let sd = (n > 1)
            .then(|| (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt());
        Some(Stat {
            mean,
            sd,
            min: v.iter().copied().fold(f64::INFINITY, f64::min),
            max: v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            n,
        })
    }
}

/// One member's run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Member {
    /// Index `k` (0-based).
    pub index: usize,
    /// Its seed.
    pub seed: u64,
    /// Its step (s): the fixed step it ran with (at most the run's duration: a step longer
    /// than the run is cut to it), for an adaptive run its first step; `null` in static mode.
    pub dt: Option<f64>,
    /// Adaptive runs: the error tolerance it ran with (the ladder scales it, not the step).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error_tolerance: Option<f64>,
    /// The step factor of the ladder applied to it (1 in static mode, which has no step).
    pub step_factor: f64,
    /// Factors of `mu_forward`, `mu_backward`, `mu_sideways`.
    pub friction_factors: [f64; 3],
    /// RMS sideways offset of the initial shape over `a`.
    pub shape_rms_over_a: f64,
    /// "ok" or "failed".
    pub status: String,
    /// Its regime, `"-"` when the run failed.
    pub regime: String,
    /// Every scalar observable (`null` when failed or not finite).
    pub observables: BTreeMap<String, Option<f64>>,
    /// Wall time of the simulation (s).
    pub wall_time_s: f64,
    /// Why it failed (empty when ok).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub reason: String,
}

/// An ensemble's result (`summary.json`'s `ensemble`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Ensemble {
    /// Number of members `K`.
    pub runs: usize,
    /// Members that finished.
    pub finished: usize,
    /// The ensemble's seed.
    pub seed: u64,
    /// The perturbation sizes.
    pub perturbation: Perturbation,
    /// For every scalar observable: mean, sd, min, max and n over the finished members.
    pub stats: BTreeMap<String, Stat>,
    /// Members per regime label (`"-"`: failed).
    pub regime_votes: BTreeMap<String, usize>,
    /// Every member.
    pub members: Vec<Member>,
    /// Wall time of the whole ensemble (s, members in parallel).
    pub wall_time_s: f64,
}
