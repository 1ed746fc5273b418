//! Issue 5: the fractional boundary-value fast path (FFT operators, Newton–Krylov) against the
//! dense reference.

mod common;
use common::Rng;
use varembed::{FftOperator, Grid, Operator, Side, Vector};

fn relative_gap<const D: usize>(fast: &[Vector<D>], dense: &[Vector<D>]) -> f64 {
    assert_eq!(fast.len(), dense.len());
    let scale = dense.iter().fold(0.0f64, |m, v| m.max(v.amax()));
    let gap = fast
        .iter()
        .zip(dense)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).amax()));
    gap / scale
}

fn check_operator<const D: usize>(rng: &mut Rng, n: usize, side: Side, alpha: f64) {
    let grid = Grid::new(0.0, 1.3, n).unwrap();
    let op = Operator::grunwald_letnikov(side, alpha, &grid).unwrap();
    let mut fast = FftOperator::new(&op);
    let q = rng.curve::<D>(n, 1.0);
    let w: Vec<Vector<D>> = rng.curve::<D>(n - 1, 1.0);
    let apply = relative_gap(&fast.apply(&q).unwrap(), &op.apply(&q).unwrap());
    let transpose = relative_gap(
        &fast.apply_transpose(&w).unwrap(),
        &op.apply_transpose(&w).unwrap(),
    );
    assert!(
        apply <= 1e-12 && transpose <= 1e-12,
        "N = {n}, {side:?}, α = {alpha}, d = {D}: apply {apply:e}, transpose {transpose:e}"
    );
}

/// Must-show 1: FFT products equal the dense loops to 1e-12 relative.
#[test]
fn fft_products_equal_the_dense_loops() {
    let mut rng = Rng(11);
    for n in [1, 2, 7, 64, 100, 333, 1000] {
        for side in [Side::Backward, Side::Forward] {
            for alpha in [0.1, 0.3, 0.5, 0.7, 0.95, 1.0] {
                check_operator::<1>(&mut rng, n, side, alpha);
                check_operator::<2>(&mut rng, n, side, alpha);
                check_operator::<3>(&mut rng, n, side, alpha);
            }
        }
    }
}

#[test]
fn fft_products_check_lengths() {
    let grid = Grid::new(0.0, 1.0, 5).unwrap();
    let op = Operator::grunwald_letnikov(Side::Forward, 0.5, &grid).unwrap();
    let mut fast = FftOperator::new(&op);
    assert!(fast.apply(&[Vector::<1>::zeros(); 5]).is_err());
    assert!(fast.apply_transpose(&[Vector::<1>::zeros(); 6]).is_err());
}
