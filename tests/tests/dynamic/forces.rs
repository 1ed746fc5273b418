//! Generalised forces on the run-time path: a `#[lagrangian]` chain with loops under Rayleigh
//! dissipation written with loops (both are models of both kinds, so `Forced` is a
//! `Lagrangian<N>` and a `DynLagrangian`) gives the same nodes on `DynProblem` as on the
//! const-generic `Problem`, for every three-point embedding and both schemes; the dissipation
//! couples neighbouring velocities, so the force's Jacobian joins the band of the step
//! Jacobian, with as many Newton iterations; and so for the Gauss–Legendre integrators. The same dissipation written as a general
//! `#[force]` with loops (its `Force<N>` and its generated `DynForce`) gives the Rayleigh
//! route's nodes on both paths. `c L` under `c f` takes the nodes of `L` under `f` (the
//! forced equations are the same). The discrete forces and the work of a run-time solution
//! are the const-generic run's, and so are its node values (the forced discrete Legendre
//! transforms). A boundary value problem under a force is refused.

use varembed::{
    BvpSolver, DynForce, DynProblem, Embedding, Error, Forced, Grid, LinearSolve, Rayleigh, Scheme,
    Side, force, lagrangian,
};
use varembed_tests::models::scaled::Scaled;
use varembed_tests::rng::Rng;

const N: usize = 12;

/// An α-FPUT chain with fixed ends.
#[lagrangian]
fn chain(x: [f64; N], v: [f64; N]) -> f64 {
    let kinetic: f64 = (0..N).map(|i| 0.5 * v[i] * v[i]).sum();
    let springs: f64 = (0..N - 1)
        .map(|i| {
            let s = x[i + 1] - x[i];
            0.5 * s * s + 0.25 * s * s * s
        })
        .sum();
    kinetic - springs - 0.5 * x[0] * x[0] - 0.5 * x[N - 1] * x[N - 1]
}

/// Dissipation between neighbours, quadratic and cubic in the relative velocity, and a
/// position-dependent drag on each site: every block of the force's Jacobian varies.
#[lagrangian]
fn dashpots(x: [f64; N], v: [f64; N], gamma: f64) -> f64 {
    let between: f64 = (0..N - 1)
        .map(|i| {
            let w = v[i + 1] - v[i];
            0.5 * gamma * w * w + 0.1 * w * w * w * w
        })
        .sum();
    let sites: f64 = (0..N)
        .map(|i| 0.05 * (1.0 + x[i] * x[i]) * v[i] * v[i])
        .sum();
    between + sites
}

/// `−∂R/∂v` of [`dashpots`], written out as a general force: each link adds to both its
/// ends, each site its own drag.
#[force]
fn dashpot_force(x: [f64; N], v: [f64; N], gamma: f64) -> [f64; N] {
    let mut f = [0.0; N];
    for i in 0..N - 1 {
        let w = v[i + 1] - v[i];
        let pull = gamma * w + 0.4 * w * w * w;
        f[i] += pull;
        f[i + 1] -= pull;
    }
    for i in 0..N {
        f[i] -= 0.1 * (1.0 + x[i] * x[i]) * v[i];
    }
    f
}

fn initial() -> ([f64; N], [f64; N]) {
    let mut q = [0.0; N];
    let mut v = [0.0; N];
    for i in 0..N {
        q[i] = 0.4 * (std::f64::consts::PI * (i + 1) as f64 / (N + 1) as f64).sin();
        v[i] = 0.2 * ((i as f64) * 0.7).cos();
    }
    (q, v)
}

fn embeddings() -> Vec<Embedding> {
    vec![
        Embedding::finite_difference(Side::Backward),
        Embedding::finite_difference(Side::Forward),
        Embedding::asymmetric(Side::Backward),
        Embedding::midpoint(),
        Embedding::trapezoidal(),
    ]
}

