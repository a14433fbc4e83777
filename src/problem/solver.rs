//! `[solver]`: the time integrator, the contact model and every tolerance and iteration cap of
//! the Newton and contact solvers, each with its unit and default (the values the solvers were
//! tuned with). A problem file lists only what it changes.

use serde::Deserialize;

/// `[solver]`: solver settings.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// Convergence: the last Newton correction is below `tolerance * a` on every position and
    /// below `tolerance` (rad) on every twist angle. Default 5e-6, in (0, 1e-3]
    /// (with `normal_force_tolerance` 1e-3: a 100x tighter pair moves v_s/v_m by 2.7e-6 on the
    /// S-start and at most 1.02e-4 on the bundled scenes, the sidewinding scene the most (3e-6
    /// brings it to 2.0e-5 at 4% more Newton iterations); at 1e-5 the PyElastica S-start moved
    /// 1.3e-4; `examples/tolerance_check.rs` prints the table).
    #[serde(default = "d_tol")]
    pub tolerance: f64,
    /// Newton iterations per step before the step is rejected. Default 50 (static: 10x).
    #[serde(default = "d_iters")]
    pub max_iterations: usize,
    /// Times a rejected step may be halved before the run stops. Default 8.
    #[serde(default = "d_halvings")]
    pub max_halvings: usize,
    /// Time integrator: "implicit" (default: variational implicit Euler by Newton, with
    /// contact), "bdf2" (second order, the same Newton and contact machinery) or "explicit" (velocity Verlet on the same discrete model,
    /// [`crate::integrator::explicit`]; dynamic mode without a `[ground]` only, stable only
    /// below a step limit: see `slither chart stability`).
    #[serde(default)]
    pub integrator: IntegratorKind,
    /// Contact model: "active-set" (default: contact statuses held and verified, the conic
    /// program only when the checks fail) or "conic" (one Clarabel program per Newton
    /// iterate). The CLI's environment variable `SLITHER_CONTACT=conic` overrides it.
    #[serde(default)]
    pub contact: ContactKind,
    /// Line search: largest number of step halvings (backtracks) per Newton iterate before
    /// the step fails. Default 40, in [1, 200].
    #[serde(default = "d_backtracks")]
    pub max_backtracks: usize,
    /// Line search: Armijo sufficient-decrease constant `c1` in
    /// `f(q + alpha dq) <= f(q) + c1 alpha g.dq`. Default 1e-4, in (0, 0.5).
    #[serde(default = "d_armijo")]
    pub armijo: f64,
    /// Line search: round-off allowance, relative to `|f(q)|`, added to the Armijo bound so a
    /// step at the minimum is not refused for noise. Default 1e-13, in [0, 1e-6].
    #[serde(default = "d_noise")]
    pub line_search_noise: f64,
    /// Diagonal shift of a Hessian that is only semi-definite: first shift, relative to its
    /// largest diagonal entry (then x10 per retry). Default 1e-10, in (0, 1e-2].
    #[serde(default = "d_shift")]
    pub shift: f64,
    /// Diagonal shift retries before the step fails. Default 12, in [1, 30].
    #[serde(default = "d_shift_tries")]
    pub shift_tries: usize,
    /// Active-set contact: Newton iterations before the conic program takes over. Default 40
    /// (capped by `max_iterations`), in [1, 10000].
    #[serde(default = "d_active_iters")]
    pub active_set_max_iterations: usize,
    /// Active-set contact: status changes allowed per step beyond the number of contacts.
    /// Default 8, in [0, 10000].
    #[serde(default = "d_switch_margin")]
    pub active_set_extra_switches: usize,
    /// Newton iterations of the conic path started where a failed active-set attempt stopped
    /// (beyond them it starts over from the step's start). Default 20, in [1, 10000]: the
    /// conic path's normal-force fixed point contracts by about 0.6 per iteration on the
    /// S-start steps the active set stalls on, about 17 iterations from its start.
    #[serde(default = "d_warm")]
    pub warm_conic_iterations: usize,
    /// Normal forces count as settled when they change by less than this fraction of the mean
    /// weight per contact `W / n_c`: between iterates on the conic path; on the active-set
    /// path, their predicted change over the last Newton step (the Hessian row at each held
    /// coordinate times the step, [`crate::contact::reactions`]). Default 1e-3, in (0, 1]
    /// (checked with `tolerance`, see there).
    #[serde(default = "d_normal_tol")]
    pub normal_force_tolerance: f64,
    /// A contact touches the ground when its gap is below this fraction of `a`; it sticks when
    /// its slip over the step is below it. Default 1e-9, in (0, 1e-3].
    #[serde(default = "d_contact_tol")]
    pub contact_tolerance: f64,
    /// Contact forces: a normal force below `-contact_force_tolerance * W / n_c` pulls (the
    /// contact lifts off), a sticking force below it is not tested against the cone, and a
    /// sticking force beyond `1 + contact_force_tolerance` times the cone's bound slides.
    /// Default 1e-9, in (0, 1e-3].
    #[serde(default = "d_contact_tol")]
    pub contact_force_tolerance: f64,
    /// Active-set contact: the sliding contacts' normal forces inside the Newton system (their
    /// change along the step enters the friction force, so Newton converges quadratically);
    /// `false` lags them by one iterate (linear convergence, the behaviour before 2026-11-30).
    /// Default true.
    #[serde(default = "d_true")]
    pub contact_coupling: bool,
    /// Clarabel's absolute and relative gap and feasibility tolerances (scaled problem).
    /// Default 1e-10, in (0, 1e-4].
    #[serde(default = "d_conic_tol")]
    pub conic_tolerance: f64,
    /// Clarabel's interior-point iteration cap. Default 100, in [1, 10000].
    #[serde(default = "d_conic_iters")]
    pub conic_max_iterations: u32,
    /// Clarabel's direct KKT solver: "qdldl" (default) or "faer" (needs the `clarabel-faer`
    /// feature). The CLI's environment variable `SLITHER_CLARABEL_METHOD` overrides it.
    #[serde(default = "d_method")]
    pub clarabel_method: String,
}

