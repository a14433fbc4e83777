//! The work-precision chart of a gait scene (ground, contact, muscles): what does an answer
//! within a given error of the converged `v_s/v_m` cost? The error of `v_s/v_m` (and of the
//! final centreline) against the converged value, mesh and step together, over wall time on
//! log-log axes, one line per method and mesh (implicit Euler over fixed steps, BDF2 over fixed
//! steps, BDF2 with error-controlled steps over tolerances ([`crate::integrator::adaptive`]);
//! by default at the scene's mesh, twice and four times it), each line's points in order of
//! cost, the `--accuracy` selection as one point (its whole wall time, probes included), and a
//! 1 % line. Another code's runs of the same scene can be added as their own series, each
//! against that code's converged value ([`super::external`]).
//!
//! **Reference.** On the finest mesh of the chart: `reference_integrator` (implicit Euler by
//! default) at fixed steps from
//! `reference_dt`, halved until `v_s/v_m` changes by less than `reference_change` (0.1 %)
//! between two successive runs (at most `reference_halvings` halvings); the finest run is the
//! reference. Because gait scenes with stick-slip can respond to the step size by small jumps
//! rather than smoothly, the reference's step is also run `reference_jitter` (4 %) shorter
//! and longer, and the spread of those three values is reported as the reference's scatter:
//! errors below it are not resolved. Implicit Euler is the default because BDF2 at fine steps
//! is sensitive on the S-start (a standard deviation of 1.3 % of v_s/v_m over perturbations
//! of the step or the 7th digit of a friction coefficient; README, "Time stepping"), while
//! implicit Euler down to 3.125e-5 s moves by at most 0.25 % under such perturbations
//! (0.30870 and 0.30829 at 6.25e-5 and 3.125e-5 s on the 50-element S-start). Below that it
//! resolves the fast modes too and scatters like BDF2 (0.30273 at 1.5625e-5 s), so the
//! halving stops there.
//! The reference is cached in `DIR/reference.json` under a hash of the problem and the
//! reference settings, so a second chart of the same scene reuses it.
//!
//! **Errors.** `|v_s/v_m - ref| / ref` (relative) and the largest distance of a real node from
//! the reference's at the final time, over the rod length.

use super::external::{ExternalPoint, ExternalRun};
use super::*;
use crate::observe::{evaluate, measure, Measure, Observed};
use crate::problem::{Adaptive, IntegratorKind};
use crate::sim::Outcome;

/// Settings of the gait work-precision chart (defaults in [`Default`]).
#[derive(Clone, Debug, serde::Serialize)]
pub struct GaitPrecisionOptions {
    /// Meshes (elements) of the runs; the reference runs on the finest. Default (empty): the
    /// scene's mesh, twice and four times it.
    pub meshes: Vec<usize>,
    /// Fixed steps of implicit Euler (s), on every mesh. Default 4e-3, 2e-3, 1e-3, 5e-4.
    pub euler_dt: Vec<f64>,
    /// Fixed steps of BDF2 (s), on every mesh. Default none.
    pub bdf2_dt: Vec<f64>,
    /// Tolerances of adaptive BDF2 (fraction of L per step), on every mesh. Default 1e-4,
    /// 1e-5.
    pub tolerances: Vec<f64>,
    /// Target of the `--accuracy` selection drawn as one point (its chosen run's error, the
    /// wall time of all its runs). Default 0.01; `None`: no point.
    pub accuracy_target: Option<f64>,
    /// First step of adaptive runs (s). Default 2e-3.
    pub adaptive_first_dt: f64,
    /// Integrator of the reference runs. Default implicit Euler.
    pub reference_integrator: IntegratorKind,
    /// Coarsest reference step (s). Default 5e-4.
    pub reference_dt: f64,
    /// Relative change of `v_s/v_m` between successive reference runs that ends the halving.
    /// Default 1e-3.
    pub reference_change: f64,
    /// Most halvings of the reference step. Default 3 (5e-4 to 6.25e-5 s: implicit Euler's
    /// damping of the rod's fast modes fades below that, and with it its insensitivity, e.g.
    /// 0.30273 at 1.5625e-5 s on the 50-element S-start against 0.30829 at 3.125e-5 s).
    pub reference_halvings: usize,
    /// Relative change of the reference step for the scatter runs. Default 0.04.
    pub reference_jitter: f64,
}

