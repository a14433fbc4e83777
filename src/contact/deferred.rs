//! The active set's deferred line search: a full Newton step is taken before its
//! sufficient-decrease test, which the next assembly decides ([`Deferred`]); a failed test
//! backtracks from the saved iterate ([`Saved`]).

use super::ContactFailure;
use super::ContactStats;
use crate::model::Model;
use crate::newton::{Failure, Newton, Path};

/// Iterate and direction saved for a [`Deferred`] test.
#[derive(Default)]
pub(super) struct Saved {
    q: Vec<f64>,
    dq: Vec<f64>,
    /// The symmetric direction (normal forces lagged), for a coupled step that fails.
    pub(super) dq_symmetric: Vec<f64>,
}

impl Saved {
    pub(super) fn save(&mut self, q: &[f64], dq: &[f64]) {
        self.q.clear();
        self.q.extend_from_slice(q);
        self.dq.clear();
        self.dq.extend_from_slice(dq);
    }

    /// A deferred full step failed its sufficient-decrease test (or could not be tested):
    /// back to the saved iterate and direction, and the backtracking line search from there,
    /// with its accepted point in `q`.
    #[allow(clippy::too_many_arguments)] // the step's parts, each borrowed separately
    pub(super) fn backtrack(
        &self,
        nw: &mut Newton,
        stats: &mut ContactStats,
        m: &Model,
        q: &mut [f64],
        d: Deferred,
        iteration: usize,
        merit: &dyn Fn(&[f64]) -> f64,
    ) -> Result<(), ContactFailure> {
        let slope = match d.symmetric_slope {
            Some(slope) => {
                nw.dq.copy_from_slice(&self.dq_symmetric);
                slope
            }
            None => {
                nw.dq.copy_from_slice(&self.dq);
                d.slope
            }
        };
        let alpha = nw.backtrack(m, &self.q, d.f0, slope, false, merit);
        let Some(alpha) = alpha else {
            return Err(Failure::LineSearch {
                path: Path::ActiveSet,
                iteration,
                slope,
            }
            .into());
        };
        if alpha < 1.0 {
            stats.residuals.push(-1.0);
        }
        q.copy_from_slice(&nw.trial);
        Ok(())
    }
}

/// A full Newton step taken before its sufficient-decrease (Armijo) test: the merit at the
/// new iterate comes with that iterate's assembly (its objective value, plus the sliding
/// dissipation with the normal forces the step was computed with), so the test costs no
/// separate energy evaluation. If it fails, the step is backtracked from the saved iterate
/// exactly as an immediate test would have, and that assembly is redone.
#[derive(Clone, Copy)]
pub(super) struct Deferred {
    /// Merit at the saved iterate.
    pub(super) f0: f64,
    /// Directional derivative of the merit along the saved direction.
    pub(super) slope: f64,
    /// For a coupled direction: the merit's slope along the symmetric one
    /// ([`Saved::dq_symmetric`]), which a failed test backtracks along instead.
    pub(super) symmetric_slope: Option<f64>,
}
