//! Ensembles (`slither::studies::ensemble`, `slither run --ensemble K`): the statistics are
//! those of the individual runs, a member is reproduced from its recorded seed, the members
//! are perturbed as documented, and the unperturbed run's results do not change.
mod common;
use slither::problem;
use slither::studies::ensemble::{self, Perturbation, Spec};
use std::path::{Path, PathBuf};
use std::process::Command;

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("slither_ensemble_{}_{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The bundled S-start cut to its first 0.4 s on 20 elements (a short, cheap gait scene).
fn short_s_start() -> problem::Problem {
    let mut p = problem::load(Path::new("problems/s_start.toml")).unwrap();
    p.rod.elements = 20;
    p.time.duration = Some(0.4);
    p.time.dt = Some(4e-3);
    p.output.interval = Some(0.04);
    p
}

#[test]
fn statistics_are_those_of_the_members_and_a_member_reruns_from_its_seed() {
    let base = short_s_start();
    let spec = Spec {
        runs: 4,
        seed: 11,
        perturbation: Perturbation::default(),
    };
    let e = ensemble::run(&base, &spec, &|_, _| {});
    assert_eq!((e.runs, e.members.len()), (4, 4));
    assert_eq!(e.finished, 4, "{:?}", e.members);
    // Every scalar observable has its statistics, recomputed here from the members.
    assert!(e.stats.len() >= 20, "{:?}", e.stats.keys());
    for (name, s) in &e.stats {
        let v: Vec<f64> = e
            .members
            .iter()
            .filter_map(|m| m.observables[name])
            .filter(|x| x.is_finite())
            .collect();
        assert_eq!(s.n, v.len(), "{name}");
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        let var = v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (v.len() - 1) as f64;
        assert!(
            (s.mean - mean).abs() <= 1e-12 * mean.abs().max(1e-300),
            "{name}"
        );
        assert!(
            (s.sd.unwrap() - var.sqrt()).abs() <= 1e-9 * s.sd.unwrap().max(1e-300),
            "{name}"
        );
        assert_eq!(
            s.min,
            v.iter().copied().fold(f64::INFINITY, f64::min),
            "{name}"
        );
        assert_eq!(
            s.max,
            v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            "{name}"
        );
    }
    let speed = &e.stats["v_s_over_v_m"];
    assert!(
        speed.sd.unwrap() > 0.0 && speed.min < speed.max,
        "{speed:?}"
    );
    // Votes: one per member, by its label.
    assert_eq!(e.regime_votes.values().sum::<usize>(), 4);
    for (label, n) in &e.regime_votes {
        assert_eq!(*n, e.members.iter().filter(|m| &m.regime == label).count());
    }
    // The perturbations are the documented ones: a geometric step ladder from dt/2.5 to
    // dt*2.5, friction factors near 1 but not 1, a sideways shape of about 1e-3 a.
    let dt = base.time.dt.unwrap();
    assert!((e.members[0].dt.unwrap() / (dt / ensemble::STEP) - 1.0).abs() < 1e-12);
    assert!((e.members[3].dt.unwrap() / (dt * ensemble::STEP) - 1.0).abs() < 1e-12);
    for m in &e.members {
        assert_eq!(m.seed, ensemble::member_seed(11, m.index));
        for f in m.friction_factors {
            assert!(
                f != 1.0 && (f - 1.0).abs() < 6.0 * ensemble::FRICTION,
                "{f}"
            );
        }
        assert!(
            m.shape_rms_over_a > 1e-5 && m.shape_rms_over_a < 5e-3,
            "{}",
            m.shape_rms_over_a
        );
    }
    // One member alone, from the recorded seed and index: the same run, bit for bit.
    let again = ensemble::run_member(&base, &spec, 2);
    assert_eq!(again.seed, e.members[2].seed);
    assert_eq!(again.observables, e.members[2].observables);
    assert_eq!(again.friction_factors, e.members[2].friction_factors);
}

#[test]
fn no_perturbation_gives_identical_members_equal_to_the_plain_run() {
    let base = short_s_start();
    let spec = Spec {
        runs: 2,
        seed: 5,
        perturbation: Perturbation::NONE,
    };
    let e = ensemble::run(&base, &spec, &|_, _| {});
    let plain = slither::observe::evaluate(
        &slither::model::Model::new(&base),
        slither::observe::Measure::Full,
        &mut |_| {},
        &mut |_| {},
    )
    .unwrap();
    let v = plain.observables.v_s_over_v_m;
    for m in &e.members {
        assert_eq!(m.observables["v_s_over_v_m"], Some(v));
    }
    let s = &e.stats["v_s_over_v_m"];
    assert_eq!((s.sd, s.min, s.max), (Some(0.0), v, v));
}

#[test]
fn run_with_ensemble_writes_the_stats_and_keeps_the_plain_results() {
    let d = dir("cli");
    let p = d.join("p.toml");
    let text = std::fs::read_to_string("problems/s_start.toml")
        .unwrap()
        .replace("elements = 50", "elements = 20")
        .replace("duration = 3.572", "duration = 0.4")
        .replace("dt = 2e-3", "dt = 4e-3")
        .replace("interval = 0.036", "interval = 0.04");
    std::fs::write(&p, text).unwrap();
    let run = |out: &Path, extra: &[&str]| {
        let r = Command::new(env!("CARGO_BIN_EXE_slither"))
            .args([
                "run",
                p.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
                "--quiet",
                "--no-plots",
            ])
            .args(extra)
            .output()
            .unwrap();
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        s
    };
    let plain = run(&d.join("plain"), &[]);
    assert!(plain.get("ensemble").is_none());
    let s = run(&d.join("ens"), &["--ensemble", "3", "--ensemble-seed", "4"]);
    assert_eq!(s["v_s_over_v_m"], plain["v_s_over_v_m"]);
    assert_eq!(s["regime"], plain["regime"]);
    let e = &s["ensemble"];
    assert_eq!(e["runs"], 3);
    assert_eq!(e["seed"], 4);
    let v: Vec<f64> = e["members"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["observables"]["v_s_over_v_m"].as_f64().unwrap())
        .collect();
    assert_eq!(v.len(), 3);
    let st = &e["stats"]["v_s_over_v_m"];
    let mean = v.iter().sum::<f64>() / 3.0;
    assert!((st["mean"].as_f64().unwrap() - mean).abs() < 1e-12);
    assert_eq!(
        st["min"].as_f64().unwrap(),
        v.iter().copied().fold(f64::INFINITY, f64::min)
    );
    assert_eq!(
        st["max"].as_f64().unwrap(),
        v.iter().copied().fold(f64::NEG_INFINITY, f64::max)
    );
    let sd = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / 2.0).sqrt();
    assert!((st["sd"].as_f64().unwrap() - sd).abs() < 1e-12);
    let votes: u64 = e["regime_votes"]
        .as_object()
        .unwrap()
        .values()
        .map(|n| n.as_u64().unwrap())
        .sum();
    assert_eq!(votes, 3);
    // Every key written is in the output schema (and so in the guide's output reference).
    let undocumented: Vec<String> = slither::output::schema::json_paths(&s)
        .into_iter()
        .filter(|k| !slither::output::schema::documented(slither::output::schema::SUMMARY, k))
        .collect();
    assert!(undocumented.is_empty(), "{undocumented:?}");
    // A bad K is refused with exit code 2.
    let r = Command::new(env!("CARGO_BIN_EXE_slither"))
        .args([
            "run",
            p.to_str().unwrap(),
            "--out",
            d.join("bad").to_str().unwrap(),
            "--ensemble",
            "0",
        ])
        .output()
        .unwrap();
    assert_eq!(r.status.code(), Some(2));
    let _ = std::fs::remove_dir_all(&d);
}