impl Default for GaitPrecisionOptions {
    fn default() -> Self {
        GaitPrecisionOptions {
            meshes: Vec::new(),
            euler_dt: vec![4e-3, 2e-3, 1e-3, 5e-4],
            bdf2_dt: Vec::new(),
            tolerances: vec![1e-4, 1e-5],
            accuracy_target: Some(0.01),
            adaptive_first_dt: 2e-3,
            reference_integrator: IntegratorKind::ImplicitEuler,
            reference_dt: 5e-4,
            reference_change: 1e-3,
            reference_halvings: 3,
            reference_jitter: 0.04,
        }
    }
}

/// One run of a gait scene: the measured speed ratio, the final centreline and the cost.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct GaitRun {
    /// How the run sets its time resolution (`implicit`, `bdf2`, `bdf2-adaptive` or
    /// `accuracy` in the files).
    pub method: GaitMethod,
    /// Real elements.
    #[serde(default)]
    pub elements: usize,
    /// Fixed step (s), or the first step of an adaptive run.
    pub dt: f64,
    /// Tolerance of an adaptive run (`None`: fixed steps).
    pub tolerance: Option<f64>,
    /// `v_s / v_m` (NaN when the run failed).
    pub v_ratio: f64,
    /// Wall time of the stepping (s).
    pub wall_s: f64,
    /// Accepted steps.
    pub steps: usize,
    /// Rejected tries (adaptive) or halvings (fixed).
    pub rejected: usize,
    /// Smallest and largest accepted step (s).
    pub dt_range: (f64, f64),
    /// "ok" or the failure.
    pub status: String,
    /// Final real-node positions (m).
    #[serde(skip_serializing_if = "Vec::is_empty", default)]
    pub x: Vec<[f64; 3]>,
}

/// `v_s/v_m` of a run by the definition of [`crate::observe`], measured on its first and last
/// frame ([`Measure::Ends`]); NaN without frames.
pub fn speed_ratio(model: &Model, o: &Outcome) -> f64 {
    if o.observed.is_empty() {
        return f64::NAN;
    }
    measure(model, o, Measure::Ends, &mut |_| {}).1.v_s_over_v_m
}

/// `model` with the given integrator and step; adaptive with `tol` when given.
pub fn variant(model: &Model, kind: IntegratorKind, dt: f64, tol: Option<f64>) -> Model {
    let mut m = model.clone();
    m.solver.integrator = kind;
    m.dt = dt;
    m.adaptive = tol.map(|tolerance| Adaptive {
        tolerance,
        dt_first: dt,
        dt_min: dt * crate::problem::time::DEFAULT_DT_MIN_FRACTION,
        dt_max: crate::problem::time::default_dt_max(dt, m.duration),
    });
    m
}

/// Run `model` (its own integrator and schedule) and measure it ([`evaluate`], the two end
/// frames). An integrator that cannot run the scene (the explicit one has no contact) gives a
/// run with that status and no steps.
pub fn gait_run(model: &Model, method: GaitMethod) -> GaitRun {
    let mut run = GaitRun {
        method,
        elements: model.elements(),
        dt: model.dt,
        tolerance: model.adaptive.map(|a| a.tolerance),
        v_ratio: f64::NAN,
        wall_s: 0.0,
        steps: 0,
        rejected: 0,
        dt_range: (f64::NAN, f64::NAN),
        status: String::new(),
        x: Vec::new(),
    };
    let Observed {
        outcome: o,
        observables,
        ..
    } = match evaluate(model, Measure::Ends, &mut |_| {}, &mut |_| {}) {
        Ok(o) => o,
        Err(e) => {
            run.status = e.to_string();
            return run;
        }
    };
    if o.error.is_none() && !o.frames.is_empty() {
        run.v_ratio = observables.v_s_over_v_m;
    }
    run.wall_s = o.wall_time_s;
    run.steps = o.steps.accepted;
    run.rejected = o.steps.rejected;
    run.dt_range = (o.steps.dt_min, o.steps.dt_max);
    run.status = o.error.as_ref().map_or("ok".into(), |e| e.to_string());
    run.x = model.real.clone().map(|i| o.state.node(i)).collect();
    run
}

