//! The spherical pendulum in Cartesian coordinates: a unit mass under unit gravity along `−z`,
//! `L = ½|v|² − x₃`, under the holonomic constraint `g(x) = ½(|x|² − 1) = 0`
//! ([`varembed::Holonomic`]), solved by [`varembed::Problem::solve_constrained_ivp`]. Its
//! errors are against the same pendulum in angles, `x = (sin θ cos φ, sin θ sin φ, −cos θ)`,
//! whose equations `θ̈ = sin θ cos θ φ̇² − sin θ`, `φ̈ = −2 cot θ θ̇ φ̇` are written by hand and
//! integrated by DOP853: a reference independent of the constrained solver and of the macro.
//! Besides the errors, the scene measures the constraint residual `max_k |g(Q_k)|` and the
//! drift of the vertical angular momentum `L_z = x p_y − y p_x`, the Noether quantity of the
//! rotations about `z` (which leave `L` and the sphere invariant); and it solves the angle form
//! itself, a `#[lagrangian]` model in `(θ, φ)`, as the minimal-coordinates route.

use crate::cost;
use crate::reference::ReferenceCurve;
use crate::scene::{
    Context, Doubling, Figure, SceneReport, Series, SweepLine, SweepPoint, doubling,
};
use varembed::{Embedding, Grid, Holonomic, Problem, Scheme, Side, Solution, Vector, lagrangian};

/// A unit mass under unit gravity along `−z`.
#[lagrangian]
pub fn falling(x: [f64; 3], v: [f64; 3]) -> f64 {
    0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) - x[2]
}

/// The unit sphere, `g = ½(|x|² − 1)`.
#[lagrangian]
pub fn sphere(x: [f64; 3], _v: [f64; 3]) -> f64 {
    0.5 * (x[0] * x[0] + x[1] * x[1] + x[2] * x[2] - 1.0)
}

/// The same pendulum in angles `(θ, φ)`: `L = ½(θ̇² + sin²θ φ̇²) + cos θ`.
#[lagrangian]
pub fn angles(x: [f64; 2], v: [f64; 2]) -> f64 {
    let s = x[0].sin();
    0.5 * (v[0] * v[0] + s * s * v[1] * v[1]) + x[0].cos()
}

/// The scene's file-name stem.
pub const NAME: &str = "spherical-pendulum";

/// `[a, b]`.
pub const INTERVAL: (f64, f64) = (0.0, 10.0);

/// `θ(0)`, `φ̇(0)` (`φ(0) = 0`, `θ̇(0) = 0`): the mass swings out and around.
pub const THETA0: f64 = 1.0;
/// See [`THETA0`].
pub const PHI_RATE0: f64 = 0.8;

/// The point of the sphere at the angles `(θ, φ)`.
pub fn cartesian(theta: f64, phi: f64) -> Vector<3> {
    Vector::<3>::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        -theta.cos(),
    )
}

/// The initial data in Cartesian coordinates (on the sphere, the velocity tangent to it).
pub fn initial() -> (Vector<3>, Vector<3>) {
    (
        cartesian(THETA0, 0.0),
        Vector::<3>::new(0.0, THETA0.sin() * PHI_RATE0, 0.0),
    )
}

/// The angle form by DOP853, its equations written by hand: `(θ, φ)` and their rates.
pub fn reference() -> ReferenceCurve<2> {
    let acceleration = |q: &[f64], v: &[f64], _t: f64, a: &mut [f64]| {
        let (s, c) = q[0].sin_cos();
        a[0] = s * c * v[1] * v[1] - s;
        a[1] = -2.0 * c / s * v[0] * v[1];
    };
    ReferenceCurve::dop853(
        &acceleration,
        INTERVAL,
        Vector::<2>::new(THETA0, 0.0),
        Vector::<2>::new(0.0, PHI_RATE0),
        20_000,
    )
}

/// How a line solves the pendulum.
#[derive(Clone, Copy, Debug)]
pub enum Route {
    /// Cartesian coordinates under the constraint `|x| = 1`.
    Constrained,
    /// The `#[lagrangian]` model in `(θ, φ)`, unconstrained.
    Angles,
}

/// One line of the sweep.
#[derive(Clone, Copy, Debug)]
pub struct Line {
    /// Legend entry.
    pub label: &'static str,
    /// Cartesian under the constraint, or in angles.
    pub route: Route,
    /// The embedding.
    pub embedding: Embedding,
    /// Direct or variational.
    pub scheme: Scheme,
    /// The `N` of the line.
    pub sizes: Doubling,
}

