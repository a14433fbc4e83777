//! What runs and studies write, defined once: every key of `summary.json` and every column of
//! `phase.csv` and `history.csv`, with its unit and meaning.
//!
//! The guide's output reference (`docs/book/src/outputs.md`) is [`markdown`], printed by
//! `slither keys --outputs-markdown`; a test keeps the two equal, another checks that every
//! key a real run writes into `summary.json` is listed here and every listed key without a
//! condition is written, and the CSV headers of the studies are compared with the column
//! lists, so a key added to a record without a line here fails the tests.

/// One key of a JSON record or one column of a CSV file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Field {
    /// JSON: dotted path (`time_steps.accepted`; `[]` marks the entries of an array, e.g.
    /// `regime_reason.checks[].value`). CSV: the column name.
    pub name: &'static str,
    /// SI unit, "turns" for writhe and link, or "" for dimensionless and non-numeric values.
    pub unit: &'static str,
    /// When it is written, if not always (e.g. "with --accuracy").
    pub when: &'static str,
    /// What it means.
    pub meaning: &'static str,
}

const fn f(name: &'static str, unit: &'static str, meaning: &'static str) -> Field {
    Field {
        name,
        unit,
        when: "",
        meaning,
    }
}

const fn only(
    name: &'static str,
    unit: &'static str,
    when: &'static str,
    meaning: &'static str,
) -> Field {
    Field {
        name,
        unit,
        when,
        meaning,
    }
}

const ACCURACY: &str = "with --accuracy or [accuracy]";
const ENSEMBLE: &str = "with --ensemble K";
const SIDEWINDING: &str = "with a sidewinding gait";

