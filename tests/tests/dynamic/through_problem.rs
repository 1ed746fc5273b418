//! A `[f64; N]` model with loops is also a run-time-dimension model: from `RUN_TIME_FROM`
//! degrees of freedom on, `Problem` hands its initial value problems (and its Gauss-FDEσ and
//! asymmetric boundary value problems) to the run-time engine.
//! The nodes are the const-generic path's, and a model of 256 degrees of freedom runs on the
//! 2 MiB stack of a test thread.

use varembed::{
    DynProblem, Embedding, Error, Grid, Lagrangian, NewtonOptions, Problem, RUN_TIME_FROM, Scheme,
    Side, Solution, Start, Vector, lagrangian,
};
use varembed_tests::models::dense::Dense;

/// Every classical embedding with a three-point recurrence.
pub(super) fn embeddings() -> [Embedding; 6] {
    [
        Embedding::finite_difference(Side::Backward),
        Embedding::finite_difference(Side::Forward),
        Embedding::asymmetric(Side::Backward),
        Embedding::asymmetric(Side::Forward),
        Embedding::midpoint(),
        Embedding::trapezoidal(),
    ]
}

pub(super) const RING: usize = 256;

/// The sine-Gordon ring: `RING` pendulums `1 − cos x` coupled to their neighbours around a
/// circle.
#[lagrangian]
pub(super) fn sine_gordon(x: [f64; RING], v: [f64; RING], c: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..RING {
        let stretch = x[(i + 1) % RING] - x[i];
        l += 0.5 * v[i] * v[i] - (1.0 - x[i].cos()) - 0.5 * c * stretch * stretch;
    }
    l
}

pub(super) const SMALL: usize = 64;

/// The same ring at the threshold's size.
#[lagrangian]
pub(super) fn small_ring(x: [f64; SMALL], v: [f64; SMALL], c: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..SMALL {
        let stretch = x[(i + 1) % SMALL] - x[i];
        l += 0.5 * v[i] * v[i] - (1.0 - x[i].cos()) - 0.5 * c * stretch * stretch;
    }
    l
}

/// A kink-like initial displacement of `n` sites.
pub(super) fn displaced(n: usize) -> (Vec<f64>, Vec<f64>) {
    let q0 = (0..n)
        .map(|i| 0.8 * (2.0 * std::f64::consts::PI * i as f64 / n as f64).sin())
        .collect();
    let v0 = (0..n).map(|i| 0.1 * (i as f64 * 0.37).cos()).collect();
    (q0, v0)
}

/// The largest gap between the nodes of `run` and `reference`, relative to the largest entry
/// of `reference`.
fn relative_gap<const D: usize>(run: &Solution<D>, reference: &Solution<D>) -> f64 {
    let size = reference.q.iter().map(|q| q.amax()).fold(0.0, f64::max);
    let gap = run
        .q
        .iter()
        .zip(&reference.q)
        .map(|(a, b)| (a - b).amax())
        .fold(0.0, f64::max);
    gap / size
}

/// Runs `f` on a thread with a stack of `bytes`.
pub(super) fn on_stack<T: Send>(bytes: usize, f: impl FnOnce() -> T + Send) -> T {
    std::thread::scope(|scope| {
        std::thread::Builder::new()
            .stack_size(bytes)
            .spawn_scoped(scope, f)
            .expect("a thread")
            .join()
            .expect("no overflow, no panic")
    })
}

