//! The semi-smooth Newton contact solve (`[solver] contact = "semi-smooth"`): in every contact
//! regime the complementarity residual (the norm of the whole semi-smooth system: force
//! balance and Alart-Curnier conditions, relative to the mean weight per contact) converges
//! superlinearly near the solution, on the steps where that regime occurs.
mod common;
use common::model;
use slither::integrator::{Integrator, Natural};
use slither::model::Model;
use slither::state::State;

const MU: [f64; 3] = [0.11, 0.14, 0.20];
/// Friction high enough that the stick tests' contacts hold.
const HIGH_MU: [f64; 3] = [5.5, 7.0, 10.0];
/// The round-off floor of the residual on these scenes: converged steps end at 1e-11 to
/// 1e-10 (or at exactly 0). The pairs' range of `r_k` starts a decade above it.
const FLOOR: f64 = 1e-10;
const LOWEST: f64 = 1e-9;

/// A 20-element rod with the semi-smooth contact solve and a tight Newton tolerance (so that
/// several iterates lie in the asymptotic range); `extra` adds or overrides sections.
fn scene(initial: &str, mu: [f64; 3], incline: f64, dt: f64, duration: f64, extra: &str) -> Model {
    model(&format!(
        r#"
[rod]
length = 1.0
diameter = 0.02
elements = 20
bending_stiffness = 1e-2
[initial]
{initial}
[ground]
mu_forward = {}
mu_backward = {}
mu_sideways = {}
incline_deg = {incline}
[time]
dt = {dt}
duration = {duration}
[solver]
contact = "semi-smooth"
tolerance = 1e-9
normal_force_tolerance = 1e-7
{extra}
"#,
        mu[0], mu[1], mu[2]
    ))
}

/// What one step did at the contacts: before and after, per real node, whether it touched
/// (positive normal force) and whether it moved horizontally.
struct StepRecord {
    residuals: Vec<f64>,
    touch: (Vec<bool>, Vec<bool>),
    moving: (Vec<bool>, Vec<bool>),
    fallback: bool,
}

/// Run `m` with the default actuation or a gait, recording every step.
fn record(m: &Model, gait: bool) -> Vec<StepRecord> {
    let act: Box<dyn slither::integrator::Actuation> = if gait {
        Box::new(slither::gait::Muscles {
            gait: m.gait.clone(),
        })
    } else {
        Box::new(Natural)
    };
    let mut integ = Integrator::new(m, act);
    let mut s = State::initial(m);
    let speed = |s: &State| -> Vec<bool> {
        m.real
            .clone()
            .map(|i| {
                let v = s.node_velocity(i);
                v[0].hypot(v[1]) > 1e-9
            })
            .collect()
    };
    let touching = |f: Vec<f64>| -> Vec<bool> { f.iter().map(|&n| n > 0.0).collect() };
    let mut out = Vec::new();
    let mut touch = touching(integ.normal_forces());
    let mut moving = speed(&s);
    let mut fallbacks = 0;
    for _ in 0..(m.duration / m.dt).round() as usize {
        integ.step(&mut s, m.dt).unwrap();
        let st = integ.stats();
        let now = touching(integ.normal_forces());
        let mv = speed(&s);
        out.push(StepRecord {
            residuals: st.contact.residuals.clone(),
            touch: (touch, now.clone()),
            moving: (moving, mv.clone()),
            fallback: st.contact.semismooth_fallbacks > fallbacks,
        });
        fallbacks = st.contact.semismooth_fallbacks;
        touch = now;
        moving = mv;
    }
    out
}

/// Successive residuals `(r_k, r_k+1)` of the selected steps that the semi-smooth Newton
/// solved (no conic fallback), `r_k` between `LOWEST` and 1; pairs around an iterate that
/// was not a full exact Newton step (marked -1) or across a change of contact statuses
/// (marked NaN: the pair's direction was computed on other branches) are not Newton pairs.
fn pairs<'a>(steps: impl Iterator<Item = &'a StepRecord>) -> Vec<(f64, f64)> {
    steps
        .filter(|r| !r.fallback)
        .flat_map(|r| r.residuals.windows(2).map(|w| (w[0], w[1])))
        .filter(|&(a, b)| (LOWEST..1.0).contains(&a) && b >= 0.0)
        .collect()
}

