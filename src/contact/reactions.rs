//! Contact reactions as functions of the Newton step, for the active-set path.
//!
//! With a contact's status held, its reaction is the objective's gradient at the held
//! coordinates (`N_c = dPhi/dz_c`; a sticking contact's friction force at `x_c, y_c`), so it
//! changes along a step `dq` by the Hessian row there: `dN_c = H[z_c, :] dq` to first order.
//! That gives two things:
//!
//! * **Contact forces inside the Newton system.** A sliding contact's friction force is
//!   `N_c u_c(q)` (`u_c` the dissipation gradient per unit normal force, from `Contacts::slide_derivatives`).
//!   Newton's linearisation of the residual `g(q) + sum_c N_c(q) u_c(q)` is
//!   `(A + sum_c u_c H[z_c, :]) dq = -g`, with `A` the symmetric Hessian the line search
//!   uses. The non-symmetric rank-`n_s` term is taken by a few sweeps
//!   `A dq^{m+1} = -g - sum_c u_c (H[z_c, :] dq^m)` with `A`'s factorisation (a Neumann series
//!   of `A^-1 U V^T`, which contracts at the rate the lagged normal forces used to: 0.04 per
//!   sweep on the S-start), so the iteration converges quadratically instead of linearly.
//! * **Force residuals in physical units.** The predicted change of every reaction over the
//!   step is how far the iterate's contact forces are from the solution's: the active-set
//!   iteration stops when it is below `[solver] normal_force_tolerance * W / n_c`, and a
//!   contact whose reaction is pulling both now and after the step (or a sticking force
//!   outside the cone both now and after the step) changes status at once, without first
//!   converging with the wrong status.

use super::{Contacts, Mode};
use crate::energy::Assembly;
use crate::newton::Newton;
use crate::rod::dof::{self, HALF_BANDWIDTH as W};

/// One row of the banded Hessian: entries `(k, k - W ..= k + W)` (zero outside `0..n`).
type Row = [f64; 2 * W + 1];

/// Largest number of sweeps for the coupled Newton direction.
pub const MAX_SWEEPS: usize = 8;

/// The Hessian rows at the held coordinates of the touching contacts, and the predicted
/// change of their reactions over a step.
#[derive(Clone, Debug, Default)]
pub struct Reactions {
    /// Rows at `x, y, z` of every contact (zero for free contacts; `x, y` only for sticking).
    rows: Vec<[Row; 3]>,
    /// Dissipation gradient per unit normal force in `(x, y)`, for sliding contacts with a
    /// positive normal force (otherwise zero: a clamped force does not change to first order).
    unit: Vec<[f64; 2]>,
    /// Predicted change of each reaction `(x, y, z)` over the last step.
    pub change: Vec<[f64; 3]>,
    rhs: Vec<f64>,
    prev: Vec<f64>,
    symmetric: Vec<f64>,
}

fn row_of(asm: &Assembly, k: usize) -> Row {
    let n = asm.n();
    std::array::from_fn(|r| {
        let j = (k + r).wrapping_sub(W);
        if j < n {
            asm.h(k, j)
        } else {
            0.0
        }
    })
}

fn row_dot(row: &Row, k: usize, dq: &[f64]) -> f64 {
    let n = dq.len();
    let mut s = 0.0;
    for (r, v) in row.iter().enumerate() {
        let j = (k + r).wrapping_sub(W);
        if j < n {
            s += v * dq[j];
        }
    }
    s
}

impl Reactions {
    /// Start an iterate with `nc` contacts: no sliding contact couples yet.
    pub fn begin(&mut self, nc: usize) {
        self.rows.resize(nc, [[0.0; 2 * W + 1]; 3]);
        self.unit.clear();
        self.unit.resize(nc, [0.0; 2]);
        self.change.resize(nc, [0.0; 3]);
    }

