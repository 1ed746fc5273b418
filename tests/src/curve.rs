//! Sizes of discrete curves `Q_0..=Q_N` and of their differences, in the max-norm the tests
//! state their tolerances in.

use varembed::Vector;

/// The one-dimensional vector `(x)`.
pub fn v1(x: f64) -> Vector<1> {
    Vector::<1>::new(x)
}

/// `max_k |Q_k|_∞`; 0 for an empty list.
pub fn max_norm<const D: usize>(q: &[Vector<D>]) -> f64 {
    q.iter().fold(0.0f64, |m, v| m.max(v.amax()))
}

/// `max_k |a_k − b_k|_∞`.
///
/// # Panics
/// If the lists differ in length: a test comparing curves of different grids is wrong.
pub fn max_diff<const D: usize>(a: &[Vector<D>], b: &[Vector<D>]) -> f64 {
    assert_eq!(a.len(), b.len(), "curves of different lengths");
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).amax()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn norms_of_a_small_curve() {
        let a = [v1(1.0), v1(-3.0), v1(2.0)];
        let b = [v1(1.5), v1(-3.0), v1(0.0)];
        assert_eq!(max_norm(&a), 3.0);
        assert_eq!(max_norm::<1>(&[]), 0.0);
        assert_eq!(max_diff(&a, &b), 2.0);
    }

    #[test]
    #[should_panic(expected = "different lengths")]
    fn max_diff_rejects_different_lengths() {
        max_diff(&[v1(0.0)], &[v1(0.0), v1(1.0)]);
    }
}
