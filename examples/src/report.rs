//! The report folder: one markdown summary (`README.md`) and the SVG figures of every scene.

use crate::console;
use crate::output::{self, OutputError};
use crate::plot;
use crate::scene::SceneReport;
use std::fmt::Write as _;
use std::path::Path;

/// The markers between which [`update_section`] replaces text.
pub const SUMMARY_START: &str = "<!-- tour-summary:start -->";
/// See [`SUMMARY_START`].
pub const SUMMARY_END: &str = "<!-- tour-summary:end -->";
/// The markers of the cost table in `core/docs/choosing.md` ([`cost_table`]).
pub const COST_START: &str = "<!-- cost-per-step:start -->";
/// See [`COST_START`].
pub const COST_END: &str = "<!-- cost-per-step:end -->";

/// The title of the report's section that explains the columns of every comparison table.
pub const LEGEND_TITLE: &str = "Reading the comparison tables";

/// The file name of a scene's work–precision figure.
pub fn work_precision_file(scene: &SceneReport) -> String {
    format!("{}-work-precision.svg", scene.name)
}

/// The summary table: per scene and scheme, the finest `N` of the sweep, its error and wall
/// time, and the observed orders `log₂(e_N / e_{2N})` over the last four sizes
/// (`N, 2N, 4N, 8N` with `8N` the finest).
pub fn summary_table(scenes: &[SceneReport]) -> String {
    let mut s = String::from(
        "| scene | scheme | N | max error | orders (last 4 N) | time (s) |\n\
         | --- | --- | ---: | ---: | --- | ---: |\n",
    );
    for scene in scenes {
        for line in &scene.sweep {
            let Some(last) = line.points.last() else {
                continue;
            };
            let orders = line.marked_orders();
            let orders = &orders[orders.len().saturating_sub(3)..];
            let _ = writeln!(
                s,
                "| {} | {} | {} | {:.2e} | {} | {:.2e} |",
                scene.title,
                line.label,
                last.n,
                last.error,
                orders.join(", "),
                last.seconds
            );
        }
    }
    s.push_str(
        "\nAn order marked `*` is pre-asymptotic (the next order differs from it by more than \
         0.1), `~` drifting (the orders' extrapolated limit is further than 0.1 from it), `!` \
         not converging (order at most 0.1), `ε` at round-off, `?` unchecked (no next order): \
         `varembed::OrderStatus`.\n",
    );
    s
}

/// Writes every figure and `README.md` into `dir` (created if needed); returns the summary
/// table. `repeats` is how many solves each time is the median of.
pub fn write(
    dir: &Path,
    scenes: &[SceneReport],
    header: &str,
    repeats: usize,
) -> output::Result<String> {
    output::create_dir_all(dir)?;
    let table = summary_table(scenes);
    let mut html = Html::default();
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# varembed: the tour\n\n{header}\n\n## Summary\n\n{table}"
    );
    // The comparison tables' legend, once for all of them.
    let _ = writeln!(md, "## {LEGEND_TITLE}\n");
    for (column, explanation) in console::table_legend(repeats) {
        let _ = writeln!(md, "- **{column}**: {explanation}");
    }
    let _ = writeln!(md);
    let time = match repeats {
        1 => "the wall time of one solve".to_string(),
        r => format!("the wall time of a solve (the median of {r})"),
    };
    for scene in scenes {
        let wp = work_precision_file(scene);
        let wp_caption = format!(
            "{}: work–precision, max error against the {} over {time}, one marker per N",
            scene.title, scene.reference
        );
        plot::work_precision(
            dir,
            &wp,
            &format!("{}: work–precision ({})", scene.title, scene.reference),
            &scene.sweep,
        )?;
        for figure in &scene.figures {
            plot::linear(dir, figure)?;
        }
        let _ = writeln!(md, "## {}\n", scene.title);
        html.section(&scene.title);
        for note in &scene.notes {
            let _ = writeln!(md, "{note}\n");
        }
        let _ = writeln!(md, "Errors against: {}.\n", scene.reference);
        let figures = std::iter::once((wp.as_str(), wp_caption.as_str())).chain(
            scene
                .figures
                .iter()
                .map(|f| (f.file.as_str(), f.title.as_str())),
        );
        for (file, caption) in figures {
            // The alt text is not shown by every viewer: the caption is a line of its own.
            let _ = writeln!(md, "![{caption}]({file})\n\n*{caption}.*\n");
            html.figure(file, caption);
        }
        let _ = writeln!(
            md,
            "Sweep (error, {time} in s, and the observed order from the previous N):\n"
        );
        let _ = writeln!(md, "| scheme | N | max error | time (s) | order |");
        let _ = writeln!(md, "| --- | ---: | ---: | ---: | ---: |");
        for line in &scene.sweep {
            let orders = line.marked_orders();
            for (i, p) in line.points.iter().enumerate() {
                let order = if i == 0 {
                    String::new()
                } else {
                    orders[i - 1].clone()
                };
                let _ = writeln!(
                    md,
                    "| {} | {} | {:.3e} | {:.2e} | {order} |",
                    line.label, p.n, p.error, p.seconds
                );
            }
        }
        for line in &scene.sweep {
            for (n, e) in &line.failures {
                let _ = writeln!(md, "\n- {} failed at N = {n}: {e}", line.label);
            }
        }
        let _ = writeln!(
            md,
            "\nComparison tables (their columns: [{LEGEND_TITLE}](#{})):\n\n```text",
            LEGEND_TITLE.to_lowercase().replace(' ', "-")
        );
        for t in &scene.tables {
            let _ = writeln!(md, "{t}\n");
        }
        let _ = writeln!(md, "```\n");
    }
    output::write(&dir.join("README.md"), md)?;
    output::write(&dir.join("index.html"), html.finish(header))?;
    Ok(table)
}

