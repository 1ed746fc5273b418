//! [`Comparison`]: the direct and the variational scheme of one embedding side by side; and
//! [`Convergence`]: one scheme solved on `N, 2N, 4N, …` steps, with the error, wall time and
//! observed order of every grid.
//!
//! Per scheme a comparison reports: the solution, the residual of the *other* scheme on it
//! (zero to round-off exactly when the embedding is coherent), the error against a reference (an
//! exact solution or an independently computed curve, named in the table), the energy
//! `E = v·∂L/∂v − L` along the run and its largest deviation from its first value, the observed
//! order of convergence, Newton iterations and wall time; and the largest distance between the
//! two solutions.
//!
//! The observed order has one definition, [`observed_order`](crate::observed_order): between successive grids of a
//! doubling run it is `log₂(e_N / e_{2N})`, with `e` the error against the reference when there
//! is one, otherwise the self-convergence estimate `e_N = ‖Q_N − Q_{2N}‖` (max-norm over the
//! nodes of the coarser grid), so that `log₂(‖Q_N − Q_{2N}‖ / ‖Q_{2N} − Q_{4N}‖)`. One order
//! alone does not show whether the errors have reached their power law, so every order carries
//! an [`OrderStatus`]: checked against the next order of the run, or at round-off. A
//! comparison's order therefore needs solves on `2N`, `4N` (and `8N` without a reference):
//! optional ([`CompareOptions::order`]), and the table states how many it made. A comparison
//! is also built from two [`Convergence`] runs
//! ([`Problem::compare_runs`](crate::Problem::compare_runs), which solves nothing), so a caller
//! that sweeps `N` anyway (the tour's work–precision report) reads its tables off the sweep's
//! own solutions, and the order in a table is the sweep's order at that `N`.
//!
//! The table prints, besides the numbers, a legend of its columns
//! ([`Comparison::legend`]), and renders as markdown too ([`Comparison::to_markdown`]).
//!
//! One comparison serves both paths: the reports are generic over the solution
//! ([`ComparedSolution`]: [`Solution<D>`](crate::Solution) of a [`Problem`](crate::Problem),
//! [`DynSolution`](crate::DynSolution) of a [`DynProblem`](crate::DynProblem)), the options
//! over the value of the reference curve (`Vector<D>`, `Vec<f64>`), and the columns are
//! computed and printed by the same code.

use crate::embedding::{Embedding, Scheme};
use crate::ensemble::{Ensemble, map_costliest_first};
use crate::error::{Error, Result};
use crate::grid::Grid;
use crate::lagrangian::Vector;
use crate::solve::start::Start;
use std::time::{Duration, Instant};

pub(crate) mod compared;
pub(crate) mod convergence;
mod dyn_problem;
pub(crate) mod order;
mod table;

use compared::ComparedSolution;
use convergence::{Convergence, Level};

use order::OrderStatus;

/// `max_k |Q_k − q(t_k)|∞`: the error of the discrete curve `q` on `grid` against `reference`.
///
/// ```
/// use varembed::{Grid, Vector, max_error};
/// let grid = Grid::new(0.0, 1.0, 2)?;
/// let q = [0.0, 0.5, 0.9].map(Vector::<1>::new);
/// assert!((max_error(&grid, &q, |t| Vector::<1>::new(t)) - 0.1).abs() < 1e-15);
/// # Ok::<(), varembed::Error>(())
/// ```
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

/// What errors are measured against: a curve `t ↦ q(t)` whose value `Q` is a [`Vector<D>`]
/// for a [`Problem`](crate::Problem) and a `Vec<f64>` of length `d` for a
/// [`DynProblem`](crate::DynProblem) (a new vector per node: a comparison stores every node
/// anyway, so this costs no more memory than the solutions).
///
/// ```
/// # use varembed::{CompareOptions, Embedding, Grid, Problem, Reference, Scheme, Side, Vector, lagrangian};
/// # #[lagrangian]
/// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
/// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 20)?, Embedding::finite_difference(Side::Backward));
/// let exact = |t: f64| Vector::<1>::new(t.cos());
/// let options = CompareOptions { reference: Reference::Exact(&exact), ..Default::default() };
/// let comparison = problem.compare_ivp_with(1.0, 0.0, &options)?;
/// assert_eq!(comparison.reference, "exact solution");
/// # Ok::<(), varembed::Error>(())
/// ```
pub enum Reference<'a, Q> {
    /// No reference: errors are not reported, the order is the self-convergence estimate.
    None,
    /// An exact solution `t ↦ q(t)`.
    Exact(&'a dyn Fn(f64) -> Q),
    /// An independently computed solution `t ↦ q(t)` (e.g. a high-order integrator on a fine
    /// grid), with the name under which the table reports it.
    Computed {
        /// How the reference was computed (shown in the table).
        name: &'a str,
        /// The reference curve.
        q: &'a dyn Fn(f64) -> Q,
    },
}

