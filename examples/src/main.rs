//! The main job: `cargo run --release -p varembed-examples [-- --quick] [--verbose] [--out DIR]
//! [--update-docs]`.
//!
//! Runs every scene, prints a few lines about each (what ran, the best line of its sweep, any
//! warning; with `--verbose` also its comparison tables, whose legend is printed once, and the
//! summary table at the end), and writes the report folder: `README.md` with the summary table
//! and every scene's notes, tables and sweeps, and the SVG figures. The folder is decided when
//! the tour runs: `--out DIR`, or by default `target/varembed-report/`
//! (`target/varembed-report-quick/` with `--quick`) under the Cargo workspace containing the
//! current directory — ignored by git, so the tour leaves a checkout clean. It is printed at
//! the end.
//!
//! `--update-docs` is for refreshing the committed results on purpose: it writes the report to
//! the checkout's `report/` and rewrites the summary in its `README.md` and the cost table of
//! `core/docs/choosing.md` (between their markers). It needs the full tour (not `--quick`)
//! and a checkout at or above the current directory.

use indicatif::{ProgressBar, ProgressStyle};
use std::error::Error;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;
use varembed_examples::scene::{Context, Mode};
use varembed_examples::{console, output, report};

const USAGE: &str = "usage: varembed-tour [--quick] [--verbose] [--out DIR] [--update-docs]";

const HELP: &str = "\
Runs every scene of varembed, prints a few lines about each and writes the report folder.

  --quick        small grids and short sweeps: the whole tour in seconds
  --verbose, -v  also print every comparison table (the legend of their columns once) and,
                 at the end, the summary table of every sweep
  --out DIR      write the report into DIR (default: target/varembed-report, or
                 target/varembed-report-quick, under the workspace)
  --update-docs  write the report into the checkout's report/ and rewrite README.md's summary
                 and the cost table of core/docs/choosing.md (full tour only, no --out)
  --help, -h     this text";

/// What the command line asked for.
struct Args {
    mode: Mode,
    verbose: bool,
    out: Option<PathBuf>,
    update_docs: bool,
}

fn parse_args() -> Result<Option<Args>, String> {
    let mut parsed = Args {
        mode: Mode::Full,
        verbose: false,
        out: None,
        update_docs: false,
    };
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--quick" => parsed.mode = Mode::Quick,
            "--verbose" | "-v" => parsed.verbose = true,
            "--out" => parsed.out = Some(PathBuf::from(args.next().ok_or(USAGE)?)),
            "--update-docs" => parsed.update_docs = true,
            "-h" | "--help" => return Ok(None),
            other => return Err(format!("unknown argument {other:?}\n{USAGE}")),
        }
    }
    if parsed.update_docs && (parsed.mode == Mode::Quick || parsed.out.is_some()) {
        return Err(format!(
            "--update-docs writes the full tour into the checkout: it takes neither --quick nor \
             --out\n{USAGE}"
        ));
    }
    Ok(Some(parsed))
}

fn main() -> ExitCode {
    let args = match parse_args() {
        Ok(Some(args)) => args,
        Ok(None) => {
            println!("{USAGE}\n\n{HELP}");
            return ExitCode::SUCCESS;
        }
        Err(message) => {
            eprintln!("{message}");
            return ExitCode::from(2);
        }
    };
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            // Display, not Debug: every error names what it was about (a path, a step).
            eprintln!("error: {error}");
            let mut source = error.source();
            while let Some(cause) = source {
                eprintln!("  caused by: {cause}");
                source = cause.source();
            }
            ExitCode::FAILURE
        }
    }
}

fn run(args: &Args) -> Result<(), Box<dyn Error>> {
    let cwd = output::at("read", &PathBuf::from("."), std::env::current_dir())?;
    let checkout = args
        .update_docs
        .then(|| output::checkout_root(&cwd))
        .transpose()?;
    let out = match (&checkout, &args.out) {
        (Some(root), _) => root.join("report"),
        (None, Some(dir)) => dir.clone(),
        (None, None) => output::default_dir(&cwd, args.mode == Mode::Quick),
    };

    // Created before the tour runs, so an unwritable folder fails in a second, not after it.
    output::create_dir_all(&out)?;

    let progress = ProgressBar::new(0).with_style(ProgressStyle::with_template(
        "{spinner} {msg:24} [{bar:40}] {pos}/{len} solves ({elapsed})",
    )?);
    let cx = Context::new(args.mode, progress);
    // The legend once, before the scenes; then each scene as it finishes.
    println!("{}\n", console::header(cx.repeats));
    if args.verbose {
        println!("{}\n", console::table_legend_text(cx.repeats));
    }
    let started = Instant::now();
    let reports = varembed_examples::run_tour(&cx, |scene| {
        cx.progress.suspend(|| {
            println!("{}\n", console::scene_summary(scene));
            if args.verbose {
                println!("{}\n", console::scene_tables(scene));
            }
        });
    })?;
    cx.progress.finish_and_clear();
    let elapsed = started.elapsed();
    let header = format!(
        "Generated by `cargo run --release -p varembed-examples{}` in {:.1} s{}.",
        match (args.mode, args.update_docs) {
            (Mode::Quick, _) => " -- --quick",
            (Mode::Full, true) => " -- --update-docs",
            (Mode::Full, false) => "",
        },
        elapsed.as_secs_f64(),
        match cx.repeats {
            1 => String::new(),
            r => format!("; each time is the median of {r} solves"),
        }
    );
    let table = report::write(&out, &reports, &header, cx.repeats)?;
    if args.verbose {
        println!("{table}");
    }
    if let Some(root) = checkout {
        report::update_docs(&root, &table, &header)?;
        println!("README.md summary and docs tables updated.");
    }
    println!(
        "Report written to {} ({:.1} s).",
        out.display(),
        elapsed.as_secs_f64()
    );
    Ok(())
}
