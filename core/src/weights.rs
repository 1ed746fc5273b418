//! Grünwald–Letnikov weights.

/// The Grünwald–Letnikov weights `α_0 = 1`, `α_r = α_{r−1} (r − 1 − α)/r`, `r = 0..len`.
///
/// This is the stable recurrence for `α_r = (−1)^r C(α, r)`; no Gamma function is evaluated.
/// At `α = 1` the weights are exactly `1, −1, 0, 0, …`, so `Δ^1_± = Δ_±`.
///
/// # Example
///
/// ```
/// let w = varembed::weights::grunwald_letnikov(0.5, 3);
/// assert_eq!(w, vec![1.0, -0.5, -0.125]);
/// ```
pub fn grunwald_letnikov(alpha: f64, len: usize) -> Vec<f64> {
    let mut w = Vec::with_capacity(len);
    let mut current = 1.0;
    for r in 0..len {
        if r > 0 {
            current *= (r as f64 - 1.0 - alpha) / r as f64;
        }
        w.push(current);
    }
    w
}