/// Superlinear: on nine pairs in ten the residual falls at least to `r^1.5` (or to the
/// round-off floor `FLOOR`).
fn assert_superlinear(regime: &str, p: &[(f64, f64)], min_pairs: usize) {
    let fast = p
        .iter()
        .filter(|&&(a, b)| b <= a.powf(1.5).max(FLOOR))
        .count();
    println!(
        "{regime}: {} pairs, {fast} at least r^1.5: {:?}",
        p.len(),
        p.iter()
            .take(12)
            .map(|(a, b)| format!("{a:.1e}->{b:.1e}"))
            .collect::<Vec<_>>()
    );
    assert!(p.len() >= min_pairs, "{regime}: only {} pairs", p.len());
    assert!(
        fast as f64 >= 0.9 * p.len() as f64,
        "{regime}: {fast} of {} pairs superlinear",
        p.len()
    );
}

/// The number of touching contacts after the step when at least two touch and none of them
/// moves (every touching contact sticks).
fn touching_stick(r: &StepRecord) -> Option<usize> {
    let (t, mv) = (&r.touch.1, &r.moving.1);
    let n = t.iter().filter(|&&x| x).count();
    (n >= 2 && t.iter().zip(mv).all(|(&t, &v)| !t || !v)).then_some(n)
}

/// Steps that fell back to the conic program (reported; the pairs leave them out).
fn fallbacks(regime: &str, steps: &[StepRecord]) -> usize {
    let fb = steps.iter().filter(|s| s.fallback).count();
    println!(
        "{regime}: {fb} of {} steps fell back to the conic program",
        steps.len()
    );
    fb
}

/// Stick: a high-friction rod bent by a travelling curvature wave holds its ground contacts
/// (zero horizontal velocity at every touching node) while the body's elasticity is
/// nonlinear.
#[test]
fn stick_converges_superlinearly() {
    let m = scene(
        "",
        HIGH_MU,
        0.0,
        2e-3,
        0.3,
        "[gait]\nkind = \"serpenoid\"\nstress = 16350.0\nspeed = 0.25\nwavelength = 0.5\nramp = 0.1",
    );
    let steps = record(&m, true);
    assert_eq!(fallbacks("stick", &steps), 0);
    let p = pairs(steps.iter().filter(|r| touching_stick(r).is_some()));
    assert_superlinear("stick", &p, 10);
}

/// Stick beside free nodes: a rod on high friction set pitching (one half lifts off, the other
/// presses into the ground and holds): on the steps where every touching contact sticks while
/// other nodes fly, the stuck contacts' reactions follow the free body's elasticity, so their
/// friction variables change from iterate to iterate (in the test above every position
/// coordinate touches and the residual is exactly zero after one iterate). Mutations tried
/// and not caught here, nor by the test above: sticking contacts' friction variables updated
/// with half their predicted change (290 of 296 pairs superlinear), and the free coordinates
/// coupled to half the held coordinates' moves (216 of 216; it fails the landing test, 13 of
/// 16). A sticking contact's branch holds its position at the step's start exactly, and after
/// the first iterate that target move is zero, so neither reaches these steps' later pairs.
#[test]
fn stick_beside_free_nodes_converges_superlinearly() {
    let steps = record(&pitching(HIGH_MU), false);
    assert_eq!(fallbacks("stick beside free", &steps), 0);
    let beside_free = |r: &&StepRecord| touching_stick(r).is_some_and(|n| n < r.touch.1.len());
    let p = pairs(steps.iter().filter(beside_free));
    assert_superlinear("stick beside free", &p, 10);
}

