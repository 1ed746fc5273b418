//! Boundary value problems of run-time-dimension models against the const-generic solver: the
//! same scheme on the same FPUT chain (between walls, and a ring) gives the same nodes in the
//! same number of Newton iterations, for every classical embedding; a large chain's boundary
//! value problem returns the nodes of its initial value problem; bad input gives typed errors.

use varembed::{
    DynProblem, DynSolution, Embedding, Error, Grid, Location, NewtonOptions, Scheme, Side, Vector,
    lagrangian,
};
use varembed_tests::models::chain::{FputChain, displacement};
use varembed_tests::models::generated::fput16;
use varembed_tests::models::generated::ring12::{N as RING, Ring};

/// Every classical embedding the run-time-dimension boundary value problems offer, each with
/// both schemes.
pub(crate) fn kinds() -> Vec<(Embedding, Scheme)> {
    let mut out = Vec::new();
    for side in [Side::Backward, Side::Forward] {
        for embedding in [
            Embedding::finite_difference(side),
            Embedding::asymmetric(side),
        ] {
            for scheme in [Scheme::Direct, Scheme::Variational] {
                out.push((embedding, scheme));
            }
        }
    }
    for embedding in [Embedding::midpoint(), Embedding::trapezoidal()] {
        for scheme in [Scheme::Direct, Scheme::Variational] {
            out.push((embedding, scheme));
        }
    }
    out
}

/// The largest gap between the flat nodes `q` and the const-generic nodes, relative to the
/// largest node value.
fn relative_gap<const D: usize>(q: &[f64], reference: &[Vector<D>]) -> f64 {
    let flat: Vec<f64> = reference.iter().flat_map(|x| x.iter().copied()).collect();
    assert_eq!(q.len(), flat.len());
    let scale = flat.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    q.iter()
        .zip(&flat)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
        / scale
}

/// The boundary value problem `(qa, qb)` of `scheme` under `embedding`, solved through
/// `DynProblem` for the generated model and for the hand-written one: each must give the
/// const-generic `reference`'s nodes (to 1e-12 relative) in as many Newton iterations. Returns
/// both solutions for the caller's further checks.
fn both_match<G, H, const D: usize>(
    (generated, hand_written): (&G, &H),
    (grid, embedding, scheme): (Grid, Embedding, Scheme),
    (qa, qb): (&[f64], &[f64]),
    reference: &varembed::Solution<D>,
) -> [DynSolution; 2]
where
    G: varembed::DynLagrangian,
    H: varembed::DynLagrangian,
{
    let solved = [
        (
            "generated",
            DynProblem::new(generated, grid, embedding).solve_bvp(scheme, qa, qb),
        ),
        (
            "hand-written",
            DynProblem::new(hand_written, grid, embedding).solve_bvp(scheme, qa, qb),
        ),
    ];
    solved.map(|(name, solution)| {
        let solution = solution.unwrap();
        let gap = relative_gap(&solution.q, &reference.q);
        assert!(gap <= 1e-12, "{name} {embedding} {scheme}: gap {gap:e}");
        assert_eq!(
            solution.run.newton_iterations, reference.newton_iterations,
            "{name} {embedding} {scheme}"
        );
        // Well-posed, as the const-generic path finds it.
        assert_eq!(
            solution.warnings, reference.warnings,
            "{name} {embedding} {scheme}"
        );
        assert!(solution.warnings.is_empty(), "{name} {embedding} {scheme}");
        solution
    })
}

