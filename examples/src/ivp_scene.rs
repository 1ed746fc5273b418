//! The shared run of an initial value scene: the work–precision sweep of every scheme over
//! doubling `N`, the comparison tables at one `N` (read off the sweep's solutions where the
//! sweep has them, so each grid is solved once per scheme), and the trajectories and energy
//! error of the first table.

use crate::cost;
use crate::reference::ReferenceCurve;
use crate::scene::{Context, Doubling, Figure, SceneReport, Series, SweepLine, failed_table};
use std::borrow::Cow;
use varembed::Convergence;
use varembed::{
    CompareOptions, Comparison, Embedding, Grid, Lagrangian, Problem, Reference, Scheme, Side,
    Solution, Start, Vector,
};

/// How the trajectory figure draws the solution.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Trajectory {
    /// Every component of `q` against `t`.
    Time,
    /// `q_1` against `q_0` (an orbit in the plane; `D = 2`).
    Plane,
    /// The listed components of `q` against `t` (a chain of many particles: a few of them).
    Components(&'static [usize]),
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
    /// The `N` of this line, when not the scene's sweep (a high-order scheme reaches the
    /// reference's accuracy on far fewer steps).
    pub sweep: Option<Doubling>,
}

impl Variant {
    /// The `N` this line is swept over: its own, or the scene's.
    pub fn sizes(&self, scene: Doubling) -> Doubling {
        self.sweep.unwrap_or(scene)
    }
}

/// The three Gauss-FDE− lines every initial value scene sweeps: the direct scheme
/// and the variational scheme with the discrete Legendre start (both the paper's schemes as
/// stated), and the variational scheme with the second-order start (which lets the
/// Störmer–Verlet recurrence of a separable `L` reach its order 2).
pub fn standard_variants() -> Vec<Variant> {
    let fde = Embedding::finite_difference(Side::Backward);
    vec![
        Variant {
            label: "direct FDE−",
            embedding: fde,
            scheme: Scheme::Direct,
            start: Start::Legendre,
            sweep: None,
        },
        Variant {
            label: "variational FDE−, Legendre start",
            embedding: fde,
            scheme: Scheme::Variational,
            start: Start::Legendre,
            sweep: None,
        },
        Variant {
            label: "variational FDE−, second-order start",
            embedding: fde,
            scheme: Scheme::Variational,
            start: Start::SecondOrder,
            sweep: None,
        },
    ]
}

/// The `N` of the higher-order lines of a scene: the second-order midpoint and trapezoidal
/// embeddings, and the Gauss–Legendre integrators with 2 and 4 stages.
#[derive(Clone, Copy, Debug)]
pub struct HigherOrderSweeps {
    /// Both schemes of the midpoint and of the trapezoidal embedding (order 2).
    pub second_order: Doubling,
    /// Gauss–Legendre `s = 2` (order 4).
    pub gauss2: Doubling,
    /// Gauss–Legendre `s = 4` (order 8).
    pub gauss4: Doubling,
}

/// [`standard_variants`], then the higher-order lines: the direct and variational schemes of
/// the midpoint and trapezoidal embeddings (discrete Legendre start, second order for these
/// symmetric discrete Lagrangians) and the variational Gauss–Legendre integrators with 2 and 4
/// stages (orders 4 and 8; they have no direct scheme), each over its own `N`.
pub fn all_variants(sweeps: HigherOrderSweeps) -> Vec<Variant> {
    let line = |label, embedding, scheme, sweep| Variant {
        label,
        embedding,
        scheme,
        start: Start::Legendre,
        sweep: Some(sweep),
    };
    let gauss = |stages| Embedding::gauss_legendre(stages).expect("2 and 4 stages exist");
    let (second, midpoint, trapezoidal) = (
        sweeps.second_order,
        Embedding::midpoint(),
        Embedding::trapezoidal(),
    );
    let mut variants = standard_variants();
    variants.extend([
        line("direct midpoint", midpoint, Scheme::Direct, second),
        line(
            "variational midpoint",
            midpoint,
            Scheme::Variational,
            second,
        ),
        line("direct trapezoidal", trapezoidal, Scheme::Direct, second),
        line(
            "variational trapezoidal",
            trapezoidal,
            Scheme::Variational,
            second,
        ),
        line(
            "Gauss–Legendre s = 2",
            gauss(2),
            Scheme::Variational,
            sweeps.gauss2,
        ),
        line(
            "Gauss–Legendre s = 4",
            gauss(4),
            Scheme::Variational,
            sweeps.gauss4,
        ),
    ]);
    variants
}

