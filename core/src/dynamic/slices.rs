//! The vector operations of the run-time steps on slices: max-norm and dot product over
//! interleaved lanes, and the weighted sums a step's terms accumulate.

/// `r ← w x − π` (`Some(π)`: the first term) or `r ← r + w x`, measuring on the way:
/// returns `max |w x_i|` (the term's size) and `max |r_i|` after the update (NaN when an entry
/// of `r` is NaN), so that a residual's last term leaves no pass of its own for its norms.
///
/// Four running maxima over interleaved entries, as in [`max_norm`].
#[inline]
pub(super) fn accumulate(r: &mut [f64], w: f64, x: &[f64], first: Option<&[f64]>) -> (f64, f64) {
    match first {
        Some(pi) => accumulate_with(r, w, x, pi, |term, pi, _| term - pi),
        None => accumulate_with(r, w, x, x, |term, _, r| r + term),
    }
}

/// `r_i ← update(w x_i, π_i, r_i)` over four interleaved lanes (a shape the compiler turns
/// into vector instructions), with the maxima of [`accumulate`].
#[inline(always)]
fn accumulate_with(
    r: &mut [f64],
    w: f64,
    x: &[f64],
    pi: &[f64],
    update: impl Fn(f64, f64, f64) -> f64,
) -> (f64, f64) {
    let (mut terms, mut sums) = ([0.0f64; 4], [0.0f64; 4]);
    let mut nan = false;
    let n = r.len().min(x.len()).min(pi.len());
    let (r, x, pi) = (&mut r[..n], &x[..n], &pi[..n]);
    let mut step = |lane: usize, r: &mut f64, x: f64, pi: f64| {
        let term = w * x;
        *r = update(term, pi, *r);
        let (t, a) = (term.abs(), r.abs());
        terms[lane] = if t > terms[lane] { t } else { terms[lane] };
        sums[lane] = if a > sums[lane] { a } else { sums[lane] };
        nan |= a.is_nan();
    };
    let mut chunks = r.chunks_exact_mut(4);
    let (xs, ps) = (x.chunks_exact(4), pi.chunks_exact(4));
    let (x_tail, p_tail) = (xs.remainder(), ps.remainder());
    for ((r, x), pi) in (&mut chunks).zip(xs).zip(ps) {
        for lane in 0..4 {
            step(lane, &mut r[lane], x[lane], pi[lane]);
        }
    }
    for (lane, r) in chunks.into_remainder().iter_mut().enumerate() {
        step(lane, r, x_tail[lane], p_tail[lane]);
    }
    let largest = |lanes: [f64; 4]| lanes.into_iter().fold(0.0, f64::max);
    let residual = if nan { f64::NAN } else { largest(sums) };
    (largest(terms), residual)
}

/// `y ← w x` (`fresh`) or `y ← y + w x`.
#[inline]
pub(super) fn axpy(y: &mut [f64], w: f64, x: &[f64], fresh: bool) {
    for (y, x) in y.iter_mut().zip(x) {
        *y = if fresh { w * x } else { *y + w * x };
    }
}

/// Max-norm of a slice; NaN when an entry is NaN.
///
/// Four running maxima over interleaved entries, so that each comparison waits on the one
/// four entries back rather than on the last (a single running maximum is a chain of
/// dependent comparisons, the slowest pass of a Newton iteration on a chain).
pub(crate) fn max_norm(x: &[f64]) -> f64 {
    let mut lanes = [0.0f64; 4];
    let mut nan = false;
    let mut chunks = x.chunks_exact(4);
    for chunk in &mut chunks {
        for (m, c) in lanes.iter_mut().zip(chunk) {
            let a = c.abs();
            *m = if a > *m { a } else { *m };
            nan |= a.is_nan();
        }
    }
    for (m, c) in lanes.iter_mut().zip(chunks.remainder()) {
        let a = c.abs();
        *m = if a > *m { a } else { *m };
        nan |= a.is_nan();
    }
    if nan {
        f64::NAN
    } else {
        lanes.into_iter().fold(0.0, f64::max)
    }
}

/// `Σ a_i b_i` over four running sums of interleaved terms (a single running sum is a chain
/// of dependent additions, as slow as a whole explicit step at large `d`); the guard's `v·p`,
/// where the order of the additions only moves the last bits.
pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut lanes = [0.0f64; 4];
    let (mut x, mut y) = (a.chunks_exact(4), b.chunks_exact(4));
    for (x, y) in (&mut x).zip(&mut y) {
        for ((s, x), y) in lanes.iter_mut().zip(x).zip(y) {
            *s += x * y;
        }
    }
    let tail: f64 = x
        .remainder()
        .iter()
        .zip(y.remainder())
        .map(|(x, y)| x * y)
        .sum();
    (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]) + tail
}

#[cfg(test)]
mod tests {
    use super::{accumulate, dot, max_norm};

    #[test]
    fn dot_is_the_sum_of_products() {
        for n in 0..11 {
            let a: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
            let b: Vec<f64> = (0..n).map(|i| (i as f64 * 1.3).cos()).collect();
            let expected: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
            assert!(
                (dot(&a, &b) - expected).abs() <= 1e-15 * n as f64,
                "n = {n}"
            );
        }
    }

    #[test]
    fn accumulate_sums_and_measures_the_term_and_the_sum() {
        for n in 0..11 {
            let x: Vec<f64> = (0..n).map(|i| ((i * 37 % 11) as f64 - 5.3) * 1.7).collect();
            let pi: Vec<f64> = (0..n).map(|i| (i as f64 * 0.9).cos()).collect();
            let w = -0.37;
            let mut r = vec![f64::NAN; n];
            let (term, residual) = accumulate(&mut r, w, &x, Some(&pi));
            let expected: Vec<f64> = x.iter().zip(&pi).map(|(x, p)| w * x - p).collect();
            assert_eq!(r, expected, "n = {n}");
            let w_x: Vec<f64> = x.iter().map(|x| w * x).collect();
            assert_eq!((term, residual), (max_norm(&w_x), max_norm(&r)), "n = {n}");
            let (term, residual) = accumulate(&mut r, 2.0, &pi, None);
            let expected: Vec<f64> = expected.iter().zip(&pi).map(|(r, p)| r + 2.0 * p).collect();
            assert_eq!(r, expected, "n = {n}");
            let two_pi: Vec<f64> = pi.iter().map(|p| 2.0 * p).collect();
            assert_eq!(
                (term, residual),
                (max_norm(&two_pi), max_norm(&r)),
                "n = {n}"
            );
            for k in 0..n {
                let mut with_nan = x.clone();
                with_nan[k] = f64::NAN;
                let mut r = vec![0.0; n];
                assert!(
                    accumulate(&mut r, w, &with_nan, None).1.is_nan(),
                    "NaN at {k} of {n}"
                );
            }
        }
    }

    #[test]
    fn max_norm_is_the_largest_magnitude_and_nan_anywhere_shows() {
        for n in 0..11 {
            let x: Vec<f64> = (0..n).map(|i| ((i * 37 % 11) as f64 - 5.3) * 1.7).collect();
            let expected = x.iter().fold(0.0f64, |m, c| m.max(c.abs()));
            assert_eq!(max_norm(&x), expected, "n = {n}");
            for k in 0..n {
                let mut with_nan = x.clone();
                with_nan[k] = f64::NAN;
                assert!(max_norm(&with_nan).is_nan(), "NaN at {k} of {n}");
            }
        }
        assert_eq!(max_norm(&[1.0, f64::NEG_INFINITY]), f64::INFINITY);
    }
}
