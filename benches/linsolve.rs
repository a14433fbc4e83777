//! The step Hessian's factorisation and solve: faer's sparse (simplicial) Cholesky against the
//! band Cholesky, on a band matrix of the assembly's pattern at 50 and 200 elements.
use criterion::{criterion_group, criterion_main, Criterion};
use slither::band::cholesky::{FaerLlt, LinSolver};
use slither::band::Assembly;
use slither::rod::dof;
use std::hint::black_box;

/// A symmetric positive definite matrix with every entry of the band set.
fn band_matrix(elements: usize) -> Assembly {
    let n = dof::count(elements + 1);
    let mut asm = Assembly::new(n);
    let w = asm.half_bandwidth();
    let mut x = 0x9E3779B97F4A7C15u64;
    for j in 0..n {
        for i in j.saturating_sub(w)..j {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            asm.add_h(i, j, (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5);
        }
        asm.add_h(j, j, 2.0 * w as f64);
        asm.grad[j] = (j as f64).sin();
    }
    asm
}

fn bench_linsolve(c: &mut Criterion) {
    for elements in [50, 200] {
        let asm = band_matrix(elements);
        let mut faer = FaerLlt::new(&asm);
        let mut band = LinSolver::new(&asm);
        let mut b = asm.grad.clone();
        c.bench_function(&format!("faer_factor_solve_{elements}"), |bn| {
            bn.iter(|| {
                faer.factor(black_box(&asm)).unwrap();
                b.copy_from_slice(&asm.grad);
                faer.solve(&mut b);
                black_box(&b);
            })
        });
        c.bench_function(&format!("band_factor_solve_{elements}"), |bn| {
            bn.iter(|| {
                band.factor(black_box(&asm)).unwrap();
                b.copy_from_slice(&asm.grad);
                band.solve(&mut b);
                black_box(&b);
            })
        });
    }
}

criterion_group!(benches, bench_linsolve);
criterion_main!(benches);
