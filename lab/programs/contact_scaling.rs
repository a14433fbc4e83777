//! How the contact Newton's cost grows with the mesh: the bundled S-start's first
//! `DURATION` seconds (0.5 by default) with implicit Euler at `dt` (5e-4 by default) at each
//! element count, and per run the Newton iterations, factorisations and conic fallbacks per
//! step, the step halvings, microseconds per step per element and wall seconds per simulated
//! second, plus the time split (assembly, factorisation, solves, line search, Clarabel).
//!
//! ```sh
//! cargo run --release --example contact_scaling -- [--elements 50,100,200,400] [--duration 0.5]
//!     [--dt 5e-4[,1e-3...]] [--integrator implicit|bdf2] [--contact semi-smooth|conic]
//!     [--scene problems/s_start.toml] [--cap N] [--perturb X] [--merit-memory M] [--penalty P]
//!     [--certificate N] [--adaptive TOL] [--chart OUT.png [--pyelastica STEPS.csv]]
//! ```
//!
//! `--chart` draws the wall seconds per simulated second against the element count on log-log
//! axes, one line per step, with a line of slope one (cost linear in the element count)
//! through the first point; `--pyelastica` adds PyElastica's cost at its largest stable step
//! from the CSV written by `compare/stable_steps.sh` (its `stable` rows).
//!
//! `--duration full` runs the whole scene and adds v_s/v_m. `--certificate N` certifies every
//! N-th semi-smooth step with the conic program (`[solver] conic_certificate`) and reports it.
//! `--adaptive TOL` runs adaptive BDF2 instead (error tolerance `TOL`, a fraction of L per step;
//! `dt` is its first step); `--integrator bdf2`, BDF2 at the fixed step `dt`. `--cap N` sets
//! `[solver] semi_smooth_max_iterations` (and `max_iterations`, which caps it, to at least
//! `N`); `--merit-memory M` sets `[solver] semi_smooth_merit_memory` (the semi-smooth
//! Newton's non-monotone line search; 1 is monotone), `--penalty P` its `semi_smooth_penalty`;
//! `--perturb X` adds `X` to `mu_forward` (another trajectory of the same scene, for solver
//! statistics that depend on it). `lab/contact_scaling/contact_scaling.sh` keeps the output as a dated
//! record under `docs/results/contact-scaling/`.
use slither::model::Model;
use slither::{observe, problem, sim};
use std::path::PathBuf;

struct Args {
    scene: PathBuf,
    elements: Vec<usize>,
    duration: Option<f64>,
    dts: Vec<f64>,
    contact: Option<problem::ContactKind>,
    /// Fixed-step BDF2 instead of implicit Euler (`--integrator bdf2`).
    bdf2: bool,
    /// `[solver] semi_smooth_max_iterations` (`--cap`; the file's by default).
    cap: Option<usize>,
    /// `[solver] semi_smooth_merit_memory` (`--merit-memory`; the file's by default).
    memory: Option<usize>,
    /// `[solver] semi_smooth_penalty` (`--penalty`; the file's by default).
    penalty: Option<f64>,
    /// Added to `[ground] mu_forward` (`--perturb`): another trajectory of the same scene.
    perturb: f64,
    certificate: usize,
    /// Adaptive BDF2 with this error tolerance (fraction of L), `dt` its first step.
    adaptive: Option<f64>,
    chart: Option<PathBuf>,
    pyelastica: Option<PathBuf>,
}

