//! Active-set contact: the conic program's solution fixes, per contact, whether it is free,
//! sticking or sliding; the following steps keep that status and are solved by plain Newton
//! iterations on a smooth problem, with the exact Coulomb conditions verified at convergence.
//!
//! With the status fixed, the step problem of MODEL section 3 is smooth:
//! * a touching contact (sticking or sliding) holds its gap at zero: `z = a/2` is an exact
//!   linear constraint, and the reaction at the held coordinate (the objective's gradient
//!   there) is its normal force `N`;
//! * a sticking contact also holds its tangential position at the start of the step (zero
//!   slip); the reaction there is its friction force;
//! * a sliding contact carries the dissipation `N sqrt((mu(v_f) v_f)^2 + (mu_s v_s)^2)`,
//!   smooth away from zero slip (gradient and positive semi-definite Hessian below), with `N`
//!   the reaction at the current iterate and its change along the step inside the Newton
//!   system ([`super::reactions`]; `[solver] contact_coupling = false` lags it one iterate);
//! * a free contact has no force and must keep a positive gap.
//!
//! The converged point is the exact solution of the conic step problem (the same KKT system)
//! when every normal force is non-negative, every sticking contact's friction force lies in
//! the anisotropic friction set, every sliding contact still slides and no free contact
//! reached the ground. Otherwise the integrator falls back to the conic program.
//!
//! Within a step, statuses change as the iteration goes: at a converged point whose exact
//! conditions fail, and earlier when a contact pulls, or leaves the cone, both now and after
//! the step (at most [`EARLY_CHANGES`] times per contact and step). After an early lift-off
//! or slide the Newton step is still taken (it held fixed only the coordinates the change
//! releases); after a slip reversal or a landing it is taken too, without its components at
//! the coordinates now held, as long as it still descends. A sliding contact whose slip
//! vanished sticks before the iterate is assembled. An exact repeat of iterate, statuses and early changes
//! is a cycle and goes to the conic program at once; so does a stall (the correction not
//! falling tenfold in [`STALL_WINDOW`] iterations with unchanged statuses), and an iteration
//! or status change cap. The iterations of a failed attempt count in the step's total.

use super::deferred::{Deferred, Saved};
use super::reactions::{Reactions, UNCOUPLED};
use super::status::{Mode, Statuses};
use super::{Conic, ContactFailure, ContactModel, ContactStats, Contacts, Ground};
use crate::model::Model;
use crate::newton::{Failure, HessianCache, Newton, Objective, Path, Potential};
use crate::rod::dof;
use std::time::Instant;

mod switches;

/// Iterations with unchanged contact statuses over which the active-set correction must fall
/// tenfold ([`ContactFailure::Stalled`]). On the S-start, the iterations that ran into the 40-iteration
/// cap did so either crawling (contraction 0.93 per iteration) or nearly cycling (period 3,
/// not bitwise exact); converging stretches contract by 0.3 or better. A window of 8 sent too
/// many slow but converging iterations to the (expensive) conic program at 200 elements: 8.84
/// and 8.27 iterations per step, 21 to 27 s, against 8.10 and 7.96, 18 to 21 s with 16 (two
/// runs, friction perturbed by 1e-6); at 50 and 100 elements the two do the same.
pub const STALL_WINDOW: usize = 16;

/// Converged points in a row, each with a contact leaving the friction cone, that mark a slip
/// front running along the body ([`FRONT_MARGIN`]). On the 200-element S-start such fronts
/// moved one contact per Newton iteration (38 in a row in one step, each contact 1.5 to 2 %
/// outside the cone once its neighbour slid, the whole stretch within 2 % of the cone) into
/// the 40-iteration cap. Measured (S-start it/step at 50, 100 and 200 elements; fallbacks at
/// 200; the sidewinding scene's change under a 100x tighter solve): without 3.81, 3.95, 8.10,
/// 122, 9.9e-5; 2 rounds 4.13, 4.04, 5.85, 104; 3 rounds 3.85, 3.64, 6.19, 109, 1.5e-4;
/// 4 rounds 3.82, 3.90, 6.38, 114, 1.01e-4; **6 rounds 3.81, 3.77, 6.88, 101, 9.9e-5**;
/// 8 rounds 3.81, 3.75, 7.39, 129. Fewer rounds also switch contacts of short stick-slip
/// episodes, which cost iterations at 50 elements and moved sidewinding's default-tolerance
/// result away from the tight one (the tight results agree to 1e-7).
///
/// Re-measured with the whole S-start at dt 5e-4, with the reversals
/// taken in the step, [`EARLY_CHANGES`] 4 and [`SWITCH_ROUNDS`] 3: 1 round gives 2.54, 2.99
/// and 3.66 it/step at 50, 100 and 200 elements (0, 2 and 1 fallbacks); 2 rounds 4.06 at 200
/// (0 fallbacks, with one early change per contact); 6 rounds 4.89 (1). The default was 6.
const FRONT_ROUNDS: usize = 1;

