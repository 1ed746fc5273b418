//! The scenes of the tour, one per file. Each writes its Lagrangian with `#[lagrangian]` and
//! models only what it needs.

pub mod damped;
pub mod double_pendulum;
pub mod duffing;
pub mod four_bar;
pub mod fput;
pub mod fractional;
pub mod harmonic;
pub mod kepler;
pub mod large_chain;
pub mod parametric;
pub mod pendulum;
pub mod spherical_pendulum;
pub mod stiff_fpu;

use crate::scene::{Context, SceneReport};

/// A scene's entry point.
pub type Run = fn(&Context) -> varembed::Result<SceneReport>;

/// Every scene, in the order of the report.
pub const ALL: [(&str, Run); 13] = [
    ("harmonic oscillator", harmonic::run),
    ("pendulum", pendulum::run),
    ("Kepler, e = 0.9", kepler::run),
    ("double pendulum", double_pendulum::run),
    ("parametric oscillator", parametric::run),
    ("q̈ + q̇ + q = 0", damped::run),
    ("spherical pendulum", spherical_pendulum::run),
    ("four-bar linkage", four_bar::run),
    ("driven Duffing", duffing::run),
    ("FPUT recurrence", fput::run),
    ("stiff FPU", stiff_fpu::run),
    ("large chain", large_chain::run),
    ("fractional BVP", fractional::run),
];
