//! The phase file: its `[phase]` table (base problem, grids, refinement) and `[accuracy]`,
//! and the problem of one cell.
use crate::problem::study_keys::{
    PHASE_REFINE_STEPS, PHASE_VERIFY_PERTURBATIONS, PHASE_VERIFY_SEED, PHASE_VERIFY_STEP,
};
use crate::problem::{self, key_line, Problem, ProblemError};
use crate::studies::accuracy::{self, StudyAccuracy};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Bisection steps per neighbour pair ([`super::refine`]) when `refine = true` and
/// `refine_steps` is not given.
pub const DEFAULT_STEPS: usize = PHASE_REFINE_STEPS.int() as usize;

/// Largest `refine_steps`: 8 steps narrow a pair to 1/256 of its grid spacing (0.001 decades
/// on a 20-point-per-3-decades grid), finer than the regime test's own sensitivity, and each
/// step is one more simulation per pair.
pub const MAX_STEPS: usize = PHASE_REFINE_STEPS.int_range().1 as usize;

/// A parsed and validated phase file.
#[derive(Clone, Debug)]
pub struct Phase {
    /// The phase file.
    pub file: PathBuf,
    /// The base problem's path.
    pub base_path: PathBuf,
    /// The base problem.
    pub base: Problem,
    /// Hash of the effective base problem ([`crate::studies::problem_hash`]: parsed, defaults
    /// filled in; a comment does not count), the rows' resume key.
    pub base_hash: u64,
    /// Scaled weights `W` (dimensionless).
    pub weight: Vec<f64>,
    /// Scaled torques `G` (dimensionless).
    pub torque: Vec<f64>,
    /// `Some(K)`: `refine = true`, bisect the boundaries `K = refine_steps` times per
    /// neighbour pair ([`super::refine`]); `None`: boundaries through cell midpoints.
    pub refine: Option<usize>,
    /// `verify = { finer, perturbations, ... }`: each cell re-run finer and perturbed
    /// ([`Verify`]); `None` when absent or when it asks for no extra run.
    pub verify: Option<Verify>,
    /// How a cell's `W` is set and whether the cells are dynamically similar
    /// (`weight_via`, `similar`; [`Protocol`]).
    pub protocol: Protocol,
    /// `[accuracy]`, if given ([`crate::studies::accuracy`]).
    pub accuracy: Option<problem::AccuracySpec>,
    /// The model chosen for it (set by [`prepare_accuracy`]).
    pub chosen: Option<StudyAccuracy>,
    /// `growth = { ... }`: the base snake grown along a line of sizes ([`super::growth`]).
    pub growth: Option<super::allometry::Growth>,
    /// The command-line settings (`--set KEY=VALUE`, as `KEY=VALUE`) the file was read with:
    /// recorded in `phase.json`, and applied again when `merge` re-reads the file.
    pub settings: Vec<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PhaseFile {
    phase: PhaseTable,
    accuracy: Option<problem::AccuracySpec>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PhaseTable {
    base: String,
    weight: toml::Value,
    torque: toml::Value,
    #[serde(default)]
    refine: bool,
    refine_steps: Option<toml::Value>,
    verify: Option<VerifyTable>,
    weight_via: Option<String>,
    #[serde(default)]
    similar: bool,
    growth: Option<super::allometry::GrowthTable>,
}

/// `[phase] weight_via`: which physical parameter sets a cell's scaled weight
/// `W = rho g a^2 L^3 / B`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum WeightVia {
    /// The bending stiffness `B` (with `C` and `EA` scaled alike): the default, and the
    /// studies before this key.
    #[default]
    Stiffness,
    /// Gravity `g` (`B`, `rho` the base's).
    Gravity,
    /// The density `rho` (`B`, `g` the base's).
    Density,
}

/// How the grid's cells are made from the base problem ([`cell_problem_with`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Protocol {
    /// Which parameter sets `W`.
    pub weight_via: WeightVia,
    /// `similar = true`: every cell keeps the base's ratio of the pulse time `L / v_m` to the
    /// elastic time `L^2 sqrt(rho A / B)`, i.e. `v_m L sqrt(rho A / B)` constant, by setting
    /// `v_m`; the duration, step and output interval follow the pulse time.
    pub similar: bool,
}

impl Protocol {
    /// Whether this is today's protocol (`W` through `B`, no similarity): rows keyed as before.
    pub fn is_default(&self) -> bool {
        *self == Protocol::default()
    }

