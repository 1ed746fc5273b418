//! Coherence (paper §2.2–3.2): on random Q the direct and variational residuals
//! agree to round-off for the asymmetric Gauss-FDE± and Gauss-GLE± (both forms), and differ by O(1) for
//! Gauss-FDE±.

use varembed::{Embedding, Grid, Scheme, Side};
use varembed_tests::curve::{max_diff, max_norm};
use varembed_tests::models::hand::Coupled;
use varembed_tests::rng::Rng;

#[test]
fn asymmetric_and_grunwald_letnikov_embeddings_are_coherent() {
    let grid = Grid::new(0.0, 2.0, 40).unwrap();
    let mut rng = Rng(3);
    for side in [Side::Backward, Side::Forward] {
        let mut embeddings = vec![Embedding::asymmetric(side)];
        for alpha in [0.1, 0.3, 0.5, 0.7, 0.9, 1.0] {
            embeddings.push(Embedding::grunwald_letnikov(side, alpha).unwrap());
            embeddings.push(Embedding::caputo(side, alpha).unwrap());
        }
        for embedding in embeddings {
            let problem = varembed_tests::problem(&Coupled, grid, embedding);
            assert_eq!(
                problem.residual_rows(Scheme::Direct),
                problem.residual_rows(Scheme::Variational)
            );
            for _ in 0..5 {
                let q = rng.curve::<2>(grid.n(), 1.0);
                let direct = problem.residual(Scheme::Direct, &q).unwrap();
                let variational = problem.residual(Scheme::Variational, &q).unwrap();
                let relative = max_diff(&direct, &variational) / max_norm(&variational);
                assert!(relative < 1e-12, "{embedding}: relative gap {relative:e}");
            }
        }
    }
}

#[test]
fn finite_difference_embedding_is_not_coherent() {
    let grid = Grid::new(0.0, 2.0, 40).unwrap();
    let mut rng = Rng(5);
    for side in [Side::Backward, Side::Forward] {
        let problem = varembed_tests::problem(&Coupled, grid, Embedding::finite_difference(side));
        let direct_rows = problem.residual_rows(Scheme::Direct);
        let expected = match side {
            Side::Backward => 2..=40,
            Side::Forward => 0..=38,
        };
        assert_eq!(direct_rows, expected);
        let q = rng.curve::<2>(grid.n(), 1.0);
        let direct = problem.residual(Scheme::Direct, &q).unwrap();
        let variational = problem.residual(Scheme::Variational, &q).unwrap();
        // Compare the rows both schemes have (nodes 2..=38 for both sides).
        let d0 = *direct_rows.start();
        let gap = (2..=38)
            .map(|k| (direct[k - d0] - variational[k - 1]).amax())
            .fold(0.0f64, f64::max);
        let relative = gap / max_norm(&variational);
        assert!(
            relative > 0.1,
            "{side:?}: Gauss-FDE should not be coherent, gap {relative:e}"
        );
    }
}