/// How a start is named in the tables and the solve ledger.
pub fn start_name(start: Start) -> &'static str {
    match start {
        Start::Legendre => "discrete Legendre start",
        Start::SecondOrder => "second-order start",
    }
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
    /// `N` of the comparison tables, the trajectory and the energy figures. When the sweep
    /// holds `N` and `2N` (the order needs both), the tables of the swept schemes are read off
    /// the sweep's runs.
    pub table_n: usize,
    /// The embeddings compared in tables (Legendre start), then Gauss-FDE− with the
    /// second-order start.
    pub table_embeddings: Vec<Embedding>,
    /// The `N` of the sweep.
    pub sweep: Doubling,
    /// The lines of the sweep.
    pub variants: Vec<Variant>,
    /// How the trajectory is drawn.
    pub trajectory: Trajectory,
    /// The units of the model's time, position and energy, for the figures' axis titles.
    pub units: Units,
    /// Which scheme to use, read off the sweep ([`cost::advice`]).
    pub advice: Advice,
}

/// What the scene's advice compares the lines at, and why the winner wins.
#[derive(Clone, Debug)]
pub struct Advice {
    /// The max error the lines are compared at.
    pub target: f64,
    /// What makes the winner win (order, structure), as the scene knows it.
    pub why: &'static str,
}

/// The units a nondimensional model measures time, position and energy in (e.g. `√(l/g)`,
/// `rad`, `mgl` for a pendulum), as the figures' axis titles print them.
#[derive(Clone, Copy, Debug)]
pub struct Units {
    /// Unit of `t`.
    pub time: &'static str,
    /// Unit of `q`.
    pub position: &'static str,
    /// Unit of the energy `E`.
    pub energy: &'static str,
}

impl Units {
    /// `time t (unit)`.
    pub fn time_axis(&self) -> String {
        format!("time t ({})", self.time)
    }
}

/// Everything an initial value scene solved, as the library returned it.
pub struct IvpRuns<const D: usize> {
    /// One run per variant over the sweep's `N`, in the order of the variants.
    pub sweep: Vec<Convergence<Solution<D>>>,
    /// The comparison tables at `table_n` with their start: every table embedding with the
    /// discrete Legendre start, then Gauss-FDE− with the second-order start. A table whose
    /// runs failed at `table_n` is the failure, as text ([`failed_table`]).
    pub tables: Vec<(Start, Result<Comparison<Solution<D>>, String>)>,
}

/// Where a table takes the run of one scheme from.
#[derive(Clone, Copy)]
enum Source {
    /// The sweep's run of this variant.
    Sweep(usize),
    /// A run of its own on `table_n` and `2 table_n`.
    Own,
}

