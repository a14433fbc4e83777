//! Problem files: the TOML schema (SI units), its defaults, and validation.
//!
//! Every field is documented with its meaning, unit and default. Tables and fields may be
//! omitted where a default exists; unknown keys are rejected. [`load`] parses and validates a
//! file and returns errors that name the file, the key, its line and the allowed range.

mod gait;
pub mod limits;
pub mod ranges;
mod solver;
pub mod time;

pub use gait::{GaitSpec, Kind};
pub use solver::{set_overrides, ContactKind, IntegratorKind, Overrides, SolverSpec};
pub use time::Adaptive;

use serde::Deserialize;
use std::path::{Path, PathBuf};

/// A whole problem file.
#[derive(Clone, Debug, Deserialize)]
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
    /// Muscle activation (gait). Default: none.
    #[serde(default)]
    pub gait: GaitSpec,
    /// Accuracy target: `slither run` picks the tolerance and the mesh
    /// (`crate::chart::accuracy`). Absent: run the file as written.
    pub accuracy: Option<AccuracySpec>,
}

/// `[accuracy]`: run the cheapest model whose estimated error of `v_s/v_m` is below a target.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AccuracySpec {
    /// Relative error of `v_s/v_m` allowed (time and mesh together), e.g. 0.01. Required, in
    /// [1e-4, 0.5]. `slither run --accuracy X` overrides it.
    pub target: f64,
    /// Most elements the mesh refinement may use. Default 400, in [rod.elements, 100000].
    #[serde(default = "d_max_elements")]
    pub max_elements: usize,
}
fn d_max_elements() -> usize {
    400
}

/// Range checks of an `[accuracy]` table against the problem it applies to (a problem file's
/// own, or a study's base problem): `Err((key, value as written, allowed range))`.
pub fn check_accuracy(a: &AccuracySpec, p: &Problem) -> Result<(), (&'static str, String, String)> {
    if !(a.target.is_finite() && (1e-4..=0.5).contains(&a.target)) {
        return Err((
            "target",
            format!("{}", a.target),
            "in [1e-4, 0.5] (relative error of v_s/v_m)".into(),
        ));
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
            format!("{}", a.target),
            "given only for a dynamic scene with [ground] and a [gait] (it controls the error of v_s/v_m)".into(),
        ));
    }
    Ok(())
}

/// `[ground]`: a plane `z = 0` with anisotropic kinetic Coulomb friction.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroundSpec {
    /// Coefficient resisting forward (toward the head) sliding. Default 0.11, >= 0.
    #[serde(default = "d_mu_f")]
    pub mu_forward: f64,
    /// Coefficient resisting backward sliding. Default 0.14, >= 0.
    #[serde(default = "d_mu_b")]
    pub mu_backward: f64,
    /// Coefficient resisting sideways sliding. Default 0.20, >= 0.
    #[serde(default = "d_mu_s")]
    pub mu_sideways: f64,
    /// Incline (degrees): gravity is tilted about y so that the slope rises along +x.
    /// Default 0, in (-90, 90).
    #[serde(default)]
    pub incline_deg: f64,
}
fn d_mu_f() -> f64 {
    0.11
}
fn d_mu_b() -> f64 {
    0.14
}
fn d_mu_s() -> f64 {
    0.20
}

/// Which end of the rod is clamped (position and material frame held).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
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

/// `[rod]`: geometry and material of the snake.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RodSpec {
    /// Length `L` (m). Required, > 0.
    pub length: f64,
    /// Diameter `a` of the circular cross-section (m). Required, > 0.
    pub diameter: f64,
    /// Number of elements (edges) `N`. Default 50, at least 2.
    #[serde(default = "d_elements")]
    pub elements: usize,
    /// Density `rho` (kg/m^3). Default 1000, > 0.
    #[serde(default = "d_density")]
    pub density: f64,
    /// Bending rigidity `B` (N m^2). Required, > 0.
    pub bending_stiffness: f64,
    /// Twist rigidity `C` (N m^2). Default `2B/3` (Poisson ratio 0.5), > 0.
    pub twist_stiffness: Option<f64>,
    /// Stretching rigidity (N). Default `16 B / a^2`, the homogeneous circular rod's `EA`.
    pub stretch_stiffness: Option<f64>,
    /// Clamped end: "none" (default), "head" or "tail".
    #[serde(default)]
    pub clamp: Clamp,
    /// Natural curvature `[about d1, about d2]` (1/m). Default `[0, 0]`.
    #[serde(default)]
    pub natural_curvature: [f64; 2],
    /// Natural twist rate (rad/m). Default 0.
    #[serde(default)]
    pub natural_twist: f64,
}
fn d_elements() -> usize {
    50
}
fn d_density() -> f64 {
    1000.0
}

