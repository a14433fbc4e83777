//! Command-line overrides of file keys: `--set KEY=VALUE` on `run`, `optimize` and `phase`.
//!
//! A setting edits the file's text as a TOML document (`toml_edit`, which keeps every other
//! line as written) before the file is parsed, so it is validated exactly like a key written
//! in the file. An error about a key that a setting changed names the setting instead of a
//! line of the file.
//!
//! Keys are dotted (`rod.length`), array elements are indexed (`gait.centers[1]`). A value is
//! a TOML value (`0.3`, `true`, `"coil"`, `[0.2, 0.5, 0.8]`); a bare word that is not one is
//! taken as a string (`gait.kind=s-start`). An integer given for a key whose current value is
//! a float becomes that float (`rod.elements=100` stays an integer).

use super::ProblemError;
use std::path::Path;
use toml_edit::{DocumentMut, Item, Value};

/// One `--set KEY=VALUE`.
#[derive(Clone, Debug)]
pub struct Setting {
    /// The argument as given, `KEY=VALUE` (for messages).
    pub arg: String,
    /// The dotted key without indices (`gait.centers`), as validation names it.
    pub key: String,
    steps: Vec<Step>,
    value: Value,
}

#[derive(Clone, Debug, PartialEq)]
enum Step {
    Key(String),
    Index(usize),
}

impl Setting {
    /// The first table of the key (`rod` for `rod.length`).
    pub fn table(&self) -> &str {
        match &self.steps[0] {
            Step::Key(k) => k,
            Step::Index(_) => "",
        }
    }
}

impl std::str::FromStr for Setting {
    type Err = String;
    /// Parse `KEY=VALUE`; `Err` says what is wrong with the argument.
    fn from_str(arg: &str) -> Result<Self, String> {
        let form =
            "must be KEY=VALUE with a dotted key, e.g. rod.length=1.5 or gait.centers[1]=0.3";
        let (key, value) = arg
            .split_once('=')
            .ok_or_else(|| format!("--set {arg:?}: no '='; {form}"))?;
        let (key, value) = (key.trim(), value.trim());
        let mut steps = Vec::new();
        for part in key.split('.') {
            let (name, mut rest) = part.split_once('[').map_or((part, ""), |(n, r)| (n, r));
            let name = name.trim();
            if name.is_empty()
                || !name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
            {
                return Err(format!(
                    "--set {arg:?}: key part {part:?} is not a key name; {form}"
                ));
            }
            steps.push(Step::Key(name.to_string()));
            while !rest.is_empty() {
                let (index, after) = rest
                    .split_once(']')
                    .ok_or_else(|| format!("--set {arg:?}: unclosed '['; {form}"))?;
                let i = index.trim().parse::<usize>().map_err(|_| {
                    format!("--set {arg:?}: index {index:?} is not a non-negative integer; {form}")
                })?;
                steps.push(Step::Index(i));
                rest = after.strip_prefix('[').unwrap_or(after);
                if !after.is_empty() && !after.starts_with('[') {
                    return Err(format!("--set {arg:?}: text after ']' in {part:?}; {form}"));
                }
            }
        }
        if value.is_empty() {
            return Err(format!("--set {arg:?}: no value after '='; {form}"));
        }
        let value = match value.parse::<Value>() {
            Ok(v) => v,
            Err(_) if !value.contains(['"', '\'', '[', ']', '{', '}', '=']) => Value::from(value),
            Err(e) => {
                let why = e.to_string();
                let why = why.lines().last().unwrap_or("").trim();
                return Err(format!(
                    "--set {arg:?}: {value:?} is not a TOML value ({why})"
                ));
            }
        };
        Ok(Setting {
            arg: arg.to_string(),
            key: dotted(&steps),
            steps,
            value,
        })
    }
}

/// Settings split between a study or phase file and its base problem: those whose first table
/// is one of the file's `own` tables (`[phase]`, `[study]`, its `[accuracy]`) edit that file,
/// the rest (`rod`, `gait`, `ground`, ...) edit the base problem.
pub fn split<'a>(settings: &[&'a Setting], own: &[&str]) -> (Vec<&'a Setting>, Vec<&'a Setting>) {
    settings.iter().partition(|s| own.contains(&s.table()))
}

