//! `slither status DIR`: what a study or run directory holds, read without changing anything.
//!
//! - A phase study (`phase.json`, `phase.csv`): the grid or the shard it owns, its cells done
//!   (ok and failed) and missing, the growth line's sizes (`growth.csv`) and refinement
//!   (`refine.csv`).
//! - A folder of shard directories (sub-folders holding `phase.json`): each shard as above,
//!   the cells no shard has finished and the `slither merge` command.
//! - An optimize study (`history.csv`): evaluations ok and failed, whether `optimum.json` says
//!   it finished.
//! - A run directory (`summary.json`): its status and time reached.
//!
//! For each: the lock (`.slither.lock`: process, host and whether the process lives, "unknown"
//! for another host's) and the command that resumes it. Exit 0, or 2 for a folder that is none
//! of these.
use slither::output::lock::{LockInfo, LOCK_FILE};
use slither::studies::phase::{RunInfo, Shard};
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// A study's or run's output directory, or a folder holding shard directories.
    pub dir: PathBuf,
}

/// The rows of a study CSV (`phase.csv`, `growth.csv`, `refine.csv`, `history.csv`): the
/// values of `columns` in each complete line (a torn last line is not counted).
fn rows(csv: &Path, columns: &[&str]) -> Option<Vec<Vec<String>>> {
    let text = std::fs::read_to_string(csv).ok()?;
    let complete = match text.rfind('\n') {
        Some(end) => &text[..end],
        None => "",
    };
    let mut lines = complete.lines();
    let header: Vec<&str> = lines.next()?.split(',').collect();
    let at: Vec<usize> = columns
        .iter()
        .map(|c| header.iter().position(|h| h == c))
        .collect::<Option<_>>()?;
    Some(
        lines
            .filter(|l| !l.trim().is_empty())
            .map(|l| {
                let f: Vec<&str> = l.split(',').collect();
                at.iter()
                    .map(|&i| f.get(i).unwrap_or(&"").to_string())
                    .collect()
            })
            .collect(),
    )
}

/// "N ok, M failed" of rows whose first field is the status.
fn ok_failed(statuses: impl Iterator<Item = String>) -> (usize, usize) {
    statuses.fold(
        (0, 0),
        |(o, f), s| {
            if s == "ok" {
                (o + 1, f)
            } else {
                (o, f + 1)
            }
        },
    )
}

/// The lock line of `dir`.
fn lock_line(dir: &Path) -> String {
    let path = dir.join(LOCK_FILE);
    if !path.exists() {
        return "lock: none (no slither process is writing here)".into();
    }
    match LockInfo::read(&path) {
        Some(l) => format!(
            "lock: {} held by process {} on host {}: {}",
            path.display(),
            l.pid,
            l.host
                .as_deref()
                .unwrap_or("unknown (an older lock: taken as this host)"),
            l.liveness()
        ),
        None => format!("lock: {} is not readable as a slither lock", path.display()),
    }
}

/// A phase directory's grid cells it owns, and which of them are done.
struct PhaseDir {
    info: RunInfo,
    owned: Vec<(u64, u64)>,
    done: HashSet<(u64, u64)>,
    ok: usize,
    failed: usize,
}

fn read_phase(dir: &Path) -> Option<PhaseDir> {
    let info: RunInfo =
        serde_json::from_str(&std::fs::read_to_string(dir.join("phase.json")).ok()?).ok()?;
    let owned: Vec<(u64, u64)> = info
        .weight
        .iter()
        .flat_map(|&w| info.torque.iter().map(move |&g| (w.to_bits(), g.to_bits())))
        .enumerate()
        .filter(|(k, _)| info.shard.is_none_or(|s| s.owns(*k)))
        .map(|(_, c)| c)
        .collect();
    let owned_set: HashSet<_> = owned.iter().copied().collect();
    let mut done = HashSet::new();
    let (mut ok, mut failed) = (0, 0);
    for r in rows(&dir.join("phase.csv"), &["weight", "torque", "status"]).unwrap_or_default() {
        let (Ok(w), Ok(g)) = (r[0].parse::<f64>(), r[1].parse::<f64>()) else {
            continue;
        };
        let key = (w.to_bits(), g.to_bits());
        if owned_set.contains(&key) && done.insert(key) {
            if r[2] == "ok" {
                ok += 1
            } else {
                failed += 1
            }
        }
    }
    Some(PhaseDir {
        info,
        owned,
        done,
        ok,
        failed,
    })
}

