//! Self-contact against independent references: conservation laws, Newton's third law, a
//! static force balance and the frictionless contact's geometry, plus the flailing cells of
//! the phase map and the bundled scenes (which never come close, so self-contact must leave
//! them unchanged to the bit).
//!
//! Mutations (each run once on a temporary copy of `src/energy/self_contact.rs`, then
//! restored), on the first four tests:
//! * force removed (the barrier returns zero and the line searches are not capped: what
//!   self-contact adds to a step, gone): every one fails on penetration: the crossing parts at
//!   step 4 (closest 0.951 a), the coil at step 1, the sliding legs at step 5, the first
//!   flailing cell (W 29.8, G 100) with its closest pair at 0.0002 a;
//! * sign flipped (the barrier's value and derivatives negated): every one fails: the crossing
//!   parts, the coil and the sliding legs when their first contact step is rejected after 8
//!   halvings (Newton or the conic program fails: the barrier pulls the parts together), the
//!   flailing cell with no pair ever within the activation gap (the capped line searches hold
//!   them just outside it).

mod common;

use slither::energy::self_contact::SelfContact;
use slither::gait::Muscles;
use slither::integrator::Integrator;
use slither::model::Model;
use slither::problem;
use slither::rod::{dof, frames, vec3::f};
use slither::state::State;
use std::path::Path;

const A: f64 = 0.02;

/// A 111-element rod of 1.11 m without gravity or ground, laid out as two straight legs of 40
/// edges that cross at the origin, joined by a quarter circle: leg A along +x at
/// `z = za`, leg B along -y at `z = zb` (heights ramped along the arc). `va` and `vb` are
/// the legs' velocities (the arc's ramped between them). `toml_extra` adds tables (the
/// default has no gravity and no ground).
fn crossing(toml_extra: &str, za: f64, zb: f64, va: [f64; 3], vb: [f64; 3]) -> Model {
    let gravity = if toml_extra.contains("[gravity]") {
        ""
    } else {
        "[gravity]\ng = 0.0\n"
    };
    let toml = format!(
        "[rod]\nlength = 1.11\ndiameter = {A}\nelements = 111\nbending_stiffness = 0.01308\n\
         {gravity}[time]\ndt = 1e-3\nduration = 0.05\n{toml_extra}"
    );
    let p = problem::parse(&toml, Path::new("<crossing>")).unwrap();
    let mut m = Model::new(&p);
    let r = 0.31 / std::f64::consts::FRAC_PI_2;
    let mut xs = Vec::new();
    let mut vs = Vec::new();
    for i in 0..m.nodes {
        let (x, w) = if i <= 40 {
            ([r - 0.4 + 0.01 * i as f64, 0.0, za], 1.0)
        } else if i <= 71 {
            let phi = (i - 40) as f64 / 31.0 * std::f64::consts::FRAC_PI_2;
            let w = 1.0 - (i - 40) as f64 / 31.0;
            ([r * phi.cos(), r * phi.sin(), zb + (za - zb) * w], w)
        } else {
            ([0.0, r - 0.01 * (i - 71) as f64, zb], 0.0)
        };
        xs.push(x);
        vs.push(f::add(f::scale(va, w), f::scale(vb, 1.0 - w)));
    }
    for i in 0..m.nodes {
        let k = dof::node(i);
        m.q0[k..k + 3].copy_from_slice(&xs[i]);
        m.v0[k..k + 3].copy_from_slice(&vs[i]);
    }
    for j in 0..m.nodes - 1 {
        m.a1_0[j] = frames::initial_director(f::unit(f::sub(xs[j + 1], xs[j])));
        m.v0[dof::edge(j)] = 0.0;
    }
    m
}

fn stepper(m: &Model) -> Integrator<'_> {
    Integrator::new(
        m,
        Box::new(Muscles {
            gait: m.gait.clone(),
        }),
    )
}

