//! The verdict of the initial value problems' stability check: the eigenvalues of the
//! linearised step map `(Q_{n−2}, Q_{n−1}) ↦ (Q_{n−1}, Q_n)` of a three-point recurrence
//! (every classical scheme, the symmetric embeddings' included), from its two lower blocks.

use nalgebra::allocator::Allocator;
use nalgebra::linalg::Schur;
use nalgebra::{Complex, DefaultAllocator, DimDiff, DimSub, OMatrix, U1};

use crate::lagrangian::Matrix;

/// The verdict on the step-map Jacobian `[[0, I], [A, B]]` (`A = ∂Q_n/∂Q_{n−2}`,
/// `B = ∂Q_n/∂Q_{n−1}`) of a step of size `h`: cleared without the Schur form when
/// [`near_identity`], otherwise from its eigenvalues ([`first_unstable`]).
pub(crate) fn step_map_verdict<const D: usize>(a: &Matrix<D>, b: &Matrix<D>, h: f64) -> Verdict {
    if near_identity(a, b, h) {
        return Verdict::Stable;
    }
    let entry = |r: usize, c: usize| match (r < D, c < D) {
        (true, _) => {
            if c == D + r {
                1.0
            } else {
                0.0
            }
        }
        (false, true) => a[(r - D, c)],
        (false, false) => b[(r - D, c - D)],
    };
    // The Schur form on the stack for d ≤ 2 (the models this crate is mostly run on): the
    // same algorithm as on the heap, without its allocations.
    match D {
        1 => first_unstable(nalgebra::Matrix2::from_fn(entry)),
        2 => first_unstable(nalgebra::Matrix4::from_fn(entry)),
        _ => first_unstable(nalgebra::DMatrix::from_fn(2 * D, 2 * D, entry)),
    }
}

/// What the eigenvalues of the step map's Jacobian say about a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Verdict {
    /// No verdict: the real Schur form did not converge.
    Undecided,
    /// Every eigenvalue is acceptable.
    Stable,
    /// The first eigenvalue that marks the step as too large for the scheme.
    Unstable(Complex<f64>),
}

/// Whether every eigenvalue of the step-map Jacobian `J = [[0, I], [A, B]]` provably lies in
/// the disc `|λ − 1| ≤ ½`, where none can be flagged (`|λ| < 2`, `Re λ > 0`): the usual case
/// of a resolved step, decided without the Schur form.
///
/// In the coordinates `(b, (b − a)/h)` the map's Jacobian is the similar matrix
/// `M = [[A + B, −hA], [(A + B − I)/h, −A]]`, which is `I + O(ωh)` for a resolved step
/// (for Störmer–Verlet, `A = −I`, `B = 2I − h²U″`), and every eigenvalue of `M` (so of `J`)
/// lies within `‖M − I‖∞` of 1. The margin to the flagged region (½ in `Re λ`, ½ in `|λ|`)
/// dwarfs any rounding; a step this test cannot clear goes to the Schur form as before.
fn near_identity<const D: usize>(a: &Matrix<D>, b: &Matrix<D>, h: f64) -> bool {
    let s = a + b - Matrix::<D>::identity(); // A + B − I
    let a_plus_i = a + Matrix::<D>::identity(); // −(−A − I)
    (0..D).all(|r| {
        let row = |m: &Matrix<D>| m.row(r).iter().map(|x| x.abs()).sum::<f64>();
        let top = row(&s) + h * row(a);
        let bottom = row(&s) / h + row(&a_plus_i);
        top.max(bottom) <= 0.5
    })
}

/// The verdict of the eigenvalues of the step-map Jacobian `m` (see
/// `Ivp::check_stability`).
fn first_unstable<R>(m: OMatrix<f64, R, R>) -> Verdict
where
    R: DimSub<U1>,
    DefaultAllocator:
        Allocator<R, DimDiff<R, U1>> + Allocator<DimDiff<R, U1>> + Allocator<R, R> + Allocator<R>,
{
    let Some(schur) = Schur::try_new(m, f64::EPSILON, 10_000) else {
        return Verdict::Undecided;
    };
    let eigenvalues = schur.complex_eigenvalues();
    let unstable = eigenvalues.iter().copied().find(|lambda| {
        let sawtooth = lambda.im.abs() <= 1e-6 * lambda.norm() && lambda.re < -1.0 - 1e-4;
        sawtooth || lambda.norm() >= 2.0
    });
    unstable.map_or(Verdict::Stable, Verdict::Unstable)
}

#[cfg(test)]
mod tests {
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
}