/// The cached reference of a gait chart.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct GaitReference {
    /// Hash of the problem and the reference settings (the cache key).
    pub key: String,
    /// The halving runs, coarsest first (the last is the reference).
    pub runs: Vec<GaitRun>,
    /// Relative change of `v_s/v_m` between the last two halving runs.
    pub change: f64,
    /// Whether the change fell below `reference_change`.
    pub converged: bool,
    /// The scatter runs at the reference step times `1 -+ reference_jitter`.
    pub scatter_runs: Vec<GaitRun>,
    /// `(max - min) / reference` of `v_s/v_m` over the reference and its scatter runs.
    pub scatter: f64,
    /// Reference `v_s/v_m`.
    pub v_ratio: f64,
    /// Wall time of all reference runs (s).
    pub wall_s: f64,
}

/// One point of the gait chart.
#[derive(Clone, Debug, serde::Serialize)]
pub struct GaitPoint {
    /// The run.
    #[serde(flatten)]
    pub run: GaitRun,
    /// `|v_s/v_m - ref| / ref`.
    pub v_error: f64,
    /// Largest node distance from the reference's final centreline over L.
    pub x_error: f64,
}

/// The gait work-precision data.
#[derive(Clone, Debug, serde::Serialize)]
pub struct GaitPrecision {
    /// Scene file.
    pub scene: String,
    /// Real elements of the reference (the finest mesh).
    pub elements: usize,
    /// Duration (s).
    pub duration: f64,
    /// Settings.
    pub options: GaitPrecisionOptions,
    /// The reference.
    pub reference: GaitReference,
    /// All runs.
    pub points: Vec<GaitPoint>,
    /// Another code's runs of the same scene, each against its own converged value
    /// ([`super::external`]); empty unless added by [`GaitPrecision::with_external`].
    pub external: Vec<ExternalPoint>,
}

/// FNV-1a, 64 bit: the cache key of a reference (stable across builds, unlike `std`'s hasher).
fn fnv1a(text: &str) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// A run's step as the logs print it: `dt` (already formatted) and, for an adaptive run, its
/// tolerance; a fixed-step run has no tolerance and says "fixed step" instead.
fn step_text(dt: &str, tolerance: Option<f64>) -> String {
    match tolerance {
        Some(tol) => format!("dt {dt} s, tol {tol:.0e}"),
        None => format!("dt {dt} s, fixed step"),
    }
}

fn log_run(log: &mut dyn FnMut(&str), what: &str, r: &GaitRun) {
    log(&format!(
        "{what}: {} {}: v_s/v_m {:.5}, {} steps ({} rejected), {:.2} s ({})",
        r.method,
        step_text(&format!("{:.3e}", r.dt), r.tolerance),
        r.v_ratio,
        r.steps,
        r.rejected,
        r.wall_s,
        r.status
    ));
}

/// Compute the reference (or load it from `cache` when its key matches).
pub fn gait_reference(
    problem: &Problem,
    model: &Model,
    opts: &GaitPrecisionOptions,
    cache: Option<&Path>,
    log: &mut dyn FnMut(&str),
) -> Result<GaitReference, ChartError> {
    let key = fnv1a(&format!(
        "{problem:?}|{}|{}|{}|{}|{:?}",
        opts.reference_dt,
        opts.reference_change,
        opts.reference_halvings,
        opts.reference_jitter,
        opts.reference_integrator
    ));
    if let Some(path) = cache {
        if let Ok(text) = std::fs::read_to_string(path) {
            if let Ok(r) = serde_json::from_str::<GaitReference>(&text) {
                if r.key == key && r.runs.last().is_some_and(|x| !x.x.is_empty()) {
                    log(&format!("reference from {} (cached)", path.display()));
                    return Ok(r);
                }
            }
        }
    }
    let kind = opts.reference_integrator;
    // The reference's runs are labelled implicit Euler unless they are BDF2's.
    let name = match kind {
        IntegratorKind::Bdf2 => GaitMethod::Fixed(IntegratorKind::Bdf2),
        _ => GaitMethod::Fixed(IntegratorKind::ImplicitEuler),
    };
    let mut runs: Vec<GaitRun> = Vec::new();
    let mut dt = opts.reference_dt;
    let mut change = f64::NAN;
    for k in 0..=opts.reference_halvings {
        let r = gait_run(&variant(model, kind, dt, None), name);
        log_run(log, "reference", &r);
        if r.status != "ok" || !r.v_ratio.is_finite() {
            let why = if r.status == "ok" {
                "the run finished but v_s/v_m is not finite (a scene without a gait has no speed ratio to compare)".to_string()
            } else {
                r.status.clone()
            };
            return Err(ChartError::Reference(format!(
                "{name} at dt = {dt:e} s: {why}"
            )));
        }
        if let Some(prev) = runs.last() {
            change = (r.v_ratio / prev.v_ratio - 1.0).abs();
        }
        runs.push(r);
        if change < opts.reference_change || k == opts.reference_halvings {
            break;
        }
        dt *= 0.5;
    }
    let best = runs.last().expect("one run").clone();
    let mut scatter_runs = Vec::new();
    for f in [1.0 - opts.reference_jitter, 1.0 + opts.reference_jitter] {
        let r = gait_run(&variant(model, kind, best.dt * f, None), name);
        log_run(log, "reference scatter", &r);
        scatter_runs.push(r);
    }
    let values: Vec<f64> = std::iter::once(best.v_ratio)
        .chain(scatter_runs.iter().map(|r| r.v_ratio))
        .collect();
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let wall_s = runs
        .iter()
        .chain(scatter_runs.iter())
        .map(|r| r.wall_s)
        .sum();
    for r in scatter_runs.iter_mut() {
        r.x.clear();
    }
    let n = runs.len();
    for r in runs.iter_mut().take(n - 1) {
        r.x.clear();
    }
    let reference = GaitReference {
        key,
        converged: change < opts.reference_change,
        change,
        scatter: (hi - lo) / best.v_ratio,
        v_ratio: best.v_ratio,
        runs,
        scatter_runs,
        wall_s,
    };
    if let Some(path) = cache {
        let json = serde_json::to_string(&reference).expect("serialisable");
        write(path, &json)?;
    }
    Ok(reference)
}

