//! The Gamma function, for the closed forms of fractional derivatives of powers
//! (`D^α t^β = Γ(β + 1)/Γ(β + 1 − α) t^{β−α}`) that exact fractional solutions are built from.

use std::f64::consts::PI;

/// The Lanczos coefficients for `g = 7`, nine terms (relative error about `10⁻¹⁵` for
/// `x ≥ 1/2`).
const LANCZOS: [f64; 9] = [
    0.999_999_999_999_809_9,
    676.520_368_121_885_1,
    -1_259.139_216_722_402_8,
    771.323_428_777_653_1,
    -176.615_029_162_140_6,
    12.507_343_278_686_905,
    -0.138_571_095_265_720_12,
    9.984_369_578_019_572e-6,
    1.505_632_735_149_311_6e-7,
];

/// `Γ(x)` for real `x` not a pole: the Lanczos approximation for `x ≥ 1/2`, the reflection
/// formula `Γ(x) Γ(1 − x) = π / sin(πx)` below.
///
/// ```
/// use varembed_tests::special::gamma;
/// assert!((gamma(5.0) - 24.0).abs() < 1e-12);
/// assert!((gamma(0.5) - std::f64::consts::PI.sqrt()).abs() < 1e-14);
/// ```
pub fn gamma(x: f64) -> f64 {
    if x < 0.5 {
        return PI / ((PI * x).sin() * gamma(1.0 - x));
    }
    let x = x - 1.0;
    let t = x + 7.5;
    let sum = LANCZOS[1..]
        .iter()
        .enumerate()
        .fold(LANCZOS[0], |s, (i, c)| s + c / (x + i as f64 + 1.0));
    (2.0 * PI).sqrt() * t.powf(x + 0.5) * (-t).exp() * sum
}

#[cfg(test)]
mod tests {
    use super::gamma;

    /// Against the factorials, `Γ(n + 1/2) = √π (2n)!/(4ⁿ n!)` and the recurrence
    /// `Γ(x + 1) = x Γ(x)` at non-half-integer points.
    #[test]
    fn gamma_matches_closed_forms_and_its_recurrence() {
        let mut factorial = 1.0;
        for n in 1..15 {
            factorial *= n as f64;
            let g = gamma(n as f64 + 1.0);
            assert!(
                (g - factorial).abs() <= 1e-13 * factorial,
                "Γ({}) = {g}",
                n + 1
            );
        }
        let mut half = std::f64::consts::PI.sqrt();
        for n in 0..10 {
            let g = gamma(n as f64 + 0.5);
            assert!((g - half).abs() <= 1e-13 * half, "Γ({n}.5) = {g} vs {half}");
            half *= n as f64 + 0.5;
        }
        for x in [0.1, 0.3, 0.77, 1.2, 2.6, 4.4] {
            let (a, b) = (gamma(x + 1.0), x * gamma(x));
            assert!((a - b).abs() <= 1e-13 * a, "Γ({x} + 1) = {a} vs {b}");
        }
    }
}
