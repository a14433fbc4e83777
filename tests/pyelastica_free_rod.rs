//! slither on a free, muscle-driven rod against PyElastica's trajectory of the same rod
//! (issue 50): no gravity, no ground, no damping, muscles as an internal moment on both sides
//! (slither's natural strains, PyElastica's time-dependent rest curvature). The fixtures are
//! PyElastica 1.0.0's node positions every 0.05 s over 1 s, step 1e-5 s (within 1.3e-6 a of
//! its runs at half that step), written by `compare/free_rod_fixture.py`; the command that
//! wrote each is in the file and in `tests/fixtures/README.md`. No Python here.
//!
//! * `pyelastica_free_rod.json`: the S-start's three couples (G 15, sigma 0.04 L, centres
//!   0.2/0.3/0.4 L, v_m 0.25 m/s, ramp over 0.05 T), 100 elements.
//! * `pyelastica_free_rod_spin.json`: an in-plane couple (scale 1) and an out-of-plane one
//!   (scale 0.5) at the same place (0.3 L), on a rod spinning about its own axis at 2 rad/s
//!   from the start, 100 elements. The couples act in the material frame, so the plane they
//!   bend the body in turns with it.
//! * `pyelastica_free_rod_twisted.json`, where twist matters most: the S-start's couples on a
//!   rod with a natural twist of 2 pi rad/m, at rest in it at the start (the couples' centres
//!   lie in material frames 36 degrees apart: the body bends in a helical wave). PyElastica
//!   at 200 elements, stored at every other node: its own mesh error is larger than the bound
//!   at 100 (its 100- and 200-element runs are 0.083 a apart at 1 s, its 50- and 100-element
//!   runs 0.34 a). slither runs it at 200 elements too (at 100: 0.085 a at 1 s).
//!
//! slither runs each rod (`problems/pyelastica_s_start.toml`'s: W 300, C = 2B/3, stretch
//! stiffness 10 x 16 B / a^2) with BDF2 at 5e-4 s on the fixture's mesh. Measured: the rms node
//! distance to the fixture after the best rigid rotation (Kabsch, proper rotations only), and
//! the angle of that rotation (both codes start from the same pose and conserve angular
//! momentum, so it stays small; a free rod cannot otherwise tell a couple turned about the
//! body's axis).
//!
//! Measured (2026-12-05), rms in diameters a at 0.1 / 0.2 / 0.4 / 1 s, largest rotation
//! (`free_rods_at_smaller_steps`, ignored, gives the other steps and meshes):
//!
//! | fixture | BDF2 5e-4 s (these tests) | BDF2 2.5e-5 s |
//! |---|---|---|
//! | S-start | 0.0025 / 0.0057 / 0.0238 / 0.0408, 0.17 deg | 0.0026 / 0.0059 / 0.0239 / 0.0415, 0.17 deg |
//! | spin | 0.0013 / 0.0036 / 0.0083 / 0.0457, 0.04 deg | 0.0014 / 0.0037 / 0.0084 / 0.0459, 0.04 deg |
//! | twisted (200 elements) | 0.0021 / 0.0062 / 0.0144 / 0.0591, 0.38 deg | (1e-4 s) 0.0021 / 0.0063 / 0.0145 / 0.0595, 0.38 deg |
//!
//! The twisted rod passes its 1 s bound by 1.5 % only: most of the distance there is the two
//! discretisations (slither at 400 elements: 0.054 a; PyElastica's own mesh change above).
//!
//! Pass: rms at most 0.01 a at 0.2 s and at most 0.06 a at every frame up to 1 s (issue 50's
//! bounds), best rotation at most 1 degree.
//!
//! Mutations: `*_mutations_fail` run them every time and require each to fail, through
//! slither's own [`Muscles`] with a changed gait or through `common::MutatedMuscles` (a copy of
//! its map with one change). Measured (rms at 0.2 / 1 s, largest rotation):
//!
//! | mutation | S-start | spin | twisted |
//! |---|---|---|---|
//! | moment x 1.05 | 0.18 / 0.58 a, 10.6 deg | 0.097 / 0.90 a, 1.3 deg | 0.21 / 1.19 a, 18.5 deg |
//! | in-plane couple a's sign flipped | 2.1 / 4.5 a, 178 deg | rotation 127 deg (rms unchanged) | 2.6 / 7.4 a, 79 deg |
//! | out-of-plane couple b's sign flipped | 1.9 / 3.4 a, 102 deg | rotation 53 deg (rms unchanged) | 2.1 / 8.2 a, 171 deg |
//! | in-plane couple c's sign flipped | 2.1 / 6.6 a, 172 deg | (no c) | 2.0 / 5.5 a, 179 deg |
//! | axes swapped | 1.9 / 3.4 a, 155 deg | rotation 37 deg (rms unchanged) | 2.1 / 8.2 a, 179 deg |
//! | couples turned 90 deg about the body axis | rotation 90 deg | rotation 90 deg | 0.17 a at 1 s, 90 deg |
//! | both signs flipped (kappa0 = +m/B) | rotation 180 deg | rotation 180 deg | 0.17 a at 1 s, 180 deg |
//! | spin reversed / none | - | 0.023 / 0.059 a, 17 deg; 0.012 / 0.050 a, 8.7 deg | - |
//! | natural twist reversed / none | - | - | 1.9 / 9.2 a; 0.89 / 7.7 a |
//!
//! On a free rod a couple's sign flip at a single place, or all couples turned about the body
//! axis, is a rigid rotation of the whole motion: only the rotation check sees it (the spin
//! rod's rows).
//!
//! The same mutations made in `Muscles::rest_strains` in `src/gait/mod.rs` itself (2026-12-05,
//! temporarily, then reverted) fail all three `*_matches_pyelastica` tests with the numbers
//! of the table: `+ mm[0] / m.bend` (the out-of-plane couple's sign), `[mm[1], mm[0]]` (axes
//! swapped), `1.05 * mm` (the moment scaled).
mod common;
use common::{model, MutatedMuscles};
use nalgebra::{Matrix3, Vector3};
use slither::gait::{Actuation, Gait, Muscles};
use slither::model::Model;
use slither::rod::dof;
use slither::sim;

