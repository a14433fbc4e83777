//! Every bundled problem file loads and runs over a short horizon; solver statistics of the
//! bundled scenes are pinned so that a silent slowdown (more Newton iterations or conic
//! solves per step) fails here.
mod common;

use slither::integrator::Natural;
use slither::model::Model;
use slither::problem::{self, Mode};
use slither::{design, sim};
use std::path::Path;

#[test]
fn every_bundled_problem_runs_over_a_short_horizon() {
    let mut seen = 0;
    let mut studies = 0;
    for entry in std::fs::read_dir("problems").unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        // Study files (optimiser, phase diagram) name a base problem; they must load, and their
        // base is one of the problems checked here.
        let text = std::fs::read_to_string(&path).unwrap();
        let table: toml::Table = toml::from_str(&text).unwrap();
        if table.contains_key("study") {
            design::load_study(&path).unwrap_or_else(|e| panic!("{e}"));
            studies += 1;
            continue;
        }
        if table.contains_key("phase") {
            design::phase::load(&path).unwrap_or_else(|e| panic!("{e}"));
            studies += 1;
            continue;
        }
        let p = problem::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let mut m = Model::new(&p);
        if m.mode == Mode::Dynamic {
            m.duration = m.duration.min(50.0 * m.dt);
        }
        let o = sim::run(&m, Box::new(Natural), &mut |_| {}, &mut |_| {});
        assert!(o.error.is_none(), "{}: {:?}", path.display(), o.error);
        assert!(
            o.max_strain < 1e-3,
            "{}: strain {}",
            path.display(),
            o.max_strain
        );
        let newton = o.stats.newton_iterations as f64 / o.stats.steps as f64;
        let conic = o.stats.contact.conic_solves as f64 / o.stats.steps as f64;
        println!(
            "{}: {} steps, {newton:.2} Newton it/step, {conic:.2} conic solves/step, {} halvings",
            path.display(),
            o.stats.steps,
            o.stats.step_halvings
        );
        assert_eq!(o.stats.step_halvings, 0, "{}", path.display());
        if m.ground.is_some() {
            // Pinned: straight sliding and inclined scenes need one conic solve per step.
            assert!(
                conic <= 1.05,
                "{}: {conic} conic solves per step",
                path.display()
            );
        }
        seen += 1;
    }
    assert!(seen >= 3);
    assert!(studies >= 2);
}

#[test]
fn static_cantilever_needs_few_newton_iterations() {
    let p = problem::load(Path::new("problems/cantilever_sag.toml")).unwrap();
    let m = Model::new(&p);
    let o = sim::run(&m, Box::new(Natural), &mut |_| {}, &mut |_| {});
    assert!(
        o.stats.newton_iterations <= 8,
        "{} Newton iterations",
        o.stats.newton_iterations
    );
}

/// Pinned: when the S-start lifts its bends, contacts that start pulling are freed by the
/// active-set path's Coulomb check. (A normal-force test that compared the clamped force with
/// the raw pulling reaction never settled, so every lift-off step used to fall back to the
/// conic program: 99 fallbacks in the first 1.2 s, 3.9 times the wall time.)
#[test]
fn s_start_lift_off_stays_on_the_active_set_path() {
    let o = s_start_until(0.3);
    println!(
        "{} steps, {} active-set steps, {} fallbacks, {} conic solves",
        o.stats.steps,
        o.stats.contact.active_set_steps,
        o.stats.contact.active_set_fallbacks,
        o.stats.contact.conic_solves
    );
    assert_eq!(o.stats.contact.active_set_fallbacks, 0);
}

