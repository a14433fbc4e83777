//! The import graph of `src/` has no cycle: neither among the top-level modules (the layers of
//! `src/lib.rs`'s module map) nor among files. An edge `a -> b` is a path `crate::...`,
//! `super::...` or `self::...` in `a` (outside its test module) that names module `b` (the
//! longest prefix of the path that is a module); a `use x::{...}` group adds each of its
//! members. Bare relative paths (`mod x; pub use x::Y`) add no edge, so a parent re-exporting
//! its children is not a cycle. Files named `tests.rs` and code after a file's first
//! `#[cfg(test)]` are test code and do not count.
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

type Module = Vec<String>;

/// Every `.rs` file under `dir`.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The module path of a file: `studies/phase/mod.rs` is `studies::phase`, `lib.rs` the crate.
fn module_of(src: &Path, file: &Path) -> Module {
    let rel = file.strip_prefix(src).unwrap();
    let mut parts: Module = rel
        .iter()
        .map(|s| s.to_string_lossy().into_owned())
        .collect();
    let last = parts.pop().unwrap();
    let stem = last.trim_end_matches(".rs");
    if stem != "mod" && !(parts.is_empty() && (stem == "lib" || stem == "main")) {
        parts.push(stem.to_string());
    }
    parts
}

fn is_ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// The code of a file that counts: before its first `#[cfg(test)]`, line comments removed.
fn code(text: &str) -> String {
    let text = text.split("#[cfg(test)]").next().unwrap_or("");
    text.lines()
        .map(|l| l.find("//").map_or(l, |i| &l[..i]))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The identifiers of a path starting at `s` (`a::b::c`), and the rest of `s` after it (which
/// may start with `::{`).
fn path_at(s: &str) -> (Vec<String>, &str) {
    let mut segs = Vec::new();
    let mut rest = s;
    loop {
        let n = rest.find(|c: char| !is_ident(c)).unwrap_or(rest.len());
        if n == 0 {
            break;
        }
        segs.push(rest[..n].to_string());
        rest = &rest[n..];
        match rest.strip_prefix("::") {
            Some(r) if r.starts_with(|c: char| is_ident(c)) => rest = r,
            _ => break,
        }
    }
    (segs, rest)
}

/// Every `crate::`, `super::` or `self::` path in `text`, with `{...}` groups expanded.
fn paths(text: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let mut i = 0;
    let bytes = text.as_bytes();
    while i < text.len() {
        let start_ok = i == 0 || !is_ident(bytes[i - 1] as char);
        let rest = &text[i..];
        let head = ["crate::", "super::", "self::"]
            .into_iter()
            .find(|h| rest.starts_with(h));
        if !(start_ok && head.is_some()) {
            i += rest.chars().next().map_or(1, char::len_utf8);
            continue;
        }
        let (segs, after) = path_at(rest);
        let consumed = rest.len() - after.len();
        if let Some(group) = after.strip_prefix("::{") {
            // One group, nested groups included: each top-level member.
            let (mut depth, mut end) = (1, group.len());
            for (k, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' => {
                        depth -= 1;
                        if depth == 0 {
                            end = k;
                            break;
                        }
                    }
                    _ => {}
                }
            }
            let (mut depth, mut member) = (0, String::new());
            let mut members = Vec::new();
            for c in group[..end].chars() {
                match c {
                    '{' => depth += 1,
                    '}' => depth -= 1,
                    ',' if depth == 0 => members.push(std::mem::take(&mut member)),
                    _ => {}
                }
                member.push(c);
            }
            members.push(member);
            for m in members {
                let m = m.trim().trim_start_matches(',').trim();
                let (inner, _) = path_at(m);
                if !inner.is_empty() {
                    out.push(segs.iter().cloned().chain(inner).collect());
                }
            }
            i += consumed + 3 + end;
        } else {
            if segs.len() > 1 {
                out.push(segs);
            }
            i += consumed.max(1);
        }
    }
    out
}

/// The module a path in module `here` names: the longest prefix that is a module.
fn resolve(known: &BTreeSet<Module>, here: &Module, path: &[String]) -> Option<Module> {
    let (cur, segs): (Module, &[String]) = match path[0].as_str() {
        "crate" => (Vec::new(), &path[1..]),
        "self" => (here.clone(), &path[1..]),
        _ => {
            let (mut cur, mut segs) = (here.clone(), path);
            while segs.first().is_some_and(|s| s == "super") {
                cur.pop();
                segs = &segs[1..];
            }
            (cur, segs)
        }
    };
    (0..=segs.len())
        .rev()
        .map(|k| cur.iter().chain(&segs[..k]).cloned().collect::<Module>())
        .find(|cand| known.contains(cand))
}

