//! Whether a boundary value problem is ill-posed: its linearisation at the solution (nearly)
//! singular, as at a resonance (`q̈ = −q` on `[0, π]` with `q(0) = 0`, `q(π) = 1` has no
//! solution, and its discrete solutions grow without bound as `N` grows).
//!
//! A plain condition number cannot tell: it grows like `N²` for every well-posed second-order
//! problem. The measure here converges with the grid instead. The smallest eigenvalue `σ` (in
//! modulus) of the converged Newton system's Jacobian, by inverse iteration on the
//! factorisation the solve already has, is set against the lowest eigenvalue of the system's
//! kinetic part alone, `κ = a (π h / T)^{2α}`, where `a` is the largest coupling between
//! neighbouring nodes (the second difference's off-diagonal, `∂²L/∂v²` over `h` or `h²` as the
//! scheme scales its rows; `α = 1` for the classical embeddings) and `T = b − a`. Both scale
//! alike with the rows, `h` and `L`, so on `L = ½ m v² − ½ k x²` the ratio tends to
//! `min_j |(jπ/T)² m − k| / ((π/T)² m)`: 0 at a resonance (`O(h²)` on the grid), ¾ for the
//! same oscillator over `[0, π/2]`.
//!
//! **Fractional embeddings.** There `a (π h / T)^{2α}` is not the lowest eigenvalue of the
//! kinetic part `P' = Dᵀ L_vv D`: on `L = ½v² − ½k x²` on `[0, 1]` the lowest eigenvalue `μ₁`
//! of `DᵀD` is 1.12 times it at α = 0.74 and 2.4 times at α = 0.3 (`N = 200`, dense
//! eigenvalues). So both fractional solvers measure against `P'` itself: the measure is the
//! smallest eigenvalue in modulus of the pencil `(J, P')`, `min |λ|` with `J x = λ P' x`,
//! which tends to `min_j |1 − k/μ_j|` on that oscillator: 0 at a resonance, the relative
//! distance of the stiffness from the nearest kinetic eigenvalue otherwise, and the same as
//! the classical measure at the first resonance where `κ = μ₁`. The dense solver gets it by
//! inverse iteration in the `P'` norm ([`smallest_pencil_eigenvalue`]), the fast one from the
//! Lanczos matrix of the preconditioned operator `P'⁻¹J` (its preconditioner is `P'⁻¹`): a
//! few MINRES iterations at the converged iterate (past `2¹⁸` steps on that many, the solution
//! interpolated to them: `solve::fractional::posedness`), whose Ritz values approximate the
//! eigenvalues of `P'⁻¹J`. A Ritz value only flags a problem when its bound puts an
//! eigenvalue below the threshold (see `solve::fractional::posedness`), so an interior Ritz
//! value that has not converged never flags a well-posed problem.

use std::f64::consts::PI;

/// Below this the solution carries [`Warning::IllPosed`](crate::Warning::IllPosed): the lowest
/// mode of the linearised problem is within 1 % of the kinetic scale from a resonance, so the
/// data are amplified by at least a hundred times that of a problem with the kinetic part
/// alone.
pub(crate) const ILL_POSED_BELOW: f64 = 1e-2;

/// Inverse iterations. Each multiplies the start's component along the mode of the smallest
/// eigenvalue `σ₁` by `σ₂/σ₁` against the next one's: near a resonance, where the measure
/// matters, that ratio is large (a thousand at a measure of 1e-3) and two steps leave the
/// estimate within a few per cent; far from one the estimate `1/‖J⁻¹x‖` stays above `σ₁`, so a
/// problem is never flagged for want of iterations. Two keep the check within 5 % of a banded
/// solve (BENCHMARKS.md).
const ITERATIONS: usize = 2;

/// What [`inverse_iteration`] finds.
#[derive(Clone, Copy, Debug)]
pub(crate) struct InverseIteration {
    /// The estimate of the smallest eigenvalue in modulus, `1/‖J⁻¹ x‖₂` for the last unit `x`.
    pub(crate) sigma: f64,
    /// The largest `‖J⁻¹ x‖₂` over the unit vectors `x` of the iteration: a lower bound of
    /// `‖J⁻¹‖₂`. On a matrix far from normal (a recurrence amplifying a parasitic mode) the
    /// first step's can exceed the last one's by many orders of magnitude.
    pub(crate) largest_growth: f64,
}

/// The smallest eigenvalue in modulus of a matrix of order `n`, by [`ITERATIONS`] steps of
/// inverse iteration with `solve` (which overwrites its argument `x` with `J⁻¹ x`), and the
/// largest growth on the way; `None` when a solve gave a non-finite vector. Starts from a
/// vector with a component along every mode.
pub(crate) fn inverse_iteration(
    n: usize,
    mut solve: impl FnMut(&mut [f64]),
) -> Option<InverseIteration> {
    let norm = |x: &[f64]| x.iter().map(|c| c * c).sum::<f64>().sqrt();
    let mut x = start(n);
    let mut size = norm(&x);
    let (mut growth, mut largest_growth) = (0.0, 0.0f64);
    for _ in 0..ITERATIONS {
        let inverse = 1.0 / size;
        x.iter_mut().for_each(|c| *c *= inverse);
        solve(&mut x);
        size = norm(&x);
        growth = size;
        if !growth.is_finite() {
            return None;
        }
        largest_growth = largest_growth.max(growth);
    }
    (growth > 0.0).then(|| InverseIteration {
        sigma: 1.0 / growth,
        largest_growth,
    })
}

