//! Starting columns for the Grünwald–Letnikov operators: the corrections of the
//! [corrected Gauss-GLEσ](crate::Embedding::corrected_grunwald_letnikov) at the ends where the
//! solution of a fractional problem is singular.
//!
//! Write `Δ` for `Δ^α_−` (σ = +'s operators are its mirror image, node `k` read as `N − k`).
//! Each corrected operator is `Δ` plus two columns next to the node where its sums are cut, with
//! weights chosen row by row (Lubich's starting weights) so that the operator is exact on the
//! two leading singular terms of the data it is applied to:
//!
//! - **the velocity** `V = Δ̃ Q`: near `a` the solution is `q ~ c₁ t^α + c₂ t^{1+α}` (a momentum
//!   not vanishing at `a`, and its slope). Columns at nodes 1 and 2 make `Δ̃ t^g`, `g = α, 1 + α`,
//!   equal `D^α t^g = Γ(g+1)/Γ(g+1−α) t^{g−α}` at `t_k − αh/2`: the point where the plain
//!   operator is second order on smooth data, so that the corrections leave the smooth part's
//!   error, which the scheme cancels, as it is;
//! - **the momentum** in the direct scheme's `Δ̃ᵀ`-side operator `Δ^α_+ p`: near `b` the
//!   momentum is `p ~ p(b) + p'(b)(t − b)`, and `D^α_+` of that carries `(b − t)^{−α}` and
//!   `(b − t)^{1−α}`. Columns at nodes `N` and `N − 1` make the operator exact at `t_j` on
//!   `(b − t)^g`, `g = 0, 1`, sampled at `t_k − αh/2`, where the momenta of the scheme
//!   approximate `p` to second order.
//!
//! All weights are `h^{−α}` times a number that depends on the row's distance from the end and
//! on α only; at α = 1 every one is zero (the classical differences are exact on these
//! functions at those points).

use crate::toeplitz::TriangularToeplitz;
use crate::weights::grunwald_letnikov;

/// The role of a corrected operator, which fixes the functions it is made exact on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Role {
    /// The velocity operator, applied to the curve: columns at distance 1 and 2 from its start.
    Velocity,
    /// The operator the direct scheme applies to the momenta: columns at distance 0 and 1.
    Momentum,
}

impl Role {
    /// The distances from the start node of the two corrected columns.
    pub(crate) fn distances(self) -> [usize; 2] {
        match self {
            Role::Velocity => [1, 2],
            Role::Momentum => [0, 1],
        }
    }

    /// The two exponents `g` of the functions the operator is made exact on.
    fn exponents(self, alpha: f64) -> [f64; 2] {
        match self {
            Role::Velocity => [alpha, 1.0 + alpha],
            Role::Momentum => [0.0, 1.0],
        }
    }

    /// The function of exponent `g` at distance `i` from the start, in units of `h`: `i^g`
    /// for the velocity, `(i + α/2)^g` for the momenta (sampled at `t_k − αh/2`).
    fn sample(self, alpha: f64, g: f64, i: usize) -> f64 {
        match self {
            Role::Velocity => (i as f64).powf(g),
            Role::Momentum => (i as f64 + alpha / 2.0).powf(g),
        }
    }

    /// The exact fractional derivative `Γ(g + 1)/Γ(g + 1 − α) s^{g−α}` of the function of
    /// exponent `g` in the row at distance `m` (in units of `h`, without `h^{g−α}`): at
    /// `s = m − α/2` for the velocity, at `s = m` for the momenta. `1/Γ(g + 1 − α)` is zero at
    /// its pole (`g = 0`, `α = 1`).
    fn exact(self, alpha: f64, g: f64, m: usize) -> f64 {
        let s = match self {
            Role::Velocity => m as f64 - alpha / 2.0,
            Role::Momentum => m as f64,
        };
        let reciprocal = if g + 1.0 - alpha > 0.0 {
            1.0 / gamma(g + 1.0 - alpha)
        } else {
            0.0
        };
        gamma(g + 1.0) * reciprocal * s.powf(g - alpha)
    }
}

