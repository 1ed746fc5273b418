//! Small dense and banded linear algebra: the `d × d` step systems, the banded
//! (block-tridiagonal) Jacobian of the classical boundary value problems, dense LU for the
//! fractional reference path, and the max-norm every stopping rule measures with.

use crate::lagrangian::{Matrix, Vector};

mod dense_lu;
mod tridiagonal;

pub use dense_lu::DenseLu;
pub use tridiagonal::TridiagonalMatrix;

/// Max-norm of a list of points.
pub fn max_norm<const D: usize>(x: &[Vector<D>]) -> f64 {
    x.iter().fold(0.0, |m, v| m.max(v.amax()))
}

/// Block `j` of a vector of `D`-blocks stored flat, `x[jD..(j+1)D]`.
pub fn block<const D: usize>(x: &[f64], j: usize) -> Vector<D> {
    Vector::<D>::from_column_slice(&x[j * D..(j + 1) * D])
}

/// Sets block `j` of a vector of `D`-blocks stored flat.
pub fn set_block<const D: usize>(x: &mut [f64], j: usize, v: &Vector<D>) {
    x[j * D..(j + 1) * D].copy_from_slice(v.as_slice());
}

/// Adds `v` to block `j` of a vector of `D`-blocks stored flat.
pub fn add_to_block<const D: usize>(x: &mut [f64], j: usize, v: &Vector<D>) {
    for (x, v) in x[j * D..(j + 1) * D].iter_mut().zip(v.iter()) {
        *x += v;
    }
}

/// `buffer` as `len` zeros, reusing its allocation; one that must grow grows to `len` exactly
/// (`resize` alone may double it: a vector lent from `N − 1` unknowns to `N` rows would
/// keep twice the memory it needs).
pub fn zeroed(buffer: &mut Vec<f64>, len: usize) -> &mut Vec<f64> {
    buffer.clear();
    buffer.reserve_exact(len);
    buffer.resize(len, 0.0);
    buffer
}

/// A pivot smaller than this times the largest entry of its column block is treated as zero:
/// the matrix is numerically singular and the caller reports a typed error.
const SINGULAR_RATIO: f64 = 1e-14;

/// Solves `A x = b` for a `D × D` block by Gaussian elimination with partial pivoting.
/// `None` when `A` is singular (to the relative threshold `1e-14` of its largest entry) or
/// not finite. The solution itself may overflow: callers check it (that is a
/// [`NotFinite`](crate::error::Error::NotFinite), not a singular matrix).
pub fn solve_small<const D: usize>(a: &Matrix<D>, b: &Vector<D>) -> Option<Vector<D>> {
    if D == 1 {
        // The scalar case is the hot path of every d = 1 Newton step.
        let a = a[(0, 0)];
        return (a != 0.0 && a.is_finite()).then(|| Vector::<D>::from_element(b[0] / a));
    }
    let mut m = *a;
    let mut x = *b;
    let norm = m.amax();
    if !norm.is_finite() || norm == 0.0 {
        return None;
    }
    for col in 0..D {
        let (piv, max) = (col..D)
            .map(|r| (r, m[(r, col)].abs()))
            .fold((col, -1.0), |best, c| if c.1 > best.1 { c } else { best });
        if max <= SINGULAR_RATIO * norm {
            return None;
        }
        if piv != col {
            m.swap_rows(piv, col);
            x.swap_rows(piv, col);
        }
        for r in col + 1..D {
            let l = m[(r, col)] / m[(col, col)];
            for c in col..D {
                m[(r, c)] -= l * m[(col, c)];
            }
            x[r] -= l * x[col];
        }
    }
    for col in (0..D).rev() {
        let mut s = x[col];
        for c in col + 1..D {
            s -= m[(col, c)] * x[c];
        }
        x[col] = s / m[(col, col)];
    }
    Some(x)
}

/// A square banded matrix with `kl` sub- and `ku` super-diagonals, factorised in place by LU
/// with partial pivoting (the LAPACK `gbtrf` scheme): `O(n (kl + ku) kl)` work, `O(n (2kl + ku))`
/// memory. Row `i` stores columns `i − kl ..= i + kl + ku` (the extra `kl` hold the fill-in
/// that row exchanges bring).
pub struct BandedMatrix {
    n: usize,
    kl: usize,
    ku: usize,
    width: usize,
    data: Vec<f64>,
    pivots: Vec<usize>,
}

impl BandedMatrix {
    /// The zero `n × n` matrix with bandwidths `kl`, `ku`.
    pub fn zeros(n: usize, kl: usize, ku: usize) -> Self {
        let width = 2 * kl + ku + 1;
        BandedMatrix {
            n,
            kl,
            ku,
            width,
            data: vec![0.0; n * width],
            pivots: Vec::new(),
        }
    }

