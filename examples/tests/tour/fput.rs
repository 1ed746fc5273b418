//! The physics of the two FPU scenes, each against an oracle: the FPUT recurrence (energy
//! leaves mode 1 and comes back near the time Fermi, Pasta, Ulam and Tsingou saw), the
//! normal-mode transform and mode energies against the chain written bond by bond, and the
//! stiff FPU problem's oscillatory energy `I` (an adiabatic invariant, HLW §I.5.1) kept by the
//! variational scheme and lost by the direct one; both models' energies against their
//! Hamiltonians written out by hand.

use varembed::{Lagrangian, Scheme, Vector};
use varembed_examples::scenes::fput::{self, LongRun, N, NormalModes, Recurrence};
use varembed_examples::scenes::stiff_fpu::{self, DIM};
use varembed_tests::rng::Rng;

fn close(what: &str, a: f64, b: f64, tolerance: f64) {
    assert!(
        (a - b).abs() <= tolerance * (1.0 + b.abs()),
        "{what}: {a} against {b}"
    );
}

/// The chain's `H` written bond by bond with the walls `x_0 = x_{N+1} = 0`.
fn fput_hamiltonian(x: &Vector<N>, v: &Vector<N>) -> f64 {
    let at = |i: usize| if i == 0 || i == N + 1 { 0.0 } else { x[i - 1] };
    let kinetic: f64 = v.iter().map(|v| 0.5 * v * v).sum();
    let bonds: f64 = (0..=N)
        .map(|i| {
            let d = at(i + 1) - at(i);
            0.5 * d * d + fput::ALPHA / 3.0 * d * d * d
        })
        .sum();
    kinetic + bonds
}

/// The recurrence at `h = 0.1`, as measured when the scene was written: `E_1` falls to 9.4 %
/// of its start near t = 4300 and returns to 98.0 % at t = 10195 (154 periods of mode 1). The
/// thresholds leave room around those numbers but
/// would fail for a chain that thermalises (no return) or one that never leaves mode 1.
#[test]
fn energy_leaves_mode_one_and_returns_near_the_recurrence_time() {
    let modes = NormalModes::new();
    let run = LongRun::new(Scheme::Variational, 11_000.0, fput::LONG_H, &modes)
        .expect("Störmer–Verlet runs at h = 0.1");
    let r = Recurrence::of(&run).expect("a run of many steps");
    // E_1(0) = ½ω_1² a_1², a_1 = A √((N+1)/2) for x_i = A sin(πi/(N+1)): the half-step value
    // is within O(h²) of it.
    let a1 = fput::AMPLITUDE * ((N + 1) as f64 / 2.0).sqrt();
    close(
        "E_1(0)",
        r.initial,
        0.5 * (fput::frequency(1) * a1).powi(2),
        1e-4,
    );
    assert!(r.low.1 < 0.2 * r.initial, "E_1 never left mode 1: {r:?}");
    assert!(r.back.1 > 0.95 * r.initial, "E_1 did not return: {r:?}");
    let periods = r.back.0 / fput::first_period();
    assert!(
        (145.0..165.0).contains(&periods),
        "{periods} periods: {r:?}"
    );
    // Total energy: bounded to a small relative band (measured 1.4e-4).
    assert!(run.energy_spread() < 1e-3, "{}", run.energy_spread());
    // While E_1 is low the energy is in the other modes: at the minimum, modes 2..=N hold
    // the rest of the harmonic energy.
    let at = run
        .times
        .iter()
        .position(|t| *t >= r.low.0)
        .expect("in the run");
    let rest: f64 = run.modes[at].iter().skip(1).sum();
    assert!(rest > 0.7 * r.initial, "{rest}");
}

/// The direct Gauss-FDE− scheme at the same step loses the energy the variational one keeps:
/// after t = 300 it has left the variational band by far.
#[test]
fn the_direct_scheme_dissipates_the_chains_energy() {
    let modes = NormalModes::new();
    let run = LongRun::new(Scheme::Direct, 300.0, fput::LONG_H, &modes).expect("implicit steps");
    let (e0, last) = (run.energy[0].1, run.energy.last().expect("nodes").1);
    assert!(last < 0.9 * e0, "{last} of {e0}");
    assert!(last > 0.0);
    let e1 = run.mode(1);
    assert!(e1.last().expect("steps").1 < 0.9 * e1[0].1);
}