/// Pinned: a step that leaves the active-set path (here a contact on the friction cone's
/// boundary, first at t = 1.22 s) continues with the conic program from where the active set
/// stopped, so it needs a few conic solves, not a whole Newton solve from the step's start
/// (40 solves for 19 fallbacks in the first 1.5 s; 227 when each started afresh; with the
/// normal forces inside the Newton system, 4 fallbacks in the first 1.5 s, so the test runs
/// to 2.5 s). With the early status changes' step taken and `tolerance` 5e-6: 7 fallbacks
/// and 22 conic solves, five fallbacks needing 1 to 4 solves and two (whose active-set
/// statuses were far from the solution's, 0.18 a away) 7 each: the bound is 4 solves per
/// fallback on average (a fresh start needs about 12), and no warm start may fail. With the
/// coupled direction by GMRES, stalls sent to the conic program after 16 iterations without a
/// tenfold fall of the correction, and `warm_conic_iterations` 20: 6 fallbacks and 28 conic
/// solves, four needing 1 solve, one 6 and one 18 (a step the active set stalls on, where the
/// conic path's normal-force fixed point contracts by 0.57 per iteration; with the old cap of
/// 8 its warm start failed and the step took 8 + 17 solves). The bound is 5 solves per
/// fallback on average (loosened from 4 for that step), and no warm start may fail.
#[test]
fn s_start_fallbacks_start_the_conic_path_near_the_solution() {
    let o = s_start_until(2.5);
    let (fb, conic) = (
        o.stats.contact.active_set_fallbacks,
        o.stats.contact.conic_solves,
    );
    println!(
        "{fb} fallbacks, {conic} conic solves, {} halvings",
        o.stats.step_halvings
    );
    // Re-pinned after the contact rewrite (reversals and landings taken in the step, early
    // status changes, one front round): 4 fallbacks and 29 conic solves, where there were 6
    // and 28. The easy fallbacks are gone; the ones left are the hard steps (one of them
    // alone needed 18 solves before), so the pin bounds the total cost of the fallback path
    // (28 before, 29 now; 32 leaves room for another machine's round-off) and still asks the
    // scene to exercise it.
    assert!(fb >= 1, "the scene must exercise the fallback: {fb}");
    assert!(conic <= 32, "{conic} conic solves for {fb} fallbacks");
    assert_eq!(o.stats.contact.warm_conic_restarts, 0);
    assert_eq!(o.stats.step_halvings, 0);
}

/// The S-start on 50 elements with implicit Euler at 2e-3 s ([`common::s_start_coarse`]), run
/// to `t` seconds.
fn s_start_until(t: f64) -> sim::Outcome {
    let p = active_set(common::s_start_coarse());
    let mut m = Model::new(&p);
    m.duration = t;
    let o = sim::run_gait(&m, p.solver.integrator, &mut |_| {}, &mut |_| {}).unwrap();
    assert!(o.error.is_none(), "{:?}", o.error);
    o
}

/// `p` with the active-set contact solve (the default before the semi-smooth Newton): the
/// tests of its own path and the pins of its statistics run it explicitly.
fn active_set(mut p: problem::Problem) -> problem::Problem {
    p.solver.contact = problem::ContactKind::ActiveSet;
    p
}

/// Run a gait problem to its end: the outcome (with its statistics printed), Newton
/// iterations per step and v_s/v_m.
fn whole_run(p: &problem::Problem) -> (sim::Outcome, f64, f64) {
    let m = Model::new(p);
    let o = sim::run_gait(&m, p.solver.integrator, &mut |_| {}, &mut |_| {}).unwrap();
    assert!(o.error.is_none(), "{:?}", o.error);
    let st = &o.stats;
    let per_step = st.newton_iterations as f64 / st.steps as f64;
    println!(
        "{} steps, {per_step:.3} Newton it/step, {} conic solves, {} fallbacks, {} halvings",
        st.steps, st.contact.conic_solves, st.contact.active_set_fallbacks, st.step_halvings
    );
    let v = slither::observe::of_outcome(&m, &o).v_s_over_v_m;
    (o, per_step, v)
}

