//! Generalised forces (`Forced`, `Rayleigh`), against oracles independent of the schemes:
//!
//! - the damped oscillator `q̈ + γq̇ + q = 0` by Rayleigh friction, against its exact solution:
//!   every classical embedding and scheme keeps the order it has without a force
//!   (`Embedding::order`), as an initial value problem and as a boundary value problem;
//! - the forced discrete Noether theorem: on a model invariant under a common translation, under
//!   a force that depends on `x`, `v` and `t` non-linearly, the variational schemes' momentum
//!   along the symmetry changes by the sum of the discrete impulses, to round-off;
//! - the energy balance `E_k − E_0 = W_k` to the scheme's order;
//! - the closed-form steps of a constant-Jacobian force against the same steps by Newton, and
//!   the boundary value problem through the nodes of the initial value problem;
//! - `Rayleigh`'s force and Jacobian against central differences of the dissipation function
//!   the macro differentiated, at generated points;
//! - what is refused: a fractional problem under a force, the impulse of a Gauss–Legendre run.

use varembed::{
    Dependence, Embedding, EmbeddingKind, Error, Force, ForceDependence, ForceJacobian, Forced,
    Grid, Lagrangian, Matrix, NewtonOptions, Problem, Rayleigh, Scheme, Side, Vector, lagrangian,
};

#[lagrangian]
fn oscillator(x: f64, v: f64) -> f64 {
    0.5 * v * v - 0.5 * x * x
}

/// Linear friction, `f = −γ v`.
#[lagrangian]
fn friction(_x: f64, v: f64, gamma: f64) -> f64 {
    0.5 * gamma * v * v
}

const GAMMA: f64 = 0.3;

/// `q̈ + γq̇ + q = 0`, `q(0) = 1`, `q̇(0) = 0`: `q = e^{−γt/2}(cos ωt + γ/(2ω) sin ωt)`.
fn damped_exact(t: f64) -> f64 {
    let omega = (1.0 - GAMMA * GAMMA / 4.0).sqrt();
    (-GAMMA * t / 2.0).exp() * ((omega * t).cos() + GAMMA / (2.0 * omega) * (omega * t).sin())
}

/// Every classical embedding with the schemes it has.
pub(crate) fn classical() -> Vec<(Embedding, Scheme)> {
    let mut runs = Vec::new();
    for side in [Side::Backward, Side::Forward] {
        for scheme in [Scheme::Direct, Scheme::Variational] {
            runs.push((Embedding::finite_difference(side), scheme));
            runs.push((Embedding::asymmetric(side), scheme));
        }
    }
    for scheme in [Scheme::Direct, Scheme::Variational] {
        runs.push((Embedding::midpoint(), scheme));
        runs.push((Embedding::trapezoidal(), scheme));
    }
    for s in 1..=4 {
        runs.push((Embedding::gauss_legendre(s).unwrap(), Scheme::Variational));
    }
    runs
}

fn is_gauss_legendre(embedding: &Embedding) -> bool {
    matches!(embedding.kind(), EmbeddingKind::GaussLegendre { .. })
}

fn max_error(q: &[Vector<1>], grid: &Grid) -> f64 {
    q.iter()
        .zip(grid.nodes())
        .map(|(q, t)| (q[0] - damped_exact(t)).abs())
        .fold(0.0, f64::max)
}

pub(crate) fn tight() -> NewtonOptions {
    NewtonOptions {
        tolerance: 1e-15,
        ..Default::default()
    }
}

/// Observed orders `log₂(e_N / e_2N)` of the damped oscillator on `[0, 6]` against the order
/// each embedding and scheme has without a force, initial value problems.
#[test]
fn damped_oscillator_keeps_every_order() {
    let damped = Forced::new(Oscillator, Rayleigh(Friction { gamma: GAMMA }));
    for (embedding, scheme) in classical() {
        let expected = embedding
            .order(scheme)
            .expect("a classical embedding has an order") as f64;
        // Coarser grids for the high orders, to stay clear of round-off.
        let n = if expected > 4.0 { 12 } else { 200 };
        let error = |n: usize| {
            let grid = Grid::new(0.0, 6.0, n).unwrap();
            let solution = varembed_tests::problem(&damped, grid, embedding)
                .with_newton(tight())
                .solve_ivp(scheme, 1.0, 0.0)
                .unwrap();
            max_error(&solution.q, &grid)
        };
        let (coarse, fine) = (error(n), error(2 * n));
        let order = (coarse / fine).log2();
        assert!(
            (order - expected).abs() <= 0.25 && fine < 0.05,
            "{embedding} {scheme}: errors {coarse:e}, {fine:e}, order {order:.2}, expected {expected}"
        );
    }
}

