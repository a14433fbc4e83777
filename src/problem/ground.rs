//! `[ground]`: the plane `z = 0` and its anisotropic kinetic Coulomb friction, and its checks.

use super::{keys, Checker, Mode, Problem, ProblemError};
use serde::Deserialize;

/// `[ground]`: a plane `z = 0` with anisotropic kinetic Coulomb friction. Defaults and ranges
/// of every field: [`keys`].
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct GroundSpec {
    /// Coefficient resisting forward (toward the head) sliding ([`keys::GROUND_MU_FORWARD`]).
    #[serde(default = "d_mu_f")]
    pub mu_forward: f64,
    /// Coefficient resisting backward sliding ([`keys::GROUND_MU_BACKWARD`]).
    #[serde(default = "d_mu_b")]
    pub mu_backward: f64,
    /// Coefficient resisting sideways sliding ([`keys::GROUND_MU_SIDEWAYS`]).
    #[serde(default = "d_mu_s")]
    pub mu_sideways: f64,
    /// Incline (degrees): gravity is tilted about y so that the slope rises along +x
    /// ([`keys::GROUND_INCLINE_DEG`]).
    #[serde(default = "d_incline")]
    pub incline_deg: f64,
}
fn d_mu_f() -> f64 {
    keys::GROUND_MU_FORWARD.real()
}
fn d_mu_b() -> f64 {
    keys::GROUND_MU_BACKWARD.real()
}
fn d_mu_s() -> f64 {
    keys::GROUND_MU_SIDEWAYS.real()
}
fn d_incline() -> f64 {
    keys::GROUND_INCLINE_DEG.real()
}

/// Range checks of `[ground]`, and what a ground needs (dynamic mode, gravity).
pub(super) fn check(p: &Problem, c: &Checker) -> Result<(), ProblemError> {
    use keys::*;
    if let Some(gr) = &p.ground {
        c.key(&GROUND_MU_FORWARD, gr.mu_forward)?;
        c.key(&GROUND_MU_BACKWARD, gr.mu_backward)?;
        c.key(&GROUND_MU_SIDEWAYS, gr.mu_sideways)?;
        c.key(&GROUND_INCLINE_DEG, gr.incline_deg)?;
        if p.time.mode == Mode::Static {
            return Err(c.fail(
                "time",
                "mode",
                "\"static\"".into(),
                "\"dynamic\" when a [ground] is present (friction needs time)",
            ));
        }
        if p.gravity.g == 0.0 {
            return Err(c.fail(
                "gravity",
                "g",
                "0".into(),
                "> 0 when a [ground] is present (the normal contact forces, and so friction, come from the weight)",
            ));
        }
    }
    Ok(())
}