/// The lines: the constrained midpoint and Gauss-FDE− runs (both schemes) and trapezoidal
/// (variational) run, and the angle form under the variational midpoint embedding.
pub fn lines(cx: &Context) -> Vec<Line> {
    let second = doubling(cx.pick(250, 100), cx.pick(6, 3));
    let first = doubling(cx.pick(500, 100), cx.pick(5, 3));
    let line = |label, route, embedding, scheme, sizes| Line {
        label,
        route,
        embedding,
        scheme,
        sizes,
    };
    let (midpoint, constrained) = (Embedding::midpoint(), Route::Constrained);
    vec![
        line(
            "constrained: variational midpoint",
            constrained,
            midpoint,
            Scheme::Variational,
            second,
        ),
        line(
            "constrained: direct midpoint",
            constrained,
            midpoint,
            Scheme::Direct,
            second,
        ),
        line(
            "constrained: variational trapezoidal",
            constrained,
            Embedding::trapezoidal(),
            Scheme::Variational,
            second,
        ),
        line(
            "constrained: variational FDE−",
            constrained,
            Embedding::finite_difference(Side::Backward),
            Scheme::Variational,
            first,
        ),
        line(
            "constrained: direct FDE−",
            constrained,
            Embedding::finite_difference(Side::Backward),
            Scheme::Direct,
            first,
        ),
        line(
            "angles: variational midpoint",
            Route::Angles,
            midpoint,
            Scheme::Variational,
            second,
        ),
    ]
}

/// A run of one line, as the scene reads it.
pub struct Run {
    /// The nodes on the sphere (the angle form's mapped by [`cartesian`]).
    pub q: Vec<Vector<3>>,
    /// `L_z` at the nodes: `x p_y − y p_x` with the momenta of `Solution::node_values`, or
    /// `p_φ` of the angle form (the same quantity).
    pub lz: Vec<f64>,
    /// Newton iterations of the run.
    pub newton_iterations: usize,
}

impl Run {
    /// `max_k |Q_k − x(t_k)|∞` against the reference mapped onto the sphere.
    pub fn error(&self, grid: &Grid, reference: &ReferenceCurve<2>) -> f64 {
        self.q
            .iter()
            .enumerate()
            .map(|(k, q)| {
                let angles = reference.q(grid.t(k));
                (q - cartesian(angles[0], angles[1])).amax()
            })
            .fold(0.0, f64::max)
    }

    /// `max_k |g(Q_k)|`, `g = ½(|x|² − 1)`.
    pub fn residual(&self) -> f64 {
        self.q
            .iter()
            .map(|q| (0.5 * (q.norm_squared() - 1.0)).abs())
            .fold(0.0, f64::max)
    }

    /// `max |L_z(t_k) − L_z(0)|` over the interior nodes `0 < k < N` (the end nodes' velocity
    /// formula of a direct scheme is one-sided, [`varembed::NodeRule`]).
    pub fn interior_drift(&self, grid: &Grid) -> f64 {
        let drift = self.lz_drift(grid);
        drift[1..drift.len() - 1]
            .iter()
            .map(|(_, d)| d.abs())
            .fold(0.0, f64::max)
    }

    /// `(t_k, L_z(t_k) − L_z(0))`, `L_z(0)` that of the initial data.
    pub fn lz_drift(&self, grid: &Grid) -> Vec<(f64, f64)> {
        let lz0 = THETA0.sin().powi(2) * PHI_RATE0;
        self.lz
            .iter()
            .enumerate()
            .map(|(k, lz)| (grid.t(k), lz - lz0))
            .collect()
    }
}

/// The solution of one line on `grid`, in the coordinates of its route.
enum Solved {
    Cartesian(Solution<3>),
    Angles(Solution<2>),
}

fn solve(line: &Line, grid: Grid) -> varembed::Result<Solved> {
    match line.route {
        Route::Constrained => {
            let (q0, v0) = initial();
            let problem = Problem::new(&Falling, grid, line.embedding);
            let run = problem.solve_constrained_ivp(line.scheme, &Holonomic(Sphere), q0, v0)?;
            Ok(Solved::Cartesian(run.solution))
        }
        Route::Angles => {
            let problem = Problem::new(&Angles, grid, line.embedding);
            let solution = problem.solve_ivp(line.scheme, [THETA0, 0.0], [0.0, PHI_RATE0])?;
            Ok(Solved::Angles(solution))
        }
    }
}

fn read(solved: Solved) -> varembed::Result<Run> {
    Ok(match solved {
        Solved::Cartesian(solution) => {
            let nodes = solution.node_values(&Falling)?;
            let lz = nodes
                .iter()
                .map(|node| node.q[0] * node.p[1] - node.q[1] * node.p[0])
                .collect();
            Run {
                newton_iterations: solution.newton_iterations,
                q: solution.q,
                lz,
            }
        }
        Solved::Angles(solution) => {
            let nodes = solution.node_values(&Angles)?;
            let lz = nodes.iter().map(|node| node.p[1]).collect();
            Run {
                newton_iterations: solution.newton_iterations,
                q: solution.q.iter().map(|q| cartesian(q[0], q[1])).collect(),
                lz,
            }
        }
    })
}