    /// Mix the protocol into a rows' hash (unchanged for the default protocol).
    pub fn row_hash(&self, hash: u64) -> u64 {
        if self.is_default() {
            hash
        } else {
            let text = format!(
                "{hash:016x} weight_via={:?} similar={}",
                self.weight_via, self.similar
            );
            crate::studies::fnv1a(text.as_bytes())
        }
    }
}

/// Most perturbed runs per cell (`verify.perturbations`).
pub const MAX_PERTURBATIONS: usize = PHASE_VERIFY_PERTURBATIONS.int_range().1 as usize;

/// `[phase] verify = { finer = true, perturbations = K }`: how each cell is checked
/// ([`super::cell::simulate_verified`]).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Verify {
    /// `finer` (default false): also run the cell at half the step and twice the elements;
    /// the cell's reported label (and every value of its row) is then the finer run's.
    pub finer: bool,
    /// `perturbations` (default 0, at most [`MAX_PERTURBATIONS`]): also run the cell `K`
    /// times perturbed as an ensemble ([`crate::studies::ensemble`]) at the study's resolution.
    pub perturbations: usize,
    /// `seed` (default `phase.verify.seed` of the key table, [`crate::studies::ensemble::SEED`]): the cells' seeds derive from it
    /// and the cell's `(W, G)`, so a cell's runs do not depend on the shard it is in.
    pub seed: u64,
    /// `step` (default `phase.verify.step` of the key table, [`crate::studies::ensemble::STEP`], in [1, 10]): the perturbed runs' step
    /// ladder, from `dt / step` to `dt * step`.
    pub step: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct VerifyTable {
    #[serde(default)]
    finer: bool,
    #[serde(default)]
    perturbations: i64,
    seed: Option<i64>,
    step: Option<f64>,
}

impl Verify {
    /// The perturbation sizes of the perturbed runs.
    pub fn perturbation(&self) -> crate::studies::ensemble::Perturbation {
        crate::studies::ensemble::Perturbation {
            step: self.step,
            ..Default::default()
        }
    }

    /// The resume key of a verified row: the base problem's hash mixed with the settings, so
    /// rows of another verification (or of none) are never reused.
    pub fn row_hash(&self, base_hash: u64) -> u64 {
        let text = format!(
            "{base_hash:016x} finer={} perturbations={} seed={} step={:e}",
            self.finer, self.perturbations, self.seed, self.step
        );
        crate::studies::fnv1a(text.as_bytes())
    }

    /// Runs per cell: the study's, the finer one, the perturbed ones.
    pub fn runs(&self) -> usize {
        1 + self.finer as usize + self.perturbations
    }
}

/// A grid axis as written: a list, or `{ from, to, count, spacing = "log" | "linear" }`
/// (log by default; the ends included).
fn grid_axis(v: &toml::Value) -> Result<Vec<f64>, String> {
    let num = |v: &toml::Value| v.as_float().or_else(|| v.as_integer().map(|i| i as f64));
    match v {
        toml::Value::Array(a) => a
            .iter()
            .map(|x| num(x).ok_or_else(|| format!("{x} is not a number")))
            .collect(),
        toml::Value::Table(t) => {
            for k in t.keys() {
                if !matches!(k.as_str(), "from" | "to" | "count" | "spacing") {
                    return Err(format!("unknown key `{k}` (from, to, count, spacing)"));
                }
            }
            let get = |k: &str| {
                t.get(k)
                    .and_then(num)
                    .ok_or(format!("`{k}` is missing or not a number"))
            };
            let (from, to) = (get("from")?, get("to")?);
            let count =
                t.get("count")
                    .and_then(|c| c.as_integer())
                    .filter(|&c| (1..=10_000).contains(&c))
                    .ok_or("`count` must be an integer in [1, 10000]")? as usize;
            let log = match t.get("spacing").map(|s| s.as_str()) {
                None | Some(Some("log")) => true,
                Some(Some("linear")) => false,
                _ => return Err("`spacing` must be \"log\" or \"linear\"".into()),
            };
            if !(from.is_finite() && to.is_finite()) || (count > 1 && to <= from) {
                return Err(format!("from = {from}, to = {to}: need finite from < to"));
            }
            if log && from <= 0.0 {
                return Err(format!("from = {from}: a log-spaced range needs from > 0"));
            }
            if count == 1 {
                return Ok(vec![from]);
            }
            let n = (count - 1) as f64;
            Ok((0..count)
                .map(|k| {
                    if k == count - 1 {
                        to
                    } else if log {
                        from * (to / from).powf(k as f64 / n)
                    } else {
                        from + (to - from) * k as f64 / n
                    }
                })
                .collect())
        }
        other => Err(format!("{other} is neither a list nor a range table")),
    }
}

