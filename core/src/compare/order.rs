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
/// law from errors that have not reached it yet, from errors that do not fall at all, or from
/// round-off.
///
/// With errors `e` on `N, 2N, 4N, …` and orders `p(N) = log₂(e_N / e_{2N})`, `p(2N)`, …, the
/// order at `N` is
///
/// - [`RoundOff`](Self::RoundOff) when `e_N` or `e_{2N}` is at most
///   [`ROUND_OFF`](Self::ROUND_OFF)` = 100 ε` times the size `max_k |Q_k|∞` of the solution: the
///   ratio then measures rounding, not convergence;
/// - else [`NotConverging`](Self::NotConverging) when `p(N) ≤`
///   [`NOT_CONVERGING`](Self::NOT_CONVERGING)` = 0.1`: doubling `N` gains less than 7 % of the
///   error (e.g. estimates that stay at 0.105 from `N = 50` to `800`);
/// - else [`Unchecked`](Self::Unchecked) when there is no `p(2N)` (the run ends at `2N`) or
///   `e_{4N}` is at round-off;
/// - else [`PreAsymptotic`](Self::PreAsymptotic) when `|p(N) − p(2N)| >`
///   [`TOLERANCE`](Self::TOLERANCE)` = 0.1` (e.g. the orders 0.5, 3.18 of a coarse run);
/// - else [`Drifting`](Self::Drifting) when the run has three successive orders to extrapolate
///   and `p(N)` is more than [`TOLERANCE`](Self::TOLERANCE) from their limit: Aitken's `Δ²` on
///   the last three orders `p₀, p₁, p₂` (differences `d₁ = p₁ − p₀`, `d₂ = p₂ − p₁`, ratio
///   `ρ = d₂/d₁`) gives the limit `p₂ + d₂ ρ/(1 − ρ)` when `|ρ| < 1`, and none when the
///   differences do not shrink (a steady drift such as 0.27, 0.33, 0.38, 0.41, 0.44, whose
///   steps are each below the tolerance); differences `|d₂| ≤ 0.01` count as settled, the limit
///   then being `p₂` (1.95, 1.98, 1.99 is asymptotic);
/// - else [`Asymptotic`](Self::Asymptotic).
///
/// New statuses may be added (the enum is `#[non_exhaustive]`): match with a wildcard arm.
///
/// ```
/// use varembed::OrderStatus;
/// assert_eq!(OrderStatus::PreAsymptotic.mark(), "*");
/// assert_eq!(OrderStatus::Drifting.mark(), "~");
/// assert_eq!(OrderStatus::Asymptotic.mark(), "");
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum OrderStatus {
    /// The next order agrees within [`TOLERANCE`](Self::TOLERANCE), and so does the limit the
    /// run's last orders extrapolate to.
    Asymptotic,
    /// The next order differs by more than [`TOLERANCE`](Self::TOLERANCE): the errors do not
    /// follow a power law yet.
    PreAsymptotic,
    /// Each next order is within [`TOLERANCE`](Self::TOLERANCE), but the orders drift: their
    /// extrapolated limit is further than that from this order, or they have none.
    Drifting,
    /// The order is at most [`NOT_CONVERGING`](Self::NOT_CONVERGING): the errors do not fall
    /// with `N` (a solve whose error is dominated by something other than the step: the
    /// data's regularity, a model error, a tolerance).
    NotConverging,
    /// An error is at round-off: the order measures rounding.
    RoundOff,
    /// No next order to check against.
    Unchecked,
}

