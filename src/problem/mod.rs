//! Problem files: the TOML schema (SI units), its defaults, and validation.
//!
//! Every field is documented with its meaning, unit and default. Tables and fields may be
//! omitted where a default exists; unknown keys are rejected. [`load`] parses and validates a
//! file and returns errors that name the file, the key, its line and the allowed range.

mod derived;
mod gait;
mod ground;
mod initial;
pub mod keys;
pub mod limits;
pub mod ranges;
pub mod reference;
mod self_contact;
pub mod set;
mod solver;
pub mod study_keys;
pub mod time;
mod validate;

use validate::{validate, Checker};

pub use gait::{GaitSpec, Kind};
pub use ground::GroundSpec;
pub use initial::{InitialSpec, Shape};
pub use self_contact::SelfContactSpec;
pub use solver::{
    set_overrides, ContactKind, GroundPoints, IntegratorKind, Overrides, SolverSpec,
    RETIRED_ACTIVE_SET,
};
pub use time::Adaptive;

use serde::Deserialize;
use std::path::{Path, PathBuf};

/// A whole problem file.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Problem {
    /// The rod (required table).
    pub rod: RodSpec,
    /// Initial shape and velocity.
    #[serde(default)]
    pub initial: InitialSpec,
    /// Gravity.
    #[serde(default)]
    pub gravity: GravitySpec,
    /// Time integration (required table).
    pub time: TimeSpec,
    /// What is written and how often.
    #[serde(default)]
    pub output: OutputSpec,
    /// Newton solver settings.
    #[serde(default)]
    pub solver: SolverSpec,
    /// The ground; absent: no ground, no contact.
    pub ground: Option<GroundSpec>,
    /// Self-contact (on by default).
    #[serde(default)]
    pub self_contact: SelfContactSpec,
    /// Muscle activation (gait). Default: none.
    #[serde(default)]
    pub gait: GaitSpec,
    /// Accuracy target: `slither run` picks the tolerance and the mesh
    /// (`crate::studies::accuracy::selection`). Absent: run the file as written.
    pub accuracy: Option<AccuracySpec>,
}

impl Problem {
    /// The problem as a problem file, every key written with defaults filled in: what
    /// `--dump-problem` writes. It reads back to the same problem ([`parse`]).
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("a validated problem is representable in TOML")
    }
}

/// `[accuracy]`: run the cheapest model whose estimated error of `v_s/v_m` is below a target.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct AccuracySpec {
    /// Relative error of `v_s/v_m` allowed (time and mesh together), e.g. 0.01
    /// ([`keys::ACCURACY_TARGET`]). `slither run --accuracy X` overrides it.
    pub target: f64,
    /// Most elements the mesh refinement may use ([`keys::ACCURACY_MAX_ELEMENTS`]).
    #[serde(default = "d_max_elements")]
    pub max_elements: usize,
}
fn d_max_elements() -> usize {
    keys::ACCURACY_MAX_ELEMENTS.int() as usize
}

/// Range checks of an `[accuracy]` table against the problem it applies to (a problem file's
/// own, or a study's base problem): `Err((key, value as written, allowed range))`.
pub fn check_accuracy(a: &AccuracySpec, p: &Problem) -> Result<(), (&'static str, String, String)> {
    if !keys::ACCURACY_TARGET.check_real(a.target) {
        return Err(("target", num(a.target), keys::ACCURACY_TARGET.allowed()));
    }
    let n = p.rod.elements;
    if !(n..=100_000).contains(&a.max_elements) {
        return Err((
            "max_elements",
            format!("{}", a.max_elements),
            format!("an integer in [rod.elements, 100000] = [{n}, 100000]"),
        ));
    }
    if p.time.mode != Mode::Dynamic || p.ground.is_none() || p.gait.kind == Kind::None {
        return Err((
            "target",
            num(a.target),
            "given only for a dynamic scene with [ground] and a [gait] (it controls the error of v_s/v_m)".into(),
        ));
    }
    Ok(())
}

