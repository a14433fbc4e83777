//! Newton's method on a smooth objective: the solver layer under every implicit time step.
//!
//! An [`Objective`] gives its value and assembles its gradient and Hessian (every stencil
//! projected to positive semi-definite on request) into the fixed banded pattern of an
//! [`Assembly`]; [`Newton`] owns that assembly, the band Cholesky factorisation
//! ([`linsolve`]), the correction and trial vectors and the [`NewtonStats`]. One iteration:
//! assemble (the exact Hessian; once one is found indefinite, every stencil projected for the
//! rest of the solve), hold the fixed coordinates, factorise (shifting the diagonal if the
//! matrix is only semi-definite), solve `H dq = -g`, backtrack on the objective (Armijo),
//! accept. The
//! iteration has converged when the full correction is below `tolerance * a` on every position
//! and below `tolerance` rad on every twist angle.
//!
//! The time step's objective is the incremental potential [`Potential`]:
//! `Phi(q) = w/2 (q - qhat)^T M (q - qhat) + E(q, t_{n+1})`, with the predictor `qhat` and the
//! inertia weight `w` supplied by the time integrator (`w = 1/h^2` for implicit Euler), or
//! `E(q)` alone for static equilibrium. Contact models ([`crate::contact`]) run their own
//! iterations from the same building blocks ([`Newton::factor_shifted`],
//! [`Newton::solve_direction`], [`Newton::correction_norms`], [`Newton::backtrack`]).
//!
//! Every tolerance and cap is a `[solver]` setting ([`crate::problem::SolverSpec`]).
//! Failures are typed ([`NewtonFailure`]); diagnostics go to the `log` crate (`debug` level).

pub use crate::band::cholesky as linsolve;

use crate::band::Assembly;
use crate::energy::self_contact::SelfContact;
use crate::energy::{self, Ctx, Term};
use crate::model::Model;
use crate::rod::dof;
use crate::rod::frames::StencilFrame;
use linsolve::LinSolver;
use std::time::Instant;

/// Newton's own cumulative statistics (the time integrator counts steps and iterations, the
/// contact model its own outcomes: [`crate::contact::ContactStats`]).
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct NewtonStats {
    /// Line-search backtracks.
    pub backtracks: usize,
    /// Numeric factorisations of the Hessian (each try, shifted ones included).
    pub factorizations: usize,
    /// Times a factorisation needed a diagonal shift.
    pub shifted_factorizations: usize,
    /// Seconds in energy, gradient and Hessian assembly.
    pub assembly_s: f64,
    /// Seconds in numeric factorisation.
    pub factor_s: f64,
    /// Seconds in triangular solves.
    pub solve_s: f64,
    /// Seconds in line-search energy evaluations.
    pub line_search_s: f64,
    /// Newton iterations (plain and contact) assembled with every stencil's Hessian
    /// projected to positive semi-definite, after the exact Hessian was found indefinite.
    pub projected_iterations: usize,
    /// Semi-smooth iterations that kept the bending and twist Hessian of an earlier iterate
    /// of the step and assembled only their gradient (`[solver] hessian_reuse`).
    pub hessian_reuses: usize,
}

/// Which iteration failed (for messages).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Path {
    /// Plain or conic Newton iterations.
    Newton,
    /// Semi-smooth Newton contact iterations.
    SemiSmooth,
}

impl Path {
    fn iteration(self) -> &'static str {
        match self {
            Path::Newton => "Newton",
            Path::SemiSmooth => "semi-smooth",
        }
    }
    fn solver(self) -> &'static str {
        match self {
            Path::Newton => "Newton",
            Path::SemiSmooth => "semi-smooth Newton",
        }
    }
}