fn momentum(m: &Model, s: &State) -> [f64; 3] {
    let mut p = [0.0; 3];
    for i in m.real.clone() {
        let k = dof::node(i);
        for (c, pc) in p.iter_mut().enumerate() {
            *pc += m.mass[k + c] * s.v[k + c];
        }
    }
    p
}

/// Two straight parts of one rod driven into each other at 1 m/s (no gravity, no ground, no
/// friction), implicit Euler: no pair ever closer than `a`, total linear momentum conserved
/// to 1e-10 of the momentum scale, the pair forces equal and opposite at every step, and the
/// energy (kinetic, elastic and the barrier's) never increasing.
#[test]
fn crossing_parts_driven_into_each_other() {
    let m = crossing("", 0.6 * A, -0.6 * A, [0.0, 0.0, -0.5], [0.0, 0.0, 0.5]);
    let sc = SelfContact::of(&m).expect("self-contact is on by default");
    let mut st = stepper(&m);
    let mut s = State::initial(&m);
    let scale: f64 = m.real.clone().map(|i| m.mass[dof::node(i)] * 0.5).sum();
    let p0 = momentum(&m, &s);
    let energy = |st: &mut Integrator, s: &State| st.energies(s).total + sc.value(&s.q);
    let mut e_prev = energy(&mut st, &s);
    let mut closest = f64::INFINITY;
    let mut touched = 0;
    for step in 0..50 {
        st.step(&mut s, 1e-3)
            .unwrap_or_else(|e| panic!("step {step}: {e}"));
        let d = sc.closest_distance(&s.q);
        closest = closest.min(d);
        assert!(d > A, "penetration at step {step}: closest {} a", d / A);
        let p = momentum(&m, &s);
        let dp = f::norm(f::sub(p, p0));
        assert!(
            dp <= 1e-10 * scale,
            "step {step}: momentum changed by {dp:.3e} (scale {scale:.3e})"
        );
        let forces = sc.forces(&s.q);
        touched += usize::from(!forces.is_empty());
        for (pair, fs) in forces {
            let on_i = f::add(fs[0], fs[1]);
            let on_j = f::add(fs[2], fs[3]);
            assert!(
                f::norm(f::add(on_i, on_j)) <= 1e-12 * f::norm(on_i),
                "step {step}: pair {:?} forces not opposite",
                pair.edges
            );
        }
        let e = energy(&mut st, &s);
        assert!(
            e <= e_prev * (1.0 + 1e-9),
            "step {step}: energy rose from {e_prev} to {e}"
        );
        e_prev = e;
    }
    assert!(touched >= 10, "the parts touched at {touched} steps only");
    assert!(
        closest < 1.01 * A,
        "closest {} a: the parts never met",
        closest / A
    );
}

/// The same crossing with BDF2 (the multistep scheme, its start a step of implicit Euler):
/// no pair closer than `a`, linear momentum conserved to 1e-10 of its scale, and each pair's
/// forces equal and opposite.
#[test]
fn crossing_parts_with_bdf2() {
    let m = crossing(
        "[solver]\nintegrator = \"bdf2\"\n",
        0.6 * A,
        -0.6 * A,
        [0.0, 0.0, -0.5],
        [0.0, 0.0, 0.5],
    );
    let sc = SelfContact::of(&m).unwrap();
    let mut st = stepper(&m);
    let mut s = State::initial(&m);
    let scale: f64 = m.real.clone().map(|i| m.mass[dof::node(i)] * 0.5).sum();
    let p0 = momentum(&m, &s);
    let mut touched = 0;
    for step in 0..50 {
        st.step(&mut s, 1e-3)
            .unwrap_or_else(|e| panic!("step {step}: {e}"));
        let d = sc.closest_distance(&s.q);
        assert!(d > A, "penetration at step {step}: closest {} a", d / A);
        let dp = f::norm(f::sub(momentum(&m, &s), p0));
        assert!(
            dp <= 1e-10 * scale,
            "step {step}: momentum changed by {dp:.3e}"
        );
        for (_, fs) in sc.forces(&s.q) {
            touched += 1;
            let on_i = f::add(fs[0], fs[1]);
            assert!(f::norm(f::add(on_i, f::add(fs[2], fs[3]))) <= 1e-12 * f::norm(on_i));
        }
    }
    assert!(touched >= 10, "the parts touched {touched} times");
}

