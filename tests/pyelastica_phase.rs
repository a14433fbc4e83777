//! The phase grid of `problems/phase_pyelastica_straight.toml` side by side with PyElastica
//! (issue 50): slither runs each cell of the grid at the phase file's base (200 elements,
//! implicit Euler 1e-3 s); PyElastica's runs of the same cells (`lab/pyelastica_phase/pyelastica_phase.sh
//! pe`, muscles as a rest curvature, 50 and 200 elements) are labelled by slither's own
//! observables and regime rules (`slither::observe`), computed from PyElastica's frames.
//!
//! PyElastica's ground is a penalty spring the body sinks into, so "touching" needs a rule of
//! its own there: a node touches while PyElastica's spring pushes on it, i.e. while its centre
//! lies below `a/2` (elevation < 0); above it is lifted. (slither's own contact is exact: a
//! node touches while its normal force is positive.) The frames are PyElastica's every 0.02 s,
//! slither's observation grid for this scene (`T / 200`).
//!
//! Needs PyElastica's frames, so it is ignored in the ordinary suite:
//! `PE_PHASE_DIR=out/pyelastica_phase cargo test --release --test pyelastica_phase --
//! --ignored --nocapture` (what `lab/pyelastica_phase/pyelastica_phase.sh label` runs).
use slither::model::Model;
use slither::observe::{self, classify, Regime};
use slither::sim::{self, Frame};
use slither::studies::phase::{self, cell_problem};
use std::path::Path;

/// PyElastica's frames of one run (slither's axes and node order).
fn pe_frames(path: &Path, m: &Model) -> Vec<Frame> {
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let vecs = |f: &serde_json::Value| -> Vec<[f64; 3]> {
        f.as_array()
            .unwrap()
            .iter()
            .map(|p| {
                let p = p.as_array().unwrap();
                [
                    p[0].as_f64().unwrap(),
                    p[1].as_f64().unwrap(),
                    p[2].as_f64().unwrap(),
                ]
            })
            .collect()
    };
    let t = v["t"].as_array().unwrap();
    let a = m.diameter;
    // Any force above slither's contact threshold marks a touching node.
    let touching = 1.0 + 2.0 * m.contact_threshold();
    (0..t.len())
        .map(|k| {
            let x = vecs(&v["x"][k]);
            assert_eq!(x.len(), m.real.len(), "{}", path.display());
            let normal = x
                .iter()
                .map(|p| if p[2] - 0.5 * a < 0.0 { touching } else { 0.0 })
                .collect();
            Frame {
                t: t[k].as_f64().unwrap(),
                theta: vec![0.0; x.len() - 1],
                v: vecs(&v["v"][k]),
                d1: vecs(&v["d1"][k]),
                normal,
                x,
            }
        })
        .collect()
}

/// A regime reason as a Markdown table cell (its `|v_s/v_m|` would end the cell).
fn cell_text(text: &str) -> String {
    text.replace('|', "\\|")
}

fn label(r: Regime) -> &'static str {
    match r {
        Regime::S => "S",
        Regime::M => "M",
        Regime::F => "F",
        Regime::N => "N",
        Regime::U => "U",
    }
}

#[test]
#[ignore]
fn pyelastica_phase_side_by_side() {
    let Ok(dir) = std::env::var("PE_PHASE_DIR") else {
        return;
    };
    let study = phase::load(Path::new("problems/phase_pyelastica_straight.toml")).unwrap();
    println!("| W | G | slither (200 el.) | v_s/v_m | PyElastica 50 el. | v_s/v_m | PyElastica 200 el. | v_s/v_m |");
    println!("|---|---|---|---|---|---|---|---|");
    let mut agree = [0usize; 2];
    let mut cells = 0;
    for &w in &study.weight {
        for &g in &study.torque {
            let p = cell_problem(&study.base, w, g);
            let m = Model::new(&p);
            let o = sim::run_gait(&m, p.solver.integrator, &mut |_| {}, &mut |_| {}).unwrap();
            let (sl, sl_v) = if o.error.is_some() {
                ("failed".to_string(), f64::NAN)
            } else {
                let ob = observe::of_outcome(&m, &o);
                let (r, why) = classify(&ob.regime_inputs());
                (
                    format!("{} ({})", label(r), cell_text(&why.text)),
                    ob.v_s_over_v_m,
                )
            };
            let mut row = format!("| {w} | {g} | {sl} | {sl_v:.3} |");
            for (k, n) in [50usize, 200].into_iter().enumerate() {
                let file = Path::new(&dir).join(format!("pe_{n}_{w:?}_{g:?}.json"));
                if !file.exists() {
                    row.push_str(" (not run) | |");
                    continue;
                }
                let mut pn = p.clone();
                pn.rod.elements = n;
                let mn = Model::new(&pn);
                let frames = pe_frames(&file, &mn);
                let fl = observe::fields(&mn, &frames);
                let ob = observe::observe(&mn, &frames, &fl);
                let (r, why) = classify(&ob.regime_inputs());
                if sl.starts_with(label(r)) {
                    agree[k] += 1;
                }
                row.push_str(&format!(
                    " {} ({}) | {:.3} |",
                    label(r),
                    cell_text(&why.text),
                    ob.v_s_over_v_m
                ));
            }
            println!("{row}");
            cells += 1;
        }
    }
    println!(
        "regime class agreement with slither: PyElastica 50 elements {} of {cells}, 200 elements {} of {cells}",
        agree[0], agree[1]
    );
}
