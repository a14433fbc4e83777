//! Twist, writhe, link and the local densities of a 100-element framed rod: the cost of
//! evaluating topology at one output frame.
use criterion::{criterion_group, criterion_main, Criterion};
use slither::topology::{self, FramedCurve};

fn curve(n: usize) -> FramedCurve {
    // A helix-like, twisted open curve.
    let nodes: Vec<[f64; 3]> = (0..=n)
        .map(|i| {
            let s = i as f64 / n as f64;
            [0.1 * (8.0 * s).cos(), 0.1 * (8.0 * s).sin(), 0.3 * s]
        })
        .collect();
    let d1: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let t = [
                nodes[i + 1][0] - nodes[i][0],
                nodes[i + 1][1] - nodes[i][1],
                nodes[i + 1][2] - nodes[i][2],
            ];
            let u = [0.0, 0.0, 1.0];
            let c = [
                t[1] * u[2] - t[2] * u[1],
                t[2] * u[0] - t[0] * u[2],
                t[0] * u[1] - t[1] * u[0],
            ];
            let l = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
            [c[0] / l, c[1] / l, c[2] / l]
        })
        .collect();
    FramedCurve {
        nodes,
        d1,
        closed: false,
    }
}

fn bench(c: &mut Criterion) {
    let k = curve(100);
    c.bench_function("topology_100_elements", |b| {
        b.iter(|| topology::topology(&k))
    });
    c.bench_function("densities_100_elements_window_L10", |b| {
        b.iter(|| topology::densities(&k, 0.03))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
