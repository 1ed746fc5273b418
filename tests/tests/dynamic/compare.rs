//! The comparison of a run-time-dimension model against the const-generic comparison of the
//! same model (its oracle): on the FPUT chain and on uncoupled oscillators, initial and
//! boundary value problems, Gauss-FDE− and FDE+ (incoherent: the other scheme's residual is
//! large) and the asymmetric embedding (coherent: it is round-off), with an exact reference, a
//! computed one and none, every column agrees: errors, energies and their drift, the other
//! scheme's residual, orders and their status, Newton iterations, the grids of the order and
//! the legend. Bad input fails with the const-generic path's typed error.

use varembed::{
    CompareOptions, ComparedSolution, Comparison, DynProblem, DynSolution, Embedding, Error, Grid,
    Lagrangian, NewtonOptions, Reference, SchemeReport, Side, Solution, Start, Vector, lagrangian,
};
use varembed_tests::models::chain::FputChain;
use varembed_tests::models::generated::fput16;

const D: usize = 4;

/// Four uncoupled unit oscillators: `x_i = a_i cos t + b_i sin t` exactly.
#[lagrangian]
fn oscillators(x: [f64; D], v: [f64; D]) -> f64 {
    let mut l = 0.0;
    for i in 0..D {
        l += 0.5 * (v[i] * v[i] - x[i] * x[i]);
    }
    l
}

/// A smooth displacement of the 16-particle chain (not a normal mode).
fn displacement(amplitude: f64, phase: f64) -> Vec<f64> {
    (0..16)
        .map(|i| amplitude * ((i as f64 + 1.0) * 0.7 + phase).sin())
        .collect()
}

/// `|a − b| ≤ tolerance · max(|a|, |b|, floor)`.
fn close(a: f64, b: f64, tolerance: f64, floor: f64) -> bool {
    (a - b).abs() <= tolerance * a.abs().max(b.abs()).max(floor)
}

fn same_option(a: Option<f64>, b: Option<f64>, tolerance: f64) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => close(a, b, tolerance, 0.0),
        (None, None) => true,
        _ => false,
    }
}

/// One scheme's line of the run-time-dimension comparison against the const-generic one:
/// the nodes, then every column. `coherent`: the other scheme's residual is round-off on both.
fn assert_same_report<const N: usize>(
    name: &str,
    ours: &SchemeReport<DynSolution>,
    oracle: &SchemeReport<Solution<N>>,
    coherent: bool,
) {
    let flat: Vec<f64> = oracle
        .solution
        .q
        .iter()
        .flat_map(|x| x.iter().copied())
        .collect();
    let scale = oracle.solution.size();
    let gap = ours
        .solution
        .q
        .iter()
        .zip(&flat)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(gap <= 1e-12 * scale, "{name}: node gap {gap:e}");
    assert!(
        same_option(ours.error, oracle.error, 1e-8),
        "{name}: errors {:?} {:?}",
        ours.error,
        oracle.error
    );
    assert_eq!(ours.energy.len(), oracle.energy.len(), "{name}");
    let e_scale = oracle.energy.iter().fold(0.0f64, |m, e| m.max(e.abs()));
    for (a, b) in ours.energy.iter().zip(&oracle.energy) {
        assert!(close(*a, *b, 1e-11, e_scale), "{name}: energy {a} {b}");
    }
    match (ours.energy_deviation, oracle.energy_deviation) {
        (Some(a), Some(b)) => assert!(close(a, b, 1e-6, 1e-9 * e_scale), "{name}: ΔE {a:e} {b:e}"),
        (a, b) => assert_eq!(a, b, "{name}"),
    }
    let (r, r_oracle) = (ours.residual_of_other, oracle.residual_of_other);
    if coherent {
        assert!(r < 1e-12 && r_oracle < 1e-12, "{name}: {r:e} {r_oracle:e}");
    } else {
        assert!(
            r_oracle > 1e-6,
            "{name}: the oracle is incoherent, {r_oracle:e}"
        );
        assert!(close(r, r_oracle, 1e-6, 0.0), "{name}: {r:e} {r_oracle:e}");
    }
    assert!(
        same_option(ours.order, oracle.order, 1e-6),
        "{name}: orders {:?} {:?}",
        ours.order,
        oracle.order
    );
    assert_eq!(ours.order_status, oracle.order_status, "{name}");
    assert_eq!(ours.theoretical_order, oracle.theoretical_order, "{name}");
    assert_eq!(
        ours.solution.newton_iterations(),
        oracle.solution.newton_iterations,
        "{name}"
    );
}

