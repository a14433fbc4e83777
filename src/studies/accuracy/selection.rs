//! The accuracy selection: the model chosen for a target error (`studies::accuracy` owns it; the
//! command line and the studies' `[accuracy]` call it). Runs that ask for an accuracy
//! (`slither run PROBLEM.toml --accuracy 0.01`, or `[accuracy] target`): refine the time
//! resolution and the mesh, Richardson-style, until the estimated relative error of `v_s/v_m`
//! from time and from mesh is below the target, and stop there.
//!
//! **Time resolution** ([`Resolution`]) follows the file's `[solver] integrator` and
//! `[time] adaptive`: adaptive BDF2 (`"bdf2"` with `adaptive = true`) is refined by dividing
//! the error tolerance by ten; every other file (implicit Euler, the default; explicit; BDF2 at
//! fixed steps, as the bundled S-start) by implicit Euler from the file's `dt`, refined by
//! halving it. Fixed-step BDF2 is not refined as BDF2 because its value scatters between
//! neighbouring steps (see "Why implicit Euler is the default" below).
//!
//! **Estimates** ([`PairEstimate`]). The error of a model (`N` elements, resolution `h`) is
//! estimated from its own two pairs: the time pair (`N`, one refinement coarser than `h`) and
//! the mesh pair (`N/2`, `h`). Each part bounds its error if the error shrinks at least at
//! first order from here on (by 1/2 per halving of the step or the element length; by
//! `10^(-2/3)` per decade of BDF2's tolerance, whose global error goes as `tol^(2/3)`): it is
//! the geometric tail of an envelope, the larger of the last difference, the difference before
//! it carried one refinement further (when run: `N` two refinements coarser; `N/4`) and, for
//! time, the same time pair on `N/2` elements. Observed rates are reported, never used for the
//! bound: on the S-start they range from order 0.5 to 2.6. Differences that grow from one pair
//! to the next are not converging: such a model never meets a target.
//!
//! 1. **The step to start from**, on the file's mesh `N0`: the coarsest resolution (from the
//!    file's) whose next refinement moves `v_s/v_m` by at most half the target, the two
//!    differences shrinking (at most [`Resolution::max_refinements`] refinements). This only
//!    steers the search: the coarse mesh's own time error is not the fine meshes' (the
//!    50-element S-start moves by up to 1 % between any two steps below 5e-4 s, while 200
//!    elements move by 0.09 % from 5e-4 to 2.5e-4 s).
//! 2. **The model** (`N`, `h`) from `2 N0` and that step, with the runs its estimates need:
//!    itself, (`N`, 2h), (`N/2`, h), (`N/2`, 2h) and (`N/4`, h). When its time and mesh
//!    estimates add up to at most the target, it is the answer. Otherwise the next model is
//!    the cheapest move whose estimates, each shrunk at the bound's rate, would meet the
//!    target: halve the step, double the mesh, or both. When none would, the part with the
//!    larger estimate is refined: the step while the time estimate is above half the target
//!    and at least the mesh's, else the mesh (up to `[accuracy] max_elements`; the step down
//!    to `max_refinements`). With both at their limits the last model is the
//!    answer, with `met = false`; when a refined model's run fails, or a run of its pairs, the
//!    previous model is (a failed run's pair estimates nothing: infinite, untrusted). Every
//!    run is made once: a refined model reuses the runs it shares with the previous ones.
//! 3. `summary.json` carries the estimates, the observed orders, the chosen model, every run,
//!    the probes' wall time (every run but the chosen one) and all runs' wall time
//!    ([`crate::output::AccuracyReport`]), and the Richardson extrapolation of `v_s/v_m` to the
//!    limits of time and mesh refinement with its uncertainty (the bound plus the correction:
//!    its interval contains the answer's).
//!
//! **Which value is the answer.** The chosen run's `v_s/v_m`, the finest model run: it is a
//! simulated motion that every other output (frames, kymographs, topology) describes, and its
//! error is bounded by the estimate under the stated assumption. The extrapolation is often
//! closer to the converged number, but it is not a simulated state and its interval rests on
//! monotone convergence, which contact scenes do not always show, so it is reported beside the
//! answer, not in its place.
//!
//! **Why implicit Euler is the default.** On gait scenes with stick-slip, BDF2 at fine steps
//! is sensitive: any perturbation (the step, the tolerance, the 7th digit of a friction
//! coefficient) moves the S-start's v_s/v_m with a standard deviation of 1.3 % (README, "Time
//! stepping"), so a BDF2 difference `d` of that size is scatter, not a smooth error. Measured
//! on the S-start with target 0.01 and adaptive BDF2: estimated 0.86 %, actual 2.2 % against
//! BDF2 at a fixed 2.5e-4 s on the chosen 100-element mesh. Implicit Euler is deterministic
//! at the steps the selection visits (perturbations of 1e-7 leave 6 digits unchanged), so its
//! estimates are reproducible; it is not monotone in the step on the S-start either (README),
//! and the measured estimate and actual error are in the guide's "Speed against accuracy".

