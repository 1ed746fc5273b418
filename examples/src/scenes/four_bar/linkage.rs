//! The four-bar linkage: the model in its three link angles under the loop constraint, its
//! initial data, and the reference in the crank angle.
//!
//! A crank of length 1 from the ground pivot `(0, 0)`, a coupler of length 2.2, a rocker of
//! length 1.6 to the ground pivot `(2, 0)`: uniform rods of unit mass per length under gravity
//! 9.81. The loop closes by two holonomic constraints (the coupler's far end on the rocker's).
//! The reference is the motion along the loop closed in closed form at each crank angle, on the
//! assembly branch of the initial data: `m(θ) θ̈ + ½ m'(θ) θ̇² + V'(θ) = 0`, with the reduced
//! mass `m = Jᵀ M J` and the potential `V` along the branch, `J = dq/dθ` and its derivative by
//! implicit differentiation of the loop, all written by hand and integrated by DOP853:
//! independent of the constrained solver and of the macro.

use crate::reference::ReferenceCurve;
use std::f64::consts::{PI, TAU};
use varembed::{Constraint, Holonomic, Vector, lagrangian, project_initial_data};

/// The linkage in its three link angles: each rod of length `l` and mass `l`, the crank and the
/// rocker turning about their ground pivots (`I = l³/3`), the coupler carried by the crank's
/// tip (the kinetic energy of its centre plus `l³/12` about it).
#[lagrangian]
pub fn linkage(x: [f64; 3], v: [f64; 3]) -> f64 {
    let (l1, l2, l3) = (1.0, 2.2, 1.6);
    let crank = l1 * l1 * l1 / 3.0 * v[0] * v[0] / 2.0;
    let tip_x = -l1 * x[0].sin() * v[0];
    let tip_y = l1 * x[0].cos() * v[0];
    let mid_x = tip_x - 0.5 * l2 * x[1].sin() * v[1];
    let mid_y = tip_y + 0.5 * l2 * x[1].cos() * v[1];
    let coupler = 0.5 * l2 * (mid_x * mid_x + mid_y * mid_y) + l2 * l2 * l2 / 24.0 * v[1] * v[1];
    let rocker = l3 * l3 * l3 / 3.0 * v[2] * v[2] / 2.0;
    let height = l1 * 0.5 * l1 * x[0].sin()
        + l2 * (l1 * x[0].sin() + 0.5 * l2 * x[1].sin())
        + l3 * 0.5 * l3 * x[2].sin();
    crank + coupler + rocker - 9.81 * height
}

/// The loop's horizontal closure: crank tip plus coupler ends where the rocker's far end is.
#[lagrangian]
pub fn loop_x(x: [f64; 3], _v: [f64; 3]) -> f64 {
    x[0].cos() + 2.2 * x[1].cos() - 1.6 * x[2].cos() - 2.0
}

/// The loop's vertical closure.
#[lagrangian]
pub fn loop_y(x: [f64; 3], _v: [f64; 3]) -> f64 {
    x[0].sin() + 2.2 * x[1].sin() - 1.6 * x[2].sin()
}

/// Both closures: `M = 2` constraints on the three angles.
pub type Closure = (Holonomic<LoopX>, Holonomic<LoopY>);

/// The loop constraint.
pub const CLOSURE: Closure = (Holonomic(LoopX), Holonomic(LoopY));

/// The lengths of the crank, coupler, rocker and ground, and gravity: the numbers of
/// [`linkage`] and the loop, for the reference (written by hand, not read off the macro).
pub const LENGTHS: [f64; 4] = [1.0, 2.2, 1.6, 2.0];
/// See [`LENGTHS`].
pub const GRAVITY: f64 = 9.81;

/// The initial guess: the crank horizontal towards the rocker, the coupler and rocker near
/// their angles on the loop there, the crank turning at `CRANK_RATE` (the velocity is
/// projected onto the loop's tangent, which slows the crank somewhat). The energy is well above
/// the potential's maximum on the loop, so the crank turns fully.
pub const GUESS: [f64; 3] = [0.0, 0.7, 1.2];
/// See [`GUESS`].
pub const CRANK_RATE: f64 = 12.0;

/// The initial data on the loop: [`GUESS`] and the crank rate projected by
/// [`project_initial_data`].
pub fn initial() -> varembed::Result<(Vector<3>, Vector<3>)> {
    let guess = Vector::<3>::from(GUESS);
    project_initial_data(&CLOSURE, guess, Vector::<3>::new(CRANK_RATE, 0.0, 0.0))
}

