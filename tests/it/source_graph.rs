//! The workspace's module graphs and public names, read from the sources: no crate has an import cycle, and each
//! public type name is defined once across the crates.
//!
//! A module's edges are its `use` lines (those outside an inline `#[cfg(test)]` module) and the `crate::` and
//! `super::` paths its code names, each followed to the module that defines the name: a `use` of a name another
//! module imports or re-exports goes on to where that name comes from. A `pub use` is a module's facade, not
//! something it uses, so it makes no edge of its own.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The crates' source folders, from the workspace root.
const CRATES: [&str; 5] = ["src", "crates/integrate/src", "crates/collide/src", "crates/contact/src", "python/src"];

type Module = Vec<String>;

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The module a file holds: its path below the source folder, `mod.rs` and `lib.rs` naming their folder.
fn module_of(src: &Path, file: &Path) -> Module {
    let rel = file.strip_prefix(src).unwrap().with_extension("");
    let mut parts: Module = rel.iter().map(|s| s.to_string_lossy().into_owned()).collect();
    if matches!(parts.last().map(String::as_str), Some("mod" | "lib" | "main")) {
        parts.pop();
    }
    parts
}

/// The text without line comments, cut where an inline test module (`#[cfg(test)] mod name {`) starts.
fn code(text: &str) -> String {
    let kept: Vec<&str> = text.lines().map(|l| l.find("//").map_or(l, |i| &l[..i])).collect();
    let joined = kept.join("\n");
    let inline_test = joined.match_indices("#[cfg(test)]\nmod ").map(|(i, _)| i).find(|&i| {
        let line = joined[i..].lines().nth(1).unwrap_or("");
        line.trim_end().ends_with('{')
    });
    match inline_test {
        Some(i) => joined[..i].to_string(),
        None => joined,
    }
}

/// Every path a `use` tree names, with the name it brings in (its last segment or its `as`).
fn expand(tree: &str) -> Vec<(Vec<String>, String)> {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else {
        let (path, alias) = match tree.split_once(" as ") {
            Some((p, a)) => (p.trim(), Some(a.trim().to_string())),
            None => (tree, None),
        };
        let segs: Vec<String> = path.split("::").map(|s| s.trim().to_string()).filter(|s| !s.is_empty()).collect();
        let name = alias.unwrap_or_else(|| segs.last().cloned().unwrap_or_default());
        return vec![(segs, name)];
    };
    let prefix: Vec<String> =
        tree[..open].split("::").map(|s| s.trim().to_string()).filter(|s| !s.is_empty()).collect();
    let body = &tree[open + 1..tree.rfind('}').unwrap()];
    let (mut parts, mut depth, mut cur) = (Vec::new(), 0, String::new());
    for ch in body.chars() {
        match ch {
            '{' => depth += 1,
            '}' => depth -= 1,
            _ => {}
        }
        if ch == ',' && depth == 0 {
            parts.push(std::mem::take(&mut cur));
        } else {
            cur.push(ch);
        }
    }
    parts.push(cur);
    let mut out = Vec::new();
    for p in parts.iter().filter(|p| !p.trim().is_empty()) {
        for (segs, name) in expand(p) {
            let name = if segs == ["self"] { prefix.last().cloned().unwrap_or_default() } else { name };
            let full: Vec<String> = prefix.iter().cloned().chain(segs.into_iter().filter(|s| s != "self")).collect();
            out.push((full, name));
        }
    }
    out
}

/// One crate's `use` lines: for each module, its imports (name, absolute path, whether re-exported).
struct Crate {
    modules: BTreeMap<Module, Vec<(String, Module, bool)>>,
}