/// The same as boundary value problems (exact end values on `[0, 6]`), for the embeddings that
/// have them.
#[test]
fn damped_boundary_value_problems_keep_their_order() {
    let damped = Forced::new(Oscillator, Rayleigh(Friction { gamma: GAMMA }));
    for (embedding, scheme) in classical() {
        if is_gauss_legendre(&embedding) {
            continue;
        }
        let expected = embedding.order(scheme).unwrap() as f64;
        let error = |n: usize| {
            let grid = Grid::new(0.0, 6.0, n).unwrap();
            let solution = varembed_tests::problem(&damped, grid, embedding)
                .solve_bvp(scheme, 1.0, damped_exact(6.0))
                .unwrap();
            max_error(&solution.q, &grid)
        };
        let (coarse, fine) = (error(200), error(400));
        let order = (coarse / fine).log2();
        assert!(
            (order - expected).abs() <= 0.25,
            "{embedding} {scheme}: errors {coarse:e}, {fine:e}, order {order:.2}"
        );
    }
}

/// Two bodies joined by a non-linear spring: invariant under a common translation
/// `ξ = (1, 1)`, so its momentum `m₀v₀ + m₁v₁` is conserved without a force.
#[lagrangian]
pub(crate) fn pair(x: [f64; 2], v: [f64; 2]) -> f64 {
    let stretch = x[0] - x[1];
    0.5 * v[0] * v[0] + v[1] * v[1] - 0.5 * stretch * stretch - 0.1 * stretch.powi(4)
}

/// Quadratic drag on the first body with a drive, a position-dependent pull on the second:
/// `f = (−0.3 v₀|v₀| + 0.2 sin t, −0.1 v₁ + 0.05 x₀)`.
pub(crate) struct Drag;

impl Force<2> for Drag {
    fn force(&self, x: &Vector<2>, v: &Vector<2>, t: f64) -> Vector<2> {
        Vector::<2>::new(
            -0.3 * v[0] * v[0].abs() + 0.2 * t.sin(),
            -0.1 * v[1] + 0.05 * x[0],
        )
    }
    fn jacobian(&self, _x: &Vector<2>, v: &Vector<2>, _t: f64) -> ForceJacobian<2> {
        ForceJacobian {
            x: Matrix::<2>::new(0.0, 0.0, 0.05, 0.0),
            v: Matrix::<2>::new(-0.6 * v[0].abs(), 0.0, 0.0, -0.1),
        }
    }
}

/// `p_N·ξ − p_0·ξ = Σ_k impulse_k·ξ` for the variational scheme of every embedding whose
/// impulse the solution gives, to round-off (the momenta are the forced discrete Legendre
/// transforms of `Solution::node_values`; the impulses are summed here, independently).
#[test]
fn forced_noether_holds_to_round_off() {
    let forced = Forced::new(Pair, Drag);
    let xi = Vector::<2>::new(1.0, 1.0);
    for (embedding, scheme) in classical() {
        if scheme != Scheme::Variational || is_gauss_legendre(&embedding) {
            continue;
        }
        let grid = Grid::new(0.0, 8.0, 400).unwrap();
        let solution = varembed_tests::problem(&forced, grid, embedding)
            .with_newton(tight())
            .solve_ivp(scheme, [0.4, -0.2], [1.0, -0.5])
            .unwrap();
        let nodes = solution.node_values(&forced).unwrap();
        let impulses = forced.impulses(&solution).unwrap();
        let transferred: f64 = impulses.iter().map(|i| i.dot(&xi)).sum();
        let change = nodes.p[400].dot(&xi) - nodes.p[0].dot(&xi);
        // The force changes the momentum by O(1): the balance is not trivially zero.
        assert!(transferred.abs() > 0.1, "{embedding}: {transferred}");
        assert!(
            (change - transferred).abs() <= 1e-12,
            "{embedding}: momentum change {change}, impulse {transferred}, gap {:e}",
            change - transferred
        );
    }
}

