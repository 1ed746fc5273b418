//! How a [`Comparison`] prints: the table, the solutions' warnings and a legend of every
//! column, as text (`Display`; `{:#}` without the legend) and as markdown
//! ([`Comparison::to_markdown`]), from one set of cells.

use super::compared::ComparedSolution;
use super::{Comparison, OrderStatus, SchemeReport};
use crate::solve::solution::Warning;
use std::fmt;

/// The column headers, in order.
const COLUMNS: [&str; 8] = [
    "scheme",
    "max error",
    "order",
    "theory",
    "max |ΔE|",
    "other's resid.",
    "Newton",
    "time",
];

/// The mark after an order in the table, as the legend explains it.
fn mark(status: Option<OrderStatus>) -> &'static str {
    status.map_or("", OrderStatus::mark)
}

fn cells<S: ComparedSolution>(name: &str, r: &SchemeReport<S>) -> [String; 8] {
    let dash = || "—".to_string();
    [
        name.to_string(),
        r.error.map_or_else(dash, |e| format!("{e:.3e}")),
        r.order
            .map_or_else(dash, |o| format!("{o:.2}{}", mark(r.order_status))),
        r.theoretical_order.map_or_else(dash, |o| o.to_string()),
        r.energy_deviation.map_or_else(dash, |e| format!("{e:.3e}")),
        format!("{:.3e}", r.residual_of_other),
        r.solution.newton_iterations().to_string(),
        r.wall_time.map_or_else(dash, |t| format!("{t:.3?}")),
    ]
}