/// slither's copy of the fixtures' rod: `problems/pyelastica_s_start.toml`'s rod at 100
/// elements, no gravity, no ground; BDF2 at 5e-4 s; frames every 0.05 s over 1 s. Without
/// self-contact, as PyElastica: these tests compare the muscles' physics, and the twisted
/// rod's PyElastica motion passes through itself (between 0.55 and 0.6 s, and at 0.85 s with
/// its closest pair at 0.103 a; see `twisted_rod_with_self_contact_matches_until_it_touches`).
const FREE_ROD: &str = r#"
[rod]
length = 1.0
diameter = 0.02
elements = ELEMENTS
density = 1000.0
bending_stiffness = 0.01308
twist_stiffness = 0.00872
stretch_stiffness = 5232.0
natural_twist = TWIST

[gravity]
g = 0.0

[gait]
kind = "s-start"
stress = 24525.0
sigma = 0.04
speed = 0.25
centers = [CENTERS]
scales = [SCALES]
ramp = 0.05

[solver]
integrator = "bdf2"

[time]
dt = 5e-4
duration = 1.0

[output]
interval = 0.05

[initial]
angular_velocity = [SPIN, 0.0, 0.0]

[self_contact]
enabled = false
"#;

/// A stored PyElastica trajectory.
struct Fixture {
    name: &'static str,
    t: Vec<f64>,
    x: Vec<Vec<[f64; 3]>>,
    centres: [f64; 3],
    scales: [f64; 3],
    spin: f64,
    twist: f64,
    /// PyElastica's mesh (the fixture stores the nodes of a 100-element mesh); slither runs
    /// the same.
    elements: usize,
}

fn triple(v: &serde_json::Value) -> [f64; 3] {
    let a = v.as_array().unwrap();
    [
        a[0].as_f64().unwrap(),
        a[1].as_f64().unwrap(),
        a[2].as_f64().unwrap(),
    ]
}

fn load(name: &'static str) -> Fixture {
    load_from(name, &format!("tests/fixtures/{name}"))
}

