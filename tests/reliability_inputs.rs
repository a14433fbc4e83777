//! Odd inputs answered with a clear refusal (exit 2, naming the key or the row) instead of a
//! run that fails later, a silent fallback or a wrong number: derived quantities that
//! overflow, zero gravity with a ground, a topology curve that doubles back or starts with a
//! byte order mark, solver choices this build cannot honour.

use std::path::PathBuf;
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_slither");

/// A tiny valid scene with a ground and an S-start gait (milliseconds to run).
const BASE: &str = "\
[rod]
length = 1.0
diameter = 0.02
elements = 20
density = 1000.0
bending_stiffness = 0.01308

[gravity]
g = 9.81

[ground]
mu_forward = 0.55
mu_backward = 0.70
mu_sideways = 1.00

[gait]
kind = \"s-start\"
stress = 24525.0
sigma = 0.0525
speed = 0.28

[time]
dt = 1e-2
duration = 0.02
";

fn scratch(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("slither-rel-inputs-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn edit(old: &str, new: &str) -> String {
    assert!(BASE.contains(old), "{old:?} not in BASE");
    BASE.replace(old, new)
}

fn run(name: &str, text: &str, env: &[(&str, &str)]) -> (Output, PathBuf) {
    let dir = scratch(name);
    let file = dir.join("p.toml");
    std::fs::write(&file, text).unwrap();
    let out = dir.join("out");
    let mut cmd = Command::new(BIN);
    cmd.args(["run", "--quiet", "--no-plots"])
        .arg(&file)
        .arg("--out")
        .arg(&out);
    for (k, v) in env {
        cmd.env(k, v);
    }
    (cmd.output().unwrap(), out)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Exit 2, the message names `key`, contains every `needles`, has no number written out to
/// hundreds of digits, and nothing was simulated.
fn refused(name: &str, text: &str, key: &str, needles: &[&str]) {
    let (o, out) = run(name, text, &[]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{name}: {e}");
    assert!(
        e.contains(&format!("`{key}`")),
        "{name}: key {key} not named: {e}"
    );
    for n in needles {
        assert!(e.contains(n), "{name}: {n:?} not in: {e}");
    }
    assert!(
        !e.contains("0000000000"),
        "{name}: a number printed in full: {e}"
    );
    assert!(!out.join("summary.json").exists());
}

#[test]
fn the_base_scene_runs() {
    let (o, out) = run("base", BASE, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(out.join("summary.json").exists());
}

#[test]
fn overflowing_derived_quantities_are_refused_naming_the_key() {
    refused(
        "density",
        &edit("density = 1000.0", "density = 1e308"),
        "rod.density",
        &["1e308", "node mass"],
    );
    refused(
        "g",
        &edit("g = 9.81", "g = 1e308"),
        "gravity.g",
        &["1e308", "weight"],
    );
    refused(
        "stress",
        &edit("stress = 24525.0", "stress = 1e308"),
        "gait.stress",
        &["1e308"],
    );
    refused(
        "tiny_speed",
        &edit("speed = 0.28", "speed = 1e-300"),
        "gait.speed",
        &["pulse time"],
    );
}

#[test]
fn zero_gravity_with_a_ground_is_refused_up_front() {
    refused(
        "g0",
        &edit("g = 9.81", "g = 0.0"),
        "gravity.g",
        &["[ground]"],
    );
}

#[test]
fn clarabel_faer_without_the_feature_is_refused_at_load() {
    let text = format!("{BASE}\n[solver]\nclarabel_method = \"faer\"\n");
    if cfg!(feature = "clarabel-faer") {
        let (o, _) = run("faer_on", &text, &[]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    } else {
        refused("faer", &text, "solver.clarabel_method", &["clarabel-faer"]);
    }
}

/// Nodes of an open curve in the plane, with d1 = e_z, written as `slither topology` CSV.
fn curve_csv(nodes: &[[f64; 3]]) -> String {
    let mut s = String::from("x,y,z,d1x,d1y,d1z\n");
    for n in nodes {
        s.push_str(&format!("{},{},{},0,0,1\n", n[0], n[1], n[2]));
    }
    s
}

fn helix_nodes() -> Vec<[f64; 3]> {
    (0..30)
        .map(|i| {
            let t = i as f64 * 0.3;
            [t.cos(), t.sin(), 0.1 * t]
        })
        .collect()
}

fn topology(name: &str, text: &str, closed: bool) -> Output {
    let dir = scratch(name);
    let file = dir.join("c.csv");
    std::fs::write(&file, text).unwrap();
    let mut cmd = Command::new(BIN);
    cmd.arg("topology").arg(&file);
    if closed {
        cmd.arg("--closed");
    }
    cmd.output().unwrap()
}

#[test]
fn topology_refuses_a_curve_that_doubles_back() {
    // The repro: node 20 repeated after node 21 (20 -> 21 -> 20 -> 22).
    let mut nodes = helix_nodes();
    nodes.insert(22, nodes[20]);
    let text = curve_csv(&nodes);
    for closed in [false, true] {
        let o = topology("doubles", &text, closed);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "closed {closed}: {e}");
        // Node 21 (0-based) is data row 22, line 23 (after the header).
        assert!(e.contains(":23:") && e.contains("node 21"), "{e}");
        assert!(e.contains("doubles back"), "{e}");
    }
    // The curve without the repeat is accepted.
    let o = topology("helix", &curve_csv(&helix_nodes()), false);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

#[test]
fn topology_skips_a_byte_order_mark() {
    // The `final.csv` layout of `slither run`: a leading arc-length column, recognised by its
    // header `s,...`, which a byte order mark in front used to hide.
    let text: String = curve_csv(&helix_nodes())
        .lines()
        .enumerate()
        .map(|(k, l)| {
            if k == 0 {
                format!("s,{l}\n")
            } else {
                format!("{},{l}\n", k - 1)
            }
        })
        .collect();
    let plain = topology("plain", &text, false);
    let bom = topology("bom", &format!("\u{feff}{text}"), false);
    assert_eq!(bom.status.code(), Some(0), "{}", stderr(&bom));
    assert_eq!(plain.stdout, bom.stdout);
}

#[test]
fn work_precision_of_a_ground_scene_without_a_gait_says_why() {
    let dir = scratch("wp");
    let o = Command::new(BIN)
        .args(["chart", "work-precision", "problems/slide.toml", "--out"])
        .arg(dir.join("out"))
        .output()
        .unwrap();
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("needs a [gait]") && !e.trim_end().ends_with("ok"),
        "{e}"
    );
}

#[test]
fn unknown_solver_overrides_in_the_environment_are_refused() {
    for (var, value) in [
        ("SLITHER_CONTACT", "bogus"),
        ("SLITHER_CLARABEL_METHOD", "xyz"),
    ] {
        let (o, out) = run(var, BASE, &[(var, value)]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{var}: {e}");
        assert!(e.contains(var) && e.contains(value), "{e}");
        assert!(!out.join("summary.json").exists());
    }
    // The retired active set is named as retired.
    let (o, out) = run("active-set", BASE, &[("SLITHER_CONTACT", "active-set")]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("SLITHER_CONTACT") && e.contains("retired"),
        "{e}"
    );
    assert!(!out.join("summary.json").exists());
    // The allowed values still run.
    let (o, _) = run("conic", BASE, &[("SLITHER_CONTACT", "conic")]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}