/// `[solver] integrator`.
#[derive(Clone, Copy, Debug, Default, Deserialize, serde::Serialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum IntegratorKind {
    /// Variational implicit Euler (Newton), the production integrator.
    #[default]
    Implicit,
    /// Velocity Verlet, the explicit symplectic reference (no contact).
    Explicit,
    /// Second-order backward differentiation (BDF2) as an incremental potential, with contact
    /// ([`crate::integrator::bdf2`]).
    Bdf2,
}

/// `[solver] contact`.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum ContactKind {
    /// Active set first, the conic program as the certified fallback.
    #[default]
    ActiveSet,
    /// The conic program at every Newton iterate.
    Conic,
}

fn d_true() -> bool {
    true
}

fn d_tol() -> f64 {
    5e-6
}
fn d_iters() -> usize {
    50
}
fn d_halvings() -> usize {
    8
}
fn d_backtracks() -> usize {
    40
}
fn d_armijo() -> f64 {
    1e-4
}
fn d_noise() -> f64 {
    1e-13
}
fn d_shift() -> f64 {
    1e-10
}
fn d_shift_tries() -> usize {
    12
}
fn d_active_iters() -> usize {
    40
}
fn d_switch_margin() -> usize {
    8
}
fn d_warm() -> usize {
    20
}
fn d_normal_tol() -> f64 {
    1e-3
}
fn d_contact_tol() -> f64 {
    1e-9
}
fn d_conic_tol() -> f64 {
    1e-10
}
fn d_conic_iters() -> u32 {
    100
}
fn d_method() -> String {
    "qdldl".into()
}