#[test]
fn a_ring_of_256_runs_through_problem_on_a_two_megabyte_stack() {
    const { assert!(RING >= RUN_TIME_FROM) };
    let model = SineGordon { c: 4.0 };
    let grid = Grid::new(0.0, 1.0, 40).unwrap();
    let (q0, v0) = displaced(RING);
    on_stack(2 << 20, || {
        for embedding in embeddings() {
            for scheme in [Scheme::Direct, Scheme::Variational] {
                let x0 = Vector::<RING>::from_column_slice(&q0);
                let u0 = Vector::<RING>::from_column_slice(&v0);
                let run = Problem::new(&model, grid, embedding)
                    .solve_ivp(scheme, x0, u0)
                    .unwrap();
                let reference = DynProblem::new(&model, grid, embedding)
                    .solve_ivp(scheme, &q0, &v0)
                    .unwrap();
                assert_eq!(run.q.len(), grid.n() + 1);
                for (k, node) in run.q.iter().enumerate() {
                    assert_eq!(node.as_slice(), reference.node(k), "{embedding} {scheme:?}");
                }
                // From given first nodes: the run-time engine's run from the same nodes.
                let x1 = run.q[1] + Vector::<RING>::from_element(1e-3);
                let from_nodes = Problem::new(&model, grid, embedding)
                    .solve_ivp_from_nodes(scheme, x0, x1)
                    .unwrap();
                let reference = DynProblem::new(&model, grid, embedding)
                    .solve_ivp_from_nodes(scheme, &q0, x1.as_slice())
                    .unwrap();
                assert_eq!(from_nodes.q[1], x1);
                for (k, node) in from_nodes.q.iter().enumerate() {
                    assert_eq!(node.as_slice(), reference.node(k), "{embedding} {scheme:?}");
                }
            }
        }
        // Gauss–Legendre is a one-step map of (q, p): no run from two nodes on either path.
        let gauss = Embedding::gauss_legendre(2).unwrap();
        let x0 = Vector::<RING>::from_column_slice(&q0);
        let routed =
            Problem::new(&model, grid, gauss).solve_ivp_from_nodes(Scheme::Variational, x0, x0);
        let run_time = DynProblem::new(&model, grid, gauss).solve_ivp_from_nodes(
            Scheme::Variational,
            &q0,
            &q0,
        );
        for result in [routed.map(|_| ()), run_time.map(|_| ())] {
            assert!(
                matches!(result, Err(Error::Unsupported { .. })),
                "{result:?}"
            );
        }
    });
}

/// Given first nodes of the wrong length or not finite are errors that name `q1`.
#[test]
fn bad_first_nodes_are_named() {
    let model = SmallRing { c: 4.0 };
    let grid = Grid::new(0.0, 1.0, 10).unwrap();
    let problem = DynProblem::new(&model, grid, Embedding::midpoint());
    let q0 = vec![0.1; SMALL];
    let short = problem.solve_ivp_from_nodes(Scheme::Variational, &q0, &q0[1..]);
    assert!(
        matches!(short, Err(Error::WrongLength { what: "q1", expected: SMALL, found }) if found == SMALL - 1),
        "{short:?}"
    );
    let mut q1 = q0.clone();
    q1[5] = f64::NAN;
    let message = problem
        .solve_ivp_from_nodes(Scheme::Variational, &q0, &q1)
        .unwrap_err()
        .to_string();
    assert!(message.contains("q1[5]"), "{message}");
}

#[test]
fn at_the_threshold_problem_gives_the_const_generic_nodes() {
    const { assert!(SMALL == RUN_TIME_FROM) };
    let model = SmallRing { c: 4.0 };
    // `Dense` forwards the model but not its run-time form: the const-generic path.
    assert!(Lagrangian::<SMALL>::run_time(&model).is_some());
    assert!(Lagrangian::<SMALL>::run_time(&Dense(&model)).is_none());
    let grid = Grid::new(0.0, 2.0, 100).unwrap();
    let (q0, v0) = displaced(SMALL);
    let (x0, u0) = (
        Vector::<SMALL>::from_column_slice(&q0),
        Vector::<SMALL>::from_column_slice(&v0),
    );
    // The const-generic path keeps `64 × 64` blocks on the stack: a large one.
    on_stack(64 << 20, || {
        for embedding in embeddings() {
            for scheme in [Scheme::Direct, Scheme::Variational] {
                let routed: Solution<SMALL> = Problem::new(&model, grid, embedding)
                    .solve_ivp(scheme, x0, u0)
                    .unwrap();
                let reference = Problem::new(&Dense(&model), grid, embedding)
                    .solve_ivp(scheme, x0, u0)
                    .unwrap();
                let gap = relative_gap(&routed, &reference);
                assert!(gap <= 1e-12, "{embedding} {scheme:?}: {gap:e}");
                let x1 = routed.q[1] + Vector::<SMALL>::from_element(1e-3);
                let routed = Problem::new(&model, grid, embedding)
                    .solve_ivp_from_nodes(scheme, x0, x1)
                    .unwrap();
                let reference = Problem::new(&Dense(&model), grid, embedding)
                    .solve_ivp_from_nodes(scheme, x0, x1)
                    .unwrap();
                let gap = relative_gap(&routed, &reference);
                assert!(gap <= 1e-12, "from nodes, {embedding} {scheme:?}: {gap:e}");
            }
        }
    });
}

