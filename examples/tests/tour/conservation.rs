//! Conservation over long runs: the pendulum's energy (bounded for the variational scheme, drifting
//! down for the direct one) and Kepler's discrete angular momentum.

use varembed::Scheme;
use varembed_examples::scenes::{kepler, pendulum};

/// Pendulum, 10⁵ steps of `h = 0.01`: the variational energy error does not drift (its max over
/// the second half is at most 1.5× that over the first), while the direct σ = − energy drifts
/// down by more than the variational run's whole deviation.
#[test]
fn pendulum_energy_variational_bounded_direct_drifts_down() {
    let run = pendulum::EnergyRun::new(100_000).expect("both runs complete");
    assert_eq!(run.variational.len(), 100_000);
    let (first, second) = run.variational_halves();
    assert!(
        second <= 1.5 * first,
        "variational energy error grows: {first:e} then {second:e}"
    );
    let drift = run.direct_drift();
    let deviation = run.variational_deviation();
    assert!(
        drift < -deviation,
        "direct drift {drift:e} vs variational deviation {deviation:e}"
    );
    // The oracle for the sign: the exact energy is −cos 1; the direct run loses energy toward
    // the bottom of the well, E ≥ −1, never below.
    assert!(
        run.direct
            .iter()
            .all(|(_, e)| *e >= -1.0 + 1f64.cos() - 1e-9)
    );
}

/// Kepler at e = 0.9: the discrete angular momentum `Q_k × Q_{k+1} / h` of the variational run
/// is conserved to 10⁻¹² relative at 1000 and 2000 steps per orbit; beyond, round-off adds up
/// as a random walk (`≲ ε N^{3/2}`), still ≥ 10⁸ times below the direct run's spread, which is
/// of order one wherever the direct run completes.
#[test]
fn kepler_angular_momentum_variational_conserved_direct_not() {
    for steps in [1000, 2000] {
        let j = kepler::angular_momenta(Scheme::Variational, 1.0, steps).expect("runs");
        let spread = kepler::relative_spread(&j);
        assert!(
            spread <= 1e-12,
            "N = {steps}: variational spread {spread:e}"
        );
    }
    for steps in [16_000, 32_000] {
        let direct = kepler::relative_spread(
            &kepler::angular_momenta(Scheme::Direct, 1.0, steps).expect("the direct run passes"),
        );
        let variational = kepler::relative_spread(
            &kepler::angular_momenta(Scheme::Variational, 1.0, steps).expect("runs"),
        );
        let round_off = f64::EPSILON * (steps as f64).powf(1.5);
        assert!(direct > 1e-3, "N = {steps}: direct spread only {direct:e}");
        assert!(
            variational <= round_off,
            "N = {steps}: variational spread {variational:e} above ε N^1.5 = {round_off:e}"
        );
        assert!(variational * 1e8 < direct);
    }
}
