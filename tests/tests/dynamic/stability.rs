//! The run-time engine's stability check at the initial data, for every three-point kind with
//! a step limit, against the const-generic path's eigenvalue verdict on the same chain.

use varembed::{
    DynLagrangian, DynProblem, Embedding, Error, Grid, HessianDependence, Location, Scheme, Side,
    SparseHessian, Vector,
};
use varembed_tests::models::chain::{FputChain, displacement};
use varembed_tests::models::dense::ConstGeneric;
use varembed_tests::models::generated::fput64;
use varembed_tests::models::scaled::Scaled;

/// The chain of every test here: 64 particles between walls, `α = 0.25`, `β = 0`, displaced by
/// `10⁻³` (nearly harmonic).
fn chain() -> FputChain {
    FputChain {
        n: 64,
        alpha: 0.25,
        beta: 0.0,
        periodic: false,
    }
}

/// The largest eigenvalue of the harmonic chain's `K`, `2 − 2cos(64π/65)`.
fn kappa_max() -> f64 {
    2.0 - 2.0 * (64.0 * std::f64::consts::PI / 65.0).cos()
}

/// The eigenvalue and the largest stable step of an `Error::Unstable`, and where it was found.
fn unstable(error: Error) -> (Location, f64, f64, f64) {
    match error {
        Error::Unstable {
            at,
            re,
            im,
            largest_stable_step: Some(step),
        } => (at, re, im, step),
        other => panic!("expected an instability with its remedy, got {other}"),
    }
}

/// An FPUT chain of 64 particles displaced by `10⁻³`, nearly harmonic (fixed ends,
/// `κ_max ≈ 2 − 2cos(64π/65)`), 10 % past each kind's limit `h√κ_max = z*`: the run-time
/// engine refuses it before its first step, and the const-generic path at its first check
/// (step 2), with flagged eigenvalues of the same modulus to 1 % and real parts of the same
/// sign, and largest stable steps within 1 % of `z*/√κ_max`. 10 % inside the limit the
/// variational steps run to the end; the direct σ = + step is unstable at every step size (its
/// amplitude grows by `(1 + h²κ)^{1/2}` a step) and is only flagged past its limit.
#[test]
fn each_kind_is_stopped_past_its_own_limit_as_on_the_const_generic_path() {
    let chain = chain();
    let oracle_model = ConstGeneric(fput64::Fput {
        alpha: 0.25,
        beta: 0.0,
    });
    let kappa = kappa_max();
    let q0 = displacement(64, 1e-3, 0.0);
    let cases = [
        (
            Embedding::finite_difference(Side::Forward),
            Scheme::Direct,
            3f64.sqrt(),
        ),
        (Embedding::midpoint(), Scheme::Direct, 2.0),
        (Embedding::trapezoidal(), Scheme::Variational, 2.0),
        (Embedding::trapezoidal(), Scheme::Direct, 2.0),
        (
            Embedding::finite_difference(Side::Backward),
            Scheme::Variational,
            2.0,
        ),
    ];
    for (embedding, scheme, limit) in cases {
        let what = format!("{embedding} {scheme}");
        let h = 1.1 * limit / kappa.sqrt();
        let grid = Grid::new(0.0, 40.0 * h, 40).unwrap();
        let run = DynProblem::new(&chain, grid, embedding).solve_ivp(scheme, &q0, &[0.0; 64]);
        let (at, re, im, step) = unstable(run.unwrap_err());
        assert_eq!(at, Location::Step(0), "{what}");
        let oracle = varembed_tests::problem(&oracle_model, grid, embedding)
            .solve_ivp(
                scheme,
                Vector::<64>::from_column_slice(&q0),
                Vector::<64>::zeros(),
            )
            .unwrap_err();
        let (oracle_at, oracle_re, oracle_im, oracle_step) = unstable(oracle);
        assert_eq!(oracle_at, Location::Step(2), "{what}");
        let (lambda, exact) = (re.hypot(im), oracle_re.hypot(oracle_im));
        assert!(
            (lambda - exact).abs() < 0.01 * exact && re.signum() == oracle_re.signum(),
            "{what}: {re} {im}i against {oracle_re} {oracle_im}i"
        );
        let exact_step = limit / kappa.sqrt();
        for s in [step, oracle_step] {
            assert!(
                (s - exact_step).abs() < 0.01 * exact_step,
                "{what}: {s} against {exact_step}"
            );
        }
        if scheme == Scheme::Variational {
            let h = 0.9 * limit / kappa.sqrt();
            let grid = Grid::new(0.0, 400.0 * h, 400).unwrap();
            DynProblem::new(&chain, grid, embedding)
                .solve_ivp(scheme, &q0, &[0.0; 64])
                .unwrap_or_else(|e| panic!("{what} inside its limit: {e}"));
        }
    }
}

