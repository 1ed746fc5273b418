//! [`RowBlocks`]: one `D × D` block per row of the fast path, stored once while every row has
//! the same (the `L_vv` of a constant mass matrix, the zero `L_xv` of most mechanical
//! Lagrangians): at `N = 10⁷` rows a block per row is 80 MB at `d = 1`.

use crate::lagrangian::Matrix;

/// `len` blocks, one per row: a single block while all are equal, one per row once two differ.
#[derive(Clone, Debug)]
pub(super) enum RowBlocks<const D: usize> {
    /// Every row's block is this one.
    Uniform(Matrix<D>, usize),
    PerRow(Vec<Matrix<D>>),
}

impl<const D: usize> RowBlocks<D> {
    /// `len` copies of `block`.
    pub(super) fn uniform(block: Matrix<D>, len: usize) -> Self {
        RowBlocks::Uniform(block, len)
    }

    /// Row `i`'s block.
    #[inline]
    pub(super) fn get(&self, i: usize) -> &Matrix<D> {
        match self {
            RowBlocks::Uniform(block, _) => block,
            RowBlocks::PerRow(blocks) => &blocks[i],
        }
    }

    /// Sets row `i`'s block. Rows are set in order from 0 at a new linearisation: row 0's block
    /// makes uniform blocks that of every row, and a later row that differs stores one block
    /// per row (the rows before it hold row 0's). Blocks once stored per row stay so.
    pub(super) fn set(&mut self, i: usize, value: Matrix<D>) {
        match self {
            RowBlocks::Uniform(block, _) if i == 0 => *block = value,
            RowBlocks::Uniform(block, _) if *block == value => {}
            RowBlocks::Uniform(block, len) => {
                let mut blocks = vec![*block; *len];
                blocks[i] = value;
                *self = RowBlocks::PerRow(blocks);
            }
            RowBlocks::PerRow(blocks) => blocks[i] = value,
        }
    }

    /// Every row's block, once each where they are uniform.
    pub(super) fn distinct(&self) -> &[Matrix<D>] {
        match self {
            RowBlocks::Uniform(block, _) => std::slice::from_ref(block),
            RowBlocks::PerRow(blocks) => blocks,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against a plain vector of blocks, through sequences of linearisations that stay
    /// uniform, turn per-row at the first, a middle and the last row, and then become uniform
    /// again (stored per row still, with the same values).
    #[test]
    fn row_blocks_read_as_the_blocks_set() {
        let len = 5;
        let m = |x: f64| Matrix::<2>::new(x, 1.0, 0.0, -x);
        let sequences = [
            vec![0.5; len],
            vec![0.5, 2.0, 0.5, 0.5, 0.5],
            vec![0.5, 0.5, 0.5, 0.5, 3.0],
            vec![1.0; len],
            vec![-1.0, 0.5, 0.5, 0.5, 0.5],
        ];
        for first in 0..sequences.len() {
            let mut blocks = RowBlocks::uniform(Matrix::<2>::zeros(), len);
            for values in sequences.iter().cycle().skip(first).take(sequences.len()) {
                for (i, &x) in values.iter().enumerate() {
                    blocks.set(i, m(x));
                }
                for (i, &x) in values.iter().enumerate() {
                    assert_eq!(*blocks.get(i), m(x), "{values:?} row {i}");
                }
                let uniform = values.iter().all(|&x| x == values[0]);
                if uniform && matches!(blocks, RowBlocks::Uniform(..)) {
                    assert_eq!(blocks.distinct(), [m(values[0])]);
                } else {
                    assert_eq!(blocks.distinct().len(), len);
                }
            }
        }
    }
}