/// Slide: a rod pushed forward and spinning slides on every contact, each in its own
/// direction.
#[test]
fn slide_converges_superlinearly() {
    let m = scene(
        "velocity = [0.5, 0.0, 0.0]\nangular_velocity = [0.0, 0.0, 2.0]",
        MU,
        0.0,
        5e-3,
        0.3,
        "",
    );
    let steps = record(&m, false);
    assert_eq!(fallbacks("slide", &steps), 0);
    let sliding = |r: &&StepRecord| r.touch.1.iter().zip(&r.moving.1).all(|(&t, &v)| t && v);
    let p = pairs(steps.iter().filter(sliding));
    assert_superlinear("slide", &p, 10);
}

/// A rod lying on the ground with friction `mu`, set pitching (one half lifts off, the other
/// presses into the ground), over 0.4 s.
fn pitching(mu: [f64; 3]) -> Model {
    scene(
        "velocity = [0.1, 0.0, 0.0]\nangular_velocity = [0.0, 3.0, 0.0]",
        mu,
        0.0,
        2e-3,
        0.4,
        "",
    )
}

/// Lift-off and landing: the pitching rod flies and lands again.
fn drop_steps() -> Vec<StepRecord> {
    let steps = record(&pitching(MU), false);
    fallbacks("drop", &steps);
    steps
}

/// Landing: the steps where a contact touches down. 12 of 13 pairs superlinear; the slow one,
/// 1.3e-6 -> 1.6e-9 (a factor of 800 where `r^1.5` asks for 880), is the kept elastic
/// Hessian's (`[solver] hessian_reuse`: kept since an iterate 2.6e-3 m away; with
/// `hessian_reuse = 0` that step's pair falls below 1e-10), not the inexact solves' (with
/// `normal_force_tolerance` 1e-9, GMRES to 1e-11, the pair is the same). Until the
/// semi-smooth path marked its status changes in the residual history (NaN, as the active
/// set does), pairs across them counted, among them 3.0e-1 -> 2.2e-1 and 4.2e-1 -> 1.8e0,
/// and this test failed with 14 of 17 (ignored). Until the force balance in the residual was
/// summed once per coordinate, it had a round-off floor of about 1e-7 (the bare gradient's
/// squares plus the contacts' changes, which cancel to `sqrt(eps)` times the reactions), and
/// these tests took pairs from 1e-6 with a floor of 1e-7.
///
/// Checked mutations: the sliding contacts' friction coupled to half their new normal force
/// (`Reactions::set_slide` with `n = 2`) leaves 14 of 16 landing pairs superlinear and fails
/// this test (the lift-off test passes it, 4 of 4; with pairs across status changes counted
/// it failed 4 of 5); half the sliding contacts' spring across the slip (`k` in `branches`)
/// leaves 120 of 240 sliding pairs and fails the slide test. Not caught: sticking contacts'
/// friction variables updated with half their predicted change (landing 19 of 21 pairs
/// superlinear, 90.5 %; the other tests unchanged).
#[test]
fn landing_converges_superlinearly() {
    let steps = drop_steps();
    let landing = |r: &&StepRecord| r.touch.0.iter().zip(&r.touch.1).any(|(&a, &b)| !a && b);
    let p = pairs(steps.iter().filter(landing));
    assert_superlinear("landing", &p, 2);
}

/// Lift-off: the steps where a contact leaves the ground (mutation checked: see
/// [`landing_converges_superlinearly`]).
#[test]
fn lift_off_converges_superlinearly() {
    let steps = drop_steps();
    let lift = |r: &&StepRecord| r.touch.0.iter().zip(&r.touch.1).any(|(&a, &b)| a && !b);
    let p = pairs(steps.iter().filter(lift));
    assert_superlinear("lift-off", &p, 2);
}

/// Stick to slide at the cone's edge: a rod at rest on an incline just steeper than the
/// friction angle (0.3 degrees above) starts sliding: every contact's force is at the edge of
/// the friction cone.
#[test]
fn stick_to_slide_at_the_cone_edge_converges_superlinearly() {
    let critical = MU[1].atan().to_degrees();
    let m = scene("", MU, critical + 0.3, 2e-3, 0.1, "");
    let steps = record(&m, false);
    assert_eq!(fallbacks("edge", &steps), 0);
    let starting = |r: &&StepRecord| {
        r.touch
            .1
            .iter()
            .zip(&r.moving.0)
            .zip(&r.moving.1)
            .any(|((&t, &a), &b)| t && !a && b)
    };
    assert!(
        steps.iter().filter(starting).count() >= 1,
        "no contact started sliding"
    );
    // The steps from rest into sliding and the first ones after it.
    let first = steps.iter().position(|r| starting(&r)).unwrap();
    let p = pairs(steps[first..(first + 10).min(steps.len())].iter());
    assert_superlinear("stick-to-slide", &p, 2);
}

