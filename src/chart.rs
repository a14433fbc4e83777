//! Speed against accuracy (MODEL section 8): the work-precision chart and the stability map
//! of the implicit integrator ([`crate::integrator`]) and the explicit velocity Verlet
//! reference ([`crate::integrator::explicit`]) on the same discrete model, for scenes without
//! ground (the explicit integrator has no contact).
//!
//! * **Work-precision** ([`work_precision`]): the reference solution is the scene run by
//!   velocity Verlet at three fine steps `h, h/2, h/4`; Richardson's estimate from the final
//!   centrelines gives the observed order `p = log2(d1/d2)` (`d1 = |x_h - x_{h/2}|`,
//!   `d2 = |x_{h/2} - x_{h/4}|`, max node distance) and the error of the finest run,
//!   `d2 / (2^p - 1)`, which becomes the reference. Each integrator then runs the scene at
//!   several steps; the error is the largest distance of a real node from the reference at the
//!   final time (m), against the wall time of the run (s). The mesh is the scene's: this
//!   measures time-integration error of one discrete model, not spatial error.
//!   No ground means no `v_s`; the centreline error stands for accuracy.
//! * **Stability map** ([`stability_map`]): over scaled weight `W = rho g a^2 L^3 / B` and
//!   element count `N`, the largest step each method runs the scene with to its end by
//!   geometric bisection (relative resolution `rtol`). Stable means: every step accepted with
//!   finite state, for the explicit integrator no energy blow-up (see
//!   [`crate::integrator::explicit`]), for the implicit one Newton converged in every step
//!   without halving (`max_halvings = 0`). Bisection assumes that stability is monotone in the
//!   step, which the measurement does not prove. The implicit search stops at the scene's
//!   duration (one step); a method that holds there is reported as capped. Beside the
//!   measurement: the linear-theory Verlet limit `2/omega_max` from the eigenvalues of
//!   `M^{-1} K` at the initial state ([`linear_stability_limit`]) and the stretch, bending and
//!   twist time scales `l0 sqrt(rho A/EA)`, `l0^2 sqrt(rho A/B)`, `l0 sqrt(rho J/C)`.

use crate::gait::Muscles;
use crate::integrator::explicit::{Explicit, Unsupported};
use crate::integrator::{Integrator, StepError};
use crate::model::Model;
use crate::plot::{self, PlotError};
use crate::problem::Problem;
use crate::rod::{dof, vec3::f};
use crate::sim::{drive, Schedule};
use crate::state::State;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A time integrator of the comparison.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Variational implicit Euler by Newton.
    Implicit,
    /// Velocity Verlet.
    Explicit,
}

impl Method {
    /// Name in files.
    pub fn name(self) -> &'static str {
        match self {
            Method::Implicit => "implicit",
            Method::Explicit => "explicit",
        }
    }
}

/// Errors of the charts.
#[derive(Debug, thiserror::Error)]
pub enum ChartError {
    /// The scene cannot be run by the explicit integrator.
    #[error(transparent)]
    Unsupported(#[from] Unsupported),
    /// The reference solution could not be computed or did not converge.
    #[error("reference solution: {0}")]
    Reference(String),
    /// A file could not be written.
    #[error("{path}: cannot write: {source}")]
    Io {
        /// File.
        path: PathBuf,
        /// Cause.
        source: std::io::Error,
    },
    /// A figure could not be drawn.
    #[error(transparent)]
    Plot(#[from] PlotError),
}

/// One finished run.
#[derive(Clone, Debug)]
pub struct RunResult {
    /// Final positions of the real nodes (m).
    pub x: Vec<[f64; 3]>,
    /// Final time (s).
    pub t: f64,
    /// Wall time of the stepping (s).
    pub wall_s: f64,
    /// Steps taken.
    pub steps: usize,
    /// Newton iterations (implicit).
    pub newton_iterations: usize,
    /// Step halvings (implicit).
    pub step_halvings: usize,
}

/// Run `model` from its initial state with `n` steps of `h` by `method` (gait from the model).
/// The implicit integrator halves failed steps up to `model.max_halvings` times.
pub fn simulate(
    model: &Model,
    method: Method,
    h: f64,
    n: usize,
) -> Result<Result<RunResult, StepError>, Unsupported> {
    let actuation = Box::new(Muscles {
        gait: model.gait.clone(),
    });
    let start = Instant::now();
    let schedule = Schedule::fixed(h, n);
    let o = match method {
        Method::Implicit => {
            let mut integ = Integrator::new(model, actuation);
            drive(model, &mut integ, schedule, start, &mut |_| {}, &mut |_| {})
        }
        Method::Explicit => {
            let mut integ = Explicit::new(model, actuation)?;
            drive(model, &mut integ, schedule, start, &mut |_| {}, &mut |_| {})
        }
    };
    let s = &o.state;
    Ok(match o.error {
        Some(e) => Err(e),
        None => Ok(RunResult {
            x: model.real.clone().map(|i| s.node(i)).collect(),
            t: s.t,
            wall_s: o.wall_time_s,
            steps: n,
            newton_iterations: o.stats.newton_iterations,
            step_halvings: o.stats.step_halvings,
        }),
    })
}

/// Largest distance between corresponding nodes (m).
pub fn max_distance(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| f::norm(f::sub(*p, *q)))
        .fold(0.0, f64::max)
}

/// Verlet's linear stability limit and the mode that sets it.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct LinearLimit {
    /// `2 / omega_max` (s).
    pub dt: f64,
    /// Shares of the fastest mode's kinetic energy in motion along the rod (stretch), across
    /// it (bend) and in twist; they sum to 1.
    pub shares: [f64; 3],
}