/// `text` with `settings` applied in order, or the argument that cannot be applied
/// (`--set KEY=VALUE`) and why (an index beyond its array, a key inside a value that is not a
/// table; the text is not TOML).
pub fn apply(text: &str, settings: &[&Setting]) -> Result<String, (String, String)> {
    if settings.is_empty() {
        return Ok(text.to_string());
    }
    let mut doc: DocumentMut = text.parse().map_err(|e: toml_edit::TomlError| {
        (
            "--set".to_string(),
            format!("the file is not a TOML document: {e}"),
        )
    })?;
    for s in settings {
        set_one(doc.as_item_mut(), &s.steps, &s.value)
            .map_err(|why| (format!("--set {}", s.arg), why))?;
    }
    Ok(doc.to_string())
}

fn set_one(mut item: &mut Item, steps: &[Step], value: &Value) -> Result<(), String> {
    let mut path = String::new();
    for (n, step) in steps.iter().enumerate() {
        let last = n + 1 == steps.len();
        match step {
            Step::Key(k) => {
                if !path.is_empty() {
                    path.push('.');
                }
                path.push_str(k);
                let table = item.as_table_like_mut().ok_or_else(|| {
                    format!(
                        "`{}` is a value, not a table",
                        path.rsplit_once('.').map_or("", |p| p.0)
                    )
                })?;
                if last {
                    let old = table.get(k).and_then(Item::as_value);
                    let new = coerce(old, value, &dotted(steps));
                    match table.get_mut(k) {
                        Some(slot) => *slot = Item::Value(new),
                        None => {
                            table.insert(k, Item::Value(new));
                        }
                    }
                    return Ok(());
                }
                if table.get(k).is_none() {
                    if matches!(steps[n + 1], Step::Index(_)) {
                        return Err(format!(
                            "`{path}` is not in the file: set the whole array (e.g. {path}=[...])"
                        ));
                    }
                    let mut t = toml_edit::Table::new();
                    t.set_implicit(true);
                    table.insert(k, Item::Table(t));
                }
                item = table.get_mut(k).expect("inserted above");
            }
            Step::Index(i) => {
                path.push_str(&format!("[{i}]"));
                let arr = item
                    .as_array_mut()
                    .ok_or_else(|| format!("`{path}`: the key is not an array in the file"))?;
                let len = arr.len();
                let Some(slot) = arr.get_mut(*i) else {
                    return Err(format!(
                        "`{path}`: index {i} is beyond the array's {len} elements (indices from 0)"
                    ));
                };
                if last {
                    *slot = coerce(Some(slot), value, &dotted(steps));
                    return Ok(());
                }
                return Err(format!(
                    "`{path}`: only the last part of a key may be an index"
                ));
            }
        }
    }
    Ok(())
}

/// The dotted key of `steps` without indices.
fn dotted(steps: &[Step]) -> String {
    steps
        .iter()
        .filter_map(|s| match s {
            Step::Key(k) => Some(k.as_str()),
            Step::Index(_) => None,
        })
        .collect::<Vec<_>>()
        .join(".")
}

/// `new`, as a float when it is an integer and the key holds numbers that are not integers
/// (its current value is a float, or the key table says so): `rod.length=2` means 2.0.
fn coerce(old: Option<&Value>, new: &Value, key: &str) -> Value {
    use super::keys::{self, DefaultValue, Range};
    let real_key = keys::find(key).is_some_and(|k| {
        !matches!(k.range, Range::Int { .. }) && !matches!(k.default, DefaultValue::Int(_))
    });
    let mut v = match (old, new) {
        (Some(Value::Float(_)), Value::Integer(i)) => Value::from(*i.value() as f64),
        (_, Value::Integer(i)) if real_key => Value::from(*i.value() as f64),
        _ => new.clone(),
    };
    match old {
        // The old value's spacing and trailing comment stay.
        Some(o) => *v.decor_mut() = o.decor().clone(),
        None => v.decor_mut().set_prefix(" "),
    }
    v
}

