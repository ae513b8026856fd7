//! The architecture's invariants (docs/ARCHITECTURE.md), checked on the sources:
//!
//! - each crate depends only on the floors below it: the physics stages (hydro -> surface ->
//!   sensors) on the ones before them, learn and products on no physics, fusion on no
//!   deep-learning framework, burn only through learn and GDAL only through products;
//! - no crate's modules import each other in a cycle;
//! - the report only renders: it imports no physics, trains and scans nothing;
//! - the binary only parses, calls and prints, in under 800 lines.

mod common;

use common::{sources, workspace};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The `[dependencies]` of a crate's Cargo.toml (not its dev-dependencies).
fn dependencies(krate: &str) -> BTreeSet<String> {
    let path = workspace().join("crates").join(krate).join("Cargo.toml");
    let text = std::fs::read_to_string(&path).expect("readable Cargo.toml");
    let manifest: toml::Table = text.parse().expect("valid Cargo.toml");
    manifest
        .get("dependencies")
        .and_then(|d| d.as_table())
        .map(|d| d.keys().cloned().collect())
        .unwrap_or_default()
}

fn crates() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(workspace().join("crates"))
        .expect("crates/")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|n| workspace().join("crates").join(n).join("Cargo.toml").exists())
        .collect();
    names.sort();
    names
}

#[test]
fn each_crate_depends_only_on_the_floors_below_it() {
    // the wakelab crates each crate may use (study and the binary join everything)
    let allowed: BTreeMap<&str, &[&str]> = BTreeMap::from([
        ("core", &[][..]),
        ("schema", &["core"][..]),
        ("hydro", &["core"][..]),
        ("surface", &["core", "hydro"][..]),
        ("sensors", &["core", "hydro", "surface"][..]),
        ("dataset", &["core", "schema", "hydro", "surface", "sensors"][..]),
        ("products", &["core", "schema"][..]),
        ("learn", &["core", "schema"][..]),
        ("fusion", &["core", "schema"][..]),
        ("ships", &[][..]),
    ]);
    let mut wrong = Vec::new();
    for krate in crates() {
        let deps = dependencies(&krate);
        if let Some(allowed) = allowed.get(krate.as_str()) {
            for dep in deps.iter().filter_map(|d| d.strip_prefix("wakelab-")) {
                if !allowed.contains(&dep) {
                    wrong.push(format!("{krate} depends on wakelab-{dep}"));
                }
            }
        }
        // burn only through learn, GDAL only through products
        if krate != "learn" && deps.contains("burn") {
            wrong.push(format!("{krate} depends on burn directly"));
        }
        if krate != "products" && deps.iter().any(|d| d.starts_with("gdal")) {
            wrong.push(format!("{krate} depends on GDAL directly"));
        }
    }
    assert!(
        allowed.keys().all(|k| crates().iter().any(|c| c == k)),
        "a crate was renamed"
    );
    assert!(wrong.is_empty(), "{wrong:#?}");
}

/// A crate's modules ("" the crate root, "steps::whole_scene") and their files.
fn modules(src: &Path) -> BTreeMap<String, PathBuf> {
    let mut files = Vec::new();
    sources(src, &mut files);
    files
        .into_iter()
        .map(|f| {
            let rel = f.strip_prefix(src).expect("inside src").with_extension("");
            let mut parts: Vec<String> = rel.iter().map(|p| p.to_string_lossy().into_owned()).collect();
            if matches!(parts.last().map(String::as_str), Some("mod" | "lib" | "main")) {
                parts.pop();
            }
            (parts.join("::"), f)
        })
        .collect()
}

/// A source without its test module and its comments (doc links are not imports).
fn code_of(path: &Path) -> String {
    let text = std::fs::read_to_string(path).expect("readable source");
    let text = text.split("#[cfg(test)]").next().unwrap_or_default();
    text.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The paths `prefix` is followed by in `code` ("crate::a::b::C" gives "a::b::C").
fn paths_after<'a>(code: &'a str, prefix: &str) -> Vec<&'a str> {
    code.match_indices(prefix)
        .filter(|(at, _)| !code[..*at].ends_with(|c: char| c.is_alphanumeric() || c == '_' || c == ':'))
        .map(|(at, _)| {
            let rest = &code[at + prefix.len()..];
            let end = rest
                .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
                .unwrap_or(rest.len());
            &rest[..end]
        })
        .collect()
}

/// The longest module of `modules` that `path` (segments from a module) starts with.
fn module_of(modules: &BTreeMap<String, PathBuf>, segments: &[&str]) -> Option<String> {
    (1..=segments.len())
        .rev()
        .map(|k| segments[..k].join("::"))
        .find(|m| modules.contains_key(m))
}

/// `module`'s name within `parent` if it is a direct submodule of it.
fn child_of<'a>(parent: &str, module: &'a str) -> Option<&'a str> {
    let rest = if parent.is_empty() {
        module
    } else {
        module.strip_prefix(parent)?.strip_prefix("::")?
    };
    (!rest.is_empty() && !rest.contains("::")).then_some(rest)
}

