//! The subcommands of the `slither` binary, one module each, and what they share: the
//! logger and the environment overrides, the output-directory lock, the accuracy messages.
//! This is the only code that reads the environment and prints; the library returns values and
//! reports progress through callbacks.
pub mod chart;
pub mod keys;
pub mod merge;
pub mod movie;
pub mod optimize;
pub mod phase;
pub mod run;
pub mod topology;

use slither::{design, output, problem};
use std::path::Path;
use std::process::ExitCode;

/// Diagnostics of the library (`log` crate) on stderr, at debug level when `SLITHER_DEBUG` is
/// set (every Newton iteration), else warnings only.
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

/// Read the environment once: the logger and the solver overrides.
pub fn configure_from_env() {
    static LOGGER: StderrLog = StderrLog;
    if log::set_logger(&LOGGER).is_ok() {
        log::set_max_level(if std::env::var_os("SLITHER_DEBUG").is_some() {
            log::LevelFilter::Debug
        } else {
            log::LevelFilter::Warn
        });
    }
    problem::set_overrides(problem::Overrides {
        contact: std::env::var("SLITHER_CONTACT")
            .ok()
            .map(|v| match v.as_str() {
                "conic" => problem::ContactKind::Conic,
                _ => problem::ContactKind::ActiveSet,
            }),
        clarabel_method: std::env::var("SLITHER_CLARABEL_METHOD").ok(),
    });
}

/// Create `out` and lock it for this process: exit 2 if another live run holds it, 1 if it
/// cannot be created or written (found before any simulation).
pub fn lock_out(out: &Path) -> Result<output::lock::OutLock, ExitCode> {
    if let Err(e) = std::fs::create_dir_all(out) {
        eprintln!(
            "error: {}: cannot create output directory: {e}",
            out.display()
        );
        return Err(ExitCode::from(1));
    }
    output::lock::OutLock::acquire(out).map_err(|e| {
        eprintln!("error: {e}");
        ExitCode::from(match e {
            output::lock::LockError::Busy { .. } => 2,
            output::lock::LockError::Io { .. } => 1,
        })
    })
}

/// A study's `[accuracy]` after [`design::accuracy::prepare_study`] or `prepare_phase`
/// (`prepared`: whether a recorded choice was reused): prints the choice. `Err` is the exit
/// code (1: `accuracy.json` could not be written).
pub fn study_accuracy(
    out: &Path,
    quiet: bool,
    prepared: std::io::Result<bool>,
    chosen: Option<&design::accuracy::StudyAccuracy>,
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
                out.join(design::accuracy::ACCURACY_FILE).display()
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
    slither::chart::accuracy::Resolution::from_parts(dt, tolerance)
        .map_or("no time resolution".into(), |r| r.to_string())
}
