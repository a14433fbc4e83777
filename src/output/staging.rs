//! A run's outputs are written into a staging folder inside the output directory
//! (`DIR/.run.tmp/`) and swapped in only when they are complete ([`Staging::commit`]): the
//! previous run's files ([`super::RUN_OUTPUTS`]) are removed and the new ones renamed into
//! place (a rename within one file system, so each file appears whole). A run that is
//! interrupted or killed before that leaves the previous results untouched; the stale staging
//! folder goes with the next run ([`Staging::new`]) or when the [`Staging`] is dropped
//! without a commit.

use std::io;
use std::path::{Path, PathBuf};

/// Name of the staging folder inside the output directory.
pub const STAGING_DIR: &str = ".run.tmp";

/// The staging folder of one run in `out` (hold the output directory's lock first).
#[derive(Debug)]
pub struct Staging {
    out: PathBuf,
    dir: PathBuf,
    committed: bool,
}

impl Staging {
    /// Create `out/.run.tmp/`, empty (a folder left by a killed run is removed first).
    pub fn new(out: &Path) -> io::Result<Self> {
        let dir = out.join(STAGING_DIR);
        match std::fs::remove_dir_all(&dir) {
            Err(e) if e.kind() != io::ErrorKind::NotFound => {
                return Err(io::Error::new(e.kind(), format!("{}: {e}", dir.display())))
            }
            _ => {}
        }
        std::fs::create_dir(&dir)
            .map_err(|e| io::Error::new(e.kind(), format!("{}: {e}", dir.display())))?;
        Ok(Staging {
            out: out.into(),
            dir,
            committed: false,
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

    /// Replace the previous run's outputs in `out` by the staged ones.
    pub fn commit(mut self) -> io::Result<()> {
        super::remove_previous(&self.out)?;
        for entry in std::fs::read_dir(&self.dir)? {
            let entry = entry?;
            let target = self.out.join(entry.file_name());
            if entry.path().is_dir() && target.is_dir() {
                // `vtk/` kept by remove_previous because it holds a user's own files: move
                // the new frames in beside them.
                for inner in std::fs::read_dir(entry.path())? {
                    let inner = inner?;
                    std::fs::rename(inner.path(), target.join(inner.file_name()))?;
                }
            } else {
                std::fs::rename(entry.path(), &target)
                    .map_err(|e| io::Error::new(e.kind(), format!("{}: {e}", target.display())))?;
            }
        }
        self.committed = true;
        std::fs::remove_dir_all(&self.dir)
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn previous_results_survive_until_the_commit() {
        let out = std::env::temp_dir().join(format!("slither_staging_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&out);
        std::fs::create_dir_all(out.join("vtk")).unwrap();
        std::fs::write(out.join("summary.json"), "old").unwrap();
        std::fs::write(out.join("final.csv"), "old").unwrap();
        std::fs::write(out.join("vtk/frame_0.vtp"), "old").unwrap();
        std::fs::write(out.join("vtk/mine.txt"), "user").unwrap();
        std::fs::write(out.join("notes.txt"), "user").unwrap();
        // A run dropped before its commit (interrupted) leaves everything as it was.
        {
            let st = Staging::new(&out).unwrap();
            assert!(st.has_previous());
            std::fs::write(st.dir().join("summary.json"), "new").unwrap();
        }
        assert!(!out.join(STAGING_DIR).exists());
        assert_eq!(
            std::fs::read_to_string(out.join("summary.json")).unwrap(),
            "old"
        );
        assert_eq!(
            std::fs::read_to_string(out.join("final.csv")).unwrap(),
            "old"
        );
        // A committed run replaces the previous outputs and keeps the user's files.
        let st = Staging::new(&out).unwrap();
        std::fs::write(st.dir().join("summary.json"), "new").unwrap();
        std::fs::create_dir(st.dir().join("vtk")).unwrap();
        std::fs::write(st.dir().join("vtk/frame_1.vtp"), "new").unwrap();
        st.commit().unwrap();
        assert_eq!(
            std::fs::read_to_string(out.join("summary.json")).unwrap(),
            "new"
        );
        assert!(
            !out.join("final.csv").exists(),
            "an old output not rewritten is gone"
        );
        assert!(!out.join("vtk/frame_0.vtp").exists());
        assert!(out.join("vtk/frame_1.vtp").exists() && out.join("vtk/mine.txt").exists());
        assert!(out.join("notes.txt").exists() && !out.join(STAGING_DIR).exists());
        std::fs::remove_dir_all(&out).unwrap();
    }
}