/// Every line swept against the reference, with the run of each line at `n` (every line's
/// sizes hold it).
pub fn sweep(
    cx: &Context,
    reference: &ReferenceCurve<2>,
    n: usize,
) -> varembed::Result<Vec<(Line, SweepLine, Run)>> {
    let lines = lines(cx);
    let grids: usize = lines.iter().map(|l| l.sizes.count).sum();
    cx.progress.inc_length((cx.repeats * grids) as u64);
    let mut out = Vec::with_capacity(lines.len());
    for line in lines {
        let mut points = Vec::new();
        let mut at_n = None;
        for size in line.sizes.sizes() {
            let grid = Grid::new(INTERVAL.0, INTERVAL.1, size)?;
            let (solved, seconds) = cx.median_time(|| solve(&line, grid))?;
            let what = format!("{} {} {}", line.label, line.embedding, line.scheme);
            cx.record(NAME, &what, size);
            let run = read(solved)?;
            let error = run.error(&grid, reference);
            points.push(SweepPoint {
                n: size,
                seconds,
                error,
            });
            if size == n {
                at_n = Some(run);
            }
        }
        let run = at_n.expect("every line's sizes hold the table's N");
        let swept = SweepLine {
            label: line.label.to_string(),
            points,
            failures: Vec::new(),
            statuses: Vec::new(),
        };
        out.push((line, swept, run));
    }
    Ok(out)
}

/// The table at `n`: per line, its max error, constraint residual, `L_z` drift, Newton
/// iterations and wall time.
fn table(n: usize, runs: &[(Line, SweepLine, Run)]) -> String {
    let mut text = format!(
        "spherical pendulum on [{}, {}], N = {n}: Cartesian under |x| = 1 and in angles\n  \
         {:<38} {:>10} {:>12} {:>14} {:>7} {:>9}\n",
        INTERVAL.0,
        INTERVAL.1,
        "line",
        "max error",
        "max |g(Q_k)|",
        "max |ΔL_z|",
        "Newton",
        "time (s)"
    );
    let grid = Grid::new(INTERVAL.0, INTERVAL.1, n).expect("a valid grid");
    for (line, swept, run) in runs {
        let point = swept.points.iter().find(|p| p.n == n);
        let (error, seconds) = point.map_or((f64::NAN, f64::NAN), |p| (p.error, p.seconds));
        let drift = run
            .lz_drift(&grid)
            .iter()
            .map(|(_, d)| d.abs())
            .fold(0.0, f64::max);
        text += &format!(
            "  {:<38} {error:>10.2e} {:>12.1e} {drift:>14.1e} {:>7} {seconds:>9.2e}\n",
            line.label,
            run.residual(),
            run.newton_iterations,
        );
    }
    text.trim_end().to_string()
}