use crate::model::Model;
use crate::output::{AccuracyReport, AccuracyRun};
use crate::problem::{IntegratorKind, Problem};
use crate::sim::Outcome;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The time resolution of a model: fixed implicit Euler steps or adaptive BDF2's tolerance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Resolution {
    /// Implicit Euler at fixed steps of this size (s).
    Step(f64),
    /// Adaptive BDF2 at this error tolerance (fraction of L per step).
    Tolerance(f64),
}

impl Resolution {
    /// The resolution the selection starts from for `p`: adaptive BDF2 at the file's
    /// tolerance (or the default) when `[solver] integrator = "bdf2"` with `[time] adaptive`,
    /// else implicit Euler at the file's `dt`.
    pub fn of(p: &Problem) -> Self {
        match p.solver.integrator {
            IntegratorKind::Bdf2 if p.time.adaptive => Resolution::Tolerance(
                p.time
                    .error_tolerance
                    .unwrap_or(crate::problem::time::DEFAULT_TOLERANCE),
            ),
            _ => Resolution::Step(p.time.dt.unwrap_or(1e-3)),
        }
    }

    /// The resolution recorded as a step or a tolerance (exactly one of them; `None`
    /// otherwise).
    pub fn from_parts(dt: Option<f64>, tolerance: Option<f64>) -> Option<Self> {
        match (dt, tolerance) {
            (Some(h), None) => Some(Resolution::Step(h)),
            (None, Some(t)) => Some(Resolution::Tolerance(t)),
            _ => None,
        }
    }

    /// The next finer resolution: half the step, a tenth of the tolerance.
    pub fn refined(self) -> Self {
        match self {
            Resolution::Step(h) => Resolution::Step(0.5 * h),
            Resolution::Tolerance(t) => Resolution::Tolerance(0.1 * t),
        }
    }

    /// Ratio of the errors of a resolution and the next finer one: 2 for implicit Euler's
    /// first order in the step, `10^(2/3)` for adaptive BDF2's global error `tol^(2/3)`.
    pub fn error_ratio(self) -> f64 {
        match self {
            Resolution::Step(_) => 2.0,
            Resolution::Tolerance(_) => 10f64.powf(2.0 / 3.0),
        }
    }

    /// Most refinements below the file's resolution: 5 halvings of the step (2e-3 s to
    /// 6.25e-5 s), 3 decades of the tolerance.
    pub fn max_refinements(self) -> usize {
        match self {
            Resolution::Step(_) => 5,
            Resolution::Tolerance(_) => 3,
        }
    }

    /// `"implicit"` or `"bdf2-adaptive"`.
    pub fn integrator(self) -> &'static str {
        match self {
            Resolution::Step(_) => "implicit",
            Resolution::Tolerance(_) => "bdf2-adaptive",
        }
    }

    /// The step (implicit Euler).
    pub fn dt(self) -> Option<f64> {
        match self {
            Resolution::Step(h) => Some(h),
            Resolution::Tolerance(_) => None,
        }
    }

    /// The error tolerance (adaptive BDF2).
    pub fn tolerance(self) -> Option<f64> {
        match self {
            Resolution::Step(_) => None,
            Resolution::Tolerance(t) => Some(t),
        }
    }
}

