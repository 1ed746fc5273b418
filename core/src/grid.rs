//! The uniform grid `t_k = a + k h`, `k = 0..=N`, `h = (b − a)/N`.

use crate::error::{Error, Result};

/// A uniform partition of `[a, b]` into `N ≥ 1` steps.
///
/// # Example
///
/// ```
/// let grid = varembed::Grid::new(0.0, 1.0, 4)?;
/// assert_eq!(grid.h(), 0.25);
/// assert_eq!(grid.t(3), 0.75);
/// # Ok::<(), varembed::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    a: f64,
    b: f64,
    n: usize,
    h: f64,
}

impl Grid {
    /// The most steps a grid may have: a count whose nodes (at least 8 bytes each, times the
    /// dimension) could still be indexed. A grid this fine is refused long before, by its step
    /// (`h` must move both ends); storing its nodes may still not fit in memory, which the
    /// solvers report as [`Error::TooLarge`].
    ///
    /// ```
    /// use varembed::Grid;
    /// assert!(Grid::new(0.0, 1.0, usize::MAX).is_err());
    /// assert!(Grid::MAX_STEPS >= 1 << 40);
    /// ```
    pub const MAX_STEPS: usize = (isize::MAX as usize) / 64;

    /// The grid of `[a, b]` with `n` steps. Errors unless `a`, `b` are finite, `a < b`, `n ≥ 1`
    /// and `h = (b − a)/n` is a positive normal number.
    ///
    /// ```
    /// assert!(varembed::Grid::new(0.0, 1.0, 10).is_ok());
    /// let error = varembed::Grid::new(1.0, 0.0, 10).unwrap_err();
    /// assert_eq!(error.to_string(), "invalid grid [1, 0] with N = 10: a must be smaller than b");
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn new(a: f64, b: f64, n: usize) -> Result<Self> {
        let invalid = |reason| Err(Error::InvalidGrid { a, b, n, reason });
        if !a.is_finite() || !b.is_finite() {
            return invalid("the ends must be finite");
        }
        if n == 0 {
            return invalid("N must be at least 1");
        }
        if a >= b {
            return invalid("a must be smaller than b");
        }
        if n > Self::MAX_STEPS {
            return invalid("N is too large to index its nodes");
        }
        let h = (b - a) / n as f64;
        // Both ends must move by h in floating point, or the nodes near them coincide.
        if !h.is_normal() || a + h == a || b - h == b {
            return invalid("the step h = (b − a)/N is too small to resolve");
        }
        Ok(Grid { a, b, n, h })
    }

    /// Left end `a`.
    ///
    /// ```
    /// let grid = varembed::Grid::new(1.0, 2.0, 4)?;
    /// assert_eq!(grid.a(), 1.0);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn a(&self) -> f64 {
        self.a
    }
    /// Right end `b`.
    ///
    /// ```
    /// let grid = varembed::Grid::new(1.0, 2.0, 4)?;
    /// assert_eq!(grid.b(), 2.0);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn b(&self) -> f64 {
        self.b
    }
    /// Number of steps `N`.
    ///
    /// ```
    /// let grid = varembed::Grid::new(1.0, 2.0, 4)?;
    /// assert_eq!(grid.n(), 4);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn n(&self) -> usize {
        self.n
    }
    /// Step size `h`.
    ///
    /// ```
    /// let grid = varembed::Grid::new(1.0, 2.0, 4)?;
    /// assert_eq!(grid.h(), 0.25);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn h(&self) -> f64 {
        self.h
    }
    /// Node `t_k = a + k h` (`t_N = b` exactly).
    ///
    /// ```
    /// let grid = varembed::Grid::new(1.0, 2.0, 4)?;
    /// assert_eq!((grid.t(1), grid.t(4)), (1.25, 2.0));
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn t(&self, k: usize) -> f64 {
        if k == self.n {
            self.b
        } else {
            self.a + k as f64 * self.h
        }
    }
    /// All nodes `t_0, …, t_N`.
    ///
    /// ```
    /// let grid = varembed::Grid::new(1.0, 2.0, 4)?;
    /// assert_eq!(grid.nodes(), [1.0, 1.25, 1.5, 1.75, 2.0]);
    /// # Ok::<(), varembed::Error>(())
    /// ```
    pub fn nodes(&self) -> Vec<f64> {
        (0..=self.n).map(|k| self.t(k)).collect()
    }
}