#[test]
fn the_sparse_lu_solve_matches_the_const_generic_solve_for_every_scheme() {
    let (alpha, beta) = (0.25, 0.5);
    let model = fput16::Fput { alpha, beta };
    let chain = FputChain {
        n: 16,
        alpha,
        beta,
        periodic: false,
    };
    let grid = Grid::new(0.0, 2.0, 50).unwrap();
    let (qa, qb) = (displacement(16, 0.3, 0.0), displacement(16, 0.3, 1.1));
    let (qa16, qb16): ([f64; 16], [f64; 16]) = (
        qa.clone().try_into().unwrap(),
        qb.clone().try_into().unwrap(),
    );
    for (embedding, scheme) in kinds() {
        let reference = varembed_tests::problem(&model, grid, embedding)
            .solve_bvp(scheme, qa16, qb16)
            .unwrap();
        assert!(reference.newton_iterations >= 2, "{embedding} {scheme}");
        let kind = (grid, embedding, scheme);
        for solution in both_match((&model, &chain), kind, (&qa, &qb), &reference) {
            assert_eq!(solution.len(), 51);
            assert_eq!(solution.indices, (0..=50).collect::<Vec<_>>());
            assert_eq!(solution.run.last, qb);
            // Three consecutive nodes, each block tridiagonal: the time-major band is d or d + 1.
            assert!(
                (16..=17).contains(&solution.run.band),
                "{}",
                solution.run.band
            );
            assert_eq!(solution.run.explicit_steps, 0);
        }
    }
}

/// A model whose `∂²L/∂v²` depends on `x`, whose `∂²L/∂x∂v` is not symmetric and which depends
/// on `t` (the `[f64; 8]` model of the Gauss–Legendre tests, both traits from one source):
/// the run-time boundary value problem gives the const-generic nodes for every embedding and
/// scheme, to 1e-12.
#[test]
fn a_model_with_every_block_varying_matches_the_const_generic_solve() {
    use super::gauss_legendre::{M, Twisted, initial};
    let model = Twisted { k: 1.5 };
    let grid = Grid::new(0.0, 1.0, 40).unwrap();
    let (qa, v0) = initial();
    let qb: Vec<f64> = qa.iter().zip(&v0).map(|(q, v)| q + 0.5 * v).collect();
    let (qa8, qb8) = (
        Vector::<M>::from_column_slice(&qa),
        Vector::<M>::from_column_slice(&qb),
    );
    for (embedding, scheme) in kinds() {
        let reference = varembed_tests::problem(&model, grid, embedding)
            .solve_bvp(scheme, qa8, qb8)
            .unwrap();
        assert!(reference.newton_iterations >= 2, "{embedding} {scheme}");
        let run = DynProblem::new(&model, grid, embedding)
            .solve_bvp(scheme, &qa, &qb)
            .unwrap();
        let gap = relative_gap(&run.q, &reference.q);
        assert!(gap <= 1e-12, "{embedding} {scheme}: {gap:e}");
    }
}

#[test]
fn a_ring_which_is_not_banded_matches_the_const_generic_ring() {
    let (alpha, beta) = (0.3, 0.4);
    let oracle = Ring { alpha, beta };
    let chain = FputChain {
        n: RING,
        alpha,
        beta,
        periodic: true,
    };
    let grid = Grid::new(0.0, 1.0, 40).unwrap();
    let (qa, qb) = (displacement(RING, 0.3, 0.4), displacement(RING, 0.25, 2.0));
    let (qa12, qb12): ([f64; RING], [f64; RING]) = (
        qa.clone().try_into().unwrap(),
        qb.clone().try_into().unwrap(),
    );
    for (embedding, scheme) in kinds() {
        let reference = varembed_tests::problem(&oracle, grid, embedding)
            .solve_bvp(scheme, qa12, qb12)
            .unwrap();
        let kind = (grid, embedding, scheme);
        both_match((&oracle, &chain), kind, (&qa, &qb), &reference);
    }
}

