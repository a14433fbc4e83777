//! Periodic observables on synthetic frames: rigid bodies whose answers are known.

use super::*;

const N: usize = 21;
const L: f64 = 1.0;
const P: f64 = 1.0;
const VM: f64 = 0.5;

/// A straight body of length `L` along the angle `phi` (head at +phi from its centroid), the
/// centroid at `c`; every node gets velocity `v` and normal force `normal(i)`.
fn body(t: f64, c: [f64; 2], phi: f64, v: [f64; 3], normal: &dyn Fn(usize) -> f64) -> Frame {
    let (cs, sn) = (phi.cos(), phi.sin());
    let x = (0..N)
        .map(|i| {
            let s = 0.5 * L - L * i as f64 / (N - 1) as f64;
            [c[0] + s * cs, c[1] + s * sn, 0.01]
        })
        .collect();
    Frame {
        t,
        x,
        theta: vec![0.0; N - 1],
        v: vec![v; N],
        normal: (0..N).map(normal).collect(),
        d1: vec![[0.0, 0.0, 1.0]; N - 1],
    }
}

fn frames(
    cycles: f64,
    per_cycle: usize,
    at: &dyn Fn(f64) -> ([f64; 2], f64),
    v: [f64; 3],
    normal: &dyn Fn(usize) -> f64,
) -> Vec<Frame> {
    let n = (cycles * per_cycle as f64).round() as usize;
    (0..=n)
        .map(|k| {
            let t = k as f64 * P / per_cycle as f64;
            let (c, phi) = at(t);
            body(t, c, phi, v, normal)
        })
        .collect()
}

fn on(n: f64) -> bool {
    n > 0.5
}

#[test]
fn a_body_translating_broadside_travels_at_90_degrees() {
    // Head along +x, moving +y at 0.2 m/s; half the nodes stand still on the ground.
    let u = 0.2;
    let fr = frames(5.0, 40, &|t| ([0.0, u * t], 0.0), [0.0, 0.0, 0.0], &|i| {
        if i % 2 == 0 {
            1.0
        } else {
            0.0
        }
    });
    let p = measure(&fr, P, VM, L, &on);
    assert_eq!(p.cycles.len(), 4, "cycles 1..4 after the settling cycle 0");
    assert_eq!(p.cycles[0].index, 1);
    for c in &p.cycles {
        assert!((c.travel_angle_deg - 90.0).abs() < 1e-9, "{c:?}");
        assert!((c.broadside_deg - 90.0).abs() < 1e-9);
        assert!(c.turn_deg.abs() < 1e-9);
        assert!((c.displacement_over_length - u * P / L).abs() < 1e-12);
        assert!((c.lateral_speed_over_v_m - u / VM).abs() < 1e-12);
        assert!(c.along_speed_over_v_m.abs() < 1e-12);
        // The even nodes, 0, 2, ..., 20: 11 separate one-node patches, all still.
        assert!((c.contact_patches_mean - 11.0).abs() < 1e-12);
        assert_eq!(c.stationary_contact_share, 1.0);
        assert!((c.stationary_body_fraction - 11.0 / 21.0).abs() < 1e-12);
    }
    assert!(p.sidewinding, "{}", p.missed());
    assert_eq!(p.spread.broadside_deg, 0.0);
}

#[test]
fn head_first_and_tail_first_travel_are_not_broadside() {
    let fwd = frames(
        3.0,
        20,
        &|t| ([0.3 * t, 0.0], 0.0),
        [0.3, 0.0, 0.0],
        &|_| 1.0,
    );
    let p = measure(&fwd, P, VM, L, &on);
    assert!(p.cycles.iter().all(|c| c.travel_angle_deg.abs() < 1e-9));
    assert!((p.cycles[0].along_speed_over_v_m - 0.6).abs() < 1e-12);
    // Sliding at 0.3 m/s > 0.1 v_m: no node is stationary; too few cycles as well.
    assert_eq!(p.stationary_contact_share_min, 0.0);
    assert!(!p.sidewinding);
    let failed: Vec<&str> = p
        .sidewinding_checks
        .iter()
        .filter(|c| !c.holds)
        .map(|c| c.quantity)
        .collect();
    assert_eq!(
        failed,
        [
            "cycles",
            "broadside_deg_min",
            "stationary_contact_share_min"
        ]
    );
    // Backwards at 45 degrees to the axis, the axis itself at 30 degrees.
    let phi = 30f64.to_radians();
    let dir = phi + 135f64.to_radians();
    let back = frames(
        3.0,
        20,
        &|t| ([0.1 * t * dir.cos(), 0.1 * t * dir.sin()], phi),
        [0.0; 3],
        &|_| 1.0,
    );
    let p = measure(&back, P, VM, L, &on);
    for c in &p.cycles {
        assert!((c.travel_angle_deg - 135.0).abs() < 1e-9, "{c:?}");
        assert!((c.broadside_deg - 45.0).abs() < 1e-9);
    }
}

