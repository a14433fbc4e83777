//! The allowed range of every input-file key, as written in error messages (from the key table
//! [`super::keys`]), and the fixed lengths of array keys.
//!
//! TOML type errors (a string for a number, `elements = -5` for an unsigned integer) come from
//! the deserializer, which knows only the Rust type; [`allowed`] adds the key's range so every
//! error says what would be accepted. [`FIXED_LENGTHS`] lists the arrays whose length is
//! fixed: the deserializer reads the first `n` elements of a longer array and ignores the
//! rest, so `check_lengths` rejects any other length.

use super::{key_line, keys, ProblemError};
use std::path::Path;

/// The allowed values of a dotted key, if it is one of the documented keys: a problem-file
/// key's or a study or phase key's ([`super::study_keys`]) [`keys::Key::allowed`].
/// (Enumerations whose message serde already lists get toml's message alone when not listed.)
pub fn allowed(key: &str) -> Option<String> {
    keys::find(key)
        .or_else(|| super::study_keys::find(key))
        .map(|k| k.allowed())
}

/// `(table, key, length)` of every fixed-length array in problem and study files.
pub const FIXED_LENGTHS: &[(&str, &str, usize)] = &[
    ("rod", "natural_curvature", 2),
    ("initial", "velocity", 3),
    ("initial", "angular_velocity", 3),
    ("gait", "centers", 3),
    ("gait", "scales", 3),
    ("optimize", "stress", 2),
    ("optimize", "sigma", 2),
    ("optimize", "speed", 2),
];

/// Reject an array key of [`FIXED_LENGTHS`] whose length differs (the text has already
/// deserialized, so it is valid TOML).
pub(crate) fn check_lengths(text: &str, path: &Path) -> Result<(), ProblemError> {
    let Ok(doc) = text.parse::<toml::Table>() else {
        return Ok(());
    };
    for &(table, key, n) in FIXED_LENGTHS {
        let Some(toml::Value::Array(a)) = doc
            .get(table)
            .and_then(|t| t.as_table())
            .and_then(|t| t.get(key))
        else {
            continue;
        };
        if a.len() != n {
            let dotted = format!("{table}.{key}");
            let what =
                allowed(&dotted).unwrap_or_else(|| "an array of the documented length".into());
            return Err(ProblemError::Invalid {
                file: path.into(),
                line: key_line(text, table, key),
                key: dotted,
                value: format!("an array of {} elements", a.len()),
                allowed: format!("{what}: exactly {n} elements"),
            });
        }
    }
    Ok(())
}
