//! The argmin glue: the simulator as a cost function, Nelder-Mead stopped at the evaluation
//! budget, the reflecting particle swarm, the iteration observer, and the driver [`optimize`].
//!
//! # The reflecting swarm
//!
//! argmin's `ParticleSwarm` limits every new position to its bounds by clamping and keeps the
//! particle's velocity, so a particle that overshoots a face stays on it while its momentum
//! keeps pointing outwards; on the bundled gait study every swarm ended on the upper `v_m`
//! bound. The swarm therefore runs on a window [`SWARM_WINDOW`] cube widths wider than the
//! unit cube on each side (argmin needs finite bounds; the window is never reached in
//! practice, the inertia weight 0.72 shrinks velocities every generation) and [`Reflected`]
//! maps each position to the cube by [`reflect`], a triangle wave of period 2 on each
//! coordinate (0.3 -> 0.3, 1.2 -> 0.8, -0.1 -> 0.1): a particle that overshoots a bound is
//! evaluated as far inside as it went outside, and can come back. The map is deterministic, so
//! the evaluated points (in the bounds, SI values in `history.csv` and `optimum.json`) and a
//! resumed run's replay are unchanged in kind; no out-of-cube penalty applies to the swarm.

use super::*;

/// Notified before and after every evaluation (the CLI's progress bar and log lines).
pub trait EvaluationObserver {
    /// Evaluation number `count` (1-based within this run) starts at `point`; `cached` when it
    /// is answered from `history.csv` without simulating.
    fn started(&mut self, _count: usize, _point: &GaitParams, _cached: bool) {}
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
    fatal: Option<OptimizeError>,
}

/// The simulator as an argmin cost function over normalised coordinates. Cost calls beyond
/// the current limit (the evaluation budget, or one start's share of it), or after a fatal
/// error, are answered with `+inf` without simulating and the solver wrapper stops at the end
/// of that iteration (argmin's Nelder-Mead unwraps cost errors during its initialisation, so
/// this function never returns an error).
///
/// [`CostFunction::bulk_cost`] (the particle swarm's generation) simulates the new points of a
/// batch in parallel with rayon, one simulation per core; rows are then written, and
/// evaluation numbers given, in the batch's order, so a run is deterministic whatever the
/// threads' timing and resumes like a sequential one.
#[derive(Clone)]
pub struct Evaluator<'a> {
    shared: Rc<RefCell<Shared<'a>>>,
    calls: Rc<Cell<usize>>,
    limit: Rc<Cell<usize>>,
    fatal: Rc<Cell<bool>>,
}

/// How one point of a batch is answered.
enum Slot {
    /// Beyond the budget (or after a fatal error): `+inf`, not simulated.
    Skip,
    /// From the cache, with the evaluation number `count`.
    Known(usize, Box<Evaluation>, Source, f64),
    /// The `i`-th new simulation of the batch (a second request of the same point in one batch
    /// is a repeat).
    Run(usize, usize, Source, f64),
}

impl Evaluator<'_> {
    /// Answer a batch of normalised points, simulating the new ones in parallel.
    fn batch(&self, us: &[&[f64]]) -> Vec<f64> {
        let mut sh = self.shared.borrow_mut();
        let study = sh.study;
        let mut slots = Vec::with_capacity(us.len());
        let mut runs: Vec<(GaitParams, Key)> = Vec::new();
        for u in us {
            if self.calls.get() >= self.limit.get() || sh.fatal.is_some() {
                slots.push(Slot::Skip);
                continue;
            }
            self.calls.set(self.calls.get() + 1);
            let count = self.calls.get();
            let (p, dist) = study.space.point(u);
            let k = key(&p, study.duration(&p));
            if let Some((e, from_file)) = sh.cache.get(&k) {
                let e = e.clone();
                let source = if *from_file {
                    Source::Reused
                } else {
                    Source::Repeat
                };
                sh.observer.started(count, &p, true);
                slots.push(Slot::Known(count, Box::new(e), source, dist));
            } else if let Some(i) = runs.iter().position(|r| r.1 == k) {
                sh.observer.started(count, &p, true);
                slots.push(Slot::Run(count, i, Source::Repeat, dist));
            } else {
                sh.observer.started(count, &p, false);
                runs.push((p, k));
                slots.push(Slot::Run(count, runs.len() - 1, Source::Simulated, dist));
            }
        }
        let results: Vec<Evaluation> = if runs.len() == 1 {
            let obs = &mut *sh.observer;
            vec![simulate(study, &runs[0].0, &mut |f| obs.progress(f))]
        } else {
            runs.par_iter()
                .map(|(p, _)| simulate(study, p, &mut |_| {}))
                .collect()
        };
        let mut new = Vec::with_capacity(results.len());
        for (mut e, (_, k)) in results.into_iter().zip(runs) {
            e.eval = sh.next_eval;
            sh.next_eval += 1;
            let row = e.csv_row(&study.row_hash()) + "\n";
            let written = sh
                .history
                .write_all(row.as_bytes())
                .and_then(|_| sh.history.flush())
                .and_then(|_| sh.history.sync_data());
            if let Err(source) = written {
                self.fatal.set(true);
                if sh.fatal.is_none() {
                    sh.fatal = Some(OptimizeError::Io {
                        path: sh.history_path.clone(),
                        source,
                    });
                }
            }
            sh.cache.insert(k, (e.clone(), false));
            new.push(e);
        }
        slots
            .into_iter()
            .map(|slot| {
                let (count, e, source, dist) = match slot {
                    Slot::Skip => return f64::INFINITY,
                    Slot::Known(c, e, s, d) => (c, *e, s, d),
                    Slot::Run(c, i, s, d) => (c, new[i].clone(), s, d),
                };
                sh.observer.finished(count, &e, source == Source::Reused);
                let cost = e.objective() + study.penalty * dist + study.heading_penalty(&e);
                sh.visited.push((e, source, cost));
                cost
            })
            .collect()
    }
}

