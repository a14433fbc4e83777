//! `[solver]`: the time integrator, the contact model and every tolerance and iteration cap of
//! the Newton and contact solvers. Each field's unit, default (the value the solvers were tuned
//! with) and range is its `SOLVER_*` entry of [`super::keys`], written there once; the guide's
//! solver chapter explains how the defaults were chosen. A problem file lists only what it
//! changes.

use super::keys::{self, Key};
use serde::Deserialize;

/// `[solver]`: solver settings (defaults and ranges: the `SOLVER_*` keys of [`keys`]).
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// Convergence: the last Newton correction is below `tolerance * a` on every position and
    /// below `tolerance` (rad) on every twist angle ([`keys::SOLVER_TOLERANCE`]).
    #[serde(default = "d_tol")]
    pub tolerance: f64,
    /// Newton iterations per step before the step is rejected; static: 10x
    /// ([`keys::SOLVER_MAX_ITERATIONS`]).
    #[serde(default = "d_iters")]
    pub max_iterations: usize,
    /// Times a rejected step may be halved before the run stops
    /// ([`keys::SOLVER_MAX_HALVINGS`]).
    #[serde(default = "d_halvings")]
    pub max_halvings: usize,
    /// Time integrator: "implicit" (variational implicit Euler by Newton, with contact),
    /// "bdf2" (second order, the same Newton and contact machinery) or "explicit" (velocity
    /// Verlet on the same discrete model, [`crate::integrator::explicit`]; dynamic mode without
    /// a `[ground]` only, stable only below a step limit: see `slither chart stability`)
    /// ([`keys::SOLVER_INTEGRATOR`]).
    #[serde(default)]
    pub integrator: IntegratorKind,
    /// Contact solver: "semi-smooth" (every contact's status from each iterate, all at once:
    /// [`crate::contact::semismooth`]; the conic program as the fallback and certificate) or
    /// "conic" (one Clarabel program per Newton iterate). The CLI's environment variable
    /// `SLITHER_CONTACT=conic` overrides it ([`keys::SOLVER_CONTACT`]). "active-set" was
    /// retired and is refused by [`check_retired`].
    #[serde(default)]
    pub contact: ContactKind,
    /// Where the ground touches the body: at the nodes, or between them on a curve through
    /// them ([`crate::contact::set`]) ([`keys::SOLVER_GROUND_POINTS`]).
    #[serde(default)]
    pub ground_points: GroundPoints,
    /// Line search: largest number of step halvings (backtracks) per Newton iterate before
    /// the step fails ([`keys::SOLVER_MAX_BACKTRACKS`]).
    #[serde(default = "d_backtracks")]
    pub max_backtracks: usize,
    /// Line search: Armijo sufficient-decrease constant `c1` in
    /// `f(q + alpha dq) <= f(q) + c1 alpha g.dq` ([`keys::SOLVER_ARMIJO`]).
    #[serde(default = "d_armijo")]
    pub armijo: f64,
    /// Line search: round-off allowance, relative to `|f(q)|`, added to the Armijo bound so a
    /// step at the minimum is not refused for noise ([`keys::SOLVER_LINE_SEARCH_NOISE`]).
    #[serde(default = "d_noise")]
    pub line_search_noise: f64,
    /// Diagonal shift of a Hessian that is only semi-definite: first shift, relative to its
    /// largest diagonal entry, then x10 per retry ([`keys::SOLVER_SHIFT`]).
    #[serde(default = "d_shift")]
    pub shift: f64,
    /// Diagonal shift retries before the step fails ([`keys::SOLVER_SHIFT_TRIES`]).
    #[serde(default = "d_shift_tries")]
    pub shift_tries: usize,
    /// Semi-smooth contact: Newton iterations of one attempt before it retries or the conic
    /// program takes over, capped by `max_iterations`
    /// ([`keys::SOLVER_SEMI_SMOOTH_MAX_ITERATIONS`]).
    #[serde(default = "d_semi_smooth_iters")]
    pub semi_smooth_max_iterations: usize,
    /// Semi-smooth contact: accepted merits the non-monotone line search compares a full step
    /// with ([`keys::SOLVER_SEMI_SMOOTH_MERIT_MEMORY`]).
    #[serde(default = "d_merit_memory")]
    pub semi_smooth_merit_memory: usize,
    /// Semi-smooth contact: the Alart-Curnier penalty as a multiple of each contact node's
    /// inertia stiffness ([`keys::SOLVER_SEMI_SMOOTH_PENALTY`]).
    #[serde(default = "d_penalty")]
    pub semi_smooth_penalty: f64,
    /// Semi-smooth contact: retries of a failed step from its start, with other penalties,
    /// before the conic fallback ([`keys::SOLVER_SEMI_SMOOTH_RETRIES`]).
    #[serde(default = "d_retries")]
    pub semi_smooth_retries: usize,
    /// Newton iterations of the conic path started where a failed semi-smooth step stopped
    /// (beyond them it starts over from the step's start): the conic path's normal-force fixed
    /// point contracted by about 0.6 per iteration on the S-start steps that the retired active
    /// set stalled on, about 17 iterations from their start
    /// ([`keys::SOLVER_WARM_CONIC_ITERATIONS`]).
    #[serde(default = "d_warm")]
    pub warm_conic_iterations: usize,
    /// Normal forces count as settled when they change by less than this fraction of the mean
    /// weight per contact `W / n_c`: between iterates on the conic path; in the semi-smooth
    /// Newton, their predicted change over the last Newton step (the Hessian row at each held
    /// coordinate times the step, [`crate::contact::reactions`])
    /// ([`keys::SOLVER_NORMAL_FORCE_TOLERANCE`]).
    #[serde(default = "d_normal_tol")]
    pub normal_force_tolerance: f64,
    /// A contact touches the ground when its gap is below this fraction of `a`; it sticks when
    /// its slip over the step is below it ([`keys::SOLVER_CONTACT_TOLERANCE`]).
    #[serde(default = "d_contact_tol")]
    pub contact_tolerance: f64,
    /// Semi-smooth contact: the sliding contacts' normal forces inside the Newton system (their
    /// change along the step enters the friction force, so Newton converges quadratically);
    /// `false` lags them by one iterate (linear convergence) ([`keys::SOLVER_CONTACT_COUPLING`]).
    #[serde(default = "d_coupling")]
    pub contact_coupling: bool,
    /// Semi-smooth contact: the bending and twist Hessian of an earlier iterate of the step is kept
    /// while every position stays within this fraction of the shortest element (and every
    /// angle within this many rad) of it; the gradient is exact at every iterate
    /// ([`crate::newton::HessianCache`]; 0: assembled at every iterate)
    /// ([`keys::SOLVER_HESSIAN_REUSE`]).
    #[serde(default = "d_hessian_reuse")]
    pub hessian_reuse: f64,
    /// Semi-smooth contact: certify every N-th step it solves with one conic program from its
    /// solution, whose correction must stay below the Newton tolerance and whose normal-force
    /// change below `normal_force_tolerance` (0: never). For tests and audits: a conic solve
    /// costs about 30 ms at 200 elements ([`keys::SOLVER_CONIC_CERTIFICATE`]).
    #[serde(default = "d_certificate")]
    pub conic_certificate: usize,
    /// Clarabel's absolute and relative gap and feasibility tolerances (scaled problem)
    /// ([`keys::SOLVER_CONIC_TOLERANCE`]).
    #[serde(default = "d_conic_tol")]
    pub conic_tolerance: f64,
    /// Clarabel's interior-point iteration cap ([`keys::SOLVER_CONIC_MAX_ITERATIONS`]).
    #[serde(default = "d_conic_iters")]
    pub conic_max_iterations: u32,
    /// Clarabel's direct KKT solver: "qdldl" or "faer" (needs the `clarabel-faer` feature).
    /// The CLI's environment variable `SLITHER_CLARABEL_METHOD` overrides it
    /// ([`keys::SOLVER_CLARABEL_METHOD`]).
    #[serde(default = "d_method")]
    pub clarabel_method: String,
}