/// Which modules of the crate at `src` each module imports (through `crate::`, `super::` or a
/// parent's own submodule).
fn import_graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let modules = modules(src);
    let mut graph = BTreeMap::new();
    for (name, file) in &modules {
        let code = code_of(file);
        let here: Vec<&str> = if name.is_empty() {
            Vec::new()
        } else {
            name.split("::").collect()
        };
        let mut edges = BTreeSet::new();
        for path in paths_after(&code, "crate::") {
            let segments: Vec<&str> = path.split("::").filter(|s| !s.is_empty()).collect();
            edges.extend(module_of(&modules, &segments));
        }
        let parent = &here[..here.len().saturating_sub(1)];
        for path in paths_after(&code, "super::") {
            let mut segments = parent.to_vec();
            segments.extend(path.split("::").filter(|s| !s.is_empty()));
            edges.extend(module_of(&modules, &segments));
        }
        // a module's own submodules, named bare ("whole_scene::scan_step")
        for other in modules.keys() {
            if let Some(leaf) = child_of(name, other) {
                if !paths_after(&code, &format!("{leaf}::")).is_empty() {
                    edges.insert(other.clone());
                }
            }
        }
        edges.remove(name);
        graph.insert(name.clone(), edges);
    }
    graph
}

/// The strongly connected components of more than one module (Tarjan).
fn cycles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct State<'a> {
        graph: &'a BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on_stack: BTreeSet<&'a str>,
        found: Vec<Vec<String>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a str) {
        let n = s.index.len();
        s.index.insert(v, n);
        s.low.insert(v, n);
        s.stack.push(v);
        s.on_stack.insert(v);
        for w in &s.graph[v] {
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
    let mut state = State {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        found: Vec::new(),
    };
    for v in graph.keys() {
        if !state.index.contains_key(v.as_str()) {
            visit(&mut state, v);
        }
    }
    state.found
}

#[test]
fn the_cycle_finder_finds_a_cycle() {
    let graph: BTreeMap<String, BTreeSet<String>> = [
        ("a", &["b"][..]),
        ("b", &["c"][..]),
        ("c", &["a"][..]),
        ("d", &["a"][..]),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v.iter().map(|s| s.to_string()).collect()))
    .collect();
    assert_eq!(cycles(&graph), vec![vec!["a".to_string(), "b".into(), "c".into()]]);
    assert_eq!(paths_after("use crate::a::B; x::crate::no", "crate::"), vec!["a::B"]);
}

#[test]
fn no_crate_imports_its_own_modules_in_a_cycle() {
    let mut found = Vec::new();
    for krate in crates() {
        let src = workspace().join("crates").join(&krate).join("src");
        found.extend(
            cycles(&import_graph(&src))
                .into_iter()
                .map(|c| format!("{krate}: {c:?}")),
        );
    }
    assert!(found.is_empty(), "modules importing each other in a cycle: {found:#?}");
}

#[test]
fn the_report_only_renders() {
    // what the report may read: configuration and I/O, the schema, the study file's and the
    // results' types, and the scene's grid (where a pixel lies); no physics, training or scanning
    let allowed = [
        "wakelab_core::",
        "wakelab_schema::",
        "wakelab_dataset::study",
        "wakelab_dataset::learning",
        "wakelab_learn::calibration::ReliabilityBin",
        "wakelab_learn::evaluate",
        "wakelab_learn::masks",
        "wakelab_learn::models",
        "wakelab_surface::scene",
    ];
    let dir = workspace().join("crates/study/src/report");
    let mut wrong = Vec::new();
    for (_, file) in modules(&dir) {
        let code = code_of(&file);
        for (at, _) in code.match_indices("wakelab_") {
            if code[..at].ends_with(|c: char| c.is_alphanumeric() || c == '_' || c == '.') {
                continue;
            }
            let rest = &code[at..];
            let path: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                .collect();
            if path.contains("::") && !allowed.iter().any(|a| path.starts_with(a)) {
                wrong.push(format!("{}: {path}", file.display()));
            }
        }
        for call in [
            "render_pair(",
            "simulate_surface(",
            "hydro_map(",
            "detect_image(",
            "evaluate(",
            "train_",
        ] {
            if code.contains(call) {
                wrong.push(format!("{}: calls {call}", file.display()));
            }
        }
    }
    assert!(wrong.is_empty(), "the report computes: {wrong:#?}");
}

#[test]
fn the_binary_stays_thin() {
    let src = workspace().join("crates/wakelab/src");
    let lines: usize = modules(&src)
        .values()
        .map(|f| std::fs::read_to_string(f).expect("readable").lines().count())
        .sum();
    assert!(
        lines < 800,
        "the binary has {lines} lines; move logic into the library crates"
    );
    // the binary calls the stages through the study crate and prints; it trains nothing itself
    for (_, file) in modules(&src) {
        let code = code_of(&file);
        for call in [
            "evaluate(",
            "train_detector(",
            "render_pair(",
            "simulate_surface(",
            "scan_product(",
        ] {
            assert!(!code.contains(call), "{} calls {call}", file.display());
        }
    }
}