    /// Sets every entry to zero, keeping the allocation (a matrix refilled at every Newton
    /// iteration).
    pub fn clear(&mut self) {
        self.data.fill(0.0);
    }

    /// Row `i` of the storage: columns `i − kl ..= i + kl + ku` at offsets `0 ..= 2kl + ku`
    /// (entry `(i, j)` at `j + kl − i`; the last `kl` hold the fill of the factorisation and
    /// are zero before it). Offsets of columns outside `0..n` must stay zero.
    pub fn row_mut(&mut self, i: usize) -> &mut [f64] {
        &mut self.data[i * self.width..(i + 1) * self.width]
    }

    /// `(min |u_ii|, max |u_ii|)` over the diagonal of `U` after
    /// [`factorize`](Self::factorize): the pivots a degeneracy check measures against a
    /// reference scale.
    pub(crate) fn pivot_range(&self) -> (f64, f64) {
        (0..self.n)
            .map(|i| self.data[self.slot(i, i)].abs())
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), u| {
                (lo.min(u), hi.max(u))
            })
    }

    /// Order `n`.
    pub fn order(&self) -> usize {
        self.n
    }

    fn slot(&self, i: usize, j: usize) -> usize {
        debug_assert!(
            j + self.kl >= i && j <= i + self.kl + self.ku,
            "({i}, {j}) outside the band"
        );
        i * self.width + (j + self.kl - i)
    }

    /// Adds `value` to entry `(i, j)`, which must lie within the band.
    pub fn add(&mut self, i: usize, j: usize, value: f64) {
        let s = self.slot(i, j);
        self.data[s] += value;
    }

    /// Entry `(i, j)` (zero outside the stored band).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        if j + self.kl < i || j > i + self.kl + self.ku {
            0.0
        } else {
            self.data[self.slot(i, j)]
        }
    }

    /// `‖A‖∞`, the largest absolute row sum (before factorisation); NaN or ∞ when an entry is
    /// not finite, so that one pass also checks finiteness.
    pub fn norm_inf(&self) -> f64 {
        self.data
            .chunks(self.width)
            .map(|row| row.iter().map(|x| x.abs()).sum::<f64>())
            .fold(0.0, |m, s| if s > m || s.is_nan() { s } else { m })
    }

    /// Whether every stored entry is finite.
    pub fn is_finite(&self) -> bool {
        self.data.iter().all(|v| v.is_finite())
    }

    /// Factorises in place. Returns the index of the first pivot column that is numerically
    /// zero (relative to the largest entry) as `Err`.
    ///
    /// Row by row on slices of the storage (row `i` holds columns `i − kl ..= i + kl + ku` at
    /// offsets `0 ..`), so that the elimination of a row is one contiguous, vectorisable update.
    pub fn factorize(&mut self) -> std::result::Result<(), usize> {
        let norms = self.norms();
        if !norms.is_finite() {
            return Err(0);
        }
        self.factorize_scaled(norms.largest)
    }

    /// `‖A‖∞` and the largest absolute entry in one pass, with whether every entry is finite.
    pub fn norms(&self) -> BandNorms {
        let (mut inf, mut largest, mut finite) = (0.0f64, 0.0f64, true);
        for row in self.data.chunks(self.width) {
            let sum: f64 = row.iter().map(|a| a.abs()).sum();
            let top = row.iter().fold(0.0f64, |m, a| m.max(a.abs()));
            inf = inf.max(sum);
            largest = largest.max(top);
            finite &= row.iter().all(|a| a.is_finite());
        }
        BandNorms {
            inf,
            largest,
            finite,
        }
    }

    /// [`factorize`](Self::factorize) with the largest absolute entry `largest` given (from
    /// [`norms`](Self::norms)), the scale of its singularity threshold.
    pub fn factorize_scaled(&mut self, largest: f64) -> std::result::Result<(), usize> {
        let (n, kl, ku, w) = (self.n, self.kl, self.ku, self.width);
        let norm = largest;
        self.pivots.clear();
        self.pivots.resize(n, 0);
        let data = &mut self.data;
        for j in 0..n {
            let last_row = (j + kl).min(n - 1);
            // Entry (i, j) sits at offset j + kl − i of row i.
            let mut piv = j;
            let mut max = data[j * w + kl].abs();
            for i in j + 1..=last_row {
                let a = data[i * w + j + kl - i].abs();
                if a > max {
                    max = a;
                    piv = i;
                }
            }
            if max <= SINGULAR_RATIO * norm {
                return Err(j);
            }
            self.pivots[j] = piv;
            let last_col = (j + kl + ku).min(n - 1);
            if piv != j {
                for c in j..=last_col {
                    data.swap(j * w + c + kl - j, piv * w + c + kl - piv);
                }
            }
            let (head, tail) = data.split_at_mut((j + 1) * w);
            let row_j = &head[j * w..];
            let d = row_j[kl];
            // Columns j + 1 ..= last_col of row j.
            let upper = &row_j[kl + 1..kl + 1 + (last_col - j)];
            for i in j + 1..=last_row {
                let row_i = &mut tail[(i - j - 1) * w..(i - j) * w];
                let at = j + kl - i;
                let l = row_i[at] / d;
                row_i[at] = l;
                if l != 0.0 {
                    for (a, u) in row_i[at + 1..at + 1 + upper.len()].iter_mut().zip(upper) {
                        *a -= l * u;
                    }
                }
            }
        }
        Ok(())
    }

    /// Solves `A x = b` in place with the factors of [`factorize`](Self::factorize).
    pub fn solve_inplace(&self, b: &mut [f64]) {
        let (n, kl, ku, w) = (self.n, self.kl, self.ku, self.width);
        let data = &self.data;
        for j in 0..n {
            b.swap(j, self.pivots[j]);
            let bj = b[j];
            let last_row = (j + kl).min(n - 1);
            for i in j + 1..=last_row {
                b[i] -= data[i * w + j + kl - i] * bj;
            }
        }
        for i in (0..n).rev() {
            let row = &data[i * w..(i + 1) * w];
            let last_col = (i + kl + ku).min(n - 1);
            let s: f64 = row[kl + 1..kl + 1 + (last_col - i)]
                .iter()
                .zip(&b[i + 1..=last_col])
                .map(|(u, x)| u * x)
                .sum();
            b[i] = (b[i] - s) / row[kl];
        }
    }
}

