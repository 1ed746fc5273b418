//! Harmonic oscillator: every run equals its exact discrete solution node for node
//! ([`DiscreteOscillation`]).
//! Variational: `Q_k = A cos(kθ) + B sin(kθ)`, `cos θ = 1 − (ωh)²/2`.
//! Direct σ = −: `Q_k = r^k (A' cos(kφ) + B' sin(kφ))`, `r = (1 + ω²h²)^{−1/2}`, `tan φ = ωh`:
//! it loses exactly the factor `r` of amplitude per step.

use varembed::{Embedding, Grid, Scheme, Side};
use varembed_tests::models::hand::Oscillator;
use varembed_tests::reference::DiscreteOscillation;

const OMEGA: f64 = 2.0;

#[test]
fn variational_run_is_the_exact_discrete_rotation() {
    let grid = Grid::new(0.0, 30.0, 1500).unwrap();
    let h = grid.h();
    for side in [Side::Backward, Side::Forward] {
        let problem = varembed_tests::problem(
            &Oscillator { omega: OMEGA },
            grid,
            Embedding::finite_difference(side),
        );
        let run = problem.solve_ivp(Scheme::Variational, 1.0, 0.5).unwrap();
        let rotation = DiscreteOscillation::variational(OMEGA * h, run.q[0][0], run.q[1][0]);
        for (k, q) in run.q.iter().enumerate() {
            let exact = rotation.at(k);
            assert!(
                (q[0] - exact).abs() < 1e-10,
                "{side:?} k = {k}: {} vs {exact}",
                q[0]
            );
        }
    }
}

#[test]
fn direct_backward_run_loses_the_factor_r_per_step() {
    let grid = Grid::new(0.0, 30.0, 1500).unwrap();
    let h = grid.h();
    let problem = varembed_tests::problem(
        &Oscillator { omega: OMEGA },
        grid,
        Embedding::finite_difference(Side::Backward),
    );
    let run = problem.solve_ivp(Scheme::Direct, 1.0, 0.5).unwrap();
    let spiral = DiscreteOscillation::direct_backward(OMEGA * h, run.q[0][0], run.q[1][0]);
    let r = spiral.ratio;
    for (k, q) in run.q.iter().enumerate() {
        let exact = spiral.at(k);
        assert!((q[0] - exact).abs() < 1e-10, "k = {k}: {} vs {exact}", q[0]);
    }
    // Measured on the run: the peak over the last period (≈ 157 steps, 2π/φ) against the peak
    // over the first is between r^1500 = 0.30 and r^1300 = 0.35 (≈ e^{−ω²hT/2} = e^{−1.2}).
    let peak = |range: std::ops::Range<usize>| range.map(|k| run.q[k][0].abs()).fold(0.0, f64::max);
    let ratio = peak(1301..1501) / peak(0..200);
    assert!(
        (r.powi(1500)..r.powi(1300)).contains(&ratio),
        "decay ratio {ratio}"
    );
}

#[test]
fn direct_forward_run_gains_the_factor_one_over_r_per_step() {
    // (Q_{k+2} − 2Q_{k+1} + Q_k)/h² = −ω²Q_k has roots 1 ± iωh, of modulus 1/r.
    let grid = Grid::new(0.0, 5.0, 500).unwrap();
    let h = grid.h();
    let problem = varembed_tests::problem(
        &Oscillator { omega: OMEGA },
        grid,
        Embedding::finite_difference(Side::Forward),
    );
    let run = problem.solve_ivp(Scheme::Direct, 1.0, 0.5).unwrap();
    let spiral = DiscreteOscillation::direct_forward(OMEGA * h, run.q[0][0], run.q[1][0]);
    let growth = spiral.ratio;
    for (k, q) in run.q.iter().enumerate() {
        let exact = spiral.at(k);
        assert!(
            (q[0] - exact).abs() < 1e-10 * growth.powi(k as i32),
            "k = {k}"
        );
    }
}

/// The oscillator declaring its second derivatives constant: every step of every scheme is then
/// affine in the newest node and taken in closed form, with no Newton iteration.
struct AffineOscillator(Oscillator);

impl varembed::Lagrangian<1> for AffineOscillator {
    fn value(&self, x: &varembed::Vector<1>, v: &varembed::Vector<1>, t: f64) -> f64 {
        self.0.value(x, v, t)
    }
    fn gradient(
        &self,
        x: &varembed::Vector<1>,
        v: &varembed::Vector<1>,
        t: f64,
    ) -> (varembed::Vector<1>, varembed::Vector<1>) {
        self.0.gradient(x, v, t)
    }
    fn hessian(
        &self,
        x: &varembed::Vector<1>,
        v: &varembed::Vector<1>,
        t: f64,
    ) -> varembed::Hessian<1> {
        self.0.hessian(x, v, t)
    }
    fn hessian_dependence(&self) -> varembed::HessianDependence {
        use varembed::Dependence;
        varembed::HessianDependence {
            xx: Dependence::NONE,
            xv: Dependence::NONE,
            vv: Dependence::NONE,
        }
    }
}

#[test]
fn affine_steps_run_without_newton_and_agree_with_newton() {
    let grid = Grid::new(0.0, 10.0, 1000).unwrap();
    for side in [Side::Backward, Side::Forward] {
        for scheme in [Scheme::Direct, Scheme::Variational] {
            let embedding = Embedding::finite_difference(side);
            let explicit = varembed_tests::problem(
                &AffineOscillator(Oscillator { omega: OMEGA }),
                grid,
                embedding,
            )
            .solve_ivp(scheme, 1.0, 0.5)
            .unwrap();
            let newton = varembed_tests::problem(&Oscillator { omega: OMEGA }, grid, embedding)
                .solve_ivp(scheme, 1.0, 0.5)
                .unwrap();
            assert_eq!(
                (explicit.newton_iterations, explicit.explicit_steps),
                (0, grid.n() - 1),
                "{side:?} {scheme}"
            );
            assert!(
                newton.newton_iterations >= grid.n() - 1,
                "the plain oscillator runs Newton"
            );
            let gap = explicit
                .q
                .iter()
                .zip(&newton.q)
                .map(|(a, b)| (a - b).amax())
                .fold(0.0, f64::max);
            assert!(gap < 1e-12, "{side:?} {scheme}: {gap:e}");
        }
    }
}

#[test]
fn energy_default_is_v_dot_p_minus_l() {
    use varembed::{Lagrangian as _, Vector};
    // E = v·∂L/∂v − L = ½v² + ½ω²x² for the oscillator.
    let (x, v) = (Vector::<1>::new(0.7), Vector::<1>::new(-1.3));
    let e = Oscillator { omega: OMEGA }.energy(&x, &v, 0.0);
    assert!((e - (0.5 * 1.3 * 1.3 + 0.5 * OMEGA * OMEGA * 0.49)).abs() < 1e-15);
}
