//! The discretisation's evaluations against independent computations: the FFT route against
//! the dense loops, the assembled Jacobian against finite differences of the residual.
use super::*;
use crate::side::Side;
use crate::test_models::Mixed;

/// Above [`FFT_OPERATOR_THRESHOLD`] the fractional operators go by FFT: velocity, both
/// residuals, action and energy equal the dense loops' to round-off, for both sides and
/// every form (Grünwald–Letnikov, Caputo, and the corrected form, whose starting columns are
/// added beside the FFT products).
#[test]
fn fft_route_matches_the_dense_loops_above_the_threshold() {
    let n = 3 * FFT_OPERATOR_THRESHOLD + 7;
    let grid = Grid::new(0.1, 1.3, n).unwrap();
    let q: Vec<Vector<2>> = (0..=n)
        .map(|k| {
            let t = k as f64 / n as f64;
            Vector::<2>::new((5.0 * t).sin(), (3.0 * t).cos() - 0.5)
        })
        .collect();
    let close = |a: &[Vector<2>], b: &[Vector<2>], what: &str| {
        assert_eq!(a.len(), b.len());
        let scale = 1.0 + b.iter().fold(0.0f64, |m, x| m.max(x.amax()));
        for (k, (x, y)) in a.iter().zip(b).enumerate() {
            assert!((x - y).amax() <= 1e-12 * scale, "{what} {k}: {x} vs {y}");
        }
    };
    let embeddings = [Side::Backward, Side::Forward]
        .into_iter()
        .flat_map(|side| {
            [
                Embedding::grunwald_letnikov(side, 0.65).unwrap(),
                Embedding::caputo(side, 0.65).unwrap(),
                Embedding::corrected_grunwald_letnikov(side, 0.65).unwrap(),
            ]
        });
    for embedding in embeddings {
        let side = embedding.side();
        let fast = Discretisation::new(&Mixed, grid, embedding);
        let mut dense = Discretisation::new(&Mixed, grid, embedding);
        dense.fft_threshold = usize::MAX;
        assert!(fast.by_fft() && !dense.by_fft());
        close(
            &fast.velocity(&q).unwrap(),
            &dense.velocity(&q).unwrap(),
            "V",
        );
        for scheme in [Scheme::Direct, Scheme::Variational] {
            let (a, b) = (fast.residual(scheme, &q), dense.residual(scheme, &q));
            close(&a.unwrap(), &b.unwrap(), &format!("{side:?} {scheme:?}"));
        }
        let (a, b) = (fast.action(&q).unwrap(), dense.action(&q).unwrap());
        assert!((a - b).abs() <= 1e-13 * (1.0 + b.abs()), "{a} vs {b}");
        let (a, b) = (fast.energy(&q).unwrap(), dense.energy(&q).unwrap());
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() <= 1e-12 * (1.0 + y.abs()), "{x} vs {y}");
        }
    }
}

/// The FFT forms are built by the first evaluation that needs them and then kept; the dense
/// loops never build them.
#[test]
fn fft_forms_are_built_once_and_only_when_used() {
    let n = FFT_OPERATOR_THRESHOLD + 1;
    let q: Vec<Vector<2>> = (0..=n)
        .map(|k| Vector::<2>::new((0.01 * k as f64).sin(), 0.5))
        .collect();
    let embedding = Embedding::grunwald_letnikov(Side::Backward, 0.6).unwrap();
    let fast = Discretisation::new(&Mixed, Grid::new(0.0, 1.0, n).unwrap(), embedding);
    assert!(fast.velocity_fft.0.get().is_none() && fast.adjoint_fft.0.get().is_none());
    fast.residual(Scheme::Variational, &q).unwrap();
    let built = fast.velocity_fft.0.get().map(|m| m as *const _);
    assert!(built.is_some() && fast.adjoint_fft.0.get().is_none());
    fast.residual(Scheme::Direct, &q).unwrap();
    fast.action(&q).unwrap();
    assert_eq!(fast.velocity_fft.0.get().map(|m| m as *const _), built);
    assert!(fast.adjoint_fft.0.get().is_some());

    let small = Grid::new(0.0, 1.0, FFT_OPERATOR_THRESHOLD).unwrap();
    let dense = Discretisation::new(&Mixed, small, embedding);
    dense
        .residual(Scheme::Direct, &q[..=FFT_OPERATOR_THRESHOLD])
        .unwrap();
    dense
        .residual(Scheme::Variational, &q[..=FFT_OPERATOR_THRESHOLD])
        .unwrap();
    assert!(dense.velocity_fft.0.get().is_none() && dense.adjoint_fft.0.get().is_none());
}

/// The assembled Jacobian equals central differences of the residual, for every scheme of
/// every embedding (so Newton's quadratic convergence rests on the right matrix).
#[test]
fn jacobian_matches_finite_differences_of_the_residual() {
    jacobian_matches(&Mixed, true);
    // Under a force: the classical embeddings (the fractional ones refuse a force).
    jacobian_matches(&crate::test_models::FORCED_MIXED, false);
}