impl<S: ComparedSolution> Comparison<S> {
    /// The warnings of the two solutions (e.g. [`Warning::IllPosedFractional`]), each once.
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, Problem, Side, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 20)?, Embedding::finite_difference(Side::Backward));
    /// let comparison = problem.compare_ivp(1.0, 0.0)?;
    /// assert!(comparison.warnings().is_empty());
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn warnings(&self) -> Vec<Warning> {
        let mut all = self.direct.solution.warnings().to_vec();
        for w in self.variational.solution.warnings() {
            if !all.contains(w) {
                all.push(*w);
            }
        }
        all
    }

    /// What every column of the table shows, as `(column, explanation)`: where the errors
    /// come from, how the order was computed (from how many more solves, or read off the runs)
    /// and what its marks mean, and why the energy column is empty when it is.
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, Problem, Side, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 20)?, Embedding::finite_difference(Side::Backward));
    /// let comparison = problem.compare_ivp(1.0, 0.0)?;
    /// let legend = comparison.legend();
    /// assert!(legend.iter().any(|(column, _)| *column == "order"));
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn legend(&self) -> Vec<(&'static str, String)> {
        let n = self.grid.n();
        let error = match self.direct.error {
            Some(_) => format!("max_k |Q_k − q(t_k)|∞ against the {}", self.reference),
            None => "— : no reference was given".to_string(),
        };
        let estimate = match self.direct.error {
            Some(_) => "e the error against the reference",
            None => "e the self-convergence estimate ‖Q_N − Q_2N‖∞ on the nodes of the N grid",
        };
        let grids: Vec<String> = self.order_grids.iter().map(usize::to_string).collect();
        let source = if self.order_grids.is_empty() {
            "not computed (—): no finer grid was solved (CompareOptions::order off, or the runs \
             end at N)"
                .to_string()
        } else if self.extra_solves > 0 {
            format!(
                "from {} more solves per scheme made by this comparison, on N = {}",
                self.extra_solves,
                grids.join(", ")
            )
        } else {
            format!(
                "read off the runs the comparison was built from (N = {}; no extra solve)",
                grids.join(", ")
            )
        };
        let order = format!(
            "observed order log₂(e_N / e_2N) from N = {n} to 2N, {estimate}; {source}. \
             Unmarked: agrees with the order at 2N and with the limit the orders extrapolate \
             to within {tol}; {legend}",
            tol = OrderStatus::TOLERANCE,
            legend = OrderStatus::legend()
        );
        let energy = match self.energy_not_conserved {
            None => "max_k |E_k − E_first| of the discrete energy E_k = V_k·∂L/∂v − L on the \
                     quadrature nodes (per interval for the midpoint and trapezoidal \
                     embeddings): L is autonomous and the embedding classical, so the flow \
                     conserves E and the drift is the scheme's"
                .to_string(),
            Some(reason) => format!("— : {reason}, so its drift would measure nothing"),
        };
        vec![
            (
                COLUMNS[0],
                "direct: the embedding applied to the Euler–Lagrange equation; variational: \
                 the critical points of the discrete action"
                    .to_string(),
            ),
            (COLUMNS[1], error),
            (COLUMNS[2], order),
            (
                COLUMNS[3],
                "the scheme's order on a smooth solution of a general Lagrangian \
                 (Embedding::order): 2 for the midpoint and trapezoidal embeddings, 1 for the \
                 others. The variational recurrence of Gauss-FDEσ (and of its asymmetric form) \
                 is Störmer–Verlet on L = ½vᵀMv − U(x) with a constant M, second order there as \
                 a boundary value problem or from the second-order start; — : Gauss-GLEσ with \
                 α < 1, whose order depends on the data"
                    .to_string(),
            ),
            (COLUMNS[4], energy),
            (
                COLUMNS[5],
                "max-norm of the other scheme's residual on this scheme's solution: zero to \
                 round-off exactly when the embedding is coherent"
                    .to_string(),
            ),
            (
                COLUMNS[6],
                "Newton iterations: summed over the steps (initial value problem) or of the \
                 global system (boundary value problem)"
                    .to_string(),
            ),
            (
                COLUMNS[7],
                match self.direct.wall_time {
                    Some(_) => format!("wall time of the solve on N = {n}"),
                    None => "— : not measured (CompareOptions::timing off: the solves ran in \
                             parallel, where each one's time would measure the others too)"
                        .to_string(),
                },
            ),
        ]
    }

    /// The table as markdown: the heading line, a markdown table, the distance between the
    /// solutions, the warnings and the legend as a list.
    ///
    /// ```
    /// # use varembed::{Embedding, Grid, Problem, Side, lagrangian};
    /// # #[lagrangian]
    /// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
    /// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 20)?, Embedding::finite_difference(Side::Backward));
    /// let comparison = problem.compare_ivp(1.0, 0.0)?;
    /// let markdown = comparison.to_markdown();
    /// assert!(markdown.contains("| direct |"));
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn to_markdown(&self) -> String {
        let escape = |s: &str| s.replace('|', "\\|");
        let row = |cells: &[String]| {
            let cells: Vec<String> = cells.iter().map(|c| escape(c)).collect();
            format!("| {} |\n", cells.join(" | "))
        };
        let mut md = format!("{}\n\n", self.heading());
        let header: Vec<String> = COLUMNS.iter().map(|c| c.to_string()).collect();
        md += &row(&header);
        md += "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
        md += &row(&cells("direct", &self.direct));
        md += &row(&cells("variational", &self.variational));
        md += &format!(
            "\nmax |Q_direct − Q_variational| = {:.3e}\n",
            self.max_distance
        );
        for w in self.warnings() {
            md += &format!("\n**Warning:** {w}\n");
        }
        md += "\n";
        for (column, text) in self.legend() {
            md += &format!("- **{column}**: {text}\n");
        }
        md
    }

    fn heading(&self) -> String {
        format!(
            "{} under {}, N = {}, h = {:.3e}, errors against: {}",
            self.kind,
            self.embedding,
            self.grid.n(),
            self.grid.h(),
            self.reference
        )
    }
}

/// The table, its legend last; `{:#}` without the legend.
impl<S: ComparedSolution> fmt::Display for Comparison<S> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{}", self.heading())?;
        let line = |f: &mut fmt::Formatter<'_>, c: &[String; 8]| {
            writeln!(
                f,
                "  {:<12} {:>11} {:>7} {:>6} {:>11} {:>15} {:>8} {:>11}",
                c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]
            )
        };
        line(f, &COLUMNS.map(str::to_string))?;
        line(f, &cells("direct", &self.direct))?;
        line(f, &cells("variational", &self.variational))?;
        write!(
            f,
            "  max |Q_direct − Q_variational| = {:.3e}",
            self.max_distance
        )?;
        for w in self.warnings() {
            write!(f, "\n  warning: {w}")?;
        }
        if f.alternate() {
            return Ok(());
        }
        write!(f, "\n  legend:")?;
        for (column, text) in self.legend() {
            write!(f, "\n    {column}: {text}")?;
        }
        Ok(())
    }
}
