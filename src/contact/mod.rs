//! Ground contact with anisotropic Coulomb friction as one second-order-cone program per
//! Newton iterate, solved by Clarabel (MODEL section 3).
//!
//! Contact candidates are the real nodes, with the exact gap `z_i - a/2 >= 0` against the
//! plane `z = 0` (an incline tilts gravity, not the plane, so gaps stay linear and exact: a
//! sliding body cannot rise, there is no Anitescu drift to correct).
//!
//! At each contact the local frame is: forward `f` = the body tangent at the node projected
//! on the ground, toward the head (s decreasing), taken at the start of the step; sideways
//! `s = e_z x f`; normal `e_z`. With the node's slip velocity `v = (x - x_n)/h`, the friction
//! dissipation potential is `D = N sqrt((mu(v_f) v_f)^2 + (mu_s v_s)^2)`, `mu = mu_f` for
//! forward sliding and `mu_b` backward: the support function of the admissible force set (a
//! union of two half-ellipses). It is second-order-cone representable with
//! `v_f = u - w`, `u, w >= 0`, `sigma >= ||(mu_f u, mu_b w, mu_s v_s)||`, cost `h N sigma`.
//!
//! Each Newton iterate solves the convex SOCP
//! `min 1/2 dq^T H dq + g^T dq + h sum_c N_c sigma_c` subject to the gaps at `q + dq`, the
//! cone constraints and the linear slip definitions. The duals of the gap rows are the normal
//! forces `N_c`; they enter the next iterate's dissipation (a fixed point on the normal
//! forces, converged together with Newton), so at convergence the contact forces satisfy
//! exact Coulomb complementarity: stiction inside the cone, sliding on its boundary.
//!
//! The integrator solves most steps without this program: [`active`] keeps every contact's
//! status (free, sticking, sliding) and solves the then smooth step problem by Newton,
//! changing statuses that violate the Coulomb conditions and verifying them at convergence;
//! the conic program runs only when that fails (and its solution resets the statuses).

pub mod active;
pub mod conic;
pub mod reactions;

pub use active::{ActiveSet, Mode};
pub use conic::Conic;

pub use crate::model::Ground;

use crate::energy::Assembly;
use crate::model::Model;
use crate::newton::{Failure, Newton, Potential};
use crate::rod::{dof, vec3::f};
use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};

/// A contact model: what a time step needs of ground contact. The integrator calls
/// [`ContactModel::begin_step`] once per step, [`ContactModel::solve`] to solve the step problem
/// (the incremental potential plus friction, subject to the contact constraints) with Newton's
/// building blocks, then [`ContactModel::accept`] or [`ContactModel::reject`]; the run loop reads
/// the normal forces. Implementations: [`Conic`] (one conic program per Newton iterate) and
/// [`ActiveSet`] (contact statuses held and verified, the conic program as the fallback).
pub trait ContactModel: Send {
    /// Freeze the contact frames at `q_start` and the slip origin `slip_origin` (slip is
    /// `x - x_origin`: the time integrator's velocity times its effective step), and put the
    /// iterate `q` on the feasible side of the ground. `v_start`, `h`: the state and step.
    fn begin_step(
        &mut self,
        m: &Model,
        q_start: &[f64],
        slip_origin: &[f64],
        v_start: &[f64],
        h: f64,
        q: &mut [f64],
    );
    /// Solve the step problem `min obj + friction` from the iterate `q` (overwritten with the
    /// solution). Returns the Newton iteration count.
    fn solve(
        &mut self,
        newton: &mut Newton,
        obj: &Potential,
        q: &mut Vec<f64>,
    ) -> Result<usize, Failure>;
    /// The step's solution `q` was accepted.
    fn accept(&mut self, m: &Model, q: &[f64]);
    /// The step was rejected: restore what `begin_step` saved.
    fn reject(&mut self);
    /// Normal force on every real node (N; zero off the ground), into `out`.
    fn normal_forces(&self, m: &Model, out: &mut [f64]);
}

/// The contact model a problem asks for (`[solver] contact`).
pub fn model_for(m: &Model) -> Option<Box<dyn ContactModel>> {
    m.ground.as_ref()?;
    Some(match m.solver.contact {
        crate::problem::ContactKind::ActiveSet => Box::new(ActiveSet::new(m)),
        crate::problem::ContactKind::Conic => Box::new(Conic::new(m)),
    })
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
    /// As a Newton failure at iteration `it`.
    pub fn at(self, it: usize) -> Failure {
        match self {
            ConicError::Setup(message) => Failure::ConicSetup {
                message,
                iteration: it,
            },
            ConicError::Status { status, iterations } => Failure::Conic {
                status,
                conic_iterations: iterations,
                iteration: it,
            },
        }
    }
}

