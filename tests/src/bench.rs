//! The criterion set-up every bench of the workspace uses: two timing budgets and one entry
//! point, so that all benches are configured, and their command lines read, the same way.
//!
//! A bench file ends with
//!
//! ```text
//! varembed_tests::bench_main!(varembed_tests::bench::kernels(); my_bench);
//! ```
//!
//! Command-line flags (`--warm-up-time`, `--measurement-time`, a filter) override the budget,
//! as in any criterion bench.

use std::time::Duration;

use crate::models::generated::DoublePendulum;

/// The criterion crate, so that [`bench_main!`](crate::bench_main) can name it from a bench
/// crate that does not depend on it directly.
pub use criterion;
use criterion::Criterion;

/// For calls of nanoseconds to microseconds (one derivative evaluation, one step): 0.5 s of
/// warm-up and 2 s of measurement give criterion millions of iterations.
pub fn kernels() -> Criterion {
    Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
}

/// For whole runs of milliseconds or more (10⁶ steps, a boundary value solve): 1 s of warm-up
/// and 4 s of measurement, so that even the slowest run is sampled a few dozen times.
pub fn runs() -> Criterion {
    Criterion::default()
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(4))
}

/// A bench's `main`: runs the given bench functions with the given [`Criterion`]
/// configuration (with the command line applied on top), then prints criterion's summary.
#[macro_export]
macro_rules! bench_main {
    ($config:expr; $($target:path),+ $(,)?) => {
        $crate::bench::criterion::criterion_group! {
            name = benches;
            config = $config;
            targets = $($target),+
        }
        $crate::bench::criterion::criterion_main!(benches);
    };
}

/// The double pendulum of the implicit-step benches: unequal arms, so that the derivatives are
/// not sums of exact small integers and agreement between two evaluations is a real check.
pub const DOUBLE_PENDULUM: DoublePendulum = DoublePendulum {
    m1: 1.2,
    m2: 0.7,
    l1: 1.1,
    l2: 0.8,
    g: 9.81,
};
/// Its initial angles and angular velocities: both arms raised past horizontal and thrown, the
/// chaotic regime.
pub const DOUBLE_PENDULUM_START: ([f64; 2], [f64; 2]) = ([2.0, 2.5], [1.0, -1.5]);
