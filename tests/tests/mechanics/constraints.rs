//! Holonomic constraints (`Problem::solve_constrained_ivp`), against oracles independent of the
//! constrained solver:
//!
//! - the spherical pendulum in Cartesian coordinates (`|x| = 1`) against the same pendulum in
//!   angles, integrated by RK4 on its equations of motion written by hand: every classical
//!   embedding and scheme keeps its order (`Embedding::order`);
//! - the constraint at every node to `1e-12`;
//! - the vertical angular momentum, the Noether quantity of a symmetry the constraint respects,
//!   conserved by the variational schemes to round-off;
//! - the macro-generated constraint Jacobian and second derivatives against central differences;
//! - the typed errors: inconsistent initial data (naming the constraint) and their projection,
//!   a rank-deficient Jacobian.

use varembed::{
    Constraint, Embedding, EmbeddingKind, Error, Forced, Grid, Holonomic, Location, Rayleigh,
    Scheme, Side, Vector, lagrangian, project_initial_data,
};

/// A unit mass under unit gravity along `−z`.
#[lagrangian]
pub(super) fn falling(x: [f64; 3], v: [f64; 3]) -> f64 {
    0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) - x[2]
}

/// The unit sphere.
#[lagrangian]
pub(super) fn sphere(x: [f64; 3], _v: [f64; 3]) -> f64 {
    0.5 * (x[0] * x[0] + x[1] * x[1] + x[2] * x[2] - 1.0)
}

const THETA0: f64 = 1.0;
const PHI_RATE0: f64 = 0.8;
pub(super) const T_END: f64 = 5.0;

/// `x = (sin θ cos φ, sin θ sin φ, −cos θ)`.
fn cartesian(theta: f64, phi: f64) -> Vector<3> {
    Vector::<3>::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        -theta.cos(),
    )
}

/// The initial data: `θ = 1`, `φ = 0`, `θ̇ = 0`, `φ̇ = 0.8`.
pub(super) fn initial() -> (Vector<3>, Vector<3>) {
    (
        cartesian(THETA0, 0.0),
        Vector::<3>::new(0.0, THETA0.sin() * PHI_RATE0, 0.0),
    )
}

