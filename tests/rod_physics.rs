//! Physics of the bare rod against analytic results, an independent elastica solution and
//! conserved quantities (issue: rod mechanics core).
mod common;
use common::model;
use slither::integrator::{Integrator, Natural};
use slither::model::Model;
use slither::problem;
use slither::rod::{dof, vec3::f};
use slither::sim;
use slither::state::State;
use std::path::Path;

fn load(path: &str) -> (String, Model) {
    let text = std::fs::read_to_string(path).unwrap();
    let p = problem::parse(&text, Path::new(path)).unwrap();
    (text, Model::new(&p))
}

fn run(m: &Model) -> sim::Outcome {
    let o = sim::run(m, Box::new(Natural), &mut |_| {}, &mut |_| {});
    assert!(o.error.is_none(), "run failed: {:?}", o.error);
    o
}

/// Sag of the free end (the head, s = 0) below its initial height.
fn head_sag(m: &Model, o: &sim::Outcome) -> f64 {
    m.q0[dof::node(m.real.start) + 2] - o.state.node(m.real.start)[2]
}

#[test]
fn cantilever_small_deflection_matches_beam_theory_static_and_dynamic() {
    let (text, m) = load("problems/cantilever_sag.toml");
    let q = m.line_density() * 9.81;
    let exact = q * m.length.powi(4) / (8.0 * m.bend);
    let o = run(&m);
    let sag = head_sag(&m, &o);
    println!(
        "static sag {sag:.6e} m, beam theory {exact:.6e} m, rel {:.2e}",
        sag / exact - 1.0
    );
    assert!((sag / exact - 1.0).abs() < 0.01);
    assert!(o.max_strain < 1e-3);
    // The dynamic run of the same rod settles to the same shape.
    let dynamic = text.replace("mode = \"static\"", "mode = \"dynamic\"");
    let md = model(&dynamic);
    let od = run(&md);
    let sag_d = head_sag(&md, &od);
    println!("dynamic sag after {} s: {sag_d:.6e} m", md.duration);
    assert!(
        (sag_d / sag - 1.0).abs() < 1e-3,
        "dynamic {sag_d} vs static {sag}"
    );
    for i in md.real.clone() {
        let d = f::norm(f::sub(od.state.node(i), o.state.node(i)));
        assert!(d < 1e-3 * sag, "node {i} differs by {d} m");
    }
}

/// Planar elastica of a horizontally clamped cantilever under its own weight q:
/// `B theta'' = -q (L - s) cos(theta)`, `theta(0) = 0`, `theta'(L) = 0`, by shooting on
/// `theta'(0)` with RK4; returns (horizontal reach, vertical drop) of the tip.
fn elastica_tip(b: f64, q: f64, l: f64) -> (f64, f64) {
    let n = 20000;
    let integrate = |k0: f64| -> (f64, f64, f64) {
        let h = l / n as f64;
        let (mut th, mut k, mut x, mut y) = (0.0f64, k0, 0.0, 0.0);
        let rhs = |s: f64, th: f64, k: f64| -> [f64; 4] {
            [k, -q * (l - s) * th.cos() / b, th.cos(), th.sin()]
        };
        for i in 0..n {
            let s = i as f64 * h;
            let k1 = rhs(s, th, k);
            let k2 = rhs(s + h / 2.0, th + h / 2.0 * k1[0], k + h / 2.0 * k1[1]);
            let k3 = rhs(s + h / 2.0, th + h / 2.0 * k2[0], k + h / 2.0 * k2[1]);
            let k4 = rhs(s + h, th + h * k3[0], k + h * k3[1]);
            th += h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0]);
            k += h / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1]);
            x += h / 6.0 * (k1[2] + 2.0 * k2[2] + 2.0 * k3[2] + k4[2]);
            y += h / 6.0 * (k1[3] + 2.0 * k2[3] + 2.0 * k3[3] + k4[3]);
        }
        (k, x, y)
    };
    // theta'(L) as a function of theta'(0): bisection on [0, qL^2/(2B)] (the linear root moment).
    let (mut lo, mut hi) = (0.0, q * l * l / (2.0 * b));
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if integrate(mid).0 > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let (_, x, y) = integrate(0.5 * (lo + hi));
    (x, y)
}

