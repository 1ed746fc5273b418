//! A tridiagonal matrix factorised by LU with partial pivoting in the LAPACK `gttrf` scheme:
//! the band LU of [`BandedMatrix`](super::BandedMatrix) with `kl = ku = 1`, on three (four,
//! with the fill) diagonals instead of rows of four slots, without the index arithmetic of a
//! general band. A chain's step Jacobian is this matrix; the row exchanges, the multipliers
//! and the pivots are those of the band LU, operation for operation, so both give the same
//! multipliers and pivots to the last bit. The rows of `U` are kept divided by their pivots,
//! so that the solve has no division and one product on its recurrence, as the Thomas
//! algorithm's back substitution (solutions agree with the band LU's to rounding).

use super::{BandNorms, SINGULAR_RATIO};

/// An `n × n` tridiagonal matrix: `lower[i] = A(i + 1, i)`, `diagonal[i] = A(i, i)`,
/// `upper[i] = A(i, i + 1)`. After [`factorize_measured`](Self::factorize_measured) they hold
/// the factors `P A = L U`: `lower` the multipliers of `L`, `diagonal` the pivots `u_ii`, and
/// `upper`, `fill` the entries `(i, i + 1)`, `(i, i + 2)` of `U` divided by `u_ii` (`fill`: what
/// a row exchange brings).
pub struct TridiagonalMatrix {
    lower: Vec<f64>,
    diagonal: Vec<f64>,
    upper: Vec<f64>,
    fill: Vec<f64>,
    /// `1 / u_ii` after factorisation.
    inverse: Vec<f64>,
    /// Whether rows `i` and `i + 1` were exchanged at column `i`.
    exchanged: Vec<bool>,
}

impl TridiagonalMatrix {
    /// The zero `n × n` matrix.
    pub fn zeros(n: usize) -> Self {
        let off = n.saturating_sub(1);
        TridiagonalMatrix {
            lower: vec![0.0; off],
            diagonal: vec![0.0; n],
            upper: vec![0.0; off],
            fill: vec![0.0; n.saturating_sub(2)],
            inverse: vec![0.0; n],
            exchanged: vec![false; off],
        }
    }

    /// Order `n`.
    pub fn order(&self) -> usize {
        self.diagonal.len()
    }

    /// The three diagonals to write, `(lower, diagonal, upper)` (before factorisation).
    pub fn diagonals_mut(&mut self) -> (&mut [f64], &mut [f64], &mut [f64]) {
        (&mut self.lower, &mut self.diagonal, &mut self.upper)
    }

    /// Sets every entry to zero.
    pub fn clear(&mut self) {
        self.lower.fill(0.0);
        self.diagonal.fill(0.0);
        self.upper.fill(0.0);
    }

    /// Adds `value` to entry `(i, j)`, which must satisfy `|i − j| ≤ 1`.
    pub fn add(&mut self, i: usize, j: usize, value: f64) {
        debug_assert!(i.abs_diff(j) <= 1, "({i}, {j}) outside the three diagonals");
        if i == j {
            self.diagonal[i] += value;
        } else if i > j {
            self.lower[j] += value;
        } else {
            self.upper[i] += value;
        }
    }

    /// Factorises in place and measures the matrix it factorises on the way: its norms (of
    /// the entries as given), and whether it is regular, that is finite with no pivot at or
    /// below `1e-14` times its largest entry (the band LU's threshold), and with finite
    /// factors. The last condition is where the two can differ, only when the elimination
    /// overflows or a pivot's reciprocal does (entries near `1e-295`): the band LU would go on
    /// with a NaN or infinite factor, this one calls the matrix singular.
    ///
    /// The measure costs no pass of its own: row `i + 1` is read before column `i`'s
    /// elimination changes it, while the elimination waits on its division. The reciprocals of
    /// the pivots are kept, so that [`solve_inplace`](Self::solve_inplace) multiplies where the
    /// band LU divides.
    pub fn factorize_measured(&mut self) -> (BandNorms, bool) {
        self.eliminate(&mut [])
    }

