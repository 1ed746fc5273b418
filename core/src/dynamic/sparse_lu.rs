//! The global Newton system of a boundary value problem of a run-time-dimension model: a
//! sparse matrix assembled row block by row block, and its LU factorisation with partial
//! pivoting after a fill-reducing (COLAMD) column ordering, by `faer`.
//!
//! The matrix is stored by rows (compressed sparse rows), which is the column storage of its
//! transpose: `faer` factorises `Jᵀ` and the solves use the transposed factors, so that each row
//! block of the Jacobian is written once, in order, without a global sort. The pattern and the
//! symbolic factorisation (the ordering, the elimination tree, the supernodes) are computed
//! once per solve; each Newton iteration refills the values and factorises numerically. A
//! model whose Hessian lists a new entry (one that lists only nonzero entries) makes the
//! pattern and the symbolic factorisation be computed again.
//!
//! The chain of `d` particles on `N` steps is a grid graph of `N × d` unknowns: in time-major
//! order its band is about `2d` (`O(N d³)` work), while the fill-reducing ordering factorises
//! it like a two-dimensional mesh.

use crate::solve::krylov::onto;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::SparseColMatRef;
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::lu::{NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::{Conj, MatMut, Par, Spec};

/// An entry of the matrix outside the planned pattern.
#[derive(Debug)]
pub(crate) struct OutsidePattern;

/// The pattern of a square sparse matrix by rows, and its values.
pub(crate) struct SparseRows {
    n: usize,
    row_ptr: Vec<usize>,
    col_idx: Vec<usize>,
    values: Vec<f64>,
}

impl SparseRows {
    /// An empty `n × n` pattern, rows appended with [`push_rows`](Self::push_rows).
    pub(crate) fn with_order(n: usize) -> Self {
        SparseRows {
            n,
            row_ptr: vec![0],
            col_idx: Vec::new(),
            values: Vec::new(),
        }
    }

    /// Appends the next rows `first..first + count` from their entries `(row, col)` (any
    /// order, repeats allowed); the values are zero.
    pub(crate) fn push_rows(&mut self, first: usize, count: usize, entries: &mut [(usize, usize)]) {
        debug_assert_eq!(self.row_ptr.len() - 1, first, "rows appended in order");
        entries.sort_unstable();
        let mut entries = entries.iter().peekable();
        for row in first..first + count {
            let mut last = None;
            while let Some(&&(r, c)) = entries.peek() {
                if r != row {
                    break;
                }
                if last != Some(c) {
                    self.col_idx.push(c);
                    last = Some(c);
                }
                entries.next();
            }
            self.row_ptr.push(self.col_idx.len());
        }
        self.values.resize(self.col_idx.len(), 0.0);
    }

    /// Whether every row has been appended.
    pub(crate) fn is_complete(&self) -> bool {
        self.row_ptr.len() == self.n + 1
    }

    /// The largest `|i − j|` over the stored entries.
    pub(crate) fn bandwidth(&self) -> usize {
        (0..self.n)
            .flat_map(|i| self.columns(i).iter().map(move |&j| i.abs_diff(j)))
            .max()
            .unwrap_or(0)
    }

    /// The order `n`.
    pub(crate) fn order(&self) -> usize {
        self.n
    }

    /// The stored entries `(row, col, value)`, row by row.
    pub(crate) fn entries(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        (0..self.n).flat_map(move |i| {
            let at = self.row_ptr[i]..self.row_ptr[i + 1];
            self.col_idx[at.clone()]
                .iter()
                .zip(&self.values[at])
                .map(move |(&j, &value)| (i, j, value))
        })
    }

    fn columns(&self, row: usize) -> &[usize] {
        &self.col_idx[self.row_ptr[row]..self.row_ptr[row + 1]]
    }

    /// Sets every value to zero.
    pub(crate) fn clear(&mut self) {
        self.values.fill(0.0);
    }

    /// Adds `value` to entry `(row, col)`, which must be in the pattern.
    #[inline]
    pub(crate) fn add(&mut self, row: usize, col: usize, value: f64) -> Result<(), OutsidePattern> {
        let start = self.row_ptr[row];
        match self.columns(row).binary_search(&col) {
            Ok(at) => {
                self.values[start + at] += value;
                Ok(())
            }
            Err(_) => Err(OutsidePattern),
        }
    }

    /// `y = A x`.
    pub(crate) fn apply(&self, x: &[f64], y: &mut [f64]) {
        self.apply_onto(x, (1.0, 0.0), y);
    }

    /// `y ← c A x + β y` (`y` only written where `β = 0`).
    pub(crate) fn apply_onto(&self, x: &[f64], (c, beta): (f64, f64), y: &mut [f64]) {
        for (i, y) in y.iter_mut().enumerate() {
            let at = self.row_ptr[i]..self.row_ptr[i + 1];
            let ax: f64 = self.col_idx[at.clone()]
                .iter()
                .zip(&self.values[at])
                .map(|(&j, v)| v * x[j])
                .sum();
            *y = onto(*y, ax, (c, beta));
        }
    }

    /// Whether every value is finite.
    pub(crate) fn is_finite(&self) -> bool {
        self.values.iter().all(|v| v.is_finite())
    }

    /// `‖A‖∞`, the largest absolute row sum.
    pub(crate) fn norm_inf(&self) -> f64 {
        (0..self.n)
            .map(|i| {
                self.values[self.row_ptr[i]..self.row_ptr[i + 1]]
                    .iter()
                    .map(|v| v.abs())
                    .sum::<f64>()
            })
            .fold(0.0, f64::max)
    }

    /// The matrix's transpose in `faer`'s column storage.
    fn transpose(&self) -> SparseColMatRef<'_, usize, f64> {
        let symbolic = SymbolicSparseColMatRef::new_checked(
            self.n,
            self.n,
            &self.row_ptr,
            None,
            &self.col_idx,
        );
        SparseColMatRef::new(symbolic, &self.values)
    }
}

