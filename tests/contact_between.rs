//! Ground contacts between the nodes (contacts that hold no node coordinate): a rod on
//! contacts at its segments' midpoints slides, sticks and stops as Coulomb's law says with
//! either contact solver, and the lowest point of the curve through the nodes
//! (`[solver] ground_points = "curve"`).
mod common;
use slither::contact::Dispatcher;
use slither::integrator::{Integrator, Natural};
use slither::model::Model;
use slither::rod::vec3::f;
use slither::state::State;

const G: f64 = 9.81;
const MU: [f64; 3] = [0.11, 0.14, 0.20];

fn scene(heading: f64, velocity: [f64; 3], incline: f64, height: f64, duration: f64) -> Model {
    common::rod_on_ground(heading, velocity, incline, height, duration, "implicit", MU)
}

/// A dispatcher whose contacts are the middle of every segment of `m` (a stencil of its two
/// nodes with weights 1/2) instead of the nodes, each starting with an equal share of the
/// weight; `semismooth`: the semi-smooth Newton (else the conic program alone).
fn midpoints(m: &Model, semismooth: bool) -> (Dispatcher, Vec<slither::contact::Contact>) {
    use slither::contact::{Contact, ContactSet, Stencil};
    let law = *m.ground.as_ref().unwrap();
    let weight = m.total_mass() * f::norm(m.gravity);
    let contacts: Vec<Contact> = m
        .real
        .clone()
        .take(m.real.len() - 1)
        .map(|i| Contact::new(Stencil::new(&[i, i + 1], &[0.5, 0.5]).unwrap(), law))
        .collect();
    let n = contacts.len() as f64;
    let set = ContactSet::new(contacts.iter().map(|c| (c.clone(), weight / n)).collect());
    (Dispatcher::with_set(m, set, semismooth), contacts)
}

/// Contacts between nodes: the ground's contacts replaced by one at the middle of every
/// segment ([`midpoints`]), which hold no node coordinate. The semi-smooth Newton takes them
/// (their held components as an augmented Lagrangian), with no conic fallback; the conic
/// program takes them as they are. A straight rod sliding forward on them stops after
/// `v0^2 / (2 mu_f g)` as with contacts at the nodes (the stop depends on the friction law,
/// not on where the contacts sit), no midpoint sinks below the ground by more than `1e-9 a`,
/// and the normal forces spread to the nodes carry the weight.
#[test]
fn contacts_between_nodes_stop_a_sliding_rod_with_either_solver() {
    let v = [0.5, 0.0, 0.0];
    let m = scene(0.0, v, 0.0, 0.0, 1.1 * f::norm(v) / (MU[0] * G));
    let weight = m.total_mass() * G;
    for semismooth in [true, false] {
        let (dispatcher, contacts) = midpoints(&m, semismooth);
        let mut integ = Integrator::new(&m, Box::new(Natural));
        integ.set_contact(Some(Box::new(dispatcher)));
        let mut s = State::initial(&m);
        let c0 = s.centroid(&m);
        let steps = (m.duration / m.dt).round() as usize;
        for _ in 0..steps {
            integ.step(&mut s, m.dt).unwrap();
            for c in &contacts {
                let gap = c.gap(&s.q, m.diameter);
                assert!(
                    gap >= -1e-9 * m.diameter,
                    "a midpoint {gap:e} m below the ground at t = {}",
                    s.t
                );
            }
        }
        let st = integ.stats();
        println!(
            "semi-smooth {semismooth}: {} steps, {} semi-smooth steps, {} fallbacks, {} conic solves, {:.2} Newton iterations per step",
            st.steps,
            st.contact.semismooth_steps,
            st.contact.semismooth_fallbacks,
            st.contact.conic_solves,
            st.newton_iterations as f64 / st.steps as f64
        );
        if semismooth {
            assert_eq!(st.contact.semismooth_steps, st.steps);
            assert_eq!(st.contact.semismooth_fallbacks, 0);
        } else {
            assert_eq!(st.contact.semismooth_steps, 0);
        }
        let d = f::norm(f::sub(s.centroid(&m), c0));
        let expected = f::dot(v, v) / (2.0 * MU[0] * G);
        println!("stopped after {d:.6} m (analytic {expected:.6} m)");
        assert!((d / expected - 1.0).abs() < 0.01, "{d} against {expected}");
        let speed = f::norm(s.node_velocity(m.real.start));
        assert!(speed < 1e-9, "still moving at {speed}");
        let carried: f64 = integ.normal_forces().iter().sum();
        println!("normal forces {carried:.9} N against the weight {weight:.9} N");
        assert!(
            (carried / weight - 1.0).abs() < 1e-6,
            "{carried} against {weight}"
        );
    }
}

