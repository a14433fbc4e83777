//! Error-controlled steps ([`slither::integrator::adaptive`]) and variable-step BDF2
//! ([`slither::integrator::bdf2`]): accuracy against fine fixed-step references, second order
//! through step-size changes, stick-slip still exact, frames on the output interval, and the
//! `[time]` keys' validation.
mod common;

use common::model;
use slither::integrator::{Integrator, Natural, StepError};
use slither::model::Model;
use slither::problem;
use slither::rod::vec3::f;
use slither::sim;
use slither::state::State;

/// `problems/cantilever_swing.toml` (0.5 s) with the given integrator, first step and, when
/// `tol` is given, adaptive steps with that tolerance.
fn swing(integrator: &str, dt: f64, tol: Option<f64>) -> Model {
    let text = std::fs::read_to_string("problems/cantilever_swing.toml").unwrap();
    let mut p = problem::parse(&text, std::path::Path::new("cantilever_swing.toml")).unwrap();
    p.solver.integrator = match integrator {
        "bdf2" => problem::IntegratorKind::Bdf2,
        _ => problem::IntegratorKind::ImplicitEuler,
    };
    p.time.dt = Some(dt);
    p.time.duration = Some(0.5);
    if let Some(tol) = tol {
        p.time.adaptive = true;
        p.time.error_tolerance = Some(tol);
    }
    Model::new(&p)
}

/// Run a model by its own schedule (fixed or adaptive) to the end.
fn run(m: &Model) -> sim::Outcome {
    let o = sim::run_gait(m, m.solver.integrator, &mut |_| {}, &mut |_| {}).unwrap();
    assert!(o.error.is_none(), "{:?}", o.error);
    o
}

fn final_nodes(m: &Model, o: &sim::Outcome) -> Vec<[f64; 3]> {
    m.real.clone().map(|i| o.state.node(i)).collect()
}

/// The swing's reference: BDF2 at a fixed 1.25e-4 s (its error is below 1e-6 m: the fixed-step
/// differences at 4e-3, 2e-3 and 1e-3 s fall with order 2.7 in tests/bdf2.rs).
fn swing_reference() -> Vec<[f64; 3]> {
    let m = swing("bdf2", 1.25e-4, None);
    let o = run(&m);
    final_nodes(&m, &o)
}

/// The tolerance bounds the local error per step; the global error of a method of order `p`
/// under such control scales as `tol^(p/(p+1))` (2/3 for BDF2, 1/2 for implicit Euler). On the
/// swing (0.5 s) both methods meet their tolerance in that sense, the step size varies, the
/// run ends exactly at the duration, and BDF2 needs fewer steps than implicit Euler for a
/// smaller error.
#[test]
fn adaptive_steps_meet_the_tolerance_on_the_cantilever_swing() {
    let reference = swing_reference();
    let mut finest = Vec::new();
    for (integrator, p) in [("bdf2", 2.0), ("implicit", 1.0)] {
        let mut errors = Vec::new();
        for tol in [1e-4, 1e-5, 1e-6] {
            let m = swing(integrator, 1e-3, Some(tol));
            let o = run(&m);
            let err = slither::charts::max_distance(&final_nodes(&m, &o), &reference);
            let st = o.steps;
            println!(
                "{integrator} tol {tol:e}: error {err:.3e} m ({:.1} x tol L), {} steps, {} rejected, dt {:.2e} .. {:.2e} s",
                err / (tol * m.length), st.accepted, st.rejected, st.dt_min, st.dt_max
            );
            assert!(st.adaptive && st.accepted == o.stats.steps);
            // A rejected step was solved (at least one Newton iteration) before its error
            // estimate refused it; that work is counted apart from the accepted steps'.
            assert!(
                o.stats.rejected_iterations >= st.rejected_error,
                "{} iterations in {} rejected steps",
                o.stats.rejected_iterations,
                st.rejected_error
            );
            assert_eq!(o.state.t, 0.5, "ends on the duration");
            assert!(st.dt_max > 2.0 * st.dt_min, "the step varies");
            assert!(st.error_max <= 1.0);
            // Within a factor 2000 of tol L over the 0.5 s swing (the global error sums the
            // local errors of hundreds of steps, each up to tol L).
            assert!(
                err < 2000.0 * tol * m.length,
                "{integrator} tol {tol}: {err}"
            );
            errors.push((err, st.accepted));
        }
        // Global error ~ tol^(p/(p+1)): each decade of tol divides the error by 10^(p/(p+1))
        // (4.6 for BDF2, 3.2 for Euler); accept 70 % of that.
        let rate = 10f64.powf(p / (p + 1.0));
        for w in errors.windows(2) {
            assert!(w[0].0 / w[1].0 > 0.7 * rate, "{integrator}: {errors:?}");
        }
        finest.push(*errors.last().unwrap());
    }
    // BDF2 at tol 1e-6 against implicit Euler at tol 1e-6: smaller error with fewer steps.
    let (bdf2, euler) = (finest[0], finest[1]);
    assert!(
        bdf2.0 < euler.0 && bdf2.1 < euler.1,
        "{bdf2:?} vs {euler:?}"
    );
}

