//! Command-line input handling: every problem-file rule rejects a bad file with exit code 2 and
//! one message naming the file, the key (dotted, e.g. `rod.length`), and for range errors the
//! key's line and the allowed range, without writing `summary.json`; a minimal valid file runs;
//! `slither topology` reports malformed CSV rows by line and handles a planar closed ring.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_slither");

/// A tiny valid dynamic problem (milliseconds to run). The leading comments shift the line
/// numbers so that a reported line is not accidentally right.
const BASE: &str = "\
# slither CLI input test problem
# (comment lines shift the line numbers)

[rod]
length = 1.0
diameter = 0.02
elements = 4
bending_stiffness = 1.0

[gravity]
g = 9.81

[time]
dt = 0.005
duration = 0.01
";

/// A fresh, empty scratch directory unique to this test process and test name.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("slither-cli-input-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `BASE` with the line `old` replaced by `new` (`new` empty: the line removed; `new` may hold
/// several lines).
fn edit(old: &str, new: &str) -> String {
    edit_text(BASE, old, new)
}

fn edit_text(text: &str, old: &str, new: &str) -> String {
    let mut found = false;
    let mut s = String::new();
    for line in text.lines() {
        if line == old {
            found = true;
            if !new.is_empty() {
                s.push_str(new);
                s.push('\n');
            }
        } else {
            s.push_str(line);
            s.push('\n');
        }
    }
    assert!(found, "line {old:?} not in the problem text");
    s
}

/// 1-based number of the first line that starts with `prefix` (after leading blanks).
fn line_of(text: &str, prefix: &str) -> usize {
    text.lines()
        .position(|l| l.trim_start().starts_with(prefix))
        .map(|i| i + 1)
        .unwrap_or_else(|| panic!("{prefix:?} not in text"))
}

struct Run {
    dir: PathBuf,
    problem: PathBuf,
    out: PathBuf,
    output: Output,
}

