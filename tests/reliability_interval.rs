//! The measured observables and the regime do not depend on `[output] interval`: they are
//! measured on the observation grid ([`slither::sim::observation_interval`]), which the
//! physics sets, while the interval only chooses the frames written for the user.
//!
//! With fixed steps the interval does not touch the physics either, so the observables must be
//! equal to the last bit; the tests assert that (a tolerance of zero).
use proptest::prelude::*;
use slither::model::Model;
use slither::observe::{self, Observables};
use slither::{problem, sim};
use std::path::Path;

fn run(p: &problem::Problem) -> (Observables, sim::Outcome) {
    let m = Model::new(p);
    let o = sim::run_gait(&m, p.solver.integrator, &mut |_| {}, &mut |_| {}).unwrap();
    assert!(o.error.is_none(), "{:?}", o.error);
    (observe::of_outcome(&m, &o), o)
}

/// The observables the regime and the studies use, by name.
fn measured(o: &Observables) -> [(&'static str, f64); 9] {
    [
        ("v_s_over_v_m", o.v_s_over_v_m),
        ("writhe_max", o.writhe_max),
        ("writhe_snapshot", o.writhe_snapshot),
        ("lambda_pulse_r2", o.lambda_pulse_r2),
        ("lambda_pulse_speed_over_v_m", o.lambda_pulse_speed_over_v_m),
        ("max_elevation_over_a", o.max_elevation_over_a),
        ("arc_lift_max_over_a", o.arc_lift_max_over_a),
        ("two_arc_lift_over_a", o.two_arc_lift_over_a),
        ("displacement_angle_deg", o.displacement_angle_deg),
    ]
}

fn assert_same(a: &Observables, b: &Observables, what: &str) {
    assert_eq!(
        a.regime, b.regime,
        "{what}: {} vs {}",
        a.regime_reason.text, b.regime_reason.text
    );
    for ((name, x), (_, y)) in measured(a).into_iter().zip(measured(b)) {
        assert!(x.to_bits() == y.to_bits(), "{what}: {name} {x} vs {y}");
    }
}

#[test]
fn s_start_observables_do_not_depend_on_the_output_interval() {
    let base = problem::load(Path::new("problems/s_start.toml")).unwrap();
    let at = |interval: f64| {
        let mut p = base.clone();
        p.output.interval = Some(interval);
        run(&p)
    };
    let (reference, o_ref) = at(0.036);
    println!("0.036: {:?}", measured(&reference));
    assert_eq!(
        reference.regime,
        observe::Regime::S,
        "{}",
        reference.regime_reason.text
    );
    for interval in [0.25, 1.0] {
        let (ob, o) = at(interval);
        println!("{interval}: {:?}", measured(&ob));
        // The interval did change what was written...
        assert!(o.frames.len() < o_ref.frames.len());
        // ... and not what was measured.
        assert_eq!(o.observed.len(), o_ref.observed.len());
        assert_same(&reference, &ob, &format!("interval {interval}"));
        // Measured on the sparse output frames instead, the same run reads differently (the
        // defect this guards against): at 1.0 s only 5 frames, no pulse fit.
        if interval == 1.0 {
            let m = Model::new(&base);
            let fl = observe::fields(&m, &o.frames);
            let sparse = observe::observe(&m, &o.frames, &fl);
            assert!(sparse.regime != reference.regime || sparse.writhe_max != reference.writhe_max);
        }
    }
}

/// A short S-start (20 elements, the first 0.4 s): cheap enough for a property test.
fn short_scene() -> problem::Problem {
    let mut p = problem::load(Path::new("problems/s_start.toml")).unwrap();
    p.rod.elements = 20;
    p.gait.sigma = 0.08;
    p.time.duration = Some(0.4);
    p.time.dt = Some(4e-3);
    p
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 6, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn the_interval_changes_frames_not_observables(interval in 0.004f64..0.6) {
        use std::sync::OnceLock;
        static REFERENCE: OnceLock<Observables> = OnceLock::new();
        let reference = REFERENCE.get_or_init(|| run(&short_scene()).0);
        let mut p = short_scene();
        p.output.interval = Some(interval);
        let (ob, _) = run(&p);
        assert_same(reference, &ob, &format!("interval {interval}"));
    }
}

#[test]
fn the_observation_grid_is_set_by_the_pulse_time() {
    let p = problem::load(Path::new("problems/s_start.toml")).unwrap();
    let m = Model::new(&p);
    // T = L / v_m = 1 / 0.28 s, over 200.
    let expected = 1.0 / 0.28 / sim::OBSERVATIONS_PER_PULSE;
    assert!((sim::observation_interval(&m) - expected).abs() < 1e-15);
    let s = sim::Schedule::of(&m);
    assert_eq!(s.observe_every, 5, "0.01786 s in steps of 3.6 ms");
}
