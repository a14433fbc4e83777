//! Locomotion regimes as the S-start paper defines them (its Fig. 3d and text), and the
//! thresholds that decide them.
//!
//! * **U** (inertia dominates, the body flails): the body is thrown above
//!   [`Thresholds::flail_height_over_length`] `L`, or it lifts off at least
//!   [`Thresholds::flail_lift_over_a`] `a` while the link-density pulse is incoherent (linear
//!   fit of its peak position `R^2` below [`Thresholds::flail_pulse_r2`], or no fit at all).
//!   Checked first: a flailing body is U whatever its net motion.
//! * Net motion is the forward speed `v_s/v_m` (along the initial head direction). For a run
//!   of one pulse time `T = L / v_m` it is also the centroid's forward displacement in body
//!   lengths, so the thresholds below read as fractions of `L`.
//!   * **N** (no net motion): `|v_s/v_m| <` [`Thresholds::still_speed`], or no gait;
//!   * **F** (friction dominates: the torques uncoil the body without net translation, or it
//!     moves backward): `v_s/v_m <= -still_speed` (backward) or
//!     `still_speed <= v_s/v_m <=` [`Thresholds::move_speed`] (little forward motion);
//!   * otherwise the body moves forward (`v_s/v_m > move_speed`) and is either
//! * **S** (the S-start: a localised link-density pulse travelling head to tail, with forward
//!   motion), when every S criterion holds: heading within [`Thresholds::heading_max_deg`] of
//!   the head direction, two arcs on either side of a ground contact each lifted at least
//!   [`Thresholds::arc_lift_over_a`] `a` at one instant, and a coherent pulse (fit
//!   `R^2 >=` [`Thresholds::pulse_r2_min`], speed within [`Thresholds::pulse_speed_tolerance`]
//!   of `v_m`); or
//! * **M** (moves forward, not an S-start), naming the S criteria that failed
//!   ([`Criterion`]).
//!
//! [`classify`] returns the regime with a [`RegimeReason`]: one line of text and every
//! comparison made, with its value and threshold, for `summary.json`.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// A locomotion regime. Serialised (and displayed) as its one-letter name.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Regime {
    /// S-start: forward motion by a coherent link-density pulse travelling head to tail.
    S,
    /// Moves forward, but is not an S-start (the reason names the failed S criteria).
    M,
    /// Friction dominates: little forward, or backward, net motion.
    F,
    /// No net motion (also the default: nothing measured, nothing moved).
    #[default]
    N,
    /// Inertia dominates: the body flails.
    U,
}

impl Regime {
    /// Every regime, in the order of the phase map's legend.
    pub const ALL: [Regime; 5] = [Regime::S, Regime::M, Regime::F, Regime::N, Regime::U];

    /// The one-letter name.
    pub fn as_str(self) -> &'static str {
        match self {
            Regime::S => "S",
            Regime::M => "M",
            Regime::F => "F",
            Regime::N => "N",
            Regime::U => "U",
        }
    }

    /// A few words for legends.
    pub fn description(self) -> &'static str {
        match self {
            Regime::S => "S-start",
            Regime::M => "moves, not an S-start",
            Regime::F => "friction dominates",
            Regime::N => "no net motion",
            Regime::U => "unstable, flails",
        }
    }
}

impl fmt::Display for Regime {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A string that is not one of "S", "M", "F", "N", "U".
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown regime {0:?} (allowed: S, M, F, N, U)")]
pub struct UnknownRegime(pub String);

impl FromStr for Regime {
    type Err = UnknownRegime;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Regime::ALL
            .into_iter()
            .find(|r| r.as_str() == s)
            .ok_or_else(|| UnknownRegime(s.into()))
    }
}

/// An S criterion that a forward-moving run can miss (the sub-reason of `M`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Criterion {
    /// Net motion more than [`Thresholds::heading_max_deg`] off the head direction.
    Heading,
    /// Not two arcs lifted at least [`Thresholds::arc_lift_over_a`] `a` on either side of a
    /// ground contact.
    TwoArcs,
    /// Pulse fit `R^2` below [`Thresholds::pulse_r2_min`] (or no fit).
    PulseFit,
    /// Pulse speed further than [`Thresholds::pulse_speed_tolerance`] from `v_m`.
    PulseSpeed,
}