impl Default for SolverSpec {
    fn default() -> Self {
        Self {
            tolerance: d_tol(),
            max_iterations: d_iters(),
            max_halvings: d_halvings(),
            integrator: IntegratorKind::Implicit,
            contact: ContactKind::ActiveSet,
            max_backtracks: d_backtracks(),
            armijo: d_armijo(),
            line_search_noise: d_noise(),
            shift: d_shift(),
            shift_tries: d_shift_tries(),
            active_set_max_iterations: d_active_iters(),
            active_set_extra_switches: d_switch_margin(),
            warm_conic_iterations: d_warm(),
            contact_coupling: true,
            normal_force_tolerance: d_normal_tol(),
            contact_tolerance: d_contact_tol(),
            contact_force_tolerance: d_contact_tol(),
            conic_tolerance: d_conic_tol(),
            conic_max_iterations: d_conic_iters(),
            clarabel_method: d_method(),
        }
    }
}

impl SolverSpec {
    /// Range checks of the settings beyond tolerance, iterations and halvings (checked by the
    /// problem validator): `Err((key, value, allowed))`.
    pub(crate) fn check_settings(&self) -> Result<(), (&'static str, String, &'static str)> {
        let int = |key, v: usize, lo: usize, hi: usize, allowed| {
            if (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err((key, v.to_string(), allowed))
            }
        };
        let real = |key, v: f64, ok: bool, allowed| {
            if v.is_finite() && ok {
                Ok(())
            } else {
                Err((key, v.to_string(), allowed))
            }
        };
        int(
            "max_backtracks",
            self.max_backtracks,
            1,
            200,
            "an integer in [1, 200]",
        )?;
        real(
            "armijo",
            self.armijo,
            self.armijo > 0.0 && self.armijo < 0.5,
            "in (0, 0.5)",
        )?;
        real(
            "line_search_noise",
            self.line_search_noise,
            (0.0..=1e-6).contains(&self.line_search_noise),
            "in [0, 1e-6] (relative to the objective)",
        )?;
        real(
            "shift",
            self.shift,
            self.shift > 0.0 && self.shift <= 1e-2,
            "in (0, 1e-2] (relative to the largest diagonal entry)",
        )?;
        int(
            "shift_tries",
            self.shift_tries,
            1,
            30,
            "an integer in [1, 30]",
        )?;
        int(
            "active_set_max_iterations",
            self.active_set_max_iterations,
            1,
            10_000,
            "an integer in [1, 10000]",
        )?;
        int(
            "active_set_extra_switches",
            self.active_set_extra_switches,
            0,
            10_000,
            "an integer in [0, 10000]",
        )?;
        int(
            "warm_conic_iterations",
            self.warm_conic_iterations,
            1,
            10_000,
            "an integer in [1, 10000]",
        )?;
        real(
            "normal_force_tolerance",
            self.normal_force_tolerance,
            self.normal_force_tolerance > 0.0 && self.normal_force_tolerance <= 1.0,
            "in (0, 1] (fraction of the mean weight per contact)",
        )?;
        real(
            "contact_tolerance",
            self.contact_tolerance,
            self.contact_tolerance > 0.0 && self.contact_tolerance <= 1e-3,
            "in (0, 1e-3] (fraction of the diameter a)",
        )?;
        real(
            "contact_force_tolerance",
            self.contact_force_tolerance,
            self.contact_force_tolerance > 0.0 && self.contact_force_tolerance <= 1e-3,
            "in (0, 1e-3] (fraction of the mean weight per contact)",
        )?;
        real(
            "conic_tolerance",
            self.conic_tolerance,
            self.conic_tolerance > 0.0 && self.conic_tolerance <= 1e-4,
            "in (0, 1e-4]",
        )?;
        int(
            "conic_max_iterations",
            self.conic_max_iterations as usize,
            1,
            10_000,
            "an integer in [1, 10000]",
        )?;
        if !matches!(self.clarabel_method.as_str(), "qdldl" | "faer") {
            return Err((
                "clarabel_method",
                format!("{:?}", self.clarabel_method),
                "\"qdldl\" or \"faer\"",
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