    /// Sliding contact `c`'s dissipation gradient `grad` in `(x, y)` with normal force `n`
    /// (kept per unit force; a clamped force, `n = 0`, does not couple).
    pub fn set_slide(&mut self, c: usize, grad: [f64; 2], n: f64) {
        if n > 0.0 {
            self.unit[c] = [grad[0] / n, grad[1] / n];
        }
    }

    /// Capture the rows of the assembled Hessian `asm` (before the held coordinates are
    /// fixed) at the held coordinates of the statuses of `ct`.
    pub fn capture(&mut self, ct: &Contacts, asm: &Assembly) {
        for c in 0..ct.nodes.len() {
            let k = dof::node(ct.nodes[c]);
            match ct.mode[c] {
                Mode::Free => {}
                Mode::Stick => {
                    for r in 0..3 {
                        self.rows[c][r] = row_of(asm, k + r);
                    }
                }
                Mode::Slide => self.rows[c][2] = row_of(asm, k + 2),
            }
        }
    }

    /// Predicted change of every touching contact's reactions over the step `dq`, into
    /// `change`; returns the largest normal-force change (N).
    pub fn predict(&mut self, ct: &Contacts, dq: &[f64]) -> f64 {
        let mut worst: f64 = 0.0;
        for c in 0..ct.nodes.len() {
            let k = dof::node(ct.nodes[c]);
            self.change[c] = [0.0; 3];
            let rows = match ct.mode[c] {
                Mode::Free => 0..0,
                Mode::Stick => 0..3,
                Mode::Slide => 2..3,
            };
            for r in rows {
                self.change[c][r] = row_dot(&self.rows[c][r], k + r, dq);
            }
            worst = worst.max(self.change[c][2].abs());
        }
        worst
    }

    /// Whether any sliding contact couples its normal force into the Newton system.
    pub fn coupled(&self) -> bool {
        self.unit.iter().any(|u| u[0] != 0.0 || u[1] != 0.0)
    }

    /// Turn the symmetric Newton direction `nw.dq` (solved with the factorisation in `nw.lin`
    /// for the gradient `nw.asm.grad`) into the direction of the coupled system
    /// `(A + sum_c u_c H[z_c, :]) dq = -g`, by sweeps until the normal-force changes move by
    /// less than `tol` (N). Held coordinates (`held`) keep a zero step. Returns the sweeps, or
    /// [`MAX_SWEEPS`] when the sweeps do not contract (each must at least halve the last
    /// change: far from the solution the coupling can be too strong for them) and the
    /// symmetric direction was kept.
    pub fn couple(&mut self, ct: &Contacts, nw: &mut Newton, held: &[bool], tol: f64) -> usize {
        let n = nw.dq.len();
        let nc = ct.nodes.len();
        self.rhs.resize(n, 0.0);
        self.prev.clear();
        self.prev.resize(nc, 0.0);
        self.symmetric.clear();
        self.symmetric.extend_from_slice(&nw.dq);
        let mut last = f64::INFINITY;
        for sweep in 1..=MAX_SWEEPS {
            let mut moved: f64 = 0.0;
            for k in 0..n {
                self.rhs[k] = -nw.asm.grad[k];
            }
            for c in 0..nc {
                let u = self.unit[c];
                if u == [0.0; 2] {
                    continue;
                }
                let k = dof::node(ct.nodes[c]);
                let dn = row_dot(&self.rows[c][2], k + 2, &nw.dq);
                moved = moved.max((dn - self.prev[c]).abs());
                self.prev[c] = dn;
                for r in 0..2 {
                    if !held[k + r] {
                        self.rhs[k + r] -= u[r] * dn;
                    }
                }
            }
            if moved <= tol {
                return sweep - 1;
            }
            if sweep > 1 && moved > 0.5 * last {
                break;
            }
            last = moved;
            nw.dq.copy_from_slice(&self.rhs);
            nw.lin.solve(&mut nw.dq);
        }
        nw.dq.copy_from_slice(&self.symmetric);
        MAX_SWEEPS
    }
}