/// `problem` (whose compiled model is `model`) at `elements`.
fn at_mesh(problem: &Problem, model: &Model, elements: usize) -> (Problem, Model) {
    let mut p = problem.clone();
    if elements == model.elements() {
        return (p, model.clone());
    }
    p.rod.elements = elements;
    let mut m = Model::new(&p);
    // Keep the settings the caller may have changed on the model (e.g. the duration).
    m.duration = model.duration;
    m.output_interval = model.output_interval;
    (p, m)
}

/// The reference's final centreline at the nodes of an `elements` mesh (every k-th node when
/// the reference mesh is k times finer); empty when the meshes do not nest.
fn centreline_at(xref: &[[f64; 3]], elements: usize) -> Vec<[f64; 3]> {
    let nref = xref.len().saturating_sub(1);
    if elements == 0 || !nref.is_multiple_of(elements) {
        return Vec::new();
    }
    let k = nref / elements;
    xref.iter().step_by(k).copied().collect()
}

/// Compute the gait work-precision data of a scene with ground and gait; the reference is
/// cached in `cache` (see the module doc).
pub fn gait_precision(
    scene: &str,
    problem: &Problem,
    model: &Model,
    opts: &GaitPrecisionOptions,
    cache: Option<&Path>,
    log: &mut dyn FnMut(&str),
) -> Result<GaitPrecision, ChartError> {
    let n0 = model.elements();
    let meshes = if opts.meshes.is_empty() {
        vec![n0, 2 * n0, 4 * n0]
    } else {
        opts.meshes.clone()
    };
    let finest = meshes.iter().copied().max().unwrap_or(n0);
    let (pref, mref) = at_mesh(problem, model, finest);
    let reference = gait_reference(&pref, &mref, opts, cache, log)?;
    let xref = reference.runs.last().expect("reference run").x.clone();
    let mut points = Vec::new();
    let measure = |mut run: GaitRun, points: &mut Vec<GaitPoint>| {
        let v_error = (run.v_ratio / reference.v_ratio - 1.0).abs();
        let x = centreline_at(&xref, run.elements);
        let x_error = if run.status == "ok" && !x.is_empty() && x.len() == run.x.len() {
            max_distance(&run.x, &x) / model.length
        } else {
            f64::NAN
        };
        run.x.clear();
        points.push(GaitPoint {
            run,
            v_error,
            x_error,
        });
    };
    for &n in &meshes {
        let (_, m) = at_mesh(problem, model, n);
        let mut runs = Vec::new();
        for &dt in &opts.euler_dt {
            runs.push((
                GaitMethod::Fixed(IntegratorKind::ImplicitEuler),
                variant(&m, IntegratorKind::ImplicitEuler, dt, None),
            ));
        }
        for &dt in &opts.bdf2_dt {
            runs.push((
                GaitMethod::Fixed(IntegratorKind::Bdf2),
                variant(&m, IntegratorKind::Bdf2, dt, None),
            ));
        }
        for &tol in &opts.tolerances {
            runs.push((
                GaitMethod::Adaptive(IntegratorKind::Bdf2),
                variant(&m, IntegratorKind::Bdf2, opts.adaptive_first_dt, Some(tol)),
            ));
        }
        for (method, mm) in runs {
            let run = gait_run(&mm, method);
            log_run(log, "run", &run);
            measure(run, &mut points);
        }
    }
    if let Some(target) = opts.accuracy_target {
        let mut p = problem.clone();
        p.time.duration = Some(model.duration);
        // Up to the reference's mesh: a model finer than the reference cannot be judged by it.
        let sel = crate::studies::accuracy::selection::select(&p, target, finest, log);
        let r = &sel.report;
        let o = &sel.outcome;
        let run = GaitRun {
            method: GaitMethod::Accuracy,
            elements: r.elements,
            dt: r.dt.unwrap_or(f64::NAN),
            tolerance: r.error_tolerance,
            v_ratio: r
                .runs
                .iter()
                .find(|x| {
                    x.elements == r.elements
                        && x.dt == r.dt
                        && x.error_tolerance == r.error_tolerance
                })
                .map_or(f64::NAN, |x| x.v_s_over_v_m),
            wall_s: r.wall_time_total_s,
            steps: o.steps.accepted,
            rejected: o.steps.rejected,
            dt_range: (o.steps.dt_min, o.steps.dt_max),
            status: o.error.as_ref().map_or("ok".into(), |e| e.to_string()),
            x: sel.model.real.clone().map(|i| o.state.node(i)).collect(),
        };
        log(&format!(
            "accuracy {target}: {} elements, v_s/v_m {:.5} (estimated error {:.2e}), {:.1} s in all",
            r.elements, run.v_ratio, r.estimated_error, r.wall_time_total_s
        ));
        measure(run, &mut points);
    }
    Ok(GaitPrecision {
        scene: scene.into(),
        elements: finest,
        duration: model.duration,
        options: opts.clone(),
        reference,
        points,
        external: Vec::new(),
    })
}