/// The chain with every mass doubled, `L = |v|² − U(x)`: `∂²L/∂v² = 2I`.
struct Heavy(FputChain);

impl DynLagrangian for Heavy {
    fn dimension(&self) -> usize {
        self.0.dimension()
    }
    fn value(&self, x: &[f64], v: &[f64], t: f64) -> f64 {
        self.0.value(x, v, t) + 0.5 * v.iter().map(|v| v * v).sum::<f64>()
    }
    fn force(&self, x: &[f64], v: &[f64], t: f64, f: &mut [f64]) {
        self.0.force(x, v, t, f);
    }
    fn momentum(&self, _x: &[f64], v: &[f64], _t: f64, p: &mut [f64]) {
        p.iter_mut().zip(v).for_each(|(p, v)| *p = 2.0 * v);
    }
    fn hessian(&self, x: &[f64], v: &[f64], t: f64, out: &mut SparseHessian) {
        self.0.hessian(x, v, t, out);
        (0..self.dimension()).for_each(|i| out.vv.add(i, i, 1.0));
    }
    fn hessian_dependence(&self) -> HessianDependence {
        self.0.hessian_dependence()
    }
    fn hessian_bandwidth(&self) -> Option<usize> {
        self.0.hessian_bandwidth()
    }
}

/// The heavier chain is checked against its own limit: its doubled masses move Störmer–Verlet's
/// limit to `h√κ_max = 2√2`, so a run 10 % past the unit-mass limit (inside its own) runs to
/// the end, where a check that ignored the mass would stop it, and a run 10 % past its own
/// limit is refused before its first step, with the largest stable step `2√2/√κ_max` to 1 %.
#[test]
fn a_heavier_chain_is_checked_against_its_own_limit() {
    let heavy = Heavy(chain());
    let kappa = kappa_max();
    let q0 = displacement(64, 1e-3, 0.0);
    let embedding = Embedding::finite_difference(Side::Forward);
    let run = |h: f64| {
        let grid = Grid::new(0.0, 400.0 * h, 400).unwrap();
        DynProblem::new(&heavy, grid, embedding).solve_ivp(Scheme::Variational, &q0, &[0.0; 64])
    };
    let inside = run(1.1 * 2.0 / kappa.sqrt()).unwrap();
    let last = inside.node(400);
    assert!(last.iter().all(|x| x.abs() < 1e-2), "bounded: {last:?}");
    let own_limit = 2.0 * 2f64.sqrt() / kappa.sqrt();
    let (at, _, _, step) = unstable(run(1.1 * own_limit).unwrap_err());
    assert_eq!(at, Location::Step(0));
    assert!(
        (step - own_limit).abs() < 0.01 * own_limit,
        "{step} against {own_limit}"
    );
}

/// `c L` gets the verdict of `L`, for `c` from `10⁻⁹` to `10⁹`: the same eigenvalue and largest
/// stable step to `10⁻⁹` relative, 10 % past the limit of each kind that has one.
#[test]
fn the_verdict_does_not_depend_on_the_scale_of_l() {
    let chain = chain();
    let kappa = kappa_max();
    let q0 = displacement(64, 1e-3, 0.0);
    for (embedding, scheme, limit) in [
        (
            Embedding::finite_difference(Side::Forward),
            Scheme::Direct,
            3f64.sqrt(),
        ),
        (Embedding::midpoint(), Scheme::Direct, 2.0),
        (
            Embedding::finite_difference(Side::Backward),
            Scheme::Variational,
            2.0,
        ),
    ] {
        let grid = Grid::new(0.0, 40.0 * 1.1 * limit / kappa.sqrt(), 40).unwrap();
        let verdict = |c: f64| {
            let model = Scaled::new(c, &chain);
            let run = DynProblem::new(&model, grid, embedding).solve_ivp(scheme, &q0, &[0.0; 64]);
            unstable(run.unwrap_err())
        };
        let (at, re, im, step) = verdict(1.0);
        assert_eq!(at, Location::Step(0));
        for c in [1e-9, 1e-3, 1e3, 1e9] {
            let (at_c, re_c, im_c, step_c) = verdict(c);
            let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs().max(1.0);
            assert!(
                at_c == at && close(re_c, re) && close(im_c, im) && close(step_c, step),
                "{embedding} {scheme}, c = {c:e}: {re_c} {im_c}i, {step_c} against {re} {im}i, {step}"
            );
        }
    }
}