/// Pinned: the whole S-start on 50 elements with implicit Euler at 2e-3 s
/// ([`common::s_start_coarse`], the bundled file's mesh and step until it moved to 100
/// elements and BDF2), with the default stopping thresholds (`[solver] tolerance` 1e-5,
/// `normal_force_tolerance` 1e-3) measured 6.87 Newton iterations per step, 36 conic solves
/// and 23 fallbacks in 1786 steps, no halving, v_s/v_m 0.30309 (0.30309 also with both
/// thresholds 100 times tighter); with the sliding contacts' normal forces inside the Newton
/// system and the closed-form stencils, 4.72 iterations per step, 28 conic solves and 20
/// fallbacks; with a slide started at 1e-8 a instead of 1e-6 a, 4.22, 14 and 7. Counting
/// the iterations of active-set attempts that fell back (not counted before) and taking the
/// Newton step after an early lift-off or slide instead of discarding it: 3.96 iterations per
/// step, 22 conic solves and 8 fallbacks (less wall time: 8 more conic solves against about
/// 470 fewer iterations); with `tolerance` 5e-6 instead of 1e-5 (so that a 100x tighter
/// solve moves every bundled scene's v_s/v_m by less than 1e-4), 4.04, 22 and 7. With the
/// coupled direction solved by GMRES instead of fixed-point sweeps (which failed to contract on
/// 8.7 % of the iterates, leaving them linear), vanished slips stuck before the assembly
/// instead of after it, and stalls sent to the conic program:
/// 3.81, 28 and 6 (three runs with friction perturbed by 1e-6: 3.80 to 3.81). More than 4
/// iterations per step (the target), or a storm of fallbacks, fails here; the conic bound
/// allows for the stalled step's 18 solves (see the warm-start test).
///
/// Regression pin (not a physics check: a slower or differently converging solver fails it,
/// a correct one with other statistics may too). Tolerances: the iteration bound is the
/// target (4 per step; measured 3.80 to 3.81 over three runs with friction perturbed by 1e-6,
/// which stands in for another machine's round-off: 5 % margin); v_s/v_m at 1e-4, because a
/// 100x tighter solve moves it by less than that; the bounds should survive a different
/// machine. The values are re-pinned by the lead after the contact and accuracy work, not
/// here.
#[test]
fn pin_s_start_newton_and_contact_statistics() {
    let p = active_set(common::s_start_coarse());
    let (o, per_step, v) = whole_run(&p);
    let st = &o.stats;
    assert_eq!(st.steps, 1786);
    assert!(per_step <= 4.0, "{per_step} Newton iterations per step");
    assert!(
        st.contact.conic_solves <= 30,
        "{} conic solves",
        st.contact.conic_solves
    );
    assert!(
        st.contact.active_set_fallbacks as f64 <= 0.006 * st.steps as f64,
        "{} fallbacks",
        st.contact.active_set_fallbacks
    );
    assert_eq!(st.step_halvings, 0);
    // The stall test sends the crawling steps (contraction 0.75 to 0.93 per iteration) to the
    // conic program before the 40-iteration cap.
    assert!(
        st.contact.active_set_stalls >= 1,
        "{} stalls",
        st.contact.active_set_stalls
    );
    assert!((v / 0.30309 - 1.0).abs() < 1e-4, "v_s/v_m {v}");
}

/// Pinned: the bundled S-start as the file runs it (100 elements, BDF2 at fixed steps of
/// 3.6e-3 s). Four runs (the file and `mu_forward` raised by 1e-6, 2e-6 and 3e-6, which stand
/// in for another machine's round-off) measured 993 steps, 8235 to 8486 Newton iterations
/// (8.29 to 8.55 per step: BDF2's large steps cost more iterations than implicit Euler's small
/// ones above), 4 to 7 conic fallbacks, no halving, and v_s/v_m 0.31755 to 0.31760 (0.7 to
/// 0.9 % below the converged 0.3197 to 0.3205).
///
/// Regression pin: iterations per step at most 9.0 (5 % above the largest run), fallbacks on
/// at most 1.4 % of the steps (twice the largest run), v_s/v_m within 1e-3 relative (the runs
/// spread 2e-4).
#[test]
fn pin_bundled_s_start_statistics() {
    let p = active_set(problem::load(Path::new("problems/s_start.toml")).unwrap());
    assert_eq!(p.solver.integrator, problem::IntegratorKind::Bdf2);
    assert!(!p.time.adaptive);
    let (o, per_step, v) = whole_run(&p);
    let st = &o.stats;
    assert_eq!(st.steps, 993);
    assert!(per_step <= 9.0, "{per_step} Newton iterations per step");
    assert!(
        st.contact.active_set_fallbacks as f64 <= 0.014 * st.steps as f64,
        "{} fallbacks",
        st.contact.active_set_fallbacks
    );
    assert_eq!(st.step_halvings, 0);
    assert!((v / 0.31758 - 1.0).abs() < 1e-3, "v_s/v_m {v}");
}

