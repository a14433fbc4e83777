//! The accuracy selection: the model chosen for a target error (`design` owns it; the
//! command line and the studies' `[accuracy]` call it). Runs that ask for an accuracy
//! (`slither run PROBLEM.toml --accuracy 0.01`, or `[accuracy] target`): refine the time
//! resolution and the mesh, Richardson-style, until the estimated relative error of `v_s/v_m`
//! from time and from mesh is below the target, and keep the cheapest model that meets it.
//!
//! **Time resolution** ([`Resolution`]) follows the file's `[solver] integrator`: implicit
//! Euler (the default, and for an explicit file) at fixed steps, refined by halving `dt`;
//! `"bdf2"` as adaptive BDF2, refined by dividing the error tolerance by ten.
//!
//! **Estimates** ([`PairEstimate`]). Every estimate comes from a pair of runs one refinement
//! apart, difference `d` (relative). It assumes the error shrinks per refinement at least as
//! fast as first order does (by 1/2 per halving of the step or the element length; by
//! `10^(-2/3)` per decade of BDF2's tolerance, whose global error goes as `tol^(2/3)`), or at
//! the slower rate the runs show when a third run is there: the finer run errs by at most the
//! geometric tail (`d` at first order), the coarser by `d` more. At second order the finer
//! run's actual error is `d/3`: where a scene's rates lie between first and second order the
//! estimate bounds the error and is at most three times it. The mesh estimate used to assume
//! second order (`d/3`), and on the S-start, whose mesh differences shrink at observed orders
//! from 0.5 to 2.3 (contacts at nodes), it fell below the actual error. Differences that do not
//! shrink from one pair to the next are not converging: such a pair is never accepted.
//!
//! 1. **Time.** At the mesh `N` (first the file's), runs at the current resolution and the
//!    next finer one. The coarser is kept when its estimate is at most `target/2`, else the
//!    finer when its estimate is; otherwise the pair moves one refinement down (at most
//!    [`Resolution::max_refinements`] times).
//! 2. **Mesh.** At that resolution, runs at `N` and `2N` (from `N/2` and `N` when `N` is
//!    already refined). `N` is kept when `e_time + e(N) <= target`, else `2N` when `e_time +
//!    e(2N) <= target`, else the pair moves to `2N, 4N` (up to `[accuracy] max_elements`).
//! 3. **Again on the chosen mesh.** The time error of step 1 was measured on the mesh of that
//!    round; when step 2 chose another mesh, steps 1 and 2 run again from there, step 2 now
//!    choosing that mesh or a finer one (at most [`MAX_ROUNDS`] rounds), so the time estimate
//!    is the chosen mesh's own (`time_error_elements` reports where it was measured). On the
//!    S-start this matters: 50 elements at 5e-4 s look converged in time (0.14 % to 2.5e-4 s)
//!    while 100 elements at 5e-4 s still move 0.45 %. Every run is made once: later rounds
//!    reuse earlier runs, and a run one refinement coarser than a pair, when it was made,
//!    supplies that pair's observed rate.
//! 4. The chosen model's run (already made) is the result; `summary.json` carries the
//!    estimates, the observed orders, the chosen model and every run
//!    ([`crate::output::AccuracyReport`]), their total wall time, and the Richardson
//!    extrapolation of `v_s/v_m` to the limits of time and mesh refinement with its
//!    uncertainty (the middle and half-width of the interval of limits that rates between
//!    first and second order, or the observed slower rate, allow).
//!
//! **Which value is the answer.** The chosen run's `v_s/v_m`: it is a simulated motion that
//! every other output (frames, kymographs, topology) describes, and its error is bounded by
//! the estimate under the stated assumption. The extrapolation is often closer to the
//! converged number, but its error cannot be bounded from the same runs as tightly (its
//! uncertainty is the spread of the orders, and on contact scenes the order itself is
//! irregular), so it is reported beside the answer, not in its place.
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

