//! Every input-file key in one table: its unit, default, allowed range and meaning.
//!
//! Each key is a named [`Key`] constant, and everything else reads it from there:
//! - the serde default functions of the schema structs return `KEY.real()` (or `.int()`,
//!   `.flag()`, `.word()`, `.reals3()`), so a default is written once, here;
//! - the validator checks a value against `KEY.range` ([`Key::check_real`],
//!   [`Key::check_int`]) and states [`Key::allowed`] in its error message, as does the TOML
//!   type error of [`super::from_toml`] (through [`super::ranges::allowed`]);
//! - `slither keys --markdown` prints [`super::reference::markdown`], the user guide's key reference
//!   (`docs/book/src/keys.md`, kept equal to it by a test).
//!
//! Rules that involve several keys (`time.dt` at most `time.duration`, `gait.sigma` at least one
//! element for the Gaussian gaits, ...) are checked in code; their text is the key's
//! [`Key::rule`], so the reference and the message agree.

/// A key's default.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DefaultValue {
    /// The key must be given.
    Required,
    /// A number.
    Real(f64),
    /// An integer.
    Int(u64),
    /// true or false.
    Flag(bool),
    /// A string value (written with quotes in files).
    Word(&'static str),
    /// Three numbers.
    Reals3([f64; 3]),
    /// Derived from other keys, or absent; described in words.
    Rule(&'static str),
}

/// A key's allowed values (numbers must also be finite).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Range {
    /// A finite number > 0.
    Positive,
    /// A finite number >= 0.
    NonNegative,
    /// Any finite number.
    Finite,
    /// A number between `lo` and `hi`; `*_closed` says whether the end is allowed.
    Real {
        /// Lower end.
        lo: f64,
        /// Whether `lo` itself is allowed.
        lo_closed: bool,
        /// Upper end.
        hi: f64,
        /// Whether `hi` itself is allowed.
        hi_closed: bool,
    },
    /// An integer in `[lo, hi]`.
    Int {
        /// Smallest allowed.
        lo: u64,
        /// Largest allowed.
        hi: u64,
    },
    /// Described in words (enumerations, arrays, paths); checked by serde or by code.
    Text(&'static str),
}

/// One input-file key.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Key {
    /// Dotted name, `table.key`.
    pub key: &'static str,
    /// SI unit, or "" for dimensionless and non-numeric keys.
    pub unit: &'static str,
    /// Default.
    pub default: DefaultValue,
    /// Allowed values.
    pub range: Range,
    /// A condition beyond the range (other keys involved), or "".
    pub rule: &'static str,
    /// What it means, one sentence.
    pub meaning: &'static str,
}

/// `[lo, hi]`.
pub(crate) const fn closed(lo: f64, hi: f64) -> Range {
    Range::Real {
        lo,
        lo_closed: true,
        hi,
        hi_closed: true,
    }
}

/// `(lo, hi]`.
pub(crate) const fn open_closed(lo: f64, hi: f64) -> Range {
    Range::Real {
        lo,
        lo_closed: false,
        hi,
        hi_closed: true,
    }
}

/// `(lo, hi)`.
pub(crate) const fn open(lo: f64, hi: f64) -> Range {
    Range::Real {
        lo,
        lo_closed: false,
        hi,
        hi_closed: false,
    }
}

