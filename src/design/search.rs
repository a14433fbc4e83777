//! The argmin glue: the simulator as a cost function, Nelder-Mead stopped at the evaluation
//! budget, the iteration observer, and the driver [`optimize`].

use super::*;

/// Notified before and after every evaluation (the CLI's progress bar and log lines).
pub trait EvaluationObserver {
    /// Evaluation number `count` (1-based within this run) starts at `point`; `cached` when it
    /// is answered from `history.csv` without simulating.
    fn started(&mut self, _count: usize, _point: &Point, _cached: bool) {}
    /// Fraction of the running simulation done, in [0, 1].
    fn progress(&mut self, _fraction: f64) {}
    /// Evaluation `count` ended with `e`; `reused` when it came from an earlier run's row.
    fn finished(&mut self, _count: usize, _e: &Evaluation, _reused: bool) {}
}

/// An observer that does nothing.
pub struct Silent;
impl EvaluationObserver for Silent {}

/// How an evaluation was answered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Source {
    Simulated,
    /// A row written by an earlier run.
    Reused,
    /// A point already visited in this run.
    Repeat,
}

pub(super) struct Shared<'a> {
    study: &'a Study,
    cache: HashMap<Key, (Evaluation, bool)>,
    next_eval: usize,
    history: std::fs::File,
    history_path: PathBuf,
    observer: &'a mut dyn EvaluationObserver,
    /// Every answered evaluation of this run, in order.
    visited: Vec<(Evaluation, Source, f64)>,
    fatal: Option<DesignError>,
}

/// The simulator as an argmin cost function over normalised coordinates. Cost calls beyond
/// the budget, or after a fatal error, are answered with `+inf` without simulating and the
/// solver wrapper stops at the end of that iteration (argmin's Nelder-Mead unwraps cost errors
/// during its initialisation, so this function never returns an error).
pub struct Evaluator<'a> {
    shared: Rc<RefCell<Shared<'a>>>,
    calls: Rc<Cell<usize>>,
    max: usize,
    fatal: Rc<Cell<bool>>,
}

impl CostFunction for Evaluator<'_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, u: &Self::Param) -> Result<f64, ArgminError> {
        let mut sh = self.shared.borrow_mut();
        if self.calls.get() >= self.max || sh.fatal.is_some() {
            return Ok(f64::INFINITY);
        }
        self.calls.set(self.calls.get() + 1);
        let count = self.calls.get();
        let study = sh.study;
        let (p, dist) = study.space.point(u);
        let duration = study.duration(p.speed);
        let k = key(&p, duration);
        let (e, source) = if let Some((e, from_file)) = sh.cache.get(&k) {
            let e = e.clone();
            let source = if *from_file {
                Source::Reused
            } else {
                Source::Repeat
            };
            sh.observer.started(count, &p, true);
            (e, source)
        } else {
            sh.observer.started(count, &p, false);
            let mut e = {
                let obs = &mut *sh.observer;
                simulate(study, &p, &mut |f| obs.progress(f))
            };
            e.eval = sh.next_eval;
            sh.next_eval += 1;
            let row = e.csv_row(&study.base_hash) + "\n";
            let written = sh
                .history
                .write_all(row.as_bytes())
                .and_then(|_| sh.history.flush())
                .and_then(|_| sh.history.sync_data());
            if let Err(source) = written {
                self.fatal.set(true);
                sh.fatal = Some(DesignError::Io {
                    path: sh.history_path.clone(),
                    source,
                });
            }
            sh.cache.insert(k, (e.clone(), false));
            (e, Source::Simulated)
        };
        sh.observer.finished(count, &e, source == Source::Reused);
        let cost = e.objective() + study.penalty * dist + study.heading_penalty(&e);
        sh.visited.push((e, source, cost));
        Ok(cost)
    }
}

pub(super) type NmState = IterState<Vec<f64>, (), (), (), (), f64>;

/// Nelder-Mead that also stops when the evaluation budget is spent (or a fatal error occurred).
pub(super) struct Budgeted {
    inner: NelderMead<Vec<f64>, f64>,
    calls: Rc<Cell<usize>>,
    max: usize,
    fatal: Rc<Cell<bool>>,
}

impl<O> Solver<O, NmState> for Budgeted
where
    O: CostFunction<Param = Vec<f64>, Output = f64>,
{
    fn name(&self) -> &str {
        "Nelder-Mead"
    }

    fn init(
        &mut self,
        problem: &mut ArgminProblem<O>,
        state: NmState,
    ) -> Result<(NmState, Option<KV>), ArgminError> {
        Solver::<O, NmState>::init(&mut self.inner, problem, state)
    }

    fn next_iter(
        &mut self,
        problem: &mut ArgminProblem<O>,
        state: NmState,
    ) -> Result<(NmState, Option<KV>), ArgminError> {
        Solver::<O, NmState>::next_iter(&mut self.inner, problem, state)
    }

    fn terminate(&mut self, state: &NmState) -> TerminationStatus {
        if self.fatal.get() {
            return TerminationStatus::Terminated(TerminationReason::SolverExit(
                "aborted: the history could not be written".into(),
            ));
        }
        if self.calls.get() >= self.max {
            return TerminationStatus::Terminated(TerminationReason::SolverExit(
                "max_evaluations reached".into(),
            ));
        }
        Solver::<O, NmState>::terminate(&mut self.inner, state)
    }
}

/// One Nelder-Mead iteration as seen by the iteration observer.
#[derive(Clone, Debug, Serialize)]
pub struct Iteration {
    /// Iteration number (0: after the initial simplex).
    pub iteration: u64,
    /// Best cost of the simplex (m/s, penalty included).
    pub best_cost: f64,
    /// Nelder-Mead action ("Reflection", "Expansion", ...), empty after initialisation.
    pub action: String,
}