/// The whole comparison: its heading data, both lines, the distance, the legend.
fn assert_same<const N: usize>(
    name: &str,
    ours: &Comparison<DynSolution>,
    oracle: &Comparison<Solution<N>>,
    coherent: bool,
) {
    assert_eq!(ours.kind, oracle.kind, "{name}");
    assert_eq!(ours.embedding, oracle.embedding, "{name}");
    assert_eq!(ours.grid, oracle.grid, "{name}");
    assert_eq!(ours.reference, oracle.reference, "{name}");
    assert_eq!(ours.order_grids, oracle.order_grids, "{name}");
    assert_eq!(ours.extra_solves, oracle.extra_solves, "{name}");
    assert_eq!(ours.energy_not_conserved, oracle.energy_not_conserved);
    let direct = format!("{name} direct");
    assert_same_report(&direct, &ours.direct, &oracle.direct, coherent);
    let variational = format!("{name} variational");
    assert_same_report(
        &variational,
        &ours.variational,
        &oracle.variational,
        coherent,
    );
    // Relative, or within 1e-12 where the distance is round-off (the trapezoidal rule's two
    // schemes on the chain).
    assert!(
        close(ours.max_distance, oracle.max_distance, 1e-6, 1e-6),
        "{name}: distance {:e} {:e}",
        ours.max_distance,
        oracle.max_distance
    );
    assert_eq!(ours.legend(), oracle.legend(), "{name}");
    let table = ours.to_string();
    assert!(table.contains("max |Q_direct − Q_variational|") && table.contains("variational"));
}

/// The 16-particle chain: the generated model is the oracle (const-generic) and, with the
/// hand-written chain, the run-time-dimension model.
fn chains() -> (fput16::Fput, FputChain) {
    let (alpha, beta) = (0.25, 0.5);
    let chain = FputChain {
        n: 16,
        alpha,
        beta,
        periodic: false,
    };
    (fput16::Fput { alpha, beta }, chain)
}

/// The const-generic variational solution on 32 times the grid, read at the nodes of the
/// coarser grids: the computed reference of the chain, the same curve for both paths.
fn fine_reference(
    grid: Grid,
    fine: &Solution<16>,
) -> (
    impl Fn(f64) -> Vector<16> + '_,
    impl Fn(f64) -> Vec<f64> + '_,
) {
    let h = fine.grid.h();
    let at = move |t: f64| fine.q[((t - grid.a()) / h).round() as usize];
    (at, move |t: f64| at(t).iter().copied().collect())
}

#[test]
fn the_initial_value_comparison_of_the_chain_is_the_const_generic_one() {
    let (oracle_model, chain) = chains();
    let grid = Grid::new(0.0, 2.0, 40).unwrap();
    let q0 = displacement(0.4, 0.0);
    let v0: Vec<f64> = q0.iter().map(|q| 0.5 * q).collect();
    let (q16, v16) = (
        Vector::<16>::from_column_slice(&q0),
        Vector::<16>::from_column_slice(&v0),
    );
    for embedding in [
        Embedding::finite_difference(Side::Backward),
        Embedding::finite_difference(Side::Forward),
        Embedding::midpoint(),
        Embedding::trapezoidal(),
    ] {
        let oracle_problem = varembed_tests::problem(&oracle_model, grid, embedding);
        let fine = varembed_tests::problem(
            &oracle_model,
            Grid::new(0.0, 2.0, 32 * 40).unwrap(),
            embedding,
        )
        .solve_ivp(varembed::Scheme::Variational, q16, v16)
        .unwrap();
        let (reference16, reference) = fine_reference(grid, &fine);
        let with_reference = (
            CompareOptions {
                reference: Reference::Computed {
                    name: "variational on 32 N",
                    q: &reference16,
                },
                ..Default::default()
            },
            CompareOptions {
                reference: Reference::Computed {
                    name: "variational on 32 N",
                    q: &reference,
                },
                ..Default::default()
            },
        );
        let without = (CompareOptions::default(), CompareOptions::default());
        for (options16, options) in [with_reference, without] {
            let oracle = oracle_problem
                .compare_ivp_with(q16, v16, &options16)
                .unwrap();
            for (name, ours) in [
                (
                    "generated",
                    DynProblem::new(&oracle_model, grid, embedding)
                        .compare_ivp_with(&q0, &v0, &options),
                ),
                (
                    "hand-written",
                    DynProblem::new(&chain, grid, embedding).compare_ivp_with(&q0, &v0, &options),
                ),
            ] {
                let name = format!("{name} {embedding} against {}", oracle.reference);
                // The trapezoidal rule's two schemes coincide on this chain (its force does not
                // read the velocity).
                let coherent = embedding == Embedding::trapezoidal();
                assert_same(&name, &ours.unwrap(), &oracle, coherent);
            }
        }
    }
}