/// `Γ(x)` for `0 < x ≤ 3`: Stirling's series for `ln Γ` at `x + 12` (truncation below `10⁻¹⁵`
/// relative there), brought down by the recurrence `Γ(x) = Γ(x + 12)/(x (x + 1) ⋯ (x + 11))`;
/// relative error a few `10⁻¹⁴`, from rounding `ln Γ(x + 12) ≈ 20` before the exponential.
pub(crate) fn gamma(x: f64) -> f64 {
    let z = x + 12.0;
    let (z2, z3) = (z * z, z * z * z);
    let series = 1.0 / (12.0 * z) - 1.0 / (360.0 * z3) + 1.0 / (1260.0 * z3 * z2)
        - 1.0 / (1680.0 * z3 * z2 * z2)
        + 1.0 / (1188.0 * z3 * z3 * z3);
    let ln_gamma_z = (z - 0.5) * z.ln() - z + 0.5 * (2.0 * std::f64::consts::PI).ln() + series;
    let product: f64 = (0..12).map(|i| x + i as f64).product();
    ln_gamma_z.exp() / product
}

/// The rows up to this distance sum `Σ_r w_r s_g(m − r)` directly; the rows beyond, by FFT
/// (`O(N log N)` instead of `O(N²)`: 8192 rows are about `3·10⁷` products per function, about
/// 0.1 s in release for the four functions of a corrected discretisation). Past them the fast
/// solver keeps the scheme's order (N = 4096 … 32768 against exact solutions,
/// `tests/tests/fractional/corrected.rs`).
const DIRECT_SUMS_UP_TO: usize = 8192;

/// The two columns' weights (without the factor `h^{−α}`) for the rows at distance
/// `1..=n` from the start: entry `m − 1` of each is the weight in the row at distance `m`.
///
/// Row `m` solves the 2 × 2 system `Σ_i c_i s_g(d_i) = e_g(m) − Σ_r w_r s_g(m − r)` for the two
/// exponents `g`, `d_i` the columns' distances, `s_g` the samples of the function and `e_g` the
/// exact values (module docs). The right-hand side is a small difference of two values of
/// size `m^{g−α}`: the direct sums keep it to about `10⁻¹⁶ m^{g−α} √m`, far below the scheme's
/// error; the FFT route's error, relative to the largest value, is larger in the far rows,
/// where the weights themselves are small.
pub(crate) fn columns(role: Role, alpha: f64, n: usize) -> [Vec<f64>; 2] {
    let w = grunwald_letnikov(alpha, n + 1);
    let (exponents, d) = (role.exponents(alpha), role.distances());
    // The 2 × 2 matrix A[g][i] = s_g(d_i), the same for every row.
    let a = exponents.map(|g| d.map(|di| role.sample(alpha, g, di)));
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    let residuals = exponents.map(|g| {
        let samples: Vec<f64> = (0..=n).map(|i| role.sample(alpha, g, i)).collect();
        let plain = convolve(&w, &samples);
        (1..=n)
            .map(|m| role.exact(alpha, g, m) - plain[m])
            .collect::<Vec<f64>>()
    });
    let mut out = [vec![0.0; n], vec![0.0; n]];
    for i in 0..n {
        let (r0, r1) = (residuals[0][i], residuals[1][i]);
        // Cramer's rule on the fixed, well-conditioned 2 × 2 system.
        out[0][i] = (r0 * a[1][1] - r1 * a[0][1]) / det;
        out[1][i] = (a[0][0] * r1 - a[1][0] * r0) / det;
    }
    out
}

