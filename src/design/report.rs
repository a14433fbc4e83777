//! `optimum.json` and the figures of a study.

use super::*;

/// `optimum.json`.
#[derive(Serialize)]
pub(super) struct Optimum<'a> {
    study: String,
    base: String,
    base_hash: &'a str,
    /// The optimised parameters and their bounds.
    optimized: &'a [Dim],
    /// Fastest finished evaluation within the heading limit (null if there is none).
    best: Option<Summary<'a>>,
    /// The starting point.
    initial: Summary<'a>,
    /// `best.v_s - initial.v_s` (m/s).
    v_s_gain: Option<f64>,
    evaluations: usize,
    simulations: usize,
    reused: usize,
    repeats: usize,
    failed: usize,
    max_evaluations: usize,
    /// "nelder-mead" or "particle-swarm".
    method: &'static str,
    /// Nelder-Mead starts.
    starts: usize,
    /// Particle swarm population (null for Nelder-Mead).
    particles: Option<usize>,
    /// Seed of the random draws.
    seed: u64,
    /// Iterations over all starts (Nelder-Mead steps or swarm generations after the first).
    iterations: usize,
    termination: &'a str,
    /// Optimised parameters whose optimum lies within `ON_BOUND_FRACTION` of the bounds'
    /// width of a bound (e.g. `["speed"]`): the box stopped the search.
    on_bound: Vec<&'static str>,
    /// For each entry of `on_bound`, which bound: "lower" or "upper".
    on_bound_side: Vec<&'static str>,
    duration_pulses: f64,
    /// `[study] duration_periods`, when it sets the duration (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    duration_periods: Option<f64>,
    wall_time_s: f64,
    /// The model chosen for the study's `[accuracy]` (absent without one).
    #[serde(skip_serializing_if = "Option::is_none")]
    accuracy: Option<&'a super::accuracy::StudyAccuracy>,
    /// `--ensemble K`: the best point and the runner-up re-run as ensembles (absent without).
    #[serde(skip_serializing_if = "Option::is_none")]
    ensemble: Option<&'a OptimumCheck>,
}

/// One evaluated point re-run as an ensemble ([`super::ensemble`]).
#[derive(Clone, Debug, Serialize)]
pub struct EnsembleOf {
    /// The evaluation it re-runs (its number in `history.csv`).
    pub eval: usize,
    /// Its `v_s` (m/s) in the search.
    pub v_s: f64,
    /// `v_s` over the ensemble's members (m/s): mean, sd, min, max, n.
    pub ensemble_v_s: Option<super::ensemble::Stat>,
    /// Members per regime label.
    pub regime_votes: std::collections::BTreeMap<String, usize>,
    /// The members' seeds, in order.
    pub seeds: Vec<u64>,
    /// Wall time of the ensemble (s).
    pub wall_time_s: f64,
}

/// Whether the optimum's lead is larger than the chaos and step sensitivity of the runs:
/// the best point and the runner-up (the fastest other finished point within the heading
/// limit) each re-run as an ensemble of `runs` perturbed members.
#[derive(Clone, Debug, Serialize)]
pub struct OptimumCheck {
    /// Members per ensemble.
    pub runs: usize,
    /// The ensembles' seed (the runner-up's is `seed + 1`).
    pub seed: u64,
    /// The perturbation sizes.
    pub perturbation: super::ensemble::Perturbation,
    /// The best point's ensemble.
    pub best: EnsembleOf,
    /// The runner-up's ensemble (null when no other point finished).
    pub runner_up: Option<EnsembleOf>,
    /// `best.ensemble_v_s.mean - runner_up.ensemble_v_s.mean` (m/s).
    pub improvement: Option<f64>,
    /// `sqrt(sd_best^2 + sd_runner_up^2)` (m/s).
    pub spread: Option<f64>,
    /// Every member of the best's ensemble is faster than every member of the runner-up's
    /// (`best.min > runner_up.max`): the ranking holds under the perturbations.
    pub improvement_exceeds_spread: Option<bool>,
    /// `v_s_gain` of the search (best over the start, m/s).
    pub gain_over_initial: f64,
    /// The gain exceeds the best's ensemble range (`max - min`).
    pub gain_exceeds_spread: Option<bool>,
}

