//! `[self_contact]`: two parts of the body cannot pass through each other
//! ([`crate::energy::self_contact`]), and its checks.

use super::{keys, Checker, Problem, ProblemError};
use serde::Deserialize;

/// `[self_contact]`: two parts of the body cannot pass through each other
/// ([`crate::energy::self_contact`]). Defaults and ranges: [`keys`] (`SELF_CONTACT_*`).
#[derive(Clone, Debug, Deserialize, serde::Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SelfContactSpec {
    /// On or off ([`keys::SELF_CONTACT_ENABLED`]).
    #[serde(default = "d_sc_enabled")]
    pub enabled: bool,
    /// Activation gap over `a` ([`keys::SELF_CONTACT_ACTIVATION`]).
    #[serde(default = "d_sc_activation")]
    pub activation: f64,
    /// Barrier stiffness in `B / a^2` ([`keys::SELF_CONTACT_STIFFNESS`]).
    #[serde(default = "d_sc_stiffness")]
    pub stiffness: f64,
}
fn d_sc_enabled() -> bool {
    keys::SELF_CONTACT_ENABLED.flag()
}
fn d_sc_activation() -> f64 {
    keys::SELF_CONTACT_ACTIVATION.real()
}
fn d_sc_stiffness() -> f64 {
    keys::SELF_CONTACT_STIFFNESS.real()
}
impl Default for SelfContactSpec {
    fn default() -> Self {
        SelfContactSpec {
            enabled: d_sc_enabled(),
            activation: d_sc_activation(),
            stiffness: d_sc_stiffness(),
        }
    }
}

/// Range checks of `[self_contact]`.
pub(super) fn check_keys(p: &Problem, c: &Checker) -> Result<(), ProblemError> {
    c.key(&keys::SELF_CONTACT_ACTIVATION, p.self_contact.activation)?;
    c.key(&keys::SELF_CONTACT_STIFFNESS, p.self_contact.stiffness)
}
