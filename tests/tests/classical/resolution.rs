//! The resolution check of implicit initial value runs: `Warning::UnderResolved` when `h ω` at
//! the initial data exceeds 2 per stage, `ω` the fastest rate of the linearised equation;
//! checked against exact frequencies (the oscillator, and random quadratic Lagrangians whose
//! `ω_max` comes from a symmetric eigen-decomposition).

use varembed::{Embedding, Grid, Hessian, Lagrangian, Matrix, Scheme, Side, Vector};
use varembed_tests::models::hand::Oscillator;
use varembed_tests::rng::Rng;
use varembed_tests::warnings::under_resolved;

#[test]
fn an_under_resolved_midpoint_run_is_flagged_and_a_resolved_one_is_not() {
    let oscillator = Oscillator { omega: 1.0 };
    // ωh = 10: stable, Ok, and its phase is meaningless (2 atan 5 ≈ 2.75 a step, not 10).
    let coarse = varembed_tests::problem(
        &oscillator,
        Grid::new(0.0, 100.0, 10).unwrap(),
        Embedding::midpoint(),
    );
    let run = coarse.solve_ivp(Scheme::Variational, 1.0, 0.0).unwrap();
    let found = under_resolved(&run.warnings);
    assert_eq!(found.len(), 1, "{:?}", run.warnings);
    assert!(
        (found[0].0 - 10.0).abs() < 1e-9 && found[0].1 == 2.0,
        "{found:?}"
    );
    assert!(run.warnings[0].to_string().contains("h·ω = 10.000"));
    // The same from two given nodes, and silenced on purpose.
    let nodes = coarse
        .solve_ivp_from_nodes(Scheme::Variational, 1.0, 1.0)
        .unwrap();
    assert_eq!(under_resolved(&nodes.warnings).len(), 1);
    let quiet = coarse
        .with_resolution_check(false)
        .solve_ivp(Scheme::Variational, 1.0, 0.0)
        .unwrap();
    assert!(quiet.warnings.is_empty());
    // ωh = 0.1: resolved, no warning, for every implicit symmetric scheme and the direct σ = −.
    let fine_grid = Grid::new(0.0, 10.0, 100).unwrap();
    for embedding in [
        Embedding::midpoint(),
        Embedding::trapezoidal(),
        Embedding::finite_difference(Side::Backward),
    ] {
        let fine = varembed_tests::problem(&oscillator, fine_grid, embedding);
        for scheme in [Scheme::Direct, Scheme::Variational] {
            let run = fine.solve_ivp(scheme, 1.0, 0.0).unwrap();
            assert!(
                run.warnings.is_empty(),
                "{embedding} {scheme}: {:?}",
                run.warnings
            );
        }
    }
}

#[test]
fn gauss_legendre_is_allowed_two_per_stage() {
    let oscillator = Oscillator { omega: 1.0 };
    for (stages, h, flagged) in [
        (1, 2.5, true),
        (1, 1.5, false),
        (2, 5.0, true),
        (2, 3.5, false),
        (4, 9.0, true),
        (4, 7.0, false),
    ] {
        let grid = Grid::new(0.0, 10.0 * h, 10).unwrap();
        let embedding = Embedding::gauss_legendre(stages).unwrap();
        let run = varembed_tests::problem(&oscillator, grid, embedding)
            .solve_ivp(Scheme::Variational, 1.0, 0.0)
            .unwrap();
        let found = under_resolved(&run.warnings);
        assert_eq!(
            !found.is_empty(),
            flagged,
            "s = {stages}, h = {h}: {found:?}"
        );
        if flagged {
            assert!((found[0].0 - h).abs() < 1e-9 * h && found[0].1 == 2.0 * stages as f64);
        }
    }
}

/// `L = ½ vᵀ M v − ½ xᵀ K x` with symmetric positive definite `M`, `K`.
struct Quadratic {
    m: Matrix<3>,
    k: Matrix<3>,
}

impl Lagrangian<3> for Quadratic {
    fn value(&self, x: &Vector<3>, v: &Vector<3>, _t: f64) -> f64 {
        0.5 * v.dot(&(self.m * v)) - 0.5 * x.dot(&(self.k * x))
    }
    fn gradient(&self, x: &Vector<3>, v: &Vector<3>, _t: f64) -> (Vector<3>, Vector<3>) {
        (-(self.k * x), self.m * v)
    }
    fn hessian(&self, _x: &Vector<3>, _v: &Vector<3>, _t: f64) -> Hessian<3> {
        Hessian {
            xx: -self.k,
            xv: Matrix::<3>::zeros(),
            vv: self.m,
        }
    }
}

/// A random symmetric positive definite matrix with eigenvalues spread over `spread` decades.
fn spd(rng: &mut Rng, spread: f64) -> Matrix<3> {
    let a = Matrix::<3>::from_fn(|_, _| rng.uniform(-1.0, 1.0));
    let q = a.qr().q();
    let d = Matrix::<3>::from_diagonal(&Vector::<3>::from_fn(|_, _| {
        10f64.powf(rng.uniform(0.0, spread))
    }));
    q * d * q.transpose()
}

#[test]
fn the_fastest_rate_matches_the_generalised_eigenproblem_on_random_models() {
    let mut rng = Rng(0x0002_e501_u64);
    for case in 0..60 {
        let model = Quadratic {
            m: spd(&mut rng, 2.0),
            k: spd(&mut rng, 4.0),
        };
        // ω_max² = λ_max(M^{-1/2} K M^{-1/2}), by the symmetric eigen-decomposition.
        let m_half_inv = {
            let e = model.m.symmetric_eigen();
            e.eigenvectors
                * Matrix::<3>::from_diagonal(&e.eigenvalues.map(|l| 1.0 / l.sqrt()))
                * e.eigenvectors.transpose()
        };
        let omega = (m_half_inv * model.k * m_half_inv)
            .symmetric_eigen()
            .eigenvalues
            .max()
            .sqrt();
        // Below and above the limit 2, by a margin the power iteration resolves.
        let target = if case % 2 == 0 { 1.6 } else { 2.5 };
        let h = target / omega;
        let grid = Grid::new(0.0, 20.0 * h, 20).unwrap();
        let run = varembed_tests::problem(&model, grid, Embedding::midpoint())
            .solve_ivp(Scheme::Variational, rng.vector(1.0), rng.vector(1.0))
            .unwrap();
        let found = under_resolved(&run.warnings);
        assert_eq!(
            !found.is_empty(),
            target > 2.0,
            "case {case}: {found:?}, ω = {omega}"
        );
        if let Some(&(h_omega, _)) = found.first() {
            assert!(
                (h_omega - target).abs() < 0.05 * target,
                "case {case}: h ω = {h_omega} against {target}"
            );
        }
    }
}
