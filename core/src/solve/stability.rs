//! The verdict of the initial value problems' stability check: the eigenvalues of the
//! linearised step map `(Q_{n−2}, Q_{n−1}) ↦ (Q_{n−1}, Q_n)` of a three-point recurrence
//! (every classical scheme, the symmetric embeddings' included), from its two lower blocks.

use nalgebra::allocator::Allocator;
use nalgebra::linalg::Schur;
use nalgebra::{Complex, DefaultAllocator, DimDiff, DimSub, OMatrix, U1};

use crate::lagrangian::{Hessian, Lagrangian, Matrix, Vector};
use crate::solve::resolution::fastest_frequency;
use crate::step::{Step, StepKind, StepTimes, residual};

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

/// `L = ½v² − ½x²`: the harmonic oscillator of frequency 1, on which a step kind's limit of
/// `hω` is measured.
struct UnitOscillator;

impl Lagrangian<1> for UnitOscillator {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 {
        0.5 * (v[0] * v[0] - x[0] * x[0])
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
        (-x, *v)
    }
    fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
        Hessian {
            xx: Matrix::<1>::new(-1.0),
            xv: Matrix::<1>::zeros(),
            vv: Matrix::<1>::identity(),
        }
    }
}

/// The step map `Q_n = A Q_{n−2} + B Q_{n−1}` of `kind` on [`UnitOscillator`] with step `h`,
/// from the step's own residual: it is affine in the newest node, so one Newton step from zero
/// solves it exactly. `None` when the step's Jacobian vanishes.
pub(crate) fn oscillator_step_map(kind: StepKind, h: f64) -> Option<(f64, f64)> {
    let times = StepTimes::new(h, 0.0, h, 2.0 * h);
    let solve = |a: f64, b: f64| {
        let (a, b) = (Vector::<1>::new(a), Vector::<1>::new(b));
        let step = Step::new(&UnitOscillator, kind, &a, &b, &times);
        let (r, j) = residual(&UnitOscillator, &step, &Vector::<1>::zeros());
        (j[(0, 0)] != 0.0).then(|| -r[0] / j[(0, 0)])
    };
    Some((solve(1.0, 0.0)?, solve(0.0, 1.0)?))
}

/// The largest `hω` at which `kind` passes [`step_map_verdict`] on the harmonic oscillator
/// (2 for Störmer–Verlet, whose step map has a real eigenvalue below −1 beyond it); `None`
/// when it passes up to `hω = 10³` (no step limit). The first failure on a geometric scan of
/// `hω` from `10⁻³`, then bisection to 12 digits.
pub(crate) fn oscillator_limit(kind: StepKind) -> Option<f64> {
    let unstable = |z: f64| match oscillator_step_map(kind, z) {
        Some((a, b)) => matches!(
            step_map_verdict(&Matrix::<1>::new(a), &Matrix::<1>::new(b), z),
            Verdict::Unstable(_)
        ),
        None => true,
    };
    let scan: Vec<f64> = (0..=120)
        .map(|i| 1e-3 * 10f64.powf(i as f64 / 20.0))
        .collect();
    let first = scan.iter().position(|&z| unstable(z))?;
    if first == 0 {
        return Some(0.0);
    }
    let (mut lo, mut hi) = (scan[first - 1], scan[first]);
    while hi - lo > 1e-12 * hi {
        let mid = 0.5 * (lo + hi);
        if unstable(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(lo)
}

/// The largest step at which `kind` is stable on the linearisation at `(x, v, t)`:
/// [`oscillator_limit`] over [`fastest_frequency`] (see [`Error::Unstable`](crate::Error)).
/// `None` under a generalised force: the limit on the oscillator is not the limit with
/// damping (an explicit step under friction `−γv` also needs `γh ≤ 2`), and a wrong bound
/// would mislead.
pub(crate) fn largest_stable_step<const D: usize, L: Lagrangian<D> + ?Sized>(
    lagrangian: &L,
    kind: StepKind,
    x: &Vector<D>,
    v: &Vector<D>,
    t: f64,
) -> Option<f64> {
    if lagrangian.is_forced() {
        return None;
    }
    Some(oscillator_limit(kind)? / fastest_frequency(lagrangian, x, v, t)?)
}

#[cfg(test)]
mod tests {
    use crate::step::StepKind;

    #[test]
    fn each_step_kind_has_its_oscillator_limit() {
        use StepKind::*;
        // On q̈ = −ω²q: Störmer–Verlet (the variational Gauss-FDE steps, and the trapezoidal
        // ones, which are the same recurrence there) and the direct midpoint recurrence
        // leave the unit circle at hω = 2; the direct σ = + step fails the verdict from
        // hω = √3; the direct σ = − step, implicit in the newest node, and the midpoint
        // variational rule (A-stable) never do. The bisection stops within 2.5e-9 of the
        // exact limit: 1e-8 relative.
        let expected = [
            (VariationalBackward, Some(2.0)),
            (VariationalForward, Some(2.0)),
            (DirectBackward, None),
            (DirectForward, Some(3f64.sqrt())),
            (MidpointVariational, None),
            (MidpointDirect, Some(2.0)),
            (TrapezoidalVariational, Some(2.0)),
            (TrapezoidalDirect, Some(2.0)),
        ];
        for (kind, limit) in expected {
            match (super::oscillator_limit(kind), limit) {
                (Some(found), Some(exact)) => {
                    assert!((found - exact).abs() < 1e-8 * exact, "{kind:?}: {found}")
                }
                (found, exact) => assert_eq!(found, exact, "{kind:?}"),
            }
        }
    }

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
