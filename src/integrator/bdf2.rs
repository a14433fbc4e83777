//! Second-order backward differentiation (BDF2) as an incremental potential.
//!
//! With constant steps `h`, BDF2 reads `v_{n+1} = (3 q_{n+1} - 4 q_n + q_{n-1}) / (2h)` and
//! `M (3 v_{n+1} - 4 v_n + v_{n-1}) / (2h) = F(q_{n+1})`. Eliminating `v_{n+1}` gives
//! `(9 / (4 h^2)) M (q_{n+1} - qhat) = F(q_{n+1})` with
//!
//! ```text
//! qhat = (4 q_n - q_{n-1}) / 3 + (2h / 9) (4 v_n - v_{n-1}),
//! ```
//!
//! the stationarity condition of `w/2 |q - qhat|_M^2 + E(q, t_{n+1})`, `w = 9 / (4 h^2)`: the
//! step stays a minimisation, with the same Newton and contact machinery as implicit Euler.
//! The velocity is `v_{n+1} = (q_{n+1} - x_o) / h'` with the effective step `h' = 2h/3` and
//! the origin `x_o = (4 q_n - q_{n-1}) / 3`, so friction is consistent with the integrator:
//! the dissipation `h' D(v)` is `N mu |x - x_o|`, slip measured from `x_o`
//! ([`Scheme::slip_origin`]).
//!
//! BDF2 needs the previous step: the first step, and every step whose size differs from the
//! previous one (after a halving), is an implicit Euler step (the usual start; variable-step
//! BDF2 coefficients are not used). A rejected step leaves the history untouched.

use super::Scheme;
use crate::model::Model;
use crate::state::State;

/// BDF2 with an implicit Euler start.
#[derive(Default)]
pub struct Bdf2 {
    /// `q_{n-1}`, `v_{n-1}` and the step that led from them to `q_n`.
    history: Option<(Vec<f64>, Vec<f64>, f64)>,
    /// Whether the current step uses BDF2 (else implicit Euler).
    second_order: bool,
    origin: Vec<f64>,
}

impl Bdf2 {
    fn uses_history(&self, h: f64) -> bool {
        matches!(&self.history, Some((_, _, hp)) if (hp - h).abs() <= 1e-12 * h)
    }
}

impl Scheme for Bdf2 {
    fn name(&self) -> &'static str {
        "bdf2"
    }

    fn predictor(&mut self, m: &Model, s: &State, h: f64, qhat: &mut [f64]) {
        self.second_order = self.uses_history(h);
        self.origin.resize(m.ndof, 0.0);
        match (&self.history, self.second_order) {
            (Some((q1, v1, _)), true) => {
                for k in 0..m.ndof {
                    let o = (4.0 * s.q[k] - q1[k]) / 3.0;
                    self.origin[k] = o;
                    qhat[k] = if m.fixed[k] {
                        s.q[k]
                    } else {
                        o + 2.0 * h / 9.0 * (4.0 * s.v[k] - v1[k])
                    };
                }
            }
            _ => {
                for k in 0..m.ndof {
                    self.origin[k] = s.q[k];
                    qhat[k] = if m.fixed[k] {
                        s.q[k]
                    } else {
                        s.q[k] + h * s.v[k]
                    };
                }
            }
        }
    }

    fn inertia_weight(&self, h: f64) -> f64 {
        if self.second_order {
            9.0 / (4.0 * h * h)
        } else {
            1.0 / (h * h)
        }
    }

    fn slip_origin<'a>(&'a self, q_prev: &'a [f64]) -> &'a [f64] {
        if self.second_order {
            &self.origin
        } else {
            q_prev
        }
    }

    fn update(&mut self, m: &Model, q_prev: &[f64], v_prev: &[f64], h: f64, s: &mut State) {
        if self.second_order {
            let w = 1.5 / h;
            for k in 0..m.ndof {
                s.v[k] = w * (s.q[k] - self.origin[k]);
            }
        } else {
            for k in 0..m.ndof {
                s.v[k] = (s.q[k] - q_prev[k]) / h;
            }
        }
        match &mut self.history {
            Some((q1, v1, hp)) => {
                q1.copy_from_slice(q_prev);
                v1.copy_from_slice(v_prev);
                *hp = h;
            }
            None => self.history = Some((q_prev.to_vec(), v_prev.to_vec(), h)),
        }
    }
}