impl GaitPrecision {
    /// The chart with another code's `runs` of the same scene added (their wall time is
    /// their wall seconds per simulated second times this chart's duration).
    pub fn with_external(mut self, runs: Vec<ExternalRun>) -> GaitPrecision {
        let t = self.duration;
        self.external
            .extend(runs.into_iter().map(|r| ExternalPoint::new(r, t)));
        self
    }

    /// The external runs' lines: each (code, element count) once, in order.
    fn external_lines(&self) -> Vec<(&str, usize)> {
        let mut lines: Vec<(&str, usize)> = self
            .external
            .iter()
            .map(|p| (p.run.code.as_str(), p.run.elements))
            .collect();
        lines.sort_unstable();
        lines.dedup();
        lines
    }

    /// A plain-text table of the reference and every run.
    pub fn summary(&self) -> String {
        let r = &self.reference;
        let mut s = format!(
            "{} ({} elements, T = {} s)\nreference: {} dt = {:.3e} s, v_s/v_m = {:.5} (last change {:.2e}, {}); scatter over dt x (1 -+ {}): {:.2e}\n\
             method         el.  dt (s)     tol     steps  rej  wall (s)  v_s/v_m  v error   x error/L\n",
            self.scene,
            self.elements,
            self.duration,
            r.runs.last().map_or("?", |x| x.method.name()),
            r.runs.last().map_or(f64::NAN, |x| x.dt),
            r.v_ratio,
            r.change,
            if r.converged { "converged" } else { "NOT converged" },
            self.options.reference_jitter,
            r.scatter,
        );
        for p in &self.points {
            let q = &p.run;
            let _ = writeln!(
                s,
                "{:14} {:4} {:.3e} {:7.0e} {:6} {:4} {:8.2} {:8.5} {:9.2e} {:9.2e}{}",
                q.method,
                q.elements,
                q.dt,
                q.tolerance.unwrap_or(f64::NAN),
                q.steps,
                q.rejected,
                q.wall_s,
                q.v_ratio,
                p.v_error,
                p.x_error,
                if q.status == "ok" { "" } else { "  failed" }
            );
        }
        if !self.external.is_empty() {
            s.push_str(
                "external runs, each against its own code's converged value; wall time for T:\n\
                 code                el.  dt (s)     v_s/v_m  own ref.  v error   wall/sim. s  wall (s)\n",
            );
            for p in &self.external {
                let r = &p.run;
                let _ = writeln!(
                    s,
                    "{:18} {:4} {:.3e} {:8.5} {:8.5} {:9.2e} {:11.3} {:8.2}",
                    r.code,
                    r.elements,
                    r.dt,
                    r.v_ratio,
                    r.reference,
                    p.v_error,
                    r.wall_per_simulated_s,
                    p.wall_s
                );
            }
        }
        s.push_str(&self.first_within(0.01));
        s.push_str(&self.cheapest_within(0.01));
        s
    }

