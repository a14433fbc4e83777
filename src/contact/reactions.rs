//! Contact reactions as functions of the Newton step, for the semi-smooth Newton.
//!
//! With a contact's status held, its reaction is the objective's gradient at the held
//! coordinates (`N_c = dPhi/dz_c`; a sticking contact's friction force at `x_c, y_c`), so it
//! changes along a step `dq` by the Hessian row there: `dN_c = H[z_c, :] dq` to first order.
//! That gives two things:
//!
//! * **Contact forces inside the Newton system.** A sliding contact's friction force is
//!   `N_c u_c` (`u_c` the friction force per unit normal force of the sliding branch, from
//!   [`super::semismooth`]).
//!   Newton's linearisation of the residual `g(q) + sum_c N_c(q) u_c(q)` is
//!   `(A + sum_c u_c H[z_c, :]) dq = -g`, with `A` the symmetric Hessian the line search
//!   uses. The non-symmetric rank-`n_s` term reduces to a system in the `n_s` normal-force
//!   changes, solved by GMRES with `A`'s factorisation (one solve per iteration), so the
//!   iteration converges quadratically instead of linearly. A fixed-point sweep
//!   `A dq^{m+1} = -g - sum_c u_c (H[z_c, :] dq^m)` (a Neumann series, used before) failed to
//!   contract on 8.7 % of the S-start's iterates (50 elements), which then fell back to the
//!   lagged forces and converged linearly (contraction about 0.3 per iteration); GMRES takes at
//!   most 4 iterations there. A sliding contact between nodes takes part in the same way, its
//!   normal force the augmented Lagrangian's multiplier (`dN_c = -rho_al J_z dq`,
//!   `semismooth/between.rs`) and its friction spread over its stencil.
//! * **Force residuals in physical units.** The predicted change of every reaction over the
//!   step gives the iterate's contact forces after the step: the semi-smooth Newton's new force
//!   variables, and its convergence test (changes below `[solver] normal_force_tolerance * W /
//!   n_c`).

use super::{ContactSet, ContactStatus};
use crate::band::Assembly;
use crate::newton::Newton;
use crate::rod::dof::{self, HALF_BANDWIDTH as W};

/// One row of the banded Hessian: entries `(k, k - W ..= k + W)` (zero outside `0..n`).
type Row = [f64; 2 * W + 1];

/// Returned by [`Reactions::couple`] when the coupled direction was not found (the symmetric
/// one is kept).
pub const UNCOUPLED: usize = usize::MAX;

/// Largest number of GMRES iterations for the coupled Newton direction.
const MAX_KRYLOV: usize = 16;

