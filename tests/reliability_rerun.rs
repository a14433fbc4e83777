//! Reruns and interruptions never destroy results: a rerun into a used output directory that
//! is interrupted (Ctrl-C, SIGINT) leaves the previous run's files as they were; Ctrl-C on a
//! fresh run saves what was computed with `"status": "interrupted"`, exits 130 and releases
//! its lock. The output directory is refused clearly when it is a file, a dangling symbolic
//! link or a symbolic link loop.
#![cfg(unix)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::Duration;

const BIN: &str = env!("CARGO_BIN_EXE_slither");

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("slither-rel-rerun-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The bundled S-start with `dt` and `duration` replaced.
fn s_start(dir: &Path, dt: f64, duration: f64) -> PathBuf {
    let text = std::fs::read_to_string("problems/s_start.toml").unwrap();
    let text: String = text
        .lines()
        .map(|l| {
            if l.starts_with("dt =") {
                format!("dt = {dt}\n")
            } else if l.starts_with("duration =") {
                format!("duration = {duration}\n")
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    let file = dir.join(format!("s_{dt}_{duration}.toml"));
    std::fs::write(&file, text).unwrap();
    file
}

fn run(problem: &Path, out: &Path) -> Output {
    Command::new(BIN)
        .args(["run", "--quiet", "--no-plots"])
        .arg(problem)
        .arg("--out")
        .arg(out)
        .env("RAYON_NUM_THREADS", "1")
        .output()
        .unwrap()
}

/// Start a run, send it SIGINT once its lock exists (it is simulating) plus `delay`, and
/// collect it.
fn interrupted_run(problem: &Path, out: &Path, delay: Duration) -> Output {
    let child = Command::new(BIN)
        .args(["run", "--quiet", "--no-plots"])
        .arg(problem)
        .arg("--out")
        .arg(out)
        .env("RAYON_NUM_THREADS", "1")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let lock = out.join(".slither.lock");
    for _ in 0..500 {
        if lock.exists() {
            break;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    std::thread::sleep(delay);
    // SIGINT to the child itself (what Ctrl-C delivers to the foreground process).
    let rc = unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGINT) };
    assert_eq!(rc, 0);
    child.wait_with_output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn an_interrupted_rerun_keeps_the_previous_results() {
    let dir = scratch("rerun");
    let out = dir.join("out");
    // A short first run, then a long rerun into the same directory, interrupted.
    let first = run(&s_start(&dir, 2e-3, 0.2), &out);
    assert_eq!(first.status.code(), Some(0), "{}", stderr(&first));
    let before: Vec<(String, Vec<u8>)> = ["summary.json", "final.csv", "trajectory.npz"]
        .iter()
        .map(|n| (n.to_string(), std::fs::read(out.join(n)).unwrap()))
        .collect();
    let o = interrupted_run(
        &s_start(&dir, 5e-4, 3.572),
        &out,
        Duration::from_millis(600),
    );
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(130), "{e}");
    assert!(e.contains("interrupted") && e.contains("kept"), "{e}");
    for (name, bytes) in before {
        assert_eq!(
            std::fs::read(out.join(&name)).unwrap(),
            bytes,
            "{name} changed"
        );
    }
    assert!(
        !out.join(".slither.lock").exists(),
        "the lock was not released"
    );
    assert!(
        !out.join(".run.tmp").exists(),
        "the staging folder was left"
    );
}

#[test]
fn ctrl_c_on_a_fresh_run_saves_what_was_computed() {
    let dir = scratch("fresh");
    let out = dir.join("out");
    let o = interrupted_run(
        &s_start(&dir, 5e-4, 3.572),
        &out,
        Duration::from_millis(600),
    );
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(130), "{e}");
    let j: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(j["status"], "interrupted", "{j}");
    let t = j["t_final"].as_f64().unwrap();
    assert!(t > 0.0 && t < 3.572, "t_final {t}");
    assert!(out.join("final.csv").exists() && out.join("trajectory.npz").exists());
    assert!(
        !out.join(".slither.lock").exists(),
        "the lock was not released"
    );
}

#[test]
fn an_output_path_that_is_not_a_directory_is_refused_clearly() {
    let dir = scratch("outpath");
    let problem = s_start(&dir, 1e-2, 0.02);
    let file = dir.join("a_file");
    std::fs::write(&file, "x").unwrap();
    let dangling = dir.join("dangling");
    std::os::unix::fs::symlink(dir.join("missing"), &dangling).unwrap();
    let looped = dir.join("loop");
    std::os::unix::fs::symlink(&looped, &looped).unwrap();
    for (path, words) in [
        (&file, "is a file"),
        (&dangling, "dangling symbolic link"),
        (&looped, "symbolic link loop"),
    ] {
        let o = run(&problem, path);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{e}");
        assert!(e.contains(words) && e.contains("--out"), "{path:?}: {e}");
        assert!(!e.contains("File exists"), "{e}");
    }
}
