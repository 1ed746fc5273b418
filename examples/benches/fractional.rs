//! The fractional BVP solve time against N, fast path vs dense LU, in one run, and the fast
//! path's time and peak resident memory per solve at N = 10⁵, 10⁶ (and 10⁷).
//!
//! Pendulum `L = ½v² + cos x`, Gauss-GLE− with α = 0.7 on `[0, 1]`, `Q_0 = 0`, `Q_N = 1`.
//! Five solves side by side: dense LU, the fast path at the default Newton tolerance (1e-12
//! relative), the corrected Gauss-GLE−'s direct scheme on both (`corrected_dense`,
//! `corrected_fast`: GMRES), and the fast path run to round-off (`fast_floor`: tolerance 1e-16, so Newton stops
//! when the residual stops falling; `tests/tests/classical/residual_floor.rs` shows that this is the residual of
//! the exact discrete solution rounded to doubles). Before timing each size, the solve is run
//! once and its Newton iterations and reached residual are printed (see `report`).
//!
//! **Scaling table.** Peak resident memory is a property of a whole process, so each entry of
//! the scaling table is measured by a fresh process that runs one solve and nothing else: the
//! bench starts its own binary with `VAREMBED_BENCH_PROBE=N` (see [`probe`]), which prints the
//! solve's wall time, the time `Problem::new` took before it (the discretisation: for the
//! corrected scheme, its starting columns), Newton iterations, `VmHWM` and a few nodes of the
//! solution. With
//! `VAREMBED_BENCH_BASELINE=<another build of this bench>` the same probes run that binary too,
//! alternately with this one, so that two builds of the library are compared in one run under
//! the same load. Each probe runs [`PROBE_REPEATS`] times; the table gives the fastest time.
//! The corrected Gauss-GLE− (its direct scheme, on the fast path) is probed too
//! (`VAREMBED_BENCH_PROBE_CORRECTED=1`), by this build, and by the baseline when
//! `VAREMBED_BENCH_BASELINE_CORRECTED` is set (a build from before that probe ignores the
//! variable and solves the paper's scheme). The criterion group also times `Problem::new` of the
//! corrected scheme at `N = 10⁵` (`corrected_build`).
//!
//! `cargo bench -p varembed-examples --bench fractional -- --warm-up-time 1 --measurement-time 3`;
//! set `VAREMBED_BENCH_MILLION=1` to include N = 10⁶ in the criterion timings, and
//! `VAREMBED_BENCH_TEN_MILLION=1` to add N = 10⁷ to the scaling table (probes only: criterion's
//! ten samples would take minutes).

use std::hint::black_box;
use std::process::Command;
use std::time::Instant;

use criterion::{BenchmarkId, Criterion};
use varembed::__private::fft_operator::FftOperator;
use varembed::__private::operator::Operator;
use varembed::{Embedding, FractionalSolver, Grid, NewtonOptions, Problem, Scheme, Side};
use varembed_tests::models::hand::Pendulum;

/// One of the timed solves: its name, its linear algebra, its Newton tolerance, and whether
/// it is the corrected Gauss-GLE− (its direct scheme) rather than the paper's (variational).
#[derive(Clone, Copy)]
struct Variant {
    name: &'static str,
    solver: FractionalSolver,
    tolerance: f64,
    corrected: bool,
}

impl Variant {
    fn scheme(&self) -> Scheme {
        if self.corrected {
            Scheme::Direct
        } else {
            Scheme::Variational
        }
    }
}

const DEFAULT_TOLERANCE: f64 = 1e-12;

/// Solves per probe size and binary in the scaling table.
const PROBE_REPEATS: usize = 3;

fn problem(n: usize, variant: Variant) -> Problem<'static, Pendulum, 1> {
    let grid = Grid::new(0.0, 1.0, n).expect("valid grid");
    let embedding = if variant.corrected {
        Embedding::corrected_grunwald_letnikov(Side::Backward, 0.7)
    } else {
        Embedding::grunwald_letnikov(Side::Backward, 0.7)
    };
    let embedding = embedding.expect("valid α");
    Problem::new(&Pendulum { g: 1.0, l: 1.0 }, grid, embedding)
        .with_fractional_solver(variant.solver)
        .with_newton(NewtonOptions {
            tolerance: variant.tolerance,
            ..NewtonOptions::default()
        })
}

