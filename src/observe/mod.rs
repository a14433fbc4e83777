//! What is measured (MODEL section 5): forward speed, kymographs of elevation, slip speed and
//! local link density, topology over time, contact patches, and the regime classification
//! ([`regime`]: S, M, F, N, U as the paper defines them, with the thresholds and the reason for
//! each label).
//!
//! Contact and slip: a node is in contact when its normal force exceeds
//! [`crate::model::CONTACT_FRACTION`] of its share of the weight ([`Model::in_contact`]); slip speeds are reported only for such nodes
//! (the horizontal speed of a node in the air is not slip): NaN elsewhere in the kymograph,
//! the npz `slip_speed` and the ParaView point data ([`contact_slip`]), and the summary's
//! `slip_speed_max` and every slip statistic use the same test.
//!
//! Local link density `lambda`: windows of `L/10` (rest length) start at every node whose
//! window fits in the rest length; the windows are laid out once, so a frame in which the body
//! is compressed slightly (strain ~1e-4) keeps its last window, shortened to end at the tail
//! ([`topology::densities_shortened`]) instead of a NaN.
//!
//! Resolution: every scalar observable and the regime are measured on the run's observation
//! frames ([`crate::sim::Outcome::observed`], use [`of_outcome`]): a grid of
//! [`crate::sim::OBSERVATIONS_PER_PULSE`] instants per pulse time `T = L / v_m`, set by the
//! physics and independent of `[output] interval`, which only sets the frames written for the
//! user (trajectory, kymographs, figures). Fewer output frames never change a measured value.
//! [`observe`] itself measures whatever frames it is given.
//!
//! Lift: `max_elevation_over_a` is the body's highest point at any instant, which may be an
//! end (a tail tip standing up); `arc_lift_max_over_a` is the highest point of an arc, a lifted
//! stretch with ground contact on both sides; `two_arc_lift_over_a` is the lower of two such
//! arcs at one instant. The S criterion uses the two arcs; the flailing test of U uses the
//! body's highest point (a body thrown up by its end flails too).
//!
//! The writhe snapshot (the paper's Fig. 3a plots the writhe at one instant of the motion) is
//! taken at the frame nearest to the instant the centre of couple b, the middle of the
//! triplet, passes mid-body: `t* = (L/2 - s_b0) / v_m` (`s_b0` its initial arc length), clamped
//! to the recorded frames.
//!
//! [`evaluate()`] is the one pipeline that simulates a scene and measures it here.

pub mod evaluate;
pub mod periodic;
pub mod regime;
pub mod tracks;

pub use evaluate::{evaluate, measure, Measure, Observed};
pub use regime::{classify, Regime, RegimeInputs, RegimeReason};

use crate::model::Model;
use crate::rod::vec3::f;
use crate::sim::{Frame, Outcome};
use crate::topology::{self, FramedCurve};
use serde::Serialize;

/// Space-time fields for kymographs and plots.
#[derive(Clone, Debug, Default)]
pub struct Fields {
    /// Arc length of each node (m).
    pub s: Vec<f64>,
    /// Arc length of the centre of each `lambda` window (m).
    pub s_window: Vec<f64>,
    /// Frame times (s).
    pub t: Vec<f64>,
    /// Elevation `z - a/2` (m), frames x nodes.
    pub elevation: Vec<Vec<f64>>,
    /// Slip speed (m/s), frames x nodes: the horizontal speed of nodes in contact, NaN for
    /// nodes in the air ([`contact_slip`]).
    pub slip: Vec<Vec<f64>>,
    /// Local link density `lambda` (turns/m), frames x windows.
    pub lambda: Vec<Vec<f64>>,
    /// Total twist per frame (turns).
    pub tw: Vec<f64>,
    /// Writhe per frame (turns).
    pub wr: Vec<f64>,
    /// Link `Tw + Wr` per frame (turns).
    pub lk: Vec<f64>,
}