/// The options of a `Problem` reach the run-time engine it hands a run to: Newton's (an
/// iteration budget too small to converge gives the run-time path's own error), the
/// resolution check (a step too coarse for the ring's fastest motion is warned about, and not
/// when the check is off), and the start (the second-order start gives other nodes than the
/// Legendre start), each equal to `DynProblem` with the same option.
#[test]
fn the_hand_off_keeps_the_problems_options() {
    let model = SineGordon { c: 4.0 };
    let (q0, v0) = displaced(RING);
    let (x0, u0) = (
        Vector::<RING>::from_column_slice(&q0),
        Vector::<RING>::from_column_slice(&v0),
    );
    on_stack(2 << 20, || {
        let midpoint = Embedding::midpoint();
        let grid = Grid::new(0.0, 1.0, 40).unwrap();
        let starved = NewtonOptions {
            max_iterations: 1,
            ..NewtonOptions::default()
        };
        let routed = Problem::new(&model, grid, midpoint)
            .with_newton(starved)
            .solve_ivp(Scheme::Variational, x0, u0)
            .unwrap_err();
        let direct = DynProblem::new(&model, grid, midpoint)
            .with_newton(starved)
            .solve_ivp(Scheme::Variational, &q0, &v0)
            .unwrap_err();
        assert!(
            matches!(routed, Error::NewtonDidNotConverge { .. }),
            "{routed:?}"
        );
        assert_eq!(routed, direct);

        let coarse = Grid::new(0.0, 20.0, 20).unwrap();
        for check in [true, false] {
            let routed = Problem::new(&model, coarse, midpoint)
                .with_resolution_check(check)
                .solve_ivp(Scheme::Variational, x0, u0)
                .unwrap();
            let direct = DynProblem::new(&model, coarse, midpoint)
                .with_resolution_check(check)
                .solve_ivp(Scheme::Variational, &q0, &v0)
                .unwrap();
            assert_eq!(routed.warnings, direct.warnings, "check {check}");
            assert_eq!(routed.warnings.is_empty(), !check, "{:?}", routed.warnings);
        }

        let backward = Embedding::finite_difference(Side::Backward);
        let legendre = Problem::new(&model, grid, backward)
            .solve_ivp_with(Scheme::Variational, x0, u0, Start::Legendre)
            .unwrap();
        let second = Problem::new(&model, grid, backward)
            .solve_ivp_with(Scheme::Variational, x0, u0, Start::SecondOrder)
            .unwrap();
        let reference = DynProblem::new(&model, grid, backward)
            .with_start(Start::SecondOrder)
            .solve_ivp(Scheme::Variational, &q0, &v0)
            .unwrap();
        assert_ne!(legendre.q[1], second.q[1]);
        for (k, node) in second.q.iter().enumerate() {
            assert_eq!(node.as_slice(), reference.node(k), "node {k}");
        }
    });
}

