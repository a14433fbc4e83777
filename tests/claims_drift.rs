//! The numbers the README and the guide's claims chapter quote cannot drift from their records.
//!
//! A quoted number is a Markdown link to the record it comes from, titled with its key there:
//!
//! ```text
//! [0.3177](docs/results/s-start/latest.md "v_s_over_v_m")
//! ```
//!
//! (or to a dated record, `docs/results/s-start/2026-12-05.md`, for a number that a later
//! record of the kind no longer carries).
//!
//! - **The key** locates the value in the record's output (the text after `## Output`): one or
//!   more anchors separated by ` … `, each found after the previous one (an anchor that starts
//!   or ends with a letter or digit must not continue a longer word, nor be continued by one:
//!   `label_purity_by_W` is not found in `label_purity_by_W_over_G`); the value is the first number
//!   after the last anchor. `\|` in a key stands for `|` (escaped inside tables).
//! - **The comparison** rounds the record's value to the quoted number's decimals; they must be
//!   equal. A quoted text that is not a number (a regime letter) must equal the rest of the
//!   anchor's line.
//! - **The records** that the two pages link (tagged or not) must have exit code 0, be made
//!   from a clean tree (no "with uncommitted changes") and name no private path (`/work/`,
//!   `/tmp/`) in their command.
//! - **Untagged numbers.** In a table introduced by `<!-- numbers: tagged, column "NAME" -->`,
//!   every decimal number of column NAME is tagged (numbers in backticks are settings, not
//!   results).
//!
//! `cargo test --release --test claims_drift -- --nocapture` prints every number it checked.

use std::path::{Path, PathBuf};

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// The pages whose numbers are checked, relative to the repository.
const PAGES: [&str; 2] = ["README.md", "docs/book/src/claims.md"];

/// One link to a record in a page.
#[derive(Debug, Clone)]
struct Link {
    line: usize,
    text: String,
    /// The record's path relative to the repository (`docs/results/NAME/latest.md`, or a
    /// dated record).
    record: String,
    key: Option<String>,
}

/// Every link of `page` (a file in directory `dir`, relative to the repository) to a record
/// (`docs/results/NAME/latest.md` or a dated one, [`is_record`]).
fn record_links(page: &str, dir: &Path) -> Vec<Link> {
    let mut links = Vec::new();
    for (n, line) in page.lines().enumerate() {
        let mut from = 0;
        while let Some(i) = line[from..].find("](") {
            let close = from + i;
            let open = match line[..close].rfind('[') {
                Some(o) => o,
                None => {
                    from = close + 2;
                    continue;
                }
            };
            let text = &line[open + 1..close];
            let rest = &line[close + 2..];
            let (target, key, used) = if let Some(end) = rest.find(')') {
                let inner = &rest[..end];
                match inner.find(" \"") {
                    Some(q) => {
                        // A title may hold ')': it ends at the first `")`.
                        let title_end = rest.find("\")").expect("an unterminated link title");
                        (
                            rest[..q].to_string(),
                            Some(rest[q + 2..title_end].to_string()),
                            title_end + 2,
                        )
                    }
                    None => (inner.to_string(), None, end + 1),
                }
            } else {
                break;
            };
            from = close + 2 + used;
            if !is_record(&target) {
                continue;
            }
            let record = normalize(&dir.join(&target));
            links.push(Link {
                line: n + 1,
                text: text.to_string(),
                record,
                key,
            });
        }
    }
    links
}

/// Whether a link's target is a record: `results/NAME/latest.md`, or a dated one,
/// `results/NAME/YYYY-MM-DD.md` or `YYYY-MM-DD-N.md` (a dated record never changes; the
/// latest one is the guide's default).
fn is_record(target: &str) -> bool {
    if !target.contains("results/") {
        return false;
    }
    let Some(name) = target
        .rsplit('/')
        .next()
        .and_then(|f| f.strip_suffix(".md"))
    else {
        return false;
    };
    if name == "latest" {
        return true;
    }
    let b = name.as_bytes();
    let digits = |r: std::ops::Range<usize>| b[r].iter().all(u8::is_ascii_digit);
    b.len() >= 10
        && digits(0..4)
        && b[4] == b'-'
        && digits(5..7)
        && b[7] == b'-'
        && digits(8..10)
        && (b.len() == 10 || (b.len() > 11 && b[10] == b'-' && digits(11..b.len())))
}

