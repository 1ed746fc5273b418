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

/// The smallest eigenvalue in modulus of a matrix of order `n`, by inverse iteration with
/// `solve` (which overwrites its argument `x` with `J⁻¹ x`); `None` when a solve gave a
/// non-finite vector. Starts from a vector with a component along every mode.
pub(crate) fn smallest_eigenvalue(n: usize, mut solve: impl FnMut(&mut [f64])) -> Option<f64> {
    let norm = |x: &[f64]| x.iter().map(|c| c * c).sum::<f64>().sqrt();
    // A ramp (its overlap with the j-th sine mode is ±1/(jπ): no low mode, even or odd, is
    // missing) plus the golden-ratio sequence (equidistributed: every high mode present), with
    // no transcendental call per unknown.
    let mut x: Vec<f64> = (0..n)
        .map(|i| 1.0 + i as f64 / n as f64 + 0.5 * (i as f64 * 0.618_033_988_749_895).fract())
        .collect();
    let mut size = norm(&x);
    let mut growth = 0.0;
    for _ in 0..ITERATIONS {
        let inverse = 1.0 / size;
        x.iter_mut().for_each(|c| *c *= inverse);
        solve(&mut x);
        size = norm(&x);
        growth = size;
        if !growth.is_finite() {
            return None;
        }
    }
    (growth > 0.0).then(|| 1.0 / growth)
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