impl Crate {
    fn read(src: &Path) -> Crate {
        let mut files = Vec::new();
        sources(src, &mut files);
        let names: BTreeSet<Module> = files.iter().map(|f| module_of(src, f)).collect();
        let mut modules = BTreeMap::new();
        for f in &files {
            let here = module_of(src, f);
            let text = code(&std::fs::read_to_string(f).unwrap());
            let mut imports = Vec::new();
            let mut uses = Vec::new();
            let mut rest = text.as_str();
            while let Some(i) = rest.find("use ") {
                let before = rest[..i].trim_end_matches(' ');
                let line_start = before.rfind('\n').map_or(0, |k| k + 1);
                let lead = before[line_start..].trim();
                let at_start = i == 0 || rest.as_bytes()[i - 1] == b' ' || rest.as_bytes()[i - 1] == b'\n';
                let is_use = at_start && (lead.is_empty() || lead.starts_with("pub"));
                let Some(end) = rest[i..].find(';') else { break };
                if is_use {
                    let at = text.len() - rest.len() + i;
                    uses.push(at..at + end);
                    for (path, name) in expand(&rest[i + 4..i + end]) {
                        if let Some(abs) = absolute(&here, &path, &names) {
                            imports.push((name, abs, lead.starts_with("pub")));
                        }
                    }
                }
                rest = &rest[i + 4..];
            }
            for path in paths_in_code(&text, &uses) {
                if let Some(abs) = absolute(&here, &path, &names) {
                    imports.push((String::from("::path"), abs, false));
                }
            }
            modules.insert(here, imports);
        }
        Crate { modules }
    }

    /// The module that defines what `path` names: its longest module prefix, followed through imports.
    fn definer(&self, path: &[String]) -> Module {
        let mut path = path.to_vec();
        for _ in 0..32 {
            let k = (0..=path.len()).rev().find(|&k| self.modules.contains_key(&path[..k])).unwrap_or(0);
            let module = path[..k].to_vec();
            let Some(name) = path.get(k) else { return module };
            match self.modules[&module].iter().find(|(n, ..)| n == name) {
                Some((_, target, _)) if target.as_slice() != path.as_slice() => {
                    path = target.iter().cloned().chain(path[k + 1..].iter().cloned()).collect();
                }
                _ => return module,
            }
        }
        path
    }

    fn edges(&self) -> BTreeMap<Module, BTreeSet<Module>> {
        let mut edges = BTreeMap::new();
        for (m, imports) in &self.modules {
            let out: BTreeSet<Module> = imports
                .iter()
                .filter(|(.., reexport)| !reexport)
                .map(|(_, p, _)| self.definer(p))
                .filter(|t| t != m)
                .collect();
            edges.insert(m.clone(), out);
        }
        edges
    }
}

/// The `crate::` and `super::` paths written in code outside the `use` statements (spans `uses`): a call or a type
/// named by its path depends on its module as an import does.
fn paths_in_code(text: &str, uses: &[std::ops::Range<usize>]) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    for start in ["crate::", "super::"] {
        for (i, _) in text.match_indices(start) {
            let before = text[..i].chars().next_back();
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':' || c == '$')
                || uses.iter().any(|u| u.contains(&i))
            {
                continue;
            }
            let tail = &text[i..];
            let len = tail.find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':')).unwrap_or(tail.len());
            let segs: Vec<String> = tail[..len].split("::").filter(|s| !s.is_empty()).map(String::from).collect();
            out.push(segs);
        }
    }
    out
}

/// `path` as seen from module `here`, from the crate root; None for another crate's.
fn absolute(here: &Module, path: &[String], names: &BTreeSet<Module>) -> Option<Module> {
    let first = path.first()?;
    let (mut base, mut rest): (Module, &[String]) = match first.as_str() {
        "crate" => (Vec::new(), &path[1..]),
        "self" => (here.clone(), &path[1..]),
        "super" => (here[..here.len().saturating_sub(1)].to_vec(), &path[1..]),
        _ => {
            let child: Module = here.iter().chain([first]).cloned().collect();
            if !names.contains(&child) {
                return None;
            }
            (here.clone(), path)
        }
    };
    while rest.first().is_some_and(|s| s == "super") {
        base.pop();
        rest = &rest[1..];
    }
    Some(base.into_iter().chain(rest.iter().cloned()).collect())
}

