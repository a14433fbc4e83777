//! Ground contact and anisotropic Coulomb friction against analytic results
//! (issue: ground contact as a conic program).
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

/// Step to the end, calling `each` after every step.
fn simulate(m: &Model, each: impl FnMut(&State, &mut Integrator)) -> (State, Integrator<'_>) {
    simulate_path(m, true, each)
}

/// Step with the default contact solver, the semi-smooth Newton (`active = true`), or with one
/// conic solve per Newton iterate (`false`), so that both solvers stay tested.
fn simulate_path(
    m: &Model,
    active: bool,
    mut each: impl FnMut(&State, &mut Integrator),
) -> (State, Integrator<'_>) {
    let mut integ = Integrator::new(m, Box::new(Natural));
    if !active {
        integ.set_contact(Some(Box::new(Dispatcher::new(m, false))));
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
    let m = common::rod_on_ground(
        heading,
        v,
        0.0,
        0.0,
        1.1 * f::norm(v) / (mu * G),
        integrator,
        MU,
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
    let m = common::rod_on_ground(heading, [0.0; 3], below, 0.0, 1.0, integrator, MU);
    let c0 = State::initial(&m).centroid(&m);
    let (s, _) = simulate_path(&m, active, |_, _| {});
    let drift = f::norm(f::sub(s.centroid(&m), c0));
    println!("heading {heading}: {below:.2} deg (threshold {critical:.2}): drift {drift:e} m");
    assert!(drift < 1e-9, "crept by {drift} m below the threshold");
    // Above: slides down with acceleration g (sin - mu cos).
    let above = critical + 4.0;
    let m = common::rod_on_ground(heading, [0.0; 3], above, 0.0, 0.5, integrator, MU);
    let (s, _) = simulate_path(&m, active, |_, _| {});
    let vx: f64 = m.real.clone().map(|i| s.node_velocity(i)[0]).sum::<f64>() / m.real.len() as f64;
    let acc = -vx / s.t;
    let b = above.to_radians();
    let expected = G * (b.sin() - mu * b.cos());
    println!(
        "heading {heading}: {above:.2} deg: acceleration {acc:.9} (analytic {expected:.9}), rel {:.2e}",
        acc / expected - 1.0
    );
    // Rigid sliding from rest at constant acceleration: implicit Euler and BDF2 give the
    // velocity exactly, so only the solver's tolerance is left: measured 1.4e-11 and 1.8e-12
    // (the retired active set, implicit Euler), 9e-13 and 1.4e-12 (BDF2), -2.9e-7 (conic program alone,
    // its interior-point tolerance): 1e-6 is 3.4 times the largest.
    assert!(
        (acc / expected - 1.0).abs() < 1e-6,
        "acceleration {acc} vs {expected}"
    );
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
    let m = common::rod_on_ground(0.0, [0.0; 3], 0.0, height, 0.25, integrator, MU);
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
    // One conic (Clarabel) solve per Newton iterate, no semi-smooth Newton: the fallback path.
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

// ---------------------------------------------------------------------------------------------
// Sliding at oblique angles to the body.
// ---------------------------------------------------------------------------------------------

/// Where a rigid body sliding on anisotropic friction stops (MODEL section 3): per unit mass
/// the friction force is minus the gradient of `D(v) = g sqrt((mu v_f)^2 + (mu_s v_s)^2)`
/// (`mu` = `mu_f` forward, `mu_b` backward), so
/// `dv_f/dt = -g mu^2 v_f / r`, `dv_s/dt = -g mu_s^2 v_s / r`, `r = sqrt(...)`. The velocity
/// follows `|v_s| = |v_s0| (|v_f| / |v_f0|)^k`, `k = mu_s^2 / mu^2` (the sideways part dies
/// first: the path curves toward the body axis), and with `v_f` as the variable
/// `x_f = int_0^|v_f0| r / (g mu^2) du`, `x_s = int_0^|v_f0| v_s(u) r / (g mu^2 u) du` (signs
/// of `v_f0`, `v_s0`). Simpson's rule, 20 000 intervals. Returns the stop displacement
/// `(x_f, x_s)`.
fn anisotropic_stop(vf0: f64, vs0: f64) -> [f64; 2] {
    let mu = if vf0 > 0.0 { MU[0] } else { MU[1] };
    let ms = MU[2];
    let k = (ms / mu).powi(2);
    let u0 = vf0.abs();
    let vs = |u: f64| vs0.abs() * (u / u0).powf(k);
    let r = |u: f64| ((mu * u).powi(2) + (ms * vs(u)).powi(2)).sqrt();
    let n = 20_000;
    let h = u0 / n as f64;
    let (mut xf, mut xs) = (0.0, 0.0);
    for i in 0..=n {
        let u = i as f64 * h;
        let w = if i == 0 || i == n {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        xf += w * r(u) / (G * mu * mu);
        // v_s r / u -> 0 as u -> 0 (k > 1).
        if u > 0.0 {
            xs += w * vs(u) * r(u) / (G * mu * mu * u);
        }
    }
    [vf0.signum() * xf * h / 3.0, vs0.signum() * xs * h / 3.0]
}

/// Acceleration (per unit mass) by anisotropic friction at sliding velocity `(v_f, v_s)`:
/// minus the gradient of `g sqrt((mu v_f)^2 + (mu_s v_s)^2)`.
fn anisotropic_deceleration(vf: f64, vs: f64) -> [f64; 2] {
    let mu = if vf > 0.0 { MU[0] } else { MU[1] };
    let r = (mu * vf).hypot(MU[2] * vs);
    [-G * mu * mu * vf / r, -G * MU[2] * MU[2] * vs / r]
}

/// Heading of the sliding rod (degrees): not along an axis, so that the contact frames and
/// the chain rule from `(v_f, v_s)` to `(x, y)` are exercised.
const HEADING: f64 = 20.0;

/// Slide a straight rod (heading [`HEADING`], forward toward the head) launched at `alpha`
/// degrees to its body at `speed`, with step `dt`: returns the stop displacement of the
/// centroid in the body's frame (forward, sideways), the largest turn of the body (rad) and
/// the largest rise, and the mean node velocity after the first step (body frame).
fn oblique_slide(alpha: f64, speed: f64, dt: f64) -> ([f64; 2], f64, f64, [f64; 2]) {
    let (a, h) = (alpha.to_radians(), HEADING.to_radians());
    let v = [speed * (a + h).cos(), speed * (a + h).sin(), 0.0];
    // World (x, y) to body (forward, sideways).
    let body = |w: [f64; 3]| {
        [
            w[0] * h.cos() + w[1] * h.sin(),
            -w[0] * h.sin() + w[1] * h.cos(),
        ]
    };
    let mut m = scene(HEADING, v, 0.0, 0.0, 1.0);
    m.dt = dt;
    let mut integ = Integrator::new(&m, Box::new(Natural));
    let mut s = State::initial(&m);
    let c0 = s.centroid(&m);
    let (mut turn, mut rise) = (0.0f64, 0.0f64);
    let mut v_probe = [0.0; 2];
    let mut steps = 0;
    // Until the rod has stopped (every node below 1e-9 m/s), at most 1 s.
    loop {
        integ.step(&mut s, dt).unwrap();
        steps += 1;
        let (head, tail) = (s.node(m.real.start), s.node(m.real.end - 1));
        turn = turn.max(((head[1] - tail[1]).atan2(head[0] - tail[0]) - h).abs());
        rise = rise.max(max_height(&m, &s) - 0.5 * m.diameter);
        let vmax = m
            .real
            .clone()
            .map(|i| f::norm(s.node_velocity(i)))
            .fold(0.0, f64::max);
        if steps == 1 {
            let vc: [f64; 3] = m
                .real
                .clone()
                .map(|i| s.node_velocity(i))
                .fold([0.0; 3], f::add);
            v_probe = body(f::scale(vc, 1.0 / m.real.len() as f64));
        }
        if vmax < 1e-9 || steps as f64 * dt > 1.0 {
            break;
        }
    }
    (body(f::sub(s.centroid(&m), c0)), turn, rise, v_probe)
}

/// A straight rod (at 20 degrees to the x axis) launched at 30, 45 and 135 degrees to its body
/// stops where integrating the
/// anisotropic dissipation says (not on the line of its launch: the sideways part of the
/// velocity dies first), decelerates at first along the dissipation's gradient, and never
/// turns or rises. Implicit Euler is first order in the step, so the stop point is
/// Richardson-extrapolated from dt = 1 ms and 0.5 ms. Measured: 3.3e-7, 4.7e-7 and 1.5e-6
/// (30, 45, 135 degrees; 2.5e-3 to 3.2e-3 at 1 ms, half that at 0.5 ms); the launch line
/// misses the stop point by 0.18 to 0.30 rad. Mutation: `mu_forward` and `mu_backward`
/// swapped where the model is built (`src/model/mod.rs`, `Ground`): at 30 degrees the stop
/// point is off by 0.20 and the first step's deceleration by 0.22, fails.
/// The first step's acceleration is the friction law's at the step's end velocity.
#[test]
fn oblique_sliding_stops_where_the_anisotropic_dissipation_says() {
    let speed = 0.5;
    for alpha in [30.0f64, 45.0, 135.0] {
        let a = alpha.to_radians();
        let (vf0, vs0) = (speed * a.cos(), speed * a.sin());
        let stop = anisotropic_stop(vf0, vs0);
        let (d1, turn1, rise1, v1) = oblique_slide(alpha, speed, 1e-3);
        let (d2, turn2, rise2, _) = oblique_slide(alpha, speed, 5e-4);
        let rich = [2.0 * d2[0] - d1[0], 2.0 * d2[1] - d1[1]];
        let err = |d: [f64; 2]| (d[0] - stop[0]).hypot(d[1] - stop[1]) / stop[0].hypot(stop[1]);
        // Where a force along -v (isotropic direction) would have stopped it: on the launch
        // line. The test must tell the two apart.
        let launch_line = (stop[1].atan2(stop[0]) - a).abs();
        // The first step's acceleration: implicit Euler evaluates the friction force at the
        // step's end velocity, so it must equal the gradient law at the measured `v_1`.
        let acc = [(v1[0] - vf0) / 1e-3, (v1[1] - vs0) / 1e-3];
        let decel = anisotropic_deceleration(v1[0], v1[1]);
        let acc_err = (acc[0] - decel[0]).hypot(acc[1] - decel[1]) / decel[0].hypot(decel[1]);
        println!(
            "{alpha} deg: stop ({:.6}, {:.6}) m, analytic ({:.6}, {:.6}) m; rel. error \
             {:.2e} (1 ms), {:.2e} (0.5 ms), {:.2e} (extrapolated); off the launch line by \
             {launch_line:.3} rad; deceleration ({:.5}, {:.5}) vs ({:.5}, {:.5}), rel {acc_err:.1e}; \
             turn {:.1e} rad, rise {:.1e} m",
            rich[0],
            rich[1],
            stop[0],
            stop[1],
            err(d1),
            err(d2),
            err(rich),
            acc[0],
            acc[1],
            decel[0],
            decel[1],
            turn1.max(turn2),
            rise1.max(rise2)
        );
        assert!(
            launch_line > 0.05,
            "{alpha}: the reference is not anisotropic"
        );
        // Measured up to 1.5e-6 (135 degrees); the first-order error at 0.5 ms is 1.6e-3.
        assert!(err(rich) < 1e-5, "{alpha} deg: stop {rich:?} vs {stop:?}");
        assert!(
            err(d2) < 5e-3,
            "{alpha} deg: stop {d2:?} vs {stop:?} at 0.5 ms"
        );
        // Measured up to 1.3e-11: the law holds to the Newton tolerance.
        assert!(
            acc_err < 1e-8,
            "{alpha} deg: deceleration {acc:?} vs {decel:?}"
        );
        assert!(turn1.max(turn2) < 1e-9, "{alpha} deg: the body turned");
        assert!(
            rise1.max(rise2) < 1e-6 * m_diameter(),
            "{alpha} deg: the body rose"
        );
    }
}

fn m_diameter() -> f64 {
    0.02
}

/// `[solver] conic_certificate = 1`: the conic program, run from every step the contact
/// Newton (the default semi-smooth one) solved, moves the solution by less than the Newton tolerance and the normal forces by less
/// than `normal_force_tolerance` (a rod sliding obliquely to a stop, then sticking; and one
/// sliding down an incline above the friction angle).
#[test]
fn conic_certificate_confirms_the_contact_newton_while_sliding_and_sticking() {
    let v = [0.4, 0.2, 0.0];
    for (heading, velocity, incline, duration) in [
        (30.0, v, 0.0, 1.1 * f::norm(v) / (MU[0] * G)),
        (0.0, [0.0; 3], MU[1].atan().to_degrees() + 4.0, 0.3),
    ] {
        let mut m = scene(heading, velocity, incline, 0.0, duration);
        m.solver.conic_certificate = 1;
        let (_, integ) = simulate(&m, |_, _| {});
        let c = &integ.stats().contact;
        let solved = c.semismooth_steps;
        println!(
            "heading {heading}, incline {incline:.2}: {} of {solved} steps certified, {} failed, largest correction {:.3e} and normal-force change {:.3e} tolerances",
            c.certificates,
            c.certificate_failures,
            c.certificate_max_correction,
            c.certificate_max_normal_change
        );
        assert!(solved > 0);
        assert_eq!(c.certificates, solved);
        assert_eq!(c.certificate_failures, 0);
    }
}

/// The S-start's first 0.3 s on 50 elements with implicit Euler at 2e-3 s
/// ([`common::s_start_coarse`]) with `[solver] hessian_reuse` as given: the final state,
/// Newton iterations and the iterations that kept the bending and twist Hessian.
fn s_start_with_reuse(reuse: f64) -> (State, usize, usize) {
    use slither::gait::Muscles;
    let mut p = common::s_start_coarse();
    p.time.duration = Some(0.3);
    p.solver.hessian_reuse = reuse;
    let m = Model::new(&p);
    let mut integ = Integrator::new(
        &m,
        Box::new(Muscles {
            gait: m.gait.clone(),
        }),
    );
    let mut s = State::initial(&m);
    for _ in 0..(m.duration / m.dt).round() as usize {
        integ.step(&mut s, m.dt).unwrap();
    }
    let st = integ.stats();
    (s, st.newton_iterations, st.newton.hessian_reuses)
}

/// Keeping the bending and twist Hessian over a step's iterates changes only Newton's path,
/// not its solution: the gradient is exact at every iterate, so the S-start's state after
/// 0.3 s (150 steps with muscles acting, most of them with contacts changing status) is the
/// one with the Hessian assembled at every iterate, to the Newton tolerance, at no more
/// iterations. Fails if the kept Hessian were used with a stale gradient, or if the reuse
/// never happened.
#[test]
fn a_kept_hessian_leaves_the_s_start_where_a_fresh_one_does() {
    let (fresh, it_fresh, kept_fresh) = s_start_with_reuse(0.0);
    let default = slither::problem::SolverSpec::default().hessian_reuse;
    assert!(default > 0.0, "the default keeps the Hessian");
    let (kept, it_kept, kept_n) = s_start_with_reuse(default);
    assert_eq!(kept_fresh, 0);
    assert!(
        kept_n > it_kept / 2,
        "kept the Hessian at {kept_n} of {it_kept} iterations"
    );
    assert!(
        it_kept as f64 <= 1.05 * it_fresh as f64,
        "{it_kept} iterations against {it_fresh}"
    );
    let dx = fresh
        .q
        .iter()
        .zip(&kept.q)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!("max |q_kept - q_fresh| = {dx:e}; iterations {it_kept} / {it_fresh}, kept {kept_n}");
    assert!(dx < 1e-6, "states differ by {dx:e}");
}