/// The loop closed in closed form at crank angle `theta`: the coupler–rocker joint is where the
/// circles about the crank's tip (radius 2.2) and the rocker's pivot (1.6) meet, on the side
/// `branch` (±1) of the line from the tip to the pivot. Angles of the coupler and rocker in
/// `(−π, π]`.
pub fn chart(theta: f64, branch: f64) -> Vector<3> {
    let [l1, l2, l3, ground] = LENGTHS;
    let (tip_x, tip_y) = (l1 * theta.cos(), l1 * theta.sin());
    let (dx, dy) = (ground - tip_x, -tip_y);
    let d = dx.hypot(dy);
    let along = (d * d + l2 * l2 - l3 * l3) / (2.0 * d);
    let across = branch * (l2 * l2 - along * along).sqrt();
    let joint_x = tip_x + (along * dx - across * dy) / d;
    let joint_y = tip_y + (along * dy + across * dx) / d;
    Vector::<3>::new(
        theta,
        (joint_y - tip_y).atan2(joint_x - tip_x),
        joint_y.atan2(joint_x - ground),
    )
}

/// The assembly branch of `q` (the side of the joint, as in [`chart`]).
pub fn branch(q: &Vector<3>) -> f64 {
    let [l1, _, _, ground] = LENGTHS;
    let (tip_x, tip_y) = (l1 * q[0].cos(), l1 * q[0].sin());
    let (dx, dy) = (ground - tip_x, -tip_y);
    (dx * q[1].sin() - dy * q[1].cos()).signum()
}

/// The reduced dynamics along the chart at crank angle `theta`: `(m, m', V')`, with
/// `m = Jᵀ M J` the reduced mass, `J = dq/dθ` the loop's tangent and `M` the linkage's mass
/// matrix, `V` its potential.
fn reduced(theta: f64, branch: f64) -> (f64, f64, f64) {
    let [l1, l2, l3, _] = LENGTHS;
    let q = chart(theta, branch);
    let (s, c) = (q.map(f64::sin), q.map(f64::cos));
    // `G J = 0` with `J = (1, j2, j3)`: the coupler and rocker columns of `G` against the crank's.
    let solve = |b0: f64, b1: f64| {
        let det = l2 * l3 * (s[1] * c[2] - s[2] * c[1]);
        (
            (-l3 * c[2] * b0 - l3 * s[2] * b1) / det,
            (-l2 * c[1] * b0 - l2 * s[1] * b1) / det,
        )
    };
    let (j2, j3) = solve(l1 * s[0], -l1 * c[0]);
    // `G J' = −(Σ_k ∂²g/∂q_k² J_k²)`: the loop's second derivatives are diagonal.
    let (dj2, dj3) = solve(
        l1 * c[0] + l2 * c[1] * j2 * j2 - l3 * c[2] * j3 * j3,
        l1 * s[0] + l2 * s[1] * j2 * j2 - l3 * s[2] * j3 * j3,
    );
    let (m11, m22, m33) = (
        l1.powi(3) / 3.0 + l2 * l1 * l1,
        l2.powi(3) / 3.0,
        l3.powi(3) / 3.0,
    );
    let m12 = 0.5 * l2 * l2 * l1 * (q[0] - q[1]).cos();
    let dm12 = -0.5 * l2 * l2 * l1 * (q[0] - q[1]).sin() * (1.0 - j2);
    let m = m11 + 2.0 * m12 * j2 + m22 * j2 * j2 + m33 * j3 * j3;
    let dm = 2.0 * (m12 * dj2 + m22 * j2 * dj2 + m33 * j3 * dj3) + 2.0 * dm12 * j2;
    // `V' = ∇V·J`.
    let dv = GRAVITY
        * ((0.5 * l1 * l1 + l2 * l1) * c[0]
            + 0.5 * l2 * l2 * c[1] * j2
            + 0.5 * l3 * l3 * c[2] * j3);
    (m, dm, dv)
}

/// `V(q)`: the rods' weight times the heights of their centres.
pub fn potential(q: &Vector<3>) -> f64 {
    let [l1, l2, l3, _] = LENGTHS;
    GRAVITY
        * ((0.5 * l1 * l1 + l2 * l1) * q[0].sin()
            + 0.5 * l2 * l2 * q[1].sin()
            + 0.5 * l3 * l3 * q[2].sin())
}

