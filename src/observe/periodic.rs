//! Periodic-gait observables: a gait with a launch period (sidewinding) measured cycle by cycle,
//! and the sidewinding criteria.
//!
//! Cycle `k` is the interval `[k P, (k + 1) P]` of the gait's launch period `P`, its ends the
//! frames nearest to those instants (the observation frames, [`crate::sim::Outcome::observed`],
//! `T / 200` apart whatever the run's length, so a cycle's values do not depend on how
//! long the run lasts: [`crate::sim::observation_interval`]). The first [`SETTLING_CYCLES`] cycles are the start-up and are not measured.
//! Per cycle, in the ground plane:
//!
//! * the **axis**: the mean over the cycle's frames of the unit tail-to-head direction
//!   (horizontal part of head minus tail), normalised: the paper's body axis, which a turning
//!   body carries with it;
//! * the **centroid displacement** from the cycle's first to its last frame, over `L`;
//! * the **travel angle**: the angle between that displacement and the axis (0 to 180 degrees;
//!   0 travels head first, 90 broadside), and the **broadside angle** `min(angle, 180 - angle)`;
//! * the **turn**: the signed rotation (degrees, counter-clockwise positive seen from above) of
//!   the tail-to-head direction from the cycle's first to its last frame (the same gait phase);
//! * the **lateral** and **along** speeds: the displacement across and along the axis over `P`,
//!   over `v_m`;
//! * **stationary contact**: a node in contact ([`crate::model::Model::in_contact`]) is
//!   stationary when its horizontal speed is at most [`STATIONARY_SLIP_OVER_V_M`]` v_m`. The
//!   stationary share is the fraction of the contact node-time (every contact node at every
//!   frame after the cycle's first) that is stationary: the fraction of the patch time the
//!   patches hold still. The stationary body fraction is the mean over those frames of the
//!   share of all nodes in stationary contact;
//! * **patches**: the mean number of separate runs of contact nodes per frame.
//!
//! The spread of every per-cycle value is its range (max - min) over the measured cycles.
//!
//! **Sidewinding** (a sub-label of the regime for periodic gaits; every criterion must hold in
//! every measured cycle, over at least [`MIN_CYCLES`] cycles): broadside angle at least
//! [`BROADSIDE_MIN_DEG`], |turn| at most [`TURN_MAX_DEG`] per cycle, displacement at least
//! [`DISPLACEMENT_MIN_OVER_L`]` L`, stationary share at least [`STATIONARY_SHARE_MIN`].

use super::regime::{check, Check};
use crate::model::Model;
use crate::sim::{Frame, Outcome};
use serde::Serialize;

/// Cycles at the start that are not measured (the body settles into the gait).
pub const SETTLING_CYCLES: usize = 1;
/// Fewest measured cycles for the sidewinding label.
pub const MIN_CYCLES: usize = 4;
/// Smallest broadside angle of sidewinding (degrees from the axis).
pub const BROADSIDE_MIN_DEG: f64 = 60.0;
/// Largest |turn| of sidewinding (degrees per cycle).
pub const TURN_MAX_DEG: f64 = 5.0;
/// Smallest centroid displacement of sidewinding per cycle (over `L`).
pub const DISPLACEMENT_MIN_OVER_L: f64 = 0.1;
/// Slip speed (over `v_m`) at or below which a contact node is stationary.
pub const STATIONARY_SLIP_OVER_V_M: f64 = 0.1;
/// Smallest stationary share of the contact node-time of sidewinding.
pub const STATIONARY_SHARE_MIN: f64 = 0.8;

