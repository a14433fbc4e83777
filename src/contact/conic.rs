//! The conic contact model: one second-order-cone program (Clarabel) per Newton iterate, its
//! duals the lagged normal forces of the next iterate (see the module doc of
//! [`crate::contact`]). A solver of its own (`[solver] contact = "conic"`), and the fallback
//! and certificate of the semi-smooth Newton.
//!
//! [`Conic::program`] formulates and solves the program of one iterate from the contact set
//! (each contact's gap and slip rows through its stencil, so a contact between nodes is one
//! more row with more entries); [`Conic::iterate`] runs the Newton iterations around it.

use super::{ContactFailure, ContactSet, ContactStats};
use crate::band::Assembly;
use crate::model::Model;
use crate::newton::{Newton, NewtonFailure, Objective, Path, Potential};
use crate::rod::{dof, vec3::f};
use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use std::time::Instant;

/// A conic step whose predicted decrease is below this fraction of the objective is an
/// accuracy-level correction of the interior-point solve: it is taken in full.
const NEGLIGIBLE_DECREASE: f64 = 1e-12;

/// The conic program as a contact solver: Newton iterations, each solving one conic program
/// of the quadratic model with the contact set's lagged normal forces.
pub struct Conic {
    /// The gradient the conic model predicts at the next iterate.
    pred_grad: Vec<f64>,
    /// Clarabel's KKT solver, tolerances and iteration cap (`[solver]`).
    direct_method: String,
    tolerance: f64,
    max_iterations: u32,
}

impl Conic {
    /// The conic solver of `m` (Clarabel settings from `[solver]`).
    pub fn new(m: &Model) -> Self {
        Conic {
            pred_grad: vec![0.0; m.ndof],
            direct_method: m.solver.clarabel_method.clone(),
            tolerance: m.solver.conic_tolerance,
            max_iterations: m.solver.conic_max_iterations,
        }
    }

    /// Certify a converged step `q` with [`Self::certify`] and record the outcome in the
    /// statistics (`certificates`, the largest correction and normal-force change in
    /// tolerances, and a failure where either exceeds one; a warning is logged then).
    pub(crate) fn certify_recorded(
        &mut self,
        set: &mut ContactSet,
        stats: &mut ContactStats,
        nw: &mut Newton,
        obj: &Potential,
        q: &[f64],
    ) -> Result<(), ContactFailure> {
        let m = obj.model;
        let (dq, dn) = self.certify(set, stats, nw, obj, q)?;
        let dq = dq / m.tolerance;
        let dn = dn / (m.solver.normal_force_tolerance * set.weight_scale(m));
        let st = stats;
        st.certificates += 1;
        st.certificate_max_correction = st.certificate_max_correction.max(dq);
        st.certificate_max_normal_change = st.certificate_max_normal_change.max(dn);
        if dq > 1.0 || dn > 1.0 {
            st.certificate_failures += 1;
            log::warn!(
                "conic certificate: correction {dq:.3e} tolerances, normal-force change {dn:.3e} tolerances"
            );
        }
        Ok(())
    }

    /// Certify a converged step `q` (from another solve, with its normal forces in `ct.normal`):
    /// one conic program of the quadratic model at `q`, whose step is zero at the exact
    /// solution. Returns the program's correction `max(|dx| / a, |dtheta|)` and its largest
    /// normal-force change (N); `q` and the normal forces stay as they are.
    pub(crate) fn certify(
        &mut self,
        set: &mut ContactSet,
        stats: &mut ContactStats,
        nw: &mut Newton,
        obj: &Potential,
        q: &[f64],
    ) -> Result<(f64, f64), ContactFailure> {
        let m = obj.model;
        let t0 = Instant::now();
        obj.assemble(q, &mut nw.asm, true);
        for k in 0..m.ndof {
            if m.fixed[k] {
                nw.asm.fix(k);
            }
        }
        nw.stats.assembly_s += t0.elapsed().as_secs_f64();
        let t1 = Instant::now();
        let r = self
            .program(set, m, &nw.asm, q, &mut nw.dq)
            .map_err(|e| e.at(1))?;
        stats.conic_solves += 1;
        stats.conic_iterations += r.iterations as usize;
        stats.conic_s += t1.elapsed().as_secs_f64();
        let (dx, dth) = nw.correction_norms();
        Ok(((dx / m.diameter).max(dth), r.max_normal_change))
    }