/// `y_m = Σ_{r=0}^{m} w_r x_{m−r}`, `m = 0..len`: by direct sums for `m ≤`
/// [`DIRECT_SUMS_UP_TO`], by FFT above (whose rounding, relative to the largest value, would
/// swamp the first rows' small differences, where the weights are largest).
fn convolve(w: &[f64], x: &[f64]) -> Vec<f64> {
    let len = x.len();
    let direct = |m: usize| (0..=m).map(|r| w[r] * x[m - r]).sum::<f64>();
    if len <= DIRECT_SUMS_UP_TO + 1 {
        return (0..len).map(direct).collect();
    }
    let (toeplitz, mut workspace) = TriangularToeplitz::with_workspace(&w[..len]);
    let mut y = vec![0.0; len];
    toeplitz.mul(false, &mut workspace, x, &mut y);
    for (m, y) in y.iter_mut().enumerate().take(DIRECT_SUMS_UP_TO + 1) {
        *y = direct(m);
    }
    y
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Past the threshold the plain sums go by FFT, equal to the direct sums to the rounding
    /// of the largest value; below it they are the direct sums.
    #[test]
    fn fft_sums_equal_direct_sums() {
        let n = DIRECT_SUMS_UP_TO + 500;
        let w = grunwald_letnikov(0.6, n + 1);
        let x: Vec<f64> = (0..=n).map(|i| (i as f64).powf(1.6)).collect();
        let by_fft = convolve(&w, &x);
        let largest = (n as f64).powf(1.6);
        for m in [
            0,
            1,
            2,
            17,
            1000,
            DIRECT_SUMS_UP_TO,
            DIRECT_SUMS_UP_TO + 1,
            n,
        ] {
            let direct: f64 = (0..=m).map(|r| w[r] * x[m - r]).sum();
            let bound = if m <= DIRECT_SUMS_UP_TO {
                0.0
            } else {
                1e-13 * largest
            };
            assert!(
                (by_fft[m] - direct).abs() <= bound,
                "{m}: {} vs {direct}",
                by_fft[m]
            );
        }
    }

    #[test]
    fn gamma_matches_closed_forms() {
        let sqrt_pi = std::f64::consts::PI.sqrt();
        for (x, exact) in [
            (1.0, 1.0),
            (2.0, 1.0),
            (3.0, 2.0),
            (0.5, sqrt_pi),
            (1.5, 0.5 * sqrt_pi),
            (2.5, 0.75 * sqrt_pi),
        ] {
            assert!(
                (gamma(x) / exact - 1.0).abs() < 1e-14,
                "Γ({x}) = {}",
                gamma(x)
            );
        }
        // The recurrence at points with no closed form.
        for x in [0.1, 0.37, 0.8, 1.3] {
            assert!((gamma(x + 1.0) / (x * gamma(x)) - 1.0).abs() < 1e-13);
        }
    }

    /// Each corrected row is exact on the two functions of its role (the plain weights plus
    /// the two columns, summed here as a dense row would be), the exact values checked
    /// against closed forms; the weights vanish at α = 1.
    #[test]
    fn corrected_rows_are_exact_on_the_leading_terms() {
        // D^α t^α = Γ(1 + α); D^α_+ 1 = (b − t)^{−α}/Γ(1 − α).
        assert!((Role::Velocity.exact(0.5, 0.5, 7) - gamma(1.5)).abs() < 1e-14);
        let expected = 7f64.powf(-0.5) / std::f64::consts::PI.sqrt();
        assert!((Role::Momentum.exact(0.5, 0.0, 7) - expected).abs() < 1e-14);
        let n = 40;
        for alpha in [0.3, 0.6, 0.9] {
            let w = grunwald_letnikov(alpha, n + 1);
            for role in [Role::Velocity, Role::Momentum] {
                let c = columns(role, alpha, n);
                let d = role.distances();
                for g in role.exponents(alpha) {
                    let sample = |i| role.sample(alpha, g, i);
                    for m in 1..=n {
                        let row: f64 = (0..=m).map(|r| w[r] * sample(m - r)).sum::<f64>()
                            + c[0][m - 1] * sample(d[0])
                            + c[1][m - 1] * sample(d[1]);
                        let exact = role.exact(alpha, g, m);
                        assert!(
                            (row - exact).abs() < 1e-12 * exact.abs().max(1.0),
                            "{role:?} α = {alpha} g = {g} m = {m}: {row} vs {exact}"
                        );
                    }
                }
            }
        }
        for role in [Role::Velocity, Role::Momentum] {
            let c = columns(role, 1.0, 10);
            assert!(
                c.iter().flatten().all(|x| x.abs() < 1e-13),
                "{role:?}: {c:?}"
            );
        }
    }
}