/// Why a Newton solve failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum NewtonFailure {
    /// The objective or its gradient was not finite.
    #[error("non-finite objective or gradient at {} iteration {iteration}", path.iteration())]
    NonFiniteObjective {
        /// Iteration kind.
        path: Path,
        /// 1-based iteration.
        iteration: usize,
    },
    /// The Newton correction was not finite.
    #[error("non-finite {} at {} iteration {iteration}", if *path == Path::Newton { "step" } else { "Newton direction" }, path.iteration())]
    NonFiniteStep {
        /// Iteration kind.
        path: Path,
        /// 1-based iteration.
        iteration: usize,
    },
    /// No step length satisfied the Armijo condition.
    #[error("line search failed at {} iteration {iteration} (slope {slope:.3e})", path.iteration())]
    LineSearch {
        /// Iteration kind.
        path: Path,
        /// 1-based iteration.
        iteration: usize,
        /// Directional derivative of the merit function (J).
        slope: f64,
    },
    /// The iteration cap was reached.
    #[error("{} did not converge in {iterations} iterations", path.solver())]
    NotConverged {
        /// Iteration kind.
        path: Path,
        /// The cap.
        iterations: usize,
    },
    /// The Hessian could not be factorised, even shifted.
    #[error("Hessian not positive definite even with a diagonal shift (iteration {iteration})")]
    NotPositiveDefinite {
        /// 1-based iteration.
        iteration: usize,
    },
}

/// A smooth objective for Newton's method.
pub trait Objective {
    /// Value at `q`.
    fn value(&self, q: &[f64]) -> f64;
    /// Clear `asm` and assemble value, gradient and Hessian at `q` (stencils projected to
    /// positive semi-definite when `project`); returns the value.
    fn assemble(&self, q: &[f64], asm: &mut Assembly, project: bool) -> f64;
    /// Called after every accepted iterate (static equilibrium re-bases its frames here).
    fn accepted(&mut self, _q: &[f64]) {}
    /// The largest step length in `(0, 1]` along `dq` from `q` that keeps the objective's
    /// domain (the self-contact's pairs apart): where Newton's line search starts.
    fn max_step(&self, _q: &[f64], _dq: &[f64]) -> f64 {
        1.0
    }
}

/// The inertial part of an incremental potential: `w/2 |q - qhat|_M^2`, with the weight
/// `w` on every coordinate except those listed in `euler`, which carry `w_e`.
#[derive(Clone, Copy)]
pub struct Inertia<'a> {
    /// Weight `w` (1/s^2; `1/h^2` for implicit Euler).
    pub weight: f64,
    /// Predictor `qhat`.
    pub qhat: &'a [f64],
    /// Coordinates that take an implicit Euler step inside a multistep one (BDF2's contact
    /// normals, [`crate::integrator::bdf2`]).
    pub euler: &'a [usize],
    /// Their weight `w_e = 1/h^2`.
    pub euler_weight: f64,
}

/// The rod's energy at the step's rest strains, plus the inertial term in a dynamic step.
#[derive(Clone, Copy)]
pub struct Potential<'a> {
    /// The model (masses).
    pub model: &'a Model,
    /// Energy terms.
    pub terms: &'a [Box<dyn Term>],
    /// Frozen stencil frames of the step.
    pub frames: &'a [StencilFrame],
    /// Integrated natural curvature per node.
    pub kappa0: &'a [[f64; 2]],
    /// Integrated natural twist per node.
    pub m0: &'a [f64],
    /// Gravity (m/s^2).
    pub gravity: [f64; 3],
    /// Edge rest lengths the stretching pulls toward ([`Ctx::rest_len`]).
    pub rest_len: &'a [f64],
    /// Factor on the elastic stiffnesses ([`Ctx::elastic_scale`]).
    pub elastic_scale: f64,
    /// Inertia (dynamic steps).
    pub inertia: Option<Inertia<'a>>,
    /// Self-contact barrier, if on.
    pub self_contact: Option<&'a SelfContact>,
}

impl Potential<'_> {
    fn ctx(&self) -> Ctx<'_> {
        Ctx {
            model: self.model,
            frames: self.frames,
            kappa0: self.kappa0,
            m0: self.m0,
            gravity: self.gravity,
            rest_len: self.rest_len,
            elastic_scale: self.elastic_scale,
        }
    }
}

