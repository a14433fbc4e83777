//! The studies (`optimize`, `phase`) and `topology`, as their subcommands run them. The studies
//! write their usual files into `out`; the Python side reads those files back, so the objects
//! it returns hold exactly what the files hold.
use crate::{detached, Watch};
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use slither::studies::{self, optimize::OptimizeError, phase::PhaseError};
use slither::{output, problem, topology as topo};
use std::path::{Path, PathBuf};

/// A line on Python's `sys.stderr` (shown in notebooks too).
fn say(line: &str) {
    Python::with_gil(|py| {
        if let Ok(err) = py.import("sys").and_then(|s| s.getattr("stderr")) {
            let _ = err.call_method1("write", (format!("{line}\n"),));
            let _ = err.call_method0("flush");
        }
    })
}

/// A problem-file error as Python sees it: unreadable file `OSError`, else `ValueError`.
fn problem_error(e: problem::ProblemError) -> PyErr {
    match e {
        problem::ProblemError::Io { .. } => PyOSError::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// Create `out` and lock it for this process, with the CLI's messages.
fn lock_out(out: &Path) -> PyResult<output::lock::OutLock> {
    std::fs::create_dir_all(out).map_err(|e| {
        PyOSError::new_err(format!(
            "{}: cannot create output directory: {e}",
            out.display()
        ))
    })?;
    output::lock::OutLock::acquire(out).map_err(|e| match e {
        output::lock::LockError::Busy { .. } => PyRuntimeError::new_err(e.to_string()),
        output::lock::LockError::Io { .. } => PyOSError::new_err(e.to_string()),
    })
}

/// Progress of an optimisation: one line per evaluation, Ctrl-C between evaluations.
struct Observer<'a> {
    watch: &'a Watch,
    lines: bool,
    max: usize,
}

impl studies::optimize::EvaluationObserver for Observer<'_> {
    fn started(&mut self, _count: usize, _p: &studies::optimize::GaitParams, _cached: bool) {
        self.watch.raise_pending();
        self.watch.poll();
    }

    fn progress(&mut self, _fraction: f64) {
        // Inside the simulation, which catches panics: keep the interrupt for later.
        self.watch.poll_deferred();
    }

    fn finished(&mut self, count: usize, e: &studies::optimize::Evaluation, reused: bool) {
        if self.lines {
            let source = if reused {
                "reused from history.csv".to_string()
            } else {
                format!("{:.1} s", e.wall_time_s)
            };
            let result = match e.status {
                studies::optimize::Status::Ok => format!(
                    "v_s = {:.5} m/s, v_s/v_m = {:.4}, {:.1} deg, regime {}",
                    e.v_s, e.v_s_over_v_m, e.displacement_angle_deg, e.regime
                ),
                studies::optimize::Status::Failed => format!("FAILED: {}", e.reason),
            };
            say(&format!(
                "eval {count}/{} (row {}): stress {} Pa, sigma {}, speed {} m/s -> {result} [{source}]",
                self.max, e.eval, e.point.stress, e.point.sigma, e.point.speed
            ));
        }
        self.watch.raise_pending();
    }
}

/// Run the gait study `study` (a study file) into `out`, as `slither optimize`; returns the
/// run's counts (the results are the files in `out`).
#[pyfunction]
#[pyo3(signature = (study, out, progress = true))]
pub fn optimize(
    py: Python<'_>,
    study: PathBuf,
    out: PathBuf,
    progress: bool,
) -> PyResult<Py<PyDict>> {
    let mut s =
        studies::optimize::load_study(&study).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let _lock = lock_out(&out)?;
    let r = detached(py, |watch| {
        let mut log = |line: &str| {
            watch.now();
            if progress {
                say(line)
            }
        };
        studies::optimize::prepare_accuracy(&mut s, &out, &mut log).map_err(|e| {
            PyOSError::new_err(format!(
                "{}: {e}",
                out.join(studies::accuracy::ACCURACY_FILE).display()
            ))
        })?;
        let mut obs = Observer {
            watch,
            lines: progress,
            max: s.max_evaluations,
        };
        studies::optimize::optimize(&s, &out, &mut obs).map_err(|e| match e {
            OptimizeError::History { .. } => PyValueError::new_err(e.to_string()),
            OptimizeError::Io { .. } | OptimizeError::Plot { .. } => {
                PyOSError::new_err(e.to_string())
            }
            OptimizeError::Solver(_) => PyRuntimeError::new_err(e.to_string()),
        })
    })??;
    let d = PyDict::new(py);
    d.set_item("evaluations", r.evaluations)?;
    d.set_item("simulations", r.simulations)?;
    d.set_item("reused", r.reused)?;
    d.set_item("repeats", r.repeats)?;
    d.set_item("failed", r.failed)?;
    d.set_item("termination", r.termination)?;
    d.set_item("wall_time_s", r.wall_time_s)?;
    Ok(d.unbind())
}