/// On contacts between nodes ([`midpoints`], the semi-smooth Newton) a rod on an incline
/// sticks below the friction angle (drift below 1e-9 m in 1 s) and slides above it with the
/// analytic acceleration `g (sin b - mu cos b)` to 1e-6 (measured 1.6e-8 at most), with no
/// conic fallback: Coulomb's law exact at contacts that hold no node coordinate. Mutation: the
/// augmented Lagrangian's normal-force update without the step's move (`lambda' = lambda - rho
/// r_z`, `src/contact/semismooth/between.rs`) makes steps fall back to the conic program, fails.
#[test]
fn contacts_between_nodes_stick_and_slide_on_an_incline_as_coulomb_says() {
    for (heading, mu) in [(0.0, MU[1]), (90.0, MU[2])] {
        let critical = f64::atan(mu).to_degrees();
        for (incline, duration) in [(critical - 2.0, 1.0), (critical + 4.0, 0.5)] {
            let m = scene(heading, [0.0; 3], incline, 0.0, duration);
            let mut integ = Integrator::new(&m, Box::new(Natural));
            integ.set_contact(Some(Box::new(midpoints(&m, true).0)));
            let mut s = State::initial(&m);
            let c0 = s.centroid(&m);
            for _ in 0..(m.duration / m.dt).round() as usize {
                integ.step(&mut s, m.dt).unwrap();
            }
            assert_eq!(integ.stats().contact.semismooth_fallbacks, 0);
            if incline < critical {
                let drift = f::norm(f::sub(s.centroid(&m), c0));
                println!("heading {heading}: {incline:.2} deg: drift {drift:e} m");
                assert!(drift < 1e-9, "crept by {drift} m below the threshold");
            } else {
                let vx: f64 = m.real.clone().map(|i| s.node_velocity(i)[0]).sum::<f64>()
                    / m.real.len() as f64;
                let acc = -vx / s.t;
                let b = incline.to_radians();
                let expected = G * (b.sin() - mu * b.cos());
                println!(
                    "heading {heading}: {incline:.2} deg: acceleration {acc:.9} (analytic {expected:.9})"
                );
                assert!(
                    (acc / expected - 1.0).abs() < 1e-6,
                    "acceleration {acc} vs {expected}"
                );
            }
        }
    }
}