/// One measured cycle (module doc).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Cycle {
    /// Cycle number, counted from 0 at the first launch.
    pub index: usize,
    /// Time of its first frame (s).
    pub t_start: f64,
    /// Time of its last frame (s).
    pub t_end: f64,
    /// Centroid displacement over the cycle, over `L`.
    pub displacement_over_length: f64,
    /// Angle between the displacement and the cycle-mean tail-to-head axis (degrees, 0..180).
    pub travel_angle_deg: f64,
    /// `min(travel_angle_deg, 180 - travel_angle_deg)` (degrees, 0..90; 90 is broadside).
    pub broadside_deg: f64,
    /// Signed rotation of the tail-to-head direction over the cycle (degrees).
    pub turn_deg: f64,
    /// Displacement across the axis over `P v_m`.
    pub lateral_speed_over_v_m: f64,
    /// Displacement along the axis (tail to head positive) over `P v_m`.
    pub along_speed_over_v_m: f64,
    /// Share of the contact node-time with slip at most `0.1 v_m`.
    pub stationary_contact_share: f64,
    /// Mean share of all nodes in stationary contact.
    pub stationary_body_fraction: f64,
    /// Mean number of contact patches per frame.
    pub contact_patches_mean: f64,
}

/// Range (max - min) over the measured cycles of the per-cycle values.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Spread {
    /// Of `displacement_over_length`.
    pub displacement_over_length: f64,
    /// Of `broadside_deg`.
    pub broadside_deg: f64,
    /// Of `turn_deg`.
    pub turn_deg: f64,
    /// Of `lateral_speed_over_v_m`.
    pub lateral_speed_over_v_m: f64,
    /// Of `stationary_contact_share`.
    pub stationary_contact_share: f64,
}

/// The periodic observables of a run (module doc).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Periodic {
    /// Launch period `P` (s).
    pub period: f64,
    /// Cycles not measured at the start.
    pub settling_cycles: usize,
    /// The measured cycles, in order.
    pub cycles: Vec<Cycle>,
    /// Mean lateral speed over `v_m` of the measured cycles (NaN without one).
    pub lateral_speed_over_v_m: f64,
    /// Mean |turn| per cycle (degrees; NaN without a cycle).
    pub turn_deg_mean_abs: f64,
    /// Smallest broadside angle over the cycles (degrees).
    pub broadside_deg_min: f64,
    /// Largest |turn| over the cycles (degrees).
    pub turn_deg_max_abs: f64,
    /// Smallest displacement over the cycles (over `L`).
    pub displacement_over_length_min: f64,
    /// Smallest stationary contact share over the cycles.
    pub stationary_contact_share_min: f64,
    /// Spread of the per-cycle values.
    pub spread: Spread,
    /// Whether every sidewinding criterion holds (module doc).
    pub sidewinding: bool,
    /// How far the worst cycle lies inside the sidewinding criteria
    /// ([`Periodic::sidewinding_margin`]; NaN with fewer than [`MIN_CYCLES`] cycles).
    pub sidewinding_margin: f64,
    /// The sidewinding comparisons, worst cycle against threshold.
    pub sidewinding_checks: Vec<Check>,
}

fn horizontal_unit(d: [f64; 3]) -> [f64; 2] {
    let r = d[0].hypot(d[1]);
    if r > 0.0 {
        [d[0] / r, d[1] / r]
    } else {
        [f64::NAN, f64::NAN]
    }
}

fn axis(fr: &Frame) -> [f64; 2] {
    let (h, t) = (fr.x[0], fr.x[fr.x.len() - 1]);
    horizontal_unit([h[0] - t[0], h[1] - t[1], 0.0])
}

fn centroid(fr: &Frame) -> [f64; 2] {
    let n = fr.x.len() as f64;
    let (sx, sy) =
        fr.x.iter()
            .fold((0.0, 0.0), |(a, b), x| (a + x[0], b + x[1]));
    [sx / n, sy / n]
}

fn nearest(frames: &[Frame], t: f64) -> usize {
    (0..frames.len())
        .min_by(|&a, &b| (frames[a].t - t).abs().total_cmp(&(frames[b].t - t).abs()))
        .unwrap_or(0)
}

