//! A rerun whose final move fails loses nothing (`src/output/staging.rs`): the previous
//! results stay as they were, the new ones are kept in a folder the error names, and the lock
//! and staging folder go. Made to fail even as root (a directory where a result file must go)
//! and, where `runuser` exists and the tests run as root, as an unprivileged user (`nobody`)
//! with a subfolder of the previous results that it cannot change. A rerun also removes the
//! renderings of `slither movie` it does not write again, and never a user's file.
#![cfg(unix)]

use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_slither");
const DATA: [&str; 3] = ["summary.json", "final.csv", "trajectory.npz"];

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("slither-commit-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The bundled sliding rod (0.6 s, 600 steps: well under a second with figures).
fn slide(dir: &Path) -> PathBuf {
    let file = dir.join("slide.toml");
    std::fs::copy("problems/slide.toml", &file).unwrap();
    file
}

fn slither(args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .env("RAYON_NUM_THREADS", "1")
        .output()
        .unwrap()
}

fn data(out: &Path) -> Vec<Vec<u8>> {
    DATA.iter()
        .map(|n| std::fs::read(out.join(n)).unwrap())
        .collect()
}

/// The folder of new results the error names (`unsaved_run_PID`), checked to exist.
fn kept_folder(err: &str, out: &Path) -> PathBuf {
    let kept: Vec<PathBuf> = std::fs::read_dir(out)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("unsaved_run_")
        })
        .collect();
    assert_eq!(kept.len(), 1, "{err}");
    assert!(
        err.contains(&kept[0].display().to_string()),
        "the error names {}: {err}",
        kept[0].display()
    );
    kept[0].clone()
}

fn no_leftovers(out: &Path) {
    for n in [".slither.lock", ".run.tmp", ".run.old"] {
        assert!(!out.join(n).exists(), "{n} left in {}", out.display());
    }
}

#[test]
fn a_rerun_whose_final_move_fails_keeps_both_results() {
    let dir = scratch("root");
    let (file, out) = (slide(&dir), dir.join("out"));
    let (f, o) = (file.to_str().unwrap(), out.to_str().unwrap());
    let first = slither(&["run", f, "--out", o, "--quiet", "--no-plots"]);
    assert_eq!(
        first.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let before = data(&out);
    // A non-empty directory where the rerun's tracks.png must go: no rename replaces it,
    // whoever runs.
    std::fs::create_dir_all(out.join("tracks.png/inside")).unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let rerun = slither(&["run", f, "--out", o, "--quiet"]);
    let err = String::from_utf8_lossy(&rerun.stderr).into_owned();
    assert_eq!(rerun.status.code(), Some(1), "{err}");
    assert!(
        err.contains("tracks.png") && err.contains("previous results are unchanged"),
        "{err}"
    );
    assert_eq!(data(&out), before, "the previous results changed");
    let kept = kept_folder(&err, &out);
    for n in DATA.iter().chain(&["tracks.png", "snapshots.png"]) {
        assert!(kept.join(n).is_file(), "{n} not kept in {}", kept.display());
    }
    assert!(
        !out.join("snapshots.png").exists(),
        "a new figure was moved in"
    );
    no_leftovers(&out);
    // The obstacle gone, a rerun replaces the results; the user's file stays.
    std::fs::remove_dir_all(out.join("tracks.png")).unwrap();
    let again = slither(&["run", f, "--out", o, "--quiet"]);
    assert_eq!(
        again.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
    assert!(out.join("tracks.png").is_file() && out.join("snapshots.png").is_file());
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "mine"
    );
    no_leftovers(&out);
}

#[test]
fn a_rerun_removes_earlier_movie_renderings_but_no_user_file() {
    let dir = scratch("movies");
    let (file, out) = (slide(&dir), dir.join("out"));
    let (f, o) = (file.to_str().unwrap(), out.to_str().unwrap());
    assert!(slither(&["run", f, "--out", o, "--quiet", "--no-plots"])
        .status
        .success());
    let m = slither(&["movie", o, "--view", "top", "--size", "160x120"]);
    assert!(m.status.success(), "{}", String::from_utf8_lossy(&m.stderr));
    assert!(
        slither(&["movie", o, "--still", "0.3", "--size", "160x120"])
            .status
            .success()
    );
    assert!(out.join("movie_top_contact.gif").exists() && out.join("still_0.3.png").exists());
    std::fs::write(out.join("movie_notes.txt"), "mine").unwrap();
    std::fs::write(out.join("my_still.png"), "mine").unwrap();
    assert!(slither(&["run", f, "--out", o, "--quiet", "--no-plots"])
        .status
        .success());
    assert!(!out.join("movie_top_contact.gif").exists() && !out.join("still_0.3.png").exists());
    assert!(out.join("movie_notes.txt").exists() && out.join("my_still.png").exists());
}

/// `chown` by name through the system tool (the tests run as root there).
fn chown(owner: &str, path: &Path, recursive: bool) {
    let mut c = Command::new("chown");
    if recursive {
        c.arg("-R");
    }
    assert!(c.arg(owner).arg(path).status().unwrap().success());
}

#[test]
fn an_unprivileged_rerun_that_cannot_replace_a_subfolder_keeps_both_results() {
    let runuser = ["/usr/sbin/runuser", "/sbin/runuser", "/usr/bin/runuser"]
        .into_iter()
        .find(|p| Path::new(p).exists());
    let Some(runuser) = runuser else {
        eprintln!("skipped: no runuser on this machine");
        return;
    };
    if unsafe { libc::geteuid() } != 0 {
        eprintln!("skipped: runuser needs root (the tests run as root in CI)");
        return;
    }
    let as_nobody = |args: &[&str]| {
        Command::new(runuser)
            .args(["-u", "nobody", "--", BIN])
            .args(args)
            .env("RAYON_NUM_THREADS", "1")
            .output()
            .unwrap()
    };
    if !as_nobody(&["--version"]).status.success() {
        eprintln!("skipped: user nobody cannot run {BIN}");
        return;
    }
    let dir = scratch("nobody");
    std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o755)).unwrap();
    let (file, out) = (slide(&dir), dir.join("out"));
    let (f, o) = (file.to_str().unwrap(), out.to_str().unwrap());
    assert!(slither(&["run", f, "--out", o, "--quiet", "--no-plots"])
        .status
        .success());
    // The previous results belong to nobody, but their vtk/ (with a ParaView frame a rerun
    // must remove) to root: nobody cannot move anything out of it.
    std::fs::create_dir(out.join("vtk")).unwrap();
    std::fs::write(out.join("vtk/frame_0.vtp"), "old frame").unwrap();
    chown("nobody", &out, true);
    chown("root", &out.join("vtk"), true);
    let before = data(&out);
    let rerun = as_nobody(&["run", f, "--out", o, "--quiet", "--no-plots"]);
    let err = String::from_utf8_lossy(&rerun.stderr).into_owned();
    assert_eq!(rerun.status.code(), Some(1), "{err}");
    assert!(
        err.contains("vtk/frame_0.vtp") && err.contains("previous results are unchanged"),
        "{err}"
    );
    assert_eq!(data(&out), before, "the previous results changed");
    assert_eq!(
        std::fs::read_to_string(out.join("vtk/frame_0.vtp")).unwrap(),
        "old frame"
    );
    let kept = kept_folder(&err, &out);
    for n in DATA {
        assert!(kept.join(n).is_file(), "{n} not kept in {}", kept.display());
    }
    no_leftovers(&out);
    let _ = std::fs::remove_dir_all(&dir);
}
