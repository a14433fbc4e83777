//! The optimiser's periodic-gait parameters (`optimize.period`, `optimize.spacing`,
//! `optimize.lift`, `study.duration_periods`) on a tiny sidewinding (16 elements, 10 ms step,
//! three launch periods of 0.4 s): bounds are checked naming file, key, value and range; a
//! study that varies the period runs at the periods it chooses (duration and history columns
//! follow); history rows are reused only for the exact same simulation, whichever parameters
//! the study that wrote them varied; a history file of the older format is read and rewritten.

use slither::studies::{self, optimize::Param, optimize::Status};
use std::path::PathBuf;

mod common;
use common::{col, history_rows, TINY_SIDEWINDING as BASE};

/// The study: period, spacing and lift optimised, three launch periods per run.
const STUDY: &str = "\
# periodic optimiser test study
[study]
base = \"base.toml\"
max_evaluations = 8
duration_periods = 3.0
objective = \"broadside\"

[optimize]
period = [0.3, 0.6]
spacing = [0.08, 0.14]
lift = [0.8, 1.6]
";

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "slither-design-periodic-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn setup(name: &str, base: &str, study: &str) -> PathBuf {
    let dir = scratch(name);
    std::fs::write(dir.join("base.toml"), base).unwrap();
    std::fs::write(dir.join("study.toml"), study).unwrap();
    dir.join("study.toml")
}

/// The error of a study file that must be refused.
fn refused(name: &str, base: &str, study: &str) -> (String, PathBuf) {
    let path = setup(name, base, study);
    match studies::optimize::load_study(&path) {
        Ok(_) => panic!("{name}: accepted:\n{study}"),
        Err(e) => (e.to_string(), path),
    }
}

#[test]
fn periodic_bounds_are_checked_naming_file_key_value_and_range() {
    // A valid study: three dimensions in column order, starting at the base's values.
    let path = setup("valid", BASE, STUDY);
    let s = studies::optimize::load_study(&path).unwrap();
    let params: Vec<Param> = s.space.dims.iter().map(|d| d.param).collect();
    assert_eq!(params, [Param::Period, Param::Spacing, Param::Lift]);
    let x0 = s.space.initial();
    assert_eq!((x0.period, x0.lift), (0.4, 1.2));
    assert!((x0.spacing - 0.1).abs() < 1e-15);
    assert_eq!(s.duration(&x0), 1.2000000000000002);

    let cases: &[(&str, &str, &str, &str, &[&str])] = &[
        // (name, base, replace, by, the message must contain)
        (
            "period_lohi",
            BASE,
            "period = [0.3, 0.6]",
            "period = [0.6, 0.3]",
            &[
                "`optimize.period` = [0.6, 0.3]",
                "0 < lo < hi",
                "(s)",
                ":9:",
            ],
        ),
        (
            "period_zero",
            BASE,
            "period = [0.3, 0.6]",
            "period = [0.0, 0.6]",
            &["`optimize.period` = [0, 0.6]", "0 < lo < hi"],
        ),
        (
            "spacing_off_body",
            BASE,
            "spacing = [0.08, 0.14]",
            "spacing = [0.08, 0.6]",
            &[
                "`optimize.spacing` = [0.08, 0.6]",
                "gait.centers[0] + 2 hi = 0 + 2 hi <= 1",
                ":10:",
            ],
        ),
        (
            "lift_lohi",
            BASE,
            "lift = [0.8, 1.6]",
            "lift = [1.6, 1.6]",
            &["`optimize.lift` = [1.6, 1.6]", "lo < hi", "gait.scales[1]"],
        ),
        (
            "initial_period",
            BASE,
            "lift = [0.8, 1.6]",
            "lift = [0.8, 1.6]\ninitial = { period = 0.9 }",
            &["`optimize.initial.period` = 0.9", "in [0.3, 0.6] (s)"],
        ),
        (
            "base_outside",
            BASE,
            "period = [0.3, 0.6]",
            "period = [0.5, 0.6]",
            &[
                "`optimize.period`",
                "containing the base file's gait.period = 0.4",
            ],
        ),
        (
            "both_durations",
            BASE,
            "duration_periods = 3.0",
            "duration_periods = 3.0\nduration_pulses = 1.0",
            &[
                "`study.duration_periods` = 3",
                "absent when study.duration_pulses",
            ],
        ),
        (
            "stationary_without_broadside",
            BASE,
            "objective = \"broadside\"",
            "stationary_penalty = 1.0",
            &[
                "`study.stationary_penalty` = 1",
                "only with objective = \"broadside\"",
            ],
        ),
        (
            "periods_nonpositive",
            BASE,
            "duration_periods = 3.0",
            "duration_periods = -1.0",
            &["`study.duration_periods` = -1", "(0, 1000]"],
        ),
    ];
    for (name, base, from, to, want) in cases {
        let study = STUDY.replace(from, to);
        assert_ne!(study, STUDY, "{name}");
        let (err, path) = refused(name, base, &study);
        assert!(err.contains(&path.display().to_string()), "{name}: {err}");
        for w in *want {
            assert!(err.contains(w), "{name}: {err:?} lacks {w:?}");
        }
    }

    // Uneven centres: the spacing cannot set them.
    let (err, _) = refused(
        "uneven",
        &BASE.replace("centers = [0.0, 0.1, 0.2]", "centers = [0.0, 0.1, 0.3]"),
        STUDY,
    );
    assert!(
        err.contains("`optimize.spacing`") && err.contains("not evenly spaced"),
        "{err}"
    );

    // A serpenoid has no period, no triplet and no launch period.
    let serpenoid = BASE
        .replace("kind = \"sidewinding\"", "kind = \"serpenoid\"")
        .replace("sigma = 0.07\n", "wavelength = 0.6\n");
    let plain = "[study]\nbase = \"base.toml\"\nmax_evaluations = 8\n\n[optimize]\n";
    for (key, want) in [
        ("period", "unless the base's gait is \"sidewinding\""),
        ("spacing", "\"s-start\" or \"sidewinding\""),
        ("lift", "\"s-start\" or \"sidewinding\""),
    ] {
        let (err, _) = refused(
            &format!("serpenoid_{key}"),
            &serpenoid,
            &format!("{plain}{key} = [0.2, 0.6]\n"),
        );
        assert!(
            err.contains(&format!("`optimize.{key}`")) && err.contains(want),
            "{key}: {err}"
        );
    }
    let (err, _) = refused(
        "serpenoid_periods",
        &serpenoid,
        &format!("{plain}stress = [6000.0, 30000.0]\n").replace(
            "max_evaluations = 8",
            "max_evaluations = 8\nduration_periods = 2.0",
        ),
    );
    assert!(
        err.contains("`study.duration_periods` = 2") && err.contains("\"sidewinding\""),
        "{err}"
    );
}

