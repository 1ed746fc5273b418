//! The sparse linear systems of a run-time-dimension model: a `d × d` matrix whose pattern is
//! that of the model's second derivatives, stored and factorised as a band after a
//! bandwidth-reducing ordering.
//!
//! A model that claims a half-bandwidth `b` ([`DynLagrangian::hessian_bandwidth`]) is stored in
//! its own order with that band. Any other model is ordered by reverse Cuthill–McKee on the
//! pattern its Hessian lists: a periodic chain (`x[(i + 1) % n]`, one entry in each corner)
//! becomes a band of half-width 2, a 2-D lattice of side `m` one of width about `m`. An entry
//! outside the planned band (a hand-written model that lists entries only where they are
//! nonzero, or a wrong claim) makes the caller plan again from the new pattern: a wrong
//! claim costs speed, never the answer.
//!
//! [`DynLagrangian::hessian_bandwidth`]: super::DynLagrangian::hessian_bandwidth

use crate::linalg::{BandNorms, BandedMatrix};

use super::sparse::SparseBlock;

/// An entry of the matrix falls outside the planned band.
#[derive(Debug)]
pub(crate) struct OutsideBand;

/// A band matrix of order `d` in a bandwidth-reducing order, with the buffers of its solves.
pub(crate) struct BandSystem {
    /// `position[i]`: where unknown `i` sits in the band order (`None`: the identity).
    position: Option<Vec<usize>>,
    band: usize,
    matrix: BandedMatrix,
    /// The right-hand side in band order.
    scratch: Vec<f64>,
}

impl BandSystem {
    /// The system for the pattern of `blocks` (the blocks that enter the matrix, their entries
    /// listed): the claimed band `claimed` when every entry lies within it, otherwise the
    /// reverse Cuthill–McKee order of the pattern.
    pub(crate) fn plan(d: usize, claimed: Option<usize>, blocks: &[&SparseBlock]) -> Self {
        let entries = || {
            blocks
                .iter()
                .flat_map(|b| b.entries().iter().map(|e| (e.0, e.1)))
        };
        if let Some(b) = claimed.filter(|&b| entries().all(|(i, j)| i.abs_diff(j) <= b)) {
            return Self::with(d, None, b.min(d.saturating_sub(1)));
        }
        let position = reverse_cuthill_mckee(d, entries());
        let band = entries()
            .map(|(i, j)| position[i].abs_diff(position[j]))
            .max()
            .unwrap_or(0);
        Self::with(d, Some(position), band)
    }

    fn with(d: usize, position: Option<Vec<usize>>, band: usize) -> Self {
        BandSystem {
            position,
            band,
            matrix: BandedMatrix::zeros(d, band, band),
            scratch: vec![0.0; d],
        }
    }

    /// The half-bandwidth in the planned order.
    pub(crate) fn band(&self) -> usize {
        self.band
    }

    /// Whether the unknowns are reordered.
    pub(crate) fn is_reordered(&self) -> bool {
        self.position.is_some()
    }

    /// Sets the matrix to zero.
    pub(crate) fn clear(&mut self) {
        self.matrix.clear();
    }

    /// Adds `value` to entry `(i, j)` (in the model's order).
    #[inline]
    pub(crate) fn add(&mut self, i: usize, j: usize, value: f64) -> Result<(), OutsideBand> {
        let (i, j) = match &self.position {
            Some(p) => (p[i], p[j]),
            None => (i, j),
        };
        if i.abs_diff(j) > self.band {
            return Err(OutsideBand);
        }
        self.matrix.add(i, j, value);
        Ok(())
    }