impl Criterion {
    /// The snake_case name (as serialised).
    pub fn as_str(self) -> &'static str {
        match self {
            Criterion::Heading => "heading",
            Criterion::TwoArcs => "two_arcs",
            Criterion::PulseFit => "pulse_fit",
            Criterion::PulseSpeed => "pulse_speed",
        }
    }
}

/// The thresholds of the classification. Defaults in [`Thresholds::DEFAULT`]; the guide's
/// chapter "Regimes" (`docs/book/src/regimes.md`) gives each one's reason and how many cells of the bundled phase study change label when it
/// moves by 20 %.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Thresholds {
    /// U: the body is thrown above this fraction of its length `L` (default 0.25: a quarter of
    /// the body in the air is flailing whatever the pulse does).
    pub flail_height_over_length: f64,
    /// U: lifted off at least this many diameters `a` ... (default 1: a flailing body is thrown
    /// clear of the ground by at least its own thickness; a bend lifted less than that is the
    /// muscles raising it against the weight. At 0.5, the level used before, the heavy
    /// `W = 3000, G = 15` cell of the bundled phase study, a single bend at 0.51 a moving
    /// 0.0016 v_m, was labelled U, where the paper has heavy weak snakes in N).
    pub flail_lift_over_a: f64,
    /// U: ... while the pulse fit's `R^2` is below this (default 0.5: less than half of the
    /// peak's motion explained by steady travel).
    pub flail_pulse_r2: f64,
    /// N: `|v_s/v_m|` below this (default 0.01: the centroid moves less than 1 % of `L` in one
    /// pulse time).
    pub still_speed: f64,
    /// Forward motion: `v_s/v_m` above this (default 0.02: 2 % of `L` in one pulse time); at or
    /// below it, but at least `still_speed`, the motion is "little" (F).
    pub move_speed: f64,
    /// S: net motion at most this many degrees off the initial head direction (default 45:
    /// more forward than sideways).
    pub heading_max_deg: f64,
    /// S: each of two arcs on either side of a ground contact lifted at least this many
    /// diameters at one instant (default 0.5: half a diameter, clearly off the ground).
    pub arc_lift_over_a: f64,
    /// S: pulse fit `R^2` at least this (default 0.8: a steadily travelling peak).
    pub pulse_r2_min: f64,
    /// S: pulse speed within this fraction of `v_m` (default 0.3: the pulse is carried by the
    /// muscles, which travel at `v_m`).
    pub pulse_speed_tolerance: f64,
}

impl Default for Thresholds {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl Thresholds {
    /// The defaults (documented per field).
    pub const DEFAULT: Thresholds = Thresholds {
        flail_height_over_length: 0.25,
        flail_lift_over_a: 1.0,
        flail_pulse_r2: 0.5,
        still_speed: 0.01,
        move_speed: 0.02,
        heading_max_deg: 45.0,
        arc_lift_over_a: 0.5,
        pulse_r2_min: 0.8,
        pulse_speed_tolerance: 0.3,
    };

    /// Field names, in the order of the classification.
    pub const NAMES: [&'static str; 9] = [
        "flail_height_over_length",
        "flail_lift_over_a",
        "flail_pulse_r2",
        "still_speed",
        "move_speed",
        "heading_max_deg",
        "arc_lift_over_a",
        "pulse_r2_min",
        "pulse_speed_tolerance",
    ];

    /// The threshold called `name` (one of [`Thresholds::NAMES`]).
    pub fn get_mut(&mut self, name: &str) -> Option<&mut f64> {
        Some(match name {
            "flail_height_over_length" => &mut self.flail_height_over_length,
            "flail_lift_over_a" => &mut self.flail_lift_over_a,
            "flail_pulse_r2" => &mut self.flail_pulse_r2,
            "still_speed" => &mut self.still_speed,
            "move_speed" => &mut self.move_speed,
            "heading_max_deg" => &mut self.heading_max_deg,
            "arc_lift_over_a" => &mut self.arc_lift_over_a,
            "pulse_r2_min" => &mut self.pulse_r2_min,
            "pulse_speed_tolerance" => &mut self.pulse_speed_tolerance,
            _ => return None,
        })
    }