#[test]
fn from_a_guess_the_solve_matches_the_const_generic_solve() {
    let model = fput16::Fput {
        alpha: 0.25,
        beta: 0.5,
    };
    let grid = Grid::new(0.0, 1.0, 30).unwrap();
    let guess: Vec<Vector<16>> = (0..=30)
        .map(|k| Vector::<16>::from_iterator(displacement(16, 0.2, 0.05 * k as f64)))
        .collect();
    let flat: Vec<f64> = guess.iter().flat_map(|x| x.iter().copied()).collect();
    let embedding = Embedding::finite_difference(Side::Forward);
    for scheme in [Scheme::Direct, Scheme::Variational] {
        let reference = varembed_tests::problem(&model, grid, embedding)
            .solve_bvp_from(scheme, &guess)
            .unwrap();
        let solution = DynProblem::new(&model, grid, embedding)
            .solve_bvp_from(scheme, &flat)
            .unwrap();
        assert!(relative_gap(&solution.q, &reference.q) <= 1e-12);
        assert_eq!(solution.run.newton_iterations, reference.newton_iterations);
    }
}

/// A chain of 300 particles (walls, and a ring): the boundary value problem between the first
/// and last nodes of an initial value run returns that run's nodes.
#[test]
fn a_large_chain_returns_the_nodes_of_its_initial_value_run() {
    for periodic in [false, true] {
        let chain = FputChain {
            n: 300,
            alpha: 0.25,
            beta: 0.5,
            periodic,
        };
        let grid = Grid::new(0.0, 1.0, 40).unwrap();
        let q0 = displacement(300, 0.3, 0.0);
        let v0: Vec<f64> = q0.iter().map(|q| 0.2 * q).collect();
        for (side, scheme) in [
            (Side::Backward, Scheme::Direct),
            (Side::Forward, Scheme::Variational),
        ] {
            let problem = DynProblem::new(&chain, grid, Embedding::finite_difference(side));
            let run = problem.solve_ivp(scheme, &q0, &v0).unwrap();
            let bvp = problem
                .solve_bvp(scheme, run.node(0), run.node(40))
                .unwrap();
            let gap = bvp
                .q
                .iter()
                .zip(&run.q)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(
                gap <= 1e-10,
                "periodic {periodic} {side:?} {scheme}: {gap:e}"
            );
            assert!(run.warnings.is_empty() && bvp.warnings.is_empty());
        }
    }
}

