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
//! A band of half-width 1 (a chain's Jacobian) is stored as three diagonals and factorised
//! by the tridiagonal LU, which gives the band LU's factors without its index arithmetic.
//!
//! [`DynLagrangian::hessian_bandwidth`]: super::DynLagrangian::hessian_bandwidth

use crate::linalg::{BandNorms, BandedMatrix, TridiagonalMatrix};

use super::sparse::SparseBlock;

/// An entry of the matrix falls outside the planned band.
#[derive(Debug)]
pub(crate) struct OutsideBand;

/// A band matrix of order `d` in a bandwidth-reducing order, with the buffers of its solves.
pub(crate) struct BandSystem {
    /// `position[i]`: where unknown `i` sits in the band order (`None`: the identity).
    position: Option<Vec<usize>>,
    band: usize,
    matrix: Storage,
    /// The right-hand side in band order.
    scratch: Vec<f64>,
}

/// The matrix of a [`BandSystem`]: three diagonals for a half-width of at most 1, rows of the
/// band otherwise.
enum Storage {
    Tridiagonal(TridiagonalMatrix),
    Band(BandedMatrix),
}

impl BandSystem {
    /// The system for the pattern of `blocks` (the blocks that enter the matrix, their entries
    /// listed): the claimed band `claimed` when every entry lies within it, otherwise the
    /// reverse Cuthill–McKee order of the pattern.
    pub(crate) fn plan(d: usize, claimed: Option<usize>, blocks: &[&SparseBlock]) -> Self {
        let (position, band) = order(d, claimed, blocks);
        Self::with(d, position, band)
    }

    /// The system of `s` unknowns per coordinate of a model of dimension `d` (unknown `(i, c)`
    /// at `i d + c`, a stage system's order), stored component by component: unknown
    /// `(i, c)` sits at `c' s + i`, `c'` the place of `c` in the order [`plan`](Self::plan)
    /// gives `blocks`. A pattern of half-width `b` in that order becomes a band of half-width
    /// `s (b + 1) − 1`. Also returns whether the model's coordinates were reordered.
    pub(crate) fn interleaved(
        d: usize,
        s: usize,
        claimed: Option<usize>,
        blocks: &[&SparseBlock],
    ) -> (Self, bool) {
        let (model, b) = order(d, claimed, blocks);
        let reordered = model.is_some();
        if s == 1 {
            return (Self::with(d, model, b), reordered);
        }
        let place = |c: usize| model.as_ref().map_or(c, |p| p[c]);
        let position = (0..s * d).map(|k| place(k % d) * s + k / d).collect();
        let band = (s * (b + 1) - 1).min(s * d - 1);
        (Self::with(s * d, Some(position), band), reordered)
    }