#[test]
fn forced_runs_of_run_time_dimension_are_the_const_generic_runs() {
    let forced = Forced::new(Chain, Rayleigh(Dashpots { gamma: 0.3 }));
    let (q0, v0) = initial();
    let grid = Grid::new(0.0, 4.0, 200).unwrap();
    for embedding in embeddings() {
        for scheme in [Scheme::Direct, Scheme::Variational] {
            let reference = varembed_tests::problem(&forced, grid, embedding)
                .solve_ivp(scheme, q0, v0)
                .unwrap();
            let run = DynProblem::new(&forced, grid, embedding)
                .solve_ivp(scheme, &q0, &v0)
                .unwrap();
            let mut gap = 0.0f64;
            for (k, node) in reference.q.iter().enumerate() {
                for i in 0..N {
                    gap = gap.max((run.node(k)[i] - node[i]).abs());
                }
            }
            assert!(gap <= 1e-12, "{embedding} {scheme}: {gap:e}");
            // Newton's iterations as many as on the const-generic path, whose dense Jacobian
            // has the force's blocks: a band Jacobian without them would converge linearly.
            let (dyn_iterations, const_iterations) =
                (run.run.newton_iterations, reference.newton_iterations);
            assert!(
                dyn_iterations.abs_diff(const_iterations) <= const_iterations / 50,
                "{embedding} {scheme}: {dyn_iterations} against {const_iterations} iterations"
            );
            assert_eq!(
                run.run.explicit_steps, reference.explicit_steps,
                "{embedding} {scheme}"
            );
            // The chain and the dashpots both declare a half-band of 1 (`Forced` the wider of
            // the two): the step Jacobian is factorised on it in the model's own order.
            assert_eq!(
                (run.run.band, run.run.reordered),
                (1, false),
                "{embedding} {scheme}"
            );
            // The force does work of order one: a run that ignored it would be far off.
            let unforced = DynProblem::new(&Chain, grid, embedding)
                .solve_ivp(scheme, &q0, &v0)
                .unwrap();
            let moved = (0..N)
                .map(|i| (unforced.node(200)[i] - run.node(200)[i]).abs())
                .fold(0.0, f64::max);
            assert!(moved > 1e-2, "{embedding} {scheme}: {moved:e}");
        }
    }
}

/// The Gauss–Legendre integrators under the same forces: on the run-time path (the force's
/// Jacobian joins the stage Jacobian's `∂Ṗ/∂x` and `∂Ṗ/∂v` blocks in the interleaved band) the
/// nodes, momenta and Newton iterations of the const-generic run, for every stage count, with
/// the dissipation as Rayleigh's and as a general `#[force]`.
#[test]
fn forced_gauss_legendre_runs_are_the_const_generic_runs() {
    let rayleigh = Forced::new(Chain, Rayleigh(Dashpots { gamma: 0.3 }));
    let general = Forced::new(Chain, DashpotForce { gamma: 0.3 });
    let (q0, v0) = initial();
    let grid = Grid::new(0.0, 4.0, 80).unwrap();
    let flat = |nodes: &[varembed::Vector<N>]| -> Vec<f64> {
        nodes.iter().flat_map(|q| q.iter().copied()).collect()
    };
    for s in 1..=4 {
        let embedding = Embedding::gauss_legendre(s).unwrap();
        let reference = varembed_tests::problem(&rayleigh, grid, embedding)
            .solve_ivp(Scheme::Variational, q0, v0)
            .unwrap();
        let runs = [
            DynProblem::new(&rayleigh, grid, embedding).solve_ivp(Scheme::Variational, &q0, &v0),
            DynProblem::new(&general, grid, embedding).solve_ivp(Scheme::Variational, &q0, &v0),
        ];
        for run in runs {
            let run = run.unwrap();
            for (got, expected) in [
                (&run.q, flat(&reference.q)),
                (&run.momenta, flat(&reference.momenta)),
            ] {
                let gap = got
                    .iter()
                    .zip(&expected)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                assert!(gap <= 1e-12, "s = {s}: {gap:e}");
            }
            assert_eq!(
                run.run.newton_iterations, reference.newton_iterations,
                "s = {s}"
            );
            assert_eq!(run.run.band, 2 * s - 1, "s = {s}");
        }
        // The force does work: the unforced run ends elsewhere.
        let unforced = DynProblem::new(&Chain, grid, embedding)
            .solve_ivp(Scheme::Variational, &q0, &v0)
            .unwrap();
        let last = &reference.q[80];
        let moved = (0..N)
            .map(|i| (unforced.node(80)[i] - last[i]).abs())
            .fold(0.0, f64::max);
        assert!(moved > 1e-2, "s = {s}: {moved:e}");
    }
}

