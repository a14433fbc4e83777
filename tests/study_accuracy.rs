//! `[accuracy]` in study files: the model is chosen once on the base scene, every cell and
//! evaluation runs at it, the choice is recorded and reused on resume, bad values exit 2.
mod common;
use common::TINY_S_START as BASE;
use slither::studies::{self, accuracy::StudyAccuracy};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_slither");

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "slither-study-accuracy-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("base.toml"), BASE).unwrap();
    dir
}

fn run(cmd: &str, file: &Path, out: &Path) -> Output {
    Command::new(BIN)
        .args([cmd, file.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .output()
        .unwrap()
}

const PHASE: &str = "[phase]\nbase = \"base.toml\"\nweight = [300.0]\ntorque = [12.0, 18.0]\n";

#[test]
fn phase_cells_run_at_the_selected_model_and_resume_reuses_the_choice() {
    let dir = scratch("phase");
    // This study's base asks for adaptive BDF2: the selection refines its tolerance (the
    // optimize test below covers implicit Euler's steps).
    std::fs::write(
        dir.join("base.toml"),
        format!(
            "{}\n[solver]\nintegrator = \"bdf2\"\n",
            BASE.replace("[time]\n", "[time]\nadaptive = true\n")
        ),
    )
    .unwrap();
    let file = dir.join("phase.toml");
    std::fs::write(
        &file,
        format!("{PHASE}\n[accuracy]\ntarget = 0.5\nmax_elements = 40\n"),
    )
    .unwrap();
    let out = dir.join("out");
    let o = run("phase", &file, &out);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{err}");
    assert!(err.contains("accuracy 0.5: chose"), "{err}");
    assert!(err.contains("2 simulated, 0 reused"), "{err}");
    // The choice is recorded in accuracy.json and phase.json alike.
    let info: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("phase.json")).unwrap()).unwrap();
    let chosen: StudyAccuracy = serde_json::from_value(info["accuracy"].clone()).unwrap();
    let recorded: StudyAccuracy = serde_json::from_str(
        &std::fs::read_to_string(out.join(studies::accuracy::ACCURACY_FILE)).unwrap(),
    )
    .unwrap();
    assert_eq!(chosen, recorded);
    assert!(chosen.elements == 20 || chosen.elements == 40, "{chosen:?}");
    assert_eq!(chosen.target, 0.5);
    assert_eq!(
        chosen.selection["elements"].as_u64(),
        Some(chosen.elements as u64)
    );
    assert!(chosen.selection["runs"].as_array().unwrap().len() >= 3);
    // The rows are keyed by the base file and the chosen model.
    let ph = studies::phase::load(&file).unwrap();
    assert_eq!(chosen.base_file_hash, format!("{:016x}", ph.base_hash));
    assert_eq!(info["base_hash"], format!("{:016x}", chosen.row_hash()));
    // Each cell is the simulation of that cell at the chosen model (adaptive BDF2 at the chosen
    // mesh and tolerance), and not the base file's model (adaptive BDF2 at the default
    // tolerance on its 20 elements).
    let csv = std::fs::read_to_string(out.join("phase.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert_eq!(rows.len(), 2, "{csv}");
    let at_model = chosen.apply(&ph.base);
    assert_eq!(at_model.rod.elements, chosen.elements);
    assert!(
        chosen.error_tolerance.is_some() && chosen.dt.is_none(),
        "{chosen:?}"
    );
    assert_eq!(at_model.time.error_tolerance, chosen.error_tolerance);
    assert!(at_model.time.adaptive);
    let mut differs = false;
    // (Rows are in the order the cells finished.)
    for row in &rows {
        let g: f64 = row.split(',').nth(1).unwrap().parse().unwrap();
        let c = studies::phase::simulate(&at_model, 300.0, g);
        let mut f: Vec<&str> = row.split(',').collect();
        f[16] = "";
        assert_eq!(
            studies::phase::comparable_row(&c, chosen.row_hash()),
            f.join(",")
        );
        let base_cell = studies::phase::simulate(&ph.base, 300.0, g);
        differs |= base_cell.v_s_over_v_m != c.v_s_over_v_m;
    }
    assert!(differs, "the cells did not change with the model");
    // Resume: the recorded choice is reused without selecting, and every cell is reused.
    let o = run("phase", &file, &out);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{err}");
    assert!(err.contains("reusing the recorded choice"), "{err}");
    assert!(
        !err.contains("accuracy: 20 elements"),
        "selected again: {err}"
    );
    assert!(err.contains("0 simulated, 2 reused"), "{err}");
    // Without [accuracy] the base model's cells are simulated again (other resume key) and the
    // stale record goes.
    std::fs::write(&file, PHASE).unwrap();
    let o = run("phase", &file, &out);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{err}");
    assert!(err.contains("2 simulated, 0 reused"), "{err}");
    assert!(!out.join(studies::accuracy::ACCURACY_FILE).exists());
    let info: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("phase.json")).unwrap()).unwrap();
    assert!(info.get("accuracy").is_none(), "{info}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn optimize_evaluations_run_at_the_selected_model() {
    let dir = scratch("optimize");
    let file = dir.join("study.toml");
    std::fs::write(
        &file,
        "[study]\nbase = \"base.toml\"\nmax_evaluations = 2\n\n[optimize]\nstress = [20000.0, 26000.0]\n\n[accuracy]\ntarget = 0.5\nmax_elements = 40\n",
    )
    .unwrap();
    let out = dir.join("out");
    let o = run("optimize", &file, &out);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{err}");
    assert!(err.contains("accuracy 0.5: chose"), "{err}");
    let optimum: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("optimum.json")).unwrap()).unwrap();
    let chosen: StudyAccuracy = serde_json::from_value(optimum["accuracy"].clone()).unwrap();
    let row_hash = format!("{:016x}", chosen.row_hash());
    assert_eq!(optimum["base_hash"], row_hash.as_str());
    // The library path reuses the record (no second selection) and sets the model.
    let mut study = studies::optimize::load_study(&file).unwrap();
    let mut lines = Vec::new();
    let reused =
        studies::optimize::prepare_accuracy(&mut study, &out, &mut |l| lines.push(l.to_string()))
            .unwrap();
    assert!(reused && lines.is_empty(), "{lines:?}");
    assert_eq!(study.base.rod.elements, chosen.elements);
    assert_eq!(study.base_hash, row_hash);
    // The base file is implicit Euler: the choice is a fixed step, a halving of the file's.
    let h = chosen.dt.expect("implicit Euler chooses a step");
    assert!(chosen.error_tolerance.is_none(), "{chosen:?}");
    assert_eq!(study.base.time.dt, Some(h));
    assert!(!study.base.time.adaptive);
    let k = (1e-2 / h).log2();
    assert!((k - k.round()).abs() < 1e-9, "{h}");
    // The first evaluation (the start) is the simulation at the chosen model.
    let history = std::fs::read_to_string(out.join(studies::optimize::HISTORY_FILE)).unwrap();
    let first: Vec<&str> = history.lines().nth(1).unwrap().split(',').collect();
    let col = |name: &str| {
        studies::optimize::HISTORY_HEADER
            .split(',')
            .position(|c| c == name)
            .unwrap()
    };
    assert_eq!(first[col("base_hash")], row_hash, "{history}");
    let e = studies::optimize::simulate(&study, &study.space.initial(), &mut |_| {});
    assert_eq!(
        first[col("v_s_over_v_m")].parse::<f64>().unwrap(),
        e.v_s_over_v_m,
        "{history}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

fn rejects(cmd: &str, name: &str, text: &str, needles: &[&str]) {
    let dir = scratch(name);
    let file = dir.join("study.toml");
    std::fs::write(&file, text).unwrap();
    let o = run(cmd, &file, &dir.join("out"));
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(2), "{name}: {err}");
    assert!(err.contains("study.toml"), "{name}: {err}");
    for n in needles {
        assert!(err.contains(n), "{name}: {n:?} not in {err}");
    }
    assert!(
        !dir.join("out").join("accuracy.json").exists(),
        "{name}: selected before rejecting"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_accuracy_tables_in_study_files_exit_2_naming_the_key() {
    let opt = "[study]\nbase = \"base.toml\"\nmax_evaluations = 2\n\n[optimize]\nstress = [20000.0, 26000.0]\n";
    for (cmd, head) in [("phase", PHASE), ("optimize", opt)] {
        rejects(
            cmd,
            &format!("{cmd}_target"),
            &format!("{head}\n[accuracy]\ntarget = 0.0\n"),
            &["`accuracy.target`", "[1e-4, 0.5]"],
        );
        rejects(
            cmd,
            &format!("{cmd}_target_big"),
            &format!("{head}\n[accuracy]\ntarget = 0.7\n"),
            &["`accuracy.target`", "[1e-4, 0.5]"],
        );
        rejects(
            cmd,
            &format!("{cmd}_max"),
            &format!("{head}\n[accuracy]\ntarget = 0.1\nmax_elements = 10\n"),
            &["`accuracy.max_elements`", "[20, 100000]"],
        );
        rejects(
            cmd,
            &format!("{cmd}_unknown"),
            &format!("{head}\n[accuracy]\ntarget = 0.1\nelements = 10\n"),
            &["elements"],
        );
    }
}

/// Sharded with `[accuracy]` and `refine = true`: the merge checks the base file against the
/// choice's record (the rows are keyed by file and model), refines at the chosen model, and
/// gives the unsharded run's cells and refinement.
#[test]
fn sharded_accuracy_study_with_refine_merges_like_the_unsharded_run() {
    let dir = scratch("shard-refine");
    let file = dir.join("phase.toml");
    std::fs::write(
        &file,
        "[phase]\nbase = \"base.toml\"\nweight = [300.0]\ntorque = [4.0, 18.0]\nrefine = true\n\
         refine_steps = 1\n\n[accuracy]\ntarget = 0.5\nmax_elements = 40\n",
    )
    .unwrap();
    let csv = |d: &Path, name: &str| -> Vec<String> {
        let text = std::fs::read_to_string(d.join(name)).unwrap_or_default();
        let mut rows: Vec<String> = text
            .lines()
            .skip(1)
            .map(|l| {
                // Every column but the wall time (16).
                let mut f: Vec<&str> = l.split(',').collect();
                if f.len() > 16 {
                    f[16] = "";
                }
                f.join(",")
            })
            .collect();
        rows.sort();
        rows
    };
    let whole = dir.join("whole");
    let o = run("phase", &file, &whole);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut dirs = Vec::new();
    for i in 1..=2 {
        let d = dir.join(format!("shard{i}"));
        let o = Command::new(BIN)
            .args([
                "phase",
                file.to_str().unwrap(),
                "--out",
                d.to_str().unwrap(),
            ])
            .args(["--shard", &format!("{i}/2")])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        dirs.push(d);
    }
    let merged = dir.join("merged");
    let o = Command::new(BIN)
        .arg("merge")
        .args(dirs.iter().map(|d| d.to_str().unwrap()))
        .args(["--out", merged.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(csv(&merged, "phase.csv"), csv(&whole, "phase.csv"));
    assert_eq!(csv(&merged, "refine.csv"), csv(&whole, "refine.csv"));
}
