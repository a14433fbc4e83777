//! The explicit reference integrator (velocity Verlet, `slither::integrator::explicit`):
//! its gradient-only forces against the implicit path's gradient and finite differences; its
//! energy error, bounded and second order in the step (with muscles: after their work);
//! agreement with the implicit integrator on a cantilever swing within the implicit
//! integrator's own first-order error; and its stability limit, measured by bisection against
//! the linear theory `2/omega_max` (stretch- and bending-limited), with the blow-up above it
//! reported as an error naming t and dt; scenes with ground or in static mode are refused.
mod common;
use common::{model, Rng};
use slither::charts;
use slither::fd;
use slither::integrator::explicit::{Explicit, Unsupported};
use slither::integrator::{Integrator, Natural, StepError};
use slither::model::Model;
use slither::problem::IntegratorKind;
use slither::state::State;

/// A free, bent and twisted rod with natural curvature and twist, spinning and translating.
fn free_rod(elements: usize, g: f64) -> Model {
    model(&format!(
        r#"
[rod]
length = 0.5
diameter = 0.02
elements = {elements}
bending_stiffness = 2e-3
natural_curvature = [3.0, 6.0]
natural_twist = 4.0
[initial]
velocity = [0.1, 0.05, 0.0]
angular_velocity = [0.5, 0.0, 2.0]
[gravity]
g = {g}
[time]
dt = 1e-3
duration = 1.0
"#
    ))
}

/// The soft cantilever of `problems/cantilever_swing.toml` (W = 10) with `elements` elements.
fn cantilever(elements: usize, duration: f64) -> Model {
    cantilever_of_length(1.0, elements, duration)
}

/// The same rod cut to `length` (m).
fn cantilever_of_length(length: f64, elements: usize, duration: f64) -> Model {
    let text = std::fs::read_to_string("problems/cantilever_swing.toml").unwrap();
    let text = text
        .replace("length = 1.0 ", &format!("length = {length} "))
        .replace("elements = 50", &format!("elements = {elements}"))
        .replace("duration = 0.5 ", &format!("duration = {duration} "));
    let m = model(&text);
    assert_eq!(m.elements(), elements);
    assert_eq!(m.duration, duration);
    assert_eq!(m.length, length);
    m
}

fn rel_max(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |s, x| s.max(x.abs()));
    a.iter()
        .zip(b)
        .fold(0.0f64, |s, (x, y)| s.max((x - y).abs()))
        / scale
}

#[test]
fn gradient_only_forces_match_the_assembled_gradient_and_finite_differences() {
    for (seed, clamp) in [(1u64, "none"), (2, "tail"), (3, "head")] {
        let text = format!(
            "[rod]\nlength = 0.5\ndiameter = 0.02\nelements = 7\nbending_stiffness = 2e-3\n\
             clamp = \"{clamp}\"\nnatural_curvature = [2.0, -3.0]\nnatural_twist = 1.5\n\
             [time]\ndt = 1e-3\nduration = 1.0\n"
        );
        let m = model(&text);
        let mut r = Rng((seed * 0x9E37_79B9_7F4A_7C15) | 1);
        let mut s = State::initial(&m);
        let l0 = m.rest_len[0];
        for k in 0..m.ndof {
            if !m.fixed[k] {
                s.q[k] += if slither::rod::dof::is_edge(k) {
                    1.5 * r.sym()
                } else {
                    0.3 * l0 * r.sym()
                };
            }
        }
        let mut implicit = Integrator::new(&m, Box::new(Natural));
        let mut ex = Explicit::new(&m, Box::new(Natural)).unwrap();
        // Frames current (as where Verlet evaluates forces): closed form; then stale frames
        // (the shape moved after the frames were transported): dual numbers.
        for (stale, path) in [(false, 0), (true, 1)] {
            if stale {
                for k in 0..m.ndof {
                    if !m.fixed[k] {
                        s.q[k] += 0.1 * l0 * r.sym();
                    }
                }
            } else {
                s.update_frames();
            }
            let before = ex.stencil_paths;
            let g = ex.gradient(&s).to_vec();
            let used = [
                ex.stencil_paths[0] - before[0],
                ex.stencil_paths[1] - before[1],
            ];
            assert_eq!(used[path], m.nodes - 2, "{clamp}: paths {used:?}");
            assert_eq!(used[1 - path], 0, "{clamp}: paths {used:?}");
            let (energy, asm) = implicit.energy_derivatives(&s, &s.q, false);
            let pot = ex.potential(&s);
            assert!(
                (pot - energy).abs() <= 1e-12 * energy.abs(),
                "{clamp}, stale {stale}: energy {pot} vs {energy}"
            );
            let q0 = s.q.clone();
            let num = fd::gradient(&mut |q: &[f64]| implicit.energy_at(&s, q), &q0, 1e-6);
            let e_asm = rel_max(&g, &asm.grad);
            let e_fd = rel_max(&g, &num);
            println!("clamp {clamp}, stale frames {stale}: vs assembled {e_asm:.2e}, vs finite differences {e_fd:.2e}");
            assert!(e_asm < 1e-10, "{clamp}, stale {stale}: {e_asm:e}");
            assert!(e_fd < 1e-6, "{clamp}, stale {stale}: {e_fd:e}");
            // The two gradients are computed differently: the check can fail.
            assert!(e_asm > 0.0 || stale);
        }
    }
}