impl CostFunction for Evaluator<'_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, u: &Self::Param) -> Result<f64, ArgminError> {
        Ok(self.batch(&[u.as_slice()])[0])
    }

    fn bulk_cost<P>(&self, params: &[P]) -> Result<Vec<f64>, ArgminError>
    where
        P: std::borrow::Borrow<Self::Param> + argmin::core::SyncAlias,
        f64: argmin::core::SendAlias,
        Self: argmin::core::SyncAlias,
    {
        let us: Vec<&[f64]> = params.iter().map(|p| p.borrow().as_slice()).collect();
        Ok(self.batch(&us))
    }
}

/// Half-width beyond the unit cube, in cube widths, of the window argmin's swarm moves in
/// (its bounds are `[-SWARM_WINDOW, 1 + SWARM_WINDOW]` on every coordinate). Only there so
/// that argmin's clamp is never what turns a particle around; [`reflect`] brings every position
/// back into the cube.
pub const SWARM_WINDOW: f64 = 100.0;

/// The reflecting map of a normalised coordinate into [0, 1]: a triangle wave of period 2,
/// the identity on [0, 1] and continuous, `reflect(1 + t) = 1 - t`, `reflect(-t) = t`
/// (1.2 -> 0.8, -0.1 -> 0.1, 2.3 -> 0.3). A non-finite coordinate gives NaN, which
/// [`Space::point`] answers at infinite distance.
pub fn reflect(u: f64) -> f64 {
    let r = u.rem_euclid(2.0);
    if r <= 1.0 {
        r
    } else {
        2.0 - r
    }
}

/// A cost function over the unit cube seen from the swarm's unbounded positions: each position
/// is mapped to the cube by [`reflect`] before `.0` is asked (batches stay batches).
#[derive(Clone)]
pub struct Reflected<C>(pub C);

impl<C> CostFunction for Reflected<C>
where
    C: CostFunction<Param = Vec<f64>, Output = f64>,
{
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, u: &Self::Param) -> Result<f64, ArgminError> {
        self.0.cost(&u.iter().map(|&x| reflect(x)).collect())
    }

    fn bulk_cost<P>(&self, params: &[P]) -> Result<Vec<f64>, ArgminError>
    where
        P: std::borrow::Borrow<Self::Param> + argmin::core::SyncAlias,
        f64: argmin::core::SendAlias,
        Self: argmin::core::SyncAlias,
    {
        let us: Vec<Vec<f64>> = params
            .iter()
            .map(|p| p.borrow().iter().map(|&x| reflect(x)).collect())
            .collect();
        self.0.bulk_cost(&us)
    }
}

/// argmin's particle swarm (its default weights) over `n` coordinates on the window
/// `[-SWARM_WINDOW, 1 + SWARM_WINDOW]^n`, its random numbers from xoshiro256++ seeded by `seed`;
/// run it on a [`Reflected`] cost function.
pub(super) fn reflecting_swarm(
    n: usize,
    particles: usize,
    seed: u64,
) -> ParticleSwarm<Vec<f64>, f64, Xoshiro256PlusPlus> {
    ParticleSwarm::new(
        (vec![-SWARM_WINDOW; n], vec![1.0 + SWARM_WINDOW; n]),
        particles,
    )
    .with_rng_generator(Xoshiro256PlusPlus::seed_from_u64(seed))
}

