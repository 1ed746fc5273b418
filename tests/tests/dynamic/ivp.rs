//! The run-time-dimension solver against the const-generic one: the same scheme on the same
//! FPUT chain gives the same nodes, through the banded and the reordered (periodic) step
//! solves; strides and observers see the same nodes; bad input gives typed errors.

use varembed::{
    DynProblem, DynSolution, Embedding, Error, Grid, Lagrangian, Location, Scheme, Side, Solution,
    Start, Vector, lagrangian,
};
use varembed_tests::models::chain::{FputChain, displacement};
use varembed_tests::models::dense::ConstGeneric;
use varembed_tests::models::generated::ring12::{N as RING, Ring};
use varembed_tests::models::generated::{fput16, fput64};

/// The const-generic run of `model` (the oracle of the run-time-dimension one) from `q0`, `v0`.
fn const_generic_run<L: Lagrangian<D> + Sync, const D: usize>(
    model: &L,
    (grid, embedding, scheme): (Grid, Embedding, Scheme),
    q0: &[f64],
    v0: &[f64],
) -> Solution<D> {
    const_generic_run_from(model, (grid, embedding, scheme), q0, v0, Start::Legendre)
}

/// [`const_generic_run`] with `start`.
pub(super) fn const_generic_run_from<L: Lagrangian<D> + Sync, const D: usize>(
    model: &L,
    (grid, embedding, scheme): (Grid, Embedding, Scheme),
    q0: &[f64],
    v0: &[f64],
    start: Start,
) -> Solution<D> {
    varembed_tests::problem(model, grid, embedding)
        .solve_ivp_with(
            scheme,
            Vector::<D>::from_column_slice(q0),
            Vector::<D>::from_column_slice(v0),
            start,
        )
        .unwrap()
}

