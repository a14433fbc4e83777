//! Speed against accuracy (MODEL section 8): the work-precision chart and the stability map
//! of the implicit integrator ([`crate::integrator`]) and the explicit velocity Verlet
//! reference ([`crate::integrator::explicit`]) on the same discrete model, for scenes without
//! ground (the explicit integrator has no contact).
//!
//! * **Work-precision** ([`work_precision`]): the reference solution is the scene run by
//!   velocity Verlet at three fine steps `h, h/2, h/4`; Richardson's estimate from the final
//!   centrelines gives the observed order `p = log2(d1/d2)` (`d1 = |x_h - x_{h/2}|`,
//!   `d2 = |x_{h/2} - x_{h/4}|`, max node distance) and the error of the finest run,
//!   `d2 / (2^p - 1)`, which becomes the reference. Each integrator then runs the scene at
//!   several steps; the error is the largest distance of a real node from the reference at the
//!   final time (m), against the wall time of the run (s). The mesh is the scene's: this
//!   measures time-integration error of one discrete model, not spatial error.
//!   No ground means no `v_s`; the centreline error stands for accuracy.
//! * **Gait work-precision** ([`gait_precision`]): scenes with ground and muscles, where the
//!   explicit reference cannot run: implicit Euler and BDF2 over fixed steps and adaptive BDF2
//!   over tolerances against an implicit Euler reference refined until `v_s/v_m` settles
//!   (`src/charts/gait_precision.rs`).
//! * **Stability map** ([`stability_map`]): over scaled weight `W = rho g a^2 L^3 / B` and
//!   element count `N`, the largest step each method runs the scene with to its end by
//!   geometric bisection (relative resolution `rtol`). Stable means: every step accepted with
//!   finite state, for the explicit integrator no energy blow-up (see
//!   [`crate::integrator::explicit`]), for the implicit one Newton converged in every step
//!   without halving (`max_halvings = 0`). Bisection assumes that stability is monotone in the
//!   step, which the measurement does not prove. The implicit search stops at the scene's
//!   duration (one step); a method that holds there is reported as capped. Beside the
//!   measurement: the linear-theory Verlet limit `2/omega_max` from the eigenvalues of
//!   `M^{-1} K` at the initial state ([`linear_stability_limit`]) and the stretch, bending and
//!   twist time scales `l0 sqrt(rho A/EA)`, `l0^2 sqrt(rho A/B)`, `l0 sqrt(rho J/C)`.

use crate::gait::Muscles;
use crate::integrator::explicit::{Explicit, Unsupported};
use crate::integrator::{Integrator, StepError};
use crate::model::Model;
use crate::plot::{self, PlotError};
use crate::problem::{IntegratorKind, Problem};
use crate::rod::{dof, vec3::f};
use crate::sim::{drive, Schedule};
use crate::state::State;

pub mod external;
mod gait_method;
mod gait_precision;
mod stability;
mod work_precision;

pub use external::{read_external, ExternalError, ExternalPoint, ExternalRun};
pub use gait_method::GaitMethod;
pub use gait_precision::{
    gait_precision, gait_reference, gait_run, speed_ratio, variant, write_gait_precision,
    GaitPoint, GaitPrecision, GaitPrecisionOptions, GaitReference, GaitRun,
};
pub use stability::{
    stability_map, stable, write_stability, StabilityCell, StabilityMap, StabilityOptions,
};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;
pub use work_precision::{
    work_precision, write_work_precision, Comparison, Reference, WorkPoint, WorkPrecision,
    WorkPrecisionOptions,
};