// By hand: a derive would ask `Q: Copy`, and `Vec<f64>` is not, though only references to
// curves are held.
impl<Q> Clone for Reference<'_, Q> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<Q> Copy for Reference<'_, Q> {}

impl<Q> Reference<'_, Q> {
    fn curve(&self) -> Option<&dyn Fn(f64) -> Q> {
        match self {
            Reference::None => None,
            Reference::Exact(q) | Reference::Computed { q, .. } => Some(*q),
        }
    }
    fn name(&self) -> &str {
        match self {
            Reference::None => "none",
            Reference::Exact(_) => "exact solution",
            Reference::Computed { name, .. } => name,
        }
    }
}

/// Options of the comparisons ([`Problem::compare_ivp_with`](crate::Problem::compare_ivp_with), [`Problem::compare_bvp_with`](crate::Problem::compare_bvp_with)) and
/// of the convergence runs ([`Problem::convergence_ivp`](crate::Problem::convergence_ivp), [`Problem::convergence_bvp`](crate::Problem::convergence_bvp)),
/// and of their [`DynProblem`](crate::DynProblem) counterparts; `Q` is the value of the
/// reference curve: [`Vector<D>`] for a [`Problem`](crate::Problem), `Vec<f64>` of length `d`
/// for a [`DynProblem`](crate::DynProblem).
///
/// ```
/// # use varembed::{CompareOptions, Embedding, Grid, Problem, Reference, Scheme, Side, Vector, lagrangian};
/// # #[lagrangian]
/// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
/// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 20)?, Embedding::finite_difference(Side::Backward));
/// let exact = |t: f64| Vector::<1>::new(t.cos());
/// let options = CompareOptions { reference: Reference::Exact(&exact), ..Default::default() };
/// let options = CompareOptions { order: false, ..options };
/// let comparison = problem.compare_ivp_with(1.0, 0.0, &options)?;
/// assert_eq!((comparison.extra_solves, comparison.direct.order), (0, None));
/// # Ok::<(), varembed::Error>(())
/// ```
pub struct CompareOptions<'a, Q> {
    /// The reference for the error column.
    pub reference: Reference<'a, Q>,
    /// The start of initial value problems.
    pub start: Start,
    /// Whether a comparison solves on `2N` and `4N` (and `8N` without a reference) for the
    /// observed order and its status: per scheme 2 (3) more solves, about 6 (14) times the cost
    /// of the solve on `N` when that cost is linear in `N`. The table states which ran
    /// ([`Comparison::extra_solves`]). Convergence runs ignore it: their number of grids is an
    /// argument.
    pub order: bool,
    /// Whether each solve's wall time is measured (the table's `time` column; on by default).
    /// Timed, the solves run one at a time on the calling thread, since solves running side
    /// by side slow each other down and their times would measure the machine's load. Off,
    /// the solves of the grids (and of both schemes, in a comparison) run in parallel on
    /// rayon's pool when the `parallel` feature is on, with the serial run's numbers bit for
    /// bit, and the wall times are `None` (`—` in the table). A convergence study's levels cost
    /// about `1 : 2 : 4 : 8`, so the finest grid bounds its speed-up: near `15/8` for one
    /// scheme on four grids, however many cores.
    pub timing: bool,
}

// By hand, as for `Reference`: no bound on `Q`.
impl<Q> Clone for CompareOptions<'_, Q> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<Q> Copy for CompareOptions<'_, Q> {}

impl<Q> Default for CompareOptions<'_, Q> {
    fn default() -> Self {
        CompareOptions {
            reference: Reference::None,
            start: Start::Legendre,
            order: true,
            timing: true,
        }
    }
}