fn parse() -> Args {
    let mut a = Args {
        scene: PathBuf::from("problems/s_start.toml"),
        elements: vec![50, 100, 200, 400],
        duration: Some(0.5),
        dts: vec![5e-4],
        contact: None,
        bdf2: false,
        cap: None,
        memory: None,
        penalty: None,
        perturb: 0.0,
        certificate: 0,
        adaptive: None,
        chart: None,
        pyelastica: None,
    };
    let argv: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
    while i < argv.len() {
        let v = argv.get(i + 1).cloned().unwrap_or_default();
        match argv[i].as_str() {
            "--scene" => a.scene = PathBuf::from(v),
            "--elements" => {
                a.elements = v
                    .split(',')
                    .map(|s| s.trim().parse().expect("--elements: integers"))
                    .collect()
            }
            "--duration" => {
                a.duration = if v == "full" {
                    None
                } else {
                    Some(v.parse().expect("--duration: seconds or full"))
                }
            }
            "--dt" => {
                a.dts = v
                    .split(',')
                    .map(|s| s.trim().parse().expect("--dt: seconds, comma-separated"))
                    .collect()
            }
            "--chart" => a.chart = Some(PathBuf::from(v)),
            "--pyelastica" => a.pyelastica = Some(PathBuf::from(v)),
            "--certificate" => a.certificate = v.parse().expect("--certificate: every N steps"),
            "--adaptive" => {
                a.adaptive = Some(
                    v.parse()
                        .expect("--adaptive: error tolerance, fraction of L"),
                )
            }
            "--penalty" => a.penalty = Some(v.parse().expect("--penalty: a positive number")),
            "--merit-memory" => {
                a.memory = Some(
                    v.parse()
                        .expect("--merit-memory: accepted merits remembered"),
                )
            }
            "--cap" => a.cap = Some(v.parse().expect("--cap: semi-smooth iterations per step")),
            "--perturb" => a.perturb = v.parse().expect("--perturb: added to mu_forward"),
            "--integrator" => {
                a.bdf2 = match v.as_str() {
                    "implicit" => false,
                    "bdf2" => true,
                    _ => panic!("--integrator: implicit or bdf2"),
                }
            }
            "--contact" => {
                a.contact = Some(match v.as_str() {
                    "semi-smooth" => problem::ContactKind::SemiSmooth,
                    "conic" => problem::ContactKind::Conic,
                    _ => panic!("--contact: semi-smooth or conic (the active set was retired)"),
                })
            }
            other => {
                eprintln!("unknown argument {other}");
                std::process::exit(2);
            }
        }
        i += 2;
    }
    if a.pyelastica.is_some() && a.chart.is_none() {
        eprintln!("--pyelastica needs --chart");
        std::process::exit(2);
    }
    a
}

/// PyElastica's `(elements, wall seconds per simulated second, dt)` at its largest stable step:
/// the `stable` rows of `compare/stable_steps.sh`'s CSV.
fn pyelastica_points(path: &std::path::Path) -> Vec<(f64, f64, f64)> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| {
        eprintln!("error: {}: cannot read: {e}", path.display());
        std::process::exit(2)
    });
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let col = |name: &str| {
        header.iter().position(|h| *h == name).unwrap_or_else(|| {
            eprintln!("error: {}: no column `{name}`", path.display());
            std::process::exit(2)
        })
    };
    let (ce, cd, cr, cs, cw) = (
        col("elements"),
        col("dt"),
        col("role"),
        col("stable"),
        col("wall_per_sim_second"),
    );
    let num = |f: &[&str], c: usize, line: &str| -> f64 {
        f.get(c).and_then(|v| v.parse().ok()).unwrap_or_else(|| {
            eprintln!("error: {}: bad row {line:?}", path.display());
            std::process::exit(2)
        })
    };
    let mut pts: Vec<(f64, f64, f64)> = lines
        .filter(|l| !l.trim().is_empty())
        .filter_map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f.get(cr) == Some(&"stable") && f.get(cs) == Some(&"true"))
                .then(|| (num(&f, ce, l), num(&f, cw, l), num(&f, cd, l)))
        })
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    pts
}

/// Library diagnostics on stderr at debug level when `SLITHER_DEBUG` is set (every Newton
/// iteration and contact status change).
struct StderrLog;

