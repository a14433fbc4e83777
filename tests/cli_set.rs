//! Command-line overrides (`--set KEY=VALUE`), the effective problem (`--dump-problem`), and
//! validation where the physics ends (overflowing inputs, scaled groups out of range, an
//! unmet accuracy target): `slither run` end to end.
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("slither_cli_set_{}_{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn run(problem: &Path, out: &Path, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_slither"))
        .args([
            "run",
            problem.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ])
        .args(extra)
        .output()
        .unwrap()
}

/// The command succeeded (else its stderr).
fn ok(r: &Output) {
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(0), "{err}");
}

fn bundled(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("problems")
        .join(name)
}

#[test]
fn settings_change_the_run_and_the_dumped_problem_reruns_to_the_same_result() {
    let d = dir("dump");
    let dump = d.join("effective.toml");
    let r = run(
        &bundled("slide.toml"),
        &d.join("a"),
        &[
            "--no-plots",
            "--set",
            "rod.elements=12",
            "--set",
            "initial.velocity[0]=0.3",
            "--set",
            "time.duration=0.05",
            "--dump-problem",
            dump.to_str().unwrap(),
        ],
    );
    ok(&r);
    let text = std::fs::read_to_string(&dump).unwrap();
    assert!(text.starts_with("# The effective problem of "), "{text}");
    assert!(text.contains("--set rod.elements=12"), "{text}");
    let p = slither::problem::load(&dump).unwrap();
    assert_eq!(p.rod.elements, 12);
    assert_eq!(p.initial.velocity, [0.3, 0.0, 0.0]);
    assert_eq!(p.time.duration, Some(0.05));
    // Every key written: the dump of the dump is the same text.
    assert_eq!(text.split_once('\n').unwrap().1, p.to_toml());
    // The run used the settings: 13 nodes in the final state.
    let fin = std::fs::read_to_string(d.join("a/final.csv")).unwrap();
    assert_eq!(
        fin.lines().filter(|l| !l.starts_with('#')).count(),
        1 + 13,
        "{fin}"
    );
    // The dumped problem reruns to the same final state, bit for bit.
    let r = run(&dump, &d.join("b"), &["--no-plots"]);
    ok(&r);
    assert_eq!(fin, std::fs::read_to_string(d.join("b/final.csv")).unwrap());
}

#[test]
fn a_bad_setting_is_refused_naming_the_setting_and_the_range() {
    let d = dir("bad");
    let slide = bundled("slide.toml");
    for (arg, wanted) in [
        ("rod.length=-1", "--set rod.length=-1: `rod.length` = -1 is not allowed: must be a finite number > 0 (m)"),
        ("rod.lenght=1", "unknown field `lenght`"),
        ("rod.length=abc", "expected f64"),
        ("initial.velocity[3]=1", "index 3 is beyond the array's 3 elements"),
        ("gait.centers[0]=0.5", "`gait.centers` is not in the file"),
        ("rod.length.x=1", "`rod.length` is a value, not a table"),
        ("rod.length", "no '='"),
    ] {
        let r = run(&slide, &d.join("o"), &["--set", arg]);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{arg}: {err}");
        assert!(err.contains(wanted), "{arg}: {err}");
        assert!(!d.join("o/summary.json").exists());
    }
    // A type error keeps the key's allowed range and does not quote the edited text's lines.
    let r = run(&slide, &d.join("o"), &["--set", "rod.length=abc"]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(
        err.contains("allowed: `rod.length` must be a finite number > 0 (m)"),
        "{err}"
    );
    assert!(!err.contains("line 5"), "{err}");
    // A key the settings did not change, made invalid by one they did, says so.
    let r = run(
        &bundled("s_start.toml"),
        &d.join("o"),
        &["--set", "rod.elements=10"],
    );
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(2), "{err}");
    assert!(
        err.contains("`gait.sigma`")
            && err.contains("(the file as changed by --set rod.elements=10)"),
        "{err}"
    );
}