/// Measure one cycle on `frames[k0..=k1]`.
fn cycle(
    frames: &[Frame],
    (k0, k1): (usize, usize),
    index: usize,
    (period, v_m, length): (f64, f64, f64),
    in_contact: &dyn Fn(f64) -> bool,
) -> Cycle {
    let (a, b) = (&frames[k0], &frames[k1]);
    let mut m = [0.0, 0.0];
    for fr in &frames[k0..=k1] {
        let u = axis(fr);
        m = [m[0] + u[0], m[1] + u[1]];
    }
    let m = horizontal_unit([m[0], m[1], 0.0]);
    let (c0, c1) = (centroid(a), centroid(b));
    let d = [c1[0] - c0[0], c1[1] - c0[1]];
    let along = m[0] * d[0] + m[1] * d[1];
    let across = m[0] * d[1] - m[1] * d[0];
    let angle = across.abs().atan2(along).to_degrees();
    let (u0, u1) = (axis(a), axis(b));
    let turn = (u0[0] * u1[1] - u0[1] * u1[0])
        .atan2(u0[0] * u1[0] + u0[1] * u1[1])
        .to_degrees();
    let (mut contact, mut still, mut body, mut patches) = (0usize, 0usize, 0.0, 0usize);
    for fr in &frames[k0 + 1..=k1] {
        let mut prev = false;
        let mut here = 0usize;
        for (v, &n) in fr.v.iter().zip(&fr.normal) {
            let on = in_contact(n);
            if on {
                contact += 1;
                if v[0].hypot(v[1]) <= STATIONARY_SLIP_OVER_V_M * v_m {
                    still += 1;
                    here += 1;
                }
                if !prev {
                    patches += 1;
                }
            }
            prev = on;
        }
        body += here as f64 / fr.x.len() as f64;
    }
    let frames_n = (k1 - k0) as f64;
    Cycle {
        index,
        t_start: a.t,
        t_end: b.t,
        displacement_over_length: d[0].hypot(d[1]) / length,
        travel_angle_deg: angle,
        broadside_deg: angle.min(180.0 - angle),
        turn_deg: turn,
        lateral_speed_over_v_m: across.abs() / (period * v_m),
        along_speed_over_v_m: along / (period * v_m),
        stationary_contact_share: if contact > 0 {
            still as f64 / contact as f64
        } else {
            f64::NAN
        },
        stationary_body_fraction: body / frames_n,
        contact_patches_mean: patches as f64 / frames_n,
    }
}

/// The periodic observables of `frames` (module doc) for launch period `period` (s), travelling
/// speed `v_m` (m/s) and rod length `length` (m); `in_contact` tells a node in contact by its
/// normal force. Cycles end at the last frame that completes one.
pub fn measure(
    frames: &[Frame],
    period: f64,
    v_m: f64,
    length: f64,
    in_contact: &dyn Fn(f64) -> bool,
) -> Periodic {
    let mut cycles = Vec::new();
    if let (Some(last), true) = (frames.last(), period > 0.0) {
        // Half an observation interval of slack at the end.
        let slack = if frames.len() > 1 {
            0.5 * (frames[1].t - frames[0].t)
        } else {
            0.0
        };
        let mut k = SETTLING_CYCLES;
        while (k + 1) as f64 * period <= last.t + slack {
            let (k0, k1) = (
                nearest(frames, k as f64 * period),
                nearest(frames, (k + 1) as f64 * period),
            );
            if k1 > k0 {
                cycles.push(cycle(
                    frames,
                    (k0, k1),
                    k,
                    (period, v_m, length),
                    in_contact,
                ));
            }
            k += 1;
        }
    }
    summarise(period, cycles)
}

/// The periodic observables of a run whose gait has a launch period (sidewinding), measured on
/// its observation frames; `None` for other gaits and without a couple (`G = 0`).
pub fn of_outcome(m: &Model, o: &Outcome) -> Option<Periodic> {
    let g = &m.gait;
    if !g.kind.has_launch_period() || g.couple <= 0.0 {
        return None;
    }
    Some(measure(&o.observed, g.period, g.speed, m.length, &|n| {
        m.in_contact(n)
    }))
}

fn fold(cycles: &[Cycle], f: impl Fn(&Cycle) -> f64, min: bool) -> f64 {
    let it = cycles.iter().map(f);
    if cycles.is_empty() {
        f64::NAN
    } else if min {
        it.fold(f64::INFINITY, f64::min)
    } else {
        it.fold(f64::NEG_INFINITY, f64::max)
    }
}

fn range(cycles: &[Cycle], f: impl Fn(&Cycle) -> f64 + Copy) -> f64 {
    fold(cycles, f, false) - fold(cycles, f, true)
}

