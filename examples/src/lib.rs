//! The tour: every scene of varembed solved by both schemes, compared, swept over `N`, and
//! written up as a report folder (markdown and SVG). `main.rs` is the command line; this
//! library is what the tour's tests drive.
//!
//! One scene per file under [`scenes`]; [`ivp_scene`] is the shared run of an initial value
//! scene; [`cost`] reads the cost of reaching an error off a sweep;
//! [`reference`](mod@reference) computes the independent reference solutions; [`plot`] and
//! [`report`] write the figures and the summary; [`console`] is what the tour prints. Errors,
//! wall times and observed orders are the library's ([`varembed::Comparison`],
//! [`varembed::Convergence`]): the tour solves each grid once for them, and times it again
//! ([`scene::Context::timed`]) so that each time it reports is a median.
#![deny(missing_docs)]

pub mod console;
pub mod cost;
pub mod ivp_scene;
pub mod output;
pub mod plot;
pub mod reference;
pub mod report;
pub mod scene;
pub mod scenes;
pub mod ticks;

use scene::{Context, SceneReport};

/// Runs every scene in order, handing each report to `done` as it finishes.
pub fn run_tour(
    cx: &Context,
    mut done: impl FnMut(&SceneReport),
) -> varembed::Result<Vec<SceneReport>> {
    let mut reports = Vec::new();
    for (name, run) in scenes::ALL {
        cx.progress.set_message(name);
        let report = run(cx)?;
        done(&report);
        reports.push(report);
    }
    Ok(reports)
}