/// Sticking contacts within this fraction of the friction cone, contiguous with a contact that
/// left it at a slip front, slide with it. 0.01, 0.02, 0.03, 0.05 at 200 elements (2 rounds):
/// 5.78, 5.85, 5.87, 5.86 it/step with 133, 104, 114, 142 fallbacks (8.10 and 122 without).
/// At 6 rounds, two runs each (the file, `mu_forward` + 1e-7): 0.005 gives 6.87 and 6.88 it/step
/// with 88 and 111 fallbacks, 0.01 6.99 and 6.91 with 96 and 98, 0.02 6.88 and 6.86 with 101
/// and 133, 0.03 6.91 and 6.87 with 138 and 128: below 0.03 the differences are within the
/// trajectory's own spread.
const FRONT_MARGIN: f64 = 0.02;

/// Status changes allowed per contact and step before convergence (early lift-offs and
/// slides; a contact then changes only at converged points). Once, before: at 400 elements a
/// touchdown front lifted or slid one contact per converged point, several Newton iterations
/// each, into the 40-iteration cap. S-start at dt 5e-4 (whole scene; 1 front round, reversals
/// taken, 3 switch rounds): 200 elements 3.79, 3.78, 3.66 and 3.71 it/step for 1, 2, 4 and
/// unlimited; 400 elements over the first 2 s 5.26 it/step and 49 fallbacks with 4.
const EARLY_CHANGES: u32 = 4;

/// Status changes allowed per step, in multiples of the number of contacts (plus
/// `[solver] active_set_extra_switches`). With one multiple, the S-start's middle patch at the
/// edge of the friction cone (about 60 contacts at 200 elements, slipping by 1e-10 m per step)
/// sticks and slides again within one step, and 34 steps at 200 elements hit the cap and went
/// to the conic program; with 3, none (4.03 -> 4.06 it/step, 34 -> 0 fallbacks).
const SWITCH_ROUNDS: usize = 3;

/// The active-set contact model: each step first runs [`ActiveSet::iterate`] with the
/// statuses of the last step (guessed from the state before any conic solve); if its checks
/// fail, the conic path continues from where it stopped (at most
/// `[solver] warm_conic_iterations`), then from the step's start.
pub struct ActiveSet {
    /// The conic model: contact data, the fallback and the statistics.
    pub conic: Conic,
    /// Every contact's status.
    pub status: Statuses,
    q_init: Vec<f64>,
    /// Where a handoff started ([`ActiveSet::handoff`]).
    handoff_q: Vec<f64>,
    last_conic: bool,
    /// Iterations of the last [`ActiveSet::iterate`] (counted in the step's total also when
    /// it fails and the conic path finishes the step).
    spent: usize,
    /// The iteration's per-step state and reused storage.
    scratch: Scratch,
}

/// The per-step state of [`ActiveSet::iterate`] (counters reset at each step) and its reused
/// storage.
#[derive(Default)]
struct Scratch {
    /// Held coordinates (fixed ones, touching heights, sticking positions).
    held: Vec<bool>,
    reactions: Reactions,
    /// Objective gradient at `(x, y)` of every sticking contact (its friction force).
    tangential: Vec<[f64; 2]>,
    /// Status changes of every contact before convergence in this step (at most
    /// [`EARLY_CHANGES`] each, so that a contact at the edge of the friction cone cannot cycle).
    early: Vec<u32>,
    /// Fingerprints of the iterates within the step.
    seen: Vec<(u64, usize)>,
    /// Corrections `max(dx / a, dtheta)` since the last status change.
    progress: Vec<f64>,
    /// Contacts that left the cone at the current converged point.
    slid: Vec<usize>,
    /// The iterate and direction of a full step whose sufficient decrease is checked at the
    /// next assembly ([`Deferred`]).
    saved: Saved,
    deferred: Option<Deferred>,
    /// Iterations so far (each one assembly).
    it: usize,
    /// Status changes so far.
    switches: usize,
    /// Converged points in a row with a contact leaving the cone ([`FRONT_ROUNDS`]).
    conv_slide_rounds: usize,
    /// Whether the Hessians are projected (the exact one was found indefinite).
    project: bool,
    /// `switches` at the last fingerprint.
    fingerprinted: usize,
    /// `switches` when `progress` was last cleared.
    progress_switches: usize,
    /// The bending and twist Hessian kept over the step's iterates close together.
    hessians: HessianCache,
}

