//! Ground contact and anisotropic Coulomb friction against analytic results
//! (issue: ground contact as a conic program).
mod common;
use common::model;
use slither::contact::Conic;
use slither::integrator::{Integrator, Natural};
use slither::model::Model;
use slither::rod::vec3::f;
use slither::state::State;

const G: f64 = 9.81;
const MU: [f64; 3] = [0.11, 0.14, 0.20];

fn scene(heading: f64, velocity: [f64; 3], incline: f64, height: f64, duration: f64) -> Model {
    scene_with(heading, velocity, incline, height, duration, "implicit")
}

/// The scene with `[solver] integrator = integrator`.
fn scene_with(
    heading: f64,
    velocity: [f64; 3],
    incline: f64,
    height: f64,
    duration: f64,
    integrator: &str,
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
        velocity[0], velocity[1], velocity[2], MU[0], MU[1], MU[2]
    ))
}

/// Step to the end, calling `each` after every step.
fn simulate(m: &Model, each: impl FnMut(&State, &mut Integrator)) -> (State, Integrator<'_>) {
    simulate_path(m, true, each)
}

/// Step with the active-set contact Newton (`active = true`, the default) or with one conic
/// solve per Newton iterate (`false`), so that both paths stay tested.
fn simulate_path(
    m: &Model,
    active: bool,
    mut each: impl FnMut(&State, &mut Integrator),
) -> (State, Integrator<'_>) {
    let mut integ = Integrator::new(m, Box::new(Natural));
    if !active {
        integ.set_contact(Some(Box::new(Conic::new(m))));
    }
    let mut s = State::initial(m);
    let steps = (m.duration / m.dt).round() as usize;
    for _ in 0..steps {
        integ.step(&mut s, m.dt).unwrap();
        each(&s, &mut integ);
    }
    (s, integ)
}

fn max_height(m: &Model, s: &State) -> f64 {
    m.real
        .clone()
        .map(|i| s.node(i)[2])
        .fold(f64::MIN, f64::max)
}

#[test]
fn rod_at_rest_stays_put_and_carries_its_weight() {
    let m = scene(0.0, [0.0; 3], 0.0, 0.0, 1.0);
    let c0 = State::initial(&m).centroid(&m);
    let a = m.diameter;
    let mut worst_pen: f64 = 0.0;
    let (s, integ) = simulate(&m, |s, _| {
        for i in m.real.clone() {
            worst_pen = worst_pen.max(0.5 * a - s.node(i)[2]);
        }
    });
    let drift = f::norm(f::sub(s.centroid(&m), c0));
    let weight = m.total_mass() * G;
    let n: f64 = integ.normal_forces().iter().sum();
    println!("drift {drift:e} m, normal {n} N vs weight {weight} N, penetration {worst_pen:e} m");
    assert!(drift < 1e-9);
    assert!((n / weight - 1.0).abs() < 1e-6);
    assert!(worst_pen < 1e-6 * a);
    assert!(integ.stats().contact.conic_solves as f64 / integ.stats().steps as f64 <= 1.5);
}

fn stop_distance(heading: f64, v: [f64; 3], mu: f64) {
    stop_distance_path(heading, v, mu, true);
}

fn stop_distance_path(heading: f64, v: [f64; 3], mu: f64, active: bool) {
    stop_distance_with(heading, v, mu, active, "implicit");
}

fn stop_distance_with(heading: f64, v: [f64; 3], mu: f64, active: bool, integrator: &str) {
    let m = scene_with(
        heading,
        v,
        0.0,
        0.0,
        1.1 * f::norm(v) / (mu * G),
        integrator,
    );
    let c0 = State::initial(&m).centroid(&m);
    let ceiling = 0.5 * m.diameter * (1.0 + 2e-6);
    let (s, integ) = simulate_path(&m, active, |s, _| {
        let h = max_height(&m, s);
        assert!(h <= ceiling, "rod rose to {h} at t = {}", s.t);
    });
    let d = f::norm(f::sub(s.centroid(&m), c0));
    let expected = f::dot(v, v) / (2.0 * mu * G);
    let speed = f::norm(s.node_velocity(m.real.start));
    println!("heading {heading}: stopped after {d:.6} m (analytic {expected:.6} m), final speed {speed:e}, {:.2} conic solves/step", integ.stats().contact.conic_solves as f64 / integ.stats().steps as f64);
    assert!((d / expected - 1.0).abs() < 0.01);
    assert!(speed < 1e-9, "still moving at {speed}");
}