impl log::Log for StderrLog {
    fn enabled(&self, meta: &log::Metadata) -> bool {
        meta.level() <= log::max_level()
    }
    fn log(&self, record: &log::Record) {
        eprintln!("{}", record.args());
    }
    fn flush(&self) {}
}

fn main() {
    if std::env::var_os("SLITHER_DEBUG").is_some() {
        static LOGGER: StderrLog = StderrLog;
        if log::set_logger(&LOGGER).is_ok() {
            log::set_max_level(log::LevelFilter::Debug);
        }
    }
    let args = parse();
    let base = problem::load(&args.scene).unwrap_or_else(|e| {
        eprintln!("error: {e}");
        std::process::exit(2)
    });
    let mut lines: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for &dt in &args.dts {
        lines.push((
            format!("slither, {}", method(&args, dt)),
            table(&args, &base, dt),
        ));
    }
    if let Some(path) = &args.chart {
        chart(path, &args, lines);
    }
}

/// The chart of `--chart`: slither's lines, PyElastica's points, a slope-one guide.
fn chart(path: &std::path::Path, args: &Args, mut lines: Vec<(String, Vec<(f64, f64)>)>) {
    if let Some(csv) = &args.pyelastica {
        let pe = pyelastica_points(csv);
        let steps: Vec<String> = pe.iter().map(|p| format!("{:e}", p.2)).collect();
        lines.push((
            format!(
                "PyElastica 1.0, largest stable step ({} s)",
                steps.join(", ")
            ),
            pe.iter().map(|p| (p.0, p.1)).collect(),
        ));
    }
    if let Some(&(n0, w0)) = lines.first().and_then(|l| l.1.first()) {
        let n1 = args.elements.iter().copied().max().unwrap_or(1) as f64;
        lines.push((
            "cost linear in the elements".to_string(),
            vec![(n0, w0), (n1, w0 * n1 / n0)],
        ));
    }
    let series: Vec<(&str, Vec<(f64, f64)>)> =
        lines.iter().map(|(n, p)| (n.as_str(), p.clone())).collect();
    let title = format!(
        "{}: {}",
        args.scene.display(),
        args.duration
            .map_or("whole scene".to_string(), |d| format!("first {d} s"))
    );
    if let Err(e) = slither::plot::xy_log_log(
        path,
        &title,
        "elements",
        "wall seconds per simulated second",
        &series,
    ) {
        eprintln!("error: {}: {e}", path.display());
        std::process::exit(1);
    }
    eprintln!("chart: {}", path.display());
}

/// The time stepping of a table: implicit Euler at `dt`, or adaptive BDF2 starting with it.
fn method(args: &Args, dt: f64) -> String {
    let fixed = if args.bdf2 { "BDF2" } else { "implicit Euler" };
    args.adaptive
        .map_or(format!("{fixed}, dt {dt:e} s"), |tol| {
            format!("adaptive BDF2, error tolerance {tol:e}, first step {dt:e} s")
        })
}