impl LinearLimit {
    /// "stretch", "bend" or "twist": the largest share.
    pub fn mode(&self) -> &'static str {
        let k = (0..3)
            .max_by(|&a, &b| self.shares[a].total_cmp(&self.shares[b]))
            .unwrap_or(0);
        ["stretch", "bend", "twist"][k]
    }
}

/// Verlet's linear stability limit `2 / omega_max`, `omega_max^2` the largest eigenvalue of
/// `M^{-1} K` over the free coordinates, `K` the (unprojected) energy Hessian at the initial
/// state, and the kind of its mode. Dense eigen-decomposition: meant for chart-sized rods (up
/// to a few hundred elements).
pub fn linear_stability_limit(model: &Model) -> LinearLimit {
    let s = State::initial(model);
    let mut integ = Integrator::new(
        model,
        Box::new(Muscles {
            gait: model.gait.clone(),
        }),
    );
    let (_, asm) = integ.energy_derivatives(&s, &s.q, false);
    let free: Vec<usize> = (0..model.ndof).filter(|&k| !model.fixed[k]).collect();
    let nf = free.len();
    let mut a = nalgebra::DMatrix::<f64>::zeros(nf, nf);
    for (r, &i) in free.iter().enumerate() {
        for (c, &j) in free.iter().enumerate() {
            a[(r, c)] = asm.h(i, j) / (model.mass[i] * model.mass[j]).sqrt();
        }
    }
    let eig = nalgebra::SymmetricEigen::new(a);
    let top = eig.eigenvalues.imax();
    let u = eig.eigenvectors.column(top);
    // Kinetic-energy shares of the mode (mass-scaled coordinates): twist angles; node
    // displacements split along and across the local tangent.
    let mut full = vec![0.0; model.ndof];
    for (r, &k) in free.iter().enumerate() {
        full[k] = u[r];
    }
    let mut shares = [0.0; 3];
    for j in 0..model.nodes - 1 {
        shares[2] += full[dof::edge(j)].powi(2);
    }
    for i in 0..model.nodes {
        let k = dof::node(i);
        let d = [full[k], full[k + 1], full[k + 2]];
        let j = i.min(model.nodes - 2);
        let t = f::unit(crate::state::edge_vec(&s.q, j));
        let along = f::dot(d, t).powi(2);
        shares[0] += along;
        shares[1] += f::dot(d, d) - along;
    }
    let total: f64 = shares.iter().sum();
    LinearLimit {
        dt: 2.0 / eig.eigenvalues[top].sqrt(),
        shares: shares.map(|x| x / total),
    }
}

/// Settings of the work-precision chart. Steps are given as fractions of the linear-theory
/// explicit limit `2/omega_max` (explicit and reference) or as step counts over the scene's
/// duration (implicit); every step is rounded to divide the duration exactly.
#[derive(Clone, Debug)]
pub struct WorkPrecisionOptions {
    /// Explicit steps as fractions of `2/omega_max` (values above 1 show the failure).
    pub explicit_fractions: Vec<f64>,
    /// Implicit step counts over the duration.
    pub implicit_steps: Vec<usize>,
    /// Coarsest reference step as a fraction of `2/omega_max` (then halved twice).
    pub reference_fraction: f64,
}

impl Default for WorkPrecisionOptions {
    fn default() -> Self {
        WorkPrecisionOptions {
            explicit_fractions: vec![1.2, 0.9, 0.45, 0.225],
            implicit_steps: vec![25, 50, 100, 200, 400, 800, 1600],
            reference_fraction: 1.0 / 32.0,
        }
    }
}