    /// [`factorize_measured`](Self::factorize_measured), and when the matrix is regular, the
    /// solution of `A x = b` in place of `b` (otherwise `b` holds nothing of use): the forward
    /// substitution runs inside the elimination, as in the Thomas algorithm, so a
    /// factorisation used for one solve (a Newton iteration) reads the rows once less.
    pub fn factorize_solving(&mut self, b: &mut [f64]) -> (BandNorms, bool) {
        assert_eq!(b.len(), self.order(), "right-hand side of the wrong length");
        let (norms, regular) = self.eliminate(b);
        if regular {
            self.back_substitute(b);
        }
        (norms, regular)
    }

    /// The elimination of [`factorize_measured`](Self::factorize_measured), applying `P` and
    /// `L⁻¹` to `b` on the way unless `b` is empty.
    ///
    /// The pivot row's diagonal and right-hand side ride from one column to the next in
    /// registers: the recurrence is a division, a product and a difference, where reading them
    /// back from the arrays just written added a store-to-load delay to every row.
    fn eliminate(&mut self, b: &mut [f64]) -> (BandNorms, bool) {
        let n = self.order();
        let forward = !b.is_empty();
        let mut measure = Measure::default();
        let Some(&first) = self.diagonal.first() else {
            return (measure.norms(), true);
        };
        let (l, d, u, f) = (
            &mut self.lower,
            &mut self.diagonal,
            &mut self.upper,
            &mut self.fill,
        );
        let inverse = &mut self.inverse;
        measure.row(0.0, first, u.first().copied().unwrap_or(0.0));
        // The smallest pivot, and `Σ 0 / u_ii` (NaN when a reciprocal is not finite).
        let (mut smallest, mut bad_inverse) = (f64::INFINITY, 0.0);
        // Row i's diagonal and right-hand side as elimination has left them.
        let mut d_i = first;
        let mut b_i = if forward { b[0] } else { 0.0 };
        for i in 0..n - 1 {
            let has_fill = i + 2 < n;
            let (l_i, u_i, d_next) = (l[i], u[i], d[i + 1]);
            let next_upper = if has_fill { u[i + 1] } else { 0.0 };
            measure.row(l_i, d_next, next_upper);
            // The band LU exchanges rows only for a strictly larger entry below the diagonal.
            let exchange = l_i.abs() > d_i.abs();
            self.exchanged[i] = exchange;
            // Row i of U (pivot, entries (i, i+1), (i, i+2)) and row i + 1 after elimination.
            let (pivot, factor, row_upper, row_fill);
            if exchange {
                // Row i + 1 (l_i, d_next, next_upper) becomes the pivot row.
                factor = d_i / l_i;
                (pivot, row_upper, row_fill) = (l_i, d_next, next_upper);
                d_i = u_i - factor * d_next;
                if has_fill {
                    u[i + 1] = 0.0 - factor * next_upper;
                }
            } else {
                factor = l_i / d_i;
                (pivot, row_upper, row_fill) = (d_i, u_i, 0.0);
                d_i = d_next - factor * u_i;
            }
            l[i] = factor;
            d[i] = pivot;
            if forward {
                let b_next = b[i + 1];
                if exchange {
                    b[i] = b_next;
                    b_i -= factor * b_next;
                } else {
                    b[i] = b_i;
                    b_i = b_next - factor * b_i;
                }
            }
            // Row i of U is final: kept divided by its pivot, so that the back substitution
            // has no division and only one product on its recurrence.
            let reciprocal = 1.0 / pivot;
            inverse[i] = reciprocal;
            u[i] = row_upper * reciprocal;
            if has_fill {
                f[i] = row_fill * reciprocal;
            }
            smallest = smallest.min(pivot.abs());
            bad_inverse += reciprocal * 0.0;
        }
        d[n - 1] = d_i;
        if forward {
            b[n - 1] = b_i;
        }
        inverse[n - 1] = 1.0 / d_i;
        smallest = smallest.min(d_i.abs());
        bad_inverse += inverse[n - 1] * 0.0;
        let norms = measure.norms();
        // A zero pivot makes the later ones NaN, which `min` skips: the zero itself is kept.
        let regular =
            norms.finite && smallest > SINGULAR_RATIO * norms.largest && bad_inverse == 0.0;
        (norms, regular)
    }

