//! One run per output directory: a lock file `DIR/.slither.lock` holding the owner's process
//! id and host name, one a line ([`LockInfo`]).
//!
//! [`OutLock::acquire`] creates the lock atomically (written under a private name, then
//! hard-linked to `.slither.lock`, which fails if it exists), so of two runs started together
//! exactly one gets the directory; the other gets [`LockError::Busy`] naming the owner. A lock
//! left by a process of this host that no longer exists (a killed run; checked through
//! `/proc/PID`) is taken over. A lock of another host (a shared file system) is never taken
//! over: whether its process lives cannot be seen from here ([`Liveness::Unknown`]). Creating the lock also proves the directory is writable before any simulation
//! starts. The lock is removed when the [`OutLock`] is dropped.

use std::io::Write;
use std::path::{Path, PathBuf};

/// Name of the lock file inside the output directory.
pub const LOCK_FILE: &str = ".slither.lock";

/// Why the output directory could not be locked.
#[derive(Debug, thiserror::Error)]
pub enum LockError {
    /// Another live process holds the directory.
    #[error("{dir}: another slither run (process {pid} on host {host}) is writing into this output directory; wait for it to finish, or choose another --out (if that process is not slither or has ended, delete {lock})")]
    Busy {
        /// The output directory.
        dir: PathBuf,
        /// The owner's process id.
        pid: u32,
        /// The owner's host ("unknown" for a lock written without one).
        host: String,
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

/// Whether process `pid` of this host is alive. Without `/proc` (not Linux) every owner
/// counts as alive, so a stale lock must then be deleted by hand (the message names it).
fn alive(pid: u32) -> bool {
    let proc_ = Path::new("/proc");
    !proc_.join("self").exists() || proc_.join(pid.to_string()).exists()
}

/// This machine's host name ("unknown" if it cannot be read).
pub fn host_name() -> String {
    #[cfg(unix)]
    {
        let mut buf = [0u8; 256];
        // SAFETY: the buffer is valid for its length; the name is NUL-terminated within it.
        let rc = unsafe { libc::gethostname(buf.as_mut_ptr().cast(), buf.len() - 1) };
        if rc == 0 {
            let end = buf.iter().position(|&b| b == 0).unwrap_or(buf.len());
            if let Ok(h) = std::str::from_utf8(&buf[..end]) {
                if !h.is_empty() {
                    return h.to_string();
                }
            }
        }
    }
    "unknown".into()
}

/// Whether a lock's process lives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Liveness {
    /// A process of this host with that id exists.
    Alive,
    /// No process of this host has that id: the lock is stale.
    Dead,
    /// The lock is another host's: its process cannot be seen from here.
    Unknown,
}

impl std::fmt::Display for Liveness {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Liveness::Alive => "alive",
            Liveness::Dead => "dead (stale lock; the next run takes it over)",
            Liveness::Unknown => "unknown (another host)",
        })
    }
}

/// What a lock file says: its owner's process id and host.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LockInfo {
    /// The owner's process id.
    pub pid: u32,
    /// The owner's host (`None`: a lock written without one, taken as this host's).
    pub host: Option<String>,
}

impl LockInfo {
    /// This process's lock.
    pub fn mine() -> Self {
        LockInfo {
            pid: std::process::id(),
            host: Some(host_name()),
        }
    }

    /// The lock file's text: the process id, then the host, one a line.
    pub fn text(&self) -> String {
        format!(
            "{}\n{}\n",
            self.pid,
            self.host.as_deref().unwrap_or("unknown")
        )
    }

    /// Parse a lock file's text (`None`: not a lock of slither's).
    pub fn parse(text: &str) -> Option<Self> {
        let mut lines = text.lines();
        let pid = lines.next()?.trim().parse().ok()?;
        let host = lines
            .next()
            .map(|h| h.trim().to_string())
            .filter(|h| !h.is_empty());
        Some(LockInfo { pid, host })
    }

    /// Read the lock file at `path`.
    pub fn read(path: &Path) -> Option<Self> {
        Self::parse(&std::fs::read_to_string(path).ok()?)
    }

    /// Whether the owner lives, as far as this host can tell.
    pub fn liveness(&self) -> Liveness {
        match &self.host {
            Some(h) if *h != host_name() => Liveness::Unknown,
            _ if alive(self.pid) => Liveness::Alive,
            _ => Liveness::Dead,
        }
    }
}

impl OutLock {
    /// Lock `dir` (which must exist) for this process.
    pub fn acquire(dir: &Path) -> Result<OutLock, LockError> {
        let path = dir.join(LOCK_FILE);
        let info = LockInfo::mine();
        let me = info.pid;
        let io = |source| LockError::Io {
            dir: dir.into(),
            source,
        };
        let mine = dir.join(format!("{LOCK_FILE}.{me}"));
        std::fs::File::create(&mine)
            .and_then(|mut f| {
                f.write_all(info.text().as_bytes())?;
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
                        let owner = LockInfo::read(&path);
                        match owner {
                            Some(o)
                                if !(o.pid == me && o.host == info.host)
                                    && o.liveness() != Liveness::Dead =>
                            {
                                return Err(LockError::Busy {
                                    dir: dir.into(),
                                    pid: o.pid,
                                    host: o.host.unwrap_or_else(|| "unknown".into()),
                                    lock: path.clone(),
                                })
                            }
                            // Stale (dead owner of this host, unreadable or our own
                            // leftover): take over.
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lock_of_another_host_is_never_taken_over() {
        let dir = std::env::temp_dir().join(format!("slither_lock_host_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let lock = dir.join(LOCK_FILE);
        // A dead process id of this host: taken over; the new lock names this host.
        let dead = LockInfo {
            pid: u32::MAX - 1,
            host: Some(host_name()),
        };
        assert_eq!(dead.liveness(), Liveness::Dead);
        std::fs::write(&lock, dead.text()).unwrap();
        let held = OutLock::acquire(&dir).unwrap();
        assert_eq!(LockInfo::read(&lock), Some(LockInfo::mine()));
        drop(held);
        assert!(!lock.exists());
        // The same dead id on another host: liveness unknown, refused, the lock kept.
        let other = LockInfo {
            pid: u32::MAX - 1,
            host: Some(format!("{}-elsewhere", host_name())),
        };
        assert_eq!(other.liveness(), Liveness::Unknown);
        std::fs::write(&lock, other.text()).unwrap();
        match OutLock::acquire(&dir) {
            Err(LockError::Busy { host, .. }) => assert!(host.ends_with("-elsewhere")),
            r => panic!("another host's lock taken: {r:?}"),
        }
        assert_eq!(LockInfo::read(&lock), Some(other));
        // A lock written without a host (older slither) counts as this host's.
        assert_eq!(LockInfo::parse("12\n").unwrap().host, None);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