/// What a member records is what it ran: the step cut to the run when the ladder makes it
/// longer than the run, the error tolerance of an adaptive member (the ladder scales that,
/// not the step), and in static mode no ladder at all (no time step to perturb).
#[test]
fn members_record_the_step_or_tolerance_they_ran_and_static_mode_has_no_ladder() {
    let spec = Spec {
        runs: 3,
        seed: 2,
        perturbation: Perturbation::default(),
    };
    // dt 0.05 s on a 0.1 s run: the last member's step 0.125 s is longer than the run.
    let mut p = short_s_start();
    p.time.duration = Some(0.1);
    p.time.dt = Some(0.05);
    p.output.interval = Some(0.05);
    let m = ensemble::run_member(&p, &spec, 2);
    assert_eq!(m.step_factor, ensemble::STEP);
    assert_eq!(m.dt, Some(0.1), "the step it ran is the run's length");
    assert_eq!(m.error_tolerance, None);
    let m = ensemble::run_member(&p, &spec, 0);
    assert!((m.dt.unwrap() - 0.05 / ensemble::STEP).abs() < 1e-15);
    // Adaptive: the tolerance is scaled and recorded; the first step is the file's.
    let mut a = p.clone();
    a.time.adaptive = true;
    a.time.error_tolerance = Some(1e-3);
    let pr = ensemble::member_problem(&a, &spec.perturbation, 1, 0, 3);
    assert_eq!(pr.time.dt, Some(0.05));
    assert!((pr.time.error_tolerance.unwrap() - 1e-3 / ensemble::STEP).abs() < 1e-18);
    // Static mode: every member at factor 1, its step not perturbed (and recorded as none).
    let s = problem::load(Path::new("problems/cantilever_sag.toml")).unwrap();
    assert_eq!(s.time.mode, problem::Mode::Static);
    for k in 0..3 {
        assert_eq!(
            ensemble::applied_step_factor(&s, &spec.perturbation, k, 3),
            1.0
        );
        let pr = ensemble::member_problem(&s, &spec.perturbation, 1, k, 3);
        assert_eq!(pr.time.dt, s.time.dt);
    }
    let m = ensemble::run_member(&s, &spec, 2);
    assert_eq!((m.step_factor, m.dt), (1.0, None));
    assert_eq!(m.status, "ok", "{}", m.reason);
    // One member: the spread is undefined, written as null.
    let one = ensemble::run(&p, &Spec { runs: 1, ..spec }, &|_, _| {});
    let v = serde_json::to_value(&one).unwrap();
    assert!(v["stats"]["v_s"]["sd"].is_null(), "{}", v["stats"]["v_s"]);
    assert_eq!(v["stats"]["v_s"]["n"], 1);
}

