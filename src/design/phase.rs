//! The regime phase diagram (MODEL section 6): the locomotion regime (S, M, F, N, U; criteria
//! in [`crate::observe::regime`]) and the forward speed over scaled weight `W = rho g a^2 L^3 / B` and
//! scaled torque `G = Gamma a^3 L / B`.
//!
//! A phase file names a base problem with a gait and the grid:
//!
//! ```toml
//! [phase]
//! base = "s_start.toml"                 # problem file, relative to the phase file
//! weight = [100.0, 300.0, 1000.0]       # scaled weights W, each > 0
//! torque = [5.0, 10.0, 15.0, 20.0]      # scaled torques G, each >= 0
//! refine = false                        # bisect the boundaries between neighbouring cells
//! refine_steps = 3                      # bisection steps per neighbour pair, 1 to 8
//! ```
//!
//! `refine` (default `false`): after the grid, bisect every pair of neighbouring cells of
//! different regimes along the line joining them (a ray of constant `G` for neighbours in `W`,
//! of constant `W` for neighbours in `G`), `refine_steps` times (default
//! [`super::refine::DEFAULT_STEPS`], an integer in 1 to [`super::refine::MAX_STEPS`], checked
//! even when `refine = false`, which ignores it), simulating the base scene at each log-midpoint, and fit the boundary lines
//! through the bisected points instead of the cell midpoints ([`super::refine`]; the
//! simulations go to `refine.csv`). A sharded run (`--shard I/N`, `N > 1`) never refines: it
//! lacks the rest of the grid; [`merge`] refines when the shards' phase file asked for it.
//!
//! Each cell keeps the base's geometry, density, gravity, friction, gait shape, pulse speed and
//! time stepping. `W` is set through the bending stiffness, `B = rho g a^2 L^3 / W`, with the
//! twist and stretching stiffnesses scaled by the same factor (so `C/B` and `EA a^2/B` stay the
//! base's); `G` through the muscle stress, `Gamma = G B / (a^3 L)`.
//!
//! Cells run in parallel (rayon) and each finished cell is appended to `phase.csv` at once, so
//! a sweep that is interrupted keeps every finished cell; a rerun into the same directory
//! reuses the rows whose base file (hashed) and `(W, G)` match and simulates only the rest. A
//! cell whose simulation fails is recorded with status `failed` and its reason, and is not
//! retried on resume (the failure is deterministic).