    /// The cheapest slither run within `error` of slither's converged `v_s/v_m` against the
    /// cheapest external run within `error` of its own code's (one line; empty without
    /// external runs).
    pub fn cheapest_within(&self, error: f64) -> String {
        if self.external.is_empty() {
            return String::new();
        }
        let ours = self
            .points
            .iter()
            .filter(|p| p.v_error <= error)
            .min_by(|a, b| a.run.wall_s.total_cmp(&b.run.wall_s));
        let theirs = self
            .external
            .iter()
            .filter(|p| p.v_error <= error)
            .min_by(|a, b| a.wall_s.total_cmp(&b.wall_s));
        let pct = 100.0 * error;
        let ours_s = ours.map_or(format!("slither: no run within {pct:.1} %"), |p| {
            format!(
                "slither {} {} el. ({}) {:.2} s",
                p.run.method,
                p.run.elements,
                step_text(&format!("{:.1e}", p.run.dt), p.run.tolerance),
                p.run.wall_s
            )
        });
        let theirs_s = theirs.map_or(format!("external: no run within {pct:.1} %"), |p| {
            format!(
                "{} {} el. (dt {:.1e} s) {:.2} s",
                p.run.code, p.run.elements, p.run.dt, p.wall_s
            )
        });
        let ratio = match (ours, theirs) {
            (Some(a), Some(b)) => format!("; {:.1}x", b.wall_s / a.run.wall_s),
            _ => String::new(),
        };
        format!(
            "cheapest within {pct:.1} % of its own converged value: {ours_s}; {theirs_s}{ratio}\n"
        )
    }

    /// For each method and mesh, its cheapest run within `error` of the converged `v_s/v_m`
    /// (one line each, cheapest first; the lines that never get there last).
    pub fn first_within(&self, error: f64) -> String {
        let mut keys: Vec<(&str, usize)> = self
            .points
            .iter()
            .map(|p| (p.run.method.name(), p.run.elements))
            .collect();
        keys.sort_unstable();
        keys.dedup();
        let mut rows: Vec<(f64, String)> = keys
            .into_iter()
            .map(|(method, n)| {
                let best = self
                    .points
                    .iter()
                    .filter(|p| p.run.method.name() == method && p.run.elements == n)
                    .filter(|p| p.v_error <= error)
                    .min_by(|a, b| a.run.wall_s.total_cmp(&b.run.wall_s));
                match best {
                    Some(p) => (
                        p.run.wall_s,
                        format!(
                            "{method} {n} el.: within {:.1} % at {:.2} s ({}, error {:.2} %)",
                            100.0 * error,
                            p.run.wall_s,
                            step_text(&format!("{:.1e}", p.run.dt), p.run.tolerance),
                            100.0 * p.v_error
                        ),
                    ),
                    None => (
                        f64::INFINITY,
                        format!("{method} {n} el.: never within {:.1} %", 100.0 * error),
                    ),
                }
            })
            .collect();
        for (code, n) in self.external_lines() {
            let best = self
                .external
                .iter()
                .filter(|p| p.run.code == code && p.run.elements == n && p.v_error <= error)
                .min_by(|a, b| a.wall_s.total_cmp(&b.wall_s));
            rows.push(match best {
                Some(p) => (
                    p.wall_s,
                    format!(
                        "{code} {n} el.: within {:.1} % of its own converged value at {:.2} s (dt {:.1e} s, error {:.2} %)",
                        100.0 * error,
                        p.wall_s,
                        p.run.dt,
                        100.0 * p.v_error
                    ),
                ),
                None => (
                    f64::INFINITY,
                    format!(
                        "{code} {n} el.: never within {:.1} % of its own converged value",
                        100.0 * error
                    ),
                ),
            });
        }
        rows.sort_by(|a, b| a.0.total_cmp(&b.0));
        rows.into_iter().map(|(_, l)| l + "\n").collect()
    }
}

#[path = "gait_precision_output.rs"]
mod output;
pub use output::write_gait_precision;

#[cfg(test)]
#[path = "gait_precision_tests.rs"]
mod tests;
