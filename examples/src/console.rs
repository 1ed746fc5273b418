//! What the tour prints. By default a few lines per scene — what ran, the best line of its
//! sweep with its error, order and time, and any warning or failure — after a header, printed
//! once, that says how to read them. `--verbose` adds the legend of the comparison tables
//! (once) and every scene's tables; the report holds both whatever is printed.

use crate::cost::{self, Reach};
use crate::scene::{SceneReport, SweepLine, SweepPoint};
use std::fmt::Write as _;
use varembed::OrderStatus;

/// The width the tour wraps its prose to.
const WIDTH: usize = 96;

/// What the per-scene lines mean, printed once before the first scene. `repeats` is how many
/// solves each time is the median of ([`Context::repeats`](crate::scene::Context::repeats)).
pub fn header(repeats: usize) -> String {
    let times = match repeats {
        1 => "the wall time of one solve".to_string(),
        r => format!("the wall time of a solve, the median of {r}"),
    };
    wrap(
        &format!(
            "The tour: every scene solved by each scheme over doubling N (its work–precision \
             sweep) and compared in tables. Per scene: what ran; the best line of the sweep \
             (the cheapest to reach the scene's target max error, else the smallest error) \
             with, at its finest N, the max error against the reference, the last observed \
             order log₂(e_N / e_2N) and {times}; then any warning or failure. The marks after \
             an order: {}. Every table: --verbose here, and the report (its folder is printed \
             at the end).",
            OrderStatus::legend()
        ),
        "",
    )
}

/// `text` broken at spaces into lines of at most `WIDTH` (96) characters (a longer word stays
/// whole), every line after the first starting with `indent`.
pub fn wrap(text: &str, indent: &str) -> String {
    let lead = &text[..text.len() - text.trim_start().len()];
    let mut out = String::new();
    let mut line = lead.to_string();
    let mut empty = true;
    for word in text.split_whitespace() {
        if !empty && line.chars().count() + 1 + word.chars().count() > WIDTH {
            out.push_str(&line);
            out.push('\n');
            line = indent.to_string();
            empty = true;
        }
        if !empty {
            line.push(' ');
        }
        line.push_str(word);
        empty = false;
    }
    out.push_str(&line);
    out
}

/// The columns of the comparison tables, as `(column, explanation)`: the tour's form of
/// [`varembed::Comparison::legend`], said once for every table (each table's heading names its
/// `N` and its reference; every table is read off runs the tour timed, with no extra solve).
pub fn table_legend(repeats: usize) -> Vec<(&'static str, String)> {
    let time = match repeats {
        1 => "wall time of the solve on N".to_string(),
        r => format!("wall time of the solve on N, the median of {r} solves"),
    };
    vec![
        (
            "scheme",
            "direct: the embedding applied to the Euler–Lagrange equation; variational: the \
             critical points of the discrete action"
                .to_string(),
        ),
        (
            "max error",
            "max_k |Q_k − q(t_k)|∞ against the reference named in the table's heading".to_string(),
        ),
        (
            "order",
            format!(
                "observed order log₂(e_N / e_2N) from the table's N to 2N, read off the runs the \
                 table is built from; {}",
                OrderStatus::legend()
            ),
        ),
        (
            "theory",
            "the scheme's order on a smooth solution of a general Lagrangian (Embedding::order); \
             — for Gauss-GLEσ with α < 1, whose order depends on the data"
                .to_string(),
        ),
        (
            "max |ΔE|",
            "max_k |E_k − E_first| of the discrete energy E_k = V_k·∂L/∂v − L; — where the flow \
             does not conserve E (L depends on t, or the embedding is fractional)"
                .to_string(),
        ),
        (
            "other's resid.",
            "the other scheme's residual on this scheme's solution, each row against the size of \
             the terms it sums (force plus weighted momenta): zero to round-off exactly when the \
             embedding is coherent"
                .to_string(),
        ),
        (
            "Newton",
            "Newton iterations, summed over the steps (initial value problem) or of the global \
             system (boundary value problem)"
                .to_string(),
        ),
        ("time", time),
    ]
}

/// [`table_legend`] as printed: a heading line, then one indented line per column.
pub fn table_legend_text(repeats: usize) -> String {
    let mut text = String::from("Columns of the comparison tables:");
    for (column, explanation) in table_legend(repeats) {
        let _ = write!(
            text,
            "\n{}",
            wrap(&format!("  {column}: {explanation}"), "    ")
        );
    }
    text
}

