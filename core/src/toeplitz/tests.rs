use super::*;

fn dense(c: &[f64], x: &[f64], transpose: bool) -> Vec<f64> {
    let m = c.len();
    (0..m)
        .map(|k| {
            (0..m)
                .map(|j| {
                    let (row, col) = if transpose { (j, k) } else { (k, j) };
                    if row >= col { c[row - col] * x[j] } else { 0.0 }
                })
                .sum()
        })
        .collect()
}

#[test]
fn small_products_are_the_matrix_products() {
    let t = TriangularToeplitz::new(&[1.0, -1.0, 0.5]);
    let mut ws = Workspace::new(&t);
    let (mut ta, mut tta) = (vec![0.0; 3], vec![0.0; 3]);
    t.mul(false, &mut ws, &[1.0, 2.0, 3.0], &mut ta);
    t.mul(true, &mut ws, &[1.0, 2.0, 3.0], &mut tta);
    // T = [[1, 0, 0], [−1, 1, 0], [0.5, −1, 1]]
    for (x, y) in ta.iter().zip([1.0, 1.0, 1.5]) {
        assert!((x - y).abs() < 1e-14);
    }
    for (x, y) in tta.iter().zip([0.5, -1.0, 3.0]) {
        assert!((x - y).abs() < 1e-14);
    }
}

#[test]
fn products_match_the_dense_matrix() {
    for m in [1usize, 2, 3, 5, 16, 17, 100, 257] {
        let c: Vec<f64> = (0..m).map(|r| ((r * 7 + 3) as f64).sin()).collect();
        let a: Vec<f64> = (0..m).map(|r| ((r * 5 + 1) as f64).cos()).collect();
        let b: Vec<f64> = (0..m).map(|r| 1.0 / (1.0 + r as f64)).collect();
        let t = TriangularToeplitz::new(&c);
        assert!(t.fft_len() >= 2 * m - 1);
        let mut ws = Workspace::new(&t);
        for transpose in [false, true] {
            let (mut ta, mut tb) = (vec![0.0; m], vec![0.0; m]);
            t.mul(transpose, &mut ws, &a, &mut ta);
            t.mul(transpose, &mut ws, &b, &mut tb);
            for (got, want) in [
                (ta, dense(&c, &a, transpose)),
                (tb, dense(&c, &b, transpose)),
            ] {
                let scale = want.iter().fold(1e-300f64, |s, x| s.max(x.abs()));
                for (g, w) in got.iter().zip(&want) {
                    assert!((g - w).abs() <= 1e-13 * scale, "m = {m}: {g} vs {w}");
                }
            }
        }
    }
}

/// A product with the first difference folded into the spectrum is the product with the
/// differenced column `c * (1, −1)` cut at the order: against the dense matrix for small
/// orders, against the FFT product of the differenced column past [`SPLIT_FROM`] (even and odd
/// half lengths), both ways.
#[test]
fn products_with_the_difference_are_those_of_the_differenced_column() {
    for m in [1usize, 2, 3, 17, 257, 3 * SPLIT_FROM, 354_293] {
        let c: Vec<f64> = (0..m).map(|r| 1.0 / (1.0 + r as f64).powf(0.6)).collect();
        let differenced: Vec<f64> = (0..m)
            .map(|r| c[r] - if r > 0 { c[r - 1] } else { 0.0 })
            .collect();
        let x: Vec<f64> = (0..m).map(|r| ((r * 5 + 1) as f64).cos()).collect();
        let (t, mut ws) = TriangularToeplitz::with_workspace(&c);
        let reference = TriangularToeplitz::new(&differenced);
        for transpose in [false, true] {
            let mut got = vec![0.0; m];
            t.load(&mut ws, |k| x[k]);
            t.mul_loaded_with_difference(transpose, &mut ws);
            t.store(&ws, |k, y| got[k] = y);
            let want = if m < 1000 {
                dense(&differenced, &x, transpose)
            } else {
                let mut y = vec![0.0; m];
                reference.mul(transpose, &mut ws, &x, &mut y);
                y
            };
            let scale = want.iter().fold(1e-300f64, |s, x| s.max(x.abs()));
            for (k, (g, w)) in got.iter().zip(&want).enumerate() {
                assert!(
                    (g - w).abs() <= 1e-12 * scale,
                    "m = {m}, {transpose}, {k}: {g} vs {w}"
                );
            }
        }
    }
}

/// Past [`SPLIT_FROM`], where the two half-length transforms may run on two threads,
/// the products still equal the sums, checked at rows spread over the whole range.
#[test]
fn long_products_match_the_sums() {
    // K/2 = 393 216 (even) and 3¹¹ = 177 147 (odd: no middle pair in the pass).
    for m in [3 * SPLIT_FROM, 354_293] {
        long_product_matches_the_sums(m);
    }
}

fn long_product_matches_the_sums(m: usize) {
    let c: Vec<f64> = (0..m).map(|r| 1.0 / (1.0 + r as f64).powf(1.7)).collect();
    let x: Vec<f64> = (0..m).map(|r| ((r * 5 + 1) as f64).cos()).collect();
    let t = TriangularToeplitz::new(&c);
    assert!(t.fft_len() / 4 >= SPLIT_FROM);
    let mut ws = Workspace::new(&t);
    for transpose in [false, true] {
        let mut y = vec![0.0; m];
        t.mul(transpose, &mut ws, &x, &mut y);
        for k in (0..m).step_by(997).chain([1, m - 2, m - 1]) {
            let want: f64 = if transpose {
                (0..m - k).map(|r| c[r] * x[k + r]).sum()
            } else {
                (0..=k).map(|r| c[r] * x[k - r]).sum()
            };
            assert!(
                (y[k] - want).abs() < 1e-12,
                "{transpose} {k}: {} vs {want}",
                y[k]
            );
        }
    }
}