impl std::fmt::Display for Resolution {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Resolution::Step(h) => write!(f, "implicit Euler, dt {h:.3e} s"),
            Resolution::Tolerance(t) => write!(f, "adaptive BDF2, tolerance {t:.0e}"),
        }
    }
}

/// The error estimates of one refinement pair: runs `a` (coarser) and `b` (finer, one
/// refinement further) with relative difference `d = |b - a| / |b|`; `d_prev` the difference
/// of the pair one refinement coarser in the same direction, and `d_beside` the difference of
/// the same refinement on the next coarser mesh (time pairs only), when they were run.
///
/// **The bound.** From here on the error shrinks by at least the factor `slowest` per
/// refinement (1/2: first order in the step or the element length, the method's lowest formal
/// order). The finer run's error is then at most the geometric tail
/// `D slowest / (1 - slowest)` (`D` itself at 1/2) of the envelope
/// `D = max(d, slowest d_prev, d_beside)`, and the coarser run's at most `d` more. At second
/// order the finer run's actual error is `d/3`, so where the last difference is the envelope
/// the bound is at most three times the error for rates between first and second order.
///
/// Why the envelope (measured on the S-start, the guide's "Speed against accuracy"): contacts
/// land and lift node by node and the step decides between stick-slip outcomes, so successive
/// differences shrink irregularly, and a last difference can be small by a cancellation. At
/// 100 elements the steps 1e-3 and 5e-4 s differ by 0.04 % while the model errs by 1.4 %; at
/// 400 elements 5e-4 and 2.5e-4 s by 0.09 % and 200 and 400 elements by 0.14 % while it errs
/// by up to 0.28 %: the last pairs alone fall below the error, the envelope does not. The
/// previous difference is carried one refinement further at the bound's rate; the time
/// difference beside (same steps, half the elements) at full size, since the time error does
/// not shrink with the mesh. An observed rate faster than first order is never used (the
/// S-start's 25/50/100-element differences shrink at order 2.3 and then 0.5), nor a slower
/// one (the order 0.5 of 50/100/200 elements at 2.5e-4 s is followed by order 2.6 from 200
/// to 400 elements); both are reported ([`PairEstimate::order`]).
///
/// A pair with a failed run (value NaN) has an infinite, untrusted estimate.
///
/// A pair whose difference is not smaller than the previous pair's (`ratio >= 1`) is not
/// converging yet: it is marked untrusted, and the selection never accepts it as meeting a
/// target.
///
/// **Extrapolation** (Richardson, where the runs allow it). When a previous pair moved the
/// same way (the convergence looks monotone), the last difference is the envelope (no larger
/// difference before or beside it) and the error shrinks at a rate between
/// `min(ratio, fastest)` and the bound's, the limit lies between `b + s t_fast` and
/// `b + s t_bound` (`s` the sign of `b - a`, `t` the tails): [`PairEstimate::correction`] moves
/// `b` to the middle of that interval. Otherwise (no previous pair, differences that change
/// sign, do not shrink, or are irregular) the direction of the remaining error is unknown and
/// the correction is 0. [`PairEstimate::spread`] is `|b|` times the bound plus the correction's
/// size: the extrapolation's interval contains the answer's, because monotone-looking
/// differences can still turn (the 1 s serpenoid's mesh differences at 2e-3 s are +, + from 10
/// to 40 elements and then change sign, and the limit lies outside the one-sided interval from
/// 40 elements; at 400 elements the S-start's at 2.5e-4 s keep their sign, +1.19, +0.85,
/// +0.14 %, and the limit lies below the 400-element value).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairEstimate {
    /// Estimated relative error of the coarser run.
    pub coarse: f64,
    /// Estimated relative error of the finer run.
    pub fine: f64,
    /// Signed correction from the finer run's value to the extrapolated limit (absolute).
    pub correction: f64,
    /// Half-width of the extrapolation's interval of limits (absolute): the bound plus the
    /// correction's size.
    pub spread: f64,
    /// Observed ratio of this pair's difference to the previous pair's (`None` without one).
    pub ratio: Option<f64>,
    /// Whether the differences shrink (always true without a previous pair).
    pub trusted: bool,
}