/// The explicit reference has no self-contact: driven into each other, the parts stop the
/// run with a clear error as soon as a pair comes within the activation gap (and a run with
/// self-contact off goes on through).
#[test]
fn explicit_integrator_stops_at_self_contact() {
    use slither::integrator::explicit::Explicit;
    use slither::integrator::StepError;
    let m = crossing("", 0.6 * A, -0.6 * A, [0.0, 0.0, -0.5], [0.0, 0.0, 0.5]);
    let mut ex = Explicit::new(
        &m,
        Box::new(Muscles {
            gait: m.gait.clone(),
        }),
    )
    .unwrap();
    let mut s = State::initial(&m);
    let err = (0..20_000)
        .find_map(|_| ex.step(&mut s, 2e-6).err())
        .expect("the explicit run should stop at the contact");
    match &err {
        StepError::SelfContact {
            distance_over_a, ..
        } => {
            assert!(*distance_over_a < 1.01 && *distance_over_a > 1.0, "{err}")
        }
        other => panic!("another error: {other}"),
    }
    assert!(
        err.to_string().contains("self_contact.enabled = false"),
        "{err}"
    );
    let off = crossing(
        "[self_contact]\nenabled = false\n",
        0.6 * A,
        -0.6 * A,
        [0.0, 0.0, -0.5],
        [0.0, 0.0, 0.5],
    );
    let mut ex = Explicit::new(
        &off,
        Box::new(Muscles {
            gait: off.gait.clone(),
        }),
    )
    .unwrap();
    let mut s = State::initial(&off);
    for step in 0..6000 {
        ex.step(&mut s, 2e-6)
            .unwrap_or_else(|e| panic!("step {step}: {e}"));
    }
}

/// Frictionless sliding: under gravity, leg A lies across leg B, which lies on the ground
/// (friction 0.5 : 0.7 : 1), and slides along its axis at 0.2 m/s. Every pair force lies on
/// the line of the closest points, normal to each edge whose closest point is inside it (no
/// tangential force); no pair comes closer than `a`.
#[test]
fn sliding_across_a_part_is_frictionless() {
    let zb = 0.5 * A;
    let ground =
        "[gravity]\ng = 9.81\n[ground]\nmu_forward = 0.5\nmu_backward = 0.7\nmu_sideways = 1.0\n";
    let m = crossing(
        ground,
        zb + A * (1.0 + 0.008),
        zb,
        [0.2, 0.0, 0.0],
        [0.0; 3],
    );
    let sc = SelfContact::of(&m).unwrap();
    let mut st = stepper(&m);
    let mut s = State::initial(&m);
    let x0: f64 = (0..=40).map(|i| s.q[dof::node(i)]).sum::<f64>() / 41.0;
    let (mut axial, mut normal, mut pressed) = (0.0, 0.0, 0);
    for step in 0..40 {
        st.step(&mut s, 1e-3)
            .unwrap_or_else(|e| panic!("step {step}: {e}"));
        assert!(sc.closest_distance(&s.q) > A, "penetration at step {step}");
        for (pair, fs) in sc.forces(&s.q) {
            pressed += 1;
            let (i, j) = pair.edges;
            let e = |k: usize| f::unit(f::sub(s.node(k + 1), s.node(k)));
            let on_i = f::add(fs[0], fs[1]);
            let n = f::norm(on_i);
            // Normal: perpendicular to each edge whose closest point lies inside it (where
            // the closest point is an end, the contact's normal is the line to that end).
            let inside = |x: f64| x > 0.0 && x < 1.0;
            if inside(pair.closest.s) {
                assert!(
                    f::dot(on_i, e(i)).abs() <= 1e-9 * n,
                    "step {step}: force along edge {i}"
                );
            }
            if inside(pair.closest.t) {
                assert!(
                    f::dot(on_i, e(j)).abs() <= 1e-9 * n,
                    "step {step}: force along edge {j}"
                );
            }
            assert!(f::norm(f::cross(on_i, pair.closest.delta)) <= 1e-9 * n * pair.closest.dist);
            let on_a = if i < 40 { on_i } else { f::add(fs[2], fs[3]) };
            axial += on_a[0];
            normal += n;
        }
    }
    let x1: f64 = (0..=40).map(|i| s.q[dof::node(i)]).sum::<f64>() / 41.0;
    assert!(
        pressed >= 20,
        "the legs pressed at {pressed} pair-steps only"
    );
    assert!(x1 - x0 > 0.001, "leg A travelled {} m", x1 - x0);
    // Not zero: leg A bends under the load, so the normal tilts (1.7 % of the normal impulse
    // here); what frictionless means is checked pair by pair above.
    eprintln!(
        "axial impulse / normal impulse on leg A: {:.3e}",
        axial / normal
    );
}