impl OrderStatus {
    /// Largest difference between successive orders for an order to count as asymptotic, and
    /// largest distance from the extrapolated limit.
    ///
    /// ```
    /// assert_eq!(varembed::OrderStatus::TOLERANCE, 0.1);
    /// ```
    pub const TOLERANCE: f64 = 0.1;
    /// An order at or below this is [`NotConverging`](Self::NotConverging).
    ///
    /// ```
    /// assert_eq!(varembed::OrderStatus::NOT_CONVERGING, 0.1);
    /// ```
    pub const NOT_CONVERGING: f64 = 0.1;
    /// An error at most this times the solution's size is at round-off.
    ///
    /// ```
    /// assert!(varembed::OrderStatus::ROUND_OFF < 1e-13);
    /// ```
    pub const ROUND_OFF: f64 = 100.0 * f64::EPSILON;

    /// The mark printed after an order of this status in the comparison table and the report:
    /// none when asymptotic, `*` pre-asymptotic, `~` drifting, `!` not converging, `ε` at
    /// round-off, `?` unchecked.
    ///
    /// ```
    /// assert_eq!(varembed::OrderStatus::NotConverging.mark(), "!");
    /// ```
    pub fn mark(self) -> &'static str {
        match self {
            OrderStatus::Asymptotic => "",
            OrderStatus::PreAsymptotic => "*",
            OrderStatus::Drifting => "~",
            OrderStatus::NotConverging => "!",
            OrderStatus::RoundOff => "ε",
            OrderStatus::Unchecked => "?",
        }
    }

    /// One line per mark, for the legend of a table: what each mark after an order means.
    ///
    /// ```
    /// assert!(varembed::OrderStatus::legend().contains("~ drifting"));
    /// ```
    pub fn legend() -> String {
        format!(
            "* pre-asymptotic (the next order differs by more than {tol}); ~ drifting (the \
             orders' extrapolated limit is further than {tol}, or they have none); ! not \
             converging (order at most {nc}); ε at round-off (an error ≤ 100 ε max|Q|); ? not \
             checked (no next order)",
            tol = Self::TOLERANCE,
            nc = Self::NOT_CONVERGING,
        )
    }
}

/// Differences of successive orders at most this count as settled in the extrapolation.
const SETTLED: f64 = 0.01;

/// The limit Aitken's `Δ²` extrapolates from three successive orders, `None` when their
/// differences do not shrink (see [`OrderStatus`]).
fn extrapolated_order([p0, p1, p2]: [f64; 3]) -> Option<f64> {
    let (d1, d2) = (p1 - p0, p2 - p1);
    if d2.abs() <= SETTLED {
        return Some(p2);
    }
    let rho = d2 / d1;
    (rho.abs() < 1.0).then(|| p2 + d2 * rho / (1.0 - rho))
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
    let count = errors.len().saturating_sub(1);
    // The orders that measure convergence: finite, neither error at round-off.
    let usable = |i: usize| !at_round_off(i) && !at_round_off(i + 1) && order(i).is_finite();
    // The last three successive usable orders, extrapolated: `Some(None)` when they have no
    // limit, `None` when the run has no three such orders.
    let limit = (0..count.saturating_sub(2))
        .rev()
        .find(|&i| (i..i + 3).all(usable))
        .map(|i| extrapolated_order([order(i), order(i + 1), order(i + 2)]));
    let agrees_with_next = |i: usize| (order(i) - order(i + 1)).abs() <= OrderStatus::TOLERANCE;
    (0..count)
        .map(|i| {
            if at_round_off(i) || at_round_off(i + 1) {
                OrderStatus::RoundOff
            } else if order(i) <= OrderStatus::NOT_CONVERGING {
                OrderStatus::NotConverging
            } else if i + 2 >= errors.len() || at_round_off(i + 2) {
                OrderStatus::Unchecked
            } else if !agrees_with_next(i) {
                // Also when an order is not a number.
                OrderStatus::PreAsymptotic
            } else {
                match limit {
                    Some(None) => OrderStatus::Drifting,
                    Some(Some(p)) if (order(i) - p).abs() > OrderStatus::TOLERANCE => {
                        OrderStatus::Drifting
                    }
                    _ => OrderStatus::Asymptotic,
                }
            }
        })
        .collect()
}
