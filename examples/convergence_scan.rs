//! `v_s/v_m` of a scene over meshes and steps (implicit Euler at fixed steps), one line per
//! run with its wall time: the raw numbers behind a convergence table.
//!
//! ```sh
//! cargo run --release --example convergence_scan -- SCENE.toml DURATION N1,N2,.. DT1,DT2,..
//! ```
//! `DURATION` 0 keeps the file's.
use slither::design::selection::{accuracy_problem, Resolution};
use slither::model::Model;
use slither::{observe, problem, sim};
use std::path::Path;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    if a.len() < 5 {
        eprintln!("usage: convergence_scan SCENE.toml DURATION N1,N2,.. DT1,DT2,..");
        std::process::exit(2);
    }
    let mut p = problem::load(Path::new(&a[1])).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(2)
    });
    let duration: f64 = a[2].parse().expect("DURATION");
    if duration > 0.0 {
        p.time.duration = Some(duration);
    }
    let list = |s: &str| -> Vec<f64> { s.split(',').map(|x| x.parse().expect("number")).collect() };
    for n in list(&a[3]) {
        for h in list(&a[4]) {
            let q = accuracy_problem(&p, n as usize, Resolution::Step(h));
            let m = Model::new(&q);
            let muscles = Box::new(slither::gait::Muscles {
                gait: m.gait.clone(),
            });
            let o = sim::run(&m, muscles, &mut |_| {}, &mut |_| {});
            let v = if o.error.is_none() && !o.observed.is_empty() {
                observe::measure(&m, &o, observe::Measure::Ends, &mut |_| {})
                    .1
                    .v_s_over_v_m
            } else {
                f64::NAN
            };
            println!(
                "{n:5} {h:.4e} {v:.6} {:.2} s {} steps{}",
                o.wall_time_s,
                o.steps.accepted,
                o.error.map_or(String::new(), |e| format!(" failed: {e}"))
            );
        }
    }
}