fn load_from(name: &'static str, path: &str) -> Fixture {
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let elements = v["elements"].as_u64().unwrap() as usize;
    let stored = v["stored_nodes"].as_u64().unwrap() as usize;
    assert_eq!((elements % (stored - 1), stored), (0, 101), "{path}");
    // The fixture must be the rod this file builds.
    let rod = &v["rod"];
    let close = |key: &str, want: f64| {
        let got = rod[key].as_f64().unwrap();
        assert!(
            (got / want - 1.0).abs() < 1e-3,
            "{path}: rod.{key} {got} vs {want}"
        );
    };
    close("length", 1.0);
    close("diameter", 0.02);
    close("density", 1000.0);
    close("bending_stiffness", 0.01308);
    close("twist_stiffness", 0.00872);
    close("stretch_stiffness", 5232.0);
    let g = &v["gait"];
    assert!((g["Gamma_a3"].as_f64().unwrap() / (24525.0 * 0.02f64.powi(3)) - 1.0).abs() < 1e-9);
    assert!((g["sigma"].as_f64().unwrap() - 0.04).abs() < 1e-12);
    assert!((g["v_m"].as_f64().unwrap() - 0.25).abs() < 1e-12);
    assert!((g["ramp_time"].as_f64().unwrap() - 0.2).abs() < 1e-12);
    let t: Vec<f64> = v["t"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    let x: Vec<Vec<[f64; 3]>> = v["x"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_array().unwrap().iter().map(triple).collect())
        .collect();
    assert_eq!(t.len(), 21);
    assert!(x.iter().all(|f| f.len() == stored));
    Fixture {
        name,
        t,
        x,
        centres: triple(&g["centres"]),
        scales: triple(&g["scales"]),
        spin: v["spin"].as_f64().unwrap(),
        twist: v["natural_twist"].as_f64().unwrap(),
        elements,
    }
}

fn list(v: [f64; 3]) -> String {
    format!("{:?}, {:?}, {:?}", v[0], v[1], v[2])
}

/// slither's model of a fixture's rod (`spin` and `twist` as given, so that a mutation can
/// change them). A natural twist `twist` (rad/m) starts at rest in it: the edge angles
/// `theta_j = twist s_j` (`s_j` the edge's centre from the head) turn the material frame
/// right-handedly about the tangent, unturned at the head, as the fixture's rod (checked).
fn free_rod(fx: &Fixture, spin: f64, twist: f64) -> Model {
    free_rod_at(fx, spin, twist, 5e-4, fx.elements)
}

/// [`free_rod`] at step `dt` (s) on `elements` elements.
fn free_rod_at(fx: &Fixture, spin: f64, twist: f64, dt: f64, elements: usize) -> Model {
    let mut m = model(
        &FREE_ROD
            .replace("dt = 5e-4", &format!("dt = {dt:?}"))
            .replace("ELEMENTS", &elements.to_string())
            .replace("CENTERS", &list(fx.centres))
            .replace("SCALES", &list(fx.scales))
            .replace("SPIN", &format!("{spin:?}"))
            .replace("TWIST", &format!("{twist:?}")),
    );
    for j in m.real.start..m.real.end - 1 {
        let s = 0.5 * (m.arc_length(j) + m.arc_length(j + 1));
        m.q0[dof::edge(j)] = twist * s;
    }
    m
}

/// The fixture's material frame at the start: PyElastica's `d1` (up) turned about +x by
/// `-twist s`, i.e. slither's `d1` (horizontal, -y) turned the same way.
fn initial_frame_matches(fx: &Fixture, m: &Model) {
    let f = slither::sim::Frame::of(
        m,
        &slither::state::State::initial(m),
        0.0,
        vec![0.0; m.real.len()],
    );
    for (j, d1) in f.d1.iter().enumerate() {
        let s = (j as f64 + 0.5) * m.length / m.elements() as f64;
        let want = [0.0, -(fx.twist * s).cos(), (fx.twist * s).sin()];
        let err = (0..3).map(|k| (d1[k] - want[k]).abs()).fold(0.0, f64::max);
        assert!(
            err < 1e-9,
            "{}: d1 of edge {j} {d1:?}, expected {want:?}",
            fx.name
        );
    }
}

/// Rms distance (m) of `p` to `q` after the best proper rotation and translation of `p`, and
/// that rotation's angle (degrees).
fn kabsch(p: &[[f64; 3]], q: &[[f64; 3]]) -> (f64, f64) {
    let n = p.len() as f64;
    let centroid = |x: &[[f64; 3]]| {
        x.iter()
            .fold(Vector3::zeros(), |c, y| c + Vector3::from(*y))
            / n
    };
    let (pc, qc) = (centroid(p), centroid(q));
    let mut h = Matrix3::zeros();
    for (a, b) in p.iter().zip(q) {
        h += (Vector3::from(*a) - pc) * (Vector3::from(*b) - qc).transpose();
    }
    let svd = h.svd(true, true);
    let (u, vt) = (svd.u.unwrap(), svd.v_t.unwrap());
    let d = (vt.transpose() * u.transpose()).determinant().signum();
    let r = vt.transpose() * Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, d)) * u.transpose();
    let ss: f64 = p
        .iter()
        .zip(q)
        .map(|(a, b)| (r * (Vector3::from(*a) - pc) + qc - Vector3::from(*b)).norm_squared())
        .sum();
    let angle = ((r.trace() - 1.0) / 2.0)
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees();
    ((ss / n).sqrt(), angle)
}

