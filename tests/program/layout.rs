//! The house rules of the source tree (issue 31, docs/ARCHITECTURE.md), read from the
//! sources themselves:
//! - study/'s files import each other without a cycle: a helper two of them share goes
//!   below both;
//! - no source file is over 1,000 lines before its test module;
//! - study/ reads and writes results through the typed schema of `results/`: no untyped
//!   JSON (`serde_json::Value`) in its code.
//!
//! An import is a path to another module of the crate in code (`crate::a::b`, `super::c`),
//! comments and test modules left out; it counts toward the module the path names, the
//! longest prefix that is a file of the tree (a type re-exported by a folder's `mod.rs`
//! counts toward that `mod.rs`).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The largest source file, in lines before its `#[cfg(test)]` module.
const MAX_LINES: usize = 1000;

/// Every `.rs` file under `dir`, by module path (`study::compare::matching`; a `mod.rs`
/// is its folder's module).
fn modules(root: &Path, dir: &Path, out: &mut BTreeMap<String, PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            modules(root, &path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let rel = path.strip_prefix(root).unwrap().with_extension("");
            let mut parts: Vec<String> = rel
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            if matches!(
                parts.last().map(String::as_str),
                Some("mod" | "lib" | "main")
            ) {
                parts.pop();
            }
            out.insert(parts.join("::"), path);
        }
    }
}

/// A file's text before its test module (`#[cfg(test)]`, then any attributes and comments,
/// then `mod tests`): a test-only helper module declared higher up (`#[cfg(test)] mod
/// test_support;`) does not end the code.
fn before_tests(text: &str) -> &str {
    let lines: Vec<(usize, &str)> = text
        .split_inclusive('\n')
        .scan(0, |at, l| {
            let start = *at;
            *at += l.len();
            Some((start, l.trim_end()))
        })
        .collect();
    for (k, &(start, line)) in lines.iter().enumerate() {
        if line != "#[cfg(test)]" {
            continue;
        }
        let next = lines[k + 1..]
            .iter()
            .map(|(_, l)| l.trim_start())
            .find(|l| !(l.starts_with("//") || l.starts_with("#[")));
        if next.is_some_and(|l| l.starts_with("mod tests")) {
            return &text[..start];
        }
    }
    text
}

/// A file's code: before its test module, without comments.
fn code(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    before_tests(&text)
        .lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The module paths `code` names after `prefix` (`crate::` or `super::`), each a
/// `::`-separated run of lower-case identifiers.
fn paths_after<'a>(code: &'a str, prefix: &'a str) -> impl Iterator<Item = Vec<&'a str>> + 'a {
    code.match_indices(prefix).filter_map(move |(at, _)| {
        // `super::` inside `crate::a::super::`-like text does not occur; a preceding
        // identifier character means another word (e.g. `my_crate::`).
        let before = code[..at].chars().next_back();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            return None;
        }
        let rest = &code[at + prefix.len()..];
        let mut parts = Vec::new();
        let mut tail = rest;
        loop {
            let end = tail
                .find(|c: char| !(c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_'))
                .unwrap_or(tail.len());
            if end == 0 {
                break;
            }
            parts.push(&tail[..end]);
            match tail[end..].strip_prefix("::") {
                Some(next) => tail = next,
                None => break,
            }
        }
        (!parts.is_empty()).then_some(parts)
    })
}

/// The longest prefix of `parts` that is a module of the tree.
fn resolve(modules: &BTreeMap<String, PathBuf>, parts: &[&str]) -> Option<String> {
    (1..=parts.len())
        .rev()
        .map(|k| parts[..k].join("::"))
        .find(|m| modules.contains_key(m))
}

/// The import graph among the crate's modules.
fn imports(modules: &BTreeMap<String, PathBuf>) -> BTreeMap<String, BTreeSet<String>> {
    let mut graph = BTreeMap::new();
    for (name, path) in modules {
        let code = code(path);
        let mut to = BTreeSet::new();
        for parts in paths_after(&code, "crate::") {
            to.extend(resolve(modules, &parts));
        }
        // `super::` is relative to the module's parent.
        let own: Vec<&str> = name.split("::").filter(|p| !p.is_empty()).collect();
        let parent = &own[..own.len().saturating_sub(1)];
        for parts in paths_after(&code, "super::") {
            let full: Vec<&str> = parent.iter().copied().chain(parts).collect();
            to.extend(resolve(modules, &full));
        }
        to.remove(name);
        graph.insert(name.clone(), to);
    }
    graph
}

/// The strongly connected components of more than one module among `nodes` (Tarjan).
fn cycles(
    graph: &BTreeMap<String, BTreeSet<String>>,
    nodes: &BTreeSet<String>,
) -> Vec<Vec<String>> {
    struct State<'a> {
        graph: &'a BTreeMap<String, BTreeSet<String>>,
        nodes: &'a BTreeSet<String>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on_stack: BTreeSet<&'a str>,
        found: Vec<Vec<String>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a str) {
        let i = s.index.len();
        s.index.insert(v, i);
        s.low.insert(v, i);
        s.stack.push(v);
        s.on_stack.insert(v);
        for w in &s.graph[v] {
            if !s.nodes.contains(w) {
                continue;
            }
            let w = w.as_str();
            if !s.index.contains_key(w) {
                visit(s, w);
                let low = s.low[v].min(s.low[w]);
                s.low.insert(v, low);
            } else if s.on_stack.contains(w) {
                let low = s.low[v].min(s.index[w]);
                s.low.insert(v, low);
            }
        }
        if s.low[v] == s.index[v] {
            let mut component = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack.remove(w);
                component.push(w.to_string());
                if w == v {
                    break;
                }
            }
            if component.len() > 1 {
                component.sort();
                s.found.push(component);
            }
        }
    }
    let mut s = State {
        graph,
        nodes,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        found: Vec::new(),
    };
    for v in nodes {
        if !s.index.contains_key(v.as_str()) {
            visit(&mut s, v);
        }
    }
    s.found
}