/// Scalar observables reported in `summary.json`.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Observables {
    /// Mean forward speed of the centroid along the initial tail-to-head direction (m/s).
    pub v_s: f64,
    /// `v_s / v_m` (`NaN` without a gait).
    pub v_s_over_v_m: f64,
    /// Centroid displacement (forward along the initial head direction, lateral) (m).
    pub displacement: [f64; 2],
    /// Angle of the net displacement from the initial head direction (degrees, 0..180).
    pub displacement_angle_deg: f64,
    /// Largest |writhe| over the frames (turns).
    pub writhe_max: f64,
    /// Writhe (signed, turns) at the frame nearest to `writhe_snapshot_t` (module doc; NaN
    /// without a gait).
    pub writhe_snapshot: f64,
    /// Time of that frame (s): nearest to `(L/2 - s_b0) / v_m`, when couple b is at mid-body.
    pub writhe_snapshot_t: f64,
    /// Mean writhe over the frames (turns).
    pub writhe_mean: f64,
    /// Largest |link| over the frames (turns).
    pub link_max: f64,
    /// Speed of the `lambda` peak along the body (m/s), from a linear fit.
    pub lambda_pulse_speed: f64,
    /// `lambda_pulse_speed / v_m`.
    pub lambda_pulse_speed_over_v_m: f64,
    /// `R^2` of that fit.
    pub lambda_pulse_r2: f64,
    /// `(max - min) / max` of the peak |lambda| over the fitted frames.
    pub lambda_amplitude_variation: f64,
    /// Largest elevation over `a` of any node: the body's highest point, possibly an end.
    pub max_elevation_over_a: f64,
    /// Largest elevation over `a` of a node between two ground contacts: the highest arc (an
    /// end lifted from the ground is not an arc; 0 with fewer than two contacts).
    pub arc_lift_max_over_a: f64,
    /// Largest elevation over `L`.
    pub max_elevation_over_length: f64,
    /// Most separate arcs lifted at least `a/2` at one instant.
    pub lifted_arcs_max: usize,
    /// Height over `a` of the lower of two arcs on either side of a ground contact, at the
    /// instant that maximises it: the largest `h` such that at some instant a node in contact
    /// has nodes lifted at least `h` both ahead of it and behind it (0 if never).
    pub two_arc_lift_over_a: f64,
    /// Median (over the pulse frames) of the mean slip speed of the middle contact segment,
    /// over `v_m`. The middle segment is the set of nodes in contact between the centres of
    /// couples a and c (the ground contact between the two lifted bends).
    pub middle_slip_over_v_m: f64,
    /// Fraction of the pulse frames in which the middle contact segment exists and its mean
    /// slip speed is below `0.1 v_m`.
    pub middle_static_fraction: f64,
    /// Fraction of frames with at least two separate contact patches.
    pub two_patch_fraction: f64,
    /// Median slip speed of contact nodes over `v_m`.
    pub contact_slip_over_v_m: f64,
    /// Regime, serialised as "S", "M", "F", "N" or "U" (criteria in [`regime`] and the guide's chapter "Regimes").
    pub regime: Regime,
    /// Why: the deciding comparisons in one line, the S criteria an `M` run missed, and every
    /// comparison with its value and threshold.
    pub regime_reason: RegimeReason,
}

impl Observables {
    /// The values the regime depends on.
    pub fn regime_inputs(&self) -> RegimeInputs {
        RegimeInputs {
            v_s_over_v_m: self.v_s_over_v_m,
            displacement_angle_deg: self.displacement_angle_deg,
            max_elevation_over_a: self.max_elevation_over_a,
            max_elevation_over_length: self.max_elevation_over_length,
            two_arc_lift_over_a: self.two_arc_lift_over_a,
            lambda_pulse_r2: self.lambda_pulse_r2,
            lambda_pulse_speed_over_v_m: self.lambda_pulse_speed_over_v_m,
        }
    }
}

fn runs(mask: impl Iterator<Item = bool>) -> usize {
    let mut n = 0;
    let mut prev = false;
    for m in mask {
        if m && !prev {
            n += 1;
        }
        prev = m;
    }
    n
}

