//! The run-time engine's stability check at the initial data, for every three-point kind with
//! a step limit, against the const-generic path's eigenvalue verdict on the same chain.

use varembed::{
    DynLagrangian, DynProblem, Embedding, Error, Grid, HessianDependence, Location, Problem,
    Scheme, Side, SparseHessian, Vector,
};
use varembed_tests::models::chain::{FputChain, displacement};
use varembed_tests::models::dense::ConstGeneric;
use varembed_tests::models::generated::fput64;

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
    let chain = FputChain {
        n: 64,
        alpha: 0.25,
        beta: 0.0,
        periodic: false,
    };
    let oracle_model = ConstGeneric(fput64::Fput {
        alpha: 0.25,
        beta: 0.0,
    });
    let kappa = 2.0 - 2.0 * (64.0 * std::f64::consts::PI / 65.0).cos();
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
        let oracle = Problem::new(&oracle_model, grid, embedding)
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

/// A model whose modes do not decouple gets no verdict at the initial data: the doubled
/// masses move Störmer–Verlet's limit to `h√κ_max = 2√2`, and a run 10 % past the unit-mass
/// limit (inside its own) runs to the end, where a check that ignored the mass would stop it.
#[test]
fn no_verdict_where_the_modes_do_not_decouple() {
    let heavy = Heavy(FputChain {
        n: 64,
        alpha: 0.25,
        beta: 0.0,
        periodic: false,
    });
    let kappa = 2.0 - 2.0 * (64.0 * std::f64::consts::PI / 65.0).cos();
    let h = 1.1 * 2.0 / kappa.sqrt();
    let grid = Grid::new(0.0, 400.0 * h, 400).unwrap();
    let q0 = displacement(64, 1e-3, 0.0);
    let embedding = Embedding::finite_difference(Side::Forward);
    let run = DynProblem::new(&heavy, grid, embedding)
        .solve_ivp(Scheme::Variational, &q0, &[0.0; 64])
        .unwrap();
    let last = run.node(400);
    assert!(last.iter().all(|x| x.abs() < 1e-2), "bounded: {last:?}");
}