/// Which end of the rod is clamped (position and material frame held).
#[derive(Clone, Copy, Debug, Default, Deserialize, serde::Serialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Clamp {
    /// Both ends free.
    #[default]
    None,
    /// The head (s = 0) is clamped.
    Head,
    /// The tail (s = L) is clamped.
    Tail,
}

/// `[rod]`: geometry and material of the snake. Units, defaults and ranges of every field:
/// [`keys`] (`ROD_*`).
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct RodSpec {
    /// Length `L` (m). Required.
    pub length: f64,
    /// Diameter `a` of the circular cross-section (m). Required.
    pub diameter: f64,
    /// Number of elements (edges) `N` ([`keys::ROD_ELEMENTS`]).
    #[serde(default = "d_elements")]
    pub elements: usize,
    /// Density `rho` (kg/m^3) ([`keys::ROD_DENSITY`]).
    #[serde(default = "d_density")]
    pub density: f64,
    /// Bending rigidity `B` (N m^2). Required.
    pub bending_stiffness: f64,
    /// Twist rigidity `C` (N m^2); absent: `2B/3` (Poisson ratio 0.5), computed by the model.
    pub twist_stiffness: Option<f64>,
    /// Stretching rigidity (N); absent: `16 B / a^2`, the homogeneous circular rod's `EA`.
    pub stretch_stiffness: Option<f64>,
    /// Kelvin-Voigt damping time (s) ([`keys::ROD_DAMPING_TIME`]).
    #[serde(default = "d_damping_time")]
    pub damping_time: f64,
    /// Clamped end: "none" (default), "head" or "tail".
    #[serde(default)]
    pub clamp: Clamp,
    /// Natural curvature `[about d1, about d2]` (1/m), default zero.
    #[serde(default)]
    pub natural_curvature: [f64; 2],
    /// Natural twist rate (rad/m) ([`keys::ROD_NATURAL_TWIST`]).
    #[serde(default = "d_natural_twist")]
    pub natural_twist: f64,
}
fn d_elements() -> usize {
    keys::ROD_ELEMENTS.int() as usize
}
fn d_density() -> f64 {
    keys::ROD_DENSITY.real()
}
fn d_damping_time() -> f64 {
    keys::ROD_DAMPING_TIME.real()
}
fn d_natural_twist() -> f64 {
    keys::ROD_NATURAL_TWIST.real()
}

/// `[gravity]`.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct GravitySpec {
    /// Gravitational acceleration along -z (m/s^2); 0 disables ([`keys::GRAVITY_G`]).
    #[serde(default = "d_g")]
    pub g: f64,
}
fn d_g() -> f64 {
    keys::GRAVITY_G.real()
}
impl Default for GravitySpec {
    fn default() -> Self {
        Self { g: d_g() }
    }
}

/// Integration mode.
#[derive(Clone, Copy, Debug, Default, Deserialize, serde::Serialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// Variational implicit Euler in time.
    #[default]
    Dynamic,
    /// No inertia: minimise the potential energy (needs a clamp).
    Static,
}

/// `[time]`. Units, defaults and ranges: [`keys`] (`TIME_*`).
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct TimeSpec {
    /// "dynamic" (default) or "static".
    #[serde(default)]
    pub mode: Mode,
    /// Time step `h` (s). Required in dynamic mode, > 0. With `adaptive = true`: the first
    /// step.
    pub dt: Option<f64>,
    /// Simulated duration (s). Required in dynamic mode, > 0.
    pub duration: Option<f64>,
    /// Static mode: number of load increments (gravity and natural strains ramped)
    /// ([`keys::TIME_LOAD_STEPS`]).
    #[serde(default = "d_load_steps")]
    pub load_steps: usize,
    /// Error-controlled steps ([`crate::integrator::adaptive`]): `dt` is the first step, each
    /// step is sized so that its local error estimate stays below `error_tolerance`. Default
    /// false (fixed steps of `dt`). Dynamic mode, `implicit` or `bdf2` integrator.
    #[serde(default = "d_adaptive")]
    pub adaptive: bool,
    /// Adaptive only: allowed local error per step of any node position, as a fraction of
    /// `rod.length` (twist angles count with the surface displacement `a/2 * angle`). Default
    /// [`time::DEFAULT_TOLERANCE`] ([`keys::TIME_ERROR_TOLERANCE`]).
    pub error_tolerance: Option<f64>,
    /// Adaptive only: largest step (s). Default `duration / 50` (at least `dt`,
    /// [`time::default_dt_max`]), independent of the output interval; in [dt, duration].
    pub dt_max: Option<f64>,
    /// Adaptive only: smallest step (s); a step that would have to be smaller stops the run
    /// (exit 3) naming the time, step and error. Default `dt * 1e-4`; in (0, dt].
    pub dt_min: Option<f64>,
}
fn d_load_steps() -> usize {
    keys::TIME_LOAD_STEPS.int() as usize
}
fn d_adaptive() -> bool {
    keys::TIME_ADAPTIVE.flag()
}

