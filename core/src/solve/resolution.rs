//! Whether an implicit initial value run resolves the fastest motion of its linearisation at
//! the initial data: an A-stable scheme returns `Ok` at any step, and past a few steps per
//! period of that motion its phase means nothing. The check warns
//! ([`Warning::UnderResolved`]); it never stops a run.

use nalgebra::{DMatrix, DVector, Dyn, LU};

use crate::lagrangian::{Lagrangian, Matrix, Vector};
use crate::solve::solution::Warning;

/// Products with the linearisation's matrix in [`dominant_rate`]'s power iteration.
const POWER_ITERATIONS: usize = 30;

/// The largest `hω` per stage of the scheme (one for the three-point recurrences) that the
/// check accepts: at `hω = 2` a step samples the fastest motion at `π` points a period, the
/// fewest at which Störmer–Verlet is still stable, and no scheme of this crate follows a phase
/// below that. A Gauss–Legendre step of `s` stages samples it at `s` points, so its limit is
/// `2s`.
pub(crate) const RESOLUTION_LIMIT: f64 = 2.0;

/// The fastest rate of the equation linearised at `(x, v, t)`, `ω = √|μ|` with `μ` the
/// eigenvalue of largest modulus of `K = (∂²L/∂v²)⁻¹(−∂²L/∂x²)` ([`dominant_rate`] on the dense
/// blocks); the velocity couplings `∂²L/∂x∂v` are left out. `None` when `∂²L/∂v²` is singular
/// or a block is not finite.
pub(crate) fn fastest_rate<const D: usize, L: Lagrangian<D> + ?Sized>(
    lagrangian: &L,
    x: &Vector<D>,
    v: &Vector<D>,
    t: f64,
) -> Option<f64> {
    let (lu, stiffness) = linearisation(lagrangian, x, v, t);
    dominant_rate(D, |y, out| {
        let next = lu.solve(&(&stiffness * DVector::from_column_slice(y)))?;
        out.copy_from_slice(next.as_slice());
        Some(())
    })
}

/// `√|μ|`, `μ` the eigenvalue of largest modulus of an operator `K` of order `n` given by its
/// products (`product(y, out)` writes `K y` into `out`; `None` when it cannot, e.g. a singular
/// solve): by power iteration from a vector with a component along every coordinate, the norm
/// ratio of the last two products (within a few per cent of `|μ|` when the dominant eigenvalue
/// is separated, which is all a threshold needs). `None` when a product failed or is not
/// finite. For `K = (∂²L/∂v²)⁻¹(−∂²L/∂x²)` it is the angular frequency of the fastest
/// oscillation (`μ > 0`) or the rate of the fastest exponential (`μ < 0`), whatever the storage
/// of the blocks (dense on the const-generic path, band and sparse on the run-time one).
pub(crate) fn dominant_rate(
    n: usize,
    mut product: impl FnMut(&[f64], &mut [f64]) -> Option<()>,
) -> Option<f64> {
    let norm = |y: &[f64]| y.iter().map(|c| c * c).sum::<f64>().sqrt();
    let mut y: Vec<f64> = (0..n)
        .map(|i| 1.0 + 0.5 * if i % 2 == 0 { 1.0 } else { -1.0 } + 0.25 * (i as f64).sin())
        .collect();
    let mut next = vec![0.0; n];
    let mut ratio = 0.0;
    for _ in 0..POWER_ITERATIONS {
        let size = norm(&y);
        if size == 0.0 || !size.is_finite() {
            break;
        }
        y.iter_mut().for_each(|c| *c /= size);
        product(&y, &mut next)?;
        ratio = norm(&next);
        std::mem::swap(&mut y, &mut next);
    }
    (ratio.is_finite()).then(|| ratio.sqrt())
}

/// The fastest frequency `ω` of the equation linearised at `(x, v, t)`: the square root of the
/// largest real positive eigenvalue of `(∂²L/∂v²)⁻¹(−∂²L/∂x²)` (by its Schur form: exact, for
/// the error path); `None` when there is none (no oscillation) or `∂²L/∂v²` is singular.
pub(crate) fn fastest_frequency<const D: usize, L: Lagrangian<D> + ?Sized>(
    lagrangian: &L,
    x: &Vector<D>,
    v: &Vector<D>,
    t: f64,
) -> Option<f64> {
    let (lu, stiffness) = linearisation(lagrangian, x, v, t);
    let k = lu.solve(&stiffness)?;
    if !k.iter().all(|c| c.is_finite()) {
        return None;
    }
    let largest = k
        .complex_eigenvalues()
        .iter()
        .filter(|l| l.im.abs() <= 1e-8 * l.re.abs())
        .fold(0.0f64, |m, l| m.max(l.re));
    (largest > 0.0).then(|| largest.sqrt())
}

/// The LU factorisation of `∂²L/∂v²` and the stiffness `−∂²L/∂x²` at `(x, v, t)`, on the heap
/// (any `D`): the two halves of the linearisation `(∂²L/∂v²)⁻¹(−∂²L/∂x²)`.
fn linearisation<const D: usize, L: Lagrangian<D> + ?Sized>(
    lagrangian: &L,
    x: &Vector<D>,
    v: &Vector<D>,
    t: f64,
) -> (LU<f64, Dyn, Dyn>, DMatrix<f64>) {
    let hessian = lagrangian.hessian(x, v, t);
    let dense = |m: &Matrix<D>| DMatrix::from_fn(D, D, |i, j| m[(i, j)]);
    (dense(&hessian.vv).lu(), -dense(&hessian.xx))
}

/// [`Warning::UnderResolved`] when `h ω` at the initial data `(q0, v0, t0)` exceeds
/// [`RESOLUTION_LIMIT`] times `stages`.
pub(crate) fn resolution_warning<const D: usize, L: Lagrangian<D> + ?Sized>(
    lagrangian: &L,
    (q0, v0, t0): (&Vector<D>, &Vector<D>, f64),
    h: f64,
    stages: usize,
) -> Option<Warning> {
    under_resolved(fastest_rate(lagrangian, q0, v0, t0)?, h, stages)
}

/// Whether a bound `B ≥ ‖K‖₂` on the linearisation's matrix proves the check silent: every
/// norm ratio of [`dominant_rate`] is at most `‖K‖₂`, so its `ω` is at most `√B`, and `h √B`
/// within [`RESOLUTION_LIMIT`] times `stages` (with a margin for rounding) means no
/// [`Warning::UnderResolved`], without the power iteration.
pub(crate) fn proved_resolved(bound: f64, h: f64, stages: usize) -> bool {
    h * bound.sqrt() * (1.0 + 1e-9) <= RESOLUTION_LIMIT * stages as f64
}

/// [`Warning::UnderResolved`] when `h ω` exceeds [`RESOLUTION_LIMIT`] times `stages`, for the
/// fastest rate `ω` at the initial data.
pub(crate) fn under_resolved(omega: f64, h: f64, stages: usize) -> Option<Warning> {
    let limit = RESOLUTION_LIMIT * stages as f64;
    (h * omega > limit).then_some(Warning::UnderResolved {
        h_omega: h * omega,
        limit,
    })
}