#[test]
fn large_deflection_cantilever_matches_elastica() {
    let m = model(
        r#"
[rod]
length = 1.0
diameter = 0.02
elements = 50
bending_stiffness = 0.8
clamp = "tail"
[time]
mode = "static"
load_steps = 4
"#,
    );
    let q = m.line_density() * 9.81;
    let o = run(&m);
    let head = o.state.node(m.real.start);
    let tail = o.state.node(m.real.end - 1);
    let drop = tail[2] - head[2];
    let reach = head[0] - tail[0];
    let (xe, ye) = elastica_tip(m.bend, q, m.length);
    println!("DER drop {drop:.6} reach {reach:.6}; elastica drop {ye:.6} reach {xe:.6}");
    assert!(drop > 0.3 * m.length, "not a large deflection: {drop}");
    assert!(
        (drop / ye - 1.0).abs() < 0.01,
        "drop {drop} vs elastica {ye}"
    );
    assert!(
        (reach / xe - 1.0).abs() < 0.01,
        "reach {reach} vs elastica {xe}"
    );
}

#[test]
fn free_rod_conserves_momentum_and_never_gains_energy() {
    let m = model(
        r#"
[rod]
length = 0.5
diameter = 0.02
elements = 30
bending_stiffness = 1e-3
natural_curvature = [2.0, 4.0]
natural_twist = 3.0
[initial]
velocity = [0.3, -0.1, 0.05]
angular_velocity = [0.5, 0.0, 4.0]
[gravity]
g = 0.0
[time]
dt = 2e-3
duration = 0.4
"#,
    );
    let mut integ = Integrator::new(&m, Box::new(Natural));
    let mut s = State::initial(&m);
    let p0 = s.momentum(&m);
    let np0 = f::norm(p0);
    let mut e_prev = integ.energies(&s).total;
    let mut dissipated = 0.0;
    let steps = (m.duration / m.dt).round() as usize;
    for _ in 0..steps {
        integ.step(&mut s, m.dt).unwrap();
        let p = s.momentum(&m);
        assert!(
            f::norm(f::sub(p, p0)) <= 1e-9 * np0,
            "momentum drift {:?} vs {:?}",
            p,
            p0
        );
        let e = integ.energies(&s).total;
        assert!(
            e <= e_prev * (1.0 + 1e-12),
            "energy increased at t = {}: {e_prev} -> {e}",
            s.t
        );
        dissipated += e_prev - e;
        e_prev = e;
    }
    // Something happened: the rod bent (elastic energy moved) and implicit Euler dissipated.
    assert!(dissipated > 0.0);
    assert_eq!(integ.stats().step_halvings, 0);
}

#[test]
fn clamped_rod_with_rest_twist_rotates_its_end_by_the_analytic_angle() {
    let tau0 = 2.0;
    let m = model(&format!(
        r#"
[rod]
length = 1.0
diameter = 0.02
elements = 40
bending_stiffness = 1e-2
clamp = "head"
natural_twist = {tau0}
[gravity]
g = 0.0
[time]
mode = "static"
"#
    ));
    let o = run(&m);
    let s = &o.state;
    let last = m.real_edges().end - 1;
    let (d_clamp, _) = s.directors(0);
    let (d_end, _) = s.directors(last);
    let t = f::unit(state_edge(s, last));
    let angle = f::dot(f::cross(d_clamp, d_end), t).atan2(f::dot(d_clamp, d_end));
    // The edge frame sits at the edge midpoint, s = L - l0/2 from the clamp at s = 0.
    let expected = tau0 * (m.length - 0.5 * m.rest_len[last]);
    println!("end rotation {angle:.12} rad, analytic {expected:.12} rad");
    assert!((angle - expected).abs() < 1e-8);
}

fn state_edge(s: &State, j: usize) -> [f64; 3] {
    slither::state::edge_vec(&s.q, j)
}