    /// Newton iterations on `obj` plus friction from `q`, each solving the conic program of
    /// the quadratic model, at most `cap`. Convergence: a full step below the tolerance with
    /// settled normal forces, or a step whose true gradient matches the conic model's
    /// prediction (then the conic optimality conditions hold for the true problem).
    pub(crate) fn iterate(
        &mut self,
        set: &mut ContactSet,
        stats: &mut ContactStats,
        nw: &mut Newton,
        obj: &Potential,
        q: &mut Vec<f64>,
        cap: usize,
    ) -> Result<usize, ContactFailure> {
        let m = obj.model;
        let n = m.ndof;
        let a = m.diameter;
        let path = Path::Newton;
        let mut have_pred = false;
        for it in 1..=cap {
            let t0 = Instant::now();
            let f0 = obj.assemble(q, &mut nw.asm, true);
            for k in 0..n {
                if m.fixed[k] {
                    nw.asm.fix(k);
                }
            }
            if !f0.is_finite() || nw.asm.grad.iter().any(|g| !g.is_finite()) {
                return Err(NewtonFailure::NonFiniteObjective {
                    path,
                    iteration: it,
                }
                .into());
            }
            if have_pred {
                // The conic model was exact up to the tolerance: the true gradient at the new
                // iterate equals the predicted one, so the conic optimality conditions hold
                // for the true step problem (the constraints are linear).
                let mut worst: f64 = 0.0;
                for k in 0..n {
                    if m.fixed[k] {
                        continue;
                    }
                    let corr = (nw.asm.grad[k] - self.pred_grad[k]).abs() / nw.asm.h(k, k);
                    let scale = if crate::rod::dof::is_edge(k) { 1.0 } else { a };
                    worst = worst.max(corr / scale);
                }
                if worst <= m.tolerance {
                    nw.stats.assembly_s += t0.elapsed().as_secs_f64();
                    return Ok(it - 1);
                }
            }
            let t1 = Instant::now();
            nw.stats.assembly_s += (t1 - t0).as_secs_f64();
            let r = self
                .program(set, m, &nw.asm, q, &mut nw.dq)
                .map_err(|e| e.at(it))?;
            stats.conic_solves += 1;
            stats.conic_iterations += r.iterations as usize;
            let t2 = Instant::now();
            stats.conic_s += (t2 - t1).as_secs_f64();
            let t3 = Instant::now();
            if nw.dq.iter().any(|d| !d.is_finite()) {
                return Err(NewtonFailure::NonFiniteStep {
                    path,
                    iteration: it,
                }
                .into());
            }
            // Merit: the step objective plus friction dissipation with the lagged normal
            // forces; the model decrease is the conic optimum's.
            let ct = &*set;
            let merit = |x: &[f64]| obj.value(x) + ct.dissipation(x);
            let f0 = merit(q);
            let slope = r.predicted_decrease.min(0.0);
            let (dx, dth) = nw.correction_norms();
            let normals_settled =
                r.max_normal_change <= m.solver.normal_force_tolerance * ct.weight_scale(m);
            let negligible = -slope <= NEGLIGIBLE_DECREASE * f0.abs();
            let small = dx <= m.tolerance * a && dth <= m.tolerance;
            nw.step_cap = obj.max_step(q, &nw.dq);
            let alpha = nw.backtrack(m, q, f0, slope, small || negligible, &merit);
            nw.stats.line_search_s += t3.elapsed().as_secs_f64();
            let Some(alpha) = alpha else {
                return Err(NewtonFailure::LineSearch {
                    path,
                    iteration: it,
                    slope,
                }
                .into());
            };
            std::mem::swap(q, &mut nw.trial);
            std::mem::swap(&mut set.normal, &mut set.pending);
            log::debug!("  it {it}: alpha {alpha:.3e} dx {dx:.3e} dth {dth:.3e} normals_settled {normals_settled} slope {slope:.3e}");
            if alpha == 1.0 && small && normals_settled {
                return Ok(it);
            }
            have_pred = false;
            if alpha == 1.0 && normals_settled {
                nw.asm.mul(&nw.dq, &mut self.pred_grad);
                for k in 0..n {
                    self.pred_grad[k] += nw.asm.grad[k];
                }
                have_pred = true;
            }
        }
        Err(NewtonFailure::NotConverged {
            path,
            iterations: cap,
        }
        .into())
    }
}

/// Why a conic program was not solved.
#[derive(Clone, Debug)]
pub enum ConicError {
    /// Clarabel refused the settings or the problem.
    Setup(String),
    /// Clarabel ended with another status than `Solved`.
    Status {
        /// The status.
        status: String,
        /// Interior-point iterations.
        iterations: u32,
    },
}