#[test]
fn sliding_forward_stops_after_v0_squared_over_two_mu_forward_g() {
    stop_distance(0.0, [0.5, 0.0, 0.0], MU[0]);
}

#[test]
fn sliding_backward_stops_after_v0_squared_over_two_mu_backward_g() {
    stop_distance(0.0, [-0.5, 0.0, 0.0], MU[1]);
}

#[test]
fn sliding_sideways_stops_after_v0_squared_over_two_mu_sideways_g() {
    stop_distance(90.0, [0.5, 0.0, 0.0], MU[2]);
}

/// On an incline rising along +x the rod tends to slide toward -x: backward for heading 0
/// (head up the slope), sideways for heading 90.
fn incline(heading: f64, mu: f64) {
    incline_path(heading, mu, true);
}

fn incline_path(heading: f64, mu: f64, active: bool) {
    incline_with(heading, mu, active, "implicit");
}

fn incline_with(heading: f64, mu: f64, active: bool, integrator: &str) {
    let critical = mu.atan().to_degrees();
    // Below the threshold: stays put.
    let below = critical - 2.0;
    let m = scene_with(heading, [0.0; 3], below, 0.0, 1.0, integrator);
    let c0 = State::initial(&m).centroid(&m);
    let (s, _) = simulate_path(&m, active, |_, _| {});
    let drift = f::norm(f::sub(s.centroid(&m), c0));
    println!("heading {heading}: {below:.2} deg (threshold {critical:.2}): drift {drift:e} m");
    assert!(drift < 1e-9, "crept by {drift} m below the threshold");
    // Above: slides down with acceleration g (sin - mu cos).
    let above = critical + 4.0;
    let m = scene_with(heading, [0.0; 3], above, 0.0, 0.5, integrator);
    let (s, _) = simulate_path(&m, active, |_, _| {});
    let vx: f64 = m.real.clone().map(|i| s.node_velocity(i)[0]).sum::<f64>() / m.real.len() as f64;
    let acc = -vx / s.t;
    let b = above.to_radians();
    let expected = G * (b.sin() - mu * b.cos());
    println!("heading {heading}: {above:.2} deg: acceleration {acc:.6} (analytic {expected:.6})");
    assert!((acc / expected - 1.0).abs() < 0.01);
}

#[test]
fn incline_backward_sticks_below_and_slides_above_the_friction_angle() {
    incline(0.0, MU[1]);
}

#[test]
fn incline_sideways_sticks_below_and_slides_above_the_friction_angle() {
    incline(90.0, MU[2]);
}

#[test]
fn dropped_rod_comes_to_rest_without_gaining_energy() {
    let m = scene(30.0, [0.1, 0.0, 0.0], 0.0, 0.05, 1.0);
    let mut integ0 = Integrator::new(&m, Box::new(Natural));
    let mut e_prev = integ0.energies(&State::initial(&m)).total;
    let (s, mut integ) = simulate(&m, |s, integ| {
        let e = integ.energies(s).total;
        assert!(
            e <= e_prev + 1e-12 * e_prev.abs(),
            "energy rose at t = {}: {e_prev} -> {e}",
            s.t
        );
        e_prev = e;
    });
    let ke = integ.energies(&s).kinetic;
    let h = max_height(&m, &s);
    println!("after the drop: kinetic {ke:e} J, height {h}");
    assert!(ke < 1e-12);
    assert!((h - 0.5 * m.diameter).abs() < 1e-9);
}

