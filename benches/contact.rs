//! One implicit step with ground contact and friction at 50 and 200 elements (the semi-smooth
//! Newton, conic program as fallback); prints conic solves and iterations per step and
//! Clarabel's share, also for the conic path alone.
use criterion::{criterion_group, criterion_main, Criterion};
use slither::integrator::{Integrator, Natural};
use slither::model::Model;
use slither::problem;
use slither::state::State;
use std::path::Path;

fn model(elements: usize) -> Model {
    let text = format!(
        r#"
[rod]
length = 1.0
diameter = 0.02
elements = {elements}
bending_stiffness = 1e-2
natural_curvature = [0.0, 3.0]
[initial]
velocity = [0.4, 0.1, 0.0]
[ground]
[time]
dt = 1e-3
duration = 1.0
"#
    );
    Model::new(&problem::parse(&text, Path::new("bench")).unwrap())
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("contact_step");
    for n in [50, 200] {
        let m = model(n);
        let mut integ = Integrator::new(&m, Box::new(Natural));
        let mut s0 = State::initial(&m);
        for _ in 0..20 {
            integ.step(&mut s0, m.dt).unwrap();
        }
        g.bench_function(format!("{n}_elements"), |b| {
            b.iter_batched_ref(
                || s0.clone(),
                |s| integ.step(s, m.dt).unwrap(),
                criterion::BatchSize::SmallInput,
            )
        });
        // The same 200 steps with the semi-smooth Newton (default) and with a conic program at
        // every Newton iterate (the fallback path alone), for comparison.
        for semismooth in [true, false] {
            let mut integ = Integrator::new(&m, Box::new(Natural));
            if !semismooth {
                integ.set_contact(Some(Box::new(slither::contact::Dispatcher::new(&m, false))));
            }
            let mut s = s0.clone();
            let t = std::time::Instant::now();
            for _ in 0..200 {
                integ.step(&mut s, m.dt).unwrap();
            }
            let wall = t.elapsed().as_secs_f64();
            let st = integ.stats();
            println!(
                "{n} elements, {}: {:.3} ms/step, {:.2} Newton it/step, {:.2} conic solves/step, {} semi-smooth steps, {} fallbacks, {:.1} Clarabel iterations/solve, Clarabel {:.0}% of step time, assembly {:.0}%",
                if semismooth { "semi-smooth" } else { "conic only" },
                1e3 * wall / st.steps as f64,
                st.newton_iterations as f64 / st.steps as f64,
                st.contact.conic_solves as f64 / st.steps as f64,
                st.contact.semismooth_steps,
                st.contact.semismooth_fallbacks,
                st.contact.conic_iterations as f64 / st.contact.conic_solves.max(1) as f64,
                100.0 * st.contact.conic_s / wall,
                100.0 * st.newton.assembly_s / wall
            );
        }
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(3));
    targets = bench
}
criterion_main!(benches);