/// An error of a file edited by `settings`: one about a key a setting changed names the
/// setting (`--set rod.length=-1`) instead of a line of the edited text.
pub fn attribute(e: ProblemError, settings: &[&Setting], path: &Path) -> ProblemError {
    let named = |key: &str| {
        settings
            .iter()
            .rev()
            .find(|s| s.key == key || key.starts_with(&format!("{}.", s.key)))
    };
    match e {
        ProblemError::Invalid {
            key,
            value,
            allowed,
            ..
        } if named(&key).is_some() => ProblemError::Set {
            file: path.into(),
            arg: format!("--set {}", named(&key).unwrap().arg),
            message: format!("`{key}` = {value} is not allowed: must be {allowed}"),
        },
        ProblemError::Parse { message, .. }
            if message
                .strip_prefix('`')
                .and_then(|m| m.split_once('`'))
                .is_some_and(|(k, _)| named(k).is_some()) =>
        {
            let (key, rest) = message[1..].split_once('`').unwrap();
            let key = key.to_string();
            // toml's message quotes the edited text (its lines are not the file's): keep what
            // is wrong and the allowed range.
            let what: Vec<&str> = rest
                .trim_start_matches(':')
                .lines()
                .map(str::trim)
                .filter(|l| {
                    let quoted = l
                        .split_once('|')
                        .is_some_and(|(n, _)| n.trim().chars().all(|c| c.is_ascii_digit()));
                    !l.is_empty() && !quoted && !l.starts_with("TOML parse error")
                })
                .collect();
            ProblemError::Set {
                file: path.into(),
                arg: format!("--set {}", named(&key).unwrap().arg),
                message: what.join("; "),
            }
        }
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(args: &[&str], text: &str) -> Result<String, String> {
        let s: Vec<Setting> = args.iter().map(|a| a.parse().unwrap()).collect();
        apply(text, &s.iter().collect::<Vec<_>>()).map_err(|(arg, why)| format!("{arg}: {why}"))
    }

    #[test]
    fn keys_indices_and_values_are_parsed() {
        let s: Setting = "gait.centers[1]=0.3".parse().unwrap();
        assert_eq!(s.key, "gait.centers");
        assert_eq!(
            s.steps,
            vec![
                Step::Key("gait".into()),
                Step::Key("centers".into()),
                Step::Index(1)
            ]
        );
        let w: Setting = "gait.kind=s-start".parse().unwrap();
        assert_eq!(w.value.as_str(), Some("s-start"));
        let b: Setting = "self_contact.enabled=false".parse().unwrap();
        assert_eq!(b.value.as_bool(), Some(false));
        for bad in [
            "rod.length",
            "=1",
            "rod..length=1",
            "a[x]=1",
            "a[1=2",
            "rod.length=",
            "a=[1,",
        ] {
            assert!(bad.parse::<Setting>().is_err(), "{bad} was accepted");
        }
    }

    #[test]
    fn a_setting_edits_only_its_key() {
        let text = "# comment\n[rod]\nlength = 1.0 # m\nelements = 50\n\n[gait]\ncenters = [0.1, 0.2, 0.3]\n";
        let out = set(
            &["rod.length=2", "gait.centers[2]=0.9", "rod.elements=80"],
            text,
        )
        .unwrap();
        assert!(out.contains("length = 2.0 # m"), "{out}");
        assert!(out.contains("elements = 80\n"), "{out}");
        assert!(out.contains("centers = [0.1, 0.2, 0.9]"), "{out}");
        assert!(out.starts_with("# comment\n[rod]\n"), "{out}");
        // A new table and a new key.
        let out = set(&["accuracy.target=0.01", "rod.density=900"], text).unwrap();
        let back: toml::Table = toml::from_str(&out).unwrap();
        assert_eq!(back["accuracy"]["target"].as_float(), Some(0.01));
        assert_eq!(back["rod"]["density"].as_float(), Some(900.0));
        // An index beyond the array, and a key below a value.
        let e = set(&["gait.centers[3]=1"], text).unwrap_err();
        assert!(e.contains("beyond the array's 3 elements"), "{e}");
        let e = set(&["rod.length.x=1"], text).unwrap_err();
        assert!(e.contains("`rod.length` is a value"), "{e}");
        let e = set(&["ground.mu[0]=1"], text).unwrap_err();
        assert!(e.contains("`ground.mu` is not in the file"), "{e}");
    }

    #[test]
    fn a_problem_written_by_to_toml_reads_back_to_itself() {
        for file in [
            "s_start.toml",
            "coil.toml",
            "sidewinding.toml",
            "cantilever_sag.toml",
            "incline.toml",
        ] {
            let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("problems")
                .join(file);
            let p = crate::problem::load(&path).unwrap();
            let text = p.to_toml();
            let q = crate::problem::parse(&text, &path).unwrap();
            assert_eq!(format!("{p:?}"), format!("{q:?}"), "{file}");
            assert_eq!(text, q.to_toml(), "{file}");
        }
    }
}