impl Key {
    /// The default number (compile-time error when used in a `const` on a key without one).
    pub const fn real(&self) -> f64 {
        match self.default {
            DefaultValue::Real(v) => v,
            _ => panic!("key has no numeric default"),
        }
    }
    /// The default integer.
    pub const fn int(&self) -> u64 {
        match self.default {
            DefaultValue::Int(v) => v,
            _ => panic!("key has no integer default"),
        }
    }
    /// The default flag.
    pub const fn flag(&self) -> bool {
        match self.default {
            DefaultValue::Flag(v) => v,
            _ => panic!("key has no boolean default"),
        }
    }
    /// The default string value.
    pub const fn word(&self) -> &'static str {
        match self.default {
            DefaultValue::Word(v) => v,
            _ => panic!("key has no string default"),
        }
    }
    /// The default three numbers.
    pub const fn reals3(&self) -> [f64; 3] {
        match self.default {
            DefaultValue::Reals3(v) => v,
            _ => panic!("key has no array default"),
        }
    }

    /// The integer range's ends (compile-time error when used in a `const` on a key without
    /// one).
    pub const fn int_range(&self) -> (u64, u64) {
        match self.range {
            Range::Int { lo, hi } => (lo, hi),
            _ => panic!("key has no integer range"),
        }
    }

    /// The allowed values in words, as error messages and the reference state them, e.g.
    /// "a number in (0, 0.001]" or "a finite number > 0 (m)".
    pub fn allowed(&self) -> String {
        let unit = if self.unit.is_empty() {
            String::new()
        } else {
            format!(" ({})", self.unit)
        };
        let base = match self.range {
            Range::Positive => format!("a finite number > 0{unit}"),
            Range::NonNegative => format!("a finite number >= 0{unit}"),
            Range::Finite => format!("a finite number{unit}"),
            Range::Real {
                lo,
                lo_closed,
                hi,
                hi_closed,
            } => format!(
                "a number in {}{}, {}{}{unit}",
                if lo_closed { '[' } else { '(' },
                number(lo),
                number(hi),
                if hi_closed { ']' } else { ')' },
            ),
            Range::Int { lo, hi } => format!("an integer in [{lo}, {hi}]"),
            Range::Text(t) => t.to_string(),
        };
        if self.rule.is_empty() {
            base
        } else {
            format!("{base}, {}", self.rule)
        }
    }

    /// Whether `v` is in the key's numeric range (true for [`Range::Text`] and
    /// [`Range::Int`], which this does not check).
    pub fn check_real(&self, v: f64) -> bool {
        match self.range {
            Range::Positive => v.is_finite() && v > 0.0,
            Range::NonNegative => v.is_finite() && v >= 0.0,
            Range::Finite => v.is_finite(),
            Range::Real {
                lo,
                lo_closed,
                hi,
                hi_closed,
            } => {
                v.is_finite()
                    && (if lo_closed { v >= lo } else { v > lo })
                    && (if hi_closed { v <= hi } else { v < hi })
            }
            Range::Int { .. } | Range::Text(_) => true,
        }
    }

    /// Whether `v` is in the key's integer range (true for other ranges).
    pub fn check_int(&self, v: u64) -> bool {
        match self.range {
            Range::Int { lo, hi } => (lo..=hi).contains(&v),
            _ => true,
        }
    }

    /// The default as the reference prints it.
    pub fn default_text(&self) -> String {
        match self.default {
            DefaultValue::Required => "required".into(),
            DefaultValue::Real(v) => number(v),
            DefaultValue::Int(v) => v.to_string(),
            DefaultValue::Flag(v) => v.to_string(),
            DefaultValue::Word(w) => format!("\"{w}\""),
            DefaultValue::Reals3(v) => {
                format!("[{}, {}, {}]", number(v[0]), number(v[1]), number(v[2]))
            }
            DefaultValue::Rule(r) => r.into(),
        }
    }
}

