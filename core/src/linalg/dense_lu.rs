//! Dense LU with partial pivoting, in place: faer's blocked kernel over nalgebra's storage.
//!
//! The dense fractional solver factorises its `(N − 1)d × (N − 1)d` Jacobian at every Newton
//! iteration. nalgebra's LU eliminates one column at a time (about 2.4 Gflop/s measured at
//! N = 800); faer's partial-pivoting LU works in blocks through its GEMM, and writes `L` and
//! `U` over the matrix itself, so the factorisation needs no memory beside it but the pivots.
//! Both are column-major, so faer works on nalgebra's buffer as it is. BENCHMARKS.md has the
//! dense solver's times before and after.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::perm::PermRef;
use faer::{MatMut, MatRef, Par, Spec};

/// A pivot at most this fraction of the largest entry is numerically zero: the matrix is
/// singular.
const SINGULAR_RATIO: f64 = super::SINGULAR_RATIO;

/// `P A = L U` of a square matrix, `L` (unit lower) and `U` stored in one matrix.
pub struct DenseLu {
    lu: nalgebra::DMatrix<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
}

impl DenseLu {
    /// Factorises `a`; `None` when `a` is not square, not finite, or has a pivot at most
    /// `1e-14` times its largest entry (singular to working precision).
    pub fn new(mut a: nalgebra::DMatrix<f64>) -> Option<DenseLu> {
        let n = a.nrows();
        let norm = a.amax();
        if a.ncols() != n || !norm.is_finite() {
            return None;
        }
        let (mut perm, mut perm_inv) = (vec![0; n], vec![0; n]);
        let params = Spec::default();
        let scratch = factor::lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, params);
        let mut buffer = MemBuffer::new(scratch);
        let view = MatMut::from_column_major_slice_mut(a.as_mut_slice(), n, n);
        factor::lu_in_place(
            view,
            &mut perm,
            &mut perm_inv,
            Par::Seq,
            MemStack::new(&mut buffer),
            params,
        );
        let singular = (0..n).any(|i| a[(i, i)].abs() <= SINGULAR_RATIO * norm);
        (!singular).then_some(DenseLu {
            lu: a,
            perm,
            perm_inv,
        })
    }

    /// The dimension.
    pub fn len(&self) -> usize {
        self.perm.len()
    }

    /// Whether the matrix is `0 × 0`.
    pub fn is_empty(&self) -> bool {
        self.perm.is_empty()
    }

    /// Overwrites `b` with `A⁻¹ b`; `false` (and `b` unspecified) when the result is not finite.
    pub fn solve(&self, b: &mut [f64]) -> bool {
        let n = self.len();
        assert_eq!(b.len(), n, "the right-hand side has the matrix's dimension");
        let lu = MatRef::from_column_major_slice(self.lu.as_slice(), n, n);
        let perm = PermRef::new_checked(&self.perm, &self.perm_inv, n);
        let scratch = solve::solve_in_place_scratch::<usize, f64>(n, 1, Par::Seq);
        let mut buffer = MemBuffer::new(scratch);
        let rhs = MatMut::from_column_major_slice_mut(b, n, 1);
        solve::solve_in_place(lu, lu, perm, rhs, Par::Seq, MemStack::new(&mut buffer));
        b.iter().all(|x| x.is_finite())
    }
}