/// Per fixture frame: (t, rms distance / a, best rotation in degrees).
fn compare(fx: &Fixture, m: &Model, actuation: Box<dyn Actuation>) -> Vec<(f64, f64, f64)> {
    let o = sim::run(m, actuation, &mut |_| {}, &mut |_| {});
    assert!(o.error.is_none(), "{}: {:?}", fx.name, o.error);
    fx.t.iter()
        .zip(&fx.x)
        .map(|(&t, x)| {
            let f = o
                .frames
                .iter()
                .find(|f| (f.t - t).abs() < 1e-9)
                .unwrap_or_else(|| panic!("{}: no slither frame at t = {t}", fx.name));
            // a finer slither mesh: the nodes at the fixture's arc lengths
            let every = (f.x.len() - 1) / (x.len() - 1);
            assert_eq!(every * (x.len() - 1), f.x.len() - 1);
            let sub: Vec<[f64; 3]> = f.x.iter().step_by(every).copied().collect();
            let (rms, angle) = kabsch(&sub, x);
            (t, rms / m.diameter, angle)
        })
        .collect()
}

/// The pass rule: rms <= 0.01 a at 0.2 s, <= 0.06 a at every frame, rotation <= 1 degree.
fn verdict(d: &[(f64, f64, f64)]) -> Result<(), String> {
    let at = |t: f64| d.iter().find(|r| (r.0 - t).abs() < 1e-9).unwrap();
    let worst = d
        .iter()
        .fold((0.0, 0.0, 0.0), |w, r| if r.1 > w.1 { *r } else { w });
    let turn = d.iter().map(|r| r.2).fold(0.0, f64::max);
    let mut why = Vec::new();
    if at(0.2).1 > 0.01 {
        why.push(format!("rms {:.4} a at 0.2 s > 0.01 a", at(0.2).1));
    }
    if worst.1 > 0.06 {
        why.push(format!("rms {:.4} a at {:.2} s > 0.06 a", worst.1, worst.0));
    }
    if turn > 1.0 {
        why.push(format!("best rotation {turn:.2} deg > 1 deg"));
    }
    if why.is_empty() {
        Ok(())
    } else {
        Err(why.join("; "))
    }
}

fn summary(d: &[(f64, f64, f64)]) -> String {
    let at = |t: f64| d.iter().find(|r| (r.0 - t).abs() < 1e-9).unwrap();
    let turn = d.iter().map(|r| r.2).fold(0.0, f64::max);
    format!(
        "rms at 0.1/0.2/0.4/1 s: {:.4} / {:.4} / {:.4} / {:.4} a, largest rotation {turn:.2} deg",
        at(0.1).1,
        at(0.2).1,
        at(0.4).1,
        at(1.0).1
    )
}

fn muscles(m: &Model) -> Box<dyn Actuation> {
    Box::new(Muscles {
        gait: m.gait.clone(),
    })
}

