//! The run-time-dimension solvers give `c L` the nodes of `L` (`c > 0`), as the const-generic
//! ones do (the `classical` binary's `scale_invariance`): 300 random cases of a factor
//! `c = 10^u`, `u` uniform in `[−12, 12]` (a quarter `c = 2^k`, whose nodes must be equal bit
//! for bit, with the same Newton iterations, except the chain's closed-form steps, see
//! [`case`]), a model (pendulum, the 2-D coupled model, the
//! Caldirola–Kanai oscillator, all through a run-time-dimension adapter, and the FPUT chain)
//! and a `DynProblem` solver (initial and boundary value problems of every classical
//! embedding and scheme the run-time path offers).

use std::collections::BTreeMap;

use varembed::{
    BvpSolver, Dependence, DynLagrangian, DynProblem, DynSolution, Embedding, Grid,
    HessianDependence, Lagrangian, Scheme, Side, SparseHessian, Vector,
};
use varembed_tests::models::chain::{FputChain, displacement};
use varembed_tests::models::hand::{CaldirolaKanai, Coupled, Pendulum};
use varembed_tests::models::scaled::Scaled;
use varembed_tests::rng::Rng;

/// A const-generic model as a run-time-dimension one: every entry of the three blocks, the
/// dependence forwarded.
struct AsDyn<L, const D: usize>(L);

impl<L: Lagrangian<D>, const D: usize> DynLagrangian for AsDyn<L, D> {
    fn dimension(&self) -> usize {
        D
    }
    fn value(&self, x: &[f64], v: &[f64], t: f64) -> f64 {
        let (x, v) = (
            Vector::<D>::from_column_slice(x),
            Vector::<D>::from_column_slice(v),
        );
        self.0.value(&x, &v, t)
    }
    fn force(&self, x: &[f64], v: &[f64], t: f64, f: &mut [f64]) {
        let (x, v) = (
            Vector::<D>::from_column_slice(x),
            Vector::<D>::from_column_slice(v),
        );
        f.copy_from_slice(self.0.gradient(&x, &v, t).0.as_slice());
    }
    fn momentum(&self, x: &[f64], v: &[f64], t: f64, p: &mut [f64]) {
        let (x, v) = (
            Vector::<D>::from_column_slice(x),
            Vector::<D>::from_column_slice(v),
        );
        p.copy_from_slice(self.0.gradient(&x, &v, t).1.as_slice());
    }
    fn hessian(&self, x: &[f64], v: &[f64], t: f64, out: &mut SparseHessian) {
        let (x, v) = (
            Vector::<D>::from_column_slice(x),
            Vector::<D>::from_column_slice(v),
        );
        let hs = self.0.hessian(&x, &v, t);
        for i in 0..D {
            for j in 0..D {
                out.xx.add(i, j, hs.xx[(i, j)]);
                out.xv.add(i, j, hs.xv[(i, j)]);
                out.vv.add(i, j, hs.vv[(i, j)]);
            }
        }
    }
    fn hessian_dependence(&self) -> HessianDependence {
        self.0.hessian_dependence()
    }
    fn dependence(&self) -> Dependence {
        self.0.dependence()
    }
}

/// What a case solves: an initial or a boundary value problem of the scheme under the
/// embedding.
#[derive(Clone, Copy, Debug)]
struct Kind {
    embedding: Embedding,
    scheme: Scheme,
    bvp: bool,
    /// A boundary value problem by Newton–MINRES instead of sparse LU.
    minres: bool,
}

fn solvers() -> Vec<(String, Kind)> {
    let mut out = Vec::new();
    for bvp in [false, true] {
        for side in [Side::Backward, Side::Forward] {
            for embedding in [
                Embedding::finite_difference(side),
                Embedding::asymmetric(side),
            ] {
                for scheme in [Scheme::Direct, Scheme::Variational] {
                    let what = if bvp { "BVP" } else { "IVP" };
                    let kind = Kind {
                        embedding,
                        scheme,
                        bvp,
                        minres: false,
                    };
                    out.push((format!("DynProblem {what} {embedding} {scheme:?}"), kind));
                }
            }
        }
    }
    for bvp in [false, true] {
        let what = if bvp { "BVP" } else { "IVP" };
        for embedding in [Embedding::midpoint(), Embedding::trapezoidal()] {
            for scheme in [Scheme::Direct, Scheme::Variational] {
                let kind = Kind {
                    embedding,
                    scheme,
                    bvp,
                    minres: false,
                };
                out.push((format!("DynProblem {what} {embedding} {scheme:?}"), kind));
            }
        }
        // The Gauss–Legendre integrators, variational only.
        for s in 1..=4 {
            let embedding = Embedding::gauss_legendre(s).unwrap();
            let kind = Kind {
                embedding,
                scheme: Scheme::Variational,
                bvp,
                minres: false,
            };
            out.push((format!("DynProblem {what} {embedding}"), kind));
        }
    }
    // The variational boundary value problems by Newton–MINRES.
    for embedding in [
        Embedding::finite_difference(Side::Backward),
        Embedding::asymmetric(Side::Forward),
        Embedding::midpoint(),
        Embedding::trapezoidal(),
    ] {
        let kind = Kind {
            embedding,
            scheme: Scheme::Variational,
            bvp: true,
            minres: true,
        };
        out.push((format!("DynProblem BVP by MINRES {embedding}"), kind));
    }
    out
}

