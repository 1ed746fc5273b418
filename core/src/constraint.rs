//! Holonomic constraints `g(x) = 0`: the [`Constraint`] trait, [`Holonomic`] (one constraint
//! written as a `#[lagrangian]` fn, differentiated by the macro), and the checks and projection
//! of initial data.
//!
//! A constrained model obeys `d/dt ∂L/∂v − ∂L/∂x = G(x)ᵀλ`, `g(x) = 0`, with `G = ∂g/∂x` and
//! multipliers `λ ∈ R^M`: the constraint force `G(x)ᵀλ` enters each scheme where `∂L/∂x` does,
//! at one node of each row (see [`Problem::solve_constrained_ivp`](crate::Problem)).

use nalgebra::{DMatrix, DVector, SMatrix, SVector};

use crate::error::{Error, Location, Result};
use crate::lagrangian::{Lagrangian, Matrix, Vector};

/// `M` holonomic constraints `g(x) = 0` on `R^D`, with their Jacobian and second derivatives.
///
/// Implement it by hand, generate it from a fn `g(x) -> [f64; M]` with
/// [`#[constraint]`](macro@crate::constraint), or write each constraint as a `#[lagrangian]` fn
/// and wrap it in [`Holonomic`]; a pair `(A, B)` of single constraints is a constraint with
/// `M = 2`.
///
/// # Example
///
/// ```
/// use nalgebra::{SMatrix, SVector};
/// use varembed::{Constraint, Matrix, Vector};
///
/// /// The unit sphere, `g = (|x|² − 1)/2`.
/// struct Sphere;
///
/// impl Constraint<3, 1> for Sphere {
///     fn value(&self, x: &Vector<3>) -> SVector<f64, 1> {
///         SVector::<f64, 1>::new(0.5 * (x.norm_squared() - 1.0))
///     }
///     fn jacobian(&self, x: &Vector<3>) -> SMatrix<f64, 1, 3> {
///         x.transpose()
///     }
///     fn weighted_hessian(&self, _x: &Vector<3>, lambda: &SVector<f64, 1>) -> Matrix<3> {
///         Matrix::<3>::identity() * lambda[0]
///     }
/// }
/// assert_eq!(Sphere.value(&Vector::<3>::new(0.0, 0.0, 1.0))[0], 0.0);
/// ```
pub trait Constraint<const D: usize, const M: usize> {
    /// `g(x)`.
    fn value(&self, x: &Vector<D>) -> SVector<f64, M>;

    /// `G(x) = ∂g/∂x`, row `i` the gradient of `g_i`.
    fn jacobian(&self, x: &Vector<D>) -> SMatrix<f64, M, D>;

    /// `Σ_i λ_i ∂²g_i/∂x²`: the derivative of the constraint force `G(x)ᵀλ` in `x`.
    fn weighted_hessian(&self, x: &Vector<D>, lambda: &SVector<f64, M>) -> Matrix<D>;

    /// Why these are not holonomic, scleronomic constraints, if they are not: a constraint
    /// that reads the velocity or the time (which [`Holonomic`] would evaluate at `v = 0`,
    /// `t = 0`). The solver refuses such a model with
    /// [`Error::InvalidModel`] before any step. The default finds
    /// nothing.
    fn not_holonomic(&self) -> Option<String> {
        None
    }
}

/// One constraint `g(x) = 0` given as a [`Lagrangian`] that reads only `x` (write `g` as a
/// `#[lagrangian]` fn of `x` and `v` that ignores `v`: the macro's gradient is `G`, its `xx`
/// block the second derivatives).
///
/// # Example
///
/// ```
/// use varembed::{Constraint, Holonomic, Vector, lagrangian};
///
/// /// A rod of length `l` from the origin.
/// #[lagrangian]
/// fn rod(x: [f64; 2], _v: [f64; 2], l: f64) -> f64 {
///     0.5 * (x[0] * x[0] + x[1] * x[1] - l * l)
/// }
/// let rod = Holonomic(Rod { l: 2.0 });
/// let x = Vector::<2>::new(0.0, 2.0);
/// assert_eq!(rod.value(&x)[0], 0.0);
/// assert_eq!(rod.jacobian(&x)[(0, 1)], 2.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Holonomic<G>(pub G);

impl<const D: usize, G: Lagrangian<D>> Constraint<D, 1> for Holonomic<G> {
    fn value(&self, x: &Vector<D>) -> SVector<f64, 1> {
        SVector::<f64, 1>::new(self.0.value(x, &Vector::<D>::zeros(), 0.0))
    }

    fn jacobian(&self, x: &Vector<D>) -> SMatrix<f64, 1, D> {
        self.0.gradient(x, &Vector::<D>::zeros(), 0.0).0.transpose()
    }