/// The norms of a [`BandedMatrix`] from one pass over its storage ([`BandedMatrix::norms`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BandNorms {
    /// `‖A‖∞`, the largest absolute row sum.
    pub inf: f64,
    /// The largest absolute entry.
    pub largest: f64,
    /// Whether every entry is finite (`inf` and `largest` mean nothing otherwise).
    finite: bool,
}

impl BandNorms {
    /// The norms of a matrix with an entry that is not finite.
    pub const NOT_FINITE: BandNorms = BandNorms {
        inf: f64::NAN,
        largest: f64::NAN,
        finite: false,
    };

    /// Whether every entry of the matrix is finite.
    pub fn is_finite(&self) -> bool {
        self.finite
    }
}

/// Solves the `n × n` system `A x = b` in place by Gaussian elimination with partial pivoting:
/// `a` holds `A` row by row (and is overwritten by its factors), `b` becomes `x`. Small systems
/// solved many times (the stage systems of the Gauss–Legendre steps) use it with buffers kept
/// across solves, where nalgebra's dynamic matrices would allocate every time. `false` when `A`
/// is singular (a pivot at most `1e-14` times the largest entry) or not finite.
pub fn solve_dense_in_place(a: &mut [f64], b: &mut [f64]) -> bool {
    let n = b.len();
    debug_assert_eq!(a.len(), n * n);
    let norm = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if !norm.is_finite() || norm == 0.0 {
        return false;
    }
    for col in 0..n {
        let (piv, max) = (col..n)
            .map(|r| (r, a[r * n + col].abs()))
            .fold((col, -1.0), |best, c| if c.1 > best.1 { c } else { best });
        if max <= SINGULAR_RATIO * norm {
            return false;
        }
        if piv != col {
            for c in 0..n {
                a.swap(piv * n + c, col * n + c);
            }
            b.swap(piv, col);
        }
        let pivot = a[col * n + col];
        for r in col + 1..n {
            let l = a[r * n + col] / pivot;
            if l != 0.0 {
                for c in col + 1..n {
                    a[r * n + c] -= l * a[col * n + c];
                }
                b[r] -= l * b[col];
            }
        }
    }
    for col in (0..n).rev() {
        let mut s = b[col];
        for c in col + 1..n {
            s -= a[col * n + c] * b[c];
        }
        b[col] = s / a[col * n + col];
    }
    true
}

