//! `slither optimize --ensemble K`: the best point and the runner-up are re-run as ensembles,
//! and `optimum.json` says whether the improvement is larger than the spread, consistently
//! with the ensembles' own numbers and with `history.csv`. A tiny serpenoid keeps it fast.
use std::path::PathBuf;
use std::process::Command;

const BASE: &str = "\
[rod]
length = 1.0
diameter = 0.02
elements = 12
bending_stiffness = 0.01308

[ground]
mu_forward = 0.11
mu_backward = 0.14
mu_sideways = 0.30

[gait]
kind = \"serpenoid\"
stress = 12000.0
speed = 0.5
wavelength = 0.6
ramp = 0.1

[time]
dt = 1e-2
duration = 1.0

[output]
interval = 0.05
";

const STUDY: &str = "\
[study]
base = \"base.toml\"
max_evaluations = 6
duration_pulses = 0.5

[optimize]
stress = [6000.0, 24000.0]
speed = [0.3, 0.8]
initial = { stress = 9000.0, speed = 0.4 }
";

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("slither-opt-ens-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn optimum_json_compares_the_best_and_the_runner_up_as_ensembles() {
    let dir = scratch("check");
    std::fs::write(dir.join("base.toml"), BASE).unwrap();
    std::fs::write(dir.join("study.toml"), STUDY).unwrap();
    let out = dir.join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_slither"))
        .args([
            "optimize",
            dir.join("study.toml").to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--ensemble",
            "3",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("runner-up"), "{err}");
    let opt: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("optimum.json")).unwrap()).unwrap();
    let c = &opt["ensemble"];
    assert_eq!(c["runs"], 3);
    assert_eq!(c["best"]["eval"], opt["best"]["eval"]);
    assert_eq!(c["best"]["v_s"], opt["best"]["v_s"]);
    // The runner-up is the fastest other finished evaluation in history.csv.
    let text = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = |name: &str| head.iter().position(|c| *c == name).unwrap();
    let best_eval = opt["best"]["eval"].as_u64().unwrap();
    let (mut top, mut top_eval) = (f64::NEG_INFINITY, 0);
    let best_point: Vec<String> = lines
        .clone()
        .map(|l| l.split(',').collect::<Vec<_>>())
        .find(|f| f[at("eval")].parse::<u64>().unwrap() == best_eval)
        .map(|f| vec![f[at("stress")].to_string(), f[at("speed")].to_string()])
        .unwrap();
    for l in lines {
        let f: Vec<&str> = l.split(',').collect();
        let same_point = f[at("stress")] == best_point[0] && f[at("speed")] == best_point[1];
        if f[at("status")] == "ok" && !same_point {
            let v: f64 = f[at("v_s")].parse().unwrap();
            if v > top {
                (top, top_eval) = (v, f[at("eval")].parse::<u64>().unwrap());
            }
        }
    }
    assert_eq!(c["runner_up"]["eval"].as_u64().unwrap(), top_eval);
    assert_eq!(c["runner_up"]["v_s"].as_f64().unwrap(), top);
    // The verdict follows from the two ensembles' statistics of the study's objective (here
    // "v_s": the objective is -v_s, lower is better), as recorded in optimum.json.
    assert_eq!(c["objective"], "v_s");
    assert_eq!(opt["settings"]["objective"], "v_s");
    assert_eq!(opt["settings"]["ensemble"]["runs"], 3);
    assert!(opt["settings"]["max_heading_deg"].is_null());
    assert!(opt["settings"]["turn_penalty"].is_null());
    let s = |who: &str, k: &str| c[who]["ensemble_objective"][k].as_f64().unwrap();
    let v = |who: &str, k: &str| c[who]["ensemble_v_s"][k].as_f64().unwrap();
    assert_eq!(c["best"]["ensemble_objective"]["n"], 3);
    assert_eq!(c["runner_up"]["ensemble_objective"]["n"], 3);
    assert!(s("best", "sd") > 0.0, "the members differ");
    // For v_s the objective's statistics are those of -v_s.
    assert!((s("best", "mean") + v("best", "mean")).abs() < 1e-12);
    assert_eq!(s("best", "min"), -v("best", "max"));
    assert_eq!(
        c["best"]["objective"].as_f64().unwrap(),
        -opt["best"]["v_s"].as_f64().unwrap()
    );
    let improvement = s("runner_up", "mean") - s("best", "mean");
    assert!((c["improvement"].as_f64().unwrap() - improvement).abs() < 1e-15);
    let spread = s("best", "sd").hypot(s("runner_up", "sd"));
    assert!((c["spread"].as_f64().unwrap() - spread).abs() < 1e-15);
    // "improvement exceeds spread" means what it says; the ranges' overlap is its own key.
    assert_eq!(
        c["improvement_exceeds_spread"].as_bool().unwrap(),
        improvement > spread
    );
    assert_eq!(
        c["ranges_separate"].as_bool().unwrap(),
        s("best", "max") < s("runner_up", "min")
    );
    let gain = opt["v_s_gain"].as_f64().unwrap();
    assert_eq!(c["gain_over_initial"].as_f64().unwrap(), gain);
    assert_eq!(
        c["gain_exceeds_spread"].as_bool().unwrap(),
        gain > s("best", "max") - s("best", "min")
    );
    assert_eq!(c["best"]["seeds"].as_array().unwrap().len(), 3);
    // Without --ensemble optimum.json has no such key.
    let plain = dir.join("plain");
    let o = Command::new(env!("CARGO_BIN_EXE_slither"))
        .args([
            "optimize",
            dir.join("study.toml").to_str().unwrap(),
            "--out",
            plain.to_str().unwrap(),
            "--quiet",
        ])
        .output()
        .unwrap();
    assert!(o.status.success());
    let opt2: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(plain.join("optimum.json")).unwrap())
            .unwrap();
    assert!(opt2.get("ensemble").is_none());
    assert_eq!(opt2["best"], opt["best"]);
    let _ = std::fs::remove_dir_all(&dir);
}