#[test]
fn bad_input_gives_typed_errors() {
    let chain = FputChain {
        n: 8,
        alpha: 0.25,
        beta: 0.5,
        periodic: false,
    };
    let grid = Grid::new(0.0, 1.0, 10).unwrap();
    let fde = DynProblem::new(&chain, grid, Embedding::finite_difference(Side::Backward));
    let (qa, qb) = (vec![0.1; 8], vec![0.2; 8]);
    let v = Scheme::Variational;

    assert!(matches!(
        fde.solve_bvp(v, &qa[..7], &qb),
        Err(Error::WrongLength {
            what: "qa",
            expected: 8,
            found: 7
        })
    ));
    assert!(matches!(
        fde.solve_bvp(v, &qa, &[0.0; 9]),
        Err(Error::WrongLength {
            what: "qb",
            expected: 8,
            found: 9
        })
    ));
    assert!(matches!(
        fde.solve_bvp_from(v, &[0.0; 8 * 11 + 3]),
        Err(Error::WrongDimension { dimension: 8, .. })
    ));
    assert!(matches!(
        fde.solve_bvp_from(v, &[0.0; 8 * 10]),
        Err(Error::WrongLength {
            expected: 11,
            found: 10,
            ..
        })
    ));
    let mut bad = qa.clone();
    bad[3] = f64::NAN;
    match fde.solve_bvp(v, &bad, &qb) {
        Err(Error::NonFiniteInput { what }) => assert!(what.contains("Q_0 at a"), "{what}"),
        other => panic!("{other:?}"),
    }
    match fde.solve_bvp(v, &qa, &[f64::INFINITY; 8]) {
        Err(Error::NonFiniteInput { what }) => assert!(what.contains("Q_10 at b"), "{what}"),
        other => panic!("{other:?}"),
    }
    let mut guess = vec![0.0; 8 * 11];
    guess[8 * 4 + 2] = f64::NAN;
    match fde.solve_bvp_from(v, &guess) {
        Err(Error::NonFiniteInput { what }) => assert!(what.contains("Q_4[2]"), "{what}"),
        other => panic!("{other:?}"),
    }
    let nan_constant = fput16::Fput {
        alpha: f64::NAN,
        beta: 0.5,
    };
    let dyn16 = DynProblem::new(
        &nan_constant,
        grid,
        Embedding::finite_difference(Side::Backward),
    );
    match dyn16.solve_bvp(v, &[0.0; 16], &[0.0; 16]) {
        Err(Error::NonFiniteInput { what }) => assert!(what.contains("alpha"), "{what}"),
        other => panic!("{other:?}"),
    }
    let fractional = Embedding::grunwald_letnikov(Side::Backward, 0.7).unwrap();
    let gauss = Embedding::gauss_legendre(2).unwrap();
    for (embedding, scheme) in [
        (fractional, Scheme::Direct),
        (fractional, Scheme::Variational),
        (gauss, Scheme::Direct),
    ] {
        let problem = DynProblem::new(&chain, grid, embedding);
        assert!(
            matches!(
                problem.solve_bvp(scheme, &qa, &qb),
                Err(Error::Unsupported { .. })
            ),
            "{embedding}"
        );
        assert!(matches!(
            problem.solve_bvp_from(scheme, &[0.0; 88]),
            Err(Error::Unsupported { .. })
        ));
    }
    // Gauss–Legendre's collocation boundary value problem: the same typed errors.
    let gl = DynProblem::new(&chain, grid, gauss);
    match gl.solve_bvp(v, &qa[..7], &qb) {
        Err(Error::WrongLength { .. }) => {}
        other => panic!("{other:?}"),
    }
    let mut guess = vec![0.1; 88];
    guess[4 * 8 + 2] = f64::NAN;
    match gl.solve_bvp_from(v, &guess) {
        Err(Error::NonFiniteInput { what }) => assert!(what.contains("Q_4[2]"), "{what}"),
        other => panic!("{other:?}"),
    }
    let capped_gl = DynProblem::new(&chain, grid, gauss).with_newton(NewtonOptions {
        max_iterations: 1,
        ..NewtonOptions::default()
    });
    assert!(matches!(
        capped_gl.solve_bvp(v, &[0.5; 8], &[-0.5; 8]),
        Err(Error::NewtonDidNotConverge {
            at: Location::Newton(1),
            iterations: 1,
            ..
        })
    ));
    // Too few iterations for a nonlinear solve: the iteration count and residual are reported.
    let capped = DynProblem::new(&chain, grid, Embedding::finite_difference(Side::Forward))
        .with_newton(NewtonOptions {
            max_iterations: 1,
            ..NewtonOptions::default()
        });
    assert!(matches!(
        capped.solve_bvp(v, &[0.5; 8], &[-0.5; 8]),
        Err(Error::NewtonDidNotConverge {
            at: Location::Newton(1),
            iterations: 1,
            ..
        })
    ));
}