/// The summary values and the sidewinding label of measured cycles.
pub fn summarise(period: f64, cycles: Vec<Cycle>) -> Periodic {
    let n = cycles.len() as f64;
    let mean = |f: &dyn Fn(&Cycle) -> f64| {
        if cycles.is_empty() {
            f64::NAN
        } else {
            cycles.iter().map(f).sum::<f64>() / n
        }
    };
    let lateral = mean(&|c| c.lateral_speed_over_v_m);
    let turn_mean = mean(&|c| c.turn_deg.abs());
    let broadside_min = fold(&cycles, |c| c.broadside_deg, true);
    let turn_max = fold(&cycles, |c| c.turn_deg.abs(), false);
    let disp_min = fold(&cycles, |c| c.displacement_over_length, true);
    let still_min = fold(&cycles, |c| c.stationary_contact_share, true);
    let checks = vec![
        check("cycles", n, ">=", MIN_CYCLES as f64),
        check("broadside_deg_min", broadside_min, ">=", BROADSIDE_MIN_DEG),
        check("turn_deg_max_abs", turn_max, "<=", TURN_MAX_DEG),
        check(
            "displacement_over_length_min",
            disp_min,
            ">=",
            DISPLACEMENT_MIN_OVER_L,
        ),
        check(
            "stationary_contact_share_min",
            still_min,
            ">=",
            STATIONARY_SHARE_MIN,
        ),
    ];
    let spread = Spread {
        displacement_over_length: range(&cycles, |c| c.displacement_over_length),
        broadside_deg: range(&cycles, |c| c.broadside_deg),
        turn_deg: range(&cycles, |c| c.turn_deg),
        lateral_speed_over_v_m: range(&cycles, |c| c.lateral_speed_over_v_m),
        stationary_contact_share: range(&cycles, |c| c.stationary_contact_share),
    };
    let mut p = Periodic {
        period,
        settling_cycles: SETTLING_CYCLES,
        lateral_speed_over_v_m: lateral,
        turn_deg_mean_abs: turn_mean,
        broadside_deg_min: broadside_min,
        turn_deg_max_abs: turn_max,
        displacement_over_length_min: disp_min,
        stationary_contact_share_min: still_min,
        spread,
        sidewinding: checks.iter().all(|c| c.holds),
        sidewinding_checks: checks,
        sidewinding_margin: f64::NAN,
        cycles,
    };
    p.sidewinding_margin = p.sidewinding_margin();
    p
}

impl Periodic {
    /// How far the worst cycle is inside the sidewinding criteria: the smallest relative excess
    /// over the four thresholds, `min((share - 0.8) / 0.8, (displacement - 0.1) / 0.1,
    /// (5 - |turn|) / 5, (broadside - 60) / 60)` over the per-cycle extremes; negative when a
    /// criterion fails, NaN with fewer than [`MIN_CYCLES`] measured cycles.
    pub fn sidewinding_margin(&self) -> f64 {
        if self.cycles.len() < MIN_CYCLES {
            return f64::NAN;
        }
        [
            (self.stationary_contact_share_min - STATIONARY_SHARE_MIN) / STATIONARY_SHARE_MIN,
            (self.displacement_over_length_min - DISPLACEMENT_MIN_OVER_L) / DISPLACEMENT_MIN_OVER_L,
            (TURN_MAX_DEG - self.turn_deg_max_abs) / TURN_MAX_DEG,
            (self.broadside_deg_min - BROADSIDE_MIN_DEG) / BROADSIDE_MIN_DEG,
        ]
        .into_iter()
        .fold(f64::INFINITY, f64::min)
    }

    /// The sidewinding criteria that fail, as one line (empty when it sidewinds).
    pub fn missed(&self) -> String {
        self.sidewinding_checks
            .iter()
            .filter(|c| !c.holds)
            .map(|c| format!("{} {:.3} not {} {}", c.quantity, c.value, c.op, c.threshold))
            .collect::<Vec<_>>()
            .join("; ")
    }
}

#[cfg(test)]
#[path = "periodic_tests.rs"]
mod tests;
