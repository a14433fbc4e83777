//! The study file: schema, defaults, validation and the search space.

use super::*;

/// A whole study file (TOML).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudySpec {
    /// `[study]`: the base problem and the budget (required table).
    pub study: StudyTable,
    /// `[optimize]`: bounds of the optimised parameters (required table).
    pub optimize: Option<OptimizeTable>,
    /// `[accuracy]`: choose the model once on the base problem for every evaluation
    /// ([`crate::studies::accuracy`]). Absent: the base file's model.
    pub accuracy: Option<problem::AccuracySpec>,
}

/// `[study]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudyTable {
    /// Problem file, relative to the study file. Required. Its gait must have a kind other
    /// than "none" and its time mode must be "dynamic".
    pub base: String,
    /// Evaluations (cost-function calls: simulations plus answers from `history.csv`) before the
    /// search stops. Default 30, an integer in [n + 1, 100000] for n optimised parameters.
    #[serde(default = "d_max_evaluations")]
    pub max_evaluations: usize,
    /// Simulated duration in pulse times `L / v_m`: every evaluation runs
    /// `duration_pulses * L / v_m` seconds. Default: the base file's `time.duration * v_m / L`.
    /// In (0, 1000]. Not with `duration_periods`.
    pub duration_pulses: Option<f64>,
    /// Simulated duration in launch periods: every evaluation runs `duration_periods * period`
    /// seconds, so a study that varies the period measures the same number of cycles at every
    /// point. A sidewinding base only, not with `duration_pulses`; in (0, 1000].
    pub duration_periods: Option<f64>,
    /// Edge of the initial simplex in normalised coordinates (fraction of each bound's width).
    /// Default 0.25, in (0, 1].
    #[serde(default = "d_initial_step")]
    pub initial_step: f64,
    /// Nelder-Mead stops when the standard deviation of the cost over the simplex falls below
    /// this (m/s). Default 1e-5, >= 0.
    #[serde(default = "d_tolerance")]
    pub tolerance: f64,
    /// Penalty on a vertex outside the bounds (m/s per unit of normalised distance outside the
    /// unit cube). Default 1.0, >= 0.
    #[serde(default = "d_penalty")]
    pub penalty: f64,
    /// Heading limit (degrees): a finished run whose net displacement lies more than this off
    /// the initial head direction costs `penalty * (angle - max_heading_deg) / 90` extra (m/s)
    /// and cannot be the optimum. Default: no limit; in (0, 180].
    pub max_heading_deg: Option<f64>,
    /// What is maximised: "v_s" (default), the mean forward speed, or "broadside", the mean
    /// lateral speed per cycle of a sidewinding gait (across the cycle-mean tail-to-head axis,
    /// [`crate::observe::periodic`]) less `turn_penalty` times its mean |turn| per cycle.
    pub objective: Option<String>,
    /// With `objective = "broadside"`: cost per degree of mean |turn| per cycle (m/s per
    /// degree). Default [`DEFAULT_TURN_PENALTY`], a finite number >= 0.
    pub turn_penalty: Option<f64>,
    /// With `objective = "broadside"`: cost per unit by which the smallest stationary share of
    /// the contact time over the cycles falls short of the sidewinding criterion's
    /// [`crate::observe::periodic::STATIONARY_SHARE_MIN`] (m/s per unit share). Default 0, a
    /// finite number >= 0.
    pub stationary_penalty: Option<f64>,
}

// The serde defaults of `[study]`: the key table's (`crate::problem::study_keys`).
pub(super) fn d_max_evaluations() -> usize {
    study_keys::STUDY_MAX_EVALUATIONS.int() as usize
}
pub(super) fn d_initial_step() -> f64 {
    study_keys::STUDY_INITIAL_STEP.real()
}
pub(super) fn d_tolerance() -> f64 {
    study_keys::STUDY_TOLERANCE.real()
}
pub(super) fn d_penalty() -> f64 {
    study_keys::STUDY_PENALTY.real()
}

