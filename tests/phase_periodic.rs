//! A phase study of a gait with a launch period (sidewinding): its rows carry the periodic
//! columns of `history.csv` last, with the values `slither run` writes into the cell's
//! `summary.json` (empty where it writes none: the cell without a couple); the study resumes
//! without simulating and without changing the file, its shards merge into the same rows, its
//! refinement's rows carry the columns too, and a study never appends to a file of the other
//! format. The base is the tiny sidewinding of `tests/common` (16 elements, three launch
//! periods), so every run takes milliseconds.

mod common;
use common::{ordered_rows, TINY_SIDEWINDING, TINY_S_START};
use slither::observe::Regime;
use slither::studies::phase::{self, Format, HEADER};
use slither::studies::{
    optimize::PeriodicColumns, optimize::HISTORY_HEADER, optimize::PERIODIC_COLUMNS,
};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_slither");

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "slither-phase-periodic-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn run(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().unwrap()
}

fn ok(o: &Output) -> String {
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{err}");
    err
}

/// A phase file over `base` (written beside it as base.toml): W 300, G 0, 10 and 15.
fn study(dir: &Path, base: &str) -> PathBuf {
    std::fs::write(dir.join("base.toml"), base).unwrap();
    let p = dir.join("phase.toml");
    std::fs::write(
        &p,
        "[phase]\nbase = \"base.toml\"\nweight = [300.0]\ntorque = [0.0, 10.0, 15.0]\n",
    )
    .unwrap();
    p
}

/// The periodic header: HEADER, then the periodic columns.
fn periodic_header() -> String {
    format!("{HEADER},{PERIODIC_COLUMNS}")
}

/// The periodic columns of a row (the last six fields), by name.
fn periodic_fields(row: &str) -> Option<PeriodicColumns> {
    let f: Vec<&str> = row.split(',').collect();
    let names: Vec<&str> = PERIODIC_COLUMNS.split(',').collect();
    let at = f.len() - names.len();
    let field = |name: &str| f[at + names.iter().position(|n| *n == name).unwrap()];
    PeriodicColumns::parse_fields(&field).unwrap()
}

#[test]
fn periodic_rows_equal_the_cells_runs_resume_and_merge() {
    let dir = scratch("study");
    let file = study(&dir, TINY_SIDEWINDING);
    let f = file.to_str().unwrap();
    let whole = dir.join("whole");
    let err = ok(&run(&["phase", f, "--out", whole.to_str().unwrap()]));
    assert!(err.contains("3 simulated, 0 reused"), "{err}");
    // The per-cell log line gives the verdict.
    assert!(err.contains("sidewinding no:"), "{err}");
    let csv = whole.join("phase.csv");
    let text = std::fs::read_to_string(&csv).unwrap();
    // The header: today's columns, then history.csv's periodic columns, same names, same order.
    assert_eq!(text.lines().next().unwrap(), periodic_header());
    assert!(HISTORY_HEADER.contains(PERIODIC_COLUMNS));
    let info: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(whole.join("phase.json")).unwrap()).unwrap();
    assert_eq!(info["periodic"], true);
    // Rows in the order the cells finished: by G here.
    let mut lines: Vec<&str> = text.lines().skip(1).collect();
    let torque = |l: &str| l.split(',').nth(1).unwrap().parse::<f64>().unwrap();
    lines.sort_by(|a, b| torque(a).total_cmp(&torque(b)));
    assert_eq!(lines.len(), 3, "{text}");
    for (line, g) in lines.iter().zip(["0", "10", "15"]) {
        assert_eq!(torque(line), g.parse::<f64>().unwrap());
        let row = periodic_fields(line);
        // The cell run by itself, as `slither run` runs it: its summary.json.
        let cell = dir.join(format!("cell_g{g}"));
        ok(&run(&[
            "phase",
            f,
            "--cell",
            &format!("300,{g}"),
            "--out",
            cell.to_str().unwrap(),
            "--quiet",
        ]));
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(cell.join("summary.json")).unwrap())
                .unwrap();
        let p = &summary["periodic"];
        if g == "0" {
            // No couple, nothing launched: no periodic observables, empty columns.
            assert!(p.is_null(), "{p}");
            assert_eq!(row, None, "{line}");
            assert!(line.ends_with(",,,,,,"), "{line}");
            continue;
        }
        let row = row.unwrap_or_else(|| panic!("G {g}: no periodic columns in {line}"));
        let num = |k: &str| p[k].as_f64().unwrap_or_else(|| panic!("{k}: {p}"));
        // Three launch periods, one settling: two measured cycles, too few to sidewind.
        assert_eq!(row.cycles, 2, "{line}");
        assert_eq!(row.cycles, p["cycles"].as_array().unwrap().len(), "{line}");
        assert_eq!(
            row.displacement_over_length_min,
            num("displacement_over_length_min")
        );
        assert_eq!(row.broadside_deg_min, num("broadside_deg_min"));
        assert_eq!(row.turn_deg_max_abs, num("turn_deg_max_abs"));
        assert_eq!(
            row.stationary_contact_share_min,
            num("stationary_contact_share_min")
        );
        assert_eq!(row.sidewinding, p["sidewinding"].as_bool().unwrap());
        assert!(!row.sidewinding, "{line}");
        assert!(row.displacement_over_length_min > 0.0, "{line}");
    }
    // The two cells with a couple differ (the columns are each cell's own).
    assert_ne!(periodic_fields(lines[1]), periodic_fields(lines[2]));

    // Resume: nothing simulated, the file unchanged byte for byte.
    let err = ok(&run(&["phase", f, "--out", whole.to_str().unwrap()]));
    assert!(err.contains("0 simulated, 3 reused"), "{err}");
    assert_eq!(std::fs::read_to_string(&csv).unwrap(), text);

    // Two shards merged: the same rows (wall times aside), the same header.
    let mut dirs = Vec::new();
    for i in 1..=2 {
        let d = dir.join(format!("shard{i}"));
        ok(&run(&[
            "phase",
            f,
            "--out",
            d.to_str().unwrap(),
            "--shard",
            &format!("{i}/2"),
        ]));
        let shard = std::fs::read_to_string(d.join("phase.csv")).unwrap();
        assert_eq!(shard.lines().next().unwrap(), periodic_header());
        dirs.push(d);
    }
    let merged = dir.join("merged");
    ok(&run(&[
        "merge",
        dirs[0].to_str().unwrap(),
        dirs[1].to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]));
    let m = std::fs::read_to_string(merged.join("phase.csv")).unwrap();
    assert_eq!(m.lines().next().unwrap(), periodic_header());
    let sorted = |csv: &Path| {
        let mut r = ordered_rows(csv);
        r.sort();
        r
    };
    assert_eq!(sorted(&merged.join("phase.csv")), sorted(&csv));

    // A shard whose phase.csv lacks the columns (an older writer) is refused, naming the file
    // and both headers.
    let old = dirs[1].join("phase.csv");
    let plain: Vec<String> = std::fs::read_to_string(&old)
        .unwrap()
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            f[..f.len() - 6].join(",")
        })
        .collect();
    std::fs::write(&old, plain.join("\n") + "\n").unwrap();
    let o = run(&[
        "merge",
        dirs[0].to_str().unwrap(),
        dirs[1].to_str().unwrap(),
        "--out",
        dir.join("merged_old").to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains(old.to_str().unwrap()), "{err}");
    assert!(err.contains("launch period"), "{err}");
    assert!(err.contains(&format!("`{HEADER}`")), "{err}");
    assert!(err.contains(&format!("`{}`", periodic_header())), "{err}");
}

