//! `slither_gait._native`: the Python bindings of slither (PyO3), wrapped by the pure-Python
//! package `slither_gait` (`slither_gait/__init__.py`), which adds the result classes.
//!
//! Every entry point does what the matching `slither` subcommand does, through the same library
//! calls, so a problem gives the same `summary.json` to the bit: `run` mirrors `slither run`
//! (load, size limits, `--accuracy`, the run, the summary, post-processing, the same files on
//! `save`), `optimize`, `phase` and `topology` mirror theirs. Errors carry the CLI's messages
//! (without its `error: ` prefix): a bad problem file or key is a `ValueError`, a file that
//! cannot be written an `OSError`.
//!
//! # Threads and Ctrl-C
//!
//! The GIL is released while the library works, so Python threads run simulations in
//! parallel. The run loop calls a progress callback after every step; there the binding takes
//! the GIL back at most every [`CHECK_EVERY`] and asks Python whether a signal arrived
//! (`PyErr_CheckSignals`, which runs Python's SIGINT handler on the main thread). When the
//! handler raised (Ctrl-C: `KeyboardInterrupt`), the callback unwinds out of the library with a
//! private payload ([`Stop`]) that [`detached`] catches and turns back into the Python error.
//! Unwinding leaves nothing half-written: a run writes no file before `save`, and a study's
//! `history.csv` is appended one flushed row per finished evaluation. Studies check between
//! evaluations (`optimize`) or cells (`phase`).
mod convert;
mod run;
mod studies;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::panic::AssertUnwindSafe;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Longest time between two checks for Python signals (Ctrl-C) during a computation: a few
/// steps of the bundled S-start, and rare enough that taking the GIL back costs nothing.
pub const CHECK_EVERY: Duration = Duration::from_millis(20);

/// The unwinding payload that carries a Python exception out of the library.
struct Stop;

/// Checks for Python signals from inside a computation that released the GIL, and calls a
/// Python progress callable now and then.
pub struct Watch {
    last: Mutex<Instant>,
    err: Mutex<Option<PyErr>>,
}

impl Watch {
    fn new() -> Self {
        Watch {
            last: Mutex::new(Instant::now()),
            err: Mutex::new(None),
        }
    }

    /// Check for signals if [`CHECK_EVERY`] has passed since the last check; unwind with the
    /// Python error if a handler raised one.
    pub fn poll(&self) {
        {
            let mut last = self.last.lock().unwrap_or_else(|e| e.into_inner());
            if last.elapsed() < CHECK_EVERY {
                return;
            }
            *last = Instant::now();
        }
        self.now();
    }

    /// Check for signals now.
    pub fn now(&self) {
        if let Err(e) = Python::with_gil(|py| py.check_signals()) {
            self.fail(e);
        }
    }

    /// Check for signals if [`CHECK_EVERY`] has passed, keeping a raised error for
    /// [`Watch::raise_pending`] instead of unwinding (inside library code that catches panics).
    pub fn poll_deferred(&self) {
        {
            let mut last = self.last.lock().unwrap_or_else(|e| e.into_inner());
            if last.elapsed() < CHECK_EVERY {
                return;
            }
            *last = Instant::now();
        }
        if let Err(e) = Python::with_gil(|py| py.check_signals()) {
            *self.err.lock().unwrap_or_else(|e| e.into_inner()) = Some(e);
        }
    }

    /// Unwind with an error kept by [`Watch::poll_deferred`], if any.
    pub fn raise_pending(&self) {
        if self.err.lock().unwrap_or_else(|e| e.into_inner()).is_some() {
            std::panic::resume_unwind(Box::new(Stop))
        }
    }

    /// Stop the computation with `e` (raised in Python by [`detached`]).
    pub fn fail(&self, e: PyErr) -> ! {
        *self.err.lock().unwrap_or_else(|e| e.into_inner()) = Some(e);
        std::panic::resume_unwind(Box::new(Stop))
    }
}

/// Run `f` without the GIL; a [`Watch::fail`] inside it becomes the returned Python error.
/// Any other panic goes on (PyO3 raises it as `PanicException`).
pub fn detached<T: Send>(py: Python<'_>, f: impl FnOnce(&Watch) -> T + Send) -> PyResult<T> {
    let watch = Watch::new();
    let r = py.allow_threads(|| std::panic::catch_unwind(AssertUnwindSafe(|| f(&watch))));
    match r {
        Ok(v) => Ok(v),
        Err(payload) if payload.is::<Stop>() => Err(watch
            .err
            .into_inner()
            .unwrap_or_else(|e| e.into_inner())
            .unwrap_or_else(|| PyValueError::new_err("interrupted"))),
        Err(payload) => std::panic::resume_unwind(payload),
    }
}

/// Diagnostics of the library (`log` crate) on stderr, as the CLI: debug level when
/// `SLITHER_DEBUG` is set, else warnings only.
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

/// Read the environment once, as the CLI does: the logger and the solver overrides
/// (`SLITHER_CONTACT`, `SLITHER_CLARABEL_METHOD`), refused with the CLI's message when their
/// values are not allowed (`SLITHER_CONTACT=active-set` names the retired solver).
fn configure_from_env() -> PyResult<()> {
    use slither::problem;
    static LOGGER: StderrLog = StderrLog;
    if log::set_logger(&LOGGER).is_ok() {
        log::set_max_level(if std::env::var_os("SLITHER_DEBUG").is_some() {
            log::LevelFilter::Debug
        } else {
            log::LevelFilter::Warn
        });
    }
    let contact = std::env::var("SLITHER_CONTACT").ok();
    let method = std::env::var("SLITHER_CLARABEL_METHOD").ok();
    let overrides = problem::Overrides::from_env_values(contact.as_deref(), method.as_deref())
        .map_err(PyValueError::new_err)?;
    problem::set_overrides(overrides);
    Ok(())
}

/// The native part of `slither_gait`.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    configure_from_env()?;
    m.add_class::<convert::Problem>()?;
    m.add_class::<run::NativeRun>()?;
    m.add_function(wrap_pyfunction!(convert::load_problem, m)?)?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(studies::optimize, m)?)?;
    m.add_function(wrap_pyfunction!(studies::phase, m)?)?;
    m.add_function(wrap_pyfunction!(studies::topology, m)?)?;
    m.add("CHECK_EVERY_S", CHECK_EVERY.as_secs_f64())?;
    Ok(())
}
