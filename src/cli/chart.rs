//! `slither chart`: the work-precision chart and the stability map.
use clap::Subcommand;
use slither::model::Model;
use slither::problem;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Subcommand)]
pub enum ChartCmd {
    /// Final-centreline error against wall time for both integrators at several steps, against
    /// a Richardson-checked velocity Verlet reference (a scene without [ground]).
    WorkPrecision {
        /// Problem file: without [ground] (e.g. problems/cantilever_swing.toml) implicit Euler
        /// against velocity Verlet; with [ground] and a gait (e.g. problems/s_start.toml)
        /// implicit Euler, BDF2 and adaptive BDF2 against a cached fine implicit Euler reference.
        problem: PathBuf,
        /// Output directory (created if absent).
        #[arg(long, default_value = "out/work_precision")]
        out: PathBuf,
        /// Another code's runs of the same scene (CSV: scene, code, elements, dt_s,
        /// v_s_over_v_m, reference_v_s_over_v_m, wall_s_per_simulated_s), drawn as their own
        /// series against their own converged value (gait scenes only).
        #[arg(long)]
        external: Option<PathBuf>,
        /// Meshes (elements, comma-separated, e.g. 50,100,200) of a gait scene's runs; the
        /// reference runs on the finest. Default: the file's mesh, twice and four times it.
        #[arg(long, value_delimiter = ',', value_parser = parse_mesh)]
        meshes: Vec<usize>,
        /// Fixed BDF2 steps (s, comma-separated, e.g. 3.6e-3) of a gait scene, drawn as their
        /// own line on every mesh. Default: none.
        #[arg(long, value_delimiter = ',', value_parser = parse_step)]
        bdf2_dt: Vec<f64>,
    },
    /// Largest stable step of each integrator over scaled weight W and element count, by
    /// bisection, for the cantilever swing (or --problem).
    Stability {
        /// Base scene without [ground] (default: the bundled problems/cantilever_swing.toml).
        #[arg(long)]
        problem: Option<PathBuf>,
        /// Output directory (created if absent).
        #[arg(long, default_value = "out/stability")]
        out: PathBuf,
    },
}

pub fn chart_cmd(which: ChartCmd) -> ExitCode {
    use slither::charts;
    const SWING: &str = include_str!("../../problems/cantilever_swing.toml");
    let load = |path: &Path| problem::load(path);
    let (p, scene, out) = match &which {
        ChartCmd::WorkPrecision { problem, out, .. } => {
            (load(problem), problem.clone(), out.clone())
        }
        ChartCmd::Stability {
            problem: Some(f),
            out,
        } => (load(f), f.clone(), out.clone()),
        ChartCmd::Stability { problem: None, out } => {
            let name = PathBuf::from("problems/cantilever_swing.toml");
            (problem::parse(SWING, &name), name, out.clone())
        }
    };
    let p = match p {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let name = scene.file_name().map_or(scene.display().to_string(), |n| {
        n.to_string_lossy().into_owned()
    });
    let mut log = |line: &str| eprintln!("{line}");
    let gait_scene = p.ground.is_some() && p.time.mode == problem::Mode::Dynamic;
    let has_gait = p.gait.kind != problem::Kind::None && p.gait.stress > 0.0;
    if gait_scene && !has_gait && matches!(which, ChartCmd::WorkPrecision { .. }) {
        eprintln!(
            "error: {}: the work-precision chart of a scene with [ground] measures the error of v_s/v_m and needs a [gait] with stress > 0; this scene has none (a scene without [ground] is compared by its final centreline)",
            scene.display()
        );
        return ExitCode::from(2);
    }
    let external = match &which {
        ChartCmd::WorkPrecision {
            external: Some(f), ..
        } => Some(f),
        _ => None,
    };
    if let (Some(f), false) = (external, gait_scene) {
        eprintln!(
            "error: {}: --external {} needs a scene with [ground] and a gait (external points are errors of v_s/v_m)",
            scene.display(),
            f.display()
        );
        return ExitCode::from(2);
    }
    if gait_scene && matches!(which, ChartCmd::WorkPrecision { .. }) {
        // A scene with ground: implicit Euler, BDF2 and adaptive BDF2 against a fine implicit
        // Euler reference, and another code's runs when given (read first: a bad file fails
        // before the runs).
        let external = match external
            .map(|f| charts::read_external(f, &name))
            .transpose()
        {
            Ok(e) => e.unwrap_or_default(),
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(2);
            }
        };
        let model = Model::new(&p);
        let cache = out.join("reference.json");
        if let Err(e) = std::fs::create_dir_all(&out) {
            eprintln!("error: {}: {e}", out.display());
            return ExitCode::from(1);
        }
        let mut opts = charts::GaitPrecisionOptions::default();
        if let ChartCmd::WorkPrecision {
            meshes, bdf2_dt, ..
        } = &which
        {
            opts.meshes.clone_from(meshes);
            opts.bdf2_dt.clone_from(bdf2_dt);
        }
        let r = charts::gait_precision(&name, &p, &model, &opts, Some(&cache), &mut log).and_then(
            |g| {
                let g = g.with_external(external);
                eprint!("{}", g.summary());
                charts::write_gait_precision(&out, &g)
            },
        );
        return match r {
            Ok(()) => {
                eprintln!("wrote {}", out.display());
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {}: {e}", scene.display());
                ExitCode::from(1)
            }
        };
    }
    if p.ground.is_some() || p.time.mode == problem::Mode::Static {
        eprintln!(
            "error: {}: the stability chart (and the work-precision chart of a scene without ground) needs a dynamic scene without [ground] (the explicit integrator has no contact)",
            scene.display()
        );
        return ExitCode::from(2);
    }
    let r = match which {
        ChartCmd::WorkPrecision { .. } => {
            let model = Model::new(&p);
            charts::work_precision(&name, &model, &Default::default(), &mut log).and_then(|wp| {
                eprint!("{}", wp.summary());
                charts::write_work_precision(&out, &wp)
            })
        }
        ChartCmd::Stability { .. } => {
            charts::stability_map(&name, &p, &Default::default(), &mut log).and_then(|map| {
                eprint!("{}", map.summary());
                charts::write_stability(&out, &map)
            })
        }
    };
    match r {
        Ok(()) => {
            eprintln!("wrote {}", out.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {}: {e}", scene.display());
            ExitCode::from(1)
        }
    }
}

/// A mesh of `--meshes`: a whole number of elements in [2, 100000].
fn parse_mesh(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if (2..=100_000).contains(&n) => Ok(n),
        _ => Err(format!(
            "'{text}' is not a mesh: a whole number of elements in [2, 100000]"
        )),
    }
}

/// A step of `--bdf2-dt`: seconds in (0, 1].
fn parse_step(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(h) if h > 0.0 && h <= 1.0 => Ok(h),
        _ => Err(format!("'{text}' is not a step: seconds in (0, 1]")),
    }
}
