//! `slither run` end to end: a run that cannot converge stops with a clear error naming time,
//! step and reason, after writing everything computed so far; a good run writes every file.
use std::path::PathBuf;
use std::process::Command;

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("slither_cli_run_{}_{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn failing_run_keeps_what_it_computed_and_names_time_step_and_reason() {
    let d = dir("fail");
    let p = d.join("p.toml");
    // One Newton iteration and no halvings: the first step that needs two iterations fails.
    std::fs::write(
        &p,
        "[rod]\nlength = 1.0\ndiameter = 0.02\nelements = 10\nbending_stiffness = 1e-3\nnatural_curvature = [0.0, 20.0]\n[gravity]\ng = 0.0\n[time]\ndt = 1e-2\nduration = 1.0\n[solver]\nmax_iterations = 1\nmax_halvings = 2\n",
    )
    .unwrap();
    let out = d.join("out");
    let r = Command::new(env!("CARGO_BIN_EXE_slither"))
        .args([
            "run",
            p.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(3), "stderr: {err}");
    assert!(
        err.contains("t = ")
            && err.contains("dt = ")
            && err.contains("halvings")
            && err.contains("Newton"),
        "{err}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "failed");
    assert!(summary["error"].as_str().unwrap().contains("Newton"));
    assert!(out.join("trajectory.npz").exists() && out.join("final.csv").exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn good_run_writes_summary_csv_npz_figures_and_vtk() {
    let d = dir("good");
    let out = d.join("out");
    let r = Command::new(env!("CARGO_BIN_EXE_slither"))
        .args([
            "run",
            "problems/slide.toml",
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    for f in [
        "summary.json",
        "final.csv",
        "trajectory.npz",
        "kymograph_elevation.png",
        "kymograph_slip.png",
        "kymograph_lambda.png",
        "snapshots.png",
        "topology.png",
        "vtk/frames.pvd",
    ] {
        assert!(out.join(f).exists(), "missing {f}");
    }
    let csv = std::fs::read_to_string(out.join("final.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("s,x,y,z,d1x,d1y,d1z"));
    assert_eq!(lines.count(), 51);
    // final.csv is a valid input of `slither topology`.
    let t = Command::new(env!("CARGO_BIN_EXE_slither"))
        .args(["topology", out.join("final.csv").to_str().unwrap()])
        .output()
        .unwrap();
    assert!(t.status.success());
    let v: serde_json::Value = serde_json::from_slice(&t.stdout).unwrap();
    assert!(
        v["wr"].as_f64().unwrap().abs() < 1e-9,
        "a straight rod has no writhe: {v}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// `[solver] conic_certificate = N` is an audit a user can read: `summary.json` reports how many
/// semi-smooth steps the conic program certified (every 10th here, of a rod sliding to a stop
/// and then sticking), that none failed, and the largest correction; without the setting, no
/// step is certified.
#[test]
fn conic_certificates_are_reported_in_the_summary() {
    let d = dir("certificate");
    let base = std::fs::read_to_string("problems/slide.toml").unwrap();
    let run = |name: &str, extra: &str| -> serde_json::Value {
        let p = d.join(format!("{name}.toml"));
        std::fs::write(&p, format!("{base}\n{extra}")).unwrap();
        let out = d.join(name);
        let r = Command::new(env!("CARGO_BIN_EXE_slither"))
            .args(["run", p.to_str().unwrap(), "--out", out.to_str().unwrap()])
            .args(["--quiet", "--no-plots"])
            .output()
            .unwrap();
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
    };
    let s = run("every10", "[solver]\nconic_certificate = 10\n");
    let st = &s["stats"];
    let steps = st["semismooth_steps"].as_u64().unwrap();
    let certified = st["certificates"].as_u64().unwrap();
    assert!(steps >= 500, "{st}");
    // Every 10th step the contact Newton solved (counted over the run), within one of
    // steps / 10.
    assert!(
        certified.abs_diff(steps / 10) <= 1,
        "{certified} of {steps}"
    );
    assert_eq!(st["certificate_failures"], 0, "{st}");
    let corr = st["certificate_max_correction"].as_f64().unwrap();
    assert!((0.0..1.0).contains(&corr), "{corr}");
    let none = run("none", "");
    assert_eq!(none["stats"]["certificates"], 0);
    let _ = std::fs::remove_dir_all(&d);
}
