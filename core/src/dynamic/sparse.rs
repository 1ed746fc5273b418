//! The sparse second-derivative blocks a [`DynLagrangian`](super::DynLagrangian) writes.

use crate::degenerate::{DIRECTIONS_UP_TO, degenerate_directions};

/// One `d × d` second-derivative block as a list of entries `(i, j, value)`; an entry listed
/// twice holds the sum of its values, an entry never listed is zero.
///
/// A model writes it with [`add`](Self::add). [`clear`](Self::clear) keeps the allocation, so
/// a solver that clears and refills one block at every Newton iteration allocates only once.
///
/// The blocks the solver hands to [`DynLagrangian::hessian`](super::DynLagrangian::hessian)
/// of a banded model are in *band mode*: an entry within the band is summed in place, and
/// [`entries`](Self::entries) lists only those outside it. A model should only
/// [`add`](Self::add) to the blocks it is given, never read them back.
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
    /// In band mode (the solvers' blocks of a banded model): the entries within the band.
    band: Option<Band>,
}

/// The entries `|i − j| ≤ b` of a block, row by row: entry `(i, j)` at `i (2b + 1) + j + b − i`.
#[derive(Clone, Debug, Default, PartialEq)]
struct Band {
    half_width: usize,
    /// `2b + 1`, the length of a row.
    width: usize,
    values: Vec<f64>,
    /// Whether any entry was added since the last clear.
    touched: bool,
}

impl SparseBlock {
    /// The zero `d × d` block.
    pub fn new(d: usize) -> Self {
        SparseBlock {
            dimension: d,
            entries: Vec::new(),
            band: None,
        }
    }

    /// The zero `d × d` block in band mode: an entry within half-bandwidth `b` is summed in
    /// place, in band storage the solver combines row by row; only an entry outside the band
    /// is listed. What the step solver of a banded model fills at every Newton iteration.
    pub(crate) fn with_band(d: usize, b: usize) -> Self {
        SparseBlock {
            band: Some(Band {
                half_width: b,
                width: 2 * b + 1,
                values: vec![0.0; d * (2 * b + 1)],
                touched: false,
            }),
            ..SparseBlock::new(d)
        }
    }

    /// In band mode, the half-width and the band storage (entry `(i, j)` at
    /// `i (2b + 1) + j + b − i`); `None` when nothing was added in the band.
    pub(crate) fn band(&self) -> Option<(usize, &[f64])> {
        self.band
            .as_ref()
            .filter(|band| band.touched)
            .map(|band| (band.half_width, band.values.as_slice()))
    }

    /// Its dimension `d`.
    pub fn dimension(&self) -> usize {
        self.dimension
    }

    /// The entries as written, in order, repeats included (for a block the solver keeps in band
    /// mode, only those outside its band).
    pub fn entries(&self) -> &[(usize, usize, f64)] {
        &self.entries
    }

    /// The degenerate directions of this (symmetric) block, for
    /// [`Error::DegenerateLagrangian`](crate::Error::DegenerateLagrangian): empty above
    /// `d = 1024`.
    pub(crate) fn degenerate_directions(&self) -> Vec<Vec<(usize, f64)>> {
        let d = self.dimension;
        if d > DIRECTIONS_UP_TO {
            return Vec::new();
        }
        let mut dense = vec![0.0; d * d];
        for &(i, j, value) in &self.entries {
            dense[i * d + j] += value;
        }
        if let Some(band) = &self.band {
            let b = band.half_width;
            for i in 0..d {
                for j in i.saturating_sub(b)..(i + b + 1).min(d) {
                    dense[i * d + j] += band.values[i * (2 * b + 1) + j + b - i];
                }
            }
        }
        degenerate_directions(d, |i, j| dense[i * d + j])
    }

    /// Whether the block is the identity: every diagonal entry summing to exactly 1, and no
    /// nonzero value off the diagonal (listed or in the band).
    pub(crate) fn is_identity(&self) -> bool {
        self.as_multiple_of_identity() == Some(1.0)
    }

