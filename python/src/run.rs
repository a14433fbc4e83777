//! `run`: one simulation, as `slither run` does it, kept in memory until `save`.
use crate::convert::Problem;
use crate::{detached, Watch};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use slither::{output, pipeline, problem, sim};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// A finished (or failed) run of the run pipeline: the model, the outcome, the
/// post-processed fields and the summary, everything `slither run` writes.
#[pyclass(frozen, module = "slither_gait")]
pub struct NativeRun {
    run: pipeline::Run,
}

/// A progress line on Python's `sys.stderr` at most every half second after the first second,
/// or calls of a Python callable: at the first step, then at most every [`CALL_EVERY`], and at
/// the last step (so its first and last calls bracket the simulation).
struct Progress {
    show: Option<PyObject>,
    start: Instant,
    last: Option<Instant>,
    label: &'static str,
    callable: bool,
}

/// Shortest time between two calls of a progress callable.
const CALL_EVERY: Duration = Duration::from_millis(200);

impl Progress {
    fn new(show: Option<PyObject>, label: &'static str) -> Self {
        let callable = show
            .as_ref()
            .is_some_and(|s| Python::with_gil(|py| s.bind(py).is_callable()));
        Progress {
            show,
            callable,
            start: Instant::now(),
            last: None,
            label,
        }
    }

    fn update(&mut self, watch: &Watch, frac: f64) {
        watch.poll();
        let Some(show) = &self.show else { return };
        let due = match (self.last, self.callable) {
            (None, true) => true,
            (Some(t), true) => t.elapsed() >= CALL_EVERY || frac >= 1.0,
            (None, false) => self.start.elapsed() > Duration::from_secs(1),
            // The line ends with the last step once it has been shown.
            (Some(t), false) => t.elapsed() > Duration::from_millis(500) || frac >= 1.0,
        };
        if !due {
            return;
        }
        self.last = Some(Instant::now());
        let r = Python::with_gil(|py| -> PyResult<()> {
            let show = show.bind(py);
            if self.callable {
                show.call1((frac,))?;
            } else {
                let end = if frac >= 1.0 { "\n" } else { "" };
                let line = format!(
                    "\r{:7.1} s {:5.1}% {}{end}",
                    self.start.elapsed().as_secs_f64(),
                    100.0 * frac,
                    self.label
                );
                let err = py.import("sys")?.getattr("stderr")?;
                err.call_method1("write", (line,))?;
                err.call_method0("flush")?;
            }
            Ok(())
        });
        if let Err(e) = r {
            watch.fail(e);
        }
    }
}

/// Simulate `problem` as `slither run` does, through the same pipeline; see
/// `slither_gait.run`.
#[pyfunction]
#[pyo3(signature = (problem, accuracy = None, progress = None, force = false))]
pub fn run(
    py: Python<'_>,
    problem: &Problem,
    accuracy: Option<f64>,
    progress: Option<PyObject>,
    force: bool,
) -> PyResult<NativeRun> {
    let path = problem.path.clone();
    if !force {
        problem::check_for_run(&problem.parsed, &problem.text, &path)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
    }
    let mut req = pipeline::Request::new(problem.parsed.clone(), &path);
    req.accuracy = accuracy;
    req.validate("accuracy")
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let quiet = progress.is_none();
    detached(py, move |watch| {
        let bar = std::cell::RefCell::new(Progress::new(progress, "simulated"));
        // The post-processing shows a line but does not call a callable (its fractions would
        // start again from 0).
        let mut post: Option<Progress> = None;
        let mut post_update = |f: f64| {
            let p = post.get_or_insert_with(|| {
                let mut b = bar.borrow_mut();
                let line = b.show.take().filter(|_| !b.callable);
                Progress::new(line, "post-processing (topology of every frame)")
            });
            p.update(watch, f)
        };
        let mut log = |line: &str| {
            watch.now();
            if !quiet {
                eprintln!("{line}")
            }
        };
        let hooks = pipeline::Hooks {
            progress: &mut |f| bar.borrow_mut().update(watch, f),
            post: &mut post_update,
            log: &mut log,
        };
        let run = pipeline::simulate(&req, None, hooks)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(NativeRun { run })
    })?
}