/// One scheme's line of a [`Comparison`].
///
/// ```
/// # use varembed::{CompareOptions, Embedding, Grid, Problem, Reference, Scheme, Side, Vector, lagrangian};
/// # #[lagrangian]
/// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
/// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 20)?, Embedding::finite_difference(Side::Backward));
/// let exact = |t: f64| Vector::<1>::new(t.cos());
/// let options = CompareOptions { reference: Reference::Exact(&exact), ..Default::default() };
/// let comparison = problem.compare_ivp_with(1.0, 0.0, &options)?;
/// let report = &comparison.variational;
/// assert!(report.error.unwrap() < 0.05 && report.energy_deviation.unwrap() < 0.05);
/// # Ok::<(), varembed::Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct SchemeReport<S> {
    /// The solution ([`Solution<D>`](crate::Solution) or [`DynSolution`](crate::DynSolution)).
    pub solution: S,
    /// The other scheme's residual evaluated on this solution, row by row relative to the size
    /// of the terms the row sums: `max_k |r_k|∞ / s_k` with `s_k = |F_k|∞ + Σ_m |B[k, m]| |p_m|∞`
    /// for the row `r_k = F_k + Σ_m B[k, m] p_m` (a force plus momenta weighted by the scheme's
    /// operator). It is unchanged by the scale of `L` and does not grow with a Lagrangian that
    /// grows along the run; round-off leaves about `1e-16` to `1e-13` on a coherent pair.
    pub residual_of_other: f64,
    /// Max over the nodes of `|Q_k − q(t_k)|∞` against the reference, if any.
    pub error: Option<f64>,
    /// `E = V_k·∂L/∂v − L` at the quadrature nodes `I_σ` (per interval for the midpoint and
    /// trapezoidal embeddings: [`Problem::quadrature_energies`](crate::Problem::quadrature_energies)).
    pub energy: Vec<f64>,
    /// `max_k |E_k − E_first|`, where the flow conserves `E` (an autonomous Lagrangian under a
    /// classical embedding); `None` otherwise ([`Comparison::energy_not_conserved`] says why),
    /// since the drift of a quantity the problem does not conserve is no error.
    pub energy_deviation: Option<f64>,
    /// [`observed_order`](crate::observed_order) from `N` to the next grid of the run (`2N`), if the run has one.
    pub order: Option<f64>,
    /// How far [`order`](Self::order) can be trusted ([`Convergence::order_status_at`]), when
    /// there is one.
    pub order_status: Option<OrderStatus>,
    /// The scheme's order on a smooth solution of a general Lagrangian,
    /// [`Embedding::order`](crate::Embedding::order), shown next to the observed one.
    pub theoretical_order: Option<u32>,
    /// Wall time of the solve on `N` steps; `None` when it was not measured
    /// ([`CompareOptions::timing`] off).
    pub wall_time: Option<Duration>,
}