/// Loading and storing in decreasing order give the same product, bit for bit, and read
/// and write every entry once in that order, whole and split into halves.
#[test]
fn descending_loads_and_stores_are_the_same_product() {
    for m in [1usize, 2, 3, 5, 16, 17, 100, 4 * SPLIT_FROM + 3] {
        let c: Vec<f64> = (0..m).map(|r| 1.0 / (1.0 + r as f64).powf(1.3)).collect();
        let x: Vec<f64> = (0..m).map(|r| ((r * 5 + 1) as f64).cos()).collect();
        let t = TriangularToeplitz::new(&c);
        let mut ws = Workspace::new(&t);
        for transpose in [false, true] {
            let mut want = vec![0.0; m];
            t.mul(transpose, &mut ws, &x, &mut want);
            let (mut read, mut written) = (Vec::new(), Vec::new());
            t.load_descending(&mut ws, |k| {
                read.push(k);
                x[k]
            });
            t.mul_loaded(transpose, &mut ws);
            let mut got = vec![f64::NAN; m];
            t.store_descending(&ws, |k, y| {
                written.push(k);
                got[k] = y;
            });
            let descending: Vec<usize> = (0..m).rev().collect();
            assert_eq!(read, descending, "m = {m}");
            assert_eq!(written, descending, "m = {m}");
            assert!(
                got.iter()
                    .zip(&want)
                    .all(|(a, b)| a.to_bits() == b.to_bits())
            );
        }
    }
}

/// The strided product in place is the product of the one strided vector, bit for bit,
/// and leaves the other interleaved vectors alone, whole and split (where its loading and
/// reading run in two halves), for odd and even orders and numbers of pairs.
#[test]
fn strided_products_in_place_are_the_products() {
    for m in [
        1usize,
        2,
        3,
        5,
        16,
        17,
        100,
        4 * SPLIT_FROM + 1,
        4 * SPLIT_FROM + 3,
    ] {
        let c: Vec<f64> = (0..m).map(|r| 1.0 / (1.0 + r as f64).powf(1.3)).collect();
        let t = TriangularToeplitz::new(&c);
        let mut ws = Workspace::new(&t);
        for (stride, offset) in [(1, 0), (3, 0), (3, 2)] {
            let all: Vec<f64> = (0..m * stride)
                .map(|i| ((i * 7 + 2) as f64).sin())
                .collect();
            let x: Vec<f64> = (0..m).map(|k| all[k * stride + offset]).collect();
            for transpose in [false, true] {
                let mut want = vec![0.0; m];
                t.mul(transpose, &mut ws, &x, &mut want);
                let mut got = all.clone();
                t.mul_strided_in_place(transpose, &mut ws, &mut got, (stride, offset));
                for (i, (g, a)) in got.iter().zip(&all).enumerate() {
                    let expected = if i % stride == offset {
                        want[i / stride]
                    } else {
                        *a
                    };
                    assert_eq!(g.to_bits(), expected.to_bits(), "m = {m}, entry {i}");
                }
            }
        }
    }
}

/// A matrix sharing another's plans (and workspace) multiplies like one built alone.
#[test]
fn shared_plans_give_the_same_products() {
    let m = 40;
    let c: Vec<f64> = (0..m).map(|r| 1.0 / (1.0 + r as f64)).collect();
    let x: Vec<f64> = (0..m).map(|r| ((r * 3) as f64).sin()).collect();
    let (host, mut ws) = TriangularToeplitz::with_workspace(&vec![1.0; m + 7]);
    let shared = host.with_same_plans(&c, &mut ws);
    assert_eq!(shared.fft_len(), host.fft_len());
    let alone = TriangularToeplitz::new(&c);
    let mut ws_alone = Workspace::new(&alone);
    for transpose in [false, true] {
        let (mut a, mut b) = (vec![0.0; m], vec![0.0; m]);
        shared.mul(transpose, &mut ws, &x, &mut a);
        alone.mul(transpose, &mut ws_alone, &x, &mut b);
        let want = dense(&c, &x, transpose);
        for ((a, b), w) in a.iter().zip(&b).zip(&want) {
            assert!(
                (a - w).abs() < 1e-13 && (b - w).abs() < 1e-13,
                "{a} {b} {w}"
            );
        }
    }
}

#[test]
fn fft_lengths_are_long_enough_smooth_and_tight() {
    for m in 1..2000 {
        let l = fft_len(m);
        assert!(l >= 2 * m - 1 && l.is_multiple_of(2));
        let mut odd = l >> l.trailing_zeros();
        for p in [3, 5] {
            while odd.is_multiple_of(p) {
                odd /= p;
            }
        }
        assert_eq!(odd, 1, "{l}");
        assert!(!(l / 2).is_multiple_of(125), "{l} has 5³");
        assert!(
            l <= 2 * m - 1 + (2 * m - 1) / 8 + 8,
            "{m}: {l} is not tight"
        );
    }
}