#[test]
fn a_rotating_body_turns_by_its_rotation() {
    // Spinning about its centroid at 7 degrees per period, clockwise, while moving broadside;
    // the axis starts at 24.5 degrees so that the cycle-mean axes stay within 14 degrees of x.
    let w = -7f64.to_radians() / P;
    let phi0 = 24.5f64.to_radians();
    let fr = frames(
        6.0,
        50,
        &|t| ([0.0, 0.15 * t], phi0 + w * t),
        [0.0; 3],
        &|_| 1.0,
    );
    let p = measure(&fr, P, VM, L, &on);
    assert_eq!(p.cycles.len(), 5);
    for c in &p.cycles {
        assert!((c.turn_deg + 7.0).abs() < 1e-9, "{c:?}");
    }
    assert!((p.turn_deg_max_abs - 7.0).abs() < 1e-9);
    assert!((p.turn_deg_mean_abs - 7.0).abs() < 1e-9);
    // Turning 7 > 5 degrees per cycle is not sidewinding, though the rest holds.
    assert!(!p.sidewinding);
    assert_eq!(p.missed().split("; ").count(), 1, "{}", p.missed());
    assert!(p.missed().starts_with("turn_deg_max_abs"));
    // Against the cycle-mean axis (the axis at mid-cycle) the translation in +y is off 90
    // degrees by that axis' angle.
    for c in &p.cycles {
        let mid = phi0 + w * 0.5 * (c.t_start + c.t_end);
        assert!(
            (c.travel_angle_deg - (90.0 - mid.to_degrees())).abs() < 1e-6,
            "{c:?}"
        );
    }
}

#[test]
fn no_full_cycle_after_settling_gives_no_cycles() {
    let fr = frames(1.5, 20, &|_| ([0.0, 0.0], 0.0), [0.0; 3], &|_| 1.0);
    let p = measure(&fr, P, VM, L, &on);
    assert!(p.cycles.is_empty());
    assert!(p.broadside_deg_min.is_nan() && p.lateral_speed_over_v_m.is_nan());
    assert!(!p.sidewinding);
}

#[test]
fn the_sidewinding_margin_is_the_worst_relative_excess_over_the_criteria() {
    let cycle = |share: f64, disp: f64, turn: f64, broadside: f64| Cycle {
        displacement_over_length: disp,
        broadside_deg: broadside,
        turn_deg: turn,
        stationary_contact_share: share,
        ..Cycle::default()
    };
    let good = vec![cycle(0.9, 0.12, -2.0, 80.0); 4];
    // Share (0.9 - 0.8) / 0.8 = 0.125, displacement 0.2, turn 0.6, broadside 1/3.
    let p = summarise(1.0, good.clone());
    assert!(p.sidewinding);
    assert!((p.sidewinding_margin() - 0.125).abs() < 1e-12);
    assert_eq!(p.sidewinding_margin, p.sidewinding_margin());
    // One cycle turning 6 degrees: (5 - 6) / 5 = -0.2, and the label is lost.
    let mut bad = good.clone();
    bad[2].turn_deg = 6.0;
    let p = summarise(1.0, bad);
    assert!(!p.sidewinding);
    assert!((p.sidewinding_margin() + 0.2).abs() < 1e-12);
    // Too few cycles: not measured.
    assert!(summarise(1.0, good[..3].to_vec())
        .sidewinding_margin()
        .is_nan());
}
