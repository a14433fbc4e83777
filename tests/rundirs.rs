//! Studies write run directories: `slither optimize` re-runs its best evaluation into `best/`
//! (trajectory, summary, figures, tracks, movie) and `slither phase FILE --cell W,G --out DIR`
//! re-runs one cell of the grid; both give the numbers the study recorded for that point, and a
//! cell off the grid is refused naming the allowed values.
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod common;

const BIN: &str = env!("CARGO_BIN_EXE_slither");

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("slither-rundirs-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn slither(args: &[&str], dir: &Path) -> (Output, String) {
    let o = Command::new(BIN)
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&o.stderr).into_owned();
    (o, e)
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The files of a run directory with its figures and movie.
fn assert_run_dir(d: &Path) {
    for f in [
        "summary.json",
        "final.csv",
        "trajectory.npz",
        "snapshots.png",
        "tracks.png",
        "movie.gif",
    ] {
        assert!(d.join(f).is_file(), "{} missing", d.join(f).display());
    }
    assert_eq!(&std::fs::read(d.join("movie.gif")).unwrap()[..6], b"GIF89a");
}

/// The tiny S-start (20 elements, ten steps) as the base of both studies.
fn base(dir: &Path) {
    std::fs::write(dir.join("base.toml"), common::TINY_S_START).unwrap();
}

#[test]
fn optimize_writes_its_best_evaluation_as_a_run_directory() {
    let dir = scratch("optimize");
    base(&dir);
    std::fs::write(
        dir.join("study.toml"),
        "[study]\nbase = \"base.toml\"\nmax_evaluations = 3\nduration_pulses = 0.1\n\n[optimize]\nstress = [2e4, 3e4]\n",
    )
    .unwrap();
    let (o, e) = slither(&["optimize", "--quiet", "study.toml", "--out", "out"], &dir);
    assert!(o.status.success(), "{e}");
    let best = dir.join("out/best");
    assert_run_dir(&best);
    // The same simulation as the best evaluation: the same speed and regime, to the bit.
    let opt = json(&dir.join("out/optimum.json"));
    let run = json(&best.join("summary.json"));
    assert_eq!(run["v_s"].as_f64(), opt["best"]["v_s"].as_f64(), "{run}");
    assert_eq!(run["regime"].as_str(), opt["best"]["regime"].as_str());
    assert!(run["problem"].as_str().unwrap().ends_with("study.toml"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn phase_reruns_one_cell_into_a_run_directory() {
    let dir = scratch("phase");
    base(&dir);
    std::fs::write(
        dir.join("phase.toml"),
        "[phase]\nbase = \"base.toml\"\nweight = [300.0, 600.0]\ntorque = [15.0]\n",
    )
    .unwrap();
    let (o, e) = slither(
        &["phase", "--quiet", "--gallery", "phase.toml", "--out", "ph"],
        &dir,
    );
    assert!(o.status.success(), "{e}");
    // The gallery: one thumbnail per cell, the picture sized for the 2 x 1 grid.
    let png = std::fs::read(dir.join("ph/phase_gallery.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    let be = |i: usize| u32::from_be_bytes(png[i..i + 4].try_into().unwrap());
    assert_eq!((be(16), be(20)), slither::plot::gallery::gallery_size(2, 1));
    let (o, e) = slither(
        &["phase", "phase.toml", "--cell", "600,15", "--out", "cell"],
        &dir,
    );
    assert!(o.status.success(), "{e}");
    assert!(e.contains("cell W = 600, G = 15"), "{e}");
    let cell = dir.join("cell");
    assert_run_dir(&cell);
    // The study's row for that cell and the run agree: same model, same numbers.
    let csv = std::fs::read_to_string(dir.join("ph/phase.csv")).unwrap();
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let row: Vec<&str> = lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .find(|r| r[col("weight")].parse::<f64>().unwrap() == 600.0)
        .unwrap();
    let run = json(&cell.join("summary.json"));
    assert_eq!(
        run["v_s_over_v_m"].as_f64().unwrap(),
        row[col("v_s_over_v_m")].parse::<f64>().unwrap()
    );
    assert_eq!(run["regime"].as_str().unwrap(), row[col("regime")]);
    // W = 600 through the bending stiffness: B = rho g a^2 L^3 / W.
    let w = run["dimensionless"]["scaled_weight"].as_f64().unwrap();
    assert!((w - 600.0).abs() < 1e-9 * 600.0, "{w}");

    // A cell off the grid is refused with the nearest grid values; nothing is written.
    let (o, e) = slither(
        &["phase", "phase.toml", "--cell", "450,15", "--out", "off"],
        &dir,
    );
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("W = 450")
            && e.contains("phase.weight")
            && e.contains("300 (index 0)")
            && e.contains("600 (index 1)"),
        "{e}"
    );
    let (o, e) = slither(
        &["phase", "phase.toml", "--cell", "300,16", "--out", "off"],
        &dir,
    );
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("G = 16") && e.contains("phase.torque") && e.contains("15 (index 0)"),
        "{e}"
    );
    let (o, e) = slither(
        &["phase", "phase.toml", "--cell", "300", "--out", "off"],
        &dir,
    );
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("W,G"), "{e}");
    assert!(!dir.join("off/summary.json").exists());
    // The study's own directory is not a run directory: refused by the guard.
    let (o, e) = slither(
        &["phase", "phase.toml", "--cell", "300,15", "--out", "ph"],
        &dir,
    );
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("slither phase"), "{e}");
    assert!(!dir.join("ph/summary.json").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn gallery_thumbnails_are_the_cells_at_their_writhe_snapshot() {
    let dir = scratch("gallery");
    base(&dir);
    let f = dir.join("phase.toml");
    std::fs::write(
        &f,
        "[phase]\nbase = \"base.toml\"\nweight = [300.0, 600.0]\ntorque = [0.0, 15.0]\n",
    )
    .unwrap();
    let ph = slither::studies::phase::load(&f).unwrap();
    let cells: Vec<_> = [(300.0, 0.0), (300.0, 15.0), (600.0, 15.0)]
        .iter()
        .map(|&(w, g)| slither::studies::phase::simulate(&ph.base, w, g))
        .collect();
    let th = slither::studies::phase::gallery::thumbs(&ph, &cells);
    assert_eq!(th.len(), 3);
    // t* = (L/2 - s_b0) / v_m of the tiny S-start is past its 0.1 s: the last frame, t = 0.1;
    // without a torque (G = 0) there is no gait, and the last frame is shown too.
    for (t, c) in th.iter().zip(&cells) {
        assert_eq!(
            (t.weight, t.torque, t.regime),
            (c.weight, c.torque, c.regime)
        );
        assert_eq!(t.x.len(), 21, "one position per node");
        assert!((t.t - 0.1).abs() < 1e-9, "{}", t.t);
    }
    // The heavier snake's body differs from the lighter one's at the same instant.
    assert_ne!(th[1].x, th[2].x);
    let _ = std::fs::remove_dir_all(&dir);
}
