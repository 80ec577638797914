//! The crate's layout, as the design has it: the compiled model is pure (nothing under `src/model` uses the
//! engines), its methods live with it (no `impl Model` outside `src/model`), and so do the world's (no `impl World`
//! outside `src/world`). A hook of an engine growing back into the model fails here.

use std::path::{Path, PathBuf};

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

fn all() -> Vec<(PathBuf, String)> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&src, &mut files);
    files.sort();
    files
        .into_iter()
        .map(|f| (f.strip_prefix(&src).unwrap().to_path_buf(), std::fs::read_to_string(&f).unwrap()))
        .collect()
}

/// Lines of code (comments left out) that match `pattern`.
fn code_lines<'a>(text: &'a str, pattern: &'a str) -> impl Iterator<Item = &'a str> {
    text.lines().filter(move |l| !l.trim_start().starts_with("//") && l.contains(pattern))
}

#[test]
fn the_model_uses_nothing_of_the_engines() {
    let offending: Vec<_> = all()
        .into_iter()
        .filter(|(f, _)| f.starts_with("model"))
        .flat_map(|(f, text)| code_lines(&text, "engine").map(|l| format!("{}: {l}", f.display())).collect::<Vec<_>>())
        .collect();
    assert!(offending.is_empty(), "{offending:#?}");
}

#[test]
fn the_model_and_the_world_keep_their_methods_with_them() {
    let mut offending = Vec::new();
    for (f, text) in all() {
        for (ty, home) in [("Model", "model"), ("World", "world")] {
            if f.starts_with(home) {
                continue;
            }
            for line in text.lines().filter(|l| l.starts_with("impl")) {
                let name = line.trim_end_matches('{').split_whitespace().last().unwrap_or("");
                if name == ty {
                    offending.push(format!("{}: {line}", f.display()));
                }
            }
        }
    }
    assert!(offending.is_empty(), "{offending:#?}");
}