/// Re-run the best point of `r` and its runner-up as ensembles `spec` (the runner-up seeded
/// `spec.seed + 1`) and compare them ([`OptimumCheck`]); `None` without a best point.
pub fn check_optimum(
    study: &Study,
    r: &Report,
    spec: &super::ensemble::Spec,
) -> Option<OptimumCheck> {
    let best = r.best.as_ref()?;
    let runner_up = r
        .visited
        .iter()
        .map(|v| &v.0)
        .filter(|e| e.status == Status::Ok && study.meets_heading(e) && e.point != best.point)
        .max_by(|a, b| b.objective().total_cmp(&a.objective()));
    let of = |e: &Evaluation, seed: u64| {
        let s = super::ensemble::Spec { seed, ..*spec };
        let en = super::ensemble::run(&study.problem_at(&e.point), &s, &|_, _| {});
        EnsembleOf {
            eval: e.eval,
            v_s: e.v_s,
            ensemble_v_s: en.stats.get("v_s").copied(),
            regime_votes: en.regime_votes,
            seeds: en.members.iter().map(|m| m.seed).collect(),
            wall_time_s: en.wall_time_s,
        }
    };
    let b = of(best, spec.seed);
    let u = runner_up.map(|e| of(e, spec.seed.wrapping_add(1)));
    let (sb, su) = (b.ensemble_v_s, u.as_ref().and_then(|u| u.ensemble_v_s));
    let gain = best.v_s - r.initial.v_s;
    Some(OptimumCheck {
        runs: spec.runs,
        seed: spec.seed,
        perturbation: spec.perturbation,
        improvement: sb.zip(su).map(|(b, u)| b.mean - u.mean),
        spread: sb.zip(su).map(|(b, u)| b.sd.hypot(u.sd)),
        improvement_exceeds_spread: sb.zip(su).map(|(b, u)| b.min > u.max),
        gain_over_initial: gain,
        gain_exceeds_spread: sb.map(|b| gain > b.max - b.min),
        best: b,
        runner_up: u,
    })
}

#[derive(Serialize)]
pub(super) struct Summary<'a> {
    eval: usize,
    /// Muscle stress (Pa).
    stress: f64,
    /// Couple width (fraction of L).
    sigma: f64,
    /// Travelling speed (m/s).
    speed: f64,
    /// Launch period (s).
    period: f64,
    /// Triplet spacing (fraction of L).
    spacing: f64,
    /// Out-of-plane couple's scale.
    lift: f64,
    duration_s: f64,
    dimensionless: Groups,
    v_s: f64,
    v_s_over_v_m: f64,
    writhe_max: f64,
    writhe_mean: f64,
    /// Net displacement's angle from the initial head direction (degrees).
    displacement_angle_deg: f64,
    regime: &'a str,
    /// The periodic observables (a gait with a launch period).
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    periodic: Option<PeriodicColumns>,
    status: Status,
}

#[derive(Serialize)]
pub(super) struct Groups {
    /// Scaled torque `G = Gamma a^3 L / B`.
    #[serde(rename = "G")]
    g: f64,
    /// Scaled weight `W = rho g a^2 L^3 / B`.
    #[serde(rename = "W")]
    w: f64,
    /// `W / G = rho g L^2 / (Gamma a)`.
    #[serde(rename = "W_over_G")]
    w_over_g: f64,
}

pub(super) fn summary(e: &Evaluation) -> Summary<'_> {
    Summary {
        eval: e.eval,
        stress: e.point.stress,
        sigma: e.point.sigma,
        speed: e.point.speed,
        period: e.point.period,
        spacing: e.point.spacing,
        lift: e.point.lift,
        duration_s: e.duration,
        dimensionless: Groups {
            g: e.g,
            w: e.w,
            w_over_g: e.w / e.g,
        },
        v_s: e.v_s,
        v_s_over_v_m: e.v_s_over_v_m,
        writhe_max: e.writhe_max,
        writhe_mean: e.writhe_mean,
        displacement_angle_deg: e.displacement_angle_deg,
        regime: &e.regime,
        periodic: e.periodic,
        status: e.status,
    }
}

/// The optimised parameters at which the optimum lies on (within [`ON_BOUND_FRACTION`] of the
/// width of) a bound, with the side ("lower" or "upper"); empty without an optimum.
pub fn on_bound(study: &Study, r: &Report) -> Vec<(&'static str, &'static str)> {
    let Some(b) = &r.best else { return Vec::new() };
    study
        .space
        .dims
        .iter()
        .filter_map(|d| {
            let u = (d.param.get(&b.point) - d.lo) / (d.hi - d.lo);
            if u <= ON_BOUND_FRACTION {
                Some((d.param.key(), "lower"))
            } else if u >= 1.0 - ON_BOUND_FRACTION {
                Some((d.param.key(), "upper"))
            } else {
                None
            }
        })
        .collect()
}

