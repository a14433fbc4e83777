//! Per-cell verification of a phase study (`[phase] verify = { finer, perturbations }`):
//! a cell's agreement and spread are those of its runs recomputed one by one; on a synthetic
//! study with known labels the uncertain cells are left out of the boundary fits and counted in
//! `boundaries.json`, and hatched on the map; shards with verification merge into the
//! unsharded run, cell for cell.

mod common;
use common::TINY_S_START as BASE;
use slither::observe::Regime;
use slither::studies::ensemble;
use slither::studies::optimize::Status;
use slither::studies::phase::{self, Cell, Verification, Verify};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_slither");

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("slither-verify-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn run_args(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().unwrap()
}

#[test]
fn a_cells_agreement_and_spread_are_those_of_its_runs() {
    let base = slither::problem::parse(BASE, Path::new("base.toml")).unwrap();
    let v = Verify {
        finer: true,
        perturbations: 3,
        seed: 9,
        step: ensemble::STEP,
    };
    for (w, g) in [(300.0, 15.0), (30.0, 40.0)] {
        let c = phase::simulate_verified(&base, w, g, Some(&v), phase::Protocol::default());
        let ver = c.verify.clone().expect("verified");
        // Every run again, one by one, through other entry points.
        let study = phase::simulate(&base, w, g);
        let finer = phase::simulate(&phase::finer_problem(&base), w, g);
        let seed = phase::cell_seed(9, w, g);
        let spec = ensemble::Spec {
            runs: 3,
            seed,
            perturbation: v.perturbation(),
        };
        let cell = phase::cell_problem(&base, w, g);
        let members: Vec<ensemble::Member> = (0..3)
            .map(|k| ensemble::run_member(&cell, &spec, k))
            .collect();
        // The reported cell is the finer run's.
        assert_eq!(
            phase::comparable_row(
                &Cell {
                    verify: None,
                    ..c.clone()
                },
                1
            ),
            phase::comparable_row(&finer, 1)
        );
        assert_eq!(ver.regime_base, study.regime);
        assert_eq!(ver.regime_finer, finer.regime);
        assert_eq!((ver.runs, ver.seed), (5, seed));
        let mut labels = vec![study.regime, finer.regime];
        labels.extend(members.iter().map(|m| m.regime.parse::<Regime>().ok()));
        let agree = labels
            .iter()
            .filter(|l| l.is_some() && **l == c.regime)
            .count();
        assert_eq!(
            ver.label_agreement,
            agree as f64 / 5.0,
            "W {w} G {g}: {labels:?}"
        );
        let mut speeds = vec![study.v_s_over_v_m, finer.v_s_over_v_m];
        speeds.extend(
            members
                .iter()
                .map(|m| m.observables["v_s_over_v_m"].unwrap_or(f64::NAN)),
        );
        let lo = speeds
            .iter()
            .copied()
            .filter(|x| x.is_finite())
            .fold(f64::INFINITY, f64::min);
        let hi = speeds
            .iter()
            .copied()
            .filter(|x| x.is_finite())
            .fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(
            (ver.v_s_over_v_m_min, ver.v_s_over_v_m_max),
            (lo, hi),
            "{speeds:?}"
        );
        assert!(lo < hi, "the runs differ: {speeds:?}");
    }
}

/// The label of the synthetic study: F above `W/G = 5`, S below.
fn known(w: f64, g: f64) -> Regime {
    if w / g > 5.0 {
        Regime::F
    } else {
        Regime::S
    }
}