/// `½ vᵀ M v + V(q)`, written by hand from the rods (the exact energy of the initial data).
pub fn energy(q: &Vector<3>, v: &Vector<3>) -> f64 {
    let [l1, l2, l3, _] = LENGTHS;
    let m12 = 0.5 * l2 * l2 * l1 * (q[0] - q[1]).cos();
    let kinetic = 0.5 * (l1.powi(3) / 3.0 + l2 * l1 * l1) * v[0] * v[0]
        + m12 * v[0] * v[1]
        + 0.5 * l2.powi(3) / 3.0 * v[1] * v[1]
        + 0.5 * l3.powi(3) / 3.0 * v[2] * v[2];
    kinetic + potential(q)
}

/// The least and the greatest potential on the branch `branch`, over 3600 crank angles: the
/// crank turns fully when the energy is above the greatest.
pub fn potential_range(branch: f64) -> (f64, f64) {
    (0..3600)
        .map(|k| potential(&chart(TAU * k as f64 / 3600.0, branch)))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        })
}

/// DOP853 on the crank angle, from the crank angle and rate of `(q0, v0)`, on `interval`.
pub fn reference(q0: &Vector<3>, v0: &Vector<3>, interval: (f64, f64)) -> ReferenceCurve<1> {
    let side = branch(q0);
    let acceleration = move |q: &[f64], v: &[f64], _t: f64, a: &mut [f64]| {
        let (m, dm, dv) = reduced(q[0], side);
        a[0] = -(0.5 * dm * v[0] * v[0] + dv) / m;
    };
    ReferenceCurve::dop853(
        &acceleration,
        interval,
        Vector::<1>::new(q0[0]),
        Vector::<1>::new(v0[0]),
        20_000,
    )
}

/// `a − b` in `(−π, π]`: the chart's angles are wrapped, the runs' are continuous.
pub fn angle_difference(a: f64, b: f64) -> f64 {
    PI - (PI - (a - b)).rem_euclid(TAU)
}

/// `max_i |g_i(q)|`, the loop's opening at `q`.
pub fn opening(q: &Vector<3>) -> f64 {
    CLOSURE.value(q).amax()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The macro's Lagrangian, written rod by rod, is `½ vᵀ M v − V` with the mass matrix and
    /// potential the reference is written with, at generated states.
    #[test]
    fn the_model_is_the_reference_s_mass_matrix_and_potential() {
        use varembed::Lagrangian;
        for k in 0..20 {
            let c = k as f64;
            let q = Vector::<3>::new(0.3 * c, 1.0 - 0.2 * c, 0.7 * c.sin());
            let v = Vector::<3>::new(c.cos(), 0.5 - 0.1 * c, 2.0 * (0.3 * c).sin());
            let lagrangian = Linkage.value(&q, &v, 0.0);
            let expected = energy(&q, &v) - 2.0 * potential(&q);
            assert!((lagrangian - expected).abs() <= 1e-12 * energy(&q, &v).abs().max(1.0));
        }
    }

    /// The chart closes the loop, passes through the projected initial data, and the reduced
    /// dynamics conserve `½ m θ̇² + V`, the linkage's energy of the initial data: with a wrong
    /// tangent `J`, `m'` or `V'` the reference would not.
    #[test]
    fn the_reference_closes_the_loop_and_conserves_the_energy() {
        let (q0, v0) = initial().expect("the guess projects onto the loop");
        let side = branch(&q0);
        assert!((chart(q0[0], side) - q0).amax() <= 1e-12, "{q0:?}");
        for k in 0..36 {
            assert!(opening(&chart(TAU * k as f64 / 36.0, side)) <= 1e-14);
        }
        let exact = energy(&q0, &v0);
        let curve = reference(&q0, &v0, (0.0, 10.0));
        for k in 0..=100 {
            let (theta, rate) = curve.at(0.1 * k as f64);
            let (m, _, _) = reduced(theta[0], side);
            let e = 0.5 * m * rate[0] * rate[0] + potential(&chart(theta[0], side));
            assert!(
                (e - exact).abs() <= 1e-9 * exact,
                "t = {}: {e} vs {exact}",
                0.1 * k as f64
            );
        }
    }
}
