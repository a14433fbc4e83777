//! The core's seams are real: a time integrator and a contact model written here, outside the
//! crate, plug into the implicit stepper through the public traits ([`Scheme`],
//! [`ContactModel`]) and run through the one run loop ([`sim::drive`]).
// Index loops over dof indices read as the math does.
#![allow(clippy::needless_range_loop)]
mod common;

use common::model;
use slither::contact::ContactModel;
use slither::integrator::{Integrator, Natural, Scheme, Stepper};
use slither::model::Model;
use slither::newton::{Newton, Objective, Potential};
use slither::rod::dof;
use slither::sim::{drive, Schedule};
use slither::state::State;
use std::time::Instant;

/// Implicit Euler written outside the crate.
struct ToyEuler;

impl Scheme for ToyEuler {
    fn name(&self) -> &'static str {
        "toy-euler"
    }
    fn predictor(&mut self, m: &Model, s: &State, h: f64, qhat: &mut [f64]) {
        for k in 0..m.ndof {
            qhat[k] = if m.fixed[k] {
                s.q[k]
            } else {
                s.q[k] + h * s.v[k]
            };
        }
    }
    fn inertia_weight(&self, h: f64) -> f64 {
        1.0 / (h * h)
    }
    fn update(&mut self, m: &Model, q_prev: &[f64], _v: &[f64], h: f64, s: &mut State) {
        for k in 0..m.ndof {
            s.v[k] = (s.q[k] - q_prev[k]) / h;
        }
    }
}

/// A quasi-static "integrator": no inertia (`w = 0`), every step is the equilibrium at the
/// step's loads; velocities are finite differences.
struct QuasiStatic;

impl Scheme for QuasiStatic {
    fn name(&self) -> &'static str {
        "quasi-static"
    }
    fn predictor(&mut self, m: &Model, s: &State, _h: f64, qhat: &mut [f64]) {
        qhat[..m.ndof].copy_from_slice(&s.q);
    }
    fn inertia_weight(&self, _h: f64) -> f64 {
        0.0
    }
    fn update(&mut self, m: &Model, q_prev: &[f64], _v: &[f64], h: f64, s: &mut State) {
        for k in 0..m.ndof {
            s.v[k] = (s.q[k] - q_prev[k]) / h;
        }
    }
}

const SWING: &str = "[rod]\nlength = 1.0\ndiameter = 0.02\nelements = 20\ndensity = 1000.0\n\
    bending_stiffness = 50.0\nclamp = \"tail\"\n[gravity]\ng = 9.81\n\
    [time]\ndt = 5e-3\nduration = 0.2\n[output]\ninterval = 0.05\n";

fn run(m: &Model, integ: &mut dyn Stepper, steps: usize) -> slither::sim::Outcome {
    drive(
        m,
        integ,
        Schedule::fixed(m.dt, steps),
        Instant::now(),
        &mut |_| {},
        &mut |_| {},
    )
}

#[test]
fn a_time_integrator_written_outside_the_crate_runs_through_the_public_trait() {
    let m = model(SWING);
    let mut builtin = Integrator::new(&m, Box::new(Natural));
    let mut toy = Integrator::with_scheme(&m, Box::new(Natural), Box::new(ToyEuler));
    let a = run(&m, &mut builtin, 40);
    let b = run(&m, &mut toy, 40);
    assert!(a.error.is_none() && b.error.is_none());
    // The same method written twice: the same numbers, and the rod did move.
    assert_eq!(a.state.q, b.state.q);
    assert_eq!(a.stats.newton_iterations, b.stats.newton_iterations);
    let tip = dof::node(m.real.start) + 2;
    assert!(m.q0[tip] - a.state.q[tip] > 1e-3);
}