    fn weighted_hessian(&self, x: &Vector<D>, lambda: &SVector<f64, 1>) -> Matrix<D> {
        self.0.hessian(x, &Vector::<D>::zeros(), 0.0).xx * lambda[0]
    }

    /// The constraint's [`Lagrangian::dependence`] says it reads `v` or `t`.
    fn not_holonomic(&self) -> Option<String> {
        let dependence = self.0.dependence();
        let reads = match (dependence.v, dependence.t) {
            (false, false) => return None,
            (true, false) => "the velocity v",
            (false, true) => "the time t",
            (true, true) => "the velocity v and the time t",
        };
        Some(format!(
            "a Holonomic constraint must be a function of x alone, and this one reads {reads} \
             (its `dependence()` says so; a hand-written Lagrangian used as a constraint must \
             declare that it depends on x only, or implement `Constraint` directly)"
        ))
    }
}

impl<const D: usize, A: Constraint<D, 1>, B: Constraint<D, 1>> Constraint<D, 2> for (A, B) {
    fn value(&self, x: &Vector<D>) -> SVector<f64, 2> {
        SVector::<f64, 2>::new(self.0.value(x)[0], self.1.value(x)[0])
    }

    fn jacobian(&self, x: &Vector<D>) -> SMatrix<f64, 2, D> {
        let mut g = SMatrix::<f64, 2, D>::zeros();
        g.set_row(0, &self.0.jacobian(x));
        g.set_row(1, &self.1.jacobian(x));
        g
    }

    fn weighted_hessian(&self, x: &Vector<D>, lambda: &SVector<f64, 2>) -> Matrix<D> {
        let one = |l: f64| SVector::<f64, 1>::new(l);
        self.0.weighted_hessian(x, &one(lambda[0])) + self.1.weighted_hessian(x, &one(lambda[1]))
    }

    fn not_holonomic(&self) -> Option<String> {
        let first = self
            .0
            .not_holonomic()
            .map(|why| format!("constraint 0: {why}"));
        first.or_else(|| {
            self.1
                .not_holonomic()
                .map(|why| format!("constraint 1: {why}"))
        })
    }
}

/// The relative tolerance of the initial data's consistency (`g(q) = 0`, `G(q) q̇ = 0`).
pub const CONSISTENCY_TOLERANCE: f64 = 1e-10;

/// Below this ratio of its smallest to its largest singular value, `G` is rank-deficient.
const RANK_RATIO: f64 = 1e-12;

/// [`Error::RankDeficientConstraints`] at `at` when `G` has dependent rows.
pub(crate) fn check_rank<const D: usize, const M: usize>(
    g: &SMatrix<f64, M, D>,
    at: Location,
) -> Result<()> {
    if M == 0 {
        return Ok(());
    }
    if !g.iter().all(|c| c.is_finite()) {
        // Before the SVD, whose iteration need not end on a NaN.
        return Err(Error::NotFinite { at });
    }
    let sigma = DMatrix::from_column_slice(M, D, g.as_slice()).singular_values();
    let (min, max) = (sigma.min(), sigma.max());
    let ratio: f64 = if max > 0.0 { min / max } else { 0.0 };
    if M > D || ratio.is_nan() || ratio < RANK_RATIO {
        return Err(Error::RankDeficientConstraints { at, ratio });
    }
    Ok(())
}

/// Checks that `(q0, v0)` satisfy `g(q0) = 0` and `G(q0) v0 = 0` to [`CONSISTENCY_TOLERANCE`]
/// relative to each constraint's terms, that `G(q0)` has full rank, and that the constraint
/// is holonomic ([`Constraint::not_holonomic`]).
pub(crate) fn check_consistent<C: Constraint<D, M> + ?Sized, const D: usize, const M: usize>(
    constraint: &C,
    q0: &Vector<D>,
    v0: &Vector<D>,
) -> Result<()> {
    if let Some(reason) = constraint.not_holonomic() {
        return Err(Error::InvalidModel { reason });
    }
    let (g, jacobian) = (constraint.value(q0), constraint.jacobian(q0));
    check_rank(&jacobian, Location::Step(0))?;
    let velocity = jacobian * v0;
    for i in 0..M {
        let row = jacobian.row(i).amax();
        let position_scale = row * q0.amax().max(1.0);
        if !within(g[i], CONSISTENCY_TOLERANCE * position_scale) {
            return Err(Error::InconsistentInitialData {
                what: "position",
                constraint: i,
                residual: g[i],
            });
        }
        if !within(velocity[i], CONSISTENCY_TOLERANCE * row * v0.amax()) {
            return Err(Error::InconsistentInitialData {
                what: "velocity",
                constraint: i,
                residual: velocity[i],
            });
        }
    }
    Ok(())
}

