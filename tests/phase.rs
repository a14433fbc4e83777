//! The regime phase diagram (`slither phase`): a small grid runs, writes one `phase.csv` row
//! per cell and both figures, resumes without simulating again, and bad phase files exit 2
//! naming the file, line, key and allowed range. The base problem is a tiny S-start (20
//! elements, a tenth of a second), so the whole file runs in seconds.

mod common;
use common::ordered_rows;
use common::TINY_S_START as BASE;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_slither");

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("slither-phase-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn phase(dir: &Path, body: &str) -> PathBuf {
    std::fs::write(dir.join("base.toml"), BASE).unwrap();
    let p = dir.join("phase.toml");
    std::fs::write(&p, format!("# a phase file\n\n[phase]\n{body}")).unwrap();
    p
}

fn run(file: &Path, out: &Path) -> Output {
    Command::new(BIN)
        .args([
            "phase",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap()
}

#[test]
fn grid_runs_writes_every_cell_and_resumes() {
    let dir = scratch("grid");
    let file = phase(
        &dir,
        "base = \"base.toml\"\nweight = [300.0, 3000.0]\ntorque = [0.0, 15.0]\n",
    );
    let out = dir.join("out");
    let o = run(&file, &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("4 simulated, 0 reused"), "{err}");
    let csv = std::fs::read_to_string(out.join("phase.csv")).unwrap();
    // A gait without a launch period: the header is HEADER alone (no periodic columns), and
    // phase.json says nothing of them.
    assert_eq!(csv.lines().next().unwrap(), slither::studies::phase::HEADER);
    assert!(!csv.contains("periodic_cycles"));
    let info = std::fs::read_to_string(out.join("phase.json")).unwrap();
    assert!(!info.contains("periodic"), "{info}");
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    for col in [
        "regime",
        "regime_detail",
        "writhe_max",
        "writhe_snapshot",
        "two_arc_lift_over_a",
        "lambda_pulse_speed_over_v_m",
    ] {
        assert!(header.contains(&col), "{col} not in {header:?}");
    }
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert_eq!(rows.len(), 4, "{csv}");
    for r in &rows {
        let f: Vec<&str> = r.split(',').collect();
        assert_eq!(f[3], "ok", "{r}");
        assert!(["S", "M", "F", "N", "U"].contains(&f[4]), "{r}");
        // The M sub-reason column is "-" unless the cell is M.
        assert_eq!(f[11] == "-", f[4] != "M", "{r}");
    }
    // No torque, no motion: the G = 0 cells are regime N with v_s/v_m below 1e-6.
    for r in rows
        .iter()
        .filter(|r| r.split(',').nth(1).unwrap().parse::<f64>().unwrap() == 0.0)
    {
        let f: Vec<&str> = r.split(',').collect();
        assert_eq!(f[4], "N", "{r}");
        assert!(f[5].parse::<f64>().unwrap().abs() < 1e-6, "{r}");
    }
    for png in ["phase.png", "speed.png"] {
        assert!(
            std::fs::metadata(out.join(png)).unwrap().len() > 10_000,
            "{png}"
        );
    }
    // Resume: nothing to simulate, the same rows.
    let o = run(&file, &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("0 simulated, 4 reused"), "{err}");
    assert_eq!(std::fs::read_to_string(out.join("phase.csv")).unwrap(), csv);
    // A larger grid simulates only the new cells.
    let file = phase(
        &dir,
        "base = \"base.toml\"\nweight = [300.0, 3000.0]\ntorque = [0.0, 15.0, 20.0]\n",
    );
    let o = run(&file, &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("2 simulated, 4 reused"), "{err}");
}

fn rejects(name: &str, body: &str, needles: &[&str]) {
    let dir = scratch(name);
    let file = phase(&dir, body);
    let out = dir.join("out");
    let o = run(&file, &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{name}: {err}");
    assert!(err.contains("phase.toml"), "{name}: {err}");
    for n in needles {
        assert!(err.contains(n), "{name}: {n:?} not in {err}");
    }
    assert!(!out.join("phase.csv").exists(), "{name}");
}

#[test]
fn bad_phase_files_exit_2_naming_the_key() {
    rejects(
        "negative-weight",
        "base = \"base.toml\"\nweight = [-1.0, 3.0]\ntorque = [1.0]\n",
        &[":5:", "phase.weight", "W in [1e-6, 1e9]"],
    );
    rejects(
        "decreasing-torque",
        "base = \"base.toml\"\nweight = [1.0]\ntorque = [10.0, 5.0]\n",
        &[":6:", "phase.torque", "strictly increasing"],
    );
    rejects(
        "empty",
        "base = \"base.toml\"\nweight = []\ntorque = [1.0]\n",
        &["phase.weight", "non-empty"],
    );
    rejects(
        "missing-base",
        "base = \"nope.toml\"\nweight = [1.0]\ntorque = [1.0]\n",
        &[":4:", "phase.base", "nope.toml"],
    );
    rejects(
        "unknown-key",
        "base = \"base.toml\"\nweight = [1.0]\ntorque = [1.0]\nwidth = 3\n",
        &["width"],
    );
}

fn run_args(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().unwrap()
}

/// Rows of a `phase.csv` keyed by `(W, G)`, without the wall-time column.
fn rows(csv: &Path) -> std::collections::BTreeMap<(String, String), String> {
    let text = std::fs::read_to_string(csv).unwrap();
    text.lines()
        .skip(1)
        .map(|l| {
            let mut f: Vec<&str> = l.split(',').collect();
            f[16] = "";
            ((f[0].to_string(), f[1].to_string()), f.join(","))
        })
        .collect()
}

#[test]
fn shards_merged_equal_the_unsharded_run_cell_for_cell() {
    let dir = scratch("shards");
    // A log-spaced weight range: 100, 1000, 10000.
    let file = phase(
        &dir,
        "base = \"base.toml\"\nweight = { from = 100.0, to = 1e4, count = 3 }\ntorque = [10.0, 20.0]\n",
    );
    let f = file.to_str().unwrap();
    let whole = dir.join("whole");
    let o = run(&file, &whole);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let info: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(whole.join("phase.json")).unwrap()).unwrap();
    let w: Vec<f64> = info["weight"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert_eq!(w.len(), 3);
    assert!((w[0] - 100.0).abs() < 1e-9 && (w[1] - 1000.0).abs() < 1e-9 && w[2] == 1e4);
    let reference = rows(&whole.join("phase.csv"));
    assert_eq!(reference.len(), 6);
    for n in [2, 3] {
        let mut dirs = Vec::new();
        let mut cells = 0;
        for i in 1..=n {
            let d = dir.join(format!("shard{i}of{n}"));
            let shard = format!("{i}/{n}");
            let o = run_args(&["phase", f, "--out", d.to_str().unwrap(), "--shard", &shard]);
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            assert!(!d.join("phase.png").exists(), "a shard draws no figures");
            cells += rows(&d.join("phase.csv")).len();
            dirs.push(d);
        }
        assert_eq!(cells, 6, "every cell in exactly one of {n} shards");
        let merged = dir.join(format!("merged{n}"));
        let mut args = vec!["merge"];
        args.extend(dirs.iter().map(|d| d.to_str().unwrap()));
        args.extend(["--out", merged.to_str().unwrap()]);
        let o = run_args(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert_eq!(rows(&merged.join("phase.csv")), reference, "{n} shards");
        for fig in [
            "phase.png",
            "speed.png",
            "writhe_vs_ratio.png",
            "speed_vs_writhe.png",
            "speed_vs_ratio.png",
        ] {
            assert!(merged.join(fig).exists(), "{fig}");
            // Every figure also as SVG: XML text with one <svg> root.
            let svg = merged.join(fig).with_extension("svg");
            let text = std::fs::read_to_string(&svg).unwrap_or_else(|e| panic!("{svg:?}: {e}"));
            assert!(text.trim_start().starts_with("<svg"), "{svg:?}");
            assert!(text.trim_end().ends_with("</svg>"), "{svg:?}");
            assert_eq!(text.matches("<svg").count(), 1, "{svg:?}");
            assert!(text.contains("<text"), "{svg:?} has no labels");
        }
        // The regime map: log axes (labelled as such) and a legend of the regimes.
        let map = std::fs::read_to_string(merged.join("phase.svg")).unwrap();
        assert!(map.contains("(log)"), "no log axis label");
        assert!(map.contains("regime (cells)"), "no legend");
        let bounds: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(merged.join("boundaries.json")).unwrap())
                .unwrap();
        // Every fitted boundary is named in the map's legend.
        for b in bounds.as_array().unwrap() {
            if b["slope"].is_f64() {
                let pair = b["pair"].as_str().unwrap();
                assert!(map.contains(&format!("{pair}: s = ")), "{pair} not drawn");
            }
        }
        // A missing shard is reported, not papered over.
        let out = dir.join(format!("partial{n}"));
        let o = run_args(&[
            "merge",
            dirs[0].to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains("miss"), "{err}");
    }
}

#[test]
fn merge_refuses_shards_of_another_grid_and_bad_ranges_are_named() {
    let dir = scratch("mismatch");
    let a = phase(
        &dir,
        "base = \"base.toml\"\nweight = [300.0, 3000.0]\ntorque = [15.0]\n",
    );
    let da = dir.join("a");
    let o = run_args(&[
        "phase",
        a.to_str().unwrap(),
        "--out",
        da.to_str().unwrap(),
        "--shard",
        "1/2",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let b = dir.join("other.toml");
    std::fs::write(
        &b,
        "[phase]\nbase = \"base.toml\"\nweight = [300.0, 3000.0]\ntorque = [20.0]\n",
    )
    .unwrap();
    let db = dir.join("b");
    let o = run_args(&[
        "phase",
        b.to_str().unwrap(),
        "--out",
        db.to_str().unwrap(),
        "--shard",
        "2/2",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = dir.join("m");
    let o = run_args(&[
        "merge",
        da.to_str().unwrap(),
        db.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("cannot merge") && err.contains("grid"),
        "{err}"
    );
    assert!(!out.join("phase.csv").exists());
    // Bad ranges and shards.
    for (body, needle) in [
        ("weight = { from = 0.0, to = 10.0, count = 3 }", "from > 0"),
        ("weight = { from = 10.0, to = 1.0, count = 3 }", "from < to"),
        ("weight = { from = 1.0, to = 10.0, count = 0 }", "count"),
        (
            "weight = { from = 1.0, to = 10.0, count = 3, spacing = \"cubic\" }",
            "spacing",
        ),
    ] {
        let p = phase(
            &dir,
            &format!("base = \"base.toml\"\n{body}\ntorque = [10.0]\n"),
        );
        let o = run(&p, &dir.join("bad"));
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{body}: {err}");
        assert!(
            err.contains("phase.weight") && err.contains(needle),
            "{body}: {err}"
        );
    }
    let o = run_args(&[
        "phase",
        a.to_str().unwrap(),
        "--out",
        dir.join("s").to_str().unwrap(),
        "--shard",
        "3/2",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("I/N"));
}

fn json(file: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(file).unwrap()).unwrap()
}

/// The number before `word` in `text` ("12 simulated" -> 12).
fn count_before(text: &str, word: &str) -> usize {
    let at = text
        .find(&format!(" {word}"))
        .unwrap_or_else(|| panic!("no {word:?} in {text}"));
    text[..at]
        .rsplit([' ', '('])
        .next()
        .unwrap()
        .parse()
        .unwrap_or_else(|_| panic!("no count before {word:?} in {text}"))
}

#[test]
fn refine_bisects_the_boundaries_resumes_and_merges() {
    let dir = scratch("refine");
    let grid = "base = \"base.toml\"\nweight = [100.0, 1000.0]\ntorque = [12.0, 22.0]\nrefine = true\nrefine_steps = 2\n";
    let file = phase(&dir, grid);
    let out = dir.join("whole");
    let o = run(&file, &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    let summary = err
        .lines()
        .find(|l| l.starts_with("refinement (2 bisection steps)"))
        .unwrap_or_else(|| panic!("no refinement line in {err}"));
    let simulated = count_before(summary, "simulated");
    assert_eq!(count_before(summary, "reused"), 0, "{summary}");
    // refine.csv: phase.csv's columns, one row per refinement simulation, sorted by G then W.
    let csv = out.join("refine.csv");
    let text = std::fs::read_to_string(&csv).unwrap();
    let first = ordered_rows(&csv);
    assert_eq!(
        text.lines().next(),
        std::fs::read_to_string(out.join("phase.csv"))
            .unwrap()
            .lines()
            .next()
    );
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').take(2).map(|x| x.parse().unwrap()).collect())
        .collect();
    assert!(simulated >= 2, "{summary}");
    assert_eq!(rows.len(), simulated, "{text}");
    assert!(
        rows.windows(2)
            .all(|r| (r[0][1], r[0][0]) < (r[1][1], r[1][0])),
        "{text}"
    );
    // Each row lies strictly inside the grid, on a ray of constant G or W through it.
    for r in &rows {
        let on_row = [12.0, 22.0].contains(&r[1]) && r[0] > 100.0 && r[0] < 1000.0;
        let on_column = [100.0, 1000.0].contains(&r[0]) && r[1] > 12.0 && r[1] < 22.0;
        assert!(on_row || on_column, "{r:?}");
    }
    // boundaries.json: bisection lines through points bracketed 2^2 times tighter than the grid.
    let bounds = json(&out.join("boundaries.json"));
    let lines = bounds.as_array().unwrap();
    assert!(!lines.is_empty(), "the tiny grid has no boundary: {bounds}");
    let mut points = 0;
    for b in lines {
        assert_eq!(b["method"], "bisection", "{b}");
        for p in b["points"].as_array().unwrap() {
            points += 1;
            assert_eq!(p["method"], "bisection", "{p}");
            assert_eq!(p["steps"], 2, "{p}");
            assert!(p["failed"].is_null(), "{p}");
            let spacing = if p["along"] == "W" {
                1.0
            } else {
                (22f64 / 12.0).log10()
            };
            let h = p["half_width"].as_f64().unwrap();
            assert!((h - spacing / 8.0).abs() < 1e-12, "{p}");
        }
        assert_eq!(
            b["cells"].as_array().unwrap().len(),
            b["points"].as_array().unwrap().len()
        );
    }
    assert_eq!(
        points,
        count_before(summary, "boundary points"),
        "{summary}"
    );
    let map = std::fs::read_to_string(out.join("phase.svg")).unwrap();
    assert!(map.contains("bisected"), "the legend does not say bisected");

    // A rerun simulates nothing: every midpoint comes from refine.csv, unchanged.
    let o = run(&file, &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    let again = err
        .lines()
        .find(|l| l.starts_with("refinement"))
        .unwrap_or_else(|| panic!("{err}"));
    assert_eq!(count_before(again, "simulated"), 0, "{again}");
    assert_eq!(count_before(again, "reused"), simulated, "{again}");
    assert_eq!(std::fs::read_to_string(&csv).unwrap(), text);
    assert_eq!(json(&out.join("boundaries.json")), bounds);
    // A lost row is simulated again, and only that one.
    let mut lines_of: Vec<&str> = text.lines().collect();
    lines_of.remove(1);
    std::fs::write(&csv, lines_of.join("\n") + "\n").unwrap();
    let o = run(&file, &out);
    let err = String::from_utf8_lossy(&o.stderr);
    let third = err.lines().find(|l| l.starts_with("refinement")).unwrap();
    assert_eq!(count_before(third, "simulated"), 1, "{third}");
    assert_eq!(ordered_rows(&csv), first);

    // Shards never refine; merge does, with the same result as the unsharded run.
    let f = file.to_str().unwrap();
    let mut dirs = Vec::new();
    for i in 1..=2 {
        let d = dir.join(format!("shard{i}"));
        let o = run_args(&[
            "phase",
            f,
            "--out",
            d.to_str().unwrap(),
            "--shard",
            &format!("{i}/2"),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(!d.join("refine.csv").exists(), "a shard refined");
        assert_eq!(json(&d.join("phase.json"))["refine_steps"], 2);
        dirs.push(d.to_str().unwrap().to_string());
    }
    let merged = dir.join("merged");
    let merge = |dirs: &[String], out: &Path| {
        let mut args = vec!["merge".to_string()];
        args.extend(dirs.iter().cloned());
        args.extend(["--out".to_string(), out.to_str().unwrap().to_string()]);
        Command::new(BIN).args(&args).output().unwrap()
    };
    let o = merge(&dirs, &merged);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    let m = err
        .lines()
        .find(|l| l.starts_with("refinement"))
        .unwrap_or_else(|| panic!("{err}"));
    assert_eq!(count_before(m, "simulated"), simulated, "{m}");
    assert_eq!(ordered_rows(&merged.join("refine.csv")), first);
    assert_eq!(json(&merged.join("boundaries.json")), bounds);
    // Merge refuses to refine with a base problem that changed since the shards ran (a value;
    // a comment is no change, tests/study_settings.rs) ...
    let base = dir.join("base.toml");
    std::fs::write(&base, BASE.replace("duration = 0.1", "duration = 0.12")).unwrap();
    let o = merge(&dirs, &dir.join("merged-edited"));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("base.toml") && err.contains("changed"),
        "{err}"
    );
    std::fs::write(&base, BASE).unwrap();
    // ... and shards of one grid run with and without refinement.
    let plain = dir.join("plain.toml");
    std::fs::write(
        &plain,
        format!("[phase]\n{}", grid.replace("refine = true\n", "")),
    )
    .unwrap();
    let d = dir.join("shard2-plain");
    let o = run_args(&[
        "phase",
        plain.to_str().unwrap(),
        "--out",
        d.to_str().unwrap(),
        "--shard",
        "2/2",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    dirs[1] = d.to_str().unwrap().to_string();
    let o = merge(&dirs, &dir.join("merged-mixed"));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("cannot merge") && err.contains("refine"),
        "{err}"
    );
}

#[test]
fn bad_refine_steps_exit_2_naming_the_key_and_range() {
    for (name, steps) in [
        ("zero", "0"),
        ("nine", "9"),
        ("fraction", "2.5"),
        ("text", "\"3\""),
    ] {
        rejects(
            &format!("refine-steps-{name}"),
            &format!("base = \"base.toml\"\nweight = [1.0]\ntorque = [1.0]\nrefine = true\nrefine_steps = {steps}\n"),
            &[":8:", "phase.refine_steps", "[1, 8]"],
        );
    }
}
