//! Reading the warnings a solution carries, for the tests of the trust checks on both paths.

use varembed::Warning;

/// The measure of the `IllPosed` warning, if any.
pub fn ill_posed(warnings: &[Warning]) -> Option<f64> {
    warnings.iter().find_map(|w| match *w {
        Warning::IllPosed { measure } => Some(measure),
        _ => None,
    })
}

/// The `UnderResolved` warnings of `warnings`: `(h ω, limit)`.
pub fn under_resolved(warnings: &[Warning]) -> Vec<(f64, f64)> {
    warnings
        .iter()
        .filter_map(|w| match *w {
            Warning::UnderResolved { h_omega, limit } => Some((h_omega, limit)),
            _ => None,
        })
        .collect()
}
