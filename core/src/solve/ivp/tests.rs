//! Unit tests of the stability verdict of the initial value problems.

use super::*;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

/// The stacked Jacobian `[[0, I], [A, B]]`.
fn stacked(a: &Matrix<2>, b: &Matrix<2>) -> nalgebra::Matrix4<f64> {
    nalgebra::Matrix4::from_fn(|r, c| match (r < 2, c < 2) {
        (true, _) => {
            if c == 2 + r {
                1.0
            } else {
                0.0
            }
        }
        (false, true) => a[(r - 2, c)],
        (false, false) => b[(r - 2, c - 2)],
    })
}

#[test]
fn stormer_verlet_is_near_identity_when_resolved_only() {
    // A = −1, B = 2 − (ωh)²: resolved at ωh = 0.05, not at ωh = 1.99 or 2.01.
    let h = 0.01;
    for (omega_h, near) in [(0.05, true), (1.99, false), (2.01, false)] {
        let (a, b) = (
            Matrix::<1>::new(-1.0),
            Matrix::<1>::new(2.0 - omega_h * omega_h),
        );
        assert_eq!(near_identity(&a, &b, h), near, "ωh = {omega_h}");
    }
    // ωh = 2.01 is flagged by the Schur form (an eigenvalue below −1).
    let j = nalgebra::Matrix2::new(0.0, 1.0, -1.0, 2.0 - 2.01 * 2.01);
    assert!(matches!(first_unstable(j), Verdict::Unstable(l) if l.re < -1.0));
}

/// The shortcut never contradicts the Schur form: whenever it clears a Jacobian, the
/// eigenvalues flag nothing, on random perturbations of resolved and unresolved steps.
#[test]
fn near_identity_agrees_with_the_schur_verdict() {
    let mut rng = StdRng::seed_from_u64(11);
    let mut cleared = 0;
    for _ in 0..2000 {
        let h = 10f64.powf(rng.random_range(-4.0..-0.5));
        let scale = 10f64.powf(rng.random_range(-3.0..1.0));
        let noise = |rng: &mut StdRng| Matrix::<2>::from_fn(|_, _| rng.random_range(-1.0..1.0));
        // Around Störmer–Verlet: A = −I + O(scale·h²), B = 2I + O(scale·h²).
        let a = -Matrix::<2>::identity() + noise(&mut rng) * (scale * h * h);
        let b = Matrix::<2>::identity() * 2.0 + noise(&mut rng) * (scale * h);
        if near_identity(&a, &b, h) {
            cleared += 1;
            assert_eq!(
                first_unstable(stacked(&a, &b)),
                Verdict::Stable,
                "{a} {b} h = {h}"
            );
        }
    }
    assert!(cleared > 200, "the shortcut cleared only {cleared} of 2000");
}
