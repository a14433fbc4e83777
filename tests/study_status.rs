//! `slither status DIR` on a half-finished sharded phase study: per shard the cells done,
//! failed and missing, its lock with host, process and liveness (another host's: unknown),
//! the resume command; over the shards the cells missing, the shards seen and absent, and the
//! merge command. Also an optimize study and a run directory.

mod common;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_slither");

fn slither(args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .env("RAYON_NUM_THREADS", "2")
        .output()
        .unwrap()
}

fn status(dir: &Path) -> String {
    let o = slither(&["status", dir.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn has(text: &str, needles: &[&str]) {
    for n in needles {
        assert!(text.contains(n), "{n:?} missing from:\n{text}");
    }
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("slither-status-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn status_of_a_half_finished_sharded_study() {
    let dir = scratch("shards");
    std::fs::write(dir.join("base.toml"), common::TINY_S_START).unwrap();
    let file = dir.join("phase.toml");
    std::fs::write(
        &file,
        "[phase]\nbase = \"base.toml\"\nweight = [300.0, 3000.0]\ntorque = [10.0, 15.0, 20.0]\n",
    )
    .unwrap();
    let shards = dir.join("shards");
    let f = file.to_str().unwrap();
    // Shards 1/3 and 2/3 of the six cells run; shard 2/3 then loses its last row (a cell
    // cut short) and holds another host's lock; shard 3/3 never ran.
    for s in ["1/3", "2/3"] {
        let out = shards.join(format!("s{}", &s[..1]));
        let o = slither(&[
            "phase",
            f,
            "--quiet",
            "--shard",
            s,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let s2 = shards.join("s2");
    let csv = std::fs::read_to_string(s2.join("phase.csv")).unwrap();
    let mut lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 3, "header and two cells:\n{csv}");
    lines.pop();
    std::fs::write(s2.join("phase.csv"), lines.join("\n") + "\n").unwrap();
    std::fs::write(s2.join(".slither.lock"), "4242\nsome-other-host\n").unwrap();

    let one = status(&shards.join("s1"));
    has(
        &one,
        &[
            "shard 1/3 (2 cells of 6)",
            "cells: 2 done (2 ok, 0 failed), 0 missing",
            "lock: none",
            "shard done",
        ],
    );
    let two = status(&s2);
    has(
        &two,
        &[
            "shard 2/3 (2 cells of 6)",
            "cells: 1 done (1 ok, 0 failed), 1 missing",
            "process 4242 on host some-other-host: unknown",
            &format!(
                "resume: slither phase {f} --out {} --shard 2/3",
                s2.display()
            ),
        ],
    );
    let all = status(&shards);
    has(
        &all,
        &[
            "2 shard directories",
            "all shards: 3 of 6 cells done, 3 missing",
            "shards seen: 1/3 2/3",
            "no directory for shard 3/3",
            "slither merge",
        ],
    );
    // Status reads only: the lock and the CSV are as they were.
    assert_eq!(
        std::fs::read_to_string(s2.join(".slither.lock")).unwrap(),
        "4242\nsome-other-host\n"
    );
}

#[test]
fn status_of_a_run_and_of_nothing() {
    let dir = scratch("run");
    let out = dir.join("out");
    let o = slither(&[
        "run",
        "problems/slide.toml",
        "--quiet",
        "--no-plots",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    has(
        &status(&out),
        &[
            "status completed",
            "lock: none",
            "rerun: slither run problems/slide.toml",
        ],
    );
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let o = slither(&["status", empty.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("holds no study or run"));
}
