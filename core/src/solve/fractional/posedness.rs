//! The ill-posedness check of the fast path: the measure of the conditioning module (the
//! smallest eigenvalue in modulus of `P'⁻¹J` at the solution) from the Ritz values of a few
//! Lanczos steps, taken as MINRES iterations on the Newton system.
//!
//! **On a coarser grid past [`CHECK_STEPS`].** The Lanczos steps cost five preconditioner
//! applications, ten FFT products: about a fifth of a large solve's (BENCHMARKS.md). The
//! measure is a property of the continuous problem that each grid approximates, so past
//! [`CHECK_STEPS`] steps the check runs first on a grid of [`CHECK_STEPS`] steps over the same
//! interval, linearised at the solution interpolated to it (linearly between the solution's
//! nodes, the ends exact), at a cost that no longer grows with `N`. That grid's measure differs
//! from the solve's own by the measure's discretisation error, which decays slowly. On the
//! oscillator `L = ½v² − ½kx²` the measure is `1 − k/μ₁` next to the first resonance, `μ₁` the
//! lowest eigenvalue of the kinetic part `DᵀD` on `[0, 1]`, and `μ₁` converges like `h^p` with
//! `p` about 0.42, 0.25, 0.53, 0.83 at α = 0.3, 0.5, 0.74, 0.9 (dense eigenvalues at
//! `N = 100 … 1600`: successive differences 0.0184 … 0.0076 at α = 0.3, 0.0459 … 0.0268 at
//! α = 0.5). Extrapolated at that rate, `μ₁` on [`CHECK_STEPS`] steps is within about 2 % of its
//! value at `N = 10⁷` at α = 0.5 and within 0.05 % at α = 0.74, which next to a resonance
//! (`k ≈ μ₁`) moves the measure by about 0.02 and 0.0005 in absolute terms: twice the
//! threshold of 10⁻² at α = 0.5. So the coarser grid decides alone only where it has Ritz values
//! and each one's modulus, less its bound, lies above [`RECHECK_BELOW`] = 0.1, ten times the
//! threshold ([`in_doubt`]); otherwise the check runs again on the solve's own grid, whose measure the
//! warning then carries. The warning is therefore the one of the solve's own grid wherever the
//! two grids' measures differ by less than 0.09, and far from any resonance (the benchmark
//! pendulum's measure is about 0.8) the ten products are taken on the coarser grid. Where `N`
//! is at most [`CHECK_STEPS`] the check runs on the solve's own grid, as the dense solver's
//! does.

use super::end_columns::EndColumns;
use super::residual::{Evaluation, velocities};
use super::system::FastSystem;
use crate::discretisation::Discretisation;
use crate::embedding::Scheme;
use crate::error::{Location, Result};
use crate::grid::Grid;
use crate::lagrangian::{Lagrangian, Vector};
use crate::solve::conditioning::{ILL_POSED_BELOW, start};
use crate::solve::krylov::KrylovOptions;
use crate::solve::minres::{MinresWork, Tridiagonal, minres_in, ritz_values};

/// The largest grid the check runs on first: past it, on a grid of this many steps. Its ten
/// FFT products take about 0.1 s, against about 3 s on the grid of `N = 10⁷` (BENCHMARKS.md).
pub(super) const CHECK_STEPS: usize = 1 << 18;

/// Lanczos steps of the ill-posedness check at the converged iterate.
const LANCZOS_STEPS: usize = 4;

/// Below this, less its bound, a Ritz value of the coarser grid leaves the decision to the
/// solve's own grid (module docs).
const RECHECK_BELOW: f64 = 0.1;

/// Whether the coarser grid's `ritz` leave the decision to the solve's own grid: some Ritz
/// value whose modulus less its bound lies below [`RECHECK_BELOW`], or none at all (a Krylov
/// start that broke down). Ritz values above it say nothing of eigenvalues away from them
/// (four Lanczos steps can miss an interior one, on either grid): the rule keeps the coarser
/// grid from deciding next to the threshold where it sees an eigenvalue, nothing more.
pub(super) fn in_doubt(ritz: &[(f64, f64)]) -> bool {
    ritz.is_empty()
        || ritz
            .iter()
            .any(|(theta, bound)| theta.abs() - bound < RECHECK_BELOW)
}

