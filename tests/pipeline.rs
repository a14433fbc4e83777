//! One run pipeline (`slither::pipeline`): `slither run` and the library's
//! `pipeline::run_into` (which `slither optimize`'s `best/`, `slither phase --cell` and Python's
//! `save` call) write the same run directory: the same files, byte for byte, and the same
//! `summary.json` but for its timers and the problem's name.
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

mod common;

const BIN: &str = env!("CARGO_BIN_EXE_slither");

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("slither-pipeline-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Every file under `dir`, as paths relative to it.
fn files(dir: &Path) -> BTreeSet<PathBuf> {
    let mut out = BTreeSet::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                todo.push(p);
            } else {
                out.insert(p.strip_prefix(dir).unwrap().to_path_buf());
            }
        }
    }
    out
}

/// `summary.json` without its timers (keys ending in `_s` that hold seconds of wall time).
fn untimed(v: &mut serde_json::Value) {
    if let Some(m) = v.as_object_mut() {
        m.retain(|k, _| !(k.contains("wall") || k.ends_with("_s") && k != "v_s"));
        for x in m.values_mut() {
            untimed(x);
        }
    } else if let Some(a) = v.as_array_mut() {
        a.iter_mut().for_each(untimed);
    }
}

fn summary(dir: &Path) -> serde_json::Value {
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    untimed(&mut v);
    v
}

#[test]
fn slither_run_and_the_library_pipeline_write_the_same_run_directory() {
    let dir = scratch("same");
    let file = dir.join("tiny.toml");
    std::fs::write(&file, common::TINY_S_START).unwrap();
    let cli = dir.join("cli");
    let o = Command::new(BIN)
        .args(["run", file.to_str().unwrap(), "--quiet", "--out"])
        .arg(&cli)
        .env("RAYON_NUM_THREADS", "1")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));

    let lib = dir.join("lib");
    std::fs::create_dir_all(&lib).unwrap();
    let p = slither::problem::load(&file).unwrap();
    let (run, movie) =
        slither::pipeline::run_into(&p, &file, &lib, slither::pipeline::Files::ALL).unwrap();
    assert!(run.summary.error.is_none());
    assert!(movie.is_some(), "the bundled default writes movie.gif");

    let (a, b) = (files(&cli), files(&lib));
    assert_eq!(a, b, "the two run directories hold different files");
    for name in [
        "tracks.png",
        "movie.gif",
        "snapshots.png",
        "final.csv",
        "trajectory.npz",
    ] {
        assert!(a.contains(Path::new(name)), "{name} missing");
    }
    for f in a
        .iter()
        .filter(|f| f.as_path() != Path::new("summary.json"))
    {
        let (x, y) = (
            std::fs::read(cli.join(f)).unwrap(),
            std::fs::read(lib.join(f)).unwrap(),
        );
        assert!(
            x == y,
            "{} differs between slither run and the pipeline",
            f.display()
        );
    }
    // Every member of trajectory.npz carries zip's epoch (time 0, date 1980-01-01 = 0x0021) as
    // its timestamp, not the time of writing: runs a few seconds apart wrote different bytes
    // (pytest's byte-for-byte comparison of `save` and `slither run` failed on it).
    let npz = std::fs::read(cli.join("trajectory.npz")).unwrap();
    let mut members = 0;
    for at in (0..npz.len().saturating_sub(14)).filter(|&i| npz[i..i + 4] == *b"PK\x03\x04") {
        assert_eq!(
            &npz[at + 10..at + 14],
            &[0, 0, 0x21, 0],
            "member at byte {at}"
        );
        members += 1;
    }
    assert!(members >= 3, "{members} members");
    let (x, y) = (summary(&cli), summary(&lib));
    assert_eq!(x, y);
    // The comparison sees a change: the timers are the only keys it leaves out.
    let mut z = y.clone();
    z["steps"] = serde_json::json!(y["steps"].as_u64().unwrap() + 1);
    assert_ne!(x, z);

    // Without plots, the data alone, as `--no-plots`.
    let data = dir.join("data");
    std::fs::create_dir_all(&data).unwrap();
    slither::pipeline::run_into(&p, &file, &data, slither::pipeline::Files::DATA).unwrap();
    let names: BTreeSet<PathBuf> = ["final.csv", "summary.json", "trajectory.npz"]
        .iter()
        .map(PathBuf::from)
        .collect();
    assert_eq!(files(&data), names);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_accuracy_target_is_validated_in_one_place() {
    let p = slither::problem::parse(common::TINY_S_START, Path::new("tiny.toml")).unwrap();
    let mut req = slither::pipeline::Request::new(p, Path::new("tiny.toml"));
    assert!(req.validate("--accuracy").is_ok());
    for bad in [0.0, 0.6, f64::NAN, 1e-5] {
        req.accuracy = Some(bad);
        let e = req.validate("--accuracy").unwrap_err().to_string();
        assert!(e.contains("must be in [1e-4, 0.5]"), "{e}");
    }
    req.accuracy = Some(0.01);
    assert!(req.validate("--accuracy").is_ok());
    assert_eq!(req.target(), Some((0.01, 400)));
    req.ensemble = Some(slither::studies::ensemble::Spec::new(3));
    let e = req.validate("--accuracy").unwrap_err().to_string();
    assert!(e.contains("cannot be combined"), "{e}");
    req.accuracy = None;
    assert!(req.validate("--accuracy").is_ok());
    req.ensemble = Some(slither::studies::ensemble::Spec::new(0));
    assert!(req.validate("--accuracy").is_err());
}
