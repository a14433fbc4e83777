//! Hashes that key resumable rows: FNV-1a over bytes, and the hash of an effective problem.
//!
//! A study's rows are reused only for the problem they were simulated for. That problem is the
//! *effective* one: the file parsed, every default filled in and validated (and, once the
//! command line can override keys, with the overrides applied), not the file's text. So a
//! comment, a reordered table or a default written out does not count as a change, while any
//! value that reaches the simulation does. [`problem_hash`] hashes the [`Problem`] value
//! itself, through its `Debug` form: every field by name, numbers in their shortest round-trip
//! form, so two problems hash alike exactly when every field is bit for bit the same.
use crate::problem::Problem;

/// FNV-1a, 64 bit (stable across Rust versions, unlike `DefaultHasher`).
pub(crate) fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// Hash of the effective problem `p` (module doc): what the resume keys of `optimize`, `phase`
/// and `merge` are made of. Feed it the problem after every change that reaches the
/// simulation (defaults, overrides, an accuracy choice is keyed on top of it).
pub fn problem_hash(p: &Problem) -> u64 {
    let mut text = format!("{p:?}");
    for fragment in LATER_DEFAULTS {
        text = text.replace(fragment, "");
    }
    fnv1a(text.as_bytes())
}

/// Keys added after studies were first keyed, as the debug text prints them at their default:
/// left out of the hash, so that a study made before a key existed resumes, and a file that
/// sets the key to another value is a new problem.
const LATER_DEFAULTS: &[&str] = &["damping_time: 0.0, ", "ground_points: Nodes, "];

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    const BASE: &str = "[rod]\nlength = 0.5\ndiameter = 0.02\nbending_stiffness = 1e-3\n[time]\ndt = 1e-3\nduration = 0.1\n";

    fn hash(text: &str) -> u64 {
        problem_hash(&crate::problem::parse(text, Path::new("t.toml")).unwrap())
    }

    /// Keys added later (`rod.damping_time`, `solver.ground_points`) at their defaults leave
    /// the hash as it was before they existed (the debug text without them); another value
    /// changes it.
    #[test]
    fn a_later_key_at_its_default_keeps_earlier_hashes() {
        let p = parsed(BASE);
        let text = format!("{p:?}");
        for fragment in LATER_DEFAULTS {
            assert!(text.contains(fragment), "{fragment} not in {text}");
        }
        let before = fnv1a(
            text.replace(LATER_DEFAULTS[0], "")
                .replace(LATER_DEFAULTS[1], "")
                .as_bytes(),
        );
        assert_eq!(problem_hash(&p), before);
        let explicit = BASE.replace("[time]", "damping_time = 0.0\n[time]");
        assert_eq!(hash(&explicit), before);
        let damped = BASE.replace("[time]", "damping_time = 1e-3\n[time]");
        assert_ne!(hash(&damped), before);
        let curve = format!("{BASE}[solver]\nground_points = \"curve\"\n");
        assert_ne!(hash(&curve), before);
    }

    /// The key hashes the problem's debug text: the integrator's variants print the names
    /// earlier studies were keyed with, so their rows are reused.
    #[test]
    fn the_integrator_keeps_the_debug_text_of_earlier_keys() {
        use crate::problem::IntegratorKind;
        let names: Vec<String> = [
            IntegratorKind::ImplicitEuler,
            IntegratorKind::VelocityVerlet,
            IntegratorKind::Bdf2,
        ]
        .iter()
        .map(|k| format!("{k:?}"))
        .collect();
        assert_eq!(names, ["Implicit", "Explicit", "Bdf2"]);
        assert!(format!("{:?}", parsed(BASE)).contains("integrator: Implicit"));
    }

    fn parsed(text: &str) -> crate::problem::Problem {
        crate::problem::parse(text, Path::new("t.toml")).unwrap()
    }

    #[test]
    fn comments_layout_and_written_defaults_do_not_count_values_do() {
        let h = hash(BASE);
        // A comment, blank lines and another spelling of the same numbers.
        let commented = format!(
            "# a note\n\n{}",
            BASE.replace("0.5\n", "5e-1 # half a metre\n")
        );
        assert_eq!(hash(&commented), h);
        // A default written out (rod.elements' default) is the same problem.
        let n = crate::problem::keys::ROD_ELEMENTS.int();
        let explicit = BASE.replace("[time]", &format!("elements = {n}\n[time]"));
        assert_eq!(hash(&explicit), h);
        // Any value that reaches the simulation counts.
        assert_ne!(hash(&BASE.replace("0.5\n", "0.51\n")), h);
        assert_ne!(
            hash(&BASE.replace("dt = 1e-3", "dt = 1.0000000000000002e-3")),
            h
        );
        // Stable: the hash of a value, not of an address or a random state.
        assert_eq!(h, hash(BASE));
    }
}
