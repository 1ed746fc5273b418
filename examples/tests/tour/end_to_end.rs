//! The tour's quick mode end to end: every scene runs, solves each grid once per scheme, every
//! number in its tables, sweeps and figures is finite, and every file of the report exists and
//! is non-empty; and the orders the report prints are the library's comparisons' orders.

use std::collections::HashMap;
use std::fs;
use varembed::{Comparison, Start};
use varembed_examples::scene::{Context, Mode};
use varembed_examples::scenes::{ALL, harmonic, large_chain};
use varembed_examples::{console, report};

#[test]
fn quick_tour_writes_a_complete_finite_report() {
    let cx = Context::hidden(Mode::Quick);
    let mut printed = 0;
    let reports = varembed_examples::run_tour(&cx, |_| printed += 1).expect("the quick tour runs");
    assert_eq!(reports.len(), ALL.len());
    assert_eq!(printed, ALL.len());

    // Each scheme (with its embedding and start) of each scene is solved once per grid: the
    // tables are read off the sweeps, not solved again.
    let mut solves = HashMap::new();
    for solve in cx.solves() {
        *solves.entry(solve).or_insert(0) += 1;
    }
    let repeated: Vec<_> = solves.iter().filter(|(_, count)| **count > 1).collect();
    assert!(repeated.is_empty(), "solved more than once: {repeated:?}");
    for scene in &reports {
        for line in &scene.sweep {
            for p in &line.points {
                assert!(
                    solves.keys().any(|s| s.scene == scene.name && s.n == p.n),
                    "{}: {} at N = {} is not in the ledger",
                    scene.name,
                    line.label,
                    p.n
                );
            }
        }
    }

    // Every initial value scene's notes give its advice; the double pendulum's cost to 1e-8 is
    // computable from the quick sweep too (extrapolated along the observed orders).
    for scene in reports.iter().filter(|s| s.name != "fractional") {
        let advice = scene
            .notes
            .iter()
            .filter(|n| n.starts_with("Which scheme: "));
        assert_eq!(advice.count(), 1, "{}: {:#?}", scene.name, scene.notes);
    }
    let double = reports.iter().find(|s| s.name == "double-pendulum");
    let notes = &double.expect("the double pendulum").notes;
    assert!(
        notes.iter().any(|n| n.starts_with(
            "Cost to reach max error 1e-8: the best Gauss-FDE− line, variational FDE−"
        )),
        "{notes:#?}"
    );

    // The large chain's energy figure: the direct scheme ends below its start, the
    // variational one near it; its scaling table has one row per size, and its second table
    // is the library's comparison of the run-time model.
    let chain = reports.iter().find(|s| s.name == large_chain::NAME);
    let chain = chain.expect("the large chain");
    let energy = chain
        .figures
        .iter()
        .find(|f| f.file == "large-chain-energy.svg")
        .expect("the energy figure");
    let last = |label: &str| {
        let series = energy.series.iter().find(|s| s.label == label);
        series.expect(label).points.last().expect("points").1
    };
    assert!(last("direct") < 0.99, "{}", last("direct"));
    assert!((last("variational") - 1.0).abs() < 0.01);
    assert_eq!(chain.tables.len(), 2);
    let compared = &chain.tables[1];
    assert!(
        compared.contains("initial value problem under Gauss-FDE−, N = 400")
            && compared.contains("Runge–Kutta 4 at h/16")
            && compared.contains("  variational "),
        "{compared}"
    );
    for d in [64, 128, 256] {
        assert!(
            chain.tables[0].contains(&format!("\n  {d:>5} ")),
            "{}",
            chain.tables[0]
        );
    }

    for scene in &reports {
        assert!(!scene.tables.is_empty(), "{}: no table", scene.name);
        // A few lines per scene by default; its tables only with --verbose.
        let summary = console::scene_summary(scene);
        assert!(summary.starts_with(&format!("== {}\n  ran: ", scene.title)));
        assert!(summary.contains("\n  best: "), "{summary}");
        assert!(summary.contains("\n        at N = "), "{summary}");
        let warnings = console::warnings(scene).len();
        assert!(summary.lines().count() <= 7 + 2 * warnings, "{summary}");
        assert!(!summary.contains("other's resid."), "{summary}");
        let verbose = console::scene_tables(scene);
        for table in &scene.tables {
            assert!(verbose.contains(table.as_str()));
            assert!(!table.contains("legend:"), "{}: {table}", scene.name);
        }
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
    let table = report::write(&dir, &reports, "test run", 1).expect("the report is written");
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
    // The columns of the comparison tables are explained once, not under every table.
    assert_eq!(
        summary
            .matches(&format!("## {}", report::LEGEND_TITLE))
            .count(),
        1
    );
    assert!(!summary.contains("legend:"), "a table kept its legend");
    for file in &files[1..] {
        assert!(
            summary.contains(file.as_str()),
            "summary does not link {file}"
        );
    }
    // index.html shows every figure with a caption.
    let index = fs::read_to_string(dir.join("index.html")).expect("index.html");
    for file in &files[1..] {
        assert!(
            index.contains(&format!("<img src=\"{file}\"")),
            "index.html does not show {file}"
        );
    }
    assert_eq!(index.matches("<figcaption>").count(), files.len() - 1);
    fs::remove_dir_all(&dir).expect("clean up");
}

/// The order a table prints and the order the sweep prints at the table's `N` are one number:
/// the comparison is built from the sweep's runs, and both are the library's `observed_order`.
#[test]
fn report_orders_are_the_comparisons_orders_and_each_grid_is_solved_once() {
    let cx = Context::hidden(Mode::Quick);
    let exact = harmonic::reference();
    let scene = harmonic::scene(&cx, &harmonic::MODEL, &exact);
    let runs = scene.solve(&cx).expect("the harmonic scene solves");
    let report = scene.report(&runs);
    let line = |label: &str| {
        report
            .sweep
            .iter()
            .find(|l| l.label == label)
            .unwrap_or_else(|| panic!("no line {label}"))
    };
    let (legendre, second_order) = (&runs.tables[0], runs.tables.last().expect("tables"));
    assert_eq!(legendre.0, Start::Legendre);
    assert_eq!(second_order.0, Start::SecondOrder);
    let solved = |table: &Result<Comparison<varembed::Solution<1>>, String>| {
        table.clone().expect("the table solves")
    };
    let (legendre, second_order) = (solved(&legendre.1), solved(&second_order.1));
    let checks = [
        (&legendre.direct, "direct FDE−", &report.tables[0]),
        (
            &legendre.variational,
            "variational FDE−, Legendre start",
            &report.tables[0],
        ),
        (
            &second_order.variational,
            "variational FDE−, second-order start",
            report.tables.last().expect("tables"),
        ),
    ];
    for (scheme, label, table) in checks {
        let line = line(label);
        let i = line
            .points
            .iter()
            .position(|p| p.n == scene.table_n)
            .expect("the sweep holds the table's N");
        let order = line.orders()[i];
        assert_eq!(scheme.order, Some(order), "{label}");
        assert_eq!(scheme.error, Some(line.points[i].error), "{label}");
        let seconds = scheme.wall_time.map(|t| t.as_secs_f64());
        assert_eq!(seconds, Some(line.points[i].seconds), "{label}");
        // The order, with the mark of its status (the sweep's next order decides it).
        let variant = scene.variants.iter().position(|v| v.label == label);
        let status = runs.sweep[variant.expect("a swept variant")].order_status_at(scene.table_n);
        assert_eq!(scheme.order_status, status, "{label}");
        assert!(table.contains(&format!(" {order:.2}")), "{label}: {table}");
        // The report's sweep tables carry the same status as the comparison, as a mark.
        let marked = &line.marked_orders()[i];
        let expected_mark = status.map_or("", |s| s.mark());
        assert_eq!(marked, &format!("{order:.2}{expected_mark}"), "{label}");
    }
    // The last order of a sweep has no next one to check it against.
    let summary = varembed_examples::report::summary_table(std::slice::from_ref(&report));
    for line in &report.sweep {
        let last = line.marked_orders().last().cloned().expect("orders");
        assert!(last.ends_with('?'), "{}: {last}", line.label);
        assert!(summary.contains(&last), "{summary}");
    }
    assert!(summary.contains("`*` is pre-asymptotic"), "{summary}");

    // The ledger: every line over its sizes (the three Gauss-FDE− lines over the scene's four),
    // the FDE+ and asymmetric tables (two schemes on N and 2N each), and the direct scheme from
    // the second-order start (N and 2N); nothing else (the midpoint and trapezoidal tables are
    // read off their sweep), nothing twice.
    let solves = cx.solves();
    assert_eq!(scene.sweep.count, 4);
    let swept: usize = scene
        .variants
        .iter()
        .map(|v| v.sizes(scene.sweep).count)
        .sum();
    assert_eq!(
        swept,
        3 * 4 + 6 * 3,
        "three Gauss-FDE− lines, six higher-order"
    );
    assert_eq!(solves.len(), swept + 2 * 2 * 2 + 2, "{solves:#?}");
    let mut unique = solves.clone();
    unique.sort_by(|a, b| (&a.what, a.n).cmp(&(&b.what, b.n)));
    unique.dedup();
    assert_eq!(unique.len(), solves.len());
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

/// A table whose run fails at the table's `N` is a row of the report with the error, and the
/// scene still reports: Störmer–Verlet at ωh = 2.5 is unstable, the direct scheme is not.
#[test]
fn a_failing_table_is_a_row_with_its_error() {
    let cx = Context::hidden(Mode::Quick);
    let exact = harmonic::reference();
    let mut scene = harmonic::scene(&cx, &harmonic::MODEL, &exact);
    let (a, b) = scene.interval;
    scene.table_n = 8;
    assert!((b - a) / 8.0 > 2.0, "ωh > 2 with ω = 1");
    let runs = scene
        .solve(&cx)
        .expect("a failing table does not stop the scene");
    let failed = runs.tables[0]
        .1
        .as_ref()
        .expect_err("Störmer–Verlet is unstable");
    let lines: Vec<&str> = failed.lines().collect();
    assert!(lines[0].ends_with("N = 8: no comparison"), "{failed}");
    assert_eq!(
        lines[2].split_whitespace().collect::<Vec<_>>(),
        ["direct", "solved"]
    );
    let expected = scene.variants[1]; // variational FDE−, Legendre start
    assert_eq!(expected.scheme, varembed::Scheme::Variational);
    let problem = varembed::Problem::new(
        &harmonic::MODEL,
        varembed::Grid::new(a, b, 8).unwrap(),
        expected.embedding,
    );
    let error = problem
        .solve_ivp(expected.scheme, scene.q0, scene.v0)
        .expect_err("unstable");
    assert!(matches!(error, varembed::Error::Unstable { .. }), "{error}");
    assert_eq!(lines[3], format!("  {:<12} failed: {error}", "variational"));
    let report = scene.report(&runs);
    assert_eq!(
        report.tables[0],
        format!("{failed}\n  (discrete Legendre start)")
    );
}

/// The binary's failures are sentences naming their path, not a bare `Os { code: 2, … }`: an
/// output folder under a regular file cannot be created, and the tour says which one before
/// running any scene.
#[test]
fn the_tour_binary_names_the_folder_it_cannot_create() {
    let dir = std::env::temp_dir().join(format!("varembed-tour-bin-{}", std::process::id()));
    fs::create_dir_all(&dir).expect("temp dir");
    let file = dir.join("a-file");
    fs::write(&file, "not a folder").expect("write");
    let out = file.join("report");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_varembed-tour"))
        .args(["--quick", "--out"])
        .arg(&out)
        .output()
        .expect("the tour binary runs");
    assert!(!run.status.success());
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        stderr.starts_with(&format!(
            "error: could not create folder {}: ",
            out.display()
        )),
        "{stderr}"
    );
    assert!(!stderr.contains("Os {"), "{stderr}");
    // Asking to update the docs outside a checkout fails the same way, naming where it looked.
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_varembed-tour"))
        .arg("--update-docs")
        .current_dir(&dir)
        .output()
        .expect("the tour binary runs");
    assert!(!run.status.success());
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(stderr.contains(&dir.display().to_string()), "{stderr}");
    fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn the_double_pendulum_ensemble_ticks_the_bar_once_per_member_and_equals_serial_runs() {
    use varembed::{Embedding, Grid, Problem, Scheme, Vector};
    use varembed_examples::scenes::double_pendulum::{
        ENSEMBLE, ENSEMBLE_INTERVAL, MODEL, SPACING, initial_data, sensitivity, sensitivity_note,
    };
    let cx = Context::hidden(Mode::Quick);
    let (n, finals) = sensitivity(&cx).expect("the ensemble runs");
    // One ledger entry and one tick per member, from the ensemble's progress callback.
    assert_eq!(cx.solves().len(), ENSEMBLE);
    assert_eq!(cx.progress.position(), ENSEMBLE as u64);
    // Each member equals its own serial solve, bit for bit.
    let grid = Grid::new(ENSEMBLE_INTERVAL.0, ENSEMBLE_INTERVAL.1, n).unwrap();
    let problem = Problem::new(&MODEL, grid, Embedding::gauss_legendre(2).unwrap());
    let (q0, v0) = initial_data();
    for (k, last) in finals.iter().enumerate() {
        let q = q0 + Vector::<2>::new(k as f64 * SPACING, 0.0);
        let alone = problem.solve_ivp(Scheme::Variational, q, v0).unwrap();
        assert_eq!(alone.last()[0].to_bits(), last.to_bits(), "member {k}");
    }
    // Chaos: the spread grows over t ∈ [0, 40] (measured: 1.5e-8 to 2.7e-6, about 180×).
    let spread = finals.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
        - finals.iter().cloned().fold(f64::INFINITY, f64::min);
    assert!(spread > 30.0 * (ENSEMBLE - 1) as f64 * SPACING, "{spread}");
    assert!(sensitivity_note(n, &finals).contains("times the initial spread"));
}
