//! The work-precision chart: error against wall time of the implicit and the explicit
//! integrator on one scene (see the module doc of [`crate::charts`]).

use super::*;

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
    /// The integrator.
    pub method: IntegratorKind,
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
    let ok = |m: IntegratorKind| {
        let mut v: Vec<&WorkPoint> = points
            .iter()
            .filter(|p| p.method == m && p.error_m.is_finite() && p.error_m > 0.0)
            .collect();
        v.sort_by(|a, b| a.dt.total_cmp(&b.dt));
        v
    };
    let (imp, exp) = (
        ok(IntegratorKind::ImplicitEuler),
        ok(IntegratorKind::VelocityVerlet),
    );
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
fn observed_order(points: &[WorkPoint], method: IntegratorKind) -> f64 {
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
        let r = simulate(model, IntegratorKind::VelocityVerlet, h, n)?
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
    let mut runs: Vec<(IntegratorKind, f64, usize)> = Vec::new();
    for &n in &opts.implicit_steps {
        runs.push((IntegratorKind::ImplicitEuler, t_end / n as f64, n));
    }
    for &fr in &opts.explicit_fractions {
        let (h, n) = steps_for(t_end, fr * lin);
        runs.push((IntegratorKind::VelocityVerlet, h, n));
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
        implicit_order: observed_order(&points, IntegratorKind::ImplicitEuler),
        explicit_order: observed_order(&points, IntegratorKind::VelocityVerlet),
        comparison: compare(&points),
        reference,
        points,
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
    let series = |m: IntegratorKind| -> Vec<(f64, f64)> {
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
            (
                "implicit Euler (Newton)",
                series(IntegratorKind::ImplicitEuler),
            ),
            (
                "velocity Verlet (explicit, stable steps)",
                series(IntegratorKind::VelocityVerlet),
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