/// The reference solution and its Richardson error estimate.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Reference {
    /// The three steps (s), coarsest first.
    pub dt: [f64; 3],
    /// `|x_h - x_{h/2}|`, `|x_{h/2} - x_{h/4}|` (m, max node distance).
    pub differences: [f64; 2],
    /// Observed order `log2(d1/d2)`.
    pub order: f64,
    /// Estimated error of the finest run, `d2 / (2^p - 1)` (m).
    pub error_estimate: f64,
    /// Wall time of the three runs (s).
    pub wall_s: f64,
    /// Final positions of the finest run (m).
    #[serde(skip)]
    pub x: Vec<[f64; 3]>,
}

/// One point of the work-precision chart.
#[derive(Clone, Debug, serde::Serialize)]
pub struct WorkPoint {
    /// Method.
    pub method: Method,
    /// Step (s).
    pub dt: f64,
    /// Steps.
    pub steps: usize,
    /// Wall time (s); NaN when the run failed.
    pub wall_s: f64,
    /// Max node distance from the reference at the final time (m); NaN when failed.
    pub error_m: f64,
    /// Newton iterations per step (implicit).
    pub newton_per_step: f64,
    /// Step halvings (implicit).
    pub step_halvings: usize,
    /// "ok" or the failure.
    pub status: String,
}

/// Work-precision results.
#[derive(Clone, Debug, serde::Serialize)]
pub struct WorkPrecision {
    /// Scene file.
    pub scene: String,
    /// Real elements.
    pub elements: usize,
    /// Duration (s).
    pub duration: f64,
    /// Linear-theory explicit limit `2/omega_max` (s).
    pub linear_limit_dt: f64,
    /// Reference solution.
    pub reference: Reference,
    /// All runs.
    pub points: Vec<WorkPoint>,
    /// Observed order of each method from its two finest successful runs.
    pub implicit_order: f64,
    /// Same for the explicit integrator.
    pub explicit_order: f64,
    /// The two methods side by side (when both have successful runs).
    pub comparison: Option<Comparison>,
}

/// Both integrators at matched cost, from one chart's runs.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Comparison {
    /// The explicit run at the largest stable step tried: (dt s, error m, wall s).
    pub explicit_largest_stable: (f64, f64, f64),
    /// The implicit run with the largest step: (dt s, error m, wall s).
    pub implicit_coarsest: (f64, f64, f64),
    /// The explicit run at its largest stable step is both cheaper and more accurate than
    /// every implicit run.
    pub explicit_dominates: bool,
    /// The implicit error at the wall time of the explicit run at its largest stable step,
    /// interpolated log-log between implicit runs; `None` outside their range (m).
    pub implicit_error_at_same_wall_m: Option<f64>,
    /// The implicit step that would reach the explicit error at its largest stable step,
    /// extrapolated with the power law `e = c dt^p` through the two finest implicit runs (s).
    pub implicit_dt_for_explicit_error: f64,
    /// Wall time of that implicit run, extrapolated from the finest run's time per step (s).
    pub implicit_wall_for_explicit_error_s: f64,
}

fn compare(points: &[WorkPoint]) -> Option<Comparison> {
    let ok = |m: Method| {
        let mut v: Vec<&WorkPoint> = points
            .iter()
            .filter(|p| p.method == m && p.error_m.is_finite() && p.error_m > 0.0)
            .collect();
        v.sort_by(|a, b| a.dt.total_cmp(&b.dt));
        v
    };
    let (imp, exp) = (ok(Method::Implicit), ok(Method::Explicit));
    if imp.len() < 2 || exp.is_empty() {
        return None;
    }
    let x = *exp.last()?;
    let c = *imp.last()?;
    let mut by_wall = imp.clone();
    by_wall.sort_by(|a, b| a.wall_s.total_cmp(&b.wall_s));
    let same_wall = by_wall.windows(2).find_map(|w| {
        let (a, b) = (w[0], w[1]);
        if a.wall_s <= x.wall_s && x.wall_s <= b.wall_s && b.wall_s > a.wall_s {
            let f = (x.wall_s / a.wall_s).ln() / (b.wall_s / a.wall_s).ln();
            Some((a.error_m.ln() + f * (b.error_m / a.error_m).ln()).exp())
        } else {
            None
        }
    });
    let (f0, f1) = (imp[0], imp[1]);
    let p = (f1.error_m / f0.error_m).ln() / (f1.dt / f0.dt).ln();
    let dt = f0.dt * (x.error_m / f0.error_m).powf(1.0 / p);
    Some(Comparison {
        explicit_largest_stable: (x.dt, x.error_m, x.wall_s),
        implicit_coarsest: (c.dt, c.error_m, c.wall_s),
        explicit_dominates: imp
            .iter()
            .all(|i| x.wall_s <= i.wall_s && x.error_m <= i.error_m),
        implicit_error_at_same_wall_m: same_wall,
        implicit_dt_for_explicit_error: dt,
        implicit_wall_for_explicit_error_s: f0.wall_s * f0.dt / dt,
    })
}