/// The largest gap between every node of `run` and of `reference`.
fn node_gap<const D: usize>(run: &DynSolution, reference: &Solution<D>) -> f64 {
    (0..reference.q.len())
        .map(|k| {
            let node = run.node(k);
            (0..D)
                .map(|i| (node[i] - reference.q[k][i]).abs())
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

const KINDS: [(Side, Scheme); 4] = [
    (Side::Backward, Scheme::Direct),
    (Side::Backward, Scheme::Variational),
    (Side::Forward, Scheme::Direct),
    (Side::Forward, Scheme::Variational),
];

#[test]
fn the_banded_run_matches_the_const_generic_run_for_every_scheme() {
    let (alpha, beta) = (0.25, 0.5);
    let chain = FputChain {
        n: 16,
        alpha,
        beta,
        periodic: false,
    };
    let generated = fput16::Fput { alpha, beta };
    let grid = Grid::new(0.0, 10.0, 200).unwrap();
    let q0 = displacement(16, 0.4, 0.0);
    let v0: Vec<f64> = q0.iter().map(|q| 0.5 * q).collect();
    for (side, scheme) in KINDS {
        let embedding = Embedding::finite_difference(side);
        let run = DynProblem::new(&chain, grid, embedding)
            .solve_ivp(scheme, &q0, &v0)
            .unwrap();
        assert_eq!((run.run.band, run.run.reordered), (1, false));
        let reference = const_generic_run::<_, 16>(&generated, (grid, embedding, scheme), &q0, &v0);
        let worst = node_gap(&run, &reference);
        assert!(
            worst < 1e-12,
            "{side:?} {scheme:?}: nodes differ by {worst:.2e}"
        );
        // The same Newton iterations: a wrong step Jacobian would still find the nodes, only
        // more slowly.
        assert_eq!(
            run.run.newton_iterations, reference.newton_iterations,
            "{side:?} {scheme:?}"
        );
        // FPUT's variational σ=+ step is explicit (L_vv = I): no Newton iteration after the
        // start.
        if (side, scheme) == (Side::Forward, Scheme::Variational) {
            assert_eq!(run.run.explicit_steps, 199);
        }
    }
}

#[test]
fn the_periodic_chain_is_reordered_into_a_band_and_matches_the_const_generic_run() {
    let (alpha, beta) = (0.3, 0.2);
    let chain = FputChain {
        n: RING,
        alpha,
        beta,
        periodic: true,
    };
    let generated = Ring { alpha, beta };
    let grid = Grid::new(0.0, 5.0, 100).unwrap();
    let q0 = displacement(RING, 0.3, 0.0);
    let v0 = vec![0.1; RING];
    for (side, scheme) in KINDS {
        let embedding = Embedding::finite_difference(side);
        let run = DynProblem::new(&chain, grid, embedding)
            .solve_ivp(scheme, &q0, &v0)
            .unwrap();
        // Only the direct σ=− Jacobian reads `L_xx`, whose wrap-around entries the ordering
        // folds into a band of half-width 2; the others read `L_vv = I` alone.
        let band = if (side, scheme) == (Side::Backward, Scheme::Direct) {
            2
        } else {
            0
        };
        assert_eq!(
            (run.run.band, run.run.reordered),
            (band, true),
            "{side:?} {scheme:?}"
        );
        let reference =
            const_generic_run::<_, RING>(&generated, (grid, embedding, scheme), &q0, &v0);
        assert_eq!(
            run.run.newton_iterations, reference.newton_iterations,
            "{side:?} {scheme:?}"
        );
        let worst = node_gap(&run, &reference);
        assert!(
            worst < 1e-12,
            "{side:?} {scheme:?}: nodes differ by {worst:.2e}"
        );
    }
}

#[test]
fn a_stride_and_an_observer_see_the_nodes_of_the_full_run() {
    let chain = FputChain {
        n: 40,
        alpha: 0.25,
        beta: 0.0,
        periodic: false,
    };
    let grid = Grid::new(0.0, 3.0, 95).unwrap();
    let problem = DynProblem::new(&chain, grid, Embedding::finite_difference(Side::Backward));
    let q0 = displacement(40, 0.5, 0.0);
    let v0 = vec![0.0; 40];
    let full = problem.solve_ivp(Scheme::Direct, &q0, &v0).unwrap();
    let strided = problem
        .solve_ivp_every(Scheme::Direct, &q0, &v0, 10)
        .unwrap();
    assert_eq!(
        strided.indices,
        vec![0, 10, 20, 30, 40, 50, 60, 70, 80, 90, 95]
    );
    for (j, &k) in strided.indices.iter().enumerate() {
        assert_eq!(strided.node(j), full.node(k), "node {k}");
    }
    let mut seen = Vec::new();
    let run = problem
        .run_ivp(Scheme::Direct, &q0, &v0, |node| {
            let previous = full.node(node.index.saturating_sub(1));
            assert_eq!(node.previous, previous, "the node before {}", node.index);
            seen.push(node.index);
        })
        .unwrap();
    assert_eq!(seen, (0..=95).collect::<Vec<_>>());
    assert_eq!(run.last, full.node(95));
    assert_eq!(strided.times()[1], grid.t(10));
    assert!(matches!(
        problem.solve_ivp_every(Scheme::Direct, &q0, &v0, 0),
        Err(Error::InvalidGrid { .. })
    ));
}

#[test]
fn bad_input_gives_typed_errors_naming_it() {
    let chain = FputChain {
        n: 8,
        alpha: 0.25,
        beta: 0.0,
        periodic: false,
    };
    let grid = Grid::new(0.0, 1.0, 10).unwrap();
    let problem = DynProblem::new(&chain, grid, Embedding::finite_difference(Side::Backward));
    let (q0, v0) = (vec![0.1; 8], vec![0.0; 8]);
    assert_eq!(
        problem
            .solve_ivp(Scheme::Direct, &q0[..7], &v0)
            .unwrap_err(),
        Error::WrongLength {
            what: "q0",
            expected: 8,
            found: 7
        }
    );
    let mut bad = q0.clone();
    bad[3] = f64::NAN;
    let message = problem
        .solve_ivp(Scheme::Direct, &bad, &v0)
        .unwrap_err()
        .to_string();
    assert!(message.contains("q0[3]"), "{message}");
    let nan = FputChain {
        alpha: f64::INFINITY,
        ..chain
    };
    let message = DynProblem::new(&nan, grid, Embedding::finite_difference(Side::Backward))
        .solve_ivp(Scheme::Direct, &q0, &v0)
        .unwrap_err()
        .to_string();
    assert!(message.contains("alpha"), "{message}");
    // Gauss–Legendre is variational only, on this path as on the const-generic one.
    let gauss = DynProblem::new(&chain, grid, Embedding::gauss_legendre(2).unwrap());
    assert!(matches!(
        gauss.solve_ivp(Scheme::Direct, &q0, &v0),
        Err(Error::Unsupported { .. })
    ));
}

#[test]
fn an_unstable_explicit_run_is_an_error_with_its_step_never_ok() {
    // The variational σ=+ step is Störmer–Verlet: stable for h ω_max < 2, and the chain's
    // highest frequency is close to 2. At h = 1.2 (h ω ≈ 2.4) the sawtooth mode grows.
    let chain = FputChain {
        n: 64,
        alpha: 0.25,
        beta: 0.0,
        periodic: false,
    };
    let grid = Grid::new(0.0, 1200.0, 1000).unwrap();
    let problem = DynProblem::new(&chain, grid, Embedding::finite_difference(Side::Forward));
    let q0 = displacement(64, 1e-3, 0.0);
    let error = problem
        .solve_ivp(Scheme::Variational, &q0, &vec![0.0; 64])
        .unwrap_err();
    // Proven at the initial data, with the eigenvalue of the sawtooth mode: the const-generic
    // check's (from the step map's Schur form at step 2), or a bound of it from within.
    let Error::Unstable {
        at: Location::Step(0),
        re,
        im,
        largest_stable_step,
    } = error
    else {
        panic!("expected the instability at the initial data, got {error}");
    };
    // The const-generic path's check (a model of 64 degrees of freedom with loops would go to
    // the run-time engine: kept on the const-generic path).
    let oracle = varembed_tests::problem(
        &ConstGeneric(fput64::Fput {
            alpha: 0.25,
            beta: 0.0,
        }),
        grid,
        Embedding::finite_difference(Side::Forward),
    )
    .solve_ivp(
        Scheme::Variational,
        Vector::<64>::from_column_slice(&q0),
        Vector::<64>::zeros(),
    )
    .unwrap_err();
    let Error::Unstable {
        re: exact,
        largest_stable_step: exact_step,
        ..
    } = oracle
    else {
        panic!("the const-generic check: {oracle}");
    };
    // The remedy: the largest stable step 2/ω of the chain's fastest mode. The const-generic
    // check has it from the eigenvalues of the linearisation; this one from its bound of the
    // sawtooth eigenvalue, within 1 %. The chain's exact fastest mode, of the fixed-end
    // springs `κ = 2 − 2cos(64π/65)` (α's term is of the order of the displacement, 1e-3):
    let (step, exact_step) = (largest_stable_step.unwrap(), exact_step.unwrap());
    let kappa = 2.0 - 2.0 * (64.0 * std::f64::consts::PI / 65.0).cos();
    assert!(
        (exact_step - 2.0 / kappa.sqrt()).abs() < 1e-2 * exact_step,
        "{exact_step} against 2/√κ = {}",
        2.0 / kappa.sqrt()
    );
    assert!(
        step >= exact_step && step < 1.01 * exact_step,
        "{step} against {exact_step}"
    );
    assert_eq!(im, 0.0);
    assert!(
        exact <= re && re < -1.0 && re - exact < 0.01 * exact.abs(),
        "{re} against {exact}"
    );
    // Without the check's proof (a step just inside the limit), the run is not stopped: at
    // h ω_max ≈ 1.9 Störmer–Verlet is stable and the run ends normally.
    let stable = Grid::new(0.0, 950.0, 1000).unwrap();
    DynProblem::new(&chain, stable, Embedding::finite_difference(Side::Forward))
        .solve_ivp(Scheme::Variational, &q0, &vec![0.0; 64])
        .unwrap();
}

#[test]
fn the_runs_match_the_hand_written_loops_of_the_same_schemes() {
    use varembed_tests::models::chain::{
        HandWrittenRun, direct_backward_by_hand, stormer_verlet_by_hand,
    };
    let (alpha, beta) = (0.25, 0.7);
    let chain = FputChain {
        n: 50,
        alpha,
        beta,
        periodic: false,
    };
    let grid = Grid::new(0.0, 10.0, 200).unwrap();
    let q0 = displacement(50, 0.5, 0.0);
    let v0: Vec<f64> = q0.iter().map(|q| -0.3 * q).collect();
    let cases: [(Side, Scheme, HandWrittenRun); 2] = [
        (Side::Backward, Scheme::Direct, |q, v, g, p, o| {
            direct_backward_by_hand(q, v, g, p, o)
        }),
        (Side::Forward, Scheme::Variational, |q, v, g, p, o| {
            stormer_verlet_by_hand(q, v, g, p, o)
        }),
    ];
    for (side, scheme, by_hand) in cases {
        let run = DynProblem::new(&chain, grid, Embedding::finite_difference(side))
            .solve_ivp(scheme, &q0, &v0)
            .unwrap();
        let mut k = 0;
        let mut worst = 0.0f64;
        by_hand(
            &q0,
            &v0,
            (grid.h(), 200),
            (alpha, beta),
            &mut |node: &[f64]| {
                let gap = node
                    .iter()
                    .zip(run.node(k))
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                worst = worst.max(gap);
                k += 1;
            },
        );
        assert_eq!(k, 201);
        assert!(worst < 1e-11, "{side:?} {scheme:?}: {worst:.2e}");
    }
}

#[test]
fn the_generated_run_time_model_takes_the_hand_written_models_steps() {
    use varembed::DynLagrangian;
    use varembed_tests::models::generated::FputChain as Generated;
    let (alpha, beta) = (0.25, 0.7);
    let chain = FputChain {
        n: 64,
        alpha,
        beta,
        periodic: false,
    };
    let generated = Generated { n: 64, alpha, beta };
    assert_eq!(generated.hessian_bandwidth(), Some(1));
    let grid = Grid::new(0.0, 5.0, 100).unwrap();
    let q0 = displacement(64, 0.5, 0.0);
    let v0: Vec<f64> = q0.iter().map(|q| 0.2 * q).collect();
    for (side, scheme) in KINDS {
        let embedding = Embedding::finite_difference(side);
        let by_hand = DynProblem::new(&chain, grid, embedding)
            .solve_ivp(scheme, &q0, &v0)
            .unwrap();
        let run = DynProblem::new(&generated, grid, embedding)
            .solve_ivp(scheme, &q0, &v0)
            .unwrap();
        let gap = run
            .q
            .iter()
            .zip(&by_hand.q)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(gap < 1e-12, "{side:?} {scheme:?}: {gap:.2e}");
        assert_eq!(run.run.newton_iterations, by_hand.run.newton_iterations);
    }
    // A model that cannot be evaluated at its dimension is an error before any step.
    let empty = Generated { n: 0, alpha, beta };
    let error = DynProblem::new(&empty, grid, Embedding::finite_difference(Side::Backward))
        .solve_ivp(Scheme::Direct, &[], &[])
        .unwrap_err();
    assert!(matches!(error, Error::InvalidModel { .. }), "{error}");
}

/// The energies `E_k = ½|V_k|² + U(Q_k)` with `V_k = (Q_k − Q_{k−1})/h`, every `every`-th
/// node, of a run of `chain` from the normal mode `m` at amplitude `amplitude`, at rest.
fn energies(
    chain: &FputChain,
    (side, scheme): (Side, Scheme),
    (m, amplitude): (usize, f64),
    (t_end, steps, every): (f64, usize, usize),
) -> Vec<f64> {
    use varembed::DynLagrangian;
    let n = chain.n;
    let q0: Vec<f64> = (0..n)
        .map(|i| {
            let phase = std::f64::consts::PI * (m * (i + 1)) as f64 / (n + 1) as f64;
            amplitude * phase.sin()
        })
        .collect();
    let grid = Grid::new(0.0, t_end, steps).unwrap();
    let h = grid.h();
    let mut samples = Vec::new();
    let mut v = vec![0.0; n];
    DynProblem::new(chain, grid, Embedding::finite_difference(side))
        .run_ivp(scheme, &q0, &vec![0.0; n], |node| {
            if node.index > 0 && node.index % every == 0 {
                for ((v, q), p) in v.iter_mut().zip(node.q).zip(node.previous) {
                    *v = (q - p) / h;
                }
                samples.push(chain.energy(node.q, &v, node.t));
            }
        })
        .unwrap();
    samples
}

/// 10⁴ implicit steps at d = 4096, and the energy behaves as at d = 64: the two chains start
/// in the normal mode of the same wave number (mode 8 of 64, mode 504 of 4096: `ω` = 0.3844
/// and 0.3841), so the linear dynamics is the same and so is each scheme's energy history.
/// The direct Gauss-FDE− scheme dissipates (by 30 % to 60 % over [0, 200]), at the same rate at
/// both sizes (to 1 % of the energy at every sample); the variational scheme's energy
/// oscillates without drift, by the same amount at both sizes.
#[test]
fn a_chain_of_4096_particles_takes_ten_thousand_implicit_steps_like_a_small_one() {
    let chain = |n| FputChain {
        n,
        alpha: 0.25,
        beta: 0.0,
        periodic: false,
    };
    let run = (200.0, 10_000, 1000);
    let direct = (Side::Backward, Scheme::Direct);
    let small = energies(&chain(64), direct, (8, 0.05), run);
    let large = energies(&chain(4096), direct, (504, 0.05), run);
    assert_eq!((small.len(), large.len()), (10, 10));
    let (e0_small, e0_large) = (small[0], large[0]);
    for (k, (s, l)) in small.iter().zip(&large).enumerate() {
        let (rs, rl) = (s / e0_small, l / e0_large);
        assert!(
            (rs - rl).abs() < 0.01,
            "t = {}: E/E_1 = {rs:.4} at d = 64, {rl:.4} at d = 4096",
            20 * (k + 1)
        );
    }
    let lost = 1.0 - small[9] / small[0];
    println!(
        "direct: E(200)/E(20) = {:.4} at d = 64, {:.4} at d = 4096",
        small[9] / small[0],
        large[9] / large[0]
    );
    assert!(
        (0.3..0.6).contains(&lost),
        "the direct scheme lost {lost:.3} of its energy"
    );
    // The variational energy does not drift: sampled with the backward velocity it oscillates
    // by O(hω) about a constant, by the same amount at both sizes.
    let variational = (Side::Backward, Scheme::Variational);
    let deviation = |n, m| {
        let e = energies(&chain(n), variational, (m, 0.05), run);
        e.iter().map(|x| (x / e[0] - 1.0).abs()).fold(0.0, f64::max)
    };
    let (small, large) = (deviation(64, 8), deviation(4096, 504));
    println!("variational: max |E/E(20) − 1| = {small:.3e} at d = 64, {large:.3e} at d = 4096");
    assert!(small < 1e-2 && large < 1e-2, "{small:.2e}, {large:.2e}");
    assert!(
        (small - large).abs() < 0.1 * small,
        "{small:.3e} at d = 64, {large:.3e} at d = 4096"
    );
}

const COUPLED: usize = 12;

/// A chain with a velocity coupling `L_xv` (a magnetic-like term `x_i v_{i+1}`) and a
/// position-dependent mass: every block of its Hessian is nonzero, `L_xv` is not symmetric,
/// and no step is affine. Written with loops, the macro gives it both `Lagrangian<12>` and
/// `DynLagrangian`.
#[lagrangian]
fn coupled(x: [f64; COUPLED], v: [f64; COUPLED], a: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..COUPLED {
        l += 0.5 * (1.0 + 0.1 * x[i] * x[i]) * v[i] * v[i] - 0.5 * x[i] * x[i];
    }
    for i in 0..COUPLED - 1 {
        l += a * x[i] * v[i + 1] - 0.25 * (x[i + 1] - x[i]).powi(4);
    }
    l
}

#[test]
fn every_block_enters_the_banded_jacobian_as_in_the_const_generic_run() {
    use varembed::DynLagrangian;
    let model = Coupled { a: 0.4 };
    assert_eq!(DynLagrangian::hessian_bandwidth(&model), Some(1));
    let grid = Grid::new(0.0, 3.0, 60).unwrap();
    let q0 = displacement(COUPLED, 0.6, 0.0);
    let v0: Vec<f64> = q0.iter().map(|q| 0.4 - q).collect();
    for (side, scheme) in KINDS {
        let embedding = Embedding::finite_difference(side);
        let run = DynProblem::new(&model, grid, embedding)
            .solve_ivp(scheme, &q0, &v0)
            .unwrap();
        // The direct σ=+ step is affine (its Jacobian `L_vv/h` is read at the previous node);
        // every other step runs Newton.
        let affine = (side, scheme) == (Side::Forward, Scheme::Direct);
        assert_eq!(
            run.run.explicit_steps,
            if affine { 59 } else { 0 },
            "{side:?} {scheme:?}"
        );
        let reference =
            const_generic_run::<_, COUPLED>(&model, (grid, embedding, scheme), &q0, &v0);
        let worst = node_gap(&run, &reference);
        assert!(
            worst < 1e-12,
            "{side:?} {scheme:?}: nodes differ by {worst:.2e}"
        );
        // Quadratic convergence with the exact Jacobian: the same iterations up to the
        // rounding of the Jacobian's entries (summed in another order), which moves a step
        // across the tolerance now and then. A wrong block would cost many more.
        let (ours, theirs) = (run.run.newton_iterations, reference.newton_iterations);
        assert!(
            ours.abs_diff(theirs) * 30 <= theirs,
            "{side:?} {scheme:?}: {ours} against {theirs}"
        );
    }
}

/// A model with its promises about its Hessian changed: the bandwidth it states, and which
/// entries of `L_xx` it lists (`lists(x, i, j)`; `L_xv`, `L_vv` are listed whole). Everything
/// else is the model's.
struct Altered<L> {
    model: L,
    bandwidth: Option<usize>,
    lists: fn(&[f64], usize, usize) -> bool,
}

impl<L: varembed::DynLagrangian> Altered<L> {
    /// `model` stating `bandwidth`, every entry listed.
    fn claiming(model: L, bandwidth: Option<usize>) -> Self {
        Altered {
            model,
            bandwidth,
            lists: |_, _, _| true,
        }
    }
}

impl<L: varembed::DynLagrangian> varembed::DynLagrangian for Altered<L> {
    fn dimension(&self) -> usize {
        self.model.dimension()
    }
    fn value(&self, x: &[f64], v: &[f64], t: f64) -> f64 {
        self.model.value(x, v, t)
    }
    fn force(&self, x: &[f64], v: &[f64], t: f64, f: &mut [f64]) {
        self.model.force(x, v, t, f)
    }
    fn momentum(&self, x: &[f64], v: &[f64], t: f64, p: &mut [f64]) {
        self.model.momentum(x, v, t, p)
    }
    fn hessian(&self, x: &[f64], v: &[f64], t: f64, out: &mut varembed::SparseHessian) {
        let mut all = varembed::SparseHessian::new(self.dimension());
        self.model.hessian(x, v, t, &mut all);
        for &(i, j, value) in all.xx.entries() {
            if (self.lists)(x, i, j) {
                out.xx.add(i, j, value);
            }
        }
        for &(i, j, value) in all.xv.entries() {
            out.xv.add(i, j, value);
        }
        for &(i, j, value) in all.vv.entries() {
            out.vv.add(i, j, value);
        }
    }
    fn hessian_dependence(&self) -> varembed::HessianDependence {
        self.model.hessian_dependence()
    }
    fn hessian_bandwidth(&self) -> Option<usize> {
        self.bandwidth
    }
}

#[test]
fn a_wrong_bandwidth_claim_costs_a_reordering_never_the_answer() {
    use varembed::DynLagrangian;
    let chain = FputChain {
        n: 30,
        alpha: 0.25,
        beta: 0.5,
        periodic: false,
    };
    let grid = Grid::new(0.0, 4.0, 80).unwrap();
    let q0 = displacement(30, 0.5, 0.0);
    let v0 = vec![0.0; 30];
    let embedding = Embedding::finite_difference(Side::Backward);
    let honest = DynProblem::new(&chain, grid, embedding)
        .solve_ivp(Scheme::Direct, &q0, &v0)
        .unwrap();
    // The chain claiming a diagonal Hessian.
    let wrong = Altered::claiming(chain, Some(0));
    assert_eq!(wrong.hessian_bandwidth(), Some(0));
    let run = DynProblem::new(&wrong, grid, embedding)
        .solve_ivp(Scheme::Direct, &q0, &v0)
        .unwrap();
    assert!(run.run.reordered, "the claim was not believed");
    let gap = run
        .q
        .iter()
        .zip(&honest.q)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(gap < 1e-12, "{gap:.2e}");
}

#[test]
fn the_listed_assembly_of_a_reordered_system_matches_the_const_generic_run() {
    let model = Coupled { a: 0.4 };
    // Its bandwidth claim hidden: ordered by reverse Cuthill–McKee, the listed entries assembled.
    let hidden = Altered::claiming(Coupled { a: 0.4 }, None);
    let grid = Grid::new(0.0, 3.0, 60).unwrap();
    let q0 = displacement(COUPLED, 0.6, 0.0);
    let v0: Vec<f64> = q0.iter().map(|q| 0.4 - q).collect();
    for (side, scheme) in KINDS {
        let embedding = Embedding::finite_difference(side);
        let run = DynProblem::new(&hidden, grid, embedding)
            .solve_ivp(scheme, &q0, &v0)
            .unwrap();
        assert!(run.run.reordered, "{side:?} {scheme:?}");
        let reference =
            const_generic_run::<_, COUPLED>(&model, (grid, embedding, scheme), &q0, &v0);
        let worst = node_gap(&run, &reference);
        assert!(worst < 1e-12, "{side:?} {scheme:?}: {worst:.2e}");
        let (ours, theirs) = (run.run.newton_iterations, reference.newton_iterations);
        assert!(
            ours.abs_diff(theirs) * 30 <= theirs,
            "{side:?} {scheme:?}: {ours} against {theirs}"
        );
    }
}

const MASSES: usize = 10;

/// A chain with a constant, non-diagonal mass matrix (`L_vv` tridiagonal and constant,
/// `L_xv = 0`): both variational steps are affine with a constant Jacobian that is not the
/// identity, factorised once per run.
#[lagrangian]
fn coupled_masses(x: [f64; MASSES], v: [f64; MASSES]) -> f64 {
    let mut l = 0.0;
    for i in 0..MASSES {
        l += 0.5 * v[i] * v[i] - 0.5 * x[i] * x[i] - 0.1 * x[i].powi(4);
    }
    for i in 0..MASSES - 1 {
        l += 0.3 * v[i] * v[i + 1];
    }
    l
}

#[test]
fn a_constant_mass_matrix_is_factorised_once_and_gives_the_const_generic_nodes() {
    let model = CoupledMasses;
    let grid = Grid::new(0.0, 4.0, 80).unwrap();
    let q0 = displacement(MASSES, 0.7, 0.0);
    let v0: Vec<f64> = q0.iter().map(|q| 0.2 * q - 0.1).collect();
    for side in [Side::Backward, Side::Forward] {
        let embedding = Embedding::finite_difference(side);
        let run = DynProblem::new(&model, grid, embedding)
            .solve_ivp(Scheme::Variational, &q0, &v0)
            .unwrap();
        assert_eq!(
            (run.run.explicit_steps, run.run.newton_iterations),
            (79, 0),
            "{side:?}"
        );
        let reference = const_generic_run::<_, MASSES>(
            &model,
            (grid, embedding, Scheme::Variational),
            &q0,
            &v0,
        );
        let worst = node_gap(&run, &reference);
        assert!(worst < 1e-12, "{side:?}: {worst:.2e}");
    }
}

#[test]
fn a_pattern_that_grows_mid_run_is_planned_again_and_reported() {
    let chain = FputChain {
        n: 20,
        alpha: 0.25,
        beta: 0.5,
        periodic: false,
    };
    let grid = Grid::new(0.0, 2.0, 40).unwrap();
    let embedding = Embedding::finite_difference(Side::Backward);
    let (q0, v0) = (vec![0.0; 20], displacement(20, 0.8, 0.0));
    let honest = DynProblem::new(&chain, grid, embedding)
        .solve_ivp(Scheme::Direct, &q0, &v0)
        .unwrap();
    // Listing an entry of `L_xx` only where the state it couples is not at rest: a pattern that
    // grows during the run (at rest at the start, only the diagonal).
    let growing = Altered {
        model: chain,
        bandwidth: None,
        lists: |x, i, j| i == j || x[i] != 0.0 || x[j] != 0.0,
    };
    let run = DynProblem::new(&growing, grid, embedding)
        .solve_ivp(Scheme::Direct, &q0, &v0)
        .unwrap();
    // Planned on the diagonal at rest, then on the chain's pattern once it moved: the report
    // gives the plan the run ended with.
    assert_eq!((run.run.band, run.run.reordered), (1, true));
    let gap = run
        .q
        .iter()
        .zip(&honest.q)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(gap < 1e-12, "{gap:.2e}");
}

const DAMPED: usize = 6;

/// A Caldirola–Kanai chain: `e^{γt}` times a chain's Lagrangian, so that `p = e^{γt} v` moves
/// with `t` and the second-order start's `∂p/∂t` term is not zero.
#[lagrangian]
fn damped_chain(x: [f64; DAMPED], v: [f64; DAMPED], t: f64, gamma: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..DAMPED {
        l += 0.5 * v[i] * v[i] - 0.5 * x[i] * x[i];
    }
    for i in 0..DAMPED - 1 {
        l -= 0.25 * (x[i + 1] - x[i]).powi(4);
    }
    (gamma * t).exp() * l
}

/// Asserts, for every scheme, that the run-time-dimension run of `model` from the second-order
/// start has the const-generic run's nodes (from the same start), and that its `Q_1` is not
/// the Legendre start's (so the start was taken).
fn second_order_gaps<L: Lagrangian<D> + varembed::DynLagrangian + Sync, const D: usize>(
    model: &L,
    grid: Grid,
    (q0, v0): (&[f64], &[f64]),
) {
    for (side, scheme) in KINDS {
        let embedding = Embedding::finite_difference(side);
        let run = DynProblem::new(model, grid, embedding)
            .with_start(Start::SecondOrder)
            .solve_ivp(scheme, q0, v0)
            .unwrap();
        let reference = const_generic_run_from::<_, D>(
            model,
            (grid, embedding, scheme),
            q0,
            v0,
            Start::SecondOrder,
        );
        let worst = node_gap(&run, &reference);
        assert!(
            worst < 1e-12,
            "{side:?} {scheme:?}: nodes differ by {worst:.2e}"
        );
        let legendre = DynProblem::new(model, grid, embedding)
            .solve_ivp(scheme, q0, v0)
            .unwrap();
        let moved = (0..D)
            .map(|i| (run.node(1)[i] - legendre.node(1)[i]).abs())
            .fold(0.0, f64::max);
        assert!(
            moved > 1e-6,
            "{side:?} {scheme:?}: Q_1 moved by {moved:.2e} only"
        );
    }
}

#[test]
fn the_second_order_start_is_the_const_generic_one() {
    let grid = Grid::new(0.0, 2.0, 40).unwrap();
    // Every block nonzero and `L_xv` unsymmetric: the start's `L_vx v0` term and a mass
    // matrix that depends on x, solved as a band.
    let q0 = displacement(COUPLED, 0.6, 0.0);
    let v0: Vec<f64> = q0.iter().map(|q| 0.4 - q).collect();
    second_order_gaps::<_, COUPLED>(&Coupled { a: 0.4 }, grid, (&q0, &v0));
    // A constant tridiagonal mass matrix.
    let q0 = displacement(MASSES, 0.7, 0.0);
    let v0: Vec<f64> = q0.iter().map(|q| 0.2 * q - 0.1).collect();
    second_order_gaps::<_, MASSES>(&CoupledMasses, grid, (&q0, &v0));
    // A momentum that depends on t.
    let q0 = displacement(DAMPED, 0.5, 0.0);
    let v0: Vec<f64> = q0.iter().map(|q| -0.3 * q).collect();
    second_order_gaps::<_, DAMPED>(&DampedChain { gamma: 0.3 }, grid, (&q0, &v0));
}

/// Twelve free relativistic particles (`c = 1`) in harmonic wells: a velocity domain `|v_i| < 1`.
const TWELVE: usize = 12;

#[lagrangian]
fn relativistic_wells(x: [f64; TWELVE], v: [f64; TWELVE]) -> f64 {
    let mut l = 0.0;
    for i in 0..TWELVE {
        l += -(1.0 - v[i] * v[i]).sqrt() - 0.5 * x[i] * x[i];
    }
    l
}

/// The checks of the initial data are one function on both paths: the same error, word for
/// word, for the same bad data, whichever path and start solves it.
#[test]
fn bad_initial_data_reads_the_same_on_both_paths() {
    let grid = Grid::new(0.0, 1.0, 20).unwrap();
    let embedding = Embedding::midpoint();
    let q0: Vec<f64> = (0..TWELVE).map(|i| 0.1 * i as f64).collect();
    let v0 = vec![0.2; TWELVE];
    let both = |q0: &[f64], v0: &[f64], start: Start| {
        let model = RelativisticWells;
        let (x0, u0) = (
            Vector::<TWELVE>::from_column_slice(q0),
            Vector::from_column_slice(v0),
        );
        let fixed = varembed_tests::problem(&model, grid, embedding)
            .solve_ivp_with(Scheme::Variational, x0, u0, start)
            .map(|run| run.last()[0]);
        let dynamic = DynProblem::new(&model, grid, embedding)
            .with_start(start)
            .solve_ivp(Scheme::Variational, q0, v0)
            .map(|run| run.node(grid.n())[0]);
        (fixed, dynamic)
    };
    for start in [Start::Legendre, Start::SecondOrder] {
        // Good data: the same run.
        let (fixed, dynamic) = both(&q0, &v0, start);
        assert!((fixed.unwrap() - dynamic.unwrap()).abs() < 1e-12);
        // One particle faster than light: blamed on the velocity, both vectors shortened to
        // their ends and their largest coordinate.
        let mut fast = v0.clone();
        fast[5] = 1.5;
        let (fixed, dynamic) = both(&q0, &fast, start);
        let expected = Error::OutsideDomain {
            what:
                "the initial velocity q̇(a) = [0.2, 0.2, 0.2, …, 0.2] (d = 12; largest [5] = 1.5) \
                   (at q(a) = [0.0, 0.1, 0.2, …, 1.1] (d = 12; largest [11] = 1.1), t = 0)"
                    .to_string(),
        };
        assert_eq!(fixed.unwrap_err(), expected);
        assert_eq!(dynamic.unwrap_err(), expected);
        // A NaN in the position is named by its index.
        let mut nan = q0.clone();
        nan[7] = f64::NAN;
        let (fixed, dynamic) = both(&nan, &v0, start);
        let expected = Error::NonFiniteInput {
            what: "q0[7] = NaN (the initial position q(a))".to_string(),
        };
        assert_eq!(fixed.unwrap_err(), expected);
        assert_eq!(dynamic.unwrap_err(), expected);
    }
    // From given first nodes, checked at `Q_1` with the velocity `(Q_1 − Q_0)/h`.
    let from_nodes = |q0: &[f64], q1: &[f64]| {
        let model = RelativisticWells;
        let (x0, x1) = (
            Vector::<TWELVE>::from_column_slice(q0),
            Vector::from_column_slice(q1),
        );
        let fixed = varembed_tests::problem(&model, grid, embedding)
            .solve_ivp_from_nodes(Scheme::Variational, x0, x1)
            .map(|run| run.last()[0]);
        let dynamic = DynProblem::new(&model, grid, embedding)
            .solve_ivp_from_nodes(Scheme::Variational, q0, q1)
            .map(|run| run.node(grid.n())[0]);
        (fixed, dynamic)
    };
    let h = grid.h();
    let q1: Vec<f64> = q0.iter().zip(&v0).map(|(q, v)| q + h * v).collect();
    let (fixed, dynamic) = from_nodes(&q0, &q1);
    assert!((fixed.unwrap() - dynamic.unwrap()).abs() < 1e-12);
    let mut nan = q1.clone();
    nan[4] = f64::INFINITY;
    let (fixed, dynamic) = from_nodes(&q0, &nan);
    let expected = Error::NonFiniteInput {
        what: "q1[4] = inf (the second node Q_1)".to_string(),
    };
    assert_eq!(fixed.unwrap_err(), expected);
    assert_eq!(dynamic.unwrap_err(), expected);
    // Particle 2 moves 0.1 in one step of 0.05: twice the speed of light.
    let mut fast = q1.clone();
    fast[2] = q0[2] + 0.1;
    let (fixed, dynamic) = from_nodes(&q0, &fast);
    let (fixed, dynamic) = (fixed.unwrap_err(), dynamic.unwrap_err());
    assert_eq!(fixed, dynamic);
    match fixed {
        Error::OutsideDomain { what } => {
            assert!(
                what.starts_with("the first nodes Q_0 = [0.0, 0.1, 0.2, …, 1.1] (d = 12;")
                    && what.contains("(velocity [")
                    && what.contains("largest [2] = 2.0"),
                "{what}"
            );
        }
        other => panic!("{other:?}"),
    }
}
