//! Side by side with PyElastica: runs the two bundled copies of PyElastica's S-start reference
//! scenes and prints both codes' forward speed, heading, height and wall time per simulated
//! second (the README's table).
//!
//! ```sh
//! cargo run --release --example pyelastica_compare [-- REFERENCE_DIR]
//! ```
//!
//! `REFERENCE_DIR` (default `../shared/reference/pyelastica`) holds PyElastica's JSON results.
//! Both codes' speeds are the centroid's net displacement along the initial head direction over
//! the run time, divided by `v_m`; the heading is the displacement's angle from that direction.

use slither::model::Model;
use slither::{observe, problem, sim};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// One scene: our problem file and PyElastica's result file.
const SCENES: [(&str, &str, &str); 2] = [
    (
        "G 15, sigma 0.04 L, centres 0.2/0.3/0.4",
        "problems/pyelastica_s_start.toml",
        "sstart_forward_n50.json",
    ),
    (
        "G 17.5, sigma 0.06 L, b 0.4",
        "problems/pyelastica_straight.toml",
        "best_W300_tau17.5.json",
    ),
];

/// What is compared, for one code on one scene.
struct Row {
    v_s_over_v_m: f64,
    angle_deg: f64,
    height_over_a: f64,
    wall_per_sim_s: f64,
    dt: f64,
}

fn pyelastica(path: &Path) -> Result<Row, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    let j: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let num = |v: &serde_json::Value, what: &str| {
        v.as_f64()
            .ok_or_else(|| format!("{}: `{what}` is missing or not a number", path.display()))
    };
    let p = &j["params"];
    let t = num(&j["t_reached"], "t_reached")?;
    let vm = num(&p["v_m"], "params.v_m")?;
    // PyElastica's y axis is up: the displacement is (forward x, up y, lateral z).
    let d = j
        .get("com_disp_total")
        .or_else(|| j.get("com_disp"))
        .ok_or_else(|| format!("{}: no centre-of-mass displacement", path.display()))?;
    let (fw, lat) = (num(&d[0], "com_disp[0]")?, num(&d[2], "com_disp[2]")?);
    Ok(Row {
        v_s_over_v_m: fw / t / vm,
        angle_deg: lat.abs().atan2(fw).to_degrees(),
        height_over_a: num(&j["max_height_over_a"], "max_height_over_a")?,
        wall_per_sim_s: num(&j["wall_per_sim_second"], "wall_per_sim_second")?,
        dt: num(&p["dt"], "params.dt")?,
    })
}

fn slither_row(path: &Path) -> Result<Row, String> {
    let p = problem::load(path).map_err(|e| e.to_string())?;
    let m = Model::new(&p);
    let o = sim::run_gait(&m, p.solver.integrator, &mut |_| {}, &mut |_| {})
        .map_err(|e| format!("{}: {e}", path.display()))?;
    if let Some(e) = &o.error {
        return Err(format!("{}: {e}", path.display()));
    }
    let ob = observe::of_outcome(&m, &o);
    Ok(Row {
        v_s_over_v_m: ob.v_s_over_v_m,
        angle_deg: ob.displacement_angle_deg,
        height_over_a: ob.max_elevation_over_a,
        wall_per_sim_s: o.wall_time_s / m.duration,
        dt: m.dt,
    })
}

fn main() -> ExitCode {
    let dir = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("../shared/reference/pyelastica"));
    println!("| scene | code | step (s) | v_s/v_m | off-axis (deg) | max height / a | wall s per simulated s |");
    println!("|---|---|---|---|---|---|---|");
    for (name, ours, theirs) in SCENES {
        let rows =
            pyelastica(&dir.join(theirs)).and_then(|r| Ok((r, slither_row(Path::new(ours))?)));
        let (pe, sl) = match rows {
            Ok(r) => r,
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(2);
            }
        };
        for (code, r) in [("PyElastica", pe), ("slither", sl)] {
            println!(
                "| {name} | {code} | {:.0e} | {:.3} | {:.0} | {:.2} | {:.2} |",
                r.dt, r.v_s_over_v_m, r.angle_deg, r.height_over_a, r.wall_per_sim_s
            );
        }
    }
    ExitCode::SUCCESS
}
