//! `core/docs/choosing.md` cites the committed report: its cost table is the one
//! [`report::cost_table`] reads off `report/README.md`, so the page and the report cannot
//! disagree (`cargo run --release -p varembed-examples -- --update-docs` rewrites both).

use varembed_examples::report;

#[test]
fn the_cost_table_of_choosing_md_is_read_off_the_committed_report() {
    let page = include_str!("../../../core/docs/choosing.md");
    let committed = include_str!("../../../report/README.md");
    let start = page.find(report::COST_START).expect("start marker") + report::COST_START.len() + 1;
    let end = page.find(report::COST_END).expect("end marker");
    let expected = report::cost_table(committed);
    assert_eq!(
        &page[start..end],
        expected,
        "core/docs/choosing.md's cost table differs from report/README.md's sweeps; expected:\n{expected}"
    );
    // Every scene of the report is in it, with a positive cost per step.
    let rows: Vec<&str> = expected.lines().skip(2).collect();
    assert!(rows.len() >= 20, "{expected}");
    for row in rows {
        let cost: f64 = row.split('|').nth(5).unwrap().trim().parse().unwrap();
        assert!(cost > 0.0, "{row}");
    }
}

/// The table is read from the sweep rows only, the finest N of each line, whatever else the
/// report holds (the summary, comparison tables in code blocks).
#[test]
fn the_cost_table_keeps_the_finest_grid_of_each_line() {
    let report = "# varembed\n\n## Summary\n\n| a | b | 1 | 2 | 3 | 4 |\n\n## Scene\n\n\
                  | scheme | N | max error | time (s) | order |\n| --- | ---: | ---: | ---: | ---: |\n\
                  | direct | 100 | 1e-2 | 1.0e-4 |  |\n| direct | 200 | 5e-3 | 4.0e-4 | 1.00 |\n\
                  | variational | 100 | 1e-3 | 2.0e-4 |  |\n";
    let table = report::cost_table(report);
    let rows: Vec<&str> = table.lines().skip(2).collect();
    assert_eq!(
        rows,
        [
            "| Scene | direct | 200 | 4.00e-4 | 2000 |",
            "| Scene | variational | 100 | 2.00e-4 | 2000 |"
        ]
    );
}

/// `--update-docs` rewrites the README's summary and the page's cost table from the report it
/// has just written into the checkout, and nothing outside the markers.
#[test]
fn update_docs_rewrites_both_sections_from_the_written_report() {
    let root = std::env::temp_dir().join(format!("varembed-update-docs-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    for dir in ["report", "core/docs"] {
        std::fs::create_dir_all(root.join(dir)).expect("temp dir");
    }
    let section = |start: &str, end: &str| format!("head\n{start}\nold\n{end}\ntail\n");
    let readme = section(report::SUMMARY_START, report::SUMMARY_END);
    let page = section(report::COST_START, report::COST_END);
    std::fs::write(root.join("README.md"), &readme).expect("write");
    std::fs::write(root.join("core/docs/choosing.md"), &page).expect("write");
    let written = "## Scene\n\n| direct | 100 | 1e-2 | 1.0e-4 |  |\n";
    std::fs::write(root.join("report/README.md"), written).expect("write");

    report::update_docs(&root, "the summary\n", "generated").expect("markers present");
    let readme = std::fs::read_to_string(root.join("README.md")).expect("read");
    assert!(readme.starts_with(&format!("head\n{}\n![pendulum", report::SUMMARY_START)));
    assert!(readme.contains("the summary\n\ngenerated\n"));
    assert!(readme.ends_with(&format!("{}\ntail\n", report::SUMMARY_END)));
    let page = std::fs::read_to_string(root.join("core/docs/choosing.md")).expect("read");
    assert_eq!(
        page,
        format!(
            "head\n{}\n{}{}\ntail\n",
            report::COST_START,
            report::cost_table(written),
            report::COST_END
        )
    );
    assert!(page.contains("| Scene | direct | 100 | 1.00e-4 | 1000 |"));
    // A page without its markers is an error naming the file, and is left as it was.
    std::fs::write(root.join("core/docs/choosing.md"), "no markers\n").expect("write");
    let error = report::update_docs(&root, "x", "y")
        .unwrap_err()
        .to_string();
    assert!(error.contains("choosing.md"), "{error}");
    std::fs::remove_dir_all(&root).expect("clean up");
}