/// `a/b/../c` as `a/c`, with `/` separators.
fn normalize(p: &Path) -> String {
    let mut parts: Vec<String> = Vec::new();
    for c in p.components() {
        match c {
            std::path::Component::ParentDir => {
                parts.pop();
            }
            std::path::Component::CurDir => {}
            other => parts.push(other.as_os_str().to_string_lossy().into_owned()),
        }
    }
    parts.join("/")
}

/// The first number in `s` at or after byte `from`: its text and its value.
fn next_number(s: &str, from: usize) -> Option<(String, f64)> {
    let b = s.as_bytes();
    let mut i = from;
    while i < b.len() {
        let c = b[i];
        let starts = c.is_ascii_digit()
            || ((c == b'-' || c == b'+' || c == b'.')
                && i + 1 < b.len()
                && b[i + 1].is_ascii_digit());
        let prev_ok =
            i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_' || b[i - 1] == b'.');
        if starts && prev_ok {
            let mut j = i + 1;
            while j < b.len() && (b[j].is_ascii_digit() || b[j] == b'.') {
                j += 1;
            }
            if j < b.len() && (b[j] == b'e' || b[j] == b'E') {
                let mut k = j + 1;
                if k < b.len() && (b[k] == b'-' || b[k] == b'+') {
                    k += 1;
                }
                if k < b.len() && b[k].is_ascii_digit() {
                    j = k;
                    while j < b.len() && b[j].is_ascii_digit() {
                        j += 1;
                    }
                }
            }
            let t = s[i..j].trim_end_matches('.');
            if let Ok(v) = t.parse::<f64>() {
                return Some((t.to_string(), v));
            }
        }
        i += 1;
    }
    None
}

/// Where the key's last anchor ends in `output`.
fn locate(output: &str, key: &str) -> Result<usize, String> {
    let key = key.replace("\\|", "|");
    let mut pos = 0;
    for anchor in key.split(" … ") {
        loop {
            let i = match output[pos..].find(anchor) {
                Some(i) => pos + i,
                None => return Err(format!("key anchor {anchor:?} not found")),
            };
            let first = anchor.as_bytes()[0];
            let prev = if i > 0 {
                output.as_bytes()[i - 1]
            } else {
                b' '
            };
            let last = anchor.as_bytes()[anchor.len() - 1];
            let next = output
                .as_bytes()
                .get(i + anchor.len())
                .copied()
                .unwrap_or(b' ');
            if (first.is_ascii_alphanumeric()
                && (prev.is_ascii_alphanumeric() || prev == b'_' || prev == b'.'))
                || (last.is_ascii_alphanumeric() && (next.is_ascii_alphanumeric() || next == b'_'))
            {
                pos = i + 1;
                continue;
            }
            pos = i + anchor.len();
            break;
        }
    }
    Ok(pos)
}

/// Decimals of a quoted number ("0.3177" has 4, "18" none).
fn decimals(q: &str) -> i32 {
    q.split_once('.').map_or(0, |(_, f)| f.len() as i32)
}

/// The record's problems as a record a page may cite, or none.
fn record_problems(header: &str) -> Vec<String> {
    let mut bad = Vec::new();
    let field = |name: &str| {
        header
            .lines()
            .find(|l| l.starts_with(&format!("| {name} |")))
            .map(|l| {
                l.splitn(3, '|')
                    .nth(2)
                    .unwrap_or("")
                    .trim()
                    .trim_end_matches('|')
                    .trim()
                    .to_string()
            })
    };
    match field("exit code") {
        Some(c) if c == "0" => {}
        Some(c) => bad.push(format!("it failed (exit code {c})")),
        None => bad.push("it has no exit code".into()),
    }
    match field("commit") {
        Some(c) if c.contains("(clean)") => {}
        Some(c) => bad.push(format!("it was not made from committed code ({c})")),
        None => bad.push("it names no commit".into()),
    }
    let command = field("command").unwrap_or_default();
    for private in ["/work/", "/tmp/"] {
        if command.contains(private) {
            bad.push(format!(
                "its command names a private path ({private}): {command}"
            ));
        }
    }
    bad
}