/// `index.html`: every figure of the report with its caption, scene by scene, for a browser.
#[derive(Default)]
struct Html {
    body: String,
}

impl Html {
    fn section(&mut self, title: &str) {
        let _ = writeln!(self.body, "<h2>{}</h2>", escape(title));
    }

    fn figure(&mut self, file: &str, caption: &str) {
        let (file, caption) = (escape(file), escape(caption));
        let _ = writeln!(
            self.body,
            "<figure><img src=\"{file}\" alt=\"{caption}\"><figcaption>{caption}</figcaption></figure>"
        );
    }

    fn finish(self, header: &str) -> String {
        format!(
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
             <title>varembed: the tour</title>\n<style>body {{ font-family: sans-serif; \
             max-width: 960px; margin: auto; }} img {{ max-width: 100%; }} figcaption {{ \
             font-style: italic; margin-bottom: 2em; }}</style>\n</head>\n<body>\n\
             <h1>varembed: the tour</h1>\n<p>{}</p>\n<p>Tables, notes and sweeps: \
             <a href=\"README.md\">README.md</a>.</p>\n{}</body>\n</html>\n",
            escape(header),
            self.body
        )
    }
}

/// `text` with the HTML metacharacters escaped.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Rewrites the committed documents of the checkout at `root` from a full tour whose report
/// [`write()`] has just written to `root/report`: the summary in `README.md` (the pendulum's
/// work–precision figure, the summary `table` and the `header` saying how it was generated),
/// and the cost table of `core/docs/choosing.md`, read off `report/README.md` by [`cost_table`].
pub fn update_docs(root: &Path, table: &str, header: &str) -> output::Result<()> {
    let section = format!(
        "![pendulum work–precision](report/pendulum-work-precision.svg)\n\n{table}\n{header}\n"
    );
    update_section(&root.join("README.md"), &section)?;
    let report = output::read_to_string(&root.join("report").join("README.md"))?;
    update_between(
        &root.join("core/docs/choosing.md"),
        COST_START,
        COST_END,
        &cost_table(&report),
    )
}

/// The cost per step of every scheme of every scene, read off a report's markdown (the
/// `README.md` that [`write()`] produces): per sweep line, its finest `N`, the wall time of that
/// solve and the time per step. Reading the committed report rather than a run keeps the page
/// that shows the table and the report it cites in agreement (a test compares them).
pub fn cost_table(report: &str) -> String {
    let mut rows: Vec<(String, String, usize, f64)> = Vec::new();
    let mut scene = None;
    for line in report.lines() {
        if let Some(title) = line.strip_prefix("## ") {
            scene = (title != "Summary" && title != LEGEND_TITLE).then(|| title.to_string());
            continue;
        }
        let Some(scene) = &scene else { continue };
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        // A sweep row: `| scheme | N | max error | time (s) | order |`.
        let [_, label, n, _, seconds, _, _] = cells[..] else {
            continue;
        };
        let (Ok(n), Ok(seconds)) = (n.parse::<usize>(), seconds.parse::<f64>()) else {
            continue;
        };
        match rows.last_mut() {
            // The rows of a line come in increasing N: keep the last, the finest.
            Some(last) if last.0 == *scene && last.1 == label => (last.2, last.3) = (n, seconds),
            _ => rows.push((scene.clone(), label.to_string(), n, seconds)),
        }
    }
    let mut table = String::from(
        "| scene | scheme | finest N | time of the solve (s) | cost per step (ns) |\n\
         | --- | --- | ---: | ---: | ---: |\n",
    );
    for (scene, label, n, seconds) in rows {
        let _ = writeln!(
            table,
            "| {scene} | {label} | {n} | {seconds:.2e} | {:.0} |",
            seconds / n as f64 * 1e9
        );
    }
    table
}

/// Replaces the text between [`SUMMARY_START`] and [`SUMMARY_END`] in `file` with `content`.
/// Errors if the markers are missing (the file is left untouched).
pub fn update_section(file: &Path, content: &str) -> output::Result<()> {
    update_between(file, SUMMARY_START, SUMMARY_END, content)
}

/// Replaces the text between the markers `start` and `end` in `file` with `content`. Errors if
/// the markers are missing or out of order (the file is left untouched).
pub fn update_between(
    file: &Path,
    start: &'static str,
    end: &'static str,
    content: &str,
) -> output::Result<()> {
    let text = output::read_to_string(file)?;
    let markers = OutputError::Markers {
        path: file.to_path_buf(),
        start,
    };
    let (Some(i), Some(j)) = (text.find(start), text.find(end)) else {
        return Err(markers);
    };
    if j < i {
        return Err(markers);
    }
    let updated = format!("{}{start}\n{content}{}", &text[..i], &text[j..]);
    output::write(file, updated)
}