/// `L = ½ v₀² − ½ x₀² − ½ x₁²`, no kinetic term in the second coordinate: `∂²L/∂v²` is singular, reported at the
/// first quadrature node of the guess as for the const-generic path.
#[test]
fn a_degenerate_model_is_reported_at_a_node() {
    const TWO: usize = 2;
    #[lagrangian]
    fn half(x: [f64; TWO], v: [f64; TWO]) -> f64 {
        let mut l = 0.0;
        for i in 0..TWO - 1 {
            l += 0.5 * v[i] * v[i] - 0.5 * x[i] * x[i];
        }
        l - 0.5 * x[TWO - 1] * x[TWO - 1]
    }
    let grid = Grid::new(0.0, 1.0, 10).unwrap();
    let embedding = Embedding::finite_difference(Side::Backward);
    let dynamic = DynProblem::new(&Half, grid, embedding).solve_bvp(
        Scheme::Variational,
        &[0.0, 0.0],
        &[1.0, 1.0],
    );
    let reference = varembed_tests::problem(&Half, grid, embedding).solve_bvp(
        Scheme::Variational,
        [0.0, 0.0],
        [1.0, 1.0],
    );
    assert!(matches!(
        dynamic,
        Err(Error::DegenerateLagrangian {
            at: Location::Node(1),
            ..
        })
    ));
    assert!(matches!(
        reference,
        Err(Error::DegenerateLagrangian {
            at: Location::Node(1),
            ..
        })
    ));
    // Gauss–Legendre's boundary value problem checks its guess the same way, on both paths.
    let gauss = Embedding::gauss_legendre(2).unwrap();
    let dynamic = DynProblem::new(&Half, grid, gauss).solve_bvp(
        Scheme::Variational,
        &[0.0, 0.0],
        &[1.0, 1.0],
    );
    let fixed = varembed_tests::problem(&Half, grid, gauss).solve_bvp(
        Scheme::Variational,
        [0.0, 0.0],
        [1.0, 1.0],
    );
    for result in [dynamic.map(|_| ()), fixed.map(|_| ())] {
        assert!(matches!(
            result,
            Err(Error::DegenerateLagrangian {
                at: Location::Node(1),
                ..
            })
        ));
    }
}

/// The observed orders of the run-time boundary value problems on a harmonic chain of 24
/// masses against its exact solution (normal modes), the ends taken from it: 2 for the
/// symmetric embeddings, 1 for the direct Gauss-FDEσ scheme and 2 for its variational one on
/// this separable model (the largest node error over two halvings of the step). `T = 1.2`
/// keeps every mode short of a conjugate point (`ω T < π`).
#[test]
fn the_order_on_a_harmonic_chain_is_the_theorys() {
    use super::gauss_legendre::{harmonic_chain, harmonic_chain_at};
    let (chain, q0, v0) = harmonic_chain();
    let n = chain.n;
    let t_end = 1.2;
    let exact = |t: f64| harmonic_chain_at(n, (&q0, &v0), t);
    let qb = exact(t_end);
    let fde = |side| Embedding::finite_difference(side);
    for (embedding, scheme, expected) in [
        (Embedding::midpoint(), Scheme::Direct, 2.0),
        (Embedding::midpoint(), Scheme::Variational, 2.0),
        (Embedding::trapezoidal(), Scheme::Direct, 2.0),
        (Embedding::trapezoidal(), Scheme::Variational, 2.0),
        (fde(Side::Backward), Scheme::Direct, 1.0),
        (fde(Side::Forward), Scheme::Direct, 1.0),
        // On a separable Lagrangian the variational Gauss-FDEσ rows are Störmer–Verlet's.
        (fde(Side::Backward), Scheme::Variational, 2.0),
        (fde(Side::Forward), Scheme::Variational, 2.0),
    ] {
        let error = |steps: usize| {
            let grid = Grid::new(0.0, t_end, steps).unwrap();
            let solution = DynProblem::new(&chain, grid, embedding)
                .solve_bvp(scheme, &q0, &qb)
                .unwrap();
            assert!(solution.warnings.is_empty(), "{embedding} {scheme}");
            (0..=steps)
                .flat_map(|k| {
                    let reference = exact(grid.t(k));
                    let node = solution.node(k).to_vec();
                    node.into_iter().zip(reference).map(|(a, b)| (a - b).abs())
                })
                .fold(0.0, f64::max)
        };
        let errors = [20, 40, 80].map(error);
        for pair in errors.windows(2) {
            let order = (pair[0] / pair[1]).log2();
            assert!(
                (order - expected).abs() < 0.15,
                "{embedding} {scheme}: errors {errors:?}, order {order:.3}"
            );
        }
    }
}

