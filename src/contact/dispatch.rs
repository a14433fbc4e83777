//! The dispatcher: owns the contact set and the statistics, and hands the set to the solvers,
//! which are peers ([`SemiSmooth`], [`Conic`]).
//!
//! With `[solver] contact = "semi-smooth"` (the default) a step goes to the semi-smooth
//! Newton, with its retries; if it fails, to the conic program from where it stopped (at most
//! `[solver] warm_conic_iterations`), then from the step's start. Every `[solver]
//! conic_certificate`-th step the semi-smooth Newton solves is certified by one conic program
//! from its solution. With `"conic"` every step is the conic program's.

use super::{Conic, ContactFailure, ContactModel, ContactSet, ContactStats, SemiSmooth};
use crate::model::Model;
use crate::newton::{Newton, Potential};

/// The contact model of a run: the contact set and the solvers that take it.
pub struct Dispatcher {
    set: ContactSet,
    stats: ContactStats,
    conic: Conic,
    /// The semi-smooth Newton (`None`: the conic program alone).
    semismooth: Option<SemiSmooth>,
    /// The iterate at the step's start (the conic program's restart point).
    q_start: Vec<f64>,
}

/// How many times a step's contact points on the curve are chosen again at its solution
/// ([`ContactSet::rechoose`]) before the step is taken as it is.
pub const RECHOICES: usize = 4;

impl Dispatcher {
    /// The ground contacts of `m` with the semi-smooth Newton (conic fallback) or, if
    /// `semismooth` is false, the conic program alone.
    pub fn new(m: &Model, semismooth: bool) -> Self {
        Self::with_set(m, ContactSet::ground(m, &m.q0), semismooth)
    }

    /// The contact set `set` of `m` with the semi-smooth Newton (conic fallback) or the conic
    /// program alone.
    pub fn with_set(m: &Model, set: ContactSet, semismooth: bool) -> Self {
        Dispatcher {
            semismooth: semismooth.then(|| SemiSmooth::new(m, &set)),
            set,
            stats: ContactStats::default(),
            conic: Conic::new(m),
            q_start: vec![0.0; m.ndof],
        }
    }

    /// The contact set.
    pub fn set(&self) -> &ContactSet {
        &self.set
    }

    /// One solve of the step from `q` with the set's points as they are: the semi-smooth Newton
    /// (its conic fallback, its certificate), or the conic program alone.
    fn solve_once(
        &mut self,
        nw: &mut Newton,
        obj: &Potential,
        q: &mut Vec<f64>,
    ) -> Result<usize, ContactFailure> {
        let m = obj.model;
        let Some(ss) = &mut self.semismooth else {
            return self.conic.iterate(
                &mut self.set,
                &mut self.stats,
                nw,
                obj,
                q,
                m.max_iterations,
            );
        };
        self.q_start.copy_from_slice(q);
        match ss.solve(&mut self.set, &mut self.stats, nw, obj, q) {
            Ok(it) => {
                let every = m.solver.conic_certificate;
                if every > 0 && self.stats.semismooth_steps.is_multiple_of(every) {
                    self.conic
                        .certify_recorded(&mut self.set, &mut self.stats, nw, obj, q)?;
                }
                Ok(it)
            }
            Err((why, spent)) => self.fall_back(nw, obj, q, why, spent),
        }
    }

    /// The semi-smooth step failed (`why`, after `spent` iterations, `q` where it stopped):
    /// the conic program from there (a warm start), then from the step's start.
    fn fall_back(
        &mut self,
        nw: &mut Newton,
        obj: &Potential,
        q: &mut Vec<f64>,
        why: ContactFailure,
        spent: usize,
    ) -> Result<usize, ContactFailure> {
        let m = obj.model;
        log::debug!("  semi-smooth Newton failed: {why}");
        self.stats.semismooth_fallbacks += 1;
        let (set, stats) = (&mut self.set, &mut self.stats);
        let ss = self
            .semismooth
            .as_mut()
            .expect("a semi-smooth step fell back");
        if q.iter().all(|x| x.is_finite()) {
            set.lift(m, q);
            let cap = m.max_iterations.min(m.solver.warm_conic_iterations);
            match self.conic.iterate(set, stats, nw, obj, q, cap) {
                Ok(it) => {
                    ss.reset_forces(set, m, q);
                    return Ok(spent + it);
                }
                Err(why) => {
                    log::debug!("  warm conic start failed: {why}");
                    stats.warm_conic_restarts += 1;
                }
            }
        }
        q.copy_from_slice(&self.q_start);
        set.restore_normals();
        let it = self
            .conic
            .iterate(set, stats, nw, obj, q, m.max_iterations)?;
        ss.reset_forces(set, m, q);
        Ok(spent + it)
    }
}

impl ContactModel for Dispatcher {
    fn begin_step(
        &mut self,
        m: &Model,
        q_start: &[f64],
        slip_origin: &[f64],
        _v_start: &[f64],
        h: f64,
        q: &mut [f64],
    ) {
        // Points on the curve are chosen at the step's first iterate, the predicted end of the
        // step, where the body will lie (at the step's start: more of them chosen again).
        self.set.begin_step(m, q_start, q, slip_origin, h);
        // Start from a feasible iterate: lift predicted penetrations onto the ground.
        self.set.lift(m, q);
        if let Some(ss) = &mut self.semismooth {
            ss.begin_step(&self.set, m, h, q);
        }
    }

    fn extrapolated_start(&self) -> bool {
        self.semismooth.is_some()
    }

    fn points_at_nodes(&mut self, on: bool) -> bool {
        self.set.points_at_nodes(on)
    }

    fn solve(
        &mut self,
        nw: &mut Newton,
        obj: &Potential,
        q: &mut Vec<f64>,
    ) -> Result<usize, ContactFailure> {
        let m = obj.model;
        let mut it = self.solve_once(nw, obj, q)?;
        for _ in 0..RECHOICES {
            if !self.set.rechoose(m, q) {
                return Ok(it);
            }
            self.stats.ground_point_rechoices += 1;
            it += self.solve_once(nw, obj, q)?;
        }
        if self.set.nodes_below(m, q) {
            // Chosen again as often as allowed: the step stands as solved.
            self.stats.ground_point_rechoice_limits += 1;
        }
        Ok(it)
    }

    fn accept(&mut self, _m: &Model, _q: &[f64]) {}

    fn reject(&mut self) {
        self.set.restore_normals();
        if let Some(ss) = &mut self.semismooth {
            ss.restore();
        }
    }

    fn normal_forces(&self, m: &Model, out: &mut [f64]) {
        self.set.normal_forces(m, out);
    }

    fn started_below(&self, m: &Model, out: &mut [bool]) {
        self.set
            .mark_started_below(m, m.tolerance * m.diameter, out);
    }

    fn stats(&self) -> &ContactStats {
        &self.stats
    }
}