/// The initial data moved onto the constraints: `q` by Gauss–Newton along `Gᵀ` (the nearest
/// point of `g = 0` for a small violation), then `v` projected orthogonally onto `G(q) v = 0`.
///
/// Errors: [`Error::InvalidModel`] for a constraint that reads `v` or `t`
/// ([`Constraint::not_holonomic`]), [`Error::RankDeficientConstraints`] where `G` has dependent rows,
/// [`Error::NewtonDidNotConverge`] when 50 iterations do not reach the constraint to round-off.
///
/// # Example
///
/// ```
/// use varembed::{Constraint, Holonomic, Vector, lagrangian, project_initial_data};
///
/// #[lagrangian]
/// fn sphere(x: [f64; 3], _v: [f64; 3]) -> f64 {
///     0.5 * (x[0] * x[0] + x[1] * x[1] + x[2] * x[2] - 1.0)
/// }
/// let (q, v) = project_initial_data(
///     &Holonomic(Sphere),
///     Vector::<3>::new(0.0, 0.1, 1.2),
///     Vector::<3>::new(1.0, 0.0, 0.5),
/// )?;
/// assert!((q.norm() - 1.0).abs() < 1e-14 && q.dot(&v).abs() < 1e-14);
/// # Ok::<(), varembed::Error>(())
/// ```
pub fn project_initial_data<C: Constraint<D, M> + ?Sized, const D: usize, const M: usize>(
    constraint: &C,
    q0: Vector<D>,
    v0: Vector<D>,
) -> Result<(Vector<D>, Vector<D>)> {
    if let Some(reason) = constraint.not_holonomic() {
        return Err(Error::InvalidModel { reason });
    }
    let at = Location::Step(0);
    let q = project_position(constraint, q0, at)?;
    let jacobian = constraint.jacobian(&q);
    check_rank(&jacobian, at)?;
    let Some(multipliers) = gram_solve(&jacobian, &(jacobian * v0)) else {
        return Err(Error::NotFinite { at });
    };
    Ok((q, v0 - jacobian.transpose() * multipliers))
}

/// `q` moved onto `g = 0` by Gauss–Newton along `Gᵀ` (the nearest point of the constraints
/// for a small violation); errors located at `at` as [`project_initial_data`]'s.
pub(crate) fn project_position<C: Constraint<D, M> + ?Sized, const D: usize, const M: usize>(
    constraint: &C,
    mut q: Vector<D>,
    at: Location,
) -> Result<Vector<D>> {
    for _ in 0..PROJECTION_ITERATIONS {
        let (g, jacobian) = (constraint.value(&q), constraint.jacobian(&q));
        check_rank(&jacobian, at)?;
        let Some(multipliers) = gram_solve(&jacobian, &g) else {
            return Err(Error::NotFinite { at });
        };
        let step = jacobian.transpose() * multipliers;
        q -= step;
        if step.amax() <= 4.0 * f64::EPSILON * q.amax().max(f64::MIN_POSITIVE) {
            return Ok(q);
        }
    }
    Err(Error::NewtonDidNotConverge {
        at,
        iterations: PROJECTION_ITERATIONS,
        residual: constraint.value(&q).amax(),
    })
}

/// Gauss–Newton converges quadratically from a small violation; 50 iterations that do not
/// reach round-off mean a point far from the constraints or a constraint without a root near.
const PROJECTION_ITERATIONS: usize = 50;

/// Checks that the end value `q` (at the end `end`, `"a"` or `"b"`) satisfies `g(q) = 0` to
/// [`CONSISTENCY_TOLERANCE`] relative to each constraint's terms, and that `G(q)` has full rank.
pub(crate) fn check_end_value<C: Constraint<D, M> + ?Sized, const D: usize, const M: usize>(
    constraint: &C,
    q: &Vector<D>,
    end: &'static str,
    at: Location,
) -> Result<()> {
    let (g, jacobian) = (constraint.value(q), constraint.jacobian(q));
    check_rank(&jacobian, at)?;
    for i in 0..M {
        let scale = jacobian.row(i).amax() * q.amax().max(1.0);
        if !within(g[i], CONSISTENCY_TOLERANCE * scale) {
            return Err(Error::InconsistentBoundaryData {
                end,
                constraint: i,
                residual: g[i],
            });
        }
    }
    Ok(())
}

/// `|residual| ≤ bound`; false for a NaN residual too.
fn within(residual: f64, bound: f64) -> bool {
    residual.abs() <= bound
}

/// `(G Gᵀ)⁻¹ b`; `None` when `G Gᵀ` is singular.
fn gram_solve<const D: usize, const M: usize>(
    g: &SMatrix<f64, M, D>,
    b: &SVector<f64, M>,
) -> Option<SVector<f64, M>> {
    let gram = g * g.transpose();
    let x = DMatrix::from_column_slice(M, M, gram.as_slice())
        .lu()
        .solve(&DVector::from_column_slice(b.as_slice()))?;
    x.iter()
        .all(|c| c.is_finite())
        .then(|| SVector::<f64, M>::from_column_slice(x.as_slice()))
}