/// `[optimize]`: `[lo, hi]` bounds of each optimised parameter; a parameter without bounds
/// keeps the base problem's value.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OptimizeTable {
    /// Bounds of the muscle stress `Gamma` (Pa), `0 <= lo < hi`.
    pub stress: Option<[f64; 2]>,
    /// Bounds of the couple width `sigma` (fraction of L), `0 < lo < hi <= 1`; for the
    /// Gaussian gaits (s-start, sidewinding) also `lo >= 1/N`, one element of the base file's
    /// `N = rod.elements`.
    pub sigma: Option<[f64; 2]>,
    /// Bounds of the travelling speed `v_m` (m/s), `0 < lo < hi`.
    pub speed: Option<[f64; 2]>,
    /// Bounds of the launch period (s), `0 < lo < hi`; a sidewinding base only.
    pub period: Option<[f64; 2]>,
    /// Bounds of the triplet's spacing `b - a = c - b` (fraction of L), `0 < lo < hi` with
    /// `centers[0] + 2 hi <= 1`; an s-start or sidewinding base whose centres are evenly spaced.
    pub spacing: Option<[f64; 2]>,
    /// Bounds of the out-of-plane couple's scale `scales[1]`, `lo < hi`; an s-start or
    /// sidewinding base.
    pub lift: Option<[f64; 2]>,
    /// Starting point; each value must lie in its bounds. Default: the base problem's values.
    #[serde(default)]
    pub initial: InitialTable,
    /// Search method: "nelder-mead" (default) or "particle-swarm".
    #[serde(default)]
    pub method: SearchMethod,
    /// Nelder-Mead only: independent starts sharing `max_evaluations` equally, the first from
    /// `initial`, the others from points drawn uniformly in the bounds (seeded by `seed`).
    /// Default 1, an integer in [1, 1000] with `max_evaluations >= starts * (n + 1)`.
    pub starts: Option<usize>,
    /// Particle swarm only: particles per generation (one simulation each, run in parallel,
    /// one per core). Default [`DEFAULT_PARTICLES`], an integer in [2, 1000], at most
    /// `max_evaluations`.
    pub particles: Option<usize>,
    /// Seed of the random draws (particle swarm positions and velocities, multi-start
    /// points), so a study is reproducible and resumable. Default 1, an integer >= 0.
    pub seed: Option<u64>,
}

/// The search method of a study (`[optimize] method`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum SearchMethod {
    /// argmin's Nelder-Mead simplex, one simulation at a time (optionally multi-start).
    #[default]
    NelderMead,
    /// argmin's particle swarm: a generation of `particles` simulations evaluated in parallel.
    ParticleSwarm,
}

impl SearchMethod {
    /// The name as written in the study file.
    pub fn as_str(self) -> &'static str {
        match self {
            SearchMethod::NelderMead => "nelder-mead",
            SearchMethod::ParticleSwarm => "particle-swarm",
        }
    }
}

/// Particles per generation of the particle swarm when `[optimize] particles` is not given:
/// four simulations per core of a 2-core machine, and five generations in the default budget
/// of 40 evaluations of the bundled study.
pub const DEFAULT_PARTICLES: usize = study_keys::OPTIMIZE_PARTICLES.int() as usize;

/// An optimum closer to a bound than this fraction of the bound's width (in normalised
/// coordinates `u <= 0.01` or `u >= 0.99`) is reported as on that bound (`on_bound` in
/// `optimum.json`): the search was stopped by the box, and widening it may give more.
pub const ON_BOUND_FRACTION: f64 = 0.01;

/// `[optimize] initial = { ... }`: the starting point (only optimised parameters).
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialTable {
    /// Muscle stress (Pa).
    pub stress: Option<f64>,
    /// Couple width (fraction of L).
    pub sigma: Option<f64>,
    /// Travelling speed (m/s).
    pub speed: Option<f64>,
    /// Launch period (s).
    pub period: Option<f64>,
    /// Triplet spacing (fraction of L).
    pub spacing: Option<f64>,
    /// Out-of-plane couple's scale.
    pub lift: Option<f64>,
}

/// What `[optimize]` must hold, for messages.
pub(super) const OPTIMIZE_ONE_OF: &str = "at least one of optimize.stress (Pa), optimize.sigma (fraction of L), optimize.speed (m/s), optimize.period (s), optimize.spacing (fraction of L), optimize.lift (scale of gait.scales[1])";

