//! The shared run of an initial value scene: comparison tables at one `N`, trajectories and
//! energy error of that run, and the work–precision sweep of every scheme over doubling `N`.

use crate::reference::ReferenceCurve;
use crate::scene::{Context, Figure, SceneReport, Series, SweepLine, SweepPoint};
use varembed::{
    CompareOptions, Comparison, Embedding, Grid, Lagrangian, Problem, Reference, Scheme, Side,
    Start, Vector,
};

/// How the trajectory figure draws the solution.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Trajectory {
    /// Every component of `q` against `t`.
    Time,
    /// `q_1` against `q_0` (an orbit in the plane; `D = 2`).
    Plane,
}

/// One line of the work–precision sweep: a scheme of an embedding, with a start.
#[derive(Clone, Copy, Debug)]
pub struct Variant {
    /// Legend entry.
    pub label: &'static str,
    /// The embedding.
    pub embedding: Embedding,
    /// Direct or variational.
    pub scheme: Scheme,
    /// How `Q_1` is obtained.
    pub start: Start,
}

/// The three lines every initial value scene sweeps, all under Gauss-FDE−: the direct scheme
/// and the variational scheme with the discrete Legendre start (both the paper's schemes as
/// stated), and the variational scheme with the second-order start (DESIGN.md, Solving).
pub fn standard_variants() -> Vec<Variant> {
    let fde = Embedding::finite_difference(Side::Backward);
    vec![
        Variant {
            label: "direct FDE−",
            embedding: fde,
            scheme: Scheme::Direct,
            start: Start::Legendre,
        },
        Variant {
            label: "variational FDE−, Legendre start",
            embedding: fde,
            scheme: Scheme::Variational,
            start: Start::Legendre,
        },
        Variant {
            label: "variational FDE−, second-order start",
            embedding: fde,
            scheme: Scheme::Variational,
            start: Start::SecondOrder,
        },
    ]
}

/// An initial value scene: a Lagrangian, an interval, initial data and a reference.
pub struct IvpScene<'a, L, const D: usize> {
    /// File-name stem.
    pub name: &'static str,
    /// Section title.
    pub title: &'static str,
    /// What the scene shows (markdown paragraphs).
    pub notes: Vec<String>,
    /// The Lagrangian (a `#[lagrangian]` struct).
    pub lagrangian: &'a L,
    /// `[a, b]`.
    pub interval: (f64, f64),
    /// `q(a)`.
    pub q0: Vector<D>,
    /// `q̇(a)`.
    pub v0: Vector<D>,
    /// The exact or independently computed solution.
    pub reference: &'a ReferenceCurve<D>,
    /// Whether `reference` is a closed form (named "exact" in the tables).
    pub exact: bool,
    /// `N` of the comparison tables, the trajectory and the energy figures.
    pub table_n: usize,
    /// The embeddings compared in tables (Legendre start), then Gauss-FDE− with the
    /// second-order start.
    pub table_embeddings: Vec<Embedding>,
    /// The doubling `N` of the sweep.
    pub sweep: Vec<usize>,
    /// The lines of the sweep.
    pub variants: Vec<Variant>,
    /// How the trajectory is drawn.
    pub trajectory: Trajectory,
}

