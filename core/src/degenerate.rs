//! The degenerate directions of a symmetric matrix: what
//! [`Error::DegenerateLagrangian`](crate::Error::DegenerateLagrangian) names, on both paths.
//! Plain linear algebra on a matrix given entry by entry, so that it sits below every model.

/// Above this dimension [`degenerate_directions`] is not computed (a dense eigen-decomposition
/// of `d × d`, `O(d³)`, on the error's path only).
pub(crate) const DIRECTIONS_UP_TO: usize = 1024;

/// The degenerate directions of a symmetric `d × d` matrix given by `entry(i, j)` (see
/// [`Error::DegenerateLagrangian`](crate::Error::DegenerateLagrangian)): the unit eigenvectors whose eigenvalue is at most `10⁻¹⁰`
/// of the largest in modulus (at least the one of the smallest), each as its at most four
/// largest components `(index, value)`, by decreasing modulus, the largest positive (those
/// below `10⁻⁶` of it left out). Empty when
/// `d` exceeds [`DIRECTIONS_UP_TO`] or the matrix is not finite.
pub(crate) fn degenerate_directions(
    d: usize,
    entry: impl Fn(usize, usize) -> f64,
) -> Vec<Vec<(usize, f64)>> {
    if d == 0 || d > DIRECTIONS_UP_TO {
        return Vec::new();
    }
    let m = nalgebra::DMatrix::from_fn(d, d, |i, j| 0.5 * (entry(i, j) + entry(j, i)));
    if !m.iter().all(|c| c.is_finite()) {
        return Vec::new();
    }
    let eigen = nalgebra::SymmetricEigen::new(m);
    let moduli: Vec<f64> = eigen.eigenvalues.iter().map(|l| l.abs()).collect();
    let largest = moduli.iter().fold(0.0f64, |a, &b| a.max(b));
    let smallest = (0..d)
        .min_by(|&a, &b| moduli[a].total_cmp(&moduli[b]))
        .unwrap_or(0);
    let mut null: Vec<usize> = (0..d).filter(|&i| moduli[i] <= 1e-10 * largest).collect();
    if null.is_empty() {
        null.push(smallest);
    }
    null.iter()
        .map(|&i| {
            let column = eigen.eigenvectors.column(i);
            let mut parts: Vec<(usize, f64)> = column.iter().copied().enumerate().collect();
            parts.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
            parts.truncate(4);
            let top = parts.first().map_or(0.0, |p| p.1.abs());
            parts.retain(|p| p.1.abs() >= 1e-6 * top);
            let sign = if parts.first().is_some_and(|p| p.1 < 0.0) {
                -1.0
            } else {
                1.0
            };
            parts.iter().map(|&(k, c)| (k, sign * c)).collect()
        })
        .collect()
}
