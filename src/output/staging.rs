//! A run's outputs are written into a staging folder inside the output directory
//! (`DIR/.run.tmp/`) and swapped in only when they are complete ([`Staging::commit`]). A run
//! that is interrupted or killed before that leaves the previous results untouched; the stale
//! staging folder goes with the next run ([`Staging::new`]) or when the [`Staging`] is dropped
//! without a commit.
//!
//! The commit never loses results. It first checks that every new file can take its place
//! (nothing but a previous output of slither stands there); then it moves the previous
//! outputs aside into `DIR/.run.old/`, moves the new ones in, and only then deletes the old
//! ones. Any failure on the way moves everything back (the previous results as they were)
//! and keeps the new results in a visible folder, `DIR/unsaved_run_<PID>/`, named in the
//! error ([`CommitError`]).
//!
//! Which files are slither's ([`is_run_output`]): the fixed names of [`super::RUN_OUTPUTS`],
//! the renderings of `slither movie` (`movie_*.gif`, `still_*.png`) and, inside `vtk/`, the
//! ParaView frames (`frame_*.vtp`, `frames.pvd`). A rerun removes every one of them that it
//! does not write again; every other file (a user's notes, their own files inside `vtk/`,
//! `accuracy_runs.jsonl`) stays.

use std::io;
use std::path::{Path, PathBuf};

/// Name of the staging folder inside the output directory.
pub const STAGING_DIR: &str = ".run.tmp";
/// Name of the folder the previous outputs wait in during a commit.
pub const ASIDE_DIR: &str = ".run.old";

/// Whether `name`, at the top of an output directory, is a file slither writes there (a
/// rerun replaces or removes it): [`super::RUN_OUTPUTS`] and `slither movie`'s renderings.
pub fn is_run_output(name: &str) -> bool {
    super::RUN_OUTPUTS.contains(&name)
        || (name.starts_with("movie_") && name.ends_with(".gif"))
        || (name.starts_with("still_") && name.ends_with(".png"))
}

/// Whether `name`, inside `vtk/`, is a ParaView file slither writes there.
pub fn is_vtk_output(name: &str) -> bool {
    (name.starts_with("frame_") && name.ends_with(".vtp")) || name == "frames.pvd"
}

/// A commit that did not happen: the previous results are as they were, and the new ones
/// wait in `kept`.
#[derive(Debug, thiserror::Error)]
#[error("{what}; the previous results are unchanged and the new results are kept in {kept} (move them by hand, or fix the cause and rerun)", kept = kept.display())]
pub struct CommitError {
    /// What could not be done, naming the file.
    pub what: String,
    /// The folder holding the new results.
    pub kept: PathBuf,
}

impl From<CommitError> for io::Error {
    fn from(e: CommitError) -> io::Error {
        io::Error::other(e.to_string())
    }
}

/// The staging folder of one run in `out` (hold the output directory's lock first).
#[derive(Debug)]
pub struct Staging {
    out: PathBuf,
    dir: PathBuf,
    done: bool,
}

/// `path: e` as an error text.
fn named(path: &Path, e: impl std::fmt::Display) -> String {
    format!("{}: {e}", path.display())
}

impl Staging {
    /// Create `out/.run.tmp/`, empty (a folder left by a killed run is removed first, and so
    /// is an aside folder, `.run.old/`, after its files were put back).
    pub fn new(out: &Path) -> io::Result<Self> {
        restore_aside(out);
        let dir = out.join(STAGING_DIR);
        match std::fs::remove_dir_all(&dir) {
            Err(e) if e.kind() != io::ErrorKind::NotFound => {
                return Err(io::Error::new(e.kind(), named(&dir, e)))
            }
            _ => {}
        }
        std::fs::create_dir(&dir).map_err(|e| io::Error::new(e.kind(), named(&dir, e)))?;
        Ok(Staging {
            out: out.into(),
            dir,
            done: false,
        })
    }

    /// The folder the run writes into.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Whether `out` holds a previous run's results (its `summary.json`).
    pub fn has_previous(&self) -> bool {
        self.out.join("summary.json").exists()
    }