impl PairEstimate {
    /// The estimates of the pair `a` (coarser), `b` (finer); `previous` the signed relative
    /// difference `(b' - a') / |b'|` of the pair one refinement coarser, when it was run;
    /// `beside` the relative difference of the same refinement on the next coarser mesh
    /// (time pairs), when it was run; `slowest` and `fastest` the slowest and fastest rates of
    /// error decrease per refinement assumed (see the type's doc).
    pub fn new(
        a: f64,
        b: f64,
        previous: Option<f64>,
        beside: Option<f64>,
        slowest: f64,
        fastest: f64,
    ) -> Self {
        if !(a.is_finite() && b.is_finite()) {
            // A failed run (its value is NaN) estimates nothing: an unknown error, never met.
            return PairEstimate {
                coarse: f64::INFINITY,
                fine: f64::INFINITY,
                correction: 0.0,
                spread: f64::INFINITY,
                ratio: None,
                trusted: false,
            };
        }
        let signed = (b - a) / b.abs();
        let d = signed.abs();
        let ratio = previous.map(|dp| {
            if dp != 0.0 {
                d / dp.abs()
            } else if d > 0.0 {
                f64::INFINITY
            } else {
                0.0
            }
        });
        let trusted = ratio.is_none_or(|q| q < 1.0);
        let tail = |r: f64, x: f64| x * r / (1.0 - r);
        let envelope = d
            .max(slowest * previous.map_or(0.0, f64::abs))
            .max(beside.map_or(0.0, f64::abs));
        let bound = tail(slowest, envelope);
        // One-sided only where the last difference is the envelope: a larger earlier or
        // neighbouring difference means the convergence is irregular, its direction unknown.
        let monotone = trusted && previous.is_some_and(|dp| dp * signed > 0.0) && envelope <= d;
        let correction = if monotone {
            let fast = tail(fastest.min(ratio.unwrap_or(fastest)), d);
            (b - a).signum() * b.abs() * 0.5 * (bound + fast)
        } else {
            0.0
        };
        // The extrapolation's interval contains the answer's (b -+ the bound): it is the
        // better guess where convergence is monotone, never a tighter claim.
        let spread = b.abs() * bound + correction.abs();
        PairEstimate {
            coarse: d + bound,
            fine: bound,
            correction,
            spread,
            ratio,
            trusted,
        }
    }

    /// The observed order `-log2(ratio) / log2(refinement)` for a refinement by `factor`
    /// (`None` without a previous pair or when the differences do not shrink).
    pub fn order(&self, factor: f64) -> Option<f64> {
        self.ratio
            .filter(|&q| q > 0.0 && q < 1.0)
            .map(|q| -q.ln() / factor.ln())
    }
}

/// Slowest and fastest assumed rates of error decrease per mesh halving: first and second
/// order in the element length.
pub const MESH_RATES: (f64, f64) = (0.5, 0.25);

impl Resolution {
    /// Slowest and fastest assumed rates of error decrease per refinement: implicit Euler's
    /// first order in the step (1/2), down to 1/4 where a scene's step error is not yet
    /// asymptotic; adaptive BDF2's `tol^(2/3)` (`10^(-2/3)`), down to first order in the
    /// tolerance (1/10).
    pub fn rates(self) -> (f64, f64) {
        match self {
            Resolution::Step(_) => (0.5, 0.25),
            Resolution::Tolerance(_) => (1.0 / self.error_ratio(), 0.1),
        }
    }

    /// The next coarser resolution: twice the step, ten times the tolerance.
    pub fn coarsened(self) -> Self {
        match self {
            Resolution::Step(h) => Resolution::Step(2.0 * h),
            Resolution::Tolerance(t) => Resolution::Tolerance(10.0 * t),
        }
    }