/// Largest energy error over a run with `n` steps of `h`, measured with the implicit
/// integrator's energy evaluation (independent of the explicit one's bookkeeping), and the
/// final linear momentum drift.
fn energy_error(m: &Model, h: f64, n: usize) -> (f64, f64, f64) {
    let mut ex = Explicit::new(m, Box::new(Natural)).unwrap();
    let mut meter = Integrator::new(m, Box::new(Natural));
    let mut s = State::initial(m);
    let e0 = meter.energies(&s).total;
    let p0 = s.momentum(m);
    let mut worst: f64 = 0.0;
    for _ in 0..n {
        ex.step(&mut s, h).unwrap();
        worst = worst.max((meter.energies(&s).total - e0).abs());
    }
    let p = s.momentum(m);
    let dp = (0..3).map(|c| (p[c] - p0[c]).abs()).fold(0.0, f64::max);
    // The integrator's own monitor agrees with the independent measurement.
    assert!(
        (ex.max_energy_error() - worst).abs() <= 1e-9 * ex.energy_scale() + 1e-3 * worst,
        "monitor {} vs measured {worst}",
        ex.max_energy_error()
    );
    (worst, dp, ex.energy_scale())
}

#[test]
fn verlet_energy_error_is_bounded_and_second_order() {
    // Free rod without gravity, and the cantilever swinging under gravity (clamp held).
    let cases = [
        ("free bent twisted rod", free_rod(10, 0.0), 1e-3, 400),
        ("cantilever swing", cantilever(10, 0.2), 5e-5, 4000),
    ];
    for (name, m, h, n) in cases {
        let mut errs = Vec::new();
        for k in 0..3 {
            let (e, dp, scale) = energy_error(&m, h / (1 << k) as f64, n << k);
            println!(
                "{name}: dt = {:.3e} s: max |E - E0| = {e:.3e} J ({:.2e} of the energy scale), momentum drift {dp:.1e}{}",
                h / (1 << k) as f64,
                e / scale,
                if m.clamp == slither::problem::Clamp::None { "" } else { " (clamped: not conserved)" }
            );
            assert!(
                e < 1e-3 * scale,
                "{name}: energy error {e} vs scale {scale}"
            );
            if m.clamp == slither::problem::Clamp::None {
                assert!(dp < 1e-12, "{name}: momentum drift {dp}");
            }
            errs.push(e);
        }
        for k in 0..2 {
            let order = (errs[k] / errs[k + 1]).log2();
            println!("{name}: observed order {order:.3}");
            assert!(
                (1.8..=2.2).contains(&order),
                "{name}: energy error order {order} (errors {errs:?})"
            );
        }
    }
}