/// The direct and variational schemes of one problem, side by side; `Display` prints a table.
///
/// Per scheme: the solution, the residual of the *other* scheme on it (zero to round-off
/// exactly when the embedding is coherent), the error against a reference (an exact solution or
/// an independently computed curve, named in the table), the energy `E = v·∂L/∂v − L` along
/// the run and its largest deviation from its first value, the observed order of convergence,
/// Newton iterations and wall time; and the largest distance between the two solutions.
///
/// The observed order is `log₂(e_N / e_{2N})` with the errors against the reference when there
/// is one, otherwise the self-convergence estimate `log₂(‖Q_N − Q_{2N}‖ / ‖Q_{2N} − Q_{4N}‖)`
/// (max-norm over the nodes of the coarse grid), with its [`OrderStatus`]; it comes from more
/// solves on `2N`, `4N` (and `8N`) when [`CompareOptions::order`] asks for them, or from the
/// runs the comparison was built from. The energy is reported only where the flow conserves
/// it. `Display` prints the table with its legend and the solutions' warnings; the alternate
/// form `{:#}` leaves the legend out, for a program that prints many tables and their
/// [`legend`](Self::legend) once; [`to_markdown`](Self::to_markdown) the same as markdown.
///
/// ```
/// # use varembed::{CompareOptions, Embedding, Grid, Problem, Reference, Scheme, Side, Vector, lagrangian};
/// # #[lagrangian]
/// # fn oscillator(x: f64, v: f64) -> f64 { 0.5 * v * v - 0.5 * x * x }
/// let problem = Problem::new(&Oscillator, Grid::new(0.0, 1.0, 20)?, Embedding::finite_difference(Side::Backward));
/// let exact = |t: f64| Vector::<1>::new(t.cos());
/// let options = CompareOptions { reference: Reference::Exact(&exact), ..Default::default() };
/// let comparison = problem.compare_ivp_with(1.0, 0.0, &options)?;
/// assert_eq!(comparison.grid.n(), 20);
/// assert!(comparison.to_string().contains("variational"));
/// // The same table without its legend.
/// let table = format!("{comparison:#}");
/// assert!(table.contains("variational") && !table.contains("legend"));
/// assert!(comparison.to_string().starts_with(&table));
/// # Ok::<(), varembed::Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct Comparison<S> {
    /// What was solved: "initial value problem" or "boundary value problem".
    pub kind: &'static str,
    /// The embedding, as text.
    pub embedding: String,
    /// The grid.
    pub grid: Grid,
    /// Which reference the errors are against.
    pub reference: String,
    /// The direct scheme.
    pub direct: SchemeReport<S>,
    /// The variational scheme.
    pub variational: SchemeReport<S>,
    /// `max_k |Q_direct,k − Q_variational,k|∞`.
    pub max_distance: f64,
    /// Why the energy column is empty: `Some(reason)` when the flow does not conserve
    /// `E = v·∂L/∂v − L` (the Lagrangian may depend on `t`, as its
    /// [`dependence`](crate::Lagrangian::dependence) says; or the embedding is fractional), `None`
    /// when it does and [`SchemeReport::energy_deviation`] is reported.
    pub energy_not_conserved: Option<&'static str>,
    /// The finer grids (their `N`) whose solutions the orders and their status come from:
    /// `2N` and `4N` against a reference, also `8N` by self-convergence, as far as the runs
    /// have them; empty without an order.
    pub order_grids: Vec<usize>,
    /// How many solves per scheme this comparison made beyond the one on `N`, for the orders:
    /// `order_grids.len()` for [`Problem::compare_ivp_with`](crate::Problem::compare_ivp_with)
    /// and [`Problem::compare_bvp_with`](crate::Problem::compare_bvp_with) with
    /// [`CompareOptions::order`], 0 without, and 0 for
    /// [`Problem::compare_runs`](crate::Problem::compare_runs), which reads the runs it is given.
    pub extra_solves: usize,
}

/// What a comparison needs of a problem of either path: its grid and embedding, whether its
/// flow conserves the energy, and the energy and a scheme's residual on a solution.
/// A private view of [`Problem`](crate::Problem) implements it (its comparisons in
/// `problem/comparisons.rs`), and one of [`DynProblem`](crate::DynProblem) (in
/// `compare/dyn_problem.rs`).
pub(crate) trait Compares {
    /// The solutions it compares.
    type Solution: ComparedSolution;

    /// The grid of `N` steps the comparison is at.
    fn grid(&self) -> Grid;

    /// The embedding.
    fn embedding(&self) -> Embedding;

    /// Whether the Lagrangian may depend on `t` (its `dependence()`).
    fn depends_on_t(&self) -> bool;

    /// Whether a generalised force acts (a [`Forced`](crate::Forced) model). The default: no.
    fn is_forced(&self) -> bool {
        false
    }

    /// `E = V_k·∂L/∂v − L` at the quadrature nodes of `solution`, and the residual of `scheme`
    /// on it relative to the size of each row's terms ([`SchemeReport::residual_of_other`]).
    fn energy_and_residual(
        &self,
        scheme: Scheme,
        solution: &Self::Solution,
    ) -> Result<(Vec<f64>, f64)>;
}

/// The value of a reference curve of the solutions `S`.
type ValueOf<S> = <S as ComparedSolution>::Value;

