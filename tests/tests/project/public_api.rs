//! The public API of `varembed`, pinned: a change to it fails here until it is made on purpose.
//!
//! Three checks:
//!
//! 1. The `use` below names every public item, so removing or renaming one fails to compile;
//!    [`auto_traits`] keeps the types `Send` and `Sync` (a problem can be shared between
//!    threads), which no signature shows.
//! 2. The crate root's public items (parsed from `core/src/lib.rs`) are exactly [`ROOT`], and the
//!    crate's front page lists exactly those (so a new re-export is also documented there).
//! 3. The signature of every public item and of every public method, associated constant and
//!    trait implementation of the public types (parsed from `core/src`, bodies and docs
//!    stripped) equals the snapshot `tests/tests/public_api.txt`. To accept an intended change,
//!    run `UPDATE_PUBLIC_API=1 cargo test -p varembed-tests --test project public_api` and commit the
//!    snapshot with the change.

#[allow(unused_imports)]
use varembed::{
    CompareOptions, ComparedSolution, Comparison, Convergence, Dependence, DifferentialOperator,
    DirectEmbedding, DynSolution, DynState, Embedding, EmbeddingKind, Ensemble, Error,
    FractionalSolver, Grid, Hessian, HessianDependence, IntoVector, Lagrangian, Level, Location,
    Matrix, NewtonOptions, NodeFormula, NodeRule, NodeState, NodeValues, OrderStatus, Problem,
    Reference, Result, Scheme, SchemeReport, Side, Solution, Start, Vector, Warning, constraint,
    curve_from_flat, force, lagrangian, max_error, observed_order, observed_orders,
};

/// Compiles only while the public types keep their auto traits.
#[allow(dead_code)]
fn auto_traits<L: Lagrangian<2> + Sync + 'static>() {
    fn shared<T: Send + Sync>() {}
    shared::<Problem<'static, L, 2>>();
    shared::<Solution<2>>();
    shared::<NodeValues<2>>();
    shared::<DynState>();
    shared::<Comparison<Solution<2>>>();
    shared::<Comparison<DynSolution>>();
    shared::<Convergence<Solution<2>>>();
    shared::<OrderStatus>();
    shared::<Warning>();
    shared::<Error>();
    shared::<Embedding>();
    shared::<Grid>();
    // Shared by the threads of an ensemble: the general direct embedding's closures are
    // `Send + Sync`.
    shared::<DifferentialOperator<'static, 2>>();
    shared::<DirectEmbedding<'static, 'static, 2>>();
    // One ensemble hands its progress callback to every worker thread.
    fn synced<T: Sync>() {}
    synced::<Ensemble<'static>>();
}

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use syn::{Attribute, ImplItem, Item, TraitItem, UseTree, Visibility};

/// The public items at the crate root.
const ROOT: &[&str] = &[
    "CONSISTENCY_TOLERANCE",
    "CompareOptions",
    "ComparedSolution",
    "BlockWriter",
    "BvpSolver",
    "Comparison",
    "ConstrainedSolution",
    "Constraint",
    "Convergence",
    "Dependence",
    "DifferentialOperator",
    "DirectEmbedding",
    "DynForce",
    "DynLagrangian",
    "DynNode",
    "DynNodeState",
    "DynNodeValues",
    "DynProblem",
    "DynRun",
    "DynSolution",
    "DynState",
    "Embedding",
    "EmbeddingKind",
    "Ensemble",
    "Error",
    "Force",
    "ForceDependence",
    "ForceJacobian",
    "ForceJacobianWriter",
    "Forced",
    "FractionalSolver",
    "Grid",
    "Hessian",
    "HessianDependence",
    "HessianWriter",
    "Holonomic",
    "IntoVector",
    "Lagrangian",
    "Level",
    "LinearSolve",
    "Location",
    "Matrix",
    "NewtonOptions",
    "NodeFormula",
    "NodeRule",
    "NodeState",
    "NodeValues",
    "OrderStatus",
    "Problem",
    "RUN_TIME_FROM",
    "Rayleigh",
    "Reference",
    "Result",
    "Scheme",
    "SchemeReport",
    "Side",
    "Solution",
    "SparseBlock",
    "SparseForceJacobian",
    "SparseHessian",
    "Start",
    "Vector",
    "Warning",
    "constraint",
    "curve_from_flat",
    "force",
    "guide",
    "lagrangian",
    "max_error",
    "observed_order",
    "observed_orders",
    "project_initial_data",
];