/// The pendulum in angles, `L = ½(θ̇² + sin²θ φ̇²) + cos θ`: `θ̈ = sin θ cos θ φ̇² − sin θ`,
/// `φ̇ = p_φ / sin²θ` with `p_φ` conserved; RK4 with 20 000 steps to `T_END`.
pub(super) fn angles_at_end() -> Vector<3> {
    let p_phi = THETA0.sin().powi(2) * PHI_RATE0;
    let rhs = |s: [f64; 3]| {
        let [theta, _, rate] = s;
        let phi_rate = p_phi / theta.sin().powi(2);
        [
            rate,
            phi_rate,
            theta.sin() * theta.cos() * phi_rate * phi_rate - theta.sin(),
        ]
    };
    let steps = 20_000;
    let h = T_END / steps as f64;
    let mut s = [THETA0, 0.0, 0.0];
    let add =
        |s: [f64; 3], k: [f64; 3], c: f64| [s[0] + c * k[0], s[1] + c * k[1], s[2] + c * k[2]];
    for _ in 0..steps {
        let k1 = rhs(s);
        let k2 = rhs(add(s, k1, h / 2.0));
        let k3 = rhs(add(s, k2, h / 2.0));
        let k4 = rhs(add(s, k3, h));
        for i in 0..3 {
            s[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }
    cartesian(s[0], s[1])
}

/// Every classical embedding but Gauss–Legendre, with both schemes.
pub(super) fn runs() -> Vec<(Embedding, Scheme)> {
    let mut runs = Vec::new();
    for scheme in [Scheme::Direct, Scheme::Variational] {
        for side in [Side::Backward, Side::Forward] {
            runs.push((Embedding::finite_difference(side), scheme));
            runs.push((Embedding::asymmetric(side), scheme));
        }
        runs.push((Embedding::midpoint(), scheme));
        runs.push((Embedding::trapezoidal(), scheme));
    }
    runs
}

fn solve(embedding: Embedding, scheme: Scheme, n: usize) -> varembed::ConstrainedSolution<3, 1> {
    let (q0, v0) = initial();
    varembed_tests::problem(&Falling, Grid::new(0.0, T_END, n).unwrap(), embedding)
        .solve_constrained_ivp(scheme, &Holonomic(Sphere), q0, v0)
        .unwrap()
}

/// Observed order `log₂(e_N / e_2N)` at `t = 5` against the angle form, N = 400, 800; and the
/// constraint at every node of every run.
#[test]
fn spherical_pendulum_keeps_every_order_on_the_sphere() {
    let reference = angles_at_end();
    for (embedding, scheme) in runs() {
        let expected = embedding.order(scheme).unwrap() as f64;
        let error = |n: usize| {
            let run = solve(embedding, scheme, n);
            let on_sphere = run
                .solution
                .q
                .iter()
                .map(|q| (0.5 * (q.norm_squared() - 1.0)).abs());
            let residual = on_sphere.fold(0.0, f64::max);
            assert!(
                residual <= 1e-12,
                "{embedding} {scheme}: |g| = {residual:e}"
            );
            assert_eq!(run.multipliers.len(), n - 1);
            (run.solution.last() - reference).amax()
        };
        let (coarse, fine) = (error(400), error(800));
        let order = (coarse / fine).log2();
        assert!(
            (order - expected).abs() <= 0.3 && fine < 0.05,
            "{embedding} {scheme}: errors {coarse:e}, {fine:e}, order {order:.2}"
        );
    }
}

/// `L_z = x p_y − y p_x` at every node (the momenta of `Solution::node_values`) stays at its
/// initial value to round-off under the variational schemes: the rotation about `z` leaves
/// `L` and the sphere invariant, and the constraint force `λ x` has no moment about `z`.
#[test]
fn variational_schemes_conserve_the_vertical_angular_momentum() {
    let (q0, v0) = initial();
    let initial = q0[0] * v0[1] - q0[1] * v0[0];
    for (embedding, scheme) in runs() {
        if scheme != Scheme::Variational {
            continue;
        }
        let run = solve(embedding, scheme, 500);
        let nodes = run.solution.node_values(&Falling).unwrap();
        let drift = nodes
            .iter()
            .map(|node| (node.q[0] * node.p[1] - node.q[1] * node.p[0] - initial).abs())
            .fold(0.0, f64::max);
        assert!(drift <= 1e-13, "{embedding}: L_z drifts by {drift:e}");
    }
}

/// Under a force too: the Cartesian pendulum with friction stays on the sphere, and loses
/// energy.
#[test]
fn forces_and_constraints_together() {
    #[lagrangian]
    fn friction(_x: [f64; 3], v: [f64; 3], gamma: f64) -> f64 {
        0.5 * gamma * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    }
    let damped = Forced::new(Falling, Rayleigh(Friction { gamma: 0.3 }));
    let (q0, v0) = initial();
    let grid = Grid::new(0.0, 20.0, 2000).unwrap();
    let run = varembed_tests::problem(&damped, grid, Embedding::midpoint())
        .solve_constrained_ivp(Scheme::Variational, &Holonomic(Sphere), q0, v0)
        .unwrap();
    let residual = run
        .solution
        .q
        .iter()
        .map(|q| (0.5 * (q.norm_squared() - 1.0)).abs())
        .fold(0.0, f64::max);
    assert!(residual <= 1e-12, "{residual:e}");
    let energy = run.solution.node_values(&damped).unwrap().energy.unwrap();
    assert!(
        energy[2000] < energy[0] - 0.2,
        "{} → {}",
        energy[0],
        energy[2000]
    );
}

/// The generated `G` and `Σ λ ∇²g` of a constraint with every second derivative non-zero,
/// against central differences of the generated `g`, at 100 generated points.
#[test]
fn generated_constraint_derivatives_match_finite_differences() {
    #[lagrangian]
    fn surface(x: [f64; 3], _v: [f64; 3], a: f64) -> f64 {
        x[0] * x[1].sin() + a * x[2] * x[2] * x[0] - (x[1] * x[2]).exp()
    }
    let g = Holonomic(Surface { a: 0.7 });
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut draw = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let eps = 1e-5;
    for _ in 0..100 {
        let x = Vector::<3>::new(draw(), draw(), draw());
        let lambda = nalgebra::SVector::<f64, 1>::new(draw());
        let (jacobian, hessian) = (g.jacobian(&x), g.weighted_hessian(&x, &lambda));
        for j in 0..3 {
            let mut e = Vector::<3>::zeros();
            e[j] = eps;
            let dg = (g.value(&(x + e))[0] - g.value(&(x - e))[0]) / (2.0 * eps);
            assert!(
                (jacobian[(0, j)] - dg).abs() <= 1e-8 * (1.0 + dg.abs()),
                "G_{j}"
            );
            let dgrad = (g.jacobian(&(x + e)) - g.jacobian(&(x - e))) / (2.0 * eps) * lambda[0];
            for i in 0..3 {
                let exact = hessian[(i, j)];
                assert!(
                    (exact - dgrad[(0, i)]).abs() <= 1e-7 * (1.0 + exact.abs()),
                    "H_{i}{j}"
                );
            }
        }
    }
}

/// Data off the sphere, or a velocity across it, is an error naming the constraint; projected
/// by `project_initial_data`, the same data solve.
#[test]
fn inconsistent_initial_data_are_named_and_projected() {
    let problem = varembed_tests::problem(
        &Falling,
        Grid::new(0.0, 1.0, 50).unwrap(),
        Embedding::midpoint(),
    );
    let (q0, v0) = initial();
    let off = q0 * 1.01;
    let across = v0 + q0 * 0.1;
    let position = problem.solve_constrained_ivp(Scheme::Variational, &Holonomic(Sphere), off, v0);
    assert!(
        matches!(
            position,
            Err(Error::InconsistentInitialData {
                what: "position",
                constraint: 0,
                ..
            })
        ),
        "{position:?}"
    );
    let velocity =
        problem.solve_constrained_ivp(Scheme::Variational, &Holonomic(Sphere), q0, across);
    assert!(
        matches!(
            velocity,
            Err(Error::InconsistentInitialData {
                what: "velocity",
                constraint: 0,
                ..
            })
        ),
        "{velocity:?}"
    );
    let message = velocity.unwrap_err().to_string();
    assert!(message.contains("project_initial_data"), "{message}");
    let (q, v) = project_initial_data(&Holonomic(Sphere), off, across).unwrap();
    assert!((q.norm() - 1.0).abs() <= 1e-15 && q.dot(&v).abs() <= 1e-15);
    // The nearest point of the sphere, and the tangential part of the velocity.
    assert!((q - q0).amax() <= 1e-15, "{q:?}");
    assert!((v - v0).amax() <= 1e-15, "{v:?}");
    problem
        .solve_constrained_ivp(Scheme::Variational, &Holonomic(Sphere), q, v)
        .unwrap();
}

/// A constraint stated twice has a rank-deficient Jacobian: a typed error at the initial data,
/// not a singular Newton system.
#[test]
fn rank_deficiency_is_a_typed_error() {
    let problem = varembed_tests::problem(
        &Falling,
        Grid::new(0.0, 1.0, 50).unwrap(),
        Embedding::midpoint(),
    );
    let (q0, v0) = initial();
    let twice = (Holonomic(Sphere), Holonomic(Sphere));
    let result = problem.solve_constrained_ivp(Scheme::Variational, &twice, q0, v0);
    assert!(
        matches!(
            result,
            Err(Error::RankDeficientConstraints {
                at: Location::Step(0),
                ..
            })
        ),
        "{result:?}"
    );
}

/// A planar four-bar linkage: a crank of length 1 from the ground pivot `(0, 0)`, a coupler of
/// length 2.2, a rocker of length 1.6 to the ground pivot `(2, 0)`; unknowns the three link
/// angles, uniform rods under gravity. The loop closes by two constraints (the coupler's far
/// end on the rocker's), which no single chart of one angle covers through the whole motion.
#[lagrangian]
pub(super) fn linkage(x: [f64; 3], v: [f64; 3]) -> f64 {
    // Rod i of length l_i and unit mass per length from its pivot: I = l³/3 about the pivot;
    // the coupler moves with its pivot (the crank's tip).
    let (l1, l2, l3) = (1.0, 2.2, 1.6);
    let crank = l1 * l1 * l1 / 3.0 * v[0] * v[0] / 2.0;
    let tip_x = -l1 * x[0].sin() * v[0];
    let tip_y = l1 * x[0].cos() * v[0];
    let mid_x = tip_x - 0.5 * l2 * x[1].sin() * v[1];
    let mid_y = tip_y + 0.5 * l2 * x[1].cos() * v[1];
    let coupler = 0.5 * l2 * (mid_x * mid_x + mid_y * mid_y) + l2 * l2 * l2 / 24.0 * v[1] * v[1];
    let rocker = l3 * l3 * l3 / 3.0 * v[2] * v[2] / 2.0;
    let height = l1 * 0.5 * l1 * x[0].sin()
        + l2 * (l1 * x[0].sin() + 0.5 * l2 * x[1].sin())
        + l3 * 0.5 * l3 * x[2].sin();
    crank + coupler + rocker - 9.81 * height
}

#[lagrangian]
pub(super) fn loop_x(x: [f64; 3], _v: [f64; 3]) -> f64 {
    x[0].cos() + 2.2 * x[1].cos() - 1.6 * x[2].cos() - 2.0
}

#[lagrangian]
pub(super) fn loop_y(x: [f64; 3], _v: [f64; 3]) -> f64 {
    x[0].sin() + 2.2 * x[1].sin() - 1.6 * x[2].sin()
}

/// 10⁴ steps of the four-bar under midpoint and Gauss-FDE− variational: the loop stays closed
/// to 1e-12, and the energy of the symplectic runs stays within a bound that shrinks with `h²`
/// (midpoint) rather than drifting.
#[test]
fn a_four_bar_linkage_stays_closed() {
    let closure = (Holonomic(LoopX), Holonomic(LoopY));
    // The crank at 90°, the rest placed on the loop by the projection.
    let guess = Vector::<3>::new(std::f64::consts::FRAC_PI_2, -0.3, 1.2);
    let (q0, v0) = project_initial_data(&closure, guess, Vector::<3>::new(2.0, 0.0, 0.0)).unwrap();
    assert!(closure.value(&q0).amax() <= 1e-14);
    for embedding in [
        Embedding::midpoint(),
        Embedding::finite_difference(Side::Backward),
    ] {
        let grid = Grid::new(0.0, 20.0, 10_000).unwrap();
        let run = varembed_tests::problem(&Linkage, grid, embedding)
            .solve_constrained_ivp(Scheme::Variational, &closure, q0, v0)
            .unwrap();
        let open = run
            .solution
            .q
            .iter()
            .map(|q| closure.value(q).amax())
            .fold(0.0, f64::max);
        assert!(open <= 1e-12, "{embedding}: loop open by {open:e}");
        let energy = run.solution.node_values(&Linkage).unwrap().energy.unwrap();
        let drift = energy
            .iter()
            .map(|e| (e - energy[0]).abs())
            .fold(0.0, f64::max);
        // Midpoint: second order, so the energy error is small; Gauss-FDE−: first order.
        let bound = if embedding == Embedding::midpoint() {
            1e-2
        } else {
            1.0
        };
        assert!(
            drift <= bound * energy[0].abs().max(1.0),
            "{embedding}: energy drift {drift:e}"
        );
    }
}

/// `ConstrainedSolution::node_values`: the velocities satisfy the hidden constraint
/// `x·v = 0` at every node to round-off, the vertical angular momentum of the projected momenta
/// is still conserved to round-off, and the midpoint scheme's energy error at the nodes falls
/// as `h²`.
#[test]
fn projected_node_values_satisfy_the_hidden_constraint() {
    let (q0, v0) = initial();
    let l_z0 = q0[0] * v0[1] - q0[1] * v0[0];
    let energy0 = 0.5 * v0.norm_squared() + q0[2];
    for embedding in [
        Embedding::midpoint(),
        Embedding::finite_difference(Side::Backward),
    ] {
        let energy_error = |n: usize| {
            let run = solve(embedding, Scheme::Variational, n);
            let nodes = run.node_values(&Falling, &Holonomic(Sphere)).unwrap();
            for k in 0..=n {
                let (q, v, p) = (nodes.q[k], nodes.v[k], nodes.p[k]);
                assert!(
                    q.dot(&v).abs() <= 1e-13,
                    "{embedding} node {k}: x·v = {:e}",
                    q.dot(&v)
                );
                let l_z = q[0] * p[1] - q[1] * p[0];
                assert!(
                    (l_z - l_z0).abs() <= 1e-13,
                    "{embedding} node {k}: L_z {l_z}"
                );
            }
            let energy = nodes.energy.unwrap();
            energy
                .iter()
                .map(|e| (e - energy0).abs())
                .fold(0.0, f64::max)
        };
        let (coarse, fine) = (energy_error(500), energy_error(1000));
        let order = (coarse / fine).log2();
        let expected = embedding.order(Scheme::Variational).unwrap() as f64;
        assert!(
            order >= expected - 0.3,
            "{embedding}: energy errors {coarse:e}, {fine:e}"
        );
    }
}

/// A constraint written with the velocity or the time is not holonomic: `Holonomic` would
/// evaluate it at `v = 0`, `t = 0`, a silent wrong answer; the solver refuses it, naming what
/// it reads.
#[test]
fn a_constraint_that_reads_v_or_t_is_refused() {
    #[lagrangian]
    fn rolling(x: [f64; 3], v: [f64; 3]) -> f64 {
        x[0] * v[1] - x[1] * v[0]
    }
    #[lagrangian]
    fn shrinking(x: [f64; 3], _v: [f64; 3], t: f64) -> f64 {
        0.5 * (x[0] * x[0] + x[1] * x[1] + x[2] * x[2] - (1.0 + t).powi(2))
    }
    let problem = varembed_tests::problem(
        &Falling,
        Grid::new(0.0, 1.0, 20).unwrap(),
        Embedding::midpoint(),
    );
    let (q0, v0) = initial();
    for (constraint, reads) in [
        (
            &Holonomic(Rolling) as &dyn Constraint<3, 1>,
            "the velocity v",
        ),
        (&Holonomic(Shrinking), "the time t"),
    ] {
        let refused = problem.solve_constrained_ivp(Scheme::Variational, constraint, q0, v0);
        let Err(Error::InvalidModel { reason }) = refused else {
            panic!("{refused:?}");
        };
        assert!(reason.contains(reads), "{reason}");
    }
}

/// The multipliers: on the spherical pendulum `ẍ = −e_z + λx` with `|x| = 1` gives
/// `λ = z − |v|² = 3z − 2E` (energy `E = ½|v|² + z`). Each row's `λ` against `3z − 2E₀` at its
/// row node (`n − 1`, `n` for the direct Gauss-FDE− step, `n − 2` for the direct Gauss-FDE+
/// step), falling with the scheme's order: a multiplier of the wrong sign, scale or node
/// fails.
#[test]
fn the_multipliers_are_the_constraint_force() {
    let (q0, v0) = initial();
    let energy = 0.5 * v0.norm_squared() + q0[2];
    for (embedding, scheme) in runs() {
        let row_node = |n: usize| match (embedding.kind(), embedding.side(), scheme) {
            (EmbeddingKind::FiniteDifference, Side::Backward, Scheme::Direct) => n,
            (EmbeddingKind::FiniteDifference, Side::Forward, Scheme::Direct) => n - 2,
            _ => n - 1,
        };
        let gap = |steps: usize| {
            let run = solve(embedding, scheme, steps);
            (2..=steps)
                .map(|n| {
                    let z = run.solution.q[row_node(n)][2];
                    (run.multipliers[n - 2][0] - (3.0 * z - 2.0 * energy)).abs()
                })
                .fold(0.0, f64::max)
        };
        let (coarse, fine) = (gap(400), gap(800));
        let order = (coarse / fine).log2();
        let expected = embedding.order(scheme).unwrap() as f64;
        assert!(
            order >= expected - 0.3 && fine < 0.1,
            "{embedding} {scheme}: λ off by {coarse:e}, {fine:e} (order {order:.2})"
        );
    }
}