    /// Solves `A x = b` in place with the factors of
    /// [`factorize_measured`](Self::factorize_measured).
    pub fn solve_inplace(&self, b: &mut [f64]) {
        for i in 0..self.order().saturating_sub(1) {
            forward_step(self.exchanged[i], self.lower[i], &mut b[i..i + 2]);
        }
        self.back_substitute(b);
    }

    /// `U x = b` in place, with the rows of `U` divided by their pivots:
    /// `x_i = b_i / u_ii − u'_i x_{i+1} − f'_i x_{i+2}`.
    fn back_substitute(&self, b: &mut [f64]) {
        let n = self.order();
        if n == 0 {
            return;
        }
        let (inverse, u, f) = (&self.inverse, &self.upper, &self.fill);
        b[n - 1] *= inverse[n - 1];
        if n > 1 {
            b[n - 2] = b[n - 2] * inverse[n - 2] - u[n - 2] * b[n - 1];
        }
        // x_{i+1}, x_{i+2} carried in registers (not read back from `b` just written).
        let (mut x1, mut x2) = (b[n.saturating_sub(2)], b[n - 1]);
        for i in (0..n.saturating_sub(2)).rev() {
            let x = b[i] * inverse[i] - f[i] * x2 - u[i] * x1;
            b[i] = x;
            (x1, x2) = (x, x1);
        }
    }

    /// `(min |u_ii|, max |u_ii|)` over the diagonal of `U` after factorisation.
    pub fn pivot_range(&self) -> (f64, f64) {
        self.diagonal
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), u| {
                (lo.min(u.abs()), hi.max(u.abs()))
            })
    }
}

/// Column `i` of the forward substitution on `pair = b[i..i + 2]`, with the multiplier `l`
/// of that column and whether its rows were exchanged.
#[inline]
fn forward_step(exchanged: bool, l: f64, pair: &mut [f64]) {
    if exchanged {
        let top = pair[0];
        pair[0] = pair[1];
        pair[1] = top - l * pair[0];
    } else {
        pair[1] -= l * pair[0];
    }
}

/// The norms of a matrix measured row by row.
#[derive(Default)]
struct Measure {
    inf: f64,
    largest: f64,
    /// `Σ 0 · a` over the entries: ±0 when all are finite, NaN otherwise (one test per entry
    /// without a branch; summing the entries first could overflow finite ones).
    not_finite: f64,
}

impl Measure {
    /// Takes in the row `(a, b, c)`.
    #[inline]
    fn row(&mut self, a: f64, b: f64, c: f64) {
        let (a, b, c) = (a.abs(), b.abs(), c.abs());
        self.inf = self.inf.max(a + b + c);
        self.largest = self.largest.max(a.max(b).max(c));
        self.not_finite += a * 0.0 + b * 0.0 + c * 0.0;
    }

