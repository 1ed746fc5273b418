//! The formulas of the core crate's rustdoc are pre-rendered MathML (`docs/math/render.py`,
//! described in `docs/architecture.md`): every LaTeX source line `<!-- tex: … -->` is followed
//! by its rendered `<math display="block">` line, well formed, so that no formula is shown as
//! raw source or breaks the page.

use std::path::{Path, PathBuf};

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("core/src") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

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
                "{where_}: the formula is not rendered; run python3 docs/math/render.py"
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