impl Phase {
    /// The resume key of the rows of `phase.csv` and `refine.csv`: the base problem's hash,
    /// mixed with the protocol (unless the default) and the verification settings (if any).
    pub fn row_hash(&self) -> u64 {
        let h = self.protocol.row_hash(self.base_hash);
        self.verify.map_or(h, |v| v.row_hash(h))
    }

    /// The columns of the study's rows ([`super::Format::of`]).
    pub fn format(&self) -> super::Format {
        super::Format::of(&self.base, self.verify.as_ref())
    }
}

use crate::problem::limits::SCALED_GROUP_RANGE;

/// Read and validate a phase file and its base problem.
pub fn load(path: &Path) -> Result<Phase, ProblemError> {
    load_with(path, &[])
}

/// The tables of a phase file; `--set` keys below any other table edit the base problem.
pub const TABLES: [&str; 2] = ["phase", "accuracy"];

/// [`load`] with command-line settings (`--set`): those of [`TABLES`] edit the phase file,
/// the others its base problem, each validated as if written there.
pub fn load_with(path: &Path, settings: &[&problem::set::Setting]) -> Result<Phase, ProblemError> {
    let (own, base) = problem::set::split(settings, &TABLES);
    let text = problem::edit(&problem::read(path)?, path, &own)?;
    let mut ph = parse(&text, path, &base).map_err(|e| problem::set::attribute(e, &own, path))?;
    ph.settings = settings.iter().map(|s| s.arg.clone()).collect();
    Ok(ph)
}

/// Where a phase file's errors point: its text (for line numbers) and path.
struct At<'a> {
    text: &'a str,
    path: &'a Path,
}

impl At<'_> {
    /// `phase.key = value` is not allowed: `allowed` says what is.
    fn invalid(&self, key: &str, value: String, allowed: &str) -> ProblemError {
        ProblemError::Invalid {
            file: self.path.into(),
            line: key_line(self.text, "phase", key),
            key: format!("phase.{key}"),
            value,
            allowed: allowed.into(),
        }
    }
}

fn parse(
    text: &str,
    path: &Path,
    base_settings: &[&problem::set::Setting],
) -> Result<Phase, ProblemError> {
    let f: PhaseFile = problem::from_toml(text, path)?;
    let t = f.phase;
    let at = At { text, path };
    let (weight, torque) = axes(&at, &t)?;
    let steps = refine_steps(&at, &t)?;
    let verify = verify(&at, &t)?;
    let protocol = Protocol {
        weight_via: weight_via(&at, &t)?,
        similar: t.similar,
    };
    let growth = match &t.growth {
        None => None,
        Some(g) => Some(
            super::allometry::parse(g, grid_axis)
                .map_err(|(value, allowed)| at.invalid("growth", value, &allowed))?,
        ),
    };
    let (base_path, base) = base_problem(&at, &t, base_settings)?;
    if let Some(a) = &f.accuracy {
        if let Err((key, value, allowed)) = problem::check_accuracy(a, &base) {
            return Err(ProblemError::Invalid {
                file: path.into(),
                line: key_line(text, "accuracy", key),
                key: format!("accuracy.{key}"),
                value,
                allowed,
            });
        }
    }
    Ok(Phase {
        settings: Vec::new(),
        accuracy: f.accuracy,
        chosen: None,
        file: path.into(),
        base_hash: crate::studies::problem_hash(&base),
        base_path,
        base,
        weight,
        torque,
        refine: t.refine.then_some(steps),
        verify,
        protocol,
        growth,
    })
}

