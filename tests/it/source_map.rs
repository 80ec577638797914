//! The source map of docs/architecture.md against the files: every source folder of the workspace has its line,
//! which names each of its `.rs` files and nothing else, and every source file opens with the `//!` line that says
//! what it holds (the map names files; their own first lines describe them).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The crates' source folders, from the workspace root.
const CRATES: [&str; 5] = ["src", "crates/integrate/src", "crates/collide/src", "crates/contact/src", "python/src"];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Each folder under `dir` (itself included) with its `.rs` files, by path from the workspace root.
fn folders(dir: &Path, out: &mut BTreeMap<String, BTreeSet<String>>) {
    let rel = format!("{}/", dir.strip_prefix(root()).unwrap().display());
    let mut files = BTreeSet::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let p = entry.unwrap().path();
        if p.is_dir() {
            folders(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            files.insert(p.file_name().unwrap().to_string_lossy().into_owned());
        }
    }
    out.insert(rel, files);
}

/// The map: the fenced block under "## The source", a folder's path at the start of a line, then the names of its
/// files (on that line and the indented lines that follow).
fn map() -> BTreeMap<String, BTreeSet<String>> {
    let text = std::fs::read_to_string(root().join("docs/architecture.md")).unwrap();
    let section = text.split("## The source\n").nth(1).expect("a section '## The source'");
    let block = section.split("```").nth(1).expect("a fenced block in it");
    let mut out: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut folder = None;
    for line in block.lines().skip(1) {
        let mut words = line.split_whitespace();
        if !line.starts_with(' ') {
            let Some(path) = words.next() else { continue };
            assert!(path.ends_with('/'), "a map line starts with a folder: {line:?}");
            assert!(out.insert(path.to_string(), BTreeSet::new()).is_none(), "{path} mapped twice");
            folder = Some(path.to_string());
        }
        let Some(f) = &folder else { continue };
        let named = words.map(|w| w.trim_matches(|c: char| !c.is_alphanumeric() && c != '_' && c != '.'));
        out.get_mut(f).unwrap().extend(named.filter(|w| w.ends_with(".rs")).map(str::to_string));
    }
    out
}

#[test]
fn the_source_map_names_every_file_and_no_other() {
    let mut actual = BTreeMap::new();
    for dir in CRATES {
        folders(&root().join(dir), &mut actual);
    }
    let mapped = map();
    let mut wrong = Vec::new();
    for (folder, files) in &actual {
        match mapped.get(folder) {
            None => wrong.push(format!("{folder} is not in the map")),
            Some(named) => {
                for f in files.difference(named) {
                    wrong.push(format!("{folder}{f} is not named"));
                }
                for f in named.difference(files) {
                    wrong.push(format!("{folder}{f} is named but not there"));
                }
            }
        }
    }
    for folder in mapped.keys().filter(|f| !actual.contains_key(*f)) {
        wrong.push(format!("{folder} is mapped but not there"));
    }
    assert!(wrong.is_empty(), "docs/architecture.md's source map:\n{}", wrong.join("\n"));
}

#[test]
fn every_source_file_says_what_it_holds() {
    let mut actual = BTreeMap::new();
    for dir in CRATES {
        folders(&root().join(dir), &mut actual);
    }
    let silent: Vec<String> = actual
        .iter()
        .flat_map(|(folder, files)| files.iter().map(move |f| format!("{folder}{f}")))
        .filter(|p| !std::fs::read_to_string(root().join(p)).unwrap().starts_with("//!"))
        .collect();
    assert!(silent.is_empty(), "files without a //! line at the top:\n{}", silent.join("\n"));
}