/// The strongly connected components of more than one module (Tarjan's algorithm).
fn cycles(edges: &BTreeMap<Module, BTreeSet<Module>>) -> Vec<Vec<Module>> {
    struct Walk<'a> {
        edges: &'a BTreeMap<Module, BTreeSet<Module>>,
        index: BTreeMap<&'a Module, usize>,
        low: BTreeMap<&'a Module, usize>,
        stack: Vec<&'a Module>,
        found: Vec<Vec<Module>>,
    }
    impl<'a> Walk<'a> {
        fn visit(&mut self, v: &'a Module) {
            let n = self.index.len();
            self.index.insert(v, n);
            self.low.insert(v, n);
            self.stack.push(v);
            for w in self.edges.get(v).into_iter().flatten() {
                let Some((w, _)) = self.edges.get_key_value(w) else { continue };
                if !self.index.contains_key(w) {
                    self.visit(w);
                    let lw = self.low[w];
                    self.low.entry(v).and_modify(|l| *l = (*l).min(lw));
                } else if self.stack.contains(&w) {
                    let iw = self.index[w];
                    self.low.entry(v).and_modify(|l| *l = (*l).min(iw));
                }
            }
            if self.low[v] == self.index[v] {
                let mut comp = Vec::new();
                while let Some(w) = self.stack.pop() {
                    comp.push(w.clone());
                    if w == v {
                        break;
                    }
                }
                if comp.len() > 1 {
                    comp.sort();
                    self.found.push(comp);
                }
            }
        }
    }
    let mut walk = Walk { edges, index: BTreeMap::new(), low: BTreeMap::new(), stack: Vec::new(), found: Vec::new() };
    for v in edges.keys() {
        if !walk.index.contains_key(v) {
            walk.visit(v);
        }
    }
    walk.found
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn show(m: &Module) -> String {
    if m.is_empty() {
        "lib".into()
    } else {
        m.join("::")
    }
}

#[test]
fn no_crate_has_an_import_cycle() {
    let mut found = Vec::new();
    for dir in CRATES {
        let krate = Crate::read(&root().join(dir));
        for c in cycles(&krate.edges()) {
            found.push(format!("{dir}: {}", c.iter().map(show).collect::<Vec<_>>().join(", ")));
        }
    }
    assert!(found.is_empty(), "import cycles:\n{}", found.join("\n"));
}

/// The checker itself: a cycle through a re-export is found, and a facade alone makes none.
#[test]
fn the_cycle_check_follows_imports_to_their_definers() {
    let names: BTreeSet<Module> = [vec![], vec!["a".into()], vec!["b".into()]].into_iter().collect();
    let imp = |here: &Module, tree: &str, re: bool| {
        expand(tree).into_iter().map(|(p, n)| (n, absolute(here, &p, &names).unwrap(), re)).collect::<Vec<_>>()
    };
    let (lib, a, b): (Module, Module, Module) = (vec![], vec!["a".into()], vec!["b".into()]);
    let mut modules = BTreeMap::new();
    modules.insert(lib.clone(), imp(&lib, "crate::{a::A, b::B}", true));
    modules.insert(a.clone(), imp(&a, "crate::B", false));
    modules.insert(b.clone(), Vec::new());
    let krate = Crate { modules: modules.clone() };
    assert!(cycles(&krate.edges()).is_empty(), "a facade and one import make no cycle");
    modules.insert(b.clone(), imp(&b, "super::A", false));
    let krate = Crate { modules };
    assert_eq!(cycles(&krate.edges()), vec![vec![a, b]], "a uses B and b uses A, both through lib's re-exports");
}

/// Paths in code make edges as `use` lines do: a call by `crate::` or `super::` path is found, one inside a `use`
/// statement, a macro's `$crate::` or a longer name ending in `crate` is not.
#[test]
fn paths_named_in_code_are_found() {
    let text = "use crate::a::X;\nfn f() { crate::b::g(); super::c::H::new(); $crate::d::i(); my_crate::e(); }";
    let use_statement = 0..text.find(';').unwrap();
    let found = paths_in_code(text, std::slice::from_ref(&use_statement));
    let want: Vec<Vec<String>> =
        vec![vec!["crate".into(), "b".into(), "g".into()], vec!["super".into(), "c".into(), "H".into(), "new".into()]];
    assert_eq!(found, want);
}

#[test]
fn each_public_type_name_is_defined_once() {
    let mut defined: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for dir in CRATES {
        let mut files = Vec::new();
        sources(&root().join(dir), &mut files);
        for f in files {
            let text = code(&std::fs::read_to_string(&f).unwrap());
            for line in text.lines() {
                let words: Vec<&str> = line.split_whitespace().collect();
                if words.len() >= 3
                    && words[0] == "pub"
                    && ["struct", "enum", "trait", "type", "union"].contains(&words[1])
                {
                    let name: String = words[2].chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
                    defined.entry(name).or_default().push(f.strip_prefix(root()).unwrap().display().to_string());
                }
            }
        }
    }
    let twice: Vec<String> =
        defined.iter().filter(|(_, at)| at.len() > 1).map(|(n, at)| format!("{n}: {}", at.join(", "))).collect();
    assert!(twice.is_empty(), "public type names defined more than once:\n{}", twice.join("\n"));
}
