//! The symmetric embeddings (midpoint, trapezoidal; direct and variational) on the run-time
//! path: the same nodes as the const-generic run of the same model, their order against an
//! exact solution, and the typed errors of bad input.

use varembed::{
    DynProblem, DynSolution, Embedding, Ensemble, Error, Grid, Lagrangian, NewtonOptions, Scheme,
    Solution, Start, Vector, lagrangian,
};

use super::ivp::const_generic_run_from;
use varembed_tests::models::chain::{FputChain, displacement};
use varembed_tests::models::generated::fput16;

/// An embedding's name and constructor.
type Named = (&'static str, fn() -> Embedding);

const SYMMETRIC: [Named; 2] = [
    ("midpoint", Embedding::midpoint),
    ("trapezoidal", Embedding::trapezoidal),
];
const SCHEMES: [Scheme; 2] = [Scheme::Direct, Scheme::Variational];
const STARTS: [Start; 2] = [Start::Legendre, Start::SecondOrder];

/// The largest gap between the nodes of `run` and of `reference`, relative to the largest
/// node entry.
fn relative_gap<const D: usize>(run: &DynSolution, reference: &Solution<D>) -> f64 {
    let mut gap = 0.0f64;
    let mut size = 0.0f64;
    for (k, node) in reference.q.iter().enumerate() {
        for (i, x) in node.iter().enumerate() {
            gap = gap.max((run.node(k)[i] - x).abs());
            size = size.max(x.abs());
        }
    }
    gap / size
}

#[test]
fn the_symmetric_runs_of_a_chain_are_the_const_generic_runs() {
    let (alpha, beta) = (0.25, 0.5);
    let chain = FputChain {
        n: 16,
        alpha,
        beta,
        periodic: false,
    };
    let twin = fput16::Fput { alpha, beta };
    let grid = Grid::new(0.0, 10.0, 400).unwrap();
    let q0 = displacement(16, 0.4, 0.0);
    let v0: Vec<f64> = q0.iter().map(|q| 0.5 * q).collect();
    for (name, embedding) in SYMMETRIC {
        for scheme in SCHEMES {
            for start in STARTS {
                let run = DynProblem::new(&chain, grid, embedding())
                    .with_start(start)
                    .solve_ivp(scheme, &q0, &v0)
                    .unwrap();
                let reference = const_generic_run_from::<_, 16>(
                    &twin,
                    (grid, embedding(), scheme),
                    &q0,
                    &v0,
                    start,
                );
                let gap = relative_gap(&run, &reference);
                assert!(gap <= 1e-12, "{name} {scheme:?} {start:?}: {gap:e}");
                assert_eq!(run.run.band, 1, "{name} {scheme:?}");
                assert!(run.run.newton_iterations > 0, "{name} {scheme:?}");
            }
        }
    }
}

const M: usize = 8;

/// A chain whose mass depends on the position, with a gyroscopic coupling `x_i v_{i+1}` (so
/// `L_xv` is not symmetric) that grows with time: every block of the Hessian depends on
/// something, and every term of every step Jacobian is read.
#[lagrangian]
fn twisted(x: [f64; M], v: [f64; M], t: f64, k: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..M {
        l += 0.5 * (1.0 + 0.3 * x[i] * x[i]) * v[i] * v[i] - 0.5 * k * x[i] * x[i];
    }
    for i in 0..M - 1 {
        l += 0.2 * (1.0 + 0.1 * t) * x[i] * v[i + 1] - 0.1 * (x[i + 1] - x[i]).powi(4);
    }
    l
}

#[test]
fn a_model_with_every_block_varying_takes_the_const_generic_steps() {
    let model = Twisted { k: 2.0 };
    let grid = Grid::new(0.0, 3.0, 300).unwrap();
    let q0: Vec<f64> = (0..M).map(|i| 0.3 * ((i as f64) * 0.9).sin()).collect();
    let v0: Vec<f64> = (0..M).map(|i| 0.2 * ((i as f64) * 0.5).cos()).collect();
    // The model varies in every block: check it does, so that the test reads every term.
    let x = Vector::<M>::from_column_slice(&q0);
    let v = Vector::<M>::from_column_slice(&v0);
    let hessian = Lagrangian::<M>::hessian(&model, &x, &v, 0.5);
    assert!((hessian.xv - hessian.xv.transpose()).amax() > 0.1);
    assert!((0..M).any(|i| hessian.vv[(i, i)] != 1.0));
    for (name, embedding) in SYMMETRIC {
        for scheme in SCHEMES {
            for start in STARTS {
                let run = DynProblem::new(&model, grid, embedding())
                    .with_start(start)
                    .solve_ivp(scheme, &q0, &v0)
                    .unwrap();
                let reference = const_generic_run_from::<_, M>(
                    &model,
                    (grid, embedding(), scheme),
                    &q0,
                    &v0,
                    start,
                );
                let gap = relative_gap(&run, &reference);
                assert!(gap <= 1e-12, "{name} {scheme:?} {start:?}: {gap:e}");
            }
        }
    }
}

/// The exact solution of the linear chain (`α = β = 0`, fixed ends) of `n` unit masses at
/// time `t` from rest at `q0`: by its normal modes `sin(j k π/(n + 1))`, of frequencies
/// `2 sin(k π/(2(n + 1)))`.
fn linear_chain_exact(q0: &[f64], t: f64) -> Vec<f64> {
    let n = q0.len();
    let mode = |k: usize, j: usize| {
        ((j + 1) as f64 * k as f64 * std::f64::consts::PI / (n + 1) as f64).sin()
    };
    let norm = (n + 1) as f64 / 2.0;
    let mut q = vec![0.0; n];
    for k in 1..=n {
        let amplitude: f64 = (0..n).map(|j| q0[j] * mode(k, j)).sum::<f64>() / norm;
        let omega = 2.0 * (k as f64 * std::f64::consts::PI / (2.0 * (n + 1) as f64)).sin();
        for (j, q) in q.iter_mut().enumerate() {
            *q += amplitude * (omega * t).cos() * mode(k, j);
        }
    }
    q
}

#[test]
fn the_symmetric_runs_of_a_linear_chain_are_second_order() {
    let n = 16;
    let chain = FputChain {
        n,
        alpha: 0.0,
        beta: 0.0,
        periodic: false,
    };
    let q0 = displacement(n, 0.5, 0.3);
    let v0 = vec![0.0; n];
    let t_end = 5.0;
    let exact = linear_chain_exact(&q0, t_end);
    for (name, embedding) in SYMMETRIC {
        for scheme in SCHEMES {
            for start in STARTS {
                let error = |steps: usize| {
                    let grid = Grid::new(0.0, t_end, steps).unwrap();
                    let run = DynProblem::new(&chain, grid, embedding())
                        .with_start(start)
                        .solve_ivp(scheme, &q0, &v0)
                        .unwrap();
                    let last = run.node(steps);
                    last.iter()
                        .zip(&exact)
                        .map(|(q, e)| (q - e).abs())
                        .fold(0.0, f64::max)
                };
                let errors: Vec<f64> = [100, 200, 400].into_iter().map(error).collect();
                for pair in errors.windows(2) {
                    let order = (pair[0] / pair[1]).log2();
                    assert!(
                        (1.9..2.2).contains(&order),
                        "{name} {scheme:?} {start:?}: errors {errors:?}, order {order}"
                    );
                }
            }
        }
    }
}

/// `½ (v₀ − v₁)² − ½|x|²`: `∂²L/∂v²` is singular at every point.
#[lagrangian]
fn degenerate(x: [f64; 2], v: [f64; 2]) -> f64 {
    let mut l = 0.5 * (v[0] - v[1]) * (v[0] - v[1]);
    for i in 0..2 {
        l -= 0.5 * x[i] * x[i];
    }
    l
}

#[test]
fn bad_input_on_the_symmetric_runs_gives_the_typed_errors() {
    let model = Twisted { k: 2.0 };
    let grid = Grid::new(0.0, 1.0, 50).unwrap();
    let q0 = vec![0.1; M];
    let v0 = vec![0.0; M];
    for (name, embedding) in SYMMETRIC {
        for scheme in SCHEMES {
            let problem = DynProblem::new(&model, grid, embedding());
            let mut nan = q0.clone();
            nan[3] = f64::NAN;
            let error = problem.solve_ivp(scheme, &nan, &v0).unwrap_err();
            assert!(
                matches!(&error, Error::NonFiniteInput { what } if what.contains("q0[3]")),
                "{name} {scheme:?}: {error}"
            );
            let error = DynProblem::new(&Degenerate, grid, embedding())
                .solve_ivp(scheme, &[0.1, 0.2], &[0.0, 0.0])
                .unwrap_err();
            assert!(
                matches!(error, Error::DegenerateLagrangian { .. }),
                "{name} {scheme:?}: {error}"
            );
            // One Newton iteration allowed and a tolerance no iterate meets: the error names
            // the step.
            let strict = NewtonOptions {
                max_iterations: 1,
                tolerance: 1e-300,
            };
            let error = DynProblem::new(&model, Grid::new(0.0, 1.0, 5).unwrap(), embedding())
                .with_newton(strict)
                .solve_ivp(scheme, &[0.8; M], &[0.5; M])
                .unwrap_err();
            assert!(
                matches!(error, Error::NewtonDidNotConverge { .. }),
                "{name} {scheme:?}: {error}"
            );
        }
    }
}

/// The start is chosen the same way on both paths: `with_start` on the problem for every run,
/// or `solve_ivp_with` for one run. The two give the same nodes on each path, the two paths the
/// same nodes as each other, and the two starts different nodes (neither call ignores it).
#[test]
fn the_start_is_chosen_the_same_way_on_both_paths() {
    let (alpha, beta) = (0.25, 0.5);
    let chain = FputChain {
        n: 16,
        alpha,
        beta,
        periodic: false,
    };
    let twin = fput16::Fput { alpha, beta };
    let grid = Grid::new(0.0, 2.0, 50).unwrap();
    let q0 = displacement(16, 0.4, 0.0);
    let v0: Vec<f64> = q0.iter().map(|q| 0.5 * q).collect();
    let (x0, u0) = (
        Vector::<16>::from_column_slice(&q0),
        Vector::<16>::from_column_slice(&v0),
    );
    for embedding in [
        Embedding::midpoint(),
        Embedding::finite_difference(varembed::Side::Backward),
    ] {
        let mut first_nodes = Vec::new();
        for start in STARTS {
            let scheme = Scheme::Variational;
            let by_builder = DynProblem::new(&chain, grid, embedding)
                .with_start(start)
                .solve_ivp(scheme, &q0, &v0)
                .unwrap();
            let by_call = DynProblem::new(&chain, grid, embedding)
                .solve_ivp_with(scheme, &q0, &v0, start)
                .unwrap();
            assert_eq!(by_builder.q, by_call.q, "{embedding} {start:?}");
            let twin_builder = varembed_tests::problem(&twin, grid, embedding)
                .with_start(start)
                .solve_ivp(scheme, x0, u0)
                .unwrap();
            let twin_call = varembed_tests::problem(&twin, grid, embedding)
                .solve_ivp_with(scheme, x0, u0, start)
                .unwrap();
            assert_eq!(twin_builder.q, twin_call.q, "{embedding} {start:?}");
            let gap = relative_gap(&by_builder, &twin_builder);
            assert!(gap <= 1e-12, "{embedding} {start:?}: {gap:e}");
            // The ensembles of both paths run from the problem's start too.
            let members = [&twin];
            let models = varembed_tests::problem(&twin, grid, embedding)
                .with_start(start)
                .solve_ivp_models(scheme, &members, |m| *m, x0, u0, &Ensemble::serial());
            assert_eq!(models[0].as_ref().unwrap().q, twin_builder.q, "{start:?}");
            let dyn_members = [&chain];
            let dyn_models = DynProblem::new(&chain, grid, embedding)
                .with_start(start)
                .solve_ivp_models(scheme, &dyn_members, |m| *m, &q0, &v0, &Ensemble::serial());
            assert_eq!(dyn_models[0].as_ref().unwrap().q, by_builder.q, "{start:?}");
            first_nodes.push(by_builder.node(1).to_vec());
        }
        assert_ne!(first_nodes[0], first_nodes[1], "{embedding}");
    }
}