#[test]
fn a_general_force_with_loops_gives_the_rayleigh_nodes_on_both_paths() {
    let rayleigh = Forced::new(Chain, Rayleigh(Dashpots { gamma: 0.3 }));
    let general = Forced::new(Chain, DashpotForce { gamma: 0.3 });
    // The generated `DynForce` declares the links' band: the step stays on the chain's band.
    assert_eq!(DynForce::bandwidth(&DashpotForce { gamma: 0.3 }), Some(1));
    let (q0, v0) = initial();
    let grid = Grid::new(0.0, 4.0, 200).unwrap();
    for embedding in embeddings() {
        for scheme in [Scheme::Direct, Scheme::Variational] {
            let reference = varembed_tests::problem(&rayleigh, grid, embedding)
                .solve_ivp(scheme, q0, v0)
                .unwrap();
            let on_const = varembed_tests::problem(&general, grid, embedding)
                .solve_ivp(scheme, q0, v0)
                .unwrap();
            let on_run_time = DynProblem::new(&general, grid, embedding)
                .solve_ivp(scheme, &q0, &v0)
                .unwrap();
            let mut gap = 0.0f64;
            for (k, node) in reference.q.iter().enumerate() {
                for i in 0..N {
                    gap = gap
                        .max((on_const.q[k][i] - node[i]).abs())
                        .max((on_run_time.node(k)[i] - node[i]).abs());
                }
            }
            assert!(gap <= 1e-12, "{embedding} {scheme}: {gap:e}");
            assert_eq!(
                on_const.newton_iterations, reference.newton_iterations,
                "{embedding} {scheme}"
            );
            assert_eq!(
                (on_run_time.run.band, on_run_time.run.reordered),
                (1, false),
                "{embedding} {scheme}"
            );
        }
    }
}

/// 40 random cases: the chain `c L` under the dashpots `c R` (so the force `c f`) on the
/// run-time path, `c = 10^u` with `u` uniform in `[−12, 12]` or (every fourth case) `c = 2^k`,
/// `k` in `−39..39`, under a random three-point embedding and scheme: the nodes of `L` under
/// `f` to 1e-9 relative, and for a power of two bit for bit with the same Newton iterations.
#[test]
fn c_l_under_c_f_takes_the_nodes_of_l_under_f() {
    let mut rng = Rng(27);
    let (q0, v0) = initial();
    let grid = Grid::new(0.0, 2.0, 80).unwrap();
    let plain = Forced::new(Chain, Rayleigh(Dashpots { gamma: 0.3 }));
    let mut worst = 0.0f64;
    for case in 0..40 {
        let exact = case % 4 == 0;
        let c = if exact {
            2f64.powi(rng.below(79) as i32 - 39)
        } else {
            10f64.powf(rng.uniform(-12.0, 12.0))
        };
        let embedding = embeddings()[rng.below(5)];
        let scheme = [Scheme::Direct, Scheme::Variational][rng.below(2)];
        let scaled = Forced::new(
            Scaled::new(c, Chain),
            Rayleigh(Scaled::new(c, Dashpots { gamma: 0.3 })),
        );
        let a = DynProblem::new(&plain, grid, embedding)
            .solve_ivp(scheme, &q0, &v0)
            .unwrap();
        let b = DynProblem::new(&scaled, grid, embedding)
            .solve_ivp(scheme, &q0, &v0)
            .unwrap();
        let largest = a.q.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let gap =
            a.q.iter()
                .zip(&b.q)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
                / largest;
        assert!(gap <= 1e-9, "c = {c:e}, {embedding} {scheme}: {gap:e}");
        if exact {
            let iterations = (a.run.newton_iterations, b.run.newton_iterations);
            assert!(
                a.q == b.q && iterations.0 == iterations.1,
                "c = {c:e} = 2^k, {embedding} {scheme}: {gap:e} apart, iterations {iterations:?}"
            );
        }
        worst = worst.max(gap);
    }
    println!("forced c L: worst relative gap {worst:e}");
}