/// JSON numbers cannot be NaN or infinite: serde_json writes them as null.
pub(super) fn write_optimum(study: &Study, out: &Path, r: &Report) -> Result<(), DesignError> {
    let o = Optimum {
        study: study.path.display().to_string(),
        base: study.base_path.display().to_string(),
        base_hash: &study.base_hash,
        optimized: &study.space.dims,
        best: r.best.as_ref().map(summary),
        initial: summary(&r.initial),
        v_s_gain: r.best.as_ref().map(|b| b.v_s - r.initial.v_s),
        evaluations: r.evaluations,
        simulations: r.simulations,
        reused: r.reused,
        repeats: r.repeats,
        failed: r.failed,
        max_evaluations: study.max_evaluations,
        method: study.method.as_str(),
        starts: study.starts,
        particles: (study.method == SearchMethod::ParticleSwarm).then_some(study.particles),
        seed: study.seed,
        iterations: r.iterations.iter().filter(|i| i.iteration > 0).count(),
        on_bound: on_bound(study, r).iter().map(|b| b.0).collect(),
        on_bound_side: on_bound(study, r).iter().map(|b| b.1).collect(),
        termination: &r.termination,
        duration_pulses: study.duration_pulses,
        duration_periods: study.duration_periods,
        wall_time_s: r.wall_time_s,
        accuracy: study.chosen.as_ref(),
        ensemble: r.check.as_ref(),
    };
    let path = out.join("optimum.json");
    let text = serde_json::to_string_pretty(&o).map_err(|e| DesignError::Io {
        path: path.clone(),
        source: std::io::Error::other(e),
    })?;
    // Through a temporary name: a full disk leaves no truncated optimum.json.
    crate::output::write_atomic(&path, (text + "\n").as_bytes())
        .map_err(|source| DesignError::Io { path, source })
}

pub(super) fn write_figures(study: &Study, out: &Path, r: &Report) -> Result<(), DesignError> {
    let ok: Vec<&Evaluation> = r
        .visited
        .iter()
        .map(|v| &v.0)
        .filter(|e| e.status == Status::Ok)
        .collect();
    let path = out.join("speed_vs_writhe.png");
    let (within, beyond): (Vec<&Evaluation>, Vec<&Evaluation>) =
        ok.iter().partition(|e| study.meets_heading(e));
    let mut series: Vec<(String, Vec<(f64, f64)>)> = vec![(
        format!("finished evaluations ({})", within.len()),
        within
            .iter()
            .map(|e| (e.writhe_max, e.v_s_over_v_m))
            .collect(),
    )];
    if let (Some(max), false) = (study.max_heading_deg, beyond.is_empty()) {
        series.push((
            format!(
                "more than {max} deg off the head direction ({})",
                beyond.len()
            ),
            beyond
                .iter()
                .map(|e| (e.writhe_max, e.v_s_over_v_m))
                .collect(),
        ));
    }
    if r.initial.status == Status::Ok {
        series.push((
            "start".into(),
            vec![(r.initial.writhe_max, r.initial.v_s_over_v_m)],
        ));
    }
    if let Some(b) = &r.best {
        let bounds = on_bound(study, r);
        let note = if bounds.is_empty() {
            String::new()
        } else {
            format!(
                ", on the {} bound",
                bounds
                    .iter()
                    .map(|(p, side)| format!("{side} {p}"))
                    .collect::<Vec<_>>()
                    .join(" and ")
            )
        };
        series.push((
            format!("optimum (eval {}, v_s = {:.4} m/s{note})", b.eval, b.v_s),
            vec![(b.writhe_max, b.v_s_over_v_m)],
        ));
    }
    if !ok.is_empty() {
        let s: Vec<(&str, Vec<(f64, f64)>)> = series
            .iter()
            .map(|(n, p)| (n.as_str(), p.clone()))
            .collect();
        for path in [path.clone(), plot::svg_twin(&path)] {
            plot::scatter(
                &path,
                "Gait design: speed against writhe",
                "largest |writhe| Wr_max (turns)",
                "v_s / v_m (dimensionless)",
                &s,
            )
            .map_err(|source| DesignError::Plot { path, source })?;
        }
    }
    let path = out.join("history.png");
    let mut best = f64::NEG_INFINITY;
    let mut each = Vec::new();
    let mut running = Vec::new();
    for (k, (e, _)) in r.visited.iter().enumerate() {
        let x = (k + 1) as f64;
        if e.status == Status::Ok {
            each.push((x, e.v_s));
            best = best.max(e.v_s);
        } else {
            each.push((x, f64::NAN));
        }
        running.push((x, if best.is_finite() { best } else { f64::NAN }));
    }
    if each.iter().any(|p| p.1.is_finite()) {
        let series = [("v_s of the evaluation", each), ("best so far", running)];
        for path in [path.clone(), plot::svg_twin(&path)] {
            plot::xy(
                &path,
                "Gait design: objective per evaluation",
                "evaluation (this run)",
                "forward speed v_s (m/s)",
                &series,
                false,
                false,
            )
            .map_err(|source| DesignError::Plot { path, source })?;
        }
    }
    Ok(())
}