    /// `m` when the block is `m I`: every diagonal entry summing to the same `m`, and no nonzero
    /// value off the diagonal (listed or in the band); `None` otherwise.
    pub(crate) fn as_multiple_of_identity(&self) -> Option<f64> {
        let mut diagonal = vec![0.0; self.dimension];
        let mut off_diagonal = false;
        let mut each = |i: usize, j: usize, value: f64| {
            if i == j {
                diagonal[i] += value;
            } else {
                off_diagonal |= value != 0.0;
            }
        };
        for &(i, j, value) in &self.entries {
            each(i, j, value);
        }
        if let Some(band) = &self.band {
            let b = band.half_width;
            for (k, &value) in band.values.iter().enumerate() {
                // Row i, column j = i + (k mod (2b + 1)) − b (zeros outside the block).
                let (i, offset) = (k / band.width, k % band.width);
                each(i, (i + offset).wrapping_sub(b), value);
            }
        }
        let m = *diagonal.first()?;
        (!off_diagonal && diagonal.iter().all(|&c| c == m)).then_some(m)
    }

    /// Whether every value, listed or in the band, is zero.
    pub(crate) fn is_zero(&self) -> bool {
        let banded = self.band.as_ref().map_or(&[][..], |band| &band.values);
        self.entries.iter().all(|e| e.2 == 0.0) && banded.iter().all(|&v| v == 0.0)
    }

    /// Entry `(i, j)`: the sum of its values (`O(entries)`; for tests and small blocks).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let listed: f64 = self
            .entries
            .iter()
            .filter(|e| e.0 == i && e.1 == j)
            .map(|e| e.2)
            .sum();
        let banded = match &self.band {
            Some(band) if i.abs_diff(j) <= band.half_width => {
                let b = band.half_width;
                band.values[i * (2 * b + 1) + j + b - i]
            }
            _ => 0.0,
        };
        listed + banded
    }

    /// Adds `value` to entry `(i, j)` (appends the entry).
    ///
    /// # Panics
    ///
    /// When `i` or `j` is not below the dimension: a model that writes outside its own
    /// dimension is a bug in the model, and an entry there would be silently dropped.
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, value: f64) {
        // The same check, index and flag as `BlockWriter::add`, written out: going through a
        // writer built for each entry made the hand-written chain's runs (`hand_model` in the
        // large-chain bench) 3–8 % slower, measured. The two are pinned to each other and to a
        // dense sum by the unit test below.
        if i >= self.dimension || j >= self.dimension {
            outside(i, j, self.dimension);
        }
        if let Some(band) = &mut self.band {
            let b = band.half_width;
            if i.abs_diff(j) <= b {
                // Row i starts at i (2b + 1); column j sits at j + b − i within it.
                band.values[i * band.width + j + b - i] += value;
                band.touched = true;
                return;
            }
        }
        self.entries.push((i, j, value));
    }

    /// The block held open for many [`add`](BlockWriter::add)s, as a model's `hessian` writes
    /// its entries: the same entries in the same order, with the block's dimension, band and
    /// storage kept in the writer's own variables. Through [`add`](Self::add) each entry
    /// reads them back from the block after the last entry's write (the compiler cannot tell
    /// that a write into the values leaves them unchanged), which in a loop over a large
    /// model's entries costs more than the arithmetic of the entries.
    ///
    /// ```
    /// use varembed::SparseBlock;
    /// let mut b = SparseBlock::new(3);
    /// let mut w = b.writer();
    /// for i in 0..3 {
    ///     w.add(i, i, 2.0);
    /// }
    /// w.add(0, 2, -1.0);
    /// assert_eq!((b.get(1, 1), b.get(0, 2), b.entries().len()), (2.0, -1.0, 4));
    /// ```
    pub fn writer(&mut self) -> BlockWriter<'_> {
        let (reach, width, values, touched) = match &mut self.band {
            Some(band) => (
                band.half_width + 1,
                band.width,
                band.values.as_mut_slice(),
                Some(&mut band.touched),
            ),
            None => (0, 0, &mut [][..], None),
        };
        BlockWriter {
            dimension: self.dimension,
            reach,
            width,
            values,
            entries: &mut self.entries,
            touched,
            wrote: false,
        }
    }

    /// Removes every entry, keeping the allocation.
    pub fn clear(&mut self) {
        self.entries.clear();
        if let Some(band) = &mut self.band
            && band.touched
        {
            band.values.fill(0.0);
            band.touched = false;
        }
    }

    /// The largest `|i − j|` over the entries (0 for none; for a block in band mode, the
    /// band's half-width once anything was added in it).
    pub fn bandwidth(&self) -> usize {
        let listed = self.entries.iter().map(|e| e.0.abs_diff(e.1)).max();
        let banded = self.band().map(|(b, _)| b);
        listed.max(banded).unwrap_or(0)
    }
}