/// `Forced::dyn_work` of the run-time run is `Forced::work` of the const-generic one (the same
/// nodes, the same quadrature), under every three-point embedding; it moves by order one
/// (the force does work); a solution that skips nodes is refused.
#[test]
fn the_work_of_a_run_time_solution_is_the_const_generic_work() {
    let model = Forced::new(Chain, DashpotForce { gamma: 0.3 });
    let (q0, v0) = initial();
    let grid = Grid::new(0.0, 4.0, 200).unwrap();
    for embedding in embeddings() {
        let reference = varembed_tests::problem(&model, grid, embedding)
            .solve_ivp(Scheme::Variational, q0, v0)
            .unwrap();
        let run = DynProblem::new(&model, grid, embedding)
            .solve_ivp(Scheme::Variational, &q0, &v0)
            .unwrap();
        let (work, dyn_work) = (
            model.work(&reference).unwrap(),
            model.dyn_work(&run).unwrap(),
        );
        assert_eq!(dyn_work.len(), 201);
        let gap = work
            .iter()
            .zip(&dyn_work)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(gap <= 1e-12, "{embedding}: {gap:e}");
        assert!(
            work[200] < -1e-3,
            "{embedding}: the dashpots did {:e}",
            work[200]
        );
        let pairs = model.discrete_forces(&reference).unwrap();
        let dyn_pairs = model.dyn_discrete_forces(&run).unwrap();
        for (k, (a, b)) in pairs.iter().zip(&dyn_pairs).enumerate() {
            for i in 0..N {
                let gap = (a.0[i] - b.0[i]).abs().max((a.1[i] - b.1[i]).abs());
                assert!(
                    gap <= 1e-13,
                    "{embedding}: interval {k}, component {i}: {gap:e}"
                );
            }
        }
    }
    let thinned = DynProblem::new(&model, grid, Embedding::midpoint())
        .solve_ivp_every(Scheme::Variational, &q0, &v0, 10)
        .unwrap();
    let refused = model.dyn_work(&thinned);
    assert!(
        matches!(
            refused,
            Err(Error::WrongLength {
                expected: 201,
                found: 21,
                ..
            })
        ),
        "{refused:?}"
    );
}

/// The node velocities and momenta of a forced run-time solution are the const-generic run's
/// under every three-point embedding and both schemes: the variational schemes' momenta are
/// the forced discrete Legendre transforms on both paths (the force enters them through the
/// model's `force`), which differ from the unforced ones by the discrete force.
#[test]
fn the_node_values_of_a_forced_run_are_the_const_generic_ones() {
    let model = Forced::new(Chain, DashpotForce { gamma: 0.3 });
    let (q0, v0) = initial();
    let grid = Grid::new(0.0, 2.0, 100).unwrap();
    for embedding in embeddings() {
        for scheme in [Scheme::Direct, Scheme::Variational] {
            let solution = varembed_tests::problem(&model, grid, embedding)
                .solve_ivp(scheme, q0, v0)
                .unwrap();
            let reference = solution.node_values(&model).unwrap();
            let run = DynProblem::new(&model, grid, embedding)
                .solve_ivp(scheme, &q0, &v0)
                .unwrap();
            let nodes = run.node_values(&model).unwrap();
            let mut gap = 0.0f64;
            for k in 0..=100 {
                for i in 0..N {
                    let (v, p) = (nodes.v[k * N + i], nodes.p[k * N + i]);
                    gap = gap
                        .max((v - reference.v[k][i]).abs())
                        .max((p - reference.p[k][i]).abs());
                }
            }
            assert!(gap <= 1e-12, "{embedding} {scheme}: {gap:e}");
            // The unforced chain's transforms at the same nodes differ by the discrete force
            // where the node's transform reads it: not under Gauss-FDEσ and the asymmetric
            // embedding, whose quadrature point sits on the other node of the step.
            if scheme == Scheme::Variational && embedding.is_symmetric() {
                let unforced = solution.node_values(&Chain).unwrap();
                let moved = (0..N)
                    .map(|i| (unforced.p[50][i] - reference.p[50][i]).abs())
                    .fold(0.0, f64::max);
                assert!(moved > 1e-6, "{embedding}: {moved:e}");
            }
        }
    }
}

