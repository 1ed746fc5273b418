//! The variational residual is `(1/h) ∂S_h/∂Q_j`, checked by central finite
//! differences of `action`, for σ = ±, α ∈ {1, 0.3, 0.7}, on a non-separable, time-dependent L.

use varembed::{Embedding, Grid, Lagrangian, Scheme, Side, Vector};
use varembed_tests::models::hand::Coupled;
use varembed_tests::rng::Rng;

/// Guards the oracle itself: the hand-written gradient and Hessian of `Coupled` match central
/// differences of its value and gradient.
#[test]
fn coupled_lagrangian_derivatives_are_consistent() {
    let mut rng = Rng(7);
    for _ in 0..20 {
        let x = Vector::<2>::new(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0));
        let v = Vector::<2>::new(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0));
        let t = rng.uniform(0.0, 3.0);
        let eps = 1e-6;
        let (f, p) = Coupled.gradient(&x, &v, t);
        let hs = Coupled.hessian(&x, &v, t);
        for i in 0..2 {
            let e = Vector::<2>::from_fn(|r, _| if r == i { eps } else { 0.0 });
            let dx =
                (Coupled.value(&(x + e), &v, t) - Coupled.value(&(x - e), &v, t)) / (2.0 * eps);
            let dv =
                (Coupled.value(&x, &(v + e), t) - Coupled.value(&x, &(v - e), t)) / (2.0 * eps);
            assert!((dx - f[i]).abs() < 1e-8 && (dv - p[i]).abs() < 1e-8);
            let (fxp, pxp) = Coupled.gradient(&(x + e), &v, t);
            let (fxm, pxm) = Coupled.gradient(&(x - e), &v, t);
            let (fvp, _) = Coupled.gradient(&x, &(v + e), t);
            let (fvm, _) = Coupled.gradient(&x, &(v - e), t);
            let (_, pvp) = Coupled.gradient(&x, &(v + e), t);
            let (_, pvm) = Coupled.gradient(&x, &(v - e), t);
            for j in 0..2 {
                assert!(((fxp[j] - fxm[j]) / (2.0 * eps) - hs.xx[(j, i)]).abs() < 1e-7);
                assert!(((fvp[j] - fvm[j]) / (2.0 * eps) - hs.xv[(j, i)]).abs() < 1e-7);
                assert!(((pxp[j] - pxm[j]) / (2.0 * eps) - hs.xv[(i, j)]).abs() < 1e-7);
                assert!(((pvp[j] - pvm[j]) / (2.0 * eps) - hs.vv[(j, i)]).abs() < 1e-7);
            }
        }
    }
}

#[test]
fn variational_residual_is_the_gradient_of_the_discrete_action() {
    let grid = Grid::new(0.2, 1.7, 12).unwrap();
    let mut rng = Rng(42);
    let mut embeddings = Vec::new();
    for side in [Side::Backward, Side::Forward] {
        embeddings.push(Embedding::finite_difference(side));
        embeddings.push(Embedding::asymmetric(side));
        for alpha in [1.0, 0.3, 0.7] {
            embeddings.push(Embedding::grunwald_letnikov(side, alpha).unwrap());
            embeddings.push(Embedding::caputo(side, alpha).unwrap());
        }
    }
    for embedding in embeddings {
        let problem = varembed_tests::problem(&Coupled, grid, embedding);
        let q = rng.curve::<2>(grid.n(), 0.8);
        let residual = problem.residual(Scheme::Variational, &q).unwrap();
        assert_eq!(problem.residual_rows(Scheme::Variational), 1..=grid.n() - 1);
        // Central differences of S_h: error O(eps²·S''') + O(ε_mach·S/eps); with eps = 1e-5
        // and |S| ~ 1 both are below 1e-9, and dividing by h = 0.125 keeps them below 1e-8.
        let eps = 1e-5;
        let mut worst = 0.0f64;
        for (i, j) in (1..grid.n()).enumerate() {
            for c in 0..2 {
                let mut plus = q.clone();
                plus[j][c] += eps;
                let mut minus = q.clone();
                minus[j][c] -= eps;
                let grad = (problem.action(&plus).unwrap() - problem.action(&minus).unwrap())
                    / (2.0 * eps * grid.h());
                worst = worst.max((grad - residual[i][c]).abs() / (1.0 + grad.abs()));
            }
        }
        assert!(worst < 1e-7, "{embedding}: worst relative gap {worst:e}");
    }
}
