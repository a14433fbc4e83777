//! The subcommands of the `slither` binary, one module each, and what they share: the
//! logger and the environment overrides, the output-directory lock, the accuracy messages.
//! This is the only code that reads the environment and prints; the library returns values and
//! reports progress through callbacks.
pub mod chart;
pub mod guard;
pub mod keys;
pub mod merge;
pub mod movie;
pub mod optimize;
pub mod phase;
pub mod run;
pub mod signals;
pub mod status;
pub mod topology;

use slither::{output, problem, studies};
use std::path::Path;
use std::process::ExitCode;

/// Diagnostics of the library (`log` crate) on stderr, at debug level when `SLITHER_DEBUG` is
/// set (every Newton iteration), at trace level when it is `trace`, else warnings only.
struct StderrLog;

impl log::Log for StderrLog {
    fn enabled(&self, meta: &log::Metadata) -> bool {
        meta.level() <= log::max_level()
    }
    fn log(&self, record: &log::Record) {
        if self.enabled(record.metadata()) {
            eprintln!("{}", record.args());
        }
    }
    fn flush(&self) {}
}

/// Read the environment once: the logger and the solver overrides. An override with a value
/// this build does not know (`SLITHER_CONTACT=bogus`, `SLITHER_CLARABEL_METHOD=xyz`, or
/// `faer` without the cargo feature) is refused: `Err` is exit code 2 after the message.
pub fn configure_from_env() -> Result<(), ExitCode> {
    static LOGGER: StderrLog = StderrLog;
    if log::set_logger(&LOGGER).is_ok() {
        log::set_max_level(match std::env::var("SLITHER_DEBUG").as_deref() {
            Ok("trace") => log::LevelFilter::Trace,
            Ok(_) => log::LevelFilter::Debug,
            Err(_) => log::LevelFilter::Warn,
        });
    }
    let var = |name: &str| std::env::var(name).ok();
    let contact = var("SLITHER_CONTACT");
    let method = var("SLITHER_CLARABEL_METHOD");
    match problem::Overrides::from_env_values(contact.as_deref(), method.as_deref()) {
        Ok(o) => {
            problem::set_overrides(o);
            Ok(())
        }
        Err(message) => {
            eprintln!("error: {message}");
            Err(ExitCode::from(2))
        }
    }
}

#[cfg(unix)]
const ELOOP: i32 = libc::ELOOP;
#[cfg(not(unix))]
const ELOOP: i32 = -1;

/// Why `out` cannot be an output directory although creating it failed or would fail: a
/// file, a dangling symbolic link or a symbolic link loop (`None`: something else).
fn not_a_directory(out: &Path) -> Option<&'static str> {
    let link = std::fs::symlink_metadata(out).ok()?;
    if link.file_type().is_symlink() {
        return match std::fs::metadata(out) {
            Ok(m) if m.is_dir() => None,
            Ok(_) => Some("is a symbolic link to a file, not a directory"),
            Err(e) if e.raw_os_error() == Some(ELOOP) => Some("is a symbolic link loop (ELOOP)"),
            Err(_) => Some("is a dangling symbolic link (its target does not exist)"),
        };
    }
    (!link.is_dir()).then_some("is a file, not a directory")
}

/// Create `out` and lock it for this process: exit 2 if another live run holds it, 1 if it
/// cannot be created or written (found before any simulation).
pub fn lock_out(out: &Path) -> Result<output::lock::OutLock, ExitCode> {
    if let Some(why) = not_a_directory(out) {
        eprintln!(
            "error: --out {}: {why}; choose a directory (it is created if absent)",
            out.display()
        );
        return Err(ExitCode::from(1));
    }
    if let Err(e) = std::fs::create_dir_all(out) {
        eprintln!(
            "error: {}: cannot create output directory: {e}",
            out.display()
        );
        return Err(ExitCode::from(1));
    }
    let lock = output::lock::OutLock::acquire(out).map_err(|e| {
        eprintln!("error: {e}");
        ExitCode::from(match e {
            output::lock::LockError::Busy { .. } => 2,
            output::lock::LockError::Io { .. } => 1,
        })
    })?;
    signals::register(out);
    Ok(lock)
}

/// A study's `[accuracy]` after [`studies::optimize::prepare_accuracy`] or [`studies::phase::prepare_accuracy`]
/// (`prepared`: whether a recorded choice was reused): prints the choice. `Err` is the exit
/// code (1: `accuracy.json` could not be written).
pub fn study_accuracy(
    out: &Path,
    quiet: bool,
    prepared: std::io::Result<bool>,
    chosen: Option<&studies::accuracy::StudyAccuracy>,
) -> Result<(), ExitCode> {
    match prepared {
        Ok(reused) => {
            if let (Some(c), false) = (chosen, quiet) {
                eprintln!(
                    "accuracy {}: {} {} elements, {} for every run{}",
                    c.target,
                    if reused {
                        "reusing the recorded choice of"
                    } else {
                        "chose"
                    },
                    c.elements,
                    model_label(c.dt, c.error_tolerance),
                    match c.selection["estimated_error"].as_f64() {
                        Some(e) => format!(" (estimated error {e:.2e})"),
                        None => String::new(),
                    }
                );
            }
            Ok(())
        }
        Err(e) => {
            eprintln!(
                "error: {}: {e}",
                out.join(studies::accuracy::ACCURACY_FILE).display()
            );
            Err(ExitCode::from(1))
        }
    }
}

/// One line per run of an accuracy selection (nothing with `--quiet`).
pub fn selection_log(quiet: bool) -> impl FnMut(&str) {
    move |line: &str| {
        if !quiet {
            eprintln!("{line}")
        }
    }
}

/// The time resolution of an accuracy choice, for messages.
pub fn model_label(dt: Option<f64>, tolerance: Option<f64>) -> String {
    slither::studies::accuracy::selection::Resolution::from_parts(dt, tolerance)
        .map_or("no time resolution".into(), |r| r.to_string())
}