/// A straight rod dropped flat from `height` onto the ground with the given integrator and
/// step: the largest height (above resting on the ground, as a fraction of the diameter) any
/// node reaches after the first touchdown, and the largest upward node speed after it.
fn bounce_after_drop(integrator: &str, dt: f64, height: f64) -> (f64, f64) {
    let m = scene_with(0.0, [0.0; 3], 0.0, height, 0.25, integrator);
    let mut integ = Integrator::new(&m, Box::new(Natural));
    let mut s = State::initial(&m);
    let mut landed = false;
    let (mut rise, mut up): (f64, f64) = (0.0, 0.0);
    for _ in 0..(m.duration / dt).round() as usize {
        integ.step(&mut s, dt).unwrap();
        if landed {
            rise = rise.max(max_height(&m, &s) - 0.5 * m.diameter);
            for i in m.real.clone() {
                up = up.max(s.node_velocity(i)[2]);
            }
        }
        landed |= integ.normal_forces().iter().any(|&n| n > 0.0);
    }
    assert!(landed);
    (rise / m.diameter, up)
}

/// The contact model has no restitution: a rod dropped flat stays down after it lands, with
/// BDF2 as with implicit Euler. (BDF2 with its plain two-step history bounced it: 1.62
/// diameters and 0.74 m/s upward at dt 2e-3, 0.20 diameters at 5e-4, from a drop of one
/// diameter at 0.63 m/s.)
#[test]
fn bdf2_landing_is_inelastic() {
    for integrator in ["implicit", "bdf2"] {
        for dt in [2e-3, 5e-4] {
            let (rise, up) = bounce_after_drop(integrator, dt, 0.03);
            println!("{integrator} dt {dt}: rise {rise:.3e} a, upward speed {up:.3e} m/s");
            assert!(rise < 1e-6, "{integrator} dt {dt}: rose {rise} diameters");
            assert!(up < 1e-6, "{integrator} dt {dt}: {up} m/s upward");
        }
    }
}

#[test]
fn bad_ground_keys_are_rejected_with_the_key_named() {
    let base = "[rod]\nlength = 1.0\ndiameter = 0.02\nbending_stiffness = 1e-2\n[time]\ndt = 1e-3\nduration = 0.1\n[ground]\n";
    for (line, key) in [
        ("mu_forward = -0.1", "ground.mu_forward"),
        ("mu_sideways = nan", "ground.mu_sideways"),
        ("incline_deg = 90.0", "ground.incline_deg"),
        ("incline_deg = -95.0", "ground.incline_deg"),
    ] {
        let text = format!("{base}{line}\n");
        let err = slither::problem::parse(&text, std::path::Path::new("g.toml"))
            .unwrap_err()
            .to_string();
        assert!(
            err.contains(key) && err.contains("g.toml:9:"),
            "{line}: {err}"
        );
    }
}

#[test]
fn conic_path_alone_stops_and_sticks_and_slides_correctly() {
    // One conic (Clarabel) solve per Newton iterate, no active set: the fallback path.
    stop_distance_path(0.0, [0.5, 0.0, 0.0], MU[0], false);
    stop_distance_path(90.0, [0.5, 0.0, 0.0], MU[2], false);
    incline_path(0.0, MU[1], false);
}

#[test]
fn bdf2_slides_to_the_same_stop_distances_and_sticks_below_the_friction_angle() {
    stop_distance_with(0.0, [0.5, 0.0, 0.0], MU[0], true, "bdf2");
    stop_distance_with(0.0, [-0.5, 0.0, 0.0], MU[1], true, "bdf2");
    stop_distance_with(90.0, [0.5, 0.0, 0.0], MU[2], true, "bdf2");
    incline_with(0.0, MU[1], true, "bdf2");
    incline_with(90.0, MU[2], true, "bdf2");
}

