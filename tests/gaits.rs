//! Gaits on the bundled problems: the juvenile S-start, the heavy adult that cannot, periodic
//! S-starts as sidewinding, and lateral undulation (issue: muscles, gaits, topology).
//! These are full 4-5 s simulations (tens of seconds each in release).
use slither::gait::Muscles;
use slither::model::Model;
use slither::observe::{self, Observables, Regime};
use slither::{problem, sim};
use std::path::Path;

fn run(path: &str) -> (Model, Observables, sim::Outcome) {
    let p = problem::load(Path::new(path)).unwrap();
    let m = Model::new(&p);
    let o = sim::run(
        &m,
        Box::new(Muscles {
            gait: m.gait.clone(),
        }),
        &mut |_| {},
        &mut |_| {},
    );
    assert!(o.error.is_none(), "{path}: {:?}", o.error);
    let ob = observe::of_outcome(&m, &o);
    println!("{path}: {ob:?}\n  max strain {:.2e}, max penetration {:.2e} m, {} steps in {:.1} s, {} halvings", o.max_strain, o.max_penetration, o.stats.steps, o.wall_time_s, o.stats.step_halvings);
    (m, ob, o)
}

#[test]
fn juvenile_s_starts_forward() {
    let (m, ob, o) = run("problems/s_start.toml");
    assert!(o.max_strain < 1e-3, "strain {}", o.max_strain);
    assert!(o.max_penetration < 1e-6 * m.diameter);
    assert!(ob.v_s_over_v_m > 0.05, "v_s/v_m {}", ob.v_s_over_v_m);
    assert!(
        ob.displacement_angle_deg <= 30.0,
        "moved {} degrees off the head direction",
        ob.displacement_angle_deg
    );
    assert!(
        ob.middle_slip_over_v_m < 0.1,
        "middle slips at {} v_m",
        ob.middle_slip_over_v_m
    );
    assert!(
        ob.middle_static_fraction >= 0.8,
        "middle static in only {} of the pulse frames",
        ob.middle_static_fraction
    );
    assert!(ob.lifted_arcs_max >= 2 && ob.max_elevation_over_a >= 0.5);
    assert!(
        (ob.lambda_pulse_speed / m.gait.speed - 1.0).abs() <= 0.15,
        "pulse speed {}",
        ob.lambda_pulse_speed
    );
    assert!(ob.lambda_pulse_r2 >= 0.8);
    assert!(
        ob.lambda_amplitude_variation <= 0.30,
        "amplitude variation {}",
        ob.lambda_amplitude_variation
    );
    assert_eq!(ob.regime, Regime::S, "{}", ob.regime_reason.text);
    assert!(ob.regime_reason.not_s.is_empty());
    assert!(ob.two_arc_lift_over_a >= 0.5, "{}", ob.two_arc_lift_over_a);
    // The writhe snapshot: when couple b (0.35 L) reaches mid-body, (0.5 - 0.35) L / v_m,
    // to within half an output interval; a frame's writhe, so within the largest |writhe|.
    let t_star = (0.5 - 0.35) * m.length / m.gait.speed;
    assert!(
        (ob.writhe_snapshot_t - t_star).abs() <= 0.5 * 0.036 + 1e-12,
        "snapshot at {} s, not {t_star} s",
        ob.writhe_snapshot_t
    );
    assert!(ob.writhe_snapshot.is_finite() && ob.writhe_snapshot.abs() <= ob.writhe_max);
}

#[test]
fn heavy_adult_cannot_s_start() {
    let (_, ob, _) = run("problems/s_start_heavy.toml");
    assert!(ob.v_s_over_v_m.abs() < 0.01, "v_s/v_m {}", ob.v_s_over_v_m);
    assert!(
        ob.regime == Regime::F || ob.regime == Regime::N,
        "regime {}: {}",
        ob.regime,
        ob.regime_reason.text
    );
    assert!(
        ob.max_elevation_over_a < 0.5,
        "lifted to {} a",
        ob.max_elevation_over_a
    );
}

#[test]
fn periodic_s_starts_sidewind() {
    let (_, ob, o) = run("problems/sidewinding.toml");
    // This run is the bundled scene where the active set's line search backtracks (once):
    // its sufficient-decrease test is deferred to the next assembly, and on failure the step
    // is backtracked from the saved iterate. The run must land where the immediate test took
    // it: v_s = 0.02355980099372444 m/s with the line search before the deferral (commit
    // 4fc56e1, bitwise equal since).
    assert!(
        o.stats.newton.backtracks >= 1,
        "no backtrack: the deferred path is not exercised"
    );
    assert!(
        (ob.v_s - 0.02355980099372444).abs() < 1e-9 * 0.0236,
        "v_s {} m/s",
        ob.v_s
    );
    assert!(
        ob.displacement_angle_deg >= 60.0,
        "moved {} degrees off the body axis",
        ob.displacement_angle_deg
    );
    assert!(
        ob.two_patch_fraction > 0.5,
        "two contact patches in {} of the frames",
        ob.two_patch_fraction
    );
    assert!(
        ob.contact_slip_over_v_m < 0.1,
        "contacts slip at {} v_m",
        ob.contact_slip_over_v_m
    );
}

#[test]
fn serpenoid_slithers_forward() {
    let (_, ob, _) = run("problems/serpenoid.toml");
    println!("serpenoid average forward speed {} m/s", ob.v_s);
    assert!(ob.v_s > 0.0 && ob.displacement_angle_deg < 10.0);
}
