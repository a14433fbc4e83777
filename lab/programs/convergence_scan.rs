//! `v_s/v_m` of a scene over meshes and fixed steps, one line per run with its wall time: the
//! raw numbers behind a convergence table, and with `--chart` a chart of `v_s/v_m` against the
//! element count.
//!
//! ```sh
//! cargo run --release --example convergence_scan -- SCENE.toml DURATION N1,N2,.. DT1,DT2,..
//!     [--bdf2] [--csv OUT.csv] [--chart OUT.png] [--reference LO,HI]
//! ```
//! `DURATION` 0 keeps the file's. A step is implicit Euler's (BDF2's with `--bdf2`), or names
//! its integrator: `implicit:5e-4`, `bdf2:2e-3`. The runs are independent and run in parallel (rayon, one
//! per core); lines are printed in the order of the lists. `--reference LO,HI` draws the
//! interval the converged value is known to lie in as two horizontal lines, and prints every
//! run's error against its middle. Printed after the runs: for each step, the mean and
//! standard deviation of `v_s/v_m` over the meshes of each half of the element list (the
//! scatter from mesh to mesh, against the trend).
use rayon::prelude::*;
use slither::model::Model;
use slither::problem::IntegratorKind;
use slither::studies::accuracy::selection::{accuracy_problem, Resolution};
use slither::{observe, plot, problem, sim};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

struct Args {
    scene: PathBuf,
    duration: f64,
    elements: Vec<usize>,
    steps: Vec<(bool, f64)>,
    csv: Option<PathBuf>,
    chart: Option<PathBuf>,
    reference: Option<(f64, f64)>,
}

fn usage() -> ! {
    eprintln!(
        "usage: convergence_scan SCENE.toml DURATION N1,N2,.. DT1,DT2,.. [--bdf2] [--csv OUT.csv] \
         [--chart OUT.png] [--reference LO,HI]"
    );
    std::process::exit(2)
}

fn list<T: std::str::FromStr>(s: &str, what: &str) -> Vec<T> {
    s.split(',')
        .map(|x| {
            x.trim().parse().unwrap_or_else(|_| {
                eprintln!("convergence_scan: {what}: '{x}' is not a number");
                std::process::exit(2)
            })
        })
        .collect()
}

fn parse() -> Args {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let positional: Vec<&String> = a.iter().take_while(|s| !s.starts_with("--")).collect();
    if positional.len() != 4 {
        usage();
    }
    let mut args = Args {
        scene: PathBuf::from(positional[0]),
        duration: list(positional[1], "DURATION")[0],
        elements: list(positional[2], "element counts"),
        steps: Vec::new(),
        csv: None,
        chart: None,
        reference: None,
    };
    let mut bdf2 = false;
    let mut rest = a[4..].iter();
    while let Some(flag) = rest.next() {
        let mut value = || rest.next().cloned().unwrap_or_else(|| usage());
        match flag.as_str() {
            "--bdf2" => bdf2 = true,
            "--csv" => args.csv = Some(PathBuf::from(value())),
            "--chart" => args.chart = Some(PathBuf::from(value())),
            "--reference" => {
                let r: Vec<f64> = list(&value(), "--reference");
                if r.len() != 2 || r[0].is_nan() || r[1].is_nan() || r[0] > r[1] {
                    eprintln!("convergence_scan: --reference takes LO,HI with LO <= HI");
                    std::process::exit(2)
                }
                args.reference = Some((r[0], r[1]));
            }
            _ => usage(),
        }
    }
    args.steps = positional[3]
        .split(',')
        .map(|token| match token.split_once(':') {
            Some(("implicit", h)) => (false, list(h, "steps")[0]),
            Some(("bdf2", h)) => (true, list(h, "steps")[0]),
            Some((other, _)) => {
                eprintln!("convergence_scan: unknown integrator '{other}' (implicit or bdf2)");
                std::process::exit(2)
            }
            None => (bdf2, list(token, "steps")[0]),
        })
        .collect();
    args
}

fn method(bdf2: bool) -> &'static str {
    if bdf2 {
        "BDF2"
    } else {
        "implicit Euler"
    }
}

struct Run {
    elements: usize,
    bdf2: bool,
    dt: f64,
    v: f64,
    wall: f64,
    steps: usize,
    iterations: f64,
    failure: Option<String>,
}