/// Keys of `summary.json` (`slither run`). A failed run writes every gait observable and
/// `regime` / `regime_reason` as `null`: it has not measured them.
pub const SUMMARY: &[Field] = &[
    f("status", "", "\"completed\" or \"failed\""),
    f("error", "", "why the run stopped early, or null"),
    f("problem", "", "the problem file, as given on the command line"),
    f("mode", "", "\"dynamic\" or \"static\""),
    f("t_final", "s", "simulated time reached"),
    f("steps", "", "accepted steps (static: load increments)"),
    f("wall_time_s", "s", "wall-clock time of the integration"),
    f("max_strain", "", "largest |edge strain| over the run"),
    f("energy_final", "J", "total energy at the end: kinetic + elastic + gravitational"),
    f("energies_final.kinetic", "J", "kinetic energy at the end"),
    f("energies_final.elastic", "J", "elastic energy (stretch, bend, twist) at the end"),
    f("energies_final.gravity", "J", "gravitational potential energy at the end"),
    f("energies_final.total", "J", "their sum"),
    f("newton_iterations_mean", "", "Newton iterations per accepted step"),
    f("step_halvings", "", "steps retried with dt/2 after a failed solve"),
    f("time_steps.adaptive", "", "whether the steps were error controlled"),
    f("time_steps.accepted", "", "accepted steps"),
    f("time_steps.rejected", "", "rejected tries: rejected_error + rejected_solve"),
    f("time_steps.rejected_error", "", "tries whose error estimate exceeded the tolerance"),
    f("time_steps.rejected_solve", "", "tries whose Newton or contact solve failed"),
    f("time_steps.dt_min", "s", "smallest accepted step"),
    f("time_steps.dt_max", "s", "largest accepted step"),
    f("time_steps.error_max", "", "largest scaled error estimate of an accepted step (adaptive; 0 for fixed steps)"),
    f("dimensionless.scaled_weight", "", "scaled weight W = rho g a^2 L^3 / B"),
    f("dimensionless.aspect_ratio", "", "aspect ratio L / a"),
    f("stats.steps", "", "accepted steps (static: load increments)"),
    f("stats.newton_iterations", "", "Newton iterations over all accepted steps, including those of semi-smooth attempts that retried or fell back"),
    f("stats.rejected_iterations", "", "Newton iterations of solved steps that the adaptive error control rejected"),
    f("stats.step_halvings", "", "failed attempts retried with dt/2"),
    f("stats.ground_point_fallbacks", "", "fixed steps that failed with ground contact on the curve after every halving and were taken with contact at the nodes"),
    f("stats.backtracks", "", "line-search backtracks"),
    f("stats.factorizations", "", "numeric factorisations of the Newton Hessian (every try, shifted ones included)"),
    f("stats.shifted_factorizations", "", "factorisations that needed a diagonal shift"),
    f("stats.assembly_s", "s", "time in energy, gradient and Hessian assembly"),
    f("stats.factor_s", "s", "time in numeric factorisation"),
    f("stats.solve_s", "s", "time in triangular solves"),
    f("stats.line_search_s", "s", "time in line-search energy evaluations"),
    f("stats.conic_solves", "", "conic (Clarabel) solves"),
    f("stats.conic_iterations", "", "Clarabel interior-point iterations over all solves"),
    f("stats.conic_s", "s", "time in Clarabel (set-up and solve)"),
    f("stats.warm_conic_restarts", "", "fallbacks whose warm-started conic path failed and was rerun from the step's start"),
    f("stats.semismooth_steps", "", "contact steps solved by the semi-smooth Newton alone (solver.contact = \"semi-smooth\")"),
    f("stats.semismooth_fallbacks", "", "contact steps where the semi-smooth Newton failed and the conic path ran"),
    f("stats.semismooth_retries", "", "semi-smooth attempts that failed and started again from the step's start with another penalty (solver.semi_smooth_retries); a step a retry solves is no fallback"),
    f("stats.ground_point_rechoices", "", "contact solves made again because a node with its ground contact on the curve sank below the ground (by more than 5e-7 a) at the step's solution; its point was chosen again there"),
    f("stats.ground_point_rechoice_limits", "", "steps whose points on the curve were chosen again 4 times and still left a node below the ground (taken as they were)"),
    f("stats.semismooth_residual_stops", "", "semi-smooth steps that converged by their residual: force balance and Alart-Curnier residuals within normal_force_tolerance * W / n_c and the positions settled, while the Newton direction still moved the contact forces"),
    f("stats.certificates", "", "semi-smooth steps certified by one conic program from their solution (solver.conic_certificate = N: every N-th step; 0 without)"),
    f("stats.certificate_failures", "", "certified steps whose conic program moved the solution by more than the Newton tolerance or changed a normal force by more than normal_force_tolerance * W / n_c"),
    f("stats.certificate_max_correction", "", "largest correction of a certifying conic program, in units of solver.tolerance (positions over a, angles in rad)"),
    f("stats.certificate_max_normal_change", "", "largest normal-force change of a certifying conic program, in units of normal_force_tolerance * W / n_c"),
    f("stats.hessian_reuses", "", "semi-smooth iterations that kept the bending and twist Hessian of an earlier iterate of the step (solver.hessian_reuse) and assembled their gradient alone"),
    f("stats.projected_iterations", "", "Newton iterations assembled with projected (positive semi-definite) stencil Hessians"),
    f("max_penetration", "m", "largest penetration below z = a/2 (0 without a ground)"),
    f("self_contact.enabled", "", "whether the run had self-contact ([self_contact] enabled)"),
    f("self_contact.closest_over_a", "", "closest centreline distance between parts of the body more than 2a apart along it, over a: over every accepted step (exact below 1 + activation) and every recorded frame; null when no pair is eligible"),
    f("self_contact.active_steps", "", "accepted steps that ended with a pair within the activation gap (the barrier acting)"),
    f("self_contact.max_force", "N", "largest force of one self-contact pair at the end of a step"),
    f("self_contact.max_pairs", "", "most self-contact pairs within the activation gap at once"),
    f("centroid_displacement", "m", "centroid displacement [x, y, z] from the first to the last frame"),
    f("slip_speed_max", "m/s", "fastest slip of a node in contact over every accepted step (0 when nothing touches)"),
    f("normal_force_final", "N", "summed normal force at the end"),
    f("conic_iterations_mean", "", "Clarabel iterations per conic solve"),
    f("conic_solves_per_step", "", "conic solves per accepted step"),
    f("v_s", "m/s", "mean forward speed of the centroid along the initial tail-to-head direction"),
    f("v_s_over_v_m", "", "v_s over the muscles' travelling speed v_m (NaN without a gait)"),
    f("displacement", "m", "centroid displacement [forward along the initial head direction, lateral]"),
    f("displacement_angle_deg", "degrees", "angle of the net displacement from the initial head direction (0 to 180)"),
    f("writhe_max", "turns", "largest |writhe| over the observation frames (T/200, independent of [output] interval)"),
    f("writhe_snapshot", "turns", "signed writhe at the frame nearest to writhe_snapshot_t (NaN without a gait)"),
    f("writhe_snapshot_t", "s", "time of that frame: nearest to (L/2 - s_b0) / v_m, when couple b passes mid-body"),
    f("writhe_mean", "turns", "mean writhe over the frames"),
    f("link_max", "turns", "largest |link| over the frames"),
    f("lambda_pulse_speed", "m/s", "speed of the link-density (lambda) peak along the body, from a linear fit"),
    f("lambda_pulse_speed_over_v_m", "", "lambda_pulse_speed / v_m"),
    f("lambda_pulse_r2", "", "R^2 of that fit"),
    f("lambda_amplitude_variation", "", "(max - min) / max of the peak |lambda| over the fitted frames"),
    f("max_elevation_over_a", "", "largest elevation of any node over the diameter a: the body's highest point, possibly an end"),
    f("arc_lift_max_over_a", "", "largest elevation over a of a node between two ground contacts: the highest arc (a lifted end is not an arc)"),
    f("max_elevation_over_length", "", "largest elevation over L"),
    f("lifted_arcs_max", "", "most separate arcs lifted at least a/2 at one instant"),
    f("two_arc_lift_over_a", "", "height over a of the lower of two arcs on either side of a ground contact, at the instant that maximises it"),
    f("middle_slip_over_v_m", "", "median over the pulse frames of the middle contact's mean slip speed (between couples a and c), over v_m"),
    f("middle_static_fraction", "", "fraction of the pulse frames in which the middle contact exists and slips below 0.1 v_m"),
    f("two_patch_fraction", "", "fraction of frames with at least two separate contact patches"),
    f("contact_slip_over_v_m", "", "median slip speed of contact nodes over v_m"),
    f("regime", "", "locomotion regime: \"S\", \"M\", \"F\", \"N\" or \"U\" (guide: Regimes)"),
    f("regime_reason.text", "", "the deciding comparisons in one line"),
    f("regime_reason.not_s", "", "for M: the S criteria it missed (heading, two_arcs, pulse_fit, pulse_speed)"),
    f("regime_reason.checks[].quantity", "", "a quantity the classification compared, e.g. v_s_over_v_m"),
    f("regime_reason.checks[].value", "", "its value"),
    f("regime_reason.checks[].op", "", "the comparison: <, <=, > or >="),
    f("regime_reason.checks[].threshold", "", "the threshold it was compared with"),
    f("regime_reason.checks[].holds", "", "whether the comparison holds (false for NaN)"),
    only("periodic.period", "s", SIDEWINDING, "launch period P of the gait"),
    only("periodic.settling_cycles", "", SIDEWINDING, "cycles at the start that are not measured (1)"),
    only("periodic.cycles[].index", "", SIDEWINDING, "cycle number k, counted from 0 at the first launch: the interval [k P, (k + 1) P]"),
    only("periodic.cycles[].t_start", "s", SIDEWINDING, "time of the cycle's first observation frame"),
    only("periodic.cycles[].t_end", "s", SIDEWINDING, "time of its last observation frame"),
    only("periodic.cycles[].displacement_over_length", "", SIDEWINDING, "centroid displacement over the cycle (ground plane), over L"),
    only("periodic.cycles[].travel_angle_deg", "degrees", SIDEWINDING, "angle between that displacement and the cycle-mean tail-to-head axis (0 to 180; 90 is broadside)"),
    only("periodic.cycles[].broadside_deg", "degrees", SIDEWINDING, "min(travel_angle_deg, 180 - travel_angle_deg)"),
    only("periodic.cycles[].turn_deg", "degrees", SIDEWINDING, "signed rotation of the tail-to-head direction over the cycle (counter-clockwise positive)"),
    only("periodic.cycles[].lateral_speed_over_v_m", "", SIDEWINDING, "displacement across the cycle-mean axis over P v_m"),
    only("periodic.cycles[].along_speed_over_v_m", "", SIDEWINDING, "displacement along the cycle-mean axis (tail to head positive) over P v_m"),
    only("periodic.cycles[].stationary_contact_share", "", SIDEWINDING, "share of the contact node-time with slip at most 0.1 v_m"),
    only("periodic.cycles[].stationary_body_fraction", "", SIDEWINDING, "mean share of all nodes in stationary contact"),
    only("periodic.cycles[].contact_patches_mean", "", SIDEWINDING, "mean number of contact patches per frame"),
    only("periodic.lateral_speed_over_v_m", "", SIDEWINDING, "mean lateral speed over v_m of the measured cycles"),
    only("periodic.turn_deg_mean_abs", "degrees", SIDEWINDING, "mean |turn| per cycle"),
    only("periodic.broadside_deg_min", "degrees", SIDEWINDING, "smallest broadside angle over the cycles"),
    only("periodic.turn_deg_max_abs", "degrees", SIDEWINDING, "largest |turn| over the cycles"),
    only("periodic.displacement_over_length_min", "", SIDEWINDING, "smallest displacement per cycle over L"),
    only("periodic.stationary_contact_share_min", "", SIDEWINDING, "smallest stationary contact share over the cycles"),
    only("periodic.spread.displacement_over_length", "", SIDEWINDING, "range (max - min) over the cycles of displacement_over_length"),
    only("periodic.spread.broadside_deg", "degrees", SIDEWINDING, "range over the cycles of broadside_deg"),
    only("periodic.spread.turn_deg", "degrees", SIDEWINDING, "range over the cycles of turn_deg"),
    only("periodic.spread.lateral_speed_over_v_m", "", SIDEWINDING, "range over the cycles of lateral_speed_over_v_m"),
    only("periodic.spread.stationary_contact_share", "", SIDEWINDING, "range over the cycles of stationary_contact_share"),
    only("periodic.sidewinding", "", SIDEWINDING, "whether every sidewinding criterion holds (guide: Regimes)"),
    only("periodic.sidewinding_margin", "", SIDEWINDING, "how far the worst cycle lies inside the four criteria: the smallest of (share - 0.8)/0.8, (displacement - 0.1 L)/0.1 L, (5 - |turn|)/5, (broadside - 60)/60; negative when one fails, null with fewer than 4 cycles"),
    only("periodic.sidewinding_checks[].quantity", "", SIDEWINDING, "a sidewinding criterion: cycles, broadside_deg_min, turn_deg_max_abs, displacement_over_length_min or stationary_contact_share_min"),
    only("periodic.sidewinding_checks[].value", "", SIDEWINDING, "its value"),
    only("periodic.sidewinding_checks[].op", "", SIDEWINDING, "the comparison: <= or >="),
    only("periodic.sidewinding_checks[].threshold", "", SIDEWINDING, "the threshold"),
    only("periodic.sidewinding_checks[].holds", "", SIDEWINDING, "whether it holds (false for NaN)"),
    f("head_final", "m", "head (s = 0) position at the end"),
    f("tail_final", "m", "tail position at the end"),
    only("accuracy.target", "", ACCURACY, "allowed relative error of v_s/v_m"),
    only("accuracy.integrator", "", ACCURACY, "how time was refined: \"implicit\" (fixed steps halved) or \"bdf2-adaptive\" (tolerance divided by ten)"),
    only("accuracy.elements", "", ACCURACY, "chosen mesh"),
    only("accuracy.dt", "s", ACCURACY, "chosen fixed step (implicit Euler only)"),
    only("accuracy.error_tolerance", "", ACCURACY, "chosen error tolerance, fraction of L per step (adaptive BDF2 only)"),
    only("accuracy.time_error", "", ACCURACY, "estimated relative error of v_s/v_m from the time stepping"),
    only("accuracy.time_error_elements", "", ACCURACY, "the mesh the time error was measured on (the chosen one)"),
    only("accuracy.mesh_error", "", ACCURACY, "estimated relative error of v_s/v_m from the mesh"),
    only("accuracy.estimated_error", "", ACCURACY, "time_error + mesh_error"),
    only("accuracy.met", "", ACCURACY, "whether the estimate is below the target and its runs converge (differences that shrink)"),
    only("accuracy.time_order_observed", "", ACCURACY, "observed order of the time estimate's three runs (absent with two, or when they do not converge)"),
    only("accuracy.mesh_order_observed", "", ACCURACY, "observed order in the element length of the mesh estimate's three runs (absent with two, or when they do not converge)"),
    only("accuracy.v_s_over_v_m_extrapolated", "", ACCURACY, "Richardson extrapolation of v_s/v_m to the limits of time and mesh refinement"),
    only("accuracy.v_s_over_v_m_extrapolated_uncertainty", "", ACCURACY, "its uncertainty (absolute): the answer's estimated error plus the extrapolation's correction, so its interval contains the answer's; the answer is the chosen run's v_s/v_m"),
    only("accuracy.runs[].elements", "", ACCURACY, "a selection run's mesh"),
    only("accuracy.runs[].dt", "s", ACCURACY, "its fixed step (implicit Euler)"),
    only("accuracy.runs[].error_tolerance", "", ACCURACY, "its error tolerance (adaptive BDF2)"),
    only("accuracy.runs[].v_s_over_v_m", "", ACCURACY, "its v_s/v_m (NaN when it failed)"),
    only("accuracy.runs[].steps", "", ACCURACY, "its accepted steps"),
    only("accuracy.runs[].wall_time_s", "s", ACCURACY, "its wall time"),
    only("accuracy.runs[].status", "", ACCURACY, "\"ok\" or the failure"),
    only("accuracy.probes_wall_time_s", "s", ACCURACY, "wall time of the probes: every selection run except the chosen one"),
    only("accuracy.wall_time_total_s", "s", ACCURACY, "wall time of all selection runs, the chosen one included"),
    only("accuracy.elapsed_s", "s", ACCURACY, "elapsed time of the whole selection, whose runs go in parallel (one per core)"),
    only("ensemble.runs", "", ENSEMBLE, "K, the perturbed runs (besides the run the rest of the file describes, which is not perturbed)"),
    only("ensemble.finished", "", ENSEMBLE, "perturbed runs that finished"),
    only("ensemble.seed", "", ENSEMBLE, "the ensemble's seed (--ensemble-seed)"),
    only("ensemble.perturbation.friction", "", ENSEMBLE, "relative standard deviation of each friction coefficient's factor"),
    only("ensemble.perturbation.shape", "", ENSEMBLE, "size of the sideways initial bend, in diameters a"),
    only("ensemble.perturbation.step", "", ENSEMBLE, "step ladder: the runs' steps go geometrically from dt/step to dt*step"),
    only("ensemble.stats.<observable>.mean", "", ENSEMBLE, "mean of a scalar observable (any numeric key above from v_s to contact_slip_over_v_m, and for a gait with a launch period periodic.cycles, periodic.lateral_speed_over_v_m, periodic.turn_deg_mean_abs, periodic.broadside_deg_min, periodic.turn_deg_max_abs, periodic.displacement_over_length_min, periodic.stationary_contact_share_min, periodic.sidewinding_margin and periodic.sidewinding, 1 or 0) over the finished runs, e.g. ensemble.stats.v_s_over_v_m.mean; unit of the observable"),
    only("ensemble.stats.<observable>.sd", "", ENSEMBLE, "its sample standard deviation (n - 1); null for one value, where it is undefined"),
    only("ensemble.stats.<observable>.min", "", ENSEMBLE, "its smallest value"),
    only("ensemble.stats.<observable>.max", "", ENSEMBLE, "its largest value"),
    only("ensemble.stats.<observable>.n", "", ENSEMBLE, "runs with a finite value"),
    only("ensemble.regime_votes.<label>", "", ENSEMBLE, "runs per regime label (S, M, F, N, U; \"-\" for a failed run)"),
    only("ensemble.members[].index", "", ENSEMBLE, "a run's index k (0-based)"),
    only("ensemble.members[].seed", "", ENSEMBLE, "its seed (reruns it alone)"),
    only("ensemble.members[].dt", "s", ENSEMBLE, "the step it ran with, at most the duration (adaptive: the first step; static: null)"),
    only("ensemble.members[].error_tolerance", "", ENSEMBLE, "adaptive runs: the error tolerance it ran with (the ladder scales it)"),
    only("ensemble.members[].step_factor", "", ENSEMBLE, "its step over the file's (adaptive: its tolerance over the file's; static: 1, no ladder)"),
    only("ensemble.members[].friction_factors", "", ENSEMBLE, "factors of mu_forward, mu_backward, mu_sideways"),
    only("ensemble.members[].shape_rms_over_a", "", ENSEMBLE, "RMS sideways offset of its initial shape over a"),
    only("ensemble.members[].status", "", ENSEMBLE, "\"ok\" or \"failed\""),
    only("ensemble.members[].regime", "", ENSEMBLE, "its regime, \"-\" when failed"),
    only("ensemble.members[].observables.<observable>", "", ENSEMBLE, "its scalar observables (null when failed or not finite)"),
    only("ensemble.members[].wall_time_s", "s", ENSEMBLE, "its wall time"),
    only("ensemble.members[].reason", "", ENSEMBLE, "why it failed (absent when ok)"),
    only("ensemble.wall_time_s", "s", ENSEMBLE, "wall time of the ensemble (runs in parallel)"),
];

