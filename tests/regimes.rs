//! Regimes as the paper defines them, on full simulations of these scenes:
//! `problems/pyelastica_straight.toml` at W = 30, G = 10 moves forward at about 0.29 v_m with
//! its pulse travelling at about 1.3 v_m (labelled F before: now M, not F or N), and the same
//! base at W = 3000, G = 20 barely moves (still F or N). The juvenile S-start stays S
//! (`tests/gaits.rs`). Each scene is one 4 s simulation (about 20-40 s in release).

use slither::model::Model;
use slither::observe::{self, Observables, Regime};
use slither::studies::phase::cell_problem;
use slither::{problem, sim};
use std::path::Path;

fn run(w: f64, g: f64) -> (problem::Problem, Observables) {
    let base = problem::load(Path::new("problems/pyelastica_straight.toml")).unwrap();
    let p = cell_problem(&base, w, g);
    let m = Model::new(&p);
    let o = sim::run_gait(&m, p.solver.integrator, &mut |_| {}, &mut |_| {}).unwrap();
    assert!(o.error.is_none(), "W {w} G {g}: {:?}", o.error);
    let ob = observe::of_outcome(&m, &o);
    println!(
        "W {w} G {g}: {} ({}), {:.1} s wall\n  {ob:?}",
        ob.regime, ob.regime_reason.text, o.wall_time_s
    );
    (p, ob)
}

#[test]
fn forward_mover_with_a_fast_pulse_is_m_not_f() {
    let (p, ob) = run(30.0, 10.0);
    // The scene: B, C and EA ten times the base's, stress 163500 Pa.
    assert!((p.rod.bending_stiffness / 0.1308 - 1.0).abs() < 1e-12);
    assert!((p.gait.stress / 163_500.0 - 1.0).abs() < 1e-12);
    // It moves forward well ...
    assert!(ob.v_s_over_v_m > 0.2, "v_s/v_m {}", ob.v_s_over_v_m);
    // ... so it is neither friction-dominated nor motionless. Its pulse runs at the edge of
    // the S criterion's tolerance (|v_pulse/v_m - 1| <= 0.3): 1.298 v_m measured on the
    // observation grid (T/200), above 1.3 on the old 0.05 s output frames, so S or M is
    // decided by the third digit; what the test holds is that it is not F.
    assert!(
        matches!(ob.regime, Regime::M | Regime::S),
        "{}",
        ob.regime_reason.text
    );
    assert!(
        (ob.lambda_pulse_speed_over_v_m - 1.0).abs() > 0.25,
        "pulse at {} v_m",
        ob.lambda_pulse_speed_over_v_m
    );
    // summary.json carries the label and the comparisons that decided it.
    let j = serde_json::to_value(&ob).unwrap();
    assert_eq!(j["regime"], ob.regime.as_str());
    if ob.regime == Regime::M {
        assert!(j["regime_reason"]["text"]
            .as_str()
            .unwrap()
            .contains("not an S-start"));
        assert!(j["regime_reason"]["not_s"]
            .as_array()
            .unwrap()
            .contains(&"pulse_speed".into()));
    }
    let checks = j["regime_reason"]["checks"].as_array().unwrap();
    assert_eq!(checks.len(), 9, "{checks:?}");
    assert!(j["writhe_snapshot"].is_number() && j["writhe_max"].is_number());
}

#[test]
fn heavy_weak_cell_is_still_f_or_n() {
    let (_, ob) = run(3000.0, 20.0);
    assert!(ob.v_s_over_v_m.abs() < 0.02, "v_s/v_m {}", ob.v_s_over_v_m);
    assert!(
        ob.regime == Regime::F || ob.regime == Regime::N,
        "regime {}: {}",
        ob.regime,
        ob.regime_reason.text
    );
}