impl WorkPrecision {
    /// A plain-text summary: the reference, every run, and the comparison.
    pub fn summary(&self) -> String {
        let r = &self.reference;
        let mut s = format!(
            "{} ({} elements, T = {} s); explicit linear limit 2/omega_max = {:.3e} s\n\
             reference: velocity Verlet at dt = {:.3e}, {:.3e}, {:.3e} s: differences {:.3e}, {:.3e} m, observed order {:.3}, error estimate {:.2e} m\n\
             method    dt (s)      steps  wall (s)  error (m)   Newton/step\n",
            self.scene,
            self.elements,
            self.duration,
            self.linear_limit_dt,
            r.dt[0],
            r.dt[1],
            r.dt[2],
            r.differences[0],
            r.differences[1],
            r.order,
            r.error_estimate
        );
        for p in &self.points {
            let _ = writeln!(
                s,
                "{:9} {:.4e} {:6} {:8.3} {:10.3e} {:6.2}{}",
                p.method.name(),
                p.dt,
                p.steps,
                p.wall_s,
                p.error_m,
                p.newton_per_step,
                if p.status == "ok" { "" } else { "  unstable" }
            );
        }
        let _ = writeln!(
            s,
            "observed orders (two finest runs): implicit {:.2}, explicit {:.2}",
            self.implicit_order, self.explicit_order
        );
        let smallest = self
            .points
            .iter()
            .map(|p| p.error_m)
            .filter(|e| e.is_finite())
            .fold(f64::INFINITY, f64::min);
        let _ = writeln!(
            s,
            "reference error estimate / smallest measured error = {:.1e}",
            r.error_estimate / smallest
        );
        if let Some(c) = &self.comparison {
            let (xd, xe, xw) = c.explicit_largest_stable;
            let (id, ie, iw) = c.implicit_coarsest;
            let _ = writeln!(
                s,
                "explicit at its largest stable step {xd:.3e} s: error {xe:.2e} m in {xw:.3} s; implicit at its largest step {id:.3e} s: error {ie:.2e} m in {iw:.3} s ({:.1e} x the explicit error, {:.2} x its wall time){}",
                ie / xe,
                iw / xw,
                if c.explicit_dominates {
                    "; the explicit run is cheaper and more accurate than every implicit run"
                } else {
                    ""
                }
            );
            if let Some(e) = c.implicit_error_at_same_wall_m {
                let _ = writeln!(
                    s,
                    "implicit error at the same wall time as that explicit run: {e:.2e} m ({:.1e} x)",
                    e / xe
                );
            }
            let _ = writeln!(
                s,
                "implicit step for the explicit error (extrapolated e ~ dt^p): {:.1e} s, ~{:.0} s wall",
                c.implicit_dt_for_explicit_error, c.implicit_wall_for_explicit_error_s
            );
        }
        s
    }
}

/// Step that divides `duration` into `n` equal steps.
fn steps_for(duration: f64, dt: f64) -> (f64, usize) {
    let n = (duration / dt).ceil().max(1.0) as usize;
    (duration / n as f64, n)
}

/// Observed order `log(e1/e2)/log(h1/h2)` of the two finest successful points of `method`.
fn observed_order(points: &[WorkPoint], method: Method) -> f64 {
    let mut ok: Vec<&WorkPoint> = points
        .iter()
        .filter(|p| p.method == method && p.error_m.is_finite() && p.error_m > 0.0)
        .collect();
    ok.sort_by(|a, b| a.dt.total_cmp(&b.dt));
    if ok.len() < 2 {
        return f64::NAN;
    }
    (ok[1].error_m / ok[0].error_m).ln() / (ok[1].dt / ok[0].dt).ln()
}