/// The first generation: `start` and `particles - 1` points drawn uniformly in the unit cube,
/// velocities uniform in [-1, 1]^n (argmin's own initialisation, with the start included so
/// `initial` is the study's start); the draws come from `rng`.
pub(super) fn first_generation(
    start: Vec<f64>,
    particles: usize,
    rng: &mut Xoshiro256PlusPlus,
) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let n = start.len();
    let mut positions = vec![start];
    for _ in 1..particles {
        positions.push((0..n).map(|_| unit_draw(rng)).collect());
    }
    let velocities = (0..particles)
        .map(|_| (0..n).map(|_| 2.0 * unit_draw(rng) - 1.0).collect())
        .collect();
    (positions, velocities)
}

pub(super) type PsoState = PopulationState<Particle<Vec<f64>, f64>, f64>;

/// argmin's particles from the first generation's positions, velocities and costs.
pub(super) fn population(
    positions: Vec<Vec<f64>>,
    velocities: Vec<Vec<f64>>,
    costs: Vec<f64>,
) -> Vec<Particle<Vec<f64>, f64>> {
    positions
        .into_iter()
        .zip(velocities)
        .zip(costs)
        .map(|((p, v), c)| Particle::new(p, c, v))
        .collect()
}

/// A solver that also stops when the evaluation limit is reached (or a fatal error occurred).
pub(super) struct Budgeted<S> {
    inner: S,
    calls: Rc<Cell<usize>>,
    limit: Rc<Cell<usize>>,
    fatal: Rc<Cell<bool>>,
}

impl<O, S, I> Solver<O, I> for Budgeted<S>
where
    S: Solver<O, I>,
    I: State,
{
    fn name(&self) -> &str {
        self.inner.name()
    }

    fn init(
        &mut self,
        problem: &mut ArgminProblem<O>,
        state: I,
    ) -> Result<(I, Option<KV>), ArgminError> {
        self.inner.init(problem, state)
    }

    fn next_iter(
        &mut self,
        problem: &mut ArgminProblem<O>,
        state: I,
    ) -> Result<(I, Option<KV>), ArgminError> {
        self.inner.next_iter(problem, state)
    }

    fn terminate(&mut self, state: &I) -> TerminationStatus {
        if self.fatal.get() {
            return TerminationStatus::Terminated(TerminationReason::SolverExit(
                "aborted: the history could not be written".into(),
            ));
        }
        if self.calls.get() >= self.limit.get() {
            return TerminationStatus::Terminated(TerminationReason::SolverExit(
                "max_evaluations reached".into(),
            ));
        }
        self.inner.terminate(state)
    }
}

/// One iteration (Nelder-Mead step or swarm generation) as seen by the iteration observer.
#[derive(Clone, Debug, Serialize)]
pub struct Iteration {
    /// The start it belongs to (1-based; always 1 but for multi-start Nelder-Mead).
    pub start: usize,
    /// Iteration number (0: after the initial simplex or population).
    pub iteration: u64,
    /// Best cost of the simplex or swarm (m/s, penalty included).
    pub best_cost: f64,
    /// Nelder-Mead action ("Reflection", "Expansion", ...), empty after initialisation and
    /// for the swarm.
    pub action: String,
}

/// argmin observer recording the best cost after every iteration of start `.1`.
pub(super) struct IterationLog(Arc<Mutex<Vec<Iteration>>>, usize);

impl<S: State<Float = f64>> Observe<S> for IterationLog {
    fn observe_init(&mut self, _name: &str, state: &S, _kv: &KV) -> Result<(), ArgminError> {
        if let Ok(mut v) = self.0.lock() {
            v.push(Iteration {
                start: self.1,
                iteration: 0,
                best_cost: state.get_best_cost(),
                action: String::new(),
            });
        }
        Ok(())
    }

    fn observe_iter(&mut self, state: &S, kv: &KV) -> Result<(), ArgminError> {
        let action = kv
            .get("action")
            .and_then(|a| a.get_string())
            .unwrap_or_default();
        if let Ok(mut v) = self.0.lock() {
            v.push(Iteration {
                start: self.1,
                iteration: state.get_iter() + 1,
                best_cost: state.get_best_cost(),
                action,
            });
        }
        Ok(())
    }
}

