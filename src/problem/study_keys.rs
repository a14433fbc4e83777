//! The keys of study files (`slither optimize`: `[study]`, `[optimize]`) and phase files
//! (`slither phase`: `[phase]`), in the same [`Key`] table as the problem-file keys: unit,
//! default, allowed range and meaning. The study and phase parsers take their defaults from
//! these constants and check their ranges with [`Key::check_real`] and [`Key::check_int`]; the
//! rules that involve other keys or the base problem (`max_evaluations` at least `n + 1`, a
//! sidewinding base for `duration_periods`, ...) are checked in code and stated in
//! [`Key::rule`]. `[accuracy]` in a study or phase file is the problem file's
//! ([`super::keys::ACCURACY_TARGET`]).
use super::keys::{closed, key_table, open_closed, DefaultValue, Key, Range};

use DefaultValue::{Flag, Int, Real, Required, Rule, Word};
use Range::{NonNegative, Text};

key_table! {
    STUDY_KEYS;
    // [study]
    STUDY_BASE = "study.base", "", Required, Text("a path (string) to a problem file, relative to the study file"), "its gait not \"none\", in dynamic mode",
        "The base problem every evaluation varies.";
    STUDY_MAX_EVALUATIONS = "study.max_evaluations", "", Int(30), Range::Int { lo: 2, hi: 100_000 }, "at least n + 1 for n optimised parameters",
        "Evaluations (simulations plus answers from `history.csv`) before the search stops.";
    STUDY_DURATION_PULSES = "study.duration_pulses", "pulse times L / v_m", Rule("the base file's time.duration * v_m / L"), open_closed(0.0, 1000.0), "not with study.duration_periods",
        "Simulated duration of every evaluation, `duration_pulses * L / v_m` seconds.";
    STUDY_DURATION_PERIODS = "study.duration_periods", "launch periods gait.period", Rule("absent: duration_pulses sets the duration"), open_closed(0.0, 1000.0), "a sidewinding base only, not with study.duration_pulses",
        "Simulated duration of every evaluation in launch periods, so every point measures the same number of cycles.";
    STUDY_INITIAL_STEP = "study.initial_step", "fraction of each bound's width", Real(0.25), open_closed(0.0, 1.0), "",
        "Edge of the initial simplex in normalised coordinates.";
    STUDY_TOLERANCE = "study.tolerance", "m/s", Real(1e-5), NonNegative, "",
        "Nelder-Mead stops when the standard deviation of the cost over the simplex falls below this.";
    STUDY_PENALTY = "study.penalty", "m/s per unit normalised distance", Real(1.0), NonNegative, "",
        "Penalty on a vertex outside the bounds, per unit of normalised distance outside the unit cube.";
    STUDY_MAX_HEADING_DEG = "study.max_heading_deg", "degrees", Rule("no limit"), open_closed(0.0, 180.0), "",
        "Heading limit: a finished run whose net displacement lies more than this off the initial head direction costs `penalty * (angle - max_heading_deg) / 90` extra and cannot be the optimum.";
    STUDY_OBJECTIVE = "study.objective", "", Word("v_s"), Text("\"v_s\", \"broadside\" or \"sidewinding\""), "the last two: a sidewinding base only",
        "What is maximised: the mean forward speed, the mean lateral speed per cycle less `turn_penalty` times the mean turn, or the sidewinding margin.";
    STUDY_TURN_PENALTY = "study.turn_penalty", "m/s per degree per cycle", Real(0.002), NonNegative, "only with objective = \"broadside\"",
        "Cost per degree of mean |turn| per cycle.";
    STUDY_STATIONARY_PENALTY = "study.stationary_penalty", "m/s per unit of stationary share short of 0.8", Real(0.0), NonNegative, "only with objective = \"broadside\"",
        "Cost per unit by which the smallest stationary share of the contact time falls short of the sidewinding criterion's.";
    // [optimize]
    OPTIMIZE_STRESS = "optimize.stress", "Pa", Rule("absent: not optimised"), Text("[lo, hi] with 0 <= lo < hi, finite (Pa)"), "",
        "Bounds of the muscle stress `Gamma`.";
    OPTIMIZE_SIGMA = "optimize.sigma", "fraction of rod.length", Rule("absent: not optimised"), Text("[lo, hi] with 0 < lo < hi <= 1 (fraction of rod.length)"), "lo >= 1/rod.elements for s-start and sidewinding",
        "Bounds of the couple width `sigma`.";
    OPTIMIZE_SPEED = "optimize.speed", "m/s", Rule("absent: not optimised"), Text("[lo, hi] with 0 < lo < hi, finite (m/s)"), "",
        "Bounds of the travelling speed `v_m`.";
    OPTIMIZE_PERIOD = "optimize.period", "s", Rule("absent: not optimised"), Text("[lo, hi] with 0 < lo < hi, finite (s)"), "a sidewinding base only",
        "Bounds of the launch period.";
    OPTIMIZE_SPACING = "optimize.spacing", "fraction of rod.length", Rule("absent: not optimised"), Text("[lo, hi] with 0 < lo < hi and gait.centers[0] + 2 hi <= 1 (fraction of rod.length)"), "an s-start or sidewinding base with evenly spaced centres",
        "Bounds of the triplet's spacing `b - a = c - b`.";
    OPTIMIZE_LIFT = "optimize.lift", "", Rule("absent: not optimised"), Text("[lo, hi] with lo < hi, finite (scale of gait.scales[1])"), "an s-start or sidewinding base",
        "Bounds of the out-of-plane couple's scale `scales[1]`.";
    OPTIMIZE_INITIAL_STRESS = "optimize.initial.stress", "Pa", Rule("the base file's gait.stress"), Text("a number within optimize.stress (Pa)"), "",
        "Starting point of the muscle stress.";
    OPTIMIZE_INITIAL_SIGMA = "optimize.initial.sigma", "fraction of rod.length", Rule("the base file's gait.sigma"), Text("a number within optimize.sigma (fraction of rod.length)"), "",
        "Starting point of the couple width.";
    OPTIMIZE_INITIAL_SPEED = "optimize.initial.speed", "m/s", Rule("the base file's gait.speed"), Text("a number within optimize.speed (m/s)"), "",
        "Starting point of the travelling speed.";
    OPTIMIZE_INITIAL_PERIOD = "optimize.initial.period", "s", Rule("the base file's gait.period"), Text("a number within optimize.period (s)"), "",
        "Starting point of the launch period.";
    OPTIMIZE_INITIAL_SPACING = "optimize.initial.spacing", "fraction of rod.length", Rule("the base file's spacing of gait.centers"), Text("a number within optimize.spacing (fraction of rod.length)"), "",
        "Starting point of the triplet's spacing.";
    OPTIMIZE_INITIAL_LIFT = "optimize.initial.lift", "", Rule("the base file's gait.scales[1]"), Text("a number within optimize.lift"), "",
        "Starting point of the out-of-plane couple's scale.";
    OPTIMIZE_METHOD = "optimize.method", "", Word("nelder-mead"), Text("\"nelder-mead\" or \"particle-swarm\""), "",
        "Search method: argmin's Nelder-Mead simplex (one simulation at a time) or its particle swarm (a generation simulated in parallel).";
    OPTIMIZE_STARTS = "optimize.starts", "", Int(1), Range::Int { lo: 1, hi: 1000 }, "Nelder-Mead only, with study.max_evaluations >= starts * (n + 1)",
        "Independent Nelder-Mead starts sharing `max_evaluations` equally: the first from `initial`, the others from points drawn uniformly in the bounds.";
    OPTIMIZE_PARTICLES = "optimize.particles", "", Int(8), Range::Int { lo: 2, hi: 1000 }, "particle swarm only, at most study.max_evaluations",
        "Particles per generation of the swarm (one simulation each, run in parallel).";
    OPTIMIZE_SEED = "optimize.seed", "", Int(1), Text("an integer >= 0"), "",
        "Seed of the random draws (swarm positions and velocities, multi-start points), so a study is reproducible and resumable.";
    // [phase]
    PHASE_BASE = "phase.base", "", Required, Text("a path (string) to a problem file, relative to the phase file"), "with a gait and a ground",
        "The base problem every cell varies.";
    PHASE_WEIGHT = "phase.weight", "", Required, Text("a non-empty, strictly increasing array of scaled weights W in [1e-6, 1e9], or { from, to, count, spacing = \"log\" | \"linear\" }"), "",
        "The grid's scaled weights `W = rho g a^2 L^3 / B`.";
    PHASE_TORQUE = "phase.torque", "", Required, Text("a non-empty, strictly increasing array of scaled torques G = 0 or in [1e-6, 1e9], or { from, to, count, spacing = \"log\" | \"linear\" }"), "",
        "The grid's scaled torques `G = Gamma a^3 L / B`.";
    PHASE_REFINE = "phase.refine", "", Flag(false), Text("true or false"), "",
        "Bisect every pair of neighbouring cells of different regimes and fit the boundaries through the bisected points.";
    PHASE_REFINE_STEPS = "phase.refine_steps", "", Int(3), Range::Int { lo: 1, hi: 8 }, "",
        "Bisection steps per neighbour pair (checked even when `refine = false`).";
    PHASE_WEIGHT_VIA = "phase.weight_via", "", Word("stiffness"), Text("\"stiffness\", \"gravity\" or \"density\""), "",
        "The parameter that sets a cell's `W`.";
    PHASE_SIMILAR = "phase.similar", "", Flag(false), Text("true or false"), "",
        "Keep the cells dynamically similar: `v_m L sqrt(rho A / B)` the base's, the times scaled with `L / v_m`.";
    PHASE_VERIFY = "phase.verify", "", Rule("absent: one run per cell"), Text("{ finer = true | false, perturbations = K in [0, 64], seed = integer >= 0, step = number in [1, 10] }"), "",
        "Runs per cell beyond the study's: a finer one and perturbed ones (the keys below).";
    PHASE_VERIFY_FINER = "phase.verify.finer", "", Flag(false), Text("true or false"), "",
        "Also run each cell at half the step and twice the elements; the reported label is the finer run's.";
    PHASE_VERIFY_PERTURBATIONS = "phase.verify.perturbations", "", Int(0), Range::Int { lo: 0, hi: 64 }, "",
        "Perturbed runs per cell (an ensemble at the study's resolution).";
    PHASE_VERIFY_SEED = "phase.verify.seed", "", Int(1), Text("an integer >= 0"), "",
        "Seed the cells' perturbation seeds derive from (with the cell's `(W, G)`).";
    PHASE_VERIFY_STEP = "phase.verify.step", "", Real(2.5), closed(1.0, 10.0), "",
        "The perturbed runs' step ladder, from `dt / step` to `dt * step`.";
    PHASE_GROWTH = "phase.growth", "", Rule("absent: no growth line"), Text("{ diameters, stress, reference_diameter, exponent }"), "",
        "The base snake grown along a line of sizes, placed on the map.";
}

/// The study or phase key of a dotted name.
pub fn find(key: &str) -> Option<&'static Key> {
    STUDY_KEYS.iter().find(|k| k.key == key)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_dotted_and_apart_from_the_problem_keys() {
        for (i, k) in STUDY_KEYS.iter().enumerate() {
            assert!(k.key.split_once('.').is_some(), "{}", k.key);
            assert!(
                STUDY_KEYS[..i].iter().all(|o| o.key != k.key),
                "{} twice",
                k.key
            );
            assert!(super::super::keys::find(k.key).is_none(), "{}", k.key);
        }
    }

    #[test]
    fn defaults_lie_in_their_ranges() {
        for k in STUDY_KEYS {
            match k.default {
                DefaultValue::Real(v) => assert!(k.check_real(v), "{}: {v}", k.key),
                DefaultValue::Int(v) => assert!(k.check_int(v), "{}: {v}", k.key),
                _ => {}
            }
        }
    }
}
