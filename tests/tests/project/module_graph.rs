//! The module graphs of `core` and `macros` have no cycles, no source file is too long to read
//! as one concept, and every formula of core's rustdoc is rendered.
//!
//! A module is a file. An edge `a → b` is any path in `a` that names an item of `b` through
//! `crate::`, `super::` or `self::` (in `use` declarations, expressions, types or patterns).
//! A path that goes through a re-export of the crate root (`crate::Problem`) counts as an
//! import of the file that defines the item, so `lib.rs` re-exports cannot hide a cycle; the
//! root itself is not a node (it declares and re-exports every module). Code under
//! `#[cfg(test)]` is left out: a unit test may build anything.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use syn::visit::Visit;

/// Longest source file (in lines) allowed outside tests.
const MAX_LINES: usize = 600;

/// A crate's module tree: module path (`["solve", "ivp"]`) → parsed file.
struct Crate {
    files: BTreeMap<Vec<String>, syn::File>,
    /// Names the root re-exports (`pub use a::b::Name;`) → the module path they resolve in.
    root_exports: BTreeMap<String, Vec<String>>,
}

fn module_path(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).expect("file under src");
    let mut parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    let last = parts.pop().expect("a file name");
    let stem = last.trim_end_matches(".rs");
    if stem != "mod" && stem != "lib" {
        parts.push(stem.to_string());
    }
    parts
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("readable source folder") {
        let path = entry.expect("directory entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

fn is_cfg_test(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|a| {
        a.path().is_ident("cfg")
            && a.parse_args::<syn::Meta>()
                .is_ok_and(|m| m.path().is_ident("test"))
    })
}

/// Every `use` tree flattened to its paths (`a::{b, c::d}` → `a::b`, `a::c::d`).
fn flatten_use(tree: &syn::UseTree, prefix: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    match tree {
        syn::UseTree::Path(p) => {
            prefix.push(p.ident.to_string());
            flatten_use(&p.tree, prefix, out);
            prefix.pop();
        }
        syn::UseTree::Name(n) => {
            let mut path = prefix.clone();
            if n.ident != "self" {
                path.push(n.ident.to_string());
            }
            out.push(path);
        }
        syn::UseTree::Rename(r) => {
            let mut path = prefix.clone();
            path.push(r.ident.to_string());
            out.push(path);
        }
        syn::UseTree::Glob(_) => out.push(prefix.clone()),
        syn::UseTree::Group(g) => g.items.iter().for_each(|t| flatten_use(t, prefix, out)),
    }
}

/// The paths a file names, with `#[cfg(test)]` items left out.
#[derive(Default)]
struct Paths(Vec<Vec<String>>);

impl<'ast> Visit<'ast> for Paths {
    fn visit_item_mod(&mut self, m: &'ast syn::ItemMod) {
        if !is_cfg_test(&m.attrs) {
            syn::visit::visit_item_mod(self, m);
        }
    }
    fn visit_item_fn(&mut self, f: &'ast syn::ItemFn) {
        if !is_cfg_test(&f.attrs) {
            syn::visit::visit_item_fn(self, f);
        }
    }
    fn visit_item_use(&mut self, u: &'ast syn::ItemUse) {
        if !is_cfg_test(&u.attrs) {
            flatten_use(&u.tree, &mut Vec::new(), &mut self.0);
        }
    }
    fn visit_path(&mut self, p: &'ast syn::Path) {
        self.0
            .push(p.segments.iter().map(|s| s.ident.to_string()).collect());
        syn::visit::visit_path(self, p);
    }
}

impl Crate {
    fn load(src: &Path) -> Crate {
        let mut paths = Vec::new();
        rust_files(src, &mut paths);
        let files: BTreeMap<_, _> = paths
            .iter()
            .map(|f| {
                let text = std::fs::read_to_string(f).expect("readable source");
                let file = syn::parse_file(&text)
                    .unwrap_or_else(|e| panic!("{} does not parse: {e}", f.display()));
                (module_path(src, f), file)
            })
            .collect();
        Crate::from_files(files)
    }

    fn from_files(files: BTreeMap<Vec<String>, syn::File>) -> Crate {
        let mut root_exports = BTreeMap::new();
        if let Some(root) = files.get(&Vec::new()) {
            for item in &root.items {
                if let syn::Item::Use(u) = item {
                    let mut flat = Vec::new();
                    flatten_use(&u.tree, &mut Vec::new(), &mut flat);
                    for mut path in flat {
                        if path.first().is_some_and(|s| s == "crate") {
                            path.remove(0);
                        }
                        if let Some(name) = path.last().cloned() {
                            root_exports.insert(name, path);
                        }
                    }
                }
            }
        }
        Crate {
            files,
            root_exports,
        }
    }

    /// The file (module path) a path written in `from` refers to, if it is one of ours and
    /// not `from` itself or the root.
    fn resolve(&self, from: &[String], path: &[String]) -> Option<Vec<String>> {
        let mut abs: Vec<String> = match path.first().map(String::as_str) {
            Some("crate") => path[1..].to_vec(),
            Some("super") => {
                let mut base = from.to_vec();
                let mut rest = path;
                while rest.first().is_some_and(|s| s == "super") {
                    base.pop();
                    rest = &rest[1..];
                }
                base.extend_from_slice(rest);
                base
            }
            Some("self") => {
                let mut base = from.to_vec();
                base.extend_from_slice(&path[1..]);
                base
            }
            _ => return None,
        };
        // Through a root re-export: `crate::Name…` names the defining module's item.
        if let Some(first) = abs.first()
            && !self.files.contains_key(&abs[..1])
            && let Some(target) = self.root_exports.get(first)
        {
            let mut via = target.clone();
            via.extend_from_slice(&abs[1..]);
            abs = via;
        }
        let module = (1..=abs.len())
            .rev()
            .map(|n| abs[..n].to_vec())
            .find(|m| self.files.contains_key(m))?;
        (module != from && !module.is_empty()).then_some(module)
    }

    fn edges(&self) -> BTreeMap<Vec<String>, BTreeSet<Vec<String>>> {
        let mut edges = BTreeMap::new();
        for (module, file) in self.files.iter().filter(|(m, _)| !m.is_empty()) {
            let mut paths = Paths::default();
            paths.visit_file(file);
            let targets: BTreeSet<_> = paths
                .0
                .iter()
                .filter_map(|p| self.resolve(module, p))
                .collect();
            edges.insert(module.clone(), targets);
        }
        edges
    }
}

/// One cycle of the graph, if there is any (depth-first search, white/grey/black).
fn find_cycle(edges: &BTreeMap<Vec<String>, BTreeSet<Vec<String>>>) -> Option<Vec<String>> {
    fn dfs(
        node: &Vec<String>,
        edges: &BTreeMap<Vec<String>, BTreeSet<Vec<String>>>,
        state: &mut BTreeMap<Vec<String>, u8>,
        stack: &mut Vec<Vec<String>>,
    ) -> Option<Vec<String>> {
        state.insert(node.clone(), 1);
        stack.push(node.clone());
        for next in edges.get(node).into_iter().flatten() {
            match state.get(next).copied().unwrap_or(0) {
                1 => {
                    let start = stack.iter().position(|n| n == next).expect("on the stack");
                    let mut cycle: Vec<String> =
                        stack[start..].iter().map(|m| m.join("::")).collect();
                    cycle.push(next.join("::"));
                    return Some(cycle);
                }
                0 => {
                    if let Some(c) = dfs(next, edges, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(node.clone(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for node in edges.keys() {
        if state.get(node).copied().unwrap_or(0) == 0
            && let Some(c) = dfs(node, edges, &mut state, &mut Vec::new())
        {
            return Some(c);
        }
    }
    None
}

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the workspace root")
        .to_path_buf()
}

fn assert_acyclic(krate: &str) {
    let graph = Crate::load(&workspace().join(krate).join("src"));
    assert!(graph.files.len() > 3, "{krate}: found its source files");
    if let Some(cycle) = find_cycle(&graph.edges()) {
        panic!("{krate}: import cycle {}", cycle.join(" → "));
    }
}

#[test]
fn core_modules_import_in_one_direction() {
    assert_acyclic("core");
}

#[test]
fn macro_modules_import_in_one_direction() {
    assert_acyclic("macros");
}

#[test]
fn the_check_finds_a_cycle_through_a_root_reexport_and_super() {
    let parse = |s: &str| syn::parse_file(s).expect("test source parses");
    let files = BTreeMap::from([
        (vec![], parse("pub use a::Alpha; mod a; mod b;")),
        (
            vec!["a".to_string()],
            parse("use crate::b::beta; pub struct Alpha;"),
        ),
        (
            vec!["b".to_string()],
            parse("pub fn beta() -> crate::Alpha { super::Alpha }"),
        ),
        (
            vec!["c".to_string()],
            parse("#[cfg(test)] mod tests { use crate::a::Alpha; }"),
        ),
    ]);
    let graph = Crate::from_files(files);
    let cycle = find_cycle(&graph.edges()).expect("a → b → a");
    assert_eq!(cycle.len(), 3, "{cycle:?}");
    // The test module's import is not an edge.
    assert!(graph.edges()[&vec!["c".to_string()]].is_empty());
}

#[test]
fn no_source_file_is_longer_than_the_limit() {
    let mut long = Vec::new();
    for krate in ["core", "macros", "examples"] {
        let mut files = Vec::new();
        rust_files(&workspace().join(krate).join("src"), &mut files);
        for f in files {
            // Unit tests kept beside their module (`tests.rs`, `tests/…`) are tests.
            if f.iter().any(|c| c == "tests" || c == "tests.rs") {
                continue;
            }
            let lines = std::fs::read_to_string(&f)
                .expect("readable")
                .lines()
                .count();
            if lines > MAX_LINES {
                long.push(format!("{} ({lines} lines)", f.display()));
            }
        }
    }
    assert!(long.is_empty(), "files over {MAX_LINES} lines: {long:?}");
}

/// The formulas of the core crate's rustdoc are pre-rendered MathML
/// (`core/docs/math/render.py`, described in `core/docs/architecture.md`): every LaTeX source
/// line `<!-- tex: … -->` is followed by its rendered `<math display="block">` line, well
/// formed, so that no formula is shown as raw source or breaks the page.
#[test]
fn every_formula_is_rendered_as_mathml() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../core/src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut formulas = 0;
    for file in files {
        let text = std::fs::read_to_string(&file).expect("source");
        let lines: Vec<&str> = text.lines().collect();
        for (i, line) in lines.iter().enumerate() {
            if !line.contains("<!-- tex: ") {
                continue;
            }
            formulas += 1;
            let next = lines.get(i + 1).copied().unwrap_or("");
            let where_ = format!("{}:{}", file.display(), i + 2);
            assert!(
                next.contains("<math display=\"block\">") && next.trim_end().ends_with("</math>"),
                "{where_}: the formula is not rendered; run python3 core/docs/math/render.py"
            );
            assert!(
                !next.contains("<merror"),
                "{where_}: LaTeX the renderer rejected"
            );
            // Balanced tags: as many closing tags as opening ones (self-closing aside).
            let opening = next.matches('<').count() - next.matches("</").count();
            let self_closing = next.matches("/>").count();
            assert_eq!(
                opening - self_closing,
                next.matches("</").count(),
                "{where_}: unbalanced MathML"
            );
        }
    }
    assert!(formulas >= 5, "only {formulas} formulas");
}