/// `[solver] ground_points = "curve"`: each node's contact is the lowest point of the parabola
/// through it and its neighbours within half an element of it. On a flat body it is the node
/// itself; on a sag it is the parabola's vertex, whose height the stencil reproduces; as the
/// sag flattens the point moves continuously back to
/// the node (no jump below the regularisation).
#[test]
fn the_lowest_point_of_a_curve_through_the_nodes() {
    use slither::contact::set::lowest_point;
    let m = scene(0.0, [0.0; 3], 0.0, 0.0, 0.1);
    let a = m.diameter;
    let mut q = m.q0.clone();
    let z = |q: &mut Vec<f64>, i: usize, v: f64| q[slither::rod::dof::node(i) + 2] = v;
    for i in m.real.clone() {
        assert_eq!(lowest_point(&m, &q, i).single(), Some(i), "flat: node {i}");
    }
    // A sag about node 5 whose vertex lies a quarter element toward node 6: heights
    // z(t) = a/2 + 1e-4 a (t - 1/4)^2 over nodes 4, 5, 6 (t = -1, 0, 1).
    let zt = |t: f64| 0.5 * a + 1e-3 * a * (t - 0.25) * (t - 0.25);
    for (k, t) in [(4, -1.0), (5, 0.0), (6, 1.0)] {
        z(&mut q, k, zt(t));
    }
    let st = lowest_point(&m, &q, 5);
    let x = st.position(&q);
    println!(
        "sag: stencil {:?}, height {:e} a above a/2",
        st.iter().collect::<Vec<_>>(),
        (x[2] - 0.5 * a) / a
    );
    assert!(st.single().is_none());
    // The vertex's offset 0.25 times the regularisation `e^2 / (e^2 + tau^2)` of the sag
    // beyond the dead zone, `e = c - d`, here with `c = 2e-3 a` (a 0.25 % pull toward the
    // node), and the parabola's height there.
    let tau = slither::contact::set::LOWEST_POINT_TAU * a;
    let e = 2e-3 * a - slither::contact::set::LOWEST_POINT_DEAD_ZONE * a;
    let expected = 0.25 * e * e / (e * e + tau * tau);
    let t = st.iter().map(|(i, w)| w * (i as f64 - 5.0)).sum::<f64>();
    assert!(
        (t - expected).abs() < 1e-12,
        "the point at t = {t}, expected {expected}"
    );
    assert!((x[2] - zt(t)).abs() < 1e-12 * a, "{} vs {}", x[2], zt(t));
    // The sag flattened by 1e6: the point within 1e-3 of an element of the node.
    for (k, t) in [(4, -1.0), (5, 0.0), (6, 1.0)] {
        z(&mut q, k, 0.5 * a + 1e-9 * a * (t - 0.25) * (t - 0.25));
    }
    let st = lowest_point(&m, &q, 5);
    let t = st.iter().map(|(i, w)| w * (i as f64 - 5.0)).sum::<f64>();
    println!("flattened: t = {t:e}");
    assert!(t.abs() < 1e-3);
    // Ripples at the Newton tolerance (5e-6 a per coordinate: heights +e, -e, 0, a vertex a
    // sixth of an element from the node, a sag of 1.5e-5 a) are noise, not a sag: within the
    // dead zone the point is the node itself (with `tau = 1e-6 a` and no dead zone it sat at
    // the vertex; with `tau = 1e-4 a` alone, 4e-3 of an element from the node).
    let e = 5e-6 * a;
    for (k, dz) in [(4, e), (5, -e), (6, 0.0)] {
        z(&mut q, k, 0.5 * a + dz);
    }
    let st = lowest_point(&m, &q, 5);
    let t = st.iter().map(|(i, w)| w * (i as f64 - 5.0)).sum::<f64>();
    println!("ripple: t = {t:e}");
    assert_eq!(st.single(), Some(5), "the point at t = {t}");
}

/// Contacts between nodes on the damped S-start (`problems/s_start.toml` with
/// `ground_points = "curve"`, 100 elements, implicit Euler at 2.5e-4 s, the first 0.6 s, the
/// damping time of 5 ms at which the watchdog was measured; the file now has 10 ms). When a
/// sliding contact between nodes lagged its normal force in its friction, a full step whose
/// normal force changed much raised the merit although the next one settled it. Without the
/// semi-smooth Newton's watchdog the line search crept (measured: 22 retries, 7 conic
/// fallbacks, 3.87 iterations per step; on the whole scene 92 fallbacks, and at 400 elements
/// the conic program then failed); with it none, 2.64 iterations per step, and the same
/// `v_s/v_m` to 4e-7. With the normal force's change coupled into the direction
/// (`src/contact/semismooth/between.rs`) 2.28 iterations per step, against 2.59 with it
/// lagged (the code before the coupling): the bound of 2.45 fails if the coupling is lost.
#[test]
fn contacts_between_nodes_converge_without_retries_on_the_damped_s_start() {
    use slither::problem;
    let mut p = problem::load(std::path::Path::new("problems/s_start.toml")).unwrap();
    p.rod.elements = 100;
    p.time.dt = Some(2.5e-4);
    p.time.duration = Some(0.6);
    p.solver.integrator = problem::IntegratorKind::ImplicitEuler;
    p.solver.ground_points = problem::GroundPoints::Curve;
    p.rod.damping_time = 5e-3;
    let (_, o) = common::run_problem(&p);
    assert!(o.error.is_none(), "{:?}", o.error);
    let st = &o.stats;
    let per_step = st.newton_iterations as f64 / st.steps as f64;
    println!(
        "{} steps, {per_step:.3} iterations per step, {} retries, {} fallbacks",
        st.steps, st.contact.semismooth_retries, st.contact.semismooth_fallbacks
    );
    assert_eq!(st.contact.semismooth_retries, 0);
    assert_eq!(st.contact.semismooth_fallbacks, 0);
    assert!(per_step < 2.45, "{per_step} iterations per step");
}