/// Compute the work-precision data of `model` (a scene without ground). `log` receives one
/// line per run.
pub fn work_precision(
    scene: &str,
    model: &Model,
    opts: &WorkPrecisionOptions,
    log: &mut dyn FnMut(&str),
) -> Result<WorkPrecision, ChartError> {
    if model.ground.is_some() {
        return Err(Unsupported::Ground.into());
    }
    let t_end = model.duration;
    let limit = linear_stability_limit(model);
    let lin = limit.dt;
    log(&format!(
        "linear-theory explicit limit 2/omega_max = {lin:.4e} s ({} mode)",
        limit.mode()
    ));
    // Reference: velocity Verlet at h, h/2, h/4.
    let (h0, n0) = steps_for(t_end, opts.reference_fraction * lin);
    let mut xs = Vec::new();
    let mut wall = 0.0;
    for k in 0..3 {
        let (h, n) = (h0 / (1 << k) as f64, n0 << k);
        let r = simulate(model, Method::Explicit, h, n)?
            .map_err(|e| ChartError::Reference(e.to_string()))?;
        log(&format!(
            "reference run: explicit dt = {h:.4e} s, {n} steps, {:.2} s",
            r.wall_s
        ));
        wall += r.wall_s;
        xs.push(r.x);
    }
    let d1 = max_distance(&xs[0], &xs[1]);
    let d2 = max_distance(&xs[1], &xs[2]);
    let order = (d1 / d2).log2();
    // Velocity Verlet is second order: anything else means the steps are not yet in the
    // asymptotic range and the estimate below would not hold.
    if !(order.is_finite() && (1.8..=2.3).contains(&order)) {
        return Err(ChartError::Reference(format!(
            "not in the asymptotic range: differences {d1:.3e} m, {d2:.3e} m (order {order:.2}); use a finer reference step"
        )));
    }
    let reference = Reference {
        dt: [h0, h0 / 2.0, h0 / 4.0],
        differences: [d1, d2],
        order,
        error_estimate: d2 / (2f64.powf(order) - 1.0),
        wall_s: wall,
        x: xs.pop().expect("three runs"),
    };
    log(&format!(
        "reference: observed order {order:.3}, error estimate {:.3e} m",
        reference.error_estimate
    ));
    let mut runs: Vec<(Method, f64, usize)> = Vec::new();
    for &n in &opts.implicit_steps {
        runs.push((Method::Implicit, t_end / n as f64, n));
    }
    for &fr in &opts.explicit_fractions {
        let (h, n) = steps_for(t_end, fr * lin);
        runs.push((Method::Explicit, h, n));
    }
    let mut points = Vec::new();
    for (method, h, n) in runs {
        let p = match simulate(model, method, h, n)? {
            Ok(r) => WorkPoint {
                method,
                dt: h,
                steps: n,
                wall_s: r.wall_s,
                error_m: max_distance(&r.x, &reference.x),
                newton_per_step: r.newton_iterations as f64 / n as f64,
                step_halvings: r.step_halvings,
                status: "ok".into(),
            },
            Err(e) => WorkPoint {
                method,
                dt: h,
                steps: n,
                wall_s: f64::NAN,
                error_m: f64::NAN,
                newton_per_step: f64::NAN,
                step_halvings: 0,
                status: e.to_string(),
            },
        };
        log(&format!(
            "{} dt = {:.4e} s: error {:.3e} m, wall {:.3} s ({})",
            method.name(),
            h,
            p.error_m,
            p.wall_s,
            p.status
        ));
        points.push(p);
    }
    Ok(WorkPrecision {
        scene: scene.to_string(),
        elements: model.elements(),
        duration: t_end,
        linear_limit_dt: lin,
        implicit_order: observed_order(&points, Method::Implicit),
        explicit_order: observed_order(&points, Method::Explicit),
        comparison: compare(&points),
        reference,
        points,
    })
}

fn write(path: &Path, text: &str) -> Result<(), ChartError> {
    std::fs::write(path, text).map_err(|source| ChartError::Io {
        path: path.into(),
        source,
    })
}

/// Write `work_precision.csv`, `work_precision.json` and `work_precision.png` into `dir`.
pub fn write_work_precision(dir: &Path, wp: &WorkPrecision) -> Result<(), ChartError> {
    std::fs::create_dir_all(dir).map_err(|source| ChartError::Io {
        path: dir.into(),
        source,
    })?;
    let mut csv = String::from(
        "method,dt_s,steps,wall_s,error_m,newton_iterations_per_step,step_halvings,status\n",
    );
    for p in &wp.points {
        let _ = writeln!(
            csv,
            "{},{:e},{},{:e},{:e},{},{},\"{}\"",
            p.method.name(),
            p.dt,
            p.steps,
            p.wall_s,
            p.error_m,
            p.newton_per_step,
            p.step_halvings,
            p.status.replace('"', "'")
        );
    }
    write(&dir.join("work_precision.csv"), &csv)?;
    let json = serde_json::to_string_pretty(wp).expect("serialisable");
    write(&dir.join("work_precision.json"), &json)?;
    let series = |m: Method| -> Vec<(f64, f64)> {
        let mut v: Vec<(f64, f64)> = wp
            .points
            .iter()
            .filter(|p| p.method == m && p.error_m.is_finite())
            .map(|p| (p.wall_s, p.error_m))
            .collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        v
    };
    let walls: Vec<f64> = wp
        .points
        .iter()
        .map(|p| p.wall_s)
        .filter(|w| w.is_finite())
        .collect();
    let wmin = walls.iter().copied().fold(f64::INFINITY, f64::min);
    let wmax = walls.iter().copied().fold(0.0, f64::max);
    plot::xy(
        &dir.join("work_precision.png"),
        &format!(
            "Work-precision: {} ({} elements, T = {} s)",
            wp.scene, wp.elements, wp.duration
        ),
        "wall time (s)",
        "final centreline error, max node distance (m)",
        &[
            ("implicit Euler (Newton)", series(Method::Implicit)),
            (
                "velocity Verlet (explicit, stable steps)",
                series(Method::Explicit),
            ),
            (
                "reference error estimate",
                vec![
                    (wmin, wp.reference.error_estimate),
                    (wmax, wp.reference.error_estimate),
                ],
            ),
        ],
        true,
        true,
    )?;
    Ok(())
}