/// Solves a dense system by LU with partial pivoting ([`DenseLu`]); `None` when a pivot is
/// numerically zero relative to the largest entry or the solution is not finite.
pub fn solve_dense(
    a: nalgebra::DMatrix<f64>,
    b: &nalgebra::DVector<f64>,
) -> Option<nalgebra::DVector<f64>> {
    let mut x = b.clone();
    DenseLu::new(a)?.solve(x.as_mut_slice()).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_solve_matches_the_product_and_flags_singular() {
        let a = Matrix::<3>::new(0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0);
        let x = Vector::<3>::new(1.0, -2.0, 0.5);
        let sol = solve_small(&a, &(a * x)).unwrap();
        assert!((sol - x).amax() < 1e-14);
        let s = Matrix::<2>::new(1.0, 2.0, 2.0, 4.0);
        assert!(solve_small(&s, &Vector::<2>::new(1.0, 1.0)).is_none());
        assert!(solve_small(&Matrix::<1>::zeros(), &Vector::<1>::new(1.0)).is_none());
    }

    /// The in-place solve against nalgebra's LU on a matrix that needs row exchanges, and a
    /// singular matrix flagged.
    #[test]
    fn in_place_solve_matches_nalgebra_and_flags_singular() {
        let n = 7;
        let entry = |i: usize, j: usize| {
            if i == j {
                1e-3
            } else {
                ((i * 5 + j * 3) % 7) as f64 - 2.9
            }
        };
        let dense = nalgebra::DMatrix::<f64>::from_fn(n, n, entry);
        let rhs: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let expected = solve_dense(dense, &nalgebra::DVector::from_vec(rhs.clone())).unwrap();
        let mut a: Vec<f64> = (0..n * n).map(|k| entry(k / n, k % n)).collect();
        let mut x = rhs;
        assert!(solve_dense_in_place(&mut a, &mut x));
        for i in 0..n {
            assert!((x[i] - expected[i]).abs() < 1e-12 * expected.amax(), "{i}");
        }
        let mut singular = vec![1.0, 2.0, 2.0, 4.0];
        assert!(!solve_dense_in_place(&mut singular, &mut [1.0, 1.0]));
        assert!(!solve_dense_in_place(&mut [f64::NAN], &mut [1.0]));
    }

    /// The blocked dense LU against nalgebra's column-at-a-time LU, on matrices large enough
    /// for several of faer's blocks and with a small diagonal (so rows are exchanged), and
    /// singular, not finite and empty matrices.
    #[test]
    fn dense_lu_matches_nalgebra_and_flags_singular() {
        for n in [1, 2, 7, 64, 301] {
            let entry = |i: usize, j: usize| {
                let x = ((i * 7919 + j * 104_729) % 1009) as f64 / 1009.0 - 0.5;
                if i == j { 1e-3 * x } else { x }
            };
            let a = nalgebra::DMatrix::<f64>::from_fn(n, n, entry);
            let b = nalgebra::DVector::<f64>::from_fn(n, |i, _| (i as f64 * 0.37).sin());
            let expected = a.clone().lu().solve(&b).unwrap();
            let got = solve_dense(a.clone(), &b).unwrap();
            let residual = (&a * &got - &b).amax();
            assert!(
                residual <= 1e-10 * b.amax(),
                "n = {n}: residual {residual:e}"
            );
            let difference = (&got - &expected).amax();
            assert!(
                difference <= 1e-8 * expected.amax(),
                "n = {n}: {difference:e}"
            );
        }
        let singular = nalgebra::DMatrix::<f64>::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 4.0]);
        assert!(DenseLu::new(singular).is_none());
        assert!(DenseLu::new(nalgebra::DMatrix::from_element(2, 2, f64::NAN)).is_none());
        assert!(DenseLu::new(nalgebra::DMatrix::zeros(2, 3)).is_none());
        let empty = DenseLu::new(nalgebra::DMatrix::zeros(0, 0)).unwrap();
        assert!(empty.is_empty() && empty.solve(&mut []));
    }

    #[test]
    fn banded_lu_matches_dense_lu_with_pivoting() {
        // A band matrix whose diagonal is tiny, so that partial pivoting must exchange rows.
        let (n, kl, ku) = (9, 2, 1);
        let mut band = BandedMatrix::zeros(n, kl, ku);
        let mut dense = nalgebra::DMatrix::<f64>::zeros(n, n);
        for i in 0..n {
            for j in i.saturating_sub(kl)..=(i + ku).min(n - 1) {
                let v = if i == j {
                    1e-3
                } else {
                    ((i * 7 + j * 3) % 5) as f64 - 1.7
                };
                band.add(i, j, v);
                dense[(i, j)] = v;
            }
        }
        let rhs: Vec<f64> = (0..n).map(|i| (i as f64).cos()).collect();
        let expected = solve_dense(dense, &nalgebra::DVector::from_vec(rhs.clone())).unwrap();
        band.factorize().unwrap();
        let mut x = rhs;
        band.solve_inplace(&mut x);
        for i in 0..n {
            assert!(
                (x[i] - expected[i]).abs() < 1e-12 * expected.amax(),
                "{i}: {} vs {}",
                x[i],
                expected[i]
            );
        }
        let mut singular = BandedMatrix::zeros(3, 1, 1);
        singular.add(0, 0, 1.0);
        singular.add(1, 1, 1.0);
        assert_eq!(singular.factorize(), Err(2));
    }
}