fn matches(name: &'static str) {
    let fx = load(name);
    let m = free_rod(&fx, fx.spin, fx.twist);
    initial_frame_matches(&fx, &m);
    let d = compare(&fx, &m, muscles(&m));
    println!("{name}: {}", summary(&d));
    if let Err(e) = verdict(&d) {
        panic!("{name}: slither parts from PyElastica: {e}");
    }
}

/// With self-contact (slither's default), the twisted rod agrees with PyElastica's (which has
/// none) as long as PyElastica's stays apart. Its stored frames come within a of themselves at
/// 0.85 s (closest pair 0.103 a, segment distance of the stored nodes), and between the frames
/// at 0.55 and 0.6 s (1.33 and 1.44 a) it must pass closer: there slither's barrier acts and
/// the two part (rms 0.0127 a at 0.55 s, 1.02 a at 0.6 s, measured), while slither without
/// self-contact follows PyElastica to the end (`free_twisted_rod_matches_pyelastica`). So up
/// to 0.55 s: within 0.06 a and 1 degree; and slither's rod never comes closer than `a`.
#[test]
fn twisted_rod_with_self_contact_matches_until_it_touches() {
    let fx = load("pyelastica_free_rod_twisted.json");
    let mut m = free_rod(&fx, fx.spin, fx.twist);
    m.self_contact = Some(slither::model::SelfContactParams {
        activation: 0.01,
        stiffness: 1.0,
    });
    let d = compare(&fx, &m, muscles(&m));
    let before: Vec<_> = d.iter().copied().filter(|r| r.0 <= 0.55 + 1e-9).collect();
    println!("twisted, self-contact, to 0.55 s: {:?}", before.last());
    let worst = before.iter().map(|r| r.1).fold(0.0, f64::max);
    let turn = before.iter().map(|r| r.2).fold(0.0, f64::max);
    assert!(
        worst <= 0.06 && turn <= 1.0,
        "rms up to {worst:.4} a, rotation {turn:.2} deg"
    );
    let o = sim::run(&m, muscles(&m), &mut |_| {}, &mut |_| {});
    let closest = slither::output::SelfContactSummary::new(&m, &o)
        .closest_over_a
        .unwrap();
    assert!(closest >= 1.0, "closest pair {closest} a");
}