/// `data` as a numpy array of `shape`.
fn array<'py>(py: Python<'py>, data: Vec<f64>, shape: &[usize]) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_vec(py, data).reshape(shape)?.into_any())
}

#[pymethods]
impl NativeRun {
    /// The text of `summary.json`.
    fn summary_json(&self) -> String {
        output::summary_json(&self.run.summary)
    }

    /// The failure that stopped the run, if any (as `slither run` reports it).
    fn error(&self) -> Option<String> {
        let r = &self.run;
        r.outcome.error.as_ref().map(|e| {
            format!(
                "{}: {e}; results up to t = {} s",
                r.summary.problem, r.outcome.state.t
            )
        })
    }

    /// The arrays of `trajectory.npz`, by name (`lambda` included), as numpy arrays.
    fn arrays<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let (m, fr, fl) = (&self.run.model, &self.run.outcome.frames, &self.run.fields);
        let (nf, nn) = (fr.len(), m.real.len());
        let d = PyDict::new(py);
        let flat = |f: &dyn Fn(&sim::Frame) -> Vec<f64>| fr.iter().flat_map(f).collect::<Vec<_>>();
        d.set_item("t", array(py, flat(&|f| vec![f.t]), &[nf])?)?;
        d.set_item(
            "s",
            array(py, m.real.clone().map(|i| m.arc_length(i)).collect(), &[nn])?,
        )?;
        d.set_item("x", array(py, flat(&|f| f.x.concat()), &[nf, nn, 3])?)?;
        d.set_item("v", array(py, flat(&|f| f.v.concat()), &[nf, nn, 3])?)?;
        d.set_item(
            "theta",
            array(py, flat(&|f| f.theta.clone()), &[nf, nn - 1])?,
        )?;
        d.set_item(
            "normal_force",
            array(py, flat(&|f| f.normal.clone()), &[nf, nn])?,
        )?;
        let slip = flat(&|f| {
            f.v.iter()
                .zip(&f.normal)
                .flat_map(|(v, n)| {
                    if m.in_contact(*n) {
                        [v[0], v[1], 0.0]
                    } else {
                        [0.0; 3]
                    }
                })
                .collect()
        });
        d.set_item("slip_velocity", array(py, slip, &[nf, nn, 3])?)?;
        for (name, data) in [
            ("elevation", &fl.elevation),
            ("slip_speed", &fl.slip),
            ("lambda", &fl.lambda),
        ] {
            let k = data.first().map_or(0, |r| r.len());
            d.set_item(name, array(py, data.concat(), &[data.len(), k])?)?;
        }
        let (closest, touching) = output::self_contact_arrays(m, fr);
        d.set_item("closest_distance", array(py, closest, &[nf])?)?;
        d.set_item("self_contact", array(py, touching, &[nf, nn])?)?;
        // The one-element arrays the movie renderer reads (`diameter`, `gait_period`, ...),
        // as `trajectory.npz` stores them.
        for (name, v) in output::movie::movie_scalars(m) {
            d.set_item(name, array(py, vec![v], &[1])?)?;
        }
        Ok(d)
    }

    /// Write the files `slither run` writes into `out_dir` (created if absent) through the
    /// run pipeline, staged and swapped in as `slither run` does: the previous run's outputs
    /// there are replaced when every new file is written, or kept if the swap fails (the error
    /// names the folder that holds the new ones); `plots=False` skips the figures, the
    /// ParaView export, the tracks and the movie, as `--no-plots`.
    #[pyo3(signature = (out_dir, plots = true))]
    fn save(&self, py: Python<'_>, out_dir: PathBuf, plots: bool) -> PyResult<()> {
        let r = py.allow_threads(|| self.write(&out_dir, plots));
        r.map_err(PyOSError::new_err)
    }
}

impl NativeRun {
    /// The pipeline's writing; `Err` is its message.
    fn write(&self, out: &Path, plots: bool) -> Result<(), String> {
        std::fs::create_dir_all(out)
            .map_err(|e| format!("{}: cannot create output directory: {e}", out.display()))?;
        let _lock = output::lock::OutLock::acquire(out).map_err(|e| e.to_string())?;
        let files = if plots {
            pipeline::Files::ALL
        } else {
            pipeline::Files::DATA
        };
        self.run.save(out, files).map_err(|e| e.to_string())?;
        Ok(())
    }
}
