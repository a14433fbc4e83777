//! Unit tests of the gait work-precision chart ([`super`]).
use super::*;

/// A fixed-step run has no tolerance: its line says so instead of printing "tol NaN".
#[test]
fn a_fixed_step_run_prints_its_step_not_a_nan_tolerance() {
    assert_eq!(step_text("2.0e-3", None), "dt 2.0e-3 s, fixed step");
    assert_eq!(step_text("2.0e-3", Some(1e-4)), "dt 2.0e-3 s, tol 1e-4");
    let mut lines = Vec::new();
    let run = GaitRun {
        method: GaitMethod::Fixed(IntegratorKind::ImplicitEuler),
        elements: 50,
        dt: 2e-3,
        tolerance: None,
        v_ratio: 0.23,
        wall_s: 0.5,
        steps: 2000,
        rejected: 0,
        dt_range: (2e-3, 2e-3),
        status: "ok".into(),
        x: Vec::new(),
    };
    log_run(&mut |l: &str| lines.push(l.to_string()), "run", &run);
    assert!(!lines[0].contains("NaN"), "{}", lines[0]);
    assert!(lines[0].contains("fixed step"), "{}", lines[0]);
}