/// The names generated code and the benchmarks reach through the hidden `__private` module:
/// not public API, but the macro's output depends on them.
const PRIVATE: &[&str] = &[
    "Constraint",
    "Dependence",
    "DynForce",
    "DynLagrangian",
    "Force",
    "ForceDependence",
    "ForceJacobian",
    "Hessian",
    "HessianDependence",
    "Lagrangian",
    "Matrix",
    "SMatrix",
    "SVector",
    "SparseForceJacobian",
    "SparseHessian",
    "Vector",
    "fft_operator",
    "krylov",
    "lagrangian_helpers",
    "linalg",
    "operator",
    "sech2",
    "step",
    "toeplitz",
    "weights",
];

fn core_src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../core/src")
}

fn parse(path: &Path) -> syn::File {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    syn::parse_file(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Every `(path, name)` a `use` tree brings in, `path` the segments before the name.
fn use_leaves(tree: &UseTree, prefix: &mut Vec<String>, out: &mut Vec<(Vec<String>, String)>) {
    match tree {
        UseTree::Path(p) => {
            prefix.push(p.ident.to_string());
            use_leaves(&p.tree, prefix, out);
            prefix.pop();
        }
        UseTree::Name(n) => out.push((prefix.clone(), n.ident.to_string())),
        UseTree::Rename(r) => out.push((prefix.clone(), r.rename.to_string())),
        UseTree::Glob(_) => out.push((prefix.clone(), "*".to_string())),
        UseTree::Group(g) => g.items.iter().for_each(|t| use_leaves(t, prefix, out)),
    }
}

fn is_pub(vis: &Visibility) -> bool {
    matches!(vis, Visibility::Public(_))
}

fn is_hidden(attrs: &[Attribute]) -> bool {
    attrs.iter().any(|a| {
        a.path().is_ident("doc")
            && a.meta
                .require_list()
                .is_ok_and(|l| l.tokens.to_string() == "hidden")
    })
}

/// The name of a public item, if it is one.
fn public_name(item: &Item) -> Option<String> {
    let (vis, ident) = match item {
        Item::Const(i) => (&i.vis, &i.ident),
        Item::Enum(i) => (&i.vis, &i.ident),
        Item::Fn(i) => (&i.vis, &i.sig.ident),
        Item::Mod(i) => (&i.vis, &i.ident),
        Item::Static(i) => (&i.vis, &i.ident),
        Item::Struct(i) => (&i.vis, &i.ident),
        Item::Trait(i) => (&i.vis, &i.ident),
        Item::Type(i) => (&i.vis, &i.ident),
        Item::Union(i) => (&i.vis, &i.ident),
        _ => return None,
    };
    is_pub(vis).then(|| ident.to_string())
}

/// Whether an item exists only under `cfg(test)` or `cfg(doctest)`.
fn test_only(item: &Item) -> bool {
    let attrs: &[Attribute] = match item {
        Item::Struct(i) => &i.attrs,
        Item::Mod(i) => &i.attrs,
        Item::Fn(i) => &i.attrs,
        _ => return false,
    };
    attrs.iter().any(|a| {
        a.path().is_ident("cfg")
            && a.meta.require_list().is_ok_and(|l| {
                let cfg = l.tokens.to_string();
                cfg == "test" || cfg == "doctest"
            })
    })
}

/// `(path, name)` of every public `use` at the root, and the names of the other public items.
fn root_items(lib: &syn::File) -> (Vec<(Vec<String>, String)>, BTreeSet<String>) {
    let mut uses = Vec::new();
    let mut others = BTreeSet::new();
    for item in lib.items.iter().filter(|i| !test_only(i)) {
        match item {
            Item::Use(u) if is_pub(&u.vis) => use_leaves(&u.tree, &mut Vec::new(), &mut uses),
            Item::Mod(m) if is_pub(&m.vis) && is_hidden(&m.attrs) => {}
            other => others.extend(public_name(other)),
        }
    }
    (uses, others)
}

#[test]
fn the_root_exports_exactly_the_listed_items() {
    let lib = parse(&core_src().join("lib.rs"));
    let (uses, others) = root_items(&lib);
    let mut found: BTreeSet<String> = uses.iter().map(|(_, name)| name.clone()).collect();
    found.extend(others);
    let expected: BTreeSet<String> = ROOT.iter().map(|s| s.to_string()).collect();
    assert_eq!(
        found, expected,
        "the crate root's public items changed: update ROOT here, the list on the crate's front \
         page and the snapshot"
    );
}

#[test]
fn the_front_page_lists_every_public_item() {
    let lib = parse(&core_src().join("lib.rs"));
    let docs: String = lib
        .attrs
        .iter()
        .filter_map(|a| match &a.meta {
            syn::Meta::NameValue(nv) if nv.path.is_ident("doc") => match &nv.value {
                syn::Expr::Lit(syn::ExprLit {
                    lit: syn::Lit::Str(s),
                    ..
                }) => Some(s.value() + "\n"),
                _ => None,
            },
            _ => None,
        })
        .collect();
    let section = docs
        .split("# Public API")
        .nth(1)
        .expect("the front page has a `# Public API` section");
    let section = section.split("\n# ").next().unwrap_or(section);
    // Every "[`Name`]" (with or without a link target) in the section.
    let listed: BTreeSet<String> = section
        .split("[`")
        .skip(1)
        .filter_map(|s| s.split('`').next())
        .map(|s| s.to_string())
        .collect();
    let expected: BTreeSet<String> = ROOT.iter().map(|s| s.to_string()).collect();
    assert_eq!(listed, expected, "the front page's list of public items");
}

#[test]
fn the_hidden_module_exports_what_generated_code_needs() {
    let lib = parse(&core_src().join("lib.rs"));
    let private = lib
        .items
        .iter()
        .find_map(|item| match item {
            Item::Mod(m) if m.ident == "__private" => Some(m),
            _ => None,
        })
        .expect("lib.rs has `pub mod __private`");
    assert!(is_pub(&private.vis) && is_hidden(&private.attrs));
    let mut names = BTreeSet::new();
    for item in &private.content.as_ref().expect("inline module").1 {
        match item {
            Item::Use(u) if is_pub(&u.vis) => {
                let mut leaves = Vec::new();
                use_leaves(&u.tree, &mut Vec::new(), &mut leaves);
                names.extend(leaves.into_iter().map(|(_, name)| name));
            }
            other => names.extend(public_name(other)),
        }
    }
    let expected: BTreeSet<String> = PRIVATE.iter().map(|s| s.to_string()).collect();
    assert_eq!(names, expected, "the names in `varembed::__private`");
}

/// The file of module `path` (segments below the crate root).
fn module_file(path: &[String]) -> PathBuf {
    let mut dir = core_src();
    for segment in &path[..path.len() - 1] {
        dir = dir.join(segment);
    }
    let last = &path[path.len() - 1];
    let flat = dir.join(format!("{last}.rs"));
    if flat.exists() {
        flat
    } else {
        dir.join(last).join("mod.rs")
    }
}

/// The items of every module compiled outside tests: the crate root's, then, depth first,
/// those of each `mod` it declares (in its own file or inline) that is not `cfg(test)`.
fn crate_items() -> Vec<Item> {
    fn walk(items: &[Item], dir: &Path, out: &mut Vec<Item>) {
        for item in items.iter().filter(|i| !test_only(i)) {
            out.push(item.clone());
            let Item::Mod(m) = item else { continue };
            let sub = dir.join(m.ident.to_string());
            match &m.content {
                Some((_, inline)) => walk(inline, &sub, out),
                None => {
                    let flat = dir.join(format!("{}.rs", m.ident));
                    let file = if flat.exists() {
                        flat
                    } else {
                        sub.join("mod.rs")
                    };
                    walk(&parse(&file).items, &sub, out);
                }
            }
        }
    }
    let mut out = Vec::new();
    let src = core_src();
    walk(&parse(&src.join("lib.rs")).items, &src, &mut out);
    out
}

/// The attributes that are part of an item's interface: derives, `#[default]`,
/// `#[non_exhaustive]`, `#[repr]`.
fn keep_interface_attrs(attrs: &mut Vec<Attribute>) {
    attrs.retain(|a| {
        ["derive", "default", "non_exhaustive", "repr"]
            .iter()
            .any(|name| a.path().is_ident(name))
    });
}

fn empty_block() -> syn::Block {
    syn::parse_quote!({})
}

/// The item as a signature: docs dropped, bodies emptied, private fields and items dropped.
fn signature(item: &Item) -> Option<Item> {
    let mut item = item.clone();
    match &mut item {
        Item::Struct(s) => {
            keep_interface_attrs(&mut s.attrs);
            if let syn::Fields::Named(fields) = &mut s.fields {
                fields.named = fields
                    .named
                    .iter()
                    .filter(|f| is_pub(&f.vis))
                    .cloned()
                    .map(|mut f| {
                        f.attrs.clear();
                        f
                    })
                    .collect();
            }
            if let syn::Fields::Unnamed(fields) = &mut s.fields {
                fields.unnamed.iter_mut().for_each(|f| f.attrs.clear());
            }
        }
        Item::Enum(e) => {
            keep_interface_attrs(&mut e.attrs);
            for v in &mut e.variants {
                keep_interface_attrs(&mut v.attrs);
                v.fields.iter_mut().for_each(|f| f.attrs.clear());
            }
        }
        Item::Trait(t) => {
            keep_interface_attrs(&mut t.attrs);
            for member in &mut t.items {
                match member {
                    TraitItem::Fn(f) => {
                        f.attrs.clear();
                        f.default = None;
                        f.semi_token = Some(Default::default());
                    }
                    TraitItem::Const(c) => c.attrs.clear(),
                    TraitItem::Type(ty) => ty.attrs.clear(),
                    _ => {}
                }
            }
        }
        Item::Fn(f) => {
            f.attrs.clear();
            *f.block = empty_block();
        }
        Item::Type(t) => t.attrs.clear(),
        Item::Const(c) => c.attrs.clear(),
        _ => return None,
    }
    Some(item)
}

/// The last identifier of a type path (`Problem` for `Problem<'_, L, D>`).
fn type_name(ty: &syn::Type) -> Option<String> {
    match ty {
        syn::Type::Path(p) => p.path.segments.last().map(|s| s.ident.to_string()),
        syn::Type::Reference(r) => type_name(&r.elem),
        _ => None,
    }
}

/// An impl block reduced to its interface: for an inherent impl the public methods and
/// constants (bodies emptied); for a trait impl the header alone.
fn impl_signature(block: &syn::ItemImpl) -> Option<Item> {
    let mut block = block.clone();
    block.attrs.clear();
    if block.trait_.is_some() {
        block.items.clear();
    } else {
        block.items.retain(|member| match member {
            ImplItem::Fn(f) => is_pub(&f.vis) && !is_hidden(&f.attrs),
            ImplItem::Const(c) => is_pub(&c.vis) && !is_hidden(&c.attrs),
            _ => false,
        });
        if block.items.is_empty() {
            return None;
        }
        for member in &mut block.items {
            match member {
                ImplItem::Fn(f) => {
                    f.attrs.clear();
                    f.block = empty_block();
                }
                ImplItem::Const(c) => c.attrs.clear(),
                _ => {}
            }
        }
    }
    Some(Item::Impl(block))
}

fn render(items: Vec<Item>) -> String {
    prettyplease::unparse(&syn::File {
        shebang: None,
        attrs: Vec::new(),
        items,
    })
}

/// The public API as text: each root item's signature, then the impls of the public types and
/// traits found anywhere in the crate, each group sorted.
fn public_api() -> String {
    let lib = parse(&core_src().join("lib.rs"));
    let (uses, _) = root_items(&lib);
    let mut out = String::new();
    let mut public_types = BTreeSet::new();
    for (path, name) in &uses {
        let Some(first) = path.first() else { continue };
        if first != "crate"
            && !lib
                .items
                .iter()
                .any(|i| matches!(i, Item::Mod(m) if m.ident == first))
        {
            out.push_str(&format!("pub use {}::{name};\n", path.join("::")));
            continue;
        }
        let module: Vec<String> = path.iter().filter(|s| *s != "crate").cloned().collect();
        let file = parse(&module_file(&module));
        let item = file
            .items
            .iter()
            .find(|i| public_name(i).as_deref() == Some(name.as_str()))
            .unwrap_or_else(|| panic!("`{name}` is not a public item of {}", module.join("::")));
        out.push_str(&format!("// {}::{name}\n", module.join("::")));
        out.push_str(&render(signature(item).into_iter().collect()));
        public_types.insert(name.clone());
    }
    let mut impls = BTreeSet::new();
    for item in crate_items() {
        let Item::Impl(block) = &item else { continue };
        let self_type = type_name(&block.self_ty);
        let trait_name = block
            .trait_
            .as_ref()
            .and_then(|(_, p, _)| p.segments.last().map(|s| s.ident.to_string()));
        let concerns_public = self_type.is_some_and(|t| public_types.contains(&t))
            || trait_name.is_some_and(|t| public_types.contains(&t));
        if concerns_public && let Some(sig) = impl_signature(block) {
            impls.insert(render(vec![sig]));
        }
    }
    out.push_str("\n// implementations\n");
    for i in impls {
        out.push_str(&i);
    }
    out
}

#[test]
fn the_public_signatures_match_the_snapshot() {
    let snapshot = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/public_api.txt");
    let actual = public_api();
    if std::env::var_os("UPDATE_PUBLIC_API").is_some() {
        std::fs::write(&snapshot, &actual).expect("the snapshot is writable");
        return;
    }
    let expected = std::fs::read_to_string(&snapshot).unwrap_or_default();
    if actual != expected {
        panic!(
            "the public API changed (- snapshot, + now):\n{}\nIf this is intended, run \
             `UPDATE_PUBLIC_API=1 cargo test -p varembed-tests --test project public_api` and commit {}.",
            diff(&expected, &actual),
            snapshot.display()
        );
    }
}

/// The lines that differ between `old` and `new` (longest common subsequence), each with the
/// line before it for context.
fn diff(old: &str, new: &str) -> String {
    let (a, b): (Vec<&str>, Vec<&str>) = (old.lines().collect(), new.lines().collect());
    // common[i][j]: length of the longest common subsequence of a[i..] and b[j..].
    let mut common = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for i in (0..a.len()).rev() {
        for j in (0..b.len()).rev() {
            common[i][j] = if a[i] == b[j] {
                common[i + 1][j + 1] + 1
            } else {
                common[i + 1][j].max(common[i][j + 1])
            };
        }
    }
    let (mut i, mut j, mut out, mut last) = (0, 0, String::new(), "");
    let change = |sign: char, line: &str, last: &str, out: &mut String| {
        out.push_str(&format!("  {last}\n{sign} {line}\n"));
    };
    while i < a.len() || j < b.len() {
        if i < a.len() && j < b.len() && a[i] == b[j] {
            last = a[i];
            (i, j) = (i + 1, j + 1);
        } else if j < b.len() && (i == a.len() || common[i][j + 1] >= common[i + 1][j]) {
            change('+', b[j], last, &mut out);
            j += 1;
        } else {
            change('-', a[i], last, &mut out);
            i += 1;
        }
    }
    out
}
