//! Parallel runs equal serial ones bit for bit: the ensembles of `Problem` and `DynProblem`
//! (initial conditions and parameter sets) against `Ensemble::serial()` and against one solve
//! per member, and an untimed comparison or convergence study (its grids and schemes solved in
//! parallel) against the timed one, which solves one grid at a time. Results come back in
//! input order, a failing member in its place, and the progress callback counts every member
//! once.

use std::sync::Mutex;

use varembed::{
    CompareOptions, ComparedSolution, Comparison, DynProblem, DynSolution, Embedding, Ensemble,
    Error, Grid, Reference, Scheme, SchemeReport, Side, Solution, Start, Vector,
};
use varembed_tests::models::generated::{DoublePendulum, FputChain, Pendulum};

const DOUBLE_PENDULUM: DoublePendulum = varembed_tests::bench::DOUBLE_PENDULUM;

/// The bits of every node, so that equality is bit for bit (`-0.0` differs from `0.0`).
fn bits<const D: usize>(q: &[Vector<D>]) -> Vec<u64> {
    q.iter()
        .flat_map(|x| x.iter().map(|c| c.to_bits()))
        .collect()
}

fn solution_bits<const D: usize>(run: &varembed::Result<Solution<D>>) -> Vec<u64> {
    bits(&run.as_ref().expect("the member solves").q)
}

/// Eight initial states of the chaotic double pendulum, around the benches' start.
fn double_pendulum_members() -> Vec<([f64; 2], [f64; 2])> {
    let ([a, b], v) = varembed_tests::bench::DOUBLE_PENDULUM_START;
    (0..8)
        .map(|i| ([a + 0.01 * i as f64, b - 0.02 * i as f64], v))
        .collect()
}

#[test]
fn an_ensemble_of_initial_conditions_equals_the_serial_run_and_single_solves() {
    let grid = Grid::new(0.0, 2.0, 2000).unwrap();
    let members = double_pendulum_members();
    for (embedding, scheme) in [
        (Embedding::finite_difference(Side::Backward), Scheme::Direct),
        (Embedding::midpoint(), Scheme::Variational),
    ] {
        let problem = varembed_tests::problem(&DOUBLE_PENDULUM, grid, embedding);
        let parallel = problem.solve_ivp_ensemble(scheme, &members, &Ensemble::new());
        let serial = problem.solve_ivp_ensemble(scheme, &members, &Ensemble::serial());
        assert_eq!(parallel.len(), members.len());
        for (i, (q0, v0)) in members.iter().enumerate() {
            let alone = problem.solve_ivp(scheme, *q0, *v0);
            assert_eq!(solution_bits(&parallel[i]), solution_bits(&alone), "{i}");
            assert_eq!(solution_bits(&serial[i]), solution_bits(&alone), "{i}");
            assert_eq!(parallel[i], alone, "{embedding} {scheme}, member {i}");
        }
    }
}

#[test]
fn an_ensemble_of_models_equals_the_serial_run_and_single_solves() {
    let grid = Grid::new(0.0, 3.0, 1500).unwrap();
    let lengths: Vec<f64> = (1..=8).map(|i| 0.25 * i as f64).collect();
    let build = |&l: &f64| Pendulum { g: 9.81, l };
    let first = build(&lengths[0]);
    let strict = varembed::NewtonOptions {
        tolerance: 1e-13,
        max_iterations: 30,
    };
    let problem =
        varembed_tests::problem(&first, grid, Embedding::trapezoidal()).with_newton(strict);
    let scheme = Scheme::Direct;
    let parallel = problem.solve_ivp_models(scheme, &lengths, build, 1.0, 0.0, &Ensemble::new());
    let models: Vec<Pendulum> = lengths.iter().map(build).collect();
    let slice = problem.solve_ivp_models(scheme, &models, |m| m, 1.0, 0.0, &Ensemble::serial());
    for (i, model) in models.iter().enumerate() {
        let alone = varembed_tests::problem(model, grid, Embedding::trapezoidal())
            .with_newton(strict)
            .solve_ivp(scheme, 1.0, 0.0);
        assert_eq!(solution_bits(&parallel[i]), solution_bits(&alone), "{i}");
        assert_eq!(solution_bits(&slice[i]), solution_bits(&alone), "{i}");
    }
}

