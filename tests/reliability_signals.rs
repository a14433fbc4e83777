//! SIGTERM (what Slurm sends at a job's time limit, 30 s before SIGKILL), SIGHUP and SIGINT
//! end a run and a study the same way (`src/cli/signals.rs`): a run writes its data with
//! `"status": "interrupted"` (figures skipped after SIGTERM and SIGHUP) and a study keeps its
//! finished rows; both release the lock, leave no temporary folder and exit 128 + the
//! signal's number, within seconds of the signal.
#![cfg(unix)]

mod common;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_slither");

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("slither-signals-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The tiny S-start (20 elements, 10 ms steps) lasting `duration` s: minutes of stepping for a
/// long duration, so the signal always arrives mid-run.
fn tiny(dir: &Path, duration: f64) -> PathBuf {
    let text = common::TINY_S_START.replace("duration = 0.1", &format!("duration = {duration}"));
    assert!(text.contains(&format!("duration = {duration}")));
    let file = dir.join("base.toml");
    std::fs::write(&file, text).unwrap();
    file
}

/// Start `args`, wait for the lock of `out` (the work has begun) plus `delay`, send `sig` and
/// collect the process, with the time from the signal to its end.
fn signalled(args: &[&str], out: &Path, sig: i32, delay: Duration) -> (Output, Duration) {
    let child: Child = Command::new(BIN)
        .args(args)
        .env("RAYON_NUM_THREADS", "2")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let lock = out.join(".slither.lock");
    let start = Instant::now();
    while !lock.exists() && start.elapsed() < Duration::from_secs(20) {
        std::thread::sleep(Duration::from_millis(10));
    }
    assert!(
        lock.exists(),
        "the lock never appeared in {}",
        out.display()
    );
    std::thread::sleep(delay);
    let sent = Instant::now();
    assert_eq!(unsafe { libc::kill(child.id() as libc::pid_t, sig) }, 0);
    let o = child.wait_with_output().unwrap();
    (o, sent.elapsed())
}

/// Run `args` writing into `out`, send `sig` 300 ms after its lock appears, and check that it
/// exits with 128 + the signal within 10 s; its stderr.
fn ended_by(args: &[&str], out: &Path, sig: i32, name: &str) -> String {
    let (o, took) = signalled(args, out, sig, Duration::from_millis(300));
    let e = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(128 + sig), "{name}: {e}");
    assert!(
        took < Duration::from_secs(10),
        "{name}: ended {took:?} after the signal"
    );
    e
}

/// No lock and no temporary folder or file left in `out`.
fn clean(out: &Path, what: &str) {
    let left: Vec<String> = std::fs::read_dir(out)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".slither.lock") || n.contains(".tmp") || n == ".run.old")
        .collect();
    assert!(
        left.is_empty(),
        "{what}: left behind in {}: {left:?}",
        out.display()
    );
}

const SIGNALS: [(i32, &str); 3] = [
    (libc::SIGTERM, "SIGTERM"),
    (libc::SIGHUP, "SIGHUP"),
    (libc::SIGINT, "SIGINT"),
];

#[test]
fn each_signal_ends_a_run_with_its_data_written() {
    let dir = scratch("run");
    let base = tiny(&dir, 1000.0);
    for (sig, name) in SIGNALS {
        let out = dir.join(name);
        let e = ended_by(
            &[
                "run",
                base.to_str().unwrap(),
                "--quiet",
                "--out",
                out.to_str().unwrap(),
            ],
            &out,
            sig,
            name,
        );
        assert!(e.contains("interrupted") && e.contains(name), "{name}: {e}");
        let j: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        assert_eq!(j["status"], "interrupted", "{name}");
        let t = j["t_final"].as_f64().unwrap();
        assert!(t > 0.0 && t < 1000.0, "{name}: t_final {t}");
        assert!(out.join("trajectory.npz").exists() && out.join("final.csv").exists());
        // A scheduler's signal skips the figures; Ctrl-C draws them.
        assert_eq!(
            out.join("snapshots.png").exists(),
            sig == libc::SIGINT,
            "{name}"
        );
        clean(&out, name);
    }
}

#[test]
fn each_signal_ends_a_phase_study_keeping_it_resumable() {
    let dir = scratch("phase");
    tiny(&dir, 1000.0);
    let file = dir.join("phase.toml");
    std::fs::write(
        &file,
        "[phase]\nbase = \"base.toml\"\nweight = [300.0, 3000.0]\ntorque = [10.0, 15.0]\n",
    )
    .unwrap();
    for (sig, name) in SIGNALS {
        let out = dir.join(name);
        let e = ended_by(
            &[
                "phase",
                file.to_str().unwrap(),
                "--quiet",
                "--out",
                out.to_str().unwrap(),
            ],
            &out,
            sig,
            name,
        );
        assert!(
            e.contains("interrupted") && e.contains("resume"),
            "{name}: {e}"
        );
        // The study's record is there to resume from: its grid and its CSV header.
        assert!(out.join("phase.json").exists() && out.join("phase.csv").exists());
        clean(&out, name);
        // `slither status` sees the four cells missing and no lock.
        let s = Command::new(BIN)
            .args(["status", out.to_str().unwrap()])
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&s.stdout);
        assert!(
            text.contains("0 done") && text.contains("4 missing"),
            "{text}"
        );
        assert!(text.contains("lock: none"), "{text}");
    }
}

#[test]
fn sigterm_ends_an_optimize_study_and_its_lock() {
    let dir = scratch("optimize");
    tiny(&dir, 0.1);
    let file = dir.join("study.toml");
    std::fs::write(
        &file,
        "[study]\nbase = \"base.toml\"\nmax_evaluations = 4\nduration_pulses = 200.0\n\n[optimize]\nstress = [15000.0, 35000.0]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let e = ended_by(
        &[
            "optimize",
            file.to_str().unwrap(),
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ],
        &out,
        libc::SIGTERM,
        "SIGTERM",
    );
    assert!(e.contains("SIGTERM") && e.contains("resume"), "{e}");
    clean(&out, "optimize");
}

#[test]
fn sighup_ends_a_merge_that_is_refining() {
    // Shards of a 2 x 2 grid with one regime boundary; the merge bisects it (`refine`), one
    // simulation of 200 s of the tiny S-start per step: the signal arrives mid-refinement.
    let dir = scratch("merge");
    tiny(&dir, 200.0);
    let file = dir.join("phase.toml");
    std::fs::write(
        &file,
        "[phase]\nbase = \"base.toml\"\nweight = [100.0, 1000.0]\ntorque = [12.0, 22.0]\nrefine = true\nrefine_steps = 2\n",
    )
    .unwrap();
    let f = file.to_str().unwrap();
    let shards: Vec<String> = ["1/2", "2/2"]
        .iter()
        .map(|s| {
            let out = dir.join(format!("shard_{}", &s[..1]));
            let o = Command::new(BIN)
                .args([
                    "phase",
                    f,
                    "--quiet",
                    "--shard",
                    s,
                    "--out",
                    out.to_str().unwrap(),
                ])
                .output()
                .unwrap();
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            out.to_str().unwrap().to_string()
        })
        .collect();
    let merged = dir.join("merged");
    let e = ended_by(
        &[
            "merge",
            &shards[0],
            &shards[1],
            "--out",
            merged.to_str().unwrap(),
        ],
        &merged,
        libc::SIGHUP,
        "SIGHUP",
    );
    assert!(e.contains("SIGHUP") && e.contains("resume"), "{e}");
    clean(&merged, "merge");
    for s in &shards {
        clean(Path::new(s), "a merge's input");
    }
}