/// Checks one link; `Ok(description)` when it holds.
fn check_link(link: &Link, record_text: &str) -> Result<String, String> {
    let (header, output) = match record_text.find("## Output") {
        Some(i) => (&record_text[..i], &record_text[i..]),
        None => return Err("the record has no `## Output`".into()),
    };
    let problems = record_problems(header);
    if !problems.is_empty() {
        return Err(problems.join("; "));
    }
    let Some(key) = &link.key else {
        return Ok(format!("{} (record checked)", link.record));
    };
    let pos = locate(output, key)?;
    let quoted = link.text.trim();
    match quoted.parse::<f64>() {
        Ok(q) => {
            let (found, v) =
                next_number(output, pos).ok_or_else(|| format!("no number after key {key:?}"))?;
            // Rounded to the quoted decimals, the record's value is the quoted one: within half
            // a unit of its last digit (a value exactly half-way may round either way).
            let half = 0.5 * 10f64.powi(-decimals(quoted));
            if (v - q).abs() > half * (1.0 + 1e-9) {
                return Err(format!(
                    "quotes {quoted} for key {key:?}, the record has {found}"
                ));
            }
            Ok(format!("{quoted} = {found} ({key})"))
        }
        Err(_) => {
            let rest = output[pos..].lines().next().unwrap_or("").trim();
            if rest != quoted {
                return Err(format!(
                    "quotes {quoted:?} for key {key:?}, the record has {rest:?}"
                ));
            }
            Ok(format!("{quoted:?} ({key})"))
        }
    }
}

/// Decimal numbers in the marked tables' checked column that are not tagged.
fn untagged_numbers(page: &str) -> Vec<String> {
    let mut bad = Vec::new();
    let mut column: Option<usize> = None;
    let mut pending: Option<String> = None;
    for (n, line) in page.lines().enumerate() {
        if let Some(rest) = line.trim().strip_prefix("<!-- numbers: tagged, column \"") {
            pending = rest.split('"').next().map(str::to_string);
            column = None;
            continue;
        }
        if !line.starts_with('|') {
            if column.is_some() || (pending.is_some() && !line.trim().is_empty()) {
                column = None;
                if !line.trim().is_empty() {
                    pending = None;
                }
            }
            continue;
        }
        let cells = split_row(line);
        if let Some(name) = pending.take() {
            column = cells.iter().position(|c| c.trim() == name);
            assert!(
                column.is_some(),
                "line {}: no column {name:?} in the table",
                n + 1
            );
            continue;
        }
        let Some(col) = column else { continue };
        if line.starts_with("|---") {
            continue;
        }
        let cell = cells.get(col).cloned().unwrap_or_default();
        let stripped = strip_tagged(&cell);
        let mut from = 0;
        while let Some((t, _)) = next_number(&stripped, from) {
            let at = stripped[from..]
                .find(&t)
                .map_or(stripped.len(), |i| from + i);
            if t.contains('.') {
                bad.push(format!(
                    "line {}: untagged number {t} in {:?}",
                    n + 1,
                    stripped.trim()
                ));
            }
            from = at + t.len().max(1);
        }
    }
    bad
}

/// A table row's cells, split at `|` that is not escaped.
fn split_row(line: &str) -> Vec<String> {
    let mut cells = Vec::new();
    let mut cur = String::new();
    let mut prev = ' ';
    for c in line.trim().trim_start_matches('|').chars() {
        if c == '|' && prev != '\\' {
            cells.push(std::mem::take(&mut cur));
        } else {
            cur.push(c);
        }
        prev = c;
    }
    if !cur.trim().is_empty() {
        cells.push(cur);
    }
    cells
}

