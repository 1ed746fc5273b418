//! A const-generic solve whose dense `D × D` blocks need a stack segment the system will not
//! map is a typed error that says what to do, not a panic: checked in a child process whose
//! address space is limited (`ulimit -v`), so that the outcome does not depend on the
//! machine's memory or overcommit rule.

use super::through_problem::{SMALL, SmallRing, displaced, embeddings, on_stack};
use varembed::{DynProblem, Embedding, Error, Grid, Problem, Scheme, Vector, lagrangian};
use varembed_tests::models::dense::ConstGeneric;

/// Its const-generic segment (`256 D²` values, 8.6 GB) is twice the child's address space.
const WIDE: usize = 2048;

/// `WIDE` uncoupled oscillators.
#[lagrangian]
fn wide_wells(x: [f64; WIDE], v: [f64; WIDE]) -> f64 {
    let mut l = 0.0;
    for i in 0..WIDE {
        l += 0.5 * v[i] * v[i] - 0.5 * x[i] * x[i];
    }
    l
}

/// The child's address space: 4 GiB, in the KiB `ulimit -v` counts.
const ADDRESS_SPACE_KIB: u64 = 4 << 20;

/// Set in the child, which runs the checks; the parent only launches it.
const CHILD: &str = "VAREMBED_STACK_SEGMENT_CHILD";

#[test]
fn a_segment_the_system_will_not_map_is_a_typed_error() {
    if std::env::var_os(CHILD).is_some() {
        return checks_in_a_limited_address_space();
    }
    if !cfg!(target_os = "linux") {
        return;
    }
    let name = "stack_segments::a_segment_the_system_will_not_map_is_a_typed_error";
    let output = std::process::Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v {ADDRESS_SPACE_KIB} && exec \"$0\" --exact {name} --nocapture --test-threads 1"
        ))
        .arg(std::env::current_exe().unwrap())
        .env(CHILD, "1")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success() && stdout.contains("1 passed"),
        "{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
}

/// On a 2 MiB thread: the wide model on the const-generic path is refused with
/// [`Error::TooLarge`]; the same model through `DynProblem`, and a 64-site ring on the
/// const-generic path (an 8 MiB segment), run.
fn checks_in_a_limited_address_space() {
    let grid = Grid::new(0.0, 1.0, 10).unwrap();
    on_stack(2 << 20, || {
        let model = WideWells;
        let q0 = vec![0.5; WIDE];
        let v0 = vec![0.0; WIDE];
        let x0 = Vector::<WIDE>::from_column_slice(&q0);
        let refused = Problem::new(&ConstGeneric(model), grid, Embedding::midpoint()).solve_ivp(
            Scheme::Variational,
            x0,
            x0 * 0.0,
        );
        match refused {
            Err(Error::TooLarge { what }) => {
                for part in [
                    "Lagrangian<2048>",
                    "2048 × 2048",
                    "DynProblem",
                    "DynLagrangian",
                ] {
                    assert!(what.contains(part), "{what}");
                }
            }
            other => panic!("{:?}", other.map(|run| run.last()[0])),
        }
        // q = 0.5 cos t, through the run-time engine.
        let run = DynProblem::new(&model, grid, Embedding::midpoint())
            .solve_ivp(Scheme::Variational, &q0, &v0)
            .unwrap();
        assert!((run.node(grid.n())[0] - 0.5 * 1f64.cos()).abs() < 1e-2);
        // A segment that fits is granted.
        let ring = ConstGeneric(SmallRing { c: 4.0 });
        let (q0, v0) = displaced(SMALL);
        let (x0, u0) = (
            Vector::<SMALL>::from_column_slice(&q0),
            Vector::from_column_slice(&v0),
        );
        let embedding = embeddings()[4];
        let run = Problem::new(&ring, grid, embedding)
            .solve_ivp(Scheme::Variational, x0, u0)
            .unwrap();
        let reference = DynProblem::new(&ring.0, grid, embedding)
            .solve_ivp(Scheme::Variational, &q0, &v0)
            .unwrap();
        let last = Vector::<SMALL>::from_column_slice(reference.node(grid.n()));
        let gap = (run.last() - last).amax();
        assert!(gap < 1e-12, "{gap:e}");
    });
}
