//! Ensembles: one scene run `K` times with small independent perturbations, and the spread of
//! every scalar observable over the runs (`slither run --ensemble K`, the per-cell verification
//! of [`super::phase`], the optimiser's check of its best point).
//!
//! # The perturbations
//!
//! Member `k` of `K` (0-based) with seed `s_k` ([`member_seed`]) changes three things of the
//! problem, all else as written:
//!
//! * **friction**: each of `mu_forward`, `mu_backward`, `mu_sideways` is multiplied by its own
//!   `1 + friction * z`, `z` standard normal (default [`FRICTION`] = 1e-3, a relative change);
//! * **initial shape**: the straight body is bent sideways in the ground plane by
//!   `shape * a * sum_{m=1..4} z_m sin(m pi s / L) / 2` (default [`SHAPE`] = 1e-3: offsets of
//!   about a thousandth of the diameter, independent of the mesh), the reference directors
//!   re-made perpendicular to the new edges;
//! * **step**: the fixed step is multiplied by `step^(2k/(K-1) - 1)`, a geometric ladder from
//!   `dt/step` to `dt*step` (default [`STEP`] = 2.5; an adaptive run scales its error tolerance
//!   by the same factor, recorded as `members[].error_tolerance`; `K = 1`: factor 1). Static
//!   mode has no time step: the ladder is skipped (factor 1, `dt` null), friction and shape
//!   are still perturbed.
//!
//! Why these sizes. On the 50-element S-start (`problems/s_start.toml`) at dt 5e-4, changes
//! of all three friction coefficients by 1e-7 to 1e-3 move `v_s/v_m` by at most 1.3e-4 (the
//! scene is not chaotic there), while the steps from 2.5e-4 to 1e-3 s move it by 6.4e-3
//! (0.3072 at 1e-3 to 0.3136 at 2.5e-4). An ensemble that is to say how sure a result is must
//! contain that discretisation spread, so the step is perturbed too, in both directions.
//! A ladder from dt/2 to 2 dt was measured to fall just short (8 members: range 6.33e-3,
//! because the perturbed dt/2 member landed at 0.3130, not 0.3136); from dt/2.5 to 2.5 dt it
//! covers it (numbers in the guide, studies chapter, "Ensembles"). Friction and shape add the
//! chaotic part where a scene has one (1e-7 changes of friction switched an older S-start
//! between two outcomes 2.5 % apart).
//!
//! The seeds are recorded with each member (`members[].seed`, `members[].dt`), so one member
//! can be rerun alone ([`member_problem`] and [`perturb_model`] with its seed, index and `K`).
//!
//! # The statistics
//!
//! For every scalar (numeric) observable of [`crate::observe::Observables`] and, for a gait
//! with a launch period, every periodic one ([`periodic_scalars`], `periodic.*`), over the members
//! that finished and measured a finite value: `mean`, `sd` (sample standard deviation, `n - 1`
//! in the denominator; 0 for one value), `min`, `max` and `n`. `regime_votes` counts the
//! members per regime label, `"-"` for a member whose run failed.
use crate::model::Model;
use crate::observe::{self, Measure};
use crate::problem::Problem;
use crate::rod::{dof, frames};
use rand_xoshiro::rand_core::{RngCore, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::time::Instant;

pub use crate::output::ensemble::{Ensemble, Member, Perturbation, Stat, FRICTION, SHAPE, STEP};

/// Default seed of an ensemble.
pub const SEED: u64 = 1;
/// Number of sine modes of the initial-shape perturbation.
const SHAPE_MODES: usize = 4;

/// What the ensemble was asked for.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Spec {
    /// Number of members `K` (>= 1).
    pub runs: usize,
    /// Seed of the ensemble; member `k`'s own seed is [`member_seed`]`(seed, k)`.
    pub seed: u64,
    /// The perturbation sizes.
    pub perturbation: Perturbation,
}

impl Spec {
    /// `runs` members with the default seed and perturbations.
    pub fn new(runs: usize) -> Self {
        Spec {
            runs,
            seed: SEED,
            perturbation: Perturbation::default(),
        }
    }
}