/// Most rounds of (time, mesh) refinement: a round whose mesh stage changes the mesh is
/// followed by one that measures the time error again on the new mesh.
pub const MAX_ROUNDS: usize = 3;

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
    /// tolerance (or the default) when `[solver] integrator = "bdf2"`, else implicit Euler at
    /// the file's `dt`.
    pub fn of(p: &Problem) -> Self {
        match p.solver.integrator {
            IntegratorKind::Bdf2 => Resolution::Tolerance(
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
/// refinement further) with relative difference `d = |b - a| / |b|`.
///
/// **The assumption.** The error shrinks by at least the factor `slowest` per refinement
/// (1/2: at least first order in the step or the element length), unless the runs show a
/// slower rate: with a previous pair (one refinement coarser, difference `d_prev`), the
/// observed ratio `rho_obs = d / d_prev` replaces `slowest` when it is larger. The finer run's
/// error is then at most the geometric tail `d rho / (1 - rho)` (`d` at `rho = 1/2`) and the
/// coarser run's at most `d` more. When the error in fact shrinks at the formal rate of a
/// second-order discretization (`rho = 1/4`) the finer run's error is `d/3`, so the estimate
/// is at most three times the error wherever the true rate lies between 1/4 and 1/2.
///
/// A pair whose difference is not smaller than the previous pair's (`rho_obs >= 1`) is not
/// converging yet: it is marked untrusted and its estimate uses `rho = 0.9` (nine times
/// `d`), which the selection never accepts as meeting a target.
///
/// **Extrapolation** (Richardson, where the runs allow it). When a previous pair moved the
/// same way (the convergence looks monotone) and the error shrinks at a rate between
/// `min(rho_obs, fastest)` and `rho`, the limit lies between `b + s t_fast` and `b + s t_slow`
/// (`s` the sign of `b - a`, `t` the tails at those rates):
/// [`PairEstimate::correction`] is the middle of that interval and [`PairEstimate::spread`]
/// its half-width. Without a previous pair, when the differences change sign or when they do
/// not shrink, the direction of the remaining error is unknown: the interval is
/// `b -+ t_slow`, correction 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairEstimate {
    /// Estimated relative error of the coarser run.
    pub coarse: f64,
    /// Estimated relative error of the finer run.
    pub fine: f64,
    /// Signed correction from the finer run's value to the extrapolated limit (absolute).
    pub correction: f64,
    /// Half-width of the interval of limits (absolute).
    pub spread: f64,
    /// Observed ratio of this pair's difference to the previous pair's (`None` without one).
    pub ratio: Option<f64>,
    /// Whether the differences shrink (always true without a previous pair).
    pub trusted: bool,
}

/// Largest rate of error decrease an estimate uses: an untrusted pair's.
const RATE_CAP: f64 = 0.9;

impl PairEstimate {
    /// The estimates of the pair `a` (coarser), `b` (finer); `previous` the signed relative
    /// difference `(b' - a') / |b'|` of the pair one refinement coarser, when it was run;
    /// `slowest` and `fastest` the slowest and fastest rates of error decrease per refinement
    /// assumed (see the type's doc).
    pub fn new(a: f64, b: f64, previous: Option<f64>, slowest: f64, fastest: f64) -> Self {
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
        let rho = ratio.map_or(slowest, |q| q.max(slowest)).min(RATE_CAP);
        let tail = |r: f64| d * r / (1.0 - r);
        let slow = tail(rho);
        let monotone = trusted && previous.is_some_and(|dp| dp * signed > 0.0);
        let (correction, spread) = if monotone {
            let fast = tail(fastest.min(ratio.unwrap_or(fastest)));
            let s = (b - a).signum() * b.abs();
            (s * 0.5 * (slow + fast), b.abs() * 0.5 * (slow - fast))
        } else {
            (0.0, b.abs() * slow)
        };
        PairEstimate {
            coarse: d + slow,
            fine: slow,
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
            q.solver.integrator = IntegratorKind::Implicit;
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

struct Done {
    elements: usize,
    res: Resolution,
    v: f64,
    model: Model,
    outcome: Outcome,
}

/// The value of a run already made (`None` when it was not).
fn made(done: &[Done], elements: usize, res: Resolution) -> Option<f64> {
    done.iter()
        .find(|d| d.elements == elements && d.res == res)
        .map(|d| d.v)
}

/// Signed relative difference of two runs' values, `(b - a) / |b|`.
fn rel(a: f64, b: f64) -> f64 {
    (b - a) / b.abs()
}

/// What one stage (time or mesh) chose: whether the coarser member of its last pair is the
/// chosen one, the pair's estimates.
#[derive(Clone, Copy)]
struct Stage {
    coarse: bool,
    est: PairEstimate,
    /// The finer member's value minus the coarser's.
    diff: f64,
}

impl Stage {
    /// Estimated relative error of the chosen member.
    fn error(&self) -> f64 {
        if self.coarse {
            self.est.coarse
        } else {
            self.est.fine
        }
    }
    /// Signed correction from the chosen member's value to the extrapolated limit.
    fn correction(&self) -> f64 {
        self.est.correction + if self.coarse { self.diff } else { 0.0 }
    }
}

/// Choose the model for `target` (relative error of `v_s/v_m`) and run it; `log` gets one line
/// per run.
pub fn select(
    p: &Problem,
    target: f64,
    max_elements: usize,
    log: &mut dyn FnMut(&str),
) -> Selection {
    let mut done: Vec<Done> = Vec::new();
    let mut run = |elements: usize, res: Resolution, done: &mut Vec<Done>| -> f64 {
        if let Some(v) = made(done, elements, res) {
            return v;
        }
        let model = Model::new(&accuracy_problem(p, elements, res));
        let muscles = Box::new(crate::gait::Muscles {
            gait: model.gait.clone(),
        });
        let outcome = crate::sim::run(&model, muscles, &mut |_| {}, &mut |_| {});
        let v = if outcome.error.is_none() {
            speed_ratio(&model, &outcome)
        } else {
            f64::NAN
        };
        log(&format!(
            "accuracy: {elements} elements, {res}: v_s/v_m {v:.5}, {} steps, {:.2} s{}",
            outcome.steps.accepted,
            outcome.wall_time_s,
            outcome
                .error
                .as_ref()
                .map_or(String::new(), |e| format!(" (failed: {e})"))
        ));
        done.push(Done {
            elements,
            res,
            v,
            model,
            outcome,
        });
        v
    };
    let n0 = p.rod.elements;
    let res0 = Resolution::of(p);
    let (t_slow, t_fast) = res0.rates();
    let (x_slow, x_fast) = MESH_RATES;
    let mut n = n0;
    let mut res = res0;
    let mut round = 0;
    let (n_c, res_c, n_time, time, mesh) = loop {
        round += 1;
        // 1. Time, at mesh `n`, from `res`; the pair one refinement coarser, when it was run
        // (an earlier round), gives the observed rate.
        let mut previous = made(&done, n, res.coarsened())
            .map(|c| rel(c, made(&done, n, res).unwrap_or(f64::NAN)));
        let mut refinements = 0;
        let (res_t, time) = loop {
            let fine = res.refined();
            let (a, b) = (run(n, res, &mut done), run(n, fine, &mut done));
            let est = PairEstimate::new(a, b, previous.filter(|x| x.is_finite()), t_slow, t_fast);
            refinements += 1;
            let stage = |coarse| Stage {
                coarse,
                est,
                diff: b - a,
            };
            if est.trusted && est.coarse <= 0.5 * target {
                break (res, stage(true));
            }
            if (est.trusted && est.fine <= 0.5 * target) || refinements >= res0.max_refinements() {
                break (fine, stage(false));
            }
            previous = Some(rel(a, b));
            res = fine;
        };
        let e_time = time.error();
        // 2. Mesh, at `res_t`, from the pair ending at `n` (or starting at the file's mesh),
        // choosing `n` or finer (a coarser mesh than the time error was measured on could
        // have a larger time error).
        let mut m = if n > n0 { n / 2 } else { n0 };
        let mut previous = if m % 2 == 0 {
            made(&done, m / 2, res_t).map(|c| rel(c, made(&done, m, res_t).unwrap_or(f64::NAN)))
        } else {
            None
        };
        let (n_m, mesh) = loop {
            let (a, b) = (run(m, res_t, &mut done), run(2 * m, res_t, &mut done));
            let est = PairEstimate::new(a, b, previous.filter(|x| x.is_finite()), x_slow, x_fast);
            let stage = |coarse| Stage {
                coarse,
                est,
                diff: b - a,
            };
            if est.trusted && m >= n && e_time + est.coarse <= target {
                break (m, stage(true));
            }
            if (est.trusted && e_time + est.fine <= target) || 4 * m > max_elements {
                break (2 * m, stage(false));
            }
            previous = Some(rel(a, b));
            m *= 2;
        };
        // The time estimate holds for the mesh it was measured on: done when that is the
        // chosen one, else measure time again on the chosen mesh.
        if n_m == n || round >= MAX_ROUNDS {
            break (n_m, res_t, n, time, mesh);
        }
        n = n_m;
        res = res_t;
    };
    let runs: Vec<AccuracyRun> = done
        .iter()
        .map(|d| AccuracyRun {
            elements: d.elements,
            dt: d.res.dt(),
            error_tolerance: d.res.tolerance(),
            v_s_over_v_m: d.v,
            steps: d.outcome.steps.accepted,
            wall_time_s: d.outcome.wall_time_s,
            status: d
                .outcome
                .error
                .as_ref()
                .map_or("ok".into(), |e| e.to_string()),
        })
        .collect();
    let wall_time_total_s = runs.iter().map(|r| r.wall_time_s).sum();
    let k = done
        .iter()
        .position(|d| d.elements == n_c && d.res == res_c)
        .expect("the chosen model was run");
    let chosen = done.swap_remove(k);
    // The chosen value plus the signed corrections toward the limits of time and mesh
    // refinement; its uncertainty the half-widths of the two intervals of limits.
    let v_extrapolated = chosen.v + time.correction() + mesh.correction();
    let uncertainty = time.est.spread + mesh.est.spread;
    let estimated = time.error() + mesh.error();
    let trusted = time.est.trusted && mesh.est.trusted;
    Selection {
        report: AccuracyReport {
            target,
            integrator: res_c.integrator().into(),
            elements: n_c,
            dt: res_c.dt(),
            error_tolerance: res_c.tolerance(),
            time_error: time.error(),
            time_error_elements: n_time,
            mesh_error: mesh.error(),
            estimated_error: estimated,
            met: trusted && estimated <= target,
            time_order_observed: time.est.order(res_c.factor()),
            mesh_order_observed: mesh.est.order(2.0),
            v_s_over_v_m_extrapolated: v_extrapolated,
            v_s_over_v_m_extrapolated_uncertainty: uncertainty,
            runs,
            wall_time_total_s,
        },
        model: chosen.model,
        outcome: chosen.outcome,
    }
}

/// `v_s/v_m` of a run by the definition of [`crate::observe`], measured on its first and last
/// frame ([`crate::observe::Measure::Ends`]); NaN without frames.
fn speed_ratio(model: &Model, o: &Outcome) -> f64 {
    if o.observed.is_empty() {
        return f64::NAN;
    }
    let ends = crate::observe::Measure::Ends;
    crate::observe::measure(model, o, ends, &mut |_| {})
        .1
        .v_s_over_v_m
}
