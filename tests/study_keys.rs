//! The study-file and phase-file keys of the key table (`slither::problem::study_keys`) are
//! the parsers' own: writing a key's table default explicitly parses to the same study or
//! phase study as leaving it out, and the defaults kept elsewhere agree with the table.
use slither::problem::keys::{DefaultValue, Key};
use slither::problem::study_keys::{self, STUDY_KEYS};
use slither::studies::{ensemble, optimize, phase};
use std::path::Path;

/// A key's default as a TOML value, where it has a plain one.
fn toml_default(k: &Key) -> Option<String> {
    match k.default {
        DefaultValue::Real(v) => Some(format!("{v:?}")),
        DefaultValue::Int(v) => Some(v.to_string()),
        DefaultValue::Flag(v) => Some(v.to_string()),
        DefaultValue::Word(w) => Some(format!("\"{w}\"")),
        _ => None,
    }
}

/// `text` with `name = value` added under `[table]` (a header the text has).
fn with_key(text: &str, table: &str, name: &str, value: &str) -> String {
    let header = format!("[{table}]\n");
    text.replacen(&header, &format!("{header}{name} = {value}\n"), 1)
}

fn base() -> String {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/s_start.toml");
    format!("{:?}", p.display().to_string())
}

#[test]
fn study_key_defaults_are_the_study_parsers() {
    let file = Path::new("study.toml");
    let text = format!(
        "[study]\nbase = {}\nduration_pulses = 0.5\n\n[optimize]\nstress = [15000.0, 35000.0]\n",
        base()
    );
    let parse = |t: &str| format!("{:?}", optimize::parse_study(t, file).unwrap());
    let absent = parse(&text);
    let mut checked = 0;
    for k in STUDY_KEYS.iter().filter(|k| !k.key.starts_with("phase.")) {
        let Some(v) = toml_default(k) else { continue };
        let (table, name) = k.key.split_once('.').unwrap();
        // The broadside penalties are refused with the default objective, and the swarm's
        // particles with the default method; their defaults are checked below.
        if name.ends_with("_penalty") || name == "particles" {
            continue;
        }
        assert_eq!(
            parse(&with_key(&text, table, name, &v)),
            absent,
            "{} = {v}",
            k.key
        );
        checked += 1;
    }
    assert!(checked >= 6, "{checked} keys checked");
    assert_eq!(
        optimize::DEFAULT_TURN_PENALTY,
        study_keys::STUDY_TURN_PENALTY.real()
    );
    assert_eq!(
        optimize::DEFAULT_PARTICLES as u64,
        study_keys::OPTIMIZE_PARTICLES.int()
    );
}

#[test]
fn phase_key_defaults_are_the_phase_parsers() {
    let dir = std::env::temp_dir().join(format!("slither-study-keys-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("phase.toml");
    let text = format!(
        "[phase]\nbase = {}\nweight = [100.0, 1000.0]\ntorque = [5.0]\n",
        base()
    );
    let parse = |t: &str| {
        std::fs::write(&file, t).unwrap();
        format!("{:?}", phase::load(&file).unwrap())
    };
    let absent = parse(&text);
    let mut checked = 0;
    for k in STUDY_KEYS.iter().filter(|k| k.key.starts_with("phase.")) {
        let Some(v) = toml_default(k) else { continue };
        let name = &k.key["phase.".len()..];
        let explicit = match name.split_once('.') {
            // A verification that asks for no extra run is none; checked with one perturbed
            // run against the same table without the key.
            Some(("verify", sub)) => {
                let one = |extra: &str| {
                    with_key(
                        &text,
                        "phase",
                        "verify",
                        &format!("{{ perturbations = 1{extra} }}"),
                    )
                };
                if sub == "perturbations" {
                    continue;
                }
                assert_eq!(
                    parse(&one(&format!(", {sub} = {v}"))),
                    parse(&one("")),
                    "{}",
                    k.key
                );
                checked += 1;
                continue;
            }
            _ => parse(&with_key(&text, "phase", name, &v)),
        };
        assert_eq!(explicit, absent, "{} = {v}", k.key);
        checked += 1;
    }
    assert!(checked >= 6, "{checked} keys checked");
    assert_eq!(study_keys::PHASE_VERIFY_STEP.real(), ensemble::STEP);
    assert_eq!(study_keys::PHASE_VERIFY_SEED.int(), ensemble::SEED);
    std::fs::remove_dir_all(&dir).ok();
}
