//! [`Comparison`]: the direct and the variational scheme of one embedding side by side, run
//! through [`Problem`]'s solvers.

use crate::embedding::Scheme;
use crate::error::Result;
use crate::grid::Grid;
use crate::lagrangian::{IntoVector, Lagrangian, Vector};
use crate::linalg::max_norm;
use crate::problem::Problem;
use crate::solve::ivp::Start;
use crate::solve::solution::Solution;
use std::fmt;
use std::time::{Duration, Instant};

/// What errors are measured against.
#[derive(Clone, Copy)]
pub enum Reference<'a, const D: usize> {
    /// No reference: errors are not reported, the order is the self-convergence estimate.
    None,
    /// An exact solution `t ↦ q(t)`.
    Exact(&'a dyn Fn(f64) -> Vector<D>),
    /// An independently computed solution `t ↦ q(t)` (e.g. a high-order integrator on a fine
    /// grid), with the name under which the table reports it.
    Computed {
        /// How the reference was computed (shown in the table).
        name: &'a str,
        /// The reference curve.
        q: &'a dyn Fn(f64) -> Vector<D>,
    },
}

impl<const D: usize> Reference<'_, D> {
    fn curve(&self) -> Option<&dyn Fn(f64) -> Vector<D>> {
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

/// Options of [`Problem::compare_ivp_with`] and [`Problem::compare_bvp_with`].
#[derive(Clone, Copy)]
pub struct CompareOptions<'a, const D: usize> {
    /// The reference for the error column.
    pub reference: Reference<'a, D>,
    /// The start of initial value problems.
    pub start: Start,
    /// Whether to solve on `2N` and `4N` steps for the observed order.
    pub order: bool,
}

impl<const D: usize> Default for CompareOptions<'_, D> {
    fn default() -> Self {
        CompareOptions {
            reference: Reference::None,
            start: Start::Legendre,
            order: true,
        }
    }
}

/// One scheme's line of a [`Comparison`].
#[derive(Clone, Debug)]
pub struct SchemeReport<const D: usize> {
    /// The solution.
    pub solution: Solution<D>,
    /// Max-norm of the other scheme's residual evaluated on this solution.
    pub residual_of_other: f64,
    /// Max over the nodes of `|Q_k − q(t_k)|∞` against the reference, if any.
    pub error: Option<f64>,
    /// `E = V_k·∂L/∂v − L` at the quadrature nodes `I_σ`.
    pub energy: Vec<f64>,
    /// `max_k |E_k − E_first|`.
    pub energy_deviation: f64,
    /// Observed order of convergence (see [`Comparison`]), if asked for.
    pub order: Option<f64>,
    /// Wall time of the solve on `N` steps.
    pub wall_time: Duration,
}

/// The direct and variational schemes of one problem, side by side; `Display` prints a table.
///
/// Per scheme: the solution, the residual of the *other* scheme on it (zero to round-off
/// exactly when the embedding is coherent), the error against a reference (an exact solution or
/// an independently computed curve, named in the table), the energy `E = v·∂L/∂v − L` along
/// the run and its largest deviation from its first value, the observed order of convergence,
/// Newton iterations and wall time; and the largest distance between the two solutions.
///
/// The observed order comes from two more solves on `2N` and `4N` steps:
/// `log₂(e_N / e_{2N})` with the errors against the reference when there is one, otherwise the
/// self-convergence estimate `log₂(‖Q_N − Q_{2N}‖ / ‖Q_{2N} − Q_{4N}‖)` (max-norm over the nodes
/// of the coarse grid).
#[derive(Clone, Debug)]
pub struct Comparison<const D: usize> {
    /// What was solved: "initial value problem" or "boundary value problem".
    pub kind: &'static str,
    /// The embedding, as text.
    pub embedding: String,
    /// The grid.
    pub grid: Grid,
    /// Which reference the errors are against.
    pub reference: String,
    /// The direct scheme.
    pub direct: SchemeReport<D>,
    /// The variational scheme.
    pub variational: SchemeReport<D>,
    /// `max_k |Q_direct,k − Q_variational,k|∞`.
    pub max_distance: f64,
}