impl ConicError {
    /// As a contact failure at Newton iteration `it`.
    pub fn at(self, it: usize) -> ContactFailure {
        match self {
            ConicError::Setup(message) => ContactFailure::ConicSetup {
                message,
                iteration: it,
            },
            ConicError::Status { status, iterations } => ContactFailure::Conic {
                status,
                conic_iterations: iterations,
                iteration: it,
            },
        }
    }
}

/// Outcome of one conic solve.
pub struct ConicStep {
    /// Largest change of a normal force between the lagged and new value (N).
    pub max_normal_change: f64,
    /// Optimal value of the conic model minus its value at `dq = 0` (J, <= 0).
    pub predicted_decrease: f64,
    /// Clarabel's interior-point iterations.
    pub iterations: u32,
}

impl Conic {
    /// Solve the conic subproblem of the contact set `set` at the iterate `q`: writes the
    /// step into `dq` and the new normal forces into `set.pending`.
    pub fn program(
        &self,
        set: &mut ContactSet,
        m: &Model,
        asm: &Assembly,
        q: &[f64],
        dq: &mut [f64],
    ) -> Result<ConicStep, ConicError> {
        let n = asm.n();
        let nc = set.len();
        let h = set.h;
        // The Hessian's low-rank part `U U^T` (self-contact) as one variable per column,
        // `w_l = u_l . dq`, with the cost `w_l^2 / 2`: the band stays the band.
        let nl = asm.low_rank.len();
        let nv = n + 4 * nc + nl;
        let aux = |l: usize| n + 4 * nc + l;
        let var = |c: usize, k: usize| n + 4 * c + k; // u, w, y, sigma
                                                      // Scaling (the interior-point tolerances are absolute): displacements in units of
                                                      // `ls`, the larger of this step's largest node displacement and `g h^2`; slip variables
                                                      // as displacements (`h u / ls`, ...); the objective multiplied by `k` so that the
                                                      // Hessian's mean diagonal is one.
        let mut disp: f64 = 0.0;
        for ct in &set.contacts {
            disp = disp.max(f::norm(f::sub(ct.stencil.position(q), ct.origin)));
        }
        let ls = disp.max(h * h * f::norm(m.gravity)).max(1e-9 * m.diameter);
        let mean_diag = (0..n).map(|k| asm.h(k, k)).sum::<f64>() / n as f64;
        let ks = 1.0 / (ls * ls * mean_diag);
        // Jacobi scaling of the coordinates, `dq_k = d_k x_k`, so that every scaled Hessian
        // diagonal is one (twist angles and positions differ by orders of magnitude).
        let d: Vec<f64> = (0..n)
            .map(|k| ls * (mean_diag / asm.h(k, k).max(1e-300 * mean_diag)).sqrt())
            .collect();
        // P: the Hessian's upper triangle, then empty columns.
        let mut colptr = asm.col_ptr.clone();
        let nnz = *colptr.last().unwrap();
        colptr.extend(std::iter::repeat_n(nnz, 4 * nc));
        let mut pv = asm.values.clone();
        for j in 0..n {
            for idx in asm.col_ptr[j]..asm.col_ptr[j + 1] {
                pv[idx] *= ks * d[asm.row_idx[idx]] * d[j];
            }
        }
        let mut rows = asm.row_idx.clone();
        for l in 0..nl {
            rows.push(aux(l));
            pv.push(ks);
            colptr.push(nnz + l + 1);
        }
        let p = CscMatrix::new(nv, nv, colptr, rows, pv);
        let mut lin = vec![0.0; nv];
        for k in 0..n {
            lin[k] = asm.grad[k] * ks * d[k];
        }
        for c in 0..nc {
            // A tiny cost on sigma, u and w keeps the optimal set bounded where a contact
            // carries no load (otherwise sigma and u = w could grow freely, which stalls the
            // interior-point method); it changes forces by ~1e-9 of the scaled units.
            lin[var(c, 3)] = ks * ls * set.normal[c] + 1e-9;
            lin[var(c, 0)] = 1e-9;
            lin[var(c, 1)] = 1e-9;
        }
        // Constraints A x + s = b.
        let (mut ri, mut ci, mut vv) = (Vec::new(), Vec::new(), Vec::new());
        let mut b = Vec::new();
        let mut row = 0;
        let push = |r: usize,
                    c: usize,
                    v: f64,
                    ri: &mut Vec<usize>,
                    ci: &mut Vec<usize>,
                    vv: &mut Vec<f64>| {
            ri.push(r);
            ci.push(c);
            vv.push(v);
        };
        // Zero cone: slip definitions (displacement units, scaled by `ls`).
        for (c, ct) in set.contacts.iter().enumerate() {
            let d0 = f::sub(ct.stencil.position(q), ct.origin);
            let fr = &ct.frame;
            for (dir, sign_var) in [(fr.forward, 0usize), (fr.side, 2usize)] {
                // The slip along `dir` is `sum_i w_i dir . x_i`: one entry per node and
                // direction component.
                for (i, w) in ct.stencil.iter() {
                    let k = dof::node(i);
                    for a in 0..2 {
                        let coef = w * dir[a];
                        if coef != 0.0 {
                            push(row, k + a, coef * d[k + a] / ls, &mut ri, &mut ci, &mut vv);
                        }
                    }
                }
                if sign_var == 0 {
                    push(row, var(c, 0), -1.0, &mut ri, &mut ci, &mut vv);
                    push(row, var(c, 1), 1.0, &mut ri, &mut ci, &mut vv);
                } else {
                    push(row, var(c, 2), -1.0, &mut ri, &mut ci, &mut vv);
                }
                b.push(-f::dot(d0, dir) / ls);
                row += 1;
            }
        }
        // Zero cone: the low-rank variables' definitions, `u_l . D x - w_l = 0`.
        for (l, u) in asm.low_rank.iter().enumerate() {
            for (&k, &v) in u.idx.iter().zip(&u.val) {
                if v != 0.0 {
                    push(row, k, v * d[k], &mut ri, &mut ci, &mut vv);
                }
            }
            push(row, aux(l), -1.0, &mut ri, &mut ci, &mut vv);
            b.push(0.0);
            row += 1;
        }
        let n_zero = row;
        // Nonnegative: gaps (the stencil's height, `sum_i w_i z_i - a/2`), then u, w >= 0.
        for ct in &set.contacts {
            for (i, w) in ct.stencil.iter() {
                let k = dof::node(i) + 2;
                push(row, k, -w * d[k] / ls, &mut ri, &mut ci, &mut vv);
            }
            b.push(ct.gap(q, m.diameter) / ls);
            row += 1;
        }
        for c in 0..nc {
            for kk in 0..2 {
                push(row, var(c, kk), -1.0, &mut ri, &mut ci, &mut vv);
                b.push(0.0);
                row += 1;
            }
        }
        let n_nonneg = row - n_zero;
        // Second-order cones (sigma, mu_f u, mu_b w, mu_s y).
        for (c, ct) in set.contacts.iter().enumerate() {
            let g = &ct.law;
            for (kk, coef) in [(3usize, 1.0), (0, g.mu_f), (1, g.mu_b), (2, g.mu_s)] {
                push(row, var(c, kk), -coef, &mut ri, &mut ci, &mut vv);
                b.push(0.0);
                row += 1;
            }
        }
        let a = CscMatrix::new_from_triplets(row, nv, ri, ci, vv);
        let mut cones = vec![
            SupportedConeT::ZeroConeT(n_zero),
            SupportedConeT::NonnegativeConeT(n_nonneg),
        ];
        cones.extend(std::iter::repeat_n(SupportedConeT::SecondOrderConeT(4), nc));
        let settings = DefaultSettingsBuilder::default()
            .verbose(false)
            .tol_gap_abs(self.tolerance)
            .tol_gap_rel(self.tolerance)
            .tol_feas(self.tolerance)
            .max_iter(self.max_iterations)
            .direct_solve_method(self.direct_method.clone())
            .build()
            .map_err(|e| ConicError::Setup(format!("Clarabel settings: {e:?}")))?;
        let mut solver = DefaultSolver::new(&p, &lin, &a, &b, &cones, settings)
            .map_err(|e| ConicError::Setup(format!("Clarabel setup: {e:?}")))?;
        solver.solve();
        let sol = &solver.solution;
        if sol.status != SolverStatus::Solved {
            return Err(ConicError::Status {
                status: format!("{:?}", sol.status),
                iterations: sol.iterations,
            });
        }
        for k in 0..n {
            dq[k] = sol.x[k] * d[k];
        }
        let mut change: f64 = 0.0;
        for c in 0..nc {
            let lam = (sol.z[n_zero + c] / (ks * ls)).max(0.0);
            change = change.max((lam - set.normal[c]).abs());
            set.pending[c] = lam;
        }
        let predicted_decrease = sol.obj_val / ks - set.dissipation(q);
        Ok(ConicStep {
            max_normal_change: change,
            predicted_decrease,
            iterations: sol.iterations,
        })
    }
}