/// A forced chain's boundary value problems on the run-time path give the const-generic nodes
/// (to 1e-12, in as many Newton iterations) for every classical embedding and scheme, under
/// Rayleigh's dissipation and the same force written as a general `#[force]`: the force and
/// its Jacobian join the rows wherever `∂L/∂x` is read.
#[test]
fn forced_boundary_value_problems_of_run_time_dimension_are_the_const_generic_ones() {
    let rayleigh = Forced::new(Chain, Rayleigh(Dashpots { gamma: 0.3 }));
    let general = Forced::new(Chain, DashpotForce { gamma: 0.3 });
    let (qa, v0) = initial();
    let qb: [f64; N] = std::array::from_fn(|i| 0.8 * qa[i] + 0.5 * v0[i]);
    let grid = Grid::new(0.0, 1.0, 20).unwrap();
    for embedding in embeddings() {
        for scheme in [Scheme::Direct, Scheme::Variational] {
            let reference = varembed_tests::problem(&rayleigh, grid, embedding)
                .solve_bvp(scheme, qa, qb)
                .unwrap();
            // MINRES asked for: a force's `∂f/∂v` makes the Jacobian non-symmetric, so sparse
            // LU solves it all the same.
            let runs = [
                DynProblem::new(&rayleigh, grid, embedding).solve_bvp(scheme, &qa, &qb),
                DynProblem::new(&general, grid, embedding)
                    .with_bvp_solver(BvpSolver::Minres)
                    .solve_bvp(scheme, &qa, &qb),
            ];
            for run in runs {
                let run = run.unwrap();
                assert_eq!(run.run.linear_solve, Some(LinearSolve::SparseLu));
                let gap = reference
                    .q
                    .iter()
                    .enumerate()
                    .flat_map(|(k, x)| x.iter().zip(run.node(k)).map(|(a, b)| (a - b).abs()))
                    .fold(0.0, f64::max);
                assert!(gap <= 1e-12, "{embedding} {scheme}: {gap:e}");
                assert_eq!(
                    run.run.newton_iterations, reference.newton_iterations,
                    "{embedding} {scheme}"
                );
            }
        }
    }
}

/// Dissipation on a run-time number of sites.
#[lagrangian]
fn damping(_x: &[f64], v: &[f64], n: usize, gamma: f64) -> f64 {
    (0..n).map(|i| 0.5 * gamma * v[i] * v[i]).sum()
}

#[test]
fn a_force_of_another_dimension_is_refused() {
    let mismatched = Forced::new(Chain, Rayleigh(Damping { n: 8, gamma: 0.3 }));
    let (q0, v0) = initial();
    let grid = Grid::new(0.0, 1.0, 20).unwrap();
    let refused = DynProblem::new(&mismatched, grid, Embedding::midpoint()).solve_ivp(
        Scheme::Variational,
        &q0,
        &v0,
    );
    let Err(Error::InvalidModel { reason }) = refused else {
        panic!("{refused:?}");
    };
    assert!(reason.contains("dimension 8"), "{reason}");
    // The same dissipation at the model's dimension runs.
    let matched = Forced::new(Chain, Rayleigh(Damping { n: N, gamma: 0.3 }));
    DynProblem::new(&matched, grid, Embedding::midpoint())
        .solve_ivp(Scheme::Variational, &q0, &v0)
        .unwrap();
}

/// A forced chain's Gauss–Legendre boundary value problem between the ends of its own run
/// returns the run's nodes and momenta on both paths (the const-generic model's dense blocks
/// and the run-time form's sparse ones, each with the force's Jacobian in the global system),
/// for every `s`.
#[test]
fn forced_gauss_legendre_boundary_value_problems_return_the_run() {
    let forced = Forced::new(Chain, Rayleigh(Dashpots { gamma: 0.3 }));
    let (q0, v0) = initial();
    let grid = Grid::new(0.0, 1.0, 12).unwrap();
    for s in 1..=4 {
        let embedding = Embedding::gauss_legendre(s).unwrap();
        let problem = varembed_tests::problem(&forced, grid, embedding);
        let run = problem.solve_ivp(Scheme::Variational, q0, v0).unwrap();
        let (qa, qb) = (run.q[0], run.q[12]);
        let fixed = problem.solve_bvp(Scheme::Variational, qa, qb).unwrap();
        let dynamic = DynProblem::new(&forced, grid, embedding)
            .solve_bvp(Scheme::Variational, qa.as_slice(), qb.as_slice())
            .unwrap();
        for k in 0..=12 {
            let gap = (fixed.q[k] - run.q[k]).amax();
            assert!(gap <= 1e-12, "s = {s}, node {k}: {gap:e}");
            let gap = (fixed.momenta[k] - run.momenta[k]).amax();
            assert!(gap <= 1e-11, "s = {s}, momentum {k}: {gap:e}");
            let gap = dynamic
                .node(k)
                .iter()
                .zip(run.q[k].iter())
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(gap <= 1e-12, "s = {s}, run-time node {k}: {gap:e}");
        }
    }
}