impl<L: Lagrangian<D> + ?Sized, const D: usize> Problem<'_, L, D> {
    /// Compares both schemes on the initial value problem `q(a) = q0`, `q̇(a) = v0` (discrete
    /// Legendre start, no reference, observed order by self-convergence).
    pub fn compare_ivp(
        &self,
        q0: impl IntoVector<D>,
        v0: impl IntoVector<D>,
    ) -> Result<Comparison<D>> {
        self.compare_ivp_with(q0, v0, &CompareOptions::default())
    }

    /// [`compare_ivp`](Self::compare_ivp) with options.
    pub fn compare_ivp_with(
        &self,
        q0: impl IntoVector<D>,
        v0: impl IntoVector<D>,
        options: &CompareOptions<'_, D>,
    ) -> Result<Comparison<D>> {
        let (q0, v0) = (q0.into_vector(), v0.into_vector());
        self.compare("initial value problem", options, |p, scheme| {
            p.solve_ivp_with(scheme, q0, v0, options.start)
        })
    }

    /// Compares both schemes on the boundary value problem `Q_0 = qa`, `Q_N = qb`.
    pub fn compare_bvp(
        &self,
        qa: impl IntoVector<D>,
        qb: impl IntoVector<D>,
    ) -> Result<Comparison<D>> {
        self.compare_bvp_with(qa, qb, &CompareOptions::default())
    }

    /// [`compare_bvp`](Self::compare_bvp) with options (the start is not used).
    pub fn compare_bvp_with(
        &self,
        qa: impl IntoVector<D>,
        qb: impl IntoVector<D>,
        options: &CompareOptions<'_, D>,
    ) -> Result<Comparison<D>> {
        let (qa, qb) = (qa.into_vector(), qb.into_vector());
        self.compare("boundary value problem", options, |p, scheme| {
            p.solve_bvp(scheme, qa, qb)
        })
    }

    fn compare(
        &self,
        kind: &'static str,
        options: &CompareOptions<'_, D>,
        solve: impl Fn(&Problem<'_, L, D>, Scheme) -> Result<Solution<D>>,
    ) -> Result<Comparison<D>> {
        let mut reports = Vec::with_capacity(2);
        for scheme in [Scheme::Direct, Scheme::Variational] {
            let start = Instant::now();
            let solution = solve(self, scheme)?;
            let wall_time = start.elapsed();
            let residual_of_other = max_norm(&self.residual(scheme.other(), &solution.q)?);
            let error = options
                .reference
                .curve()
                .map(|q| self.error_against(&solution.q, q));
            let energy = self.energy(&solution.q)?;
            let energy_deviation = energy
                .iter()
                .map(|e| (e - energy[0]).abs())
                .fold(0.0, f64::max);
            let order = if options.order {
                Some(self.observed_order(scheme, &solution, options, &solve)?)
            } else {
                None
            };
            reports.push(SchemeReport {
                solution,
                residual_of_other,
                error,
                energy,
                energy_deviation,
                order,
                wall_time,
            });
        }
        let variational = reports.pop().expect("two reports");
        let direct = reports.pop().expect("two reports");
        let max_distance = direct
            .solution
            .max_distance(&variational.solution.q)
            .unwrap_or(f64::NAN);
        Ok(Comparison {
            kind,
            embedding: self.embedding().to_string(),
            grid: *self.grid(),
            reference: options.reference.name().to_string(),
            direct,
            variational,
            max_distance,
        })
    }

    fn error_against(&self, q: &[Vector<D>], reference: &dyn Fn(f64) -> Vector<D>) -> f64 {
        q.iter()
            .enumerate()
            .map(|(k, x)| (x - reference(self.grid().t(k))).amax())
            .fold(0.0, f64::max)
    }

    fn observed_order(
        &self,
        scheme: Scheme,
        coarse: &Solution<D>,
        options: &CompareOptions<'_, D>,
        solve: &impl Fn(&Problem<'_, L, D>, Scheme) -> Result<Solution<D>>,
    ) -> Result<f64> {
        let grid = *self.grid();
        let n = grid.n();
        let refine = |factor: usize| -> Result<Solution<D>> {
            let finer = Grid::new(grid.a(), grid.b(), n * factor)?;
            solve(&self.on_grid(finer), scheme)
        };
        let fine = refine(2)?;
        // Max over the coarse nodes of |a_k − b_{k·stride}|.
        let gap = |a: &[Vector<D>], b: &[Vector<D>], stride: usize| {
            a.iter()
                .enumerate()
                .map(|(k, x)| (x - b[k * stride]).amax())
                .fold(0.0, f64::max)
        };
        Ok(match options.reference.curve() {
            Some(q) => {
                let e_coarse = self.error_against(&coarse.q, q);
                let e_fine = (0..=n)
                    .map(|k| (fine.q[2 * k] - q(grid.t(k))).amax())
                    .fold(0.0, f64::max);
                (e_coarse / e_fine).log2()
            }
            None => {
                let finest = refine(4)?;
                let (d_coarse, d_fine) = (gap(&coarse.q, &fine.q, 2), gap(&fine.q, &finest.q, 2));
                (d_coarse / d_fine).log2()
            }
        })
    }
}

impl<const D: usize> fmt::Display for Comparison<D> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{} under {}, N = {}, h = {:.3e}, errors against: {}",
            self.kind,
            self.embedding,
            self.grid.n(),
            self.grid.h(),
            self.reference
        )?;
        writeln!(
            f,
            "  {:<12} {:>11} {:>7} {:>11} {:>15} {:>8} {:>11}",
            "scheme", "max error", "order", "max |ΔE|", "other's resid.", "Newton", "time"
        )?;
        for (name, r) in [("direct", &self.direct), ("variational", &self.variational)] {
            let error = r.error.map_or("—".to_string(), |e| format!("{e:.3e}"));
            let order = r.order.map_or("—".to_string(), |o| format!("{o:.2}"));
            writeln!(
                f,
                "  {:<12} {:>11} {:>7} {:>11.3e} {:>15.3e} {:>8} {:>11}",
                name,
                error,
                order,
                r.energy_deviation,
                r.residual_of_other,
                r.solution.newton_iterations,
                format!("{:.3?}", r.wall_time)
            )?;
        }
        write!(
            f,
            "  max |Q_direct − Q_variational| = {:.3e}",
            self.max_distance
        )
    }
}
