//! How many cells of a phase study change regime when each classification threshold moves by
//! +-20 %, without simulating again: the regimes are recomputed from the observables stored in
//! `phase.csv` (the README's sensitivity table).
//!
//! ```sh
//! cargo run --release -- phase problems/phase_s_start.toml --out out/phase
//! cargo run --release --example regime_sensitivity -- out/phase/phase.csv [FRACTION]
//! ```
//!
//! `FRACTION` defaults to 0.2. Columns are found by name in the header, so the file may carry
//! other columns too. Failed cells are skipped. The tool first checks that the default
//! thresholds reproduce the stored labels, then prints one Markdown row per threshold: its
//! default, and the cells (`W/G old->new`) that change label at `1 - FRACTION` and at
//! `1 + FRACTION` times it. Exit code 2 on a missing or malformed file.

use slither::observe::regime::{
    classify, classify_with, sensitivity, Regime, RegimeInputs, Thresholds,
};
use std::process::ExitCode;

struct Row {
    weight: f64,
    torque: f64,
    stored: Regime,
    inputs: RegimeInputs,
}

fn read(path: &str) -> Result<Vec<Row>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let mut lines = text.lines().enumerate();
    let header: Vec<&str> = lines
        .next()
        .ok_or(format!("{path}: empty file"))?
        .1
        .split(',')
        .collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .ok_or(format!("{path}: no column `{name}` in the header (a phase.csv written by this version of slither has it)"))
    };
    let names = [
        "weight",
        "torque",
        "status",
        "regime",
        "v_s_over_v_m",
        "displacement_angle_deg",
        "max_elevation_over_a",
        "max_elevation_over_length",
        "two_arc_lift_over_a",
        "lambda_pulse_r2",
        "lambda_pulse_speed_over_v_m",
    ];
    let idx: Vec<usize> = names.iter().map(|n| col(n)).collect::<Result<_, _>>()?;
    let mut rows = Vec::new();
    for (n, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let f: Vec<&str> = line.split(',').collect();
        let field = |k: usize| {
            f.get(idx[k])
                .copied()
                .ok_or(format!("{path}:{}: too few columns", n + 1))
        };
        let num = |k: usize| {
            field(k)?.parse::<f64>().map_err(|_| {
                format!(
                    "{path}:{}: column `{}` is not a number: {:?}",
                    n + 1,
                    names[k],
                    field(k).unwrap_or("")
                )
            })
        };
        if field(2)? != "ok" {
            continue;
        }
        rows.push(Row {
            weight: num(0)?,
            torque: num(1)?,
            stored: field(3)?
                .parse()
                .map_err(|e| format!("{path}:{}: {e}", n + 1))?,
            inputs: RegimeInputs {
                v_s_over_v_m: num(4)?,
                displacement_angle_deg: num(5)?,
                max_elevation_over_a: num(6)?,
                max_elevation_over_length: num(7)?,
                two_arc_lift_over_a: num(8)?,
                lambda_pulse_r2: num(9)?,
                lambda_pulse_speed_over_v_m: num(10)?,
            },
        });
    }
    Ok(rows)
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        eprintln!("usage: regime_sensitivity PHASE_CSV [FRACTION]");
        return ExitCode::from(2);
    };
    let frac = match args.get(1).map(|s| s.parse::<f64>()) {
        None => 0.2,
        Some(Ok(x)) if x > 0.0 && x < 1.0 => x,
        Some(_) => {
            eprintln!(
                "error: FRACTION must be a number in (0, 1), got {:?}",
                args[1]
            );
            return ExitCode::from(2);
        }
    };
    let rows = match read(path) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let name = |r: &Row| format!("{}/{}", r.weight, r.torque);
    let mismatched: Vec<String> = rows
        .iter()
        .filter(|r| classify(&r.inputs).0 != r.stored)
        .map(|r| {
            format!(
                "{} (stored {}, relabelled {})",
                name(r),
                r.stored,
                classify(&r.inputs).0
            )
        })
        .collect();
    let mut counts: Vec<String> = Regime::ALL
        .iter()
        .map(|&g| format!("{g} {}", rows.iter().filter(|r| r.stored == g).count()))
        .collect();
    counts.retain(|c| !c.ends_with(" 0"));
    println!(
        "{path}: {} cells ({}); default thresholds reproduce {} of the stored labels{}",
        rows.len(),
        counts.join(", "),
        rows.len() - mismatched.len(),
        if mismatched.is_empty() {
            String::new()
        } else {
            format!(" (differ: {})", mismatched.join(", "))
        }
    );
    println!();
    let pct = (frac * 100.0).round();
    println!("| threshold | default | cells changed at -{pct} % | cells changed at +{pct} % |");
    println!("|---|---|---|---|");
    let inputs: Vec<RegimeInputs> = rows.iter().map(|r| r.inputs).collect();
    let base = Thresholds::DEFAULT;
    for (thr, value, lo, hi) in sensitivity(&inputs, &base, frac) {
        let list = |changed: &[usize], factor: f64| {
            if changed.is_empty() {
                return "0".to_string();
            }
            let t = base.scaled(thr, factor).expect("a listed threshold");
            let cells: Vec<String> = changed
                .iter()
                .map(|&k| {
                    let r = &rows[k];
                    let (old, new) = (classify(&r.inputs).0, classify_with(&r.inputs, &t).0);
                    format!("W {} G {} {old}->{new}", r.weight, r.torque)
                })
                .collect();
            format!("{}: {}", changed.len(), cells.join(", "))
        };
        println!(
            "| `{thr}` | {value} | {} | {} |",
            list(&lo, 1.0 - frac),
            list(&hi, 1.0 + frac)
        );
    }
    ExitCode::SUCCESS
}