/// The time integrator: `[solver] integrator` in a problem file, and the one name of an
/// integrator in the solver ([`crate::integrator::scheme_for`]), the charts
/// ([`crate::charts`]) and their files (`implicit`, `explicit`, `bdf2`: [`IntegratorKind::name`]).
#[derive(Clone, Copy, Default, Deserialize, serde::Serialize, PartialEq, Eq)]
pub enum IntegratorKind {
    /// Variational implicit Euler (Newton), the production integrator (`"implicit"`).
    #[default]
    #[serde(rename = "implicit")]
    ImplicitEuler,
    /// Velocity Verlet, the explicit symplectic reference (no contact; `"explicit"`).
    #[serde(rename = "explicit")]
    VelocityVerlet,
    /// Second-order backward differentiation (BDF2) as an incremental potential, with contact
    /// ([`crate::integrator::bdf2`]; `"bdf2"`).
    #[serde(rename = "bdf2")]
    Bdf2,
}

/// `Implicit`, `Explicit` or `Bdf2`: the names the variants had before they were named for
/// their methods. The resume keys of the studies hash the problem's debug text
/// ([`crate::studies::problem_hash`]), so this text must stay for `history.csv`, `phase.csv`
/// and the charts' cached references written earlier to be reused.
impl std::fmt::Debug for IntegratorKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            IntegratorKind::ImplicitEuler => "Implicit",
            IntegratorKind::VelocityVerlet => "Explicit",
            IntegratorKind::Bdf2 => "Bdf2",
        })
    }
}

