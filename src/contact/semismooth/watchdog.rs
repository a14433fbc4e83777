//! The semi-smooth Newton's line-search memory ([`super::SemiSmooth`]): the accepted merits
//! the non-monotone test compares with, and the watchdog for contacts between nodes (a full
//! step that raises the merit is taken while such a contact touches, and judged by the full
//! steps after it; see [`SemiSmooth::watchdog`]).

use super::{Pending, SemiSmooth};
use crate::contact::status::ContactStatus;
use crate::contact::{ContactFailure, ContactSet};
use crate::model::Model;
use crate::newton::{NewtonFailure, Path};

/// A full step taken without sufficient decrease (the watchdog): the merit it started from,
/// which a later iterate must fall below before the iterate after it is tested.
#[derive(Clone, Copy)]
pub(super) struct Watch {
    pub(super) theta0: f64,
    /// Full steps left before the merit must have fallen below `theta0`.
    pub(super) left: usize,
}

/// The merit test's facts the watchdog reads ([`SemiSmooth::watchdog`]).
struct Watchdog {
    /// The iterate's merit.
    theta: f64,
    /// Whether it passed the (non-monotone) sufficient-decrease test.
    decrease: bool,
    armijo: f64,
    noise: f64,
    /// Whether a watchdog step may start here: after a full step, without self-contact pairs.
    allowed: bool,
}

/// Full steps the watchdog allows after the one taken without decrease.
pub(super) const WATCH_STEPS: usize = 2;

/// The sufficient-decrease test of the iterate after a step ([`SemiSmooth::merit_test`]).
pub(super) struct MeritTest {
    /// The step's pending test: the merit it started from and its length.
    pub(super) p: Pending,
    /// The iterate's merit.
    pub(super) theta: f64,
    /// Accepted iterates since the lowest merit, and the memory's length.
    pub(super) since_best: usize,
    pub(super) memory: usize,
    /// Whether the test is monotone (self-contact pairs act).
    pub(super) monotone: bool,
    pub(super) iteration: usize,
}

impl SemiSmooth {
    /// The (non-monotone) sufficient-decrease test of the iterate after a step, with the
    /// watchdog: `None` accepts the iterate; `Some` is the pending test of the backtrack
    /// taken instead (the iterate already moved); a step halved `max_backtracks` times fails.
    pub(super) fn merit_test(
        &mut self,
        t: MeritTest,
        watch: &mut Option<Watch>,
        ct: &ContactSet,
        m: &Model,
        q: &mut [f64],
    ) -> Result<Option<Pending>, ContactFailure> {
        let set = &m.solver;
        let p = t.p;
        let noise = 1e-20 * (m.ndof + 3 * ct.len()) as f64;
        let reference = if t.since_best < t.memory && !t.monotone {
            self.scratch.recent.iter().fold(p.theta0, |a, &b| a.max(b))
        } else {
            p.theta0
        };
        let decrease = t.theta <= (1.0 - 2.0 * set.armijo * p.alpha) * reference + noise;
        let wd = Watchdog {
            theta: t.theta,
            decrease,
            armijo: set.armijo,
            noise,
            allowed: p.alpha == 1.0 && !t.monotone,
        };
        if let Some(back) = self.watchdog(watch, p, wd, ct, m, q) {
            return Ok(Some(back));
        }
        if decrease || watch.is_some() {
            return Ok(None);
        }
        // Not enough decrease: back along the saved direction.
        let alpha = 0.5 * p.alpha;
        if alpha < 0.5f64.powi(set.max_backtracks as i32) {
            return Err(NewtonFailure::LineSearch {
                path: Path::SemiSmooth,
                iteration: t.iteration,
                slope: -2.0 * p.theta0,
            }
            .into());
        }
        self.step_from_saved(ct, m, q, alpha);
        Ok(Some(Pending {
            theta0: p.theta0,
            alpha,
        }))
    }

    /// The watchdog's part of the merit test of the iterate after a step `p`. A contact
    /// between nodes lags its normal force in its friction, so a full step whose normal force
    /// changes much raises the merit although the next one settles it (on the damped S-start,
    /// 100 elements, implicit Euler at 2.5e-4 s with `ground_points = "curve"`, the line
    /// search crept at `alpha` 2^-10 for 100 iterations, then the conic program took over).
    /// Such a step without sufficient decrease is taken (a checkpoint is kept) while a contact
    /// between nodes touches; its merit must fall below the checkpoint's within
    /// [`WATCH_STEPS`] more full steps, each decreasing, or the search goes back to the
    /// checkpoint and halves its step there: `Some` is that backtrack's pending test, with the
    /// iterate already moved.
    fn watchdog(
        &mut self,
        watch: &mut Option<Watch>,
        p: Pending,
        wd: Watchdog,
        ct: &ContactSet,
        m: &Model,
        q: &mut [f64],
    ) -> Option<Pending> {
        match *watch {
            Some(w) if wd.theta <= (1.0 - 2.0 * wd.armijo) * w.theta0 + wd.noise => *watch = None,
            Some(w) if w.left == 0 || !wd.decrease => {
                *watch = None;
                self.restore_watch();
                self.step_from_saved(ct, m, q, 0.5);
                return Some(Pending {
                    theta0: w.theta0,
                    alpha: 0.5,
                });
            }
            Some(w) => {
                *watch = Some(Watch {
                    left: w.left - 1,
                    ..w
                })
            }
            None if !wd.decrease && wd.allowed && self.any_between() => {
                self.keep_watch();
                *watch = Some(Watch {
                    theta0: p.theta0,
                    left: WATCH_STEPS,
                });
            }
            None => {}
        }
        None
    }

    /// Whether a contact between nodes touches (its held components enter by the augmented
    /// Lagrangian, and a sliding one lags its normal force).
    fn any_between(&self) -> bool {
        (0..self.mode.len())
            .any(|c| self.scratch.at_node[c].is_none() && self.mode[c] != ContactStatus::Free)
    }

    /// Keep the saved step as the watchdog's checkpoint.
    fn keep_watch(&mut self) {
        let s = &mut self.scratch;
        s.watch.copy_from(&s.saved);
    }

    /// Make the watchdog's checkpoint the saved step again (the saved one it replaces is
    /// abandoned, so the two are swapped rather than copied).
    fn restore_watch(&mut self) {
        let s = &mut self.scratch;
        std::mem::swap(&mut s.saved, &mut s.watch);
    }

    /// Keep an accepted iterate's merit in the non-monotone test's memory (the last `memory`).
    pub(super) fn remember(&mut self, theta: f64, memory: usize) {
        let recent = &mut self.scratch.recent;
        recent.push_back(theta);
        while recent.len() > memory {
            recent.pop_front();
        }
    }
}