fn jacobian_matches<L: Lagrangian<2>>(lagrangian: &L, fractional: bool) {
    let n = 9;
    let grid = Grid::new(0.1, 1.0, n).unwrap();
    let mut embeddings = Vec::new();
    for side in [Side::Backward, Side::Forward] {
        embeddings.push(Embedding::finite_difference(side));
        embeddings.push(Embedding::asymmetric(side));
        if fractional {
            embeddings.push(Embedding::grunwald_letnikov(side, 0.6).unwrap());
            embeddings.push(Embedding::caputo(side, 0.6).unwrap());
            embeddings.push(Embedding::corrected_grunwald_letnikov(side, 0.6).unwrap());
        }
    }
    embeddings.push(Embedding::midpoint());
    embeddings.push(Embedding::trapezoidal());
    let q: Vec<Vector<2>> = (0..=n)
        .map(|k| Vector::<2>::new((k as f64 * 0.7).sin(), (k as f64 * 0.3).cos() - 0.5))
        .collect();
    for embedding in embeddings {
        let mut disc = Discretisation::new(lagrangian, grid, embedding);
        // Panels of two unknown nodes: the kinetic term's products cross panel borders.
        disc.kinetic_panel = 2;
        for scheme in [Scheme::Direct, Scheme::Variational] {
            let pw = disc.pointwise(&q).unwrap();
            let jac = disc.dense_jacobian(scheme, &q, &pw);
            let eps = 1e-6;
            for j in 1..n {
                for c in 0..2 {
                    let (mut plus, mut minus) = (q.clone(), q.clone());
                    plus[j][c] += eps;
                    minus[j][c] -= eps;
                    let rp = disc.residual(scheme, &plus).unwrap();
                    let rm = disc.residual(scheme, &minus).unwrap();
                    for i in 0..n - 1 {
                        for a in 0..2 {
                            let fd = (rp[i][a] - rm[i][a]) / (2.0 * eps);
                            let exact = jac[(i * 2 + a, (j - 1) * 2 + c)];
                            assert!(
                                (fd - exact).abs() <= 1e-6 * (1.0 + fd.abs()),
                                "{embedding} {scheme}: d r_{i}[{a}] / d Q_{j}[{c}] = {exact} vs {fd}"
                            );
                        }
                    }
                }
            }
        }
    }
}

/// The kinetic term of a fractional Jacobian by matrix products in panels of columns equals
/// the sum `Σ_m B[k, m] L_vv(m) D[m, j]` written out entry by entry, whatever the panel width
/// (one node, a width that does not divide `N − 1`, all columns at once), for both sides,
/// both schemes and every fractional form, on a model whose `L_vv` depends on `x` and `v`.
#[test]
fn kinetic_products_in_panels_equal_the_sum_entry_by_entry() {
    let n = 23;
    let grid = Grid::new(0.1, 1.0, n).unwrap();
    let q: Vec<Vector<2>> = (0..=n)
        .map(|k| Vector::<2>::new((k as f64 * 0.4).sin(), (k as f64 * 0.2).cos() - 0.3))
        .collect();
    for side in [Side::Backward, Side::Forward] {
        for embedding in [
            Embedding::grunwald_letnikov(side, 0.7).unwrap(),
            Embedding::caputo(side, 0.45).unwrap(),
            Embedding::corrected_grunwald_letnikov(side, 0.6).unwrap(),
        ] {
            let mut disc = Discretisation::new(&Mixed, grid, embedding);
            let pw = disc.pointwise(&q).unwrap();
            for scheme in [Scheme::Direct, Scheme::Variational] {
                // The oracle: the triple sum, block by block.
                let sigma = embedding.side().sign();
                let size = (n - 1) * 2;
                let mut want = nalgebra::DMatrix::<f64>::zeros(size, size);
                let operators = (&disc.velocity, &disc.adjoint);
                for (i, k) in disc.rows(scheme).enumerate() {
                    for (m, b) in embedding.momentum_row(scheme, operators, k) {
                        let vv = Mixed.hessian(&q[m], &pw.v[m], grid.t(m)).vv;
                        for (j, c) in disc.velocity.row_entries(m) {
                            if (1..n).contains(&j) {
                                let mut view = want.view_mut((i * 2, (j - 1) * 2), (2, 2));
                                view += vv * (b * -sigma * c);
                            }
                        }
                    }
                }
                let scale = want.amax();
                for panel in [1, 5, n] {
                    disc.kinetic_panel = panel;
                    let vv: Vec<_> = (0..=n)
                        .map(|m| {
                            let reached = embedding.quadrature_rows(n).contains(&m);
                            reached.then(|| Mixed.hessian(&q[m], &pw.v[m], grid.t(m)).vv)
                        })
                        .collect();
                    let mut got = nalgebra::DMatrix::<f64>::zeros(size, size);
                    disc.add_kinetic_term(scheme, &vv, &mut |i, j, block| {
                        let mut view = got.view_mut((i * 2, j * 2), (2, 2));
                        view += block;
                    });
                    let error = (&got - &want).amax();
                    assert!(
                        error <= 1e-13 * scale,
                        "{embedding} {scheme}, panel {panel}: {error:e} of {scale:e}"
                    );
                }
            }
        }
    }
}