#[test]
fn a_dyn_ensemble_equals_the_serial_run_and_single_solves() {
    let n = 16;
    let chain = FputChain {
        n,
        alpha: 0.25,
        beta: 0.1,
    };
    let grid = Grid::new(0.0, 5.0, 500).unwrap();
    let problem = DynProblem::new(&chain, grid, Embedding::finite_difference(Side::Backward))
        .with_start(Start::SecondOrder);
    let members: Vec<(Vec<f64>, Vec<f64>)> = (0..6)
        .map(|i| {
            let q0 = varembed_tests::models::chain::displacement(n, 0.1 * (i + 1) as f64, 0.3);
            (q0, vec![0.0; n])
        })
        .collect();
    for scheme in [Scheme::Direct, Scheme::Variational] {
        let parallel = problem.solve_ivp_ensemble(scheme, &members, &Ensemble::new());
        let serial = problem.solve_ivp_ensemble(scheme, &members, &Ensemble::serial());
        for (i, (q0, v0)) in members.iter().enumerate() {
            let alone = problem.solve_ivp(scheme, q0, v0).unwrap();
            let flat = |s: &DynSolution| s.q.iter().map(|c| c.to_bits()).collect::<Vec<_>>();
            assert_eq!(flat(parallel[i].as_ref().unwrap()), flat(&alone), "{i}");
            assert_eq!(serial[i].as_ref().unwrap(), &alone, "{i}");
        }
    }
    // Parameter sets: the nonlinearity α per member.
    let alphas = [0.0, 0.25, 0.5, 1.0];
    let build = |&alpha: &f64| FputChain {
        n,
        alpha,
        beta: 0.1,
    };
    let (q0, v0) = &members[2];
    let scheme = Scheme::Variational;
    let runs = problem.solve_ivp_models(scheme, &alphas, build, q0, v0, &Ensemble::new());
    for (run, alpha) in runs.iter().zip(&alphas) {
        let model = build(alpha);
        let alone = DynProblem::new(&model, grid, Embedding::finite_difference(Side::Backward))
            .with_start(Start::SecondOrder)
            .solve_ivp(scheme, q0, v0)
            .unwrap();
        assert_eq!(run.as_ref().unwrap(), &alone, "α = {alpha}");
    }
}

#[test]
fn failing_members_keep_their_place_and_progress_counts_every_member() {
    // Non-finite initial data between good members.
    let grid = Grid::new(0.0, 10.0, 1000).unwrap();
    let pendulum = Pendulum { g: 1.0, l: 1.0 };
    let problem = varembed_tests::problem(
        &pendulum,
        grid,
        Embedding::finite_difference(Side::Backward),
    );
    let members = [
        (0.5, 0.0),
        (f64::NAN, 0.0),
        (1.0, 0.0),
        (0.1, f64::INFINITY),
    ];
    let seen = Mutex::new(Vec::new());
    let ensemble = Ensemble::new().with_progress(|done, total| {
        seen.lock().unwrap().push((done, total));
    });
    let runs = problem.solve_ivp_ensemble(Scheme::Variational, &members, &ensemble);
    drop(ensemble);
    assert!(runs[0].is_ok() && runs[2].is_ok());
    assert!(matches!(runs[1], Err(Error::NonFiniteInput { .. })));
    assert!(matches!(runs[3], Err(Error::NonFiniteInput { .. })));
    assert_eq!(runs[2], problem.solve_ivp(Scheme::Variational, 1.0, 0.0));
    let mut seen = seen.into_inner().unwrap();
    seen.sort_unstable();
    assert_eq!(seen, [(1, 4), (2, 4), (3, 4), (4, 4)]);
}

/// Every number of two comparisons' scheme reports, bit for bit; the wall time only where
/// each says.
fn assert_same_report<S: ComparedSolution + PartialEq>(
    what: &str,
    timed: &SchemeReport<S>,
    untimed: &SchemeReport<S>,
) {
    assert_eq!(timed.solution, untimed.solution, "{what}: solution");
    let b = |x: f64| x.to_bits();
    assert_eq!(
        b(timed.residual_of_other),
        b(untimed.residual_of_other),
        "{what}"
    );
    assert_eq!(timed.error.map(b), untimed.error.map(b), "{what}: error");
    let energies = |r: &SchemeReport<S>| r.energy.iter().map(|e| e.to_bits()).collect::<Vec<_>>();
    assert_eq!(energies(timed), energies(untimed), "{what}: energy");
    assert_eq!(
        timed.energy_deviation.map(b),
        untimed.energy_deviation.map(b),
        "{what}: energy deviation"
    );
    assert_eq!(timed.order.map(b), untimed.order.map(b), "{what}: order");
    assert_eq!(timed.order_status, untimed.order_status, "{what}");
    assert_eq!(timed.theoretical_order, untimed.theoretical_order);
    assert!(timed.wall_time.is_some(), "{what}: timed");
    assert!(untimed.wall_time.is_none(), "{what}: untimed");
}