#[test]
fn a_quasi_static_scheme_reaches_the_cantilever_sag_each_step() {
    let m = model(SWING);
    let mut qs = Integrator::with_scheme(&m, Box::new(Natural), Box::new(QuasiStatic));
    let o = run(&m, &mut qs, 2);
    assert!(o.error.is_none(), "{:?}", o.error);
    // Equilibrium under gravity: tip sag q L^4 / (8 B), q = rho A g (discretisation 0.1 %).
    let q = m.line_density() * 9.81;
    let sag = q * m.length.powi(4) / (8.0 * m.bend);
    let tip = dof::node(m.real.start) + 2;
    let got = m.q0[tip] - o.state.q[tip];
    assert!((got / sag - 1.0).abs() < 5e-3, "sag {got} vs {sag}");
    // Inertia matters: implicit Euler's first steps are far from the static sag.
    let mut dynamic = Integrator::new(&m, Box::new(Natural));
    let d = run(&m, &mut dynamic, 2);
    let got_dyn = m.q0[tip] - d.state.q[tip];
    assert!(got_dyn < 0.5 * sag, "dynamic sag {got_dyn} vs static {sag}");
}

/// A frictionless hard floor written outside the crate: nodes at or below the floor are held
/// on it (their height eliminated from Newton's system), and the reaction at a held height is
/// its normal force.
struct Frictionless {
    held: Vec<bool>,
    normal: Vec<f64>,
}

impl ContactModel for Frictionless {
    fn begin_step(
        &mut self,
        m: &Model,
        _q_start: &[f64],
        _slip_origin: &[f64],
        _v_start: &[f64],
        _h: f64,
        q: &mut [f64],
    ) {
        self.held.copy_from_slice(&m.fixed);
        for i in m.real.clone() {
            let k = dof::node(i) + 2;
            if q[k] <= 0.5 * m.diameter {
                q[k] = 0.5 * m.diameter;
                self.held[k] = true;
            }
        }
    }
    fn solve(
        &mut self,
        newton: &mut Newton,
        obj: &Potential,
        q: &mut Vec<f64>,
    ) -> Result<usize, slither::contact::ContactFailure> {
        let m = obj.model;
        let mut o = *obj;
        let it = newton.minimize(m, &mut o, q, &self.held, m.max_iterations)?;
        // Reactions: the objective's gradient at the held heights.
        o.assemble(q, &mut newton.asm, false);
        for (r, i) in m.real.clone().enumerate() {
            let k = dof::node(i) + 2;
            self.normal[r] = if self.held[k] {
                newton.asm.grad[k].max(0.0)
            } else {
                0.0
            };
        }
        Ok(it)
    }
    fn accept(&mut self, _m: &Model, _q: &[f64]) {}
    fn reject(&mut self) {}
    fn normal_forces(&self, _m: &Model, out: &mut [f64]) {
        out.copy_from_slice(&self.normal);
    }
}

const SLIDE: &str = "[rod]\nlength = 1.0\ndiameter = 0.02\nelements = 20\ndensity = 1000.0\n\
    bending_stiffness = 1e-2\n[initial]\nvelocity = [0.5, 0.0, 0.0]\n[gravity]\ng = 9.81\n\
    [ground]\nmu_forward = 0.11\nmu_backward = 0.14\nmu_sideways = 0.2\n\
    [time]\ndt = 1e-3\nduration = 0.1\n";

#[test]
fn a_contact_model_written_outside_the_crate_replaces_coulomb_friction() {
    let m = model(SLIDE);
    let mut toy = Integrator::new(&m, Box::new(Natural));
    toy.set_contact(Some(Box::new(Frictionless {
        held: vec![false; m.ndof],
        normal: vec![0.0; m.real.len()],
    })));
    let o = run(&m, &mut toy, 100);
    assert!(o.error.is_none(), "{:?}", o.error);
    // Frictionless: the rod keeps its speed, stays on the floor, the floor carries its weight.
    let v = o.state.node_velocity(m.real.start + 10);
    assert!((v[0] - 0.5).abs() < 1e-9 && v[2].abs() < 1e-12, "{v:?}");
    assert!(o.max_penetration <= 1e-15);
    let weight = m.total_mass() * 9.81;
    let n: f64 = o.frames.last().unwrap().normal.iter().sum();
    assert!(
        (n / weight - 1.0).abs() < 1e-6,
        "normal {n} vs weight {weight}"
    );
    // The built-in Coulomb contact decelerates the same rod by mu_f g.
    let mut coulomb = Integrator::new(&m, Box::new(Natural));
    let c = run(&m, &mut coulomb, 100);
    let vc = c.state.node_velocity(m.real.start + 10)[0];
    assert!((vc - (0.5 - 0.11 * 9.81 * 0.1)).abs() < 1e-3, "{vc}");
}