/// The normal-mode transform is orthogonal and its own inverse (`Σ a_k² = Σ x_i²`,
/// `S S x = x`), its vectors are the eigenvectors of the chain's stiffness matrix with
/// eigenvalues `ω_k²` (checked bond by bond), and the half-step mode energies add up to the
/// harmonic part of the chain written bond by bond, `½|ΔQ/h|² + ½ Σ_bonds d_i d_i'`.
#[test]
fn normal_modes_against_the_chain_written_bond_by_bond() {
    let modes = NormalModes::new();
    let mut rng = Rng(0xF0F7);
    let bonds = |x: &Vector<N>| -> Vec<f64> {
        let at = |i: usize| if i == 0 || i == N + 1 { 0.0 } else { x[i - 1] };
        (0..=N).map(|i| at(i + 1) - at(i)).collect()
    };
    for _ in 0..20 {
        let x = rng.vector::<N>(1.0);
        let a = modes.amplitudes(&x);
        close("Σa² = Σx²", a.norm_squared(), x.norm_squared(), 1e-12);
        assert!((modes.positions(&a) - x).amax() < 1e-12);
        let next = rng.vector::<N>(1.0);
        let h = rng.uniform(0.05, 0.5);
        let total: f64 = modes.half_step_energies(&x, &next, h).iter().sum();
        let (d, e) = (bonds(&x), bonds(&next));
        let harmonic = 0.5 * ((next - x) / h).norm_squared()
            + 0.5 * d.iter().zip(&e).map(|(d, e)| d * e).sum::<f64>();
        close("Σ E_k", total, harmonic, 1e-12);
    }
    for k in 1..=N {
        let mut unit = Vector::<N>::zeros();
        unit[k - 1] = 1.0;
        let mode = modes.positions(&unit);
        // (K x)_i = 2x_i − x_{i−1} − x_{i+1}, walls at 0.
        let at = |i: usize| {
            if i == 0 || i == N + 1 {
                0.0
            } else {
                mode[i - 1]
            }
        };
        let w2 = fput::frequency(k).powi(2);
        for i in 1..=N {
            let kx = 2.0 * at(i) - at(i - 1) - at(i + 1);
            close(&format!("K S_{k} at {i}"), kx, w2 * at(i), 1e-12);
        }
    }
}

/// The chain's energy from the macro's `Lagrangian::energy` is `H` written bond by bond, and
/// the hand-written acceleration of the DOP853 reference is the macro's `∂L/∂x`.
#[test]
fn the_chains_energy_and_force_match_the_hand_written_ones() {
    let mut rng = Rng(0xF0F8);
    for _ in 0..20 {
        let (x, v) = (rng.vector::<N>(1.5), rng.vector::<N>(1.0));
        let e = fput::MODEL.energy(&x, &v, 0.0);
        close("E", e, fput_hamiltonian(&x, &v), 1e-12);
        let (f, _) = fput::MODEL.gradient(&x, &v, 0.0);
        let mut a = [0.0; N];
        fput::acceleration(x.as_slice(), v.as_slice(), 0.0, &mut a);
        for i in 0..N {
            close("force", a[i], f[i], 1e-12);
        }
    }
}

/// HLW's stiff FPU: the model's `Lagrangian::energy` is their Hamiltonian at random states,
/// the hand-written acceleration is the macro's force, and their initial data have `I = 1`.
#[test]
fn the_stiff_models_energy_is_the_hamiltonian_of_hlw() {
    let mut rng = Rng(0x57FF);
    for _ in 0..50 {
        let (q, p) = (rng.vector::<DIM>(0.8), rng.vector::<DIM>(2.0));
        let e = stiff_fpu::MODEL.energy(&q, &p, 0.0);
        let (qa, pa) = (std::array::from_fn(|i| q[i]), std::array::from_fn(|i| p[i]));
        close("E", e, stiff_fpu::hamiltonian(&qa, &pa), 1e-12);
        let (f, _) = stiff_fpu::MODEL.gradient(&q, &p, 0.0);
        let mut a = [0.0; DIM];
        stiff_fpu::acceleration(q.as_slice(), p.as_slice(), 0.0, &mut a);
        for i in 0..DIM {
            close("force", a[i], f[i], 1e-12);
        }
    }
    let (q0, v0) = stiff_fpu::initial_data();
    let i0: f64 = stiff_fpu::oscillatory(&q0, &v0).iter().sum();
    close("I(0)", i0, 1.0, 1e-15);
}

/// `I` over `t ∈ [0, 200]` at `hω = 0.1`: the variational scheme keeps it within 0.1 of
/// `I(0) = 1` (measured 0.068; HLW's figure shows oscillations of a few times `1/ω = 0.02`)
/// while the energy moves from the first stiff spring to the third (measured: `I_3` above
/// 0.9 near t = 150); the direct scheme's `I` leaves that band within the first time unit.
#[test]
fn the_oscillatory_energy_is_an_adiabatic_invariant_of_the_variational_scheme_only() {
    let h = stiff_fpu::LONG_H;
    let variational = stiff_fpu::LongRun::new(Scheme::Variational, 200.0, h).expect("runs");
    assert!(variational.deviation() < 0.1, "{}", variational.deviation());
    let third = variational.spring(3);
    let peak = third.iter().fold(0.0f64, |m, (_, i)| m.max(*i));
    assert!(peak > 0.9, "I_3 peaks at {peak}");
    let first = variational.spring(1);
    assert!(first.last().expect("steps").1 < 0.2);
    // Over t ≤ 1 the direct I leaves the band (the run ends at t = 1) and ends below 0.1.
    let direct = stiff_fpu::LongRun::new(Scheme::Direct, 1.0, h).expect("runs");
    let total = direct.total();
    assert!(
        total.iter().any(|(_, i)| (i - 1.0).abs() > 0.1),
        "the direct I stays in the band"
    );
    assert!(total.last().expect("steps").1 < 0.1);
}