/// Largest `h` such that a node `j` with `contact[j]` has elevations `>= h` both before and
/// after it in `e`: the height of the lower of two arcs separated by a ground contact
/// (`-inf` if no contact node has nodes on both sides).
fn two_arc_height(e: &[f64], contact: impl Fn(usize) -> bool) -> f64 {
    let n = e.len();
    let mut after = vec![f64::NEG_INFINITY; n + 1];
    for i in (0..n).rev() {
        after[i] = after[i + 1].max(e[i]);
    }
    let mut before = f64::NEG_INFINITY;
    let mut best = f64::NEG_INFINITY;
    for j in 0..n {
        if contact(j) {
            best = best.max(before.min(after[j + 1]));
        }
        before = before.max(e[j]);
    }
    best
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// Slip speed (m/s) of a node: its horizontal speed if it is in contact, NaN in the air.
pub fn contact_slip(m: &Model, v: [f64; 3], normal: f64) -> f64 {
    if m.in_contact(normal) {
        (v[0] * v[0] + v[1] * v[1]).sqrt()
    } else {
        f64::NAN
    }
}

/// Fields of every frame.
pub fn fields(m: &Model, frames: &[Frame]) -> Fields {
    fields_with_progress(m, frames, &mut |_| {})
}

/// [`fields`], reporting the fraction of frames done to `progress` (the topology of a long
/// run on a fine mesh takes a while: about `0.6 N^2` segment pairs per frame). Frames are
/// processed in parallel (rayon), in chunks between progress reports.
pub fn fields_with_progress(m: &Model, frames: &[Frame], progress: &mut dyn FnMut(f64)) -> Fields {
    use rayon::prelude::*;
    let a = m.diameter;
    let delta = m.length / 10.0;
    let s: Vec<f64> = m.real.clone().map(|i| m.arc_length(i)).collect();
    // Windows on the rest length: every node whose window [s, s + L/10] fits in L.
    let tol = 1e-9 * m.length;
    let count = s.iter().filter(|&&si| si + delta <= m.length + tol).count();
    let mut out = Fields {
        s_window: s[..count].iter().map(|si| si + 0.5 * delta).collect(),
        s,
        ..Default::default()
    };
    let per_frame = |fr: &Frame| {
        let c = FramedCurve {
            nodes: fr.x.clone(),
            d1: fr.d1.clone(),
            closed: false,
        };
        let top = topology::topology(&c);
        let d = topology::densities_shortened(&c, delta, count);
        let mut row = d.lambda;
        row.resize(count, f64::NAN);
        (top, row)
    };
    let chunk = (rayon::current_num_threads() * 4).max(1);
    for (k, part) in frames.chunks(chunk).enumerate() {
        let done: Vec<_> = part.par_iter().map(per_frame).collect();
        for (fr, (top, row)) in part.iter().zip(done) {
            out.t.push(fr.t);
            out.elevation
                .push(fr.x.iter().map(|x| x[2] - 0.5 * a).collect());
            out.slip.push(
                fr.v.iter()
                    .zip(&fr.normal)
                    .map(|(v, &n)| contact_slip(m, *v, n))
                    .collect(),
            );
            out.tw.push(top.tw);
            out.wr.push(top.wr);
            out.lk.push(top.lk);
            out.lambda.push(row);
        }
        progress(((k + 1) * chunk).min(frames.len()) as f64 / frames.len() as f64);
    }
    out
}

/// The observables of a run, measured on its observation frames ([`Outcome::observed`], module
/// doc), never on the output frames.
pub fn of_outcome(m: &Model, o: &Outcome) -> Observables {
    let fl = fields(m, &o.observed);
    observe(m, &o.observed, &fl)
}

/// Highest elevation in `e` strictly between the first and the last node for which
/// `contact` holds (`-inf` without two contacts): the top of the highest arc.
fn arc_height(e: &[f64], contact: impl Fn(usize) -> bool) -> f64 {
    let first = (0..e.len()).find(|&j| contact(j));
    let last = (0..e.len()).rev().find(|&j| contact(j));
    match (first, last) {
        (Some(i), Some(j)) if j > i + 1 => {
            e[i + 1..j].iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b))
        }
        _ => f64::NEG_INFINITY,
    }
}