impl IntegratorKind {
    /// Its name in problem files and in the charts' files.
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::ImplicitEuler => "implicit",
            IntegratorKind::VelocityVerlet => "explicit",
            IntegratorKind::Bdf2 => "bdf2",
        }
    }
}

/// `[solver] contact`.
#[derive(Clone, Copy, Debug, Default, Deserialize, serde::Serialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum ContactKind {
    /// The conic program at every Newton iterate.
    Conic,
    /// Semi-smooth Newton on the Alart-Curnier contact conditions, every contact's status
    /// from the current iterate ([`crate::contact::semismooth`]); the conic program as the
    /// fallback. The default.
    #[default]
    SemiSmooth,
}

/// `[solver] ground_points`.
#[derive(Clone, Copy, Debug, Default, Deserialize, serde::Serialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum GroundPoints {
    /// A contact at every node.
    #[default]
    Nodes,
    /// A contact per node at the lowest point of the parabola through the node and its two
    /// neighbours, within half an element of the node.
    Curve,
}

fn d_certificate() -> usize {
    keys::SOLVER_CONIC_CERTIFICATE.int() as usize
}
fn d_tol() -> f64 {
    keys::SOLVER_TOLERANCE.real()
}
fn d_iters() -> usize {
    keys::SOLVER_MAX_ITERATIONS.int() as usize
}
fn d_halvings() -> usize {
    keys::SOLVER_MAX_HALVINGS.int() as usize
}
fn d_backtracks() -> usize {
    keys::SOLVER_MAX_BACKTRACKS.int() as usize
}
fn d_armijo() -> f64 {
    keys::SOLVER_ARMIJO.real()
}
fn d_noise() -> f64 {
    keys::SOLVER_LINE_SEARCH_NOISE.real()
}
fn d_shift() -> f64 {
    keys::SOLVER_SHIFT.real()
}
fn d_shift_tries() -> usize {
    keys::SOLVER_SHIFT_TRIES.int() as usize
}
fn d_semi_smooth_iters() -> usize {
    keys::SOLVER_SEMI_SMOOTH_MAX_ITERATIONS.int() as usize
}
fn d_penalty() -> f64 {
    keys::SOLVER_SEMI_SMOOTH_PENALTY.real()
}
fn d_retries() -> usize {
    keys::SOLVER_SEMI_SMOOTH_RETRIES.int() as usize
}
fn d_merit_memory() -> usize {
    keys::SOLVER_SEMI_SMOOTH_MERIT_MEMORY.int() as usize
}
fn d_warm() -> usize {
    keys::SOLVER_WARM_CONIC_ITERATIONS.int() as usize
}
fn d_normal_tol() -> f64 {
    keys::SOLVER_NORMAL_FORCE_TOLERANCE.real()
}
fn d_contact_tol() -> f64 {
    keys::SOLVER_CONTACT_TOLERANCE.real()
}
fn d_coupling() -> bool {
    keys::SOLVER_CONTACT_COUPLING.flag()
}
fn d_hessian_reuse() -> f64 {
    keys::SOLVER_HESSIAN_REUSE.real()
}
fn d_conic_tol() -> f64 {
    keys::SOLVER_CONIC_TOLERANCE.real()
}
fn d_conic_iters() -> u32 {
    keys::SOLVER_CONIC_MAX_ITERATIONS.int() as u32
}
fn d_method() -> String {
    keys::SOLVER_CLARABEL_METHOD.word().into()
}