/// Settings of the stability map.
#[derive(Clone, Debug)]
pub struct StabilityOptions {
    /// Scaled weights `W = rho g a^2 L^3 / B` (the bending stiffness follows).
    pub scaled_weights: Vec<f64>,
    /// Element counts.
    pub elements: Vec<usize>,
    /// Simulated time of every trial (s).
    pub duration: f64,
    /// Relative resolution of the bisection.
    pub rtol: f64,
}

impl Default for StabilityOptions {
    fn default() -> Self {
        StabilityOptions {
            scaled_weights: vec![3.0, 30.0, 300.0],
            elements: vec![10, 20, 40, 80, 160],
            duration: 0.2,
            rtol: 0.02,
        }
    }
}

/// One cell of the stability map.
#[derive(Clone, Debug, serde::Serialize)]
pub struct StabilityCell {
    /// Elements.
    pub elements: usize,
    /// Scaled weight.
    pub scaled_weight: f64,
    /// Bending stiffness (N m^2).
    pub bending_stiffness: f64,
    /// Stretching stiffness (N).
    pub stretch_stiffness: f64,
    /// Element length (m).
    pub l0: f64,
    /// Largest stable explicit step found (s).
    pub explicit_dt_max: f64,
    /// Explicit trial runs.
    pub explicit_trials: usize,
    /// Largest stable implicit step found (s).
    pub implicit_dt_max: f64,
    /// The implicit search reached the trial duration (one step) and held.
    pub implicit_capped: bool,
    /// Implicit trial runs.
    pub implicit_trials: usize,
    /// Why the last failed implicit trial failed (empty if none failed).
    pub implicit_failure: String,
    /// Linear-theory Verlet limit `2/omega_max` (s).
    pub linear_dt: f64,
    /// Kind of the fastest linear mode: "stretch", "bend" or "twist".
    pub linear_mode: &'static str,
    /// `l0 sqrt(rho A / EA)` (s).
    pub stretch_scale: f64,
    /// `l0^2 sqrt(rho A / B)` (s).
    pub bend_scale: f64,
    /// `l0 sqrt(rho J / C)` (s).
    pub twist_scale: f64,
}

/// The stability map and the exponents fitted to it.
#[derive(Clone, Debug, serde::Serialize)]
pub struct StabilityMap {
    /// Scene.
    pub scene: String,
    /// Trial duration (s).
    pub duration: f64,
    /// Cells, element count fastest.
    pub cells: Vec<StabilityCell>,
    /// Local exponents of the explicit limit against `l0` between consecutive element counts
    /// at fixed `W`, as `(W, N1, N2, exponent)` (1: stretch or twist waves, 2: bending waves).
    pub exponents_l0: Vec<(f64, usize, usize, f64)>,
    /// Least-squares exponent of the explicit limit against `B` at fixed `N`.
    pub exponent_bend: f64,
}

impl StabilityMap {
    /// A plain-text summary: one line per cell and the fitted exponents.
    pub fn summary(&self) -> String {
        let mut s = format!(
            "{}: largest stable step over {} s runs\n\
             W      N    explicit (s)  2/omega_max (s) mode     l0 sqrt(rhoA/EA) (s)  l0^2 sqrt(rhoA/B) (s)  implicit (s)\n",
            self.scene, self.duration
        );
        for c in &self.cells {
            let _ = writeln!(
                s,
                "{:<6} {:<4} {:.4e}    {:.4e}       {:8} {:.4e}            {:.4e}             {:.4e}{}",
                c.scaled_weight,
                c.elements,
                c.explicit_dt_max,
                c.linear_dt,
                c.linear_mode,
                c.stretch_scale,
                c.bend_scale,
                c.implicit_dt_max,
                if c.implicit_capped { " (whole run in one step)" } else { "" }
            );
        }
        let _ = write!(s, "explicit limit ~ l0^e between consecutive N:");
        for (w, a, b, e) in &self.exponents_l0 {
            let _ = write!(s, " W={w} N {a}->{b}: {e:.2};");
        }
        let _ = writeln!(
            s,
            "\nexplicit limit ~ B^{:.3} at fixed N",
            self.exponent_bend
        );
        s
    }
}

