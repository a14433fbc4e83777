//! Kelvin-Voigt rod damping (`rod.damping_time`) against the analytic decay of a cantilever's
//! first bending mode, with either implicit integrator, and its input checks.
mod common;
use common::model;
use slither::integrator::bdf2::Bdf2;
use slither::integrator::{Integrator, Natural, Scheme};
use slither::model::Model;
use slither::state::State;

/// A cantilever of 20 elements clamped at the tail, released straight under gravity: its
/// static sag is 1.9 % of its length, so it rings about the sagged shape in its first mode.
fn cantilever(tau: f64, integrator: &str, dt: f64) -> String {
    format!(
        r#"
[rod]
length = 1.0
diameter = 0.02
elements = 20
bending_stiffness = 20.0
clamp = "tail"
damping_time = {tau}
[gravity]
g = 9.81
[time]
dt = {dt}
duration = 3.0
[solver]
integrator = "{integrator}"
"#
    )
}

/// The free end's height at every step.
fn tip_heights(m: &Model) -> Vec<(f64, f64)> {
    let mut it = Integrator::new(m, Box::new(Natural));
    let mut s = State::initial(m);
    let tip = m.real.start;
    let steps = (m.duration / m.dt).round() as usize;
    let mut out = Vec::with_capacity(steps + 1);
    out.push((s.t, s.node(tip)[2]));
    for _ in 0..steps {
        it.step(&mut s, m.dt).expect("step");
        out.push((s.t, s.node(tip)[2]));
    }
    out
}

/// Decay rate (1/s) and angular frequency (rad/s) of the ringing after `t0`: a least-squares
/// line through the logarithms of the half-swings between successive extremes, and the mean
/// time between them.
fn decay_and_frequency(h: &[(f64, f64)], t0: f64) -> (f64, f64) {
    let mut ext = Vec::new();
    for w in h.windows(3) {
        let (a, b, c) = (w[0].1, w[1].1, w[2].1);
        if w[1].0 >= t0 && ((b > a && b >= c) || (b < a && b <= c)) {
            ext.push(w[1]);
        }
    }
    assert!(ext.len() >= 8, "only {} extremes", ext.len());
    let pts: Vec<(f64, f64)> = ext
        .windows(2)
        .map(|p| {
            (
                0.5 * (p[0].0 + p[1].0),
                (0.5 * (p[0].1 - p[1].1).abs()).ln(),
            )
        })
        .collect();
    let n = pts.len() as f64;
    let (mt, ml) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let slope = pts.iter().map(|p| (p.0 - mt) * (p.1 - ml)).sum::<f64>()
        / pts.iter().map(|p| (p.0 - mt).powi(2)).sum::<f64>();
    let half = (ext.last().unwrap().0 - ext[0].0) / (ext.len() - 1) as f64;
    (-slope, std::f64::consts::PI / half)
}

/// A Kelvin-Voigt beam `rho A w_tt + B w_xxxx + tau B w_xxxxt = 0` rings in its first mode as
/// `x'' + tau w^2 x' + w^2 x = 0`: its amplitude decays at `tau w^2 / 2`. The rate added by
/// `tau` to the run without damping (whose own decay is the integrator's numerical damping)
/// must be that, within 2 %, for implicit Euler and BDF2.
#[test]
fn damping_time_gives_a_cantilever_the_kelvin_voigt_decay_rate() {
    let tau = 1e-3;
    for (integrator, dt) in [("bdf2", 1e-3), ("implicit", 2.5e-4)] {
        let (rate0, w0) =
            decay_and_frequency(&tip_heights(&model(&cantilever(0.0, integrator, dt))), 0.5);
        let (rate, w) =
            decay_and_frequency(&tip_heights(&model(&cantilever(tau, integrator, dt))), 0.5);
        // The damped frequency is w sqrt(1 - (tau w / 2)^2): within 1e-4 of the undamped one.
        let expected = 0.5 * tau * w0 * w0;
        println!(
            "{integrator} dt {dt}: w {w0:.4} rad/s (damped {w:.4}), decay {rate0:.5} without, \
             {rate:.5} with damping: added {:.5} against tau w^2/2 = {expected:.5} ({:+.3} %)",
            rate - rate0,
            100.0 * ((rate - rate0) / expected - 1.0)
        );
        assert!(
            ((rate - rate0) / expected - 1.0).abs() < 0.02,
            "{integrator}: added decay {} against {expected}",
            rate - rate0
        );
        // Extremes fall on steps: the frequency estimate resolves about 1e-3.
        assert!(
            (w / w0 - 1.0).abs() < 2e-3,
            "{integrator}: frequency {w} against {w0}"
        );
    }
}

/// Without damping the explicit integrator is refused with rod damping, with the key and why.
#[test]
fn rod_damping_is_refused_with_the_explicit_integrator_and_below_zero() {
    let text = cantilever(1e-3, "explicit", 1e-5);
    let err = slither::problem::parse(&text, std::path::Path::new("damped.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("solver.integrator") && err.contains("rod.damping_time > 0"),
        "{err}"
    );
    let text = cantilever(-1e-3, "bdf2", 1e-3);
    let err = slither::problem::parse(&text, std::path::Path::new("damped.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("damped.toml") && err.contains("rod.damping_time") && err.contains(">= 0"),
        "{err}"
    );
}

/// BDF2 measures a strain's rate with its own three-level formula (as it measures velocity and
/// friction's slip): exact for a strain quadratic in time, at a step ratio other than 1. Without
/// it (the default origin, implicit Euler's `(e - e_n)/h`) the rate of `1 + 2t + 3t^2` comes
/// out 2 - 3h instead of 2.
#[test]
fn bdf2_measures_strain_rates_with_its_own_formula() {
    let m = model(&cantilever(1e-3, "bdf2", 1e-3));
    let mut scheme = Bdf2::default();
    let mut s = State::initial(&m);
    let mut qhat = vec![0.0; m.ndof];
    let (h0, h1) = (1e-3, 1.5e-3);
    scheme.predictor(&m, &s, h0, &mut qhat);
    assert_eq!(
        scheme.strain_origin(h0),
        (1.0, 0.0, h0),
        "the first step is implicit Euler"
    );
    let (q0, v0) = (s.q.clone(), s.v.clone());
    scheme.update(&m, &q0, &v0, h0, &mut s);
    scheme.predictor(&m, &s, h1, &mut qhat);
    let (c_n, c_p, h_eff) = scheme.strain_origin(h1);
    // e(t) = 1 + 2t + 3t^2 with t_{n+1} = 0, t_n = -h1, t_{n-1} = -h1 - h0: de/dt(0) = 2.
    let e = |t: f64| 1.0 + 2.0 * t + 3.0 * t * t;
    let rate = (e(0.0) - (c_n * e(-h1) + c_p * e(-h1 - h0))) / h_eff;
    assert!((rate - 2.0).abs() < 1e-9, "rate {rate}");
}