/// Columns of `phase.csv` (`slither phase`, `slither merge`), in order; `refine.csv` has the
/// same columns. Every value the regime depends on is here, so a study can be relabelled
/// without simulating again.
pub const PHASE_CSV: &[Field] = &[
    f(
        "weight",
        "",
        "scaled weight W = rho g a^2 L^3 / B of the cell",
    ),
    f(
        "torque",
        "",
        "scaled torque G = Gamma a^3 L / B of the cell",
    ),
    f(
        "W_over_G",
        "",
        "W / G = rho g L^2 / (Gamma a), weight against muscle",
    ),
    f("status", "", "\"ok\" or \"failed\""),
    f("regime", "", "S, M, F, N or U; \"-\" when failed"),
    f("v_s_over_v_m", "", "forward speed over the muscles' speed"),
    f(
        "displacement_angle_deg",
        "degrees",
        "heading of the net displacement off the initial head direction",
    ),
    f("max_elevation_over_a", "", "largest elevation over a"),
    f(
        "lifted_arcs_max",
        "",
        "most arcs lifted at least a/2 at one instant",
    ),
    f("writhe_max", "turns", "largest |writhe|"),
    f("lambda_pulse_r2", "", "R^2 of the lambda pulse fit"),
    f(
        "regime_detail",
        "",
        "for M: the S criteria it missed, ;-separated; \"-\" otherwise",
    ),
    f("max_elevation_over_length", "", "largest elevation over L"),
    f(
        "two_arc_lift_over_a",
        "",
        "lower of two arcs around a ground contact, over a",
    ),
    f(
        "lambda_pulse_speed_over_v_m",
        "",
        "speed of the lambda pulse over v_m",
    ),
    f(
        "writhe_snapshot",
        "turns",
        "writhe when couple b is at mid-body",
    ),
    f("wall_time_s", "s", "wall time of the cell's simulation"),
    f(
        "base_hash",
        "",
        "hash of the base problem file (and chosen model), the resume key",
    ),
    f("reason", "", "why it failed (empty when ok)"),
];