    /// Sets the matrix to `Σ c_k B_k + c_t B_tᵀ` for blocks `B_k` (`plain`) and `B_t`
    /// (`transposed`) in band mode with this system's half-width, row by row on the band
    /// storage; their entries outside the band are then added one by one. `Err` when the
    /// system is reordered, a block's band has another width, or an entry falls outside the
    /// band (the caller re-plans).
    pub(crate) fn set_from_bands(
        &mut self,
        plain: [(f64, &SparseBlock); 3],
        transposed: (f64, &SparseBlock),
    ) -> Result<(), OutsideBand> {
        if self.position.is_some() {
            return Err(OutsideBand);
        }
        let b = self.band;
        let width = 2 * b + 1;
        let terms = [
            band_of(b, plain[0])?,
            band_of(b, plain[1])?,
            band_of(b, plain[2])?,
        ];
        let transposed_band = band_of(b, transposed)?;
        let d = self.matrix.order();
        for i in 0..d {
            let row = self.matrix.row_mut(i);
            row.fill(0.0);
            let head = &mut row[..width];
            for (c, values) in terms.iter().flatten() {
                for (a, x) in head.iter_mut().zip(&values[i * width..(i + 1) * width]) {
                    *a += c * x;
                }
            }
            if let Some((c, values)) = transposed_band {
                // Entry (i, j) of Bᵀ is B(j, i), at offset i + b − j of row j.
                for (o, a) in head.iter_mut().enumerate() {
                    let Some(j) = (i + o).checked_sub(b).filter(|&j| j < d) else {
                        continue;
                    };
                    *a += c * values[j * width + 2 * b - o];
                }
            }
        }
        for (c, block) in plain {
            if c != 0.0 {
                for &(i, j, value) in block.entries() {
                    self.add(i, j, c * value)?;
                }
            }
        }
        let (c, block) = transposed;
        if c != 0.0 {
            for &(i, j, value) in block.entries() {
                self.add(j, i, c * value)?;
            }
        }
        Ok(())
    }

    /// `‖A‖∞` and the largest entry (before [`factorize`](Self::factorize)), from one pass.
    pub(crate) fn norms(&self) -> BandNorms {
        self.matrix.norms()
    }

    /// Factorises in place; `false` when singular or not finite.
    pub(crate) fn factorize(&mut self) -> bool {
        self.matrix.factorize().is_ok()
    }

    /// [`factorize`](Self::factorize) with the norms already measured.
    pub(crate) fn factorize_scaled(&mut self, norms: &BandNorms) -> bool {
        norms.is_finite() && self.matrix.factorize_scaled(norms.largest).is_ok()
    }

    /// The pivot ratio of the factors (see [`BandedMatrix::pivot_ratio`]).
    pub(crate) fn pivot_ratio(&self) -> f64 {
        self.matrix.pivot_ratio()
    }

    /// The smallest and largest pivot of the factors (see [`BandedMatrix::pivot_range`]).
    pub(crate) fn pivot_range(&self) -> (f64, f64) {
        self.matrix.pivot_range()
    }

    /// Solves `A z = r` with the factors, `z` overwriting `r`.
    pub(crate) fn solve_in_place(&mut self, r: &mut [f64]) {
        match &self.position {
            None => self.matrix.solve_inplace(r),
            Some(p) => {
                for (i, &pi) in p.iter().enumerate() {
                    self.scratch[pi] = r[i];
                }
                self.matrix.solve_inplace(&mut self.scratch);
                for (i, &pi) in p.iter().enumerate() {
                    r[i] = self.scratch[pi];
                }
            }
        }
    }
}

/// A term `c B` of [`BandSystem::set_from_bands`]: `B`'s band storage when it has one of
/// half-width `b` and `c ≠ 0`; `None` for nothing to add; `Err` for a band of another width.
fn band_of(
    b: usize,
    (c, block): (f64, &SparseBlock),
) -> Result<Option<(f64, &[f64])>, OutsideBand> {
    match block.band() {
        _ if c == 0.0 => Ok(None),
        None => Ok(None),
        Some((half_width, values)) if half_width == b => Ok(Some((c, values))),
        Some(_) => Err(OutsideBand),
    }
}