/// The best line of a scene's sweep and why it is the best.
#[derive(Clone, Debug)]
pub struct Best<'a> {
    /// The line.
    pub line: &'a SweepLine,
    /// Its finest point.
    pub finest: SweepPoint,
    /// Why it is the best: the cheapest to reach the scene's target, or the smallest error.
    pub why: String,
}

/// The best line of `scene`'s sweep: among the lines whose measured points reach the scene's
/// [`advice_target`](SceneReport::advice_target), the one that does so in the least time (as
/// the scene's advice reads it, [`cost::cost_to_reach`]); without a target, or when no line
/// reaches it, the line whose finest point has the smallest error.
pub fn best(scene: &SceneReport) -> Option<Best<'_>> {
    let finest = |line: &SweepLine| line.points.last().copied();
    if let Some(target) = scene.advice_target {
        let cheapest = scene
            .sweep
            .iter()
            .filter_map(|line| Some((line, cost::cost_to_reach(line, target)?)))
            .filter(|(_, cost)| cost.reach == Reach::Measured)
            .min_by(|a, b| a.1.seconds.total_cmp(&b.1.seconds));
        if let Some((line, cost)) = cheapest {
            return Some(Best {
                line,
                finest: finest(line)?,
                why: format!(
                    "the cheapest to max error {target:.0e}: N ≈ {:.0}, {:.2e} s",
                    cost.n, cost.seconds
                ),
            });
        }
    }
    let (line, point) = scene
        .sweep
        .iter()
        .filter_map(|line| Some((line, finest(line)?)))
        .min_by(|a, b| a.1.error.total_cmp(&b.1.error))?;
    let why = match scene.advice_target {
        Some(target) => format!("the smallest error; no line reaches {target:.0e}"),
        None => "the smallest error".to_string(),
    };
    Some(Best {
        line,
        finest: point,
        why,
    })
}

/// A scene in a few lines: its title; what ran (the sweep's lines and sizes, the number of
/// tables) and the reference of its errors; the best line ([`best`]) with the error, last order and time at its
/// finest `N`; then every warning of its tables and every failure of its sweep and tables.
pub fn scene_summary(scene: &SceneReport) -> String {
    let mut text = format!("== {}\n", scene.title);
    let sizes = scene.sweep.iter().flat_map(|l| {
        l.points
            .iter()
            .map(|p| p.n)
            .chain(l.failures.iter().map(|f| f.0))
    });
    let (lo, hi) = sizes.fold((usize::MAX, 0), |(lo, hi), n| (lo.min(n), hi.max(n)));
    let grids: usize = scene
        .sweep
        .iter()
        .map(|l| l.points.len() + l.failures.len())
        .sum();
    let _ = writeln!(
        text,
        "  ran: {} lines of the sweep, N = {lo} … {hi} ({grids} grids), {} tables",
        scene.sweep.len(),
        scene.tables.len(),
    );
    let against = format!("  errors against: {}", scene.reference);
    let _ = writeln!(text, "{}", wrap(&against, "    "));
    match best(scene) {
        Some(best) => {
            let order = best.line.marked_orders().last().cloned();
            let line = format!("  best: {} — {}", best.line.label, best.why);
            let _ = writeln!(
                text,
                "{}\n        at N = {}: max error {:.2e}, order {}, {:.2e} s",
                wrap(&line, "        "),
                best.finest.n,
                best.finest.error,
                order.as_deref().unwrap_or("—"),
                best.finest.seconds
            );
        }
        None => text.push_str("  best: no line solved\n"),
    }
    for warning in warnings(scene) {
        let _ = writeln!(text, "{}", wrap(&format!("  {warning}"), "    "));
    }
    text.trim_end().to_string()
}

/// The warnings of a scene's tables (each once), the tables that could not be built, and the
/// lines of its sweep that failed somewhere (with the first failure).
pub fn warnings(scene: &SceneReport) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for table in &scene.tables {
        let first = table.lines().next().unwrap_or("");
        if first.ends_with(": no comparison") {
            out.push(format!("failed: {first}"));
        }
        for line in table.lines() {
            if let Some(warning) = line.trim_start().strip_prefix("warning: ") {
                let warning = format!("warning: {warning}");
                if !out.contains(&warning) {
                    out.push(warning);
                }
            }
        }
    }
    for line in &scene.sweep {
        if let Some((n, error)) = line.failures.first() {
            out.push(format!(
                "failed: {} at {} of its N (first at N = {n}): {error}",
                line.label,
                line.failures.len()
            ));
        }
    }
    out
}

/// A scene's comparison tables, as `--verbose` prints them after its summary.
pub fn scene_tables(scene: &SceneReport) -> String {
    scene.tables.join("\n\n")
}