/// The columns a verified phase study (`[phase] verify = { ... }`) adds to `phase.csv` and
/// `refine.csv`, after [`PHASE_CSV`]'s; the row's other values are then its reported run's
/// (the finer run with `finer = true`).
pub const PHASE_VERIFY_CSV: &[Field] = &[
    f("label_agreement", "", "fraction of the cell's runs (the study's, the finer one, the perturbed ones) whose label is the reported one, and for a gait with a launch period whose sidewinding verdict is too; a failed run agrees with nothing"),
    f("v_s_over_v_m_min", "", "smallest v_s/v_m over the cell's runs that finished"),
    f("v_s_over_v_m_max", "", "largest v_s/v_m over them"),
    f("regime_base", "", "the label at the study's resolution (\"-\" when failed)"),
    f("regime_finer", "", "the label at the finer resolution, half the step and twice the elements (\"-\" when failed or without finer = true)"),
    f("verify_runs", "", "runs of the cell"),
    f("verify_seed", "", "the cell's seed (hex): perturbed run k has seed ensemble::member_seed(seed, k)"),
];

/// The periodic columns ([`crate::studies::optimize::PERIODIC_COLUMNS`]): in [`HISTORY_CSV`] and, last,
/// in [`PHASE_PERIODIC_CSV`].
const PERIODIC_CYCLES: Field = f(
    "periodic_cycles",
    "",
    "measured cycles after the settling one (a gait with a launch period; the periodic columns are empty otherwise)",
);
const PERIODIC_DISPLACEMENT: Field = f(
    "displacement_over_length_min",
    "",
    "smallest centroid displacement per cycle, over L",
);
const PERIODIC_BROADSIDE: Field = f(
    "broadside_deg_min",
    "degrees",
    "smallest broadside angle per cycle (90 is broadside)",
);
const PERIODIC_TURN: Field = f(
    "turn_deg_max_abs",
    "degrees",
    "largest |turn| of the tail-to-head direction per cycle",
);
const PERIODIC_STATIONARY: Field = f(
    "stationary_contact_share_min",
    "",
    "smallest share per cycle of the contact time with slip at most 0.1 v_m",
);
const PERIODIC_SIDEWINDING: Field = f(
    "sidewinding",
    "",
    "\"yes\" when every sidewinding criterion holds, else \"no\"",
);