fn cell_text(c: &(u64, u64)) -> String {
    format!("{},{}", f64::from_bits(c.0), f64::from_bits(c.1))
}

/// A short list of missing cells (the first few, then how many more).
fn missing_text(missing: &[(u64, u64)]) -> String {
    let mut s: Vec<String> = missing.iter().take(5).map(cell_text).collect();
    if missing.len() > 5 {
        s.push(format!("... ({} more)", missing.len() - 5));
    }
    s.join("  ")
}

fn phase_status(dir: &Path, p: &PhaseDir) {
    let i = &p.info;
    let missing: Vec<_> = p
        .owned
        .iter()
        .filter(|c| !p.done.contains(c))
        .copied()
        .collect();
    println!(
        "{}: phase study of {} (base {}), grid {} W x {} G{}",
        dir.display(),
        i.phase_file,
        i.base_file,
        i.weight.len(),
        i.torque.len(),
        match i.shard {
            Some(s) => format!(
                ", shard {}/{} ({} cells of {})",
                s.index,
                s.count,
                p.owned.len(),
                i.weight.len() * i.torque.len()
            ),
            None => String::new(),
        }
    );
    println!(
        "cells: {} done ({} ok, {} failed), {} missing{}",
        p.done.len(),
        p.ok,
        p.failed,
        missing.len(),
        if missing.is_empty() {
            String::new()
        } else {
            format!(" (W,G: {})", missing_text(&missing))
        }
    );
    if let Some(g) = &i.growth {
        let r = rows(&dir.join("growth.csv"), &["status"]).unwrap_or_default();
        let (ok, failed) = ok_failed(r.into_iter().map(|mut v| v.remove(0)));
        println!(
            "growth line: {} sizes; {} rows ({ok} ok, {failed} failed) in growth.csv",
            g.diameters.len(),
            ok + failed
        );
    }
    if i.refine_steps.is_some() && i.shard.is_none_or(|s| s.count == 1) {
        let r = rows(&dir.join("refine.csv"), &["status"]).unwrap_or_default();
        let (ok, failed) = ok_failed(r.into_iter().map(|mut v| v.remove(0)));
        println!(
            "refinement: {} simulations ({ok} ok, {failed} failed) in refine.csv",
            ok + failed
        );
    }
    let sharded = i.shard.is_some_and(|s| s.count > 1);
    let finished = missing.is_empty() && (sharded || dir.join("boundaries.json").exists());
    println!("{}", lock_line(dir));
    if finished && sharded {
        println!(
            "shard done: every cell of this shard finished (merge the shards with slither merge)"
        );
    } else if finished {
        println!("finished: every cell done and the figures written (a rerun replays without simulating)");
    } else {
        println!(
            "resume: slither phase {} --out {}{}{}",
            i.phase_file,
            dir.display(),
            i.shard.map_or(String::new(), |s| format!(
                " --shard {}/{}",
                s.index, s.count
            )),
            set_args(&i.settings)
        );
    }
}

/// The `--set` arguments a study ran with (from `phase.json`), quoted for a shell.
fn set_args(settings: &[String]) -> String {
    settings
        .iter()
        .map(|s| format!(" --set '{}'", s.replace('\'', "'\\''")))
        .collect()
}