/// The seed of member `k` of an ensemble seeded `seed` (a SplitMix64 step of `seed + k`).
pub fn member_seed(seed: u64, k: usize) -> u64 {
    let mut z = seed.wrapping_add((k as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15));
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The step factor of member `k` of `runs`: `step^(2k/(runs-1) - 1)` (1 for one run).
pub fn step_factor(step: f64, k: usize, runs: usize) -> f64 {
    if runs < 2 {
        1.0
    } else {
        step.powf(2.0 * k as f64 / (runs - 1) as f64 - 1.0)
    }
}

/// The step factor member `k` of `runs` runs with: [`step_factor`], or 1 in static mode (no
/// time step: the ladder is skipped there, every member at the file's load increments).
pub fn applied_step_factor(base: &Problem, p: &Perturbation, k: usize, runs: usize) -> f64 {
    if base.time.mode == crate::problem::Mode::Static {
        1.0
    } else {
        step_factor(p.step, k, runs)
    }
}

/// The periodic observables of a run (a gait with a launch period) as member observables,
/// named as in `summary.json`'s `periodic` block (`periodic.lateral_speed_over_v_m`, ...;
/// `periodic.sidewinding` 1 or 0, so its mean is the share of sidewinding members).
pub fn periodic_scalars(p: &observe::periodic::Periodic) -> BTreeMap<String, Option<f64>> {
    let finite = |x: f64| x.is_finite().then_some(x);
    [
        ("cycles", p.cycles.len() as f64),
        ("lateral_speed_over_v_m", p.lateral_speed_over_v_m),
        ("turn_deg_mean_abs", p.turn_deg_mean_abs),
        ("broadside_deg_min", p.broadside_deg_min),
        ("turn_deg_max_abs", p.turn_deg_max_abs),
        (
            "displacement_over_length_min",
            p.displacement_over_length_min,
        ),
        (
            "stationary_contact_share_min",
            p.stationary_contact_share_min,
        ),
        ("sidewinding_margin", p.sidewinding_margin),
        ("sidewinding", if p.sidewinding { 1.0 } else { 0.0 }),
    ]
    .into_iter()
    .map(|(k, v)| (format!("periodic.{k}"), finite(v)))
    .collect()
}

/// A standard normal number (Box-Muller on two uniform numbers in (0, 1]).
fn normal(rng: &mut Xoshiro256PlusPlus) -> f64 {
    let u =
        |rng: &mut Xoshiro256PlusPlus| ((rng.next_u64() >> 11) as f64 + 1.0) / (1u64 << 53) as f64;
    let (u1, u2) = (u(rng), u(rng));
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}

/// The random draws of one member: three friction factors and the shape's mode amplitudes.
#[derive(Clone, Copy, Debug)]
struct Draws {
    friction: [f64; 3],
    modes: [f64; SHAPE_MODES],
}

fn draws(seed: u64, p: &Perturbation) -> Draws {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut friction = [1.0; 3];
    for f in &mut friction {
        *f = 1.0 + p.friction * normal(&mut rng);
    }
    let mut modes = [0.0; SHAPE_MODES];
    for m in &mut modes {
        *m = normal(&mut rng);
    }
    Draws { friction, modes }
}

/// Member `k` of `runs` (seed `seed`, from [`member_seed`]) as a problem: friction and step
/// perturbed. The shape is perturbed on the model ([`perturb_model`]).
pub fn member_problem(
    base: &Problem,
    p: &Perturbation,
    seed: u64,
    k: usize,
    runs: usize,
) -> Problem {
    let d = draws(seed, p);
    let mut pr = base.clone();
    if let Some(g) = pr.ground.as_mut() {
        g.mu_forward *= d.friction[0];
        g.mu_backward *= d.friction[1];
        g.mu_sideways *= d.friction[2];
    }
    let f = applied_step_factor(base, p, k, runs);
    if f != 1.0 {
        if pr.time.adaptive {
            let tol = pr
                .time
                .error_tolerance
                .unwrap_or(crate::problem::time::DEFAULT_TOLERANCE);
            pr.time.error_tolerance = Some(tol * f);
        } else if let Some(dt) = pr.time.dt {
            pr.time.dt = Some(dt * f);
        }
    }
    pr
}

/// Bend the model's straight initial body sideways (in the ground plane, across the initial
/// heading) by the member's shape perturbation, and make each edge's reference director
/// perpendicular to its new tangent. Clamped coordinates are not moved. Returns the RMS offset
/// over `a` (0 when `p.shape` is 0).
pub fn perturb_model(model: &mut Model, p: &Perturbation, seed: u64) -> f64 {
    if p.shape == 0.0 {
        return 0.0;
    }
    let d = draws(seed, p);
    let (head, tail) = (model.real.start, model.real.end - 1);
    let node = |q: &[f64], i: usize| [q[dof::node(i)], q[dof::node(i) + 1], q[dof::node(i) + 2]];
    let (h, t) = (node(&model.q0, head), node(&model.q0, tail));
    let along = [h[0] - t[0], h[1] - t[1]];
    let len = (along[0] * along[0] + along[1] * along[1]).sqrt();
    if len == 0.0 {
        return 0.0;
    }
    let side = [-along[1] / len, along[0] / len];
    let (mut sum2, mut count) = (0.0, 0usize);
    for i in 0..model.nodes {
        let x = node(&model.q0, i);
        // s from the head, along the initial body.
        let s = ((h[0] - x[0]) * along[0] + (h[1] - x[1]) * along[1]) / len;
        let shape: f64 = d
            .modes
            .iter()
            .enumerate()
            .map(|(m, z)| z * ((m + 1) as f64 * std::f64::consts::PI * s / model.length).sin())
            .sum::<f64>()
            * 0.5;
        let y = p.shape * model.diameter * shape;
        for (c, side_c) in side.iter().enumerate() {
            let k = dof::node(i) + c;
            if !model.fixed[k] {
                model.q0[k] += y * side_c;
            }
        }
        if model.real.contains(&i) {
            sum2 += (y / model.diameter).powi(2);
            count += 1;
        }
    }
    for j in 0..model.nodes - 1 {
        let (a, b) = (node(&model.q0, j), node(&model.q0, j + 1));
        let e = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let n = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
        model.a1_0[j] = frames::initial_director([e[0] / n, e[1] / n, e[2] / n]);
    }
    (sum2 / count.max(1) as f64).sqrt()
}

/// The scalar observables of a run, by name (their `summary.json` keys).
pub fn scalars(ob: &observe::Observables) -> BTreeMap<String, Option<f64>> {
    let v = serde_json::to_value(ob).expect("serialisable");
    let mut out = BTreeMap::new();
    if let serde_json::Value::Object(map) = v {
        for (k, x) in map {
            match x {
                serde_json::Value::Number(n) => {
                    out.insert(k, n.as_f64());
                }
                // serde_json writes a non-finite f64 as null: keep the key.
                serde_json::Value::Null => {
                    out.insert(k, None);
                }
                _ => {}
            }
        }
    }
    out
}

/// Run member `k` of the ensemble `spec` of `base` (never panics: a panic is a failed member).
pub fn run_member(base: &Problem, spec: &Spec, k: usize) -> Member {
    let start = Instant::now();
    let seed = member_seed(spec.seed, k);
    let p = &spec.perturbation;
    let pr = member_problem(base, p, seed, k, spec.runs);
    let d = draws(seed, p);
    let duration = pr.time.duration.unwrap_or(f64::INFINITY);
    let mut member = Member {
        index: k,
        seed,
        dt: match pr.time.mode {
            crate::problem::Mode::Static => None,
            crate::problem::Mode::Dynamic => pr.time.dt.map(|dt| dt.min(duration)),
        },
        error_tolerance: pr.time.adaptive.then(|| {
            pr.time
                .error_tolerance
                .unwrap_or(crate::problem::time::DEFAULT_TOLERANCE)
        }),
        step_factor: applied_step_factor(base, p, k, spec.runs),
        friction_factors: if base.ground.is_some() {
            d.friction
        } else {
            [1.0; 3]
        },
        shape_rms_over_a: 0.0,
        status: "failed".into(),
        regime: "-".into(),
        observables: BTreeMap::new(),
        wall_time_s: 0.0,
        reason: String::new(),
    };
    let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let mut model = Model::new(&pr);
        let rms = perturb_model(&mut model, p, seed);
        let o = observe::evaluate(&model, Measure::Full, &mut |_| {}, &mut |_| {})?;
        let periodic = observe::periodic::of_outcome(&model, &o.outcome);
        Ok::<_, crate::integrator::explicit::Unsupported>((rms, o, periodic))
    }));
    match run {
        Err(_) => member.reason = "the simulation panicked".into(),
        Ok(Err(e)) => member.reason = e.to_string(),
        Ok(Ok((rms, o, periodic))) => {
            member.shape_rms_over_a = rms;
            if let Some(e) = &o.outcome.error {
                member.reason = e.to_string();
            } else if o.outcome.interrupted {
                member.reason = "interrupted".into();
            } else {
                member.status = "ok".into();
                member.regime = o.observables.regime.to_string();
                member.observables = scalars(&o.observables);
                if let Some(p) = &periodic {
                    member.observables.extend(periodic_scalars(p));
                }
            }
        }
    }
    member.wall_time_s = start.elapsed().as_secs_f64();
    member
}