/// The grid's axes `weight` and `torque` (lists or ranges), each non-empty, strictly
/// increasing and in [`SCALED_GROUP_RANGE`] (a torque may be 0).
fn axes(at: &At, t: &PhaseTable) -> Result<(Vec<f64>, Vec<f64>), ProblemError> {
    let check = |key: &str, v: &[f64], ok: fn(f64) -> bool, what: &str| {
        if v.is_empty() {
            return Err(at.invalid(key, "[]".into(), &format!("a non-empty list of {what}")));
        }
        if let Some(x) = v.iter().find(|&&x| !ok(x)) {
            return Err(at.invalid(key, format!("[.. {} ..]", problem::num(*x)), what));
        }
        if v.windows(2).any(|w| w[1] <= w[0]) {
            return Err(at.invalid(
                key,
                format!("{v:?}"),
                &format!("{what}, strictly increasing"),
            ));
        }
        Ok(())
    };
    let axis = |key: &str, v: &toml::Value| {
        grid_axis(v).map_err(|why| {
            at.invalid(
                key,
                format!("{v}"),
                &format!("a list of numbers or {{ from, to, count, spacing = \"log\" | \"linear\" }}: {why}"),
            )
        })
    };
    let weight = axis("weight", &t.weight)?;
    let torque = axis("torque", &t.torque)?;
    check(
        "weight",
        &weight,
        |x| (SCALED_GROUP_RANGE.0..=SCALED_GROUP_RANGE.1).contains(&x),
        "scaled weights W in [1e-6, 1e9] (problem::limits::SCALED_GROUP_RANGE: outside it the scene is no snake on the ground)",
    )?;
    check(
        "torque",
        &torque,
        |x| x == 0.0 || (SCALED_GROUP_RANGE.0..=SCALED_GROUP_RANGE.1).contains(&x),
        "scaled torques G = 0 or in [1e-6, 1e9] (problem::limits::SCALED_GROUP_RANGE)",
    )?;
    Ok((weight, torque))
}

/// `refine_steps`: bisection steps per neighbour pair.
fn refine_steps(at: &At, t: &PhaseTable) -> Result<usize, ProblemError> {
    Ok(match &t.refine_steps {
        None => DEFAULT_STEPS,
        Some(v) => v
            .as_integer()
            .filter(|&k| k >= 0 && PHASE_REFINE_STEPS.check_int(k as u64))
            .map(|k| k as usize)
            .ok_or_else(|| {
                at.invalid(
                    "refine_steps",
                    format!("{v}"),
                    &format!(
                        "an integer in [1, {}] (bisection steps per neighbour pair; default {})",
                        MAX_STEPS, DEFAULT_STEPS
                    ),
                )
            })?,
    })
}

/// `verify = { finer, perturbations, seed, step }`: the runs per cell (`None`: one run).
fn verify(at: &At, t: &PhaseTable) -> Result<Option<Verify>, ProblemError> {
    Ok(match &t.verify {
        None => None,
        Some(v) => {
            let perturbations_ok = v.perturbations >= 0
                && PHASE_VERIFY_PERTURBATIONS.check_int(v.perturbations as u64);
            if !perturbations_ok {
                return Err(at.invalid(
                    "verify",
                    format!("{{ perturbations = {} }}", v.perturbations),
                    &format!("perturbations an integer in [0, {MAX_PERTURBATIONS}] (perturbed runs per cell)"),
                ));
            }
            if v.seed.is_some_and(|s| s < 0) {
                return Err(at.invalid(
                    "verify",
                    format!("{{ seed = {} }}", v.seed.unwrap_or(0)),
                    "seed an integer >= 0",
                ));
            }
            let step = v.step.unwrap_or(PHASE_VERIFY_STEP.real());
            if !PHASE_VERIFY_STEP.check_real(step) {
                return Err(at.invalid(
                    "verify",
                    format!("{{ step = {step} }}"),
                    "step a number in [1, 10] (the perturbed runs step from dt/step to dt*step)",
                ));
            }
            let verify = Verify {
                finer: v.finer,
                perturbations: v.perturbations as usize,
                seed: v.seed.map_or(PHASE_VERIFY_SEED.int(), |s| s as u64),
                step,
            };
            (verify.runs() > 1).then_some(verify)
        }
    })
}

/// `weight_via`: the parameter that sets W.
fn weight_via(at: &At, t: &PhaseTable) -> Result<WeightVia, ProblemError> {
    Ok(match t.weight_via.as_deref() {
        None | Some("stiffness") => WeightVia::Stiffness,
        Some("gravity") => WeightVia::Gravity,
        Some("density") => WeightVia::Density,
        Some(other) => {
            return Err(at.invalid(
                "weight_via",
                format!("\"{other}\""),
                "\"stiffness\", \"gravity\" or \"density\" (the parameter that sets W)",
            ))
        }
    })
}

