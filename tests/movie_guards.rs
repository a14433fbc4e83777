//! `slither movie` never writes over a run's data and says what it refuses: the format comes
//! from `--out`'s extension (`.gif` movie, `.png` still with `--still`, nothing else), a still
//! time outside the run's recorded times and an `--fps` outside [0.1, 100] are errors naming
//! the option and its range; `run --no-plots --movie` writes the movie alone.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_slither");

fn slither(args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .env("RAYON_NUM_THREADS", "1")
        .output()
        .unwrap()
}

fn err(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The bundled sliding rod (0.6 s) run into a fresh directory with `--no-plots --movie`.
fn slide_run(name: &str) -> PathBuf {
    let out = std::env::temp_dir().join(format!(
        "slither-movie-guards-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&out);
    let o = slither(&[
        "run",
        "problems/slide.toml",
        "--out",
        out.to_str().unwrap(),
        "--quiet",
        "--no-plots",
        "--movie",
    ]);
    assert!(o.status.success(), "{}", err(&o));
    out
}

/// `slither movie DIR ARGS...`: exit code 2 and a message holding every needle.
fn refused(dir: &Path, args: &[&str], needles: &[&str]) {
    let mut all = vec!["movie", dir.to_str().unwrap(), "--size", "160x120"];
    all.extend_from_slice(args);
    let o = slither(&all);
    let e = err(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
    for n in needles {
        assert!(e.contains(n), "{args:?}: {n:?} missing from: {e}");
    }
}

#[test]
fn no_plots_with_movie_writes_the_movie_alone() {
    let out = slide_run("alone");
    let gif = std::fs::read(out.join("movie.gif")).unwrap();
    assert_eq!(&gif[..6], b"GIF89a");
    for n in ["snapshots.png", "tracks.png", "vtk"] {
        assert!(!out.join(n).exists(), "{n} written with --no-plots");
    }
}

#[test]
fn movie_refuses_data_files_wrong_formats_late_stills_and_bad_fps() {
    let out = slide_run("guards");
    let npz = out.join("trajectory.npz");
    let data = std::fs::read(&npz).unwrap();
    refused(
        &out,
        &["--out", npz.to_str().unwrap()],
        &["trajectory.npz", ".gif", ".png"],
    );
    refused(
        &out,
        &["--out", out.join("summary.json").to_str().unwrap()],
        &["summary.json", ".gif"],
    );
    assert_eq!(
        std::fs::read(&npz).unwrap(),
        data,
        "the data file was overwritten"
    );
    let png = out.join("x.png");
    refused(
        &out,
        &["--out", png.to_str().unwrap()],
        &["x.png", "--still"],
    );
    assert!(!png.exists());
    let gif = out.join("x.gif");
    refused(
        &out,
        &["--still", "0.3", "--out", gif.to_str().unwrap()],
        &["x.gif", ".png"],
    );
    refused(&out, &["--out", out.to_str().unwrap()], &["is a directory"]);
    refused(&out, &["--still", "100"], &["--still 100", "[0, 0.6"]);
    refused(&out, &["--still=-1"], &["--still -1", "[0, 0.6"]);
    assert!(!out.join("still_100.png").exists());
    for fps in ["0.001", "1000", "0"] {
        refused(
            &out,
            &["--fps", fps],
            &[&format!("--fps {fps}"), "[0.1, 100]"],
        );
    }
    // Within the ranges both work, and the format follows the extension.
    let o = slither(&[
        "movie",
        out.to_str().unwrap(),
        "--size",
        "160x120",
        "--still",
        "0.6",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", err(&o));
    assert_eq!(&std::fs::read(&png).unwrap()[1..4], b"PNG");
    let o = slither(&[
        "movie",
        out.to_str().unwrap(),
        "--size",
        "160x120",
        "--fps",
        "0.1",
        "--out",
        gif.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", err(&o));
    assert_eq!(&std::fs::read(&gif).unwrap()[..6], b"GIF89a");
}