#[test]
fn explicit_and_implicit_agree_within_the_implicit_first_order_error() {
    let m = cantilever(20, 0.1);
    let tip = |x: &[[f64; 3]]| x[0];
    let run = |method, h: f64| {
        let n = (m.duration / h).round() as usize;
        charts::simulate(&m, method, h, n).unwrap().unwrap()
    };
    let ex = run(IntegratorKind::VelocityVerlet, 2e-5);
    let ex2 = run(IntegratorKind::VelocityVerlet, 1e-5);
    let im = run(IntegratorKind::ImplicitEuler, 1e-3);
    let im2 = run(IntegratorKind::ImplicitEuler, 5e-4);
    let d =
        |a: [f64; 3], b: [f64; 3]| slither::rod::vec3::f::norm(slither::rod::vec3::f::sub(a, b));
    // Implicit Euler is first order: e(h) ~ c h, so |x_h - x_{h/2}| estimates the error of
    // x_{h/2} against the exact solution of the discrete model.
    let est = d(tip(&im.x), tip(&im2.x));
    let err = d(tip(&im2.x), tip(&ex.x));
    let verlet = d(tip(&ex.x), tip(&ex2.x));
    let drop = m.q0[slither::rod::dof::node(m.real.start) + 2] - tip(&ex.x)[2];
    println!(
        "tip drop {drop:.4e} m; implicit dt 5e-4 vs explicit: {err:.3e} m; implicit estimate {est:.3e} m; explicit self-difference {verlet:.3e} m"
    );
    assert!(drop > 0.01, "the tip falls: {drop}");
    assert!(verlet < 1e-3 * est, "explicit converged: {verlet} vs {est}");
    let ratio = err / est;
    assert!(
        (0.8..=1.25).contains(&ratio),
        "implicit error {err} vs its first-order estimate {est} (ratio {ratio})"
    );
    // and the implicit error itself halves with the step
    let err1 = d(tip(&im.x), tip(&ex.x));
    let order = (err1 / err).log2();
    assert!((0.9..=1.1).contains(&order), "implicit order {order}");
}