/// `[output]`.
#[derive(Clone, Debug, Default, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Interval between recorded frames (s); absent: [`OutputSpec::interval_for`]
    /// ([`keys::OUTPUT_INTERVAL`]).
    pub interval: Option<f64>,
    /// Whether `slither run` writes `movie.gif` (with its figures, so not with `--no-plots`);
    /// absent: [`keys::OUTPUT_MOVIE`].
    #[serde(default = "movie_default")]
    pub movie: bool,
}

impl OutputSpec {
    /// The frame interval of a run of `duration` seconds: the file's, or by default
    /// `duration / 100` (the default of [`keys::OUTPUT_INTERVAL`]).
    pub fn interval_for(&self, duration: f64) -> f64 {
        self.interval.unwrap_or(duration / 100.0)
    }
}

fn movie_default() -> bool {
    keys::OUTPUT_MOVIE.flag()
}

/// A problem-file error: names the file, the key and its line, and what is allowed.
#[derive(Debug, thiserror::Error)]
pub enum ProblemError {
    /// The file could not be read.
    #[error("{file}: cannot read: {source}")]
    Io {
        /// File.
        file: PathBuf,
        /// Cause.
        source: std::io::Error,
    },
    /// The file is not valid UTF-8.
    #[error("{file}:{line}: not valid UTF-8 (byte {byte} of the file); save it as UTF-8 text")]
    Encoding {
        /// File.
        file: PathBuf,
        /// 1-based line of the first invalid byte.
        line: usize,
        /// 0-based offset of the first invalid byte.
        byte: usize,
    },
    /// TOML syntax, type, unknown or missing key.
    #[error("{file}: {message}")]
    Parse {
        /// File.
        file: PathBuf,
        /// toml's message (line, column, snippet, key).
        message: String,
    },
    /// A command-line setting (`--set KEY=VALUE`) that cannot be applied, or whose value is
    /// not allowed.
    #[error("{file}: {arg}: {message}")]
    Set {
        /// The file the setting edits.
        file: PathBuf,
        /// The argument, `--set KEY=VALUE`.
        arg: String,
        /// What is wrong, with the allowed range.
        message: String,
    },
    /// A value outside its allowed range.
    #[error("{file}:{line}: `{key}` = {value} is not allowed: must be {allowed}")]
    Invalid {
        /// File.
        file: PathBuf,
        /// 1-based line of the key (or of its table when the key is absent).
        line: usize,
        /// Dotted key, e.g. `rod.length`.
        key: String,
        /// The offending value as written.
        value: String,
        /// Allowed range with unit.
        allowed: String,
    },
}

/// Read, parse and validate a problem file.
pub fn load(path: &Path) -> Result<Problem, ProblemError> {
    parse(&read(path)?, path)
}

/// Parse and validate problem text; `path` is only used in messages.
pub fn parse(text: &str, path: &Path) -> Result<Problem, ProblemError> {
    solver::check_retired(text, path)?;
    let p: Problem = from_toml(text, path)?;
    validate(&p, text, path)?;
    Ok(p)
}

