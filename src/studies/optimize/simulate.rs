//! One evaluation: a simulation of the base problem at a point, measured.

use super::*;

/// Simulate the study's base problem at `p` (the evaluation index is set by the caller) and
/// measure it. Never panics: a failed step, an unsupported integrator, a non-finite speed or a
/// panic inside the simulator gives status [`Status::Failed`] with the reason.
pub fn simulate(study: &Study, p: &GaitParams, progress: &mut dyn FnMut(f64)) -> Evaluation {
    let start = Instant::now();
    let pr = study.problem_at(p);
    let duration = pr.time.duration.unwrap_or(0.0);
    let model = Model::new(&pr);
    let b = model.bend;
    let g = model.gait.couple * model.length / b;
    let w = model.dimensionless().scaled_weight;
    let mut e = Evaluation {
        eval: 0,
        point: *p,
        duration,
        g,
        w,
        v_s: f64::NAN,
        v_s_over_v_m: f64::NAN,
        writhe_max: f64::NAN,
        writhe_mean: f64::NAN,
        displacement_angle_deg: f64::NAN,
        regime: "-".into(),
        periodic: None,
        status: Status::Failed,
        wall_time_s: 0.0,
        reason: String::new(),
        objective_value: f64::NAN,
    };
    let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let o = observe::evaluate(&model, observe::Measure::Full, progress, &mut |_| {})
            .map_err(|err| err.to_string())?;
        let periodic = observe::periodic::of_outcome(&model, &o.outcome);
        Ok::<_, String>((
            (o.observables, periodic),
            o.outcome.error.map(|err| err.to_string()),
        ))
    }));
    match run {
        // A run cut short has not measured the gait: its observables stay NaN (regime "-").
        Ok(Ok((_, Some(reason)))) => {
            e.reason = reason;
            e.regime = "-".into();
        }
        Ok(Ok(((ob, periodic), None))) => {
            e.v_s = ob.v_s;
            e.v_s_over_v_m = ob.v_s_over_v_m;
            e.writhe_max = ob.writhe_max;
            e.writhe_mean = ob.writhe_mean;
            e.displacement_angle_deg = ob.displacement_angle_deg;
            e.regime = ob.regime.to_string();
            e.periodic = periodic.as_ref().map(PeriodicColumns::of);
            let value = study.objective_of(&ObjectiveInputs::of(
                ob.v_s,
                model.gait.speed,
                periodic.as_ref(),
            ));
            e.objective_value = value;
            if !ob.v_s.is_finite() {
                e.reason = "v_s is not finite".into();
            } else if !value.is_finite() {
                e.reason = match study.objective {
                    Objective::Sidewinding => "fewer than 4 full cycles after the settling one: the sidewinding margin is not measured",
                    _ => "no full cycle after the settling one: the broadside objective is not measured",
                }
                .into();
            } else {
                e.status = Status::Ok;
            }
        }
        Ok(Err(reason)) => e.reason = reason,
        Err(panic) => {
            let msg = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            e.reason = format!("the simulator panicked: {msg}");
        }
    }
    e.wall_time_s = start.elapsed().as_secs_f64();
    e
}