/// A validated study.
#[derive(Clone, Debug)]
pub struct Study {
    /// The study file.
    pub path: PathBuf,
    /// The base problem file (resolved against the study file's directory).
    pub base_path: PathBuf,
    /// The base problem.
    pub base: Problem,
    /// Hash of the effective base problem ([`problem_hash`], 16 hex digits; after
    /// `[accuracy]`, of the chosen model): resume only reuses rows whose key
    /// ([`Study::row_hash`]) matches.
    pub base_hash: String,
    /// Evaluation budget.
    pub max_evaluations: usize,
    /// Duration of every evaluation in pulse times `L / v_m` (the base file's duration in
    /// them when the study gives `duration_periods`).
    pub duration_pulses: f64,
    /// Duration of every evaluation in launch periods, when the study gives it (then it, not
    /// `duration_pulses`, sets the duration).
    pub duration_periods: Option<f64>,
    /// Initial simplex edge (normalised).
    pub initial_step: f64,
    /// Nelder-Mead cost standard-deviation tolerance (m/s).
    pub tolerance: f64,
    /// Out-of-bounds penalty (m/s per unit normalised distance).
    pub penalty: f64,
    /// Heading limit (degrees), if any.
    pub max_heading_deg: Option<f64>,
    /// What is maximised.
    pub objective: Objective,
    /// Cost per degree of mean |turn| per cycle (m/s per degree), for [`Objective::Broadside`].
    pub turn_penalty: f64,
    /// Cost per unit of stationary-share shortfall (m/s), for [`Objective::Broadside`].
    pub stationary_penalty: f64,
    /// The search space.
    pub space: Space,
    /// The search method.
    pub method: SearchMethod,
    /// Nelder-Mead starts (1 for the particle swarm).
    pub starts: usize,
    /// Particle swarm population (0 for Nelder-Mead).
    pub particles: usize,
    /// Seed of the random draws.
    pub seed: u64,
    /// `[accuracy]`, if given.
    pub accuracy: Option<problem::AccuracySpec>,
    /// The model chosen for it (set by [`prepare_accuracy`]).
    pub chosen: Option<crate::studies::accuracy::StudyAccuracy>,
    /// Re-evaluate the best point and the runner-up as ensembles at the end
    /// (`slither optimize --ensemble K`; [`super::report::check_optimum`]); `None`: no check.
    pub ensemble: Option<crate::studies::ensemble::Spec>,
}

impl Study {
    /// Whether a run's heading is within `max_heading_deg` (always, without a limit).
    pub fn meets_heading(&self, e: &Evaluation) -> bool {
        self.max_heading_deg
            .is_none_or(|max| !(e.displacement_angle_deg > max))
    }

    /// Extra cost (m/s) of a finished run that heads more than `max_heading_deg` off the
    /// initial head direction: `penalty * (angle - max_heading_deg) / 90`; zero otherwise.
    pub fn heading_penalty(&self, e: &Evaluation) -> f64 {
        match (self.max_heading_deg, e.status) {
            (Some(max), Status::Ok) if e.displacement_angle_deg > max => {
                self.penalty * (e.displacement_angle_deg - max) / 90.0
            }
            _ => 0.0,
        }
    }

    /// Duration of a run at `p` (s): `duration_periods * period`, or `duration_pulses * L /
    /// v_m`.
    pub fn duration(&self, p: &GaitParams) -> f64 {
        match self.duration_periods {
            Some(n) => n * p.period,
            None => self.duration_pulses * self.base.rod.length / p.speed,
        }
    }

    /// The base problem with the point's gait values and the matching duration. The centres
    /// change only when the spacing is optimised (the base's own centres are kept bit for bit
    /// otherwise).
    pub fn problem_at(&self, p: &GaitParams) -> Problem {
        let mut pr = self.base.clone();
        pr.gait.stress = p.stress;
        pr.gait.sigma = p.sigma;
        pr.gait.speed = p.speed;
        pr.gait.period = p.period;
        pr.gait.scales[1] = p.lift;
        if self.space.varies(Param::Spacing) {
            let a = pr.gait.centers[0];
            pr.gait.centers = [a, a + p.spacing, a + 2.0 * p.spacing];
        }
        pr.time.duration = Some(self.duration(p));
        pr
    }
}

/// A study-file error: names the file, the dotted key, its line and what is allowed.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// The study file could not be read, is not valid TOML of the study's shape, or has a value
    /// outside its allowed range (the same errors as a problem file's).
    #[error(transparent)]
    File(#[from] ProblemError),
    /// The base problem file is missing or invalid.
    #[error("{file}:{line}: `study.base` = {value:?}: {source}; must be a valid problem file (path relative to the study file)")]
    Base {
        /// The study file.
        file: PathBuf,
        /// Line of `base`.
        line: usize,
        /// The value as written.
        value: String,
        /// The problem-file error (names the base file, its key and line); boxed to keep the
        /// error small.
        source: Box<ProblemError>,
    },
}

/// Read, parse and validate a study file (and its base problem).
pub fn load_study(path: &Path) -> Result<Study, StudyError> {
    load_study_with(path, &[])
}