/// Largest explicit step that runs `m` to the end, by bisection on whole runs (2 %
/// resolution), from a bracket that is not centred on the prediction `lin`.
fn measured_limit(m: &Model, lin: f64) -> f64 {
    let (mut lo, mut hi) = (0.6 * lin, 1.9 * lin);
    assert!(charts::stable(m, IntegratorKind::VelocityVerlet, lo, m.duration).unwrap());
    assert!(!charts::stable(m, IntegratorKind::VelocityVerlet, hi, m.duration).unwrap());
    while hi / lo > 1.02 {
        let mid = (lo * hi).sqrt();
        if charts::stable(m, IntegratorKind::VelocityVerlet, mid, m.duration).unwrap() {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

#[test]
fn explicit_blows_up_above_its_limit_and_reports_t_and_dt() {
    // The swing's rod (l0 = 5a, 2.5a: stretch waves should limit the step) and a short piece
    // of it finely meshed (l0 = a/4, a/8: bending waves should).
    let cases = [
        ("swing", 1.0, [10, 20], 0.1, "stretch"),
        ("short", 0.2, [40, 80], 0.02, "bend"),
    ];
    for (name, length, elements, duration, mode) in cases {
        let mut limits = Vec::new();
        for n in elements {
            let m = cantilever_of_length(length, n, duration);
            let lin = charts::linear_stability_limit(&m);
            let lo = measured_limit(&m, lin.dt);
            let rho_a = m.line_density();
            let l0 = m.length / n as f64;
            let stretch = l0 * (rho_a / m.stretch).sqrt();
            let bend = l0 * l0 * (rho_a / m.bend).sqrt();
            println!(
                "{name}, {n} elements (l0/a = {:.3}): measured dt_max = {lo:.4e} s, linear theory 2/omega_max = {:.4e} s ({} mode, shares {:.3?}), l0 sqrt(rhoA/EA) = {stretch:.3e} s, l0^2 sqrt(rhoA/B) = {bend:.3e} s",
                l0 / m.diameter,
                lin.dt,
                lin.mode(),
                lin.shares
            );
            assert!(
                (lo / lin.dt - 1.0).abs() < 0.05,
                "{name}: measured {lo} vs linear theory {}",
                lin.dt
            );
            assert_eq!(lin.mode(), mode, "{name}, {n} elements");
            limits.push((l0, lo, lin.dt));
            // Above the limit: an error naming the time and the step; the state is that of
            // the last good step.
            let h = 1.3 * lo;
            let mut ex = Explicit::new(&m, Box::new(Natural)).unwrap();
            let mut s = State::initial(&m);
            let steps = (duration / h).ceil() as usize;
            let mut failure = None;
            for _ in 0..steps {
                let t = s.t;
                if let Err(e) = ex.step(&mut s, h) {
                    assert_eq!(s.t, t, "state restored to the start of the failed step");
                    assert!(s.q.iter().all(|x| x.is_finite()));
                    failure = Some(e);
                    break;
                }
            }
            let e = failure.expect("unstable above the limit");
            let StepError::Unstable { t, dt, .. } = &e else {
                panic!("wrong error {e}");
            };
            assert_eq!(*dt, h);
            assert!(*t > 0.0 && *t < duration, "t = {t}");
            let msg = e.to_string();
            println!("{msg}");
            assert!(msg.contains(&format!("t = {t} s")) && msg.contains(&format!("dt = {h} s")));
        }
        // Halving l0 scales the limit as the linear theory says (measured, not assumed).
        let measured = (limits[0].1 / limits[1].1).log2();
        let theory = (limits[0].2 / limits[1].2).log2();
        println!("{name}: limit ~ l0^{measured:.3} (linear theory l0^{theory:.3})");
        assert!((measured - theory).abs() < 0.15, "{measured} vs {theory}");
    }
}

#[test]
fn explicit_rejects_ground_and_static_scenes() {
    let ground = free_rod(4, 9.81);
    let mut with_ground = ground.clone();
    with_ground.ground = Some(slither::contact::Ground {
        mu_f: 0.1,
        mu_b: 0.1,
        mu_s: 0.1,
    });
    assert_eq!(
        Explicit::new(&with_ground, Box::new(Natural)).err(),
        Some(Unsupported::Ground)
    );
    assert!(matches!(
        slither::sim::run_explicit(&with_ground, Box::new(Natural), &mut |_| {}, &mut |_| {}),
        Err(Unsupported::Ground)
    ));
    let mut stat = ground;
    stat.mode = slither::problem::Mode::Static;
    assert_eq!(
        Explicit::new(&stat, Box::new(Natural)).err(),
        Some(Unsupported::Static)
    );
}

#[test]
fn muscle_work_is_accounted_in_the_energy_monitor() {
    // A free rod driven by a travelling serpenoid wave (no gravity, no ground): the muscles
    // change the energy; the monitor subtracts their work (trapezoid rule), so its error is
    // second order in the step and far below the change of the energy itself.
    let m = model(
        r#"
[rod]
length = 0.5
diameter = 0.02
elements = 10
bending_stiffness = 2e-3
[gravity]
g = 0.0
[time]
dt = 1e-3
duration = 0.5
[gait]
kind = "serpenoid"
stress = 1250.0
speed = 0.5
wavelength = 0.5
"#,
    );
    let mut errs = Vec::new();
    for (h, n) in [(5e-4, 1000), (2.5e-4, 2000), (1.25e-4, 4000)] {
        let mut ex = Explicit::new(
            &m,
            Box::new(slither::gait::Muscles {
                gait: m.gait.clone(),
            }),
        )
        .unwrap();
        let mut s = State::initial(&m);
        let e0 = ex.energies(&s).total;
        let mut change: f64 = 0.0;
        for _ in 0..n {
            ex.step(&mut s, h).unwrap();
            change = change.max((ex.energies(&s).total - e0).abs());
        }
        let err = ex.max_energy_error();
        println!(
            "dt = {h:.3e} s: energy change up to {change:.3e} J, monitored error {err:.3e} J, scale {:.3e} J",
            ex.energy_scale()
        );
        assert!(change > 1000.0 * err, "{change} vs {err}");
        errs.push(err);
    }
    for k in 0..2 {
        let order = (errs[k] / errs[k + 1]).log2();
        println!("monitored error order {order:.3}");
        assert!((1.8..=2.2).contains(&order), "{errs:?}");
    }
}