#[test]
fn a_study_varying_the_period_runs_at_the_periods_it_chooses() {
    let path = setup("moves", BASE, STUDY);
    let study = studies::optimize::load_study(&path).unwrap();
    let out = path.parent().unwrap().join("out");
    let r = studies::optimize::optimize(&study, &out, &mut studies::optimize::Silent).unwrap();
    assert_eq!(r.evaluations, 8);
    let mut periods: Vec<f64> = r.visited.iter().map(|v| v.0.point.period).collect();
    periods.sort_by(f64::total_cmp);
    periods.dedup();
    // The initial simplex alone moves the period once (0.4 -> 0.475).
    assert!(periods.len() >= 2, "{periods:?}");
    for (e, _) in &r.visited {
        let p = e.point;
        assert!((0.3..=0.6).contains(&p.period), "{p:?}");
        assert!((0.08..=0.14).contains(&p.spacing), "{p:?}");
        assert!((0.8..=1.6).contains(&p.lift), "{p:?}");
        // Three launch periods, whatever the period.
        assert_eq!(e.duration, 3.0 * p.period);
        // The run measured the period it was given: its cycles are the chosen period long
        // (the periodic columns hold two measured cycles of three).
        if e.status == Status::Ok {
            assert_eq!(e.periodic.unwrap().cycles, 2, "{e:?}");
        }
    }
    // The problem the study simulates carries the point's values.
    let p = r.visited.last().unwrap().0.point;
    let pr = study.problem_at(&p);
    assert_eq!(pr.gait.period, p.period);
    assert_eq!(pr.gait.scales, [0.53, p.lift, 1.0]);
    assert_eq!(
        pr.gait.centers,
        [0.0, p.spacing, 2.0 * p.spacing],
        "the spacing sets the centres from the base's first"
    );
    // history.csv has the new columns, one row per simulation, with the periodic block.
    let rows = history_rows(&out);
    assert_eq!(rows.len(), r.simulations);
    for (row, (e, _)) in rows.iter().zip(r.visited.iter()) {
        assert_eq!(
            row.len(),
            studies::optimize::HISTORY_HEADER.split(',').count()
        );
        assert_eq!(row[col("period")].parse::<f64>().unwrap(), e.point.period);
        assert_eq!(row[col("spacing")].parse::<f64>().unwrap(), e.point.spacing);
        assert_eq!(row[col("lift")].parse::<f64>().unwrap(), e.point.lift);
        if row[col("status")] == "ok" {
            assert_eq!(row[col("periodic_cycles")], "2");
            assert!(["yes", "no"].contains(&row[col("sidewinding")].as_str()));
            let share: f64 = row[col("stationary_contact_share_min")].parse().unwrap();
            assert!((0.0..=1.0).contains(&share), "{share}");
        }
    }
    // optimum.json names the new parameters.
    let j: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("optimum.json")).unwrap()).unwrap();
    assert_eq!(
        j["initial"]["period"].as_f64(),
        Some(0.4),
        "{}",
        j["initial"]
    );
    assert_eq!(j["duration_periods"].as_f64(), Some(3.0));
    assert!(j["initial"]["periodic_cycles"].as_u64().is_some());

    // A rerun replays the study from the rows without simulating.
    let again = studies::optimize::optimize(&study, &out, &mut studies::optimize::Silent).unwrap();
    assert_eq!(again.simulations, 0);
    assert_eq!(again.reused + again.repeats, again.evaluations);
    let points = |r: &studies::optimize::Report| -> Vec<studies::optimize::GaitParams> {
        r.visited.iter().map(|v| v.0.point).collect()
    };
    assert_eq!(points(&again), points(&r));
}