/// An isotropic anharmonic oscillator in the plane, `L = ½|v|² − ½|x|² − ¼|x|⁴`: invariant
/// under rotations, generator `ξ(q) = (−q₁, q₀)`, so its angular momentum `q₀p₁ − q₁p₀` is
/// conserved without a force.
#[lagrangian]
fn isotropic(x: [f64; 2], v: [f64; 2]) -> f64 {
    let r2 = x[0] * x[0] + x[1] * x[1];
    0.5 * (v[0] * v[0] + v[1] * v[1]) - 0.5 * r2 - 0.25 * r2 * r2
}

/// The forced discrete Noether theorem for a symmetry whose generator depends on `q`:
/// `J_N − J_0 = Σ_k f_d^−·ξ(Q_k) + f_d^+·ξ(Q_{k+1})` to round-off, for the variational scheme of
/// every embedding whose discrete forces the solution gives (the momenta of
/// `Solution::node_values`; the sum formed here from `Forced::discrete_forces`). Gauss-FDE∓
/// put the whole discrete force on one node (`θ = 1`, `θ = 0`), so a split between the nodes
/// other than the scheme's breaks the balance by the order of the scheme's error.
#[test]
fn forced_noether_holds_for_a_rotation() {
    let forced = Forced::new(Isotropic, Drag);
    let xi = |q: &Vector<2>| Vector::<2>::new(-q[1], q[0]);
    for (embedding, scheme) in classical() {
        if scheme != Scheme::Variational || is_gauss_legendre(&embedding) {
            continue;
        }
        let grid = Grid::new(0.0, 6.0, 300).unwrap();
        let solution = varembed_tests::problem(&forced, grid, embedding)
            .with_newton(tight())
            .solve_ivp(scheme, [0.8, 0.1], [0.2, 0.9])
            .unwrap();
        let nodes = solution.node_values(&forced).unwrap();
        let q = &solution.q;
        let forces = forced.discrete_forces(&solution).unwrap();
        let transferred: f64 = forces
            .iter()
            .enumerate()
            .map(|(k, (left, right))| left.dot(&xi(&q[k])) + right.dot(&xi(&q[k + 1])))
            .sum();
        let momentum = |k: usize| nodes.p[k].dot(&xi(&q[k]));
        let change = momentum(300) - momentum(0);
        assert!(transferred.abs() > 0.1, "{embedding}: {transferred}");
        assert!(
            (change - transferred).abs() <= 1e-12,
            "{embedding}: angular momentum change {change}, impulse {transferred}, gap {:e}",
            change - transferred
        );
        // The split matters where the scheme puts the force on one node: swapped, the
        // balance fails by the order of the scheme's error.
        if embedding == Embedding::finite_difference(Side::Backward) {
            let swapped: f64 = forces
                .iter()
                .enumerate()
                .map(|(k, (left, right))| right.dot(&xi(&q[k])) + left.dot(&xi(&q[k + 1])))
                .sum();
            assert!(
                (change - swapped).abs() > 1e-4,
                "{embedding}: the swapped split balances too ({:e})",
                change - swapped
            );
        }
    }
}

/// `max_k |E_k − E_0 − W_k|` falls with the scheme's order (`Forced::work` by the embedding's
/// quadrature; `E` at the nodes by `Solution::node_values`), on the non-linear pair under its
/// drag. (On the damped linear oscillator the midpoint rule's balance is exact: 3e-15.)
#[test]
fn energy_balance_holds_to_the_schemes_order() {
    let forced = Forced::new(Pair, Drag);
    for (embedding, scheme) in classical() {
        if is_gauss_legendre(&embedding) {
            continue;
        }
        let expected = embedding.order(scheme).unwrap() as f64;
        let gap = |n: usize| {
            let grid = Grid::new(0.0, 6.0, n).unwrap();
            let solution = varembed_tests::problem(&forced, grid, embedding)
                .with_newton(tight())
                .solve_ivp(scheme, [0.4, -0.2], [1.0, -0.5])
                .unwrap();
            let energy = solution.node_values(&forced).unwrap().energy.unwrap();
            let work = forced.work(&solution).unwrap();
            // The drag does work of order one.
            assert!(work[n].abs() > 0.1, "{embedding} {scheme}: {}", work[n]);
            (0..=n)
                .map(|k| (energy[k] - energy[0] - work[k]).abs())
                .fold(0.0, f64::max)
        };
        let (coarse, fine) = (gap(200), gap(400));
        let order = (coarse / fine).log2();
        assert!(
            order >= expected - 0.25 && fine > 1e-12,
            "{embedding} {scheme}: balance {coarse:e}, {fine:e}, order {order:.2}"
        );
    }
}