#[test]
fn overflowing_inputs_are_refused_with_exit_2_and_the_key() {
    let d = dir("overflow");
    for (file, arg, key) in [
        (
            "slide.toml",
            "initial.velocity=[1e308, 0, 0]",
            "`initial.velocity`",
        ),
        (
            "slide.toml",
            "initial.velocity=[1e20, 0, 0]",
            "at most 1000 m/s",
        ),
        (
            "slide.toml",
            "initial.angular_velocity=[0, 0, 1e200]",
            "`initial.angular_velocity`",
        ),
        (
            "slide.toml",
            "ground.mu_forward=1e308",
            "`ground.mu_forward` = 1e308 is not allowed: must be a number in [0, 100]",
        ),
        (
            "s_start.toml",
            "gait.scales=[1e300, 1, 1]",
            "`gait.scales` = 1e300",
        ),
    ] {
        let r = run(&bundled(file), &d.join("o"), &["--set", arg]);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{arg}: {err}");
        assert!(err.contains(key), "{arg}: {err}");
    }
}

#[test]
fn scaled_groups_outside_the_physical_range_need_force() {
    let d = dir("groups");
    let s = bundled("s_start.toml");
    for (arg, what) in [
        ("gravity.g=1e-30", "scaled weight W"),
        ("gait.stress=1e-30", "scaled torque G"),
        ("rod.density=1e12", "scaled weight W"),
    ] {
        let r = run(&s, &d.join("o"), &["--set", arg]);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{arg}: {err}");
        assert!(
            err.contains(what) && err.contains("--force"),
            "{arg}: {err}"
        );
    }
    // Zero stays valid (no muscles), and --force runs a refused one (vanishing muscles: the
    // snake lies still; vanishing gravity makes Newton fail to converge, which the check
    // prevents).
    for extra in [
        &["--set", "gait.stress=0"][..],
        &["--force", "--set", "gait.stress=1e-30"],
    ] {
        let mut args = vec!["--no-plots", "--set", "time.duration=0.02"];
        args.extend(extra);
        let r = run(&s, &d.join("o"), &args);
        assert_eq!(
            r.status.code(),
            Some(0),
            "{args:?}: {}",
            String::from_utf8_lossy(&r.stderr)
        );
    }
}

#[test]
fn an_unmet_accuracy_target_exits_4_with_one_line_even_when_quiet() {
    let d = dir("accuracy");
    let r = run(
        &bundled("s_start.toml"),
        &d.join("o"),
        &[
            "--no-plots",
            "--set",
            "rod.elements=8",
            "--set",
            "gait.sigma=0.15",
            "--set",
            "time.duration=0.2",
            "--set",
            "time.dt=0.01",
            "--set",
            "accuracy.target=1e-4",
            "--set",
            "accuracy.max_elements=16",
        ],
    );
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(4), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("accuracy target 0.0001 NOT met"), "{err}");
    let summary = std::fs::read_to_string(d.join("o/summary.json")).unwrap();
    assert!(summary.contains("\"met\": false"), "{summary}");
}

fn slither(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_slither"))
        .args(args)
        .output()
        .unwrap()
}

/// A 2 x 1 phase grid on the coarse S-start, in `d` (the base copied beside it).
fn tiny_phase(d: &Path) -> PathBuf {
    std::fs::copy(bundled("s_start_coarse.toml"), d.join("base.toml")).unwrap();
    let f = d.join("phase.toml");
    std::fs::write(
        &f,
        "[phase]\nbase = \"base.toml\"\nweight = [100.0, 300.0]\ntorque = [15.0]\n",
    )
    .unwrap();
    f
}

