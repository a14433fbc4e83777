//! The growth line of a phase study (`[phase] growth = { ... }`): its sizes' `W` and `G`, the
//! dimensional similarity that lets each size run as a cell of the base, the verdict, and the
//! files (resumable, refused input named).
mod common;

use slither::model::Model;
use slither::observe::{self, Measure, Regime};
use slither::problem::{self, Problem};
use slither::studies::optimize::Status;
use slither::studies::phase::{
    self,
    growth::{self, Growth, GrowthLine, GrowthPoint},
    Cell,
};
use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_slither");

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("slither-growth-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The tiny S-start with a longer run (the pulse a third of the way along the body).
fn base() -> Problem {
    let text = common::TINY_S_START
        .replace("duration = 0.1", "duration = 1.2")
        .replace("dt = 1e-2", "dt = 5e-3");
    problem::parse(&text, Path::new("base.toml")).unwrap()
}

fn moon(diameters: Vec<f64>) -> Growth {
    Growth {
        diameters,
        stress: growth::MOON_STRESS,
        reference_diameter: growth::MOON_REFERENCE,
        exponent: growth::MOON_EXPONENT,
    }
}

/// `W` and `G` of a problem, from its own SI values.
fn groups(p: &Problem) -> (f64, f64) {
    let r = &p.rod;
    (
        r.density * p.gravity.g * r.diameter.powi(2) * r.length.powi(3) / r.bending_stiffness,
        p.gait.stress * r.diameter.powi(3) * r.length / r.bending_stiffness,
    )
}

/// The sizes' `W` and `G` are those of the grown snake itself, `W` grows like `a` and `G`
/// like Moon's stress; at the base's own size they are the base's.
#[test]
fn sizes_have_the_grown_snakes_groups() {
    let b = base();
    let g = moon(vec![0.01, 0.02, 0.05, 0.1]);
    let pts = g.points(&b);
    for p in &pts {
        let grown = growth::grown_problem(&b, &g, p.diameter);
        let (w, gg) = groups(&grown);
        assert!((w / p.weight - 1.0).abs() < 1e-12, "{w} {}", p.weight);
        assert!((gg / p.torque - 1.0).abs() < 1e-12, "{gg} {}", p.torque);
        assert!((grown.rod.length / grown.rod.diameter - 50.0).abs() < 1e-9);
        assert!((Growth::young_modulus(&grown) / Growth::young_modulus(&b) - 1.0).abs() < 1e-12);
    }
    assert!((pts[3].weight / pts[0].weight - 10.0).abs() < 1e-12);
    let expect = 10f64.powf(growth::MOON_EXPONENT);
    assert!((pts[3].torque / pts[0].torque / expect - 1.0).abs() < 1e-12);
    // At the base's diameter (2 cm) with the base's own stress law value, the base's groups.
    let own = Growth {
        stress: b.gait.stress,
        reference_diameter: b.rod.diameter,
        ..moon(vec![b.rod.diameter])
    };
    let p = own.points(&b)[0];
    let (w0, g0) = groups(&b);
    assert!((p.weight / w0 - 1.0).abs() < 1e-12 && (p.torque / g0 - 1.0).abs() < 1e-12);
}

fn observe(p: &Problem) -> observe::Observables {
    let m = Model::new(p);
    let o = observe::evaluate(&m, Measure::Full, &mut |_| {}, &mut |_| {}).unwrap();
    assert!(o.outcome.error.is_none(), "{:?}", o.outcome.error);
    o.observables
}

/// Dimensional similarity: the snake of 5 cm itself (2.5 m long, in SI units) and the base's
/// cell at its `(W, G)` under the line's protocol (1 m long, softer, slower pulse) move alike
/// in every dimensionless observable. A protocol without similarity (`v_m` kept) does not.
#[test]
fn a_size_moves_as_its_cell() {
    let b = base();
    let g = moon(vec![0.05]);
    let pt = g.points(&b)[0];
    let real = observe(&growth::grown_problem(&b, &g, 0.05));
    let cell = observe(&phase::cell_problem_with(
        &b,
        pt.weight,
        pt.torque,
        growth::PROTOCOL,
    ));
    let plain = observe(&phase::cell_problem(&b, pt.weight, pt.torque));
    let vm_real = b.gait.speed;
    let vm_cell = phase::cell_problem_with(&b, pt.weight, pt.torque, growth::PROTOCOL)
        .gait
        .speed;
    let (r, c, n) = (
        real.v_s / vm_real,
        cell.v_s / vm_cell,
        plain.v_s / b.gait.speed,
    );
    eprintln!(
        "v_s/v_m: snake {r:.6}, similar cell {c:.6}, plain cell {n:.6}; max elevation/a {:.6} {:.6} {:.6}",
        real.max_elevation_over_a, cell.max_elevation_over_a, plain.max_elevation_over_a
    );
    assert!(r.abs() > 1e-3, "the run must move: v_s/v_m {r}");
    assert!((r - c).abs() < 1e-5 * r.abs(), "{r} vs {c}");
    assert!(
        (real.max_elevation_over_a - cell.max_elevation_over_a).abs()
            < 1e-5 * real.max_elevation_over_a
    );
    assert!(
        (real.displacement_angle_deg - cell.displacement_angle_deg).abs() < 0.05,
        "{} {}",
        real.displacement_angle_deg,
        cell.displacement_angle_deg
    );
    // The same (W, G) without similarity is another motion.
    assert!((r - n).abs() > 1e-2 * r.abs(), "{r} vs {n}");
}

fn cell(regime: Option<Regime>, agreement: Option<f64>) -> Cell {
    let v = 0.1;
    Cell {
        weight: 1.0,
        torque: 1.0,
        status: if regime.is_some() {
            Status::Ok
        } else {
            Status::Failed
        },
        regime,
        regime_detail: "-".into(),
        v_s_over_v_m: v,
        displacement_angle_deg: 0.0,
        max_elevation_over_a: 0.0,
        lifted_arcs_max: 0,
        writhe_max: 0.0,
        lambda_pulse_r2: 0.0,
        max_elevation_over_length: 0.0,
        two_arc_lift_over_a: 0.0,
        lambda_pulse_speed_over_v_m: 0.0,
        writhe_snapshot: 0.0,
        wall_time_s: 0.0,
        reason: String::new(),
        verify: agreement.map(|a| phase::Verification {
            label_agreement: a,
            v_s_over_v_m_min: v,
            v_s_over_v_m_max: v,
            regime_base: regime,
            regime_finer: regime,
            runs: 3,
            seed: 1,
        }),
        periodic: None,
    }
}

fn line(labels: &[(Option<Regime>, Option<f64>)]) -> GrowthLine {
    let b = base();
    let d: Vec<f64> = (0..labels.len()).map(|k| 0.01 * (k + 1) as f64).collect();
    let g = moon(d);
    let cells: Vec<(GrowthPoint, Cell)> = g
        .points(&b)
        .into_iter()
        .zip(labels)
        .map(|(p, &(r, a))| (p, cell(r, a)))
        .collect();
    GrowthLine::new(&b, &g, &cells)
}

/// The verdict: where the confident S label ends, and the two ways it may not.
#[test]
fn the_verdict_names_where_the_s_start_stops() {
    use Regime::*;
    let l = line(&[
        (Some(M), None),
        (Some(S), None),
        (Some(S), None),
        (Some(F), None),
    ]);
    assert_eq!(l.stops.len(), 1);
    assert_eq!((l.stops[0].last_s, l.stops[0].next), (0.03, 0.04));
    assert!(
        l.verdict.contains("between 3 cm (S) and 4 cm (F)"),
        "{}",
        l.verdict
    );
    assert!(
        l.verdict
            .starts_with("confident S at 2 of 4 sizes (2 cm, 3 cm)"),
        "{}",
        l.verdict
    );
    assert!(
        l.verdict.ends_with("below 2 cm, 1 cm is M"),
        "{}",
        l.verdict
    );
    assert_eq!(l.s_diameters, vec![0.02, 0.03]);
    // A not-confident S does not count as S; a not-confident next label is said so.
    let l = line(&[
        (Some(S), Some(1.0)),
        (Some(S), Some(0.5)),
        (Some(F), Some(1.0)),
    ]);
    assert_eq!((l.stops[0].last_s, l.stops[0].next), (0.01, 0.02));
    assert!(l.verdict.contains("S (not confident)"), "{}", l.verdict);
    let l = line(&[(Some(S), None), (None, None)]);
    assert!(
        l.verdict.contains("2 cm (- (not confident))"),
        "{}",
        l.verdict
    );
    let l = line(&[(Some(S), None), (Some(S), None)]);
    assert!(
        l.stops.is_empty() && l.verdict.contains("no threshold"),
        "{}",
        l.verdict
    );
    let l = line(&[(Some(M), None), (Some(F), None)]);
    assert!(
        l.stops.is_empty() && l.verdict.starts_with("no size"),
        "{}",
        l.verdict
    );
    let l = line(&[
        (Some(S), None),
        (Some(U), None),
        (Some(S), None),
        (Some(N), None),
    ]);
    assert_eq!(l.stops.len(), 2);
    assert!(l.verdict.contains("stops 2 times"), "{}", l.verdict);
}

/// A line whose every size failed has no answer: a failure verdict (not "no size
/// S-starts"), and `all_failed`, on which `phase` and `merge` exit 3.
#[test]
fn a_line_whose_every_size_failed_has_a_failure_verdict() {
    let l = line(&[(None, None), (None, None), (None, None)]);
    assert!(l.all_failed());
    assert_eq!(l.failed_sizes, 3);
    assert!(
        l.verdict
            .starts_with("every size between 1 cm and 3 cm failed"),
        "{}",
        l.verdict
    );
    assert!(!l.verdict.contains("S-starts"), "{}", l.verdict);
    // One size finished: a verdict on the others, not a failure.
    let l = line(&[(None, None), (Some(Regime::M), None)]);
    assert!(!l.all_failed());
    assert_eq!(l.failed_sizes, 1);
    assert!(l.verdict.starts_with("no size"), "{}", l.verdict);
}

fn slither(args: &[&str]) -> std::process::Output {
    Command::new(BIN).args(args).output().unwrap()
}

/// `slither phase` with a growth line writes its files, reuses its rows on a second run, and
/// names the key of a bad growth table.
#[test]
fn a_phase_run_draws_and_resumes_its_growth_line() {
    let d = scratch("run");
    std::fs::write(d.join("base.toml"), common::TINY_S_START).unwrap();
    let file = d.join("phase.toml");
    std::fs::write(
        &file,
        "[phase]\nbase = \"base.toml\"\nweight = [300.0]\ntorque = [15.0]\ngrowth = { diameters = { from = 0.01, to = 0.1, count = 3 } }\n",
    )
    .unwrap();
    let out = d.join("out");
    let run = || {
        slither(&[
            "phase",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ])
    };
    let o = run();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("growth line (3 sizes, 3 simulated now)"),
        "{err}"
    );
    for f in ["growth.csv", "growth.json", "growth.png", "growth.svg"] {
        assert!(out.join(f).exists(), "{f}");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("growth.json")).unwrap()).unwrap();
    let pts = json["points"].as_array().unwrap();
    assert_eq!(pts.len(), 3);
    // growth.json records how the sizes were run: no verification, the similar protocol.
    assert!(json["verify"].is_null(), "{json}");
    assert_eq!(json["protocol"]["similar"], true);
    assert_eq!(json["failed_sizes"], 0);
    assert!((pts[2]["diameter"].as_f64().unwrap() - 0.1).abs() < 1e-15);
    assert_eq!(
        std::fs::read_to_string(out.join("growth.csv"))
            .unwrap()
            .lines()
            .count(),
        4
    );
    let o = run();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("0 simulated now"), "{err}");
    assert_eq!(
        std::fs::read_to_string(out.join("growth.csv"))
            .unwrap()
            .lines()
            .count(),
        4
    );
    // Refused tables name phase.growth and the allowed values.
    for (bad, says) in [
        (
            "growth = { diameters = [0.02, 0.01] }",
            "strictly increasing",
        ),
        (
            "growth = { diameters = [0.01], stress = -1.0 }",
            "stress (Pa) finite and > 0",
        ),
        (
            "growth = { diameters = [0.01], exponent = 40.0 }",
            "exponent in [-10, 10]",
        ),
        ("growth = { sizes = [0.01] }", "sizes"),
    ] {
        std::fs::write(
            &file,
            format!("[phase]\nbase = \"base.toml\"\nweight = [300.0]\ntorque = [15.0]\n{bad}\n"),
        )
        .unwrap();
        let o = run();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{bad}: {err}");
        assert!(
            err.contains("phase.toml") && err.contains(says),
            "{bad}: {err}"
        );
    }
}

/// On the command line: a growth line whose every size failed (steps that would have to
/// fall below `dt_min`) says so in `growth.json` and on stderr, and exits 3.
#[test]
fn a_phase_run_whose_growth_line_failed_exits_3() {
    let d = scratch("all-failed");
    let base = common::TINY_S_START.replace(
        "dt = 1e-2\n",
        "dt = 1e-2\nadaptive = true\nerror_tolerance = 1e-9\ndt_min = 1e-2\n",
    );
    std::fs::write(d.join("base.toml"), base).unwrap();
    let file = d.join("phase.toml");
    std::fs::write(
        &file,
        "[phase]\nbase = \"base.toml\"\nweight = [300.0]\ntorque = [15.0]\ngrowth = { diameters = [0.01, 0.02] }\n",
    )
    .unwrap();
    let out = d.join("out");
    let o = slither(&[
        "phase",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{err}");
    assert!(
        err.contains("every size of the growth line failed (2 sizes)"),
        "{err}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("growth.json")).unwrap()).unwrap();
    assert_eq!(json["failed_sizes"], 2);
    let verdict = json["verdict"].as_str().unwrap();
    assert!(
        verdict.contains("failed") && !verdict.contains("S-starts"),
        "{verdict}"
    );
}
