//! The variational Gauss–Legendre integrators under holonomic constraints, with the constraint
//! at the nodes (the constrained discrete Euler–Lagrange equations of the Gauss–Legendre
//! discrete Lagrangian), against oracles independent of the constrained solver:
//!
//! - the order, measured: 2 for every stage count `s = 1..4`, not `2s` (the stages are not
//!   constrained), on the Cartesian spherical pendulum against the angle form and on the
//!   four-bar linkage (a kinetic energy that depends on the configuration) against a
//!   Richardson-extrapolated midpoint reference;
//! - the constraint at every node to 1e-12; the vertical angular momentum, the Noether
//!   momentum of a symmetry the constraint respects, to round-off; the multipliers against the
//!   spherical pendulum's `λ = 3z − 2E`.

use varembed::{Embedding, Error, Grid, Holonomic, Scheme, Vector, project_initial_data};

use super::constraints::{Falling, Linkage, LoopX, LoopY, Sphere, T_END, angles_at_end, initial};

fn pendulum(stages: usize, n: usize) -> varembed::ConstrainedSolution<3, 1> {
    let (q0, v0) = initial();
    let embedding = Embedding::gauss_legendre(stages).unwrap();
    varembed_tests::problem(&Falling, Grid::new(0.0, T_END, n).unwrap(), embedding)
        .solve_constrained_ivp(Scheme::Variational, &Holonomic(Sphere), q0, v0)
        .unwrap()
}

/// Observed orders `log₂(e_N / e_2N)` at `N = 100, 200` within 0.1 of 2 for every `s`, on the
/// spherical pendulum at `t = 5` and the four-bar linkage at `t = 1`; the constraint at every
/// node to 1e-12.
#[test]
fn gauss_legendre_under_constraints_is_second_order_for_every_stage_count() {
    let reference = angles_at_end();
    let closure = (Holonomic(LoopX), Holonomic(LoopY));
    let guess = Vector::<3>::new(std::f64::consts::FRAC_PI_2, -0.3, 1.2);
    let (q0, v0) = project_initial_data(&closure, guess, Vector::<3>::new(2.0, 0.0, 0.0)).unwrap();
    let linkage = |embedding: Embedding, n: usize| {
        varembed_tests::problem(&Linkage, Grid::new(0.0, 1.0, n).unwrap(), embedding)
            .solve_constrained_ivp(Scheme::Variational, &closure, q0, v0)
            .unwrap()
            .solution
    };
    // Midpoint's error is `C h² + O(h⁴)`: the extrapolation is accurate to about 1e-12 here.
    let (coarse, fine) = (
        linkage(Embedding::midpoint(), 12_800).last(),
        linkage(Embedding::midpoint(), 25_600).last(),
    );
    let linkage_reference = (fine * 4.0 - coarse) / 3.0;
    for stages in 1..=4 {
        let error = |n: usize| {
            let run = pendulum(stages, n);
            let off = run
                .solution
                .q
                .iter()
                .map(|q| (0.5 * (q.norm_squared() - 1.0)).abs())
                .fold(0.0, f64::max);
            assert!(off <= 1e-12, "s = {stages}: |g| = {off:e}");
            (run.solution.last() - reference).amax()
        };
        let order = (error(100) / error(200)).log2();
        assert!(
            (order - 2.0).abs() <= 0.1,
            "pendulum, s = {stages}: order {order:.2}"
        );
        let embedding = Embedding::gauss_legendre(stages).unwrap();
        let error = |n: usize| (linkage(embedding, n).last() - linkage_reference).amax();
        let order = (error(100) / error(200)).log2();
        assert!(
            (order - 2.0).abs() <= 0.1,
            "linkage, s = {stages}: order {order:.2}"
        );
    }
}

/// The vertical angular momentum of the momenta `p_k` the run returns stays at its initial
/// value to round-off over 500 steps, for every `s`: the constraint impulse `μ x` has no moment
/// about `z`, and the Gauss–Legendre step conserves the quadratic invariant.
#[test]
fn gauss_legendre_under_constraints_conserves_the_vertical_angular_momentum() {
    let (q0, v0) = initial();
    let initial = q0[0] * v0[1] - q0[1] * v0[0];
    for stages in 1..=4 {
        let nodes = pendulum(stages, 500)
            .solution
            .node_values(&Falling)
            .unwrap();
        let drift = nodes
            .iter()
            .map(|node| (node.q[0] * node.p[1] - node.q[1] * node.p[0] - initial).abs())
            .fold(0.0, f64::max);
        assert!(drift <= 1e-13, "s = {stages}: L_z drifts by {drift:e}");
    }
}

/// The multiplier of each step's impulse at its first node `n − 1` (`n = 2..=N`) against
/// `λ = 3z − 2E₀` there, falling as `h²`.
#[test]
fn gauss_legendre_multipliers_are_the_constraint_force() {
    let (q0, v0) = initial();
    let energy = 0.5 * v0.norm_squared() + q0[2];
    for stages in [1, 3] {
        let gap = |steps: usize| {
            let run = pendulum(stages, steps);
            assert_eq!(run.multipliers.len(), steps - 1);
            (2..=steps)
                .map(|n| {
                    let z = run.solution.q[n - 1][2];
                    (run.multipliers[n - 2][0] - (3.0 * z - 2.0 * energy)).abs()
                })
                .fold(0.0, f64::max)
        };
        let (coarse, fine) = (gap(200), gap(400));
        let order = (coarse / fine).log2();
        assert!(
            order >= 1.7 && fine < 0.01,
            "s = {stages}: λ off by {coarse:e}, {fine:e} (order {order:.2})"
        );
    }
}

/// Gauss–Legendre is variational only, under constraints too.
#[test]
fn gauss_legendre_has_no_constrained_direct_scheme() {
    let (q0, v0) = initial();
    let problem = varembed_tests::problem(
        &Falling,
        Grid::new(0.0, 1.0, 10).unwrap(),
        Embedding::gauss_legendre(2).unwrap(),
    );
    let refused = problem.solve_constrained_ivp(Scheme::Direct, &Holonomic(Sphere), q0, v0);
    assert!(
        matches!(refused, Err(Error::Unsupported { .. })),
        "{refused:?}"
    );
}
