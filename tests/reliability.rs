//! No silent wrong answers from odd input, crash-safe result files, one run per output
//! directory. One test (or more) per defect found; each failed against the code before the
//! fix.
mod common;

use slither::observe;
use slither::sim::Frame;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_slither");

/// A fresh scratch directory for one test.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("slither-reliability-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn slither(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().expect("run slither")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A tiny valid problem (milliseconds to run).
const TINY: &str = "\
[rod]
length = 1.0
diameter = 0.02
elements = 4
bending_stiffness = 1.0

[time]
dt = 0.005
duration = 0.01
";

/// `slither run` of `text` into `dir/out`; returns the output and the out dir.
fn run_text(dir: &Path, text: &str, extra: &[&str]) -> (Output, PathBuf) {
    let p = dir.join("problem.toml");
    std::fs::write(&p, text).unwrap();
    let out = dir.join("out");
    let mut args = vec!["run", s(&p), "--out", s(&out), "--quiet"];
    args.extend_from_slice(extra);
    (slither(&args), out)
}

fn rejected_with(name: &str, text: &str, needles: &[&str]) -> String {
    let d = scratch(name);
    let (o, out) = run_text(&d, text, &[]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{text}\n{err}");
    assert_eq!(err.matches("error:").count(), 1, "{err}");
    for n in needles {
        assert!(err.contains(n), "{n:?} not in {err}");
    }
    assert!(!out.join("summary.json").exists());
    let _ = std::fs::remove_dir_all(&d);
    err
}

// ---------------------------------------------------------------------------------------------
// 1. Post-processing cost and run-size limits
// ---------------------------------------------------------------------------------------------

// The densities' cost is counted in pair evaluations in `src/topology/tests.rs`
// (`densities_of_a_fine_mesh_are_not_cubic`), not timed here.

#[test]
fn runs_above_the_size_limits_are_refused_up_front() {
    let tiny_dt = TINY.replace("dt = 0.005", "dt = 1e-9");
    let err = rejected_with("dt", &tiny_dt, &["`time.dt`", "--force", "steps"]);
    assert!(err.contains(":8: "), "names the line of dt: {err}");
    let tiny_interval = format!("{TINY}\n[output]\ninterval = 1e-9\n");
    let tiny_interval = tiny_interval
        .replace("dt = 0.005", "dt = 1e-5")
        .replace("duration = 0.01", "duration = 1.5");
    rejected_with(
        "interval",
        &tiny_interval,
        &["`output.interval`", "--force", "frames"],
    );
    let fine = TINY
        .replace("elements = 4", "elements = 30000")
        .replace("duration = 0.01", "duration = 0.25")
        .replace("diameter = 0.02", "diameter = 0.00002");
    rejected_with("fine", &fine, &["post-processing", "--force"]);
    // --force skips the limits: the same file then gets past them to the output directory
    // (here /proc, which cannot be written: exit 1 before simulating, not exit 2).
    let d = scratch("force");
    let p = d.join("p.toml");
    std::fs::write(&p, &tiny_dt).unwrap();
    let o = slither(&["run", s(&p), "--out", "/proc", "--quiet"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let o = slither(&["run", s(&p), "--out", "/proc", "--quiet", "--force"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("before simulating"), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(&d);
}

// ---------------------------------------------------------------------------------------------
// 2. Crash-safe phase.csv
// ---------------------------------------------------------------------------------------------

/// A phase file over a tiny S-start base (10 elements, 5 steps) and a 1 x 2 grid.
fn tiny_phase(dir: &Path) -> PathBuf {
    std::fs::write(
        dir.join("base.toml"),
        "[rod]\nlength = 1.0\ndiameter = 0.02\nelements = 10\nbending_stiffness = 0.01308\n[ground]\nmu_forward = 0.55\nmu_backward = 0.7\nmu_sideways = 1.0\n[gait]\nkind = \"s-start\"\nstress = 24525.0\nsigma = 0.1\nspeed = 0.28\ncenters = [0.2, 0.35, 0.5]\n[time]\ndt = 0.01\nduration = 0.05\n",
    )
    .unwrap();
    let f = dir.join("phase.toml");
    std::fs::write(
        &f,
        "[phase]\nbase = \"base.toml\"\nweight = [300.0]\ntorque = [10.0, 15.0]\n",
    )
    .unwrap();
    f
}

#[test]
fn phase_csv_torn_last_row_is_dropped_and_resimulated() {
    let d = scratch("phase-torn");
    let f = tiny_phase(&d);
    let out = d.join("out");
    let o = slither(&["phase", s(&f), "--out", s(&out), "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = out.join("phase.csv");
    let full = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = full.lines().collect();
    assert_eq!(lines.len(), 3);
    // A crash cut the second row in its middle (no newline).
    let torn = format!(
        "{}\n{}\n{}",
        lines[0],
        lines[1],
        &lines[2][..lines[2].len() / 2]
    );
    std::fs::write(&csv, torn).unwrap();
    let o = slither(&["phase", s(&f), "--out", s(&out)]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("incomplete last row"), "{err}");
    assert!(err.contains("1 simulated, 1 reused"), "{err}");
    let again = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(again.lines().count(), 3, "{again}");
    assert!(again.ends_with('\n'));
    let columns = slither::studies::phase::HEADER.split(',').count();
    for l in again.lines() {
        assert_eq!(l.split(',').count(), columns, "{l}");
    }
    // A third run reuses both cells.
    let o = slither(&["phase", s(&f), "--out", s(&out)]);
    assert!(
        stderr(&o).contains("0 simulated, 2 reused"),
        "{}",
        stderr(&o)
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn phase_csv_corrupt_middle_row_is_exit_2_naming_it() {
    let d = scratch("phase-corrupt");
    let f = tiny_phase(&d);
    let out = d.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let o = slither(&["phase", s(&f), "--out", s(&out), "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = out.join("phase.csv");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    lines[1] = lines[1].replacen(',', ",x", 1);
    std::fs::write(&csv, lines.join("\n") + "\n").unwrap();
    let o = slither(&["phase", s(&f), "--out", s(&out), "--quiet"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("phase.csv:2:"), "{err}");
    let _ = std::fs::remove_dir_all(&d);
}

// ---------------------------------------------------------------------------------------------
// 3, 4, 13. Array lengths, ranges and type errors
// ---------------------------------------------------------------------------------------------

const GAIT: &str =
    "\n[ground]\n\n[gait]\nkind = \"s-start\"\nstress = 1000.0\nsigma = 0.3\nspeed = 0.3\n";

#[test]
fn fixed_length_arrays_reject_extra_elements() {
    rejected_with(
        "centers5",
        &format!("{TINY}{GAIT}centers = [0.2, 0.35, 0.5, 0.9, 7.0]\n"),
        &[
            "`gait.centers`",
            "exactly 3 elements",
            "an array of 5 elements",
        ],
    );
    rejected_with(
        "velocity4",
        &format!("{TINY}\n[initial]\nvelocity = [0.1, 0.0, 0.0, 5.0]\n"),
        &["`initial.velocity`", "exactly 3 elements"],
    );
    // A study's bounds.
    let d = scratch("study3");
    std::fs::write(
        d.join("base.toml"),
        format!("{TINY}{GAIT}").replace("elements = 4", "elements = 10"),
    )
    .unwrap();
    let study = d.join("study.toml");
    std::fs::write(
        &study,
        "[study]\nbase = \"base.toml\"\n[optimize]\nstress = [15000.0, 35000.0, 99.0]\n",
    )
    .unwrap();
    let o = slither(&["optimize", s(&study), "--out", s(&d.join("out")), "--quiet"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("`optimize.stress`") && err.contains("exactly 2"),
        "{err}"
    );
    assert!(err.contains(":4: "), "{err}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn gait_centres_and_width_must_act_on_the_body() {
    rejected_with(
        "centre-off",
        &format!("{TINY}{GAIT}centers = [0.2, 0.35, 1.5]\n"),
        &["`gait.centers`", "[0, 1]"],
    );
    rejected_with(
        "centre-neg",
        &format!("{TINY}{GAIT}centers = [-0.2, 0.35, 0.5]\n"),
        &["`gait.centers`"],
    );
    let narrow = format!("{TINY}{GAIT}").replace("sigma = 0.3", "sigma = 0.001");
    rejected_with(
        "sigma",
        &narrow,
        &["`gait.sigma`", "at least one element length", "0.25"],
    );
    // The bound is one element: 4 elements allow 0.25.
    let d = scratch("sigma-ok");
    let ok = format!("{TINY}{GAIT}").replace("sigma = 0.3", "sigma = 0.25");
    let (o, _) = run_text(&d, &ok, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn type_errors_name_the_allowed_range() {
    let e = rejected_with(
        "elements-neg",
        &TINY.replace("elements = 4", "elements = -5"),
        &["`rod.elements`", "an integer in [2, 100000]"],
    );
    assert!(e.contains("line 4"), "{e}");
    rejected_with(
        "length-str",
        &TINY.replace("length = 1.0", "length = \"1.0\""),
        &["`rod.length`", "a finite number > 0 (m)"],
    );
}

#[test]
fn non_utf8_input_names_the_file_and_line() {
    let d = scratch("utf8");
    let p = d.join("problem.toml");
    let mut bytes = b"[rod]\nlength = 1.0\n# caf".to_vec();
    bytes.extend_from_slice(&[0xe9, b'\n']);
    std::fs::write(&p, &bytes).unwrap();
    let o = slither(&["run", s(&p), "--out", s(&d.join("out")), "--quiet"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains(&format!("{}:3:", p.display())), "{err}");
    assert!(err.contains("UTF-8") && err.contains("byte 24"), "{err}");
    let csv = d.join("curve.csv");
    std::fs::write(&csv, &bytes).unwrap();
    let o = slither(&["topology", s(&csv)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains(":3: not valid UTF-8"), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_directory_as_input_says_so() {
    let d = scratch("dir");
    std::fs::create_dir_all(d.join("base.toml")).unwrap();
    let f = d.join("phase.toml");
    std::fs::write(
        &f,
        "[phase]\nbase = \"base.toml\"\nweight = [300.0]\ntorque = [10.0]\n",
    )
    .unwrap();
    let o = slither(&["phase", s(&f), "--out", s(&d.join("out")), "--quiet"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("is a directory") && !err.contains("not found"),
        "{err}"
    );
    let o = slither(&["run", s(&d.join("base.toml")), "--out", s(&d.join("out"))]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("is a directory"), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(&d);
}

// ---------------------------------------------------------------------------------------------
// 5, 6. One run per output directory; outputs written whole
// ---------------------------------------------------------------------------------------------

#[test]
fn a_live_lock_refuses_a_second_run_and_a_stale_one_is_taken_over() {
    let d = scratch("lock");
    let out = d.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let lock = out.join(".slither.lock");
    // This test process is alive: its lock holds the directory.
    std::fs::write(&lock, format!("{}\n", std::process::id())).unwrap();
    let (o, _) = run_text(&d, TINY, &[]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("another slither run") && err.contains(&std::process::id().to_string()),
        "{err}"
    );
    assert!(!out.join("summary.json").exists());
    // A lock of a process that has exited is stale.
    let mut child = Command::new("true").spawn().unwrap();
    let dead = child.id();
    child.wait().unwrap();
    std::fs::write(&lock, format!("{dead}\n")).unwrap();
    let (o, _) = run_text(&d, TINY, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.join("summary.json").exists());
    assert!(!lock.exists(), "the lock is released at the end");
    let _ = std::fs::remove_dir_all(&d);
}

/// A run stopped (SIGSTOP) while it holds its output directory; continued and reaped when
/// dropped, also when the test fails.
struct Stopped(Option<std::process::Child>);

impl Stopped {
    fn child(&mut self) -> &mut std::process::Child {
        self.0.as_mut().unwrap()
    }
    fn signal(&mut self, sig: &str) {
        let pid = self.child().id().to_string();
        let ok = Command::new("kill")
            .args([sig, &pid])
            .status()
            .is_ok_and(|s| s.success());
        assert!(ok, "kill {sig} {pid}");
    }
    /// Continue the run and wait for its end.
    fn finish(mut self) -> Output {
        self.signal("-CONT");
        self.0.take().unwrap().wait_with_output().unwrap()
    }
}

impl Drop for Stopped {
    fn drop(&mut self) {
        if let Some(c) = self.0.as_mut() {
            let _ = Command::new("kill")
                .args(["-CONT", &c.id().to_string()])
                .status();
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

#[test]
fn concurrent_runs_into_one_directory_do_not_mix() {
    // No race on start-up order: the first run is stopped while it provably holds the lock
    // (its process id in `.slither.lock`), the second is started and must be refused, then
    // the first continues and finishes.
    let d = scratch("concurrent");
    let p = d.join("p.toml");
    std::fs::write(
        &p,
        std::fs::read_to_string("problems/slide.toml")
            .unwrap()
            .replace("duration = 0.6", "duration = 0.3"),
    )
    .unwrap();
    let out = d.join("out");
    let lock = out.join(slither::output::lock::LOCK_FILE);
    let spawn = || {
        Command::new(BIN)
            .args(["run", s(&p), "--out", s(&out), "--quiet"])
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap()
    };
    let mut a = Stopped(Some(spawn()));
    let pid = a.child().id().to_string();
    // Wait on the lock file: it is written whole (hard-linked from a private name) before
    // the run simulates, and removed only when the run ends.
    loop {
        if std::fs::read_to_string(&lock).is_ok_and(|t| t.lines().next() == Some(pid.as_str())) {
            break;
        }
        if let Some(st) = a.child().try_wait().unwrap() {
            panic!(
                "the first run ended ({st}) without holding {}",
                lock.display()
            );
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    a.signal("-STOP");
    assert!(
        a.child().try_wait().unwrap().is_none()
            && std::fs::read_to_string(&lock).is_ok_and(|t| t.lines().next() == Some(pid.as_str())),
        "the first run finished before it could be stopped (its run takes ~0.5 s)"
    );
    let b = spawn().wait_with_output().unwrap();
    assert_eq!(b.status.code(), Some(2), "refused: {}", stderr(&b));
    assert!(stderr(&b).contains(&pid), "names the owner: {}", stderr(&b));
    let a = a.finish();
    assert_eq!(a.status.code(), Some(0), "{}", stderr(&a));
    assert!(!lock.exists(), "the lock is released at the end");
    // The directory holds one run: as many .vtp files as the .pvd lists.
    let pvd = std::fs::read_to_string(out.join("vtk/frames.pvd")).unwrap();
    let listed = pvd.matches("<DataSet").count();
    let files = std::fs::read_dir(out.join("vtk")).unwrap().count() - 1;
    assert_eq!(listed, files);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_run_into_a_used_directory_removes_the_previous_outputs() {
    let d = scratch("reuse");
    let (o, out) = run_text(&d, &format!("{TINY}\n[ground]\n"), &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.join("kymograph_slip.png").exists() && out.join("vtk/frames.pvd").exists());
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let (o, out) = run_text(&d, TINY, &["--no-plots"]);
    assert!(o.status.success(), "{}", stderr(&o));
    for gone in [
        "kymograph_elevation.png",
        "kymograph_slip.png",
        "kymograph_lambda.png",
        "snapshots.png",
        "topology.png",
        "vtk",
    ] {
        assert!(
            !out.join(gone).exists(),
            "{gone} of the previous run is left"
        );
    }
    assert!(out.join("summary.json").exists() && out.join("trajectory.npz").exists());
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "mine"
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn an_unwritable_output_directory_is_found_before_simulating() {
    // /proc exists but no file can be created in it, not even by root.
    let d = scratch("unwritable");
    let p = d.join("p.toml");
    std::fs::write(&p, TINY).unwrap();
    let o = slither(&["run", s(&p), "--out", "/proc", "--quiet"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("before simulating"), "{err}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_full_disk_gives_one_clear_error_and_no_truncated_file() {
    // A run writes into its staging folder (`out/.run.tmp`, recreated empty by every run), so
    // the trap is set where the writer puts the trajectory's temporary file: a link to
    // /dev/full, on which every write fails with ENOSPC. The command line prints this error as
    // its one line ("error: OUT: cannot write results: ...") and swaps nothing in.
    let d = scratch("full");
    std::fs::create_dir_all(&d).unwrap();
    let p = slither::problem::parse(TINY, Path::new("tiny.toml")).unwrap();
    let m = slither::model::Model::new(&p);
    let o = slither::sim::run_gait(&m, m.solver.integrator, &mut |_| {}, &mut |_| {}).unwrap();
    std::os::unix::fs::symlink("/dev/full", d.join(".trajectory.npz.tmp")).unwrap();
    let err = slither::output::write_trajectory(&d, &m, &o.frames, &[])
        .unwrap_err()
        .to_string();
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.contains("trajectory.npz") && err.contains("No space left"),
        "{err}"
    );
    assert!(!err.contains("ZipWriter"), "{err}");
    assert!(!d.join("trajectory.npz").exists());
    let _ = std::fs::remove_dir_all(&d);
}

// ---------------------------------------------------------------------------------------------
// 8, 9, 10. Slip in contact only, no NaN window, failed runs measure nothing
// ---------------------------------------------------------------------------------------------

#[test]
fn airborne_nodes_have_no_slip() {
    // Launched sideways 0.5 m above the ground: it does not land within the run.
    let d = scratch("airborne");
    let text = format!(
        "{}\n[ground]\n\n[initial]\nheight = 0.5\nvelocity = [0.5, 0.3, 0.0]\n",
        TINY.replace("duration = 0.01", "duration = 0.05")
    );
    let (o, out) = run_text(&d, &text, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["slip_speed_max"].as_f64(), Some(0.0), "{summary}");
    let mut npz = npyz::npz::NpzArchive::open(out.join("trajectory.npz")).unwrap();
    let slip: Vec<f64> = npz
        .by_name("slip_speed")
        .unwrap()
        .unwrap()
        .into_vec()
        .unwrap();
    assert!(!slip.is_empty());
    assert!(slip.iter().all(|v| v.is_nan()), "{slip:?}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn contact_slip_uses_one_threshold() {
    let m = common::model(
        "[rod]\nlength = 1.0\ndiameter = 0.02\nelements = 10\nbending_stiffness = 1.0\n[ground]\n[time]\ndt = 0.01\nduration = 0.1\n",
    );
    let w_node = m.total_mass() * 9.81 / 10.0;
    let th = m.contact_threshold();
    assert!((th / w_node - slither::model::CONTACT_FRACTION).abs() < 1e-12);
    // A tiny positive normal force (interior-point residue) is not contact.
    assert!(observe::contact_slip(&m, [1.0, 0.0, 0.0], 1e-3 * th).is_nan());
    assert_eq!(observe::contact_slip(&m, [3.0, 4.0, 9.0], 2.0 * th), 5.0);
}

#[test]
fn lambda_keeps_its_last_window_when_the_body_is_compressed() {
    let m = common::model(
        "[rod]\nlength = 1.0\ndiameter = 0.02\nelements = 50\nbending_stiffness = 1.0\n[time]\ndt = 0.01\nduration = 0.1\n",
    );
    let frame = |t: f64, squeeze: f64| Frame {
        t,
        x: (0..=50)
            .map(|i| [(1.0 - i as f64 / 50.0) * squeeze, 0.0, 0.01])
            .collect(),
        theta: vec![0.0; 50],
        v: vec![[0.0; 3]; 51],
        normal: vec![0.0; 51],
        d1: vec![[0.0, 1.0, 0.0]; 50],
    };
    let frames = vec![
        frame(0.0, 1.0),
        frame(0.1, 1.0 - 1e-4),
        frame(0.2, 1.0 + 1e-4),
    ];
    let fl = observe::fields(&m, &frames);
    assert_eq!(fl.s_window.len(), 46);
    for row in &fl.lambda {
        assert_eq!(row.len(), 46);
        assert!(row.iter().all(|l| l.is_finite()), "{row:?}");
    }
}

#[test]
fn a_failed_run_reports_no_observables() {
    let d = scratch("failed");
    let failing = "[rod]\nlength = 1.0\ndiameter = 0.02\nelements = 10\nbending_stiffness = 1e-3\nnatural_curvature = [0.0, 20.0]\n[gravity]\ng = 0.0\n[time]\ndt = 1e-2\nduration = 1.0\n[solver]\nmax_iterations = 1\nmax_halvings = 2\n";
    let (o, out) = run_text(&d, failing, &[]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "failed");
    for key in [
        "v_s",
        "v_s_over_v_m",
        "regime",
        "writhe_max",
        "lifted_arcs_max",
    ] {
        assert!(summary.get(key).is_some(), "{key} present");
        assert!(summary[key].is_null(), "{key} = {}", summary[key]);
    }
    // Statistics of what was computed stay.
    assert!(summary["steps"].as_u64().is_some());
    let _ = std::fs::remove_dir_all(&d);
}

// ---------------------------------------------------------------------------------------------
// 11. topology --closed
// ---------------------------------------------------------------------------------------------

/// A unit ring (or a planar figure eight) with `n` nodes; on the ring `d1` turns `turns`
/// times about the tangent (in the plane of `e_z` and the radial direction).
fn ring_csv(n: usize, repeat_first: bool, eight: bool, turns: f64) -> String {
    let mut text = String::from("x,y,z,d1x,d1y,d1z\n");
    let angle = |i: f64| 2.0 * std::f64::consts::PI * (i + 0.25) / n as f64;
    for i in 0..n + usize::from(repeat_first) {
        let t = angle((i % n) as f64);
        let r = if eight {
            [t.sin(), t.sin() * t.cos(), 0.0]
        } else {
            [t.cos(), t.sin(), 0.0]
        };
        // The director of the edge starting here, at the edge's middle angle.
        let m = angle((i % n) as f64 + 0.5);
        let phi = turns * m;
        let d = [phi.sin() * m.cos(), phi.sin() * m.sin(), phi.cos()];
        text += &format!("{},{},{},{},{},{}\n", r[0], r[1], r[2], d[0], d[1], d[2]);
    }
    text
}

fn topology_json(dir: &Path, csv: &str) -> serde_json::Value {
    let f = dir.join("curve.csv");
    std::fs::write(&f, csv).unwrap();
    let o = slither(&["topology", s(&f), "--closed"]);
    assert!(o.status.success(), "{}", stderr(&o));
    serde_json::from_slice(&o.stdout).unwrap()
}

#[test]
fn topology_closed_curves() {
    let d = scratch("topology");
    // A repeated closing node changes nothing.
    // (A ring whose director turns once: Lk = -1 by the convention of the angle above.)
    let plain = topology_json(&d, &ring_csv(60, false, false, -1.0));
    let repeated = topology_json(&d, &ring_csv(60, true, false, -1.0));
    assert!(
        (plain["lk_gauss"].as_f64().unwrap().abs() - 1.0).abs() < 1e-6,
        "{plain}"
    );
    for k in ["tw", "wr", "lk", "lk_gauss"] {
        let (a, b) = (plain[k].as_f64().unwrap(), repeated[k].as_f64().unwrap());
        assert!((a - b).abs() < 1e-9, "{k}: {a} vs {b}");
    }
    // A planar figure eight has writhe 0.
    let eight = topology_json(&d, &ring_csv(80, false, true, 0.0));
    assert!(eight["wr"].as_f64().unwrap().abs() < 1e-12, "{eight}");
    // A director along its edge is exit 2 naming its line.
    let bad = "x,y,z,d1x,d1y,d1z\n0,0,0,0,0,1\n1,0,0,0,0,1\n1,1,0,2,0,0\n0,1,0,0,0,1\n";
    let f = d.join("bad.csv");
    std::fs::write(&f, bad).unwrap();
    let o = slither(&["topology", s(&f), "--closed"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains(":4: ") && stderr(&o).contains("tangent"),
        "{}",
        stderr(&o)
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_duration_that_is_not_a_whole_number_of_steps_ends_exactly_on_it() {
    // dt 0.4 s over 0.59 s: one step of 0.4 s and a last one of 0.19 s (main ran one step and
    // reported t = 0.4 as completed).
    let d = scratch("last-step");
    let text = TINY
        .replace("dt = 0.005", "dt = 0.4")
        .replace("duration = 0.01", "duration = 0.59")
        .replace("[time]", "[output]\ninterval = 0.4\n\n[time]");
    let (o, out) = run_text(&d, &text, &["--no-plots"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let t = summary["t_final"].as_f64().unwrap();
    assert!((t - 0.59).abs() < 1e-12, "t_final {t}");
    assert_eq!(summary["steps"].as_u64(), Some(2), "{summary}");
}
