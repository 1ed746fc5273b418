//! The sparse second-derivative blocks a [`DynLagrangian`](super::DynLagrangian) writes.

/// One `d × d` second-derivative block as a list of entries `(i, j, value)`; an entry listed
/// twice holds the sum of its values, an entry never listed is zero.
///
/// A model writes it with [`add`](Self::add). [`clear`](Self::clear) keeps the allocation, so
/// a solver that clears and refills one block at every Newton iteration allocates only once.
///
/// ```
/// use varembed::SparseBlock;
/// let mut b = SparseBlock::new(3);
/// b.add(0, 1, 2.0);
/// b.add(0, 1, 0.5);
/// b.add(2, 2, -1.0);
/// assert_eq!((b.get(0, 1), b.get(2, 2), b.get(1, 1)), (2.5, -1.0, 0.0));
/// assert_eq!(b.entries().len(), 3);
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SparseBlock {
    dimension: usize,
    entries: Vec<(usize, usize, f64)>,
}

impl SparseBlock {
    /// The zero `d × d` block.
    pub fn new(d: usize) -> Self {
        SparseBlock {
            dimension: d,
            entries: Vec::new(),
        }
    }

    /// Its dimension `d`.
    pub fn dimension(&self) -> usize {
        self.dimension
    }

    /// The entries as written, in order, repeats included.
    pub fn entries(&self) -> &[(usize, usize, f64)] {
        &self.entries
    }

    /// Entry `(i, j)`: the sum of its listed values (`O(entries)`; for tests and small blocks).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.entries
            .iter()
            .filter(|e| e.0 == i && e.1 == j)
            .map(|e| e.2)
            .sum()
    }

    /// Adds `value` to entry `(i, j)` (appends the entry).
    ///
    /// # Panics
    ///
    /// When `i` or `j` is not below the dimension: a model that writes outside its own
    /// dimension is a bug in the model, and an entry there would be silently dropped.
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, value: f64) {
        assert!(
            i < self.dimension && j < self.dimension,
            "entry ({i}, {j}) of a {0} × {0} block",
            self.dimension
        );
        self.entries.push((i, j, value));
    }

    /// Removes every entry, keeping the allocation.
    pub fn clear(&mut self) {
        self.entries.clear();
    }

    /// The largest `|i − j|` over the listed entries (0 for none).
    pub fn bandwidth(&self) -> usize {
        self.entries
            .iter()
            .map(|e| e.0.abs_diff(e.1))
            .max()
            .unwrap_or(0)
    }
}

/// The three second-derivative blocks of a [`DynLagrangian`](super::DynLagrangian) at one
/// point, each sparse: `xx = ∂²L/∂x∂x`, `xv = ∂²L/∂x∂v` (row: x index), `vv = ∂²L/∂v∂v`.
///
/// ```
/// use varembed::SparseHessian;
/// let mut h = SparseHessian::new(2);
/// h.vv.add(0, 0, 1.0);
/// h.xv.add(1, 0, 3.0);
/// assert_eq!((h.vv.get(0, 0), h.xv.get(1, 0), h.xx.entries().len()), (1.0, 3.0, 0));
/// h.clear();
/// assert!(h.vv.entries().is_empty());
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SparseHessian {
    /// `∂²L/∂x∂x`.
    pub xx: SparseBlock,
    /// `∂²L/∂x∂v` (row: x index, column: v index).
    pub xv: SparseBlock,
    /// `∂²L/∂v∂v`.
    pub vv: SparseBlock,
}

impl SparseHessian {
    /// Three zero `d × d` blocks.
    pub fn new(d: usize) -> Self {
        SparseHessian {
            xx: SparseBlock::new(d),
            xv: SparseBlock::new(d),
            vv: SparseBlock::new(d),
        }
    }

    /// Removes every entry of the three blocks, keeping the allocations.
    pub fn clear(&mut self) {
        self.xx.clear();
        self.xv.clear();
        self.vv.clear();
    }

    /// Whether every listed value is finite.
    pub fn is_finite(&self) -> bool {
        [&self.xx, &self.xv, &self.vv]
            .iter()
            .all(|b| b.entries.iter().all(|e| e.2.is_finite()))
    }
}