    /// Replace the previous run's outputs in `out` by the staged ones (module doc): all of
    /// them, or none and a [`CommitError`] naming the folder that keeps the new ones.
    pub fn commit(mut self) -> Result<(), CommitError> {
        self.done = true;
        let result = swap(&self.out, &self.dir);
        if let Err(what) = result {
            let unsaved = self.out.join(format!("unsaved_run_{}", std::process::id()));
            let kept = match std::fs::rename(&self.dir, &unsaved) {
                Ok(()) => unsaved,
                Err(_) => self.dir.clone(),
            };
            return Err(CommitError { what, kept });
        }
        let _ = std::fs::remove_dir_all(&self.dir);
        Ok(())
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.done {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
    }
}

/// One move of the swap: `from` to `to`, both absolute.
type Move = (PathBuf, PathBuf);

/// The moves of a commit of `stage` into `out`: the previous outputs aside (into `aside`),
/// then the new ones in. `Err` names what cannot be replaced (checked before anything moves).
fn plan(out: &Path, stage: &Path, aside: &Path) -> Result<(Vec<Move>, Vec<Move>), String> {
    let list = |d: &Path| -> Result<Vec<String>, String> {
        let mut v = Vec::new();
        for e in std::fs::read_dir(d).map_err(|e| named(d, e))? {
            v.push(
                e.map_err(|e| named(d, e))?
                    .file_name()
                    .to_string_lossy()
                    .into_owned(),
            );
        }
        v.sort();
        Ok(v)
    };
    let is_file = |p: &Path| std::fs::symlink_metadata(p).is_ok_and(|m| !m.is_dir());
    let (mut old, mut new) = (Vec::new(), Vec::new());
    for name in list(out)? {
        let p = out.join(&name);
        if name != "vtk" && is_run_output(&name) && is_file(&p) {
            old.push((p, aside.join(&name)));
        }
    }
    let out_vtk = out.join("vtk");
    let vtk_is_dir = std::fs::symlink_metadata(&out_vtk).is_ok_and(|m| m.is_dir());
    if vtk_is_dir {
        for name in list(&out_vtk)? {
            let p = out_vtk.join(&name);
            if is_vtk_output(&name) && is_file(&p) {
                old.push((p, aside.join("vtk").join(&name)));
            }
        }
    }
    let leaving: Vec<&PathBuf> = old.iter().map(|(p, _)| p).collect();
    let free = |target: &Path| -> Result<(), String> {
        match std::fs::symlink_metadata(target) {
            Err(_) => Ok(()),
            Ok(_) if leaving.iter().any(|p| p.as_path() == target) => Ok(()),
            Ok(m) => Err(format!(
                "{}: cannot be replaced by the new result: it is {} that is not a previous output of slither",
                target.display(),
                if m.is_dir() { "a directory" } else { "a file" }
            )),
        }
    };
    for name in list(stage)? {
        let from = stage.join(&name);
        if name == "vtk" && vtk_is_dir && from.is_dir() {
            // `vtk/` can hold a user's own files: the new frames go in beside them.
            for inner in list(&from)? {
                let to = out_vtk.join(&inner);
                free(&to)?;
                new.push((from.join(&inner), to));
            }
        } else {
            let to = out.join(&name);
            free(&to)?;
            new.push((from, to));
        }
    }
    Ok((old, new))
}

/// Move the previous outputs of `out` aside, the staged ones in, then delete the old ones;
/// on an error undo every move done (module doc) and name what failed.
fn swap(out: &Path, stage: &Path) -> Result<(), String> {
    let aside = out.join(ASIDE_DIR);
    restore_aside(out);
    let (old, new) = plan(out, stage, &aside)?;
    std::fs::create_dir_all(aside.join("vtk")).map_err(|e| named(&aside, e))?;
    let mut done: Vec<&Move> = Vec::new();
    let mut failure = None;
    for m in old.iter().chain(&new) {
        if let Err(e) = std::fs::rename(&m.0, &m.1) {
            failure = Some(format!(
                "{}: cannot be {}: {e}",
                if done.len() < old.len() { &m.0 } else { &m.1 }.display(),
                if done.len() < old.len() {
                    "moved aside (it would be replaced or removed)"
                } else {
                    "written"
                }
            ));
            break;
        }
        done.push(m);
    }
    if let Some(what) = failure {
        // Undo in reverse order: the new files back to the staging folder, the old ones back
        // into place.
        let mut lost = Vec::new();
        for (from, to) in done.iter().rev() {
            if std::fs::rename(to, from).is_err() {
                lost.push(to.display().to_string());
            }
        }
        if lost.is_empty() {
            let _ = std::fs::remove_dir_all(&aside);
        }
        return Err(if lost.is_empty() {
            what
        } else {
            format!(
                "{what}; and these could not be moved back (they are in {}): {}",
                aside.display(),
                lost.join(", ")
            )
        });
    }
    // Every new file is in place: the old ones go (an empty `vtk/` left by them too).
    let _ = std::fs::remove_dir_all(&aside);
    if old
        .iter()
        .any(|(p, _)| p.parent() == Some(out.join("vtk").as_path()))
        && !new.iter().any(|(_, to)| to.starts_with(out.join("vtk")))
    {
        let _ = std::fs::remove_dir(out.join("vtk"));
    }
    Ok(())
}

/// Put back the previous outputs a killed commit left in `out/.run.old/` (where nothing took
/// their place), then remove that folder.
fn restore_aside(out: &Path) {
    let aside = out.join(ASIDE_DIR);
    let Ok(entries) = std::fs::read_dir(&aside) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name();
        if name == "vtk" {
            if let Ok(inner) = std::fs::read_dir(e.path()) {
                for f in inner.flatten() {
                    let to = out.join("vtk").join(f.file_name());
                    if !to.exists() && std::fs::create_dir_all(out.join("vtk")).is_ok() {
                        let _ = std::fs::rename(f.path(), to);
                    }
                }
            }
        } else if !out.join(&name).exists() {
            let _ = std::fs::rename(e.path(), out.join(&name));
        }
    }
    let _ = std::fs::remove_dir_all(&aside);
}