/// No node sinks below the ground with contacts on the curve: the bundled S-start (100
/// elements, BDF2 at 3.6e-3 s), whose nodes sank by up to 4.9e-5 m (2.4e-3 a) when each step
/// held the points chosen at its start. Now a node that sinks at a step's solution has its
/// point chosen again there and the step is solved again (`ContactSet::rechoose`). Measured:
/// 9.9e-9 m (5e-7 a) at most, 55 solves made again in 993 steps (64 before the lowest point's
/// dead zone), none left below; node contacts keep to 0 on this run (3.4e-9 m with implicit
/// Euler at 5e-4 s).
#[test]
fn no_node_sinks_with_contacts_on_the_curve() {
    use slither::problem;
    let mut p = problem::load(std::path::Path::new("problems/s_start.toml")).unwrap();
    p.solver.ground_points = problem::GroundPoints::Curve;
    let (m, o) = common::run_problem(&p);
    assert!(o.error.is_none(), "{:?}", o.error);
    let c = &o.stats.contact;
    println!(
        "deepest node {:.3e} m, {} solves made again, {} steps left below",
        o.max_penetration, c.ground_point_rechoices, c.ground_point_rechoice_limits
    );
    assert!(
        o.max_penetration < 1e-6 * m.diameter,
        "{} m",
        o.max_penetration
    );
    assert!(c.ground_point_rechoices > 0);
    assert_eq!(c.ground_point_rechoice_limits, 0);
}

/// Adaptive BDF2 with contact on the curve at a coarse mesh. There a point chosen at a step's
/// start can lie below the ground (the parabola through a bend that lifts off dips below its
/// nodes), and the step lifts it by that depth whatever its size: an impact, which the local
/// error estimate leaves out as it leaves out a landing. Counted in, the 20-element S-start
/// stopped at t = 0.359 s, its step driven below `dt_min` by an estimate of 3.7 times the
/// tolerance from the head's point 4.7e-5 m deep. Measured with the lowest point's dead zone:
/// 0.58484 in 235 steps, against fixed-step BDF2 at 1e-4 s 0.58450 (0.06 % apart); before it
/// 0.58354 in 231 steps, against 0.58392, 0.58451 and 0.58435 at 4e-4, 2e-4 and 1e-4 s.
#[test]
fn adaptive_steps_on_the_curve_complete_at_a_coarse_mesh() {
    use slither::problem;
    let mut p = problem::load(std::path::Path::new("problems/s_start.toml")).unwrap();
    p.rod.elements = 20;
    p.time.duration = Some(0.6);
    p.output.interval = Some(0.06);
    p.solver.integrator = problem::IntegratorKind::Bdf2;
    p.solver.ground_points = problem::GroundPoints::Curve;
    let mut fixed = p.clone();
    fixed.time.dt = Some(1e-4);
    p.time.adaptive = true;
    let (m, o) = common::run_problem(&p);
    assert!(o.error.is_none(), "{:?}", o.error);
    let (mf, r) = common::run_problem(&fixed);
    assert!(r.error.is_none(), "{:?}", r.error);
    let a = slither::observe::of_outcome(&m, &o).v_s_over_v_m;
    let b = slither::observe::of_outcome(&mf, &r).v_s_over_v_m;
    println!(
        "adaptive {a:.5} in {} steps, fixed 1e-4 s {b:.5}",
        o.stats.steps
    );
    assert!((a / b - 1.0).abs() < 5e-3, "adaptive {a} against fixed {b}");
}

/// A contact model that fails every solve of one step while its contacts are on the curve
/// (from the `fail_at`-th step it begins until the integrator puts them at the nodes), and
/// records every `points_at_nodes` call: the integrator's fallback, seen from outside.
struct FailsOnTheCurve {
    inner: Box<dyn slither::contact::ContactModel>,
    begun: usize,
    fail_at: usize,
    /// The integrator has put the contacts at the nodes once: no more failures.
    done: bool,
    calls: std::sync::Arc<std::sync::Mutex<Vec<bool>>>,
}