/// Variable-step BDF2 keeps second order when the step changes every step: the swing stepped by
/// a repeating pattern of steps `(1, 1.5, 0.5) h` (ratios 1.5, 1/3, 2) at three `h` has
/// observed order near 2 (implicit Euler restarts at every change would give order 1).
#[test]
fn variable_step_bdf2_is_second_order() {
    let pattern = [1.0, 1.5, 0.5];
    let finals: Vec<Vec<[f64; 3]>> = [40usize, 80, 160]
        .iter()
        .map(|&blocks| {
            let m = swing("bdf2", 1e-3, None);
            let h = 0.5 / (3.0 * blocks as f64);
            let mut integ = Integrator::new(&m, Box::new(Natural));
            let mut s = State::initial(&m);
            for _ in 0..blocks {
                for r in pattern {
                    integ.step(&mut s, r * h).unwrap();
                }
            }
            assert!((s.t - 0.5).abs() < 1e-12);
            assert_eq!(integ.stats().step_halvings, 0);
            m.real.clone().map(|i| s.node(i)).collect()
        })
        .collect();
    let d1 = slither::charts::max_distance(&finals[0], &finals[1]);
    let d2 = slither::charts::max_distance(&finals[1], &finals[2]);
    let order = (d1 / d2).log2();
    println!("variable-step BDF2: differences {d1:.3e}, {d2:.3e} m, observed order {order:.3}");
    assert!(order >= 1.8, "order {order}");
}

/// Output frames stay on the `[output] interval` with adaptive steps (0.01 s on the swing).
#[test]
fn adaptive_frames_land_on_the_output_interval() {
    let m = swing("bdf2", 1e-3, Some(1e-5));
    let o = run(&m);
    assert_eq!(o.frames.len(), 51);
    for (k, fr) in o.frames.iter().enumerate() {
        assert!(
            (fr.t - 0.01 * k as f64).abs() < 1e-9,
            "frame {k} at {}",
            fr.t
        );
    }
}

/// A step that would have to shrink below `dt_min` stops the run with the time, the step and
/// the reason, keeping everything computed so far.
#[test]
fn a_step_below_dt_min_stops_the_run_with_a_clear_error() {
    let text = std::fs::read_to_string("problems/cantilever_swing.toml").unwrap();
    let text = text.replace(
        "duration = 0.5                # s: the head falls 0.85 m (clamp-to-head chord 71 deg down)",
        "duration = 0.5\nadaptive = true\nerror_tolerance = 1e-12\ndt_min = 5e-4",
    );
    let p = problem::parse(&text, std::path::Path::new("swing.toml")).unwrap();
    let m = Model::new(&p);
    let o = sim::run_gait(&m, m.solver.integrator, &mut |_| {}, &mut |_| {}).unwrap();
    let Some(StepError::BelowMinimum { t, dt, dt_min, .. }) = &o.error else {
        panic!("expected BelowMinimum, got {:?}", o.error);
    };
    let msg = o.error.as_ref().unwrap().to_string();
    println!("{msg}");
    assert_eq!(*dt_min, 5e-4);
    assert!(*dt < 5e-4 && *t < 0.5);
    assert!(msg.contains("time.dt_min") && msg.contains("local error estimate"));
    assert_eq!(o.status(), sim::RunStatus::Failed);
    assert!(!o.frames.is_empty());
}