#[test]
fn a_study_never_appends_to_rows_of_the_other_format() {
    // A sidewinding study into an S-start study's directory, and the reverse: exit 2 naming
    // the file and both headers; the file is left as it was.
    for (first, second, found, expected) in [
        (
            TINY_S_START,
            TINY_SIDEWINDING,
            HEADER.to_string(),
            periodic_header(),
        ),
        (
            TINY_SIDEWINDING,
            TINY_S_START,
            periodic_header(),
            HEADER.to_string(),
        ),
    ] {
        let dir = scratch(if expected == HEADER {
            "to-plain"
        } else {
            "to-periodic"
        });
        let file = study(&dir, first);
        let out = dir.join("out");
        ok(&run(&[
            "phase",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]));
        let csv = out.join("phase.csv");
        let before = std::fs::read_to_string(&csv).unwrap();
        assert_eq!(before.lines().next().unwrap(), found);
        let file = study(&dir, second);
        let o = run(&[
            "phase",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains(csv.to_str().unwrap()), "{err}");
        assert!(err.contains("cannot append"), "{err}");
        assert!(err.contains(&format!("its header is `{found}`")), "{err}");
        assert!(
            err.contains(&format!("this study's is `{expected}`")),
            "{err}"
        );
        assert_eq!(std::fs::read_to_string(&csv).unwrap(), before);
    }
}

#[test]
fn refinement_rows_of_a_periodic_study_carry_the_columns_and_resume() {
    let dir = scratch("refine");
    let file = study(&dir, TINY_SIDEWINDING);
    let ph = phase::load(&file).unwrap();
    assert_eq!(
        ph.format(),
        Format {
            verified: false,
            periodic: true
        }
    );
    // Two neighbours in G labelled apart (labels given, not simulated): one pair, bisected
    // twice along G, each midpoint a real simulation of the base.
    let (weight, torque) = ([300.0], [10.0, 15.0]);
    let labels = [Some(Regime::S), Some(Regime::F)];
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let refine = || {
        phase::refine::refine(
            &ph.base,
            ph.row_hash(),
            2,
            None,
            ph.protocol,
            &out,
            &weight,
            &torque,
            &labels,
            &|_, _| {},
        )
        .unwrap()
    };
    let r = refine();
    assert_eq!(r.pairs, 1);
    assert!(r.simulated >= 1, "{r:?}");
    let csv = out.join("refine.csv");
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(text.lines().next().unwrap(), periodic_header());
    let read = phase::read_rows(&csv).unwrap();
    assert_eq!(read.format, ph.format());
    assert_eq!(read.rows.len(), r.simulated);
    for (c, _) in &read.rows {
        // Each midpoint's columns are those of the cell run by itself.
        let p = phase::simulate(&ph.base, c.weight, c.torque);
        assert_eq!(c.periodic, p.periodic);
        assert_eq!(c.periodic.map(|p| p.cycles), Some(2), "{c:?}");
    }
    // Resumed: every midpoint from its row, the file unchanged.
    let again = refine();
    assert_eq!((again.simulated, again.reused), (0, r.simulated));
    assert_eq!(std::fs::read_to_string(&csv).unwrap(), text);
}