/// Initial shape.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Shape {
    /// Straight along the heading; head (s = 0) at x = L, tail at the origin.
    #[default]
    Straight,
}

/// `[initial]`: initial configuration and velocity.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialSpec {
    /// Shape: "straight" (default): along +x, head (s = 0) at x = L, tail at x = 0,
    /// centreline at z = a/2 + `height`.
    #[serde(default)]
    pub shape: Shape,
    /// Uniform initial velocity (m/s). Default `[0, 0, 0]`.
    #[serde(default)]
    pub velocity: [f64; 3],
    /// Initial rigid angular velocity about the centroid (rad/s). Default `[0, 0, 0]`.
    #[serde(default)]
    pub angular_velocity: [f64; 3],
    /// Rotation of the straight rod about z (degrees); 0 = head toward +x. Default 0.
    #[serde(default)]
    pub heading_deg: f64,
    /// Extra height of the centreline above `a/2` (m). Default 0.
    #[serde(default)]
    pub height: f64,
}
impl Default for InitialSpec {
    fn default() -> Self {
        Self {
            shape: Shape::Straight,
            velocity: [0.0; 3],
            angular_velocity: [0.0; 3],
            heading_deg: 0.0,
            height: 0.0,
        }
    }
}

/// `[gravity]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GravitySpec {
    /// Gravitational acceleration along -z (m/s^2). Default 9.81; 0 disables; >= 0.
    #[serde(default = "d_g")]
    pub g: f64,
}
fn d_g() -> f64 {
    9.81
}
impl Default for GravitySpec {
    fn default() -> Self {
        Self { g: d_g() }
    }
}

/// Integration mode.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// Variational implicit Euler in time.
    #[default]
    Dynamic,
    /// No inertia: minimise the potential energy (needs a clamp).
    Static,
}

/// `[time]`.
#[derive(Clone, Debug, Deserialize)]
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
    /// Static mode: number of load increments (gravity and natural strains ramped). Default 1.
    #[serde(default = "d_one")]
    pub load_steps: usize,
    /// Error-controlled steps ([`crate::integrator::adaptive`]): `dt` is the first step, each
    /// step is sized so that its local error estimate stays below `error_tolerance`. Default
    /// false (fixed steps of `dt`). Dynamic mode, `implicit` or `bdf2` integrator.
    #[serde(default)]
    pub adaptive: bool,
    /// Adaptive only: allowed local error per step of any node position, as a fraction of
    /// `rod.length` (twist angles count with the surface displacement `a/2 * angle`). Default
    /// [`time::DEFAULT_TOLERANCE`], in [1e-12, 0.1].
    pub error_tolerance: Option<f64>,
    /// Adaptive only: largest step (s). Default the output interval (at least `dt`); in
    /// [dt, duration].
    pub dt_max: Option<f64>,
    /// Adaptive only: smallest step (s); a step that would have to be smaller stops the run
    /// (exit 3) naming the time, step and error. Default `dt * 1e-4`; in (0, dt].
    pub dt_min: Option<f64>,
}
fn d_one() -> usize {
    1
}

/// `[output]`.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Interval between recorded frames (s). Default `duration / 100`; > 0.
    pub interval: Option<f64>,
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
    let p: Problem = from_toml(text, path)?;
    validate(&p, text, path)?;
    Ok(p)
}

/// Read, parse and validate a problem file for `slither run`: also refuses a run above the
/// size limits of [`limits`] unless `force`.
pub fn load_for_run(path: &Path, force: bool) -> Result<Problem, ProblemError> {
    let text = read(path)?;
    let p = parse(&text, path)?;
    if !force {
        limits::check_run_size(&p, &text, path)?;
    }
    Ok(p)
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

struct Checker<'a> {
    text: &'a str,
    path: &'a Path,
}