#[test]
fn a_phase_cell_with_settings_dumps_its_problem_which_reruns_to_the_same_result() {
    let d = dir("cell");
    let f = tiny_phase(&d);
    let dump = d.join("cell.toml");
    let cell = d.join("cell");
    let r = slither(&[
        "phase",
        f.to_str().unwrap(),
        "--cell-index",
        "1,0",
        "--out",
        cell.to_str().unwrap(),
        "--quiet",
        "--no-plots",
        "--set",
        "rod.elements=20",
        "--set",
        "time.duration=0.1",
        "--dump-problem",
        dump.to_str().unwrap(),
    ]);
    ok(&r);
    let p = slither::problem::load(&dump).unwrap();
    assert_eq!((p.rod.elements, p.time.duration), (20, Some(0.1)));
    // The cell's W = 300 is the base's (set through B, as the study does).
    let (w, g) = slither::problem::limits::scaled_groups(&p);
    assert!(
        (w / 300.0 - 1.0).abs() < 1e-12 && (g / 15.0 - 1.0).abs() < 1e-12,
        "{w} {g}"
    );
    let again = d.join("again");
    let r = run(&dump, &again, &["--no-plots"]);
    ok(&r);
    assert_eq!(
        std::fs::read_to_string(cell.join("final.csv")).unwrap(),
        std::fs::read_to_string(again.join("final.csv")).unwrap()
    );
    // A setting of the phase table is validated like the file, and names itself.
    let r = slither(&[
        "phase",
        f.to_str().unwrap(),
        "--out",
        d.join("x").to_str().unwrap(),
        "--set",
        "phase.weight=[1e-30]",
    ]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(2), "{err}");
    assert!(
        err.contains("--set phase.weight=[1e-30]") && err.contains("[1e-6, 1e9]"),
        "{err}"
    );
}

#[test]
fn shards_run_with_settings_merge_because_phase_json_records_them() {
    let d = dir("shards");
    let f = tiny_phase(&d);
    let set = ["--set", "rod.elements=20", "--set", "time.duration=0.05"];
    let mut dirs = Vec::new();
    let shards = d.join("shards");
    for k in ["1/2", "2/2"] {
        let out = shards.join(&k[..1]);
        let mut args = vec![
            "phase",
            f.to_str().unwrap(),
            "--shard",
            k,
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ];
        args.extend(set);
        let r = slither(&args);
        ok(&r);
        let info = std::fs::read_to_string(out.join("phase.json")).unwrap();
        assert!(info.contains("\"rod.elements=20\""), "{info}");
        if k == "1/2" {
            // Half done: the command for the missing shard carries the settings.
            let o = slither(&["status", shards.to_str().unwrap()]);
            let text = String::from_utf8_lossy(&o.stdout);
            assert!(
                text.contains("--shard 2/2")
                    && text.contains("--set 'rod.elements=20' --set 'time.duration=0.05'"),
                "{text}"
            );
        }
        dirs.push(out);
    }
    let merged = d.join("merged");
    let r = slither(&[
        "merge",
        dirs[0].to_str().unwrap(),
        dirs[1].to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]);
    ok(&r);
    assert_eq!(
        std::fs::read_to_string(merged.join("phase.csv"))
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with('#'))
            .count(),
        3
    );
}

#[test]
fn optimize_settings_edit_the_study_or_its_base_and_name_themselves() {
    let d = dir("optimize");
    let study = bundled("optimize_s_start.toml");
    for (arg, wanted) in [
        (
            "study.max_evaluations=0",
            "--set study.max_evaluations=0: `study.max_evaluations` = 0 is not allowed",
        ),
        (
            "rod.elements=1",
            "--set rod.elements=1: `rod.elements` = 1 is not allowed",
        ),
        (
            "optimize.sigma=[0.07, 0.04]",
            "--set optimize.sigma=[0.07, 0.04]",
        ),
    ] {
        let r = slither(&[
            "optimize",
            study.to_str().unwrap(),
            "--out",
            d.join("o").to_str().unwrap(),
            "--set",
            arg,
        ]);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{arg}: {err}");
        assert!(err.contains(wanted), "{arg}: {err}");
    }
}