    fn with(d: usize, position: Option<Vec<usize>>, band: usize) -> Self {
        BandSystem {
            position,
            band,
            matrix: if band <= 1 {
                Storage::Tridiagonal(TridiagonalMatrix::zeros(d))
            } else {
                Storage::Band(BandedMatrix::zeros(d, band, band))
            },
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
        match &mut self.matrix {
            Storage::Tridiagonal(m) => m.clear(),
            Storage::Band(m) => m.clear(),
        }
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
        match &mut self.matrix {
            Storage::Tridiagonal(m) => m.add(i, j, value),
            Storage::Band(m) => m.add(i, j, value),
        }
        Ok(())
    }

    /// Sets the matrix to `Σ c_k B_k + c_t B_tᵀ` (`fresh`), or adds that sum to it, for blocks
    /// `B_k` (`plain`) and `B_t` (`transposed`) in band mode with this system's half-width, row
    /// by row on the band storage; their entries outside the band are then added one by one.
    /// `Err` when the system is reordered, a block's band has another width, or an entry falls
    /// outside the band (the caller re-plans).
    pub(crate) fn add_bands(
        &mut self,
        plain: [(f64, &SparseBlock); 3],
        transposed: (f64, &SparseBlock),
        fresh: bool,
    ) -> Result<(), OutsideBand> {
        if self.position.is_some() {
            return Err(OutsideBand);
        }
        let b = self.band;
        let terms = [
            band_of(b, plain[0])?,
            band_of(b, plain[1])?,
            band_of(b, plain[2])?,
        ];
        let transposed_band = band_of(b, transposed)?;
        match &mut self.matrix {
            Storage::Tridiagonal(m) => set_diagonals(m, b, &terms, transposed_band, fresh),
            Storage::Band(m) => set_rows(m, b, &terms, transposed_band, fresh),
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

    /// Factorises in place; `false` when singular or not finite.
    pub(crate) fn factorize(&mut self) -> bool {
        self.factorize_measured().1
    }

    /// Factorises in place and returns the norms of the matrix as it was (`‖A‖∞` for the
    /// round-off floor of Newton's stopping rule), and whether it is regular: finite, with no
    /// pivot at or below `1e-14` times its largest entry. The tridiagonal LU measures on its
    /// way through the rows; a wider band takes one pass first.
    pub(crate) fn factorize_measured(&mut self) -> (BandNorms, bool) {
        match &mut self.matrix {
            Storage::Tridiagonal(m) => m.factorize_measured(),
            Storage::Band(m) => {
                let norms = m.norms();
                let regular = norms.is_finite() && m.factorize_scaled(norms.largest).is_ok();
                (norms, regular)
            }
        }
    }

    /// [`factorize_measured`](Self::factorize_measured), and when the matrix is regular, the
    /// solution `z` of `A z = r` in place of `r` (a Newton iteration's solve: the tridiagonal
    /// LU substitutes forward during its elimination).
    pub(crate) fn factorize_solving(&mut self, r: &mut [f64]) -> (BandNorms, bool) {
        if let (Storage::Tridiagonal(m), None) = (&mut self.matrix, &self.position) {
            return m.factorize_solving(r);
        }
        let (norms, regular) = self.factorize_measured();
        if regular {
            self.solve_in_place(r);
        }
        (norms, regular)
    }

    /// The smallest over the largest pivot of the factors: the scale-free ratio the
    /// degeneracy checks read (0 when every pivot is 0).
    pub(crate) fn pivot_ratio(&self) -> f64 {
        let (lo, hi) = self.pivot_range();
        if hi > 0.0 { lo / hi } else { 0.0 }
    }

    /// The smallest and largest pivot of the factors (see [`BandedMatrix::pivot_range`]).
    pub(crate) fn pivot_range(&self) -> (f64, f64) {
        match &self.matrix {
            Storage::Tridiagonal(m) => m.pivot_range(),
            Storage::Band(m) => m.pivot_range(),
        }
    }

    /// Solves `A z = r` with the factors, `z` overwriting `r`.
    pub(crate) fn solve_in_place(&mut self, r: &mut [f64]) {
        let solve = |matrix: &Storage, r: &mut [f64]| match matrix {
            Storage::Tridiagonal(m) => m.solve_inplace(r),
            Storage::Band(m) => m.solve_inplace(r),
        };
        match &self.position {
            None => solve(&self.matrix, r),
            Some(p) => {
                for (i, &pi) in p.iter().enumerate() {
                    self.scratch[pi] = r[i];
                }
                solve(&self.matrix, &mut self.scratch);
                for (i, &pi) in p.iter().enumerate() {
                    r[i] = self.scratch[pi];
                }
            }
        }
    }
}

/// The order of the unknowns for the pattern of `blocks` and its half-width: the claimed band
/// `claimed` in the model's own order (`None`) when every entry lies within it, otherwise the
/// reverse Cuthill–McKee order of the pattern (`position[i]`: the place of unknown `i`).
fn order(d: usize, claimed: Option<usize>, blocks: &[&SparseBlock]) -> (Option<Vec<usize>>, usize) {
    let entries = || {
        blocks
            .iter()
            .flat_map(|b| b.entries().iter().map(|e| (e.0, e.1)))
    };
    if let Some(b) = claimed.filter(|&b| entries().all(|(i, j)| i.abs_diff(j) <= b)) {
        return (None, b.min(d.saturating_sub(1)));
    }
    let position = reverse_cuthill_mckee(d, entries());
    let band = entries()
        .map(|(i, j)| position[i].abs_diff(position[j]))
        .max()
        .unwrap_or(0);
    (Some(position), band)
}

/// A block's band storage scaled by `c` (entry `(i, j)` at `i (2b + 1) + j + b − i`), one
/// term of [`BandSystem::add_bands`].
type Term<'a> = Option<(f64, &'a [f64])>;

/// `Σ c_k B_k + c_t B_tᵀ` into (`fresh`) or onto the rows of a band matrix of half-width `b`.
fn set_rows(
    matrix: &mut BandedMatrix,
    b: usize,
    plain: &[Term<'_>; 3],
    transposed: Term<'_>,
    fresh: bool,
) {
    let width = 2 * b + 1;
    let d = matrix.order();
    for i in 0..d {
        let row = matrix.row_mut(i);
        if fresh {
            row.fill(0.0);
        }
        let head = &mut row[..width];
        for (c, values) in plain.iter().flatten() {
            for (a, x) in head.iter_mut().zip(&values[i * width..(i + 1) * width]) {
                *a += c * x;
            }
        }
        if let Some((c, values)) = transposed {
            // Entry (i, j) of Bᵀ is B(j, i), at offset i + b − j of row j.
            for (o, a) in head.iter_mut().enumerate() {
                let Some(j) = (i + o).checked_sub(b).filter(|&j| j < d) else {
                    continue;
                };
                *a += c * values[j * width + 2 * b - o];
            }
        }
    }
}

/// `Σ c_k B_k + c_t B_tᵀ` into (`fresh`) or onto the three diagonals of a matrix of
/// half-width `b ≤ 1`, one diagonal at a time. In the blocks' storage (rows of `2b + 1`),
/// `B(i, i)` sits at `i w + b`, `B(i, i + 1)` at `i w + b + 1` and `B(i + 1, i)` at
/// `(i + 1) w + b − 1`; `Bᵀ` exchanges the last two.
fn set_diagonals(
    matrix: &mut TridiagonalMatrix,
    b: usize,
    plain: &[Term<'_>; 3],
    transposed: Term<'_>,
    fresh: bool,
) {
    let w = 2 * b + 1;
    let (lower, diagonal, upper) = matrix.diagonals_mut();
    if fresh {
        lower.fill(0.0);
        diagonal.fill(0.0);
        upper.fill(0.0);
    }
    let terms = plain.iter().flatten().map(|&t| (t, false));
    for ((c, values), transpose) in terms.chain(transposed.map(|t| (t, true))) {
        for (a, row) in diagonal.iter_mut().zip(values.chunks_exact(w)) {
            *a += c * row[b];
        }
        if b == 0 {
            continue;
        }
        // Row i + 1's entry before its diagonal, and row i's entry after it.
        let below = values[w..].chunks_exact(w).map(|row| row[0]);
        let above = values.chunks_exact(w).map(|row| row[2]);
        let (below_into, above_into) = if transpose {
            (upper.iter_mut(), lower.iter_mut())
        } else {
            (lower.iter_mut(), upper.iter_mut())
        };
        for (a, x) in below_into.zip(below) {
            *a += c * x;
        }
        for (a, x) in above_into.zip(above) {
            *a += c * x;
        }
    }
}

/// A term `c B` of [`BandSystem::add_bands`]: `B`'s band storage when it has one of
/// half-width `b` and `c ≠ 0`; `None` for nothing to add; `Err` for a band of another width.
fn band_of(b: usize, (c, block): (f64, &SparseBlock)) -> Result<Term<'_>, OutsideBand> {
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
    fn the_diagonals_are_the_band_rows_of_the_same_combination() {
        // Blocks in band mode with every entry of the band set, plain and transposed terms
        // with distinct coefficients, at half-widths 1 and 0.
        for b in [1, 0] {
            let d = 7;
            let mut hessian = SparseHessian::with_band(d, b);
            for i in 0..d {
                for j in i.saturating_sub(b)..=(i + b).min(d - 1) {
                    let (x, y) = (i as f64, j as f64);
                    hessian.xx.add(i, j, (0.3 * x + 1.1 * y).sin());
                    hessian.xv.add(i, j, (0.7 * x - 0.2 * y).cos());
                    hessian.vv.add(i, j, 1.0 + 0.1 * x * y);
                }
            }
            let terms = [
                band_of(b, (1.0, &hessian.vv)).unwrap(),
                band_of(b, (-0.3, &hessian.xx)).unwrap(),
                band_of(b, (0.7, &hessian.xv)).unwrap(),
            ];
            let transposed = band_of(b, (1.9, &hessian.xv)).unwrap();
            let mut rows = BandedMatrix::zeros(d, b, b);
            set_rows(&mut rows, b, &terms, transposed, true);
            let mut tri = TridiagonalMatrix::zeros(d);
            set_diagonals(&mut tri, b, &terms, transposed, true);
            let (lower, diagonal, upper) = tri.diagonals_mut();
            for i in 0..d {
                assert_eq!(
                    diagonal[i].to_bits(),
                    rows.get(i, i).to_bits(),
                    "b = {b}, {i}"
                );
                if i + 1 < d {
                    assert_eq!(lower[i].to_bits(), rows.get(i + 1, i).to_bits(), "{i}");
                    assert_eq!(upper[i].to_bits(), rows.get(i, i + 1).to_bits(), "{i}");
                }
            }
            // The transposed term is not the plain one: the combination is not symmetric.
            assert!(b == 0 || lower[2] != upper[2]);
        }
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