    /// A copy with the threshold `name` multiplied by `factor` (`None` for an unknown name).
    pub fn scaled(&self, name: &str, factor: f64) -> Option<Thresholds> {
        let mut t = *self;
        *t.get_mut(name)? *= factor;
        Some(t)
    }
}

/// The measured values the regime depends on (from [`super::Observables`], or from a stored
/// `phase.csv` row).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RegimeInputs {
    /// `v_s / v_m` (NaN without a gait).
    pub v_s_over_v_m: f64,
    /// Angle of the net displacement from the initial head direction (degrees).
    pub displacement_angle_deg: f64,
    /// Largest elevation over `a`.
    pub max_elevation_over_a: f64,
    /// Largest elevation over `L`.
    pub max_elevation_over_length: f64,
    /// Height over `a` of the lower of two arcs on either side of a ground contact, at the
    /// instant that maximises it (0 if never two).
    pub two_arc_lift_over_a: f64,
    /// `R^2` of the pulse fit (NaN without a fit).
    pub lambda_pulse_r2: f64,
    /// Pulse speed over `v_m` (NaN without a fit).
    pub lambda_pulse_speed_over_v_m: f64,
}

/// One comparison made by [`classify`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Check {
    /// The quantity compared, e.g. "v_s_over_v_m".
    pub quantity: &'static str,
    /// Its value.
    pub value: f64,
    /// The comparison: "<", "<=", ">", ">=".
    pub op: &'static str,
    /// The threshold it is compared with.
    pub threshold: f64,
    /// Whether `value op threshold` holds (false for a NaN value).
    pub holds: bool,
}

/// Why a run got its regime.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct RegimeReason {
    /// One line naming the deciding comparisons, e.g. "moves forward (v_s/v_m 0.290 > 0.02),
    /// not an S-start: pulse speed 1.32 v_m (outside 0.70..1.30)".
    pub text: String,
    /// For `M`: the S criteria that failed; empty for every other regime.
    pub not_s: Vec<Criterion>,
    /// The comparisons made, in the order of the classification.
    pub checks: Vec<Check>,
}

pub(crate) fn check(quantity: &'static str, value: f64, op: &'static str, threshold: f64) -> Check {
    let holds = match op {
        "<" => value < threshold,
        "<=" => value <= threshold,
        ">" => value > threshold,
        _ => value >= threshold,
    };
    Check {
        quantity,
        value,
        op,
        threshold,
        holds,
    }
}

/// The regime of a run with the default thresholds.
pub fn classify(x: &RegimeInputs) -> (Regime, RegimeReason) {
    classify_with(x, &Thresholds::DEFAULT)
}

