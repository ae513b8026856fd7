//! Spec traceability: every equation the spec's map (spec README, "Map") assigns to a stage is
//! cited, in the one form `Eq. (N.M)` / `Eqs. (N.M)-(N.K)`, somewhere in that stage's crates, and
//! no source cites the spec's equations in another form; and `docs/spec-map.md`, the map from
//! each equation to the functions that cite it, is the one these citations generate
//! (`WAKELAB_BLESS=1 cargo test -p wakelab-study --test spec_traceability` rewrites it).

mod common;

use common::{sources, workspace};
use std::collections::BTreeSet;

/// Equations (chapter, first, last) of a stage.
type Equations = &'static [(u32, u32, u32)];

/// The stages of the spec's map, their crates and the equations the map gives them.
const STAGES: [(&str, &[&str], Equations); 5] = [
    (
        "hydrodynamics",
        &["hydro"],
        &[(2, 1, 1), (2, 4, 14), (2, 15, 21), (2, 22, 25), (2, 26, 62)],
    ),
    ("ocean surface", &["surface"], &[(2, 66, 69), (2, 71, 76)]),
    ("sensors", &["sensors"], &[(3, 1, 21)]),
    ("learning", &["learn", "schema"], &[(4, 3, 3)]),
    ("fusion", &["fusion"], &[(5, 1, 6)]),
];

/// Equation numbers (chapter, number) a text cites as `Eq. (N.M)` or `Eqs. (a), (b)-(c) and (d)`.
fn citations(text: &str) -> BTreeSet<(u32, u32)> {
    let mut found = BTreeSet::new();
    for (start, _) in text.match_indices("Eq") {
        let rest = &text[start..];
        let Some(rest) = rest.strip_prefix("Eqs. ").or_else(|| rest.strip_prefix("Eq. ")) else {
            continue;
        };
        let mut rest = rest;
        let mut previous: Option<(u32, u32)> = None;
        let mut range = false;
        while let Some((number, after)) = parenthesised_number(rest) {
            if let (true, Some((c, a))) = (range, previous) {
                if c == number.0 {
                    found.extend((a..=number.1).map(|n| (c, n)));
                }
            }
            found.insert(number);
            previous = Some(number);
            range = after.starts_with('-');
            rest = ["-", ", ", " and "]
                .iter()
                .find_map(|sep| after.strip_prefix(sep))
                .unwrap_or("");
        }
    }
    found
}

/// "(2.44)..." -> ((2, 44), "...").
fn parenthesised_number(text: &str) -> Option<((u32, u32), &str)> {
    let inner = text.strip_prefix('(')?;
    let close = inner.find(')')?;
    let (chapter, number) = inner[..close].split_once('.')?;
    Some(((chapter.parse().ok()?, number.parse().ok()?), &inner[close + 1..]))
}

#[test]
fn the_citation_reader_reads_ranges_and_lists() {
    let cited = citations("see Eqs. (2.7), (2.22)-(2.24) and (3.1); Eq. (4.3).");
    let expected: BTreeSet<(u32, u32)> = [(2, 7), (2, 22), (2, 23), (2, 24), (3, 1), (4, 3)].into();
    assert_eq!(cited, expected);
    assert!(citations("Eq. 2.4 and KHCC03 Eq. 56").is_empty());
}

#[test]
fn every_mapped_equation_is_cited_in_its_stage() {
    let mut missing = Vec::new();
    for (stage, crates, ranges) in STAGES {
        let mut files = Vec::new();
        for c in crates {
            sources(&workspace().join("crates").join(c).join("src"), &mut files);
        }
        let cited: BTreeSet<(u32, u32)> = files
            .iter()
            .flat_map(|f| citations(&std::fs::read_to_string(f).expect("readable source")))
            .collect();
        for &(chapter, first, last) in ranges {
            for n in first..=last {
                if !cited.contains(&(chapter, n)) {
                    missing.push(format!("{stage}: Eq. ({chapter}.{n})"));
                }
            }
        }
    }
    assert!(missing.is_empty(), "not cited: {missing:?}");
}

#[test]
fn the_spec_is_cited_in_one_form() {
    let mut files = Vec::new();
    sources(&workspace().join("crates"), &mut files);
    let mut other = Vec::new();
    // this file names the wrong form in its own examples
    files.retain(|f| !f.ends_with("spec_traceability.rs"));
    for f in files {
        let text = std::fs::read_to_string(&f).expect("readable source");
        for (i, line) in text.lines().enumerate() {
            // "Eq. 2.4" without parentheses (a spec number has one dot; "Eq. 3.10.2" of another
            // source has two and is left alone)
            for (at, _) in line.match_indices("Eq") {
                let rest = &line[at..];
                let Some(rest) = rest.strip_prefix("Eqs. ").or_else(|| rest.strip_prefix("Eq. ")) else {
                    continue;
                };
                let token: String = rest.chars().take_while(|c| c.is_ascii_digit() || *c == '.').collect();
                let token = token.trim_end_matches('.');
                if token.matches('.').count() == 1 && !token.starts_with('.') {
                    other.push(format!("{}:{}", f.display(), i + 1));
                }
            }
        }
    }
    assert!(other.is_empty(), "write spec equations as `Eq. (N.M)`: {other:?}");
}