impl Objective for Potential<'_> {
    fn value(&self, q: &[f64]) -> f64 {
        let mut f = energy::total(self.terms, &self.ctx(), q, None, false);
        if let Some(sc) = self.self_contact {
            f += sc.value(q);
        }
        if let Some(inertia) = self.inertia {
            let w = 0.5 * inertia.weight;
            for k in 0..q.len() {
                f += w * self.model.mass[k] * (q[k] - inertia.qhat[k]).powi(2);
            }
            let dw = 0.5 * (inertia.euler_weight - inertia.weight);
            for &k in inertia.euler {
                f += dw * self.model.mass[k] * (q[k] - inertia.qhat[k]).powi(2);
            }
        }
        f
    }

    fn assemble(&self, q: &[f64], asm: &mut Assembly, project: bool) -> f64 {
        asm.clear();
        let mut f = energy::total(self.terms, &self.ctx(), q, Some(asm), project);
        if let Some(sc) = self.self_contact {
            f += sc.assemble(q, asm);
        }
        self.add_inertia(q, asm, f)
    }

    fn max_step(&self, q: &[f64], dq: &[f64]) -> f64 {
        self.self_contact.map_or(1.0, |sc| sc.max_step(q, dq))
    }
}

/// The Hessian of the terms with [`crate::energy::Term::reusable_hessian`] (bending and
/// twist) at one iterate of a step, for [`Potential::assemble_reusing`]. A Newton iterate
/// whose coordinates all lie within `reuse` of that iterate (positions within `reuse * a`,
/// angles within `reuse` rad) takes their value and gradient at its own coordinates and this
/// Hessian: the gradient stays exact, so the iteration converges to the same solution, and
/// the Hessian's error is of the order of the rotation of a stencil, `reuse * a / l`, so
/// the convergence stays fast. Valid for one step (the frames and the natural curvature are
/// the step's).
pub struct HessianCache {
    hessian: Assembly,
    at: Vec<f64>,
    project: bool,
    valid: bool,
}

impl Default for HessianCache {
    fn default() -> Self {
        HessianCache::new(0)
    }
}

impl HessianCache {
    /// An empty cache for `n` coordinates.
    pub fn new(n: usize) -> Self {
        HessianCache {
            hessian: Assembly::new(n),
            at: vec![0.0; n],
            project: false,
            valid: false,
        }
    }
    /// Forget the Hessian (a new step).
    pub fn invalidate(&mut self) {
        self.valid = false;
    }
    fn usable(&self, m: &Model, q: &[f64], project: bool, reuse: f64) -> bool {
        if !self.valid || self.project != project || reuse <= 0.0 {
            return false;
        }
        let l_min = m.rest_len.iter().copied().fold(f64::INFINITY, f64::min);
        let (dx, dth) = (reuse * l_min, reuse);
        q.iter()
            .zip(&self.at)
            .enumerate()
            .all(|(k, (a, b))| (a - b).abs() <= if dof::is_edge(k) { dth } else { dx })
    }
}

impl Potential<'_> {
    /// [`Objective::assemble`], with the Hessian of the terms that allow it kept in `cache`
    /// from an earlier iterate of the step within `reuse` (see [`HessianCache`]); at other
    /// iterates it is assembled and kept. Returns the value and whether the Hessian was kept.
    pub fn assemble_reusing(
        &self,
        q: &[f64],
        asm: &mut Assembly,
        project: bool,
        cache: &mut HessianCache,
        reuse: f64,
    ) -> (f64, bool) {
        if reuse <= 0.0 {
            return (self.assemble(q, asm, project), false);
        }
        asm.clear();
        let ctx = self.ctx();
        let keep = cache.usable(self.model, q, project, reuse);
        if !keep {
            cache.hessian.clear();
        }
        let mut f = 0.0;
        for t in self.terms {
            f += match (t.reusable_hessian(), keep) {
                (true, true) => t.value_gradient(&ctx, q, &mut asm.grad),
                (true, false) => t.eval(&ctx, q, Some(&mut cache.hessian), project),
                (false, _) => t.eval(&ctx, q, Some(asm), project),
            };
        }
        if let Some(sc) = self.self_contact {
            f += sc.assemble(q, asm);
        }
        if !keep {
            cache.at.copy_from_slice(q);
            cache.project = project;
            cache.valid = true;
            for (g, c) in asm.grad.iter_mut().zip(&cache.hessian.grad) {
                *g += c;
            }
        }
        for (h, c) in asm.values.iter_mut().zip(&cache.hessian.values) {
            *h += c;
        }
        (self.add_inertia(q, asm, f), keep)
    }

    /// Add the inertial term's gradient and Hessian to `asm`; returns `f` plus its value.
    fn add_inertia(&self, q: &[f64], asm: &mut Assembly, mut f: f64) -> f64 {
        let m = self.model;
        if let Some(inertia) = self.inertia {
            let w = inertia.weight;
            for k in 0..m.ndof {
                let d = q[k] - inertia.qhat[k];
                f += 0.5 * w * m.mass[k] * d * d;
                asm.grad[k] += w * m.mass[k] * d;
                asm.add_h(k, k, w * m.mass[k]);
            }
            let dw = inertia.euler_weight - w;
            for &k in inertia.euler {
                let d = q[k] - inertia.qhat[k];
                f += 0.5 * dw * m.mass[k] * d * d;
                asm.grad[k] += dw * m.mass[k] * d;
                asm.add_h(k, k, dw * m.mass[k]);
            }
        }
        f
    }
}

