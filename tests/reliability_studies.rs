//! Studies that cannot succeed say so: a phase study in which every cell fails exits 3 with
//! "every cell failed" (not a plot error); an optimize study varying a parameter its base's
//! gait does not use is refused.
use std::path::PathBuf;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_slither");

fn scratch(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("slither-rel-studies-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

mod common;

/// The phase tests' tiny S-start base (20 elements), cut to two steps.
fn base() -> String {
    common::TINY_S_START.replace("duration = 0.1", "duration = 0.02")
}

#[test]
fn a_phase_study_in_which_every_cell_fails_exits_3() {
    let dir = scratch("allfail");
    // Every cell fails: one Newton iteration a step and no halving. (The repro, a
    // scaled torque of 1e308 whose couple overflows, is now refused by the grid's range.)
    std::fs::write(
        dir.join("base.toml"),
        base() + "\n[solver]\nmax_iterations = 1\nmax_halvings = 0\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("phase.toml"),
        "[phase]\nbase = \"base.toml\"\nweight = [300.0, 1000.0]\ntorque = [15.0]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let o = Command::new(BIN)
        .args(["phase", "--quiet"])
        .arg(dir.join("phase.toml"))
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{e}");
    assert!(e.contains("every cell failed"), "{e}");
    assert!(!e.contains("plot"), "{e}");
    assert!(out.join("phase.csv").exists());
}

#[test]
fn optimizing_sigma_of_a_serpenoid_is_refused() {
    let dir = scratch("serpenoid");
    std::fs::copy("problems/serpenoid.toml", dir.join("base.toml")).unwrap();
    std::fs::write(
        dir.join("study.toml"),
        "[study]\nbase = \"base.toml\"\nmax_evaluations = 2\n\n[optimize]\nsigma = [0.05, 0.2]\n",
    )
    .unwrap();
    let o = Command::new(BIN)
        .args(["optimize", "--quiet"])
        .arg(dir.join("study.toml"))
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("`optimize.sigma`") && e.contains("serpenoid"),
        "{e}"
    );
}