impl slither::contact::ContactModel for FailsOnTheCurve {
    fn begin_step(
        &mut self,
        m: &Model,
        q_start: &[f64],
        slip_origin: &[f64],
        v_start: &[f64],
        h: f64,
        q: &mut [f64],
    ) {
        self.begun += 1;
        self.inner
            .begin_step(m, q_start, slip_origin, v_start, h, q);
    }
    fn solve(
        &mut self,
        newton: &mut slither::newton::Newton,
        obj: &slither::newton::Potential,
        q: &mut Vec<f64>,
    ) -> Result<usize, slither::contact::ContactFailure> {
        if !self.done && self.begun >= self.fail_at {
            return Err(slither::contact::ContactFailure::Conic {
                status: "made to fail on the curve".into(),
                conic_iterations: 0,
                iteration: 1,
            });
        }
        self.inner.solve(newton, obj, q)
    }
    fn extrapolated_start(&self) -> bool {
        self.inner.extrapolated_start()
    }
    fn points_at_nodes(&mut self, on: bool) -> bool {
        self.calls.lock().unwrap().push(on);
        let has = self.inner.points_at_nodes(on);
        self.done |= on && has;
        has
    }
    fn accept(&mut self, m: &Model, q: &[f64]) {
        self.inner.accept(m, q);
    }
    fn reject(&mut self) {
        self.inner.reject();
    }
    fn normal_forces(&self, m: &Model, out: &mut [f64]) {
        self.inner.normal_forces(m, out);
    }
    fn stats(&self) -> &slither::contact::ContactStats {
        self.inner.stats()
    }
}

/// A fixed step that fails with ground contact on the curve after every halving is taken
/// again with contact at the nodes, counted and then back on the curve; with contact at the
/// nodes already, the failure stops the run as before. The rod slides flat (its curve's
/// lowest points are its nodes), so the run with the fallback ends where the plain one does;
/// with implicit Euler and with BDF2 (whose history the fallback's steps continue).
#[test]
fn a_step_that_fails_on_the_curve_is_taken_with_contact_at_the_nodes() {
    for integrator in ["implicit", "bdf2"] {
        let m = common::rod_on_ground(0.0, [0.5, 0.0, 0.0], 0.0, 0.0, 0.05, integrator, MU);
        println!("{integrator}:");
        fallback_on(m);
    }
}

fn fallback_on(mut m: Model) {
    use slither::problem::GroundPoints;
    let steps = (m.duration / m.dt).round() as usize;
    let run = |m: &Model, fail_at: Option<usize>| {
        let calls = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
        let mut integ = Integrator::new(m, Box::new(Natural));
        if let Some(fail_at) = fail_at {
            integ.set_contact(Some(Box::new(FailsOnTheCurve {
                inner: slither::contact::model_for(m).unwrap(),
                begun: 0,
                fail_at,
                done: false,
                calls: calls.clone(),
            })));
        }
        let mut s = State::initial(m);
        let mut error = None;
        for _ in 0..steps {
            if let Err(e) = integ.step(&mut s, m.dt) {
                error = Some(e.to_string());
                break;
            }
        }
        let st = integ.stats();
        let calls = calls.lock().unwrap().clone();
        (s, error, st.ground_point_fallbacks, st.step_halvings, calls)
    };
    m.solver.ground_points = GroundPoints::Curve;
    let (plain, e, n, _, _) = run(&m, None);
    assert!(e.is_none() && n == 0, "{e:?}, {n} fallbacks");
    let (fell, e, n, halvings, calls) = run(&m, Some(10));
    println!("curve: {n} fallback, {halvings} halvings, calls {calls:?}");
    assert!(e.is_none(), "{e:?}");
    assert_eq!(n, 1);
    assert_eq!(halvings, m.max_halvings);
    assert_eq!(calls, vec![true, false]);
    let diff = (0..plain.q.len())
        .map(|k| (plain.q[k] - fell.q[k]).abs())
        .fold(0.0, f64::max);
    println!("largest difference from the plain run: {diff:e} m");
    assert!(diff < 1e-9 * m.diameter, "{diff}");
    m.solver.ground_points = GroundPoints::Nodes;
    let (_, e, n, _, calls) = run(&m, Some(10));
    println!("nodes: {e:?}");
    assert!(e.is_some_and(|e| e.contains("after 8 halvings")));
    assert_eq!((n, calls), (0, vec![true]));
}
