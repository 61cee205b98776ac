//! The source tree's layering (docs/architecture.md): every module of `src/` uses only
//! modules of lower layers, and no set of modules uses each other in a circle.
//!
//! Read from the source text, so it needs no tool beyond the test suite: each file's
//! `crate::…`, `super::…` and `self::…` paths (in `use` items and written inline) are
//! resolved to the module they name, comments and string literals skipped. Unit-test
//! modules (`#[cfg(test)]` items) are left out: they are not part of the library and may
//! build their fixtures from any layer (a scenario file, say), as the integration tests do.
//! The binary (`src/bin/foldsim/`) sits above every layer and uses the library by its name.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The top-level modules, lowest layer first: each may use only those before it.
const LAYERS: [&str; 20] = [
    "math",
    "integrate",
    "law",
    "contact",
    "loads",
    "model",
    "state",
    "kinematics",
    "dynamics",
    "observe",
    "simulate",
    "linear",
    "scenario",
    "session",
    "output",
    "verify",
    "generate",
    "sweep",
    "fit",
    "export",
];

/// Every `.rs` file under `dir`, sorted.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> =
        std::fs::read_dir(dir).expect("src/ is readable").map(|e| e.unwrap().path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The module path of a source file: `src/dynamics/locks/mod.rs` → `dynamics::locks`.
fn module_of(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap().with_extension("");
    let mut parts: Vec<String> = rel.components().map(|c| c.as_os_str().to_string_lossy().into_owned()).collect();
    if parts.last().is_some_and(|p| p == "mod" || p == "lib") {
        parts.pop();
    }
    parts
}

/// The text with comments, string and character literals blanked out (newlines kept).
fn code_only(text: &str) -> String {
    let b: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let next = b.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < b.len() && b[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < b.len() {
                if b[i] == '/' && b.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if b[i] == '*' && b.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
        } else if c == 'r'
            && (next == Some('"') || (next == Some('#') && b.get(i + 2).is_some_and(|&x| x == '"' || x == '#')))
            && (i == 0 || !(b[i - 1].is_alphanumeric() || b[i - 1] == '_'))
        {
            // Raw string r"…" or r#"…"#.
            let mut j = i + 1;
            let mut hashes = 0;
            while b.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            j += 1;
            loop {
                if j >= b.len() {
                    break;
                }
                if b[j] == '"' && (0..hashes).all(|k| b.get(j + 1 + k) == Some(&'#')) {
                    j += 1 + hashes;
                    break;
                }
                if b[j] == '\n' {
                    out.push('\n');
                }
                j += 1;
            }
            out.push_str("\"\"");
            i = j;
        } else if c == '"' {
            i += 1;
            while i < b.len() && b[i] != '"' {
                if b[i] == '\\' {
                    i += 1;
                }
                if b.get(i) == Some(&'\n') {
                    out.push('\n');
                }
                i += 1;
            }
            i += 1;
            out.push_str("\"\"");
        } else if c == '\''
            && next.is_some()
            && (b.get(i + 2) == Some(&'\'') || (next == Some('\\') && b[i + 2..].iter().take(10).any(|&x| x == '\'')))
        {
            // A character literal ('x', '\n', '\u{..}'); lifetimes ('a) are left alone.
            i += 1;
            while i < b.len() && b[i] != '\'' {
                if b[i] == '\\' {
                    i += 1;
                }
                i += 1;
            }
            i += 1;
            out.push_str("' '");
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// The text with every `#[cfg(test)]` item removed (up to its `;` or its closing brace).
fn without_test_items(code: &str) -> String {
    test_items(code).0
}

/// The text without its `#[cfg(test)]` items, and the modules those declare in files of
/// their own (`#[cfg(test)] mod tests;`).
fn test_items(code: &str) -> (String, Vec<String>) {
    let mut out = String::new();
    let mut test_modules = Vec::new();
    let mut rest = code;
    while let Some(at) = rest.find("#[cfg(test)]") {
        out.push_str(&rest[..at]);
        let item = &rest[at + "#[cfg(test)]".len()..];
        let words: Vec<&str> = item.split_whitespace().take(2).collect();
        if let ["mod", name] = words[..]
            && let Some(name) = name.strip_suffix(';')
        {
            test_modules.push(name.to_string());
        }
        let mut depth = 0usize;
        let mut end = item.len();
        for (k, ch) in item.char_indices() {
            match ch {
                '{' => depth += 1,
                '}' => {
                    depth -= 1;
                    if depth == 0 {
                        end = k + 1;
                        break;
                    }
                }
                ';' if depth == 0 => {
                    end = k + 1;
                    break;
                }
                _ => {}
            }
        }
        rest = &item[end..];
    }
    out.push_str(rest);
    (out, test_modules)
}

/// An identifier starting at byte `i` of `s`, if any.
fn ident_at(s: &[u8], i: usize) -> Option<(String, usize)> {
    let mut j = i;
    while j < s.len() && (s[j].is_ascii_alphanumeric() || s[j] == b'_') {
        j += 1;
    }
    (j > i && !s[i].is_ascii_digit()).then(|| (String::from_utf8_lossy(&s[i..j]).into_owned(), j))
}

fn skip_space(s: &[u8], mut i: usize) -> usize {
    while i < s.len() && s[i].is_ascii_whitespace() {
        i += 1;
    }
    i
}

/// Parses a path (with `{…}` groups) starting at `i` after `prefix`, collecting every full
/// path it names into `out`.
fn parse_path(s: &[u8], mut i: usize, prefix: Vec<String>, out: &mut Vec<Vec<String>>) -> usize {
    let mut path = prefix;
    loop {
        i = skip_space(s, i);
        if i < s.len() && s[i] == b'{' {
            i += 1;
            loop {
                i = skip_space(s, i);
                if i < s.len() && s[i] == b'}' {
                    return i + 1;
                }
                i = parse_path(s, i, path.clone(), out);
                i = skip_space(s, i);
                if i < s.len() && s[i] == b',' {
                    i += 1;
                } else if i < s.len() && s[i] == b'}' {
                    return i + 1;
                } else {
                    return i;
                }
            }
        }
        match ident_at(s, i) {
            Some((id, j)) => {
                path.push(id);
                i = j;
            }
            None => {
                if i < s.len() && s[i] == b'*' {
                    i += 1;
                }
                out.push(path);
                return i;
            }
        }
        let k = skip_space(s, i);
        if s[k..].starts_with(b"::") {
            i = k + 2;
        } else {
            out.push(path);
            return i;
        }
    }
}

/// Every path rooted at `crate`, `super` or `self` in `code`, made absolute from `module`.
fn referenced_paths(code: &str, module: &[String]) -> Vec<Vec<String>> {
    let s = code.as_bytes();
    let mut found = Vec::new();
    for root in ["crate", "super", "self"] {
        let pat = format!("{root}::");
        let mut from = 0;
        while let Some(k) = code[from..].find(&pat) {
            let at = from + k;
            from = at + pat.len();
            if at > 0 && (s[at - 1].is_ascii_alphanumeric() || s[at - 1] == b'_' || s[at - 1] == b':') {
                continue;
            }
            let mut base: Vec<String> = match root {
                "crate" => Vec::new(),
                "self" => module.to_vec(),
                _ => module[..module.len().saturating_sub(1)].to_vec(),
            };
            let mut i = from;
            // super::super::…
            while code[i..].starts_with("super::") {
                base.pop();
                i += "super::".len();
            }
            let mut paths = Vec::new();
            parse_path(s, i, base, &mut paths);
            found.extend(paths);
        }
    }
    found
}

/// The longest prefix of `path` that is a module.
fn resolve(path: &[String], modules: &BTreeSet<Vec<String>>) -> Vec<String> {
    (0..=path.len()).rev().map(|n| path[..n].to_vec()).find(|p| modules.contains(p)).unwrap_or_default()
}

/// The use graph: module → modules it uses (itself excluded).
fn use_graph() -> BTreeMap<Vec<String>, BTreeSet<Vec<String>>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let bin = src.join("bin");
    files.retain(|f| !f.starts_with(&bin));
    let mut code_of = BTreeMap::new();
    let mut test_only = BTreeSet::new();
    for f in &files {
        let module = module_of(&src, f);
        let (code, tests) = test_items(&code_only(&std::fs::read_to_string(f).unwrap()));
        test_only.extend(tests.into_iter().map(|t| [module.clone(), vec![t]].concat()));
        code_of.insert(module, code);
    }
    // Files of test modules, and their own children, are tests too.
    code_of.retain(|m, _| !(1..=m.len()).any(|n| test_only.contains(&m[..n])));
    let modules: BTreeSet<Vec<String>> = code_of.keys().cloned().collect();
    let mut graph = BTreeMap::new();
    for (module, code) in code_of {
        let used: BTreeSet<Vec<String>> = referenced_paths(&code, &module)
            .iter()
            .map(|p| resolve(p, &modules))
            .filter(|m| *m != module && !m.is_empty())
            .collect();
        graph.insert(module, used);
    }
    graph
}

fn name(m: &[String]) -> String {
    if m.is_empty() { "crate".into() } else { m.join("::") }
}

#[test]
fn every_module_uses_only_lower_layers() {
    let graph = use_graph();
    let rank = |m: &[String]| LAYERS.iter().position(|l| m.first().is_some_and(|f| f == l));
    let mut wrong = Vec::new();
    for (m, used) in &graph {
        if m.is_empty() {
            continue; // lib.rs declares the layers.
        }
        let Some(mine) = rank(m) else {
            wrong.push(format!("{} is in no layer: add it to LAYERS and docs/architecture.md", name(m)));
            continue;
        };
        for u in used {
            match rank(u) {
                Some(theirs) if theirs <= mine => {}
                _ => wrong.push(format!("{} uses {}, which is not below it", name(m), name(u))),
            }
        }
    }
    assert!(wrong.is_empty(), "layering broken:\n{}", wrong.join("\n"));
}

#[test]
fn no_module_cycles() {
    let graph = use_graph();
    // Depth-first search for a back edge, reporting the cycle it closes.
    fn visit(
        m: &Vec<String>,
        graph: &BTreeMap<Vec<String>, BTreeSet<Vec<String>>>,
        state: &mut BTreeMap<Vec<String>, u8>,
        stack: &mut Vec<Vec<String>>,
    ) -> Option<Vec<Vec<String>>> {
        state.insert(m.clone(), 1);
        stack.push(m.clone());
        for u in graph.get(m).into_iter().flatten() {
            match state.get(u).copied().unwrap_or(0) {
                1 => {
                    let from = stack.iter().position(|x| x == u).unwrap();
                    let mut cycle = stack[from..].to_vec();
                    cycle.push(u.clone());
                    return Some(cycle);
                }
                0 => {
                    if let Some(c) = visit(u, graph, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(m.clone(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for m in graph.keys() {
        if state.get(m).copied().unwrap_or(0) == 0
            && let Some(cycle) = visit(m, &graph, &mut state, &mut Vec::new())
        {
            let text: Vec<String> = cycle.iter().map(|m| name(m)).collect();
            panic!("module cycle: {}", text.join(" → "));
        }
    }
}

/// The checker itself finds what it must: paths in groups, `super`, inline paths, and
/// nothing inside comments, strings or test items.
#[test]
fn the_checker_reads_paths_as_rustc_does() {
    let code = r#"
use crate::a::{b::C, d, e::{f, G}};
use super::h::I;
// use crate::commented::Out;
let s = "crate::in_string::Out";
fn x() { crate::inline::f(); self::child::g(); }
#[cfg(test)]
mod tests { use crate::only_in_tests::T; }
"#;
    let code = without_test_items(&code_only(code));
    let module = vec!["m".to_string(), "n".to_string()];
    let mut got: Vec<String> = referenced_paths(&code, &module).iter().map(|p| p.join("::")).collect();
    got.sort();
    assert_eq!(got, ["a::b::C", "a::d", "a::e::G", "a::e::f", "inline::f", "m::h::I", "m::n::child::g"]);
}