/// A number as the reference and the messages write it: plain between 1e-3 and 1e6, else in
/// scientific notation (`1e-9`, `2.5e-7`).
pub fn number(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || (1e-3..1e6).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// A table of keys: `key_table! { LIST; NAME = "table.key", unit, default, range, rule,
/// meaning; ... }` defines one [`Key`] constant per line and `LIST`, all of them in order.
macro_rules! key_table {
    ($list:ident; $($name:ident = $key:literal, $unit:literal, $default:expr, $range:expr, $rule:literal, $meaning:literal;)*) => {
        $(
            #[doc = concat!("`", $key, "`: ", $meaning)]
            pub const $name: Key = Key {
                key: $key,
                unit: $unit,
                default: $default,
                range: $range,
                rule: $rule,
                meaning: $meaning,
            };
        )*
        /// Every key of the table, in the order of the reference.
        pub const $list: &[Key] = &[$($name),*];
    };
}
pub(crate) use key_table;

use DefaultValue::{Flag, Int, Real, Reals3, Required, Rule, Word};
use Range::{Finite, NonNegative, Positive, Text};

key_table! {
    KEYS;
    // [rod]
    ROD_LENGTH = "rod.length", "m", Required, Positive, "",
        "Length `L` of the rod.";
    ROD_DIAMETER = "rod.diameter", "m", Required, Positive, "and < rod.length",
        "Diameter `a` of the circular cross-section.";
    ROD_ELEMENTS = "rod.elements", "", Int(50), Range::Int { lo: 2, hi: 100_000 }, "",
        "Number of elements (edges) `N`.";
    ROD_DENSITY = "rod.density", "kg/m^3", Real(1000.0), Positive, "",
        "Density `rho`.";
    ROD_BENDING_STIFFNESS = "rod.bending_stiffness", "N m^2", Required, Positive, "",
        "Bending rigidity `B`.";
    ROD_TWIST_STIFFNESS = "rod.twist_stiffness", "N m^2", Rule("2 B / 3 (Poisson ratio 0.5)"), Positive, "",
        "Twist rigidity `C`.";
    ROD_STRETCH_STIFFNESS = "rod.stretch_stiffness", "N", Rule("16 B / a^2 (homogeneous circular rod)"), Positive, "",
        "Stretching rigidity `EA`; large, so the rod is nearly inextensible.";
    ROD_DAMPING_TIME = "rod.damping_time", "s", Real(0.0), NonNegative, "",
        "Kelvin-Voigt damping time `tau` of the rod's material (viscosity over modulus): every elastic strain (bending, twist, stretch) gets a viscous stress `tau` times its stiffness times its rate; 0: an elastic rod with no internal damping.";
    ROD_CLAMP = "rod.clamp", "", Word("none"), Text("\"none\", \"head\" or \"tail\""), "",
        "Clamped end (position and material frame held); the head is `s = 0`.";
    ROD_NATURAL_CURVATURE = "rod.natural_curvature", "1/m", Rule("[0, 0]"), Text("an array of 2 finite numbers (1/m)"), "",
        "Natural curvature `[about d1, about d2]`.";
    ROD_NATURAL_TWIST = "rod.natural_twist", "rad/m", Real(0.0), Finite, "",
        "Natural twist rate.";
    // [initial]
    INITIAL_SHAPE = "initial.shape", "", Word("straight"), Text("\"straight\" or \"coil\""), "",
        "Initial shape: \"straight\" along the heading, head (`s = 0`) at `x = L`, tail at the origin, centreline at `z = a/2 + height`; \"coil\": a helix about the vertical axis through the origin, tail at the bottom (centreline at `z = a/2 + height`) winding up to the head.";
    INITIAL_VELOCITY = "initial.velocity", "m/s", Reals3([0.0, 0.0, 0.0]), Text("an array of 3 finite numbers (m/s)"), "the fastest material speed |v| + |angular_velocity| L/2 at most 1000 m/s (a body faster than sound in tissue is not a snake)",
        "Uniform initial velocity.";
    INITIAL_ANGULAR_VELOCITY = "initial.angular_velocity", "rad/s", Reals3([0.0, 0.0, 0.0]), Text("an array of 3 finite numbers (rad/s)"), "the fastest material speed |velocity| + |angular_velocity| L/2 at most 1000 m/s",
        "Initial rigid angular velocity about the centroid.";
    INITIAL_HEADING_DEG = "initial.heading_deg", "degrees", Real(0.0), Finite, "",
        "Rotation of the straight rod about z; 0 puts the head toward +x.";
    INITIAL_HEIGHT = "initial.height", "m", Real(0.0), NonNegative, "",
        "Extra height of the centreline above `a/2`.";
    INITIAL_COIL_RADIUS = "initial.coil_radius", "m", Real(0.05), Positive, "with shape = \"coil\": > rod.diameter",
        "Radius of the coil's helix.";
    INITIAL_COIL_PITCH = "initial.coil_pitch", "m", Real(0.025), Positive, "with shape = \"coil\": > rod.diameter",
        "Rise of the coil's helix per turn (the turns start `coil_pitch - a` apart).";
    // [gravity]
    GRAVITY_G = "gravity.g", "m/s^2", Real(9.81), NonNegative, "",
        "Gravitational acceleration along -z; 0 disables gravity.";
    // [time]
    TIME_MODE = "time.mode", "", Word("dynamic"), Text("\"dynamic\" or \"static\""), "",
        "\"dynamic\": time stepping; \"static\": minimise the potential energy (needs a clamp, no ground).";
    TIME_DT = "time.dt", "s", Rule("required in dynamic mode"), Positive, "at most time.duration",
        "Time step `h`; with `adaptive = true`, the first step.";
    TIME_DURATION = "time.duration", "s", Rule("required in dynamic mode"), Positive, "",
        "Simulated duration.";
    TIME_LOAD_STEPS = "time.load_steps", "", Int(1), Range::Int { lo: 1, hi: 10_000 }, "",
        "Static mode: load increments (gravity and natural strains ramped).";
    TIME_ADAPTIVE = "time.adaptive", "", Flag(false), Text("true or false (false in static mode)"), "",
        "Error-controlled steps: each step is sized so that its local error estimate stays below `error_tolerance`.";
    TIME_ERROR_TOLERANCE = "time.error_tolerance", "fraction of rod.length per step", Real(5e-6), closed(1e-12, 0.1), "with time.adaptive = true",
        "Adaptive steps: allowed local error of any node position per step (twist angles count as the surface displacement `a/2 * angle`).";
    TIME_DT_MAX = "time.dt_max", "s", Rule("duration / 50 (at least dt)"), Text("a number in [time.dt, time.duration] (s)"), "with time.adaptive = true",
        "Adaptive steps: largest step.";
    TIME_DT_MIN = "time.dt_min", "s", Rule("dt * 1e-4"), Text("a number in (0, time.dt] (s)"), "with time.adaptive = true",
        "Adaptive steps: smallest step; a step that would have to be smaller stops the run (exit 3).";
    // [output]
    OUTPUT_INTERVAL = "output.interval", "s", Rule("duration / 100"), Positive, "",
        "Interval between recorded frames (trajectory, kymographs, observables).";
    OUTPUT_MOVIE = "output.movie", "", Flag(true), Text("true or false"), "",
        "Whether `slither run` writes `movie.gif` beside its figures (not with `--no-plots`; `--movie` writes it even when this is false).";
    // [ground]
    GROUND_MU_FORWARD = "ground.mu_forward", "", Real(0.11), closed(0.0, 100.0), "" ,
        "Coulomb coefficient resisting forward (toward the head) sliding. Without a `[ground]` table there is no ground.";
    GROUND_MU_BACKWARD = "ground.mu_backward", "", Real(0.14), closed(0.0, 100.0), "" ,
        "Coulomb coefficient resisting backward sliding.";
    GROUND_MU_SIDEWAYS = "ground.mu_sideways", "", Real(0.20), closed(0.0, 100.0), "" ,
        "Coulomb coefficient resisting sideways sliding.";
    GROUND_INCLINE_DEG = "ground.incline_deg", "degrees", Real(0.0), open(-90.0, 90.0), "",
        "Incline: gravity is tilted about y so that the slope rises along +x.";
    // [self_contact]
    SELF_CONTACT_ENABLED = "self_contact.enabled", "", Flag(true), Text("true or false"), "",
        "Whether two parts of the body more than `2a` apart along it keep their centrelines at least `a` apart (a barrier in every implicit step; the explicit integrator stops when a pair comes within the activation gap). A body passing through itself is a wrong answer: turn it off only to compare.";
    SELF_CONTACT_ACTIVATION = "self_contact.activation", "fraction of rod.diameter", Real(0.01), open_closed(0.0, 0.01), "",
        "Gap beyond contact (centreline distance minus `a`) below which the barrier acts.";
    SELF_CONTACT_STIFFNESS = "self_contact.stiffness", "B / a^2", Real(1.0), closed(1e-6, 1e6), "",
        "Barrier stiffness: `kappa g_hat` in units of `B / a^2`; a pair carries this force at a gap of about 0.53 times the activation gap, ten times it at about 0.12 times.";
    // [gait]
    GAIT_KIND = "gait.kind", "", Word("none"), Text("\"none\", \"s-start\", \"sidewinding\" or \"serpenoid\""), "",
        "Muscle pattern: one travelling triplet of Gaussian couples (s-start), triplets launched every `period` (sidewinding), or an in-plane travelling sine (serpenoid).";
    GAIT_STRESS = "gait.stress", "Pa", Real(0.0), NonNegative, "",
        "Peak muscular stress `Gamma`; couple magnitude `Gamma a^3`.";
    GAIT_SIGMA = "gait.sigma", "fraction of rod.length", Real(0.05), open_closed(0.0, 1.0), "for s-start and sidewinding at least one element length 1/rod.elements",
        "Gaussian width of each couple.";
    GAIT_SPEED = "gait.speed", "m/s", Real(0.5), Positive, "",
        "Travelling speed `v_m` of the couples, head to tail relative to the body.";
    GAIT_CENTERS = "gait.centers", "fraction of rod.length", Reals3([0.15, 0.25, 0.35]), Text("an array of 3 numbers in [0, 1] (fractions of rod.length)"), "",
        "Initial centres `s0` of the couples a, b, c (0 is the head).";
    GAIT_SCALES = "gait.scales", "", Reals3([1.0, 1.0, 1.0]), Text("an array of 3 finite numbers"), "with gait.stress, each couple's products stay finite (see the derived quantities)",
        "Multipliers of `Gamma a^3` for a, b, c (sign included; a positive b presses the middle down).";
    GAIT_PERIOD = "gait.period", "s", Real(0.5), Positive, "",
        "Sidewinding: time between launched triplets.";
    GAIT_RAMP = "gait.ramp", "fraction of L / v_m", Real(0.05), closed(0.0, 1.0), "",
        "Linear ramp-in of every couple over `ramp * L / v_m`.";
    GAIT_WAVELENGTH = "gait.wavelength", "fraction of rod.length", Real(0.5), Positive, "",
        "Serpenoid: wavelength.";
    // [accuracy]
    ACCURACY_TARGET = "accuracy.target", "relative error of v_s/v_m", Rule("required in [accuracy]; absent table: run as written"), closed(1e-4, 0.5), "only for a dynamic scene with [ground] and a [gait]",
        "Run the cheapest model (mesh, step or tolerance) whose estimated error of `v_s/v_m` is below this; `slither run --accuracy X` overrides it.";
    ACCURACY_MAX_ELEMENTS = "accuracy.max_elements", "", Int(400), Text("an integer in [rod.elements, 100000]"), "",
        "Most elements the mesh refinement may use.";
    // [solver]
    SOLVER_TOLERANCE = "solver.tolerance", "", Real(5e-6), open_closed(0.0, 1e-3), "",
        "Newton has converged when its last correction is below `tolerance * a` on every position and `tolerance` rad on every twist angle.";
    SOLVER_MAX_ITERATIONS = "solver.max_iterations", "", Int(300), Range::Int { lo: 1, hi: 10_000 }, "",
        "Newton iterations per step before the step is rejected (static mode: 10 times as many). 300 and not 100 since 2026-12-06: on the damped S-start at 400 elements (implicit Euler, 5e-4 s) semi-smooth attempts that needed more than 100 iterations fell back to the conic program 22 times, which took 59 of the run's 73 s; with 300, no fallback and 12.2 s.";
    SOLVER_MAX_HALVINGS = "solver.max_halvings", "", Int(8), Range::Int { lo: 0, hi: 30 }, "",
        "Times a rejected step may be halved before the run stops (exit 3).";
    SOLVER_INTEGRATOR = "solver.integrator", "", Word("implicit"), Text("\"implicit\", \"bdf2\" or \"explicit\""), "",
        "Time integrator: implicit Euler, second-order BDF2 (same Newton and contact), or velocity Verlet (the explicit reference: no ground, dynamic mode, stable only below a step limit).";
    SOLVER_CONTACT = "solver.contact", "", Word("semi-smooth"), Text("\"semi-smooth\" or \"conic\""), "",
        "Contact solver: a semi-smooth Newton on the Alart-Curnier conditions (every status from each iterate; the conic program as fallback and certificate), or one Clarabel program per Newton iterate (`SLITHER_CONTACT=conic` overrides it). There is no active-set solver: no bundled scene needs one (record `active-set-need`).";
    SOLVER_GROUND_POINTS = "solver.ground_points", "", Word("nodes"), Text("\"nodes\" or \"curve\""), "",
        "Where the ground touches the body: at the nodes, or at each node's lowest point of the parabola through it and its two neighbours, within half an element of it, chosen for every step at its first iterate and again at its solution where a node sinks below the ground (a contact between nodes, moving along the body as it lands and lifts; the semi-smooth Newton holds it by an augmented Lagrangian); where the parabola sags by less than 2e-5 a (Newton's unresolved ripples) the point is the node. The bundled S-start uses \"curve\". The guide's \"Ground contact between the nodes\" has the measurements.";
    SOLVER_MAX_BACKTRACKS = "solver.max_backtracks", "", Int(40), Range::Int { lo: 1, hi: 200 }, "",
        "Line search: step halvings per Newton iterate before the step fails.";
    SOLVER_ARMIJO = "solver.armijo", "", Real(1e-4), open(0.0, 0.5), "",
        "Line search: sufficient-decrease constant `c1` in `f(q + alpha dq) <= f(q) + c1 alpha g.dq`.";
    SOLVER_LINE_SEARCH_NOISE = "solver.line_search_noise", "relative to the objective", Real(1e-13), closed(0.0, 1e-6), "",
        "Line search: round-off allowance added to the Armijo bound, so a step at the minimum is not refused for noise.";
    SOLVER_SHIFT = "solver.shift", "relative to the largest diagonal entry", Real(1e-10), open_closed(0.0, 1e-2), "",
        "First diagonal shift of a Hessian that is only semi-definite (times 10 per retry).";
    SOLVER_SHIFT_TRIES = "solver.shift_tries", "", Int(12), Range::Int { lo: 1, hi: 30 }, "",
        "Diagonal shift retries before the step fails.";
    SOLVER_SEMI_SMOOTH_MAX_ITERATIONS = "solver.semi_smooth_max_iterations", "", Int(300), Range::Int { lo: 1, hi: 10_000 }, "",
        "Semi-smooth contact: Newton iterations of one attempt before it retries or the conic program takes over (capped by `max_iterations`; 300, as it, since 2026-12-06).";
    SOLVER_SEMI_SMOOTH_MERIT_MEMORY = "solver.semi_smooth_merit_memory", "", Int(8), Range::Int { lo: 1, hi: 100 }, "",
        "Semi-smooth contact: a full step is accepted when its merit falls enough below the largest of the last this many accepted iterates' (a non-monotone line search); after as many iterates without a new lowest merit the test is against the last iterate again; 1 is the monotone test.";
    SOLVER_SEMI_SMOOTH_PENALTY = "solver.semi_smooth_penalty", "multiple of the node's inertia stiffness", Real(10.0), open_closed(0.0, 1e4), "",
        "Semi-smooth contact: the Alart-Curnier penalty `rho` of each contact, this times the node's mass over the step's squared time scale, divided by `1 + rod.damping_time/h'` on a damped rod. It decides which branch (free, stick, slide) each iterate takes, not the solution.";
    SOLVER_SEMI_SMOOTH_RETRIES = "solver.semi_smooth_retries", "", Int(2), Range::Int { lo: 0, hi: 4 }, "",
        "Semi-smooth contact: a step whose Newton fails starts again from the step's start this many times, with the penalty times 3, 0.3, 10 and 0.1 in turn, before the conic program takes over.";
    SOLVER_WARM_CONIC_ITERATIONS = "solver.warm_conic_iterations", "", Int(20), Range::Int { lo: 1, hi: 10_000 }, "",
        "Newton iterations of the conic path started where a failed semi-smooth step stopped (then it starts over from the step's start).";
    SOLVER_NORMAL_FORCE_TOLERANCE = "solver.normal_force_tolerance", "fraction of W / n_c", Real(1e-3), open_closed(0.0, 1.0), "",
        "Contact forces are settled when they change by less than this times the mean weight per contact (semi-smooth: their change predicted over the last Newton step).";
    SOLVER_CONTACT_COUPLING = "solver.contact_coupling", "", Flag(true), Text("true or false"), "",
        "Semi-smooth contact: the sliding contacts' normal forces inside the Newton system (quadratic convergence); false lags them one iterate.";
    SOLVER_HESSIAN_REUSE = "solver.hessian_reuse", "fraction of an element length (rad for angles)", Real(0.1), closed(0.0, 0.1), "",
        "Semi-smooth contact: Newton keeps the bending and twist Hessian of an earlier iterate of the step while no position has moved more than this times the shortest element and no angle more than this (in rad), and assembles only their gradient (exact) at the iterates between; 0 assembles it at every iterate.";
    SOLVER_CONTACT_TOLERANCE = "solver.contact_tolerance", "fraction of a", Real(1e-9), open_closed(0.0, 1e-3), "",
        "A contact touches when its gap is below this, and sticks when its slip over the step is below it.";
    SOLVER_CONIC_CERTIFICATE = "solver.conic_certificate", "", Int(0), Range::Int { lo: 0, hi: 1_000_000_000 }, "",
        "Semi-smooth contact: certify every N-th step the Newton solves with one conic program from its solution (0: never); for tests and audits (about 30 ms a solve at 200 elements).";
    SOLVER_CONIC_TOLERANCE = "solver.conic_tolerance", "", Real(1e-10), open_closed(0.0, 1e-4), "",
        "Clarabel's absolute and relative gap and feasibility tolerances.";
    SOLVER_CONIC_MAX_ITERATIONS = "solver.conic_max_iterations", "", Int(100), Range::Int { lo: 1, hi: 10_000 }, "",
        "Clarabel's interior-point iteration cap.";
    SOLVER_CLARABEL_METHOD = "solver.clarabel_method", "", Word("qdldl"), Text("\"qdldl\" or \"faer\""), "",
        "Clarabel's direct KKT solver (\"faer\" needs the `clarabel-faer` feature; `SLITHER_CLARABEL_METHOD` overrides it).";
}

/// The key of a dotted name.
pub fn find(key: &str) -> Option<&'static Key> {
    KEYS.iter().find(|k| k.key == key)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_dotted() {
        for (i, k) in KEYS.iter().enumerate() {
            assert!(k.key.split_once('.').is_some(), "{}", k.key);
            assert!(KEYS[..i].iter().all(|o| o.key != k.key), "{} twice", k.key);
        }
    }

    #[test]
    fn defaults_lie_in_their_ranges() {
        for k in KEYS {
            match k.default {
                DefaultValue::Real(v) => assert!(k.check_real(v), "{}: {v}", k.key),
                DefaultValue::Int(v) => assert!(k.check_int(v), "{}: {v}", k.key),
                _ => {}
            }
        }
    }

    /// A minimal problem with every table a key can be in; `extra` adds `key = value` lines.
    /// `[accuracy]` (which needs a gait) only for the accuracy keys.
    fn minimal(extra: &[(&str, String)]) -> String {
        let accuracy = extra.iter().any(|(k, _)| k.starts_with("accuracy."));
        let mut tables: Vec<(&str, Vec<String>)> = vec![
            (
                "rod",
                vec![
                    "length = 1.0".into(),
                    "diameter = 0.02".into(),
                    "bending_stiffness = 0.4".into(),
                ],
            ),
            ("initial", vec![]),
            ("gravity", vec![]),
            ("time", vec!["dt = 0.01".into(), "duration = 0.1".into()]),
            ("output", vec![]),
            ("ground", vec![]),
            ("self_contact", vec![]),
            ("gait", vec![]),
            ("accuracy", vec![]),
            ("solver", vec![]),
        ];
        if accuracy {
            for (t, line) in [
                ("gait", "kind = \"s-start\""),
                ("accuracy", "target = 0.01"),
            ] {
                let table = tables.iter_mut().find(|(n, _)| *n == t).expect(t);
                table.1.push(line.into());
            }
        }
        for (key, value) in extra {
            let (t, name) = key.split_once('.').unwrap();
            let table = tables.iter_mut().find(|(n, _)| *n == t).expect(t);
            table.1.retain(|l| !l.starts_with(&format!("{name} ")));
            table.1.push(format!("{name} = {value}"));
        }
        tables
            .iter()
            .filter(|(t, lines)| *t != "accuracy" || !lines.is_empty())
            .map(|(t, lines)| format!("[{t}]\n{}\n", lines.join("\n")))
            .collect()
    }

    /// Each key's default as a TOML value, where it has a plain one.
    fn toml_default(k: &Key) -> Option<String> {
        match k.default {
            DefaultValue::Real(v) => Some(format!("{v:?}")),
            DefaultValue::Int(v) => Some(v.to_string()),
            DefaultValue::Flag(v) => Some(v.to_string()),
            DefaultValue::Word(w) => Some(format!("\"{w}\"")),
            DefaultValue::Reals3(v) => Some(format!("[{:?}, {:?}, {:?}]", v[0], v[1], v[2])),
            DefaultValue::Required | DefaultValue::Rule(_) => None,
        }
    }

    /// The table's default of every key is what the parser fills in when the key is absent:
    /// writing the default explicitly parses to the same problem. (This also covers the
    /// enumerations, whose defaults are their `#[default]` variants.)
    #[test]
    fn table_defaults_are_the_parsers_defaults() {
        let path = std::path::Path::new("minimal.toml");
        let parse = |text: &str| format!("{:?}", super::super::parse(text, path).unwrap());
        let absent = parse(&minimal(&[]));
        let mut checked = 0;
        for k in KEYS {
            let Some(v) = toml_default(k) else { continue };
            if k.key == TIME_ERROR_TOLERANCE.key {
                // An optional key, given only with adaptive steps: its default is what the
                // step controller uses when it is absent.
                let adaptive = |extra: &[(&str, String)]| {
                    let mut all = vec![("time.adaptive", "true".to_string())];
                    all.extend_from_slice(extra);
                    let p = super::super::parse(&minimal(&all), path).unwrap();
                    super::super::Adaptive::of(&p).unwrap().tolerance
                };
                assert_eq!(adaptive(&[(k.key, v.clone())]), adaptive(&[]), "{}", k.key);
                checked += 1;
                continue;
            }
            let explicit = parse(&minimal(&[(k.key, v.clone())]));
            let absent = if k.key.starts_with("accuracy.") {
                // The same file with [accuracy] and its required target, without this key.
                let target = ("accuracy.target", "0.01".to_string());
                parse(&minimal(&[target]))
            } else {
                absent.clone()
            };
            assert_eq!(
                explicit, absent,
                "{} = {v}: the parser's default differs",
                k.key
            );
            checked += 1;
        }
        assert!(checked >= 35, "{checked} keys checked");
    }

    #[test]
    fn ranges_read_as_before() {
        assert_eq!(SOLVER_TOLERANCE.allowed(), "a number in (0, 0.001]");
        assert_eq!(SOLVER_ARMIJO.allowed(), "a number in (0, 0.5)");
        assert_eq!(SOLVER_MAX_BACKTRACKS.allowed(), "an integer in [1, 200]");
        assert_eq!(ROD_LENGTH.allowed(), "a finite number > 0 (m)");
        assert_eq!(
            TIME_ERROR_TOLERANCE.allowed(),
            "a number in [1e-12, 0.1] (fraction of rod.length per step), with time.adaptive = true"
        );
        assert!(!SOLVER_ARMIJO.check_real(0.5) && SOLVER_ARMIJO.check_real(0.49));
        assert!(!SOLVER_TOLERANCE.check_real(0.0) && SOLVER_TOLERANCE.check_real(1e-3));
        assert!(!ROD_LENGTH.check_real(f64::NAN) && !ROD_LENGTH.check_real(f64::INFINITY));
    }
}