/// One active-set step: the model's parts borrowed for the iteration.
struct Step<'a, 'p> {
    m: &'a Model,
    obj: &'a Potential<'p>,
    ground: &'a Ground,
    ct: &'a mut Contacts,
    st: &'a mut Statuses,
    s: &'a mut Scratch,
    stats: &'a mut ContactStats,
    nw: &'a mut Newton,
    /// Mean weight per contact (N).
    scale: f64,
    /// Iterations and status changes allowed before the conic program takes over.
    cap: usize,
    switch_cap: usize,
}

/// What an iterate learnt at its assembly.
struct Assembled {
    /// Merit at the iterate (objective plus sliding dissipation).
    f0: f64,
    /// Largest force residual on a free coordinate, relative to `scale`.
    residual: f64,
    /// Smallest reaction and largest stick ratio (for the debug log).
    n_min: f64,
    worst_ratio: f64,
}

/// The Newton direction of an iterate and what it predicts.
struct Direction {
    /// GMRES iterations of the coupled direction ([`UNCOUPLED`]: the symmetric one).
    krylov: usize,
    /// Largest position and angle corrections.
    dx: f64,
    dth: f64,
    /// Whether the correction is below the tolerance and the forces settled.
    small: bool,
    settled: bool,
}

/// What an iteration's stage asks of the loop.
enum Next {
    /// Go on with this iterate.
    Go,
    /// Start the next iteration.
    Again,
}

impl ActiveSet {
    /// The active-set model of `m`.
    pub fn new(m: &Model) -> Self {
        let conic = Conic::new(m);
        let status = Statuses::new(&conic.ct);
        ActiveSet {
            conic,
            status,
            q_init: vec![0.0; m.ndof],
            handoff_q: Vec::new(),
            last_conic: false,
            spent: 0,
            scratch: Scratch {
                held: vec![false; m.ndof],
                hessians: HessianCache::new(m.ndof),
                ..Scratch::default()
            },
        }
    }

    /// Newton iterations with every contact's status held (touching gaps and sticking
    /// positions eliminated, their reactions the contact forces, sliding dissipation with
    /// exact derivatives). `Err`: the statuses no longer fit (or Newton failed); the caller
    /// then falls back to the conic program.
    pub fn iterate(
        &mut self,
        nw: &mut Newton,
        obj: &Potential,
        q: &mut Vec<f64>,
        cap: usize,
    ) -> Result<usize, ContactFailure> {
        let m = obj.model;
        let set = &m.solver;
        let ct = &mut self.conic.ct;
        let nc = ct.nodes.len();
        let mut step = Step {
            m,
            obj,
            ground: m.ground.as_ref().expect("a contact model needs a ground"),
            scale: ct.weight_scale(m),
            ct,
            st: &mut self.status,
            s: &mut self.scratch,
            stats: &mut self.conic.stats,
            nw,
            cap,
            switch_cap: SWITCH_ROUNDS * nc + set.active_set_extra_switches,
        };
        step.begin(q);
        let r = step.run(q);
        self.spent = self.scratch.it;
        r
    }
}

impl Step<'_, '_> {
    /// Reset the per-step state and put `q` on the statuses' constraints.
    fn begin(&mut self, q: &mut [f64]) {
        let (m, s) = (self.m, &mut *self.s);
        let nc = self.ct.nodes.len();
        s.deferred = None;
        s.early.clear();
        s.early.resize(nc, 0);
        s.held.copy_from_slice(&m.fixed);
        self.st.hold(self.ct, m, q, &mut s.held);
        self.stats.residuals.clear();
        s.switches = 0;
        s.conv_slide_rounds = 0;
        // Exact (unprojected) Hessians converge quadratically; the projected one is the
        // fallback when the exact one is not positive definite.
        s.project = false;
        s.tangential.resize(nc, [0.0; 2]);
        s.it = 0;
        // Fingerprints of the iterates (coordinates, statuses, early changes) after status
        // changes: an exact repeat is a cycle the iteration cannot leave (stick -> slide ->
        // stick of one contact whose force sits on the cone's edge), for the conic program at
        // once. Near cycles without status changes (full coupled steps while the normal forces
        // change sign from one iterate to the next; not bitwise repeats, so fingerprinting
        // every iterate caught none) are left to the stall test.
        s.seen.clear();
        s.fingerprinted = usize::MAX;
        s.progress.clear();
        s.progress_switches = 0;
        s.hessians.invalidate();
        log::debug!("  active step");
    }

