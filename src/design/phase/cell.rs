//! One cell of the diagram: its simulation and the measured values.
use super::file::cell_problem;
use crate::design::Status;
use crate::model::Model;
use crate::observe::{self, Regime, RegimeInputs};
use crate::problem::Problem;

/// One cell of the diagram.
#[derive(Clone, Debug)]
pub struct Cell {
    /// Scaled weight `W`.
    pub weight: f64,
    /// Scaled torque `G`.
    pub torque: f64,
    /// Whether the cell's simulation finished (written "ok" or "failed").
    pub status: Status,
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

impl Cell {
    fn failed(w: f64, g: f64, reason: String) -> Self {
        Cell {
            weight: w,
            torque: g,
            status: Status::Failed,
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
}

/// Simulate one cell (never panics: a panic inside the simulation is recorded as a failure).
pub fn simulate(base: &Problem, w: f64, g: f64) -> Cell {
    let p = cell_problem(base, w, g);
    let run = std::panic::catch_unwind(|| {
        let m = Model::new(&p);
        let o = observe::evaluate(&m, observe::Measure::Full, &mut |_| {}, &mut |_| {})?;
        Ok::<_, crate::integrator::explicit::Unsupported>((o.observables, o.outcome))
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
            status: Status::Ok,
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
