//! How a run of the gait work-precision chart ([`super::gait_precision`]) sets its time
//! resolution: an integrator at fixed steps, an integrator with adaptive steps, or the model
//! the accuracy selection chose. It names the run's line on the chart and is its `method` in
//! `gait_precision.csv`, `gait_precision.json` and the cached reference.
use crate::problem::IntegratorKind;

/// A gait-chart run's method; written as [`GaitMethod::name`] (`implicit`, `bdf2`,
/// `bdf2-adaptive`, `accuracy`, ...).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GaitMethod {
    /// The integrator at a fixed step (`implicit`, `bdf2`, `explicit`).
    Fixed(IntegratorKind),
    /// The integrator with error-controlled steps (`bdf2-adaptive`, ...).
    Adaptive(IntegratorKind),
    /// The model (mesh and time resolution) chosen by the accuracy selection (`accuracy`).
    Accuracy,
}

impl GaitMethod {
    /// Every method, for reading a name back.
    const ALL: [GaitMethod; 7] = [
        GaitMethod::Fixed(IntegratorKind::ImplicitEuler),
        GaitMethod::Fixed(IntegratorKind::Bdf2),
        GaitMethod::Fixed(IntegratorKind::VelocityVerlet),
        GaitMethod::Adaptive(IntegratorKind::ImplicitEuler),
        GaitMethod::Adaptive(IntegratorKind::Bdf2),
        GaitMethod::Adaptive(IntegratorKind::VelocityVerlet),
        GaitMethod::Accuracy,
    ];

    /// Its name in the chart's files and lines: the integrator's [`IntegratorKind::name`],
    /// with `-adaptive` for adaptive steps, or `accuracy`.
    pub fn name(self) -> &'static str {
        match self {
            GaitMethod::Fixed(k) => k.name(),
            GaitMethod::Adaptive(IntegratorKind::ImplicitEuler) => "implicit-adaptive",
            GaitMethod::Adaptive(IntegratorKind::Bdf2) => "bdf2-adaptive",
            GaitMethod::Adaptive(IntegratorKind::VelocityVerlet) => "explicit-adaptive",
            GaitMethod::Accuracy => "accuracy",
        }
    }

    /// The method of a name ([`GaitMethod::name`]).
    pub fn from_name(name: &str) -> Option<GaitMethod> {
        GaitMethod::ALL.into_iter().find(|m| m.name() == name)
    }
}

impl std::fmt::Display for GaitMethod {
    /// The name, padded and aligned as the format asks.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.name())
    }
}

impl serde::Serialize for GaitMethod {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> serde::Deserialize<'de> for GaitMethod {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        GaitMethod::from_name(&name)
            .ok_or_else(|| serde::de::Error::custom(format!("unknown method {name:?}")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_read_back_and_pad() {
        for m in GaitMethod::ALL {
            assert_eq!(GaitMethod::from_name(m.name()), Some(m));
            let json = serde_json::to_string(&m).unwrap();
            assert_eq!(json, format!("\"{}\"", m.name()));
            assert_eq!(serde_json::from_str::<GaitMethod>(&json).unwrap(), m);
        }
        let m = GaitMethod::Fixed(IntegratorKind::Bdf2);
        assert_eq!(format!("{m:14}|"), format!("{:14}|", "bdf2"));
    }
}