/// Each mutation: its name, the model and the actuation.
type Mutation = (&'static str, Model, Box<dyn Actuation>);

fn mutations(fx: &Fixture) -> Vec<Mutation> {
    let (spin, twist) = (fx.spin, fx.twist);
    let base = free_rod(fx, spin, twist);
    let with_gait = |change: &dyn Fn(&mut Gait)| -> Box<dyn Actuation> {
        let mut gait = base.gait.clone();
        change(&mut gait);
        Box::new(Muscles { gait })
    };
    let mapped = |map: fn([f64; 2]) -> [f64; 2]| -> Box<dyn Actuation> {
        Box::new(MutatedMuscles {
            gait: base.gait.clone(),
            map,
        })
    };
    let mut out: Vec<Mutation> = vec![
        (
            "moment x 1.05",
            free_rod(fx, spin, twist),
            with_gait(&|g| g.couple *= 1.05),
        ),
        (
            "in-plane couple a: sign flipped",
            free_rod(fx, spin, twist),
            with_gait(&|g| g.scales[0] *= -1.0),
        ),
        (
            "out-of-plane couple b: sign flipped",
            free_rod(fx, spin, twist),
            with_gait(&|g| g.scales[1] *= -1.0),
        ),
        (
            "axes swapped (in-plane about d1, out-of-plane about d2)",
            free_rod(fx, spin, twist),
            mapped(|m| [m[1], m[0]]),
        ),
        (
            "couples turned 90 deg about the body axis",
            free_rod(fx, spin, twist),
            mapped(|m| [-m[1], m[0]]),
        ),
        (
            "both signs flipped (kappa0 = +m/B)",
            free_rod(fx, spin, twist),
            mapped(|m| [-m[0], -m[1]]),
        ),
    ];
    if fx.scales[2] != 0.0 {
        out.push((
            "in-plane couple c: sign flipped",
            free_rod(fx, spin, twist),
            with_gait(&|g| g.scales[2] *= -1.0),
        ));
    }
    if spin != 0.0 {
        let m_rev = free_rod(fx, -spin, twist);
        let m_none = free_rod(fx, 0.0, twist);
        let (a_rev, a_none) = (muscles(&m_rev), muscles(&m_none));
        out.push(("spin reversed", m_rev, a_rev));
        out.push(("no spin", m_none, a_none));
    }
    if twist != 0.0 {
        let m_rev = free_rod(fx, spin, -twist);
        let m_none = free_rod(fx, spin, 0.0);
        let (a_rev, a_none) = (muscles(&m_rev), muscles(&m_none));
        out.push(("natural twist reversed", m_rev, a_rev));
        out.push(("no natural twist", m_none, a_none));
    }
    out
}

fn mutations_fail(name: &'static str) {
    let fx = load(name);
    let mut survived = Vec::new();
    for (what, m, act) in mutations(&fx) {
        let d = compare(&fx, &m, act);
        match verdict(&d) {
            Ok(()) => survived.push(what),
            Err(e) => println!("{name}, {what}: fails as it must ({e}); {}", summary(&d)),
        }
    }
    assert!(
        survived.is_empty(),
        "{name}: mutations the comparison does not catch: {survived:?}"
    );
}

#[test]
fn free_rod_s_start_matches_pyelastica() {
    matches("pyelastica_free_rod.json");
}

#[test]
fn free_rod_s_start_mutations_fail() {
    mutations_fail("pyelastica_free_rod.json");
}

#[test]
fn free_twisted_rod_matches_pyelastica() {
    matches("pyelastica_free_rod_twisted.json");
}

#[test]
fn free_twisted_rod_mutations_fail() {
    mutations_fail("pyelastica_free_rod_twisted.json");
}

#[test]
fn free_spinning_rod_matches_pyelastica() {
    matches("pyelastica_free_rod_spin.json");
}

#[test]
fn free_spinning_rod_mutations_fail() {
    mutations_fail("pyelastica_free_rod_spin.json");
}

/// The same comparisons at smaller steps, to show how much of the distance is slither's step
/// (BDF2 5e-4 s in the tests above): `cargo test --release --test pyelastica_free_rod --
/// --ignored --nocapture` (about a minute).
#[test]
#[ignore]
fn free_rods_at_smaller_steps() {
    for name in [
        "pyelastica_free_rod.json",
        "pyelastica_free_rod_spin.json",
        "pyelastica_free_rod_twisted.json",
    ] {
        let fx = load(name);
        for dt in [1e-3, 5e-4, 1e-4, 2.5e-5] {
            let m = free_rod_at(&fx, fx.spin, fx.twist, dt, fx.elements);
            let d = compare(&fx, &m, muscles(&m));
            println!("{name}, BDF2 dt {dt:e}: {}", summary(&d));
        }
        for elements in [100, 200, 400] {
            let m = free_rod_at(&fx, fx.spin, fx.twist, 1e-4, elements);
            let d = compare(&fx, &m, muscles(&m));
            println!(
                "{name}, slither at {elements} elements, BDF2 dt 1e-4: {}",
                summary(&d)
            );
        }
    }
}

/// slither at 100, 200 and 400 elements against a PyElastica trajectory written by
/// `compare/free_rod_fixture.py CASE FILE --elements N --store-every N/100` (not stored): the
/// two codes' mesh errors. `FREE_ROD_FIXTURE=FILE cargo test --release --test
/// pyelastica_free_rod -- --ignored --nocapture free_rod_meshes`.
#[test]
#[ignore]
fn free_rod_meshes() {
    let Ok(path) = std::env::var("FREE_ROD_FIXTURE") else {
        return;
    };
    let fx = load_from("external", &path);
    let n = fx.elements;
    for elements in [100, 200, 400] {
        let m = free_rod_at(&fx, fx.spin, fx.twist, 1e-4, elements);
        let d = compare(&fx, &m, muscles(&m));
        println!(
            "{path} ({n} elements), slither at {elements} elements, BDF2 dt 1e-4: {}",
            summary(&d)
        );
    }
}
