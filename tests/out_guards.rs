//! An output directory keeps what it holds: a study never writes into a directory of another
//! subcommand, `merge` never into one of its inputs, a phase directory keeps one grid, a
//! shard's hand-edited regime is refused, and a phase grid above the size limits needs
//! `--force`.
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_slither");

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("slither-guards-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn slither(args: &[&Path]) -> (Output, String) {
    let o = Command::new(BIN).args(args).output().unwrap();
    let e = String::from_utf8_lossy(&o.stderr).into_owned();
    (o, e)
}

mod common;

/// The phase tests' tiny S-start base (20 elements), cut to two steps.
fn base() -> String {
    common::TINY_S_START.replace("duration = 0.1", "duration = 0.02")
}

/// Write the base and a phase file with the given grid lines into `dir`.
fn phase_file(dir: &Path, grid: &str) -> PathBuf {
    std::fs::write(dir.join("base.toml"), base()).unwrap();
    let f = dir.join("phase.toml");
    std::fs::write(&f, format!("[phase]\nbase = \"base.toml\"\n{grid}")).unwrap();
    f
}

fn p(s: &str) -> &Path {
    Path::new(s)
}

#[test]
fn a_study_refuses_a_directory_of_another_subcommand() {
    let dir = scratch("writer");
    let f = phase_file(&dir, "weight = [300.0]\ntorque = [15.0]\n");
    let out = dir.join("out");
    let (o, e) = slither(&[p("phase"), p("--quiet"), &f, p("--out"), &out]);
    assert!(o.status.success(), "{e}");
    assert!(out.join("phase.csv").exists());
    // optimize into the phase directory: refused before anything is written.
    std::fs::write(
        dir.join("study.toml"),
        "[study]\nbase = \"base.toml\"\nmax_evaluations = 2\n\n[optimize]\nstress = [2e4, 3e4]\n",
    )
    .unwrap();
    let before = std::fs::read(out.join("phase.csv")).unwrap();
    let study = dir.join("study.toml");
    let (o, e) = slither(&[p("optimize"), p("--quiet"), &study, p("--out"), &out]);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("slither phase") && e.contains("phase.csv"),
        "{e}"
    );
    assert!(!out.join("history.csv").exists());
    assert_eq!(std::fs::read(out.join("phase.csv")).unwrap(), before);
    // run into it: refused too.
    let base = dir.join("base.toml");
    let (o, e) = slither(&[p("run"), p("--quiet"), &base, p("--out"), &out]);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(!out.join("summary.json").exists());
    // and a phase study into a run's directory.
    let run_out = dir.join("run");
    let (o, e) = slither(&[
        p("run"),
        p("--quiet"),
        p("--no-plots"),
        &base,
        p("--out"),
        &run_out,
    ]);
    assert!(o.status.success(), "{e}");
    let (o, e) = slither(&[p("phase"), p("--quiet"), &f, p("--out"), &run_out]);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("slither run") && e.contains("summary.json"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_phase_directory_keeps_one_grid() {
    let dir = scratch("grid");
    let f = phase_file(&dir, "weight = [300.0]\ntorque = [15.0]\n");
    let out = dir.join("out");
    let (o, e) = slither(&[p("phase"), p("--quiet"), &f, p("--out"), &out]);
    assert!(o.status.success(), "{e}");
    let before = std::fs::read(out.join("phase.csv")).unwrap();
    // The same study again reuses its cells.
    let (o, e) = slither(&[p("phase"), p("--quiet"), &f, p("--out"), &out]);
    assert!(o.status.success(), "{e}");
    // A grid that does not contain the old one is refused; phase.csv is untouched. (A grid
    // that extends it reuses its cells: tests/phase.rs.)
    let g = phase_file(&dir, "weight = [1000.0]\ntorque = [15.0]\n");
    let (o, e) = slither(&[p("phase"), p("--quiet"), &g, p("--out"), &out]);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("another grid"), "{e}");
    assert_eq!(std::fs::read(out.join("phase.csv")).unwrap(), before);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn merge_refuses_its_input_as_output_and_an_edited_regime() {
    let dir = scratch("merge");
    let f = phase_file(&dir, "weight = [300.0, 1000.0]\ntorque = [15.0]\n");
    let (a, b) = (dir.join("a"), dir.join("b"));
    for (s, d) in [("1/2", &a), ("2/2", &b)] {
        let (o, e) = slither(&[
            p("phase"),
            p("--quiet"),
            &f,
            p("--shard"),
            p(s),
            p("--out"),
            d,
        ]);
        assert!(o.status.success(), "{e}");
    }
    // Into one of its inputs: refused, the shard untouched.
    let before = std::fs::read(a.join("phase.csv")).unwrap();
    let (o, e) = slither(&[p("merge"), &a, &b, p("--out"), &a]);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("input directory"), "{e}");
    assert_eq!(std::fs::read(a.join("phase.csv")).unwrap(), before);
    // A regime label changed by hand in a shard: refused, naming the cell.
    let text = String::from_utf8(before.clone()).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let mut fields: Vec<String> = lines[1].split(',').map(String::from).collect();
    assert_eq!(fields[3], "ok", "{text}");
    let stated = fields[4].clone();
    fields[4] = if stated == "S" {
        "U".into()
    } else {
        "S".into()
    };
    lines[1] = fields.join(",");
    std::fs::write(a.join("phase.csv"), lines.join("\n") + "\n").unwrap();
    let merged = dir.join("merged");
    let (o, e) = slither(&[p("merge"), &a, &b, p("--out"), &merged]);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("W = 300") && e.contains("regime"), "{e}");
    // The true label merges.
    std::fs::write(a.join("phase.csv"), &before).unwrap();
    let (o, e) = slither(&[p("merge"), &a, &b, p("--out"), &merged]);
    assert!(o.status.success(), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_huge_phase_grid_needs_force() {
    let dir = scratch("huge");
    let f = phase_file(
        &dir,
        "weight = { from = 10.0, to = 1000.0, count = 10000 }\ntorque = { from = 1.0, to = 100.0, count = 10000 }\n",
    );
    let out = dir.join("out");
    let (o, e) = slither(&[p("phase"), p("--quiet"), &f, p("--out"), &out]);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("phase.weight") && e.contains("100000000 cells") && e.contains("--force"),
        "{e}"
    );
    assert!(
        !out.exists(),
        "refused before the output directory is created"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