/// The graph of `src` (files, or top-level modules), test code aside.
fn graph(files_mode: bool) -> BTreeMap<Module, BTreeSet<Module>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.retain(|f| f.file_name().is_some_and(|n| n != "tests.rs"));
    let mods: Vec<(PathBuf, Module)> = files
        .iter()
        .map(|f| (f.clone(), module_of(&src, f)))
        .collect();
    let known: BTreeSet<Module> = mods.iter().map(|(_, m)| m.clone()).collect();
    let mut edges: BTreeMap<Module, BTreeSet<Module>> = BTreeMap::new();
    for (file, here) in &mods {
        let node: Module = if files_mode {
            here.clone()
        } else {
            here.iter().take(1).cloned().collect()
        };
        if node.is_empty() {
            continue;
        }
        let targets = edges.entry(node.clone()).or_default();
        for p in paths(&code(&std::fs::read_to_string(file).unwrap())) {
            let Some(r) = resolve(&known, here, &p) else {
                continue;
            };
            let r: Module = if files_mode {
                r
            } else {
                r.into_iter().take(1).collect()
            };
            if !r.is_empty() && r != node {
                targets.insert(r);
            }
        }
    }
    edges
}

/// The strongly connected components of more than one node (Tarjan).
fn cycles(edges: &BTreeMap<Module, BTreeSet<Module>>) -> Vec<Vec<Module>> {
    struct T<'a> {
        edges: &'a BTreeMap<Module, BTreeSet<Module>>,
        index: BTreeMap<&'a Module, usize>,
        low: BTreeMap<&'a Module, usize>,
        stack: Vec<&'a Module>,
        on: BTreeSet<&'a Module>,
        out: Vec<Vec<Module>>,
    }
    fn visit<'a>(t: &mut T<'a>, v: &'a Module) {
        let n = t.index.len();
        t.index.insert(v, n);
        t.low.insert(v, n);
        t.stack.push(v);
        t.on.insert(v);
        for w in &t.edges[v] {
            let Some((w, _)) = t.edges.get_key_value(w) else {
                continue;
            };
            if !t.index.contains_key(w) {
                visit(t, w);
                let lw = t.low[w];
                let lv = t.low.get_mut(v).unwrap();
                *lv = (*lv).min(lw);
            } else if t.on.contains(w) {
                let iw = t.index[w];
                let lv = t.low.get_mut(v).unwrap();
                *lv = (*lv).min(iw);
            }
        }
        if t.low[v] == t.index[v] {
            let mut comp = Vec::new();
            loop {
                let w = t.stack.pop().unwrap();
                t.on.remove(w);
                comp.push(w.clone());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                t.out.push(comp);
            }
        }
    }
    let mut t = T {
        edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in edges.keys() {
        if !t.index.contains_key(v) {
            visit(&mut t, v);
        }
    }
    t.out
}

fn name(m: &Module) -> String {
    m.join("::")
}

#[test]
fn the_top_level_modules_import_each_other_without_cycles() {
    let g = graph(false);
    assert!(
        g.len() >= 19,
        "{} modules: the graph lost its nodes",
        g.len()
    );
    // The graph has edges (a parse that finds none would pass trivially): the physics uses
    // the problem files, the command line's library half uses the studies.
    assert!(g[&vec!["energy".to_string()]].contains(&vec!["band".to_string()]));
    assert!(g[&vec!["pipeline".to_string()]].contains(&vec!["studies".to_string()]));
    let c = cycles(&g);
    assert!(
        c.is_empty(),
        "import cycles among modules: {:?}",
        c.iter()
            .map(|c| c.iter().map(name).collect::<Vec<_>>())
            .collect::<Vec<_>>()
    );
}

#[test]
fn the_files_import_each_other_without_cycles() {
    let g = graph(true);
    assert!(
        g.len() >= 100,
        "{} files: the graph lost its nodes",
        g.len()
    );
    let c = cycles(&g);
    assert!(
        c.is_empty(),
        "import cycles among files: {:?}",
        c.iter()
            .map(|c| c.iter().map(name).collect::<Vec<_>>())
            .collect::<Vec<_>>()
    );
}

#[test]
fn the_checker_finds_a_cycle_when_there_is_one() {
    // Two modules naming each other, and a third naming one of them: one cycle of two.
    let m = |s: &str| vec![s.to_string()];
    let mut g: BTreeMap<Module, BTreeSet<Module>> = BTreeMap::new();
    g.insert(m("a"), [m("b")].into());
    g.insert(m("b"), [m("a")].into());
    g.insert(m("c"), [m("a")].into());
    let c = cycles(&g);
    assert_eq!(c.len(), 1);
    assert_eq!(c[0].len(), 2);
    // And the path reader sees a group's members and a nested group's head.
    let p = paths("use crate::a::{b, c::{d, e}};\nlet x = super::f::g(1);");
    let shown: Vec<String> = p.iter().map(|p| p.join("::")).collect();
    assert!(shown.contains(&"crate::a::b".to_string()), "{shown:?}");
    assert!(shown.contains(&"crate::a::c".to_string()), "{shown:?}");
    assert!(shown.contains(&"super::f::g".to_string()), "{shown:?}");
}