/// Run the phase diagram `file` (a phase file) into `out`, as `slither phase` (`shard` "I/N" as
/// `--shard`); returns the run's counts (the results are the files in `out`).
#[pyfunction]
#[pyo3(signature = (file, out, shard = None, progress = true))]
pub fn phase(
    py: Python<'_>,
    file: PathBuf,
    out: PathBuf,
    shard: Option<&str>,
    progress: bool,
) -> PyResult<Py<PyDict>> {
    let shard: Option<studies::phase::Shard> = shard
        .map(|s| {
            s.parse()
                .map_err(|e: String| PyValueError::new_err(format!("shard {e}")))
        })
        .transpose()?;
    let mut ph = studies::phase::load(&file).map_err(problem_error)?;
    let _lock = lock_out(&out)?;
    let t0 = std::time::Instant::now();
    let sw = detached(py, |watch| {
        let mut log = |line: &str| {
            watch.now();
            if progress {
                say(line)
            }
        };
        studies::phase::prepare_accuracy(&mut ph, &out, &mut log).map_err(|e| {
            PyOSError::new_err(format!(
                "{}: {e}",
                out.join(studies::accuracy::ACCURACY_FILE).display()
            ))
        })?;
        let report = |done: usize, todo: usize, c: &studies::phase::Cell| {
            if progress {
                say(&format!(
                    "cell {done}/{todo}: W = {} G = {}: {}",
                    c.weight,
                    c.torque,
                    if c.status == studies::optimize::Status::Ok {
                        format!(
                            "regime {}, v_s/v_m = {:.4}",
                            c.regime.map_or("-", |r| r.as_str()),
                            c.v_s_over_v_m
                        )
                    } else {
                        format!("failed: {}", c.reason)
                    }
                ));
            }
        };
        let refine_report = |done: usize, c: &studies::phase::Cell| {
            if progress {
                say(&format!(
                    "refine {done}: W = {} G = {}: {}",
                    c.weight,
                    c.torque,
                    c.regime.map_or("-", |r| r.as_str())
                ));
            }
        };
        let growth_report = |done: usize, c: &studies::phase::Cell| {
            if progress {
                say(&format!(
                    "growth {done}: W = {} G = {}: {}",
                    c.weight,
                    c.torque,
                    c.regime.map_or("-", |r| r.as_str())
                ));
            }
        };
        studies::phase::sweep_shard(&ph, &out, shard, &report, &refine_report, &growth_report)
            .map_err(|e| match e {
                PhaseError::Csv { .. } | PhaseError::Header { .. } => {
                    PyValueError::new_err(e.to_string())
                }
                _ => PyOSError::new_err(e.to_string()),
            })
    })??;
    let failed = sw
        .cells
        .iter()
        .filter(|c| c.status != studies::optimize::Status::Ok)
        .count();
    let d = PyDict::new(py);
    d.set_item("cells", sw.cells.len())?;
    d.set_item("simulated", sw.simulated)?;
    d.set_item("reused", sw.reused)?;
    d.set_item("failed", failed)?;
    d.set_item("wall_time_s", t0.elapsed().as_secs_f64())?;
    Ok(d.unbind())
}

/// Twist, writhe and link (turns) of a framed curve, as `slither topology`: `curve` is a CSV
/// file (x,y,z,d1x,d1y,d1z with a header row) or a pair `(x, d1)` of (N, 3) arrays of node
/// positions and edge directors, checked as the file would be.
#[pyfunction]
#[pyo3(signature = (curve, closed = false))]
pub fn topology(py: Python<'_>, curve: &Bound<'_, PyAny>, closed: bool) -> PyResult<Py<PyDict>> {
    let (text, name) = if let Ok(path) = curve.extract::<PathBuf>() {
        (
            crate::convert::read_text(&path)?,
            path.display().to_string(),
        )
    } else {
        let (x, d1): (Vec<Vec<f64>>, Vec<Vec<f64>>) = curve.extract().map_err(|_| {
            PyValueError::new_err("curve: a CSV file or a pair (x, d1) of (N, 3) arrays")
        })?;
        if x.len() != d1.len() || x.iter().chain(&d1).any(|r| r.len() != 3) {
            return Err(PyValueError::new_err(
                "curve: x and d1 must both have shape (N, 3)",
            ));
        }
        let mut text = String::from("x,y,z,d1x,d1y,d1z\n");
        for (p, d) in x.iter().zip(&d1) {
            text += &format!(
                "{:.17e},{:.17e},{:.17e},{:.17e},{:.17e},{:.17e}\n",
                p[0], p[1], p[2], d[0], d[1], d[2]
            );
        }
        (text, "<arrays>".to_string())
    };
    let c = topo::parse_curve_csv(&text, closed)
        .map_err(|e| PyValueError::new_err(format!("{name}:{}: {}", e.line, e.message)))?;
    let (t, gauss) = py.allow_threads(|| {
        let t = topo::topology(&c);
        let gauss = closed.then(|| {
            let len: f64 = (0..c.nodes.len())
                .map(|i| {
                    let a = c.nodes[i];
                    let b = c.nodes[(i + 1) % c.nodes.len()];
                    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
                })
                .fold(f64::INFINITY, f64::min);
            topo::gauss_link(&c, 1e-3 * len)
        });
        (t, gauss)
    });
    let d = PyDict::new(py);
    d.set_item("tw", t.tw)?;
    d.set_item("wr", t.wr)?;
    d.set_item("lk", t.lk)?;
    if let Some(g) = gauss {
        d.set_item("lk_gauss", g)?;
    }
    Ok(d.unbind())
}