impl Default for SolverSpec {
    fn default() -> Self {
        Self {
            tolerance: d_tol(),
            max_iterations: d_iters(),
            max_halvings: d_halvings(),
            integrator: IntegratorKind::ImplicitEuler,
            contact: ContactKind::SemiSmooth,
            ground_points: GroundPoints::Nodes,
            max_backtracks: d_backtracks(),
            armijo: d_armijo(),
            line_search_noise: d_noise(),
            shift: d_shift(),
            shift_tries: d_shift_tries(),
            semi_smooth_max_iterations: d_semi_smooth_iters(),
            semi_smooth_merit_memory: d_merit_memory(),
            semi_smooth_penalty: d_penalty(),
            semi_smooth_retries: d_retries(),
            warm_conic_iterations: d_warm(),
            contact_coupling: d_coupling(),
            hessian_reuse: d_hessian_reuse(),
            normal_force_tolerance: d_normal_tol(),
            contact_tolerance: d_contact_tol(),
            conic_certificate: d_certificate(),
            conic_tolerance: d_conic_tol(),
            conic_max_iterations: d_conic_iters(),
            clarabel_method: d_method(),
        }
    }
}

impl SolverSpec {
    /// Range checks of every numeric setting and of `clarabel_method` against its key
    /// ([`keys`]): `Err((key, value as written))`.
    pub(crate) fn check_settings(&self) -> Result<(), (&'static Key, String)> {
        let reals: [(&'static Key, f64); 9] = [
            (&keys::SOLVER_TOLERANCE, self.tolerance),
            (&keys::SOLVER_ARMIJO, self.armijo),
            (&keys::SOLVER_LINE_SEARCH_NOISE, self.line_search_noise),
            (&keys::SOLVER_SHIFT, self.shift),
            (
                &keys::SOLVER_NORMAL_FORCE_TOLERANCE,
                self.normal_force_tolerance,
            ),
            (&keys::SOLVER_CONTACT_TOLERANCE, self.contact_tolerance),
            (&keys::SOLVER_CONIC_TOLERANCE, self.conic_tolerance),
            (&keys::SOLVER_HESSIAN_REUSE, self.hessian_reuse),
            (&keys::SOLVER_SEMI_SMOOTH_PENALTY, self.semi_smooth_penalty),
        ];
        let ints: [(&'static Key, usize); 10] = [
            (&keys::SOLVER_MAX_ITERATIONS, self.max_iterations),
            (&keys::SOLVER_MAX_HALVINGS, self.max_halvings),
            (&keys::SOLVER_MAX_BACKTRACKS, self.max_backtracks),
            (&keys::SOLVER_SHIFT_TRIES, self.shift_tries),
            (
                &keys::SOLVER_SEMI_SMOOTH_MAX_ITERATIONS,
                self.semi_smooth_max_iterations,
            ),
            (
                &keys::SOLVER_SEMI_SMOOTH_MERIT_MEMORY,
                self.semi_smooth_merit_memory,
            ),
            (&keys::SOLVER_SEMI_SMOOTH_RETRIES, self.semi_smooth_retries),
            (
                &keys::SOLVER_WARM_CONIC_ITERATIONS,
                self.warm_conic_iterations,
            ),
            (
                &keys::SOLVER_CONIC_MAX_ITERATIONS,
                self.conic_max_iterations as usize,
            ),
            (&keys::SOLVER_CONIC_CERTIFICATE, self.conic_certificate),
        ];
        for (k, v) in reals {
            if !k.check_real(v) {
                return Err((k, super::num(v)));
            }
        }
        for (k, v) in ints {
            if !k.check_int(v as u64) {
                return Err((k, v.to_string()));
            }
        }
        if !matches!(self.clarabel_method.as_str(), "qdldl" | "faer") {
            return Err((
                &keys::SOLVER_CLARABEL_METHOD,
                format!("{:?}", self.clarabel_method),
            ));
        }
        Ok(())
    }
}

/// Process-wide overrides of solver settings, set once by the command line from its
/// environment (`SLITHER_CONTACT`, `SLITHER_CLARABEL_METHOD`); the library reads no
/// environment variables.
#[derive(Clone, Debug, Default)]
pub struct Overrides {
    /// Replaces `[solver] contact`.
    pub contact: Option<ContactKind>,
    /// Replaces `[solver] clarabel_method`.
    pub clarabel_method: Option<String>,
}

/// Whether this build can use Clarabel's faer KKT solver (cargo feature `clarabel-faer`).
pub const HAS_CLARABEL_FAER: bool = cfg!(feature = "clarabel-faer");

/// `Err(allowed values)` unless `method` is a Clarabel KKT solver this build has: "qdldl", or
/// "faer" in a build with the cargo feature `clarabel-faer` (without it every conic solve
/// would fail and each fallback become a step halving).
pub(crate) fn check_clarabel_method(method: &str) -> Result<(), &'static str> {
    match method {
        "qdldl" => Ok(()),
        "faer" if HAS_CLARABEL_FAER => Ok(()),
        "faer" => Err("\"qdldl\" in this build (\"faer\" needs the cargo feature clarabel-faer: cargo build --release --features clarabel-faer)"),
        _ if HAS_CLARABEL_FAER => Err("\"qdldl\" or \"faer\""),
        _ => Err("\"qdldl\" or \"faer\" (\"faer\" only in a build with the cargo feature clarabel-faer)"),
    }
}

impl Overrides {
    /// The overrides from the values of `SLITHER_CONTACT` and `SLITHER_CLARABEL_METHOD`
    /// (`None`: unset), or a message naming the variable, its value and the allowed values.
    pub fn from_env_values(contact: Option<&str>, method: Option<&str>) -> Result<Self, String> {
        let contact = match contact {
            None => None,
            Some("conic") => Some(ContactKind::Conic),
            Some("semi-smooth") => Some(ContactKind::SemiSmooth),
            Some("active-set") => {
                return Err(format!(
                    "SLITHER_CONTACT = \"active-set\" is not allowed: must be \"semi-smooth\" or \"conic\" (or unset); {RETIRED_ACTIVE_SET}"
                ))
            }
            Some(v) => {
                return Err(format!(
                    "SLITHER_CONTACT = {v:?} is not allowed: must be \"semi-smooth\" or \"conic\" (or unset)"
                ))
            }
        };
        if let Some(m) = method {
            if let Err(allowed) = check_clarabel_method(m) {
                return Err(format!(
                    "SLITHER_CLARABEL_METHOD = {m:?} is not allowed: must be {allowed} (or unset)"
                ));
            }
        }
        Ok(Overrides {
            contact,
            clarabel_method: method.map(str::to_string),
        })
    }
}

static OVERRIDES: std::sync::OnceLock<Overrides> = std::sync::OnceLock::new();

/// Install the overrides (first call wins; later calls are ignored).
pub fn set_overrides(o: Overrides) {
    let _ = OVERRIDES.set(o);
}

impl SolverSpec {
    /// The settings with the process-wide [`Overrides`] applied (what a model runs with).
    pub fn effective(&self) -> SolverSpec {
        let mut s = self.clone();
        if let Some(o) = OVERRIDES.get() {
            if let Some(c) = o.contact {
                s.contact = c;
            }
            if let Some(m) = &o.clarabel_method {
                s.clarabel_method = m.clone();
            }
        }
        s
    }
}

/// Why `"active-set"` and its keys are refused, for messages.
pub const RETIRED_ACTIVE_SET: &str = "the active-set contact solver was retired: no bundled scene needed it (record docs/results/active-set-need/latest.md)";

/// `[solver]` keys retired with the active-set solver: the key, the value refused (`None`:
/// any), and what to write instead.
const RETIRED: [(&str, Option<&str>, &str); 4] = [
    (
        "contact",
        Some("active-set"),
        "\"semi-smooth\" or \"conic\"",
    ),
    (
        "active_set_max_iterations",
        None,
        "absent: the semi-smooth Newton's cap is `solver.semi_smooth_max_iterations`",
    ),
    (
        "active_set_extra_switches",
        None,
        "absent: only the active set used it",
    ),
    (
        "contact_force_tolerance",
        None,
        "absent: only the active set used it",
    ),
];

/// Refuse the `[solver]` keys and values retired with the active-set solver, with an error
/// naming the file, the line, the key, the allowed values and why (before the file is
/// deserialized, which would only call the key unknown). Text that is not TOML passes here and
/// fails in the parser with its own message.
pub(super) fn check_retired(text: &str, path: &std::path::Path) -> Result<(), super::ProblemError> {
    let Ok(doc) = text.parse::<toml::Table>() else {
        return Ok(());
    };
    let Some(solver) = doc.get("solver").and_then(toml::Value::as_table) else {
        return Ok(());
    };
    for (key, refused, instead) in RETIRED {
        let Some(v) = solver.get(key) else { continue };
        if refused.is_none_or(|r| v.as_str() == Some(r)) {
            return Err(super::ProblemError::Invalid {
                file: path.into(),
                line: super::key_line(text, "solver", key),
                key: format!("solver.{key}"),
                value: v.to_string(),
                allowed: format!("{instead} ({RETIRED_ACTIVE_SET})"),
            });
        }
    }
    Ok(())
}