/// A coil of two turns, with the natural curvature and twist of its helix (pitch 1.2 a),
/// dropped from 0.2 a onto the ground (gravity, friction), comes to rest with its turns
/// stacked (implicit Euler at 0.02 s, whose damping settles the turns in about 6 s). At rest the
/// top turn's weight is carried by the self-contact forces under it plus the rod's internal
/// force at the section where the turn ends (the head end is free): the three balance within
/// 0.1 % of the weight.
#[test]
fn coil_dropped_on_the_ground_rests_stacked() {
    let radius: f64 = 0.05;
    let pitch = 1.2 * A;
    let c = (2.0 * std::f64::consts::PI * radius).hypot(pitch);
    let b = pitch / (2.0 * std::f64::consts::PI);
    let kappa = radius / (radius * radius + b * b);
    let tau = b / (radius * radius + b * b);
    let toml = format!(
        "[rod]\nlength = {len}\ndiameter = {A}\nelements = 80\nbending_stiffness = 0.01308\n\
         natural_curvature = [0.0, -{kappa}]\nnatural_twist = {tau}\n\
         [initial]\nshape = \"coil\"\ncoil_radius = {radius}\ncoil_pitch = {pitch}\nheight = {h}\n\
         [ground]\n[time]\ndt = 2e-2\nduration = 8.0\n",
        len = 2.0 * c,
        h = 0.2 * A,
    );
    let p = problem::parse(&toml, Path::new("<coil>")).unwrap();
    let m = Model::new(&p);
    let sc = SelfContact::of(&m).unwrap();
    let mut st = stepper(&m);
    let mut s = State::initial(&m);
    let e0 = st.energies(&s).elastic;
    assert!(
        e0 < 1e-3,
        "the coil does not start near its natural shape: elastic energy {e0} J"
    );
    let steps = (8.0 / 2e-2) as usize;
    for step in 0..steps {
        st.step(&mut s, 2e-2)
            .unwrap_or_else(|e| panic!("step {step}: {e}"));
        assert!(sc.closest_distance(&s.q) > A, "penetration at step {step}");
    }
    // At rest.
    let v_max = m
        .real
        .clone()
        .map(|i| f::norm(s.node_velocity(i)))
        .fold(0.0, f64::max);
    assert!(v_max < 1e-4, "not at rest: largest speed {v_max} m/s");
    // The top turn: the nodes within one turn of the head (which is at the top).
    let turn: Vec<usize> = m.real.clone().filter(|&i| m.arc_length(i) <= c).collect();
    // Stacked: the top turn lies on the lower one (most of it more than 1.2 a up), off the
    // ground (its lowest node, where it joins the lower turn, above the ground contact).
    let heights: Vec<f64> = turn.iter().map(|&i| s.node(i)[2] / A).collect();
    let up = heights.iter().filter(|&&z| z > 1.2).count();
    let lowest = heights.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(
        4 * up >= 3 * turn.len() && lowest > 0.6,
        "top turn not stacked: heights over a {heights:?}"
    );
    let g = 9.81;
    let weight: f64 = turn.iter().map(|&i| m.mass[dof::node(i) + 2] * g).sum();
    let (_, asm) = st.energy_derivatives(&s, &s.q.clone(), false);
    // Elastic forces on the turn's nodes: internal ones cancel, what remains is the force
    // across the turn's end section. Gravity is in the energy too: take it back out.
    let internal: f64 = turn
        .iter()
        .map(|&i| -asm.grad[dof::node(i) + 2] + m.mass[dof::node(i) + 2] * g)
        .sum();
    let mut contact = 0.0;
    for (pair, fs) in sc.forces(&s.q) {
        let (i, j) = pair.edges;
        for (r, node) in [i, i + 1, j, j + 1].into_iter().enumerate() {
            if turn.contains(&node) {
                contact += fs[r][2];
            }
        }
    }
    assert!(
        contact > 0.1 * weight,
        "self-contact carries {contact} N of {weight} N"
    );
    let residual = contact + internal - weight;
    eprintln!("top turn: contact {contact:.6} N, internal {internal:.6} N, weight {weight:.6} N");
    assert!(
        residual.abs() <= 1e-3 * weight,
        "contact {contact} N + internal {internal} N - weight {weight} N = {residual} N"
    );
}