/// Errors of the charts.
#[derive(Debug, thiserror::Error)]
pub enum ChartError {
    /// The scene cannot be run by the explicit integrator.
    #[error(transparent)]
    Unsupported(#[from] Unsupported),
    /// The reference solution could not be computed or did not converge.
    #[error("reference solution: {0}")]
    Reference(String),
    /// A file could not be written.
    #[error("{path}: cannot write: {source}")]
    Io {
        /// File.
        path: PathBuf,
        /// Cause.
        source: std::io::Error,
    },
    /// A figure could not be drawn.
    #[error(transparent)]
    Plot(#[from] PlotError),
}

/// One finished run.
#[derive(Clone, Debug)]
pub struct RunResult {
    /// Final positions of the real nodes (m).
    pub x: Vec<[f64; 3]>,
    /// Final time (s).
    pub t: f64,
    /// Wall time of the stepping (s).
    pub wall_s: f64,
    /// Steps taken.
    pub steps: usize,
    /// Newton iterations (implicit).
    pub newton_iterations: usize,
    /// Step halvings (implicit).
    pub step_halvings: usize,
}

/// Run `model` from its initial state with `n` steps of `h` by `method` (gait from the model).
/// The implicit integrators halve failed steps up to `model.max_halvings` times.
pub fn simulate(
    model: &Model,
    method: IntegratorKind,
    h: f64,
    n: usize,
) -> Result<Result<RunResult, StepError>, Unsupported> {
    let actuation = Box::new(Muscles {
        gait: model.gait.clone(),
    });
    let start = Instant::now();
    let schedule = Schedule::fixed(h, n);
    let o = match method {
        IntegratorKind::ImplicitEuler | IntegratorKind::Bdf2 => {
            let scheme = crate::integrator::scheme_for(method).expect("an implicit integrator");
            let mut integ = Integrator::with_scheme(model, actuation, scheme);
            drive(model, &mut integ, schedule, start, &mut |_| {}, &mut |_| {})
        }
        IntegratorKind::VelocityVerlet => {
            let mut integ = Explicit::new(model, actuation)?;
            drive(model, &mut integ, schedule, start, &mut |_| {}, &mut |_| {})
        }
    };
    let s = &o.state;
    Ok(match o.error {
        Some(e) => Err(e),
        None => Ok(RunResult {
            x: model.real.clone().map(|i| s.node(i)).collect(),
            t: s.t,
            wall_s: o.wall_time_s,
            steps: n,
            newton_iterations: o.stats.newton_iterations,
            step_halvings: o.stats.step_halvings,
        }),
    })
}

/// Largest distance between corresponding nodes (m).
pub fn max_distance(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| f::norm(f::sub(*p, *q)))
        .fold(0.0, f64::max)
}

/// Verlet's linear stability limit and the mode that sets it.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct LinearLimit {
    /// `2 / omega_max` (s).
    pub dt: f64,
    /// Shares of the fastest mode's kinetic energy in motion along the rod (stretch), across
    /// it (bend) and in twist; they sum to 1.
    pub shares: [f64; 3],
}

impl LinearLimit {
    /// "stretch", "bend" or "twist": the largest share.
    pub fn mode(&self) -> &'static str {
        let k = (0..3)
            .max_by(|&a, &b| self.shares[a].total_cmp(&self.shares[b]))
            .unwrap_or(0);
        ["stretch", "bend", "twist"][k]
    }
}

/// Verlet's linear stability limit `2 / omega_max`, `omega_max^2` the largest eigenvalue of
/// `M^{-1} K` over the free coordinates, `K` the (unprojected) energy Hessian at the initial
/// state, and the kind of its mode. Dense eigen-decomposition: meant for chart-sized rods (up
/// to a few hundred elements).
pub fn linear_stability_limit(model: &Model) -> LinearLimit {
    let s = State::initial(model);
    let mut integ = Integrator::new(
        model,
        Box::new(Muscles {
            gait: model.gait.clone(),
        }),
    );
    let (_, asm) = integ.energy_derivatives(&s, &s.q, false);
    let free: Vec<usize> = (0..model.ndof).filter(|&k| !model.fixed[k]).collect();
    let nf = free.len();
    let mut a = nalgebra::DMatrix::<f64>::zeros(nf, nf);
    for (r, &i) in free.iter().enumerate() {
        for (c, &j) in free.iter().enumerate() {
            a[(r, c)] = asm.h(i, j) / (model.mass[i] * model.mass[j]).sqrt();
        }
    }
    let eig = nalgebra::SymmetricEigen::new(a);
    let top = eig.eigenvalues.imax();
    let u = eig.eigenvectors.column(top);
    // Kinetic-energy shares of the mode (mass-scaled coordinates): twist angles; node
    // displacements split along and across the local tangent.
    let mut full = vec![0.0; model.ndof];
    for (r, &k) in free.iter().enumerate() {
        full[k] = u[r];
    }
    let mut shares = [0.0; 3];
    for j in 0..model.nodes - 1 {
        shares[2] += full[dof::edge(j)].powi(2);
    }
    for i in 0..model.nodes {
        let k = dof::node(i);
        let d = [full[k], full[k + 1], full[k + 2]];
        let j = i.min(model.nodes - 2);
        let t = f::unit(crate::state::edge_vec(&s.q, j));
        let along = f::dot(d, t).powi(2);
        shares[0] += along;
        shares[1] += f::dot(d, d) - along;
    }
    let total: f64 = shares.iter().sum();
    LinearLimit {
        dt: 2.0 / eig.eigenvalues[top].sqrt(),
        shares: shares.map(|x| x / total),
    }
}

/// Write a text file, naming it on failure.
pub(crate) fn write(path: &Path, text: &str) -> Result<(), ChartError> {
    std::fs::write(path, text).map_err(|source| ChartError::Io {
        path: path.into(),
        source,
    })
}