// `Sync`: the comparisons share the model with their solves, which may run on other threads.
impl<L: Lagrangian<D> + Sync, const D: usize> IvpScene<'_, L, D> {
    /// Runs the sweep and the tables, and builds the report.
    pub fn run(&self, cx: &Context) -> varembed::Result<SceneReport> {
        Ok(self.report(&self.solve(cx)?))
    }

    /// The lines of the work–precision sweep alone (no tables).
    pub fn sweep(&self, cx: &Context) -> varembed::Result<Vec<SweepLine>> {
        let curve = |t: f64| self.reference.q(t);
        let runs = self.sweep_runs(cx, self.reference(&curve))?;
        Ok(self.sweep_lines(&runs))
    }

    /// Solves every variant over the sweep, then the tables: a table's scheme that a variant
    /// sweeps over `table_n` and `2 table_n` is read off that run, any other gets a run of its
    /// own on those two grids.
    pub fn solve(&self, cx: &Context) -> varembed::Result<IvpRuns<D>> {
        let curve = |t: f64| self.reference.q(t);
        let reference = self.reference(&curve);
        let swept = |v: &Variant| {
            let sizes = v.sizes(self.sweep);
            sizes.contains(self.table_n) && sizes.contains(2 * self.table_n)
        };
        let plan: Vec<(Embedding, Start, [Source; 2])> = self
            .table_runs()
            .map(|(embedding, start)| {
                let source = |scheme: Scheme| {
                    let same = |v: &Variant| {
                        v.embedding == embedding && v.scheme == scheme && v.start == start
                    };
                    match self.variants.iter().position(same) {
                        Some(i) if swept(&self.variants[i]) => Source::Sweep(i),
                        _ => Source::Own,
                    }
                };
                let sources = [source(Scheme::Direct), source(Scheme::Variational)];
                (embedding, start, sources)
            })
            .collect();
        let own_runs = plan
            .iter()
            .flat_map(|(_, _, sources)| sources)
            .filter(|s| matches!(s, Source::Own))
            .count();
        let swept_runs: usize = self
            .variants
            .iter()
            .map(|v| v.sizes(self.sweep).count)
            .sum();
        cx.progress
            .inc_length((cx.repeats * (swept_runs + 2 * own_runs)) as u64);
        let sweep = self.sweep_runs(cx, reference)?;
        let table_grid = Grid::new(self.interval.0, self.interval.1, self.table_n)?;
        let mut tables = Vec::with_capacity(plan.len());
        for (embedding, start, sources) in plan {
            let problem = Problem::new(self.lagrangian, table_grid, embedding);
            let options = CompareOptions {
                reference,
                start,
                order: true,
                timing: true,
            };
            let run = |source: Source, scheme: Scheme| match source {
                Source::Sweep(i) => Cow::Borrowed(&sweep[i]),
                Source::Own => {
                    let run =
                        cx.timed(|| problem.convergence_ivp(scheme, self.q0, self.v0, &options, 2));
                    cx.record_run(self.name, &describe(embedding, scheme, start), &run);
                    Cow::Owned(run)
                }
            };
            let direct = run(sources[0], Scheme::Direct);
            let variational = run(sources[1], Scheme::Variational);
            let comparison = problem.compare_runs(&direct, &variational).map_err(|e| {
                let runs = [("direct", &*direct), ("variational", &*variational)];
                failed_table(embedding, self.table_n, runs, &e)
            });
            tables.push((start, comparison));
        }
        Ok(IvpRuns { sweep, tables })
    }

    /// The report of a solved scene: the tables as text, the sweep's lines, and the trajectory
    /// and energy figures of the first table.
    pub fn report(&self, runs: &IvpRuns<D>) -> SceneReport {
        let tables = runs
            .tables
            .iter()
            .map(|(start, c)| match c {
                Ok(c) => format!("{c:#}\n  ({})", start_name(*start)),
                Err(failed) => format!("{failed}\n  ({})", start_name(*start)),
            })
            .collect();
        // The figures draw the first table that solved.
        let figures = match runs.tables.iter().find_map(|(_, c)| c.as_ref().ok()) {
            Some(first) => vec![self.trajectory_figure(first), self.energy_figure(first)],
            None => Vec::new(),
        };
        let sweep = self.sweep_lines(&runs.sweep);
        let mut notes = self.notes.clone();
        notes.push(cost::advice(&sweep, self.advice.target, self.advice.why));
        SceneReport {
            name: self.name,
            title: self.title.to_string(),
            notes,
            tables,
            reference: self.reference.name.clone(),
            sweep,
            advice_target: Some(self.advice.target),
            figures,
        }
    }

    fn reference<'c>(&'c self, curve: &'c dyn Fn(f64) -> Vector<D>) -> Reference<'c, Vector<D>> {
        if self.exact {
            Reference::Exact(curve)
        } else {
            Reference::Computed {
                name: &self.reference.name,
                q: curve,
            }
        }
    }

    /// The table embeddings with the Legendre start, then Gauss-FDE− with the second-order
    /// start.
    fn table_runs(&self) -> impl Iterator<Item = (Embedding, Start)> + '_ {
        let second_order = (
            Embedding::finite_difference(Side::Backward),
            Start::SecondOrder,
        );
        self.table_embeddings
            .iter()
            .map(|e| (*e, Start::Legendre))
            .chain([second_order])
    }

    fn sweep_runs(
        &self,
        cx: &Context,
        reference: Reference<'_, Vector<D>>,
    ) -> varembed::Result<Vec<Convergence<Solution<D>>>> {
        self.variants
            .iter()
            .map(|variant| {
                let sizes = variant.sizes(self.sweep);
                let grid = Grid::new(self.interval.0, self.interval.1, sizes.n0)?;
                let options = CompareOptions {
                    reference,
                    start: variant.start,
                    order: true,
                    // The sweeps' wall times are the work–precision plots' x axis.
                    timing: true,
                };
                let problem = Problem::new(self.lagrangian, grid, variant.embedding);
                let run = cx.timed(|| {
                    problem.convergence_ivp(variant.scheme, self.q0, self.v0, &options, sizes.count)
                });
                let what = describe(variant.embedding, variant.scheme, variant.start);
                cx.record_run(self.name, &what, &run);
                Ok(run)
            })
            .collect()
    }

    fn sweep_lines(&self, runs: &[Convergence<Solution<D>>]) -> Vec<SweepLine> {
        self.variants
            .iter()
            .zip(runs)
            .map(|(variant, run)| SweepLine::from_run(variant.label, run))
            .collect()
    }

    fn trajectory_figure(&self, c: &Comparison<Solution<D>>) -> Figure {
        let grid = c.grid;
        let nodes = |q: &[Vector<D>], i: usize| -> Vec<(f64, f64)> {
            match self.trajectory {
                Trajectory::Time | Trajectory::Components(_) => q
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
        let components: Vec<usize> = match self.trajectory {
            Trajectory::Time => (0..D).collect(),
            Trajectory::Plane => vec![0],
            Trajectory::Components(listed) => listed.iter().copied().filter(|&i| i < D).collect(),
        };
        let mut series = Vec::new();
        for &i in &components {
            let which = if D > 1 && self.trajectory != Trajectory::Plane {
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
        let position = self.units.position;
        let (x_label, y_label) = match self.trajectory {
            Trajectory::Time | Trajectory::Components(_) => {
                (self.units.time_axis(), format!("q ({position})"))
            }
            Trajectory::Plane => (format!("q0 ({position})"), format!("q1 ({position})")),
        };
        Figure {
            file: format!("{}-trajectory.svg", self.name),
            title: format!("{}: {}, N = {}", self.title, c.embedding, grid.n()),
            x_label,
            y_label,
            series,
        }
    }

    fn energy_figure(&self, c: &Comparison<Solution<D>>) -> Figure {
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
            x_label: self.units.time_axis(),
            y_label: format!("energy error E_k − E(t_k) ({})", self.units.energy),
            series: vec![
                Series::new("direct", error(&c.direct.energy)),
                Series::new("variational", error(&c.variational.energy)),
            ],
        }
    }
}

/// A scheme of an embedding with its start, as the solve ledger names it.
fn describe(embedding: Embedding, scheme: Scheme, start: Start) -> String {
    format!("{embedding} {scheme}, {}", start_name(start))
}