/// The statistics and votes of a set of members.
pub fn summarize(spec: &Spec, members: Vec<Member>, wall_time_s: f64) -> Ensemble {
    let mut names: Vec<&String> = members.iter().flat_map(|m| m.observables.keys()).collect();
    names.sort();
    names.dedup();
    let stats: BTreeMap<String, Stat> = names
        .into_iter()
        .filter_map(|name| {
            let values = members
                .iter()
                .filter(|m| m.status == "ok")
                .filter_map(|m| m.observables.get(name).copied().flatten());
            Stat::of(values).map(|s| (name.clone(), s))
        })
        .collect();
    let mut regime_votes = BTreeMap::new();
    for m in &members {
        *regime_votes.entry(m.regime.clone()).or_insert(0) += 1;
    }
    Ensemble {
        runs: spec.runs,
        finished: members.iter().filter(|m| m.status == "ok").count(),
        seed: spec.seed,
        perturbation: spec.perturbation,
        stats,
        regime_votes,
        members,
        wall_time_s,
    }
}

/// Run the ensemble `spec` of `base`: its members in parallel (rayon), then their statistics.
/// `report(done, runs)` is called after each member.
pub fn run(base: &Problem, spec: &Spec, report: &(dyn Fn(usize, usize) + Sync)) -> Ensemble {
    let start = Instant::now();
    let done = std::sync::atomic::AtomicUsize::new(0);
    let members: Vec<Member> = (0..spec.runs)
        .into_par_iter()
        .map(|k| {
            let m = run_member(base, spec, k);
            let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
            report(n, spec.runs);
            m
        })
        .collect();
    summarize(spec, members, start.elapsed().as_secs_f64())
}