/// `run --ensemble` of a gait with a launch period: the periodic (sidewinding) observables are
/// members' observables and have statistics, like the others.
#[test]
fn an_ensemble_of_a_sidewinding_has_the_periodic_statistics() {
    let p = problem::parse(common::TINY_SIDEWINDING, Path::new("<inline>")).unwrap();
    let e = ensemble::run(&p, &Spec::new(2), &|_, _| {});
    assert_eq!(e.finished, 2);
    for key in [
        "periodic.cycles",
        "periodic.lateral_speed_over_v_m",
        "periodic.turn_deg_mean_abs",
        "periodic.broadside_deg_min",
        "periodic.stationary_contact_share_min",
        "periodic.sidewinding",
    ] {
        let s = e
            .stats
            .get(key)
            .unwrap_or_else(|| panic!("no {key} in {:?}", e.stats.keys()));
        assert_eq!(s.n, 2, "{key}");
    }
    // The members' values are their own runs' periodic values.
    assert_eq!(e.stats["periodic.cycles"].mean, 2.0);
    let lateral: Vec<f64> = e
        .members
        .iter()
        .map(|m| m.observables["periodic.lateral_speed_over_v_m"].unwrap())
        .collect();
    assert!(lateral.iter().all(|v| v.abs() > 0.0), "{lateral:?}");
}