impl<L: Lagrangian<D>, const D: usize> IvpScene<'_, L, D> {
    /// Runs the tables, the figures and the sweep.
    pub fn run(&self, cx: &Context) -> varembed::Result<SceneReport> {
        let curve = |t: f64| self.reference.q(t);
        let reference = if self.exact {
            Reference::Exact(&curve)
        } else {
            Reference::Computed {
                name: &self.reference.name,
                q: &curve,
            }
        };
        let grid = Grid::new(self.interval.0, self.interval.1, self.table_n)?;
        let mut tables = Vec::new();
        let mut first = None;
        let runs = self
            .table_embeddings
            .iter()
            .map(|e| (*e, Start::Legendre))
            .chain([(
                Embedding::finite_difference(Side::Backward),
                Start::SecondOrder,
            )]);
        for (embedding, start) in runs {
            let options = CompareOptions {
                reference,
                start,
                order: true,
            };
            let comparison = Problem::new(self.lagrangian, grid, embedding)
                .compare_ivp_with(self.q0, self.v0, &options)?;
            let start_name = match start {
                Start::Legendre => "discrete Legendre start",
                Start::SecondOrder => "second-order start",
            };
            tables.push(format!("{comparison}\n  ({start_name})"));
            first.get_or_insert(comparison);
        }
        let first = first.expect("at least one table");
        let figures = vec![self.trajectory_figure(&first), self.energy_figure(&first)];
        Ok(SceneReport {
            name: self.name,
            title: self.title.to_string(),
            notes: self.notes.clone(),
            tables,
            reference: self.reference.name.clone(),
            sweep: self.sweep(cx)?,
            figures,
        })
    }

    /// Every variant over every `N` of the sweep: wall time of the solve and max error.
    pub fn sweep(&self, cx: &Context) -> varembed::Result<Vec<SweepLine>> {
        cx.progress
            .inc_length((self.variants.len() * self.sweep.len()) as u64);
        let mut lines = Vec::new();
        for variant in &self.variants {
            let (mut points, mut failures) = (Vec::new(), Vec::new());
            for &n in &self.sweep {
                let grid = Grid::new(self.interval.0, self.interval.1, n)?;
                let problem = Problem::new(self.lagrangian, grid, variant.embedding);
                match cx.time(|| {
                    problem.solve_ivp_with(variant.scheme, self.q0, self.v0, variant.start)
                }) {
                    Ok((solution, seconds)) => {
                        let error = max_error(&grid, &solution.q, |t| self.reference.q(t));
                        points.push(SweepPoint { n, seconds, error });
                    }
                    Err(e) => failures.push((n, e.to_string())),
                }
                cx.progress.inc(1);
            }
            lines.push(SweepLine {
                label: variant.label.to_string(),
                points,
                failures,
            });
        }
        Ok(lines)
    }

    fn trajectory_figure(&self, c: &Comparison<D>) -> Figure {
        let grid = c.grid;
        let nodes = |q: &[Vector<D>], i: usize| -> Vec<(f64, f64)> {
            match self.trajectory {
                Trajectory::Time => q
                    .iter()
                    .enumerate()
                    .map(|(k, x)| (grid.t(k), x[i]))
                    .collect(),
                Trajectory::Plane => q.iter().map(|x| (x[0], x[1])).collect(),
            }
        };
        let reference: Vec<Vector<D>> = (0..=grid.n())
            .map(|k| self.reference.q(grid.t(k)))
            .collect();
        let components = match self.trajectory {
            Trajectory::Time => D,
            Trajectory::Plane => 1,
        };
        let mut series = Vec::new();
        for i in 0..components {
            let which = if components > 1 {
                format!(" q{i}")
            } else {
                String::new()
            };
            series.push(Series::new(
                format!("reference{which}"),
                nodes(&reference, i),
            ));
            series.push(Series::new(
                format!("direct{which}"),
                nodes(&c.direct.solution.q, i),
            ));
            series.push(Series::new(
                format!("variational{which}"),
                nodes(&c.variational.solution.q, i),
            ));
        }
        let (x_label, y_label) = match self.trajectory {
            Trajectory::Time => ("t", "q"),
            Trajectory::Plane => ("q0", "q1"),
        };
        Figure {
            file: format!("{}-trajectory.svg", self.name),
            title: format!("{}: {}, N = {}", self.title, c.embedding, grid.n()),
            x_label: x_label.to_string(),
            y_label: y_label.to_string(),
            series,
        }
    }

    fn energy_figure(&self, c: &Comparison<D>) -> Figure {
        let grid = c.grid;
        let rows = c.direct.solution.embedding.quadrature_rows(grid.n());
        let reference_energy = |t: f64| {
            let (q, v) = self.reference.at(t);
            self.lagrangian.energy(&q, &v, t)
        };
        let error = |energy: &[f64]| -> Vec<(f64, f64)> {
            rows.clone()
                .zip(energy)
                .map(|(k, e)| (grid.t(k), e - reference_energy(grid.t(k))))
                .collect()
        };
        Figure {
            file: format!("{}-energy.svg", self.name),
            title: format!(
                "{}: energy error E_k − E(t_k), {}, N = {}",
                self.title,
                c.embedding,
                grid.n()
            ),
            x_label: "t".to_string(),
            y_label: "E_k − E(t_k)".to_string(),
            series: vec![
                Series::new("direct", error(&c.direct.energy)),
                Series::new("variational", error(&c.variational.energy)),
            ],
        }
    }
}

/// `max_k |Q_k − q(t_k)|∞`.
pub fn max_error<const D: usize>(
    grid: &Grid,
    q: &[Vector<D>],
    reference: impl Fn(f64) -> Vector<D>,
) -> f64 {
    q.iter()
        .enumerate()
        .map(|(k, x)| (x - reference(grid.t(k))).amax())
        .fold(0.0, f64::max)
}