/// The panic of [`SparseBlock::add`] out of its inlined body.
#[cold]
#[inline(never)]
fn outside(i: usize, j: usize, d: usize) -> ! {
    panic!("entry ({i}, {j}) of a {d} × {d} block")
}

/// A [`SparseBlock`] open for writing ([`SparseBlock::writer`]): [`add`](Self::add) as the
/// block's own, the block's fields held here. What `#[lagrangian]` writes a model's Hessian
/// through.
#[derive(Debug)]
pub struct BlockWriter<'a> {
    dimension: usize,
    /// `b + 1` in band mode (an entry with `|i − j| < reach` is summed in place), 0 otherwise.
    reach: usize,
    /// `2b + 1`, a band row's length.
    width: usize,
    values: &'a mut [f64],
    entries: &'a mut Vec<(usize, usize, f64)>,
    /// The band's flag that something was added in it, set at the first such entry.
    touched: Option<&'a mut bool>,
    /// Whether an entry was added in the band through this writer.
    wrote: bool,
}

impl BlockWriter<'_> {
    /// Adds `value` to entry `(i, j)`, as [`SparseBlock::add`].
    ///
    /// # Panics
    ///
    /// When `i` or `j` is not below the dimension (see [`SparseBlock::add`]).
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, value: f64) {
        if i >= self.dimension || j >= self.dimension {
            outside(i, j, self.dimension);
        }
        if i.abs_diff(j) < self.reach {
            // Row i starts at i (2b + 1); column j sits at j + b − i within it.
            self.values[i * self.width + j + self.reach - 1 - i] += value;
            // The band's flag at the first entry in it: the writer needs nothing done when it
            // goes (a writer that is forgotten leaves no values that `clear` would skip).
            if !self.wrote {
                self.wrote = true;
                if let Some(touched) = self.touched.as_deref_mut() {
                    *touched = true;
                }
            }
        } else {
            self.entries.push((i, j, value));
        }
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

    /// Three zero blocks in band mode with half-width `b` (see [`SparseBlock::with_band`]).
    pub(crate) fn with_band(d: usize, b: usize) -> Self {
        SparseHessian {
            xx: SparseBlock::with_band(d, b),
            xv: SparseBlock::with_band(d, b),
            vv: SparseBlock::with_band(d, b),
        }
    }

    /// The three blocks open for writing ([`SparseBlock::writer`]).
    pub fn writer(&mut self) -> HessianWriter<'_> {
        HessianWriter {
            xx: self.xx.writer(),
            xv: self.xv.writer(),
            vv: self.vv.writer(),
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
        [&self.xx, &self.xv, &self.vv].iter().all(|b| {
            b.entries.iter().all(|e| e.2.is_finite())
                && b.band()
                    .is_none_or(|(_, v)| v.iter().all(|c| c.is_finite()))
        })
    }
}

/// The blocks of a [`SparseHessian`] open for writing ([`SparseHessian::writer`]).
#[derive(Debug)]
pub struct HessianWriter<'a> {
    /// `∂²L/∂x∂x`.
    pub xx: BlockWriter<'a>,
    /// `∂²L/∂x∂v` (row: x index, column: v index).
    pub xv: BlockWriter<'a>,
    /// `∂²L/∂v∂v`.
    pub vv: BlockWriter<'a>,
}

/// The Jacobian of a generalised force on the run-time path: `x.add(i, j, ∂f_i/∂x_j)`,
/// `v.add(i, j, ∂f_i/∂v_j)` (see [`DynLagrangian::force_jacobian`](crate::DynLagrangian)).
///
/// ```
/// let mut j = varembed::SparseForceJacobian::new(2);
/// j.v.add(1, 1, -0.5);
/// assert_eq!((j.v.get(1, 1), j.x.entries().len()), (-0.5, 0));
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SparseForceJacobian {
    /// `∂f/∂x`.
    pub x: SparseBlock,
    /// `∂f/∂v`.
    pub v: SparseBlock,
}

impl SparseForceJacobian {
    /// Two zero `d × d` blocks.
    pub fn new(d: usize) -> Self {
        SparseForceJacobian {
            x: SparseBlock::new(d),
            v: SparseBlock::new(d),
        }
    }

    /// The two blocks open for writing ([`SparseBlock::writer`]).
    pub fn writer(&mut self) -> ForceJacobianWriter<'_> {
        ForceJacobianWriter {
            x: self.x.writer(),
            v: self.v.writer(),
        }
    }

    /// Removes every entry, keeping the allocations.
    pub fn clear(&mut self) {
        self.x.clear();
        self.v.clear();
    }
}