/// The comparison at `problem`'s grid from a run of each scheme that solved it (same data and
/// options): nothing is solved again, the solutions, errors and wall times are the runs', and
/// each order is [`Convergence::order_at`] this `N`. Errors if a run failed at this `N` (that
/// failure), or is of the wrong scheme, or did not solve this grid and embedding.
pub(crate) fn compare_runs<C: Compares>(
    problem: &C,
    direct: &Convergence<C::Solution>,
    variational: &Convergence<C::Solution>,
) -> Result<Comparison<C::Solution>> {
    let (grid, embedding) = (problem.grid(), problem.embedding());
    let mismatch = |operation| Error::Unsupported {
        operation,
        embedding: embedding.to_string(),
    };
    if direct.reference != variational.reference || direct.kind != variational.kind {
        return Err(mismatch("a comparison of runs with different data"));
    }
    let n = grid.n();
    let energy_not_conserved = if embedding.is_fractional() {
        Some("the embedding is fractional: its flow does not conserve E")
    } else if problem.depends_on_t() {
        Some("L may depend on t (its `dependence()` says so): E is not conserved")
    } else if problem.is_forced() {
        Some("a generalised force acts: E changes by its work (`Forced::work`)")
    } else {
        None
    };
    let report = |run: &Convergence<C::Solution>, scheme: Scheme| {
        if run.scheme != scheme {
            return Err(mismatch("a comparison of runs of the wrong scheme"));
        }
        if let Some((_, e)) = run.failures.iter().find(|(m, _)| *m == n) {
            return Err(e.clone());
        }
        let level = run
            .level(n)
            .filter(|l| *l.solution.grid() == grid && *l.solution.embedding() == embedding)
            .ok_or_else(|| mismatch("a comparison of runs that did not solve this grid"))?;
        let (energy, residual_of_other) =
            problem.energy_and_residual(scheme.other(), &level.solution)?;
        let energy_deviation = energy_not_conserved.is_none().then(|| {
            energy
                .iter()
                .map(|e| (e - energy[0]).abs())
                .fold(0.0, f64::max)
        });
        Ok(SchemeReport {
            solution: level.solution.clone(),
            residual_of_other,
            error: level.error,
            energy,
            energy_deviation,
            order: run.order_at(n),
            order_status: run.order_status_at(n),
            theoretical_order: embedding.order(scheme),
            wall_time: level.wall_time,
        })
    };
    let direct_report = report(direct, Scheme::Direct)?;
    let variational_report = report(variational, Scheme::Variational)?;
    let max_distance = direct_report
        .solution
        .distance_to(&variational_report.solution)
        .unwrap_or(f64::NAN);
    // The orders and their status use the next two errors after N: the levels 2N, 4N
    // against a reference, and 8N too for the self-convergence estimates.
    let needed = if direct.levels.iter().any(|l| l.error.is_some()) {
        2
    } else {
        3
    };
    let order_grids = direct
        .levels
        .iter()
        .map(Level::n)
        .filter(|&m| m > n && variational.level(m).is_some())
        .take(needed)
        .collect();
    Ok(Comparison {
        kind: direct.kind,
        embedding: embedding.to_string(),
        grid,
        reference: direct.reference.clone(),
        direct: direct_report,
        variational: variational_report,
        max_distance,
        energy_not_conserved,
        order_grids,
        extra_solves: 0,
    })
}

/// Both schemes of `problem` on `N` (and `2N`, `4N`, `8N` for the order), `solve(scheme, grid)`
/// solving one scheme on one grid; the first failure is the answer. Untimed, the solves of
/// both schemes share one parallel map ([`convergences`]).
pub(crate) fn compare<C: Compares>(
    problem: &C,
    kind: &'static str,
    options: &CompareOptions<'_, ValueOf<C::Solution>>,
    solve: impl Fn(Scheme, Grid) -> Result<C::Solution> + Sync,
) -> Result<Comparison<C::Solution>>
where
    C::Solution: Send,
{
    let levels = match (options.order, options.reference.curve()) {
        (false, _) => 1,
        (true, Some(_)) => 3,
        (true, None) => 4,
    };
    let schemes = [Scheme::Direct, Scheme::Variational];
    let study = Study {
        kind,
        grid: problem.grid(),
        levels,
        timing: options.timing,
    };
    let runs = convergences(&study, &schemes, &options.reference, solve);
    let solved = |run: &Convergence<C::Solution>| match run.failures.first() {
        Some((_, e)) => Err(e.clone()),
        None => Ok(()),
    };
    let [direct, variational] = &runs[..] else {
        unreachable!("one run per scheme")
    };
    solved(direct)?;
    solved(variational)?;
    let mut comparison = compare_runs(problem, direct, variational)?;
    comparison.extra_solves = levels - 1;
    Ok(comparison)
}

