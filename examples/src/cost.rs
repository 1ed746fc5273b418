//! The cost of reaching a target error, read off the lines of a work–precision sweep:
//! interpolated between the two measured points around the target where the sweep reached it,
//! extrapolated from the finest point along the last observed order where it did not. The
//! scenes' advice ("use this scheme") and the double pendulum's speed-up are these numbers.

use crate::scene::{SweepLine, SweepPoint};

/// How a [`Cost`] was obtained.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reach {
    /// The sweep reached the target: `N` and the time interpolated log–log between the two
    /// measured points around it (or the coarsest point, when it is already below the target).
    Measured,
    /// The sweep did not reach the target: `N = N_f (e_f / target)^{1/p}` from the finest point
    /// `(N_f, e_f)` and the last observed order `p`, and the time scaled with `N` (the cost per
    /// step of the finest point).
    Extrapolated {
        /// The observed order extrapolated along.
        order: f64,
    },
}

/// What one line needs to reach a target error.
#[derive(Clone, Debug, PartialEq)]
pub struct Cost {
    /// The line's legend entry.
    pub label: String,
    /// Steps (not rounded: an interpolated or extrapolated number).
    pub n: f64,
    /// Wall time of the solve, seconds.
    pub seconds: f64,
    /// Measured or extrapolated.
    pub reach: Reach,
}

impl Cost {
    /// `N = …, … s`, with how it was obtained.
    pub fn describe(&self) -> String {
        let how = match self.reach {
            Reach::Measured => "measured".to_string(),
            Reach::Extrapolated { order } => {
                format!("extrapolated along the observed order {order:.2}")
            }
        };
        format!(
            "{}: N ≈ {:.2e} steps, {:.2e} s ({how})",
            self.label, self.n, self.seconds
        )
    }
}

/// The cost of `line` to reach max error `target`, or `None` when the line has no point, or
/// did not reach the target and its last observed order is not positive (no extrapolation).
pub fn cost_to_reach(line: &SweepLine, target: f64) -> Option<Cost> {
    let points = &line.points;
    let cost = |n: f64, seconds: f64, reach| Cost {
        label: line.label.clone(),
        n,
        seconds,
        reach,
    };
    let first = points.first()?;
    if first.error <= target {
        return Some(cost(first.n as f64, first.seconds, Reach::Measured));
    }
    if let Some(i) = points.iter().position(|p| p.error <= target) {
        let (a, b) = (points[i - 1], points[i]);
        let (n, seconds) = interpolate(a, b, target);
        return Some(cost(n, seconds, Reach::Measured));
    }
    let order = *line.orders().last()?;
    if !(order.is_finite() && order > 0.0) {
        return None;
    }
    let last = points.last()?;
    let n = last.n as f64 * (last.error / target).powf(1.0 / order);
    let seconds = last.seconds * n / last.n as f64;
    Some(cost(n, seconds, Reach::Extrapolated { order }))
}

/// `N` and the time at which the log–log segment from `a` (error above `target`) to `b` (at or
/// below) crosses `target`.
fn interpolate(a: SweepPoint, b: SweepPoint, target: f64) -> (f64, f64) {
    let (na, nb) = (a.n as f64, b.n as f64);
    let fraction = if a.error > b.error {
        (a.error / target).ln() / (a.error / b.error).ln()
    } else {
        1.0
    };
    let n = na * (nb / na).powf(fraction);
    let seconds = a.seconds * (b.seconds / a.seconds).powf(fraction);
    (n, seconds)
}

/// The cheapest (in wall time) of `lines` to reach `target`, measured or extrapolated.
pub fn cheapest<'a>(lines: impl IntoIterator<Item = &'a SweepLine>, target: f64) -> Option<Cost> {
    lines
        .into_iter()
        .filter_map(|line| cost_to_reach(line, target))
        .min_by(|a, b| a.seconds.total_cmp(&b.seconds))
}