/// The item a line of a source belongs to: the item a doc comment (`///`) documents, the module
/// of a module comment (`//!`), else the function around the line; None in test code.
fn items_of(text: &str) -> Vec<Option<String>> {
    let lines: Vec<&str> = text.lines().collect();
    let mut items = vec![None; lines.len()];
    let mut enclosing: Option<String> = None;
    let mut in_tests = false;
    for (i, line) in lines.iter().enumerate() {
        let trimmed = line.trim_start();
        if trimmed.starts_with("#[cfg(test)]") {
            in_tests = true;
        }
        if in_tests {
            continue;
        }
        if let Some(name) = item_name(trimmed).filter(|n| n.starts_with("fn ")) {
            enclosing = Some(name);
        }
        items[i] = if trimmed.starts_with("//!") {
            Some("module".into())
        } else if trimmed.starts_with("///") {
            lines[i + 1..]
                .iter()
                .map(|l| l.trim_start())
                .find(|l| !l.starts_with("///") && !l.starts_with("#["))
                .and_then(item_name)
        } else {
            item_name(trimmed).or_else(|| enclosing.clone())
        };
    }
    items
}

/// "pub(crate) fn foo(..." -> "fn foo"; "pub struct Bar {" -> "struct Bar"; a field "pub rate: f64,"
/// -> "field rate"; None for any other line.
fn item_name(line: &str) -> Option<String> {
    let mut words = line.split_whitespace().peekable();
    while let Some(w) = words.peek() {
        if w.starts_with("pub")
            || ["const", "unsafe", "async", "extern"].contains(w) && words.clone().nth(1).is_some_and(|n| n == "fn")
        {
            words.next();
        } else {
            break;
        }
    }
    let kind = words.next()?;
    let name = words.next()?;
    let ident: String = name.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
    match kind {
        "fn" | "struct" | "enum" | "const" | "static" | "type" | "trait" | "mod" if !ident.is_empty() => {
            Some(format!("{kind} {ident}"))
        }
        "impl" => Some(format!(
            "impl {}",
            line.split_whitespace()
                .skip_while(|w| *w != "impl")
                .nth(1)?
                .trim_end_matches('{')
        )),
        k if k.ends_with(':') && !k.contains("::") && k.len() > 1 => Some(format!("field {}", k.trim_end_matches(':'))),
        _ => None,
    }
}

/// The spec map: every cited equation with the files and items that cite it, as Markdown.
fn spec_map() -> String {
    let root = workspace();
    let mut files = Vec::new();
    sources(&root.join("crates"), &mut files);
    files.retain(|f| f.components().any(|c| c.as_os_str() == "src"));
    files.sort();
    let mut rows: BTreeSet<((u32, u32), String, String)> = BTreeSet::new();
    for f in &files {
        let text = std::fs::read_to_string(f).expect("readable source");
        let items = items_of(&text);
        let rel = f
            .strip_prefix(&root)
            .expect("inside the workspace")
            .display()
            .to_string();
        for (line, item) in text.lines().zip(items) {
            let Some(item) = item else { continue };
            for number in citations(line) {
                rows.insert((number, rel.clone(), item.clone()));
            }
        }
    }
    let mut map = String::from(
        "# Spec map: equation -> code\n\n\
         Every equation of the spec (`../shared/spec/`) that the code cites as `Eq. (N.M)`, with the file and \
         the item (function, type, constant, field or module comment) that cites it. Generated from the \
         citations by `crates/study/tests/spec_traceability.rs`, which fails when this file is stale; \
         rewrite it with `WAKELAB_BLESS=1 cargo test -p wakelab-study --test spec_traceability`.\n\n\
         | equation | file | item |\n| --- | --- | --- |\n",
    );
    for ((chapter, number), file, item) in rows {
        map.push_str(&format!("| ({chapter}.{number}) | `{file}` | `{item}` |\n"));
    }
    map
}

#[test]
fn the_item_reader_names_functions_types_and_fields() {
    assert_eq!(
        item_name("pub(crate) fn stokes_drift(k: f64) -> f64 {").as_deref(),
        Some("fn stokes_drift")
    );
    assert_eq!(
        item_name("pub struct SeaSpectrum {").as_deref(),
        Some("struct SeaSpectrum")
    );
    assert_eq!(item_name("    pub rate: f64,").as_deref(), Some("field rate"));
    assert_eq!(item_name("pub const fn g() -> f64 {").as_deref(), Some("fn g"));
    assert_eq!(item_name("let x = 2.0;"), None);
    let items =
        items_of("/// Eq. (2.1)\n#[inline]\npub fn a() {\n    // Eq. (2.2)\n    x\n}\n#[cfg(test)]\nfn t() {}\n");
    assert_eq!(items[0].as_deref(), Some("fn a"));
    assert_eq!(items[3].as_deref(), Some("fn a"));
    assert_eq!(items[7], None);
}

#[test]
fn the_spec_map_is_current() {
    let path = workspace().join("docs").join("spec-map.md");
    let map = spec_map();
    if std::env::var_os("WAKELAB_BLESS").is_some() {
        std::fs::write(&path, &map).expect("docs/spec-map.md writable");
        return;
    }
    let on_disk = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        on_disk == map,
        "docs/spec-map.md is stale: rewrite it with `WAKELAB_BLESS=1 cargo test -p wakelab-study --test spec_traceability`"
    );
    // every equation the spec's map assigns to a stage appears in it
    for (_, _, ranges) in STAGES {
        for &(chapter, first, last) in ranges {
            for n in first..=last {
                assert!(
                    map.contains(&format!("| ({chapter}.{n}) |")),
                    "({chapter}.{n}) missing from the map"
                );
            }
        }
    }
}