/// Parse and validate problem text edited by command-line settings ([`set`]): an error about
/// a key a setting changed names the setting; an error of the file itself keeps its line.
pub fn parse_with(
    text: &str,
    path: &Path,
    settings: &[&set::Setting],
) -> Result<(String, Problem), ProblemError> {
    let edited = edit(text, path, settings)?;
    match parse(&edited, path) {
        Ok(p) => Ok((edited, p)),
        Err(e) if settings.is_empty() => Err(e),
        Err(e) => match set::attribute(e, settings, path) {
            e @ ProblemError::Set { .. } => Err(e),
            // Not a key a setting changed: the file's own error, with its own lines, when the
            // file alone has it; else an error the settings caused through another key.
            e => Err(match (parse(text, path), e) {
                (Err(own), _) => own,
                (
                    Ok(_),
                    ProblemError::Invalid {
                        file,
                        line,
                        key,
                        value,
                        allowed,
                    },
                ) => {
                    let by: String = settings
                        .iter()
                        .map(|s| format!(" --set {}", s.arg))
                        .collect();
                    ProblemError::Invalid {
                        file,
                        line,
                        key,
                        value,
                        allowed: format!("{allowed} (the file as changed by{by})"),
                    }
                }
                (Ok(_), e) => e,
            }),
        },
    }
}

/// `text` with `settings` applied, or a [`ProblemError::Set`] naming the one that cannot be.
pub fn edit(text: &str, path: &Path, settings: &[&set::Setting]) -> Result<String, ProblemError> {
    set::apply(text, settings).map_err(|(arg, message)| ProblemError::Set {
        file: path.into(),
        arg,
        message,
    })
}

/// Read, parse and validate a problem file for `slither run`: also refuses a run above the
/// size limits of [`limits`] unless `force`.
pub fn load_for_run(path: &Path, force: bool) -> Result<Problem, ProblemError> {
    load_for_run_with(path, force, &[])
}

/// [`load_for_run`] with command-line settings applied to the file first.
pub fn load_for_run_with(
    path: &Path,
    force: bool,
    settings: &[&set::Setting],
) -> Result<Problem, ProblemError> {
    let (text, p) = parse_with(&read(path)?, path, settings)?;
    if !force {
        check_for_run(&p, &text, path).map_err(|e| set::attribute(e, settings, path))?;
    }
    Ok(p)
}

/// The size limits of a run (steps, stored frames, post-processing) and the scaled groups'
/// ranges, checked on a parsed problem whose file text is `text` (`--force` skips them).
pub fn check_for_run(p: &Problem, text: &str, path: &Path) -> Result<(), ProblemError> {
    limits::check_run_size(p, text, path).and_then(|_| limits::check_scaled_groups(p, text, path))
}

/// The text of an input file (problem, study or phase file). A directory is "is a directory";
/// bytes that are not UTF-8 are an [`ProblemError::Encoding`] naming the line and byte.
pub fn read(path: &Path) -> Result<String, ProblemError> {
    let io = |source| ProblemError::Io {
        file: path.into(),
        source,
    };
    if path.is_dir() {
        return Err(io(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "is a directory, not a file",
        )));
    }
    let bytes = std::fs::read(path).map_err(io)?;
    utf8(bytes, path)
}

/// `bytes` as text, or an [`ProblemError::Encoding`] naming the first invalid byte and its line.
pub fn utf8(bytes: Vec<u8>, path: &Path) -> Result<String, ProblemError> {
    String::from_utf8(bytes).map_err(|e| {
        let byte = e.utf8_error().valid_up_to();
        let line = 1 + e.as_bytes()[..byte].iter().filter(|&&b| b == b'\n').count();
        ProblemError::Encoding {
            file: path.into(),
            line,
            byte,
        }
    })
}

