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
            Role::Velocity => power(i as f64, g),
            Role::Momentum => power(i as f64 + alpha / 2.0, g),
        }
    }

    /// [`exact_in_rows`](Self::exact_in_rows) in the single row at distance `m`.
    #[cfg(test)]
    fn exact(self, alpha: f64, g: f64, m: usize) -> f64 {
        self.exact_in_rows(alpha, g)(m)
    }

    /// The exact fractional derivative `Γ(g + 1)/Γ(g + 1 − α) s^{g−α}` of the function of
    /// exponent `g` in the row at distance `m` (in units of `h`, without `h^{g−α}`), as a
    /// function of `m`, with its Gamma factor computed once: at `s = m − α/2` for the
    /// velocity, at `s = m` for the momenta. `1/Γ(g + 1 − α)` is zero at its pole (`g = 0`,
    /// `α = 1`).
    fn exact_in_rows(self, alpha: f64, g: f64) -> impl Fn(usize) -> f64 {
        let reciprocal = if g + 1.0 - alpha > 0.0 {
            1.0 / gamma(g + 1.0 - alpha)
        } else {
            0.0
        };
        let factor = gamma(g + 1.0) * reciprocal;
        move |m| {
            let s = match self {
                Role::Velocity => m as f64 - alpha / 2.0,
                Role::Momentum => m as f64,
            };
            factor * power(s, g - alpha)
        }
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
/// `1..=n` from the start, `n + 1 = weights.len()` the Grünwald–Letnikov weights of the
/// operator (`weights[r] = w_r`): entry `m − 1` of each is the weight in the row at distance
/// `m`.
///
/// Row `m` solves the 2 × 2 system `Σ_i c_i s_g(d_i) = e_g(m) − Σ_r w_r s_g(m − r)` for the two
/// exponents `g`, `d_i` the columns' distances, `s_g` the samples of the function and `e_g` the
/// exact values (module docs). The right-hand side is a small difference of two values of
/// size `m^{g−α}`: the direct sums keep it to about `10⁻¹⁶ m^{g−α} √m`, far below the scheme's
/// error; the FFT route's error, relative to the largest value, is larger in the far rows,
/// where the weights themselves are small.
///
/// At `N = 10⁷` this is a large part of building a corrected discretisation, so the work per
/// row is what it must be: the two exponents share one FFT form of the weights and one pass of
/// direct sums, the Gamma factors are computed once, and a power with exponent 0 or 1 (the
/// momenta's samples, the velocity's exact values) is not a call of `powf`, whose value it
/// equals exactly.
pub(crate) fn columns(role: Role, alpha: f64, weights: &[f64]) -> [Vec<f64>; 2] {
    let n = weights.len() - 1;
    let (exponents, d) = (role.exponents(alpha), role.distances());
    // The 2 × 2 matrix A[g][i] = s_g(d_i), the same for every row.
    let a = exponents.map(|g| d.map(|di| role.sample(alpha, g, di)));
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    let plain = convolve_pair(
        weights,
        exponents.map(|g| move |i| role.sample(alpha, g, i)),
    );
    let exact = exponents.map(|g| role.exact_in_rows(alpha, g));
    // Row m's entry moves to m − 1 in place: no second pair of vectors.
    let mut out = plain.map(|mut plain| {
        plain.remove(0);
        plain
    });
    let [out0, out1] = &mut out;
    for (m, (c0, c1)) in (1..=n).zip(out0.iter_mut().zip(out1.iter_mut())) {
        let (r0, r1) = (exact[0](m) - *c0, exact[1](m) - *c1);
        // Cramer's rule on the fixed, well-conditioned 2 × 2 system.
        *c0 = (r0 * a[1][1] - r1 * a[0][1]) / det;
        *c1 = (a[0][0] * r1 - a[1][0] * r0) / det;
    }
    out
}

/// `x^e`, exactly `powf`'s value, without the call where `e` is 0 or 1.
fn power(x: f64, e: f64) -> f64 {
    if e == 0.0 {
        1.0
    } else if e == 1.0 {
        x
    } else {
        x.powf(e)
    }
}

/// `y_m = Σ_{r=0}^{m} w_r x_{m−r}`, `m = 0..len` (`len = w.len()`), for two inputs `x(k)`: by
/// direct sums for `m ≤` [`DIRECT_SUMS_UP_TO`], by FFT above (whose rounding, relative to the
/// largest value, would swamp the first rows' small differences, where the weights are
/// largest). One FFT form of the weights serves both inputs, which are read as the products
/// load them (no vector of them is kept: at `N = 10⁷` one is 80 MB), and the direct sums of
/// the two run in one pass, each summed in increasing `r` as a sum of its own would be.
fn convolve_pair(w: &[f64], x: [impl Fn(usize) -> f64; 2]) -> [Vec<f64>; 2] {
    let len = w.len();
    let direct_rows = len.min(DIRECT_SUMS_UP_TO + 1);
    let mut y = if len <= DIRECT_SUMS_UP_TO + 1 {
        [vec![0.0; len], vec![0.0; len]]
    } else {
        let (toeplitz, mut workspace) = TriangularToeplitz::with_workspace(w);
        x.each_ref().map(|x| {
            let mut y = vec![0.0; len];
            toeplitz.mul_with(false, &mut workspace, x, |k, v| y[k] = v);
            y
        })
    };
    let [x0, x1] = x.map(|x| (0..direct_rows).map(x).collect::<Vec<f64>>());
    let [y0, y1] = &mut y;
    for m in 0..direct_rows {
        // `-0.0`, the start of `Iterator::sum`: the same value for every input.
        let (mut s0, mut s1) = (-0.0, -0.0);
        let rows = w[..=m]
            .iter()
            .zip(x0[..=m].iter().rev().zip(x1[..=m].iter().rev()));
        for (w, (x0, x1)) in rows {
            s0 += w * x0;
            s1 += w * x1;
        }
        (y0[m], y1[m]) = (s0, s1);
    }
    y
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::weights::grunwald_letnikov;

    /// Past the threshold the plain sums go by FFT, equal to the direct sums to the rounding
    /// of the largest value; below it they are the direct sums.
    #[test]
    fn fft_sums_equal_direct_sums() {
        let n = DIRECT_SUMS_UP_TO + 500;
        let w = grunwald_letnikov(0.6, n + 1);
        let x: Vec<f64> = (0..=n).map(|i| (i as f64).powf(1.6)).collect();
        let ones = vec![1.0; n + 1];
        fn at(v: &[f64]) -> impl Fn(usize) -> f64 + '_ {
            move |k| v[k]
        }
        let [by_fft, sums] = convolve_pair(&w, [at(&x), at(&ones)]);
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
            let partial: f64 = w[..=m].iter().sum();
            assert!(
                (sums[m] - partial).abs() <= bound,
                "{m}: {} vs {partial}",
                sums[m]
            );
        }
    }

    /// The columns as computed one function at a time, each with its own FFT form, its own
    /// direct sums and `powf` everywhere: the shared passes give the same numbers, bit for bit,
    /// in the direct rows and in the FFT rows.
    #[test]
    fn shared_passes_give_the_columns_of_one_function_at_a_time() {
        let reference = |role: Role, alpha: f64, n: usize| -> [Vec<f64>; 2] {
            let w = grunwald_letnikov(alpha, n + 1);
            let (exponents, d) = (role.exponents(alpha), role.distances());
            let sample = |g: f64, i: usize| match role {
                Role::Velocity => (i as f64).powf(g),
                Role::Momentum => (i as f64 + alpha / 2.0).powf(g),
            };
            let exact = |g: f64, m: usize| {
                let s = match role {
                    Role::Velocity => m as f64 - alpha / 2.0,
                    Role::Momentum => m as f64,
                };
                let reciprocal = if g + 1.0 - alpha > 0.0 {
                    1.0 / gamma(g + 1.0 - alpha)
                } else {
                    0.0
                };
                gamma(g + 1.0) * reciprocal * s.powf(g - alpha)
            };
            let a = exponents.map(|g| d.map(|di| sample(g, di)));
            let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
            let residuals = exponents.map(|g| {
                let samples: Vec<f64> = (0..=n).map(|i| sample(g, i)).collect();
                let mut plain: Vec<f64> = (0..=n)
                    .map(|m| (0..=m).map(|r| w[r] * samples[m - r]).sum::<f64>())
                    .collect();
                if n > DIRECT_SUMS_UP_TO {
                    let (toeplitz, mut workspace) = TriangularToeplitz::with_workspace(&w);
                    let mut by_fft = vec![0.0; n + 1];
                    toeplitz.mul(false, &mut workspace, &samples, &mut by_fft);
                    plain[DIRECT_SUMS_UP_TO + 1..]
                        .copy_from_slice(&by_fft[DIRECT_SUMS_UP_TO + 1..]);
                }
                (1..=n)
                    .map(|m| exact(g, m) - plain[m])
                    .collect::<Vec<f64>>()
            });
            let solve = |i: usize| {
                let (r0, r1) = (residuals[0][i], residuals[1][i]);
                [
                    (r0 * a[1][1] - r1 * a[0][1]) / det,
                    (a[0][0] * r1 - a[1][0] * r0) / det,
                ]
            };
            [0, 1].map(|c| (0..n).map(|i| solve(i)[c]).collect())
        };
        // α = 1 puts exponents 1 + α − α and 1 − α at 1 and 0 (or within a rounding of them).
        for (alpha, n) in [(0.3, 40), (0.55, 7), (0.7, 2), (0.9, 100), (1.0, 12)] {
            for role in [Role::Velocity, Role::Momentum] {
                let w = grunwald_letnikov(alpha, n + 1);
                assert_eq!(
                    columns(role, alpha, &w),
                    reference(role, alpha, n),
                    "{role:?} α = {alpha}"
                );
            }
        }
        let (alpha, n) = (0.65, DIRECT_SUMS_UP_TO + 300);
        let w = grunwald_letnikov(alpha, n + 1);
        for role in [Role::Velocity, Role::Momentum] {
            assert_eq!(
                columns(role, alpha, &w),
                reference(role, alpha, n),
                "{role:?}"
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
                let c = columns(role, alpha, &w);
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
            let c = columns(role, 1.0, &grunwald_letnikov(1.0, 11));
            assert!(
                c.iter().flatten().all(|x| x.abs() < 1e-13),
                "{role:?}: {c:?}"
            );
        }
    }
}
