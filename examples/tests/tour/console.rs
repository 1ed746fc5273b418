//! What the tour prints and how it times: by default a header once and a few lines per scene,
//! no comparison table and no legend; `--verbose` adds every table and the legend of their
//! columns, once; each time is the median of the repeated solves.

use std::process::Command;
use std::time::Duration;
use varembed::{CompareOptions, Convergence, Grid, Problem, Reference, Scheme, Solution, Vector};
use varembed_examples::console;
use varembed_examples::scene::{Context, Mode, median};
use varembed_examples::scenes::{ALL, harmonic};

/// The tour binary on the quick grids with `args`, writing into a folder of its own; its
/// standard output.
fn tour(name: &str, args: &[&str]) -> String {
    let dir = std::env::temp_dir().join(format!("varembed-console-{name}-{}", std::process::id()));
    let run = Command::new(env!("CARGO_BIN_EXE_varembed-tour"))
        .args(["--quick", "--out"])
        .arg(&dir)
        .args(args)
        .output()
        .expect("the tour binary runs");
    let stdout = String::from_utf8(run.stdout).expect("UTF-8");
    assert!(
        run.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&run.stderr)
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
    stdout
}

/// The header of a comparison table, as `Comparison`'s `Display` prints it.
const TABLE_HEADER: &str = "  scheme         max error";

#[test]
fn by_default_the_tour_prints_a_few_lines_per_scene() {
    let out = tour("quiet", &[]);
    assert_eq!(out.matches("The tour: every scene").count(), 1, "{out}");
    assert_eq!(out.matches("\n== ").count(), ALL.len(), "{out}");
    assert_eq!(out.matches("\n  best: ").count(), ALL.len(), "{out}");
    assert!(!out.contains(TABLE_HEADER), "{out}");
    assert!(
        !out.contains("legend") && !out.contains("Columns of the"),
        "{out}"
    );
    assert!(!out.contains("| scene | scheme |"), "{out}");
    assert!(
        out.trim_end()
            .lines()
            .last()
            .unwrap()
            .starts_with("Report written to ")
    );
    // Five or six lines per scene (one more per failure) and a header.
    let lines = out.lines().count();
    assert!(lines <= 12 + 7 * ALL.len(), "{lines} lines:\n{out}");
}

#[test]
fn verbose_prints_every_table_and_their_legend_once() {
    let out = tour("verbose", &["--verbose"]);
    assert_eq!(out.matches("Columns of the comparison tables:").count(), 1);
    assert_eq!(out.matches("\n  other's resid.: ").count(), 1, "{out}");
    assert!(!out.contains("legend:"), "{out}");
    // Every scene's summary, then its tables: the comparisons (with the column header) and the
    // large chain's scaling table.
    assert_eq!(out.matches("\n== ").count(), ALL.len());
    assert!(out.matches(TABLE_HEADER).count() >= 3 * ALL.len(), "{out}");
    assert!(out.contains("Cost per step against d"), "{out}");
    // And the summary table at the end.
    assert!(out.contains("| scene | scheme |"), "{out}");
    let help = Command::new(env!("CARGO_BIN_EXE_varembed-tour"))
        .arg("--help")
        .output()
        .expect("the tour binary runs");
    let help = String::from_utf8(help.stdout).expect("UTF-8");
    assert!(help.contains("--verbose"), "{help}");
}

/// The tour's legend explains exactly the columns of the library's tables.
#[test]
fn the_legend_names_every_column_of_the_library_table() {
    let cx = Context::hidden(Mode::Quick);
    let exact = harmonic::reference();
    let scene = harmonic::scene(&cx, &harmonic::MODEL, &exact);
    let runs = scene.solve(&cx).expect("the harmonic scene solves");
    let comparison = runs.tables[0].1.as_ref().expect("the first table solves");
    let library: Vec<&str> = comparison.legend().iter().map(|(c, _)| *c).collect();
    let tour: Vec<&str> = console::table_legend(5).iter().map(|(c, _)| *c).collect();
    assert_eq!(tour, library);
    assert!(console::table_legend(5)[7].1.contains("median of 5"));
}

#[test]
fn median_of_durations() {
    let ms = Duration::from_millis;
    assert_eq!(median(vec![ms(5), ms(1), ms(90)]), ms(5));
    assert_eq!(median(vec![ms(4), ms(1), ms(2), ms(90)]), ms(3));
    assert_eq!(median(vec![ms(7)]), ms(7));
    assert_eq!(median(Vec::new()), Duration::ZERO);
}

/// `Context::timed` keeps the first run's solutions and gives each level the median of its
/// times over the repeats: one slow outlier per level does not show. The repeats tick the
/// progress bar and leave the ledger alone.
#[test]
fn a_timed_run_reports_the_median_of_its_repeats() {
    let problem = Problem::new(
        &harmonic::MODEL,
        Grid::new(0.0, 1.0, 10).unwrap(),
        varembed::Embedding::recommended(),
    );
    let exact = |t: f64| Vector::<1>::new(t.cos());
    let options = CompareOptions {
        reference: Reference::Exact(&exact),
        ..Default::default()
    };
    let base = problem.convergence_ivp(Scheme::Variational, 1.0, 0.0, &options, 3);
    // The times of the three calls at each level: the second call is the slow one.
    let ms = Duration::from_millis;
    let calls = [
        [ms(2), ms(3), ms(4)],
        [ms(900), ms(900), ms(900)],
        [ms(1), ms(5), ms(6)],
    ];
    let mut call = 0;
    let cx = Context::hidden(Mode::Quick).with_repeats(3);
    let timed: Convergence<Solution<1>> = cx.timed(|| {
        let mut run = base.clone();
        for (level, time) in run.levels.iter_mut().zip(calls[call]) {
            level.wall_time = Some(time);
        }
        call += 1;
        run
    });
    assert_eq!(call, 3);
    let times: Vec<Option<Duration>> = timed.levels.iter().map(|l| l.wall_time).collect();
    assert_eq!(times, [Some(ms(2)), Some(ms(5)), Some(ms(6))]);
    for (level, first) in timed.levels.iter().zip(&base.levels) {
        assert_eq!(level.solution, first.solution);
        assert_eq!(level.error, first.error);
    }
    assert_eq!(cx.progress.position(), 2 * 3);
    assert!(cx.solves().is_empty());
}

#[test]
fn prose_is_wrapped_at_spaces_with_its_indent() {
    let words = "word ".repeat(40);
    let text = console::wrap(&format!("  {words}"), "    ");
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines.len() > 1);
    assert!(lines[0].starts_with("  word"));
    assert!(lines[1..].iter().all(|l| l.starts_with("    word")));
    assert!(lines.iter().all(|l| l.chars().count() <= 96));
    assert_eq!(text.split_whitespace().count(), 40);
}