use crate::gait::Kind;
use crate::model::Model;
use crate::observe::{self, Regime, RegimeInputs};
use crate::problem::{self, key_line, Problem, ProblemError};
use crate::{plot, sim};
use plotters::prelude::*;
use rayon::prelude::*;
use serde::Deserialize;
use std::collections::HashMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// A parsed and validated phase file.
#[derive(Clone, Debug)]
pub struct Phase {
    /// The phase file.
    pub file: PathBuf,
    /// The base problem's path.
    pub base_path: PathBuf,
    /// The base problem.
    pub base: Problem,
    /// Hash of the base problem's text (resume key).
    pub base_hash: u64,
    /// Scaled weights `W` (dimensionless).
    pub weight: Vec<f64>,
    /// Scaled torques `G` (dimensionless).
    pub torque: Vec<f64>,
    /// `Some(K)`: `refine = true`, bisect the boundaries `K = refine_steps` times per
    /// neighbour pair ([`super::refine`]); `None`: boundaries through cell midpoints.
    pub refine: Option<usize>,
    /// `[accuracy]`, if given ([`super::accuracy`]).
    pub accuracy: Option<problem::AccuracySpec>,
    /// The model chosen for it (set by [`super::accuracy::prepare_phase`]).
    pub chosen: Option<super::accuracy::StudyAccuracy>,
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

/// Read and validate a phase file and its base problem.
pub fn load(path: &Path) -> Result<Phase, ProblemError> {
    let text = problem::read(path)?;
    let f: PhaseFile = problem::from_toml(&text, path)?;
    let t = f.phase;
    let invalid = |key: &str, value: String, allowed: &str| ProblemError::Invalid {
        file: path.into(),
        line: key_line(&text, "phase", key),
        key: format!("phase.{key}"),
        value,
        allowed: allowed.into(),
    };
    let check = |key: &str, v: &[f64], ok: fn(f64) -> bool, what: &str| {
        if v.is_empty() {
            return Err(invalid(
                key,
                "[]".into(),
                &format!("a non-empty list of {what}"),
            ));
        }
        if let Some(x) = v.iter().find(|&&x| !ok(x)) {
            return Err(invalid(key, format!("[.. {x} ..]"), what));
        }
        if v.windows(2).any(|w| w[1] <= w[0]) {
            return Err(invalid(
                key,
                format!("{v:?}"),
                &format!("{what}, strictly increasing"),
            ));
        }
        Ok(())
    };
    let axis = |key: &str, v: &toml::Value| {
        grid_axis(v).map_err(|why| {
            invalid(
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
        |x| x.is_finite() && x > 0.0,
        "scaled weights W > 0",
    )?;
    check(
        "torque",
        &torque,
        |x| x.is_finite() && x >= 0.0,
        "scaled torques G >= 0",
    )?;
    let steps = match &t.refine_steps {
        None => super::refine::DEFAULT_STEPS,
        Some(v) => v
            .as_integer()
            .filter(|k| (1..=super::refine::MAX_STEPS as i64).contains(k))
            .map(|k| k as usize)
            .ok_or_else(|| {
                invalid(
                    "refine_steps",
                    format!("{v}"),
                    &format!(
                        "an integer in [1, {}] (bisection steps per neighbour pair; default {})",
                        super::refine::MAX_STEPS,
                        super::refine::DEFAULT_STEPS
                    ),
                )
            })?,
    };
    let base_path = path.parent().unwrap_or(Path::new(".")).join(&t.base);
    let base_text = match problem::read(&base_path) {
        Ok(text) => text,
        Err(ProblemError::Io { source, .. }) => {
            let why = if source.kind() == std::io::ErrorKind::NotFound {
                "not found".to_string()
            } else {
                source.to_string()
            };
            return Err(invalid(
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
    let base = problem::parse(&base_text, &base_path)?;
    if base.gait.kind == Kind::None {
        return Err(invalid(
            "base",
            format!("\"{}\"", t.base),
            "a problem with a [gait] (kind other than \"none\")",
        ));
    }
    if base.ground.is_none() {
        return Err(invalid(
            "base",
            format!("\"{}\"", t.base),
            "a problem with a [ground]",
        ));
    }
    if let Some(a) = &f.accuracy {
        if let Err((key, value, allowed)) = problem::check_accuracy(a, &base) {
            return Err(ProblemError::Invalid {
                file: path.into(),
                line: key_line(&text, "accuracy", key),
                key: format!("accuracy.{key}"),
                value,
                allowed,
            });
        }
    }
    Ok(Phase {
        accuracy: f.accuracy,
        chosen: None,
        file: path.into(),
        base_hash: super::fnv1a(base_text.as_bytes()),
        base_path,
        base,
        weight,
        torque,
        refine: t.refine.then_some(steps),
    })
}

/// The base problem with scaled weight `w` and scaled torque `g` (see the module doc).
pub fn cell_problem(base: &Problem, w: f64, g: f64) -> Problem {
    let mut p = base.clone();
    let r = &base.rod;
    let b = r.density * base.gravity.g * r.diameter.powi(2) * r.length.powi(3) / w;
    let k = b / r.bending_stiffness;
    p.rod.bending_stiffness = b;
    p.rod.twist_stiffness = r.twist_stiffness.map(|c| c * k);
    p.rod.stretch_stiffness = r.stretch_stiffness.map(|ea| ea * k);
    p.gait.stress = g * b / (r.diameter.powi(3) * r.length);
    p
}

/// One cell of the diagram.
#[derive(Clone, Debug)]
pub struct Cell {
    /// Scaled weight `W`.
    pub weight: f64,
    /// Scaled torque `G`.
    pub torque: f64,
    /// Whether the cell's simulation finished (written "ok" or "failed").
    pub status: crate::design::Status,
    /// Regime (`None` when failed; written "-").
    pub regime: Option<Regime>,
    /// For `M`: the S criteria it missed, `;`-separated (e.g. "pulse_speed;heading"); "-"
    /// otherwise.
    pub regime_detail: String,
    /// `v_s / v_m`.
    pub v_s_over_v_m: f64,
    /// Angle of the net displacement from the initial head direction (degrees).
    pub displacement_angle_deg: f64,
    /// Largest elevation over `a`.
    pub max_elevation_over_a: f64,
    /// Most arcs lifted at least `a/2` at one instant.
    pub lifted_arcs_max: usize,
    /// Largest |writhe| (turns).
    pub writhe_max: f64,
    /// `R^2` of the `lambda` pulse fit.
    pub lambda_pulse_r2: f64,
    /// Largest elevation over `L`.
    pub max_elevation_over_length: f64,
    /// Height over `a` of the lower of two arcs around a ground contact (see
    /// [`observe::Observables::two_arc_lift_over_a`]).
    pub two_arc_lift_over_a: f64,
    /// Speed of the `lambda` pulse over `v_m`.
    pub lambda_pulse_speed_over_v_m: f64,
    /// Writhe when couple b is at mid-body (turns; [`observe::Observables::writhe_snapshot`]).
    pub writhe_snapshot: f64,
    /// Wall time of the simulation (s).
    pub wall_time_s: f64,
    /// Why it failed (empty when ok).
    pub reason: String,
}

/// Header of `phase.csv` (the column order is fixed; units in the README).
pub const HEADER: &str = "weight,torque,W_over_G,status,regime,v_s_over_v_m,displacement_angle_deg,max_elevation_over_a,lifted_arcs_max,writhe_max,lambda_pulse_r2,regime_detail,max_elevation_over_length,two_arc_lift_over_a,lambda_pulse_speed_over_v_m,writhe_snapshot,wall_time_s,base_hash,reason";

/// Number of columns of [`HEADER`].
const COLUMNS: usize = 19;

impl Cell {
    fn failed(w: f64, g: f64, reason: String) -> Self {
        Cell {
            weight: w,
            torque: g,
            status: crate::design::Status::Failed,
            regime: None,
            regime_detail: "-".into(),
            v_s_over_v_m: f64::NAN,
            displacement_angle_deg: f64::NAN,
            max_elevation_over_a: f64::NAN,
            lifted_arcs_max: 0,
            writhe_max: f64::NAN,
            lambda_pulse_r2: f64::NAN,
            max_elevation_over_length: f64::NAN,
            two_arc_lift_over_a: f64::NAN,
            lambda_pulse_speed_over_v_m: f64::NAN,
            writhe_snapshot: f64::NAN,
            wall_time_s: 0.0,
            reason,
        }
    }

    /// The stored values the regime depends on (relabelling without simulating).
    pub fn regime_inputs(&self) -> RegimeInputs {
        RegimeInputs {
            v_s_over_v_m: self.v_s_over_v_m,
            displacement_angle_deg: self.displacement_angle_deg,
            max_elevation_over_a: self.max_elevation_over_a,
            max_elevation_over_length: self.max_elevation_over_length,
            two_arc_lift_over_a: self.two_arc_lift_over_a,
            lambda_pulse_r2: self.lambda_pulse_r2,
            lambda_pulse_speed_over_v_m: self.lambda_pulse_speed_over_v_m,
        }
    }

    /// The cell as a `phase.csv` row (no newline) for the base file with hash `hash`.
    pub(crate) fn row(&self, hash: u64) -> String {
        let clean = super::csv_field(&self.reason);
        format!(
            "{:e},{:e},{:e},{},{},{:e},{:e},{:e},{},{:e},{:e},{},{:e},{:e},{:e},{:e},{:.3},{:016x},{}",
            self.weight,
            self.torque,
            self.weight / self.torque,
            self.status.as_str(),
            self.regime.map_or("-", Regime::as_str),
            self.v_s_over_v_m,
            self.displacement_angle_deg,
            self.max_elevation_over_a,
            self.lifted_arcs_max,
            self.writhe_max,
            self.lambda_pulse_r2,
            self.regime_detail,
            self.max_elevation_over_length,
            self.two_arc_lift_over_a,
            self.lambda_pulse_speed_over_v_m,
            self.writhe_snapshot,
            self.wall_time_s,
            hash,
            clean
        )
    }

    fn parse(line: &str) -> Option<(Cell, u64)> {
        let f: Vec<&str> = line.splitn(COLUMNS, ',').collect();
        if f.len() != COLUMNS {
            return None;
        }
        let num = |i: usize| f[i].parse::<f64>().ok();
        Some((
            Cell {
                weight: num(0)?,
                torque: num(1)?,
                status: crate::design::Status::parse(f[3])?,
                regime: match f[4] {
                    "-" => None,
                    r => Some(r.parse().ok()?),
                },
                regime_detail: f[11].into(),
                v_s_over_v_m: num(5)?,
                displacement_angle_deg: num(6)?,
                max_elevation_over_a: num(7)?,
                lifted_arcs_max: f[8].parse().ok()?,
                writhe_max: num(9)?,
                lambda_pulse_r2: num(10)?,
                max_elevation_over_length: num(12)?,
                two_arc_lift_over_a: num(13)?,
                lambda_pulse_speed_over_v_m: num(14)?,
                writhe_snapshot: num(15)?,
                wall_time_s: num(16)?,
                reason: f[18].into(),
            },
            u64::from_str_radix(f[17], 16).ok()?,
        ))
    }
}

/// Simulate one cell (never panics: a panic inside the simulation is recorded as a failure).
pub fn simulate(base: &Problem, w: f64, g: f64) -> Cell {
    let p = cell_problem(base, w, g);
    let run = std::panic::catch_unwind(|| {
        let m = Model::new(&p);
        let o = sim::run_gait(&m, p.solver.integrator, &mut |_| {}, &mut |_| {})?;
        let fl = observe::fields(&m, &o.frames);
        Ok::<_, crate::integrator::explicit::Unsupported>((observe::observe(&m, &o.frames, &fl), o))
    });
    match run {
        Err(_) => Cell::failed(w, g, "the simulation panicked".into()),
        Ok(Err(e)) => Cell::failed(w, g, e.to_string()),
        Ok(Ok((_, o))) if o.error.is_some() => {
            let mut c = Cell::failed(w, g, o.error.unwrap().to_string());
            c.wall_time_s = o.wall_time_s;
            c
        }
        Ok(Ok((ob, o))) => Cell {
            weight: w,
            torque: g,
            status: crate::design::Status::Ok,
            regime: Some(ob.regime),
            regime_detail: if ob.regime_reason.not_s.is_empty() {
                "-".into()
            } else {
                let names: Vec<&str> = ob.regime_reason.not_s.iter().map(|c| c.as_str()).collect();
                names.join(";")
            },
            // Defined at G = 0 too (the observable is NaN without a gait): v_m is the base's.
            v_s_over_v_m: ob.v_s / p.gait.speed,
            displacement_angle_deg: ob.displacement_angle_deg,
            max_elevation_over_a: ob.max_elevation_over_a,
            lifted_arcs_max: ob.lifted_arcs_max,
            writhe_max: ob.writhe_max,
            lambda_pulse_r2: ob.lambda_pulse_r2,
            max_elevation_over_length: ob.max_elevation_over_length,
            two_arc_lift_over_a: ob.two_arc_lift_over_a,
            lambda_pulse_speed_over_v_m: ob.lambda_pulse_speed_over_v_m,
            writhe_snapshot: ob.writhe_snapshot,
            wall_time_s: o.wall_time_s,
            reason: String::new(),
        },
    }
}

/// Errors of a sweep's bookkeeping (the simulations' own failures are recorded in the cells).
#[derive(Debug, thiserror::Error)]
pub enum PhaseError {
    /// Reading or writing an output file failed.
    #[error("{file}: {source}")]
    Io {
        /// The file.
        file: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// An existing `phase.csv` that is not ours.
    #[error("{file}:{line}: not a row of a phase study (expected the columns {HEADER}); move the file away or choose another --out")]
    Csv {
        /// The file.
        file: PathBuf,
        /// 1-based line.
        line: usize,
    },
    /// A directory cannot be merged with the others.
    #[error("{dir}: cannot merge: {why}")]
    Merge {
        /// The directory.
        dir: PathBuf,
        /// Why.
        why: String,
    },
    /// The merged directories do not cover the grid.
    #[error("the shards miss {count} cells of the grid: {cells}; run the missing shards (or rerun them into their directories) and merge again")]
    Missing {
        /// Number of missing cells.
        count: usize,
        /// The first ten.
        cells: String,
    },
    /// A figure could not be drawn.
    #[error("{file}: {source}")]
    Plot {
        /// The figure.
        file: PathBuf,
        /// The plotting error.
        source: plot::PlotError,
    },
}

/// What a sweep produced.
#[derive(Debug)]
pub struct Sweep {
    /// Every cell, weight-major (`cells[i * torque.len() + j]` is `(weight[i], torque[j])`).
    pub cells: Vec<Cell>,
    /// Cells simulated in this call.
    pub simulated: usize,
    /// Cells reused from an existing `phase.csv`.
    pub reused: usize,
    /// An incomplete last line of `phase.csv` (a write cut short by a crash) was dropped.
    pub dropped_partial_row: bool,
    /// The bisection of the boundaries, when the phase file asked for it and the run holds the
    /// whole grid.
    pub refinement: Option<super::refine::Refinement>,
}

/// Finished cells of an existing `phase.csv`, keyed by the bits of `(W, G)`.
#[derive(Debug, Default)]
pub struct PhaseCsv {
    /// Rows written for the base file with hash `base_hash`.
    pub cells: HashMap<(u64, u64), Cell>,
    /// The file did not exist or held nothing (not even a complete header).
    pub fresh: bool,
    /// An incomplete last line (no newline: a write cut short) was cut off the file.
    pub dropped_partial_row: bool,
}

/// Read `phase.csv` for resuming: rows of other base files are skipped; a last line without
/// its newline (a row cut short by a crash) is removed from the file, so the next row is not
/// glued onto it; any other line that is not a row is [`PhaseError::Csv`] naming it.
pub fn read_phase_csv(csv: &Path, base_hash: u64) -> Result<PhaseCsv, PhaseError> {
    let r = read_rows(csv)?;
    Ok(PhaseCsv {
        cells: r
            .rows
            .into_iter()
            .filter(|(_, h)| *h == base_hash)
            .map(|(c, _)| ((c.weight.to_bits(), c.torque.to_bits()), c))
            .collect(),
        fresh: r.fresh,
        dropped_partial_row: r.dropped_partial_row,
    })
}

/// Every row of a `phase.csv` or `refine.csv` (the same columns), in file order.
#[derive(Debug, Default)]
pub struct Rows {
    /// The rows, each with the hash of the base file it was simulated for.
    pub rows: Vec<(Cell, u64)>,
    /// The file did not exist or held nothing (not even a complete header).
    pub fresh: bool,
    /// An incomplete last line (no newline: a write cut short) was cut off the file.
    pub dropped_partial_row: bool,
}

/// Open a study's CSV of rows (`phase.csv`, `refine.csv`) for appending, writing the header
/// first when the file is `fresh`. Rows are then written one per `write_all` and flushed, so a
/// crash leaves whole lines or a torn last one ([`read_rows`] drops it).
pub(super) fn append_rows(csv: &Path, fresh: bool) -> Result<std::fs::File, PhaseError> {
    let io = |source| PhaseError::Io {
        file: csv.to_path_buf(),
        source,
    };
    let mut file = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(csv)
        .map_err(io)?;
    if fresh {
        file.write_all(format!("{HEADER}\n").as_bytes())
            .and_then(|_| file.flush())
            .map_err(io)?;
    }
    Ok(file)
}

/// Read every row of a `phase.csv` or `refine.csv` (of any base file), cutting a torn last line
/// off the file as [`read_phase_csv`] does.
pub fn read_rows(csv: &Path) -> Result<Rows, PhaseError> {
    let io = |source| PhaseError::Io {
        file: csv.to_path_buf(),
        source,
    };
    let mut out = Rows::default();
    let bytes = match std::fs::read(csv) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            out.fresh = true;
            return Ok(out);
        }
        Err(e) => return Err(io(e)),
    };
    let mut keep = bytes.len();
    if !bytes.is_empty() && !bytes.ends_with(b"\n") {
        keep = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
        std::fs::OpenOptions::new()
            .write(true)
            .open(csv)
            .and_then(|f| f.set_len(keep as u64))
            .map_err(io)?;
        out.dropped_partial_row = true;
    }
    let text = match std::str::from_utf8(&bytes[..keep]) {
        Ok(t) => t,
        Err(e) => {
            let at = e.valid_up_to();
            return Err(PhaseError::Csv {
                file: csv.to_path_buf(),
                line: 1 + bytes[..at].iter().filter(|&&b| b == b'\n').count(),
            });
        }
    };
    out.fresh = text.is_empty();
    for (n, line) in text.lines().enumerate() {
        if n == 0 {
            if line != HEADER {
                return Err(PhaseError::Csv {
                    file: csv.to_path_buf(),
                    line: 1,
                });
            }
            continue;
        }
        if line.trim().is_empty() {
            continue;
        }
        let row = Cell::parse(line).ok_or(PhaseError::Csv {
            file: csv.to_path_buf(),
            line: n + 1,
        })?;
        out.rows.push(row);
    }
    Ok(out)
}

/// One share of a sweep's cells: `index` of `count` (1-based), for spreading a study over a
/// job array. Cell `k` of the grid (weight-major) belongs to shard `k % count + 1`: a
/// deterministic split in which every cell is in exactly one shard.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Shard {
    /// This shard, 1..=count.
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

impl Shard {
    /// Whether grid cell `k` (weight-major) is in this shard.
    pub fn owns(&self, k: usize) -> bool {
        k % self.count == self.index - 1
    }
}

impl std::str::FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || format!("`{s}`: a shard is I/N with integers 1 <= I <= N (e.g. 2/4)");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count) = (
            i.trim().parse::<usize>().map_err(|_| bad())?,
            n.trim().parse::<usize>().map_err(|_| bad())?,
        );
        if index == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

/// `phase.json`: what a sweep directory holds, so shards can be checked before merging.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunInfo {
    /// The phase file.
    pub phase_file: String,
    /// The base problem file.
    pub base_file: String,
    /// Hash of the base problem's text (hex).
    pub base_hash: String,
    /// Scaled weights of the grid.
    pub weight: Vec<f64>,
    /// Scaled torques of the grid.
    pub torque: Vec<f64>,
    /// The shard this directory holds (`null`: every cell).
    pub shard: Option<Shard>,
    /// Bisection steps of `refine = true` (`null`: no refinement); [`merge`] refines with it.
    #[serde(default)]
    pub refine_steps: Option<usize>,
    /// The model chosen for the phase file's `[accuracy]` (absent without one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accuracy: Option<super::accuracy::StudyAccuracy>,
}

fn write_info(out: &Path, info: &RunInfo) -> Result<(), PhaseError> {
    let file = out.join("phase.json");
    let text = serde_json::to_string_pretty(info).expect("serialisable");
    std::fs::write(&file, text + "\n").map_err(|source| PhaseError::Io { file, source })
}

/// Run the diagram into `out` (`phase.csv`, `phase.json`, `boundaries.json` and the figures,
/// each as PNG and SVG, and with `refine = true` `refine.csv`), reusing finished rows.
/// `report(done, total, cell)` is called after each newly simulated cell of the grid,
/// `refine_report(done, cell)` after each new refinement simulation.
pub fn sweep(
    ph: &Phase,
    out: &Path,
    report: &(dyn Fn(usize, usize, &Cell) + Sync),
    refine_report: &(dyn Fn(usize, &Cell) + Sync),
) -> Result<Sweep, PhaseError> {
    sweep_shard(ph, out, None, report, refine_report)
}

/// [`sweep`] of one shard's cells only (all with `None`). A shard's directory gets
/// `phase.csv` and `phase.json` but no figures and no refinement (unless it is the only shard,
/// `1/1`); [`merge`] combines the shards.
pub fn sweep_shard(
    ph: &Phase,
    out: &Path,
    shard: Option<Shard>,
    report: &(dyn Fn(usize, usize, &Cell) + Sync),
    refine_report: &(dyn Fn(usize, &Cell) + Sync),
) -> Result<Sweep, PhaseError> {
    let io = |file: &Path| {
        let file = file.to_path_buf();
        move |source| PhaseError::Io {
            file: file.clone(),
            source,
        }
    };
    std::fs::create_dir_all(out).map_err(io(out))?;
    let csv = out.join("phase.csv");
    let key = |w: f64, g: f64| (w.to_bits(), g.to_bits());
    let old = read_phase_csv(&csv, ph.base_hash)?;
    let mut done = old.cells;
    let file = append_rows(&csv, old.fresh)?;
    write_info(
        out,
        &RunInfo {
            phase_file: ph.file.display().to_string(),
            base_file: ph.base_path.display().to_string(),
            base_hash: format!("{:016x}", ph.base_hash),
            weight: ph.weight.clone(),
            torque: ph.torque.clone(),
            shard,
            refine_steps: ph.refine,
            accuracy: ph.chosen.clone(),
        },
    )?;
    let grid: Vec<(f64, f64)> = ph
        .weight
        .iter()
        .flat_map(|&w| ph.torque.iter().map(move |&g| (w, g)))
        .enumerate()
        .filter(|(k, _)| shard.is_none_or(|s| s.owns(*k)))
        .map(|(_, c)| c)
        .collect();
    let todo: Vec<(f64, f64)> = grid
        .iter()
        .copied()
        .filter(|&(w, g)| !done.contains_key(&key(w, g)))
        .collect();
    let reused = grid.len() - todo.len();
    let sink = Mutex::new((file, 0usize, None::<std::io::Error>));
    let new: Vec<Cell> = todo
        .par_iter()
        .map(|&(w, g)| {
            let c = simulate(&ph.base, w, g);
            let mut s = sink.lock().unwrap_or_else(|e| e.into_inner());
            let line = c.row(ph.base_hash) + "\n";
            let r = s.0.write_all(line.as_bytes()).and_then(|_| s.0.flush());
            if let Err(e) = r {
                s.2.get_or_insert(e);
            }
            s.1 += 1;
            report(s.1, todo.len(), &c);
            c
        })
        .collect();
    if let Some(e) = sink.into_inner().unwrap_or_else(|e| e.into_inner()).2 {
        return Err(io(&csv)(e));
    }
    let simulated = new.len();
    for c in new {
        done.insert(key(c.weight, c.torque), c);
    }
    let cells: Vec<Cell> = grid
        .iter()
        .map(|&(w, g)| done[&key(w, g)].clone())
        .collect();
    let refinement = if shard.is_none_or(|s| s.count == 1) {
        let refine = ph.refine.map(|k| (&ph.base, ph.base_hash, k));
        finish(out, &ph.weight, &ph.torque, &cells, refine, refine_report)?
    } else {
        None
    };
    Ok(Sweep {
        cells,
        simulated,
        reused,
        dropped_partial_row: old.dropped_partial_row,
        refinement,
    })
}

/// The end of a run that holds the whole grid: the boundary points (bisected when `refine`
/// gives the base problem, its hash and the steps; else the cell midpoints), `boundaries.json`
/// and the figures.
fn finish(
    out: &Path,
    weight: &[f64],
    torque: &[f64],
    cells: &[Cell],
    refine: Option<(&Problem, u64, usize)>,
    refine_report: &(dyn Fn(usize, &Cell) + Sync),
) -> Result<Option<super::refine::Refinement>, PhaseError> {
    // A grid in which every cell failed has nothing to fit or draw: the command line reports
    // it (exit 3, "every cell failed") instead of a plot error.
    if cells.iter().all(|c| c.status != crate::design::Status::Ok) {
        return Ok(None);
    }
    let refinement = match refine {
        Some((base, hash, steps)) => Some(super::refine::refine(
            base,
            hash,
            steps,
            out,
            weight,
            torque,
            cells,
            refine_report,
        )?),
        None => None,
    };
    let bounds = match &refinement {
        Some(r) => fit_boundaries(&r.points),
        None => {
            let labels: Vec<Option<Regime>> = cells.iter().map(|c| c.regime).collect();
            boundaries(weight, torque, &labels)
        }
    };
    figures(out, weight, torque, cells, &bounds)?;
    Ok(refinement)
}

/// The figures of a complete grid, each as PNG and SVG (`phase`, `speed`, Fig. 3a-c), and
/// `boundaries.json` (the lines `bounds`).
fn figures(
    out: &Path,
    weight: &[f64],
    torque: &[f64],
    cells: &[Cell],
    bounds: &[Boundary],
) -> Result<(), PhaseError> {
    let file = out.join("boundaries.json");
    let text = serde_json::to_string_pretty(bounds).expect("serialisable");
    std::fs::write(&file, text + "\n").map_err(|source| PhaseError::Io { file, source })?;
    for ext in ["png", "svg"] {
        let f = out.join(format!("phase.{ext}"));
        regime_map(&f, weight, torque, cells, bounds)
            .map_err(|source| PhaseError::Plot { file: f, source })?;
        let f = out.join(format!("speed.{ext}"));
        speed_chart(&f, torque, cells).map_err(|source| PhaseError::Plot { file: f, source })?;
        fig3(out, ext, torque, cells)?;
    }
    Ok(())
}

/// A fitted boundary between two regimes: the line `log10 G = slope log10 W + intercept`
/// (least squares in `log10 G`) through the points where it crosses the segments between
/// neighbouring cells with these two labels: their log-midpoints, or with `[phase] refine =
/// true` the points bisection placed ([`super::refine`]). The paper's boundaries are lines of
/// constant `W/G`: slope 1.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Boundary {
    /// The two regimes, e.g. "F/N" (alphabetical).
    pub pair: String,
    /// How the points were placed: `"bisection"` when at least one point was bisected,
    /// `"midpoints"` otherwise (no refinement, or every bisection failed at its first step).
    pub method: &'static str,
    /// Slope in log-log (`None` with fewer than two distinct weights among the points).
    pub slope: Option<f64>,
    /// Intercept of `log10 G` at `log10 W = 0`.
    pub intercept: Option<f64>,
    /// `W/G` on the line at `G = 10`.
    pub ratio_at_g10: Option<f64>,
    /// Root-mean-square residual of `log10 G` (decades).
    pub residual: Option<f64>,
    /// The neighbouring cells `[[W, G], [W, G]]` whose crossings were fitted.
    pub cells: Vec<[[f64; 2]; 2]>,
    /// The fitted points: `W`, `G`, the axis each was located along, its half-width (decades
    /// along that axis), method, bisection steps and failure (see [`super::refine::Point`]).
    pub points: Vec<super::refine::Point>,
}

/// Fit every boundary between neighbouring cells (along W and along G, cells with `G > 0`) of
/// a weight-major grid of labels (`None`: failed cell, not used), through the cell pairs'
/// log-midpoints.
pub fn boundaries(weight: &[f64], torque: &[f64], labels: &[Option<Regime>]) -> Vec<Boundary> {
    fit_boundaries(&super::refine::midpoint_points(weight, torque, labels))
}

/// Fit one line per regime pair through its points (midpoints or bisected), by least squares in
/// `log10 G` against `log10 W`; the lines in alphabetical order of their pairs.
pub fn fit_boundaries(points: &[super::refine::Point]) -> Vec<Boundary> {
    let mut pairs: std::collections::BTreeMap<&str, Vec<super::refine::Point>> = Default::default();
    for p in points {
        pairs.entry(p.pair.as_str()).or_default().push(p.clone());
    }
    pairs
        .into_iter()
        .map(|(pair, points)| {
            let pts: Vec<(f64, f64)> = points.iter().map(|p| (p.w.log10(), p.g.log10())).collect();
            let n = pts.len() as f64;
            let (mx, my) = (
                pts.iter().map(|p| p.0).sum::<f64>() / n,
                pts.iter().map(|p| p.1).sum::<f64>() / n,
            );
            let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
            let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
            let fit = (sxx > 1e-12).then(|| {
                let slope = sxy / sxx;
                let intercept = my - slope * mx;
                let rms = (pts
                    .iter()
                    .map(|p| (p.1 - slope * p.0 - intercept).powi(2))
                    .sum::<f64>()
                    / n)
                    .sqrt();
                (slope, intercept, rms)
            });
            let bisected = points
                .iter()
                .any(|p| p.method == super::refine::Method::Bisection);
            Boundary {
                pair: pair.to_string(),
                method: if bisected { "bisection" } else { "midpoints" },
                slope: fit.map(|f| f.0),
                intercept: fit.map(|f| f.1),
                ratio_at_g10: fit
                    .filter(|f| f.0.abs() > 1e-12)
                    .map(|(s, c, _)| 10f64.powf((1.0 - c) / s) / 10.0),
                residual: fit.map(|f| f.2),
                cells: points.iter().map(|p| p.cells).collect(),
                points,
            }
        })
        .collect()
}

/// The paper's Fig. 3 from the cells: (a) `writhe_vs_ratio.png`, the largest writhe and the
/// writhe at the snapshot instant against `W/G`, one series per torque; (b)
/// `speed_vs_writhe.png`, `v_s/v_m` against the largest writhe, one series per regime; (c)
/// `speed_vs_ratio.png`, `v_s/v_m` against `W/G` (as `speed.png`). Failed cells are left out;
/// a figure with no finite point is skipped. `ext` is the file type, `png` or `svg`.
fn fig3(out: &Path, ext: &str, torque: &[f64], cells: &[Cell]) -> Result<(), PhaseError> {
    let ok: Vec<&Cell> = cells
        .iter()
        .filter(|c| c.status == crate::design::Status::Ok && c.torque > 0.0)
        .collect();
    let plot_err = |file: PathBuf| move |source| PhaseError::Plot { file, source };
    let skip_empty = |r: Result<(), PhaseError>| match r {
        Err(PhaseError::Plot {
            source: plot::PlotError::Invalid(_),
            ..
        }) => Ok(()),
        r => r,
    };
    // (a)
    let mut names = Vec::new();
    let mut pts = Vec::new();
    for g in shown_torques(torque).into_iter().filter(|&g| g > 0.0) {
        let mut max: Vec<(f64, f64)> = Vec::new();
        let mut snap: Vec<(f64, f64)> = Vec::new();
        for c in ok.iter().filter(|c| c.torque == g) {
            max.push((c.weight / c.torque, c.writhe_max));
            snap.push((c.weight / c.torque, c.writhe_snapshot));
        }
        max.sort_by(|a, b| a.0.total_cmp(&b.0));
        snap.sort_by(|a, b| a.0.total_cmp(&b.0));
        names.push(format!("G = {}: Wr max", short(g)));
        pts.push(max);
        names.push(format!("G = {}: Wr at snapshot", short(g)));
        pts.push(snap);
    }
    let series: Vec<(&str, Vec<(f64, f64)>)> = names.iter().map(String::as_str).zip(pts).collect();
    let png = out.join(format!("writhe_vs_ratio.{ext}"));
    skip_empty(
        plot::xy(
            &png,
            "Writhe against W/G (Fig. 3a)",
            "W / G",
            "writhe (turns)",
            &series,
            true,
            false,
        )
        .map_err(plot_err(png.clone())),
    )?;
    // (b)
    let regimes = [Regime::S, Regime::M, Regime::F, Regime::N, Regime::U];
    let by_regime: Vec<(String, Vec<(f64, f64)>)> = regimes
        .iter()
        .map(|&r| {
            (
                r.as_str().to_string(),
                ok.iter()
                    .filter(|c| c.regime == Some(r))
                    .map(|c| (c.writhe_max, c.v_s_over_v_m))
                    .collect(),
            )
        })
        .filter(|(_, p): &(String, Vec<(f64, f64)>)| !p.is_empty())
        .collect();
    let series: Vec<(&str, Vec<(f64, f64)>)> = by_regime
        .iter()
        .map(|(n, p)| (n.as_str(), p.clone()))
        .collect();
    let png = out.join(format!("speed_vs_writhe.{ext}"));
    skip_empty(
        plot::scatter(
            &png,
            "Speed against writhe, by regime (Fig. 3b)",
            "largest writhe Wr max (turns)",
            "v_s / v_m",
            &series,
        )
        .map_err(plot_err(png.clone())),
    )?;
    // (c)
    let png = out.join(format!("speed_vs_ratio.{ext}"));
    speed_chart(&png, torque, cells).map_err(plot_err(png.clone()))
}

/// What [`merge`] combined.
#[derive(Debug)]
pub struct Merged {
    /// Every cell, weight-major.
    pub cells: Vec<Cell>,
    /// Cells found in more than one directory (with identical results).
    pub duplicates: usize,
    /// The bisection of the boundaries, when the shards' phase file asked for it.
    pub refinement: Option<super::refine::Refinement>,
}

/// Combine the `phase.csv` of shard directories (of one phase file and base problem, checked
/// with their `phase.json`) into `out`: the same `phase.csv` (rows in grid order),
/// `phase.json` and figures as an unsharded run. Refuses directories of other grids or base
/// files, cells found twice with different results, and a grid with missing cells (listed).
/// When the shards ran a phase file with `refine = true` (their `phase.json`), the boundaries
/// are bisected here, into `out/refine.csv` (resumable as in an unsharded run), with the base
/// problem read again from the file named in `phase.json` (refused if its text changed since:
/// hash). `refine_report(done, cell)` is called after each refinement simulation.
pub fn merge(
    dirs: &[PathBuf],
    out: &Path,
    refine_report: &(dyn Fn(usize, &Cell) + Sync),
) -> Result<Merged, PhaseError> {
    let mismatch = |dir: &Path, why: String| PhaseError::Merge {
        dir: dir.to_path_buf(),
        why,
    };
    let mut reference: Option<RunInfo> = None;
    let mut found: HashMap<(u64, u64), (Cell, String)> = HashMap::new();
    let mut duplicates = 0;
    for dir in dirs {
        let file = dir.join("phase.json");
        let text = std::fs::read_to_string(&file).map_err(|e| {
            mismatch(
                dir,
                format!("no readable phase.json ({e}): not a `slither phase` output directory"),
            )
        })?;
        let info: RunInfo = serde_json::from_str(&text)
            .map_err(|e| mismatch(dir, format!("phase.json is not valid: {e}")))?;
        match &reference {
            None => reference = Some(info.clone()),
            Some(r) => {
                if r.base_hash != info.base_hash {
                    return Err(mismatch(
                        dir,
                        format!(
                            "base problem {} (hash {}) differs from {} (hash {})",
                            info.base_file, info.base_hash, r.base_file, r.base_hash
                        ),
                    ));
                }
                if r.refine_steps != info.refine_steps {
                    let say = |k: Option<usize>| {
                        k.map_or("refine = false".to_string(), |k| {
                            format!("refine = true, refine_steps = {k}")
                        })
                    };
                    return Err(mismatch(
                        dir,
                        format!(
                            "ran with {}, another directory with {}",
                            say(info.refine_steps),
                            say(r.refine_steps)
                        ),
                    ));
                }
                if r.weight != info.weight || r.torque != info.torque {
                    return Err(mismatch(
                        dir,
                        format!(
                            "grid W {:?} x G {:?} differs from W {:?} x G {:?}",
                            info.weight, info.torque, r.weight, r.torque
                        ),
                    ));
                }
            }
        }
        let hash = u64::from_str_radix(&info.base_hash, 16)
            .map_err(|_| mismatch(dir, "phase.json: base_hash is not hexadecimal".into()))?;
        for (key, c) in read_phase_csv(&dir.join("phase.csv"), hash)?.cells {
            let row = comparable_row(&c, hash);
            match found.get(&key) {
                Some((_, seen)) if *seen == row => duplicates += 1,
                Some(_) => {
                    return Err(mismatch(
                        dir,
                        format!(
                        "cell W = {}, G = {} is also in another directory with a different result",
                        c.weight, c.torque
                    ),
                    ))
                }
                None => {
                    found.insert(key, (c, row));
                }
            }
        }
    }
    let info =
        reference.ok_or_else(|| mismatch(Path::new("."), "no directories to merge".into()))?;
    let grid: Vec<(f64, f64)> = info
        .weight
        .iter()
        .flat_map(|&w| info.torque.iter().map(move |&g| (w, g)))
        .collect();
    let missing: Vec<String> = grid
        .iter()
        .filter(|(w, g)| !found.contains_key(&(w.to_bits(), g.to_bits())))
        .map(|(w, g)| format!("(W {w}, G {g})"))
        .collect();
    if !missing.is_empty() {
        return Err(PhaseError::Missing {
            count: missing.len(),
            cells: missing
                .iter()
                .take(10)
                .cloned()
                .collect::<Vec<_>>()
                .join(", "),
        });
    }
    let hash = u64::from_str_radix(&info.base_hash, 16).expect("checked above");
    // The base problem, for the refinement's simulations: the file the shards ran, unchanged.
    let base = match info.refine_steps {
        None => None,
        Some(_) => {
            let path = PathBuf::from(&info.base_file);
            let refuse = |why: String| PhaseError::Merge {
                dir: path.clone(),
                why: format!("cannot refine the boundaries (refine = true): {why}"),
            };
            let text = std::fs::read_to_string(&path).map_err(|e| {
                refuse(format!(
                    "the base problem named in phase.json is not readable ({e}); merge from the directory the shards ran in"
                ))
            })?;
            // With `[accuracy]` the rows are keyed by the file and the chosen model: the file
            // is checked against the choice's own record, and refined at that model.
            let (file_hash, shards_hash) = match &info.accuracy {
                Some(c) => (
                    u64::from_str_radix(&c.base_file_hash, 16).ok(),
                    c.base_file_hash.clone(),
                ),
                None => (Some(hash), info.base_hash.clone()),
            };
            if Some(super::fnv1a(text.as_bytes())) != file_hash {
                return Err(refuse(format!(
                    "the base problem changed since the shards ran (hash {:016x}, the shards' {})",
                    super::fnv1a(text.as_bytes()),
                    shards_hash
                )));
            }
            let base = problem::parse(&text, &path).map_err(|e| refuse(e.to_string()))?;
            Some(match &info.accuracy {
                Some(c) => c.apply(&base),
                None => base,
            })
        }
    };
    let cells: Vec<Cell> = grid
        .iter()
        .map(|(w, g)| found[&(w.to_bits(), g.to_bits())].0.clone())
        .collect();
    std::fs::create_dir_all(out).map_err(|source| PhaseError::Io {
        file: out.to_path_buf(),
        source,
    })?;
    let mut text = format!("{HEADER}\n");
    for c in &cells {
        text += &(c.row(hash) + "\n");
    }
    let csv = out.join("phase.csv");
    std::fs::write(&csv, text).map_err(|source| PhaseError::Io { file: csv, source })?;
    write_info(
        out,
        &RunInfo {
            shard: None,
            ..info.clone()
        },
    )?;
    let refine = base
        .as_ref()
        .zip(info.refine_steps)
        .map(|(b, k)| (b, hash, k));
    let refinement = finish(
        out,
        &info.weight,
        &info.torque,
        &cells,
        refine,
        refine_report,
    )?;
    Ok(Merged {
        cells,
        duplicates,
        refinement,
    })
}

/// A cell's row without its wall time (what must agree between two runs of one cell).
pub fn comparable_row(c: &Cell, hash: u64) -> String {
    let row = c.row(hash);
    let mut f: Vec<&str> = row.split(',').collect();
    if f.len() > 16 {
        f[16] = "";
    }
    f.join(",")
}

/// Colour of a regime in the map (dark grey for a failed cell).
pub fn regime_color(r: Option<Regime>) -> RGBColor {
    match r {
        Some(Regime::S) => RGBColor(90, 180, 100),
        Some(Regime::M) => RGBColor(100, 150, 230),
        Some(Regime::F) => RGBColor(240, 170, 80),
        Some(Regime::N) => RGBColor(190, 190, 190),
        Some(Regime::U) => RGBColor(220, 80, 80),
        None => RGBColor(60, 60, 60),
    }
}

/// How many cells have each regime (in [`Regime::ALL`] order), and how many failed.
pub fn regime_counts(cells: &[Cell]) -> ([(Regime, usize); 5], usize) {
    let count = |r: Regime| cells.iter().filter(|c| c.regime == Some(r)).count();
    (
        Regime::ALL.map(|r| (r, count(r))),
        cells.iter().filter(|c| c.regime.is_none()).count(),
    )
}

/// Cell edges on a log axis: geometric midpoints, the ends mirrored.
fn log_edges(c: &[f64]) -> Vec<f64> {
    let n = c.len();
    if n == 1 {
        return vec![c[0] / 2.0_f64.sqrt(), c[0] * 2.0_f64.sqrt()];
    }
    let mut e = vec![c[0] * (c[0] / c[1]).sqrt()];
    e.extend(c.windows(2).map(|w| (w[0] * w[1]).sqrt()));
    e.push(c[n - 1] * (c[n - 1] / c[n - 2]).sqrt());
    e
}

/// Cell edges on a linear axis: midpoints, the ends mirrored.
fn lin_edges(c: &[f64]) -> Vec<f64> {
    let n = c.len();
    if n == 1 {
        return vec![
            c[0] - 0.5 * c[0].abs().max(1.0),
            c[0] + 0.5 * c[0].abs().max(1.0),
        ];
    }
    let mut e = vec![c[0] - 0.5 * (c[1] - c[0])];
    e.extend(c.windows(2).map(|w| 0.5 * (w[0] + w[1])));
    e.push(c[n - 1] + 0.5 * (c[n - 1] - c[n - 2]));
    e
}

/// Grids with more weight columns than this label each cell with its regime letter only (the
/// `v_s/v_m` value and the M detail no longer fit in a cell of the 1000 px wide map).
pub const FULL_LABEL_MAX_COLUMNS: usize = 8;

/// Colours of the fitted boundary lines on the map, in `boundaries.json` order.
/// (Ten: the five regimes have at most ten neighbouring pairs, so no two lines share one.)
const BOUNDARY_COLORS: [RGBColor; 10] = [
    RGBColor(0, 0, 0),
    RGBColor(150, 30, 150),
    RGBColor(20, 70, 170),
    RGBColor(160, 60, 0),
    RGBColor(0, 120, 120),
    RGBColor(110, 110, 0),
    RGBColor(230, 0, 120),
    RGBColor(0, 170, 230),
    RGBColor(120, 70, 30),
    RGBColor(90, 90, 90),
];

/// The part of the line `log10 G = slope log10 W + intercept` inside the box `[lw0, lw1] x
/// [lg0, lg1]` (log10 coordinates), as 64 points `(W, G)`; `None` if it misses the box.
pub fn boundary_segment(
    slope: f64,
    intercept: f64,
    (lw0, lw1): (f64, f64),
    (lg0, lg1): (f64, f64),
) -> Option<Vec<(f64, f64)>> {
    let (mut a, mut b) = (lw0, lw1);
    if slope.abs() > 1e-12 {
        let (x0, x1) = ((lg0 - intercept) / slope, (lg1 - intercept) / slope);
        a = a.max(x0.min(x1));
        b = b.min(x0.max(x1));
    } else if !(lg0..=lg1).contains(&intercept) {
        return None;
    }
    (a < b && a.is_finite() && b.is_finite()).then(|| {
        (0..64)
            .map(|k| {
                let x = a + (b - a) * k as f64 / 63.0;
                (10f64.powf(x), 10f64.powf(slope * x + intercept))
            })
            .collect()
    })
}

/// The regime map (`phase.png` / `phase.svg`, by the extension of `path`): one coloured
/// rectangle per cell on log-log axes (log W across, log G up; a linear G axis when the grid
/// has `G = 0`), each labelled with the regime and `v_s / v_m` (and, for `M`, the S criteria it
/// missed; only the regime letter on grids wider than [`FULL_LABEL_MAX_COLUMNS`]), the fitted
/// regime boundaries of `boundaries.json` drawn as lines, and on the right a legend of the
/// regimes with their cell counts and of the boundary lines with slope and `W/G` at `G = 10`.
fn regime_map(
    path: &Path,
    weight: &[f64],
    torque: &[f64],
    cells: &[Cell],
    bounds: &[Boundary],
) -> Result<(), plot::PlotError> {
    plot::register_fonts()?;
    let err = |e: &dyn std::fmt::Display| plot::PlotError::Draw(e.to_string());
    let log_g = torque.iter().all(|&g| g > 0.0);
    let xe = log_edges(weight);
    let ye = if log_g {
        log_edges(torque)
    } else {
        lin_edges(torque)
    };
    crate::on_backend!(path, (1400, 800), |root| {
        root.fill(&WHITE).map_err(|e| err(&e))?;
        let (left, right) = root.split_horizontally(1000);
        let (xr, yr) = (xe[0]..xe[xe.len() - 1], ye[0]..ye[ye.len() - 1]);
        if log_g {
            let yr = yr.log_scale();
            map_body(&left, xr, yr, &xe, &ye, torque, cells, bounds, true)?;
        } else {
            map_body(&left, xr, yr, &xe, &ye, torque, cells, bounds, false)?;
        }
        map_legend(&right, cells, bounds)?;
        root.present().map_err(|e| err(&e))
    })
}

/// Cells, labels and boundary lines of [`regime_map`] on any backend and G axis.
#[allow(clippy::too_many_arguments)]
fn map_body<DB, Y>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    xr: std::ops::Range<f64>,
    yr: Y,
    xe: &[f64],
    ye: &[f64],
    torque: &[f64],
    cells: &[Cell],
    bounds: &[Boundary],
    log_g: bool,
) -> Result<(), plot::PlotError>
where
    DB: DrawingBackend,
    Y: plotters::coord::ranged1d::AsRangedCoord<Value = f64>,
    Y::CoordDescType: plotters::coord::ranged1d::ValueFormatter<f64>,
{
    use plotters::style::text_anchor::{HPos, Pos, VPos};
    let err = |e: &dyn std::fmt::Display| plot::PlotError::Draw(e.to_string());
    let mut chart = ChartBuilder::on(area)
        .caption(
            "Regime over scaled weight and scaled torque",
            ("sans-serif", 24),
        )
        .margin(20)
        .x_label_area_size(60)
        .y_label_area_size(80)
        .build_cartesian_2d(xr.log_scale(), yr)
        .map_err(|e| err(&e))?;
    let tick = |v: &f64| {
        if *v >= 1.0 && *v < 1e5 && v.fract() == 0.0 {
            format!("{v}")
        } else {
            format!("{v:.3}")
                .trim_end_matches('0')
                .trim_end_matches('.')
                .to_string()
        }
    };
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("scaled weight W = rho g a^2 L^3 / B (log)")
        .y_desc(if log_g {
            "scaled torque G = Gamma a^3 L / B (log)"
        } else {
            "scaled torque G = Gamma a^3 L / B"
        })
        .x_labels(12)
        .y_labels(12)
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .label_style(("sans-serif", 18))
        .axis_desc_style(("sans-serif", 22))
        .draw()
        .map_err(|e| err(&e))?;
    let centred = |px: u32| {
        ("sans-serif", px)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Center))
    };
    let nt = torque.len();
    let full = xe.len() - 1 <= FULL_LABEL_MAX_COLUMNS;
    let mid = |a: f64, b: f64| if log_g { (a * b).sqrt() } else { 0.5 * (a + b) };
    for (k, c) in cells.iter().enumerate() {
        let (i, j) = (k / nt, k % nt);
        let rect = [(xe[i], ye[j]), (xe[i + 1], ye[j + 1])];
        chart
            .draw_series([
                Rectangle::new(rect, regime_color(c.regime).filled()),
                Rectangle::new(rect, WHITE.stroke_width(if full { 2 } else { 1 })),
            ])
            .map_err(|e| err(&e))?;
        let ok = c.status == crate::design::Status::Ok;
        let label = match c.regime {
            Some(r) if ok && full => format!("{r} {:.3}", c.v_s_over_v_m),
            Some(r) if ok => r.to_string(),
            _ if full => "failed".into(),
            _ => "x".into(),
        };
        let (x, y) = ((xe[i] * xe[i + 1]).sqrt(), mid(ye[j], ye[j + 1]));
        let detail = (full && c.regime == Some(Regime::M))
            .then(|| c.regime_detail.replace('_', " ").replace(';', ", "));
        // Two lines in an M cell: the label a sixth of the cell above the centre, the detail
        // a sixth below (in the axis's own scale).
        let (above, below) = if log_g {
            let f = (ye[j + 1] / ye[j]).powf(0.15);
            (y * f, y / f)
        } else {
            let d = 0.15 * (ye[j + 1] - ye[j]);
            (y + d, y - d)
        };
        let px = if full { 17 } else { 13 };
        let y_label = if detail.is_some() { above } else { y };
        chart
            .draw_series(std::iter::once(Text::new(label, (x, y_label), centred(px))))
            .map_err(|e| err(&e))?;
        if let Some(d) = detail {
            chart
                .draw_series(std::iter::once(Text::new(d, (x, below), centred(14))))
                .map_err(|e| err(&e))?;
        }
    }
    let (lw, lg) = (
        (xe[0].log10(), xe[xe.len() - 1].log10()),
        if log_g {
            (ye[0].log10(), ye[ye.len() - 1].log10())
        } else {
            (
                ye[0].max(1e-3 * ye[ye.len() - 1]).log10(),
                ye[ye.len() - 1].log10(),
            )
        },
    );
    for (k, b) in bounds.iter().enumerate() {
        let (Some(s), Some(c)) = (b.slope, b.intercept) else {
            continue;
        };
        let col = BOUNDARY_COLORS[k % BOUNDARY_COLORS.len()];
        if let Some(seg) = boundary_segment(s, c, lw, lg) {
            chart
                .draw_series(LineSeries::new(seg, col.stroke_width(4)))
                .map_err(|e| err(&e))?;
        }
        // Bisected points: where the boundary was found, as dots of the line's colour.
        if b.method == "bisection" {
            chart
                .draw_series(
                    b.points
                        .iter()
                        .map(|p| Circle::new((p.w, p.g), 5, col.filled())),
                )
                .map_err(|e| err(&e))?;
        }
    }
    Ok(())
}

/// The legend of [`regime_map`]: regimes with cell counts, then the boundary lines.
fn map_legend<DB: DrawingBackend>(
    right: &DrawingArea<DB, plotters::coord::Shift>,
    cells: &[Cell],
    bounds: &[Boundary],
) -> Result<(), plot::PlotError> {
    use plotters::style::text_anchor::{HPos, Pos, VPos};
    let err = |e: &dyn std::fmt::Display| plot::PlotError::Draw(e.to_string());
    let (counts, failed) = regime_counts(cells);
    let left_style = |px: u32| {
        ("sans-serif", px)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Left, VPos::Center))
    };
    let mut y = 60;
    let nw = cells.len()
        / cells
            .iter()
            .filter(|c| c.weight == cells[0].weight)
            .count()
            .max(1);
    let what = if nw <= FULL_LABEL_MAX_COLUMNS {
        "cell label: regime and v_s/v_m"
    } else {
        "cell label: regime"
    };
    right
        .draw(&Text::new(what, (10, y), left_style(16)))
        .map_err(|e| err(&e))?;
    y += 30;
    right
        .draw(&Text::new("regime (cells)", (10, y), left_style(18)))
        .map_err(|e| err(&e))?;
    let rows = counts
        .iter()
        .map(|&(r, n)| (Some(r), format!("{r}: {} ({n})", r.description())))
        .chain((failed > 0).then(|| (None, format!("failed ({failed})"))));
    for (r, text) in rows {
        y += 34;
        right
            .draw(&Rectangle::new(
                [(10, y - 11), (34, y + 11)],
                regime_color(r).filled(),
            ))
            .map_err(|e| err(&e))?;
        right
            .draw(&Text::new(text, (44, y), left_style(18)))
            .map_err(|e| err(&e))?;
    }
    let fitted: Vec<(usize, &Boundary)> = bounds
        .iter()
        .enumerate()
        .filter(|(_, b)| b.slope.is_some())
        .collect();
    if fitted.is_empty() {
        return Ok(());
    }
    y += 60;
    right
        .draw(&Text::new(
            "fitted boundaries (log G = s log W + c)",
            (10, y),
            left_style(16),
        ))
        .map_err(|e| err(&e))?;
    for (k, b) in fitted {
        y += 30;
        let col = BOUNDARY_COLORS[k % BOUNDARY_COLORS.len()];
        right
            .draw(&PathElement::new(
                vec![(10, y), (34, y)],
                col.stroke_width(4),
            ))
            .map_err(|e| err(&e))?;
        let ratio = b.ratio_at_g10.map_or("-".to_string(), |r| {
            if (0.01..1e5).contains(&r.abs()) {
                short(r)
            } else {
                format!("{r:.1e}")
            }
        });
        let text = format!(
            "{}: s = {:.2}, W/G {} at G = 10 ({} {})",
            b.pair,
            b.slope.unwrap_or(f64::NAN),
            ratio,
            b.points.len(),
            if b.method == "bisection" {
                "bisected"
            } else {
                "pairs"
            }
        );
        right
            .draw(&Text::new(text, (44, y), left_style(15)))
            .map_err(|e| err(&e))?;
    }
    Ok(())
}