fn main() {
    let args = parse();
    let mut p = problem::load(&args.scene).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(2)
    });
    if args.duration > 0.0 {
        p.time.duration = Some(args.duration);
    }
    let jobs: Vec<(usize, (bool, f64))> = args
        .elements
        .iter()
        .flat_map(|&n| args.steps.iter().map(move |&h| (n, h)))
        .collect();
    let runs: Vec<Run> = jobs
        .par_iter()
        .map(|&(n, (bdf2, h))| {
            let mut q = accuracy_problem(&p, n, Resolution::Step(h));
            if bdf2 {
                q.solver.integrator = IntegratorKind::Bdf2;
            }
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
            Run {
                elements: n,
                bdf2,
                dt: h,
                v,
                wall: o.wall_time_s,
                steps: o.steps.accepted,
                iterations: o.stats.newton_iterations as f64 / o.steps.accepted.max(1) as f64,
                failure: o.error.map(|e| e.to_string()),
            }
        })
        .collect();
    let mid = args.reference.map(|(lo, hi)| 0.5 * (lo + hi));
    let mut csv = String::from("method,elements,dt_s,v_s_over_v_m,error_vs_reference,wall_time_s,steps,newton_iterations_per_step\n");
    for r in &runs {
        let err = mid.map_or(f64::NAN, |c| r.v / c - 1.0);
        println!(
            "{} {:5} {:.4e} {:.6} {} {:.2} s {} steps {:.2} it/step{}",
            method(r.bdf2),
            r.elements,
            r.dt,
            r.v,
            mid.map_or(String::new(), |_| format!("({:+.2} %)", 100.0 * err)),
            r.wall,
            r.steps,
            r.iterations,
            r.failure
                .as_ref()
                .map_or(String::new(), |e| format!(" failed: {e}"))
        );
        let _ = writeln!(
            csv,
            "{},{},{:e},{},{},{},{},{}",
            method(r.bdf2),
            r.elements,
            r.dt,
            r.v,
            err,
            r.wall,
            r.steps,
            r.iterations
        );
    }
    // The scatter from mesh to mesh: each half of the element list on its own.
    let half = args.elements.len() / 2;
    for &(bdf2, h) in &args.steps {
        for part in [&args.elements[..half], &args.elements[half..]] {
            let v: Vec<f64> = runs
                .iter()
                .filter(|r| {
                    (r.bdf2, r.dt) == (bdf2, h) && part.contains(&r.elements) && r.v.is_finite()
                })
                .map(|r| r.v)
                .collect();
            if v.len() < 2 {
                continue;
            }
            let n = v.len() as f64;
            let mean = v.iter().sum::<f64>() / n;
            let sd = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
            println!(
                "{} dt {h:.4e}, {} to {} elements ({} meshes): mean {mean:.5}{}, sd {sd:.5} ({:.2} %), range {:.5} to {:.5}",
                method(bdf2),
                part[0],
                part[part.len() - 1],
                v.len(),
                mid.map_or(String::new(), |c| format!(" ({:+.2} %)", 100.0 * (mean / c - 1.0))),
                100.0 * sd / mean,
                v.iter().cloned().fold(f64::INFINITY, f64::min),
                v.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
            );
        }
    }
    if let Some(path) = &args.csv {
        std::fs::write(path, csv).unwrap_or_else(|e| {
            eprintln!("convergence_scan: cannot write {}: {e}", path.display());
            std::process::exit(1)
        });
    }
    if let Some(path) = &args.chart {
        chart(path, &args, &runs);
    }
}

/// `v_s/v_m` against the element count, one series per step, and the reference interval.
fn chart(path: &Path, args: &Args, runs: &[Run]) {
    let mut labels = Vec::new();
    let mut series: Vec<Vec<(f64, f64)>> = Vec::new();
    for &(bdf2, h) in &args.steps {
        labels.push(format!("{}, dt {h:.2e} s", method(bdf2)));
        series.push(
            runs.iter()
                .filter(|r| (r.bdf2, r.dt) == (bdf2, h) && r.v.is_finite())
                .map(|r| (r.elements as f64, r.v))
                .collect(),
        );
    }
    if let Some((lo, hi)) = args.reference {
        let n0 = *args.elements.iter().min().unwrap_or(&1) as f64;
        let n1 = *args.elements.iter().max().unwrap_or(&1) as f64;
        labels.push(format!("converged: {lo:.4}"));
        series.push(vec![(n0, lo), (n1, lo)]);
        labels.push(format!("converged: {hi:.4}"));
        series.push(vec![(n0, hi), (n1, hi)]);
    }
    let named: Vec<(&str, Vec<(f64, f64)>)> =
        labels.iter().map(String::as_str).zip(series).collect();
    let title = format!(
        "{}: v_s/v_m against the mesh",
        args.scene
            .file_name()
            .map_or(String::new(), |f| f.to_string_lossy().into_owned())
    );
    if let Err(e) = plot::xy(path, &title, "elements", "v_s/v_m", &named, true, false) {
        eprintln!("convergence_scan: chart: {e}");
        std::process::exit(1)
    }
    println!("chart: {}", path.display());
}