fn assert_same_comparison<S: ComparedSolution + PartialEq>(
    what: &str,
    timed: &Comparison<S>,
    untimed: &Comparison<S>,
) {
    assert_same_report(&format!("{what}, direct"), &timed.direct, &untimed.direct);
    let variational = format!("{what}, variational");
    assert_same_report(&variational, &timed.variational, &untimed.variational);
    assert_eq!(timed.max_distance.to_bits(), untimed.max_distance.to_bits());
    assert_eq!(timed.order_grids, untimed.order_grids, "{what}");
    assert_eq!(timed.extra_solves, untimed.extra_solves, "{what}");
    // The tables differ in the time column and its legend only.
    let table = untimed.to_string();
    assert!(table.contains("not measured"), "{table}");
}

#[test]
fn an_untimed_comparison_equals_the_timed_one_bit_for_bit() {
    // The small-amplitude curve as the reference: the errors are only compared, bit for bit.
    let exact = |t: f64| Vector::<1>::new(0.5 * t.cos());
    let pendulum = Pendulum { g: 1.0, l: 1.0 };
    let grid = Grid::new(0.0, 4.0, 200).unwrap();
    for embedding in [
        Embedding::finite_difference(Side::Forward),
        Embedding::midpoint(),
    ] {
        let problem = varembed_tests::problem(&pendulum, grid, embedding);
        for reference in [Reference::None, Reference::Exact(&exact)] {
            let timed = CompareOptions {
                reference,
                start: Start::SecondOrder,
                ..Default::default()
            };
            let untimed = CompareOptions {
                timing: false,
                ..timed
            };
            let what = format!("{embedding} ivp");
            let a = problem.compare_ivp_with(0.5, 0.0, &timed).unwrap();
            let b = problem.compare_ivp_with(0.5, 0.0, &untimed).unwrap();
            assert_same_comparison(&what, &a, &b);
            let what = format!("{embedding} bvp");
            let a = problem.compare_bvp_with(0.0, 0.5, &timed).unwrap();
            let b = problem.compare_bvp_with(0.0, 0.5, &untimed).unwrap();
            assert_same_comparison(&what, &a, &b);
        }
        // A convergence study on its own: every level, in order.
        let timed = CompareOptions::default();
        let untimed = CompareOptions {
            timing: false,
            ..timed
        };
        let a = problem.convergence_ivp(Scheme::Variational, 0.5, 0.0, &timed, 5);
        let b = problem.convergence_ivp(Scheme::Variational, 0.5, 0.0, &untimed, 5);
        let sizes = |levels: &[varembed::Level<Solution<1>>]| {
            levels.iter().map(|l| l.n()).collect::<Vec<_>>()
        };
        assert_eq!(sizes(&b.levels), [200, 400, 800, 1600, 3200]);
        assert_eq!(sizes(&a.levels), sizes(&b.levels));
        for (x, y) in a.levels.iter().zip(&b.levels) {
            assert_eq!(bits(&x.solution.q), bits(&y.solution.q), "N = {}", x.n());
            assert!(x.wall_time.is_some() && y.wall_time.is_none());
        }
        let order_bits = |o: Vec<f64>| o.into_iter().map(f64::to_bits).collect::<Vec<_>>();
        assert_eq!(order_bits(a.orders()), order_bits(b.orders()));
    }
}

#[test]
fn an_untimed_dyn_comparison_equals_the_timed_one() {
    let n = 8;
    let chain = FputChain {
        n,
        alpha: 0.25,
        beta: 0.0,
    };
    let grid = Grid::new(0.0, 2.0, 100).unwrap();
    let problem = DynProblem::new(&chain, grid, Embedding::finite_difference(Side::Backward));
    let q0 = varembed_tests::models::chain::displacement(n, 0.2, 0.0);
    let v0 = vec![0.0; n];
    let timed = CompareOptions::default();
    let untimed = CompareOptions {
        timing: false,
        ..CompareOptions::default()
    };
    let a = problem.compare_ivp_with(&q0, &v0, &timed).unwrap();
    let b = problem.compare_ivp_with(&q0, &v0, &untimed).unwrap();
    assert_same_comparison("dyn ivp", &a, &b);
    // A failure is the same failure: a reference of the wrong length, before any solve.
    let short = |_: f64| vec![0.0; n - 1];
    let wrong = CompareOptions {
        reference: Reference::Exact(&short),
        timing: false,
        ..CompareOptions::default()
    };
    let err = problem.compare_ivp_with(&q0, &v0, &wrong).unwrap_err();
    assert!(matches!(err, Error::WrongLength { .. }), "{err}");
    let run = problem.convergence_ivp(Scheme::Direct, &q0, &v0, &wrong, 3);
    assert_eq!(run.failures.len(), 3);
    assert!(run.levels.is_empty());
}
