//! The memory a run-time-dimension run needs beyond what its observer keeps: `O(d · b)`, the
//! band `b` of the step Jacobian, independent of the number of steps. Measured with dhat's
//! heap profiler (this test binary's global allocator) as the peak of live heap bytes during
//! the run.

use varembed::{DynProblem, Embedding, Grid, Scheme, Side};
use varembed_tests::models::generated::FputChain;

#[global_allocator]
static ALLOCATOR: dhat::Alloc = dhat::Alloc;

/// The peak of live heap bytes over a run of `steps` steps of the FPUT chain of `d` particles
/// by `scheme` (σ = −), whose observer keeps nothing; the model and the initial data are made
/// before the profiler starts.
fn peak_bytes(d: usize, steps: usize, scheme: Scheme) -> usize {
    let chain = FputChain {
        n: d,
        alpha: 0.25,
        beta: 0.0,
    };
    let q0: Vec<f64> = (0..d).map(|i| 0.1 * (i as f64 * 0.01).sin()).collect();
    let v0 = vec![0.0; d];
    let grid = Grid::new(0.0, 0.05 * steps as f64, steps).unwrap();
    let problem = DynProblem::new(&chain, grid, Embedding::finite_difference(Side::Backward));
    let profiler = dhat::Profiler::builder().testing().build();
    let run = problem.run_ivp(scheme, &q0, &v0, |_| {}).unwrap();
    let peak = dhat::HeapStats::get().max_bytes;
    drop(profiler);
    assert_eq!(run.band, 1);
    drop(run);
    peak
}

/// One test, so that one profiler runs at a time.
#[test]
fn a_run_needs_memory_linear_in_d_and_independent_of_the_number_of_steps() {
    for scheme in [Scheme::Direct, Scheme::Variational] {
        let small = peak_bytes(1024, 200, scheme);
        let large = peak_bytes(4096, 200, scheme);
        let long = peak_bytes(4096, 2000, scheme);
        println!(
            "{scheme:?}: peak {small} B at d = 1024, {large} B at d = 4096 ({:.0} B per \
             particle), {long} B at d = 4096 over 10× the steps",
            large as f64 / 4096.0
        );
        // Linear in d (the band is 1), and not growing with the run.
        let ratio = large as f64 / small as f64;
        assert!(
            (3.5..=4.5).contains(&ratio),
            "{scheme:?}: ×{ratio:.2} from d = 1024 to 4096"
        );
        assert_eq!(
            long, large,
            "{scheme:?}: the peak grew with the number of steps"
        );
        // About 25 doubles per particle (193 B direct, 201 B variational measured): the state,
        // the buffers, the Hessian and the band factors — never a d × d block (134 MB at
        // d = 4096).
        assert!(large <= 256 * 4096, "{scheme:?}: {large} B at d = 4096");
    }
}