    /// The iterations, until converged or failed.
    fn run(&mut self, q: &mut Vec<f64>) -> Result<usize, ContactFailure> {
        while self.s.it < self.cap {
            self.s.it += 1;
            self.before_assembly(q)?;
            let t0 = Instant::now();
            let Some(mut at) = self.assemble(q, t0)? else {
                continue;
            };
            let t1 = Instant::now();
            self.nw.stats.assembly_s += (t1 - t0).as_secs_f64();
            if let Next::Again = self.factor(t1)? {
                continue;
            }
            let t2 = Instant::now();
            self.nw.stats.factor_s += (t2 - t1).as_secs_f64();
            let mut dir = self.direction(&at)?;
            let t3 = Instant::now();
            self.nw.stats.solve_s += (t3 - t2).as_secs_f64();
            log::debug!(
                "  active it {}: dx {:.3e} dth {:.3e} N_min {:.3e} stick ratio {:.6} switches {}",
                self.s.it,
                dir.dx,
                dir.dth,
                at.n_min,
                at.worst_ratio,
                self.s.switches
            );
            if dir.small && dir.settled {
                match self.converged_switches(q)? {
                    0 => {
                        for (x, d) in q.iter_mut().zip(&self.nw.dq) {
                            *x += d;
                        }
                        self.nw.stats.line_search_s += t3.elapsed().as_secs_f64();
                        return Ok(self.s.it);
                    }
                    _ => continue,
                }
            }
            if let Next::Again = self.early_switches(q, &mut at)? {
                self.nw.stats.line_search_s += t3.elapsed().as_secs_f64();
                continue;
            }
            self.line_search(q, &at, &mut dir)?;
            self.nw.stats.line_search_s += t3.elapsed().as_secs_f64();
        }
        Err(Failure::NotConverged {
            path: Path::ActiveSet,
            iterations: self.cap,
        }
        .into())
    }

    /// Count `switched` status changes: the residual history marks them, and too many in a
    /// step fail it.
    fn count_switches(&mut self, switched: usize) -> Result<(), ContactFailure> {
        self.s.switches += switched;
        self.stats.residuals.push(f64::NAN);
        if self.s.switches > self.switch_cap {
            return Err(ContactFailure::ContactSwitches {
                iteration: self.s.it,
            });
        }
        Ok(())
    }

    /// Before an assembly: a pending deferred step resolved if a zero-slip stick would change
    /// the statuses its merit needs; sliding contacts whose slip vanished stick; a repeat of
    /// an earlier iterate with the same statuses is a cycle.
    fn before_assembly(&mut self, q: &mut [f64]) -> Result<(), ContactFailure> {
        let (m, obj, ground) = (self.m, self.obj, self.ground);
        let tol = m.solver.contact_tolerance * m.diameter;
        let nc = self.ct.nodes.len();
        let it = self.s.it;
        if let Some(d) = self.s.deferred {
            if (0..nc).any(|c| self.st.slip_vanished(self.ct, c, q, tol)) {
                self.s.deferred = None;
                let ct: &Contacts = self.ct;
                self.s
                    .saved
                    .backtrack(self.nw, self.stats, m, q, d, it, &|x| {
                        obj.value(x) + ct.dissipation(ground, x)
                    })?;
            }
        }
        // A sliding contact whose slip vanished sticks (before the assembly it changes).
        let mut switched = 0;
        for c in 0..nc {
            if self.st.slip_vanished(self.ct, c, q, tol) {
                log::debug!("  switch zero-slip {c}");
                self.stats.switches.zero_slip_sticks += 1;
                self.st.set(self.ct, m, c, Mode::Stick, q, &mut self.s.held);
                switched += 1;
            }
        }
        if switched > 0 {
            self.count_switches(switched)?;
        }
        let s = &mut *self.s;
        if s.switches != s.fingerprinted {
            s.fingerprinted = s.switches;
            let key = fingerprint(q, &self.st.mode, &s.early);
            if let Some(&(_, first)) = s.seen.iter().find(|(k, _)| *k == key) {
                return Err(ContactFailure::ContactCycle {
                    iteration: it,
                    first,
                });
            }
            s.seen.push((key, it));
        }
        Ok(())
    }