/// A force that claims nothing about its Jacobian: every step runs Newton's method.
struct Opaque<F>(F);

impl<F: Force<1>> Force<1> for Opaque<F> {
    fn force(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> Vector<1> {
        self.0.force(x, v, t)
    }
    fn jacobian(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> ForceJacobian<1> {
        self.0.jacobian(x, v, t)
    }
}

/// Linear friction has a constant Jacobian: the Gauss-FDEσ steps of the oscillator stay in
/// closed form under it. The two kinds whose equation reads the force (variational σ = +,
/// direct σ = −) give the nodes Newton's method gives behind a force that claims nothing; the
/// other two stay in closed form there too (their equation does not read the force), so for
/// them this checks only that they do.
#[test]
fn closed_form_steps_under_a_linear_force_equal_newton() {
    let friction = Rayleigh(Friction { gamma: GAMMA });
    assert_eq!(
        friction.jacobian_dependence(),
        ForceDependence {
            x: Dependence::NONE,
            v: Dependence::NONE
        }
    );
    let closed = Forced::new(Oscillator, friction);
    let newton = Forced::new(Oscillator, Opaque(friction));
    let grid = Grid::new(0.0, 6.0, 300).unwrap();
    for side in [Side::Backward, Side::Forward] {
        for scheme in [Scheme::Direct, Scheme::Variational] {
            let embedding = Embedding::finite_difference(side);
            let solve = |l: &dyn Fn() -> varembed::Result<varembed::Solution<1>>| l().unwrap();
            let a = solve(&|| {
                varembed_tests::problem(&closed, grid, embedding)
                    .with_newton(tight())
                    .solve_ivp(scheme, 1.0, 0.0)
            });
            let b = solve(&|| {
                varembed_tests::problem(&newton, grid, embedding)
                    .with_newton(tight())
                    .solve_ivp(scheme, 1.0, 0.0)
            });
            assert!(
                a.explicit_steps >= 299,
                "{embedding} {scheme}: {}",
                a.explicit_steps
            );
            // The variational Gauss-FDE− and direct Gauss-FDE+ steps' equations (`p@right`,
            // `p@left`) do not read the force: they stay in closed form under any force.
            let explicit = matches!(
                (side, scheme),
                (Side::Backward, Scheme::Variational) | (Side::Forward, Scheme::Direct)
            );
            if explicit {
                assert!(b.explicit_steps >= 299, "{embedding} {scheme}");
            } else {
                assert_eq!(b.explicit_steps, 0, "{embedding} {scheme}");
            }
            let gap = a.max_distance(&b.q).unwrap();
            assert!(gap <= 1e-13, "{embedding} {scheme}: {gap:e}");
        }
    }
}

/// Under a force the boundary value problem of each scheme, given the end values of the
/// initial value problem's nodes, returns those nodes.
#[test]
fn boundary_value_problems_return_the_initial_value_nodes() {
    let forced = Forced::new(Pair, Drag);
    for (embedding, scheme) in classical() {
        if is_gauss_legendre(&embedding) {
            continue;
        }
        let grid = Grid::new(0.0, 3.0, 60).unwrap();
        let problem = varembed_tests::problem(&forced, grid, embedding).with_newton(tight());
        let ivp = problem.solve_ivp(scheme, [0.4, -0.2], [1.0, -0.5]).unwrap();
        let bvp = problem.solve_bvp(scheme, ivp.q[0], ivp.q[60]).unwrap();
        let gap = bvp.max_distance(&ivp.q).unwrap();
        assert!(gap <= 1e-10, "{embedding} {scheme}: {gap:e}");
    }
}

/// A dissipation function with every block of its Hessian varying.
#[lagrangian]
fn coupled_dissipation(x: [f64; 2], v: [f64; 2], t: f64, c: f64) -> f64 {
    0.5 * (1.0 + x[0] * x[0]) * v[0] * v[0] + c * v[0] * v[1] * x[1] * t.cos() + 0.05 * v[1].powi(4)
}

/// `Rayleigh`'s `f = −∂R/∂v` and its Jacobian against central differences of `R` as the macro
/// evaluates it, at 200 generated points.
#[test]
fn rayleigh_force_is_minus_the_velocity_gradient() {
    let r = CoupledDissipation { c: 0.7 };
    let force = Rayleigh(r);
    // A fixed xorshift stream: generated points, reproducible.
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut draw = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 * 4.0 - 2.0
    };
    let eps = 1e-5;
    for _ in 0..200 {
        let x = Vector::<2>::new(draw(), draw());
        let v = Vector::<2>::new(draw(), draw());
        let t = draw();
        let f = force.force(&x, &v, t);
        let jacobian = force.jacobian(&x, &v, t);
        for j in 0..2 {
            let mut e = Vector::<2>::zeros();
            e[j] = eps;
            let dr = (r.value(&x, &(v + e), t) - r.value(&x, &(v - e), t)) / (2.0 * eps);
            assert!(
                (f[j] + dr).abs() <= 1e-7 * (1.0 + dr.abs()),
                "f_{j}: {} vs {}",
                f[j],
                -dr
            );
            let df_dx = (force.force(&(x + e), &v, t) - force.force(&(x - e), &v, t)) / (2.0 * eps);
            let df_dv = (force.force(&x, &(v + e), t) - force.force(&x, &(v - e), t)) / (2.0 * eps);
            for i in 0..2 {
                let (ax, av) = (jacobian.x[(i, j)], jacobian.v[(i, j)]);
                assert!(
                    (ax - df_dx[i]).abs() <= 1e-7 * (1.0 + ax.abs()),
                    "∂f_{i}/∂x_{j}"
                );
                assert!(
                    (av - df_dv[i]).abs() <= 1e-7 * (1.0 + av.abs()),
                    "∂f_{i}/∂v_{j}"
                );
            }
        }
    }
}

/// A force under a driven resonance grows the energy a hundredfold: physics, which the
/// blow-up guard must not report.
#[test]
fn the_blow_up_guard_stands_down_under_a_force() {
    struct Resonant;
    impl Force<1> for Resonant {
        fn force(&self, _x: &Vector<1>, _v: &Vector<1>, t: f64) -> Vector<1> {
            Vector::<1>::new(t.cos())
        }
        fn jacobian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> ForceJacobian<1> {
            ForceJacobian {
                x: Matrix::<1>::zeros(),
                v: Matrix::<1>::zeros(),
            }
        }
    }
    let driven = Forced::new(Oscillator, Resonant);
    let grid = Grid::new(0.0, 200.0, 20_000).unwrap();
    let solution = Problem::recommended(&driven, grid)
        .solve_ivp(Scheme::Variational, 0.1, 0.0)
        .unwrap();
    // q ≈ 0.1 cos t + (t/2) sin t: amplitude 100 at t = 200, from 0.1.
    let amplitude = solution.q.iter().map(|q| q[0].abs()).fold(0.0, f64::max);
    assert!(amplitude > 90.0, "{amplitude}");
}

/// What has no meaning yet under a force is refused with a typed error.
#[test]
fn fractional_problems_and_stage_impulses_are_refused() {
    let damped = Forced::new(Oscillator, Rayleigh(Friction { gamma: GAMMA }));
    let grid = Grid::new(0.0, 1.0, 20).unwrap();
    let fractional = Embedding::grunwald_letnikov(Side::Backward, 0.7).unwrap();
    let refused =
        varembed_tests::problem(&damped, grid, fractional).solve_bvp(Scheme::Variational, 0.0, 1.0);
    assert!(
        matches!(refused, Err(Error::Unsupported { .. })),
        "{refused:?}"
    );
    let gauss = varembed_tests::problem(&damped, grid, Embedding::gauss_legendre(2).unwrap())
        .solve_ivp(Scheme::Variational, 1.0, 0.0)
        .unwrap();
    assert!(matches!(
        damped.impulses(&gauss),
        Err(Error::Unsupported { .. })
    ));
}

/// Quadratic drag `R = |v|³/6`: its `∂f/∂v` depends on `v`.
#[lagrangian]
fn quadratic_drag(_x: f64, v: f64) -> f64 {
    0.5 * v * v * v.abs() / 3.0
}

/// Under a force whose Jacobian is not constant, the two Gauss-FDEσ steps whose equation does
/// not read the force (variational σ = −: Störmer–Verlet; direct σ = +) keep every step in
/// closed form; the two that read it run Newton's method. Both give the nodes of a run where
/// every step runs Newton's method (the force hidden behind a model that claims nothing).
#[test]
fn only_the_steps_that_read_the_force_become_implicit() {
    let dragged = Forced::new(Oscillator, Rayleigh(QuadraticDrag));
    let grid = Grid::new(0.0, 6.0, 200).unwrap();
    for side in [Side::Backward, Side::Forward] {
        for scheme in [Scheme::Direct, Scheme::Variational] {
            let embedding = Embedding::finite_difference(side);
            let run = varembed_tests::problem(&dragged, grid, embedding)
                .with_newton(tight())
                .solve_ivp(scheme, 1.0, 0.0)
                .unwrap();
            let explicit = matches!(
                (side, scheme),
                (Side::Backward, Scheme::Variational) | (Side::Forward, Scheme::Direct)
            );
            if explicit {
                assert_eq!(run.explicit_steps, 199, "{embedding} {scheme}");
                assert_eq!(run.newton_iterations, 0, "{embedding} {scheme}");
            } else {
                assert_eq!(run.explicit_steps, 0, "{embedding} {scheme}");
            }
            let by_newton = varembed_tests::problem(&Claimless(&dragged), grid, embedding)
                .with_newton(tight())
                .solve_ivp(scheme, 1.0, 0.0)
                .unwrap();
            assert_eq!(by_newton.explicit_steps, 0);
            let gap = run.max_distance(&by_newton.q).unwrap();
            assert!(gap <= 1e-13, "{embedding} {scheme}: {gap:e}");
        }
    }
}

/// An explicit step under strong friction is unstable (`γh > 2`): the error says so, and
/// names no step limit, since the oscillator's would be wrong there.
#[test]
fn an_explicit_step_under_strong_friction_is_reported_unstable() {
    let damped = Forced::new(Oscillator, Rayleigh(Friction { gamma: 21.0 }));
    let grid = Grid::new(0.0, 5.0, 50).unwrap();
    let run = varembed_tests::problem(&damped, grid, Embedding::finite_difference(Side::Backward))
        .solve_ivp(Scheme::Variational, 1.0, 0.0);
    assert!(
        matches!(
            run,
            Err(Error::Unstable {
                largest_stable_step: None,
                ..
            })
        ),
        "{run:?}"
    );
    let calmer = Forced::new(Oscillator, Rayleigh(Friction { gamma: 19.0 }));
    varembed_tests::problem(&calmer, grid, Embedding::finite_difference(Side::Backward))
        .solve_ivp(Scheme::Variational, 1.0, 0.0)
        .unwrap();
}

/// A model that claims nothing about its second derivatives (`hessian_dependence` and
/// `force_dependence` left at their defaults): every step runs Newton's method.
struct Claimless<L>(L);

impl<L: Lagrangian<1>> Lagrangian<1> for Claimless<L> {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> f64 {
        self.0.value(x, v, t)
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> (Vector<1>, Vector<1>) {
        self.0.gradient(x, v, t)
    }
    fn hessian(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> varembed::Hessian<1> {
        self.0.hessian(x, v, t)
    }
    fn is_forced(&self) -> bool {
        self.0.is_forced()
    }
    fn force_jacobian(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> Option<ForceJacobian<1>> {
        self.0.force_jacobian(x, v, t)
    }
}

/// A drive `0.4 cos(1.3 t)`: a force of `t` alone.
struct Drive;

impl Force<1> for Drive {
    fn force(&self, _x: &Vector<1>, _v: &Vector<1>, t: f64) -> Vector<1> {
        Vector::<1>::new(0.4 * (1.3 * t).cos())
    }
    fn jacobian(&self, _x: &Vector<1>, _v: &Vector<1>, _t: f64) -> ForceJacobian<1> {
        ForceJacobian {
            x: Matrix::<1>::zeros(),
            v: Matrix::<1>::zeros(),
        }
    }
    fn jacobian_dependence(&self) -> ForceDependence {
        ForceDependence {
            x: Dependence::NONE,
            v: Dependence::NONE,
        }
    }
}

/// Two forces on one model, as a pair `(f1, f2)` and as nested `Forced`: the same nodes under
/// every classical embedding and scheme (a nested model that lost its inner force's Jacobian
/// took wrong closed-form steps), and the pair's work counts both forces.
#[test]
fn two_forces_as_a_pair_or_nested_give_the_same_nodes() {
    let friction = Rayleigh(QuadraticDrag);
    let pair = Forced::new(Oscillator, (friction, Drive));
    let nested = Forced::new(Forced::new(Oscillator, friction), Drive);
    let grid = Grid::new(0.0, 6.0, 200).unwrap();
    for (embedding, scheme) in classical() {
        let solve = |model: &dyn Lagrangian<1>| {
            Problem::new(model, grid, embedding)
                .with_newton(tight())
                .solve_ivp(scheme, 1.0, 0.0)
                .unwrap()
        };
        let (a, b) = (solve(&pair), solve(&nested));
        let gap = a.max_distance(&b.q).unwrap();
        assert!(gap <= 1e-12, "{embedding} {scheme}: {gap:e}");
        assert_eq!(a.explicit_steps, b.explicit_steps, "{embedding} {scheme}");
        assert!(
            b.newton_iterations <= a.newton_iterations + 2,
            "{embedding} {scheme}: {} against {}",
            b.newton_iterations,
            a.newton_iterations
        );
    }
    // The pair's energy balance counts the drive and the drag.
    let run = varembed_tests::problem(&pair, grid, Embedding::midpoint())
        .solve_ivp(Scheme::Variational, 1.0, 0.0)
        .unwrap();
    let energy = run.node_values(&pair).unwrap().energy.unwrap();
    let work = pair.work(&run).unwrap();
    let balance = (0..=200)
        .map(|k| (energy[k] - energy[0] - work[k]).abs())
        .fold(0.0, f64::max);
    assert!(balance <= 1e-3, "{balance:e}");
}

/// A model that forwards `L`'s blocks, their dependence and the force's Jacobian, but says
/// nothing of what the force's blocks depend on.
struct Undeclared<L>(L);

impl<L: Lagrangian<1>> Lagrangian<1> for Undeclared<L> {
    fn value(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> f64 {
        self.0.value(x, v, t)
    }
    fn gradient(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> (Vector<1>, Vector<1>) {
        self.0.gradient(x, v, t)
    }
    fn hessian(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> varembed::Hessian<1> {
        self.0.hessian(x, v, t)
    }
    fn hessian_dependence(&self) -> varembed::HessianDependence {
        self.0.hessian_dependence()
    }
    fn is_forced(&self) -> bool {
        self.0.is_forced()
    }
    fn force_jacobian(&self, x: &Vector<1>, v: &Vector<1>, t: f64) -> Option<ForceJacobian<1>> {
        self.0.force_jacobian(x, v, t)
    }
}

/// A forced model that declares nothing of its force's blocks claims nothing: the steps that
/// read the force run Newton's method, and take the declared model's steps (closed forms
/// planned as if the drag's Jacobian were constant would drop the drag).
#[test]
fn an_undeclared_force_dependence_claims_nothing() {
    let dragged = Forced::new(Oscillator, Rayleigh(QuadraticDrag));
    let grid = Grid::new(0.0, 6.0, 200).unwrap();
    for side in [Side::Backward, Side::Forward] {
        for scheme in [Scheme::Direct, Scheme::Variational] {
            let embedding = Embedding::finite_difference(side);
            let solve = |model: &dyn Lagrangian<1>| {
                Problem::new(model, grid, embedding)
                    .with_newton(tight())
                    .solve_ivp(scheme, 1.0, 0.0)
                    .unwrap()
            };
            let (declared, undeclared) = (solve(&dragged), solve(&Undeclared(&dragged)));
            let gap = declared.max_distance(&undeclared.q).unwrap();
            assert!(gap <= 1e-13, "{embedding} {scheme}: {gap:e}");
            assert_eq!(declared.explicit_steps, undeclared.explicit_steps);
        }
    }
}