// ---------------------------------------------------------------------------------------------
// Stick-slip with adaptive BDF2 (the scenes of tests/contact.rs).
// ---------------------------------------------------------------------------------------------

const G: f64 = 9.81;
const MU: [f64; 3] = [0.11, 0.14, 0.20];

/// A 20-element rod on the ground, adaptive BDF2 from a first step of 1e-3 s.
fn ground_scene(heading: f64, velocity: [f64; 3], incline: f64, duration: f64) -> Model {
    model(&format!(
        r#"
[rod]
length = 1.0
diameter = 0.02
elements = 20
bending_stiffness = 1e-2
[initial]
heading_deg = {heading}
velocity = [{}, {}, {}]
[ground]
mu_forward = {}
mu_backward = {}
mu_sideways = {}
incline_deg = {incline}
[time]
dt = 1e-3
duration = {duration}
adaptive = true
[solver]
integrator = "bdf2"
"#,
        velocity[0], velocity[1], velocity[2], MU[0], MU[1], MU[2]
    ))
}

fn simulate(m: &Model, each: &mut dyn FnMut(&State)) -> sim::Outcome {
    let o = sim::drive(
        m,
        &mut Integrator::new(m, Box::new(Natural)),
        sim::Schedule::of(m),
        std::time::Instant::now(),
        &mut |_| {},
        each,
    );
    assert!(o.error.is_none(), "{:?}", o.error);
    assert!(o.steps.adaptive);
    o
}

fn stop_distance(heading: f64, v: [f64; 3], mu: f64) {
    let m = ground_scene(heading, v, 0.0, 1.1 * f::norm(v) / (mu * G));
    let c0 = State::initial(&m).centroid(&m);
    let ceiling = 0.5 * m.diameter * (1.0 + 2e-6);
    let o = simulate(&m, &mut |s| {
        let h = m
            .real
            .clone()
            .map(|i| s.node(i)[2])
            .fold(f64::MIN, f64::max);
        assert!(h <= ceiling, "rod rose to {h} at t = {}", s.t);
    });
    let s = &o.state;
    let d = f::norm(f::sub(s.centroid(&m), c0));
    let expected = f::dot(v, v) / (2.0 * mu * G);
    let speed = f::norm(s.node_velocity(m.real.start));
    println!(
        "heading {heading}: stopped after {d:.6} m (analytic {expected:.6} m), speed {speed:e}, {} steps ({} rejected), dt {:.2e} .. {:.2e} s",
        o.steps.accepted, o.steps.rejected, o.steps.dt_min, o.steps.dt_max
    );
    assert!((d / expected - 1.0).abs() < 0.01);
    assert!(speed < 1e-9, "still moving at {speed}");
}

#[test]
fn adaptive_bdf2_slides_to_the_analytic_stop_distances() {
    stop_distance(0.0, [0.5, 0.0, 0.0], MU[0]);
    stop_distance(0.0, [-0.5, 0.0, 0.0], MU[1]);
    stop_distance(90.0, [0.5, 0.0, 0.0], MU[2]);
}

fn incline(heading: f64, mu: f64) {
    let critical = mu.atan().to_degrees();
    let below = critical - 2.0;
    let m = ground_scene(heading, [0.0; 3], below, 1.0);
    let c0 = State::initial(&m).centroid(&m);
    let o = simulate(&m, &mut |_| {});
    let drift = f::norm(f::sub(o.state.centroid(&m), c0));
    println!(
        "heading {heading}: {below:.2} deg: drift {drift:e} m, {} steps, dt up to {:.2e} s",
        o.steps.accepted, o.steps.dt_max
    );
    assert!(drift < 1e-9, "crept by {drift} m below the threshold");
    let above = critical + 4.0;
    let m = ground_scene(heading, [0.0; 3], above, 0.5);
    let o = simulate(&m, &mut |_| {});
    let s = &o.state;
    let vx: f64 = m.real.clone().map(|i| s.node_velocity(i)[0]).sum::<f64>() / m.real.len() as f64;
    let acc = -vx / s.t;
    let b = above.to_radians();
    let expected = G * (b.sin() - mu * b.cos());
    println!(
        "heading {heading}: {above:.2} deg: acceleration {acc:.9} (analytic {expected:.9}), rel {:.2e}",
        acc / expected - 1.0
    );
    // Rigid sliding from rest at constant acceleration: BDF2 gives the velocity exactly, so
    // only the solver's tolerance is left: measured 2.5e-13 (heading 0) and 3e-16 (90). The
    // bound is the one of tests/contact.rs, whose conic-only path reaches 2.9e-7.
    assert!(
        (acc / expected - 1.0).abs() < 1e-6,
        "acceleration {acc} vs {expected}"
    );
}