    /// Assemble the iterate: the deferred step's sufficient-decrease test (`None`: it failed
    /// and the step was backtracked), the reactions at the held coordinates, the sliding
    /// dissipation, the residual; the held coordinates fixed.
    fn assemble(
        &mut self,
        q: &mut [f64],
        t0: Instant,
    ) -> Result<Option<Assembled>, ContactFailure> {
        let (m, obj, ground) = (self.m, self.obj, self.ground);
        let set = &m.solver;
        let it = self.s.it;
        let (f0, kept) = obj.assemble_reusing(
            q,
            &mut self.nw.asm,
            self.s.project,
            &mut self.s.hessians,
            set.hessian_reuse,
        );
        if kept {
            self.nw.stats.hessian_reuses += 1;
        }
        if self.s.project {
            self.nw.stats.projected_iterations += 1;
        }
        if let Some(d) = self.s.deferred.take() {
            // The merit here, with the normal forces of the step's direction (not yet
            // updated from this assembly).
            let ft = f0 + self.ct.dissipation(ground, q);
            let noise = set.line_search_noise * d.f0.abs().max(1e-300);
            if !(ft.is_finite() && ft <= d.f0 + set.armijo * d.slope + noise) {
                let ct: &Contacts = self.ct;
                self.s
                    .saved
                    .backtrack(self.nw, self.stats, m, q, d, it, &|x| {
                        obj.value(x) + ct.dissipation(ground, x)
                    })?;
                self.nw.stats.assembly_s += t0.elapsed().as_secs_f64();
                return Ok(None);
            }
        }
        if !f0.is_finite() || self.nw.asm.grad.iter().any(|g| !g.is_finite()) {
            return Err(Failure::NonFiniteObjective {
                path: Path::ActiveSet,
                iteration: it,
            }
            .into());
        }
        let (n_min, worst_ratio) = self.held_reactions();
        let f0 = f0 + self.add_sliding(q);
        let (a, scale) = (m.diameter, self.scale);
        let mut residual: f64 = 0.0;
        for k in 0..m.ndof {
            if self.s.held[k] {
                self.nw.asm.fix(k);
            } else {
                let r = self.nw.asm.grad[k].abs() / if dof::is_edge(k) { a } else { 1.0 };
                residual = residual.max(r / scale);
            }
        }
        self.stats.residuals.push(residual);
        Ok(Some(Assembled {
            f0,
            residual,
            n_min,
            worst_ratio,
        }))
    }

    /// Reactions at the held coordinates: normal forces (those of the sliding dissipation)
    /// and sticking friction forces. Returns the smallest reaction and the largest ratio.
    fn held_reactions(&mut self) -> (f64, f64) {
        let (ct, st, s) = (&mut *self.ct, &mut *self.st, &mut *self.s);
        let force_tol = self.m.solver.contact_force_tolerance;
        let mut n_min = f64::INFINITY;
        let mut worst_ratio: f64 = 0.0;
        for c in 0..ct.nodes.len() {
            st.react[c] = 0.0;
            st.ratio[c] = 0.0;
            if st.mode[c] == Mode::Free {
                continue;
            }
            let k = dof::node(ct.nodes[c]);
            let nn = self.nw.asm.grad[k + 2];
            n_min = n_min.min(nn);
            st.react[c] = nn;
            ct.normal[c] = nn.max(0.0);
            if st.mode[c] == Mode::Stick {
                s.tangential[c] = [self.nw.asm.grad[k], self.nw.asm.grad[k + 1]];
                let (r, mag, dir) = ct.stick_ratio(self.ground, c, s.tangential[c], ct.normal[c]);
                if mag > force_tol * self.scale {
                    st.ratio[c] = r;
                    st.slip_dir[c] = dir;
                    worst_ratio = worst_ratio.max(r);
                }
            }
        }
        (n_min, worst_ratio)
    }