/// Pinned: the S-start at 100 elements and dt 1e-3 (the mesh where v_s/v_m is within 0.3 %
/// of 200 elements) stays on the active-set path: with a slide started at 1e-6 a, 397 of its
/// 3572 steps fell back to the conic program (contacts on the cone's edge cycling between
/// sticking and sliding) and it took 11 times the 50-element wall time; with 1e-8 a, 3
/// fallbacks and 4.77 Newton iterations per step; with the early step taken, cycles sent to
/// the conic program when detected and the fallen-back iterations counted, 6 and 4.33; with
/// `tolerance` 5e-6, 6 and 4.43; with the coupled direction by GMRES, vanished slips stuck
/// before the assembly and stalls detected, 6 and 3.95 (three runs with friction perturbed by
/// 1e-6: 3.95 to 3.96); with slip fronts slid together (`contact::active`, six converged
/// points in a row with a contact leaving the cone), 5 to 8 and 3.72 to 3.77 over four runs
/// (the bound leaves 3 % for rounding differences between machines, and fails without the
/// front rule).
///
/// Re-pinned when the active set's iteration cap went from 40 to 100 (`[solver]
/// active_set_max_iterations` 40 -> 100 and `max_iterations` 50 -> 100): steps that gave up
/// after 40 iterations now run on, and some of them into the status-change cap or a cycle
/// instead. Four runs (the file and `mu_forward` raised by 1e-6, 2e-6 and 3e-6) measured 3.80
/// to 3.88 Newton iterations per step and 3 to 9 fallbacks with the cap at 40, and 3.75 to
/// 4.00 per step and 3 to 21 fallbacks (0.6 % of the 3572 steps) with 100, in the same wall
/// time (1.84 and 1.89 s on average); at 400 elements the larger cap takes 40 to 60 % less
/// wall time (record active-set-cap).
///
/// Regression pin: iterations per step 3 % above the largest run, fallbacks on at most 1.2 %
/// of the steps (twice the largest run; the storm above was 11 %); v_s/v_m within 1 % of the
/// value the fast-Newton work recorded (0.3149; the 100-element mesh is within 0.3 % of 200
/// elements, so 1 % catches a change of the physics, not of the solver).
#[test]
fn pin_s_start_at_100_elements_has_no_fallback_storm() {
    let mut p = active_set(common::s_start_coarse());
    p.rod.elements = 100;
    p.time.dt = Some(1e-3);
    let (o, per_step, v) = whole_run(&p);
    let st = &o.stats;
    assert!(per_step <= 4.12, "{per_step} Newton iterations per step");
    // Its fallbacks were mostly stick-slide cycles caught by the exact-repeat test (5 of 6)
    // before the contact rewrite; after it, 0 cycles of 5 fallbacks (re-pinned: a cycle is
    // still counted as a fallback, never beside one).
    assert!(
        st.contact.contact_cycles <= st.contact.active_set_fallbacks,
        "{} cycles of {} fallbacks",
        st.contact.contact_cycles,
        st.contact.active_set_fallbacks
    );
    assert!(
        st.contact.active_set_fallbacks as f64 <= 0.012 * st.steps as f64,
        "{} fallbacks",
        st.contact.active_set_fallbacks
    );
    assert_eq!(st.step_halvings, 0);
    // Within 1 % of the value the fast-Newton issue recorded (0.3149).
    assert!((v / 0.3149 - 1.0).abs() < 0.01, "v_s/v_m {v}");
}

/// Pinned: the S-start on 50 elements ([`common::s_start_coarse`]) with `integrator = "bdf2"`
/// and `adaptive = true` at the default tolerance, from a first step of 2e-3 s. With inelastic
/// BDF2 landings and the default 5e-6 six runs (the file and `mu_forward` raised by 1e-6 to
/// 5e-6) measured v_s/v_m 0.30778 to 0.30835, -0.16 % to +0.02 % from implicit Euler at
/// 3.125e-5 s (0.30829), in 3752 to 3802 accepted steps with 566 to 598 rejected and 3.72 to
/// 3.76 Newton iterations per accepted step. A
/// looser default (3e-5 gives +3.0 %), a lost error estimate (more steps), or landings that
/// bounce again fail here.
///
/// Regression pin: the tolerances span the six perturbed runs above (which stand in for
/// another machine's round-off) with margin: v_s/v_m 1 % (the runs spread 0.2 %), accepted
/// steps 3500 to 4100 (runs 3752 to 3802), rejected <= 700 (566 to 598). Re-pinned by the
/// lead after the contact and accuracy work, not here.
#[test]
fn pin_adaptive_bdf2_s_start_at_the_default_tolerance() {
    let mut p = active_set(common::s_start_coarse());
    p.solver.integrator = problem::IntegratorKind::Bdf2;
    p.time.adaptive = true;
    assert!(
        p.time.error_tolerance.is_none(),
        "the file sets no tolerance"
    );
    let (o, per_step, v) = whole_run(&p);
    let steps = &o.steps;
    println!(
        "{} accepted, {} rejected, v_s/v_m {v}",
        steps.accepted, steps.rejected
    );
    assert!((v / 0.30829 - 1.0).abs() < 0.01, "v_s/v_m {v}");
    assert!(
        (3500..=4100).contains(&steps.accepted),
        "{} accepted steps",
        steps.accepted
    );
    assert!(steps.rejected <= 700, "{} rejected", steps.rejected);
    assert!(per_step <= 3.9, "{per_step} Newton iterations per step");
}

