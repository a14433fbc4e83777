//! One implicit Euler step of a bent, twisted, falling rod at 50 and 200 elements, and the
//! split of a Newton iteration into assembly, factorisation and solve.
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
natural_curvature = [3.0, 6.0]
natural_twist = 2.0
[initial]
velocity = [0.1, 0.0, 0.0]
angular_velocity = [0.0, 0.0, 1.0]
[time]
dt = 1e-3
duration = 1.0
"#
    );
    Model::new(&problem::parse(&text, Path::new("bench")).unwrap())
}

fn bench_step(c: &mut Criterion) {
    let mut g = c.benchmark_group("implicit_step");
    for n in [50, 200] {
        let m = model(n);
        // Start from a state that is already moving and bending.
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
        // Time split per Newton iteration over 200 steps.
        let mut integ = Integrator::new(&m, Box::new(Natural));
        let mut s = s0.clone();
        for _ in 0..200 {
            integ.step(&mut s, m.dt).unwrap();
        }
        let st = integ.stats();
        let it = st.newton_iterations as f64;
        println!(
            "{n} elements: {:.2} Newton iterations/step; per iteration: assembly {:.1} us, factorization {:.1} us, solve {:.1} us, line search {:.1} us",
            it / st.steps as f64,
            1e6 * st.newton.assembly_s / it,
            1e6 * st.newton.factor_s / it,
            1e6 * st.newton.solve_s / it,
            1e6 * st.newton.line_search_s / it
        );
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(3));
    targets = bench_step
}
criterion_main!(benches);