#[test]
fn rows_are_reused_only_for_the_same_simulation_whichever_parameters_were_varied() {
    // Study A varies the stress only, at the base period, spacing and lift.
    let a = STUDY
        .replace("period = [0.3, 0.6]\n", "")
        .replace("spacing = [0.08, 0.14]\n", "")
        .replace("lift = [0.8, 1.6]\n", "stress = [20000.0, 30000.0]\n")
        .replace("max_evaluations = 8", "max_evaluations = 3");
    let path_a = setup("reuse", BASE, &a);
    let dir = path_a.parent().unwrap().to_path_buf();
    let out = dir.join("out");
    let ra = studies::optimize::optimize(
        &studies::optimize::load_study(&path_a).unwrap(),
        &out,
        &mut studies::optimize::Silent,
    )
    .unwrap();
    assert_eq!(ra.simulations, 3);
    // Study B, same base and duration, varies the period from the same start: its start is
    // A's start (same simulation, reused); its other points differ in period and are run.
    let b = STUDY
        .replace("spacing = [0.08, 0.14]\n", "")
        .replace("lift = [0.8, 1.6]\n", "")
        .replace("max_evaluations = 8", "max_evaluations = 4");
    std::fs::write(dir.join("b.toml"), &b).unwrap();
    let study_b = studies::optimize::load_study(&dir.join("b.toml")).unwrap();
    let rb = studies::optimize::optimize(&study_b, &out, &mut studies::optimize::Silent).unwrap();
    assert_eq!(rb.rows_before, 3);
    assert_eq!(rb.reused, 1, "only the shared start is reused");
    assert_eq!(rb.initial.eval, ra.initial.eval);
    assert!(rb.visited[1..]
        .iter()
        .all(|v| v.0.point.period != 0.4 && v.0.eval > 3));
    assert_eq!(history_rows(&out).len(), 3 + rb.simulations);
    // A different duration is a different simulation: nothing reused.
    std::fs::write(
        dir.join("c.toml"),
        b.replace("duration_periods = 3.0", "duration_periods = 2.5"),
    )
    .unwrap();
    let rc = studies::optimize::optimize(
        &studies::optimize::load_study(&dir.join("c.toml")).unwrap(),
        &out,
        &mut studies::optimize::Silent,
    )
    .unwrap();
    assert_eq!(rc.reused, 0);
}

