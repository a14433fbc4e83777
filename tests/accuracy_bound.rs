//! Does `--accuracy`'s error estimate bound the actual error? On a small S-start (20
//! elements, 0.6 s) the selection runs for a 5 % target; the scene's converged `v_s/v_m` is
//! known from runs at 4 and 8 times the selection's finest mesh at a quarter of its finest step
//! (implicit Euler), and the chosen value's actual error against it must lie below the
//! estimate. The reported Richardson extrapolation must lie within its uncertainty of the
//! converged value.
use slither::design::selection::select;
use slither::model::Model;
use slither::{observe, problem, sim};

fn small_s_start() -> problem::Problem {
    let text = std::fs::read_to_string("problems/s_start.toml").unwrap();
    let mut p = problem::parse(&text, std::path::Path::new("s_start.toml")).unwrap();
    p.rod.elements = 20;
    p.time.duration = Some(0.6);
    p.output.interval = Some(0.06);
    p
}

fn v_ratio(p: &problem::Problem, elements: usize, dt: f64) -> f64 {
    let mut q = p.clone();
    q.rod.elements = elements;
    q.time.dt = Some(dt);
    let m = Model::new(&q);
    let o = sim::run_gait(&m, q.solver.integrator, &mut |_| {}, &mut |_| {}).unwrap();
    assert!(o.error.is_none(), "{:?}", o.error);
    let ends = [o.frames[0].clone(), o.frames[o.frames.len() - 1].clone()];
    let fl = observe::fields(&m, &ends);
    observe::observe(&m, &ends, &fl).v_s_over_v_m
}

#[test]
fn accuracy_estimate_bounds_the_error_against_a_finer_reference() {
    let p = small_s_start();
    let sel = select(&p, 0.05, 80, &mut |l| println!("{l}"));
    let r = &sel.report;
    let finest_n = r.runs.iter().map(|x| x.elements).max().unwrap();
    let finest_dt = r
        .runs
        .iter()
        .filter_map(|x| x.dt)
        .fold(f64::INFINITY, f64::min);
    let v = r
        .runs
        .iter()
        .find(|x| x.elements == r.elements && x.dt == r.dt)
        .unwrap()
        .v_s_over_v_m;
    let (v4, v8) = (
        v_ratio(&p, 4 * finest_n, finest_dt / 4.0),
        v_ratio(&p, 8 * finest_n, finest_dt / 4.0),
    );
    println!(
        "chosen {} el. dt {:?}: {v:.5}, estimate {:.3e}; extrapolated {:.5} +- {:.5}; reference {v4:.5} ({} el.), {v8:.5} ({} el.), dt {:.2e}",
        r.elements,
        r.dt,
        r.estimated_error,
        r.v_s_over_v_m_extrapolated,
        r.v_s_over_v_m_extrapolated_uncertainty,
        4 * finest_n,
        8 * finest_n,
        finest_dt / 4.0
    );
    // The reference is itself converged to well within the estimate it checks.
    let ref_change = (v8 / v4 - 1.0).abs();
    let actual = (v / v8 - 1.0).abs();
    assert!(
        ref_change < 0.25 * r.estimated_error,
        "reference not converged: {v4} {v8}"
    );
    assert!(
        actual <= r.estimated_error,
        "actual error {actual:.3e} above the estimate {:.3e}",
        r.estimated_error
    );
    assert!(
        (r.v_s_over_v_m_extrapolated - v8).abs() <= r.v_s_over_v_m_extrapolated_uncertainty,
        "extrapolated {} +- {} vs {v8}",
        r.v_s_over_v_m_extrapolated,
        r.v_s_over_v_m_extrapolated_uncertainty
    );
}