/// One line about an ensemble: `v_s/v_m` mean, sd and range, the votes and the wall time.
pub fn describe(e: &Ensemble) -> String {
    let speed = match e.stats.get("v_s_over_v_m") {
        Some(s) => format!(
            "v_s/v_m {:.4} ± {} (min {:.4}, max {:.4})",
            s.mean,
            s.sd.map_or("sd undefined, one value".into(), |sd| format!("{sd:.4} sd")),
            s.min,
            s.max
        ),
        None => "v_s/v_m not measured".into(),
    };
    let votes: Vec<String> = e
        .regime_votes
        .iter()
        .map(|(r, n)| format!("{r} {n}"))
        .collect();
    format!(
        "ensemble of {} ({} finished): {speed}; regimes {}; {:.1} s",
        e.runs,
        e.finished,
        votes.join(", "),
        e.wall_time_s
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stat_of_known_values() {
        let s = Stat::of([1.0, 2.0, f64::NAN, 3.0, 6.0]).unwrap();
        assert_eq!((s.n, s.min, s.max, s.mean), (4, 1.0, 6.0, 3.0));
        // sum of squares 4 + 1 + 0 + 9 = 14 over 3.
        assert!((s.sd.unwrap() - (14.0f64 / 3.0).sqrt()).abs() < 1e-15);
        // One value: the spread is undefined (null), not zero.
        assert_eq!(Stat::of([2.5]).unwrap().sd, None);
        assert!(Stat::of([f64::NAN]).is_none());
    }

    #[test]
    fn step_ladder_spans_the_range_and_seeds_differ() {
        assert_eq!(step_factor(2.0, 0, 5), 0.5);
        assert_eq!(step_factor(2.0, 2, 5), 1.0);
        assert_eq!(step_factor(2.0, 4, 5), 2.0);
        assert_eq!(step_factor(2.0, 0, 1), 1.0);
        const {
            assert!(
                STEP >= 2.0,
                "the ladder must span at least dt/2 to 2 dt (module doc)"
            )
        };
        let seeds: Vec<u64> = (0..100).map(|k| member_seed(7, k)).collect();
        let mut u = seeds.clone();
        u.sort();
        u.dedup();
        assert_eq!(u.len(), seeds.len());
        assert_ne!(member_seed(7, 0), member_seed(8, 0));
    }

    #[test]
    fn normal_draws_have_unit_spread() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
        let z: Vec<f64> = (0..20000).map(|_| normal(&mut rng)).collect();
        let s = Stat::of(z).unwrap();
        assert!(s.mean.abs() < 0.03, "{s:?}");
        assert!((s.sd.unwrap() - 1.0).abs() < 0.03, "{s:?}");
    }
}