#[test]
fn a_history_of_the_older_format_is_read_reused_and_rewritten() {
    // Study A writes a history; we turn it into the older format (no period, spacing, lift
    // nor periodic columns), as a study before these columns wrote it.
    let a = STUDY
        .replace("period = [0.3, 0.6]\n", "")
        .replace("spacing = [0.08, 0.14]\n", "")
        .replace("lift = [0.8, 1.6]\n", "stress = [20000.0, 30000.0]\n")
        .replace("max_evaluations = 8", "max_evaluations = 3");
    let path = setup("legacy", BASE, &a);
    let out = path.parent().unwrap().join("out");
    let study = studies::optimize::load_study(&path).unwrap();
    let first = studies::optimize::optimize(&study, &out, &mut studies::optimize::Silent).unwrap();
    let legacy_cols: Vec<&str> = studies::optimize::LEGACY_HISTORY_HEADER
        .split(',')
        .collect();
    let mut legacy = format!("{}\n", studies::optimize::LEGACY_HISTORY_HEADER);
    for row in history_rows(&out) {
        let fields: Vec<&str> = legacy_cols.iter().map(|c| row[col(c)].as_str()).collect();
        legacy += &(fields.join(",") + "\n");
    }
    // And one row of another base file, which must survive the rewrite unreused.
    legacy += "9,1000,0.05,0.5,1.2,1,1,0.01,0.02,0,0,10,U,ok,0.1,-0.01,00ff00ff00ff00ff,\n";
    std::fs::write(out.join(studies::optimize::HISTORY_FILE), &legacy).unwrap();

    let h = studies::optimize::read_history(&out.join(studies::optimize::HISTORY_FILE)).unwrap();
    assert!(h.legacy);
    assert_eq!(h.rows.len(), 4);
    assert!(h.rows[0].0.point.period.is_nan() && h.rows[0].0.periodic.is_none());

    let again = studies::optimize::optimize(&study, &out, &mut studies::optimize::Silent).unwrap();
    assert_eq!(
        again.simulations, 0,
        "every row of the older file is reused"
    );
    assert_eq!(again.reused, first.simulations);
    assert_eq!(again.rows_other_base, 1);
    assert_eq!(
        again.best.as_ref().map(|b| b.v_s),
        first.best.as_ref().map(|b| b.v_s)
    );
    // Rewritten in the current format: this base's rows carry the base's period, spacing and
    // lift; the other base's row keeps them empty.
    let rows = history_rows(&out);
    assert_eq!(rows.len(), 4);
    for row in &rows[..3] {
        assert_eq!(row[col("period")], "0.4");
        assert_eq!(row[col("lift")], "1.2");
        assert_eq!(row[col("spacing")].parse::<f64>().unwrap(), 0.1);
        assert_eq!(row[col("periodic_cycles")], "");
    }
    assert_eq!(rows[3][col("period")], "");
    assert_eq!(rows[3][col("base_hash")], "00ff00ff00ff00ff");
    // Read back in the current format, still reused.
    let third = studies::optimize::optimize(&study, &out, &mut studies::optimize::Silent).unwrap();
    assert_eq!(third.simulations, 0);
}

#[test]
fn the_sidewinding_objective_is_minus_the_margin_and_needs_four_cycles() {
    // Six launch periods: five measured cycles, the margin measured.
    let study = STUDY
        .replace("duration_periods = 3.0", "duration_periods = 6.0")
        .replace("objective = \"broadside\"", "objective = \"sidewinding\"")
        .replace("max_evaluations = 8", "max_evaluations = 4");
    let path = setup("margin", BASE, &study);
    let s = studies::optimize::load_study(&path).unwrap();
    assert_eq!(s.objective, studies::optimize::Objective::Sidewinding);
    let e = studies::optimize::simulate(&s, &s.space.initial(), &mut |_| {});
    assert_eq!(e.status, Status::Ok, "{}", e.reason);
    let (m, o) = common::run_problem(&s.problem_at(&s.space.initial()));
    let p = slither::observe::periodic::of_outcome(&m, &o).unwrap();
    assert_eq!(e.objective(), -p.sidewinding_margin());
    assert_eq!(e.periodic.unwrap().sidewinding, p.sidewinding);
    // Three periods hold two measured cycles: the margin is not measured, the run fails.
    let short = study.replace("duration_periods = 6.0", "duration_periods = 3.0");
    let path = setup("margin_short", BASE, &short);
    let s = studies::optimize::load_study(&path).unwrap();
    let e = studies::optimize::simulate(&s, &s.space.initial(), &mut |_| {});
    assert_eq!(e.status, Status::Failed);
    assert!(
        e.reason.contains("fewer than 4 full cycles"),
        "{}",
        e.reason
    );
    // Only for a sidewinding base.
    let serpenoid = BASE
        .replace("kind = \"sidewinding\"", "kind = \"serpenoid\"")
        .replace("sigma = 0.07\n", "wavelength = 0.6\n");
    let (err, _) = refused(
        "margin_serpenoid",
        &serpenoid,
        "[study]\nbase = \"base.toml\"\nobjective = \"sidewinding\"\n\n[optimize]\nstress = [6000.0, 30000.0]\n",
    );
    assert!(
        err.contains("`study.objective` = \"sidewinding\"") && err.contains("\"v_s\" for a base"),
        "{err}"
    );
}
