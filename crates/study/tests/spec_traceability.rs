//! Spec traceability: every equation the spec's map (spec README, "Map") assigns to a stage is
//! cited, in the one form `Eq. (N.M)` / `Eqs. (N.M)-(N.K)`, somewhere in that stage's crates, and
//! no source cites the spec's equations in another form.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

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

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("readable source tree") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

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