/// Most torques drawn as separate series in the speed and writhe charts: a finer grid shows
/// this many, evenly spread over the grid's indices (first and last included), so the legend
/// stays readable; the regime map and `phase.csv` keep every cell.
pub const MAX_TORQUE_SERIES: usize = 6;

/// The torques drawn as series: all when at most [`MAX_TORQUE_SERIES`], else that many spread
/// evenly over the indices.
pub fn shown_torques(torque: &[f64]) -> Vec<f64> {
    let n = torque.len();
    if n <= MAX_TORQUE_SERIES {
        return torque.to_vec();
    }
    let m = MAX_TORQUE_SERIES;
    (0..m)
        .map(|i| torque[(i * (n - 1) + (m - 1) / 2) / (m - 1)])
        .collect()
}

/// A grid value for a legend: 3 significant digits (`G = 2.64`, `G = 100`).
fn short(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let dec = (2 - v.abs().log10().floor() as i32).clamp(0, 6) as usize;
    let s = format!("{v:.dec$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// `v_s / v_m` against `W / G` (the paper's speed chart), one series per torque (at most
/// [`MAX_TORQUE_SERIES`], see [`shown_torques`]).
fn speed_chart(path: &Path, torque: &[f64], cells: &[Cell]) -> Result<(), plot::PlotError> {
    let torque = shown_torques(torque);
    let names: Vec<String> = torque
        .iter()
        .map(|&g| format!("G = {}", short(g)))
        .collect();
    let series: Vec<(&str, Vec<(f64, f64)>)> = torque
        .iter()
        .zip(&names)
        .map(|(&g, name)| {
            let mut pts: Vec<(f64, f64)> = cells
                .iter()
                .filter(|c| c.torque == g && c.status == crate::design::Status::Ok)
                .map(|c| (c.weight / c.torque, c.v_s_over_v_m))
                .collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            (name.as_str(), pts)
        })
        .collect();
    plot::xy(
        path,
        "Forward speed against weight over torque",
        "W / G = rho g L^2 / (Gamma a)",
        "v_s / v_m",
        &series,
        true,
        false,
    )
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

    #[test]
    fn boundaries_of_labels_set_by_w_over_g_have_slope_one() {
        // Labels set by W/G alone (S below 20, F up to 60, N beyond): straight boundaries of
        // slope 1 in log-log, at W/G 20 and 60 (to the grid's resolution).
        let weight: Vec<f64> = (0..12).map(|k| 10f64.powf(1.0 + k as f64 / 4.0)).collect();
        let torque: Vec<f64> = (0..8).map(|k| 10f64.powf(0.5 + k as f64 / 8.0)).collect();
        let labels: Vec<Option<Regime>> = weight
            .iter()
            .flat_map(|&w| {
                torque.iter().map(move |&g| {
                    Some(match w / g {
                        r if r < 20.0 => Regime::S,
                        r if r < 60.0 => Regime::F,
                        _ => Regime::N,
                    })
                })
            })
            .collect();
        let b = boundaries(&weight, &torque, &labels);
        let names: Vec<&str> = b.iter().map(|b| b.pair.as_str()).collect();
        assert_eq!(names, ["F/N", "F/S"]);
        for (bd, ratio) in b.iter().zip([60.0, 20.0]) {
            let s = bd.slope.unwrap();
            let r = bd.ratio_at_g10.unwrap();
            assert!((s - 1.0).abs() < 0.1, "{}: slope {s}", bd.pair);
            assert!((r / ratio).log10().abs() < 0.15, "{}: W/G {r}", bd.pair);
        }
        // A boundary that is not of constant W/G (labels by W alone) has slope far from 1.
        let by_w: Vec<Option<Regime>> = weight
            .iter()
            .flat_map(|&w| {
                torque
                    .iter()
                    .map(move |_| Some(if w < 300.0 { Regime::S } else { Regime::N }))
            })
            .collect();
        let b = boundaries(&weight, &torque, &by_w);
        assert!(b[0].slope.is_none_or(|s| s.abs() > 5.0), "{:?}", b[0].slope);
    }

    #[test]
    fn rows_round_trip() {
        let c = Cell {
            weight: 300.0,
            torque: 15.0,
            status: crate::design::Status::Failed,
            regime: None,
            regime_detail: "-".into(),
            v_s_over_v_m: f64::NAN,
            displacement_angle_deg: 12.5,
            max_elevation_over_a: 0.25,
            lifted_arcs_max: 2,
            writhe_max: 0.1,
            lambda_pulse_r2: 0.9,
            max_elevation_over_length: 0.005,
            two_arc_lift_over_a: 0.125,
            lambda_pulse_speed_over_v_m: 1.32,
            writhe_snapshot: -0.375,
            wall_time_s: 1.5,
            reason: "step rejected, at t = 1\nagain".into(),
        };
        let row = c.row(0xabc);
        assert_eq!(row.split(',').count(), HEADER.split(',').count(), "{row}");
        let (d, h) = Cell::parse(&row).unwrap();
        assert_eq!(h, 0xabc);
        assert_eq!((d.weight, d.torque, d.lifted_arcs_max), (300.0, 15.0, 2));
        assert!(d.v_s_over_v_m.is_nan());
        assert_eq!(d.regime, None);
        assert_eq!(d.displacement_angle_deg, 12.5);
        let (di, ci) = (d.regime_inputs(), c.regime_inputs());
        assert!(di.v_s_over_v_m.is_nan());
        assert_eq!(
            RegimeInputs {
                v_s_over_v_m: 0.0,
                ..di
            },
            RegimeInputs {
                v_s_over_v_m: 0.0,
                ..ci
            }
        );
        assert_eq!(d.writhe_snapshot, -0.375);
        assert_eq!(d.reason, "step rejected; at t = 1;again");
        // An M cell keeps its label and the criteria it missed.
        let m = Cell {
            status: crate::design::Status::Ok,
            regime: Some(Regime::M),
            regime_detail: "heading;pulse_speed".into(),
            v_s_over_v_m: 0.29,
            reason: String::new(),
            ..c
        };
        let (d, _) = Cell::parse(&m.row(1)).unwrap();
        assert_eq!(d.regime, Some(Regime::M));
        assert_eq!(d.regime_detail, "heading;pulse_speed");
        assert_eq!(d.v_s_over_v_m, 0.29);
        assert_eq!(d.regime_inputs(), m.regime_inputs());
        // A label that is not a regime is not a row.
        let bad = m.row(1).replacen(",M,", ",X,", 1);
        assert!(Cell::parse(&bad).is_none());
    }

    #[test]
    fn a_fine_grid_shows_six_torques_spread_over_it() {
        let g: Vec<f64> = (0..20).map(|i| i as f64).collect();
        let shown = shown_torques(&g);
        assert_eq!(shown.len(), MAX_TORQUE_SERIES);
        assert_eq!(shown[0], 0.0);
        assert_eq!(shown[5], 19.0);
        assert!(shown.windows(2).all(|w| w[1] - w[0] >= 3.0), "{shown:?}");
        assert_eq!(shown_torques(&g[..4]), g[..4].to_vec());
        assert_eq!(short(2.636650898730358), "2.64");
        assert_eq!(short(100.0), "100");
        assert_eq!(short(14.38449888287663), "14.4");
    }

    #[test]
    fn boundary_segments_stay_in_the_box_and_on_the_line() {
        let (lw, lg) = ((1.0, 4.0), (0.0, 2.0));
        // Slope 1 through W/G = 30: enters at G = 1 (W = 30), leaves at G = 100 (W = 3000).
        let c = -(30f64.log10());
        let seg = boundary_segment(1.0, c, lw, lg).unwrap();
        for &(w, g) in &seg {
            assert!((w.log10() + c - g.log10()).abs() < 1e-12);
            assert!(w.log10() >= lw.0 - 1e-12 && w.log10() <= lw.1 + 1e-12);
            assert!(g.log10() >= lg.0 - 1e-12 && g.log10() <= lg.1 + 1e-12);
        }
        assert!((seg[0].0 - 30.0).abs() < 1e-9 && (seg[63].0 - 3000.0).abs() < 1e-6);
        // A line above the box, and a flat line outside it, are not drawn.
        assert!(boundary_segment(1.0, 5.0, lw, lg).is_none());
        assert!(boundary_segment(0.0, 3.0, lw, lg).is_none());
        // A flat line inside spans the whole weight axis.
        let flat = boundary_segment(0.0, 1.0, lw, lg).unwrap();
        assert!((flat[0].0 - 10.0).abs() < 1e-9 && (flat[63].0 - 1e4).abs() < 1e-6);
    }

    #[test]
    fn edges_enclose_the_centres() {
        let c = [100.0, 300.0, 1000.0];
        let e = log_edges(&c);
        assert_eq!(e.len(), 4);
        for i in 0..3 {
            assert!(e[i] < c[i] && c[i] < e[i + 1]);
        }
        let e = lin_edges(&[5.0, 10.0, 20.0]);
        assert_eq!(e, vec![2.5, 7.5, 15.0, 25.0]);
    }
}