/// A model whose run-time form has another dimension (a hand-written pairing gone wrong) is
/// not handed to it: `Problem` solves what its `Lagrangian<D>` methods say, the const-generic
/// path's nodes.
#[test]
fn a_run_time_form_of_another_dimension_is_not_used() {
    struct Mismatched {
        model: SmallRing,
        other: SineGordon,
    }
    impl Lagrangian<SMALL> for Mismatched {
        fn value(&self, x: &Vector<SMALL>, v: &Vector<SMALL>, t: f64) -> f64 {
            self.model.value(x, v, t)
        }
        fn gradient(
            &self,
            x: &Vector<SMALL>,
            v: &Vector<SMALL>,
            t: f64,
        ) -> (Vector<SMALL>, Vector<SMALL>) {
            self.model.gradient(x, v, t)
        }
        fn hessian(
            &self,
            x: &Vector<SMALL>,
            v: &Vector<SMALL>,
            t: f64,
        ) -> varembed::Hessian<SMALL> {
            self.model.hessian(x, v, t)
        }
        fn run_time(&self) -> Option<&dyn varembed::DynLagrangian> {
            Some(&self.other)
        }
    }
    let model = Mismatched {
        model: SmallRing { c: 4.0 },
        other: SineGordon { c: 4.0 },
    };
    let grid = Grid::new(0.0, 1.0, 20).unwrap();
    let (q0, v0) = displaced(SMALL);
    let (x0, u0) = (
        Vector::<SMALL>::from_column_slice(&q0),
        Vector::<SMALL>::from_column_slice(&v0),
    );
    on_stack(64 << 20, || {
        let embedding = Embedding::midpoint();
        let run = Problem::new(&model, grid, embedding)
            .solve_ivp(Scheme::Variational, x0, u0)
            .unwrap();
        let reference = Problem::new(&Dense(&model.model), grid, embedding)
            .solve_ivp(Scheme::Variational, x0, u0)
            .unwrap();
        assert_eq!(run.q, reference.q);
    });
}

/// The boundary value problems of a large model under Gauss-FDEσ, the asymmetric and the
/// symmetric embeddings are handed to the run-time engine too: a 256-site ring on a 2 MiB stack
/// gives `DynProblem`'s nodes bit for bit, and at the threshold's size the const-generic nodes
/// of the same model (to 1e-12), with the problem's posedness check.
#[test]
fn boundary_value_problems_of_large_models_run_on_the_run_time_engine() {
    let grid = Grid::new(0.0, 1.0, 30).unwrap();
    let kinds = [
        Embedding::finite_difference(Side::Backward),
        Embedding::finite_difference(Side::Forward),
        Embedding::asymmetric(Side::Backward),
        Embedding::midpoint(),
        Embedding::trapezoidal(),
    ];
    let model = SineGordon { c: 4.0 };
    let (qa, v0) = displaced(RING);
    let qb: Vec<f64> = qa.iter().zip(&v0).map(|(q, v)| 0.9 * q + v).collect();
    on_stack(2 << 20, || {
        for embedding in kinds {
            for scheme in [Scheme::Direct, Scheme::Variational] {
                let routed = Problem::new(&model, grid, embedding)
                    .solve_bvp(
                        scheme,
                        Vector::<RING>::from_column_slice(&qa),
                        Vector::<RING>::from_column_slice(&qb),
                    )
                    .unwrap();
                let reference = DynProblem::new(&model, grid, embedding)
                    .solve_bvp(scheme, &qa, &qb)
                    .unwrap();
                for (k, node) in routed.q.iter().enumerate() {
                    assert_eq!(node.as_slice(), reference.node(k), "{embedding} {scheme:?}");
                }
                assert_eq!(routed.newton_iterations, reference.run.newton_iterations);
            }
        }
        // Gauss–Legendre's collocation boundary value problem (variational only).
        let embedding = Embedding::gauss_legendre(2).unwrap();
        let routed = Problem::new(&model, grid, embedding)
            .solve_bvp(
                Scheme::Variational,
                Vector::<RING>::from_column_slice(&qa),
                Vector::<RING>::from_column_slice(&qb),
            )
            .unwrap();
        let reference = DynProblem::new(&model, grid, embedding)
            .solve_bvp(Scheme::Variational, &qa, &qb)
            .unwrap();
        for (k, node) in routed.q.iter().enumerate() {
            assert_eq!(node.as_slice(), reference.node(k), "{embedding}");
        }
    });
    let model = SmallRing { c: 4.0 };
    let (qa, v0) = displaced(SMALL);
    let qb: Vec<f64> = qa.iter().zip(&v0).map(|(q, v)| 0.9 * q + v).collect();
    let (xa, xb) = (
        Vector::<SMALL>::from_column_slice(&qa),
        Vector::<SMALL>::from_column_slice(&qb),
    );
    on_stack(64 << 20, || {
        for embedding in kinds {
            for scheme in [Scheme::Direct, Scheme::Variational] {
                let routed = Problem::new(&model, grid, embedding)
                    .solve_bvp(scheme, xa, xb)
                    .unwrap();
                let reference = Problem::new(&Dense(&model), grid, embedding)
                    .solve_bvp(scheme, xa, xb)
                    .unwrap();
                let gap = relative_gap(&routed, &reference);
                assert!(gap <= 1e-12, "{embedding} {scheme:?}: {gap:e}");
                assert_eq!(
                    routed.warnings, reference.warnings,
                    "{embedding} {scheme:?}"
                );
            }
        }
        // Gauss–Legendre: the run-time form's sparse blocks against the dense ones.
        let embedding = Embedding::gauss_legendre(2).unwrap();
        let routed = Problem::new(&model, grid, embedding)
            .solve_bvp(Scheme::Variational, xa, xb)
            .unwrap();
        let reference = Problem::new(&Dense(&model), grid, embedding)
            .solve_bvp(Scheme::Variational, xa, xb)
            .unwrap();
        let gap = relative_gap(&routed, &reference);
        assert!(gap <= 1e-12, "{embedding}: {gap:e}");
    });
}