/// Scalar observables from the frames and fields.
pub fn observe(m: &Model, frames: &[Frame], fl: &Fields) -> Observables {
    let mut o = Observables::default();
    let (Some(first), Some(last)) = (frames.first(), frames.last()) else {
        return o;
    };
    let centroid = |fr: &Frame| {
        let mut c = [0.0; 3];
        for x in &fr.x {
            c = f::add(c, *x);
        }
        f::scale(c, 1.0 / fr.x.len() as f64)
    };
    let xh = {
        let d = f::sub(first.x[0], *first.x.last().unwrap());
        f::unit([d[0], d[1], 0.0])
    };
    let side = f::cross([0.0, 0.0, 1.0], xh);
    let disp = f::sub(centroid(last), centroid(first));
    let t_end = last.t - first.t;
    o.displacement = [f::dot(disp, xh), f::dot(disp, side)];
    o.displacement_angle_deg = o.displacement[1]
        .abs()
        .atan2(o.displacement[0])
        .to_degrees();
    o.v_s = if t_end > 0.0 {
        o.displacement[0] / t_end
    } else {
        0.0
    };
    let g = &m.gait;
    let has_gait = g.kind != crate::gait::Kind::None && g.couple > 0.0;
    let vm = g.speed;
    o.v_s_over_v_m = if has_gait { o.v_s / vm } else { f64::NAN };
    o.writhe_max = fl.wr.iter().fold(0.0, |a: f64, w| a.max(w.abs()));
    o.writhe_mean = fl.wr.iter().sum::<f64>() / fl.wr.len() as f64;
    (o.writhe_snapshot, o.writhe_snapshot_t) = if has_gait {
        let t_star = (0.5 * m.length - g.centers[1]) / vm;
        frames
            .iter()
            .zip(&fl.wr)
            .min_by(|a, b| (a.0.t - t_star).abs().total_cmp(&(b.0.t - t_star).abs()))
            .map_or((f64::NAN, f64::NAN), |(fr, &w)| (w, fr.t))
    } else {
        (f64::NAN, f64::NAN)
    };
    o.link_max = fl.lk.iter().fold(0.0, |a: f64, w| a.max(w.abs()));
    let a = m.diameter;
    o.max_elevation_over_a = fl
        .elevation
        .iter()
        .flatten()
        .fold(0.0, |x: f64, &e| x.max(e))
        / a;
    o.max_elevation_over_length = o.max_elevation_over_a * a / m.length;
    o.lifted_arcs_max = fl
        .elevation
        .iter()
        .map(|row| runs(row.iter().map(|&e| e >= 0.5 * a)))
        .max()
        .unwrap_or(0);
    if m.ground.is_some() {
        contact_observables(m, frames, fl, &mut o);
    }
    pulse_observables(m, frames, fl, has_gait, &mut o);
    (o.regime, o.regime_reason) = classify(&o.regime_inputs());
    o
}

/// The contact observables of a run on the ground: the share of frames with two contact
/// patches, the arcs' lift, the median slip of the nodes in contact (a node is in contact when
/// it carries more than a millionth of its weight).
fn contact_observables(m: &Model, frames: &[Frame], fl: &Fields, o: &mut Observables) {
    let in_contact = |n: f64| m.in_contact(n);
    let (a, vm) = (m.diameter, m.gait.speed);
    let mut two = 0;
    let mut slips = Vec::new();
    for (k, fr) in frames.iter().enumerate() {
        if runs(fr.normal.iter().map(|&n| in_contact(n))) >= 2 {
            two += 1;
        }
        for (i, &n) in fr.normal.iter().enumerate() {
            if in_contact(n) && k > 0 {
                slips.push(fl.slip[k][i]);
            }
        }
    }
    o.two_patch_fraction = two as f64 / frames.len() as f64;
    o.two_arc_lift_over_a = frames
        .iter()
        .zip(&fl.elevation)
        .map(|(fr, e)| two_arc_height(e, |j| in_contact(fr.normal[j])))
        .fold(0.0, f64::max)
        / a;
    o.arc_lift_max_over_a = frames
        .iter()
        .zip(&fl.elevation)
        .map(|(fr, e)| arc_height(e, |j| in_contact(fr.normal[j])))
        .fold(0.0, f64::max)
        / a;
    o.contact_slip_over_v_m = median(slips) / vm;
}

