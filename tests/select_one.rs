//! Selecting one item of a study to rerun: `phase --cell W,G` by values printed to six
//! digits, `--cell-index i,j`, `--growth-size D` and `run --ensemble K --member M`, each also
//! with `--no-plots`; errors name the nearest grid points.

use std::path::PathBuf;
use std::process::{Command, Output};

mod common;
use common::TINY_S_START;

const BIN: &str = env!("CARGO_BIN_EXE_slither");

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("slither-select-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn slither(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().unwrap()
}

fn summary(dir: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

#[test]
fn a_cell_or_growth_size_is_selected_by_rounded_value_or_index() {
    let dir = scratch("cell");
    std::fs::write(dir.join("base.toml"), TINY_S_START).unwrap();
    let file = dir.join("phase.toml");
    // W from 100 to 1000 in 3 log steps: the middle one is 316.22776601683796.
    std::fs::write(
        &file,
        "[phase]\nbase = \"base.toml\"\nweight = { from = 100.0, to = 1000.0, count = 3 }\ntorque = [10.0, 15.0]\ngrowth = { diameters = [0.01, 0.02] }\n",
    )
    .unwrap();
    let f = file.to_str().unwrap();
    let by_value = dir.join("by_value");
    let o = slither(&[
        "phase",
        f,
        "--cell",
        "316.228,10",
        "--out",
        by_value.to_str().unwrap(),
        "--no-plots",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(by_value.join("summary.json").exists());
    assert!(!by_value.join("movie.gif").exists() && !by_value.join("overview.png").exists());
    let pngs = std::fs::read_dir(&by_value)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .extension()
                .is_some_and(|x| x == "png")
        })
        .count();
    assert_eq!(pngs, 0, "--no-plots draws no figure");
    // The same cell by its indices: the same run.
    let by_index = dir.join("by_index");
    let o = slither(&[
        "phase",
        f,
        "--cell-index",
        "1,0",
        "--out",
        by_index.to_str().unwrap(),
        "--no-plots",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (a, b) = (summary(&by_value), summary(&by_index));
    assert!(a["v_s"].is_number());
    for key in ["v_s", "writhe_max", "regime", "steps"] {
        assert_eq!(a[key], b[key], "{key}");
    }
    // A value off the grid: refused (exit 2), naming the nearest points with their indices.
    let o = slither(&[
        "phase",
        f,
        "--cell",
        "400,10",
        "--out",
        dir.join("x").to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("W = 400") && err.contains("316.22") && err.contains("(index 1)"),
        "{err}"
    );
    let o = slither(&[
        "phase",
        f,
        "--cell-index",
        "3,0",
        "--out",
        dir.join("x").to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("indices 0 to 2"), "{err}");
    // A growth size by its diameter, to 1e-3.
    let size = dir.join("size");
    let o = slither(&[
        "phase",
        f,
        "--growth-size",
        "0.02001",
        "--out",
        size.to_str().unwrap(),
        "--no-plots",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("growth size 0.02 m"), "{err}");
    assert!(summary(&size)["v_s"].is_number());
    // --no-plots alone is for one cell.
    let o = slither(&[
        "phase",
        f,
        "--no-plots",
        "--out",
        dir.join("y").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn one_ensemble_member_reruns_alone_as_it_ran() {
    let dir = scratch("member");
    let file = dir.join("p.toml");
    std::fs::write(&file, TINY_S_START).unwrap();
    let f = file.to_str().unwrap();
    let all = dir.join("all");
    let o = slither(&[
        "run",
        f,
        "--ensemble",
        "3",
        "--out",
        all.to_str().unwrap(),
        "--no-plots",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let member = &summary(&all)["ensemble"]["members"][2];
    let one = dir.join("one");
    let o = slither(&[
        "run",
        f,
        "--ensemble",
        "3",
        "--member",
        "2",
        "--out",
        one.to_str().unwrap(),
        "--no-plots",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = summary(&one);
    assert!(s["ensemble"].is_null(), "a member alone is an ordinary run");
    for key in [
        "v_s",
        "v_s_over_v_m",
        "writhe_max",
        "displacement_angle_deg",
    ] {
        assert!(s[key].is_number(), "{key}");
        assert_eq!(s[key], member["observables"][key], "{key}");
    }
    assert_eq!(s["regime"], member["regime"]);
    let o = slither(&[
        "run",
        f,
        "--ensemble",
        "3",
        "--member",
        "3",
        "--out",
        dir.join("x").to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("members are 0 to 2"), "{err}");
}