/// `Problem::solve_ivp_models` hands each member of a large model to the run-time engine as
/// that member's own `solve_ivp` would, with the problem's options and start: bit for bit on a
/// 2 MiB stack.
#[test]
fn ensembles_of_large_models_run_on_the_run_time_engine() {
    let grid = Grid::new(0.0, 1.0, 20).unwrap();
    let (q0, v0) = displaced(RING);
    let (x0, u0) = (
        Vector::<RING>::from_column_slice(&q0),
        Vector::<RING>::from_column_slice(&v0),
    );
    let members = [SineGordon { c: 4.0 }, SineGordon { c: 1.5 }];
    on_stack(2 << 20, || {
        for embedding in [Embedding::midpoint(), Embedding::gauss_legendre(2).unwrap()] {
            let problem = Problem::new(&members[0], grid, embedding).with_start(Start::SecondOrder);
            let runs = problem.solve_ivp_models(
                Scheme::Variational,
                &members,
                |m| m,
                x0,
                u0,
                &varembed::Ensemble::serial(),
            );
            for (run, member) in runs.iter().zip(&members) {
                let alone = Problem::new(member, grid, embedding)
                    .with_start(Start::SecondOrder)
                    .solve_ivp(Scheme::Variational, x0, u0)
                    .unwrap();
                assert_eq!(run.as_ref().unwrap().q, alone.q, "{embedding}");
            }
        }
    });
}

/// `f` on a thread of `stack` bytes.
fn on_thread<R: Send>(stack: usize, f: impl FnOnce() -> R + Send) -> R {
    std::thread::scope(|scope| {
        std::thread::Builder::new()
            .stack_size(stack)
            .spawn_scoped(scope, f)
            .unwrap()
            .join()
            .unwrap()
    })
}

