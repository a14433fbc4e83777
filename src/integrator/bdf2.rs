//! Second-order backward differentiation (BDF2) with variable steps, as an incremental
//! potential.
//!
//! With the step `h = h_n`, the previous step `h_{n-1}` and their ratio `w = h / h_{n-1}`,
//! variable-step BDF2 reads `v_{n+1} = (a0 q_{n+1} + a1 q_n + a2 q_{n-1}) / h` and
//! `M (a0 v_{n+1} + a1 v_n + a2 v_{n-1}) / h = F(q_{n+1})`, with
//!
//! ```text
//! a0 = (1 + 2w) / (1 + w),   a1 = -(1 + w),   a2 = w^2 / (1 + w)
//! ```
//!
//! (`3/2, -2, 1/2` at constant steps). Eliminating `v_{n+1}` gives
//! `(a0^2 / h^2) M (q_{n+1} - qhat) = F(q_{n+1})` with the origin
//! `x_o = -(a1 q_n + a2 q_{n-1}) / a0` and the predictor
//!
//! ```text
//! qhat = x_o - (h / a0^2) (a1 v_n + a2 v_{n-1}),
//! ```
//!
//! the stationarity condition of `w_i/2 |q - qhat|_M^2 + E(q, t_{n+1})`, `w_i = a0^2 / h^2`:
//! the step stays a minimisation, with the same Newton and contact machinery as implicit
//! Euler. The velocity is `v_{n+1} = (q_{n+1} - x_o) / h'` with the effective step
//! `h' = h / a0`, so friction is consistent with the integrator: the dissipation `h' D(v)` is
//! `N mu |x - x_o|`, slip measured from `x_o` ([`Scheme::slip_origin`]). At constant steps
//! `x_o = (4 q_n - q_{n-1}) / 3` and `qhat = x_o + (2h/9)(4 v_n - v_{n-1})`.
//!
//! **Contact events.** A node that lands has its normal velocity stopped within one step, a
//! jump that no two-step formula follows: BDF2's velocity `(3 z_{n+1} - 4 z_n + z_{n-1}) / 2h`
//! at a node held on the ground after falling at speed `V` is up to `+V/2`, and the predictor
//! of the next step carries it on, so the node bounced off the ground with no restitution in
//! the model (a rod dropped from one diameter onto the ground rose 1.62 diameters at
//! `dt = 2e-3`, 0.20 at `5e-4`: `tests/contact.rs`). On the S-start this made 4x the landings and
//! lift-offs of implicit Euler, and at 200 elements it held `v_s/v_m` 1.05 % below the
//! implicit Euler limit at both 1e-3 and 5e-4 s (0.3167, 0.3168 against 0.3202). So the normal
//! coordinate `z` of a node whose BDF2 predictor goes below the ground (it may land this
//! step), or that lies on the ground while BDF2's history would lift it (the step after a
//! landing), takes an implicit Euler step instead: weight `1/h^2` ([`Scheme::euler_coordinates`]),
//! `qhat = z_n + h v_n`, `v = (z_{n+1} - z_n) / h`, and uniform motion at that velocity as its
//! history, so that the next BDF2 step extrapolates no jump. The landing is then perfectly
//! inelastic as in implicit Euler: the normal force stops the node over the landing step and the
//! next, with the friction that force carries, and the node stays down. Every other coordinate,
//! the tangential ones of the same node included, stays BDF2; a resting node's history is
//! uniform, so it is BDF2 again from the step after. At 200 elements the S-start then
//! converges toward implicit Euler's limit (0.3166, 0.3183, 0.3189 at 1e-3, 5e-4, 2.5e-4 s).
//!
//! The first step is an implicit Euler step (BDF2 needs the previous one). A step-size change
//! keeps second order through the coefficients above; a ratio `w` at or above
//! [`MAX_RATIO`] (where variable-step BDF2 loses zero-stability) restarts with an Euler step.
//! A rejected step leaves the history untouched.

use super::Scheme;
use crate::model::Model;
use crate::state::State;

/// Step ratios `h_n / h_{n-1}` at or above this restart BDF2 with an implicit Euler step:
/// variable-step BDF2 is zero-stable for ratios below `1 + sqrt 2` (Grigorieff 1983); the
/// adaptive controller grows steps by at most 2 ([`super::adaptive::GROWTH_MAX`]).
pub const MAX_RATIO: f64 = 2.4;

/// Variable-step BDF2 coefficients `(a0, a1, a2)` for the step ratio `w = h_n / h_{n-1}`.
pub fn coefficients(w: f64) -> (f64, f64, f64) {
    ((1.0 + 2.0 * w) / (1.0 + w), -(1.0 + w), w * w / (1.0 + w))
}

/// BDF2 with an implicit Euler start.
#[derive(Default)]
pub struct Bdf2 {
    /// `q_{n-1}`, `v_{n-1}` and the step that led from them to `q_n`.
    history: Option<(Vec<f64>, Vec<f64>, f64)>,
    /// `a0` of the current step when it uses BDF2, `None` for an implicit Euler step.
    a0: Option<f64>,
    /// `(a1, a2)` of the current step when it uses BDF2.
    a12: (f64, f64),
    origin: Vec<f64>,
    /// Contact normals that take an implicit Euler step in the current step (empty when the
    /// whole step is one).
    euler: Vec<usize>,
}

