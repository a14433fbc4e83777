//! Do the solver's stopping rules decide the answer? Runs every bundled scene with its settings
//! and with the two stopping thresholds (`[solver] tolerance`, `normal_force_tolerance`) 100x
//! tighter, and prints the relative change of the scene's headline observable (v_s/v_m for the
//! gaits, the centroid displacement for the others) with the cost of both runs.
//!
//! ```sh
//! cargo run --release --example tolerance_check [SCENE.toml ...]
//! ```
use slither::model::Model;
use slither::{observe, output, problem, sim};
use std::path::{Path, PathBuf};

const SCENES: [&str; 9] = [
    "problems/s_start.toml",
    // The bundled phase study's base: the S-start on 50 elements with ground contact on the curve.
    "problems/phase_s_start_base.toml",
    "problems/s_start_heavy.toml",
    "problems/sidewinding.toml",
    "problems/serpenoid.toml",
    "problems/pyelastica_s_start.toml",
    "problems/pyelastica_straight.toml",
    "problems/slide.toml",
    "problems/incline.toml",
];

struct Run {
    value: f64,
    what: &'static str,
    wall: f64,
    newton_mean: f64,
    conic: usize,
    fallbacks: usize,
    halvings: usize,
}

fn run(p: &problem::Problem) -> Result<Run, String> {
    let m = Model::new(p);
    let o = sim::run_gait(&m, m.solver.integrator, &mut |_| {}, &mut |_| {})
        .map_err(|e| e.to_string())?;
    if let Some(e) = &o.error {
        return Err(e.to_string());
    }
    let (value, what) = if m.gait.couple > 0.0 {
        (observe::of_outcome(&m, &o).v_s_over_v_m, "v_s/v_m")
    } else {
        let d = output::centroid_displacement(&o.frames);
        (
            (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt(),
            "displacement (m)",
        )
    };
    let st = &o.stats;
    Ok(Run {
        value,
        what,
        wall: o.wall_time_s,
        newton_mean: st.newton_iterations as f64 / st.steps.max(1) as f64,
        conic: st.contact.conic_solves,
        fallbacks: st.contact.semismooth_fallbacks,
        halvings: st.step_halvings,
    })
}

fn main() {
    let args: Vec<PathBuf> = std::env::args().skip(1).map(PathBuf::from).collect();
    let scenes: Vec<PathBuf> = if args.is_empty() {
        SCENES.iter().map(PathBuf::from).collect()
    } else {
        args
    };
    println!("| scene | observable | default | 100x tighter | relative change | wall s (default / tight) | Newton it./step | conic solves | fallbacks | halvings |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let mut worst: f64 = 0.0;
    for path in &scenes {
        let p = match problem::load(Path::new(path)) {
            Ok(p) => p,
            Err(e) => {
                eprintln!("error: {e}");
                std::process::exit(2);
            }
        };
        let mut tight = p.clone();
        tight.solver.tolerance /= 100.0;
        tight.solver.normal_force_tolerance /= 100.0;
        let (a, b) = match (run(&p), run(&tight)) {
            (Ok(a), Ok(b)) => (a, b),
            (a, b) => {
                println!(
                    "| {} | failed: {:?} / {:?} |",
                    path.display(),
                    a.err(),
                    b.err()
                );
                continue;
            }
        };
        let rel = (a.value - b.value).abs() / b.value.abs().max(1e-300);
        worst = worst.max(rel);
        println!(
            "| {} | {} | {:.7} | {:.7} | {:.1e} | {:.2} / {:.2} | {:.2} / {:.2} | {} / {} | {} / {} | {} / {} |",
            path.display(),
            a.what,
            a.value,
            b.value,
            rel,
            a.wall,
            b.wall,
            a.newton_mean,
            b.newton_mean,
            a.conic,
            b.conic,
            a.fallbacks,
            b.fallbacks,
            a.halvings,
            b.halvings
        );
    }
    println!("largest relative change: {worst:.1e}");
}