/// The regime of a run (criteria in the module documentation) and why.
pub fn classify_with(x: &RegimeInputs, t: &Thresholds) -> (Regime, RegimeReason) {
    let mut checks = Vec::new();
    let reason = |text: String, not_s: Vec<Criterion>, checks: Vec<Check>| RegimeReason {
        text,
        not_s,
        checks,
    };
    // U: flailing.
    let high = check(
        "max_elevation_over_length",
        x.max_elevation_over_length,
        ">",
        t.flail_height_over_length,
    );
    let lifted = check(
        "max_elevation_over_a",
        x.max_elevation_over_a,
        ">=",
        t.flail_lift_over_a,
    );
    // NaN (no fit) counts as incoherent.
    let incoherent = Check {
        holds: x.lambda_pulse_r2.is_nan() || x.lambda_pulse_r2 < t.flail_pulse_r2,
        ..check("lambda_pulse_r2", x.lambda_pulse_r2, "<", t.flail_pulse_r2)
    };
    let (h, l, i) = (high.holds, lifted.holds, incoherent.holds);
    checks.extend([high, lifted, incoherent]);
    if h {
        let text = format!(
            "flails: thrown up {:.3} L (> {} L)",
            x.max_elevation_over_length, t.flail_height_over_length
        );
        return (Regime::U, reason(text, vec![], checks));
    }
    if l && i {
        let text = format!(
            "flails: lifted {:.2} a (>= {} a) with an incoherent pulse (R^2 {:.2} < {})",
            x.max_elevation_over_a, t.flail_lift_over_a, x.lambda_pulse_r2, t.flail_pulse_r2
        );
        return (Regime::U, reason(text, vec![], checks));
    }
    // Net motion.
    let v = x.v_s_over_v_m;
    if v.is_nan() {
        return (
            Regime::N,
            reason("no gait: v_s/v_m undefined".into(), vec![], checks),
        );
    }
    let still = check("abs_v_s_over_v_m", v.abs(), "<", t.still_speed);
    let moves = check("v_s_over_v_m", v, ">", t.move_speed);
    let (s, m) = (still.holds, moves.holds);
    checks.extend([still, moves]);
    if s {
        let text = format!(
            "no net motion: |v_s/v_m| {:.2e} < {}",
            v.abs(),
            t.still_speed
        );
        return (Regime::N, reason(text, vec![], checks));
    }
    if !m {
        let text = if v < 0.0 {
            format!("backward: v_s/v_m {v:.4} <= -{}", t.still_speed)
        } else {
            format!(
                "little forward motion: v_s/v_m {v:.4} in [{}, {}]",
                t.still_speed, t.move_speed
            )
        };
        return (Regime::F, reason(text, vec![], checks));
    }
    // Forward motion: S or M.
    let s_checks = s_criteria(x, t);
    let not_s: Vec<Criterion> = s_checks
        .iter()
        .filter(|(_, c)| !c.holds)
        .map(|(k, _)| *k)
        .collect();
    checks.extend(s_checks.into_iter().map(|(_, c)| c));
    let head = format!("moves forward (v_s/v_m {v:.3} > {})", t.move_speed);
    if not_s.is_empty() {
        let text = format!(
            "S-start: {head}, heading {:.1} deg (<= {}), two arcs lifted {:.2} a (>= {} a), pulse R^2 {:.2} (>= {}) at {:.2} v_m (within {})",
            x.displacement_angle_deg,
            t.heading_max_deg,
            x.two_arc_lift_over_a,
            t.arc_lift_over_a,
            x.lambda_pulse_r2,
            t.pulse_r2_min,
            x.lambda_pulse_speed_over_v_m,
            t.pulse_speed_tolerance
        );
        return (Regime::S, reason(text, not_s, checks));
    }
    let why: Vec<String> = not_s
        .iter()
        .map(|c| match c {
            Criterion::Heading => format!(
                "heading {:.1} deg (> {})",
                x.displacement_angle_deg, t.heading_max_deg
            ),
            Criterion::TwoArcs => format!(
                "two arcs lifted only {:.2} a (< {} a)",
                x.two_arc_lift_over_a, t.arc_lift_over_a
            ),
            Criterion::PulseFit => format!(
                "pulse fit R^2 {:.2} (< {})",
                x.lambda_pulse_r2, t.pulse_r2_min
            ),
            Criterion::PulseSpeed => format!(
                "pulse speed {:.2} v_m (outside {:.2}..{:.2})",
                x.lambda_pulse_speed_over_v_m,
                1.0 - t.pulse_speed_tolerance,
                1.0 + t.pulse_speed_tolerance
            ),
        })
        .collect();
    let text = format!("{head}, not an S-start: {}", why.join(", "));
    (Regime::M, reason(text, not_s, checks))
}

/// The four S-start criteria of a forward-moving run (heading, two arcs, pulse fit, pulse
/// speed), each with its check.
fn s_criteria(x: &RegimeInputs, t: &Thresholds) -> [(Criterion, Check); 4] {
    [
        (
            Criterion::Heading,
            check(
                "displacement_angle_deg",
                x.displacement_angle_deg,
                "<=",
                t.heading_max_deg,
            ),
        ),
        (
            Criterion::TwoArcs,
            check(
                "two_arc_lift_over_a",
                x.two_arc_lift_over_a,
                ">=",
                t.arc_lift_over_a,
            ),
        ),
        (
            Criterion::PulseFit,
            check("lambda_pulse_r2", x.lambda_pulse_r2, ">=", t.pulse_r2_min),
        ),
        (
            Criterion::PulseSpeed,
            check(
                "pulse_speed_error",
                (x.lambda_pulse_speed_over_v_m - 1.0).abs(),
                "<=",
                t.pulse_speed_tolerance,
            ),
        ),
    ]
}