/// `cell` without code spans, tagged numbers (links with a title) and link targets.
fn strip_tagged(cell: &str) -> String {
    let mut out = String::new();
    let mut in_code = false;
    let chars = cell.char_indices();
    let mut skip_to = 0;
    for (i, c) in chars {
        if i < skip_to {
            continue;
        }
        if c == '`' {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        if c == '[' {
            if let Some(close) = cell[i..].find("](") {
                let after = i + close + 2;
                if let Some(end) = cell[after..].find(')') {
                    let inner = &cell[after..after + end];
                    let titled = inner.contains(" \"");
                    let end_at = if titled {
                        cell[after..]
                            .find("\")")
                            .map_or(after + end + 1, |e| after + e + 2)
                    } else {
                        after + end + 1
                    };
                    if !titled {
                        out.push_str(&cell[i + 1..i + close]);
                    }
                    skip_to = end_at;
                    continue;
                }
            }
        }
        out.push(c);
    }
    out
}

/// Every problem in the page's tagged numbers and cited records, and what was checked.
fn check_page(name: &str, text: &str) -> (Vec<String>, Vec<String>) {
    let dir = Path::new(name).parent().unwrap_or(Path::new(""));
    let mut bad = Vec::new();
    let mut ok = Vec::new();
    for link in record_links(text, dir) {
        let record = std::fs::read_to_string(repo(&link.record));
        let result = match record {
            Ok(t) => check_link(&link, &t),
            Err(e) => Err(format!("cannot read it: {e}")),
        };
        match result {
            Ok(d) => ok.push(format!("{name}:{}: {d}", link.line)),
            Err(e) => bad.push(format!(
                "{name}:{}: [{}]({}): {e}",
                link.line, link.text, link.record
            )),
        }
    }
    for u in untagged_numbers(text) {
        bad.push(format!("{name}: {u}"));
    }
    (bad, ok)
}

#[test]
fn quoted_numbers_are_their_records() {
    let mut all_bad = Vec::new();
    let mut tagged = 0;
    for page in PAGES {
        let text = std::fs::read_to_string(repo(page)).expect(page);
        let (bad, ok) = check_page(page, &text);
        tagged += ok
            .iter()
            .filter(|d| !d.ends_with("(record checked)"))
            .count();
        for d in &ok {
            println!("ok {d}");
        }
        all_bad.extend(bad);
    }
    assert!(
        tagged > 20,
        "only {tagged} tagged numbers: is the markup still read?"
    );
    assert!(
        all_bad.is_empty(),
        "numbers that drifted or records that may not be cited:\n{}",
        all_bad.join("\n")
    );
}

#[test]
fn a_changed_number_fails() {
    // The README's first tagged number, its last digit changed: the check must catch it.
    let text = std::fs::read_to_string(repo("README.md")).unwrap();
    let link = record_links(&text, Path::new(""))
        .into_iter()
        .find(|l| l.key.is_some() && l.text.parse::<f64>().is_ok())
        .expect("the README quotes a tagged number");
    let mut changed = link.text.clone();
    let last = changed.pop().unwrap();
    changed.push(if last == '9' {
        '8'
    } else {
        char::from(last as u8 + 1)
    });
    let needle = format!(
        "[{}]({} \"{}\")",
        link.text,
        link.record,
        link.key.as_deref().unwrap()
    );
    assert!(text.contains(&needle), "cannot find {needle}");
    let edited = text.replacen(&needle, &needle.replacen(&link.text, &changed, 1), 1);
    let (bad, _) = check_page("README.md", &edited);
    println!(
        "README's {} changed to {changed}:\n{}",
        link.text,
        bad.join("\n")
    );
    assert!(
        bad.iter().any(|b| b.contains(&changed)),
        "the check missed {changed}"
    );
}

#[test]
fn latest_and_dated_records_are_records() {
    for t in [
        "docs/results/s-start/latest.md",
        "docs/results/ground-points-phase/2026-12-05.md",
        "../../results/ground-points/2026-12-05-3.md",
    ] {
        assert!(is_record(t), "{t}");
    }
    for t in [
        "docs/results/legacy-measurements.md",
        "docs/results/s-start/notes.md",
        "docs/results/s-start/2026-12-05-.md",
        "docs/book/src/2026-12-05.md",
        "docs/results/s-start/2026-12-5.md",
    ] {
        assert!(!is_record(t), "{t}");
    }
}

#[test]
fn a_failed_or_dirty_record_fails() {
    let header = "| exit code | 127 |\n| commit | `abc` (with uncommitted changes) |\n| command | `/tmp/x` |\n";
    let problems = record_problems(header);
    assert_eq!(problems.len(), 3, "{problems:?}");
}

#[test]
fn untagged_decimals_in_a_marked_column_fail() {
    let page = "<!-- numbers: tagged, column \"result\" -->\n| result | x |\n|---|---|\n| speed \
                [0.3177](docs/results/s-start/latest.md \"v_s_over_v_m\") and 0.5, `1e-3` |  |\n";
    let bad = untagged_numbers(page);
    assert_eq!(bad.len(), 1, "{bad:?}");
    assert!(bad[0].contains("0.5"));
}

#[test]
fn a_key_is_not_found_inside_a_longer_word() {
    // The guide once quoted label_purity_by_W_over_G's value as label_purity_by_W's: the key
    // must not match the start of a longer key, nor the end of one.
    let output = "x.by_W_over_G 0.6875\nx.by_W 0.565\nprefix_by_W 9\n";
    let pos = locate(output, "x.by_W").unwrap();
    assert!(
        output[pos..].trim_start().starts_with("0.565"),
        "{}",
        &output[pos..]
    );
    let pos = locate(output, "x.by_W_over_G").unwrap();
    assert!(output[pos..].trim_start().starts_with("0.6875"));
    let pos = locate(output, "x.by_").unwrap();
    assert!(
        output[pos..].starts_with("W_over_G"),
        "an anchor ending in `_` may continue"
    );
}