/// argmin observer recording the simplex's best cost after every iteration.
pub(super) struct IterationLog(Arc<Mutex<Vec<Iteration>>>);

impl Observe<NmState> for IterationLog {
    fn observe_init(&mut self, _name: &str, state: &NmState, _kv: &KV) -> Result<(), ArgminError> {
        if let Ok(mut v) = self.0.lock() {
            v.push(Iteration {
                iteration: 0,
                best_cost: state.get_best_cost(),
                action: String::new(),
            });
        }
        Ok(())
    }

    fn observe_iter(&mut self, state: &NmState, kv: &KV) -> Result<(), ArgminError> {
        let action = kv
            .get("action")
            .and_then(|a| a.get_string())
            .unwrap_or_default();
        if let Ok(mut v) = self.0.lock() {
            v.push(Iteration {
                iteration: state.get_iter() + 1,
                best_cost: state.get_best_cost(),
                action,
            });
        }
        Ok(())
    }
}

/// Run a study: Nelder-Mead over the normalised bounds, every evaluation a simulation (or a
/// row of an existing `out/history.csv`), then write `optimum.json`, `speed_vs_writhe.png`
/// and `history.png` into `out` (created if absent).
pub fn optimize(
    study: &Study,
    out: &Path,
    observer: &mut dyn EvaluationObserver,
) -> Result<Report, DesignError> {
    let start = Instant::now();
    std::fs::create_dir_all(out).map_err(|source| DesignError::Io {
        path: out.into(),
        source,
    })?;
    let history_path = out.join(HISTORY_FILE);
    let old = read_history(&history_path)?;
    let rows_before = old.rows.len();
    let mut cache = HashMap::new();
    let mut rows_other_base = 0;
    let mut next_eval = 1;
    for (e, hash) in old.rows {
        next_eval = next_eval.max(e.eval + 1);
        if hash == study.base_hash {
            cache.insert(key(&e.point, e.duration), (e, true));
        } else {
            rows_other_base += 1;
        }
    }
    let mut history = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(&history_path)
        .map_err(|source| DesignError::Io {
            path: history_path.clone(),
            source,
        })?;
    if rows_before == 0 {
        let empty = history.metadata().map(|m| m.len() == 0).unwrap_or(true);
        if empty {
            writeln!(history, "{HISTORY_HEADER}")
                .and_then(|_| history.flush())
                .map_err(|source| DesignError::Io {
                    path: history_path.clone(),
                    source,
                })?;
        }
    }
    let calls = Rc::new(Cell::new(0usize));
    let fatal = Rc::new(Cell::new(false));
    let shared = Rc::new(RefCell::new(Shared {
        study,
        cache,
        next_eval,
        history,
        history_path: history_path.clone(),
        observer,
        visited: Vec::new(),
        fatal: None,
    }));
    let evaluator = Evaluator {
        shared: shared.clone(),
        calls: calls.clone(),
        max: study.max_evaluations,
        fatal: fatal.clone(),
    };
    let nm = NelderMead::new(study.space.initial_simplex(study.initial_step))
        .with_sd_tolerance(study.tolerance)
        .map_err(|e| DesignError::Solver(e.to_string()))?;
    let solver = Budgeted {
        inner: nm,
        calls: calls.clone(),
        max: study.max_evaluations,
        fatal: fatal.clone(),
    };
    let iterations = Arc::new(Mutex::new(Vec::new()));
    let run = Executor::new(evaluator, solver)
        .configure(|s| s.max_iters(study.max_evaluations as u64))
        .add_observer(IterationLog(iterations.clone()), ObserverMode::Always)
        .run();
    let termination = match run {
        Ok(res) => res
            .state()
            .get_termination_reason()
            .map_or("stopped".to_string(), |r| r.text().to_string()),
        Err(e) => return Err(DesignError::Solver(e.to_string())),
    };
    let mut sh = shared.borrow_mut();
    if let Some(e) = sh.fatal.take() {
        return Err(e);
    }
    let visited: Vec<(Evaluation, Source, f64)> = std::mem::take(&mut sh.visited);
    drop(sh);
    let count = |s: Source| visited.iter().filter(|v| v.1 == s).count();
    let mut failed_keys = std::collections::HashSet::new();
    for (e, _, _) in &visited {
        if e.status == Status::Failed {
            failed_keys.insert(key(&e.point, e.duration));
        }
    }
    let best = visited
        .iter()
        .filter(|v| v.0.status == Status::Ok && study.meets_heading(&v.0))
        .max_by(|a, b| a.0.v_s.total_cmp(&b.0.v_s))
        .map(|v| v.0.clone());
    let initial = visited
        .first()
        .map(|v| v.0.clone())
        .ok_or_else(|| DesignError::Solver("no evaluation was made".into()))?;
    let report = Report {
        evaluations: visited.len(),
        simulations: count(Source::Simulated),
        reused: count(Source::Reused),
        repeats: count(Source::Repeat),
        failed: failed_keys.len(),
        rows_before,
        rows_other_base,
        dropped_partial_row: old.dropped_partial,
        initial,
        best,
        visited: visited.into_iter().map(|(e, _, c)| (e, c)).collect(),
        iterations: iterations.lock().map(|v| v.clone()).unwrap_or_default(),
        termination,
        wall_time_s: start.elapsed().as_secs_f64(),
    };
    write_optimum(study, out, &report)?;
    write_figures(study, out, &report)?;
    Ok(report)
}