/// The base problem `base` names (relative to the phase file, with the command line's
/// settings): readable, with a gait and a ground; and its path.
fn base_problem(
    at: &At,
    t: &PhaseTable,
    base_settings: &[&problem::set::Setting],
) -> Result<(PathBuf, Problem), ProblemError> {
    let path = at.path;
    let base_path = path.parent().unwrap_or(Path::new(".")).join(&t.base);
    let base_text = match problem::read(&base_path) {
        Ok(text) => text,
        Err(ProblemError::Io { source, .. }) => {
            let why = if source.kind() == std::io::ErrorKind::NotFound {
                "not found".to_string()
            } else {
                source.to_string()
            };
            return Err(at.invalid(
                "base",
                format!("\"{}\"", t.base),
                &format!(
                    "a readable problem file (relative to the phase file; {}: {why})",
                    base_path.display()
                ),
            ));
        }
        Err(e) => return Err(e),
    };
    let (_, base) = problem::parse_with(&base_text, &base_path, base_settings)?;
    if base.gait.kind == crate::gait::Kind::None {
        return Err(at.invalid(
            "base",
            format!("\"{}\"", t.base),
            "a problem with a [gait] (kind other than \"none\")",
        ));
    }
    if base.ground.is_none() {
        return Err(at.invalid(
            "base",
            format!("\"{}\"", t.base),
            "a problem with a [ground]",
        ));
    }
    Ok((base_path, base))
}

/// The base problem with scaled weight `w` and scaled torque `g` (see the module doc): `W`
/// through the bending stiffness, the default [`Protocol`].
pub fn cell_problem(base: &Problem, w: f64, g: f64) -> Problem {
    cell_problem_with(base, w, g, Protocol::default())
}

/// The base problem with scaled weight `w` and scaled torque `g` under `protocol`: `W` through
/// `B` (`C` and `EA` scaled alike), `g` or `rho`; `G` through the muscle stress,
/// `Gamma = G B / (a^3 L)`; with `similar`, `v_m = v_m0 sqrt(B rho0 / (B0 rho))` and the
/// duration, step (adaptive: its bounds) and output interval scaled by `v_m0 / v_m`.
pub fn cell_problem_with(base: &Problem, w: f64, g: f64, protocol: Protocol) -> Problem {
    let mut p = base.clone();
    let r = &base.rod;
    let (a2l3, gravity) = (r.diameter.powi(2) * r.length.powi(3), base.gravity.g);
    match protocol.weight_via {
        WeightVia::Stiffness => {
            let b = r.density * gravity * a2l3 / w;
            let k = b / r.bending_stiffness;
            p.rod.bending_stiffness = b;
            p.rod.twist_stiffness = r.twist_stiffness.map(|c| c * k);
            p.rod.stretch_stiffness = r.stretch_stiffness.map(|ea| ea * k);
        }
        WeightVia::Gravity => p.gravity.g = w * r.bending_stiffness / (r.density * a2l3),
        WeightVia::Density => p.rod.density = w * r.bending_stiffness / (gravity * a2l3),
    }
    let b = p.rod.bending_stiffness;
    p.gait.stress = g * b / (r.diameter.powi(3) * r.length);
    if protocol.similar {
        let factor = ((b / r.bending_stiffness) * (r.density / p.rod.density)).sqrt();
        p.gait.speed = base.gait.speed * factor;
        // Times follow the pulse time L / v_m.
        super::allometry::scale_times(&mut p, 1.0 / factor);
    }
    p
}

/// The finer problem of a cell's verification: half the step (an adaptive run: an eighth of
/// the error tolerance, which halves the steps of a second-order method, local error ~ h^3)
/// and twice the elements.
pub fn finer_problem(p: &Problem) -> Problem {
    let mut f = p.clone();
    f.rod.elements *= 2;
    if f.time.adaptive {
        let tol = f
            .time
            .error_tolerance
            .unwrap_or(problem::time::DEFAULT_TOLERANCE);
        f.time.error_tolerance = Some(tol / 8.0);
    } else if let Some(dt) = f.time.dt {
        f.time.dt = Some(dt / 2.0);
    }
    f
}