/// A folder of shard directories: each shard, the union and the merge command.
fn shards_status(dir: &Path, shards: &[(PathBuf, PhaseDir)]) {
    println!("{}: {} shard directories", dir.display(), shards.len());
    let mut grid: Vec<(u64, u64)> = Vec::new();
    let mut done: HashSet<(u64, u64)> = HashSet::new();
    let mut seen: Vec<Shard> = Vec::new();
    let mut count = None;
    for (d, p) in shards {
        println!();
        phase_status(d, p);
        let all = p.info.weight.iter().flat_map(|&w| {
            p.info
                .torque
                .iter()
                .map(move |&g| (w.to_bits(), g.to_bits()))
        });
        for c in all {
            if !grid.contains(&c) {
                grid.push(c);
            }
        }
        done.extend(p.done.iter().copied());
        if let Some(s) = p.info.shard {
            seen.push(s);
            count = Some(s.count);
        }
    }
    println!();
    let missing: Vec<_> = grid.iter().filter(|c| !done.contains(c)).copied().collect();
    let absent: Vec<usize> = count.map_or(Vec::new(), |n| {
        (1..=n)
            .filter(|i| !seen.iter().any(|s| s.index == *i))
            .collect()
    });
    println!(
        "all shards: {} of {} cells done, {} missing{}; shards seen: {}{}",
        done.len(),
        grid.len(),
        missing.len(),
        if missing.is_empty() {
            String::new()
        } else {
            format!(" (W,G: {})", missing_text(&missing))
        },
        seen.iter()
            .map(|s| format!("{}/{}", s.index, s.count))
            .collect::<Vec<_>>()
            .join(" "),
        if absent.is_empty() {
            String::new()
        } else {
            format!(
                "; no directory for shard {}",
                absent
                    .iter()
                    .map(|i| format!("{i}/{}", count.unwrap_or(0)))
                    .collect::<Vec<_>>()
                    .join(" ")
            )
        }
    );
    if let Some((_, p)) = shards.first() {
        for i in &absent {
            println!(
                "run: slither phase {} --shard {i}/{} --out {}{}",
                p.info.phase_file,
                count.unwrap_or(0),
                dir.join(i.to_string()).display(),
                set_args(&p.info.settings)
            );
        }
    }
    println!(
        "merge when every shard is done: slither merge {} --out {}",
        shards
            .iter()
            .map(|(d, _)| d.display().to_string())
            .chain(
                absent
                    .iter()
                    .map(|i| dir.join(i.to_string()).display().to_string())
            )
            .collect::<Vec<_>>()
            .join(" "),
        dir.join("merged").display()
    );
}

fn optimize_status(dir: &Path) {
    let r = rows(&dir.join("history.csv"), &["status"]).unwrap_or_default();
    let (ok, failed) = ok_failed(r.into_iter().map(|mut v| v.remove(0)));
    println!("{}: optimize study", dir.display());
    println!(
        "evaluations: {} done ({ok} ok, {failed} failed) in history.csv",
        ok + failed
    );
    println!("{}", lock_line(dir));
    if dir.join("optimum.json").exists() {
        println!(
            "finished: optimum.json written (a rerun replays the evaluations without simulating)"
        );
    } else {
        println!("resume: slither optimize STUDY_FILE --out {} (the same study file: its evaluations in history.csv are reused)", dir.display());
    }
}

fn run_status(dir: &Path) {
    let s: Option<serde_json::Value> = std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok());
    let field = |k: &str| {
        s.as_ref()
            .and_then(|v| v.get(k))
            .map(|v| v.to_string().trim_matches('"').to_string())
    };
    println!(
        "{}: run of {}: status {}, reached t = {} s",
        dir.display(),
        field("problem").unwrap_or("?".into()),
        field("status").unwrap_or("?".into()),
        field("t_final").unwrap_or("?".into())
    );
    println!("{}", lock_line(dir));
    println!(
        "rerun: slither run {} --out {} (the results are replaced only when the new ones are complete)",
        field("problem").unwrap_or("PROBLEM".into()),
        dir.display()
    );
}

pub fn status(a: &Args) -> ExitCode {
    let dir = a.dir.as_path();
    if !dir.is_dir() {
        eprintln!(
            "error: {}: not a directory (give a study's or run's --out)",
            dir.display()
        );
        return ExitCode::from(2);
    }
    if let Some(p) = read_phase(dir) {
        phase_status(dir, &p);
        return ExitCode::SUCCESS;
    }
    if dir.join("history.csv").exists() {
        optimize_status(dir);
        return ExitCode::SUCCESS;
    }
    if dir.join("summary.json").exists() {
        run_status(dir);
        return ExitCode::SUCCESS;
    }
    let mut shards: Vec<(PathBuf, PhaseDir)> = std::fs::read_dir(dir)
        .map(|e| {
            e.flatten()
                .filter_map(|e| read_phase(&e.path()).map(|p| (e.path(), p)))
                .collect()
        })
        .unwrap_or_default();
    shards.sort_by(|a, b| a.0.cmp(&b.0));
    if !shards.is_empty() {
        shards_status(dir, &shards);
        return ExitCode::SUCCESS;
    }
    eprintln!(
        "error: {}: holds no study or run (no phase.json, history.csv or summary.json, nor sub-folders with phase.json)",
        dir.display()
    );
    ExitCode::from(2)
}
