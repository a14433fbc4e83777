//! The Python package (`python/`, import `slither_gait`): builds its wheel with maturin into a
//! virtual environment under `target/python/` and runs its pytest suite
//! (`python/tests/`) against this build's CLI binary, so `cargo test --release` covers it.
//!
//! Everything is kept under `target/python/` and reused by the next run: `venv/` (the virtual
//! environment with maturin, pytest and numpy, installed once), `cargo/` (the extension's own
//! Cargo target directory: the first build compiles slither and its dependencies once more,
//! later ones only what changed) and `wheels/`.
//!
//! Where `python3` (3.9 or newer) or its `venv` module is missing, or pip cannot install the
//! tools, the test prints one line saying why and passes; with `SLITHER_REQUIRE_PYTHON=1` (set
//! by CI) that skip is a failure. A failed wheel build or a failed pytest always fails.
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::Instant;

const BIN: &str = env!("CARGO_BIN_EXE_slither");
const ROOT: &str = env!("CARGO_MANIFEST_DIR");

fn text(o: &Output) -> String {
    format!(
        "{}\nstdout:\n{}\nstderr:\n{}",
        o.status,
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// One line on the terminal (not captured by the test harness).
fn say(line: &str) {
    let _ = writeln!(std::io::stderr(), "python: {line}");
}

/// Skip with one line, or fail when `SLITHER_REQUIRE_PYTHON=1`.
fn skip(why: &str) {
    if std::env::var("SLITHER_REQUIRE_PYTHON").is_ok_and(|v| v == "1") {
        panic!("SLITHER_REQUIRE_PYTHON=1 and {why}");
    }
    say(&format!("skipped: {why}"));
}

fn run(cmd: &mut Command) -> Result<Output, String> {
    let shown = format!("{cmd:?}");
    match cmd.output() {
        Ok(o) if o.status.success() => Ok(o),
        Ok(o) => Err(format!("{shown}: {}", text(&o))),
        Err(e) => Err(format!("{shown}: {e}")),
    }
}

/// The virtual environment's interpreter, created (and given maturin, pytest and numpy) when
/// absent or incomplete; `Err` says why it cannot be.
fn venv(dir: &Path) -> Result<PathBuf, String> {
    let python = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
    let check = "import sys; assert sys.version_info >= (3, 9), sys.version";
    run(Command::new(&python).args(["-c", check]))
        .map_err(|e| format!("no python3 >= 3.9 ({})", e.lines().next().unwrap_or("")))?;
    let venv = dir.join("venv");
    let py = venv.join("bin").join("python");
    let ready = || {
        venv.join("bin").join("maturin").is_file()
            && run(Command::new(&py).args(["-c", "import pytest, numpy"])).is_ok()
    };
    if ready() {
        return Ok(py);
    }
    if !py.is_file() {
        let _ = std::fs::remove_dir_all(&venv);
        run(Command::new(&python).args(["-m", "venv"]).arg(&venv)).map_err(|e| {
            format!(
                "python3 -m venv failed ({})",
                e.lines().last().unwrap_or("")
            )
        })?;
    }
    let t = Instant::now();
    run(Command::new(&py).args([
        "-m",
        "pip",
        "install",
        "--quiet",
        "--disable-pip-version-check",
        "maturin>=1.5,<2",
        "pytest",
        "numpy",
    ]))
    .map_err(|e| {
        format!(
            "pip cannot install maturin, pytest and numpy ({})",
            e.lines().last().unwrap_or("")
        )
    })?;
    say(&format!(
        "virtual environment {} ready in {:.1} s",
        venv.display(),
        t.elapsed().as_secs_f64()
    ));
    Ok(py)
}

#[test]
fn python_package() {
    let root = Path::new(ROOT);
    let dir = root.join("target").join("python");
    std::fs::create_dir_all(&dir).unwrap();
    let py = match venv(&dir) {
        Ok(p) => p,
        Err(why) => return skip(&why),
    };
    let bin = py.parent().unwrap();
    // Build the wheel (release) and install it into the environment.
    let wheels = dir.join("wheels");
    let _ = std::fs::remove_dir_all(&wheels);
    let t = Instant::now();
    run(Command::new(bin.join("maturin"))
        .args(["build", "--release", "--quiet", "--manifest-path"])
        .arg(root.join("python").join("Cargo.toml"))
        .arg("--out")
        .arg(&wheels)
        .arg("--interpreter")
        .arg(&py)
        .env("CARGO_TARGET_DIR", dir.join("cargo")))
    .unwrap_or_else(|e| panic!("maturin build failed: {e}"));
    let build_s = t.elapsed().as_secs_f64();
    let wheel = std::fs::read_dir(&wheels)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|x| x == "whl"))
        .expect("maturin wrote no wheel");
    assert!(
        wheel.to_string_lossy().contains("abi3"),
        "not an abi3 wheel: {}",
        wheel.display()
    );
    run(Command::new(&py)
        .args([
            "-m",
            "pip",
            "install",
            "--quiet",
            "--disable-pip-version-check",
            "--no-deps",
            "--force-reinstall",
        ])
        .arg(&wheel))
    .unwrap_or_else(|e| panic!("pip install of the wheel failed: {e}"));
    // The suite, against this build's CLI.
    let t = Instant::now();
    let out = Command::new(&py)
        .args(["-m", "pytest", "-q", "-p", "no:cacheprovider", "-s"])
        .arg(root.join("python").join("tests"))
        .current_dir(root)
        .env("SLITHER_BIN", BIN)
        .env("SLITHER_ROOT", root)
        .env_remove("SLITHER_CONTACT")
        .env_remove("SLITHER_CLARABEL_METHOD")
        .output()
        .expect("run pytest");
    let pytest_s = t.elapsed().as_secs_f64();
    assert!(out.status.success(), "pytest failed: {}", text(&out));
    let stdout = String::from_utf8_lossy(&out.stdout);
    for line in stdout.lines().filter(|l| {
        l.contains("KeyboardInterrupt ") || l.contains("thread 0 ") || l.contains(" passed")
    }) {
        say(line.trim_start_matches(['.', 's']));
    }
    say(&format!(
        "wheel {} built in {build_s:.1} s; pytest {pytest_s:.1} s",
        wheel.file_name().unwrap().to_string_lossy()
    ));
}
