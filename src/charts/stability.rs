//! The stability map: the largest stable step of each integrator over scaled weight and
//! element count (see the module doc of [`crate::charts`]).

use super::*;

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
pub fn stable(
    model: &Model,
    method: IntegratorKind,
    h: f64,
    duration: f64,
) -> Result<bool, Unsupported> {
    Ok(trial(model, method, h, duration)?.is_ok())
}

/// [`stable`] with the failure.
fn trial(
    model: &Model,
    method: IntegratorKind,
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
                |h| stable(&model, IntegratorKind::VelocityVerlet, h, opts.duration),
                0.7 * lin,
                opts.duration,
                opts.rtol,
            )?;
            let mut implicit_failure = String::new();
            let (dti, ti, capped) = largest_stable(
                |h| {
                    let r = trial(&model, IntegratorKind::ImplicitEuler, h, opts.duration)?;
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
        (IntegratorKind::ImplicitEuler, "implicit Euler"),
        (IntegratorKind::VelocityVerlet, "velocity Verlet"),
    ] {
        for &w in &weights {
            let mut pts: Vec<(f64, f64)> = map
                .cells
                .iter()
                .filter(|c| c.scaled_weight == w)
                .map(|c| {
                    let dt = match method {
                        IntegratorKind::VelocityVerlet => c.explicit_dt_max,
                        IntegratorKind::ImplicitEuler | IntegratorKind::Bdf2 => c.implicit_dt_max,
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