    /// Add the sliding contacts' dissipation to the assembly and capture the reaction rows;
    /// returns the dissipation (J).
    fn add_sliding(&mut self, q: &[f64]) -> f64 {
        let (ct, st, s) = (&*self.ct, &*self.st, &mut *self.s);
        let asm = &mut self.nw.asm;
        let nc = ct.nodes.len();
        s.reactions.begin(nc);
        for c in 0..nc {
            if st.mode[c] != Mode::Slide {
                continue;
            }
            let (g2, h3) = ct.slide_derivatives(self.ground, c, q);
            let k = dof::node(ct.nodes[c]);
            asm.grad[k] += g2[0];
            asm.grad[k + 1] += g2[1];
            asm.add_h(k, k, h3[0]);
            asm.add_h(k, k + 1, h3[1]);
            asm.add_h(k + 1, k + 1, h3[2]);
            s.reactions.set_slide(c, g2, ct.normal[c]);
        }
        let d = ct.dissipation(self.ground, q);
        s.reactions.capture(ct, &st.mode, asm);
        d
    }

    /// Factorise the assembled Hessian; an indefinite exact one is redone projected
    /// ([`Next::Again`]).
    fn factor(&mut self, t1: Instant) -> Result<Next, ContactFailure> {
        if self.s.project {
            self.nw.factor_shifted(self.m, self.s.it)?;
        } else if self.nw.factor().is_err() {
            // Indefinite: redo this iterate with the projected Hessian.
            self.s.project = true;
            self.s.it -= 1;
            self.nw.stats.factor_s += t1.elapsed().as_secs_f64();
            return Ok(Next::Again);
        }
        Ok(Next::Go)
    }

    /// The Newton direction: the symmetric solve, the sliding contacts' normal forces inside
    /// the Newton system, the predicted change of every reaction; the stall test.
    fn direction(&mut self, at: &Assembled) -> Result<Direction, ContactFailure> {
        let (m, set, it) = (self.m, &self.m.solver, self.s.it);
        let scale = self.scale;
        self.nw.solve_direction();
        let force_step = set.normal_force_tolerance * scale;
        let s = &mut *self.s;
        let krylov = if set.contact_coupling && s.reactions.coupled() {
            // GMRES until the coupling's residual is below the square of this
            // iterate's residual (so the iteration keeps its quadratic rate).
            let krylov_tol =
                scale * (1e-2 * set.normal_force_tolerance).min(at.residual * at.residual);
            s.reactions.couple(self.ct, self.nw, &s.held, krylov_tol)
        } else {
            0
        };
        let dn_step = s.reactions.predict(self.ct, &self.st.mode, &self.nw.dq);
        if self.nw.dq.iter().any(|d| !d.is_finite()) {
            return Err(Failure::NonFiniteStep {
                path: Path::ActiveSet,
                iteration: it,
            }
            .into());
        }
        let (dx, dth) = self.nw.correction_norms();
        if s.switches != s.progress_switches {
            s.progress.clear();
            s.progress_switches = s.switches;
        }
        s.progress.push((dx / m.diameter).max(dth));
        if let Some(&before) = s.progress.iter().rev().nth(STALL_WINDOW) {
            let now = *s.progress.last().unwrap();
            if now > 0.1 * before {
                return Err(ContactFailure::Stalled {
                    iteration: it,
                    now,
                    before,
                });
            }
        }
        log::debug!("  active it {it}: dN(step) {dn_step:.3e} krylov {krylov}");
        Ok(Direction {
            krylov,
            dx,
            dth,
            small: dx <= m.tolerance * m.diameter && dth <= m.tolerance,
            settled: dn_step <= force_step,
        })
    }