/// The tables of a study file; `--set` keys below any other table edit the base problem.
pub const STUDY_TABLES: [&str; 3] = ["study", "optimize", "accuracy"];

/// [`load_study`] with command-line settings (`--set`): those of [`STUDY_TABLES`] edit the
/// study file, the others its base problem, each validated as if written there.
pub fn load_study_with(
    path: &Path,
    settings: &[&problem::set::Setting],
) -> Result<Study, StudyError> {
    let (own, base) = problem::set::split(settings, &STUDY_TABLES);
    let text = problem::edit(&problem::read(path)?, path, &own)?;
    parse_study_with(&text, path, &base).map_err(|e| match e {
        StudyError::File(e) => StudyError::File(problem::set::attribute(e, &own, path)),
        e => e,
    })
}

/// Parse and validate study text; `path` locates the base file and names the study in messages.
pub fn parse_study(text: &str, path: &Path) -> Result<Study, StudyError> {
    parse_study_with(text, path, &[])
}

/// [`parse_study`] with command-line settings applied to the base problem.
pub fn parse_study_with(
    text: &str,
    path: &Path,
    base_settings: &[&problem::set::Setting],
) -> Result<Study, StudyError> {
    let spec: StudySpec = problem::from_toml(text, path)?;
    problem::ranges::check_lengths(text, path)?;
    let at = At { text, path };
    let s = &spec.study;
    let (base_path, base) = base_problem(&at, s, base_settings)?;
    let fixed = GaitParams::of(&base);
    let Some(opt) = &spec.optimize else {
        return Err(at.no_bounds(text.lines().count().max(1), "(missing)"));
    };
    let dims = dims(&at, opt, &base, &fixed)?;
    let n = dims.len();
    let (_, most) = study_keys::STUDY_MAX_EVALUATIONS.int_range();
    if s.max_evaluations < n + 1
        || !study_keys::STUDY_MAX_EVALUATIONS.check_int(s.max_evaluations as u64)
    {
        return Err(at.fail(
            "study",
            "max_evaluations",
            format!("{}", s.max_evaluations),
            format!(
                "an integer in [{}, {most}] (the initial simplex of {n} optimised parameters needs {} evaluations)",
                n + 1,
                n + 1
            ),
        ));
    }
    let (duration_pulses, duration_periods) = durations(&at, s, &base)?;
    check_search_settings(&at, s)?;
    let (objective, turn_penalty, stationary_penalty) = objective(&at, s, &base)?;
    let (starts, particles) = method_sizes(&at, s, opt, n)?;
    let space = Space { dims, fixed };
    let study = Study {
        path: path.into(),
        base_path,
        base_hash: format!("{:016x}", problem_hash(&base)),
        base,
        max_evaluations: s.max_evaluations,
        duration_pulses,
        duration_periods,
        initial_step: s.initial_step,
        tolerance: s.tolerance,
        penalty: s.penalty,
        max_heading_deg: s.max_heading_deg,
        objective,
        turn_penalty,
        stationary_penalty,
        space,
        method: opt.method,
        starts,
        particles,
        seed: opt.seed.unwrap_or(study_keys::OPTIMIZE_SEED.int()),
        accuracy: spec.accuracy.clone(),
        chosen: None,
        ensemble: None,
    };
    if let Some(a) = &spec.accuracy {
        if let Err((key, value, allowed)) = problem::check_accuracy(a, &study.base) {
            return Err(at.fail("accuracy", key, value, allowed));
        }
    }
    check_shortest_run(&at, s, &study)?;
    Ok(study)
}

/// Apply a study file's `[accuracy]` before the study runs: choose (or reuse) the model on the
/// base problem, set the base to it and the rows' resume key to the model's. Without
/// `[accuracy]`, removes a stale `accuracy.json` and changes nothing. Returns whether a
/// recorded choice was reused.
pub fn prepare_accuracy(
    study: &mut Study,
    out: &Path,
    log: &mut dyn FnMut(&str),
) -> std::io::Result<bool> {
    let Some(spec) = study.accuracy.clone() else {
        accuracy::forget(out)?;
        return Ok(false);
    };
    let (chosen, reused) = accuracy::choose(&study.base, &study.base_hash, &spec, out, log)?;
    study.base = chosen.apply(&study.base);
    study.base_hash = format!("{:016x}", chosen.row_hash());
    study.chosen = Some(chosen);
    Ok(reused)
}
