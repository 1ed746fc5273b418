//! An independent oracle for `#[lagrangian]`: the double pendulum's derivatives, and core's step
//! kernels on them, from the macro against the same Lagrangian differentiated by num-dual's
//! (hyper-)dual numbers, at random points and random parameters, to 1e-12.

use nalgebra::SMatrix;
use varembed::__private::step::{Step, StepKind, StepTimes, residual};
use varembed::Lagrangian;
use varembed_tests::models::generated::DoublePendulum;
use varembed_tests::models::num_dual::NumDualDoublePendulum;
use varembed_tests::rng::Rng;

const TOL: f64 = 1e-12;

/// Entry-wise `|a − b| ≤ TOL · max(scale, |b|)`.
fn close<const R: usize, const C: usize>(
    what: &str,
    a: &SMatrix<f64, R, C>,
    b: &SMatrix<f64, R, C>,
    scale: f64,
) {
    for (i, (x, y)) in a.iter().zip(b.iter()).enumerate() {
        assert!(
            (x - y).abs() <= TOL * y.abs().max(scale),
            "{what}[{i}]: macro {x:e}, num-dual {y:e}"
        );
    }
}

fn random_model(rng: &mut Rng) -> DoublePendulum {
    DoublePendulum {
        m1: rng.uniform(0.2, 3.0),
        m2: rng.uniform(0.2, 3.0),
        l1: rng.uniform(0.2, 2.0),
        l2: rng.uniform(0.2, 2.0),
        g: rng.uniform(0.5, 20.0),
    }
}

#[test]
fn double_pendulum_derivatives_match_num_dual() {
    let mut rng = Rng(5);
    for _ in 0..500 {
        let model = random_model(&mut rng);
        let dual = NumDualDoublePendulum(model);
        // Angles over several turns, velocities of a chaotic run.
        let x = rng.vector::<2>(10.0);
        let v = rng.vector::<2>(8.0);
        let t = rng.uniform(-1.0, 1.0);
        let (lm, ld) = (model.value(&x, &v, t), dual.value(&x, &v, t));
        assert!(
            (lm - ld).abs() <= TOL * ld.abs().max(1.0),
            "L: {lm:e} vs {ld:e}"
        );
        let (mf, mp) = model.gradient(&x, &v, t);
        let (df, dp) = dual.gradient(&x, &v, t);
        close("∂L/∂x", &mf, &df, 1.0);
        close("∂L/∂v", &mp, &dp, 1.0);
        let (mh, dh) = (model.hessian(&x, &v, t), dual.hessian(&x, &v, t));
        close("L_xx", &mh.xx, &dh.xx, 1.0);
        close("L_xv", &mh.xv, &dh.xv, 1.0);
        close("L_vv", &mh.vv, &dh.vv, 1.0);
        // The fused evaluation gives the same as the separate ones.
        let (gf, gp, gh) = model.gradient_and_hessian(&x, &v, t);
        close("fused ∂L/∂x", &gf, &df, 1.0);
        close("fused ∂L/∂v", &gp, &dp, 1.0);
        close("fused L_xx", &gh.xx, &dh.xx, 1.0);
        close("fused L_xv", &gh.xv, &dh.xv, 1.0);
        close("fused L_vv", &gh.vv, &dh.vv, 1.0);
    }
}

#[test]
fn double_pendulum_step_kernels_match_num_dual() {
    let mut rng = Rng(6);
    for _ in 0..200 {
        let model = random_model(&mut rng);
        let dual = NumDualDoublePendulum(model);
        let h = rng.uniform(1e-3, 0.1);
        let t_a = rng.uniform(-1.0, 1.0);
        let times = StepTimes::new(h, t_a, t_a + h, t_a + 2.0 * h);
        let a = rng.vector::<2>(3.0);
        let b = a + rng.vector::<2>(5.0 * h);
        let y = b + rng.vector::<2>(5.0 * h);
        for kind in StepKind::ALL {
            let mm = Step::new(&model, kind, &a, &b, &times).momentum;
            let step = Step::new(&dual, kind, &a, &b, &times);
            let dm = step.momentum;
            close(&format!("{kind:?} momentum"), &mm, &dm, 1.0 + dm.amax());
            // The kernels subtract terms of size |π| and |L_vv|/h: the tolerance is relative
            // to those sizes.
            let (mr, mj) = residual(&model, &step, &y);
            let (dr, dj) = residual(&dual, &step, &y);
            close(&format!("{kind:?} residual"), &mr, &dr, 1.0 + dm.amax());
            close(&format!("{kind:?} jacobian"), &mj, &dj, 1.0 + dj.amax());
        }
    }
}