/// Apply the phase file's `[accuracy]` before the sweep (as
/// [`crate::studies::optimize::prepare_accuracy`] does for an optimisation): every cell runs at the
/// chosen model, and the rows' resume key is the model's. Without `[accuracy]`, removes a stale
/// `accuracy.json` and changes nothing. Returns whether a recorded choice was reused.
pub fn prepare_accuracy(
    ph: &mut Phase,
    out: &Path,
    log: &mut dyn FnMut(&str),
) -> std::io::Result<bool> {
    let Some(spec) = ph.accuracy.clone() else {
        accuracy::forget(out)?;
        return Ok(false);
    };
    let file_hash = format!("{:016x}", ph.base_hash);
    let (chosen, reused) = accuracy::choose(&ph.base, &file_hash, &spec, out, log)?;
    ph.base = chosen.apply(&ph.base);
    ph.base_hash = chosen.row_hash();
    ph.chosen = Some(chosen);
    Ok(reused)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cell_problem_sets_the_groups_and_keeps_the_ratios() {
        let base = problem::load(Path::new("problems/s_start.toml")).unwrap();
        let p = cell_problem(&base, 1234.0, 7.5);
        let r = &p.rod;
        let w =
            r.density * p.gravity.g * r.diameter.powi(2) * r.length.powi(3) / r.bending_stiffness;
        let g = p.gait.stress * r.diameter.powi(3) * r.length / r.bending_stiffness;
        assert!((w / 1234.0 - 1.0).abs() < 1e-12, "W {w}");
        assert!((g / 7.5 - 1.0).abs() < 1e-12, "G {g}");
        let c0 = base.rod.twist_stiffness.unwrap() / base.rod.bending_stiffness;
        let c1 = r.twist_stiffness.unwrap() / r.bending_stiffness;
        assert!((c1 / c0 - 1.0).abs() < 1e-12);
        let e0 = base.rod.stretch_stiffness.unwrap() / base.rod.bending_stiffness;
        let e1 = r.stretch_stiffness.unwrap() / r.bending_stiffness;
        assert!((e1 / e0 - 1.0).abs() < 1e-12);
        assert_eq!(p.gait.speed, base.gait.speed);
        assert_eq!(p.rod.length, base.rod.length);
    }

    fn groups(p: &Problem) -> (f64, f64, f64) {
        let r = &p.rod;
        let w =
            r.density * p.gravity.g * r.diameter.powi(2) * r.length.powi(3) / r.bending_stiffness;
        let g = p.gait.stress * r.diameter.powi(3) * r.length / r.bending_stiffness;
        let area = std::f64::consts::PI * r.diameter.powi(2) / 4.0;
        let similarity = p.gait.speed * r.length * (r.density * area / r.bending_stiffness).sqrt();
        (w, g, similarity)
    }

    #[test]
    fn every_protocol_sets_the_groups_and_similar_keeps_the_time_ratio() {
        let base = problem::load(Path::new("problems/s_start.toml")).unwrap();
        let (_, _, s0) = groups(&base);
        for via in [WeightVia::Stiffness, WeightVia::Gravity, WeightVia::Density] {
            for similar in [false, true] {
                let pr = Protocol {
                    weight_via: via,
                    similar,
                };
                for (w, g) in [(30.0, 8.0), (2336.0, 61.6)] {
                    let p = cell_problem_with(&base, w, g, pr);
                    let (wp, gp, s) = groups(&p);
                    assert!((wp / w - 1.0).abs() < 1e-12, "{pr:?}: W {wp}");
                    assert!((gp / g - 1.0).abs() < 1e-12, "{pr:?}: G {gp}");
                    // Only the named parameter moves.
                    assert_eq!(p.rod.density == base.rod.density, via != WeightVia::Density);
                    assert_eq!(p.gravity.g == base.gravity.g, via != WeightVia::Gravity);
                    assert_eq!(
                        p.rod.bending_stiffness == base.rod.bending_stiffness,
                        via != WeightVia::Stiffness
                    );
                    if similar {
                        assert!((s / s0 - 1.0).abs() < 1e-12, "{pr:?}: {s} vs {s0}");
                        // The run lasts the same number of pulse times and steps.
                        let pulses = |q: &Problem| q.time.duration.unwrap() * q.gait.speed;
                        assert!((pulses(&p) / pulses(&base) - 1.0).abs() < 1e-12);
                        let steps = |q: &Problem| q.time.duration.unwrap() / q.time.dt.unwrap();
                        assert!((steps(&p) / steps(&base) - 1.0).abs() < 1e-9);
                    } else {
                        assert_eq!(p.gait.speed, base.gait.speed);
                        assert_eq!(p.time.dt, base.time.dt);
                    }
                }
            }
        }
        // The default protocol is cell_problem's, and keys rows as before.
        let d = cell_problem_with(&base, 300.0, 15.0, Protocol::default());
        assert_eq!(
            format!("{d:?}"),
            format!("{:?}", cell_problem(&base, 300.0, 15.0))
        );
        assert_eq!(Protocol::default().row_hash(42), 42);
        let gravity = Protocol {
            weight_via: WeightVia::Gravity,
            similar: false,
        };
        assert_ne!(gravity.row_hash(42), 42);
    }
}