/// Per-step contact data and the normal-force fixed point.
pub struct Contacts {
    /// Internal node index of each contact candidate.
    pub nodes: Vec<usize>,
    /// Normal force at each candidate (N), the current fixed-point value.
    pub normal: Vec<f64>,
    forward: Vec<[f64; 3]>,
    side: Vec<[f64; 3]>,
    x_start: Vec<[f64; 3]>,
    /// Normal forces from the last solve, not yet committed.
    pub pending: Vec<f64>,
    /// Clarabel iterations of the last solve.
    pub last_iterations: u32,
    /// Clarabel solve time of the last solve (s).
    pub last_time: f64,
    direct_method: String,
    conic_tolerance: f64,
    conic_max_iterations: u32,
    /// Status of every contact for the active-set path (valid after a conic solve).
    pub mode: Vec<Mode>,
    /// Whether `mode` holds a status from a converged step.
    pub modes_valid: bool,
    pub(crate) react: Vec<f64>,
    pub(crate) ratio: Vec<f64>,
    pub(crate) slip_dir: Vec<[f64; 2]>,
}

/// Outcome of one conic solve.
pub struct ConicStep {
    /// Largest change of a normal force between the lagged and new value (N).
    pub max_normal_change: f64,
    /// Optimal value of the conic model minus its value at `dq = 0` (J, <= 0).
    pub predicted_decrease: f64,
}

impl Contacts {
    /// Contact candidates of a model (real, not clamped nodes).
    pub fn new(m: &Model, q: &[f64]) -> Self {
        let nodes: Vec<usize> = m
            .real
            .clone()
            .filter(|&i| !m.fixed[dof::node(i) + 2])
            .collect();
        let nc = nodes.len();
        // Initial normal forces: each node's weight share if it touches the ground.
        let g = f::norm(m.gravity);
        let normal: Vec<f64> = nodes
            .iter()
            .map(|&i| {
                let z = q[dof::node(i) + 2];
                if z - 0.5 * m.diameter <= 1e-9 * m.diameter {
                    m.mass[dof::node(i)] * g
                } else {
                    0.0
                }
            })
            .collect();
        Contacts {
            nodes,
            pending: normal.clone(),
            normal,
            forward: vec![[0.0; 3]; nc],
            side: vec![[0.0; 3]; nc],
            x_start: vec![[0.0; 3]; nc],
            last_iterations: 0,
            last_time: 0.0,
            direct_method: m.solver.clarabel_method.clone(),
            conic_tolerance: m.solver.conic_tolerance,
            conic_max_iterations: m.solver.conic_max_iterations,
            mode: vec![Mode::Free; nc],
            modes_valid: false,
            react: vec![0.0; nc],
            ratio: vec![0.0; nc],
            slip_dir: vec![[0.0; 2]; nc],
        }
    }

    /// Mean weight per contact candidate (N): the scale of normal-force tolerances.
    pub fn weight_scale(&self, m: &Model) -> f64 {
        (m.total_mass() * f::norm(m.gravity) / self.nodes.len().max(1) as f64).max(1e-300)
    }

    /// Freeze the contact frames (from `q`) and the slip origins (from `origin`) at the
    /// beginning of a step.
    pub fn begin_step(&mut self, m: &Model, q: &[f64], origin: &[f64]) {
        for (c, &i) in self.nodes.iter().enumerate() {
            let x = |k: usize| [q[dof::node(k)], q[dof::node(k) + 1], q[dof::node(k) + 2]];
            // Toward the head: from node i+1 to node i-1 (ends one-sided), on the ground.
            let lo = if i > m.real.start { i - 1 } else { i };
            let hi = if i + 1 < m.real.end { i + 1 } else { i };
            let d = f::sub(x(lo), x(hi));
            let mut fw = [d[0], d[1], 0.0];
            if f::norm(fw) < 1e-12 {
                fw = [1.0, 0.0, 0.0];
            }
            let fw = f::unit(fw);
            self.forward[c] = fw;
            self.side[c] = f::cross([0.0, 0.0, 1.0], fw);
            let k = dof::node(i);
            self.x_start[c] = [origin[k], origin[k + 1], origin[k + 2]];
        }
    }