/// Solves once and prints the Newton iterations and the reached residual
/// `r_j = f_j + (Δᵀ p)_j` (σ = −, so `D = Δ^α_−`), computed independently of the solver by
/// [`FftOperator`] (V through the curve's differences, as accurate as the dense loops): as
/// `max|r|`, as the action gradient `h max|r| = max|∂S_h/∂Q_j|`, and relative to the Newton
/// scale `1 + max|f| + h^{−α} max|p|`.
fn report(n: usize, variant: Variant) {
    let p = problem(n, variant);
    let sol = p
        .solve_bvp(Scheme::Variational, 0.0, 1.0)
        .expect("the pendulum BVP converges");
    let op = Operator::grunwald_letnikov(Side::Backward, 0.7, p.grid()).expect("valid α");
    let mut fast = FftOperator::new(&op);
    let v = fast.apply_by_differences(&sol.q).expect("N + 1 nodes");
    let dt_p = fast.apply_transpose(&v).expect("N rows"); // p = ∂L/∂v = v
    let r_max = (1..n).fold(0.0f64, |m, j| {
        m.max((-sol.q[j][0].sin() + dt_p[j][0]).abs())
    });
    let p_max = v.iter().fold(0.0f64, |m, x| m.max(x.amax()));
    let h = p.grid().h();
    let scale = 1.0
        + 1.0f64.min(sol.q.iter().fold(0.0f64, |m, x| m.max(x[0].sin().abs())))
        + h.powf(-0.7) * p_max;
    eprintln!(
        "{} N = {n}: {} Newton iterations, max|r| = {r_max:.2e}, h·max|r| = {:.2e}, \
         max|r|/scale = {:.2e}",
        variant.name,
        sol.newton_iterations,
        h * r_max,
        r_max / scale
    );
}

/// The probe process: one fast solve at the default tolerance (or at
/// `VAREMBED_BENCH_PROBE_TOLERANCE`, 1e-16 for a reference at the round-off floor) on `n`
/// steps, then one line on stdout, `probe n=… seconds=… newton=… peak_kib=… q=…` (`q`: the
/// nodes at t = ¼, ½, ¾, to all digits, for comparing two builds), and exit.
fn probe(n: usize) -> ! {
    let tolerance = std::env::var("VAREMBED_BENCH_PROBE_TOLERANCE")
        .ok()
        .map(|t| {
            t.parse()
                .expect("VAREMBED_BENCH_PROBE_TOLERANCE is a number")
        })
        .unwrap_or(DEFAULT_TOLERANCE);
    let fast = Variant {
        name: "fast",
        solver: FractionalSolver::Fast,
        tolerance,
        corrected: std::env::var_os("VAREMBED_BENCH_PROBE_CORRECTED").is_some(),
    };
    let start = Instant::now();
    let p = problem(n, fast);
    let build_seconds = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let sol = p
        .solve_bvp(fast.scheme(), 0.0, 1.0)
        .expect("the pendulum BVP converges");
    let seconds = start.elapsed().as_secs_f64();
    let status = std::fs::read_to_string("/proc/self/status").expect("/proc/self/status");
    let peak_kib = status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .map(|v| v.trim().trim_end_matches("kB").trim().to_string())
        .expect("VmHWM in /proc/self/status");
    let nodes: Vec<String> = [n / 4, n / 2, 3 * n / 4]
        .iter()
        .map(|&k| format!("{:e}", sol.q[k][0]))
        .collect();
    println!(
        "probe n={n} seconds={seconds:.4} build_seconds={build_seconds:.4} newton={} \
         peak_kib={peak_kib} q={}",
        sol.newton_iterations,
        nodes.join(",")
    );
    std::process::exit(0);
}

/// What one probe process printed.
struct ProbeResult {
    seconds: f64,
    /// The time `Problem::new` took (the discretisation: for the corrected scheme, its
    /// starting columns); `None` from a build whose probe did not print it.
    build_seconds: Option<f64>,
    newton: String,
    peak_kib: f64,
    q: String,
}

/// Runs `binary` as a probe of `n` steps (of the corrected scheme if `corrected`) and reads
/// its line.
fn run_probe(binary: &std::path::Path, n: usize, corrected: bool) -> ProbeResult {
    let mut command = Command::new(binary);
    command.env("VAREMBED_BENCH_PROBE", n.to_string());
    if corrected {
        command.env("VAREMBED_BENCH_PROBE_CORRECTED", "1");
    }
    let output = command.output().expect("the probe process starts");
    let stdout = String::from_utf8_lossy(&output.stdout);
    let line = stdout
        .lines()
        .find(|l| l.starts_with("probe "))
        .unwrap_or_else(|| panic!("no probe line from {}: {stdout}", binary.display()));
    let optional = |name: &str| {
        line.split_whitespace()
            .find_map(|f| f.strip_prefix(name).and_then(|f| f.strip_prefix('=')))
            .map(str::to_string)
    };
    let field = |name: &str| optional(name).unwrap_or_else(|| panic!("no {name} in {line}"));
    ProbeResult {
        seconds: field("seconds").parse().expect("seconds"),
        build_seconds: optional("build_seconds").map(|s| s.parse().expect("build_seconds")),
        newton: field("newton"),
        peak_kib: field("peak_kib").parse().expect("peak_kib"),
        q: field("q"),
    }
}