fn synthetic_cell(w: f64, g: f64, agreement: f64) -> Cell {
    Cell {
        weight: w,
        torque: g,
        status: Status::Ok,
        regime: Some(known(w, g)),
        regime_detail: "-".into(),
        v_s_over_v_m: if known(w, g) == Regime::S { 0.3 } else { -0.01 },
        displacement_angle_deg: 5.0,
        max_elevation_over_a: 1.0,
        lifted_arcs_max: 2,
        writhe_max: 0.1,
        lambda_pulse_r2: 0.9,
        max_elevation_over_length: 0.02,
        two_arc_lift_over_a: 0.5,
        lambda_pulse_speed_over_v_m: 1.0,
        writhe_snapshot: 0.05,
        wall_time_s: 0.0,
        reason: String::new(),
        verify: Some(Verification {
            label_agreement: agreement,
            v_s_over_v_m_min: 0.25,
            v_s_over_v_m_max: 0.35,
            regime_base: Some(known(w, g)),
            regime_finer: Some(known(w, g)),
            runs: 4,
            seed: 1,
        }),
        periodic: None,
    }
}

#[test]
fn uncertain_cells_of_a_synthetic_study_are_left_out_of_the_fits_and_counted() {
    let dir = scratch("synthetic");
    let weight = [10.0, 100.0, 1000.0, 10000.0];
    let torque = [1.0, 10.0, 100.0, 1000.0];
    // Two cells on the boundary are uncertain: (100, 10) is F with agreement 0.5 and
    // (1000, 1000) is S with agreement 0.75.
    let uncertain = [(100.0, 10.0, 0.5), (1000.0, 1000.0, 0.75)];
    let cells: Vec<Cell> = weight
        .iter()
        .flat_map(|&w| torque.iter().map(move |&g| (w, g)))
        .map(|(w, g)| {
            let a = uncertain
                .iter()
                .find(|u| u.0 == w && u.1 == g)
                .map_or(1.0, |u| u.2);
            synthetic_cell(w, g, a)
        })
        .collect();
    // The neighbour pairs of different labels, counted here from the known labels: those
    // touching an uncertain cell must be excluded.
    let is_uncertain = |w: f64, g: f64| uncertain.iter().any(|u| u.0 == w && u.1 == g);
    let (mut pairs, mut excluded) = (0, 0);
    for i in 0..4 {
        for j in 0..4 {
            for (a, b) in [((i, j), (i + 1, j)), ((i, j), (i, j + 1))] {
                if b.0 > 3 || b.1 > 3 {
                    continue;
                }
                let (wa, ga, wb, gb) = (weight[a.0], torque[a.1], weight[b.0], torque[b.1]);
                if known(wa, ga) != known(wb, gb) {
                    pairs += 1;
                    if is_uncertain(wa, ga) || is_uncertain(wb, gb) {
                        excluded += 1;
                    }
                }
            }
        }
    }
    assert!(excluded >= 2 && excluded < pairs, "{excluded} of {pairs}");
    // The library: exclusions and confident labels.
    let ex = phase::Exclusions::of(&weight, &torque, &cells);
    assert_eq!((ex.excluded_cells, ex.excluded_pairs), (2, excluded));
    assert_eq!(
        ex.uncertain,
        vec![[100.0, 10.0, 0.5], [1000.0, 1000.0, 0.75]]
    );
    let labels = phase::confident_labels(&cells);
    assert_eq!(labels.iter().filter(|l| l.is_none()).count(), 2);
    // End to end through `slither merge` of a directory holding the synthetic rows: the fits,
    // boundaries.json and the map.
    let base_hash = 0x1234_u64;
    let v = Verify {
        finer: true,
        perturbations: 2,
        seed: 1,
        step: ensemble::STEP,
    };
    let hash = v.row_hash(base_hash);
    let shard = dir.join("shard");
    std::fs::create_dir_all(&shard).unwrap();
    let mut csv = phase::verify_header() + "\n";
    for c in &cells {
        // The row format is the library's own (`Cell::row` is crate-internal): rebuild it from
        // the comparable row, whose wall-time field is empty.
        csv += &phase::comparable_row(c, hash).replacen(",,", ",0.000,", 1);
        csv += "\n";
    }
    std::fs::write(shard.join("phase.csv"), csv).unwrap();
    let info = phase::RunInfo {
        phase_file: "synthetic.toml".into(),
        base_file: "synthetic_base.toml".into(),
        base_hash: format!("{base_hash:016x}"),
        weight: weight.to_vec(),
        torque: torque.to_vec(),
        shard: None,
        refine_steps: None,
        accuracy: None,
        verify: Some(v),
        protocol: phase::Protocol::default(),
        growth: None,
        periodic: false,
        settings: Vec::new(),
    };
    std::fs::write(
        shard.join("phase.json"),
        serde_json::to_string(&info).unwrap(),
    )
    .unwrap();
    let merged = dir.join("merged");
    let o = run_args(&[
        "merge",
        shard.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let b: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(merged.join("boundaries.json")).unwrap())
            .unwrap();
    assert_eq!(b["excluded_cells"], 2);
    assert_eq!(b["excluded_pairs"], excluded as u64);
    let lines = b["boundaries"].as_array().unwrap();
    assert_eq!(lines.len(), 1);
    assert_eq!(lines[0]["pair"], "F/S");
    let used = lines[0]["cells"].as_array().unwrap();
    assert_eq!(used.len(), pairs - excluded);
    for pair in used {
        for cell in pair.as_array().unwrap() {
            let (w, g) = (cell[0].as_f64().unwrap(), cell[1].as_f64().unwrap());
            assert!(!is_uncertain(w, g), "uncertain cell ({w}, {g}) in the fit");
        }
    }
    let map = std::fs::read_to_string(merged.join("phase.svg")).unwrap();
    assert!(
        map.contains("uncertain (2)"),
        "no legend entry for the uncertain cells"
    );
    // The merged phase.csv keeps the verification columns.
    let text = std::fs::read_to_string(merged.join("phase.csv")).unwrap();
    assert!(text.starts_with(&phase::verify_header()));
    assert_eq!(text.lines().count(), 17);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Rows of a `phase.csv` keyed by `(W, G)`, without the wall-time column.
fn rows(csv: &Path) -> std::collections::BTreeMap<(String, String), String> {
    let text = std::fs::read_to_string(csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), phase::verify_header());
    lines
        .map(|l| {
            let mut f: Vec<&str> = l.split(',').collect();
            f[16] = "";
            ((f[0].to_string(), f[1].to_string()), f.join(","))
        })
        .collect()
}

#[test]
fn shards_with_verification_merge_into_the_unsharded_run() {
    let dir = scratch("shards");
    std::fs::write(dir.join("base.toml"), BASE).unwrap();
    let file = dir.join("phase.toml");
    std::fs::write(
        &file,
        "[phase]\nbase = \"base.toml\"\nweight = [30.0, 300.0, 3000.0]\ntorque = [15.0, 40.0]\nverify = { finer = true, perturbations = 2 }\n",
    )
    .unwrap();
    let f = file.to_str().unwrap();
    let whole = dir.join("whole");
    let o = run_args(&["phase", f, "--out", whole.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let reference = rows(&whole.join("phase.csv"));
    assert_eq!(reference.len(), 6);
    for row in reference.values() {
        let f: Vec<&str> = row.split(',').collect();
        assert_eq!(f[24], "4", "runs per cell: {row}");
        let agreement: f64 = f[19].parse().unwrap();
        assert!(
            (0.0..=1.0).contains(&agreement) && (agreement * 4.0).fract() == 0.0,
            "{row}"
        );
    }
    let b: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(whole.join("boundaries.json")).unwrap())
            .unwrap();
    assert!(
        b["excluded_cells"].is_u64() && b["boundaries"].is_array(),
        "{b}"
    );
    // Resume: nothing is simulated again.
    let o = run_args(&["phase", f, "--out", whole.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && !err.contains("cell 1/"), "{err}");
    assert_eq!(rows(&whole.join("phase.csv")), reference);
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
        dirs.push(d);
    }
    let merged = dir.join("merged");
    let o = run_args(&[
        "merge",
        dirs[0].to_str().unwrap(),
        dirs[1].to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(rows(&merged.join("phase.csv")), reference);
    assert_eq!(
        std::fs::read_to_string(merged.join("boundaries.json")).unwrap(),
        std::fs::read_to_string(whole.join("boundaries.json")).unwrap()
    );
    // A plain study cannot append to a verified phase.csv: exit 2, naming the file.
    let plain = dir.join("plain.toml");
    std::fs::write(
        &plain,
        "[phase]\nbase = \"base.toml\"\nweight = [30.0, 300.0, 3000.0]\ntorque = [15.0, 40.0]\n",
    )
    .unwrap();
    let o = run_args(&[
        "phase",
        plain.to_str().unwrap(),
        "--out",
        whole.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("phase.csv") && err.contains("verification"),
        "{err}"
    );
    // A bad verify table exits 2 naming the key.
    let bad = dir.join("bad.toml");
    std::fs::write(
        &bad,
        "[phase]\nbase = \"base.toml\"\nweight = [30.0]\ntorque = [15.0]\nverify = { finer = true, perturbations = 1000 }\n",
    )
    .unwrap();
    let o = run_args(&[
        "phase",
        bad.to_str().unwrap(),
        "--out",
        dir.join("bad").to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("phase.verify") && err.contains("perturbations"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn weight_via_and_similar_are_recorded_keyed_apart_and_checked() {
    let dir = scratch("protocol");
    std::fs::write(dir.join("base.toml"), BASE).unwrap();
    let file = |name: &str, extra: &str| {
        let p = dir.join(name);
        std::fs::write(
            &p,
            format!("[phase]\nbase = \"base.toml\"\nweight = [300.0]\ntorque = [15.0]\n{extra}"),
        )
        .unwrap();
        p
    };
    let out = dir.join("out");
    let plain = file("plain.toml", "");
    let o = run_args(&[
        "phase",
        plain.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let info = |d: &Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(d.join("phase.json")).unwrap()).unwrap()
    };
    assert!(info(&out).get("protocol").is_none());
    // Another protocol into the same directory: its rows are keyed apart, so the cell runs
    // again (a second row) instead of being reused.
    let gravity = file("gravity.toml", "weight_via = \"gravity\"\nsimilar = true\n");
    let o = run_args(&[
        "phase",
        gravity.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && err.contains("cell 1/1"), "{err}");
    assert_eq!(info(&out)["protocol"]["weight_via"], "gravity");
    assert_eq!(info(&out)["protocol"]["similar"], true);
    let rows = std::fs::read_to_string(out.join("phase.csv")).unwrap();
    assert_eq!(rows.lines().count(), 3, "{rows}");
    let bad = file("bad.toml", "weight_via = \"mass\"\n");
    let o = run_args(&[
        "phase",
        bad.to_str().unwrap(),
        "--out",
        dir.join("bad").to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("phase.weight_via") && err.contains("density"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Verification of a gait with a launch period compares the sidewinding verdict as well as
/// the regime label: a run that crawls with the same label but does not sidewind disagrees.
#[test]
fn verification_of_a_sidewinding_compares_its_sidewinding_verdict() {
    let p = slither::problem::parse(common::TINY_SIDEWINDING, Path::new("<inline>")).unwrap();
    let c = phase::simulate(&p, 300.0, 14.4);
    assert_eq!(c.status, Status::Ok, "{}", c.reason);
    let periodic = c
        .periodic
        .expect("a sidewinding cell has its periodic values");
    assert!(phase::cell::agrees(&c, &c));
    let mut other = c.clone();
    other.periodic = Some(slither::studies::optimize::PeriodicColumns {
        sidewinding: !periodic.sidewinding,
        ..periodic
    });
    assert!(
        !phase::cell::agrees(&other, &c),
        "the sidewinding verdicts differ"
    );
    let mut failed = c.clone();
    failed.regime = None;
    assert!(!phase::cell::agrees(&failed, &c));
}