/// How many of `cells` change regime when each threshold is multiplied by `1 - frac` and by
/// `1 + frac` (relative to the labels with `base`). One row per threshold, in
/// [`Thresholds::NAMES`] order: `(name, base value, indices changed at 1 - frac, indices
/// changed at 1 + frac)`.
pub fn sensitivity(
    cells: &[RegimeInputs],
    base: &Thresholds,
    frac: f64,
) -> Vec<(&'static str, f64, Vec<usize>, Vec<usize>)> {
    let labels: Vec<Regime> = cells.iter().map(|c| classify_with(c, base).0).collect();
    let changed = |t: &Thresholds| -> Vec<usize> {
        cells
            .iter()
            .enumerate()
            .filter(|(k, c)| classify_with(c, t).0 != labels[*k])
            .map(|(k, _)| k)
            .collect()
    };
    Thresholds::NAMES
        .iter()
        .map(|&name| {
            let mut b = *base;
            let value = *b.get_mut(name).expect("a listed name");
            let lo = base.scaled(name, 1.0 - frac).expect("a listed name");
            let hi = base.scaled(name, 1.0 + frac).expect("a listed name");
            (name, value, changed(&lo), changed(&hi))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The juvenile S-start's measured values (problems/s_start.toml).
    fn s_start() -> RegimeInputs {
        RegimeInputs {
            v_s_over_v_m: 0.303,
            displacement_angle_deg: 29.2,
            max_elevation_over_a: 6.0,
            max_elevation_over_length: 0.12,
            two_arc_lift_over_a: 3.0,
            lambda_pulse_r2: 0.99,
            lambda_pulse_speed_over_v_m: 0.96,
        }
    }

    #[test]
    fn each_branch() {
        let x = s_start();
        let (r, why) = classify(&x);
        assert_eq!(r, Regime::S, "{}", why.text);
        assert!(why.not_s.is_empty());
        assert_eq!(why.checks.len(), 9);
        assert!(why.text.starts_with("S-start"), "{}", why.text);

        // The example: forward, coherent, but the pulse runs at 1.32 v_m.
        let m = RegimeInputs {
            v_s_over_v_m: 0.29,
            lambda_pulse_speed_over_v_m: 1.32,
            ..x
        };
        let (r, why) = classify(&m);
        assert_eq!(r, Regime::M);
        assert_eq!(why.not_s, vec![Criterion::PulseSpeed]);
        assert!(why.text.contains("1.32 v_m"), "{}", why.text);

        // Forward but sideways, one arc, no fit: M with three sub-reasons.
        let m = RegimeInputs {
            displacement_angle_deg: 60.0,
            two_arc_lift_over_a: 0.1,
            lambda_pulse_r2: f64::NAN,
            lambda_pulse_speed_over_v_m: f64::NAN,
            max_elevation_over_a: 0.3,
            ..x
        };
        let (r, why) = classify(&m);
        assert_eq!(r, Regime::M);
        assert_eq!(
            why.not_s,
            vec![
                Criterion::Heading,
                Criterion::TwoArcs,
                Criterion::PulseFit,
                Criterion::PulseSpeed
            ]
        );

        // Flailing: thrown above L/4, or lifted with an incoherent (or missing) pulse, even
        // while moving forward.
        let u = RegimeInputs {
            max_elevation_over_length: 0.3,
            ..x
        };
        assert_eq!(classify(&u).0, Regime::U);
        let u = RegimeInputs {
            lambda_pulse_r2: 0.21,
            v_s_over_v_m: 0.19,
            ..x
        };
        assert_eq!(classify(&u).0, Regime::U);
        let u = RegimeInputs {
            lambda_pulse_r2: f64::NAN,
            ..x
        };
        assert_eq!(classify(&u).0, Regime::U);
        // The same incoherent pulse on a body that stays on the ground is not U.
        let flat = RegimeInputs {
            max_elevation_over_a: 0.2,
            max_elevation_over_length: 0.004,
            two_arc_lift_over_a: 0.0,
            lambda_pulse_r2: 0.1,
            ..x
        };
        assert_eq!(classify(&flat).0, Regime::M);

        // A heavy weak body raising one bend half a diameter, with a noisy pulse, does not
        // flail: N (the bundled phase study's W = 3000, G = 15 cell).
        let heavy = RegimeInputs {
            v_s_over_v_m: 0.0016,
            displacement_angle_deg: 62.1,
            max_elevation_over_a: 0.51,
            max_elevation_over_length: 0.0102,
            two_arc_lift_over_a: 0.07,
            lambda_pulse_r2: 0.48,
            lambda_pulse_speed_over_v_m: 0.5,
        };
        assert_eq!(classify(&heavy).0, Regime::N);

        // Little, zero and backward motion.
        let n = RegimeInputs {
            v_s_over_v_m: 0.0007,
            ..flat
        };
        assert_eq!(classify(&n).0, Regime::N);
        let n = RegimeInputs {
            v_s_over_v_m: -0.009,
            ..flat
        };
        assert_eq!(classify(&n).0, Regime::N);
        let f = RegimeInputs {
            v_s_over_v_m: 0.015,
            ..flat
        };
        let (r, why) = classify(&f);
        assert_eq!(r, Regime::F);
        assert!(why.text.starts_with("little forward"), "{}", why.text);
        // Backward is F however fast, and an S-like body moving backward is not S or M.
        let f = RegimeInputs {
            v_s_over_v_m: -0.2,
            ..x
        };
        let (r, why) = classify(&f);
        assert_eq!(r, Regime::F);
        assert!(why.text.starts_with("backward"), "{}", why.text);
        // No gait.
        let g = RegimeInputs {
            v_s_over_v_m: f64::NAN,
            ..flat
        };
        assert_eq!(classify(&g).0, Regime::N);
    }

    #[test]
    fn thresholds_are_the_boundaries() {
        let x = s_start();
        // Just above and below move_speed.
        let t = Thresholds::DEFAULT;
        let at = |v: f64| {
            classify_with(
                &RegimeInputs {
                    v_s_over_v_m: v,
                    ..x
                },
                &t,
            )
            .0
        };
        assert_eq!(at(t.move_speed * 1.001), Regime::S);
        assert_eq!(at(t.move_speed), Regime::F);
        assert_eq!(at(t.still_speed * 0.999), Regime::N);
        // The heading limit moves the label.
        let h = RegimeInputs {
            displacement_angle_deg: 50.0,
            ..x
        };
        assert_eq!(classify(&h).0, Regime::M);
        let wide = t.scaled("heading_max_deg", 1.2).unwrap();
        assert_eq!(wide.heading_max_deg, 54.0);
        assert_eq!(classify_with(&h, &wide).0, Regime::S);
        assert!(t.scaled("nope", 1.2).is_none());
        for name in Thresholds::NAMES {
            let mut c = t;
            assert!(c.get_mut(name).is_some(), "{name}");
        }
    }

    #[test]
    fn sensitivity_counts_relabelled_cells() {
        let x = s_start();
        let cells = [
            x,
            // 50 degrees off: M now, S when the heading limit rises 20 % (54).
            RegimeInputs {
                displacement_angle_deg: 50.0,
                ..x
            },
            // 40 degrees: S now, M when it falls 20 % (36).
            RegimeInputs {
                displacement_angle_deg: 40.0,
                ..x
            },
        ];
        let rows = sensitivity(&cells, &Thresholds::DEFAULT, 0.2);
        assert_eq!(rows.len(), Thresholds::NAMES.len());
        let h = rows.iter().find(|r| r.0 == "heading_max_deg").unwrap();
        assert_eq!(h.1, 45.0);
        assert_eq!(h.2, vec![2]);
        assert_eq!(h.3, vec![1]);
        let r2 = rows.iter().find(|r| r.0 == "pulse_r2_min").unwrap();
        assert!(r2.2.is_empty() && r2.3.is_empty());
    }

    #[test]
    fn names_round_trip() {
        for r in Regime::ALL {
            assert_eq!(r.as_str().parse::<Regime>().unwrap(), r);
            assert_eq!(serde_json::to_string(&r).unwrap(), format!("\"{r}\""));
        }
        assert!("X".parse::<Regime>().is_err());
        assert_eq!(
            serde_json::to_string(&Criterion::PulseSpeed).unwrap(),
            "\"pulse_speed\""
        );
    }
}