/// The ill-posedness measure among `ritz` (pairs of a Ritz value of `P'⁻¹J` and its bound):
/// the smallest Ritz value in modulus among those whose bound places an eigenvalue below
/// [`ILL_POSED_BELOW`]; `None` when none does.
///
/// The lowest eigenvalue of `P'⁻¹J` is an extreme one next to a resonance of the lowest mode,
/// and its Ritz value converges at the rate of the gap to the next one: on the oscillator at
/// α = 0.74, 0.1 % below its first resonance (`N = 50 … 1000`), four steps give it within
/// 0.2 % with a bound of 1.3e-3, three within 14 % with a bound of 1e-2 (dense eigenvalues of
/// the same Lanczos process). An interior eigenvalue near zero (a resonance of a higher mode)
/// needs more steps to be resolved, and is then not flagged: the bound keeps an unconverged
/// Ritz value from flagging a well-posed problem, never the other way round.
pub(super) fn flagged(ritz: &[(f64, f64)]) -> Option<f64> {
    ritz.iter()
        .filter(|(theta, bound)| theta.abs() + bound < ILL_POSED_BELOW)
        .map(|(theta, _)| theta.abs())
        .min_by(f64::total_cmp)
}

/// The Ritz values of `P'⁻¹J` for the linearisation in `system`, with their bounds, after
/// [`LANCZOS_STEPS`] MINRES iterations from the start of the dense path's inverse iteration.
///
/// `x` is a vector of the unknowns' length for the iterates, which the check discards (the
/// Newton step's, idle by then).
pub(super) fn ritz<const D: usize>(
    system: &mut FastSystem<'_, D>,
    x: &mut [f64],
    work: &mut MinresWork,
) -> Vec<(f64, f64)> {
    let mut b = start((system.n - 1) * D);
    let mut lanczos = Tridiagonal::default();
    let options = KrylovOptions {
        tolerance: 0.0,
        max_iterations: LANCZOS_STEPS,
        restart: 0,
    };
    // Lanczos needs a symmetric J: the corrected direct scheme's is measured without its
    // starting columns (a low-rank change of the same problem's linearisation).
    system.plain = !system.symmetric();
    let _ = minres_in(system, &mut b, x, &options, Some(&mut lanczos), work);
    system.plain = false;
    ritz_values(&lanczos)
}

/// [`ritz`] on a grid of `steps` steps over the interval of `disc`, the system linearised at
/// `q` (the solution on the grid of `disc`) interpolated to it; an error where the
/// Lagrangian's values there are not finite.
pub(super) fn ritz_on_grid<L: Lagrangian<D> + ?Sized, const D: usize>(
    disc: &Discretisation<'_, L, D>,
    scheme: Scheme,
    q: &[Vector<D>],
    steps: usize,
) -> Result<Vec<(f64, f64)>> {
    let grid = disc.grid();
    let coarse = Discretisation::new(
        disc.lagrangian(),
        Grid::new(grid.a(), grid.b(), steps)?,
        *disc.embedding(),
    );
    let q = interpolate(q, steps);
    coarse.with_velocity_fft(|fft| {
        let (velocity, adjoint) = (coarse.velocity_operator(), coarse.adjoint_operator());
        let columns = EndColumns::new(scheme, velocity, adjoint);
        let mut system = FastSystem::<D>::new(velocity, columns, fft);
        let mut evaluation = Evaluation::new(steps);
        let at = Location::Newton(0);
        velocities(&coarse, &mut system, &q, 0, &mut evaluation)?;
        system.linearize(&coarse, &q, &evaluation.v, at)?;
        let mut x = vec![0.0; (steps - 1) * D];
        Ok(ritz(&mut system, &mut x, &mut MinresWork::default()))
    })
}

