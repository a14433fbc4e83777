//! Helpers shared by the integration tests.
#![allow(dead_code)]
use slither::model::Model;
use slither::problem;
use std::path::Path;

/// The rows of a study's `phase.csv` or `refine.csv` in file order, without the wall-time
/// column (field 16).
pub fn ordered_rows(csv: &Path) -> Vec<String> {
    std::fs::read_to_string(csv)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            let mut f: Vec<&str> = l.split(',').collect();
            f[16] = "";
            f.join(",")
        })
        .collect()
}

/// Simulate a problem with its own gait (the outcome as it is, failed or not).
pub fn run_problem(p: &problem::Problem) -> (Model, slither::sim::Outcome) {
    let m = Model::new(p);
    let o = slither::sim::run(
        &m,
        Box::new(slither::gait::Muscles {
            gait: m.gait.clone(),
        }),
        &mut |_| {},
        &mut |_| {},
    );
    (m, o)
}

/// Simulate a problem file with its own gait; the run must finish.
pub fn run_file(path: &str) -> (Model, slither::sim::Outcome) {
    let (m, o) = run_problem(&problem::load(Path::new(path)).unwrap());
    assert!(o.error.is_none(), "{path}: {:?}", o.error);
    (m, o)
}

/// Data rows of a study's `history.csv` in `out` (header checked).
pub fn history_rows(out: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(out.join(slither::studies::optimize::HISTORY_FILE)).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some(slither::studies::optimize::HISTORY_HEADER)
    );
    lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

/// Index of the `history.csv` column `name`.
pub fn col(name: &str) -> usize {
    slither::studies::optimize::HISTORY_HEADER
        .split(',')
        .position(|c| c == name)
        .unwrap()
}

/// Model from inline TOML.
pub fn model(toml: &str) -> Model {
    let p = problem::parse(toml, Path::new("<inline>")).expect("valid inline problem");
    Model::new(&p)
}

/// Small deterministic generator (xorshift) for random test configurations.
pub struct Rng(pub u64);
impl Rng {
    /// Uniform in [-1, 1).
    pub fn sym(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// A tiny S-start (20 elements, a tenth of a second): the base problem of the phase-study
/// tests (`tests/phase.rs`, `tests/slurm.rs`), whose cells take milliseconds.
pub const TINY_S_START: &str = "\
[rod]
length = 1.0
diameter = 0.02
elements = 20
density = 1000.0
bending_stiffness = 0.01308

[ground]
mu_forward = 0.55
mu_backward = 0.70
mu_sideways = 1.00

[gait]
kind = \"s-start\"
stress = 24525.0
sigma = 0.0525
speed = 0.28

[time]
dt = 1e-2
duration = 0.1

[output]
interval = 0.02
";

/// A tiny sidewinding (16 elements, 10 ms step, three launch periods of 0.4 s): the base of
/// the periodic-gait study tests (`tests/design_periodic.rs`, `tests/phase_periodic.rs`),
/// milliseconds per run. At `W` 300, `G` 14.4 (its own stress).
pub const TINY_SIDEWINDING: &str = "\
# tiny sidewinding for the periodic study tests
[rod]
length = 1.0
diameter = 0.02
elements = 16
bending_stiffness = 0.01308

[ground]
mu_forward = 0.44
mu_backward = 0.56
mu_sideways = 0.80

[gait]
kind = \"sidewinding\"
stress = 23500.0
sigma = 0.07
speed = 0.5
centers = [0.0, 0.1, 0.2]
scales = [0.53, 1.2, 1.0]
period = 0.4
ramp = 0.05

[time]
dt = 1e-2
duration = 1.2

[output]
interval = 0.02
";

/// `problems/s_start_coarse.toml`: the S-start scene on 50 elements with implicit Euler at
/// fixed steps of 2e-3 s (frames every 0.036 s). Cheaper than `problems/s_start.toml` (100
/// elements, BDF2 at 3.6e-3 s), and the configuration the solver-statistics pins and
/// mechanism tests were measured on (its v_s/v_m is 5.3 % below the converged value, the
/// bundled file's about 1 %).
pub fn s_start_coarse() -> problem::Problem {
    problem::load(Path::new("problems/s_start_coarse.toml")).unwrap()
}

/// A copy of [`slither::gait::Muscles`]' map (`kappa0 = natural - m / B` over the Voronoi
/// length) with the couple `[about d1, about d2]` passed through `map` first: the mutation
/// tests' wrong axes and signs (`tests/pyelastica_free_rod.rs`, `tests/muscle_statics.rs`).
pub struct MutatedMuscles {
    /// The gait.
    pub gait: slither::gait::Gait,
    /// The mutation.
    pub map: fn([f64; 2]) -> [f64; 2],
}

impl slither::gait::Actuation for MutatedMuscles {
    fn rest_strains(&self, t: f64, m: &Model, kappa0: &mut [[f64; 2]], m0: &mut [f64]) {
        for i in 1..m.nodes - 1 {
            let l = m.voronoi[i];
            let mm = (self.map)(self.gait.couple_at(m.arc_length(i), t));
            kappa0[i] = [
                (m.natural_curvature[0] - mm[0] / m.bend) * l,
                (m.natural_curvature[1] - mm[1] / m.bend) * l,
            ];
            m0[i] = m.natural_twist * l;
        }
    }
}

/// A straight rod of 20 elements (L = 1 m, a = 0.02 m) at `height` above the ground, heading
/// `heading` degrees, launched at `velocity`, on a ground inclined by `incline` degrees with
/// friction coefficients `mu` (forward, backward, sideways), for `duration` s at steps of
/// 1 ms with `[solver] integrator = integrator`: the contact tests' scene.
pub fn rod_on_ground(
    heading: f64,
    velocity: [f64; 3],
    incline: f64,
    height: f64,
    duration: f64,
    integrator: &str,
    mu: [f64; 3],
) -> Model {
    model(&format!(
        r#"
[rod]
length = 1.0
diameter = 0.02
elements = 20
bending_stiffness = 1e-2
[initial]
heading_deg = {heading}
velocity = [{}, {}, {}]
height = {height}
[ground]
mu_forward = {}
mu_backward = {}
mu_sideways = {}
incline_deg = {incline}
[time]
dt = 1e-3
duration = {duration}
[solver]
integrator = "{integrator}"
"#,
        velocity[0], velocity[1], velocity[2], mu[0], mu[1], mu[2]
    ))
}