/// The lambda pulse (its speed, straightness and amplitude variation) and the middle
/// segment's slip, measured while the whole triplet is inside the body (`has_gait`: the scene
/// has muscles).
fn pulse_observables(
    m: &Model,
    frames: &[Frame],
    fl: &Fields,
    has_gait: bool,
    o: &mut Observables,
) {
    let in_contact = |n: f64| m.in_contact(n);
    let (g, vm) = (&m.gait, m.gait.speed);
    // The lambda pulse and the middle segment, while the whole triplet is inside the body
    // (after the ramp, before couple c's centre is within 2 sigma of the tail). The pulse is
    // the lobe of lambda with the sign of its largest magnitude over that interval; its peak
    // is tracked frame by frame.
    let period = g.pulse_time(m.length);
    let t_lo = g.ramp_time + 0.05 * period;
    let t_hi = ((m.length - g.centers.iter().fold(0.0f64, |a, &c| a.max(c)) - 2.0 * g.sigma) / vm)
        .min(period);
    let window = |t: f64| has_gait && t >= t_lo && t <= t_hi;
    let mut sign = 0.0;
    let mut best = 0.0;
    for (k, fr) in frames.iter().enumerate() {
        if window(fr.t) {
            for &l in &fl.lambda[k] {
                if l.is_finite() && l.abs() > best {
                    best = l.abs();
                    sign = l.signum();
                }
            }
        }
    }
    let (mut ts, mut ss, mut amps, mut mids) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (k, fr) in frames.iter().enumerate() {
        if !window(fr.t) {
            continue;
        }
        let row = &fl.lambda[k];
        if let Some((j, amp)) = row
            .iter()
            .enumerate()
            .filter(|(_, l)| l.is_finite())
            .map(|(j, l)| (j, sign * l))
            .max_by(|a, b| a.1.total_cmp(&b.1))
        {
            ts.push(fr.t);
            ss.push(fl.s_window[j]);
            amps.push(amp);
        }
        let (sa, sc) = (g.centers[0] + vm * fr.t, g.centers[2] + vm * fr.t);
        let (lo, hi) = (sa.min(sc), sa.max(sc));
        let v: Vec<f64> = (0..fr.x.len())
            .filter(|&i| fl.s[i] > lo && fl.s[i] < hi && in_contact(fr.normal[i]))
            .map(|i| fl.slip[k][i])
            .collect();
        mids.push(if v.is_empty() {
            f64::INFINITY
        } else {
            v.iter().sum::<f64>() / v.len() as f64
        });
    }
    if ts.len() >= 3 {
        let n = ts.len() as f64;
        let mt = ts.iter().sum::<f64>() / n;
        let ms = ss.iter().sum::<f64>() / n;
        let stt: f64 = ts.iter().map(|t| (t - mt).powi(2)).sum();
        let sts: f64 = ts.iter().zip(&ss).map(|(t, s)| (t - mt) * (s - ms)).sum();
        let sss: f64 = ss.iter().map(|s| (s - ms).powi(2)).sum();
        o.lambda_pulse_speed = sts / stt;
        o.lambda_pulse_speed_over_v_m = o.lambda_pulse_speed / vm;
        o.lambda_pulse_r2 = if sss > 0.0 {
            sts * sts / (stt * sss)
        } else {
            0.0
        };
        let amax = amps.iter().fold(0.0, |a: f64, &b| a.max(b));
        let amin = amps.iter().fold(f64::INFINITY, |a: f64, &b| a.min(b));
        o.lambda_amplitude_variation = (amax - amin) / amax;
    } else {
        o.lambda_pulse_speed = f64::NAN;
        o.lambda_pulse_speed_over_v_m = f64::NAN;
        o.lambda_pulse_r2 = f64::NAN;
        o.lambda_amplitude_variation = f64::NAN;
    }
    o.middle_static_fraction = if mids.is_empty() {
        f64::NAN
    } else {
        mids.iter().filter(|&&v| v < 0.1 * vm).count() as f64 / mids.len() as f64
    };
    o.middle_slip_over_v_m = median(mids) / vm;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_arcs_need_a_contact_between_them() {
        // Two bends, 3 and 2 high, the middle node on the ground.
        let e = [0.0, 3.0, 1.0, 0.0, 2.0, 0.0];
        let on = |j: usize| e[j] == 0.0;
        assert_eq!(two_arc_height(&e, on), 2.0);
        // A single arc with a dip in its top is one arc: no contact inside it.
        let e = [0.0, 3.0, 2.9, 3.0, 0.0];
        let on = |j: usize| e[j] == 0.0;
        assert_eq!(two_arc_height(&e, on), f64::NEG_INFINITY);
        // Lifted head and tail around a contact patch.
        let e = [1.5, 0.0, 0.0, 0.7];
        let on = |j: usize| e[j] == 0.0;
        assert_eq!(two_arc_height(&e, on), 0.7);
        // No contact.
        assert_eq!(two_arc_height(&[1.0, 2.0], |_| false), f64::NEG_INFINITY);
    }

    #[test]
    fn an_arc_lies_between_two_contacts() {
        // A tail tip standing up (6) beyond the last contact is not an arc; the arc is 3 high.
        let e = [0.5, 0.0, 3.0, 1.0, 0.0, 0.0, 2.0, 6.0];
        let on = |j: usize| e[j] == 0.0;
        assert_eq!(arc_height(&e, on), 3.0);
        // One contact patch: the lifted ends are no arcs.
        let e = [4.0, 0.0, 0.0, 5.0];
        let on = |j: usize| e[j] == 0.0;
        assert_eq!(arc_height(&e, on), f64::NEG_INFINITY);
        assert_eq!(arc_height(&[1.0, 2.0], |_| false), f64::NEG_INFINITY);
    }
}
