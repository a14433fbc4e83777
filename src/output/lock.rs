//! One run per output directory: a lock file `DIR/.slither.lock` holding the owner's process
//! id.
//!
//! [`OutLock::acquire`] creates the lock atomically (written under a private name, then
//! hard-linked to `.slither.lock`, which fails if it exists), so of two runs started together
//! exactly one gets the directory; the other gets [`LockError::Busy`] naming the owner. A lock
//! left by a process that no longer exists (a killed run; checked through `/proc/PID`) is taken
//! over. Creating the lock also proves the directory is writable before any simulation
//! starts. The lock is removed when the [`OutLock`] is dropped.

use std::io::Write;
use std::path::{Path, PathBuf};

/// Name of the lock file inside the output directory.
pub const LOCK_FILE: &str = ".slither.lock";

/// Why the output directory could not be locked.
#[derive(Debug, thiserror::Error)]
pub enum LockError {
    /// Another live process holds the directory.
    #[error("{dir}: another slither run (process {pid}) is writing into this output directory; wait for it to finish, or choose another --out (if that process is not slither, delete {lock})")]
    Busy {
        /// The output directory.
        dir: PathBuf,
        /// The owner's process id.
        pid: u32,
        /// The lock file.
        lock: PathBuf,
    },
    /// The directory cannot be written (checked before simulating).
    #[error("{dir}: cannot write into the output directory (checked before simulating): {source}")]
    Io {
        /// The output directory.
        dir: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
}

/// A held output directory; dropping it removes the lock file.
#[derive(Debug)]
pub struct OutLock {
    path: PathBuf,
}

/// Whether process `pid` is alive. Without `/proc` (not Linux) every owner counts as alive, so
/// a stale lock must then be deleted by hand (the message names it).
fn alive(pid: u32) -> bool {
    let proc_ = Path::new("/proc");
    !proc_.join("self").exists() || proc_.join(pid.to_string()).exists()
}

impl OutLock {
    /// Lock `dir` (which must exist) for this process.
    pub fn acquire(dir: &Path) -> Result<OutLock, LockError> {
        let path = dir.join(LOCK_FILE);
        let me = std::process::id();
        let io = |source| LockError::Io {
            dir: dir.into(),
            source,
        };
        let mine = dir.join(format!("{LOCK_FILE}.{me}"));
        std::fs::File::create(&mine)
            .and_then(|mut f| {
                f.write_all(format!("{me}\n").as_bytes())?;
                f.sync_all()
            })
            .map_err(|e| {
                let _ = std::fs::remove_file(&mine);
                io(e)
            })?;
        let result = (|| {
            for _ in 0..2 {
                match std::fs::hard_link(&mine, &path) {
                    Ok(()) => return Ok(OutLock { path: path.clone() }),
                    Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                        let owner = std::fs::read_to_string(&path)
                            .ok()
                            .and_then(|t| t.trim().parse::<u32>().ok());
                        match owner {
                            Some(pid) if pid != me && alive(pid) => {
                                return Err(LockError::Busy {
                                    dir: dir.into(),
                                    pid,
                                    lock: path.clone(),
                                })
                            }
                            // Stale (dead owner, unreadable or our own leftover): take over.
                            _ => {
                                let _ = std::fs::remove_file(&path);
                            }
                        }
                    }
                    Err(e) => return Err(io(e)),
                }
            }
            Err(io(std::io::Error::other(
                "the lock file could not be taken over (another run took it first?)",
            )))
        })();
        let _ = std::fs::remove_file(&mine);
        result
    }
}

impl Drop for OutLock {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}
