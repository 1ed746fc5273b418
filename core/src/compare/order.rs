//! The observed order of convergence ([`observed_order`]) and how far it can be trusted
//! ([`OrderStatus`]).

/// The observed order of convergence between a coarse grid of `n_coarse` steps with error
/// `e_coarse` and a finer one of `n_fine` steps with error `e_fine`:
///
/// `p = log₂(e_coarse / e_fine) / log₂(n_fine / n_coarse)`,
///
/// which is `log₂(e_N / e_{2N})` when the fine grid has twice the steps (an error `C hᵖ` gives
/// exactly `p`). The errors are whatever measures the distance to the solution: the error
/// against a reference, or the self-convergence estimate `‖Q_N − Q_{2N}‖` on the coarser nodes
/// ([`Convergence::error_estimates`](crate::Convergence::error_estimates)).
///
/// # Example
///
/// ```
/// use varembed::observed_order;
/// // The error falls by 4 when N doubles: second order.
/// assert_eq!(observed_order((100, 0.5), (200, 0.125)), 2.0);
/// // Skipping a grid (N to 4N) does not change the order of a clean power law.
/// assert_eq!(observed_order((100, 0.5), (400, 0.03125)), 2.0);
/// ```
pub fn observed_order((n_coarse, e_coarse): (usize, f64), (n_fine, e_fine): (usize, f64)) -> f64 {
    (e_coarse / e_fine).log2() / (n_fine as f64 / n_coarse as f64).log2()
}

/// [`observed_order`] between each pair of successive entries of `(N, e)`, ordered by
/// increasing `N`: one order fewer than entries.
///
/// ```
/// let orders = varembed::observed_orders(&[(10, 0.4), (20, 0.1), (40, 0.025)]);
/// assert_eq!(orders, [2.0, 2.0]);
/// ```
pub fn observed_orders(errors: &[(usize, f64)]) -> Vec<f64> {
    errors
        .windows(2)
        .map(|w| observed_order(w[0], w[1]))
        .collect()
}

/// How far an observed order can be trusted: one order between two grids cannot tell a power
/// law from errors that have not reached it yet, or from round-off.
///
/// With errors `e` on `N, 2N, 4N` and orders `p(N) = log₂(e_N / e_{2N})`, `p(2N)`, the order at
/// `N` is
///
/// - [`RoundOff`](Self::RoundOff) when `e_N` or `e_{2N}` is at most
///   [`ROUND_OFF`](Self::ROUND_OFF)` = 100 ε` times the size `max_k |Q_k|∞` of the solution: the
///   ratio then measures rounding, not convergence;
/// - else [`Unchecked`](Self::Unchecked) when there is no `p(2N)` (the run ends at `2N`) or
///   `e_{4N}` is at round-off;
/// - else [`PreAsymptotic`](Self::PreAsymptotic) when `|p(N) − p(2N)| >`
///   [`TOLERANCE`](Self::TOLERANCE)` = 0.1` (e.g. the orders −0.29, 3.18 of a coarse run);
/// - else [`Asymptotic`](Self::Asymptotic).
///
/// ```
/// use varembed::OrderStatus;
/// assert_eq!(OrderStatus::PreAsymptotic.mark(), "*");
/// assert_eq!(OrderStatus::Asymptotic.mark(), "");
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OrderStatus {
    /// The next order agrees within [`TOLERANCE`](Self::TOLERANCE).
    Asymptotic,
    /// The next order differs by more than [`TOLERANCE`](Self::TOLERANCE): the errors do not
    /// follow a power law yet.
    PreAsymptotic,
    /// An error is at round-off: the order measures rounding.
    RoundOff,
    /// No next order to check against.
    Unchecked,
}

impl OrderStatus {
    /// Largest difference between successive orders for an order to count as asymptotic.
    ///
    /// ```
    /// assert_eq!(varembed::OrderStatus::TOLERANCE, 0.1);
    /// ```
    pub const TOLERANCE: f64 = 0.1;
    /// An error at most this times the solution's size is at round-off.
    ///
    /// ```
    /// assert!(varembed::OrderStatus::ROUND_OFF < 1e-13);
    /// ```
    pub const ROUND_OFF: f64 = 100.0 * f64::EPSILON;

    /// The mark printed after an order of this status in the comparison table and the report:
    /// none when asymptotic, `*` pre-asymptotic, `ε` at round-off, `?` unchecked.
    ///
    /// ```
    /// assert_eq!(varembed::OrderStatus::PreAsymptotic.mark(), "*");
    /// ```
    pub fn mark(self) -> &'static str {
        match self {
            OrderStatus::Asymptotic => "",
            OrderStatus::PreAsymptotic => "*",
            OrderStatus::RoundOff => "ε",
            OrderStatus::Unchecked => "?",
        }
    }
}

/// The [`OrderStatus`] of each order between successive entries of `(N, e, scale)`, `scale`
/// the size of the solution the error is measured on (see [`OrderStatus`] for the rule).
pub(crate) fn order_statuses(errors: &[(usize, f64, f64)]) -> Vec<OrderStatus> {
    let at_round_off = |i: usize| {
        let (_, e, scale) = errors[i];
        e <= OrderStatus::ROUND_OFF * scale
    };
    let order = |i: usize| {
        observed_order(
            (errors[i].0, errors[i].1),
            (errors[i + 1].0, errors[i + 1].1),
        )
    };
    (0..errors.len().saturating_sub(1))
        .map(|i| {
            if at_round_off(i) || at_round_off(i + 1) {
                OrderStatus::RoundOff
            } else if i + 2 >= errors.len() || at_round_off(i + 2) {
                OrderStatus::Unchecked
            } else if (order(i) - order(i + 1)).abs() <= OrderStatus::TOLERANCE {
                OrderStatus::Asymptotic
            } else {
                // Also when an order is not a number.
                OrderStatus::PreAsymptotic
            }
        })
        .collect()
}