/// The retries of a failed step (`[solver] semi_smooth_retries`): with an iteration cap no
/// step can meet (one iteration), every step fails its first attempt and each retry, and the
/// conic program solves it from where the last retry stopped. The retries are counted, and
/// they leave no trace in the answer: the run ends where the run without retries ends, to
/// the Newton tolerance.
#[test]
fn a_failed_step_is_retried_with_other_penalties_before_the_conic_fallback() {
    let run = |retries: usize| {
        let m = scene(
            "velocity = [0.5, 0.0, 0.0]\nangular_velocity = [0.0, 0.0, 2.0]",
            MU,
            0.0,
            5e-3,
            0.05,
            &format!("semi_smooth_max_iterations = 1\nsemi_smooth_retries = {retries}"),
        );
        let mut integ = Integrator::new(&m, Box::new(Natural));
        let mut s = State::initial(&m);
        for _ in 0..10 {
            integ.step(&mut s, m.dt).unwrap();
        }
        let st = integ.stats().contact.clone();
        (s.q, st.semismooth_fallbacks, st.semismooth_retries)
    };
    let (q0, fallbacks0, retries0) = run(0);
    let (q2, fallbacks2, retries2) = run(2);
    assert_eq!((fallbacks0, retries0), (10, 0));
    assert_eq!((fallbacks2, retries2), (10, 20));
    let worst = q0
        .iter()
        .zip(&q2)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!("largest difference of a coordinate: {worst:.3e}");
    assert!(
        worst < 1e-9 * 0.02 * 10.0,
        "the retries changed the answer by {worst:e}"
    );
}

/// The stop by the residual (`semismooth_residual_stops`, the module doc of
/// `contact::semismooth`): where a settled full step still moves the force variables, an
/// iterate whose every equation is within the force tolerance is a solution. The bundled
/// S-start at 100 elements (BDF2 at 3.6e-3 s), its first 400 steps: 71 steps stop by the
/// residual, and the run ends 5.4e-6 a from the same run at a thousandth of both tolerances
/// (the test before: 2.0e-6 a, no stop). Asserted: a tenth of the steps stop so, within ten
/// Newton tolerances on positions (`5e-5 a`). A stop that ignored the Alart-Curnier residual
/// (the force balance alone) took 136 stops and ended 3.1e-2 a away.
#[test]
fn a_step_stopped_by_its_residual_is_the_solution_of_tight_tolerances() {
    let run = |scale: f64| {
        let mut p = slither::problem::load(std::path::Path::new("problems/s_start.toml")).unwrap();
        p.solver.tolerance *= scale;
        p.solver.normal_force_tolerance *= scale;
        let m = Model::new(&p);
        let mut integ = Integrator::new(
            &m,
            Box::new(slither::gait::Muscles {
                gait: m.gait.clone(),
            }),
        );
        let mut s = State::initial(&m);
        for _ in 0..400 {
            integ.step(&mut s, m.dt).unwrap();
        }
        let st = integ.stats();
        (
            s.q,
            st.contact.semismooth_residual_stops,
            st.steps,
            m.diameter,
            m.tolerance,
        )
    };
    let (q, stops, steps, a, tol) = run(1.0);
    let (q_tight, _, _, _, _) = run(1e-3);
    let worst = q
        .iter()
        .zip(&q_tight)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    println!(
        "{stops} of {steps} steps stopped by the residual; largest difference from the tight run {:.3e} a",
        worst / a
    );
    assert!(stops >= steps / 10, "{stops} stops by the residual");
    assert!(
        worst <= 10.0 * tol * a,
        "{:.3e} a from the tight run",
        worst / a
    );
}
