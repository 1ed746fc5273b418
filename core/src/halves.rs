//! Sweeps over long vectors in two halves, on two threads with the `parallel` feature: the
//! vector updates and dot products of the fractional fast path's Krylov solver and
//! preconditioner, which at millions of unknowns are memory traffic a second core shares,
//! beside FFTs that already run on both.
//!
//! Where a half ends depends on the length alone (below [`FROM`] there is one piece), so a sum
//! over the halves (`first + second`) rounds the same with and without the feature: the
//! feature decides only whether the halves run at once.

use std::ops::Add;

/// The number of entries (or blocks) from which a sweep is taken in two halves. Below it a
/// sweep is a single piece, summed as one loop sums it.
pub(crate) const FROM: usize = 1 << 17;

/// Runs `a` and `b`, on two threads with the `parallel` feature (rayon's `join`).
pub(crate) fn both<A: Send, B: Send>(
    a: impl FnOnce() -> A + Send,
    b: impl FnOnce() -> B + Send,
) -> (A, B) {
    #[cfg(feature = "parallel")]
    return rayon::join(a, b);
    #[cfg(not(feature = "parallel"))]
    (a(), b())
}

/// Slices, and tuples of them, that a sweep splits at one index.
pub(crate) trait Split: Sized + Send {
    /// The parts before and from entry `at`.
    fn split(self, at: usize) -> (Self, Self);

    /// Whether every slice holds `len` entries.
    fn all_of_len(&self, len: usize) -> bool;
}

impl Split for &mut [f64] {
    fn split(self, at: usize) -> (Self, Self) {
        self.split_at_mut(at)
    }
    fn all_of_len(&self, len: usize) -> bool {
        self.len() == len
    }
}

impl Split for &[f64] {
    fn split(self, at: usize) -> (Self, Self) {
        self.split_at(at)
    }
    fn all_of_len(&self, len: usize) -> bool {
        self.len() == len
    }
}

impl<A: Split, B: Split> Split for (A, B) {
    fn split(self, at: usize) -> (Self, Self) {
        let ((a0, a1), (b0, b1)) = (self.0.split(at), self.1.split(at));
        ((a0, b0), (a1, b1))
    }
    fn all_of_len(&self, len: usize) -> bool {
        self.0.all_of_len(len) && self.1.all_of_len(len)
    }
}

impl<A: Split, B: Split, C: Split> Split for (A, B, C) {
    fn split(self, at: usize) -> (Self, Self) {
        let ((a0, a1), ((b0, c0), (b1, c1))) = (self.0.split(at), (self.1, self.2).split(at));
        ((a0, b0, c0), (a1, b1, c1))
    }
    fn all_of_len(&self, len: usize) -> bool {
        self.0.all_of_len(len) && self.1.all_of_len(len) && self.2.all_of_len(len)
    }
}

impl<A: Split, B: Split, C: Split, D: Split> Split for (A, B, C, D) {
    fn split(self, at: usize) -> (Self, Self) {
        let ((a0, a1), ((b0, c0, d0), (b1, c1, d1))) =
            (self.0.split(at), (self.1, self.2, self.3).split(at));
        ((a0, b0, c0, d0), (a1, b1, c1, d1))
    }
    fn all_of_len(&self, len: usize) -> bool {
        let (a, b, c, d) = self;
        a.all_of_len(len) && b.all_of_len(len) && c.all_of_len(len) && d.all_of_len(len)
    }
}

/// `f(first, parts)` over `blocks` blocks of `width` entries each (the slices of `parts` hold
/// `blocks · width` entries), as one piece (`first = 0`) below [`FROM`] blocks, else as two
/// halves split at a block boundary (`first` the index of a half's first block), their results
/// added in order.
pub(crate) fn sum<S: Split, T: Add<Output = T> + Send>(
    (blocks, width): (usize, usize),
    parts: S,
    f: impl Fn(usize, S) -> T + Sync,
) -> T {
    // The halves' closures count their blocks by their slices' lengths.
    debug_assert!(
        parts.all_of_len(blocks * width),
        "a slice not of {blocks} blocks"
    );
    if blocks < FROM {
        return f(0, parts);
    }
    let middle = blocks / 2;
    let (low, high) = parts.split(middle * width);
    let (a, b) = both(|| f(0, low), || f(middle, high));
    a + b
}

/// [`sum`] of a sweep that returns nothing.
pub(crate) fn each<S: Split>(
    (blocks, width): (usize, usize),
    parts: S,
    f: impl Fn(usize, S) + Sync,
) {
    sum((blocks, width), parts, |first, parts| {
        f(first, parts);
        Unit
    });
}

/// The result of a sweep that returns nothing.
struct Unit;

impl Add for Unit {
    type Output = Unit;
    fn add(self, _: Unit) -> Unit {
        Unit
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two halves from [`FROM`] blocks on, at a block boundary, each told its first block; one
    /// piece below; the sum is the first half's plus the second's.
    #[test]
    fn sweeps_split_in_two_halves_at_a_block_boundary() {
        for (blocks, width) in [
            (10, 3),
            (FROM - 1, 1),
            (FROM, 1),
            (FROM + 1, 2),
            (FROM + 3, 3),
        ] {
            let n = blocks * width;
            let x: Vec<f64> = (0..n).map(|i| 1.0 / (1.0 + i as f64)).collect();
            let mut y = vec![0.0; n];
            let pieces = std::sync::Mutex::new(Vec::new());
            let total = sum((blocks, width), (&mut y[..], &x[..]), |first, (y, x)| {
                pieces.lock().unwrap().push((first, x.len()));
                let mut s = 0.0;
                for (i, (y, x)) in y.iter_mut().zip(x).enumerate() {
                    *y = (first * width + i) as f64;
                    s += x;
                }
                s
            });
            let mut pieces = pieces.into_inner().unwrap();
            pieces.sort();
            let want = if blocks < FROM {
                vec![(0, n)]
            } else {
                let middle = blocks / 2;
                vec![(0, middle * width), (middle, n - middle * width)]
            };
            assert_eq!(pieces, want, "{blocks} × {width}");
            assert!(y.iter().enumerate().all(|(i, y)| *y == i as f64));
            let split = want[0].1;
            let halves: f64 = x[..split].iter().sum::<f64>() + x[split..].iter().sum::<f64>();
            assert_eq!(total.to_bits(), halves.to_bits());
        }
    }
}