/// The columns a phase study of a gait with a launch period (sidewinding) adds last to
/// `phase.csv`, `refine.csv` and `growth.csv` (after the verification columns of a verified
/// study): the periodic observables of the row's run, as in [`HISTORY_CSV`]; empty for a run
/// that failed or has no couple (`G = 0`).
pub const PHASE_PERIODIC_CSV: &[Field] = &[
    PERIODIC_CYCLES,
    PERIODIC_DISPLACEMENT,
    PERIODIC_BROADSIDE,
    PERIODIC_TURN,
    PERIODIC_STATIONARY,
    PERIODIC_SIDEWINDING,
];

/// Columns of `history.csv` (`slither optimize`), in order.
pub const HISTORY_CSV: &[Field] = &[
    f("eval", "", "evaluation number"),
    f("stress", "Pa", "muscle stress Gamma"),
    f("sigma", "fraction of L", "couple width"),
    f("speed", "m/s", "travelling speed v_m"),
    f(
        "period",
        "s",
        "launch period of a sidewinding gait (gait.period; empty in a row rewritten from an older file for another base)",
    ),
    f(
        "spacing",
        "fraction of L",
        "the triplet's spacing centers[1] - centers[0] (empty as period)",
    ),
    f(
        "lift",
        "",
        "the out-of-plane couple's scale, scales[1] (empty as period)",
    ),
    f("duration", "s", "simulated duration"),
    f("G", "", "scaled torque Gamma a^3 L / B"),
    f("W", "", "scaled weight rho g a^2 L^3 / B"),
    f("v_s", "m/s", "forward speed"),
    f("v_s_over_v_m", "", "v_s / v_m"),
    f("writhe_max", "turns", "largest |writhe|"),
    f("writhe_mean", "turns", "mean writhe"),
    f(
        "displacement_angle_deg",
        "degrees",
        "heading off the initial head direction",
    ),
    f("regime", "", "S, M, F, N or U; \"-\" when failed"),
    PERIODIC_CYCLES,
    PERIODIC_DISPLACEMENT,
    PERIODIC_BROADSIDE,
    PERIODIC_TURN,
    PERIODIC_STATIONARY,
    PERIODIC_SIDEWINDING,
    f("status", "", "\"ok\" or \"failed\""),
    f("wall_time_s", "s", "wall time of the simulation"),
    f(
        "objective",
        "m/s",
        "the objective without penalties: -v_s, or with objective = \"broadside\" minus the mean lateral speed per cycle plus turn_penalty times the mean |turn| per cycle and stationary_penalty times the stationary share short of 0.8, or with objective = \"sidewinding\" minus the sidewinding margin (dimensionless); 1000 for a failed run",
    ),
    f(
        "base_hash",
        "",
        "hash of the base problem file (and chosen model), the resume key",
    ),
    f("reason", "", "why it failed (empty when ok)"),
];

