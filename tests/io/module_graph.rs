//! The crate's top-level modules form no import cycle (issue 57: the layers a newcomer reads
//! bottom-up are geometry, sparse, vi, mesh, model, contact, body, ..., world, output, scene,
//! cli).
//!
//! The graph: module `a` uses module `b` when a code line (comment lines skipped) of a file of
//! `a` (`src/a.rs` or under `src/a/`) names `crate::b`. Test code counts too, so a test module
//! cannot hide a cycle. The leaf `crate::sparse` (`src/sparse/`) names no `crate::` path, which
//! the second test checks. Expected: zero
//! strongly connected sets of more than one module (Tarjan's algorithm), an exact count.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// `crate::NAME` references of the code lines of `text`.
fn references(text: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for line in text.lines().map(str::trim_start).filter(|l| !l.starts_with("//")) {
        let code = line.split("//").next().unwrap_or("");
        for (i, _) in code.match_indices("crate::") {
            let name: String =
                code[i + 7..].chars().take_while(|c| c.is_ascii_lowercase() || *c == '_').collect();
            if !name.is_empty() {
                out.insert(name);
            }
        }
    }
    out
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
        let path = entry.unwrap_or_else(|e| panic!("{e}")).path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Top-level module -> the other top-level modules it names.
fn graph() -> BTreeMap<String, BTreeSet<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut modules = BTreeMap::<String, BTreeSet<String>>::new();
    for entry in std::fs::read_dir(&src).unwrap_or_else(|e| panic!("{e}")) {
        let path = entry.unwrap_or_else(|e| panic!("{e}")).path();
        let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or_default().to_string();
        if name == "lib" || name == "main" {
            continue;
        }
        let mut files = Vec::new();
        if path.is_dir() {
            rust_files(&path, &mut files);
        } else {
            files.push(path);
        }
        let uses = modules.entry(name.clone()).or_default();
        for file in files {
            uses.extend(references(&read(&file)).into_iter().filter(|m| *m != name));
        }
    }
    modules
}

/// The strongly connected sets of more than one module (Tarjan).
fn cycles(g: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct Walk<'a> {
        g: &'a BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        found: Vec<Vec<String>>,
    }
    fn visit<'a>(w: &mut Walk<'a>, v: &'a str) {
        let i = w.index.len();
        w.index.insert(v, i);
        w.low.insert(v, i);
        w.stack.push(v);
        for u in w.g.get(v).into_iter().flatten() {
            let u = u.as_str();
            if !w.index.contains_key(u) {
                visit(w, u);
                let l = w.low[v].min(w.low[u]);
                w.low.insert(v, l);
            } else if w.stack.contains(&u) {
                let l = w.low[v].min(w.index[u]);
                w.low.insert(v, l);
            }
        }
        if w.low[v] == w.index[v] {
            let at = w.stack.iter().rposition(|&x| x == v).unwrap_or(0);
            let set: Vec<String> = w.stack.drain(at..).map(String::from).collect();
            if set.len() > 1 {
                w.found.push(set);
            }
        }
    }
    let mut w =
        Walk { g, index: BTreeMap::new(), low: BTreeMap::new(), stack: Vec::new(), found: Vec::new() };
    for v in g.keys() {
        if !w.index.contains_key(v.as_str()) {
            visit(&mut w, v);
        }
    }
    w.found
}

#[test]
fn top_level_modules_form_no_cycle() {
    let g = graph();
    let listing: Vec<String> = g
        .iter()
        .map(|(m, uses)| format!("{m} -> {}", uses.iter().cloned().collect::<Vec<_>>().join(", ")))
        .collect();
    assert_eq!(cycles(&g), Vec::<Vec<String>>::new(), "module graph:\n{}", listing.join("\n"));
    // the detector itself: a two-module cycle added to the graph is found
    let mut bad = g.clone();
    bad.entry("geometry".into()).or_default().insert("world".into());
    assert!(!cycles(&bad).is_empty(), "geometry -> world -> geometry not found");
}

#[test]
fn the_sparse_leaf_names_no_other_module() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    for file in ["sparse/mod.rs", "sparse/factor.rs", "sparse/inverse.rs"] {
        assert_eq!(references(&read(&root.join(file))), BTreeSet::new(), "{file}");
    }
}
