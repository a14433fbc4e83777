//! One cell of the diagram: its simulation and the measured values.
use super::file::{cell_problem, cell_problem_with, finer_problem, Protocol, Verify};
use crate::model::Model;
use crate::observe::{self, Regime, RegimeInputs};
use crate::problem::Problem;
use crate::studies::{ensemble, optimize::PeriodicColumns, optimize::Status};

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
    /// The cell's verification, when the phase file asks for one (`verify = { ... }`).
    pub verify: Option<Verification>,
    /// The periodic observables of a finished run of a gait with a launch period and a couple
    /// (`G > 0`; [`crate::observe::periodic`]), as `history.csv` has them.
    pub periodic: Option<PeriodicColumns>,
}

/// How a verified cell's runs agree ([`simulate_verified`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Verification {
    /// Fraction of the cell's runs (the study's, the finer one, the perturbed ones) whose label
    /// is the cell's reported label, and for a gait with a launch period whose sidewinding
    /// verdict is the reported one's too ([`agrees`]; a failed run agrees with nothing).
    pub label_agreement: f64,
    /// Smallest `v_s/v_m` over the runs that finished.
    pub v_s_over_v_m_min: f64,
    /// Largest `v_s/v_m` over the runs that finished.
    pub v_s_over_v_m_max: f64,
    /// The label at the study's resolution (`None`: failed).
    pub regime_base: Option<Regime>,
    /// The label at the finer resolution (`None`: failed or no finer run).
    pub regime_finer: Option<Regime>,
    /// Runs of the cell.
    pub runs: usize,
    /// The cell's ensemble seed (perturbed run `k` has seed
    /// [`ensemble::member_seed`]`(seed, k)`).
    pub seed: u64,
}

impl Cell {
    /// Whether every run of the cell gave its label (a cell without verification is taken as
    /// it is: unanimous).
    pub fn unanimous(&self) -> bool {
        self.verify
            .as_ref()
            .is_none_or(|v| v.label_agreement == 1.0)
    }
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
            verify: None,
            periodic: None,
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
    run_cell(&cell_problem(base, w, g), w, g, None)
}

/// The seed of cell `(w, g)`'s perturbed runs for the verification seed `seed`: the same in
/// every shard and every order of the cells.
pub fn cell_seed(seed: u64, w: f64, g: f64) -> u64 {
    let mut bytes = seed.to_le_bytes().to_vec();
    bytes.extend(w.to_bits().to_le_bytes());
    bytes.extend(g.to_bits().to_le_bytes());
    crate::studies::fnv1a(&bytes)
}

/// Simulate one cell with its verification (`None`: [`simulate`]). The runs: the study's, with
/// `finer` one at half the step and twice the elements ([`finer_problem`]), and `perturbations`
/// perturbed ones (member `k` of an [`ensemble`] of the cell's problem seeded by [`cell_seed`]),
/// all in parallel. The returned cell is the finest run's (the finer one if any, else the
/// study's), with [`Verification`]: the agreement of every run with its label, the spread of
/// `v_s/v_m` and the labels at both resolutions; its wall time is the sum of the runs'.
///
/// `protocol` says how the cell is made from `base` ([`cell_problem_with`]; the default is
/// [`cell_problem`]'s).
pub fn simulate_verified(
    base: &Problem,
    w: f64,
    g: f64,
    verify: Option<&Verify>,
    protocol: Protocol,
) -> Cell {
    let p = cell_problem_with(base, w, g, protocol);
    let Some(v) = verify else {
        return run_cell(&p, w, g, None);
    };
    use rayon::prelude::*;
    let seed = cell_seed(v.seed, w, g);
    let spec = ensemble::Spec {
        runs: v.perturbations,
        seed,
        perturbation: v.perturbation(),
    };
    // Run 0 the study's, run 1 the finer (if any), then the perturbed ones.
    let kinds: Vec<Option<usize>> = std::iter::once(None)
        .chain(v.finer.then_some(None))
        .chain((0..v.perturbations).map(Some))
        .collect();
    let runs: Vec<Cell> = kinds
        .par_iter()
        .enumerate()
        .map(|(i, kind)| match kind {
            None if i == 0 => run_cell(&p, w, g, None),
            None => run_cell(&finer_problem(&p), w, g, None),
            Some(k) => {
                let ms = ensemble::member_seed(seed, *k);
                let q = ensemble::member_problem(&p, &spec.perturbation, ms, *k, spec.runs);
                run_cell(&q, w, g, Some((&spec.perturbation, ms)))
            }
        })
        .collect();
    let finer = v.finer.then(|| runs[1].clone());
    let mut cell = finer.clone().unwrap_or_else(|| runs[0].clone());
    let agree = runs.iter().filter(|r| agrees(r, &cell)).count();
    let speeds = runs
        .iter()
        .filter(|r| r.status == Status::Ok)
        .map(|r| r.v_s_over_v_m)
        .filter(|x| x.is_finite());
    let (lo, hi) = speeds.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    cell.wall_time_s = runs.iter().map(|r| r.wall_time_s).sum();
    cell.verify = Some(Verification {
        label_agreement: agree as f64 / runs.len() as f64,
        v_s_over_v_m_min: if lo.is_finite() { lo } else { f64::NAN },
        v_s_over_v_m_max: if hi.is_finite() { hi } else { f64::NAN },
        regime_base: runs[0].regime,
        regime_finer: finer.and_then(|f| f.regime),
        runs: runs.len(),
        seed,
    });
    cell
}

/// Whether a verification run agrees with the cell's reported run: the same regime label and,
/// for a gait with a launch period, the same sidewinding verdict (the periodic sub-label), so
/// a cell whose runs sidewind and crawl obliquely by turns is not confident. A failed run
/// agrees with nothing.
pub fn agrees(run: &Cell, reported: &Cell) -> bool {
    run.regime.is_some()
        && run.regime == reported.regime
        && run.periodic.map(|p| p.sidewinding) == reported.periodic.map(|p| p.sidewinding)
}

/// One run of a cell's problem `p` (with the shape perturbation of an ensemble member, if
/// given).
fn run_cell(p: &Problem, w: f64, g: f64, shape: Option<(&ensemble::Perturbation, u64)>) -> Cell {
    let run = std::panic::catch_unwind(|| {
        let mut m = Model::new(p);
        if let Some((pert, seed)) = shape {
            ensemble::perturb_model(&mut m, pert, seed);
        }
        let o = observe::evaluate(&m, observe::Measure::Full, &mut |_| {}, &mut |_| {})?;
        // Measured on a finished run only (as `slither run` and the optimiser do).
        let periodic = o
            .outcome
            .error
            .is_none()
            .then(|| observe::periodic::of_outcome(&m, &o.outcome))
            .flatten();
        Ok::<_, crate::integrator::explicit::Unsupported>((
            o.observables,
            o.outcome,
            periodic.as_ref().map(PeriodicColumns::of),
        ))
    });
    match run {
        Err(_) => Cell::failed(w, g, "the simulation panicked".into()),
        Ok(Err(e)) => Cell::failed(w, g, e.to_string()),
        Ok(Ok((_, o, _))) if o.error.is_some() => {
            let mut c = Cell::failed(w, g, o.error.unwrap().to_string());
            c.wall_time_s = o.wall_time_s;
            c
        }
        Ok(Ok((ob, o, periodic))) => Cell {
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
            verify: None,
            periodic,
        },
    }
}