impl Checker<'_> {
    fn fail(&self, table: &str, key: &str, value: String, allowed: &str) -> ProblemError {
        ProblemError::Invalid {
            file: self.path.into(),
            line: key_line(self.text, table, key),
            key: format!("{table}.{key}"),
            value,
            allowed: allowed.into(),
        }
    }
    fn positive(&self, table: &str, key: &str, v: f64, unit: &str) -> Result<(), ProblemError> {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(self.fail(
                table,
                key,
                format!("{v}"),
                &format!("a finite number > 0 ({unit})"),
            ))
        }
    }
    fn finite(&self, table: &str, key: &str, v: &[f64], unit: &str) -> Result<(), ProblemError> {
        if v.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(self.fail(table, key, format!("{v:?}"), &format!("finite ({unit})")))
        }
    }
    fn range(
        &self,
        table: &str,
        key: &str,
        v: f64,
        lo: f64,
        hi: f64,
        unit: &str,
    ) -> Result<(), ProblemError> {
        if v.is_finite() && v > lo && v <= hi {
            Ok(())
        } else {
            Err(self.fail(
                table,
                key,
                format!("{v}"),
                &format!("in ({lo}, {hi}] ({unit})"),
            ))
        }
    }
}

fn validate(p: &Problem, text: &str, path: &Path) -> Result<(), ProblemError> {
    ranges::check_lengths(text, path)?;
    let c = Checker { text, path };
    let r = &p.rod;
    c.positive("rod", "length", r.length, "m")?;
    c.positive("rod", "diameter", r.diameter, "m")?;
    if r.diameter >= r.length {
        return Err(c.fail(
            "rod",
            "diameter",
            format!("{}", r.diameter),
            "smaller than rod.length (m)",
        ));
    }
    if !(2..=100_000).contains(&r.elements) {
        return Err(c.fail(
            "rod",
            "elements",
            format!("{}", r.elements),
            "an integer in [2, 100000]",
        ));
    }
    c.positive("rod", "density", r.density, "kg/m^3")?;
    c.positive("rod", "bending_stiffness", r.bending_stiffness, "N m^2")?;
    if let Some(v) = r.twist_stiffness {
        c.positive("rod", "twist_stiffness", v, "N m^2")?;
    }
    if let Some(v) = r.stretch_stiffness {
        c.positive("rod", "stretch_stiffness", v, "N")?;
    }
    c.finite("rod", "natural_curvature", &r.natural_curvature, "1/m")?;
    c.finite("rod", "natural_twist", &[r.natural_twist], "rad/m")?;
    let i = &p.initial;
    c.finite("initial", "velocity", &i.velocity, "m/s")?;
    c.finite("initial", "angular_velocity", &i.angular_velocity, "rad/s")?;
    c.finite("initial", "heading_deg", &[i.heading_deg], "degrees")?;
    if !(i.height.is_finite() && i.height >= 0.0) {
        return Err(c.fail(
            "initial",
            "height",
            format!("{}", i.height),
            "a finite number >= 0 (m)",
        ));
    }
    if !(p.gravity.g.is_finite() && p.gravity.g >= 0.0) {
        return Err(c.fail(
            "gravity",
            "g",
            format!("{}", p.gravity.g),
            "a finite number >= 0 (m/s^2)",
        ));
    }
    let t = &p.time;
    match t.mode {
        Mode::Dynamic => {
            let dt = t.dt.ok_or_else(|| {
                c.fail(
                    "time",
                    "dt",
                    "(missing)".into(),
                    "given in dynamic mode, > 0 (s)",
                )
            })?;
            c.positive("time", "dt", dt, "s")?;
            let d = t.duration.ok_or_else(|| {
                c.fail(
                    "time",
                    "duration",
                    "(missing)".into(),
                    "given in dynamic mode, > 0 (s)",
                )
            })?;
            c.positive("time", "duration", d, "s")?;
            if dt > d {
                return Err(c.fail("time", "dt", format!("{dt}"), "at most time.duration (s)"));
            }
        }
        Mode::Static => {
            if r.clamp == Clamp::None {
                return Err(c.fail("time", "mode", "\"static\"".into(), "\"dynamic\" unless rod.clamp is \"head\" or \"tail\" (a free rod has no static equilibrium)"));
            }
            if let Some(dt) = t.dt {
                c.positive("time", "dt", dt, "s")?;
            }
            if let Some(d) = t.duration {
                c.positive("time", "duration", d, "s")?;
            }
        }
    }
    time::check(p, &c)?;
    if let Some(a) = &p.accuracy {
        if let Err((key, value, allowed)) = check_accuracy(a, p) {
            return Err(c.fail("accuracy", key, value, &allowed));
        }
    }
    if !(1..=10_000).contains(&t.load_steps) {
        return Err(c.fail(
            "time",
            "load_steps",
            format!("{}", t.load_steps),
            "an integer in [1, 10000]",
        ));
    }
    if let Some(gr) = &p.ground {
        for (key, v) in [
            ("mu_forward", gr.mu_forward),
            ("mu_backward", gr.mu_backward),
            ("mu_sideways", gr.mu_sideways),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(c.fail(
                    "ground",
                    key,
                    format!("{v}"),
                    "a finite number >= 0 (dimensionless)",
                ));
            }
        }
        if !(gr.incline_deg.is_finite() && gr.incline_deg > -90.0 && gr.incline_deg < 90.0) {
            return Err(c.fail(
                "ground",
                "incline_deg",
                format!("{}", gr.incline_deg),
                "in (-90, 90) (degrees)",
            ));
        }
        if t.mode == Mode::Static {
            return Err(c.fail(
                "time",
                "mode",
                "\"static\"".into(),
                "\"dynamic\" when a [ground] is present (friction needs time)",
            ));
        }
    }
    let g = &p.gait;
    if !(g.stress.is_finite() && g.stress >= 0.0) {
        return Err(c.fail(
            "gait",
            "stress",
            format!("{}", g.stress),
            "a finite number >= 0 (Pa)",
        ));
    }
    c.range("gait", "sigma", g.sigma, 0.0, 1.0, "fraction of rod.length")?;
    c.positive("gait", "speed", g.speed, "m/s")?;
    c.finite("gait", "centers", &g.centers, "fractions of rod.length")?;
    // The couples' centres and width matter for the Gaussian gaits: a centre off the body or a
    // width below one element (a Gaussian that falls between the nodes) runs without muscle
    // action.
    if matches!(g.kind, Kind::SStart | Kind::Sidewinding) {
        if !g.centers.iter().all(|x| (0.0..=1.0).contains(x)) {
            return Err(c.fail(
                "gait",
                "centers",
                format!("{:?}", g.centers),
                "3 numbers in [0, 1] (fractions of rod.length; 0 is the head)",
            ));
        }
        let min_sigma = 1.0 / r.elements as f64;
        if g.sigma < min_sigma {
            return Err(c.fail(
                "gait",
                "sigma",
                format!("{}", g.sigma),
                &format!(
                    "at least one element length, 1/rod.elements = {min_sigma} (fraction of rod.length), and at most 1"
                ),
            ));
        }
    }
    c.finite("gait", "scales", &g.scales, "dimensionless")?;
    c.positive("gait", "period", g.period, "s")?;
    if !(g.ramp.is_finite() && (0.0..=1.0).contains(&g.ramp)) {
        return Err(c.fail(
            "gait",
            "ramp",
            format!("{}", g.ramp),
            "in [0, 1] (fraction of L / v_m)",
        ));
    }
    c.positive("gait", "wavelength", g.wavelength, "fraction of rod.length")?;
    if let Some(iv) = p.output.interval {
        c.positive("output", "interval", iv, "s")?;
    }
    c.range(
        "solver",
        "tolerance",
        p.solver.tolerance,
        0.0,
        1e-3,
        "dimensionless",
    )?;
    if !(1..=10_000).contains(&p.solver.max_iterations) {
        return Err(c.fail(
            "solver",
            "max_iterations",
            format!("{}", p.solver.max_iterations),
            "an integer in [1, 10000]",
        ));
    }
    if p.solver.integrator == IntegratorKind::Explicit {
        if p.ground.is_some() {
            return Err(c.fail(
                "solver",
                "integrator",
                "\"explicit\"".into(),
                "\"implicit\" when a [ground] is present (the explicit integrator has no contact)",
            ));
        }
        if t.mode == Mode::Static {
            return Err(c.fail(
                "solver",
                "integrator",
                "\"explicit\"".into(),
                "\"implicit\" in static mode (the explicit integrator only steps in time)",
            ));
        }
    }
    if p.solver.max_halvings > 30 {
        return Err(c.fail(
            "solver",
            "max_halvings",
            format!("{}", p.solver.max_halvings),
            "an integer in [0, 30]",
        ));
    }
    if p.solver.integrator == IntegratorKind::Bdf2 && t.mode == Mode::Static {
        return Err(c.fail(
            "solver",
            "integrator",
            "\"bdf2\"".into(),
            "\"implicit\" in static mode (BDF2 only steps in time)",
        ));
    }
    if let Err((key, value, allowed)) = p.solver.check_settings() {
        return Err(c.fail("solver", key, value, allowed));
    }
    Ok(())
}