/// The CSV header of a column list.
pub fn header(columns: &[Field]) -> String {
    columns.iter().map(|c| c.name).collect::<Vec<_>>().join(",")
}

/// The field of `name` in `fields`.
pub fn find<'a>(fields: &'a [Field], name: &str) -> Option<&'a Field> {
    fields.iter().find(|f| f.name == name)
}

/// Whether `path` (from [`json_paths`]) is documented in `fields`: listed, or an empty array
/// whose entries' keys are listed (`path[].key`). A segment written `<name>` in a field's name
/// (`ensemble.stats.<observable>.mean`) stands for any one key.
pub fn documented(fields: &[Field], path: &str) -> bool {
    let entries = format!("{path}[].");
    let matches = |name: &str, path: &str| {
        let (a, b): (Vec<&str>, Vec<&str>) = (name.split('.').collect(), path.split('.').collect());
        a.len() == b.len()
            && a.iter().zip(&b).all(|(x, y)| {
                x == y || (x.starts_with('<') && x.ends_with('>') && !y.contains('['))
            })
    };
    fields
        .iter()
        .any(|f| matches(f.name, path) || f.name.starts_with(&entries))
}

/// Every key path of a JSON value as [`Field::name`] writes them: objects add `.key`, arrays
/// of objects add `[]` and continue into their entries' keys; scalars and arrays of scalars
/// are leaves.
pub fn json_paths(v: &serde_json::Value) -> Vec<String> {
    fn walk(prefix: &str, v: &serde_json::Value, out: &mut Vec<String>) {
        match v {
            serde_json::Value::Object(map) => {
                for (k, child) in map {
                    let p = if prefix.is_empty() {
                        k.clone()
                    } else {
                        format!("{prefix}.{k}")
                    };
                    walk(&p, child, out);
                }
            }
            serde_json::Value::Array(items) if items.iter().any(|i| i.is_object()) => {
                for item in items {
                    walk(&format!("{prefix}[]"), item, out);
                }
            }
            _ => {
                if !out.iter().any(|o| o == prefix) {
                    out.push(prefix.to_string());
                }
            }
        }
    }
    let mut out = Vec::new();
    walk("", v, &mut out);
    out
}