#[test]
fn the_boundary_value_comparison_is_the_const_generic_one_coherent_or_not() {
    let (oracle_model, chain) = chains();
    let grid = Grid::new(0.0, 1.0, 24).unwrap();
    let (qa, qb) = (displacement(0.3, 0.0), displacement(0.3, 1.1));
    let (qa16, qb16) = (
        Vector::<16>::from_column_slice(&qa),
        Vector::<16>::from_column_slice(&qb),
    );
    let symmetric = [Embedding::midpoint(), Embedding::trapezoidal()];
    for side in [Side::Backward, Side::Forward] {
        for embedding in [
            Embedding::finite_difference(side),
            Embedding::asymmetric(side),
        ]
        .into_iter()
        .chain(symmetric.into_iter().filter(|_| side == Side::Backward))
        {
            // The trapezoidal rule's two schemes coincide where the force does not read the
            // velocity, as on this chain.
            let coherent = embedding.is_coherent() || embedding == Embedding::trapezoidal();
            let oracle = varembed_tests::problem(&oracle_model, grid, embedding)
                .compare_bvp(qa16, qb16)
                .unwrap();
            let ours = DynProblem::new(&chain, grid, embedding)
                .compare_bvp(&qa, &qb)
                .unwrap();
            assert_same(&format!("{embedding}"), &ours, &oracle, coherent);
        }
    }
}

#[test]
fn against_an_exact_solution_both_problems_give_the_same_comparison() {
    let (a, b) = ([1.0, 0.5, -0.3, 0.0], [0.0, 0.2, 0.4, -1.0]);
    let exact = |t: f64| -> Vec<f64> { (0..D).map(|i| a[i] * t.cos() + b[i] * t.sin()).collect() };
    let exact_vector = |t: f64| Vector::<D>::from_vec(exact(t));
    let grid = Grid::new(0.0, 3.0, 30).unwrap();
    let options = CompareOptions {
        reference: Reference::Exact(&exact),
        ..Default::default()
    };
    let options_d = CompareOptions {
        reference: Reference::Exact(&exact_vector),
        ..Default::default()
    };
    for side in [Side::Backward, Side::Forward] {
        let embedding = Embedding::finite_difference(side);
        let oracle = varembed_tests::problem(&Oscillators, grid, embedding)
            .compare_ivp_with(a, b, &options_d)
            .unwrap();
        let ours = DynProblem::new(&Oscillators, grid, embedding)
            .compare_ivp_with(&a, &b, &options)
            .unwrap();
        assert_same(&format!("{embedding} ivp"), &ours, &oracle, false);
        assert_eq!(ours.reference, "exact solution");
        // First order against the exact solution, checked against the order at 2N.
        assert!((ours.direct.order.unwrap() - 1.0).abs() < 0.1);
        assert_eq!(ours.order_grids, [60, 120]);
        // From the second-order start, Störmer–Verlet's positions are second order.
        let oracle = varembed_tests::problem(&Oscillators, grid, embedding)
            .compare_ivp_with(
                a,
                b,
                &CompareOptions {
                    start: Start::SecondOrder,
                    ..options_d
                },
            )
            .unwrap();
        let ours = DynProblem::new(&Oscillators, grid, embedding)
            .compare_ivp_with(
                &a,
                &b,
                &CompareOptions {
                    start: Start::SecondOrder,
                    ..options
                },
            )
            .unwrap();
        assert_same(
            &format!("{embedding} ivp, second-order start"),
            &ours,
            &oracle,
            false,
        );
        let order = ours.variational.order.unwrap();
        assert!((order - 2.0).abs() < 0.1, "{order}");
        let (qa, qb) = (exact(0.0), exact(3.0));
        let oracle = varembed_tests::problem(&Oscillators, grid, embedding)
            .compare_bvp_with(
                Vector::<D>::from_vec(qa.clone()),
                Vector::<D>::from_vec(qb.clone()),
                &options_d,
            )
            .unwrap();
        let ours = DynProblem::new(&Oscillators, grid, embedding)
            .compare_bvp_with(&qa, &qb, &options)
            .unwrap();
        assert_same(&format!("{embedding} bvp"), &ours, &oracle, false);
    }
}