/// The flailing cells of the phase map (`problems/phase_fine.toml` at G = 100 and the heavy
/// one at G = 37.9), which passed through themselves down to zero distance without
/// self-contact, keep every pair at least (1 - 1e-3) a apart at every step and frame.
#[test]
fn flailing_cells_never_pass_through_themselves() {
    let bin = env!("CARGO_BIN_EXE_slither");
    let dir = tempfile_dir("flailing");
    for (w, g) in [
        ("29.76351441631318", "100"),
        ("127.42749857031336", "100"),
        ("545.559478116852", "100"),
        ("545.559478116852", "37.926901907322495"),
    ] {
        let out = dir.join(format!("cell-{w}-{g}"));
        let status = std::process::Command::new(bin)
            .args(["phase", "problems/phase_fine.toml", "--cell"])
            .arg(format!("{w},{g}"))
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert!(
            status.status.success(),
            "{w},{g}: {}",
            String::from_utf8_lossy(&status.stderr)
        );
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        let closest = summary["self_contact"]["closest_over_a"].as_f64().unwrap();
        assert!(closest >= 1.0 - 1e-3, "{w},{g}: closest {closest} a");
        assert!(
            summary["self_contact"]["active_steps"].as_u64().unwrap() > 0,
            "{w},{g}: no contact"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn tempfile_dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!(
        "slither-self-contact-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The bundled scenes never bring two parts within the activation gap, so self-contact (on
/// by default) leaves them unchanged to the bit: the final state with self-contact equals
/// the one without. (Exempt from the mutation rule: it guards that nothing leaks.)
#[test]
fn bundled_scenes_unchanged_to_the_bit() {
    for path in [
        "problems/s_start.toml",
        "problems/s_start_heavy.toml",
        "problems/sidewinding.toml",
    ] {
        let on = problem::load(Path::new(path)).unwrap();
        assert!(on.self_contact.enabled);
        let mut off = on.clone();
        off.self_contact.enabled = false;
        let (_, a) = common::run_problem(&on);
        let (_, b) = common::run_problem(&off);
        assert!(a.error.is_none() && b.error.is_none(), "{path}");
        assert_eq!(a.state.q, b.state.q, "{path}: final state differs");
        assert_eq!(
            a.stats.newton_iterations, b.stats.newton_iterations,
            "{path}"
        );
        assert_eq!(a.stats.self_contact.active_steps, 0, "{path}");
    }
}