fn solve<L: DynLagrangian>(
    lagrangian: &L,
    kind: Kind,
    grid: Grid,
    data: &[Vec<f64>; 2],
) -> DynSolution {
    let solver = if kind.minres {
        BvpSolver::Minres
    } else {
        BvpSolver::SparseLu
    };
    let problem = DynProblem::new(lagrangian, grid, kind.embedding).with_bvp_solver(solver);
    let solved = if kind.bvp {
        problem.solve_bvp(kind.scheme, &data[0], &data[1])
    } else {
        problem.solve_ivp(kind.scheme, &data[0], &data[1])
    };
    solved.unwrap_or_else(|e| {
        let model = std::any::type_name::<L>();
        panic!("{kind:?} of {model} on {grid:?} from {data:?}: {e}")
    })
}

/// One case: `model` and `c · model`, from data of entries up to `amplitude`; the largest node
/// difference relative to `max |Q|`.
fn case<L: DynLagrangian>(
    rng: &mut Rng,
    (model, amplitude): (&L, f64),
    kind: Kind,
    c: f64,
    exact: bool,
) -> f64 {
    let d = model.dimension();
    let n = if kind.bvp {
        8 + rng.below(53)
    } else {
        20 + rng.below(61)
    };
    let grid = Grid::new(0.0, if kind.bvp { 1.0 } else { 2.0 }, n).unwrap();
    let mut draw = || {
        (0..d)
            .map(|_| rng.uniform(-amplitude, amplitude))
            .collect::<Vec<f64>>()
    };
    let data = [draw(), draw()];
    let plain = solve(model, kind, grid, &data);
    let scaled = solve(&Scaled::new(c, model), kind, grid, &data);
    let largest = plain.q.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let gap = plain
        .q
        .iter()
        .zip(&scaled.q)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
        / largest;
    // With `L_vv = I` the affine steps of the chain take the identity-mass forms (Störmer–
    // Verlet's `y = 2b − a + h² f`, or `y = b − h (G(b) − π)` without a solve), which `c L`
    // (`L_vv = c I`) cannot: its closed form solves with `h J = c I`, the same equations in
    // other roundings. Its initial value problems are compared to 1e-9 only.
    let identity_mass = model.hessian_dependence().vv == Dependence::NONE;
    if exact && (kind.bvp || !identity_mass) {
        let iterations = (plain.run.newton_iterations, scaled.run.newton_iterations);
        assert!(
            plain.q == scaled.q && iterations.0 == iterations.1,
            "c = {c:e} = 2^k: {kind:?}, N = {n}: nodes {gap:e} apart, iterations {iterations:?}"
        );
    }
    gap
}

/// 300 random cases: `c L` gives the nodes of `L` to 1e-9 relative on every `DynProblem`
/// solver, bit for bit when `c` is a power of two.
#[test]
fn every_dyn_solver_gives_c_l_the_nodes_of_l() {
    let solvers = solvers();
    let mut rng = Rng(0xD15CA1E);
    let mut worst: BTreeMap<&str, (f64, usize)> = BTreeMap::new();
    for _ in 0..300 {
        let exact = rng.below(4) == 0;
        let c = if exact {
            2f64.powi(rng.below(79) as i32 - 39)
        } else {
            10f64.powf(rng.uniform(-12.0, 12.0))
        };
        let (name, kind) = &solvers[rng.below(solvers.len())];
        let gap = match rng.below(4) {
            0 => {
                let pendulum = AsDyn(Pendulum { g: 2.0, l: 1.0 });
                case(&mut rng, (&pendulum, 0.8), *kind, c, exact)
            }
            1 => case(&mut rng, (&AsDyn(Coupled), 0.8), *kind, c, exact),
            2 => {
                let model = CaldirolaKanai {
                    gamma: 0.5,
                    omega: 3.0,
                };
                case(&mut rng, (&AsDyn(model), 0.8), *kind, c, exact)
            }
            _ => {
                let chain = FputChain {
                    n: 8,
                    alpha: 0.25,
                    beta: 0.5,
                    periodic: false,
                };
                // Random nodes are rough data for a chain: smaller ones keep its BVPs solvable.
                case(&mut rng, (&chain, 0.2), *kind, c, exact)
            }
        };
        let entry = worst.entry(name).or_insert((0.0, 0));
        *entry = (entry.0.max(gap), entry.1 + 1);
    }
    let mut report = String::new();
    for (name, (gap, count)) in &worst {
        report += &format!("{name}: {gap:.2e} over {count} cases\n");
    }
    eprintln!("largest relative node difference, c L against L:\n{report}");
    assert!(
        worst.len() == solvers.len(),
        "a solver was never drawn:\n{report}"
    );
    assert!(worst.values().all(|&(gap, _)| gap <= 1e-9), "{report}");
}

/// The FPUT chain at rest at 0 (every term exactly zero) stops at once, at every scale.
#[test]
fn a_chain_at_rest_stops() {
    let grid = Grid::new(0.0, 1.0, 20).unwrap();
    let chain = FputChain {
        n: 8,
        alpha: 0.25,
        beta: 0.5,
        periodic: false,
    };
    let rest = [displacement(8, 0.0, 0.0), vec![0.0; 8]];
    for (name, kind) in solvers() {
        for c in [1.0, 1e-12, 1e12] {
            let run = solve(&Scaled::new(c, &chain), kind, grid, &rest);
            assert!(
                run.q.iter().all(|&x| x == 0.0) && run.run.newton_iterations == 0,
                "{name}, c = {c:e}: {} iterations",
                run.run.newton_iterations
            );
        }
    }
}
