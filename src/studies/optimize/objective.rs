//! What a study minimises: its objective, the value of one run, and the rows' resume key.
//!
//! The objective of a finished run (m/s, or dimensionless for the sidewinding margin), lower is
//! better, without the out-of-bounds and heading penalties (those are added by the search, from
//! the row, so changing them never invalidates a row):
//!
//! * `v_s`: `-v_s`;
//! * `broadside`: `-lateral_speed + turn_penalty * mean |turn| + stationary_penalty *
//!   max(0, 0.8 - stationary share min)`, per launch period;
//! * `sidewinding`: minus the sidewinding margin.
//!
//! The same function scores a search's row ([`super::simulate`]), an ensemble member of
//! `optimize --ensemble` ([`super::check_optimum`]) and the history figure's curve.

use super::*;

/// Default `turn_penalty` (m/s per degree per cycle): a turn of 5 degrees per cycle costs
/// 0.01 m/s, about a sixth of the bundled sidewinding's lateral speed.
pub const DEFAULT_TURN_PENALTY: f64 = study_keys::STUDY_TURN_PENALTY.real();

/// What a study maximises (`[study] objective`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub enum Objective {
    /// The mean forward speed `v_s`.
    #[default]
    Vs,
    /// The mean lateral speed per cycle less `turn_penalty` times the mean |turn| per cycle.
    Broadside,
    /// The sidewinding margin ([`crate::observe::periodic::Periodic::sidewinding_margin`]): how
    /// far the worst cycle lies inside the four sidewinding criteria (dimensionless).
    Sidewinding,
}

impl Objective {
    /// The name as written in the study file (`[study] objective`).
    pub fn as_str(self) -> &'static str {
        match self {
            Objective::Vs => "v_s",
            Objective::Broadside => "broadside",
            Objective::Sidewinding => "sidewinding",
        }
    }

    /// What is maximised, for figure axes and messages (the objective is its negative).
    pub fn maximised(self) -> &'static str {
        match self {
            Objective::Vs => "forward speed v_s (m/s)",
            Objective::Broadside => "broadside speed less penalties (m/s)",
            Objective::Sidewinding => "sidewinding margin",
        }
    }
}

/// What the objective of a run is computed from: its speeds and, for a gait with a launch
/// period, its periodic values (NaN when not measured).
#[derive(Clone, Copy, Debug)]
pub struct ObjectiveInputs {
    /// Mean forward speed (m/s).
    pub v_s: f64,
    /// Travelling speed of the gait (m/s).
    pub v_m: f64,
    /// Mean lateral speed per cycle over `v_m`.
    pub lateral_speed_over_v_m: f64,
    /// Mean |turn| per cycle (degrees).
    pub turn_deg_mean_abs: f64,
    /// Smallest stationary share of the contact time over the cycles.
    pub stationary_contact_share_min: f64,
    /// The sidewinding margin.
    pub sidewinding_margin: f64,
}

impl ObjectiveInputs {
    /// From a run's forward speed, its gait's `v_m` and its periodic observables (if any).
    pub fn of(v_s: f64, v_m: f64, p: Option<&observe::periodic::Periodic>) -> Self {
        ObjectiveInputs {
            v_s,
            v_m,
            lateral_speed_over_v_m: p.map_or(f64::NAN, |p| p.lateral_speed_over_v_m),
            turn_deg_mean_abs: p.map_or(f64::NAN, |p| p.turn_deg_mean_abs),
            stationary_contact_share_min: p.map_or(f64::NAN, |p| p.stationary_contact_share_min),
            sidewinding_margin: p.map_or(f64::NAN, |p| p.sidewinding_margin()),
        }
    }
}

impl Study {
    /// The objective of a finished run (module doc): NaN when a value it needs is not measured.
    pub fn objective_of(&self, x: &ObjectiveInputs) -> f64 {
        match self.objective {
            Objective::Vs => -x.v_s,
            Objective::Broadside => {
                -x.lateral_speed_over_v_m * x.v_m
                    + self.turn_penalty * x.turn_deg_mean_abs
                    + self.stationary_penalty
                        * (observe::periodic::STATIONARY_SHARE_MIN - x.stationary_contact_share_min)
                            .max(0.0)
            }
            Objective::Sidewinding => -x.sidewinding_margin,
        }
    }

    /// The resume key of the study's rows (`base_hash` in `history.csv`): the base problem's
    /// hash, mixed with the settings the row's `objective` value depends on (unchanged for the
    /// default `v_s`, whose value is `-v_s` whatever the penalties). Rows of another key are
    /// simulated again, never reused.
    pub fn row_hash(&self) -> String {
        match self.objective {
            Objective::Vs => self.base_hash.clone(),
            o => {
                let text = format!(
                    "{} objective={} turn_penalty={:e} stationary_penalty={:e}",
                    self.base_hash,
                    o.as_str(),
                    self.turn_penalty,
                    self.stationary_penalty
                );
                format!("{:016x}", fnv1a(text.as_bytes()))
            }
        }
    }
}
