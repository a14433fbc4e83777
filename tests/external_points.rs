//! Another code's points on the gait work-precision chart (`slither chart work-precision
//! PROBLEM --external FILE`, `src/charts/external.rs`): the file's errors name the file, the
//! line and the column; a bad file stops the command before any run; the points are written
//! (JSON, CSV, summary) with their error against their own converged value and their wall time
//! scaled to the scene's duration.

use slither::charts::{
    external::parse_external, read_external, write_gait_precision, GaitMethod, GaitPoint,
    GaitPrecision, GaitPrecisionOptions, GaitReference, GaitRun,
};
use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_slither");
const SCENE: &str = "pyelastica_s_start.toml";
const HEADER: &str =
    "scene,code,elements,dt_s,v_s_over_v_m,reference_v_s_over_v_m,wall_s_per_simulated_s";

/// A fresh, empty scratch directory unique to this test process and test name.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("slither-external-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The message of parsing `text` as file `f.csv` for the chart of [`SCENE`].
fn error_of(text: &str) -> String {
    match parse_external(text, Path::new("f.csv"), SCENE) {
        Ok(r) => panic!("accepted {text:?}: {r:?}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn a_valid_file_is_read_in_any_column_order() {
    // Columns in another order than the writer's; a blank line skipped.
    let text =
        "code,scene,elements,v_s_over_v_m,dt_s,wall_s_per_simulated_s,reference_v_s_over_v_m\n\
                PyElastica 1.0.0,pyelastica_s_start.toml,50,0.1,1e-4,1.5,0.125\n\
                \n\
                PyElastica 1.0.0,pyelastica_s_start.toml,100,0.13,7e-5,2.0,0.125\n";
    let runs = parse_external(text, Path::new("f.csv"), SCENE).unwrap();
    assert_eq!(runs.len(), 2);
    assert_eq!(runs[0].code, "PyElastica 1.0.0");
    assert_eq!(runs[0].elements, 50);
    assert_eq!(runs[0].dt, 1e-4);
    assert_eq!(runs[0].v_ratio, 0.1);
    assert_eq!(runs[0].reference, 0.125);
    assert_eq!(runs[1].wall_per_simulated_s, 2.0);
}

#[test]
fn bad_header_names_the_line_and_the_column() {
    let e = error_of(
        "scene,code,elements,dt,v_s_over_v_m,reference_v_s_over_v_m,wall_s_per_simulated_s\n",
    );
    assert!(e.starts_with("f.csv:1: column 'dt': unknown column"), "{e}");
    let e = error_of("\n\nscene,code,elements,dt_s,v_s_over_v_m,wall_s_per_simulated_s\nx\n");
    assert!(
        e.starts_with("f.csv:3: column 'reference_v_s_over_v_m': missing from the header"),
        "{e}"
    );
    let e = error_of(&format!("{HEADER},code\n"));
    assert!(e.starts_with("f.csv:1: column 'code': named twice"), "{e}");
    let e = error_of("");
    assert!(e.starts_with("f.csv: empty"), "{e}");
    let e = error_of(&format!("{HEADER}\n"));
    assert!(e.starts_with("f.csv:1: a header and no runs"), "{e}");
}

#[test]
fn bad_values_name_the_line_and_the_column() {
    let row = |r: &str| format!("{HEADER}\n{SCENE},PE,50,1e-4,0.1,0.12,1.5\n{r}\n");
    let cases = [
        ("pyelastica_s_start.toml,PE,50,abc,0.1,0.12,1.5", "f.csv:3: column 'dt_s': 'abc' is not a number"),
        ("pyelastica_s_start.toml,PE,50,-1e-4,0.1,0.12,1.5", "f.csv:3: column 'dt_s': '-1e-4' is not a positive step"),
        ("pyelastica_s_start.toml,PE,0,1e-4,0.1,0.12,1.5", "f.csv:3: column 'elements': '0' is not a positive integer"),
        ("pyelastica_s_start.toml,PE,50,1e-4,NaN,0.12,1.5", "f.csv:3: column 'v_s_over_v_m': 'NaN' is not finite"),
        ("pyelastica_s_start.toml,PE,50,1e-4,0.1,0,1.5", "f.csv:3: column 'reference_v_s_over_v_m': '0' is not finite and not zero"),
        ("pyelastica_s_start.toml,PE,50,1e-4,0.1,0.12,0", "f.csv:3: column 'wall_s_per_simulated_s': '0' is not positive"),
        ("pyelastica_s_start.toml,,50,1e-4,0.1,0.12,1.5", "f.csv:3: column 'code': empty"),
        ("pyelastica_s_start.toml,PE,50,1e-4,0.1,0.12", "f.csv:3: 6 fields, the header has 7 columns"),
        ("s_start.toml,PE,50,1e-4,0.1,0.12,1.5", "f.csv:3: column 'scene': 's_start.toml' is not this chart's scene 'pyelastica_s_start.toml'"),
    ];
    for (r, want) in cases {
        let e = error_of(&row(r));
        assert!(e.starts_with(want), "row {r:?}: got {e:?}, want {want:?}");
    }
}

#[test]
fn a_missing_file_is_named() {
    let dir = scratch("missing");
    let f = dir.join("none.csv");
    let e = read_external(&f, SCENE).unwrap_err().to_string();
    assert!(
        e.starts_with(&format!("{}: cannot read", f.display())),
        "{e}"
    );
}

#[test]
fn the_command_rejects_a_bad_file_before_running() {
    let dir = scratch("cli");
    let f = dir.join("pe.csv");
    std::fs::write(&f, format!("{HEADER}\n{SCENE},PE,50,1e-4,0.1,0.12,fast\n")).unwrap();
    let problem = Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/pyelastica_s_start.toml");
    let t0 = std::time::Instant::now();
    let o = Command::new(BIN)
        .args(["chart", "work-precision"])
        .arg(&problem)
        .arg("--out")
        .arg(dir.join("out"))
        .arg("--external")
        .arg(&f)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains(&format!(
            "{}:2: column 'wall_s_per_simulated_s': 'fast' is not a number",
            f.display()
        )),
        "{err}"
    );
    // Nothing ran: no reference cache, and far less time than one run of the scene.
    assert!(!dir.join("out/reference.json").exists());
    assert!(t0.elapsed().as_secs_f64() < 2.0, "{:?}", t0.elapsed());
}

/// `--meshes` and `--bdf2-dt` name the bad value and the allowed range, before any run.
#[test]
fn the_command_rejects_bad_meshes_and_steps() {
    let dir = scratch("cli-options");
    let problem = Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/pyelastica_s_start.toml");
    for (flag, value, message) in [
        (
            "--meshes",
            "50,1",
            "'1' is not a mesh: a whole number of elements in [2, 100000]",
        ),
        ("--meshes", "50,x", "'x' is not a mesh"),
        (
            "--bdf2-dt",
            "3.6e-3,0",
            "'0' is not a step: seconds in (0, 1]",
        ),
        ("--bdf2-dt", "-1e-3", "is not a step"),
    ] {
        let o = Command::new(BIN)
            .args(["chart", "work-precision"])
            .arg(&problem)
            .arg("--out")
            .arg(dir.join("out"))
            .arg(format!("{flag}={value}"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{flag} {value}: {err}");
        assert!(
            err.contains(flag) && err.contains(message),
            "{flag} {value}: {err}"
        );
        assert!(!dir.join("out/reference.json").exists());
    }
}

/// A run of the chart with the given values (no simulation behind it).
fn run(method: &str, elements: usize, dt: f64, v: f64, wall_s: f64) -> GaitRun {
    GaitRun {
        method: GaitMethod::from_name(method).expect("a method name"),
        elements,
        dt,
        tolerance: None,
        v_ratio: v,
        wall_s,
        steps: 100,
        rejected: 0,
        dt_range: (dt, dt),
        status: "ok".into(),
        x: Vec::new(),
    }
}

#[test]
fn the_external_series_is_written() {
    let reference = 0.32;
    let points = [
        (50, 2e-3, 0.30, 1.0),
        (50, 5e-4, 0.315, 2.5),
        (100, 2e-3, 0.3199, 3.0),
    ]
    .into_iter()
    .map(|(n, dt, v, w)| GaitPoint {
        run: run("implicit", n, dt, v, w),
        v_error: (v / reference - 1.0_f64).abs(),
        x_error: 0.01,
    })
    .collect();
    let g = GaitPrecision {
        scene: SCENE.into(),
        elements: 100,
        duration: 4.0,
        options: GaitPrecisionOptions::default(),
        reference: GaitReference {
            key: String::new(),
            runs: vec![run("implicit", 100, 2.5e-4, reference, 10.0)],
            change: 1e-4,
            converged: true,
            scatter_runs: Vec::new(),
            scatter: 1e-4,
            v_ratio: reference,
            wall_s: 10.0,
        },
        points,
        external: Vec::new(),
    };
    let text = format!(
        "{HEADER}\n{SCENE},PyElastica 1.0.0,50,1e-4,0.110,0.125,1.5\n\
         {SCENE},PyElastica 1.0.0,200,3.5e-5,0.1240,0.125,6.0\n"
    );
    let runs = parse_external(&text, Path::new("pe.csv"), SCENE).unwrap();
    let g = g.with_external(runs);
    // Error against the code's own converged value; wall time for the scene's 4 s.
    assert_eq!(g.external.len(), 2);
    assert!((g.external[0].v_error - 0.12).abs() < 1e-12);
    assert!((g.external[0].wall_s - 6.0).abs() < 1e-12);
    assert!((g.external[1].v_error - 0.008).abs() < 1e-12);
    assert!((g.external[1].wall_s - 24.0).abs() < 1e-12);
    let s = g.summary();
    assert!(
        s.contains("PyElastica 1.0.0 200 el.: within 1.0 % of its own converged value at 24.00 s"),
        "{s}"
    );
    assert!(
        s.contains("PyElastica 1.0.0 50 el.: never within 1.0 % of its own converged value"),
        "{s}"
    );
    // slither's cheapest within 1 %: 100 el. at 3 s (0.03 %); 24 / 3 = 8.
    assert!(s.contains("slither implicit 100 el."), "{s}");
    assert!(s.contains("; 8.0x"), "{s}");

    let dir = scratch("write");
    write_gait_precision(&dir, &g).unwrap();
    let csv = std::fs::read_to_string(dir.join("gait_precision_external.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows.len(), 3, "{csv}");
    assert_eq!(rows[0], format!("{HEADER},wall_s,v_error"));
    assert!(
        rows[2].starts_with(&format!("{SCENE},PyElastica 1.0.0,200,3.5e-5,")),
        "{csv}"
    );
    let fields: Vec<f64> = rows[2]
        .split(',')
        .skip(3)
        .map(|f| f.parse().unwrap())
        .collect();
    assert!(
        (fields[4] - 24.0).abs() < 1e-9 && (fields[5] - 0.008).abs() < 1e-9,
        "{csv}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("gait_precision.json")).unwrap())
            .unwrap();
    let ext = json["external"].as_array().expect("external in the JSON");
    assert_eq!(ext.len(), 2);
    assert_eq!(ext[1]["code"], "PyElastica 1.0.0");
    assert_eq!(ext[1]["elements"], 200);
    assert!((ext[1]["wall_s"].as_f64().unwrap() - 24.0).abs() < 1e-9);
    // The figure with the external series is drawn.
    let png = std::fs::metadata(dir.join("gait_precision.png")).unwrap();
    assert!(png.len() > 10_000, "{}", png.len());
}