/// Run a study: Nelder-Mead (one or several starts) or the particle swarm over the normalised
/// bounds, every evaluation a simulation (or a row of an existing `out/history.csv`), then
/// write `optimum.json`, `speed_vs_writhe.png`
/// and `history.png` into `out` (created if absent).
pub fn optimize(
    study: &Study,
    out: &Path,
    observer: &mut dyn EvaluationObserver,
) -> Result<Report, OptimizeError> {
    let start = Instant::now();
    std::fs::create_dir_all(out).map_err(|source| OptimizeError::Io {
        path: out.into(),
        source,
    })?;
    let history_path = out.join(HISTORY_FILE);
    let Resumed {
        cache,
        next_eval,
        history,
        rows_before,
        rows_other_base,
        dropped_partial_row,
    } = resume(study, &history_path)?;
    let calls = Rc::new(Cell::new(0usize));
    let limit = Rc::new(Cell::new(study.max_evaluations));
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
        limit: limit.clone(),
        fatal: fatal.clone(),
    };
    let iterations = Arc::new(Mutex::new(Vec::new()));
    let mut terminations = run_method(study, &evaluator, &iterations)?;
    drop(evaluator);
    let termination = if terminations.len() == 1 {
        terminations.remove(0)
    } else {
        terminations
            .iter()
            .enumerate()
            .map(|(i, t)| format!("start {}: {t}", i + 1))
            .collect::<Vec<_>>()
            .join("; ")
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
        .max_by(|a, b| b.0.objective().total_cmp(&a.0.objective()))
        .map(|v| v.0.clone());
    let initial = visited
        .first()
        .map(|v| v.0.clone())
        .ok_or_else(|| OptimizeError::Solver("no evaluation was made".into()))?;
    let report = Report {
        evaluations: visited.len(),
        simulations: count(Source::Simulated),
        reused: count(Source::Reused),
        repeats: count(Source::Repeat),
        failed: failed_keys.len(),
        rows_before,
        rows_other_base,
        dropped_partial_row,
        initial,
        best,
        visited: visited.into_iter().map(|(e, _, c)| (e, c)).collect(),
        iterations: iterations.lock().map(|v| v.clone()).unwrap_or_default(),
        termination,
        wall_time_s: start.elapsed().as_secs_f64(),
        check: None,
    };
    let mut report = report;
    if let Some(spec) = &study.ensemble {
        report.check = check_optimum(study, &report, spec);
        report.wall_time_s = start.elapsed().as_secs_f64();
    }
    write_optimum(study, out, &report)?;
    write_figures(study, out, &report)?;
    Ok(report)
}

/// Run the study's search method over `evaluator` within its budget, recording the
/// iterations; returns why each start stopped.
fn run_method(
    study: &Study,
    evaluator: &Evaluator,
    iterations: &Arc<Mutex<Vec<Iteration>>>,
) -> Result<Vec<String>, OptimizeError> {
    let (calls, limit, fatal) = (&evaluator.calls, &evaluator.limit, &evaluator.fatal);
    let mut terminations = Vec::new();
    let budgeted = |inner| Budgeted {
        inner,
        calls: calls.clone(),
        limit: limit.clone(),
        fatal: fatal.clone(),
    };
    let budgeted_pso = |inner| Budgeted {
        inner,
        calls: calls.clone(),
        limit: limit.clone(),
        fatal: fatal.clone(),
    };
    let reason =
        |run: Result<String, ArgminError>| run.map_err(|e| OptimizeError::Solver(e.to_string()));
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(study.seed);
    let n = study.space.dims.len();
    match study.method {
        SearchMethod::NelderMead => {
            for start in 1..=study.starts {
                // Equal shares of the budget; the last start takes the remainder.
                let share = study.max_evaluations / study.starts;
                limit.set(if start == study.starts {
                    study.max_evaluations
                } else {
                    calls.get() + share
                });
                let u0 = if start == 1 {
                    study.space.to_unit(&study.space.initial())
                } else {
                    (0..n).map(|_| unit_draw(&mut rng)).collect()
                };
                let nm = NelderMead::new(study.space.simplex_at(u0, study.initial_step))
                    .with_sd_tolerance(study.tolerance)
                    .map_err(|e| OptimizeError::Solver(e.to_string()))?;
                let run = Executor::new(evaluator.clone(), budgeted(nm))
                    .configure(|s| s.max_iters(study.max_evaluations as u64))
                    .add_observer(
                        IterationLog(iterations.clone(), start),
                        ObserverMode::Always,
                    )
                    .run()
                    .map(|res| {
                        res.state()
                            .get_termination_reason()
                            .map_or("stopped".to_string(), |r| r.text().to_string())
                    });
                terminations.push(reason(run)?);
                if fatal.get() {
                    break;
                }
            }
        }
        SearchMethod::ParticleSwarm => {
            // The first generation lies in the unit cube, where `reflect` is the identity.
            let (positions, velocities) = first_generation(
                study.space.to_unit(&study.space.initial()),
                study.particles,
                &mut rng,
            );
            let us: Vec<&[f64]> = positions.iter().map(Vec::as_slice).collect();
            let costs = evaluator.batch(&us);
            let population = population(positions, velocities, costs);
            if calls.get() < study.max_evaluations && !fatal.get() {
                let pso = reflecting_swarm(n, study.particles, study.seed.wrapping_add(1));
                let run = Executor::new(Reflected(evaluator.clone()), budgeted_pso(pso))
                    .configure(|s: PsoState| {
                        s.population(population)
                            .max_iters(study.max_evaluations as u64)
                    })
                    .add_observer(IterationLog(iterations.clone(), 1), ObserverMode::Always)
                    .run()
                    .map(|res| {
                        res.state()
                            .get_termination_reason()
                            .map_or("stopped".to_string(), |r| r.text().to_string())
                    });
                terminations.push(reason(run)?);
            } else {
                terminations.push("max_evaluations reached".into());
            }
        }
    }
    Ok(terminations)
}