/// Remove what a process ended by a signal leaves in the output directory `out`: the staging
/// folder, an aside folder (its files put back first), the ParaView staging folder, the
/// temporary files of atomic writes (`.NAME.tmp`, `.NAME.tmp.png`, `.NAME.tmp.svg`, and
/// `refine.csv.tmp`) and this process's private lock file (`.slither.lock.PID`). Results and
/// every other file stay.
pub fn abandon(out: &Path) {
    restore_aside(out);
    let _ = std::fs::remove_dir_all(out.join(STAGING_DIR));
    let _ = std::fs::remove_dir_all(out.join(".vtk.tmp"));
    let Ok(entries) = std::fs::read_dir(out) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let hidden_tmp = name.starts_with('.')
            && (name.ends_with(".tmp") || name.ends_with(".tmp.png") || name.ends_with(".tmp.svg"));
        let temporary = hidden_tmp
            || name == "refine.csv.tmp"
            || name == format!("{}.{}", super::lock::LOCK_FILE, std::process::id());
        if temporary && e.file_type().is_ok_and(|t| t.is_file()) {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(p: PathBuf) -> String {
        std::fs::read_to_string(p).unwrap()
    }

    #[test]
    fn previous_results_survive_until_the_commit() {
        let out = std::env::temp_dir().join(format!("slither_staging_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&out);
        std::fs::create_dir_all(out.join("vtk")).unwrap();
        std::fs::write(out.join("summary.json"), "old").unwrap();
        std::fs::write(out.join("final.csv"), "old").unwrap();
        std::fs::write(out.join("movie_top_contact.gif"), "old").unwrap();
        std::fs::write(out.join("still_0.5.png"), "old").unwrap();
        std::fs::write(out.join("vtk/frame_0.vtp"), "old").unwrap();
        std::fs::write(out.join("vtk/mine.txt"), "user").unwrap();
        std::fs::write(out.join("notes.txt"), "user").unwrap();
        std::fs::write(out.join("movie_notes.txt"), "user").unwrap();
        // A run dropped before its commit (interrupted) leaves everything as it was.
        {
            let st = Staging::new(&out).unwrap();
            assert!(st.has_previous());
            std::fs::write(st.dir().join("summary.json"), "new").unwrap();
        }
        assert!(!out.join(STAGING_DIR).exists());
        assert_eq!(read(out.join("summary.json")), "old");
        assert_eq!(read(out.join("final.csv")), "old");
        // A committed run replaces the previous outputs and keeps the user's files.
        let st = Staging::new(&out).unwrap();
        std::fs::write(st.dir().join("summary.json"), "new").unwrap();
        std::fs::create_dir(st.dir().join("vtk")).unwrap();
        std::fs::write(st.dir().join("vtk/frame_1.vtp"), "new").unwrap();
        st.commit().unwrap();
        assert_eq!(read(out.join("summary.json")), "new");
        for gone in [
            "final.csv",
            "movie_top_contact.gif",
            "still_0.5.png",
            "vtk/frame_0.vtp",
        ] {
            assert!(
                !out.join(gone).exists(),
                "{gone}: an old output not rewritten is gone"
            );
        }
        assert!(out.join("vtk/frame_1.vtp").exists() && out.join("vtk/mine.txt").exists());
        assert!(out.join("notes.txt").exists() && out.join("movie_notes.txt").exists());
        assert!(!out.join(STAGING_DIR).exists() && !out.join(ASIDE_DIR).exists());
        std::fs::remove_dir_all(&out).unwrap();
    }

    #[test]
    fn a_commit_that_cannot_finish_changes_nothing_and_keeps_the_new_results() {
        let out = std::env::temp_dir().join(format!("slither_commit_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&out);
        std::fs::create_dir_all(&out).unwrap();
        std::fs::write(out.join("summary.json"), "old").unwrap();
        std::fs::write(out.join("final.csv"), "old").unwrap();
        // A user's non-empty directory where a new result file must go: refused before any
        // move (root too).
        std::fs::create_dir_all(out.join("tracks.png/inside")).unwrap();
        let st = Staging::new(&out).unwrap();
        for f in ["summary.json", "final.csv", "tracks.png"] {
            std::fs::write(st.dir().join(f), "new").unwrap();
        }
        let e = st.commit().unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("tracks.png") && text.contains("unsaved_run_"),
            "{text}"
        );
        assert_eq!(read(out.join("summary.json")), "old");
        assert_eq!(read(out.join("final.csv")), "old");
        assert_eq!(read(e.kept.join("summary.json")), "new");
        assert!(out.join("tracks.png/inside").is_dir() && !out.join(ASIDE_DIR).exists());
        std::fs::remove_dir_all(&out).unwrap();
    }

    #[test]
    fn abandon_removes_temporaries_and_puts_moved_aside_results_back() {
        let out = std::env::temp_dir().join(format!("slither_abandon_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&out);
        std::fs::create_dir_all(out.join(STAGING_DIR)).unwrap();
        std::fs::create_dir_all(out.join(ASIDE_DIR)).unwrap();
        std::fs::write(out.join(ASIDE_DIR).join("summary.json"), "old").unwrap();
        let temporaries = [
            ".summary.json.tmp",
            ".tracks.tmp.png",
            ".tracks.tmp.svg",
            "refine.csv.tmp",
        ];
        let users = ["notes.tmp", ".hidden", "phase.csv"];
        for n in temporaries.iter().chain(&users) {
            std::fs::write(out.join(n), "x").unwrap();
        }
        abandon(&out);
        for n in temporaries {
            assert!(!out.join(n).exists(), "{n} left");
        }
        for n in users {
            assert!(
                out.join(n).exists(),
                "{n}, not a temporary of slither's, removed"
            );
        }
        assert_eq!(read(out.join("summary.json")), "old");
        assert!(!out.join(STAGING_DIR).exists() && !out.join(ASIDE_DIR).exists());
        std::fs::remove_dir_all(&out).unwrap();
    }
}