#[test]
fn rod_with_natural_curvature_and_twist_settles_into_the_kirchhoff_helix() {
    let (kappa, tau) = (8.0, 5.0);
    let m = model(&format!(
        r#"
[rod]
length = 1.0
diameter = 0.02
elements = 60
bending_stiffness = 1e-2
clamp = "head"
natural_curvature = [{kappa}, 0.0]
natural_twist = {tau}
[gravity]
g = 0.0
[time]
mode = "static"
load_steps = 10
"#
    ));
    let o = run(&m);
    let s = &o.state;
    let l0 = m.rest_len[1];
    // Discrete curvature |kb|/l and torsion (dihedral angle of consecutive binormals)/l,
    // away from the clamp.
    let edges: Vec<[f64; 3]> = m.real_edges().map(|j| state_edge(s, j)).collect();
    let kb: Vec<[f64; 3]> = (1..edges.len())
        .map(|i| {
            let (e0, e1) = (edges[i - 1], edges[i]);
            f::scale(
                f::cross(e0, e1),
                2.0 / (f::norm(e0) * f::norm(e1) + f::dot(e0, e1)),
            )
        })
        .collect();
    for i in 5..kb.len() - 1 {
        let k = f::norm(kb[i]) / l0;
        let (b0, b1) = (f::unit(kb[i - 1]), f::unit(kb[i]));
        let t_mid = f::unit(edges[i]);
        let psi = f::dot(f::cross(b0, b1), t_mid).atan2(f::dot(b0, b1));
        let torsion = psi / l0;
        assert!(
            (k / kappa - 1.0).abs() < 1e-3,
            "node {i}: curvature {k} vs {kappa}"
        );
        assert!(
            (torsion / tau - 1.0).abs() < 1e-2,
            "node {i}: torsion {torsion} vs {tau}"
        );
    }
    println!("helix: curvature {} torsion {}", f::norm(kb[10]) / l0, tau);
}

fn cantilever(elements: usize, mode: &str, dt: f64, duration: f64) -> String {
    format!(
        r#"
[rod]
length = 1.0
diameter = 0.02
elements = {elements}
bending_stiffness = 2.0
clamp = "tail"
[time]
mode = "{mode}"
dt = {dt}
duration = {duration}
"#
    )
}

fn order(a: f64, b: f64, c: f64) -> f64 {
    ((a - b).abs() / (b - c).abs()).log2()
}

/// Observed convergence orders of the cantilever tip (printed; stated in the README).
#[test]
fn convergence_orders_in_time_and_space() {
    // Time: tip height at t = 0.3 s of a cantilever released from straight (first period
    // ~0.7 s), dt halved three times at 40 elements.
    let tip_t: Vec<f64> = [2e-3, 1e-3, 5e-4, 2.5e-4]
        .iter()
        .map(|&dt| {
            let m = model(&cantilever(40, "dynamic", dt, 0.3));
            head_sag(&m, &run(&m))
        })
        .collect();
    let p_t1 = order(tip_t[0], tip_t[1], tip_t[2]);
    let p_t2 = order(tip_t[1], tip_t[2], tip_t[3]);
    // Space: static tip sag with the element count doubled three times.
    let tip_x: Vec<f64> = [10, 20, 40, 80]
        .iter()
        .map(|&n| {
            let m = model(&cantilever(n, "static", 1.0, 1.0));
            head_sag(&m, &run(&m))
        })
        .collect();
    let p_x1 = order(tip_x[0], tip_x[1], tip_x[2]);
    let p_x2 = order(tip_x[1], tip_x[2], tip_x[3]);
    println!("tip sag vs dt {tip_t:?}: observed order {p_t1:.3}, {p_t2:.3}");
    println!("tip sag vs elements {tip_x:?}: observed order {p_x1:.3}, {p_x2:.3}");
    assert!((0.8..1.3).contains(&p_t2), "time order {p_t2}");
    assert!((1.7..2.4).contains(&p_x2), "space order {p_x2}");
}