/// The initial and boundary value problems of `model` for each of `cases`, kept on the
/// const-generic path, on `n` steps from [`displaced`] data.
fn const_generic_runs<const D: usize, L: Lagrangian<D> + Sync>(
    model: &L,
    n: usize,
    cases: &[(Embedding, Scheme)],
) -> Vec<Solution<D>> {
    let grid = Grid::new(0.0, 0.1, n).unwrap();
    let (q0, v0) = displaced(D);
    let (q0, v0) = (
        Vector::<D>::from_column_slice(&q0),
        Vector::<D>::from_column_slice(&v0),
    );
    let dense = Dense(model);
    let mut runs = Vec::new();
    for &(embedding, scheme) in cases {
        let problem = Problem::new(&dense, grid, embedding);
        runs.push(problem.solve_ivp(scheme, q0, v0).unwrap());
        runs.push(problem.solve_bvp(scheme, q0, v0).unwrap());
    }
    runs
}

/// A const-generic model's solves hold `D × D` blocks on the stack (a `Hessian<64>` by value
/// is 98 kB): on a thread of 256 KiB they run on a stack segment sized for them, with the nodes
/// of the same solves on a thread of 64 MiB (room enough: no segment there), to the bit; and a
/// solution's values at and between its nodes (`node_values`, `state_at`, which solve with
/// `∂²L/∂v²`) on a thread of 64 KiB, less than one `Hessian<64>`.
#[test]
fn const_generic_solves_run_on_a_short_stack() {
    let model = SmallRing { c: 1.0 };
    let backward = Embedding::finite_difference(Side::Backward);
    let cases = [
        (Embedding::midpoint(), Scheme::Variational),
        (Embedding::midpoint(), Scheme::Direct),
        (backward, Scheme::Variational),
        (backward, Scheme::Direct),
    ];
    let short = on_thread(256 << 10, || const_generic_runs(&model, 6, &cases));
    let roomy = on_thread(64 << 20, || const_generic_runs(&model, 6, &cases));
    for (short, roomy) in short.iter().zip(&roomy) {
        assert_eq!(short.q, roomy.q);
    }
    let run = &short[0];
    let (values, state) = on_thread(64 << 10, || {
        let dense = Dense(&model);
        (
            run.node_values(&dense).unwrap(),
            run.state_at(0.05, &dense).unwrap(),
        )
    });
    let (roomy_values, roomy_state) = on_thread(64 << 20, || {
        let dense = Dense(&model);
        (
            run.node_values(&dense).unwrap(),
            run.state_at(0.05, &dense).unwrap(),
        )
    });
    assert_eq!((values.v, values.p), (roomy_values.v, roomy_values.p));
    assert_eq!((state.q, state.v), (roomy_state.q, roomy_state.v));
}

/// The target size: the sine-Gordon ring of 256 sites kept on the const-generic path (no
/// run-time form) on a 2 MiB thread (the stack of a test thread or a rayon worker), where it
/// overflowed before: the midpoint rule's first step (the discrete Legendre start, a dense
/// `256 × 256` Newton) and its boundary value problem on two steps. Every three-point embedding
/// and scheme, with the stability check of longer runs (too slow for this suite at this size),
/// passed the same way when the segment's size was measured (`core/src/stack.rs`).
#[test]
fn a_const_generic_ring_of_256_runs_on_a_two_megabyte_stack() {
    let model = Dense(SineGordon { c: 1.0 });
    let (q0, v0) = displaced(RING);
    let (q0, v0) = (
        Vector::<RING>::from_column_slice(&q0),
        Vector::<RING>::from_column_slice(&v0),
    );
    let problem = |n| {
        Problem::new(
            &model,
            Grid::new(0.0, 0.1, n).unwrap(),
            Embedding::midpoint(),
        )
    };
    let (ivp, bvp) = on_thread(2 << 20, || {
        let ivp = problem(1).solve_ivp(Scheme::Variational, q0, v0);
        let bvp = problem(2).solve_bvp(Scheme::Variational, q0, v0);
        (ivp.map(|run| run.q.len()), bvp.map(|run| run.q.len()))
    });
    assert_eq!((ivp, bvp), (Ok(2), Ok(3)));
}