/// The scene.
pub fn run(cx: &Context) -> varembed::Result<SceneReport> {
    let reference = reference();
    let n = cx.pick(2000, 200);
    let runs = sweep(cx, &reference, n)?;
    let grid = Grid::new(INTERVAL.0, INTERVAL.1, n)?;
    let sweep: Vec<SweepLine> = runs.iter().map(|(_, line, _)| line.clone()).collect();
    let find = |label: &str| runs.iter().find(|(line, _, _)| line.label == label);
    let drift = |label: &str| {
        find(label).map_or(f64::NAN, |(_, _, run)| {
            run.lz_drift(&grid)
                .iter()
                .map(|(_, d)| d.abs())
                .fold(0.0, f64::max)
        })
    };
    let interior =
        |label: &str| find(label).map_or(f64::NAN, |(_, _, run)| run.interior_drift(&grid));
    let same_nodes = match (
        find("constrained: variational midpoint"),
        find("constrained: direct midpoint"),
        find("constrained: variational trapezoidal"),
    ) {
        (Some((_, _, a)), Some((_, _, b)), Some((_, _, c))) => {
            a.q.iter()
                .zip(&b.q)
                .zip(&c.q)
                .map(|((a, b), c)| (a - b).amax().max((a - c).amax()))
                .fold(0.0, f64::max)
        }
        _ => f64::NAN,
    };
    let residual = runs
        .iter()
        .filter(|(line, _, _)| matches!(line.route, Route::Constrained))
        .map(|(_, _, run)| run.residual())
        .fold(0.0, f64::max);
    let order = |label: &str| {
        find(label)
            .and_then(|(_, line, _)| line.orders().last().copied())
            .map_or("—".to_string(), |p| format!("{p:.2}"))
    };
    let target = 1e-5;
    let notes = vec![
        format!(
            "A unit mass on the unit sphere under unit gravity, `θ(0) = {THETA0}`, \
             `φ̇(0) = {PHI_RATE0}` on `[0, 10]`, in Cartesian coordinates `L = ½|v|² − z` under \
             the constraint `g = ½(|x|² − 1) = 0` (`Holonomic`, `solve_constrained_ivp`), errors \
             `max_k |Q_k − x(t_k)|∞` against the angle form by DOP853 mapped onto the sphere. \
             The line `angles: …` solves the angle form `L = ½(θ̇² + sin²θ φ̇²) + cos θ` itself \
             (minimal coordinates, no multiplier), its nodes mapped the same way."
        ),
        format!(
            "Each constrained line keeps the order of its embedding (observed between the two \
             finest `N`: variational midpoint {}, direct midpoint {}, variational trapezoidal \
             {}, variational FDE− {}, direct FDE− {}; angles {}). On this `L`, whose potential \
             is linear in `x`, the midpoint and trapezoidal discrete Lagrangians coincide and the \
             direct midpoint recurrence is the variational one: the three second-order \
             constrained lines compute the same nodes ({}). Every node is on the sphere: \
             `max_k |g(Q_k)|` is {residual:.1e} over the constrained runs at N = {n} (each step \
             solves the constraint at its newest node by Newton's method; figure \
             `{NAME}-constraint.svg`).",
            order("constrained: variational midpoint"),
            order("constrained: direct midpoint"),
            order("constrained: variational trapezoidal"),
            order("constrained: variational FDE−"),
            order("constrained: direct FDE−"),
            order("angles: variational midpoint"),
            if same_nodes == 0.0 {
                "bit for bit".to_string()
            } else {
                format!("to {same_nodes:.0e}")
            },
        ),
        format!(
            "The vertical angular momentum `L_z = x p_y − y p_x` (figure `{NAME}-lz.svg`, the \
             momenta of `Solution::node_values`; in angles `p_φ`, the momentum of a cyclic \
             coordinate), at N = {n}: the variational schemes conserve it to round-off (in angles to \
             the Newton tolerance), max \
             `|L_z(t_k) − L_z(0)|` {:.1e} (midpoint), {:.1e} (trapezoidal), {:.1e} (FDE−), \
             {:.1e} in angles; the direct FDE− scheme, which is not variational, drifts by \
             {:.1e}. The direct midpoint nodes are the variational ones, and its `L_z` at the \
             interior nodes (centred velocity) is conserved too ({:.1e}); only at the two end \
             nodes, where a direct scheme's node velocity is one-sided, is it off, by {:.1e}.",
            drift("constrained: variational midpoint"),
            drift("constrained: variational trapezoidal"),
            drift("constrained: variational FDE−"),
            drift("angles: variational midpoint"),
            drift("constrained: direct FDE−"),
            interior("constrained: direct midpoint"),
            drift("constrained: direct midpoint"),
        ),
        cost::advice(
            &sweep,
            target,
            "The angle form has two unknowns per step and no multiplier, the Cartesian form \
             three and one; the constrained step solves a saddle-point system of four by dense \
             LU. The constrained form needs no chart (the angles are singular at the poles).",
        ),
    ];
    let lz_series = runs
        .iter()
        .map(|(line, _, run)| Series::new(line.label, run.lz_drift(&grid)))
        .collect();
    let residual_series = runs
        .iter()
        .filter(|(line, _, _)| matches!(line.route, Route::Constrained))
        .map(|(line, _, run)| {
            let points = run
                .q
                .iter()
                .enumerate()
                .map(|(k, q)| (grid.t(k), 0.5 * (q.norm_squared() - 1.0)))
                .collect();
            Series::new(line.label, points)
        })
        .collect();
    let figures = vec![
        Figure {
            file: format!("{NAME}-lz.svg"),
            title: format!("Spherical pendulum: drift of L_z, N = {n}"),
            x_label: "time t (√(l/g))".to_string(),
            y_label: "L_z(t_k) − L_z(0) (m √(g l³))".to_string(),
            series: lz_series,
        },
        Figure {
            file: format!("{NAME}-constraint.svg"),
            title: format!("Spherical pendulum: constraint residual g(Q_k), N = {n}"),
            x_label: "time t (√(l/g))".to_string(),
            y_label: "g(Q_k) = (|Q_k|² − 1)/2".to_string(),
            series: residual_series,
        },
    ];
    Ok(SceneReport {
        name: NAME,
        title: "Spherical pendulum under |x| = 1".to_string(),
        notes,
        tables: vec![table(n, &runs)],
        reference: format!("angle form by {}", reference.name),
        sweep,
        advice_target: Some(target),
        figures,
    })
}