/// The blocks of a [`SparseForceJacobian`] open for writing ([`SparseForceJacobian::writer`]).
#[derive(Debug)]
pub struct ForceJacobianWriter<'a> {
    /// `∂f/∂x`.
    pub x: BlockWriter<'a>,
    /// `∂f/∂v`.
    pub v: BlockWriter<'a>,
}

#[cfg(test)]
mod tests {
    use super::SparseBlock;
    use rand::rngs::StdRng;
    use rand::{Rng, SeedableRng};

    /// A writer leaves a block exactly as the same entries added one by one: the same band
    /// values to the bit, the same listed entries in order, and the band marked as written only
    /// when something was added in it; and every entry is the sum of what was added to it,
    /// over random entries (inside and outside the band, on the diagonal, repeated) in both
    /// modes.
    #[test]
    fn a_writer_adds_as_the_block_does() {
        let mut rng = StdRng::seed_from_u64(17);
        for case in 0..200 {
            let d = rng.random_range(1..10);
            let band = (case % 3 > 0).then(|| rng.random_range(0..3));
            let fresh = || band.map_or(SparseBlock::new(d), |b| SparseBlock::with_band(d, b));
            let count = rng.random_range(0..3 * d);
            let entries: Vec<(usize, usize, f64)> = (0..count)
                .map(|_| {
                    let (i, j) = (rng.random_range(0..d), rng.random_range(0..d));
                    (i, j, rng.random_range(-2.0..2.0))
                })
                .collect();
            let (mut by_add, mut by_writer) = (fresh(), fresh());
            entries.iter().for_each(|&(i, j, v)| by_add.add(i, j, v));
            let mut writer = by_writer.writer();
            entries.iter().for_each(|&(i, j, v)| writer.add(i, j, v));
            assert_eq!(by_writer, by_add, "case {case}: d = {d}, band {band:?}");
            assert_eq!(
                by_writer.band().is_some(),
                by_add.band().is_some(),
                "case {case}"
            );
            // Against an independent oracle: the entries summed into a dense matrix in the
            // order given, read back through `get` (its own index formula).
            let mut dense = vec![vec![0.0; d]; d];
            entries.iter().for_each(|&(i, j, v)| dense[i][j] += v);
            for (i, row) in dense.iter().enumerate() {
                for (j, &expected) in row.iter().enumerate() {
                    assert_eq!(by_writer.get(i, j), expected, "case {case}: ({i}, {j})");
                }
            }
        }
    }

    #[test]
    #[should_panic(expected = "entry (1, 3) of a 3 × 3 block")]
    fn a_writer_refuses_an_entry_outside_the_block() {
        let mut block = SparseBlock::with_band(3, 1);
        block.writer().add(1, 3, 1.0);
    }

    /// The same entries listed and in band storage give the same answers; repeated entries
    /// are summed on the diagonal.
    #[test]
    fn identity_and_zero_read_listed_and_banded_entries() {
        for banded in [false, true] {
            let block = |entries: &[(usize, usize, f64)]| {
                let mut b = if banded {
                    SparseBlock::with_band(4, 1)
                } else {
                    SparseBlock::new(4)
                };
                entries.iter().for_each(|&(i, j, v)| b.add(i, j, v));
                b
            };
            let diagonal: Vec<_> = (0..4).map(|i| (i, i, 1.0)).collect();
            assert!(block(&diagonal).is_identity());
            let mut halves: Vec<_> = (0..4).map(|i| (i, i, 0.5)).collect();
            halves.extend_from_slice(&halves.clone());
            assert!(block(&halves).is_identity());
            let mut coupled = diagonal.clone();
            coupled.push((1, 2, 1e-3));
            assert!(!block(&coupled).is_identity() && !block(&coupled).is_zero());
            assert!(!block(&diagonal[..3]).is_identity());
            assert!(block(&[]).is_zero() && block(&[(0, 1, 0.0)]).is_zero());
            assert!(!block(&[(3, 3, 2.0)]).is_zero());
            let twice: Vec<_> = (0..4).map(|i| (i, i, 2.0)).collect();
            assert_eq!(block(&twice).as_multiple_of_identity(), Some(2.0));
            assert!(!block(&twice).is_identity());
            let mut uneven = twice.clone();
            uneven[3].2 = 3.0;
            assert_eq!(block(&uneven).as_multiple_of_identity(), None);
        }
    }
}
