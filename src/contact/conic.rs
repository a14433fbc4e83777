//! The conic contact model: one second-order-cone program (Clarabel) per Newton iterate, its
//! duals the lagged normal forces of the next iterate (see the module doc of
//! [`crate::contact`]). Also the certified fallback of the active-set model.

use super::{ContactModel, Contacts};
use crate::model::Model;
use crate::newton::{Failure, Newton, Objective, Path, Potential};
use std::time::Instant;

/// A conic step whose predicted decrease is below this fraction of the objective is an
/// accuracy-level correction of the interior-point solve: it is taken in full.
const NEGLIGIBLE_DECREASE: f64 = 1e-12;

/// One conic program per Newton iterate.
pub struct Conic {
    /// Contact data and normal forces.
    pub ct: Contacts,
    normal_saved: Vec<f64>,
    pred_grad: Vec<f64>,
    h: f64,
}

impl Conic {
    /// The conic model of `m` (initial normal forces: each touching node's weight).
    pub fn new(m: &Model) -> Self {
        Conic {
            ct: Contacts::new(m, &m.q0),
            normal_saved: Vec::new(),
            pred_grad: vec![0.0; m.ndof],
            h: 0.0,
        }
    }

    /// Restore the normal forces saved at the start of the step.
    pub(crate) fn restore_normals(&mut self) {
        self.ct.normal.clone_from(&self.normal_saved);
    }

    /// Newton iterations on `obj` plus friction from `q`, each solving the conic program of
    /// the quadratic model, at most `cap`. Convergence: a full step below the tolerance with
    /// settled normal forces, or a step whose true gradient matches the conic model's
    /// prediction (then the conic optimality conditions hold for the true problem).
    pub(crate) fn iterate(
        &mut self,
        nw: &mut Newton,
        obj: &Potential,
        q: &mut Vec<f64>,
        cap: usize,
    ) -> Result<usize, Failure> {
        let m = obj.model;
        let n = m.ndof;
        let a = m.diameter;
        let ground = m.ground.as_ref().expect("a contact model needs a ground");
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
                return Err(Failure::NonFiniteObjective {
                    path,
                    iteration: it,
                });
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
                .ct
                .conic_program(m, ground, &nw.asm, q, self.h, &mut nw.dq)
                .map_err(|e| e.at(it))?;
            nw.stats.conic_solves += 1;
            nw.stats.conic_iterations += self.ct.last_iterations as usize;
            let t2 = Instant::now();
            nw.stats.conic_s += (t2 - t1).as_secs_f64();
            let t3 = Instant::now();
            if nw.dq.iter().any(|d| !d.is_finite()) {
                return Err(Failure::NonFiniteStep {
                    path,
                    iteration: it,
                });
            }
            // Merit: the step objective plus friction dissipation with the lagged normal
            // forces; the model decrease is the conic optimum's.
            let ct = &self.ct;
            let merit = |x: &[f64]| obj.value(x) + ct.dissipation(ground, x);
            let f0 = merit(q);
            let slope = r.predicted_decrease.min(0.0);
            let (dx, dth) = nw.correction_norms();
            let normals_settled =
                r.max_normal_change <= m.solver.normal_force_tolerance * ct.weight_scale(m);
            let negligible = -slope <= NEGLIGIBLE_DECREASE * f0.abs();
            let small = dx <= m.tolerance * a && dth <= m.tolerance;
            let alpha = nw.backtrack(m, q, f0, slope, small || negligible, &merit);
            nw.stats.line_search_s += t3.elapsed().as_secs_f64();
            let Some(alpha) = alpha else {
                return Err(Failure::LineSearch {
                    path,
                    iteration: it,
                    slope,
                });
            };
            std::mem::swap(q, &mut nw.trial);
            std::mem::swap(&mut self.ct.normal, &mut self.ct.pending);
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
        Err(Failure::NotConverged {
            path,
            iterations: cap,
        })
    }
}

impl ContactModel for Conic {
    fn begin_step(
        &mut self,
        m: &Model,
        q_start: &[f64],
        slip_origin: &[f64],
        _v_start: &[f64],
        h: f64,
        q: &mut [f64],
    ) {
        self.h = h;
        self.ct.begin_step(m, q_start, slip_origin);
        self.normal_saved.clone_from(&self.ct.normal);
        // Start from a feasible iterate: lift predicted penetrations onto the ground.
        self.ct.lift(m, q);
    }

    fn solve(
        &mut self,
        nw: &mut Newton,
        obj: &Potential,
        q: &mut Vec<f64>,
    ) -> Result<usize, Failure> {
        self.iterate(nw, obj, q, obj.model.max_iterations)
    }

    fn accept(&mut self, m: &Model, q: &[f64]) {
        self.ct.classify(m, q);
    }

    fn reject(&mut self) {
        self.restore_normals();
    }

    fn normal_forces(&self, m: &Model, out: &mut [f64]) {
        self.ct.normal_forces(m, out);
    }
}
