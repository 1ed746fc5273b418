//! The tour's quick mode end to end: every scene runs, every number in its tables, sweeps and
//! figures is finite, and every file of the report exists and is non-empty.

use std::fs;
use varembed_examples::report;
use varembed_examples::scene::{Context, Mode};
use varembed_examples::scenes::ALL;

#[test]
fn quick_tour_writes_a_complete_finite_report() {
    let cx = Context::hidden(Mode::Quick);
    let mut printed = 0;
    let reports = varembed_examples::run_tour(&cx, |_| printed += 1).expect("the quick tour runs");
    assert_eq!(reports.len(), ALL.len());
    assert_eq!(printed, ALL.len());

    for scene in &reports {
        assert!(!scene.tables.is_empty(), "{}: no table", scene.name);
        for table in &scene.tables {
            let lower = table.to_lowercase();
            assert!(
                !lower.contains("nan") && !lower.contains("inf"),
                "{}: non-finite value in\n{table}",
                scene.name
            );
        }
        assert!(
            scene.sweep.len() >= 2,
            "{}: fewer than two lines",
            scene.name
        );
        for line in &scene.sweep {
            assert!(
                !line.points.is_empty(),
                "{}: {} has no point",
                scene.name,
                line.label
            );
            for p in &line.points {
                assert!(
                    p.error.is_finite()
                        && p.error > 0.0
                        && p.seconds.is_finite()
                        && p.seconds > 0.0,
                    "{}: {} at N = {}: {p:?}",
                    scene.name,
                    line.label,
                    p.n
                );
            }
            assert!(line.orders().iter().all(|o| o.is_finite()));
        }
        for figure in &scene.figures {
            assert!(!figure.series.is_empty(), "{}", figure.file);
            for series in &figure.series {
                assert!(
                    series.points.len() >= 2,
                    "{}: {}",
                    figure.file,
                    series.label
                );
                assert!(
                    series
                        .points
                        .iter()
                        .all(|(x, y)| x.is_finite() && y.is_finite()),
                    "{}: {} has a non-finite point",
                    figure.file,
                    series.label
                );
            }
        }
    }

    let dir = std::env::temp_dir().join(format!("varembed-tour-test-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    let table = report::write(&dir, &reports, "test run").expect("the report is written");
    let lower = table.to_lowercase();
    assert!(!lower.contains("nan") && !lower.contains("inf"), "{table}");
    let mut files = vec!["README.md".to_string()];
    for scene in &reports {
        assert!(
            table.contains(&scene.title),
            "summary lacks {}",
            scene.title
        );
        files.push(report::work_precision_file(scene));
        files.extend(scene.figures.iter().map(|f| f.file.clone()));
    }
    for file in &files {
        let bytes = fs::read(dir.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert!(bytes.len() > 200, "{file} is (nearly) empty");
        if file.ends_with(".svg") {
            let text = String::from_utf8(bytes).expect("SVG is text");
            assert!(
                text.contains("<svg") && text.contains("stroke-width=\"2\""),
                "{file} has no curve"
            );
        }
    }
    let summary = fs::read_to_string(dir.join("README.md")).expect("summary");
    for file in &files[1..] {
        assert!(
            summary.contains(file.as_str()),
            "summary does not link {file}"
        );
    }
    fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn readme_section_is_replaced_between_the_markers_only() {
    let dir = std::env::temp_dir().join(format!("varembed-readme-test-{}", std::process::id()));
    fs::create_dir_all(&dir).expect("temp dir");
    let file = dir.join("README.md");
    let text = format!(
        "head\n{}\nold\n{}\ntail\n",
        report::SUMMARY_START,
        report::SUMMARY_END
    );
    fs::write(&file, &text).expect("write");
    report::update_section(&file, "new table\n").expect("markers found");
    let updated = fs::read_to_string(&file).expect("read");
    assert_eq!(
        updated,
        format!(
            "head\n{}\nnew table\n{}\ntail\n",
            report::SUMMARY_START,
            report::SUMMARY_END
        )
    );
    fs::write(&file, "no markers\n").expect("write");
    assert!(report::update_section(&file, "x").is_err());
    assert_eq!(fs::read_to_string(&file).expect("read"), "no markers\n");
    fs::remove_dir_all(&dir).expect("clean up");
}