/// Newton–MINRES gives the sparse LU's nodes for every variational scheme (the FPUT chain, the
/// ring, and the model whose every block varies, with `x`-dependent `L_vv` and non-symmetric
/// `L_xv`), and reports that it was used.
#[test]
fn minres_gives_the_nodes_of_sparse_lu_for_every_variational_scheme() {
    use super::gauss_legendre::{M, Twisted, initial};
    use varembed::{BvpSolver, LinearSolve};
    let chain = FputChain {
        n: 16,
        alpha: 0.25,
        beta: 0.5,
        periodic: false,
    };
    let ring = FputChain {
        periodic: true,
        ..chain
    };
    let twisted = Twisted { k: 1.5 };
    let (tq, tv) = initial();
    let tb: Vec<f64> = tq.iter().zip(&tv).map(|(q, v)| q + 0.5 * v).collect();
    assert_eq!(tq.len(), M);
    let (qa, qb) = (displacement(16, 0.3, 0.0), displacement(16, 0.3, 1.1));
    let cases: [(&dyn varembed::DynLagrangian, &[f64], &[f64]); 3] =
        [(&chain, &qa, &qb), (&ring, &qa, &qb), (&twisted, &tq, &tb)];
    let grid = Grid::new(0.0, 1.0, 40).unwrap();
    for (model, qa, qb) in cases {
        for (embedding, scheme) in kinds() {
            if scheme == Scheme::Direct {
                continue;
            }
            let problem = || DynProblem::new(model, grid, embedding);
            let lu = problem()
                .with_bvp_solver(BvpSolver::SparseLu)
                .solve_bvp(scheme, qa, qb)
                .unwrap();
            let minres = problem()
                .with_bvp_solver(BvpSolver::Minres)
                .solve_bvp(scheme, qa, qb)
                .unwrap();
            assert_eq!(lu.run.linear_solve, Some(LinearSolve::SparseLu));
            assert!(
                matches!(minres.run.linear_solve, Some(LinearSolve::Minres { products }) if products > 0),
                "{embedding}: {:?}",
                minres.run.linear_solve
            );
            let scale = lu.q.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let gap =
                lu.q.iter()
                    .zip(&minres.q)
                    .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(gap <= 1e-11 * scale, "{embedding}: {gap:e}");
            assert_eq!(lu.warnings, minres.warnings, "{embedding}");
        }
    }
}

