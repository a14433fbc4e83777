//! `[initial]`: the initial shape (straight, or a coil) and velocity, and their checks.

use super::{keys, num, Checker, Clamp, Problem, ProblemError};
use serde::Deserialize;

/// Initial shape.
#[derive(Clone, Copy, Debug, Default, Deserialize, serde::Serialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Shape {
    /// Straight along the heading; head (s = 0) at x = L, tail at the origin.
    #[default]
    Straight,
    /// A coil: a helix about the vertical axis through the origin, from the tail at the
    /// bottom up to the head, of radius `coil_radius` rising `coil_pitch` per turn.
    Coil,
}

/// `[initial]`: initial configuration and velocity. Units, defaults and ranges: [`keys`]
/// (`INITIAL_*`).
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct InitialSpec {
    /// Shape: "straight" (default): along +x, head (s = 0) at x = L, tail at x = 0,
    /// centreline at z = a/2 + `height`.
    #[serde(default)]
    pub shape: Shape,
    /// Uniform initial velocity (m/s) ([`keys::INITIAL_VELOCITY`]).
    #[serde(default = "d_velocity")]
    pub velocity: [f64; 3],
    /// Initial rigid angular velocity about the centroid (rad/s)
    /// ([`keys::INITIAL_ANGULAR_VELOCITY`]).
    #[serde(default = "d_angular_velocity")]
    pub angular_velocity: [f64; 3],
    /// Rotation of the straight rod about z (degrees); 0 = head toward +x
    /// ([`keys::INITIAL_HEADING_DEG`]).
    #[serde(default = "d_heading")]
    pub heading_deg: f64,
    /// Extra height of the centreline above `a/2` (m) ([`keys::INITIAL_HEIGHT`]).
    #[serde(default = "d_height")]
    pub height: f64,
    /// Coil: radius of the helix (m) ([`keys::INITIAL_COIL_RADIUS`]).
    #[serde(default = "d_coil_radius")]
    pub coil_radius: f64,
    /// Coil: rise per turn (m) ([`keys::INITIAL_COIL_PITCH`]).
    #[serde(default = "d_coil_pitch")]
    pub coil_pitch: f64,
}
fn d_coil_radius() -> f64 {
    keys::INITIAL_COIL_RADIUS.real()
}
fn d_coil_pitch() -> f64 {
    keys::INITIAL_COIL_PITCH.real()
}
fn d_velocity() -> [f64; 3] {
    keys::INITIAL_VELOCITY.reals3()
}
fn d_angular_velocity() -> [f64; 3] {
    keys::INITIAL_ANGULAR_VELOCITY.reals3()
}
fn d_heading() -> f64 {
    keys::INITIAL_HEADING_DEG.real()
}
fn d_height() -> f64 {
    keys::INITIAL_HEIGHT.real()
}
impl Default for InitialSpec {
    fn default() -> Self {
        Self {
            coil_radius: d_coil_radius(),
            coil_pitch: d_coil_pitch(),
            shape: Shape::Straight,
            velocity: d_velocity(),
            angular_velocity: d_angular_velocity(),
            heading_deg: d_heading(),
            height: d_height(),
        }
    }
}

/// Fastest initial material speed, `|v| + |omega| L/2` (m/s): beyond the speed of sound in
/// tissue (about 1.5e3 m/s) the body is not a snake, and far beyond it the first step's
/// inertia overflows or its contact program has no solution (`velocity = [1e20, 0, 0]` used to
/// start and fail in the conic solve).
pub const MAX_INITIAL_SPEED: f64 = 1e3;

/// Range checks of `[initial]`, and the coil's rules (free ends; turns apart; radius above `a`).
pub(super) fn check(p: &Problem, c: &Checker) -> Result<(), ProblemError> {
    use keys::*;
    let (i, r) = (&p.initial, &p.rod);
    c.key_finite(&INITIAL_VELOCITY, &i.velocity)?;
    c.key_finite(&INITIAL_ANGULAR_VELOCITY, &i.angular_velocity)?;
    let norm = |v: &[f64; 3]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let (v, w) = (
        norm(&i.velocity),
        norm(&i.angular_velocity) * r.length / 2.0,
    );
    if !(v + w <= MAX_INITIAL_SPEED) {
        let (key, value, rule) = if v >= w {
            ("velocity", &i.velocity, INITIAL_VELOCITY.rule)
        } else {
            (
                "angular_velocity",
                &i.angular_velocity,
                INITIAL_ANGULAR_VELOCITY.rule,
            )
        };
        return Err(c.fail(
            "initial",
            key,
            format!("[{}]", value.map(num).join(", ")),
            &format!(
                "an array of 3 finite numbers with {rule}; it is {}",
                num(v + w)
            ),
        ));
    }
    c.key(&INITIAL_HEADING_DEG, i.heading_deg)?;
    c.key(&INITIAL_HEIGHT, i.height)?;
    c.key(&INITIAL_COIL_RADIUS, i.coil_radius)?;
    c.key(&INITIAL_COIL_PITCH, i.coil_pitch)?;
    if i.shape == Shape::Coil {
        if r.clamp != Clamp::None {
            return Err(c.fail(
                "initial",
                "shape",
                "\"coil\"".into(),
                "\"straight\" when rod.clamp is \"head\" or \"tail\" (a coil has free ends)",
            ));
        }
        if !(i.coil_pitch > r.diameter) {
            return Err(c.fail(
                "initial",
                "coil_pitch",
                num(i.coil_pitch),
                &format!(
                    "> rod.diameter = {} (m): the turns must start apart",
                    num(r.diameter)
                ),
            ));
        }
        if !(i.coil_radius > r.diameter) {
            return Err(c.fail(
                "initial",
                "coil_radius",
                num(i.coil_radius),
                &format!("> rod.diameter = {} (m)", num(r.diameter)),
            ));
        }
    }
    Ok(())
}
