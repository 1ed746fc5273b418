//! The Jacobian the rows assemble against central differences of the rows themselves, for
//! every classical embedding and both schemes, on a model whose every block varies.

use super::*;
use crate::side::Side;
use crate::test_models::{DYN_MIXED_DIMENSION as D, DynMixed};

/// A curve of `n + 1` nodes, every coordinate moving differently.
fn curve(n: usize) -> Vec<f64> {
    (0..=n)
        .flat_map(|k| {
            (0..D).map(move |i| {
                let s = k as f64 / n as f64;
                0.3 * (1.7 * s + i as f64).sin() - 0.1 * i as f64 + 0.2 * s * s
            })
        })
        .collect()
}

/// `∂r_i/∂Q_j` assembled by `jacobian_row` equals central differences of `evaluate`'s rows in
/// every interior node coordinate, entry by entry (a transposed `L_xv`, a wrong end weight of
/// the trapezoidal rule, a missing centred-velocity term or a missing force block each fail
/// it).
#[test]
fn the_jacobian_matches_central_differences_of_the_rows() {
    let model = DynMixed { forced: true };
    let (n, grid) = (6, Grid::new(0.1, 0.7, 6).unwrap());
    let q = curve(n);
    let embeddings = [
        Embedding::finite_difference(Side::Backward),
        Embedding::finite_difference(Side::Forward),
        Embedding::asymmetric(Side::Backward),
        Embedding::asymmetric(Side::Forward),
        Embedding::midpoint(),
        Embedding::trapezoidal(),
    ];
    for embedding in embeddings {
        for scheme in [Scheme::Direct, Scheme::Variational] {
            let rows = DynRows::new(&model, grid, embedding, scheme).unwrap();
            let mut values = rows.zero_values();
            rows.evaluate(&q, &mut values).unwrap();
            let size = (n - 1) * D;
            let mut jacobian = vec![0.0; size * size];
            let mut hessians = HessianCache::new(D);
            for i in 0..n - 1 {
                rows.jacobian_row(i, &mut hessians, &q, &values, |r, c, v| {
                    jacobian[r * size + c] += v;
                });
            }
            let eps = 1e-6;
            for col in 0..size {
                let moved = |delta: f64| {
                    let mut q = q.clone();
                    q[D + col] += delta;
                    let mut values = rows.zero_values();
                    rows.evaluate(&q, &mut values).unwrap();
                    values.r
                };
                let (plus, minus) = (moved(eps), moved(-eps));
                for row in 0..size {
                    let fd = (plus[row] - minus[row]) / (2.0 * eps);
                    let exact = jacobian[row * size + col];
                    assert!(
                        (exact - fd).abs() <= 1e-6 * (1.0 + fd.abs()),
                        "{embedding} {scheme} ({row}, {col}): {exact} vs {fd}"
                    );
                }
            }
        }
    }
}