/// One table for step `dt`: a row per element count. Returns `(elements, wall seconds per
/// simulated second)` of the runs that finished.
fn table(args: &Args, base: &problem::Problem, dt: f64) -> Vec<(f64, f64)> {
    let mut points = Vec::new();
    println!(
        "scene {}{}, {}, {}{}{}{}",
        args.scene.display(),
        if args.perturb != 0.0 {
            format!(" (mu_forward + {:e})", args.perturb)
        } else {
            String::new()
        },
        method(args, dt),
        args.duration
            .map_or("whole scene".to_string(), |d| format!("first {d} s")),
        args.cap.map_or(String::new(), |c| format!(
            ", semi-smooth cap {c} iterations"
        )),
        args.memory
            .map_or(String::new(), |k| format!(", semi-smooth merit memory {k}")),
        args.penalty
            .map_or(String::new(), |k| format!(", semi-smooth penalty {k}"))
    );
    println!();
    println!("| elements | steps | Newton it./step | factorizations/step | fallbacks/step | fallbacks | halvings | us/step/element | wall s | wall s per simulated s | assembly % | factor % | solve % | line search % | Clarabel % | v_s/v_m |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for &n in &args.elements {
        let mut p = base.clone();
        p.rod.elements = n;
        p.time.dt = Some(dt);
        p.solver.integrator = if args.bdf2 {
            problem::IntegratorKind::Bdf2
        } else {
            problem::IntegratorKind::ImplicitEuler
        };
        p.time.adaptive = false;
        if let Some(tol) = args.adaptive {
            p.solver.integrator = problem::IntegratorKind::Bdf2;
            p.time.adaptive = true;
            p.time.error_tolerance = Some(tol);
        }
        if let Some(c) = args.contact {
            p.solver.contact = c;
        }
        p.solver.conic_certificate = args.certificate;
        if let Some(pen) = args.penalty {
            p.solver.semi_smooth_penalty = pen;
        }
        if let Some(mem) = args.memory {
            p.solver.semi_smooth_merit_memory = mem;
        }
        if let Some(cap) = args.cap {
            p.solver.semi_smooth_max_iterations = cap;
            p.solver.max_iterations = p.solver.max_iterations.max(cap);
        }
        if let Some(g) = p.ground.as_mut() {
            g.mu_forward += args.perturb;
        }
        if let Some(d) = args.duration {
            p.time.duration = Some(d);
        }
        let m = Model::new(&p);
        let o = match sim::run_gait(&m, m.solver.integrator, &mut |_| {}, &mut |_| {}) {
            Ok(o) => o,
            Err(e) => {
                eprintln!("error: {e}");
                std::process::exit(1);
            }
        };
        let st = &o.stats;
        let steps = st.steps.max(1) as f64;
        if args.certificate > 0 {
            let c = &st.contact;
            eprintln!(
                "{n} elements: {} steps certified by the conic program, {} failed; largest correction {:.3e} tolerances, largest normal-force change {:.3e} tolerances",
                c.certificates, c.certificate_failures, c.certificate_max_correction, c.certificate_max_normal_change
            );
        }
        let hist: Vec<String> = st
            .iteration_histogram
            .iter()
            .enumerate()
            .filter(|(_, &c)| c > 0)
            .map(|(k, c)| format!("{k}:{c}"))
            .collect();
        eprintln!(
            "{n} elements: {} semi-smooth retries; steps by Newton iterations {}",
            st.contact.semismooth_retries,
            hist.join(" ")
        );
        let fallbacks = st.contact.semismooth_fallbacks;
        let wall = o.wall_time_s;
        let simulated = o.state.t.max(1e-300);
        let pct = |x: f64| 100.0 * x / wall.max(1e-300);
        let v = if args.duration.is_none() && o.error.is_none() {
            let fields = observe::fields(&m, &o.frames);
            format!(
                "{:.4}",
                observe::observe(&m, &o.frames, &fields).v_s_over_v_m
            )
        } else {
            "-".to_string()
        };
        println!(
            "| {n} | {} | {:.2} | {:.2} | {:.4} | {} | {} | {:.2} | {:.2} | {:.2} | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} | {v} |{}",
            st.steps,
            st.newton_iterations as f64 / steps,
            st.newton.factorizations as f64 / steps,
            fallbacks as f64 / steps,
            fallbacks,
            st.step_halvings,
            1e6 * wall / steps / n as f64,
            wall,
            wall / simulated,
            pct(st.newton.assembly_s),
            pct(st.newton.factor_s),
            pct(st.newton.solve_s),
            pct(st.newton.line_search_s),
            pct(st.contact.conic_s),
            o.error.as_ref().map_or(String::new(), |e| format!(" failed: {e}"))
        );
        if o.error.is_none() {
            points.push((n as f64, wall / simulated));
        }
    }
    println!();
    points
}
