//! Studies that know what they ran: `optimum.json` records the objective, its penalties, the
//! heading limit and the ensemble settings; a study resumed after its objective changed
//! simulates again what the change invalidates instead of reusing rows scored by the old
//! objective; base files count by their effective content (a comment is no change); `merge`
//! follows the current phase file or refuses naming the difference.

use slither::studies;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod common;
use common::{TINY_SIDEWINDING, TINY_S_START};

const BIN: &str = env!("CARGO_BIN_EXE_slither");

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "slither-study-settings-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A three-evaluation study of the tiny sidewinding's stress, three launch periods a run.
fn study(objective: &str) -> String {
    format!(
        "[study]\nbase = \"base.toml\"\nmax_evaluations = 3\nduration_periods = 3.0\nobjective = \"{objective}\"\nmax_heading_deg = 170.0\n\n[optimize]\nstress = [20000.0, 30000.0]\n"
    )
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn a_changed_objective_is_simulated_again_and_a_comment_is_no_change() {
    let dir = scratch("objective");
    std::fs::write(dir.join("base.toml"), TINY_SIDEWINDING).unwrap();
    let file = dir.join("study.toml");
    std::fs::write(&file, study("broadside")).unwrap();
    let out = dir.join("out");
    let a = studies::optimize::optimize(
        &studies::optimize::load_study(&file).unwrap(),
        &out,
        &mut studies::optimize::Silent,
    )
    .unwrap();
    assert_eq!((a.simulations, a.reused), (3, 0));
    let o = json(&out.join("optimum.json"));
    let s = &o["settings"];
    assert_eq!(s["objective"], "broadside");
    assert_eq!(s["turn_penalty"], studies::optimize::DEFAULT_TURN_PENALTY);
    assert_eq!(s["stationary_penalty"], 0.0);
    assert_eq!(s["max_heading_deg"], 170.0);
    assert_eq!(s["penalty"], 1.0);
    assert!(s["ensemble"].is_null());
    assert_eq!(
        o["best"]["objective"].as_f64().unwrap(),
        a.best.as_ref().unwrap().objective()
    );
    // The broadside rows are scored by the lateral speed, not by -v_s.
    assert!(a.visited.iter().any(|(e, _)| e.objective() != -e.v_s));

    // The objective changed: no row is reused with its broadside score; every point is
    // simulated again and scored -v_s, and the best is the fastest.
    std::fs::write(&file, study("v_s")).unwrap();
    let b = studies::optimize::optimize(
        &studies::optimize::load_study(&file).unwrap(),
        &out,
        &mut studies::optimize::Silent,
    )
    .unwrap();
    assert_eq!(b.reused, 0, "rows scored by another objective were reused");
    assert_eq!(b.rows_other_base, 3);
    assert_eq!(b.simulations, 3);
    for (e, _) in &b.visited {
        assert_eq!(e.objective(), -e.v_s, "eval {}", e.eval);
    }
    let fastest = b
        .visited
        .iter()
        .map(|v| v.0.v_s)
        .fold(f64::NEG_INFINITY, f64::max);
    assert_eq!(b.best.as_ref().unwrap().v_s, fastest);
    assert_eq!(
        json(&out.join("optimum.json"))["settings"]["objective"],
        "v_s"
    );

    // A comment-only edit of the base file is the same problem: every row reused.
    std::fs::write(
        dir.join("base.toml"),
        format!(
            "# a note about the base\n{}",
            TINY_SIDEWINDING.replace("elements = 16", "elements = 16 # as before")
        ),
    )
    .unwrap();
    let c = studies::optimize::optimize(
        &studies::optimize::load_study(&file).unwrap(),
        &out,
        &mut studies::optimize::Silent,
    )
    .unwrap();
    assert_eq!((c.reused, c.simulations), (3, 0));
    // A heading limit is applied when rows are read: changing it reuses them too.
    std::fs::write(&file, study("v_s").replace("170.0", "120.0")).unwrap();
    let d = studies::optimize::optimize(
        &studies::optimize::load_study(&file).unwrap(),
        &out,
        &mut studies::optimize::Silent,
    )
    .unwrap();
    assert_eq!((d.reused, d.simulations), (3, 0));
}

fn slither(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().unwrap()
}

#[test]
fn merge_follows_the_current_phase_file_or_names_the_difference() {
    let dir = scratch("merge");
    std::fs::write(dir.join("base.toml"), TINY_S_START).unwrap();
    let file = dir.join("phase.toml");
    let grid = "[phase]\nbase = \"base.toml\"\nweight = [300.0, 3000.0]\ntorque = [15.0]\nrefine = true\nrefine_steps = 1\n";
    std::fs::write(&file, grid).unwrap();
    let f = file.to_str().unwrap();
    let mut shards = Vec::new();
    for i in 1..=2 {
        let d = dir.join(format!("shard{i}"));
        let o = slither(&[
            "phase",
            f,
            "--out",
            d.to_str().unwrap(),
            "--shard",
            &format!("{i}/2"),
            "--quiet",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let info = json(&d.join("phase.json"));
        assert_eq!(info["refine_steps"], 1);
        // Recorded, not left out: null means no verification.
        assert!(info.as_object().unwrap().contains_key("verify"), "{info}");
        assert!(info["verify"].is_null(), "{info}");
        shards.push(d.to_str().unwrap().to_string());
    }
    let merge = |out: &str| {
        let mut args = vec!["merge"];
        args.extend(shards.iter().map(|s| s.as_str()));
        let out = dir.join(out);
        args.extend(["--out", out.to_str().unwrap()]);
        slither(&args)
    };
    // The phase file now says refine = false: merge refuses, naming the setting and both
    // values, rather than refining as the shards' record says.
    std::fs::write(&file, grid.replace("refine = true\nrefine_steps = 1\n", "")).unwrap();
    let o = merge("m1");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("the phase file changed"), "{err}");
    assert!(
        err.contains("refine: the file now says refine = false, the shards ran refine = true, refine_steps = 1"),
        "{err}"
    );
    assert!(!dir.join("m1").join("phase.csv").exists());
    // Restored, and the base file edited by a comment only: the same problem, merged.
    std::fs::write(&file, grid).unwrap();
    std::fs::write(
        dir.join("base.toml"),
        format!(
            "# the tiny S-start\n{}",
            TINY_S_START.replace("elements = 20", "elements = 20 # coarse")
        ),
    )
    .unwrap();
    let o = merge("m2");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(dir.join("m2").join("phase.csv").exists());
    // A value of the base file is a change: refused, naming the base problem.
    std::fs::write(
        dir.join("base.toml"),
        TINY_S_START.replace("duration = 0.1", "duration = 0.12"),
    )
    .unwrap();
    let o = merge("m3");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("base problem:"), "{err}");
}