impl Bdf2 {
    /// The step ratio `h / h_{n-1}` when the history allows a BDF2 step of size `h`.
    fn ratio(&self, h: f64) -> Option<f64> {
        match &self.history {
            Some((_, _, hp)) if *hp > 0.0 && h / hp < MAX_RATIO => Some(h / hp),
            _ => None,
        }
    }
}

impl Scheme for Bdf2 {
    fn name(&self) -> &'static str {
        "bdf2"
    }

    fn predictor(&mut self, m: &Model, s: &State, h: f64, qhat: &mut [f64]) {
        self.origin.resize(m.ndof, 0.0);
        self.a0 = None;
        self.euler.clear();
        match (&self.history, self.ratio(h)) {
            (Some((q1, v1, _)), Some(w)) => {
                let (a0, a1, a2) = coefficients(w);
                self.a0 = Some(a0);
                self.a12 = (a1, a2);
                let c = h / (a0 * a0);
                for k in 0..m.ndof {
                    let o = -(a1 * s.q[k] + a2 * q1[k]) / a0;
                    self.origin[k] = o;
                    qhat[k] = if m.fixed[k] {
                        s.q[k]
                    } else {
                        o - c * (a1 * s.v[k] + a2 * v1[k])
                    };
                }
                // Contact normals at an event take an implicit Euler step (module doc).
                if m.ground.is_some() {
                    let floor = 0.5 * m.diameter;
                    let eps = m.solver.contact_tolerance * m.diameter;
                    for i in m.real.clone() {
                        let k = crate::rod::dof::node(i) + 2;
                        let on_floor = m.on_ground(&s.q, i);
                        if !m.fixed[k]
                            && (qhat[k] < floor - eps || (on_floor && qhat[k] > floor + eps))
                        {
                            self.euler.push(k);
                            self.origin[k] = s.q[k];
                            qhat[k] = s.q[k] + h * s.v[k];
                        }
                    }
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

    fn euler_coordinates(&self) -> &[usize] {
        &self.euler
    }

    fn inertia_weight(&self, h: f64) -> f64 {
        match self.a0 {
            Some(a0) => a0 * a0 / (h * h),
            None => 1.0 / (h * h),
        }
    }

    fn strain_origin(&self, h: f64) -> (f64, f64, f64) {
        match self.a0 {
            Some(a0) => (-self.a12.0 / a0, -self.a12.1 / a0, h / a0),
            None => (1.0, 0.0, h),
        }
    }

    fn slip_origin<'a>(&'a self, q_prev: &'a [f64]) -> &'a [f64] {
        if self.a0.is_some() {
            &self.origin
        } else {
            q_prev
        }
    }

    fn error_predictor(
        &self,
        m: &Model,
        q_prev: &[f64],
        v_prev: &[f64],
        h: f64,
        pred: &mut [f64],
    ) -> (f64, usize) {
        match (&self.history, self.a0) {
            (Some((_, v1, hp)), Some(_)) => {
                let w = h / hp;
                for k in 0..m.ndof {
                    let acc = (v_prev[k] - v1[k]) / hp;
                    pred[k] = q_prev[k] + h * v_prev[k] + 0.5 * h * h * acc;
                }
                let c_bdf = (1.0 + w) * (1.0 + w) / (6.0 * w * (1.0 + 2.0 * w));
                let c_pred = 1.0 / 6.0 + 1.0 / (4.0 * w);
                (c_bdf / (c_bdf + c_pred), 2)
            }
            _ => super::euler_predictor(m, q_prev, v_prev, h, pred),
        }
    }

    fn update(&mut self, m: &Model, q_prev: &[f64], v_prev: &[f64], h: f64, s: &mut State) {
        if let Some(a0) = self.a0 {
            let w = a0 / h;
            for k in 0..m.ndof {
                s.v[k] = w * (s.q[k] - self.origin[k]);
            }
            for &k in &self.euler {
                s.v[k] = (s.q[k] - q_prev[k]) / h;
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
        // Uniform motion before an Euler coordinate's step: the next BDF2 step extrapolates no
        // velocity jump across the contact event.
        let (_, v1, _) = self.history.as_mut().expect("set above");
        for &k in &self.euler {
            v1[k] = s.v[k];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::coefficients;

    /// The variable-step formula differentiates quadratics exactly at any ratio, and reduces to
    /// the constant-step coefficients at ratio 1.
    #[test]
    fn coefficients_are_exact_for_quadratics() {
        assert_eq!(coefficients(1.0), (1.5, -2.0, 0.5));
        for &w in &[0.3, 0.7, 1.0, 1.6, 2.2] {
            let (a0, a1, a2) = coefficients(w);
            let h = 0.1;
            let hp = h / w;
            // y(t) = 1 + 2 t + 3 t^2 at t_{n+1} = 0, t_n = -h, t_{n-1} = -h - hp: y'(0) = 2.
            let y = |t: f64| 1.0 + 2.0 * t + 3.0 * t * t;
            let d = (a0 * y(0.0) + a1 * y(-h) + a2 * y(-h - hp)) / h;
            assert!((d - 2.0).abs() < 1e-12, "ratio {w}: {d}");
        }
    }
}