/// The scaling table: for each size, the fastest of [`PROBE_REPEATS`] probe solves and the
/// peak RSS, for this build and (when given) the baseline build, alternately.
fn scaling_table() {
    let mut sizes = vec![100_000, 1_000_000];
    if std::env::var_os("VAREMBED_BENCH_TEN_MILLION").is_some() {
        sizes.push(10_000_000);
    }
    let this = std::env::current_exe().expect("the bench binary's path");
    let mut builds = vec![("this build", this.clone(), false)];
    if let Some(baseline) = std::env::var_os("VAREMBED_BENCH_BASELINE") {
        builds.push(("baseline", baseline.into(), false));
    }
    builds.push(("corrected", this, true));
    // A baseline that knows the corrected probe (built after it existed: an older one would
    // solve the paper's scheme under this name) is probed in the corrected scheme too.
    if let (Some(baseline), Some(_)) = (
        std::env::var_os("VAREMBED_BENCH_BASELINE"),
        std::env::var_os("VAREMBED_BENCH_BASELINE_CORRECTED"),
    ) {
        builds.push(("baseline corrected", baseline.into(), true));
    }
    eprintln!("scaling table (fastest of {PROBE_REPEATS} solves, one process per solve):");
    for n in sizes {
        let mut results: Vec<Vec<ProbeResult>> = builds.iter().map(|_| Vec::new()).collect();
        for _ in 0..PROBE_REPEATS {
            for (build, results) in builds.iter().zip(results.iter_mut()) {
                results.push(run_probe(&build.1, n, build.2));
            }
        }
        for ((name, _, _), results) in builds.iter().zip(&results) {
            let fastest = results
                .iter()
                .map(|r| r.seconds)
                .fold(f64::INFINITY, f64::min);
            let peak = results.iter().map(|r| r.peak_kib).fold(0.0, f64::max);
            let times: Vec<String> = results
                .iter()
                .map(|r| format!("{:.3}", r.seconds))
                .collect();
            let build = results
                .iter()
                .filter_map(|r| r.build_seconds)
                .fold(f64::INFINITY, f64::min);
            let build = if build.is_finite() {
                format!("{build:.3} s")
            } else {
                "not printed".to_string()
            };
            eprintln!(
                "  {name:>18} N = {n:>8}: {fastest:.3} s (runs {} s; Problem::new {build}), \
                 peak RSS {:.0} MiB ({:.0} bytes/node), Newton {}, Q(¼, ½, ¾) = {}",
                times.join(", "),
                peak / 1024.0,
                peak * 1024.0 / n as f64,
                results[0].newton,
                results[0].q
            );
        }
    }
}

fn bench(c: &mut Criterion) {
    if let Some(n) = std::env::var_os("VAREMBED_BENCH_PROBE") {
        let n = n.to_str().and_then(|n| n.parse().ok());
        probe(n.expect("VAREMBED_BENCH_PROBE is a number of steps"));
    }
    scaling_table();
    let mut group = c.benchmark_group("fractional_bvp_pendulum_alpha0.7");
    group.sample_size(10);
    let mut fast_sizes = vec![1_000, 10_000, 100_000];
    if std::env::var_os("VAREMBED_BENCH_MILLION").is_some() {
        fast_sizes.push(1_000_000);
    }
    let dense = Variant {
        name: "dense",
        solver: FractionalSolver::Dense,
        tolerance: DEFAULT_TOLERANCE,
        corrected: false,
    };
    let fast = Variant {
        name: "fast",
        solver: FractionalSolver::Fast,
        tolerance: DEFAULT_TOLERANCE,
        corrected: false,
    };
    let fast_floor = Variant {
        name: "fast_floor",
        tolerance: 1e-16,
        ..fast
    };
    let corrected_fast = Variant {
        name: "corrected_fast",
        corrected: true,
        ..fast
    };
    let corrected_dense = Variant {
        name: "corrected_dense",
        corrected: true,
        ..dense
    };
    for (variant, sizes) in [
        (dense, vec![250, 500, 1_000]),
        (corrected_dense, vec![1_000]),
        (fast, fast_sizes.clone()),
        (corrected_fast, fast_sizes.clone()),
        (fast_floor, fast_sizes),
    ] {
        for n in sizes {
            let p = problem(n, variant);
            if variant.corrected {
                let solution = p.solve_bvp(variant.scheme(), 0.0, 1.0).expect("converges");
                eprintln!(
                    "{} N = {n}: {} Newton iterations",
                    variant.name, solution.newton_iterations
                );
            } else {
                report(n, variant);
            }
            group.bench_with_input(BenchmarkId::new(variant.name, n), &n, |b, _| {
                b.iter(|| black_box(p.solve_bvp(variant.scheme(), 0.0, 1.0).expect("converges")))
            });
        }
    }
    // Building a corrected discretisation computes its starting columns (O(N log N)).
    let n = 100_000;
    group.bench_with_input(BenchmarkId::new("corrected_build", n), &n, |b, &n| {
        b.iter(|| black_box(problem(n, corrected_fast)))
    });
    group.finish();
}

varembed_tests::bench_main!(varembed_tests::bench::runs(); bench);
