//! Linear solves: the `d × d` step systems, the banded (block-tridiagonal) Jacobian of the
//! classical boundary value problems, and dense LU for the fractional reference path.

use crate::lagrangian::{Matrix, Vector};

/// A pivot smaller than this times the largest entry of its column block is treated as zero:
/// the matrix is numerically singular and the caller reports a typed error.
const SINGULAR_RATIO: f64 = 1e-14;

/// Solves `A x = b` for a `D × D` block by Gaussian elimination with partial pivoting.
/// `None` when `A` is singular (to the relative threshold `1e-14` of its largest entry) or
/// not finite.
pub fn solve_small<const D: usize>(a: &Matrix<D>, b: &Vector<D>) -> Option<Vector<D>> {
    if D == 1 {
        // The scalar case is the hot path of every d = 1 Newton step.
        let x = b[0] / a[(0, 0)];
        return (a[(0, 0)] != 0.0 && x.is_finite()).then(|| Vector::<D>::from_element(x));
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
    x.iter().all(|v| v.is_finite()).then_some(x)
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
}