/// The reverse Cuthill–McKee order of the symmetric pattern of `entries` on `d` unknowns, as
/// `position[i]` = the place of unknown `i`. Each connected component is numbered by
/// breadth-first search from a pseudo-peripheral node (the last node reached from a node of
/// least degree), neighbours by increasing degree; the whole order is then reversed.
pub(crate) fn reverse_cuthill_mckee(
    d: usize,
    entries: impl Iterator<Item = (usize, usize)>,
) -> Vec<usize> {
    let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); d];
    for (i, j) in entries {
        if i != j {
            neighbours[i].push(j);
            neighbours[j].push(i);
        }
    }
    for list in &mut neighbours {
        list.sort_unstable();
        list.dedup();
    }
    let degree = |i: usize| neighbours[i].len();
    let mut order = Vec::with_capacity(d);
    // One marker array for every search: a node is marked with the number of the search that
    // reached it (0: none), so that no search clears or copies it and the whole ordering is
    // linear in the size of the pattern, however many components it has.
    let mut mark = vec![0usize; d];
    let mut search = 0;
    let mut by_degree: Vec<usize> = (0..d).collect();
    by_degree.sort_by_key(|&i| degree(i));
    let mut component = Vec::new();
    for &root in &by_degree {
        if mark[root] != 0 {
            continue;
        }
        // The last node a search from `root` reaches is far from it: start there. The probe
        // marks its nodes with its own number; the search from `far` re-marks them.
        search += 1;
        breadth_first(root, &neighbours, &mut mark, search, &mut component);
        let far = *component.last().unwrap_or(&root);
        search += 1;
        breadth_first(far, &neighbours, &mut mark, search, &mut component);
        order.extend_from_slice(&component);
    }
    let mut position = vec![0; d];
    for (place, &i) in order.iter().rev().enumerate() {
        position[i] = place;
    }
    position
}

/// The nodes reachable from `root` that no earlier component holds, in breadth-first order
/// (each node's neighbours by increasing degree), into `order`; each is marked `search`. A
/// node marked by an earlier *component* is never reached (components are disconnected), so
/// any mark below `search` but from this component's probe is simply overwritten.
fn breadth_first(
    root: usize,
    neighbours: &[Vec<usize>],
    mark: &mut [usize],
    search: usize,
    order: &mut Vec<usize>,
) {
    order.clear();
    order.push(root);
    mark[root] = search;
    let mut head = 0;
    let mut next = Vec::new();
    while head < order.len() {
        let i = order[head];
        head += 1;
        next.clear();
        next.extend(neighbours[i].iter().copied().filter(|&j| mark[j] != search));
        next.sort_by_key(|&j| neighbours[j].len());
        for &j in &next {
            mark[j] = search;
            order.push(j);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamic::sparse::SparseHessian;

    /// A periodic chain of `d` unknowns: neighbours and the wrap-around pair.
    fn ring(d: usize) -> impl Iterator<Item = (usize, usize)> {
        (0..d).flat_map(move |i| [(i, i), (i, (i + 1) % d), ((i + 1) % d, i)])
    }

    #[test]
    fn a_ring_becomes_a_band_of_half_width_two() {
        let d = 1000;
        let position = reverse_cuthill_mckee(d, ring(d));
        let mut sorted = position.clone();
        sorted.sort_unstable();
        assert!(
            sorted.iter().enumerate().all(|(k, &p)| k == p),
            "a permutation"
        );
        let band = ring(d)
            .map(|(i, j)| position[i].abs_diff(position[j]))
            .max();
        assert_eq!(band, Some(2));
    }

    #[test]
    fn disconnected_parts_are_each_ordered() {
        // Two separate chains of 5, and one isolated unknown.
        let entries = (0..4).map(|i| (i, i + 1)).chain((5..9).map(|i| (i, i + 1)));
        let position = reverse_cuthill_mckee(11, entries.clone());
        let band = entries
            .map(|(i, j)| position[i].abs_diff(position[j]))
            .max();
        assert_eq!(band, Some(1));
    }

    #[test]
    fn the_reordered_solve_matches_the_dense_one() {
        // The periodic second-difference matrix plus 3 I: diagonally dominant, nonsingular.
        let d = 12;
        let mut hessian = SparseHessian::new(d);
        for i in 0..d {
            hessian.xx.add(i, i, 5.0);
            hessian.xx.add(i, (i + 1) % d, -1.0);
            hessian.xx.add((i + 1) % d, i, -1.0);
        }
        let mut system = BandSystem::plan(d, None, &[&hessian.xx]);
        assert!(system.is_reordered() && system.band() == 2);
        let mut dense = vec![0.0; d * d];
        for &(i, j, value) in hessian.xx.entries() {
            system.add(i, j, value).unwrap();
            dense[i * d + j] += value;
        }
        let b: Vec<f64> = (0..d).map(|i| (i as f64).sin()).collect();
        let mut z = b.clone();
        assert!(system.factorize());
        system.solve_in_place(&mut z);
        for i in 0..d {
            let row: f64 = (0..d).map(|j| dense[i * d + j] * z[j]).sum();
            assert!(
                (row - b[i]).abs() < 1e-13,
                "row {i}: {row} against {}",
                b[i]
            );
        }
    }
}