/// Newton's workspace: assembly, factorisation, correction, trial point and statistics.
pub struct Newton {
    /// Gradient and Hessian of the current iterate.
    pub asm: Assembly,
    /// Factorisation of the Hessian.
    pub lin: LinSolver,
    /// Newton correction.
    pub dq: Vec<f64>,
    /// Line-search trial point.
    pub trial: Vec<f64>,
    /// Statistics so far.
    pub stats: NewtonStats,
    /// Where the next [`Newton::backtrack`] starts (then reset to 1): the caller's
    /// [`Objective::max_step`] along `dq`.
    pub step_cap: f64,
}

impl Newton {
    /// A workspace for `n` coordinates.
    pub fn new(n: usize) -> Self {
        let asm = Assembly::new(n);
        let lin = LinSolver::new(&asm);
        Newton {
            asm,
            lin,
            dq: vec![0.0; n],
            trial: vec![0.0; n],
            stats: NewtonStats::default(),
            step_cap: 1.0,
        }
    }

    /// Factorise the assembled Hessian, shifting the diagonal if it is only semi-definite
    /// (`[solver] shift`, x10 per retry, `shift_tries` retries).
    pub fn factor_shifted(&mut self, m: &Model, it: usize) -> Result<(), NewtonFailure> {
        if self.factor().is_ok() {
            return Ok(());
        }
        let n = self.asm.n();
        self.stats.shifted_factorizations += 1;
        let dmax = (0..n)
            .map(|k| self.asm.h(k, k).abs())
            .fold(0.0, f64::max)
            .max(1e-300);
        let mut shift = m.solver.shift * dmax;
        for _ in 0..m.solver.shift_tries {
            for k in 0..n {
                self.asm.add_h(k, k, shift);
            }
            if self.factor().is_ok() {
                return Ok(());
            }
            shift *= 10.0;
        }
        Err(NewtonFailure::NotPositiveDefinite { iteration: it })
    }

    /// Factorise the assembled Hessian as it is (counted in the statistics).
    pub fn factor(&mut self) -> Result<(), linsolve::NotPositiveDefinite> {
        self.stats.factorizations += 1;
        self.lin.factor(&self.asm)
    }

    /// `dq = -H^-1 g` with the last factorisation.
    pub fn solve_direction(&mut self) {
        for k in 0..self.dq.len() {
            self.dq[k] = -self.asm.grad[k];
        }
        self.lin.solve(&mut self.dq);
    }

    /// Largest position and twist-angle components of the correction `dq`.
    pub fn correction_norms(&self) -> (f64, f64) {
        let mut dx: f64 = 0.0;
        let mut dth: f64 = 0.0;
        for (k, d) in self.dq.iter().enumerate() {
            if dof::is_edge(k) {
                dth = dth.max(d.abs());
            } else {
                dx = dx.max(d.abs());
            }
        }
        (dx, dth)
    }

    /// Whether the correction is below the tolerance (`tolerance * a` on positions,
    /// `tolerance` rad on angles).
    pub fn small(&self, m: &Model) -> bool {
        let (dx, dth) = self.correction_norms();
        dx <= m.tolerance * m.diameter && dth <= m.tolerance
    }