/// The matrix is singular (no pivot found), or a factorisation could not be made.
#[derive(Debug)]
pub(crate) struct Singular;

/// The sparse LU factorisation of a [`SparseRows`] pattern: symbolic once, numeric on demand.
pub(crate) struct SparseLu {
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    factor_scratch: MemBuffer,
    solve_scratch: MemBuffer,
}

impl SparseLu {
    /// The symbolic factorisation of `matrix`'s pattern (COLAMD ordering of the columns of
    /// `Jᵀ`, i.e. of the rows of `J`).
    pub(crate) fn plan(matrix: &SparseRows) -> Result<Self, Singular> {
        let symbolic = factorize_symbolic_lu(matrix.transpose().symbolic(), Default::default())
            .map_err(|_| Singular)?;
        let factor_scratch = MemBuffer::try_new(
            symbolic.factorize_numeric_lu_scratch::<f64>(Par::Seq, Spec::default()),
        )
        .map_err(|_| Singular)?;
        let solve_scratch =
            MemBuffer::try_new(symbolic.solve_transpose_in_place_scratch::<f64>(1, Par::Seq))
                .map_err(|_| Singular)?;
        Ok(SparseLu {
            symbolic,
            numeric: NumericLu::new(),
            factor_scratch,
            solve_scratch,
        })
    }

    /// Factorises `matrix` (the planned pattern) numerically.
    pub(crate) fn factorize(&mut self, matrix: &SparseRows) -> Result<(), Singular> {
        self.symbolic
            .factorize_numeric_lu(
                &mut self.numeric,
                matrix.transpose(),
                Par::Seq,
                MemStack::new(&mut self.factor_scratch),
                Spec::default(),
            )
            .map(|_| ())
            .map_err(|_| Singular)
    }

    /// Solves `J x = r` with the factors of the last [`factorize`](Self::factorize), `x`
    /// overwriting `r` (`Jᵀ` was factorised: its transposed solve).
    pub(crate) fn solve_in_place(&mut self, r: &mut [f64]) {
        let n = r.len();
        let lu = faer::sparse::linalg::lu::LuRef::new_unchecked(&self.symbolic, &self.numeric);
        lu.solve_transpose_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(r, n, 1),
            Par::Seq,
            MemStack::new(&mut self.solve_scratch),
        );
    }
}