    fn norms(&self) -> BandNorms {
        BandNorms {
            inf: self.inf,
            largest: self.largest,
            finite: self.not_finite == 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::BandedMatrix;

    /// A tridiagonal matrix with small diagonal entries at some rows (row exchanges there) in
    /// both storages.
    fn both(n: usize) -> (TridiagonalMatrix, BandedMatrix) {
        let mut tri = TridiagonalMatrix::zeros(n);
        let mut band = BandedMatrix::zeros(n, 1, 1);
        for i in 0..n {
            for j in i.saturating_sub(1)..=(i + 1).min(n - 1) {
                let v = if i == j && i % 3 == 1 {
                    1e-3
                } else {
                    ((i * 7 + j * 3) % 5) as f64 - 1.7 + 0.1 * (i as f64).sin()
                };
                tri.add(i, j, v);
                band.add(i, j, v);
            }
        }
        (tri, band)
    }

    fn rhs_again(n: usize) -> Vec<f64> {
        (0..n).map(|i| (i as f64).cos() + 0.5).collect()
    }

    #[test]
    fn factors_norms_and_solutions_are_those_of_the_band_lu() {
        for n in [1, 2, 3, 4, 17] {
            let (mut tri, mut band) = both(n);
            let bn = band.norms();
            band.factorize_scaled(bn.largest).unwrap();
            let (tn, regular) = tri.factorize_measured();
            assert!(regular);
            assert_eq!(
                (tn.inf, tn.largest, tn.finite),
                (bn.inf, bn.largest, bn.finite)
            );
            assert!(
                n < 3 || tri.exchanged.iter().any(|&e| e),
                "some rows exchanged"
            );
            // Exchange by exchange, multiplier by multiplier, pivot by pivot: the band LU's,
            // and the rows of U divided by the pivot in the same operations.
            for i in 0..n {
                if i + 1 < n {
                    assert_eq!(tri.exchanged[i], band.pivots[i] == i + 1, "n = {n}, {i}");
                    assert_eq!(tri.lower[i].to_bits(), band.get(i + 1, i).to_bits());
                }
                let pivot = band.get(i, i);
                assert_eq!(tri.diagonal[i].to_bits(), pivot.to_bits(), "n = {n}, {i}");
                let scaled = |j: usize| band.get(i, j) * (1.0 / pivot);
                if i + 1 < n {
                    assert_eq!(tri.upper[i].to_bits(), scaled(i + 1).to_bits());
                }
                if i + 2 < n {
                    assert_eq!(tri.fill[i].to_bits(), scaled(i + 2).to_bits());
                }
            }
            let rhs = rhs_again(n);
            let (mut x, mut y) = (rhs.clone(), rhs);
            tri.solve_inplace(&mut x);
            band.solve_inplace(&mut y);
            let (mut fused, mut z) = (both(n).0, rhs_again(n));
            assert!(fused.factorize_solving(&mut z).1);
            assert_eq!(
                z, x,
                "the fused forward substitution is the same operations"
            );
            let size = y.iter().fold(0.0f64, |m, c| m.max(c.abs()));
            for (x, y) in x.iter().zip(&y) {
                assert!((x - y).abs() <= 1e-14 * size, "n = {n}: {x} against {y}");
            }
        }
    }

    #[test]
    fn singular_and_non_finite_matrices_are_reported() {
        let mut singular = TridiagonalMatrix::zeros(3);
        singular.add(0, 0, 1.0);
        singular.add(1, 1, 1.0);
        assert!(!singular.factorize_measured().1);
        // A zero pivot in the first column, then regular rows after it.
        let mut first = TridiagonalMatrix::zeros(3);
        first.add(1, 1, 1.0);
        first.add(2, 2, 1.0);
        first.add(1, 2, 1.0);
        assert!(!first.factorize_measured().1);
        let mut nan = TridiagonalMatrix::zeros(3);
        nan.add(2, 1, f64::NAN);
        assert!(!nan.factorize_measured().0.is_finite());
        let mut infinite = TridiagonalMatrix::zeros(2);
        infinite.add(0, 1, f64::INFINITY);
        assert!(!infinite.factorize_measured().0.is_finite());
        // Entries whose row sums overflow are still finite.
        let mut huge = TridiagonalMatrix::zeros(2);
        for (i, j) in [(0, 0), (0, 1), (1, 0)] {
            huge.add(i, j, f64::MAX);
        }
        let (norms, _) = huge.factorize_measured();
        assert!(norms.is_finite() && norms.inf.is_infinite());
    }
}