/// The curve `q` (nodes on a uniform grid of `N` steps) at the nodes of a uniform grid of
/// `steps` steps over the same interval, linearly between its nodes; the ends exact.
pub(super) fn interpolate<const D: usize>(q: &[Vector<D>], steps: usize) -> Vec<Vector<D>> {
    let n = q.len() - 1;
    (0..=steps)
        .map(|k| {
            // Node k sits at k·N/steps steps of the fine grid: whole steps j, fraction θ.
            let (j, rest) = ((k * n) / steps, (k * n) % steps);
            if rest == 0 {
                q[j]
            } else {
                let theta = rest as f64 / steps as f64;
                q[j] * (1.0 - theta) + q[j + 1] * theta
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::solve_with;
    use super::*;
    use crate::embedding::Embedding;
    use crate::lagrangian::{Hessian, Matrix};
    use crate::options::SolverOptions;
    use crate::side::Side;
    use crate::solve::solution::Warning;

    /// `L = ½v² − ½k x²`: its Jacobian `DᵀD − k` does not depend on the curve.
    struct Oscillator {
        k: f64,
    }

    impl Lagrangian<1> for Oscillator {
        fn value(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> f64 {
            0.5 * v[0] * v[0] - 0.5 * self.k * x[0] * x[0]
        }
        fn gradient(&self, x: &Vector<1>, v: &Vector<1>, _t: f64) -> (Vector<1>, Vector<1>) {
            (x * -self.k, *v)
        }
        fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> Hessian<1> {
            Hessian {
                xx: Matrix::<1>::new(-self.k),
                xv: Matrix::<1>::zeros(),
                vv: Matrix::<1>::identity(),
            }
        }
    }

    fn gle() -> Embedding {
        Embedding::grunwald_letnikov(Side::Backward, 0.74).unwrap()
    }

    /// The lowest eigenvalue of the kinetic part `P' = DᵀD` on `n` steps of `[0, 1]`: the
    /// dense Jacobian of `L = ½v²`, by a symmetric eigensolver.
    fn lowest_kinetic_eigenvalue(n: usize) -> f64 {
        let grid = Grid::new(0.0, 1.0, n).unwrap();
        let free = Oscillator { k: 0.0 };
        let disc = Discretisation::new(&free, grid, gle());
        let q = vec![Vector::<1>::zeros(); n + 1];
        let pw = disc.pointwise(&q).unwrap();
        let kinetic = disc.dense_jacobian(Scheme::Variational, &q, &pw);
        kinetic.symmetric_eigenvalues().min()
    }

    /// The measure of the fast solve's `IllPosed` warning on `n` steps, `Q_0 = 0`, `Q_N = 1`,
    /// the check on at most `check_steps` steps; `None` without the warning.
    fn measure(k: f64, n: usize, check_steps: usize) -> Option<f64> {
        let grid = Grid::new(0.0, 1.0, n).unwrap();
        let model = Oscillator { k };
        let disc = Discretisation::new(&model, grid, gle());
        let guess: Vec<Vector<1>> = (0..=n)
            .map(|j| Vector::<1>::new(j as f64 / n as f64))
            .collect();
        let options = SolverOptions::default();
        let scheme = Scheme::Variational;
        let (solution, _) = disc
            .with_velocity_fft(|fft| {
                solve_with(
                    &disc,
                    fft,
                    &options,
                    scheme,
                    (guess, super::super::ETA_MAX),
                    check_steps,
                )
            })
            .unwrap();
        match solution.warnings[..] {
            [Warning::IllPosed { measure }] => Some(measure),
            [] => None,
            ref other => panic!("N = {n}, k = {k}: {other:?}"),
        }
    }

    /// A Ritz value near the threshold, or none at all, leaves the decision to the solve's own
    /// grid; Ritz values all clear of it do not.
    #[test]
    fn doubt_is_a_ritz_value_near_the_threshold_or_none() {
        assert!(in_doubt(&[]));
        assert!(in_doubt(&[(0.8, 0.01), (0.15, 0.06)]));
        assert!(in_doubt(&[(-0.05, 0.0)]));
        assert!(!in_doubt(&[(0.8, 0.01), (-1.2, 0.5), (0.15, 0.04)]));
    }

    /// The coarser grid measures its own problem, and decides only far from the threshold. On
    /// the oscillator at `k = 0.999 μ₁`, `μ₁` the lowest kinetic eigenvalue on 200 steps, the
    /// 200-step problem's measure is `1 − k/μ₁ = 10⁻³` exactly: linearised at a solution on
    /// 2000 steps, the check on 200 steps finds it (within the 2 % of four Lanczos steps). That
    /// is in doubt, so a solve on 2000 steps checked past 200 carries the warning of its own
    /// grid, which is none (`μ₁` moves by more than 1 % between the grids), as a solve checked
    /// on its own grid throughout. Without stiffness (`k = 0`) the coarser grid decides.
    #[test]
    fn the_check_past_its_grid_decides_there_only_far_from_the_threshold() {
        let (coarse, fine) = (200, 2000);
        let k = 0.999 * lowest_kinetic_eigenvalue(coarse);
        let exact = 1e-3;
        let grid = Grid::new(0.0, 1.0, fine).unwrap();
        for (stiffness, doubt) in [(k, true), (0.0, false)] {
            let model = Oscillator { k: stiffness };
            let disc = Discretisation::new(&model, grid, gle());
            let q: Vec<Vector<1>> = (0..=fine)
                .map(|j| Vector::<1>::new(j as f64 / fine as f64))
                .collect();
            let ritz = ritz_on_grid(&disc, Scheme::Variational, &q, coarse).unwrap();
            assert_eq!(in_doubt(&ritz), doubt, "k = {stiffness}: {ritz:?}");
            if doubt {
                let on_coarse = flagged(&ritz).expect("flagged on the coarser grid");
                assert!(
                    (on_coarse - exact).abs() <= 0.02 * exact,
                    "checked on {coarse} steps: {on_coarse:e}, exact {exact:e}"
                );
            }
            assert_eq!(measure(stiffness, fine, coarse), None, "k = {stiffness}");
            assert_eq!(
                measure(stiffness, fine, usize::MAX),
                None,
                "k = {stiffness}"
            );
        }
        // At or below its grid a solve is checked on its own grid.
        let own = measure(k, coarse, usize::MAX).expect("flagged");
        assert_eq!(measure(k, coarse, coarse), Some(own));
        assert!((own - exact).abs() <= 0.02 * exact, "{own:e}");
    }

    /// The interpolated curve is exact on a straight line, at the ends, and where the nodes
    /// of the two grids coincide.
    #[test]
    fn interpolation_to_the_coarser_grid() {
        let n = 1000;
        let line: Vec<Vector<1>> = (0..=n)
            .map(|j| Vector::<1>::new(3.0 * j as f64 - 7.0))
            .collect();
        let wavy: Vec<Vector<1>> = (0..=n)
            .map(|j| Vector::<1>::new((j as f64).sin()))
            .collect();
        for steps in [7, 300, 999] {
            let straight = interpolate(&line, steps);
            let curved = interpolate(&wavy, steps);
            assert_eq!(
                (straight.len(), curved[0], curved[steps]),
                (steps + 1, wavy[0], wavy[n])
            );
            for (i, x) in straight.iter().enumerate() {
                let t = i as f64 * n as f64 / steps as f64;
                assert!((x[0] - (3.0 * t - 7.0)).abs() < 1e-10, "{steps}: {i}");
            }
        }
        // Every tenth node of the fine grid is a node of the coarse one.
        let sampled = interpolate(&wavy, 100);
        assert!((0..=100).all(|i| sampled[i] == wavy[10 * i]));
    }
}