    /// Backtracking (Armijo) line search along `dq` from `q` on `merit`, with value `f0` and
    /// slope `slope` at `q`, from the step length [`Newton::step_cap`] (1 unless the caller
    /// capped it); `take_full`: accept that first step without evaluating the merit.
    /// The accepted point is left in `trial`; returns its step length, or `None`.
    pub fn backtrack(
        &mut self,
        m: &Model,
        q: &[f64],
        f0: f64,
        slope: f64,
        take_full: bool,
        merit: &dyn Fn(&[f64]) -> f64,
    ) -> Option<f64> {
        let s = &m.solver;
        let mut alpha = std::mem::replace(&mut self.step_cap, 1.0).min(1.0);
        let noise = s.line_search_noise * f0.abs().max(1e-300);
        for _ in 0..s.max_backtracks {
            for k in 0..q.len() {
                self.trial[k] = q[k] + alpha * self.dq[k];
            }
            if take_full {
                return Some(alpha);
            }
            let ft = merit(&self.trial);
            if ft.is_finite() && ft <= f0 + s.armijo * alpha * slope + noise {
                return Some(alpha);
            }
            alpha *= 0.5;
            self.stats.backtracks += 1;
        }
        None
    }

    /// Minimise `obj` from `q` (overwritten with the minimiser), holding the coordinates
    /// marked in `fixed`, in at most `cap` iterations. Returns the iteration count.
    pub fn minimize(
        &mut self,
        m: &Model,
        obj: &mut dyn Objective,
        q: &mut Vec<f64>,
        fixed: &[bool],
        cap: usize,
    ) -> Result<usize, NewtonFailure> {
        let n = q.len();
        let path = Path::Newton;
        // Exact Hessians first (quadratic convergence); when one is not positive definite the
        // iterate is redone, and the rest of the solve run, with every stencil projected.
        let mut project = false;
        let mut it = 0;
        while it < cap {
            it += 1;
            let t0 = Instant::now();
            let f0 = obj.assemble(q, &mut self.asm, project);
            if project {
                self.stats.projected_iterations += 1;
            }
            for k in 0..n {
                if fixed[k] {
                    self.asm.fix(k);
                }
            }
            if !f0.is_finite() || self.asm.grad.iter().any(|g| !g.is_finite()) {
                return Err(NewtonFailure::NonFiniteObjective {
                    path,
                    iteration: it,
                });
            }
            let t1 = Instant::now();
            self.stats.assembly_s += (t1 - t0).as_secs_f64();
            if project {
                self.factor_shifted(m, it)?;
            } else if self.factor().is_err() {
                project = true;
                it -= 1;
                self.stats.factor_s += t1.elapsed().as_secs_f64();
                continue;
            }
            let t2 = Instant::now();
            self.stats.factor_s += (t2 - t1).as_secs_f64();
            self.solve_direction();
            let t3 = Instant::now();
            self.stats.solve_s += (t3 - t2).as_secs_f64();
            if self.dq.iter().any(|d| !d.is_finite()) {
                return Err(NewtonFailure::NonFiniteStep {
                    path,
                    iteration: it,
                });
            }
            let slope: f64 = self.asm.grad.iter().zip(&self.dq).map(|(g, d)| g * d).sum();
            let (dx, dth) = self.correction_norms();
            let small = dx <= m.tolerance * m.diameter && dth <= m.tolerance;
            self.step_cap = obj.max_step(q, &self.dq);
            let alpha = {
                let o: &dyn Objective = obj;
                self.backtrack(m, q, f0, slope, small, &|x| o.value(x))
            };
            self.stats.line_search_s += t3.elapsed().as_secs_f64();
            let Some(alpha) = alpha else {
                return Err(NewtonFailure::LineSearch {
                    path,
                    iteration: it,
                    slope,
                });
            };
            std::mem::swap(q, &mut self.trial);
            obj.accepted(q);
            log::debug!("  it {it}: alpha {alpha:.3e} dx {dx:.3e} dth {dth:.3e} slope {slope:.3e}");
            if alpha == 1.0 && small {
                return Ok(it);
            }
        }
        Err(NewtonFailure::NotConverged {
            path,
            iterations: cap,
        })
    }
}