/// A step the active set gives up on takes one conic solve, whose solution fixes every
/// contact's status, and the active set resumes from there (the handoff). Forced here by an
/// iteration cap of 2, so that most lift-off and slip-front steps of the S-start's first
/// 0.5 s give up: the handoff must solve most of them (the conic path finishing the rest), and
/// the trajectory must be the default run's, because both solve the same step problems to the
/// same tolerance (`[solver] tolerance` 5e-6 of `a` per step: over the 250 steps the bound
/// below is 1e-3 a, 200 times the per-step tolerance, on any node).
#[test]
fn a_handoff_resumes_the_active_set_from_one_conic_solve() {
    let p = active_set(common::s_start_coarse());
    let run = |cap: usize| {
        let mut p = p.clone();
        p.solver.active_set_max_iterations = cap;
        let mut m = Model::new(&p);
        m.duration = 0.5;
        let o = sim::run_gait(&m, p.solver.integrator, &mut |_| {}, &mut |_| {}).unwrap();
        assert!(o.error.is_none(), "{:?}", o.error);
        (m, o)
    };
    let (m, forced) = run(2);
    let (_, free) = run(p.solver.active_set_max_iterations);
    let c = &forced.stats.contact;
    println!(
        "forced: {} steps, {} fallbacks, {} handoffs, {} handoff steps, {} conic solves, {} warm restarts",
        forced.stats.steps,
        c.active_set_fallbacks,
        c.conic_handoffs,
        c.handoff_steps,
        c.conic_solves,
        c.warm_conic_restarts
    );
    assert!(c.active_set_fallbacks >= 20, "the cap must force fallbacks");
    assert_eq!(c.conic_handoffs, c.active_set_fallbacks);
    assert!(
        2 * c.handoff_steps > c.conic_handoffs,
        "{} of {} handoffs converged",
        c.handoff_steps,
        c.conic_handoffs
    );
    assert_eq!(forced.stats.step_halvings, 0);
    let a = m.diameter;
    let worst = forced
        .state
        .q
        .iter()
        .zip(&free.state.q)
        .enumerate()
        .filter(|(k, _)| !slither::rod::dof::is_edge(*k))
        .map(|(_, (x, y))| (x - y).abs() / a)
        .fold(0.0, f64::max);
    println!("largest node difference {worst:.3e} a");
    assert!(worst < 1e-3, "{worst} a");
}

/// Pinned: the default contact solve, the semi-smooth Newton, on the bundled S-start (100
/// elements, BDF2 at 3.6e-3 s), the 50-element one (implicit Euler at 2e-3 s) and the
/// 50-element one with adaptive BDF2 at the default tolerance. Four runs of each (the files
/// and `mu_forward` raised by 1e-6, 2e-6 and 3e-6, which stand in for another machine's
/// round-off) measured 7.15, 3.37 and 4.87 to 4.91 Newton iterations per step (the adaptive
/// runs 3714 to 3775 accepted steps), no conic fallback and no halving, and v_s/v_m 0.3177,
/// 0.3031 and 0.3088 to 0.3091 (the active set's pins above: 0.31758, 0.30309 and 0.30778 to
/// 0.30835).
///
/// Regression pin: iterations per step 5 % above the largest run, fallbacks on at most 0.5 %
/// of the steps (the target of the contact work), no halving, v_s/v_m within 1e-3 relative
/// (1 % for the adaptive run, as its active-set pin).
#[test]
fn pin_semi_smooth_statistics_on_the_s_start() {
    let bundled = problem::load(Path::new("problems/s_start.toml")).unwrap();
    let coarse = common::s_start_coarse();
    let mut adaptive = common::s_start_coarse();
    adaptive.solver.integrator = problem::IntegratorKind::Bdf2;
    adaptive.time.adaptive = true;
    for (name, p, bound, v_ref, v_tol) in [
        ("bundled", bundled, 7.5, 0.3177, 1e-3),
        ("50 elements", coarse, 3.55, 0.3031, 1e-3),
        ("adaptive BDF2", adaptive, 5.15, 0.30895, 0.01),
    ] {
        assert_eq!(p.solver.contact, problem::ContactKind::SemiSmooth, "{name}");
        let (o, per_step, v) = whole_run(&p);
        let st = &o.stats;
        println!(
            "{name}: {} steps, {per_step:.3} iterations per step, {} fallbacks, {} retries, v_s/v_m {v:.5}",
            st.steps, st.contact.semismooth_fallbacks, st.contact.semismooth_retries
        );
        assert!(
            per_step <= bound,
            "{name}: {per_step} Newton iterations per step"
        );
        assert!(
            st.contact.semismooth_fallbacks as f64 <= 0.005 * st.steps as f64,
            "{name}: {} fallbacks",
            st.contact.semismooth_fallbacks
        );
        assert_eq!(st.step_halvings, 0, "{name}");
        assert!((v / v_ref - 1.0).abs() < v_tol, "{name}: v_s/v_m {v}");
    }
}