/// Where the couplings the time-tridiagonal preconditioner leaves out are not small, MINRES
/// exhausts its budget and gives way to sparse LU, and the report counts the products it spent
/// (those its reason names among them); the nodes are the sparse LU's. The model couples two
/// coordinates only through `−κ x₀ x₁`, so the preconditioner is the kinetic part alone and
/// `P⁻¹J = I ∓ κ h² (second difference)⁻¹` spreads over hundreds of eigenvalues of both signs.
#[test]
fn minres_that_gives_way_reports_the_products_it_spent() {
    use varembed::{BvpSolver, LinearSolve};
    #[lagrangian]
    fn coupled(x: &[f64], v: &[f64], n: usize, kappa: f64) -> f64 {
        let mut l = 0.0;
        for i in 0..n {
            l += 0.5 * v[i] * v[i];
        }
        l - kappa * x[0] * x[1]
    }
    let model = Coupled { n: 2, kappa: 1e6 };
    let grid = Grid::new(0.0, 1.0, 2000).unwrap();
    let problem = || DynProblem::new(&model, grid, Embedding::midpoint());
    let (qa, qb) = ([0.1, 0.2], [0.3, -0.1]);
    let minres = problem()
        .with_bvp_solver(BvpSolver::Minres)
        .solve_bvp(Scheme::Variational, &qa, &qb)
        .unwrap();
    let lu = problem()
        .with_bvp_solver(BvpSolver::SparseLu)
        .solve_bvp(Scheme::Variational, &qa, &qb)
        .unwrap();
    match &minres.run.linear_solve {
        Some(LinearSolve::SparseLuAfterMinres { reason, products }) => {
            let spent: usize = reason
                .split("after ")
                .nth(1)
                .and_then(|rest| rest.split(' ').next())
                .and_then(|count| count.parse().ok())
                .unwrap_or_else(|| panic!("no count in {reason}"));
            assert!(reason.contains("MINRES stopped"), "{reason}");
            assert!(
                spent > 0 && *products >= spent,
                "{products} < {spent}: {reason}"
            );
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(lu.q, minres.q);
}

/// Where the time-tridiagonal preconditioner is not positive definite (oscillators with
/// `ω h = 3`, so `2/h² − ω² < 0`), MINRES gives way to sparse LU and says why; the nodes are the
/// sparse LU's. A direct scheme is always solved by sparse LU. A resonance is flagged on the
/// MINRES path as on the sparse LU path (here without giving way: the oscillators are
/// uncoupled, so the preconditioner is the Jacobian itself).
#[test]
fn minres_gives_way_to_sparse_lu_with_the_reason() {
    use varembed::{BvpSolver, LinearSolve, Warning};
    #[lagrangian]
    fn stiff(x: &[f64], v: &[f64], n: usize, omega: f64) -> f64 {
        let mut l = 0.0;
        for i in 0..n {
            l += 0.5 * (v[i] * v[i] - omega * omega * x[i] * x[i]);
        }
        l
    }
    let model = Stiff { n: 3, omega: 30.0 };
    let grid = Grid::new(0.0, 1.0, 10).unwrap();
    let problem = || DynProblem::new(&model, grid, Embedding::midpoint());
    let (qa, qb) = ([0.1, 0.2, 0.3], [0.3, -0.1, 0.2]);
    let lu = problem()
        .with_bvp_solver(BvpSolver::SparseLu)
        .solve_bvp(Scheme::Variational, &qa, &qb)
        .unwrap();
    let minres = problem()
        .with_bvp_solver(BvpSolver::Minres)
        .solve_bvp(Scheme::Variational, &qa, &qb)
        .unwrap();
    match &minres.run.linear_solve {
        // Found before the first product.
        Some(LinearSolve::SparseLuAfterMinres { reason, products }) => {
            assert!(reason.contains("not positive definite"), "{reason}");
            assert_eq!(*products, 0);
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(lu.q, minres.q);
    let direct = problem()
        .with_bvp_solver(BvpSolver::Minres)
        .solve_bvp(Scheme::Direct, &qa, &qb)
        .unwrap();
    assert_eq!(direct.run.linear_solve, Some(LinearSolve::SparseLu));

    // Gauss–Legendre's collocation system is not symmetric: sparse LU, MINRES asked or not.
    let gauss = DynProblem::new(&model, grid, Embedding::gauss_legendre(2).unwrap())
        .with_bvp_solver(BvpSolver::Minres)
        .solve_bvp(Scheme::Variational, &qa, &qb)
        .unwrap();
    assert_eq!(gauss.run.linear_solve, Some(LinearSolve::SparseLu));

    // q̈ = −q from 0 to 1 over [0, π]: no solution; flagged.
    let resonant = Stiff { n: 2, omega: 1.0 };
    let grid = Grid::new(0.0, std::f64::consts::PI, 100).unwrap();
    let run = DynProblem::new(&resonant, grid, Embedding::midpoint())
        .with_bvp_solver(BvpSolver::Minres)
        .solve_bvp(Scheme::Variational, &[0.0; 2], &[1.0; 2])
        .unwrap();
    assert!(
        matches!(run.run.linear_solve, Some(LinearSolve::Minres { .. })),
        "{:?}",
        run.run.linear_solve
    );
    assert!(
        matches!(run.warnings[..], [Warning::IllPosed { .. }]),
        "{:?} {:?}",
        run.warnings,
        run.run.linear_solve
    );
}
