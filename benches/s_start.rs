//! The whole S-start (`problems/s_start.toml`, 50 elements, dt 2e-3) over its first 0.5 s of
//! simulated time (lift-off, the first contact changes and the pulse forming), end to end through
//! the run loop: assembly, factorisations, semi-smooth and conic contact, frames. Beside it the
//! same window with BDF2, and the time of one simulated second is printed from the statistics.
//! A second group runs 200 elements over the first 1.5 s, where slip fronts start.
use criterion::{criterion_group, criterion_main, Criterion};
use slither::model::Model;
use slither::{problem, sim};
use std::path::Path;

fn model(integrator: problem::IntegratorKind) -> Model {
    let mut p = problem::load(Path::new("problems/s_start.toml")).expect("bundled problem");
    p.time.duration = Some(0.5);
    p.solver.integrator = integrator;
    Model::new(&p)
}

/// One run of `m` outside the timing, and its solver statistics on stdout.
fn print_stats(name: &str, m: &Model, kind: problem::IntegratorKind) {
    let o = sim::run_gait(m, kind, &mut |_| {}, &mut |_| {}).unwrap();
    let st = &o.stats;
    println!(
        "{name}: {} steps, {:.2} Newton iterations/step, {} conic solves, {} fallbacks, {} halvings",
        st.steps,
        st.newton_iterations as f64 / st.steps as f64,
        st.contact.conic_solves,
        st.contact.semismooth_fallbacks,
        st.step_halvings
    );
}

fn bench_s_start(c: &mut Criterion) {
    let mut g = c.benchmark_group("s_start_0.5s");
    g.sample_size(10);
    for (name, kind) in [
        ("implicit_euler", problem::IntegratorKind::ImplicitEuler),
        ("bdf2", problem::IntegratorKind::Bdf2),
    ] {
        let m = model(kind);
        print_stats(name, &m, kind);
        g.bench_function(name, |b| {
            b.iter(|| sim::run_gait(&m, kind, &mut |_| {}, &mut |_| {}).unwrap())
        });
    }
    g.finish();
}

/// The S-start at 200 elements and dt 1e-3 over its first 1.5 s, implicit Euler: the window
/// where slip fronts first run along the body (steps of 30 or more Newton iterations from 1.25
/// s on, before fronts slid together; `contact::active::FRONT_ROUNDS`).
fn bench_s_start_200(c: &mut Criterion) {
    let mut p = problem::load(Path::new("problems/s_start.toml")).expect("bundled problem");
    p.rod.elements = 200;
    p.time.dt = Some(1e-3);
    p.time.duration = Some(1.5);
    let m = Model::new(&p);
    let kind = problem::IntegratorKind::ImplicitEuler;
    print_stats("200 elements, 1.5 s", &m, kind);
    let mut g = c.benchmark_group("s_start_200_1.5s");
    g.sample_size(10);
    g.bench_function("implicit_euler", |b| {
        b.iter(|| sim::run_gait(&m, kind, &mut |_| {}, &mut |_| {}).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench_s_start, bench_s_start_200);
criterion_main!(benches);