/// The Hessian rows at the held coordinates of the touching contacts, and the predicted
/// change of their reactions over a step.
#[derive(Clone, Debug, Default)]
pub struct Reactions {
    /// Rows at `x, y, z` of every contact (zero for free contacts; `x, y` only for sticking).
    rows: Vec<[Row; 3]>,
    /// Dissipation gradient per unit normal force in `(x, y)`, for sliding contacts with a
    /// positive normal force (otherwise zero: a clamped force does not change to first order).
    unit: Vec<[f64; 2]>,
    /// A sliding contact between nodes: its augmented-Lagrangian stiffness `rho_al` (its
    /// normal force changes by `-rho_al J_z dq` over a step, `J_z` its stencil's weights at the
    /// heights; its friction spreads over the stencil); zero for a contact at a node.
    between: Vec<f64>,
    /// Predicted change of each reaction `(x, y, z)` over the last step.
    pub change: Vec<[f64; 3]>,
    /// The symmetric direction the last [`Reactions::couple`] started from.
    symmetric: Vec<f64>,
    /// Krylov workspace of [`Reactions::couple`]: the coupled contacts, the basis in their
    /// normal forces, its images `A^-1 U v_j`, the Hessenberg matrix and Givens rotations.
    active: Vec<usize>,
    basis: Vec<Vec<f64>>,
    images: Vec<Vec<f64>>,
    hess: Vec<Vec<f64>>,
    rot: Vec<(f64, f64)>,
    resid: Vec<f64>,
    /// The next Krylov vector before normalisation, and the least-squares solution.
    work: Vec<f64>,
    y: Vec<f64>,
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
        self.between.clear();
        self.between.resize(nc, 0.0);
        self.change.resize(nc, [0.0; 3]);
    }

    /// Sliding contact `c`'s dissipation gradient `grad` in `(x, y)` with normal force `n`
    /// (kept per unit force; a clamped force, `n = 0`, does not couple).
    pub fn set_slide(&mut self, c: usize, grad: [f64; 2], n: f64) {
        if n > 0.0 {
            self.unit[c] = [grad[0] / n, grad[1] / n];
        }
    }

    /// Sliding contact `c` between nodes with the dissipation gradient per unit normal force
    /// `unit` in `(x, y)` and the augmented-Lagrangian stiffness `rho_al`: its normal force
    /// after the step, `lambda - rho_al (r + J_z dq)`, couples into the Newton system as a
    /// contact at a node's reaction does.
    pub fn set_slide_between(&mut self, c: usize, unit: [f64; 2], rho_al: f64) {
        self.unit[c] = unit;
        self.between[c] = rho_al;
    }

    /// The change of coupled contact `c`'s normal force along `v` (`V_c^T v`).
    fn normal_change(&self, ct: &ContactSet, c: usize, v: &[f64]) -> f64 {
        if self.between[c] > 0.0 {
            let jz: f64 = ct.contacts[c]
                .stencil
                .iter()
                .map(|(i, w)| w * v[dof::node(i) + 2])
                .sum();
            -self.between[c] * jz
        } else {
            row_dot(&self.rows[c][2], ct.node_dof(c) + 2, v)
        }
    }

    /// Add coupled contact `c`'s friction gradient for a normal-force change `dn` (`U_c dn`)
    /// to `z`, but at held coordinates.
    fn add_friction(&self, ct: &ContactSet, c: usize, held: &[bool], dn: f64, z: &mut [f64]) {
        let u = self.unit[c];
        for (i, w) in ct.contacts[c].stencil.iter() {
            let k = dof::node(i);
            for r in 0..2 {
                if !held[k + r] {
                    z[k + r] += w * u[r] * dn;
                }
            }
        }
    }

    /// Capture the rows of the assembled Hessian `asm` (before the held coordinates are
    /// fixed) at the held coordinates of the contacts of `ct` with statuses `mode` (a contact
    /// between nodes holds none and is given as free).
    pub fn capture(&mut self, ct: &ContactSet, mode: &[ContactStatus], asm: &Assembly) {
        for c in 0..ct.len() {
            if mode[c] == ContactStatus::Free {
                continue;
            }
            let k = ct.node_dof(c);
            for r in mode[c].held() {
                asm.row(k + r, &mut self.rows[c][r]);
            }
        }
    }

    /// The Hessian row captured at coordinate `r` (0, 1, 2: `x, y, z`) of contact `c` by the
    /// last [`Reactions::capture`] (columns `k - W ..= k + W` of that coordinate `k`).
    pub fn row(&self, c: usize, r: usize) -> &Row {
        &self.rows[c][r]
    }

    /// Predicted change of every touching contact's reactions (statuses `mode`) over the step `dq`, into
    /// `change`; returns the largest normal-force change (N).
    pub fn predict(&mut self, ct: &ContactSet, mode: &[ContactStatus], dq: &[f64]) -> f64 {
        let mut worst: f64 = 0.0;
        for c in 0..ct.len() {
            self.change[c] = [0.0; 3];
            if mode[c] == ContactStatus::Free {
                continue;
            }
            let k = ct.node_dof(c);
            for r in mode[c].held() {
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

    /// Put the symmetric direction the last [`Reactions::couple`] started from into `dq`.
    pub fn restore_symmetric(&self, dq: &mut [f64]) {
        dq.copy_from_slice(&self.symmetric);
    }

    /// Turn the symmetric Newton direction `nw.dq` (solved with the factorisation in `nw.lin`
    /// for the gradient `nw.asm.grad`) into the direction of the coupled system
    /// `(A + U V^T) dq = -g` (`U`: the sliding contacts' unit friction gradients at their
    /// `x, y`; `V^T dq`: their normal-force changes). With `dq0 = -A^-1 g` the system reduces to
    /// the normal-force changes `dn = V^T dq`: `(I + V^T A^-1 U) dn = V^T dq0`, solved by GMRES
    /// (one solve with `A`'s factorisation per iteration; exact after as many iterations as
    /// coupled contacts, and robust where the coupling is too strong for a fixed-point sweep),
    /// until its residual is below `tol` (N); then `dq = dq0 - A^-1 U dn`. Held coordinates
    /// (`held`) keep a zero step. Returns the iterations, or [`UNCOUPLED`] when they did not
    /// reach `tol` and the symmetric direction was kept.
    pub fn couple(&mut self, ct: &ContactSet, nw: &mut Newton, held: &[bool], tol: f64) -> usize {
        let n = nw.dq.len();
        self.symmetric.clear();
        self.symmetric.extend_from_slice(&nw.dq);
        self.active.clear();
        self.active
            .extend((0..ct.len()).filter(|&c| self.unit[c] != [0.0; 2]));
        let ns = self.active.len();
        if ns == 0 {
            return 0;
        }
        let max_it = MAX_KRYLOV.min(ns);
        // Storage for `count` vectors of `len` entries (each entry is written before it is
        // read; the images are cleared as they are used).
        let grow = |v: &mut Vec<Vec<f64>>, len: usize, count: usize| {
            while v.len() < count {
                v.push(Vec::new());
            }
            for x in v.iter_mut().take(count) {
                x.resize(len, 0.0);
            }
        };
        grow(&mut self.basis, ns, max_it + 1);
        grow(&mut self.images, n, max_it);
        grow(&mut self.hess, max_it + 1, max_it);
        // Right-hand side: the normal-force changes of the symmetric direction.
        for i in 0..ns {
            self.basis[0][i] = self.normal_change(ct, self.active[i], &nw.dq);
        }
        let beta = self.basis[0].iter().map(|x| x * x).sum::<f64>().sqrt();
        if beta <= tol {
            return 0;
        }
        self.basis[0].iter_mut().for_each(|b| *b /= beta);
        self.rot.clear();
        self.resid.clear();
        self.resid.resize(max_it + 1, 0.0);
        self.resid[0] = beta;
        let mut done = 0;
        let mut converged = false;
        for j in 0..max_it {
            // w = (I + V^T A^-1 U) v_j, keeping A^-1 U v_j.
            let mut z = std::mem::take(&mut self.images[j]);
            z.fill(0.0);
            for (i, &c) in self.active.iter().enumerate() {
                self.add_friction(ct, c, held, self.basis[j][i], &mut z);
            }
            nw.lin.solve(&mut z);
            let mut w = std::mem::take(&mut self.work);
            w.clear();
            w.extend(
                self.active
                    .iter()
                    .enumerate()
                    .map(|(i, &c)| self.basis[j][i] + self.normal_change(ct, c, &z)),
            );
            self.images[j] = z;
            // Modified Gram-Schmidt.
            for i in 0..=j {
                let hij: f64 = w.iter().zip(&self.basis[i]).map(|(a, b)| a * b).sum();
                self.hess[j][i] = hij;
                for (a, b) in w.iter_mut().zip(&self.basis[i]) {
                    *a -= hij * b;
                }
            }
            let norm = w.iter().map(|x| x * x).sum::<f64>().sqrt();
            self.hess[j][j + 1] = norm;
            if norm > 0.0 {
                for (b, a) in self.basis[j + 1].iter_mut().zip(w.iter()) {
                    *b = a / norm;
                }
            }
            self.work = w;
            // Givens rotations: the least-squares residual of min |beta e1 - H y|.
            for (i, &(cs, sn)) in self.rot.iter().enumerate() {
                let (a, b) = (self.hess[j][i], self.hess[j][i + 1]);
                self.hess[j][i] = cs * a + sn * b;
                self.hess[j][i + 1] = -sn * a + cs * b;
            }
            let (a, b) = (self.hess[j][j], self.hess[j][j + 1]);
            let d = a.hypot(b);
            let (cs, sn) = if d > 0.0 { (a / d, b / d) } else { (1.0, 0.0) };
            self.rot.push((cs, sn));
            self.hess[j][j] = d;
            self.hess[j][j + 1] = 0.0;
            self.resid[j + 1] = -sn * self.resid[j];
            self.resid[j] *= cs;
            done = j + 1;
            if self.resid[j + 1].abs() <= tol || norm == 0.0 {
                converged = true;
                break;
            }
        }
        if !converged {
            return UNCOUPLED;
        }
        // Back substitution for y, then dq = dq0 - sum_j y_j A^-1 U v_j.
        let y = &mut self.y;
        y.clear();
        y.resize(done, 0.0);
        for i in (0..done).rev() {
            let mut t = self.resid[i];
            for (jj, yj) in y.iter().enumerate().skip(i + 1) {
                t -= self.hess[jj][i] * yj;
            }
            y[i] = t / self.hess[i][i];
        }
        for (j, yj) in y.iter().enumerate() {
            for (d, z) in nw.dq.iter_mut().zip(&self.images[j]) {
                *d -= yj * z;
            }
        }
        done
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Model;
    use crate::newton::Newton;

    /// A seeded stream of uniform numbers in `[-1, 1)` (a linear congruential generator).
    fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
    }

    /// A random banded SPD system in `nw`'s assembly: 10 on the diagonal, off-diagonal entries
    /// in `[-0.1, 0.1)`, a gradient in `[-1, 1)`.
    fn random_system(nw: &mut Newton, rnd: &mut impl FnMut() -> f64) {
        let n = nw.asm.grad.len();
        for j in 0..n {
            for idx in nw.asm.col_ptr[j]..nw.asm.col_ptr[j + 1] {
                nw.asm.values[idx] = if nw.asm.row_idx[idx] == j {
                    10.0
                } else {
                    0.1 * rnd()
                };
            }
        }
        for g in nw.asm.grad.iter_mut() {
            *g = rnd();
        }
    }

    /// `A dq + g` of the assembled band.
    fn band_residual(nw: &Newton, dq: &[f64]) -> Vec<f64> {
        let n = dq.len();
        (0..n)
            .map(|i| {
                let lo = i.saturating_sub(W);
                let hi = (i + W + 1).min(n);
                (lo..hi).map(|j| nw.asm.h(i, j) * dq[j]).sum::<f64>() + nw.asm.grad[i]
            })
            .collect()
    }

    /// The coupled direction solves `(A + U V^T) dq = -g` to the requested tolerance, checked
    /// entry by entry against the matrix product (a banded SPD `A` with random entries, a
    /// quarter of the contacts sliding with random unit friction gradients, strong enough that
    /// the fixed-point sweep used before diverges).
    #[test]
    fn coupled_direction_solves_the_coupled_system() {
        // (The 50-element S-start: the random system's strength is set for its size.)
        let path = std::path::Path::new("problems/s_start_coarse.toml");
        let m = Model::new(&crate::problem::load(path).unwrap());
        let s = crate::state::State::initial(&m);
        let ct = ContactSet::ground(&m, &s.q);
        let n = m.ndof;
        let mut nw = Newton::new(n);
        let mut rnd = uniform(12345);
        random_system(&mut nw, &mut rnd);
        let nc = ct.len();
        let mode = vec![ContactStatus::Slide; nc];
        let mut re = Reactions::default();
        re.begin(nc);
        for c in 0..nc {
            // Every fourth contact couples (GMRES is exact after as many iterations as coupled
            // contacts), strongly.
            if c % 4 == 0 {
                re.set_slide(c, [150.0 * rnd(), 150.0 * rnd()], 1.0);
            }
        }
        // As in the semi-smooth iteration: rows captured, then the touching heights held.
        re.capture(&ct, &mode, &nw.asm);
        let mut held = vec![false; n];
        for c in 0..nc {
            held[ct.node_dof(c) + 2] = true;
            nw.asm.fix(ct.node_dof(c) + 2);
        }
        nw.lin.factor(&nw.asm).unwrap();
        nw.solve_direction();
        let tol = 1e-12;
        let it = re.couple(&ct, &mut nw, &held, tol);
        assert!(it > 0 && it != UNCOUPLED, "{it} iterations");
        // Residual of (A + U V^T) dq + g, and the force scale it is judged against.
        let dq = nw.dq.clone();
        let mut r = band_residual(&nw, &dq);
        for c in 0..nc {
            let k = ct.node_dof(c);
            let dn = row_dot(&re.rows[c][2], k + 2, &dq);
            r[k] += re.unit[c][0] * dn;
            r[k + 1] += re.unit[c][1] * dn;
        }
        let worst = r.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        assert!(worst < 1e-9, "residual {worst:e} after {it} iterations");
        // The fixed-point sweep `dn <- V^T dq0 - V^T A^-1 U dn` diverges here: the power
        // iteration on `V^T A^-1 U` grows.
        let mut x: Vec<f64> = (0..nc).map(|_| rnd()).collect();
        let mut growth = 0.0;
        for _ in 0..50 {
            let mut z = vec![0.0; n];
            for c in 0..nc {
                let k = ct.node_dof(c);
                z[k] += re.unit[c][0] * x[c];
                z[k + 1] += re.unit[c][1] * x[c];
            }
            nw.lin.solve(&mut z);
            let y: Vec<f64> = (0..nc)
                .map(|c| row_dot(&re.rows[c][2], ct.node_dof(c) + 2, &z))
                .collect();
            let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
            growth = norm(&y) / norm(&x);
            x = y.iter().map(|a| a / norm(&y)).collect();
        }
        assert!(growth > 1.0, "spectral radius estimate {growth}");
    }

    /// With contacts between nodes among the sliding ones (every third contact a stencil of
    /// three nodes, `set_slide_between`), the coupled direction solves the same system with
    /// their normal-force change `-rho_al J_z dq` and their friction spread over the stencil
    /// by its weights: `(A + sum_c U_c V_c^T) dq = -g`, checked entry by entry. A contact
    /// between nodes holds no coordinate (its height is in `A` as the augmented Lagrangian's
    /// `rho_al J^T J`, added here to the random band).
    #[test]
    fn coupled_direction_with_contacts_between_nodes() {
        use crate::contact::{Contact, Stencil};
        let path = std::path::Path::new("problems/s_start_coarse.toml");
        let m = Model::new(&crate::problem::load(path).unwrap());
        let law = *m.ground.as_ref().unwrap();
        let n = m.ndof;
        let (lo, hi) = (m.real.start, m.real.end);
        let between = |i: usize| i % 3 == 1 && i > lo && i + 1 < hi;
        let contacts: Vec<(Contact, f64)> = (lo..hi)
            .map(|i| {
                let st = if between(i) {
                    let t: f64 = 0.3;
                    let w = [0.5 * t * (t - 1.0), 1.0 - t * t, 0.5 * t * (t + 1.0)];
                    Stencil::new(&[i - 1, i, i + 1], &w).unwrap()
                } else {
                    Stencil::node(i)
                };
                (Contact::new(st, law), 1.0)
            })
            .collect();
        let ct = ContactSet::new(contacts);
        let mut nw = Newton::new(n);
        let mut rnd = uniform(777);
        random_system(&mut nw, &mut rnd);
        let nc = ct.len();
        let rho_al = 50.0;
        let at_node: Vec<bool> = (0..nc)
            .map(|c| ct.contacts[c].stencil.single().is_some())
            .collect();
        for c in (0..nc).filter(|&c| !at_node[c]) {
            let st = &ct.contacts[c].stencil;
            for (i, wi) in st.iter() {
                for (j, wj) in st.iter() {
                    if i <= j {
                        nw.asm
                            .add_h(dof::node(i) + 2, dof::node(j) + 2, rho_al * wi * wj);
                    }
                }
            }
        }
        let mode: Vec<ContactStatus> = at_node
            .iter()
            .map(|&a| {
                if a {
                    ContactStatus::Slide
                } else {
                    ContactStatus::Free
                }
            })
            .collect();
        let mut re = Reactions::default();
        re.begin(nc);
        for c in 0..nc {
            let unit = [15.0 * rnd(), 15.0 * rnd()];
            if !at_node[c] {
                re.set_slide_between(c, unit, rho_al);
            } else if c % 2 == 0 {
                re.set_slide(c, unit, 1.0);
            }
        }
        re.capture(&ct, &mode, &nw.asm);
        let mut held = vec![false; n];
        for c in (0..nc).filter(|&c| at_node[c]) {
            held[ct.node_dof(c) + 2] = true;
            nw.asm.fix(ct.node_dof(c) + 2);
        }
        nw.lin.factor(&nw.asm).unwrap();
        nw.solve_direction();
        let it = re.couple(&ct, &mut nw, &held, 1e-12);
        assert!(it > 0 && it != UNCOUPLED, "{it} iterations");
        let dq = nw.dq.clone();
        let mut r = band_residual(&nw, &dq);
        for c in 0..nc {
            let st = &ct.contacts[c].stencil;
            let dn = if at_node[c] {
                row_dot(&re.rows[c][2], ct.node_dof(c) + 2, &dq)
            } else {
                -rho_al
                    * st.iter()
                        .map(|(i, w)| w * dq[dof::node(i) + 2])
                        .sum::<f64>()
            };
            for (i, w) in st.iter() {
                for a in 0..2 {
                    if !held[dof::node(i) + a] {
                        r[dof::node(i) + a] += w * re.unit[c][a] * dn;
                    }
                }
            }
        }
        // Held rows are fixed in the factorisation: judge the free ones.
        let worst = (0..n)
            .filter(|&k| !held[k])
            .fold(0.0f64, |a, k| a.max(r[k].abs()));
        assert!(worst < 1e-9, "residual {worst:e} after {it} iterations");
        assert!(
            it > 3,
            "a coupling this strong takes several GMRES iterations ({it})"
        );
    }
}
