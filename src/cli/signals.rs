//! SIGINT (Ctrl-C), SIGTERM (what Slurm sends at a job's time limit, 30 s before SIGKILL) and
//! SIGHUP (a closed terminal) end every writing subcommand the same way.
//!
//! - `run` ([`stop_runs`]): the signal stops the simulation after its current step
//!   ([`slither::sim::INTERRUPT`]); the run writes its data with `"status": "interrupted"` (a
//!   rerun keeps the previous results instead), skips the figures after SIGTERM and SIGHUP so
//!   the data is on disk within seconds, releases its lock and removes its staging folder.
//! - `optimize`, `phase` (growth included) and `merge` ([`end_studies`]): every finished cell
//!   or evaluation is already on disk (a row is written as each one ends), so a watcher thread
//!   removes the temporary folders and files and the locks of this process at once and ends it;
//!   a rerun of the same command resumes (`slither status DIR` shows what is missing).
//!
//! The exit code is 128 + the signal's number, as a shell reports a process ended by it: 130
//! (SIGINT), 143 (SIGTERM), 129 (SIGHUP). A second signal ends the process at once (the
//! default action). Should a run's post-processing still be busy [`GRACE`] after SIGTERM or
//! SIGHUP, the watcher removes its temporary folder and lock and ends it, so the next job finds
//! the directory free (the previous results of a rerun stay).
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};
use std::sync::Mutex;
use std::time::Duration;

/// The first signal received (0: none).
static SIGNAL: AtomicI32 = AtomicI32::new(0);
/// Whether the signal stops the simulations ([`stop_runs`]) rather than ending the process.
static STOP_SIMULATIONS: AtomicBool = AtomicBool::new(false);
/// Output directories this process locked ([`register`]).
static LOCKED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// How long a run may take after SIGTERM or SIGHUP before the watcher ends it.
pub const GRACE: Duration = Duration::from_secs(20);

#[cfg(unix)]
const HANDLED: [i32; 3] = [libc::SIGINT, libc::SIGTERM, libc::SIGHUP];

/// The signal received, if any.
pub fn received() -> Option<i32> {
    match SIGNAL.load(Ordering::Relaxed) {
        0 => None,
        s => Some(s),
    }
}

/// Whether the signal received asks the process to hurry (SIGTERM or SIGHUP: a scheduler or a
/// closed terminal, not a user at the keyboard).
pub fn hurry() -> bool {
    #[cfg(unix)]
    {
        matches!(received(), Some(s) if s == libc::SIGTERM || s == libc::SIGHUP)
    }
    #[cfg(not(unix))]
    false
}

/// The signal's name, for messages.
pub fn name() -> &'static str {
    #[cfg(unix)]
    {
        match received() {
            Some(libc::SIGTERM) => "SIGTERM",
            Some(libc::SIGHUP) => "SIGHUP",
            _ => "SIGINT",
        }
    }
    #[cfg(not(unix))]
    "SIGINT"
}

/// The exit code after the signal: 128 + its number (130 without one).
pub fn exit_code() -> ExitCode {
    ExitCode::from(128 + received().unwrap_or(2) as u8)
}

/// Remember that this process locked `dir` (the watcher releases it).
pub fn register(dir: &std::path::Path) {
    if let Ok(mut l) = LOCKED.lock() {
        l.push(dir.to_path_buf());
    }
}

/// `slither run`: the signals stop the simulations after their current step.
pub fn stop_runs() {
    STOP_SIMULATIONS.store(true, Ordering::Relaxed);
    install();
}

/// `optimize`, `phase`, `merge`: the signals end the process after releasing what it holds.
pub fn end_studies() {
    install();
}

fn install() {
    #[cfg(unix)]
    {
        extern "C" fn handler(sig: libc::c_int) {
            let _ = SIGNAL.compare_exchange(0, sig, Ordering::Relaxed, Ordering::Relaxed);
            if STOP_SIMULATIONS.load(Ordering::Relaxed) {
                slither::sim::INTERRUPT.store(true, Ordering::Relaxed);
            }
            // Async-signal-safe: a second signal gets the default action.
            for s in HANDLED {
                unsafe {
                    libc::signal(s, libc::SIG_DFL);
                }
            }
        }
        // SAFETY: the handler only touches atomics and resets dispositions, all
        // async-signal-safe.
        for s in HANDLED {
            unsafe {
                libc::signal(s, handler as *const () as libc::sighandler_t);
            }
        }
        std::thread::spawn(watch);
    }
}

/// The watcher: polls for a signal; ends a study at once, a run after [`GRACE`] (SIGTERM,
/// SIGHUP) if it has not ended by itself.
fn watch() {
    loop {
        std::thread::sleep(Duration::from_millis(50));
        if received().is_none() {
            continue;
        }
        if STOP_SIMULATIONS.load(Ordering::Relaxed) {
            if !hurry() {
                return; // Ctrl-C: the run ends by itself; a second Ctrl-C kills it.
            }
            std::thread::sleep(GRACE);
            eprintln!(
                "{}: the run did not end within {} s; its temporary files and lock are removed and it ends without writing",
                name(),
                GRACE.as_secs()
            );
        }
        release();
        if !STOP_SIMULATIONS.load(Ordering::Relaxed) {
            let dirs = LOCKED.lock().map(|l| l.clone()).unwrap_or_default();
            eprintln!(
                "interrupted ({}): every finished cell and evaluation is kept in {}; rerun the same command to resume (`slither status DIR` shows what is missing)",
                name(),
                dirs.first().map_or("--out".into(), |d| d.display().to_string())
            );
        }
        std::process::exit(128 + received().unwrap_or(2));
    }
}

/// Remove the staging folders, temporary files and locks of this process in every directory
/// it locked.
fn release() {
    let dirs = LOCKED.lock().map(|l| l.clone()).unwrap_or_default();
    let me = slither::output::lock::LockInfo::mine();
    for dir in dirs {
        slither::output::staging::abandon(&dir);
        let lock = dir.join(slither::output::lock::LOCK_FILE);
        if slither::output::lock::LockInfo::read(&lock).as_ref() == Some(&me) {
            let _ = std::fs::remove_file(lock);
        }
    }
}