#[test]
fn without_the_order_solves_and_from_runs_nothing_more_is_solved() {
    let grid = Grid::new(0.0, 1.0, 16).unwrap();
    let embedding = Embedding::finite_difference(Side::Backward);
    let (q0, v0) = ([1.0, 0.0, 0.5, -0.5], [0.0, 1.0, 0.0, 0.25]);
    let no_order = (
        CompareOptions {
            order: false,
            ..Default::default()
        },
        CompareOptions {
            order: false,
            ..Default::default()
        },
    );
    let oracle = varembed_tests::problem(&Oscillators, grid, embedding)
        .compare_ivp_with(q0, v0, &no_order.0)
        .unwrap();
    let ours = DynProblem::new(&Oscillators, grid, embedding)
        .compare_ivp_with(&q0, &v0, &no_order.1)
        .unwrap();
    assert_same("no order", &ours, &oracle, false);
    assert_eq!((ours.extra_solves, ours.direct.order), (0, None));

    let problem = DynProblem::new(&Oscillators, grid, embedding);
    let options = CompareOptions::default();
    let runs = [varembed::Scheme::Direct, varembed::Scheme::Variational]
        .map(|scheme| problem.convergence_ivp(scheme, &q0, &v0, &options, 4));
    let oracle_problem = varembed_tests::problem(&Oscillators, grid, embedding);
    let oracle_runs = [varembed::Scheme::Direct, varembed::Scheme::Variational].map(|scheme| {
        oracle_problem.convergence_ivp(scheme, q0, v0, &CompareOptions::default(), 4)
    });
    for (run, oracle_run) in runs.iter().zip(&oracle_runs) {
        assert_eq!(run.order_statuses(), oracle_run.order_statuses());
        for (p, p_oracle) in run.orders().iter().zip(oracle_run.orders()) {
            assert!(close(*p, p_oracle, 1e-8, 0.0), "{p} {p_oracle}");
        }
    }
    let from_runs = problem.compare_runs(&runs[0], &runs[1]).unwrap();
    let oracle = oracle_problem
        .compare_runs(&oracle_runs[0], &oracle_runs[1])
        .unwrap();
    assert_same("from runs", &from_runs, &oracle, false);
    assert_eq!(from_runs.extra_solves, 0);
    assert!(matches!(
        problem.compare_runs(&runs[1], &runs[0]),
        Err(Error::Unsupported { .. })
    ));
}

#[test]
fn a_failing_solve_is_the_typed_error_of_the_const_generic_comparison() {
    let grid = Grid::new(0.0, 1.0, 10).unwrap();
    let embedding = Embedding::finite_difference(Side::Forward);
    let problem = DynProblem::new(&Oscillators, grid, embedding);
    let oracle = varembed_tests::problem(&Oscillators, grid, embedding);
    let nan = [f64::NAN, 0.0, 0.0, 0.0];
    let ours = problem.compare_ivp(&nan, &[0.0; D]).unwrap_err();
    let theirs = oracle.compare_ivp(nan, [0.0; D]).unwrap_err();
    assert!(matches!(ours, Error::NonFiniteInput { .. }), "{ours}");
    assert!(matches!(theirs, Error::NonFiniteInput { .. }), "{theirs}");

    // Newton stopped after one iteration: the same failure at the same place.
    let strict = NewtonOptions {
        tolerance: 1e-300,
        max_iterations: 1,
    };
    let chain = chains();
    let bvp_grid = Grid::new(0.0, 1.0, 12).unwrap();
    let (qa, qb) = (displacement(0.3, 0.0), displacement(0.3, 1.1));
    let ours = DynProblem::new(&chain.1, bvp_grid, embedding)
        .with_newton(strict)
        .compare_bvp(&qa, &qb)
        .unwrap_err();
    let theirs = varembed_tests::problem(&chain.0, bvp_grid, embedding)
        .with_newton(strict)
        .compare_bvp(
            Vector::<16>::from_column_slice(&qa),
            Vector::<16>::from_column_slice(&qb),
        )
        .unwrap_err();
    assert!(matches!(ours, Error::NewtonDidNotConverge { .. }), "{ours}");
    assert_eq!(
        std::mem::discriminant(&ours),
        std::mem::discriminant(&theirs)
    );

    // What only the run-time dimension can get wrong: the reference's length.
    let short = |_: f64| vec![0.0; D - 1];
    let options = CompareOptions {
        reference: Reference::Exact(&short),
        ..Default::default()
    };
    let error = problem.compare_ivp_with(&[1.0; D], &[0.0; D], &options);
    assert!(matches!(error, Err(Error::WrongLength { .. })), "{error:?}");
    let fractional = Embedding::grunwald_letnikov(Side::Backward, 0.6).unwrap();
    let error = DynProblem::new(&Oscillators, grid, fractional).compare_ivp(&[1.0; D], &[0.0; D]);
    assert!(matches!(error, Err(Error::Unsupported { .. })), "{error:?}");
    // The model is used through the const-generic trait too: the same `Oscillators`.
    let _: &dyn Lagrangian<D> = &Oscillators;
}
