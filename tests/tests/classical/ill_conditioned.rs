//! A boundary value problem whose Newton system is singular to working precision ends in
//! `Error::IllConditioned`, never in an `Ok` of round-off: a spring between a unit mass and one
//! a million times lighter, which the direct Gauss-FDE− scheme on 10 steps turns into a system
//! of condition number beyond `1/ε` (it returned `Ok` with nodes of 1.6e27 and a residual of
//! 5.2e5). Over a sweep of mass ratios, grids, embeddings and schemes, every answer is either a
//! solution of its rows or a typed error.

use varembed::{Embedding, Error, Grid, Scheme, Side, Warning, lagrangian};

/// Two masses `1` and `m` on a spring, the first also tied to the origin (the kinetic term
/// written as a loop, so that the macro emits the run-time-dimension trait too).
#[lagrangian]
fn two_masses(x: [f64; 2], v: [f64; 2], m: f64) -> f64 {
    let mut kinetic = 0.0;
    for i in 0..2 {
        let mass = 1.0 + (m - 1.0) * i as f64;
        kinetic += 0.5 * mass * v[i] * v[i];
    }
    let stretch = x[0] - x[1];
    kinetic - 0.5 * stretch * stretch - 0.5 * x[0] * x[0]
}

fn solve(m: f64, n: usize, embedding: Embedding, scheme: Scheme) -> varembed::Result<f64> {
    let model = TwoMasses { m };
    let problem = varembed_tests::problem(&model, Grid::new(0.0, 10.0, n).unwrap(), embedding);
    let solution = problem.solve_bvp(scheme, [1.0, 0.0], [0.0, 1.0])?;
    // An answer solves its rows: each row's residual against the size of its terms.
    let residual = problem.residual(scheme, &solution.q).unwrap();
    let worst = residual.iter().fold(0.0f64, |m, r| m.max(r.amax()));
    let largest = solution.q.iter().fold(0.0f64, |m, q| m.max(q.amax()));
    let flagged = solution
        .warnings
        .iter()
        .any(|w| matches!(w, Warning::IllPosed { .. }));
    assert!(
        largest < 1e3 || flagged,
        "m = {m:e}, N = {n}, {embedding} {scheme:?}: Ok with nodes of {largest:e} (residual \
         {worst:e}) and no warning"
    );
    Ok(largest)
}

#[test]
fn a_system_singular_to_working_precision_is_an_error() {
    let direct = Embedding::finite_difference(Side::Backward);
    let error = solve(1e-6, 10, direct, Scheme::Direct).unwrap_err();
    let Error::IllConditioned { condition, .. } = error else {
        panic!("{error}");
    };
    assert!(condition >= 1.0 / f64::EPSILON, "{condition:e}");
    let text = error.to_string();
    assert!(
        text.contains("nondimensionalise") && text.contains("resonance"),
        "{text}"
    );
    // The check belongs to Newton's acceptance, not to the optional ill-posedness warning.
    let model = TwoMasses { m: 1e-6 };
    let problem = varembed_tests::problem(&model, Grid::new(0.0, 10.0, 10).unwrap(), direct)
        .with_posedness_check(false);
    let error = problem
        .solve_bvp(Scheme::Direct, [1.0, 0.0], [0.0, 1.0])
        .unwrap_err();
    assert!(matches!(error, Error::IllConditioned { .. }), "{error}");
}

#[test]
fn every_mass_ratio_gives_a_solution_or_a_typed_error() {
    let embeddings = [
        Embedding::finite_difference(Side::Backward),
        Embedding::finite_difference(Side::Forward),
        Embedding::asymmetric(Side::Forward),
        Embedding::midpoint(),
        Embedding::trapezoidal(),
    ];
    let mut answers = 0;
    for m in [1.0, 1e-3, 1e-6, 1e-9, 1e-12] {
        for n in [10, 100, 1000] {
            for embedding in embeddings {
                for scheme in [Scheme::Direct, Scheme::Variational] {
                    match solve(m, n, embedding, scheme) {
                        Ok(_) => answers += 1,
                        Err(
                            Error::IllConditioned { .. }
                            | Error::DegenerateLagrangian { .. }
                            | Error::SingularJacobian { .. }
                            | Error::NewtonDidNotConverge { .. },
                        ) => {}
                        Err(error) => panic!("m = {m:e}, N = {n}, {embedding} {scheme:?}: {error}"),
                    }
                }
            }
        }
    }
    // The variational schemes and the midpoint direct one solve every case.
    assert!(answers >= 60, "{answers} answers");
}

/// The run-time-dimension solve of the same model (the macro emits both traits for an array
/// model) bounds the condition number the same way.
#[test]
fn the_run_time_path_reports_the_same_system_as_ill_conditioned() {
    let model = TwoMasses { m: 1e-6 };
    let grid = Grid::new(0.0, 10.0, 10).unwrap();
    let direct = Embedding::finite_difference(Side::Backward);
    let error = varembed::DynProblem::new(&model, grid, direct)
        .solve_bvp(Scheme::Direct, &[1.0, 0.0], &[0.0, 1.0])
        .unwrap_err();
    assert!(matches!(error, Error::IllConditioned { .. }), "{error}");
    // The well-conditioned variational solve of the same problem agrees with the const path.
    let run = varembed::DynProblem::new(&model, grid, direct)
        .solve_bvp(Scheme::Variational, &[1.0, 0.0], &[0.0, 1.0])
        .unwrap();
    let reference = varembed_tests::problem(&model, grid, direct)
        .solve_bvp(Scheme::Variational, [1.0, 0.0], [0.0, 1.0])
        .unwrap();
    for (k, node) in reference.q.iter().enumerate() {
        for (i, value) in node.iter().enumerate() {
            assert!(
                (run.q[2 * k + i] - value).abs() < 1e-12,
                "node {k}: {}",
                run.q[2 * k + i]
            );
        }
    }
}