    /// Whether two resolutions are the same (equal within rounding: a tolerance coarsened
    /// and refined again is not bit-identical).
    pub fn same(self, other: Self) -> bool {
        match (self, other) {
            (Resolution::Step(a), Resolution::Step(b))
            | (Resolution::Tolerance(a), Resolution::Tolerance(b)) => {
                (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
            }
            _ => false,
        }
    }

    /// How many refinements below `base` this resolution lies (0 at `base` or coarser).
    pub fn level(self, base: Self) -> usize {
        let (x, b) = match (self, base) {
            (Resolution::Step(x), Resolution::Step(b))
            | (Resolution::Tolerance(x), Resolution::Tolerance(b)) => (x, b),
            _ => return 0,
        };
        ((b / x).ln() / self.factor().ln()).round().max(0.0) as usize
    }

    /// The refinement factor of the resolution (2 for steps, 10 for tolerances).
    pub fn factor(self) -> f64 {
        match self {
            Resolution::Step(_) => 2.0,
            Resolution::Tolerance(_) => 10.0,
        }
    }
}

/// The chosen model and its run.
pub struct Selection {
    /// The chosen model.
    pub model: Model,
    /// Its run.
    pub outcome: Outcome,
    /// The estimates and every run.
    pub report: AccuracyReport,
}

/// `p` with `elements` at the time resolution `r`: implicit Euler at fixed steps, or adaptive
/// BDF2 from the file's `dt`.
pub fn accuracy_problem(p: &Problem, elements: usize, r: Resolution) -> Problem {
    let mut q = p.clone();
    q.rod.elements = elements;
    match r {
        Resolution::Step(h) => {
            q.solver.integrator = IntegratorKind::ImplicitEuler;
            q.time.dt = Some(h);
            q.time.adaptive = false;
            q.time.error_tolerance = None;
            q.time.dt_min = None;
            q.time.dt_max = None;
        }
        Resolution::Tolerance(tol) => {
            q.solver.integrator = IntegratorKind::Bdf2;
            q.time.adaptive = true;
            q.time.error_tolerance = Some(tol);
        }
    }
    q.accuracy = None;
    q
}

/// A selection run: its record, and its model and outcome when it ran in this call (a run
/// read back from a [`Journal`] has neither).
struct Done {
    res: Resolution,
    run: AccuracyRun,
    ran: Option<(Model, Outcome)>,
}

#[path = "selection_journal.rs"]
mod journal;
pub use journal::{Journal, JOURNAL_FILE};
#[path = "selection_runs.rs"]
mod runs;
use runs::{run_missing, simulate};

/// The value of a run already made (`None` when it was not).
fn made(done: &[Done], elements: usize, res: Resolution) -> Option<f64> {
    done.iter()
        .find(|d| d.run.elements == elements && d.res.same(res))
        .map(|d| d.run.v_s_over_v_m)
}

/// Signed relative difference of two runs' values, `(b - a) / |b|`.
fn rel(a: f64, b: f64) -> f64 {
    (b - a) / b.abs()
}

/// The time estimate of the model (`elements`, `res`) from the runs made: the pair ending at
/// it (one refinement coarser in time, same mesh), with the pair before it and the same pair
/// on half the elements, when they were run. `None` when the coarser run was not made.
fn time_estimate(done: &[Done], elements: usize, res: Resolution) -> Option<PairEstimate> {
    let (slow, fast) = res.rates();
    let b = made(done, elements, res)?;
    let a = made(done, elements, res.coarsened())?;
    let previous = made(done, elements, res.coarsened().coarsened())
        .map(|c| rel(c, a))
        .filter(|x| x.is_finite());
    let beside = elements
        .is_multiple_of(2)
        .then(|| {
            let fine = made(done, elements / 2, res)?;
            Some(rel(made(done, elements / 2, res.coarsened())?, fine))
        })
        .flatten()
        .filter(|x| x.is_finite());
    Some(PairEstimate::new(a, b, previous, beside, slow, fast))
}

/// The mesh estimate of the model (`elements`, `res`) from the runs made: the pair ending at
/// it (half the elements, same time resolution), with the pair before when it was run.
/// `None` when the coarser run was not made.
fn mesh_estimate(done: &[Done], elements: usize, res: Resolution) -> Option<PairEstimate> {
    if !elements.is_multiple_of(2) {
        return None;
    }
    let (slow, fast) = MESH_RATES;
    let b = made(done, elements, res)?;
    let a = made(done, elements / 2, res)?;
    let previous = if elements.is_multiple_of(4) {
        made(done, elements / 4, res)
            .map(|c| rel(c, a))
            .filter(|x| x.is_finite())
    } else {
        None
    };
    Some(PairEstimate::new(a, b, previous, None, slow, fast))
}

/// Whether a model's time and mesh estimates, both from converging pairs, add up to at most
/// `target`.
fn meets(time: &PairEstimate, mesh: &PairEstimate, target: f64) -> bool {
    time.trusted && mesh.trusted && time.fine + mesh.fine <= target
}

/// Choose the model for `target` (relative error of `v_s/v_m`) and run it; `log` gets one line
/// per run.
pub fn select(
    p: &Problem,
    target: f64,
    max_elements: usize,
    log: &mut dyn FnMut(&str),
) -> Selection {
    select_with(p, target, max_elements, None, log)
}

/// [`select`] with a [`Journal`]: runs it holds are read back instead of made again, and every
/// run made is appended to it as it finishes. The chosen model, when read back, runs again for
/// its frames (its recorded result is the one reported).
pub fn select_with(
    p: &Problem,
    target: f64,
    max_elements: usize,
    mut journal: Option<&mut Journal>,
    log: &mut dyn FnMut(&str),
) -> Selection {
    let started = std::time::Instant::now();
    let mut done: Vec<Done> = Vec::new();
    let mut run = |wanted: &[(usize, Resolution)], done: &mut Vec<Done>| {
        run_missing(p, wanted, done, journal.as_deref_mut(), log);
    };
    let n0 = p.rod.elements;
    let res0 = Resolution::of(p);
    // 1. The step the mesh refinement starts from, on the file's mesh: the coarsest
    // resolution whose next refinement moves v_s/v_m by at most half the target (a converging
    // pair), within `max_refinements`. Only a search heuristic: every error reported is
    // estimated on the chosen model's own pairs.
    let mut res = res0;
    let mut h = loop {
        let fine = res.refined();
        run(&[(n0, res), (n0, fine)], &mut done);
        let time = time_estimate(&done, n0, fine).expect("the pair was run");
        let (a, b) = (made(&done, n0, res), made(&done, n0, fine));
        let last = rel(a.unwrap_or(f64::NAN), b.unwrap_or(f64::NAN)).abs();
        if (time.trusted && last <= 0.5 * target) || last.is_nan() {
            // (A failed finer run: stay at the last resolution that ran.)
            break res;
        }
        if fine.level(res0) >= res0.max_refinements() {
            break fine;
        }
        res = fine;
    };
    // 2. The model (`n`, `h`) with its two pairs, (n, coarser step) and (n/2, h), from twice
    // the file's mesh: done when its time and mesh estimates meet the target; else refine the
    // part whose estimate is larger (time while it is above half the target and at least the
    // mesh's), within the limits of both.
    let mut n = 2 * n0;
    let mut last_ran: Option<(usize, Resolution)> = None;
    loop {
        // The model, its pairs and, for the envelopes, the time pair on half the elements
        // (usually made already) and the mesh pair before (a quarter of the elements, cheap).
        let mut wanted = vec![
            (n / 2, h),
            (n, h),
            (n, h.coarsened()),
            (n / 2, h.coarsened()),
        ];
        if n.is_multiple_of(4) && n / 4 >= 2 {
            wanted.push((n / 4, h));
        }
        run(&wanted, &mut done);
        if made(&done, n, h).is_none_or(f64::is_nan) {
            // A failed model: the answer is the last one that ran.
            if let Some((m, r)) = last_ran {
                (n, h) = (m, r);
                break;
            }
        }
        let time = time_estimate(&done, n, h).expect("the time pair was run");
        let mesh = mesh_estimate(&done, n, h).expect("the mesh pair was run");
        if !(time.fine.is_finite() && mesh.fine.is_finite()) {
            // A pair's other run failed: as for a failed model, the answer is the last one
            // whose pairs ran.
            if let Some((m, r)) = last_ran {
                (n, h) = (m, r);
                break;
            }
        }
        if meets(&time, &mesh, target) {
            break;
        }
        last_ran = Some((n, h));
        let can_time = h.refined().level(res0) <= res0.max_refinements();
        let can_mesh = 2 * n <= max_elements;
        let (refine_time, refine_mesh) = next_move(&time, &mesh, h, target, can_time, can_mesh);
        if !(refine_time || refine_mesh) {
            break;
        }
        if refine_time {
            h = h.refined();
        }
        if refine_mesh {
            n *= 2;
        }
    }
    let (n_c, res_c) = (n, h);
    let time = time_estimate(&done, n_c, res_c).expect("the time pair was run");
    let mesh = mesh_estimate(&done, n_c, res_c).expect("the mesh pair was run");
    let runs: Vec<AccuracyRun> = done.iter().map(|d| d.run.clone()).collect();
    let wall_time_total_s: f64 = runs.iter().map(|r| r.wall_time_s).sum();
    let k = done
        .iter()
        .position(|d| d.run.elements == n_c && d.res.same(res_c))
        .expect("the chosen model was run");
    let chosen = done.swap_remove(k);
    let chosen_wall = chosen.run.wall_time_s;
    let (model, outcome) = match chosen.ran {
        Some(mo) => mo,
        None => {
            log(&format!(
                "accuracy: {} elements, {}: read back from the journal; running it again for its frames",
                chosen.run.elements, chosen.res
            ));
            simulate(p, chosen.run.elements, chosen.res)
        }
    };
    // The chosen value plus the signed corrections toward the limits of time and mesh
    // refinement; its uncertainty the half-widths of the two intervals of limits.
    let v_extrapolated = chosen.run.v_s_over_v_m + time.correction + mesh.correction;
    let uncertainty = time.spread + mesh.spread;
    let estimated = time.fine + mesh.fine;
    Selection {
        report: AccuracyReport {
            target,
            integrator: res_c.integrator().into(),
            elements: n_c,
            dt: res_c.dt(),
            error_tolerance: res_c.tolerance(),
            time_error: time.fine,
            time_error_elements: n_c,
            mesh_error: mesh.fine,
            estimated_error: estimated,
            met: meets(&time, &mesh, target),
            time_order_observed: time.order(res_c.factor()),
            mesh_order_observed: mesh.order(2.0),
            v_s_over_v_m_extrapolated: v_extrapolated,
            v_s_over_v_m_extrapolated_uncertainty: uncertainty,
            runs,
            probes_wall_time_s: wall_time_total_s - chosen_wall,
            wall_time_total_s,
            elapsed_s: started.elapsed().as_secs_f64(),
        },
        model,
        outcome,
    }
}

/// The next refinement of the model at step `h` whose estimates are `time` and `mesh`:
/// (refine the step, refine the mesh). The cheapest move whose estimates, each shrinking at
/// the bound's rate, would meet the target; else the part with the larger estimate (time
/// while it is above half the target and at least the mesh's), within the limits
/// (`can_time`, `can_mesh`). (false, false): no move left.
fn next_move(
    time: &PairEstimate,
    mesh: &PairEstimate,
    h: Resolution,
    target: f64,
    can_time: bool,
    can_mesh: bool,
) -> (bool, bool) {
    let (rt, rm) = (h.rates().0, MESH_RATES.0);
    let (et, em) = (time.fine, mesh.fine);
    // (refine the step, refine the mesh, predicted estimate), cheapest first.
    let moves = [
        (true, false, rt * et + em),
        (false, true, et + rm * em),
        (true, true, rt * et + rm * em),
    ];
    let predicted = moves
        .iter()
        .find(|&&(t, m, e)| (can_time || !t) && (can_mesh || !m) && e <= target);
    match predicted {
        Some(&(t, m, _)) => (t, m),
        None => {
            let time_first = et > 0.5 * target && et >= em;
            if can_time && (time_first || !can_mesh) {
                (true, false)
            } else {
                (false, can_mesh)
            }
        }
    }
}