    /// The step along the direction: in full (its sufficient decrease deferred to the next
    /// assembly) or backtracked on the merit; the accepted point into `q`.
    fn line_search(
        &mut self,
        q: &mut Vec<f64>,
        at: &Assembled,
        dir: &mut Direction,
    ) -> Result<(), ContactFailure> {
        let (m, obj, ground) = (self.m, self.obj, self.ground);
        let a = m.diameter;
        let nw = &mut *self.nw;
        let mut slope: f64 = nw.asm.grad.iter().zip(&nw.dq).map(|(g, d)| g * d).sum();
        if slope >= 0.0 && dir.krylov > 0 && dir.krylov != UNCOUPLED {
            // The coupled direction need not descend on the merit (whose normal forces are
            // frozen at this iterate); the symmetric direction does.
            self.s.reactions.restore_symmetric(&mut nw.dq);
            dir.krylov = UNCOUPLED;
            slope = nw.asm.grad.iter().zip(&nw.dq).map(|(g, d)| g * d).sum();
        }
        // Near the solution (correction within 100 tolerances) a converged coupled direction
        // is the Newton direction of the system with the normal forces moving, not of the
        // merit below (normal forces frozen at this iterate), which can refuse it: at 200
        // elements the line search then cut every step to a quarter and Newton crawled
        // (contraction 0.75) into the iteration cap. Such steps are taken in full;
        // convergence is still judged by the correction and the predicted force change.
        let near = dir.dx <= 100.0 * m.tolerance * a && dir.dth <= 100.0 * m.tolerance;
        let full = dir.small || (dir.krylov > 0 && dir.krylov < UNCOUPLED && near);
        if !full && slope < 0.0 {
            // The full step now, its test at the next assembly. Should a coupled step fail
            // it, the backtracking runs along the symmetric direction (normal forces lagged,
            // a descent direction of this merit), not the coupled one: at 400 elements steps
            // crawled along the refused coupled direction into the iteration cap (5 % per two
            // iterations). S-start at dt 5e-4, first 2 s at 400 elements: 5.26 -> 4.99
            // it/step, 49 -> 19 fallbacks, 2 -> 1 halvings; the whole scene at 50, 100 and 200
            // elements 2.54, 2.99, 3.66 -> 2.50, 2.99, 3.71 it/step, fallbacks 0, 2, 1 -> 0,
            // 1, 0.
            let mut symmetric_slope = None;
            if dir.krylov > 0 && dir.krylov != UNCOUPLED {
                let alt = &mut self.s.saved.dq_symmetric;
                alt.resize(nw.dq.len(), 0.0);
                self.s.reactions.restore_symmetric(alt);
                for (d, &h) in alt.iter_mut().zip(&self.s.held) {
                    if h {
                        *d = 0.0;
                    }
                }
                let sl: f64 = nw.asm.grad.iter().zip(alt.iter()).map(|(g, d)| g * d).sum();
                if sl < 0.0 {
                    symmetric_slope = Some(sl);
                }
            }
            self.s.deferred = Some(Deferred {
                f0: at.f0,
                slope,
                symmetric_slope,
            });
            self.s.saved.save(q, &nw.dq);
        }
        let ct: &Contacts = self.ct;
        let take_full = full || self.s.deferred.is_some();
        let alpha = nw.backtrack(m, q, at.f0, slope, take_full, &|x| {
            obj.value(x) + ct.dissipation(ground, x)
        });
        let Some(alpha) = alpha else {
            return Err(Failure::LineSearch {
                path: Path::ActiveSet,
                iteration: self.s.it,
                slope,
            }
            .into());
        };
        if alpha < 1.0 || self.s.project || dir.krylov == UNCOUPLED {
            // Not a full Newton step of the exact linearisation (damped, projected Hessian
            // or the coupled direction not found): marked for the convergence tests.
            self.stats.residuals.push(-1.0);
        }
        std::mem::swap(q, &mut nw.trial);
        Ok(())
    }
}

/// Active-set iterations allowed after a handoff ([`ActiveSet::handoff`]).
const HANDOFF_ITERATIONS: usize = 12;

impl ActiveSet {
    /// One conic solve from where the active set stopped; its solution fixes every contact's
    /// status, and the active set resumes from it (at most [`HANDOFF_ITERATIONS`]). `Ok`: the
    /// handoff's iterations (the conic one included) when the conic solve or the resumed
    /// active set converged; `Err`: the iterations it spent, with `q` back where it started
    /// and the conic path to go on. (Three handoffs in a row before the conic path, or 24
    /// resumed iterations, were slower on the adaptive BDF2 S-start at 200 elements.)
    fn handoff(
        &mut self,
        nw: &mut Newton,
        obj: &Potential,
        q: &mut Vec<f64>,
    ) -> Result<usize, usize> {
        let m = obj.model;
        self.handoff_q.clone_from(q);
        self.conic.stats.conic_handoffs += 1;
        let spent = match self.conic.iterate(nw, obj, q, 1) {
            Ok(_) => {
                self.status.classify(&self.conic.ct, m, q);
                return Ok(1);
            }
            Err(ContactFailure::Newton(Failure::NotConverged { .. })) => {
                self.status.classify(&self.conic.ct, m, q);
                let r = self.iterate(nw, obj, q, HANDOFF_ITERATIONS.min(m.max_iterations));
                let spent = 1 + self.spent;
                match r {
                    Ok(_) => {
                        self.conic.stats.handoff_steps += 1;
                        return Ok(spent);
                    }
                    Err(why) => log::debug!("  handoff active set rejected: {why}"),
                }
                spent
            }
            Err(why) => {
                log::debug!("  handoff conic solve failed: {why}");
                1
            }
        };
        q.clone_from(&self.handoff_q);
        Err(spent)
    }
}