fn source_tree() -> (
    BTreeMap<String, PathBuf>,
    BTreeMap<String, BTreeSet<String>>,
) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut m = BTreeMap::new();
    modules(&root, &root, &mut m);
    let g = imports(&m);
    (m, g)
}

#[test]
fn study_files_import_each_other_without_a_cycle() {
    let (modules, graph) = source_tree();
    // The folder modules' own `mod.rs` re-export their files: `study` itself is the
    // layer's front door (`crate::study::StudyError`), not one of its rooms.
    let study: BTreeSet<String> = modules
        .keys()
        .filter(|m| m.starts_with("study::"))
        .cloned()
        .collect();
    assert!(study.len() > 40, "the study layer's files: {study:?}");
    let found = cycles(&graph, &study);
    assert!(
        found.is_empty(),
        "import cycles among study/'s files: {found:?}"
    );
}

/// The check sees a cycle where there is one: a synthetic graph, and the real graph with one
/// edge added from a low helper to a command that uses it.
#[test]
fn the_cycle_check_finds_a_cycle() {
    let edge = |a: &str, b: &[&str]| (a.to_string(), b.iter().map(|s| s.to_string()).collect());
    let graph: BTreeMap<String, BTreeSet<String>> = [
        edge("a", &["b"]),
        edge("b", &["c"]),
        edge("c", &["a", "d"]),
        edge("d", &[]),
    ]
    .into_iter()
    .collect();
    let nodes: BTreeSet<String> = graph.keys().cloned().collect();
    assert_eq!(cycles(&graph, &nodes), [["a", "b", "c"]]);
    let (modules, mut graph) = source_tree();
    assert!(
        graph["study::sweep"].contains("study::staging"),
        "{:?}",
        graph["study::sweep"]
    );
    graph
        .get_mut("study::staging")
        .unwrap()
        .insert("study::sweep".into());
    let study: BTreeSet<String> = modules
        .keys()
        .filter(|m| m.starts_with("study::"))
        .cloned()
        .collect();
    let found = cycles(&graph, &study);
    assert!(
        found
            .iter()
            .any(|c| c.contains(&"study::sweep".to_string())),
        "{found:?}"
    );
    // A path in a comment or a test module is no import.
    let code = "use crate::a::b; // crate::c::d\nfn f() { super::e::g(); }";
    let stripped = code
        .lines()
        .map(|l| l.split("//").next().unwrap())
        .collect::<Vec<_>>()
        .join("\n");
    let seen: Vec<Vec<&str>> = paths_after(&stripped, "crate::").collect();
    assert_eq!(seen, [vec!["a", "b"]]);
    let text = "#[cfg(test)]\nmod support;\nuse crate::x;\n#[cfg(test)]\nmod tests {}\n";
    assert_eq!(
        before_tests(text),
        "#[cfg(test)]\nmod support;\nuse crate::x;\n"
    );
}

#[test]
fn no_source_file_is_over_a_thousand_lines_before_its_tests() {
    let (modules, _) = source_tree();
    let long: Vec<(String, usize)> = modules
        .values()
        .map(|path| {
            let text = std::fs::read_to_string(path).unwrap();
            let lines = before_tests(&text).lines().count();
            (path.display().to_string(), lines)
        })
        .filter(|(_, n)| *n > MAX_LINES)
        .collect();
    assert!(long.is_empty(), "over {MAX_LINES} lines: {long:?}");
}

/// The commands read sweep.json, cea.json and compare.json as types: a field renamed in the
/// writer is a compile error in every reader, not a report cell turned into "-". The one
/// untyped read left is the migration of older files, in `results/`.
#[test]
fn study_reads_results_only_through_the_typed_schema() {
    let (modules, _) = source_tree();
    let untyped: Vec<&String> = modules
        .iter()
        .filter(|(m, path)| {
            let code = code(path);
            m.starts_with("study")
                && (code.contains("json!(")
                    || code
                        .lines()
                        .any(|l| l.contains("serde_json") && l.contains("Value")))
        })
        .map(|(m, _)| m)
        .collect();
    assert!(untyped.is_empty(), "untyped JSON in {untyped:?}");
    // The check sees it where it is: the migration in results/ holds one.
    assert!(code(&modules["results"]).contains("serde_json::Value"));
}