/// A condition number at or above `1/ε`: the Newton system is singular to working precision,
/// and its solution is round-off ([`Error::IllConditioned`](crate::Error::IllConditioned)).
pub(crate) const NUMERICALLY_SINGULAR: f64 = 1.0 / f64::EPSILON;

/// A lower bound of the ∞-norm condition number of a matrix `J` of order `n` with row-sum norm
/// `norm_inf`, from lower bounds of `‖J⁻¹‖∞`: `correction = ‖J⁻¹ r‖∞ / ‖r‖∞` for some `r`, and
/// the inverse iteration's largest growth `g` (`‖J⁻¹‖∞ ≥ ‖J⁻¹‖₂/√n ≥ g/√n`; `None`: the
/// iteration met a non-finite vector, so `J` is singular to working precision, `∞`). Being a
/// lower bound, it never calls a well-conditioned system singular.
pub(crate) fn condition_bound(
    norm_inf: f64,
    iteration: Option<InverseIteration>,
    n: usize,
    correction: f64,
) -> f64 {
    let Some(run) = iteration else {
        return f64::INFINITY;
    };
    let inverse = (run.largest_growth / (n as f64).sqrt()).max(correction);
    norm_inf * inverse
}

/// The smallest eigenvalue in modulus of the pencil `(J, P)`, `J x = λ P x` with `P`
/// symmetric positive definite, by inverse iteration in the `P` norm: `kinetic` writes `P x`
/// into its second argument, `solve` overwrites its argument with `J⁻¹` of it. `None` when a
/// product or a solve was not finite. The start and the number of steps are those of
/// [`inverse_iteration`].
pub(crate) fn smallest_pencil_eigenvalue(
    n: usize,
    mut kinetic: impl FnMut(&[f64], &mut [f64]),
    mut solve: impl FnMut(&mut [f64]),
) -> Option<f64> {
    let mut x = start(n);
    let mut px = vec![0.0; n];
    let p_norm = |x: &[f64], px: &[f64]| x.iter().zip(px).map(|(a, b)| a * b).sum::<f64>().sqrt();
    for _ in 0..ITERATIONS {
        kinetic(&x, &mut px);
        let size = p_norm(&x, &px);
        if !(size > 0.0 && size.is_finite()) {
            return None;
        }
        x.iter_mut().zip(&px).for_each(|(x, p)| *x = p / size);
        solve(&mut x);
    }
    kinetic(&x, &mut px);
    let growth = p_norm(&x, &px);
    (growth > 0.0 && growth.is_finite()).then(|| 1.0 / growth)
}

/// The start of the inverse iterations, with a component along every mode: a ramp (its
/// overlap with the j-th sine mode is ±1/(jπ): no low mode, even or odd, is missing) plus the
/// golden-ratio sequence (equidistributed: every high mode present), with no transcendental
/// call per unknown.
pub(crate) fn start(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| 1.0 + i as f64 / n as f64 + 0.5 * (i as f64 * 0.618_033_988_749_895).fract())
        .collect()
}

/// The largest coupling between neighbouring nodes of a Jacobian of `unknowns` rows in blocks of
/// `d` (node `k`'s unknowns at `k d .. (k + 1) d`), read by `entry(i, j)`: the dense and band
/// storages, every entry of each row's next block.
pub(crate) fn neighbour_coupling(
    unknowns: usize,
    d: usize,
    entry: impl Fn(usize, usize) -> f64,
) -> f64 {
    let next_block = |i: usize| {
        let next = (i / d + 1) * d;
        (next..(next + d).min(unknowns)).map(move |j| (i, j))
    };
    neighbour_coupling_of(
        d,
        (0..unknowns)
            .flat_map(next_block)
            .map(|(i, j)| (i, j, entry(i, j))),
    )
}

/// The largest coupling between neighbouring nodes, as [`neighbour_coupling`], over the stored
/// entries `(i, j, value)` of a sparse Jacobian (any order; entries outside the next block
/// are skipped): `O(nnz)`.
pub(crate) fn neighbour_coupling_of(
    d: usize,
    entries: impl IntoIterator<Item = (usize, usize, f64)>,
) -> f64 {
    entries
        .into_iter()
        .filter(|&(i, j, _)| j / d == i / d + 1)
        .fold(0.0f64, |a, (_, _, value)| a.max(value.abs()))
}

/// The measure of the module docs: `σ / (a (π h / T)^{2α})`.
pub(crate) fn ill_posedness(sigma: f64, coupling: f64, h: f64, length: f64, alpha: f64) -> f64 {
    sigma / (coupling * (PI * h / length).powf(2.0 * alpha))
}