impl ContactModel for ActiveSet {
    fn begin_step(
        &mut self,
        m: &Model,
        q_start: &[f64],
        slip_origin: &[f64],
        v_start: &[f64],
        h: f64,
        q: &mut [f64],
    ) {
        self.conic
            .begin_step(m, q_start, slip_origin, v_start, h, q);
        if !self.status.valid {
            self.status.guess(&self.conic.ct, m, q_start, v_start, h);
        }
    }

    fn solve(
        &mut self,
        nw: &mut Newton,
        obj: &Potential,
        q: &mut Vec<f64>,
    ) -> Result<usize, ContactFailure> {
        let m = obj.model;
        if !self.status.valid {
            let it = self.conic.iterate(nw, obj, q, m.max_iterations)?;
            self.last_conic = true;
            return Ok(it);
        }
        self.q_init.copy_from_slice(q);
        // The default cap is 100 iterations (`active_set_max_iterations` and
        // `max_iterations`; 40 and 50 before): a step the active set gives up on costs a conic
        // solve and usually the conic path, about 0.25 s at 400 elements (some 500
        // active-set iterations there), while the steps that need many iterations are mostly
        // slip fronts walking one contact per iteration, which converge if let run.
        // scripts/active_set_cap.sh (record active-set-cap) measures it.
        let cap = m.max_iterations.min(m.solver.active_set_max_iterations);
        let why = match self.iterate(nw, obj, q, cap) {
            Ok(it) => {
                self.conic.stats.active_set_steps += 1;
                self.last_conic = false;
                log::debug!("  step total {it}");
                let every = m.solver.conic_certificate;
                if every > 0 && self.conic.stats.active_set_steps.is_multiple_of(every) {
                    self.conic.certify_recorded(nw, obj, q)?;
                }
                return Ok(it);
            }
            Err(why) => why,
        };
        log::debug!("  active set rejected: {why}");
        let stats = &mut self.conic.stats;
        stats.active_set_fallbacks += 1;
        match why {
            ContactFailure::ContactCycle { .. } => stats.contact_cycles += 1,
            ContactFailure::Stalled { .. } => stats.active_set_stalls += 1,
            _ => {}
        }
        let mut spent = self.spent;
        if q.iter().all(|x| x.is_finite()) {
            // Start the conic path from where the active set stopped (lifted onto the
            // ground), with its normal forces: usually a few conic solves from the solution.
            // Should that start fail, the conic path runs again from the step's start before
            // the step is rejected.
            self.conic.ct.lift(m, q);
            match self.handoff(nw, obj, q) {
                Ok(it) => {
                    self.last_conic = false;
                    log::debug!("  step total {} (handoff)", spent + it);
                    return Ok(spent + it);
                }
                Err(it) => spent += it,
            }
            let cap = m.max_iterations.min(m.solver.warm_conic_iterations);
            match self.conic.iterate(nw, obj, q, cap) {
                Ok(it) => {
                    self.last_conic = true;
                    log::debug!("  step total {} (warm conic)", spent + it);
                    return Ok(spent + it);
                }
                Err(why) => {
                    log::debug!("  warm conic start failed: {why}");
                    self.conic.stats.warm_conic_restarts += 1;
                }
            }
        }
        q.copy_from_slice(&self.q_init);
        self.conic.restore_normals();
        let it = self.conic.iterate(nw, obj, q, m.max_iterations)?;
        self.last_conic = true;
        log::debug!("  step total {} (conic)", spent + it);
        Ok(spent + it)
    }

    fn accept(&mut self, m: &Model, q: &[f64]) {
        if self.last_conic {
            self.status.classify(&self.conic.ct, m, q);
        }
    }

    fn reject(&mut self) {
        self.conic.reject();
    }

    fn normal_forces(&self, m: &Model, out: &mut [f64]) {
        self.conic.ct.normal_forces(m, out);
    }

    fn stats(&self) -> &ContactStats {
        &self.conic.stats
    }
}

/// A hash of the coordinates' bits, the contacts' statuses and which contacts already
/// changed status early (the state the rest of the iteration depends on).
fn fingerprint(q: &[f64], mode: &[Mode], early: &[u32]) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for x in q {
        x.to_bits().hash(&mut h);
    }
    for (m, e) in mode.iter().zip(early) {
        (*m as u8, *e).hash(&mut h);
    }
    h.finish()
}