/// Whether `model` runs `duration` in steps of `h` by `method` (see the module doc).
pub fn stable(model: &Model, method: Method, h: f64, duration: f64) -> Result<bool, Unsupported> {
    Ok(trial(model, method, h, duration)?.is_ok())
}

/// [`stable`] with the failure.
fn trial(
    model: &Model,
    method: Method,
    h: f64,
    duration: f64,
) -> Result<Result<(), String>, Unsupported> {
    let n = (duration / h).ceil().max(1.0) as usize;
    Ok(simulate(model, method, h, n)?
        .map(|_| ())
        .map_err(|e| e.to_string()))
}

/// Geometric bisection for the largest `h <= cap` with `trial(h)` true, starting from
/// `guess`, to relative resolution `rtol`. Returns (h, trials, capped).
fn largest_stable(
    mut trial: impl FnMut(f64) -> Result<bool, Unsupported>,
    guess: f64,
    cap: f64,
    rtol: f64,
) -> Result<(f64, usize, bool), Unsupported> {
    let mut count = 0;
    let mut run = |h: f64| {
        count += 1;
        trial(h)
    };
    let (mut lo, mut hi);
    let guess = guess.min(cap);
    if run(guess)? {
        if guess >= cap {
            return Ok((cap, count, true));
        }
        lo = guess;
        hi = (2.0 * guess).min(cap);
        while run(hi)? {
            lo = hi;
            if hi >= cap {
                return Ok((cap, count, true));
            }
            hi = (2.0 * hi).min(cap);
        }
    } else {
        hi = guess;
        lo = 0.5 * guess;
        while !run(lo)? {
            hi = lo;
            lo *= 0.5;
            if lo < 1e-12 * cap {
                return Ok((0.0, count, false));
            }
        }
    }
    while hi / lo > 1.0 + rtol {
        let mid = (lo * hi).sqrt();
        if run(mid)? {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok((lo, count, false))
}

/// Least-squares slope of `ln y` against `ln x` over groups of points (each group its own
/// intercept).
fn pooled_slope(groups: &[Vec<(f64, f64)>]) -> f64 {
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for g in groups {
        let pts: Vec<(f64, f64)> = g
            .iter()
            .filter(|p| p.0 > 0.0 && p.1 > 0.0)
            .map(|p| (p.0.ln(), p.1.ln()))
            .collect();
        if pts.len() < 2 {
            continue;
        }
        let mx = pts.iter().map(|p| p.0).sum::<f64>() / pts.len() as f64;
        let my = pts.iter().map(|p| p.1).sum::<f64>() / pts.len() as f64;
        for p in &pts {
            sxy += (p.0 - mx) * (p.1 - my);
            sxx += (p.0 - mx).powi(2);
        }
    }
    sxy / sxx
}

/// Compute the stability map of the scene `base` (without ground) over `opts`. `log`
/// receives one line per cell.
pub fn stability_map(
    scene: &str,
    base: &Problem,
    opts: &StabilityOptions,
    log: &mut dyn FnMut(&str),
) -> Result<StabilityMap, ChartError> {
    if base.ground.is_some() {
        return Err(Unsupported::Ground.into());
    }
    let mut cells = Vec::new();
    for &w in &opts.scaled_weights {
        for &n in &opts.elements {
            let mut p = base.clone();
            let r = &p.rod;
            let b = base.rod.density * base.gravity.g * r.diameter.powi(2) * r.length.powi(3) / w;
            p.rod.bending_stiffness = b;
            p.rod.elements = n;
            // Keep the defaults tied to B (a file's explicit values would decouple them).
            p.rod.twist_stiffness = None;
            p.rod.stretch_stiffness = None;
            p.time.duration = Some(opts.duration);
            p.time.dt = Some(opts.duration);
            let mut model = Model::new(&p);
            model.duration = opts.duration;
            model.max_halvings = 0;
            let limit = linear_stability_limit(&model);
            let lin = limit.dt;
            // The first guess is off the prediction so that a marginal run at exactly
            // 2/omega_max does not decide the result.
            let (dte, te, _) = largest_stable(
                |h| stable(&model, Method::Explicit, h, opts.duration),
                0.7 * lin,
                opts.duration,
                opts.rtol,
            )?;
            let mut implicit_failure = String::new();
            let (dti, ti, capped) = largest_stable(
                |h| {
                    let r = trial(&model, Method::Implicit, h, opts.duration)?;
                    if let Err(e) = &r {
                        implicit_failure = format!("dt = {h:.4e} s: {e}");
                    }
                    Ok(r.is_ok())
                },
                opts.duration,
                opts.duration,
                opts.rtol,
            )?;
            let rho_a = model.line_density();
            let rho_j = model.density * std::f64::consts::PI * model.diameter.powi(4) / 32.0;
            let l0 = model.length / n as f64;
            let cell = StabilityCell {
                elements: n,
                scaled_weight: w,
                bending_stiffness: b,
                stretch_stiffness: model.stretch,
                l0,
                explicit_dt_max: dte,
                explicit_trials: te,
                implicit_dt_max: dti,
                implicit_capped: capped,
                implicit_trials: ti,
                implicit_failure,
                linear_dt: lin,
                linear_mode: limit.mode(),
                stretch_scale: l0 * (rho_a / model.stretch).sqrt(),
                bend_scale: l0 * l0 * (rho_a / model.bend).sqrt(),
                twist_scale: l0 * (rho_j / model.twist).sqrt(),
            };
            log(&format!(
                "W = {w}, N = {n}: explicit dt_max = {dte:.4e} s (2/omega_max {lin:.4e} s, {} mode; {te} trials), implicit dt_max = {dti:.4e} s{} ({ti} trials)",
                limit.mode(),
                if capped { " (capped: the whole run in one step)" } else { "" }
            ));
            cells.push(cell);
        }
    }
    let mut exponents_l0 = Vec::new();
    let mut groups_b: Vec<Vec<(f64, f64)>> = Vec::new();
    for &n in &opts.elements {
        groups_b.push(
            cells
                .iter()
                .filter(|c| c.elements == n)
                .map(|c| (c.bending_stiffness, c.explicit_dt_max))
                .collect(),
        );
    }
    for &w in &opts.scaled_weights {
        let row: Vec<&StabilityCell> = cells.iter().filter(|c| c.scaled_weight == w).collect();
        for p in row.windows(2) {
            let e = (p[1].explicit_dt_max / p[0].explicit_dt_max).ln() / (p[1].l0 / p[0].l0).ln();
            exponents_l0.push((w, p[0].elements, p[1].elements, e));
        }
    }
    let exponent_bend = pooled_slope(&groups_b);
    Ok(StabilityMap {
        scene: scene.to_string(),
        duration: opts.duration,
        cells,
        exponents_l0,
        exponent_bend,
    })
}

/// Write `stability.csv`, `stability.json` and `stability.png` into `dir`.
pub fn write_stability(dir: &Path, map: &StabilityMap) -> Result<(), ChartError> {
    std::fs::create_dir_all(dir).map_err(|source| ChartError::Io {
        path: dir.into(),
        source,
    })?;
    let mut csv = String::from("elements,scaled_weight,bending_stiffness_Nm2,stretch_stiffness_N,l0_m,explicit_dt_max_s,explicit_trials,linear_theory_dt_s,linear_mode,stretch_scale_s,bend_scale_s,twist_scale_s,implicit_dt_max_s,implicit_capped,implicit_trials,implicit_failure\n");
    for c in &map.cells {
        let _ = writeln!(
            csv,
            "{},{},{:e},{:e},{:e},{:e},{},{:e},{},{:e},{:e},{:e},{:e},{},{},\"{}\"",
            c.elements,
            c.scaled_weight,
            c.bending_stiffness,
            c.stretch_stiffness,
            c.l0,
            c.explicit_dt_max,
            c.explicit_trials,
            c.linear_dt,
            c.linear_mode,
            c.stretch_scale,
            c.bend_scale,
            c.twist_scale,
            c.implicit_dt_max,
            c.implicit_capped,
            c.implicit_trials,
            c.implicit_failure.replace('"', "'")
        );
    }
    write(&dir.join("stability.csv"), &csv)?;
    let json = serde_json::to_string_pretty(map).expect("serialisable");
    write(&dir.join("stability.json"), &json)?;
    let mut weights: Vec<f64> = map.cells.iter().map(|c| c.scaled_weight).collect();
    weights.sort_by(f64::total_cmp);
    weights.dedup();
    let mut names = Vec::new();
    let mut series = Vec::new();
    for (method, label) in [
        (Method::Implicit, "implicit Euler"),
        (Method::Explicit, "velocity Verlet"),
    ] {
        for &w in &weights {
            let mut pts: Vec<(f64, f64)> = map
                .cells
                .iter()
                .filter(|c| c.scaled_weight == w)
                .map(|c| {
                    let dt = match method {
                        Method::Explicit => c.explicit_dt_max,
                        Method::Implicit => c.implicit_dt_max,
                    };
                    (c.elements as f64, dt)
                })
                .collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            names.push(format!("{label}, W = {w}"));
            series.push(pts);
        }
    }
    let data: Vec<(&str, Vec<(f64, f64)>)> = names.iter().map(|s| s.as_str()).zip(series).collect();
    plot::xy(
        &dir.join("stability.png"),
        &format!(
            "Largest stable step ({}, cap {} s)",
            map.scene, map.duration
        ),
        "elements N",
        "largest stable time step (s)",
        &data,
        true,
        true,
    )?;
    Ok(())
}