/// What a convergence study solves: the grids of `N, 2N, …, 2^{levels−1} N` steps over
/// `grid`'s interval (`N` its own), of which problem, and whether each solve is timed.
pub(crate) struct Study {
    /// "initial value problem" or "boundary value problem".
    pub(crate) kind: &'static str,
    /// The coarsest grid.
    pub(crate) grid: Grid,
    /// How many grids.
    pub(crate) levels: usize,
    /// Whether each solve's wall time is measured ([`CompareOptions::timing`]).
    pub(crate) timing: bool,
}

impl Study {
    /// The sizes `N·2^j`, stopping with a failure at the first that does not fit in `usize`.
    fn sizes(&self) -> (Vec<usize>, Option<Error>) {
        let (a, b, n0) = (self.grid.a(), self.grid.b(), self.grid.n());
        let mut sizes = Vec::with_capacity(self.levels);
        for j in 0..self.levels {
            let n = u32::try_from(j)
                .ok()
                .and_then(|j| 1usize.checked_shl(j))
                .and_then(|factor| n0.checked_mul(factor));
            match n {
                Some(n) => sizes.push(n),
                None => {
                    let reason = "N·2^j steps do not fit in usize";
                    return (
                        sizes,
                        Some(Error::InvalidGrid {
                            a,
                            b,
                            n: n0,
                            reason,
                        }),
                    );
                }
            }
        }
        (sizes, None)
    }
}

/// `scheme` solved by `solve(grid)` on the grids of `study`, its error measured against
/// `reference`. A size that fails is recorded in [`Convergence::failures`] and the run goes
/// on.
pub(crate) fn convergence<S: ComparedSolution + Send>(
    study: &Study,
    scheme: Scheme,
    reference: &Reference<'_, S::Value>,
    solve: impl Fn(Grid) -> Result<S> + Sync,
) -> Convergence<S> {
    let mut runs = convergences(study, &[scheme], reference, |_, grid| solve(grid));
    runs.pop().expect("one run per scheme")
}

/// The [`convergence`](fn@convergence) runs of several schemes. Timed, every solve runs alone on the calling
/// thread, scheme after scheme and grid after grid (concurrent solves would spoil each
/// other's wall time); untimed, all the solves are mapped in parallel by an [`Ensemble`], the
/// finest grids first, and the runs read the same solutions in the same order. The errors
/// against the reference are measured afterwards on the calling thread, which keeps the
/// reference curve free of any `Sync` bound.
fn convergences<S: ComparedSolution + Send>(
    study: &Study,
    schemes: &[Scheme],
    reference: &Reference<'_, S::Value>,
    solve: impl Fn(Scheme, Grid) -> Result<S> + Sync,
) -> Vec<Convergence<S>> {
    let (sizes, overflow) = study.sizes();
    let (a, b) = (study.grid.a(), study.grid.b());
    let solve_one = |&(scheme, n): &(Scheme, usize)| -> Result<(S, Option<Duration>)> {
        let grid = Grid::new(a, b, n)?;
        if study.timing {
            let start = Instant::now();
            let solution = solve(scheme, grid)?;
            Ok((solution, Some(start.elapsed())))
        } else {
            Ok((solve(scheme, grid)?, None))
        }
    };
    let tasks: Vec<(Scheme, usize)> = schemes
        .iter()
        .flat_map(|&scheme| sizes.iter().map(move |&n| (scheme, n)))
        .collect();
    let solved = if study.timing {
        tasks.iter().map(solve_one).collect()
    } else {
        map_costliest_first(&Ensemble::new(), &tasks, |&(_, n)| n, solve_one)
    };
    let mut solved = tasks.iter().zip(solved);
    schemes
        .iter()
        .map(|&scheme| {
            let mut run = Convergence {
                kind: study.kind,
                scheme,
                reference: reference.name().to_string(),
                levels: Vec::with_capacity(sizes.len()),
                failures: Vec::new(),
            };
            for (&(_, n), result) in solved.by_ref().take(sizes.len()) {
                match result {
                    Ok((solution, wall_time)) => {
                        let error = reference.curve().map(|q| solution.max_error(q));
                        run.levels.push(Level {
                            solution,
                            wall_time,
                            error,
                        });
                    }
                    Err(e) => run.failures.push((n, e)),
                }
            }
            if let Some(e) = &overflow {
                run.failures.push((usize::MAX, e.clone()));
            }
            run
        })
        .collect()
}

#[cfg(test)]
mod tests;
