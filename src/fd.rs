//! The crate's one central-difference checker for analytic derivatives (used by the tests of
//! every energy term). It only evaluates the function: gradients are differenced from values
//! and Hessians from gradients, so it is independent of the analytic code it checks.

/// A deterministic pseudo-random number in `[-0.5, 0.5)` (xorshift64), for the random
/// configurations of the tests; `state` must not be zero.
pub fn uniform(state: &mut u64) -> f64 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    (*state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
}

/// Central-difference gradient of `f` at `x` with step `h_k = eps * max(1, |x_k|)`.
pub fn gradient(f: &mut dyn FnMut(&[f64]) -> f64, x: &[f64], eps: f64) -> Vec<f64> {
    let mut y = x.to_vec();
    (0..x.len())
        .map(|k| {
            let h = eps * x[k].abs().max(1.0);
            y[k] = x[k] + h;
            let fp = f(&y);
            y[k] = x[k] - h;
            let fm = f(&y);
            y[k] = x[k];
            (fp - fm) / (2.0 * h)
        })
        .collect()
}

/// Central-difference Jacobian (row-major, `m x n`) of a vector function `g: R^n -> R^m`.
pub fn jacobian(g: &mut dyn FnMut(&[f64]) -> Vec<f64>, x: &[f64], eps: f64) -> Vec<Vec<f64>> {
    let n = x.len();
    let mut y = x.to_vec();
    let mut cols = Vec::with_capacity(n);
    for k in 0..n {
        let h = eps * x[k].abs().max(1.0);
        y[k] = x[k] + h;
        let gp = g(&y);
        y[k] = x[k] - h;
        let gm = g(&y);
        y[k] = x[k];
        cols.push(
            gp.iter()
                .zip(&gm)
                .map(|(a, b)| (a - b) / (2.0 * h))
                .collect::<Vec<f64>>(),
        );
    }
    let m = cols.first().map_or(0, |c| c.len());
    (0..m)
        .map(|r| (0..n).map(|c| cols[c][r]).collect())
        .collect()
}

/// Relative error `|a - b| / max(|b|, floor)` in the Euclidean norm.
pub fn rel_error(a: &[f64], b: &[f64], floor: f64) -> f64 {
    let d: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt();
    let nb: f64 = b.iter().map(|y| y * y).sum::<f64>().sqrt();
    d / nb.max(floor)
}