/// The scene's advice, from its sweep: which line reaches max error `target` in the least
/// wall time among those that reached it (with its `N` and time, and the runner-up), or, when
/// none did, which reached the smallest error; then every line that failed somewhere, with the
/// library's error at its coarsest failing `N`. `why` says what makes the winner win (order,
/// structure), as the scene knows it.
pub fn advice(lines: &[SweepLine], target: f64, why: &str) -> String {
    let mut reached: Vec<Cost> = lines
        .iter()
        .filter_map(|line| cost_to_reach(line, target))
        .filter(|c| c.reach == Reach::Measured)
        .collect();
    reached.sort_by(|a, b| a.seconds.total_cmp(&b.seconds));
    let mut text = match reached.as_slice() {
        [] => {
            let best = lines
                .iter()
                .filter_map(|l| {
                    l.points
                        .iter()
                        .map(|p| (l, p))
                        .min_by(|a, b| a.1.error.total_cmp(&b.1.error))
                })
                .min_by(|a, b| a.1.error.total_cmp(&b.1.error));
            match best {
                Some((line, p)) => format!(
                    "Which scheme: no line reaches max error {target:.0e} on its sweep; the \
                     smallest error is {}'s, {:.2e} at N = {} in {:.2e} s. {why}",
                    line.label, p.error, p.n, p.seconds
                ),
                None => format!("Which scheme: no line solved. {why}"),
            }
        }
        [best, rest @ ..] => {
            let runner_up = rest.first().map_or(String::new(), |c| {
                // Two significant figures below 10×, where a whole number would read "1×".
                let ratio = c.seconds / best.seconds;
                let digits = if ratio < 10.0 { 1 } else { 0 };
                format!(
                    "; next is {} (N ≈ {:.0}, {:.2e} s, {ratio:.digits$}× slower)",
                    c.label, c.n, c.seconds
                )
            });
            let among = match reached.len() {
                1 => "the only line that reaches it".to_string(),
                k => format!("the least time of the {k} lines that reach it"),
            };
            format!(
                "Which scheme: {} — it reaches max error {target:.0e} with N ≈ {:.0} in {:.2e} s \
                 (read off the measured points), {among}{runner_up}. {why}",
                best.label, best.n, best.seconds
            )
        }
    };
    for line in lines {
        if let Some((n, error)) = line.failures.first() {
            text += &format!(
                " {} failed at {} of its N (first at N = {n}): {error}.",
                line.label,
                line.failures.len()
            );
        }
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(points: &[(usize, f64, f64)]) -> SweepLine {
        SweepLine {
            label: "x".to_string(),
            points: points
                .iter()
                .map(|&(n, seconds, error)| SweepPoint { n, seconds, error })
                .collect(),
            failures: Vec::new(),
            statuses: Vec::new(),
        }
    }

    /// Second order, `e = 100 / N²`, 1 µs per step: reaching 1e-6 takes `N = 10⁴`, 0.01 s,
    /// whether read between 8000 and 16000 or extrapolated from 2000.
    #[test]
    fn interpolation_and_extrapolation_follow_the_order() {
        let point = |n: usize| (n, n as f64 * 1e-6, 100.0 / (n * n) as f64);
        let reached =
            cost_to_reach(&line(&[point(4000), point(8000), point(16000)]), 1e-6).expect("reached");
        assert_eq!(reached.reach, Reach::Measured);
        assert!((reached.n - 1e4).abs() < 1e-6, "{reached:?}");
        assert!((reached.seconds - 1e-2).abs() < 1e-12, "{reached:?}");
        let extrapolated =
            cost_to_reach(&line(&[point(1000), point(2000)]), 1e-6).expect("extrapolated");
        assert!(
            matches!(extrapolated.reach, Reach::Extrapolated { order } if (order - 2.0).abs() < 1e-12)
        );
        assert!((extrapolated.n - 1e4).abs() < 1e-6, "{extrapolated:?}");
        assert!((extrapolated.seconds - 1e-2).abs() < 1e-12);
        // Already below the target at the coarsest N: that point's cost.
        let below = cost_to_reach(&line(&[point(1000)]), 1.0).expect("reached");
        assert_eq!((below.n, below.reach), (1000.0, Reach::Measured));
        // Not reached and no positive order: no cost.
        assert!(cost_to_reach(&line(&[(10, 1e-3, 1.0), (20, 2e-3, 2.0)]), 1e-6).is_none());
    }

    #[test]
    fn advice_names_the_fastest_line_that_reached_the_target_and_the_failures() {
        let mut slow = line(&[(100, 1.0, 1e-3), (200, 2.0, 1e-9)]);
        slow.label = "slow".to_string();
        let mut fast = line(&[(10, 0.01, 1e-4), (20, 0.02, 1e-10)]);
        fast.label = "fast".to_string();
        fast.failures = vec![(5, "Newton did not converge".to_string())];
        let text = advice(&[slow, fast], 1e-8, "Why.");
        assert!(text.starts_with("Which scheme: fast — "), "{text}");
        assert!(text.contains("next is slow"), "{text}");
        assert!(
            text.contains("fast failed at 1 of its N (first at N = 5): Newton"),
            "{text}"
        );
    }
}
