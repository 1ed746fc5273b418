//! The guide's pages (`core/docs/*.md`) are read in two places: on GitHub as markdown files
//! and on docs.rs as the modules of `varembed::guide`. A link between pages is written by
//! reference, `[text][label]`, with `[label]: page.md` at the bottom of the page for GitHub;
//! `guide_links!()` in `core/src/lib.rs` defines the same labels as intra-doc links, first, so
//! rustdoc uses its own. These checks keep the two in step: an inline link to a page, or a label
//! only GitHub knows, would be a dead link on docs.rs that no rustdoc lint reports.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn core_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../core")
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Every `.md` page of `core/docs/`, by file name.
fn pages() -> BTreeMap<String, String> {
    let dir = core_dir().join("docs");
    let mut pages = BTreeMap::new();
    for entry in std::fs::read_dir(&dir).expect("core/docs") {
        let path = entry.expect("entry").path();
        if path.extension().is_some_and(|e| e == "md") {
            let name = path
                .file_name()
                .expect("name")
                .to_string_lossy()
                .to_string();
            pages.insert(name, read(&path));
        }
    }
    assert!(pages.len() >= 7, "{:?}", pages.keys());
    pages
}

/// The reference definitions `[label]: target` of a markdown text, outside code blocks.
fn definitions(text: &str) -> BTreeMap<String, String> {
    let mut in_code = false;
    let mut defs = BTreeMap::new();
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code || !line.starts_with('[') {
            continue;
        }
        if let Some((label, target)) = line[1..].split_once("]: ") {
            defs.insert(label.to_string(), target.trim().to_string());
        }
    }
    defs
}

/// The labels of the reference links `[text][label]` of a markdown text, outside code blocks.
fn used_labels(text: &str) -> Vec<String> {
    let mut in_code = false;
    let mut prose = String::new();
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
        } else if !in_code {
            prose.push_str(line);
            prose.push('\n');
        }
    }
    prose
        .split("][")
        .skip(1)
        .filter_map(|rest| rest.split_once(']').map(|(label, _)| label.to_string()))
        .collect()
}

/// The labels `guide_links!()` defines, with the module each points to.
fn rustdoc_labels() -> BTreeMap<String, String> {
    let lib = read(&core_dir().join("src/lib.rs"));
    let start = lib
        .find("macro_rules! guide_links")
        .expect("lib.rs defines guide_links!");
    let body = &lib[start..];
    let body = &body[..body.find("\n}").expect("the macro ends")];
    let mut labels = BTreeMap::new();
    for piece in body.split('[').skip(1) {
        let (label, rest) = piece.split_once("]: ").expect("a definition");
        let target = rest.split(['\\', '"']).next().expect("a target");
        labels.insert(label.to_string(), target.trim().to_string());
    }
    labels
}

/// `module → page file` from the `include_str!`s of `lib.rs` (the guide's index) and
/// `guide.rs` (its pages).
fn modules() -> BTreeMap<String, String> {
    let mut modules = BTreeMap::new();
    for (file, prefix) in [("lib.rs", "crate::"), ("guide.rs", "crate::guide::")] {
        let text = read(&core_dir().join("src").join(file));
        let mut page = None;
        for line in text.lines() {
            if let Some(rest) = line.trim().strip_prefix("#[doc = include_str!(\"../docs/") {
                page = rest.split('"').next().map(str::to_string);
            } else if let Some(rest) = line.trim().strip_prefix("pub mod ") {
                let name = rest.trim_end_matches([';', ' ', '{', '}']);
                if let Some(page) = page.take() {
                    modules.insert(format!("{prefix}{name}"), page);
                }
            }
        }
    }
    modules
}

#[test]
fn every_page_is_a_module_of_the_guide() {
    let modules = modules();
    let included: Vec<&String> = modules.values().collect();
    for page in pages().keys() {
        assert!(
            included.contains(&page),
            "core/docs/{page} is not the docs of a module in lib.rs or guide.rs: {modules:?}"
        );
    }
    assert_eq!(
        modules.get("crate::guide").map(String::as_str),
        Some("README.md")
    );
}

#[test]
fn links_between_pages_work_on_github_and_in_rustdoc() {
    let rustdoc = rustdoc_labels();
    let modules = modules();
    // Each rustdoc label points to the module whose page the label's GitHub target is.
    let page_of = |label: &str| {
        let module = &rustdoc[label];
        let (module, _fragment) = module.split_once('#').unwrap_or((module, ""));
        modules
            .get(module)
            .unwrap_or_else(|| panic!("{label}: no module {module}"))
    };
    for (name, text) in pages() {
        let defs = definitions(&text);
        for label in used_labels(&text) {
            let github = defs
                .get(&label)
                .unwrap_or_else(|| panic!("{name}: [{label}] has no definition on the page"));
            assert!(
                rustdoc.contains_key(&label),
                "{name}: [{label}] is not defined by guide_links!() in core/src/lib.rs"
            );
            let (file, _fragment) = github.split_once('#').unwrap_or((github, ""));
            assert_eq!(
                page_of(&label),
                file,
                "{name}: [{label}] leads to {file} on GitHub and elsewhere in rustdoc"
            );
        }
        // An inline link to a file resolves on GitHub only; a path out of `core/docs/` is not
        // in the published crate.
        for target in text.split("](").skip(1) {
            let target = target.split(')').next().unwrap_or(target);
            assert!(
                !target.contains(".md") && !target.starts_with("../"),
                "{name}: a link to a file must be a reference link: ]({target})"
            );
        }
    }
}