#[test]
fn adaptive_bdf2_sticks_below_and_slides_above_the_friction_angle() {
    incline(0.0, MU[1]);
    incline(90.0, MU[2]);
}

// ---------------------------------------------------------------------------------------------
// Bad `[time]` settings exit with code 2 naming the key.
// ---------------------------------------------------------------------------------------------

const BASE: &str = "\
[rod]
length = 1.0
diameter = 0.02
elements = 4
bending_stiffness = 1.0

[time]
dt = 0.005
duration = 0.01
";

/// Run `slither run` on `text`; returns (exit code, stderr).
fn cli(name: &str, text: &str) -> (Option<i32>, String) {
    cli_with(name, text, &[]).0
}

/// Run `slither run` on `text` with extra arguments; returns (exit code, stderr) and the
/// `summary.json` text if one was written.
fn cli_with(name: &str, text: &str, args: &[&str]) -> ((Option<i32>, String), Option<String>) {
    let dir = std::env::temp_dir().join(format!("slither-adaptive-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let problem = dir.join("problem.toml");
    std::fs::write(&problem, text).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_slither"))
        .arg("run")
        .arg(&problem)
        .arg("--out")
        .arg(dir.join("out"))
        .arg("--quiet")
        .args(args)
        .output()
        .unwrap();
    let summary = std::fs::read_to_string(dir.join("out/summary.json")).ok();
    let _ = std::fs::remove_dir_all(&dir);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    if out.status.code() == Some(2) {
        assert!(
            summary.is_none(),
            "{name}: no summary after a rejected file"
        );
    }
    ((out.status.code(), err), summary)
}

#[test]
fn accuracy_settings_are_checked_and_reported() {
    // Out of range, on the command line and in the file; a scene without ground or gait.
    let ((code, err), _) = cli_with("acc_flag", BASE, &["--accuracy", "2"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("--accuracy") && err.contains("[1e-4, 0.5]"),
        "{err}"
    );
    let ((code, err), _) = cli_with("acc_scene", BASE, &["--accuracy", "0.01"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("[ground]"), "{err}");
    let (code, err) = cli("acc_file", &format!("{BASE}[accuracy]\ntarget = 0.0\n"));
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("`accuracy.target`") && err.contains("[1e-4, 0.5]"),
        "{err}"
    );
    // A small S-start with a target: summary.json reports the chosen model and the estimates.
    let mut text = std::fs::read_to_string("problems/s_start.toml").unwrap();
    for (from, to) in [
        ("elements = 100", "elements = 20"),
        (
            "duration = 3.572               # T: the pulse leaves the tail",
            "duration = 0.3",
        ),
        (
            "interval = 0.036               # 10 steps",
            "interval = 0.03",
        ),
    ] {
        assert!(text.contains(from), "problems/s_start.toml has no `{from}`");
        text = text.replace(from, to);
    }
    text += "\n[accuracy]\ntarget = 0.2\nmax_elements = 40\n";
    let ((code, err), summary) = cli_with("acc_run", &text, &[]);
    let v: serde_json::Value = serde_json::from_str(&summary.unwrap()).unwrap();
    let a = &v["accuracy"];
    // Exit 4 (results written) when the target is not met, 0 when it is.
    let met = a["met"].as_bool().unwrap();
    assert_eq!(code, Some(if met { 0 } else { 4 }), "{err}");
    println!("{a}");
    assert_eq!(a["target"], 0.2);
    let chosen = a["elements"].as_u64().unwrap();
    assert!(chosen == 20 || chosen == 40);
    assert!(a["runs"].as_array().unwrap().len() >= 3);
    let est = a["estimated_error"].as_f64().unwrap();
    assert_eq!(a["met"].as_bool().unwrap(), est <= 0.2);
    // The summary's own v_s/v_m is the chosen run's.
    let vs = v["v_s_over_v_m"].as_f64().unwrap();
    assert!(a["runs"]
        .as_array()
        .unwrap()
        .iter()
        .any(|r| r["elements"].as_u64() == Some(chosen) && r["v_s_over_v_m"].as_f64() == Some(vs)));
    // The file runs BDF2 at fixed steps, which the selection refines as implicit Euler: the
    // chosen model is fixed steps.
    assert_eq!(a["integrator"], "implicit");
    assert!(a["dt"].as_f64().is_some() && a.get("error_tolerance").is_none());
    assert_eq!(v["time_steps"]["adaptive"], false);
}

#[test]
fn bad_adaptive_settings_exit_2_naming_the_key() {
    let cases: &[(&str, &str, &str, &str)] = &[
        (
            "tol_zero",
            "adaptive = true\nerror_tolerance = 0.0",
            "time.error_tolerance",
            "[1e-12, 0.1]",
        ),
        (
            "tol_big",
            "adaptive = true\nerror_tolerance = 0.5",
            "time.error_tolerance",
            "0.1",
        ),
        (
            "tol_nan",
            "adaptive = true\nerror_tolerance = nan",
            "time.error_tolerance",
            "0.1",
        ),
        (
            "dt_min_big",
            "adaptive = true\ndt_min = 0.006",
            "time.dt_min",
            "(0, time.dt]",
        ),
        (
            "dt_min_neg",
            "adaptive = true\ndt_min = -1e-6",
            "time.dt_min",
            "(0, time.dt]",
        ),
        (
            "dt_max_small",
            "adaptive = true\ndt_max = 0.001",
            "time.dt_max",
            "[time.dt, time.duration]",
        ),
        (
            "dt_max_long",
            "adaptive = true\ndt_max = 1.0",
            "time.dt_max",
            "[time.dt, time.duration]",
        ),
        (
            "tol_fixed",
            "error_tolerance = 1e-4",
            "time.error_tolerance",
            "time.adaptive = true",
        ),
        (
            "dt_max_fixed",
            "dt_max = 0.01",
            "time.dt_max",
            "time.adaptive = true",
        ),
        (
            "adaptive_type",
            "adaptive = \"yes\"",
            "time.adaptive",
            "true or false",
        ),
        (
            "explicit",
            "adaptive = true\n[solver]\nintegrator = \"explicit\"",
            "solver.integrator",
            "time.adaptive = true",
        ),
    ];
    for (name, extra, key, allowed) in cases {
        let text = format!("{BASE}{extra}\n");
        let (code, err) = cli(name, &text);
        assert_eq!(code, Some(2), "{name}: {err}");
        assert!(
            err.contains(&format!("`{key}`")),
            "{name} names {key}: {err}"
        );
        assert!(err.contains(allowed), "{name} states {allowed}: {err}");
        assert!(err.contains("problem.toml"), "{name} names the file: {err}");
    }
    let text = BASE
        .replace("[time]", "[rod.x]")
        .replace("[rod.x]", "[time]")
        + "adaptive = true\nmode = \"static\"\n";
    let text = text.replace(
        "bending_stiffness = 1.0",
        "bending_stiffness = 1.0\nclamp = \"tail\"",
    );
    let (code, err) = cli("static", &text);
    assert_eq!(code, Some(2), "static: {err}");
    assert!(err.contains("`time.adaptive`"), "{err}");
    // A valid adaptive file runs.
    let (code, err) = cli(
        "valid",
        &format!("{BASE}adaptive = true\nerror_tolerance = 1e-4\n"),
    );
    assert_eq!(code, Some(0), "{err}");
}

// ---------------------------------------------------------------------------------------------
// The gait work-precision chart and the accuracy selection, on a small S-start.
// ---------------------------------------------------------------------------------------------

/// `problems/s_start.toml` cut to `elements` and `duration` (s).
fn small_s_start(elements: usize, duration: f64) -> problem::Problem {
    let text = std::fs::read_to_string("problems/s_start.toml").unwrap();
    let mut p = problem::parse(&text, std::path::Path::new("s_start.toml")).unwrap();
    p.rod.elements = elements;
    p.time.duration = Some(duration);
    p.output.interval = Some(duration / 10.0);
    p
}

#[test]
fn gait_chart_measures_errors_and_caches_its_reference() {
    let p = small_s_start(20, 0.6);
    let m = Model::new(&p);
    let opts = slither::charts::GaitPrecisionOptions {
        // The scene's mesh only, without the accuracy point (the chart's defaults add two
        // finer meshes and an accuracy selection).
        meshes: vec![20],
        accuracy_target: None,
        euler_dt: vec![8e-3, 2e-3],
        bdf2_dt: vec![8e-3, 2e-3],
        tolerances: vec![1e-3, 1e-5],
        adaptive_first_dt: 2e-3,
        reference_integrator: problem::IntegratorKind::ImplicitEuler,
        reference_dt: 1e-3,
        reference_change: 1e-3,
        reference_halvings: 5,
        reference_jitter: 0.04,
    };
    let dir = std::env::temp_dir().join(format!("slither-gait-chart-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let cache = dir.join("reference.json");
    let mut lines = Vec::new();
    let g = slither::charts::gait_precision("small", &p, &m, &opts, Some(&cache), &mut |l| {
        lines.push(l.to_string())
    })
    .unwrap();
    print!("{}", g.summary());
    assert_eq!(g.points.len(), 6);
    let r = &g.reference;
    assert!(r.runs.len() >= 2 && r.scatter_runs.len() == 2);
    assert!(r
        .runs
        .iter()
        .chain(&r.scatter_runs)
        .all(|x| x.method.name() == "implicit" && x.tolerance.is_none()));
    assert!(r.v_ratio.is_finite() && r.v_ratio > 0.0);
    assert!(r.scatter.is_finite());
    for pt in &g.points {
        assert_eq!(pt.run.status, "ok");
        assert!(pt.v_error.is_finite() && pt.x_error.is_finite());
        // The error is measured against the reference, not taken from it.
        assert_eq!(
            pt.v_error,
            (pt.run.v_ratio / r.v_ratio - 1.0).abs(),
            "{}",
            pt.run.method
        );
    }
    // Against the converged implicit Euler reference: implicit Euler's coarse step is further
    // from it in the centreline than its fine step (first order), and BDF2 (second order) is
    // closer than implicit Euler at each step. (BDF2's own 8e-3 and 2e-3 s are not ordered on
    // this scene: 4.3e-3 and 4.6e-3 L, stick-slip.)
    let errors = |method: &str| -> Vec<f64> {
        g.points
            .iter()
            .filter(|pt| pt.run.method.name() == method)
            .map(|pt| pt.x_error)
            .collect()
    };
    let (ie, bdf2) = (errors("implicit"), errors("bdf2"));
    assert!(ie[0] > ie[1], "implicit: {ie:?}");
    assert!(bdf2[0] < ie[0] && bdf2[1] < ie[1], "{bdf2:?} vs {ie:?}");
    assert!(r.converged, "reference change {}", r.change);
    slither::charts::write_gait_precision(&dir, &g).unwrap();
    for f in [
        "gait_precision.csv",
        "gait_precision.json",
        "gait_precision.png",
        "gait_precision_centreline.png",
        "reference.json",
    ] {
        assert!(dir.join(f).exists(), "{f}");
    }
    // Second time: the reference comes from the cache, identical.
    let mut lines2 = Vec::new();
    let r2 = slither::charts::gait_reference(&p, &m, &opts, Some(&cache), &mut |l| {
        lines2.push(l.to_string())
    })
    .unwrap();
    assert!(
        lines2.len() == 1 && lines2[0].contains("cached"),
        "{lines2:?}"
    );
    assert_eq!(r2.v_ratio, r.v_ratio);
    // Another setting is another key: recomputed.
    let opts3 = slither::charts::GaitPrecisionOptions {
        reference_halvings: 0,
        ..opts.clone()
    };
    let mut lines3 = Vec::new();
    slither::charts::gait_reference(&p, &m, &opts3, Some(&cache), &mut |l| {
        lines3.push(l.to_string())
    })
    .unwrap();
    assert!(!lines3[0].contains("cached"), "{lines3:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