/// A study's `history.csv` opened to append, with what its earlier rows answer.
struct Resumed {
    /// The evaluations of this study's rows (row key [`Study::row_hash`]), by point and
    /// duration, each marked as read from the file.
    cache: HashMap<Key, (Evaluation, bool)>,
    /// The number of the next evaluation.
    next_eval: usize,
    /// The file, open to append (with its header).
    history: std::fs::File,
    /// Rows in the file before this run.
    rows_before: usize,
    /// Rows written under another key (never reused).
    rows_other_base: usize,
    /// An incomplete last row was dropped.
    dropped_partial_row: bool,
}

/// Read `history.csv` at `history_path` (its rows of this study answer evaluations again; a
/// file of the older format is rewritten in the current one) and open it to append.
fn resume(study: &Study, history_path: &Path) -> Result<Resumed, OptimizeError> {
    let old = read_history(history_path)?;
    let rows_before = old.rows.len();
    let mut cache = HashMap::new();
    let mut rows_other_base = 0;
    let mut next_eval = 1;
    let mut rows = old.rows;
    let row_hash = study.row_hash();
    for (e, hash) in &mut rows {
        next_eval = next_eval.max(e.eval + 1);
        if *hash == row_hash {
            // A legacy row (no period, spacing or lift recorded) ran the base file's.
            let p = &mut e.point;
            let f = &study.space.fixed;
            for (x, base) in [
                (&mut p.period, f.period),
                (&mut p.spacing, f.spacing),
                (&mut p.lift, f.lift),
            ] {
                if x.is_nan() {
                    *x = base;
                }
            }
            cache.insert(key(&e.point, e.duration), (e.clone(), true));
        } else {
            rows_other_base += 1;
        }
    }
    // A history of the older format is rewritten in the current one before rows are appended
    // (its rows of this base with the base's period, spacing and lift; of other bases empty).
    if old.legacy {
        rewrite_history(history_path, &rows).map_err(|source| OptimizeError::Io {
            path: history_path.into(),
            source,
        })?;
    }
    let mut history = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(history_path)
        .map_err(|source| OptimizeError::Io {
            path: history_path.into(),
            source,
        })?;
    if rows_before == 0 {
        let empty = history.metadata().map(|m| m.len() == 0).unwrap_or(true);
        if empty {
            writeln!(history, "{HISTORY_HEADER}")
                .and_then(|_| history.flush())
                .map_err(|source| OptimizeError::Io {
                    path: history_path.into(),
                    source,
                })?;
        }
    }
    Ok(Resumed {
        cache,
        next_eval,
        history,
        rows_before,
        rows_other_base,
        dropped_partial_row: old.dropped_partial,
    })
}

/// A draw uniform in [0, 1) from the top 53 bits of the generator (the study's seeded draws).
fn unit_draw(rng: &mut Xoshiro256PlusPlus) -> f64 {
    (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}

#[cfg(test)]
#[path = "search_tests.rs"]
mod tests;