impl Run {
    fn code(&self) -> Option<i32> {
        self.output.status.code()
    }
    fn stderr(&self) -> String {
        String::from_utf8_lossy(&self.output.stderr).into_owned()
    }
    fn stdout(&self) -> String {
        String::from_utf8_lossy(&self.output.stdout).into_owned()
    }
    fn cleanup(self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// Write `text` to `<scratch>/problem.toml` and run `slither run` on it with `--out <scratch>/out`.
fn run_problem(name: &str, text: &str) -> Run {
    let dir = scratch(name);
    let problem = dir.join("problem.toml");
    std::fs::write(&problem, text).unwrap();
    let out = dir.join("out");
    let output = Command::new(BIN)
        .arg("run")
        .arg(&problem)
        .arg("--out")
        .arg(&out)
        .arg("--quiet")
        .output()
        .expect("run slither");
    Run {
        dir,
        problem,
        out,
        output,
    }
}

/// What a rejected problem file's message must contain.
struct Expect<'a> {
    /// Dotted key, e.g. `rod.length` (parse errors: also the bare key name).
    key: &'a str,
    /// Range errors: the 1-based line reported as `file:line:`. Parse errors: toml's
    /// "line N".
    line: Option<usize>,
    /// Range errors: (part of) the allowed range.
    allowed: Option<&'a str>,
}

/// Run `text`, assert it is rejected as described, and return the message.
fn rejected(name: &str, text: &str, e: Expect) -> String {
    let r = run_problem(name, text);
    let err = r.stderr();
    let ctx = format!("problem:\n{text}\nstderr:\n{err}");
    assert_eq!(r.code(), Some(2), "exit code; {ctx}");
    assert!(r.stdout().is_empty(), "nothing on stdout; {ctx}");
    assert!(err.starts_with("error: "), "one `error:` message; {ctx}");
    assert_eq!(
        err.matches("error:").count(),
        1,
        "exactly one message; {ctx}"
    );
    let file = r.problem.display().to_string();
    assert!(err.contains(&file), "message names the file {file}; {ctx}");
    assert!(
        err.contains(&format!("`{}`", e.key)),
        "message names the key `{}`; {ctx}",
        e.key
    );
    let bare = e.key.rsplit('.').next().unwrap();
    assert!(
        err.contains(bare),
        "message names the key name {bare}; {ctx}"
    );
    if let Some(allowed) = e.allowed {
        // A range error: one line, `file:line: `key` = value is not allowed: must be ...`.
        assert_eq!(err.trim_end().lines().count(), 1, "one line; {ctx}");
        let line = e.line.expect("range errors name a line");
        assert!(
            err.contains(&format!("{file}:{line}: ")),
            "message names line {line}; {ctx}"
        );
        assert!(
            err.contains("must be"),
            "message states the allowed range; {ctx}"
        );
        assert!(
            err.contains(allowed),
            "message states the allowed range {allowed:?}; {ctx}"
        );
    } else if let Some(line) = e.line {
        assert!(
            err.contains(&format!("line {line}")),
            "message names line {line}; {ctx}"
        );
    }
    assert!(
        !r.out.join("summary.json").exists(),
        "no summary.json written; {ctx}"
    );
    r.cleanup();
    err
}

/// A range error on `key` (dotted), reported at the line starting with `line_prefix`.
fn range_error(name: &str, text: &str, key: &str, line_prefix: &str, allowed: &str) -> String {
    let line = line_of(text, line_prefix);
    rejected(
        name,
        text,
        Expect {
            key,
            line: Some(line),
            allowed: Some(allowed),
        },
    )
}

const POSITIVE: &str = "a finite number > 0";

// ---------------------------------------------------------------------------------------------
// A valid file runs.
// ---------------------------------------------------------------------------------------------

#[test]
fn valid_minimal_problem_runs_and_writes_completed_summary() {
    let r = run_problem("valid", BASE);
    let err = r.stderr();
    assert_eq!(r.code(), Some(0), "stderr:\n{err}");
    let summary =
        std::fs::read_to_string(r.out.join("summary.json")).expect("summary.json written");
    let v: serde_json::Value = serde_json::from_str(&summary).expect("summary.json is JSON");
    assert_eq!(v["status"], "completed", "summary:\n{summary}");
    assert!(v["t_final"].as_f64().unwrap() > 0.0, "summary:\n{summary}");
    r.cleanup();
}

// ---------------------------------------------------------------------------------------------
// Unknown keys.
// ---------------------------------------------------------------------------------------------

#[test]
fn unknown_top_level_key() {
    let text = format!("colour = \"green\"\n{BASE}");
    rejected(
        "unknown_top_key",
        &text,
        Expect {
            key: "colour",
            line: Some(1),
            allowed: None,
        },
    );
}

#[test]
fn unknown_top_level_table() {
    let text = format!("{BASE}\n[frction]\nmu = 0.1\n");
    let line = line_of(&text, "[frction]");
    let err = rejected(
        "unknown_table",
        &text,
        Expect {
            key: "frction",
            line: Some(line),
            allowed: None,
        },
    );
    assert!(err.contains("unknown field"), "{err}");
}

#[test]
fn unknown_key_in_rod() {
    let text = edit("elements = 4", "elements = 4\npoisson = 0.5");
    let line = line_of(&text, "poisson");
    let err = rejected(
        "unknown_rod_key",
        &text,
        Expect {
            key: "rod.poisson",
            line: Some(line),
            allowed: None,
        },
    );
    // toml lists the accepted keys.
    assert!(err.contains("bending_stiffness"), "{err}");
}

// ---------------------------------------------------------------------------------------------
// Wrong types.
// ---------------------------------------------------------------------------------------------

#[test]
fn wrong_type_string_for_length() {
    let text = edit("length = 1.0", "length = \"one\"");
    let line = line_of(&text, "length");
    let err = rejected(
        "wrong_type_length",
        &text,
        Expect {
            key: "rod.length",
            line: Some(line),
            allowed: None,
        },
    );
    assert!(err.contains("invalid type"), "{err}");
}

#[test]
fn wrong_type_float_for_elements() {
    let text = edit("elements = 4", "elements = 4.5");
    let line = line_of(&text, "elements");
    rejected(
        "wrong_type_elements",
        &text,
        Expect {
            key: "rod.elements",
            line: Some(line),
            allowed: None,
        },
    );
}

#[test]
fn wrong_type_in_multiline_array_names_its_key() {
    let text = edit(
        "elements = 4",
        "elements = 4\nnatural_curvature = [\n  1.0,\n  \"x\",\n]",
    );
    let line = line_of(&text, "\"x\"");
    rejected(
        "wrong_type_array",
        &text,
        Expect {
            key: "rod.natural_curvature",
            line: Some(line),
            allowed: None,
        },
    );
}

// ---------------------------------------------------------------------------------------------
// Missing required keys.
// ---------------------------------------------------------------------------------------------

#[test]
fn missing_rod_length() {
    let text = edit("length = 1.0", "");
    let err = rejected(
        "missing_length",
        &text,
        Expect {
            key: "rod.length",
            line: None,
            allowed: None,
        },
    );
    assert!(err.contains("missing"), "{err}");
}

#[test]
fn missing_rod_diameter() {
    let text = edit("diameter = 0.02", "");
    let err = rejected(
        "missing_diameter",
        &text,
        Expect {
            key: "rod.diameter",
            line: None,
            allowed: None,
        },
    );
    assert!(err.contains("missing"), "{err}");
}

#[test]
fn missing_rod_bending_stiffness() {
    let text = edit("bending_stiffness = 1.0", "");
    let err = rejected(
        "missing_bending",
        &text,
        Expect {
            key: "rod.bending_stiffness",
            line: None,
            allowed: None,
        },
    );
    assert!(err.contains("missing"), "{err}");
}

#[test]
fn missing_rod_table() {
    let mut text = BASE.to_string();
    for l in [
        "[rod]",
        "length = 1.0",
        "diameter = 0.02",
        "elements = 4",
        "bending_stiffness = 1.0",
    ] {
        text = edit_text(&text, l, "");
    }
    let err = rejected(
        "missing_rod",
        &text,
        Expect {
            key: "rod",
            line: None,
            allowed: None,
        },
    );
    assert!(err.contains("missing"), "{err}");
}

#[test]
fn missing_time_dt_in_dynamic_mode() {
    let text = edit("dt = 0.005", "");
    // Reported at the [time] header.
    let err = range_error("missing_dt", &text, "time.dt", "[time]", "dynamic mode");
    assert!(err.contains("missing"), "{err}");
}

#[test]
fn missing_time_dt_with_explicit_dynamic_mode() {
    let text = edit("dt = 0.005", "mode = \"dynamic\"");
    range_error(
        "missing_dt_explicit",
        &text,
        "time.dt",
        "[time]",
        "dynamic mode",
    );
}

// ---------------------------------------------------------------------------------------------
// Non-positive values.
// ---------------------------------------------------------------------------------------------

#[test]
fn zero_rod_length() {
    let text = edit("length = 1.0", "length = 0.0");
    range_error("zero_length", &text, "rod.length", "length", POSITIVE);
}

#[test]
fn negative_rod_length() {
    let text = edit("length = 1.0", "length = -1.0");
    range_error("negative_length", &text, "rod.length", "length", POSITIVE);
}

#[test]
fn zero_rod_diameter() {
    let text = edit("diameter = 0.02", "diameter = 0");
    range_error("zero_diameter", &text, "rod.diameter", "diameter", POSITIVE);
}

#[test]
fn negative_rod_diameter() {
    let text = edit("diameter = 0.02", "diameter = -0.02");
    range_error(
        "negative_diameter",
        &text,
        "rod.diameter",
        "diameter",
        POSITIVE,
    );
}

#[test]
fn zero_rod_bending_stiffness() {
    let text = edit("bending_stiffness = 1.0", "bending_stiffness = 0.0");
    range_error(
        "zero_bending",
        &text,
        "rod.bending_stiffness",
        "bending_stiffness",
        POSITIVE,
    );
}

#[test]
fn negative_rod_bending_stiffness() {
    let text = edit("bending_stiffness = 1.0", "bending_stiffness = -2.0");
    range_error(
        "negative_bending",
        &text,
        "rod.bending_stiffness",
        "bending_stiffness",
        POSITIVE,
    );
}

#[test]
fn zero_rod_twist_stiffness() {
    let text = edit(
        "bending_stiffness = 1.0",
        "bending_stiffness = 1.0\ntwist_stiffness = 0.0",
    );
    range_error(
        "zero_twist",
        &text,
        "rod.twist_stiffness",
        "twist_stiffness",
        POSITIVE,
    );
}

#[test]
fn negative_rod_twist_stiffness() {
    let text = edit(
        "bending_stiffness = 1.0",
        "bending_stiffness = 1.0\ntwist_stiffness = -0.5",
    );
    range_error(
        "negative_twist",
        &text,
        "rod.twist_stiffness",
        "twist_stiffness",
        POSITIVE,
    );
}

#[test]
fn zero_rod_elements() {
    let text = edit("elements = 4", "elements = 0");
    range_error(
        "zero_elements",
        &text,
        "rod.elements",
        "elements",
        "[2, 100000]",
    );
}

#[test]
fn one_rod_element() {
    let text = edit("elements = 4", "elements = 1");
    range_error(
        "one_element",
        &text,
        "rod.elements",
        "elements",
        "[2, 100000]",
    );
}

#[test]
fn negative_rod_elements() {
    // Not a usize: a toml type error naming the key.
    let text = edit("elements = 4", "elements = -3");
    let line = line_of(&text, "elements");
    rejected(
        "negative_elements",
        &text,
        Expect {
            key: "rod.elements",
            line: Some(line),
            allowed: None,
        },
    );
}

#[test]
fn zero_time_dt() {
    let text = edit("dt = 0.005", "dt = 0");
    range_error("zero_dt", &text, "time.dt", "dt", POSITIVE);
}

#[test]
fn negative_time_dt() {
    let text = edit("dt = 0.005", "dt = -0.001");
    range_error("negative_dt", &text, "time.dt", "dt", POSITIVE);
}

#[test]
fn zero_time_duration() {
    let text = edit("duration = 0.01", "duration = 0.0");
    range_error(
        "zero_duration",
        &text,
        "time.duration",
        "duration",
        POSITIVE,
    );
}

#[test]
fn negative_time_duration() {
    let text = edit("duration = 0.01", "duration = -1.0");
    range_error(
        "negative_duration",
        &text,
        "time.duration",
        "duration",
        POSITIVE,
    );
}

// ---------------------------------------------------------------------------------------------
// NaN and infinity (`nan` and `inf` are valid TOML floats).
// ---------------------------------------------------------------------------------------------

#[test]
fn nan_rod_length() {
    let text = edit("length = 1.0", "length = nan");
    let err = range_error("nan_length", &text, "rod.length", "length", POSITIVE);
    assert!(err.contains("NaN"), "{err}");
}

#[test]
fn infinite_rod_length() {
    let text = edit("length = 1.0", "length = inf");
    let err = range_error("inf_length", &text, "rod.length", "length", POSITIVE);
    assert!(err.contains("inf"), "{err}");
}

#[test]
fn nan_time_dt() {
    let text = edit("dt = 0.005", "dt = nan");
    range_error("nan_dt", &text, "time.dt", "dt", POSITIVE);
}

#[test]
fn infinite_time_dt() {
    let text = edit("dt = 0.005", "dt = +inf");
    range_error("inf_dt", &text, "time.dt", "dt", POSITIVE);
}

// ---------------------------------------------------------------------------------------------
// Gravity and static mode.
// ---------------------------------------------------------------------------------------------

#[test]
fn negative_gravity() {
    let text = edit("g = 9.81", "g = -9.81");
    range_error("negative_g", &text, "gravity.g", "g =", ">= 0");
}

#[test]
fn static_mode_without_clamp() {
    let text = edit("dt = 0.005", "mode = \"static\"\ndt = 0.005");
    let err = range_error("static_no_clamp", &text, "time.mode", "mode", "clamp");
    assert!(err.contains("static"), "{err}");
}

// ---------------------------------------------------------------------------------------------
// `slither topology`.
// ---------------------------------------------------------------------------------------------

fn run_topology(dir: &Path, csv: &str, closed: bool) -> (PathBuf, Output) {
    let path = dir.join("curve.csv");
    std::fs::write(&path, csv).unwrap();
    let mut cmd = Command::new(BIN);
    cmd.arg("topology").arg(&path);
    if closed {
        cmd.arg("--closed");
    }
    (path.clone(), cmd.output().expect("run slither topology"))
}

fn topology_rejects(name: &str, csv: &str, line: usize) -> String {
    let dir = scratch(name);
    let (path, out) = run_topology(&dir, csv, true);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    let ctx = format!("csv:\n{csv}\nstderr:\n{err}");
    assert_eq!(out.status.code(), Some(2), "exit code; {ctx}");
    assert!(out.stdout.is_empty(), "no JSON on stdout; {ctx}");
    assert!(err.starts_with("error: "), "{ctx}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line; {ctx}");
    assert!(
        err.contains(&format!("{}:{line}: ", path.display())),
        "message names the file and line {line}; {ctx}"
    );
    let _ = std::fs::remove_dir_all(&dir);
    err
}

#[test]
fn topology_malformed_csv_names_the_line() {
    let csv = "x,y,z,d1x,d1y,d1z\n0,0,0,0,0,1\n1,0,0,0,0,1\n1,1,0,0,1\n0,1,0,0,0,1\n";
    let err = topology_rejects("topo_fields", csv, 4);
    assert!(err.contains("6 fields"), "{err}");
}

#[test]
fn topology_non_numeric_field_names_the_line() {
    let csv = "x,y,z,d1x,d1y,d1z\n0,0,0,0,0,1\n1,0,0,0,0,1\n1,1,0,0,0,1\n0,one,0,0,0,1\n";
    let err = topology_rejects("topo_number", csv, 5);
    assert!(err.contains("not a number"), "{err}");
}

#[test]
fn topology_planar_square_ring() {
    // A closed square in the xy-plane, d1 = +z everywhere: writhe 0 (planar), and the push-off
    // along d1 is the square lifted out of its plane, which does not wind around it: Gauss
    // link 0 (an integer is not enough: 1 or -1 would be a wrong answer).
    let csv = "x,y,z,d1x,d1y,d1z\n0,0,0,0,0,1\n1,0,0,0,0,1\n1,1,0,0,0,1\n0,1,0,0,0,1\n";
    let dir = scratch("topo_square");
    let (_, out) = run_topology(&dir, csv, true);
    let err = String::from_utf8_lossy(&out.stderr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "stderr:\n{err}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim())
        .unwrap_or_else(|e| panic!("stdout is JSON ({e}):\n{stdout}"));
    let wr = v["wr"].as_f64().expect("wr");
    let lk_gauss = v["lk_gauss"].as_f64().expect("lk_gauss with --closed");
    assert!(wr.abs() <= 1e-12, "wr = {wr}; {stdout}");
    assert!(
        lk_gauss.abs() <= 1e-6,
        "lk_gauss = {lk_gauss}, not 0; {stdout}"
    );
    let tw = v["tw"].as_f64().expect("tw");
    assert!(
        tw.abs() <= 1e-12,
        "tw = {tw}: d1 does not turn about the tangent; {stdout}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

// ---------------------------------------------------------------------------------------------
// `[solver] integrator`.
// ---------------------------------------------------------------------------------------------

#[test]
fn unknown_integrator() {
    let text = format!("{BASE}\n[solver]\nintegrator = \"verlet\"\n");
    let line = line_of(&text, "integrator");
    let err = rejected(
        "unknown_integrator",
        &text,
        Expect {
            key: "solver.integrator",
            line: Some(line),
            allowed: None,
        },
    );
    // toml lists the allowed values.
    assert!(
        err.contains("implicit") && err.contains("explicit"),
        "{err}"
    );
}

#[test]
fn explicit_integrator_with_ground() {
    let text =
        format!("{BASE}\n[solver]\nintegrator = \"explicit\"\n\n[ground]\nmu_forward = 0.1\n");
    let err = range_error(
        "explicit_ground",
        &text,
        "solver.integrator",
        "integrator",
        "\"implicit\" or \"bdf2\" when a [ground] is present",
    );
    assert!(err.contains("no contact"), "{err}");
}

#[test]
fn explicit_integrator_in_static_mode() {
    let text = edit("dt = 0.005", "mode = \"static\"\ndt = 0.005");
    let text = edit_text(
        &text,
        "bending_stiffness = 1.0",
        "bending_stiffness = 1.0\nclamp = \"tail\"",
    );
    let text = format!("{text}\n[solver]\nintegrator = \"explicit\"\n");
    range_error(
        "explicit_static",
        &text,
        "solver.integrator",
        "integrator",
        "\"implicit\" in static mode",
    );
}

#[test]
fn explicit_integrator_runs_below_its_limit_and_fails_above_it() {
    // BASE: 4 elements of 0.25 m, EA = 16 B / a^2 = 4e4 N: the explicit limit is about
    // l0 sqrt(rho A / EA) = 7e-4 s.
    // Clamped, so that the rod deforms (a free rod only falls).
    let clamped = edit(
        "bending_stiffness = 1.0",
        "bending_stiffness = 1.0\nclamp = \"tail\"",
    );
    let fine = edit_text(&clamped, "dt = 0.005", "dt = 2.5e-4");
    let fine = format!("{fine}\n[solver]\nintegrator = \"explicit\"\n");
    let r = run_problem("explicit_fine", &fine);
    let err = r.stderr();
    assert_eq!(r.code(), Some(0), "stderr:\n{err}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(r.out.join("summary.json")).unwrap())
            .unwrap();
    assert_eq!(v["status"], "completed");
    assert_eq!(v["steps"], 40);
    r.cleanup();
    // At BASE's dt = 0.005 s (over 20 steps) the run blows up: exit code 3, the instant and the step named,
    // results so far written with "status": "failed".
    let coarse = edit_text(&clamped, "duration = 0.01", "duration = 0.1");
    let coarse = format!("{coarse}\n[solver]\nintegrator = \"explicit\"\n");
    let r = run_problem("explicit_coarse", &coarse);
    let err = r.stderr();
    assert_eq!(r.code(), Some(3), "stderr:\n{err}");
    assert!(
        err.contains("explicit integrator unstable at t = ") && err.contains("dt = 0.005 s"),
        "{err}"
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(r.out.join("summary.json")).unwrap())
            .unwrap();
    assert_eq!(v["status"], "failed");
    r.cleanup();
}

#[test]
fn dotted_key_range_error_names_its_own_line() {
    // The same key written as a dotted key at the top level: the error names its line, not
    // line 1.
    let text = BASE.replace("[gravity]\ng = 9.81\n", "").replace(
        "# (comment lines shift the line numbers)\n",
        "# (comment lines shift the line numbers)\ngravity.g = -3.0\n",
    );
    range_error(
        "dotted_gravity",
        &text,
        "gravity.g",
        "gravity.g",
        "a finite number >= 0",
    );
}

#[test]
fn solver_settings_out_of_range() {
    for (i, (line, key, allowed)) in [
        ("armijo = 0.7", "solver.armijo", "in (0, 0.5)"),
        (
            "normal_force_tolerance = 0.0",
            "solver.normal_force_tolerance",
            "in (0, 1]",
        ),
        (
            "max_backtracks = 0",
            "solver.max_backtracks",
            "an integer in [1, 200]",
        ),
        (
            "clarabel_method = \"mkl\"",
            "solver.clarabel_method",
            "\"qdldl\" or \"faer\"",
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let text = format!("{BASE}\n[solver]\n{line}\n");
        let prefix = line.split(' ').next().unwrap();
        range_error(&format!("solver_{i}"), &text, key, prefix, allowed);
    }
}

/// The retired active-set solver and the keys only it used: one message naming the file, the
/// line, the key and what to write instead, and saying the solver was retired with the record
/// that justifies it. The replacement key of the semi-smooth Newton's cap runs.
#[test]
fn retired_active_set_solver_and_its_keys_are_refused() {
    for (i, (line, key, allowed)) in [
        (
            "contact = \"active-set\"",
            "solver.contact",
            "\"semi-smooth\" or \"conic\"",
        ),
        (
            "active_set_max_iterations = 50",
            "solver.active_set_max_iterations",
            "solver.semi_smooth_max_iterations",
        ),
        (
            "active_set_extra_switches = 8",
            "solver.active_set_extra_switches",
            "only the active set used it",
        ),
        (
            "contact_force_tolerance = 1e-9",
            "solver.contact_force_tolerance",
            "only the active set used it",
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let text = format!("{BASE}\n[solver]\n{line}\n");
        let prefix = line.split(' ').next().unwrap();
        let err = range_error(&format!("retired_{i}"), &text, key, prefix, allowed);
        assert!(
            err.contains("retired") && err.contains("docs/results/active-set-need/latest.md"),
            "{err}"
        );
    }
    let text = format!("{BASE}\n[solver]\nsemi_smooth_max_iterations = 50\n");
    let r = run_problem("semi_smooth_cap", &text);
    assert_eq!(r.code(), Some(0), "{}", r.stderr());
    r.cleanup();
}

#[test]
fn bdf2_in_static_mode() {
    let text = edit("[time]", "[time]\nmode = \"static\"");
    let text = edit_text(&text, "[rod]", "[rod]\nclamp = \"tail\"");
    let text = format!("{text}\n[solver]\nintegrator = \"bdf2\"\n");
    range_error(
        "bdf2_static",
        &text,
        "solver.integrator",
        "integrator",
        "\"implicit\" in static mode",
    );
}