/// Deserialize an input file's text; a TOML error names the file and the dotted key.
pub(crate) fn from_toml<T: serde::de::DeserializeOwned>(
    text: &str,
    path: &Path,
) -> Result<T, ProblemError> {
    toml::from_str(text).map_err(|e| {
        let message = e.to_string().trim_end().to_string();
        let message = match toml_error_key(text, &e) {
            Some(key) => match ranges::allowed(&key) {
                Some(allowed) => format!("`{key}`: {message}\nallowed: `{key}` must be {allowed}"),
                None => format!("`{key}`: {message}"),
            },
            None => message,
        };
        ProblemError::Parse {
            file: path.into(),
            message,
        }
    })
}

/// The dotted key a TOML error is about (e.g. `rod.length`), found from the error's span: the
/// table header and the `key =` statement enclosing it (so a bad element of a multi-line array
/// still names its key); for "missing field" errors the table lacking the field plus the field.
pub(crate) fn toml_error_key(text: &str, e: &toml::de::Error) -> Option<String> {
    let span = e.span()?;
    let start = span.start.min(text.len());
    let (mut table, mut key) = (String::new(), None::<String>);
    let mut offset = 0;
    for raw in text.split_inclusive('\n') {
        if offset > start {
            break;
        }
        offset += raw.len();
        let line = raw.trim();
        if line.starts_with('[') {
            table = line
                .trim_start_matches('[')
                .split(']')
                .next()
                .unwrap_or("")
                .trim()
                .to_string();
            key = None;
        } else if let Some((k, _)) = line.split_once('=') {
            let k = k.trim();
            if !k.is_empty()
                && k.chars()
                    .all(|c| c.is_ascii_alphanumeric() || "_-.\"' ".contains(c))
            {
                key = Some(
                    k.split('.')
                        .map(|s| s.trim().trim_matches(['"', '\'']))
                        .collect::<Vec<_>>()
                        .join("."),
                );
            }
        }
    }
    let join = |a: &str, b: Option<&str>| match (a.is_empty(), b) {
        (_, None) => a.to_string(),
        (true, Some(b)) => b.to_string(),
        (false, Some(b)) => format!("{a}.{b}"),
    };
    let dotted = match e
        .message()
        .strip_prefix("missing field `")
        .and_then(|m| m.strip_suffix('`'))
    {
        Some(field) => {
            // The span is the table lacking the field: its `[header]`, an inline `{ ... }`, or
            // (for the root table) the start of the document.
            let spanned = text.get(span).unwrap_or("").trim();
            let owner = if spanned.starts_with('[') && spanned.ends_with(']') {
                table
            } else if spanned.starts_with('{') {
                join(&table, key.as_deref())
            } else {
                String::new()
            };
            join(&owner, Some(field))
        }
        None => join(&table, key.as_deref()),
    };
    (!dotted.is_empty()).then_some(dotted)
}

/// 1-based line of `key` inside `[table]`, or of the table header, or 1.
pub fn key_line(text: &str, table: &str, key: &str) -> usize {
    let mut current = String::new();
    let mut header_line = None;
    for (n, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if line.starts_with('[') {
            current = line
                .trim_start_matches('[')
                .split(']')
                .next()
                .unwrap_or("")
                .trim()
                .to_string();
            if current == table {
                header_line = Some(n + 1);
            }
            continue;
        }
        // `key = ...` inside `[table]`, or a dotted key (`table.key = ...` at the top level,
        // `b.key = ...` inside `[a]` for table `a.b`).
        if let Some((lhs, _)) = line.split_once('=') {
            let lhs: Vec<&str> = lhs.split('.').map(str::trim).collect();
            let mut full: Vec<&str> = if current.is_empty() {
                Vec::new()
            } else {
                current.split('.').map(str::trim).collect()
            };
            full.extend(lhs);
            if full.len() >= 2
                && full[full.len() - 1] == key
                && full[..full.len() - 1].join(".") == table
            {
                return n + 1;
            }
        }
    }
    header_line.unwrap_or(1)
}

/// A number for messages and CSV files: the shortest text that reads back to the same `f64`,
/// in scientific notation outside `[1e-4, 1e7)` (Rust's `{}` writes 1e308 with 309 digits).
pub fn num(v: f64) -> String {
    let m = v.abs();
    if m != 0.0 && m.is_finite() && !(1e-4..1e7).contains(&m) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}
