//! The user guide's references cannot drift from the code.
//!
//! - `docs/book/src/keys.md` is exactly what `slither keys --markdown` prints (the problem-file
//!   keys with unit, default and range, from `slither::problem::keys`);
//! - `docs/book/src/outputs.md` is exactly what `slither keys --outputs-markdown` prints (the
//!   keys of `summary.json` and the columns of `phase.csv` and `history.csv`, from
//!   `slither::output::schema`);
//! - every key a real run writes into `summary.json` is in the schema, and every key the schema
//!   lists without a condition is written;
//! - the studies' CSV headers are the schema's column lists.
//!
//! `SLITHER_UPDATE_DOCS=1 cargo test --release --test docs` rewrites the two generated pages.

use slither::output::schema;
use std::path::{Path, PathBuf};
use std::process::Command;

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// The first line where `a` and `b` differ, for the message.
fn first_difference(a: &str, b: &str) -> String {
    for (n, (x, y)) in a.lines().zip(b.lines()).enumerate() {
        if x != y {
            return format!("line {}:\n  guide: {x}\n  code:  {y}", n + 1);
        }
    }
    format!(
        "the guide has {} lines, the code's text {}",
        a.lines().count(),
        b.lines().count()
    )
}

/// `file` must equal `generated`; with `SLITHER_UPDATE_DOCS=1` in the environment the test
/// writes it instead (the other way to regenerate it).
fn assert_generated(file: &str, generated: &str, command: &str) {
    let path = repo(file);
    if std::env::var_os("SLITHER_UPDATE_DOCS").is_some() {
        std::fs::write(&path, generated).expect(file);
        return;
    }
    let text = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        text == generated,
        "{file} differs from the code's reference; regenerate it with\n    {command} > {file}\n\
         or  SLITHER_UPDATE_DOCS=1 cargo test --release --test docs\n(first difference at {})",
        first_difference(&text, generated)
    );
}

#[test]
fn key_reference_is_the_codes() {
    assert_generated(
        "docs/book/src/keys.md",
        &slither::problem::reference::markdown(),
        "cargo run --release -- keys --markdown",
    );
}

#[test]
fn output_reference_is_the_codes() {
    assert_generated(
        "docs/book/src/outputs.md",
        &schema::markdown(),
        "cargo run --release -- keys --outputs-markdown",
    );
}

#[test]
fn study_csv_headers_are_the_schemas() {
    assert_eq!(
        slither::studies::phase::HEADER,
        schema::header(schema::PHASE_CSV),
        "phase.csv's header and src/output/schema.rs PHASE_CSV differ: add the column there"
    );
    assert_eq!(
        slither::studies::phase::VERIFY_COLUMNS,
        schema::header(schema::PHASE_VERIFY_CSV),
        "the verification columns and src/output/schema.rs PHASE_VERIFY_CSV differ"
    );
    assert_eq!(
        slither::studies::optimize::PERIODIC_COLUMNS,
        schema::header(schema::PHASE_PERIODIC_CSV),
        "the periodic columns and src/output/schema.rs PHASE_PERIODIC_CSV differ"
    );
    assert_eq!(
        slither::studies::optimize::HISTORY_HEADER,
        schema::header(schema::HISTORY_CSV),
        "history.csv's header and src/output/schema.rs HISTORY_CSV differ: add the column there"
    );
}

/// Run the bundled slide (0.2 s of a sliding rod on the ground: every key but the accuracy
/// report's) and compare its `summary.json` with the schema both ways.
#[test]
fn every_summary_key_a_run_writes_is_in_the_schema() {
    let out = std::env::temp_dir().join(format!("slither_docs_summary_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let status = Command::new(env!("CARGO_BIN_EXE_slither"))
        .args(["run", "--quiet", "--no-plots", "--out"])
        .arg(&out)
        .arg(repo("problems/slide.toml"))
        .status()
        .expect("run slither");
    assert!(
        status.success(),
        "slither run problems/slide.toml: {status}"
    );
    let text = std::fs::read_to_string(out.join("summary.json")).expect("summary.json");
    let _ = std::fs::remove_dir_all(&out);
    let v: serde_json::Value = serde_json::from_str(&text).expect("summary.json is JSON");
    let written = schema::json_paths(&v);
    let missing: Vec<&String> = written
        .iter()
        .filter(|p| !schema::documented(schema::SUMMARY, p))
        .collect();
    assert!(
        missing.is_empty(),
        "summary.json keys without a line in src/output/schema.rs SUMMARY: {missing:?}\n\
         (add each with its unit and meaning, then regenerate the guide's output reference)"
    );
    let stale: Vec<&str> = schema::SUMMARY
        .iter()
        .filter(|f| f.when.is_empty())
        .map(|f| f.name)
        .filter(|name| {
            !written
                .iter()
                .any(|p| p == name || name.starts_with(&format!("{p}[]")))
        })
        .collect();
    assert!(
        stale.is_empty(),
        "keys listed in src/output/schema.rs SUMMARY that the run did not write: {stale:?}"
    );
    assert!(written.len() >= 60, "{} keys written", written.len());
}

/// The problem files shown in the README and in the guide's problem-file chapter are valid:
/// every TOML block with a `[rod]` table parses and validates.
#[test]
fn problem_files_shown_in_the_docs_parse() {
    let mut checked = 0;
    for file in ["README.md", "docs/book/src/problem-files.md"] {
        let text = std::fs::read_to_string(repo(file)).expect(file);
        let mut blocks = text.split("```toml\n").skip(1);
        for block in blocks.by_ref() {
            let toml = block.split("\n```").next().unwrap_or("");
            if !toml.contains("[rod]") {
                continue;
            }
            slither::problem::parse(toml, Path::new(file))
                .unwrap_or_else(|e| panic!("the problem file shown in {file} is invalid: {e}"));
            checked += 1;
        }
    }
    assert!(checked >= 2, "{checked} problem files found in the docs");
}

/// `slither keys --markdown` and `--outputs-markdown` print exactly the generated references.
#[test]
fn keys_command_prints_the_references() {
    for (flag, text) in [
        ("--markdown", slither::problem::reference::markdown()),
        ("--outputs-markdown", schema::markdown()),
    ] {
        let o = Command::new(env!("CARGO_BIN_EXE_slither"))
            .args(["keys", flag])
            .output()
            .expect("run slither keys");
        assert!(o.status.success(), "slither keys {flag}: {}", o.status);
        assert_eq!(
            String::from_utf8(o.stdout).unwrap(),
            text,
            "slither keys {flag}"
        );
    }
}