fn table(out: &mut String, fields: &[Field], what: &str) {
    let cell = |s: &str| s.replace('|', "\\|");
    out.push_str(&format!("| {what} | unit | meaning |\n|---|---|---|\n"));
    for fl in fields {
        let meaning = if fl.when.is_empty() {
            cell(fl.meaning)
        } else {
            format!("{} ({})", cell(fl.meaning), fl.when)
        };
        out.push_str(&format!(
            "| `{}` | {} | {meaning} |\n",
            fl.name,
            cell(fl.unit)
        ));
    }
}

/// The output reference as Markdown (what `slither keys --outputs-markdown` prints and the
/// guide's `outputs.md` holds).
pub fn markdown() -> String {
    let mut out = String::from(
        "# Output reference\n\n\
         <!-- Generated by `slither keys --outputs-markdown` from src/output/schema.rs; do not edit by hand. -->\n\n\
         ## `summary.json` (`slither run`)\n\n\
         Keys are dotted paths into the JSON object; `[]` marks the entries of an array. A failed\n\
         run (`\"status\": \"failed\"`) writes every gait observable and the regime as `null`.\n\n",
    );
    table(&mut out, SUMMARY, "key");
    out.push_str(
        "\n## `phase.csv` (`slither phase`, `slither merge`)\n\n\
         One row per cell, in this column order; `refine.csv` and `growth.csv` have the same columns.\n\n",
    );
    table(&mut out, PHASE_CSV, "column");
    out.push_str(
        "\nA verified study (`[phase] verify = { ... }`) adds these columns after `reason`, in \
         this order; the row's other values are then those of its reported run (the finer one \
         with `finer = true`).\n\n",
    );
    table(&mut out, PHASE_VERIFY_CSV, "column");
    out.push_str(
        "\nA study whose base gait has a launch period (sidewinding) adds the periodic columns \
         last (after the verification columns of a verified study), in this order: the row's \
         run measured cycle by cycle, as in `history.csv`; empty for a run that failed or has no \
         couple (`G = 0`). Other studies' rows are as above.\n\n",
    );
    table(&mut out, PHASE_PERIODIC_CSV, "column");
    out.push_str("\n## `history.csv` (`slither optimize`)\n\nOne row per evaluation, in this column order.\n\n");
    table(&mut out, HISTORY_CSV, "column");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique() {
        for list in [
            SUMMARY,
            PHASE_CSV,
            PHASE_VERIFY_CSV,
            PHASE_PERIODIC_CSV,
            HISTORY_CSV,
        ] {
            for (i, fl) in list.iter().enumerate() {
                assert!(list[..i].iter().all(|o| o.name != fl.name), "{}", fl.name);
            }
        }
    }

    #[test]
    fn json_paths_descend_objects_and_arrays_of_objects() {
        let v: serde_json::Value = serde_json::from_str(
            r#"{"a": 1, "b": {"c": [1, 2], "d": [{"e": 1}, {"e": 2, "f": 3}]}}"#,
        )
        .unwrap();
        let mut p = json_paths(&v);
        p.sort();
        assert_eq!(p, ["a", "b.c", "b.d[].e", "b.d[].f"]);
    }

    #[test]
    fn a_placeholder_segment_matches_one_key() {
        assert!(documented(SUMMARY, "ensemble.stats.v_s.sd"));
        assert!(documented(
            SUMMARY,
            "ensemble.members[].observables.writhe_max"
        ));
        assert!(!documented(SUMMARY, "ensemble.stats.v_s"));
        assert!(!documented(SUMMARY, "ensemble.stats.v_s.sd.x"));
        assert!(!documented(SUMMARY, "ensemble.members.observables.v_s"));
    }
}