/// The S-start's first 0.3 s with the active-set contact path, `[solver] contact_coupling`
/// as given; returns every step's residual sequence (see `Stats::residuals`).
fn s_start_residuals(coupling: bool) -> Vec<Vec<f64>> {
    use slither::gait::Muscles;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/s_start.toml");
    let mut p = slither::problem::load(&path).unwrap();
    p.time.duration = Some(0.3);
    p.solver.contact_coupling = coupling;
    p.solver.tolerance = 1e-9;
    let m = Model::new(&p);
    let mut integ = Integrator::new(
        &m,
        Box::new(Muscles {
            gait: m.gait.clone(),
        }),
    );
    let mut s = State::initial(&m);
    let mut out = Vec::new();
    for _ in 0..(m.duration / m.dt).round() as usize {
        integ.step(&mut s, m.dt).unwrap();
        out.push(integ.stats().contact.residuals.clone());
    }
    out
}

/// Contact forces inside the Newton system: on the S-start's contact steps the force
/// residual at least squares from one iterate to the next near the solution; with the
/// normal forces lagged by one iterate (`contact_coupling = false`) it only contracts.
#[test]
fn contact_newton_converges_quadratically() {
    // Successive residuals (relative to the weight per contact) near the solution: the first
    // below 0.1, the second above the round-off floor (positions ~0.5 m carry ~1e-16 m of
    // round-off, times the stretching stiffness EA / l ~ 3e5 N/m, over W / n_c ~ 0.06 N:
    // ~1e-9, and so it is observed). Pairs across a status change (NaN) or after a step that
    // was not a full exact Newton step (-1) are not Newton pairs.
    let pairs = |steps: &[Vec<f64>]| -> Vec<(f64, f64)> {
        steps
            .iter()
            .flat_map(|r| r.windows(2).map(|w| (w[0], w[1])))
            .filter(|&(a, b)| (0.0..0.1).contains(&a) && b > 1e-8)
            .collect()
    };
    let raw = s_start_residuals(true);
    for r in &raw {
        if r.windows(2)
            .any(|w| (0.0..0.1).contains(&w[0]) && w[1] > 1e-8 && w[1] > w[0] * w[0])
        {
            println!(
                "DBG {:?}",
                r.iter().map(|x| format!("{x:.2e}")).collect::<Vec<_>>()
            );
        }
    }
    let iterations = raw.iter().flatten().filter(|r| **r >= 0.0).count();
    let inexact = raw.iter().flatten().filter(|r| **r < 0.0).count();
    println!("coupled: {inexact} of {iterations} iterations not full exact Newton steps");
    assert!((inexact as f64) < 0.1 * iterations as f64);
    let coupled = pairs(&raw);
    let lagged = pairs(&s_start_residuals(false));
    let squared =
        |p: &[(f64, f64)]| p.iter().filter(|&&(a, b)| b <= a * a).count() as f64 / p.len() as f64;
    let worst = |p: &[(f64, f64)]| p.iter().map(|&(a, b)| b / (a * a)).fold(0.0, f64::max);
    let (sc, sl) = (squared(&coupled), squared(&lagged));
    let (wc, wl) = (worst(&coupled), worst(&lagged));
    println!(
        "coupled: {} pairs, {:.0} % squared, largest r1/r0^2 {wc:.2e}; lagged: {} pairs, {:.0} % squared, largest r1/r0^2 {wl:.2e}",
        coupled.len(),
        100.0 * sc,
        lagged.len(),
        100.0 * sl,
    );
    assert!(coupled.len() >= 50 && lagged.len() >= 50);
    // Quadratic: the residual squares on nine pairs in ten, and on every pair
    // `r1 <= C r0^2` with a bounded C (a contact crossing between forward and backward
    // sliding, where the dissipation's Hessian jumps, costs the odd pair its full rate).
    assert!(
        sc >= 0.9,
        "coupled: only {:.0} % of pairs squared",
        100.0 * sc
    );
    assert!(wc <= 100.0, "coupled: r1 / r0^2 up to {wc:e}");
    // The lagged iteration does not: the comparison shows what the coupling does.
    assert!(sl <= 0.5, "lagged: {:.0} % of pairs squared", 100.0 * sl);
    assert!(wl > 1e3, "lagged: r1 / r0^2 at most {wl:e}");
}