    /// Friction dissipation `h D` at `q` with the lagged normal forces (J).
    pub fn dissipation(&self, g: &Ground, q: &[f64]) -> f64 {
        let mut d = 0.0;
        for (c, &i) in self.nodes.iter().enumerate() {
            if self.normal[c] == 0.0 {
                continue;
            }
            let k = dof::node(i);
            let dx = f::sub([q[k], q[k + 1], q[k + 2]], self.x_start[c]);
            let vf = f::dot(dx, self.forward[c]);
            let vs = f::dot(dx, self.side[c]);
            let mu = if vf > 0.0 { g.mu_f } else { g.mu_b };
            d += self.normal[c] * ((mu * vf).powi(2) + (g.mu_s * vs).powi(2)).sqrt();
        }
        d // h D = h N mu |v| = N mu |dx|
    }

    /// Lift the iterate's predicted penetrations onto the ground (a feasible start).
    pub fn lift(&self, m: &Model, q: &mut [f64]) {
        for &i in &self.nodes {
            let k = dof::node(i) + 2;
            q[k] = q[k].max(0.5 * m.diameter);
        }
    }

    /// Normal force on every real node (N), into `out`.
    pub fn normal_forces(&self, m: &Model, out: &mut [f64]) {
        out.fill(0.0);
        for (c, &i) in self.nodes.iter().enumerate() {
            out[i - m.real.start] = self.normal[c];
        }
    }

    /// Solve the conic subproblem at the iterate `q`: writes the step into `dq` and the new
    /// normal forces into `pending`.
    pub fn conic_program(
        &mut self,
        m: &Model,
        g: &Ground,
        asm: &Assembly,
        q: &[f64],
        h: f64,
        dq: &mut [f64],
    ) -> Result<ConicStep, ConicError> {
        let n = asm.n();
        let nc = self.nodes.len();
        let nv = n + 4 * nc;
        let var = |c: usize, k: usize| n + 4 * c + k; // u, w, y, sigma
                                                      // Scaling (the interior-point tolerances are absolute): displacements in units of
                                                      // `ls`, the larger of this step's largest node displacement and `g h^2`; slip variables
                                                      // as displacements (`h u / ls`, ...); the objective multiplied by `k` so that the
                                                      // Hessian's mean diagonal is one.
        let mut disp: f64 = 0.0;
        for c in 0..nc {
            let kk = dof::node(self.nodes[c]);
            disp = disp.max(f::norm(f::sub(
                [q[kk], q[kk + 1], q[kk + 2]],
                self.x_start[c],
            )));
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
        let p = CscMatrix::new(nv, nv, colptr, asm.row_idx.clone(), pv);
        let mut lin = vec![0.0; nv];
        for k in 0..n {
            lin[k] = asm.grad[k] * ks * d[k];
        }
        for c in 0..nc {
            // A tiny cost on sigma, u and w keeps the optimal set bounded where a contact
            // carries no load (otherwise sigma and u = w could grow freely, which stalls the
            // interior-point method); it changes forces by ~1e-9 of the scaled units.
            lin[var(c, 3)] = ks * ls * self.normal[c] + 1e-9;
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
        for c in 0..nc {
            let k = dof::node(self.nodes[c]);
            let x = [q[k], q[k + 1], q[k + 2]];
            let d0 = f::sub(x, self.x_start[c]);
            for (dir, sign_var) in [(self.forward[c], 0usize), (self.side[c], 2usize)] {
                for a in 0..2 {
                    if dir[a] != 0.0 {
                        push(
                            row,
                            k + a,
                            dir[a] * d[k + a] / ls,
                            &mut ri,
                            &mut ci,
                            &mut vv,
                        );
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
        let n_zero = row;
        // Nonnegative: gaps, then u, w >= 0.
        for c in 0..nc {
            let k = dof::node(self.nodes[c]);
            push(row, k + 2, -d[k + 2] / ls, &mut ri, &mut ci, &mut vv);
            b.push((q[k + 2] - 0.5 * m.diameter) / ls);
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
        for c in 0..nc {
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
            .tol_gap_abs(self.conic_tolerance)
            .tol_gap_rel(self.conic_tolerance)
            .tol_feas(self.conic_tolerance)
            .max_iter(self.conic_max_iterations)
            .direct_solve_method(self.direct_method.clone())
            .build()
            .map_err(|e| ConicError::Setup(format!("Clarabel settings: {e:?}")))?;
        let mut solver = DefaultSolver::new(&p, &lin, &a, &b, &cones, settings)
            .map_err(|e| ConicError::Setup(format!("Clarabel setup: {e:?}")))?;
        solver.solve();
        let sol = &solver.solution;
        self.last_iterations = sol.iterations;
        self.last_time = sol.solve_time;
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
            change = change.max((lam - self.normal[c]).abs());
            self.pending[c] = lam;
        }
        let predicted_decrease = sol.obj_val / ks - self.dissipation(g, q);
        Ok(ConicStep {
            max_normal_change: change,
            predicted_decrease,
        })
    }
}
