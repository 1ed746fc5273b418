use super::residual::{Evaluation, evaluate};
use super::*;
use crate::embedding::Embedding;
use crate::grid::Grid;
use crate::lagrangian::{Hessian, Matrix};
use crate::linalg::block;
use crate::side::Side;
use crate::solve::krylov::{KrylovSystem, conjugate_gradient};
use crate::test_models::Mixed;
use nalgebra::DMatrix;

mod solves;

/// The fast system at `q`: its residual evaluated and its Jacobian linearised there.
fn linearized<'a, L: Lagrangian<D>, const D: usize>(
    disc: &'a Discretisation<'_, L, D>,
    fft: &'a mut FftOperator,
    q: &[Vector<D>],
) -> (FastSystem<'a, D>, Evaluation<D>) {
    linearized_for(disc, Scheme::Variational, fft, q)
}

/// [`linearized`] for `scheme` (which matters for the corrected form only).
fn linearized_for<'a, L: Lagrangian<D>, const D: usize>(
    disc: &'a Discretisation<'_, L, D>,
    scheme: Scheme,
    fft: &'a mut FftOperator,
    q: &[Vector<D>],
) -> (FastSystem<'a, D>, Evaluation<D>) {
    let (velocity, adjoint) = (disc.velocity_operator(), disc.adjoint_operator());
    let columns = EndColumns::new(scheme, velocity, adjoint);
    let mut system = FastSystem::<D>::new(velocity, columns, fft);
    let mut eval = Evaluation::new(disc.grid().n());
    evaluate(disc, &mut system, q, 0, &mut eval).unwrap();
    system
        .linearize(disc, q, &eval.v, Location::Newton(0))
        .unwrap();
    (system, eval)
}

fn curve(n: usize) -> Vec<Vector<2>> {
    (0..=n)
        .map(|k| {
            let t = k as f64;
            Vector::<2>::new((0.7 * t).sin(), 0.5 * (1.3 * t).cos())
        })
        .collect()
}

/// The matrix-free `J δ` and the residual by FFT equal the assembled dense Jacobian and the
/// dense residual, for both sides, for the paper's operators and for the corrected form's
/// (both schemes: the starting columns beside the FFT products), `J δ` both by FFT and from
/// the preconditioner's image.
#[test]
fn matrix_free_jacobian_and_residual_match_the_dense_ones() {
    let n = 13;
    let grid = Grid::new(0.2, 1.5, n).unwrap();
    for side in [Side::Backward, Side::Forward] {
        let cases = [
            (
                Embedding::grunwald_letnikov(side, 0.6).unwrap(),
                Scheme::Variational,
            ),
            (
                Embedding::corrected_grunwald_letnikov(side, 0.6).unwrap(),
                Scheme::Direct,
            ),
            (
                Embedding::corrected_grunwald_letnikov(side, 0.6).unwrap(),
                Scheme::Variational,
            ),
        ];
        for (embedding, scheme) in cases {
            let what = format!("{embedding} {scheme}");
            let disc = Discretisation::new(&Mixed, grid, embedding);
            let q = curve(n);
            let mut fft = FftOperator::new(disc.velocity_operator());
            let (mut system, eval) = linearized_for(&disc, scheme, &mut fft, &q);
            assert_eq!(system.symmetric(), scheme == Scheme::Variational, "{what}");
            let dense_r = disc.residual(scheme, &q).unwrap();
            for (j, b) in dense_r.iter().enumerate() {
                let a = block::<2>(&eval.r, j);
                assert!((a - b).amax() < 1e-12, "{what}: {a} vs {b}");
            }
            let pw = disc.pointwise(&q).unwrap();
            let m = (n - 1) * 2;
            let jac = disc.dense_jacobian(scheme, &q, &pw);
            let x: Vec<f64> = (0..m).map(|i| ((3 * i + 1) as f64).sin()).collect();
            let (mut z, mut image) = (vec![0.0; m], vec![0.0; m]);
            system.precondition_with_image(&x, &mut z, &mut image);
            for (input, image) in [(&x, None), (&z, Some(&image))] {
                let mut y = vec![0.0; m];
                match image {
                    None => system.apply(input, &mut y),
                    Some(image) => system.apply_with_image(input, image, &mut y),
                }
                let want = &jac * nalgebra::DVector::from_vec(input.clone());
                for i in 0..m {
                    assert!(
                        (y[i] - want[i]).abs() < 1e-11 * want.amax(),
                        "{what}, image {}: row {i}: {} vs {}",
                        image.is_some(),
                        y[i],
                        want[i]
                    );
                }
            }
        }
    }
}

/// The preconditioner's sweeps and the Jacobian product that takes the kinetic part from it
/// run in two halves from `halves::FROM` rows on: there, at `d = 2` with an `L_vv` that varies
/// (its Woodbury term formed anew) and `L_xx` varying along the curve, the product from the
/// preconditioner's input equals the full product by FFT, which sweeps in one piece, and so
/// does the product given the preconditioner's image (both sides).
#[test]
fn sweeps_in_halves_give_the_products_of_one_piece() {
    let n = crate::halves::FROM + 7;
    let grid = Grid::new(0.2, 1.5, n).unwrap();
    let q = curve(n);
    for side in [Side::Backward, Side::Forward] {
        let disc = Discretisation::new(
            &Unmixed,
            grid,
            Embedding::grunwald_letnikov(side, 0.6).unwrap(),
        );
        let mut fft = FftOperator::new(disc.velocity_operator());
        let (mut system, _) = linearized(&disc, &mut fft, &q);
        assert!(system.kinetic_known() && !system.forms_rows());
        let m = (n - 1) * 2;
        let r: Vec<f64> = (0..m).map(|i| ((3 * i + 1) as f64).sin()).collect();
        let (mut z, mut image) = (vec![0.0; m], vec![0.0; m]);
        system.precondition_with_image(&r, &mut z, &mut image);
        let mut want = vec![0.0; m];
        system.apply(&z, &mut want);
        let scale = want.iter().fold(0.0f64, |a, y| a.max(y.abs()));
        // Onto a vector, as MINRES takes it: 0.5 J z − 2 u.
        let u: Vec<f64> = (0..m).map(|i| ((5 * i + 2) as f64).cos()).collect();
        let mut from_kinetic = u.clone();
        system.apply_preconditioned(&z, &[], (&r, 1.0), (0.5, -2.0), &mut from_kinetic);
        from_kinetic
            .iter_mut()
            .zip(&u)
            .for_each(|(y, u)| *y = 2.0 * (*y + 2.0 * u));
        let mut from_image = vec![0.0; m];
        system.apply_with_image(&z, &image, &mut from_image);
        for (what, got) in [("kinetic", &from_kinetic), ("image", &from_image)] {
            let error = got
                .iter()
                .zip(&want)
                .fold(0.0f64, |a, (g, w)| a.max((g - w).abs()));
            assert!(
                error < 1e-9 * scale,
                "{side:?} {what}: {error:e} of {scale:e}"
            );
        }
    }
}

/// The guess's input checks hand its second derivatives to the first linearisation, which
/// reads them instead of evaluating them again: it holds the same blocks on every row, and
/// gives the same Jacobian products, as a linearisation that evaluates them (both sides, the
/// paper's and the corrected operators, `L_xv ≠ 0` and an `L_vv` that varies along the curve).
#[test]
fn hessians_kept_by_the_checks_are_the_linearisations() {
    let n = 13;
    let grid = Grid::new(0.2, 1.5, n).unwrap();
    let q = curve(n);
    for side in [Side::Backward, Side::Forward] {
        for embedding in [
            Embedding::grunwald_letnikov(side, 0.6).unwrap(),
            Embedding::corrected_grunwald_letnikov(side, 0.6).unwrap(),
        ] {
            let disc = Discretisation::new(&Mixed, grid, embedding);
            let mut fft = FftOperator::new(disc.velocity_operator());
            let (mut evaluated, _) = linearized(&disc, &mut fft, &q);
            let mut other_fft = FftOperator::new(disc.velocity_operator());
            let (velocity, adjoint) = (disc.velocity_operator(), disc.adjoint_operator());
            let columns = EndColumns::new(Scheme::Variational, velocity, adjoint);
            let mut kept = FastSystem::<2>::new(velocity, columns, &mut other_fft);
            let mut eval = Evaluation::new(n);
            evaluate(&disc, &mut kept, &q, 0, &mut eval).unwrap();
            let keep = |i, h: &Hessian<2>| assert!(kept.keep_hessian(i, h), "row {i}");
            check_nodes_with(&disc, &q, |i| block(&eval.v, i), true, keep).unwrap();
            // A curve far from `q`: a linearisation that evaluated its Hessians would differ.
            let elsewhere: Vec<Vector<2>> = q.iter().map(|x| x * 3.0).collect();
            kept.linearize(&disc, &elsewhere, &eval.v, Location::Newton(0))
                .unwrap();
            for i in 0..n {
                for (a, b) in [
                    (kept.xx.get(i), evaluated.xx.get(i)),
                    (kept.xv.get(i), evaluated.xv.get(i)),
                    (kept.vv.get(i), evaluated.vv.get(i)),
                ] {
                    assert_eq!(a, b, "{embedding}: row {i}");
                }
            }
            let m = (n - 1) * 2;
            let x: Vec<f64> = (0..m).map(|i| ((5 * i + 2) as f64).cos()).collect();
            let (mut y_kept, mut y_evaluated) = (vec![0.0; m], vec![0.0; m]);
            kept.apply(&x, &mut y_kept);
            evaluated.apply(&x, &mut y_evaluated);
            assert_eq!(y_kept, y_evaluated, "{embedding}");
            // Kept once: the next linearisation evaluates them again, at its own iterate.
            kept.linearize(&disc, &elsewhere, &eval.v, Location::Newton(1))
                .unwrap();
            assert_ne!(kept.vv.get(3), evaluated.vv.get(3), "{embedding}");
        }
    }
}

/// `L = ½(1 + t)(v₀² + v₀v₁ + v₁²) + cos x₀ + x₀x₁`: every `L_xv` zero, `L_vv` varying
/// along the grid, `L_xx` coupling the components.
struct Unmixed;

impl Lagrangian<2> for Unmixed {
    fn value(&self, x: &Vector<2>, v: &Vector<2>, t: f64) -> f64 {
        0.5 * (1.0 + t) * (v[0] * v[0] + v[0] * v[1] + v[1] * v[1]) + x[0].cos() + x[0] * x[1]
    }
    fn gradient(&self, x: &Vector<2>, v: &Vector<2>, t: f64) -> (Vector<2>, Vector<2>) {
        let dx = Vector::<2>::new(-x[0].sin() + x[1], x[0]);
        let dv = Vector::<2>::new(v[0] + 0.5 * v[1], 0.5 * v[0] + v[1]) * (1.0 + t);
        (dx, dv)
    }
    fn hessian(&self, x: &Vector<2>, _v: &Vector<2>, t: f64) -> Hessian<2> {
        Hessian {
            xx: Matrix::<2>::new(-x[0].cos(), 1.0, 1.0, 0.0),
            xv: Matrix::<2>::zeros(),
            vv: Matrix::<2>::new(1.0, 0.5, 0.5, 1.0) * (1.0 + t),
        }
    }
}

/// `L = ½(t − t₅)² v₀² + ½v₁² + cos x₀`: `L_vv` singular at the node `t₅` of the grid of
/// [`products_from_the_preconditioner_match_the_dense_jacobian`], where the preconditioner
/// holds a stand-in for its inverse.
struct VanishingMass {
    at: f64,
}

impl Lagrangian<2> for VanishingMass {
    fn value(&self, x: &Vector<2>, v: &Vector<2>, t: f64) -> f64 {
        let m = t - self.at;
        0.5 * m * m * v[0] * v[0] + 0.5 * v[1] * v[1] + x[0].cos()
    }
    fn gradient(&self, x: &Vector<2>, v: &Vector<2>, t: f64) -> (Vector<2>, Vector<2>) {
        let m = t - self.at;
        let dx = Vector::<2>::new(-x[0].sin(), 0.0);
        (dx, Vector::<2>::new(m * m * v[0], v[1]))
    }
    fn hessian(&self, x: &Vector<2>, _v: &Vector<2>, t: f64) -> Hessian<2> {
        let m = t - self.at;
        Hessian {
            xx: Matrix::<2>::new(-x[0].cos(), 0.0, 0.0, 0.0),
            xv: Matrix::<2>::zeros(),
            vv: Matrix::<2>::new(m * m, 0.0, 0.0, 1.0),
        }
    }
}

/// `J z` for `z = f · P'⁻¹ r`, formed from `f r` in place of the kinetic product, equals the
/// dense Jacobian's `J z`: with and without `L_xv` terms, both sides, for the corrected
/// form's direct scheme with its columns left out (the ill-posedness check's `plain`
/// products: the paper's operators, with the Hessians at the corrected velocities), and where the kinetic part is not known (the corrected
/// form's columns in the products; an `L_vv` the preconditioner could not invert), whose
/// products keep computing it.
#[test]
fn products_from_the_preconditioner_match_the_dense_jacobian() {
    const N: usize = 17;
    let grid = Grid::new(0.2, 1.5, N).unwrap();
    // `reference`: the embedding whose assembled variational Jacobian the products must equal.
    fn check<L: Lagrangian<2>>(
        (model, model_is_mixed): (&L, bool),
        (embedding, scheme, plain): (Embedding, Scheme, bool),
        reference: Embedding,
        kinetic_known: bool,
    ) {
        let (n, grid) = (N, Grid::new(0.2, 1.5, N).unwrap());
        let what = format!("{embedding} {scheme:?}, plain {plain}");
        let disc = Discretisation::new(model, grid, embedding);
        let q = curve(n);
        let mut fft = FftOperator::new(disc.velocity_operator());
        let (mut system, _) = linearized_for(&disc, scheme, &mut fft, &q);
        system.plain = plain;
        assert_eq!(system.kinetic_known(), kinetic_known, "{what}");
        let m = (n - 1) * 2;
        let r: Vec<f64> = (0..m).map(|i| ((7 * i + 3) as f64).sin()).collect();
        let factor = 0.37;
        // No images where the product needs none (the kinetic part known, every L_xv zero).
        let images = system.image_len();
        assert_eq!(images == 0, kinetic_known && !model_is_mixed, "{what}");
        let (mut z, mut image) = (vec![0.0; m], vec![0.0; images]);
        system.precondition_with_image(&r, &mut z, &mut image);
        z.iter_mut()
            .chain(image.iter_mut())
            .for_each(|x| *x *= factor);
        // Onto a vector, as MINRES takes it: y ← J z / 4 − 3 u, read back as J z.
        let u: Vec<f64> = (0..m).map(|i| ((7 * i + 3) as f64).sin()).collect();
        let mut y = u.clone();
        system.apply_preconditioned(&z, &image, (&r, factor), (0.25, -3.0), &mut y);
        y.iter_mut()
            .zip(&u)
            .for_each(|(y, u)| *y = 4.0 * (*y + 3.0 * u));
        let reference = Discretisation::new(model, grid, reference);
        let pw = reference.pointwise(&q).unwrap();
        let jac = reference.dense_jacobian(Scheme::Variational, &q, &pw);
        let want = &jac * nalgebra::DVector::from_vec(z.clone());
        for i in 0..m {
            assert!(
                (y[i] - want[i]).abs() < 1e-11 * want.amax(),
                "{what}: row {i}: {} vs {}",
                y[i],
                want[i]
            );
        }
    }
    let vanishing = VanishingMass { at: grid.t(5) };
    for side in [Side::Backward, Side::Forward] {
        let paper = Embedding::grunwald_letnikov(side, 0.65).unwrap();
        let corrected = Embedding::corrected_grunwald_letnikov(side, 0.65).unwrap();
        let variational = |e| (e, Scheme::Variational, false);
        check((&Mixed, true), variational(paper), paper, true);
        check((&Unmixed, false), variational(paper), paper, true);
        check((&vanishing, false), variational(paper), paper, false);
        check((&Unmixed, false), variational(corrected), corrected, false);
        // The plain products take the Hessians at the corrected velocities: the paper's
        // assembled Jacobian is their reference where the Hessians do not depend on v.
        let plain_direct = (corrected, Scheme::Direct, true);
        check((&Unmixed, false), plain_direct, paper, true);
    }
}

/// The preconditioner's by-product is `D_a z`, and `J z` from it equals `J z` by FFT.
#[test]
fn preconditioner_images_are_the_square_block_products() {
    let n = 23;
    let grid = Grid::new(0.2, 1.5, n).unwrap();
    for side in [Side::Backward, Side::Forward] {
        let embedding = Embedding::grunwald_letnikov(side, 0.55).unwrap();
        let disc = Discretisation::new(&Mixed, grid, embedding);
        let q = curve(n);
        let mut fft = FftOperator::new(disc.velocity_operator());
        let (mut system, _) = linearized(&disc, &mut fft, &q);
        let m = (n - 1) * 2;
        let r: Vec<f64> = (0..m).map(|i| ((5 * i + 2) as f64).cos()).collect();
        let (mut z, mut image) = (vec![0.0; m], vec![0.0; m]);
        system.precondition_with_image(&r, &mut z, &mut image);
        // D z on the rows of the interior nodes, D = −σΔ.
        let mut full = vec![Vector::<2>::zeros(); n + 1];
        for j in 1..n {
            full[j] = block(&z, j - 1);
        }
        let dz = disc.velocity_operator().apply(&full).unwrap();
        for j in 1..n {
            let want = dz[j - disc.velocity_operator().first_row()] * -side.sign();
            let got = block::<2>(&image, j - 1);
            assert!(
                (got - want).amax() < 1e-12 * (1.0 + want.amax()),
                "{side:?} {j}"
            );
        }
        let (mut a, mut b) = (vec![0.0; m], vec![0.0; m]);
        system.apply(&z, &mut a);
        system.apply_with_image(&z, &image, &mut b);
        let scale = a.iter().fold(0.0f64, |s, x| s.max(x.abs()));
        for i in 0..m {
            assert!(
                (a[i] - b[i]).abs() < 1e-12 * scale,
                "{side:?} {i}: {} vs {}",
                a[i],
                b[i]
            );
        }
    }
}

/// The preconditioner inverts the whole kinetic part `P' = Dᵀ L_vv D` (the square block and
/// the extra row, `L_vv` varying along the grid): `P'⁻¹ P' x = x`.
#[test]
fn preconditioner_inverts_the_whole_kinetic_part() {
    /// `L = (1 + t) v²`.
    struct Free;
    impl Lagrangian<1> for Free {
        fn value(&self, _x: &Vector<1>, v: &Vector<1>, t: f64) -> f64 {
            (1.0 + t) * v[0] * v[0]
        }
        fn gradient(&self, _x: &Vector<1>, v: &Vector<1>, t: f64) -> (Vector<1>, Vector<1>) {
            (Vector::<1>::zeros(), *v * (2.0 * (1.0 + t)))
        }
        fn hessian(&self, _x: &Vector<1>, _v: &Vector<1>, t: f64) -> Hessian<1> {
            Hessian {
                xx: Matrix::<1>::zeros(),
                xv: Matrix::<1>::zeros(),
                vv: Matrix::<1>::new(2.0 * (1.0 + t)),
            }
        }
    }
    let n = 17;
    let grid = Grid::new(0.0, 1.0, n).unwrap();
    for side in [Side::Backward, Side::Forward] {
        let embedding = Embedding::grunwald_letnikov(side, 0.45).unwrap();
        let disc = Discretisation::new(&Free, grid, embedding);
        let q: Vec<Vector<1>> = (0..=n).map(|k| Vector::<1>::new(k as f64)).collect();
        let mut fft = FftOperator::new(disc.velocity_operator());
        let (mut system, _) = linearized(&disc, &mut fft, &q);
        assert!(system.preconditioner.correction.is_some());
        // P' = Σ_k D[k, ·]ᵀ L_vv(t_k) D[k, ·] over every row k of D = −σΔ.
        let m = n - 1;
        let mut p = DMatrix::<f64>::zeros(m, m);
        let sigma = side.sign();
        for a in 1..n {
            for b in 1..n {
                let mut acc = 0.0;
                for k in disc.velocity_operator().rows() {
                    let d = |j| {
                        disc.velocity_operator()
                            .row_entries(k)
                            .find(|&(jj, _)| jj == j)
                            .map_or(0.0, |(_, c)| -sigma * c)
                    };
                    acc += d(a) * 2.0 * (1.0 + grid.t(k)) * d(b);
                }
                p[(a - 1, b - 1)] = acc;
            }
        }
        let x: Vec<f64> = (0..m).map(|i| (i as f64 * 0.37).cos()).collect();
        let px = &p * nalgebra::DVector::from_vec(x.clone());
        let mut z = vec![0.0; m];
        system.precondition(px.as_slice(), &mut z);
        for i in 0..m {
            assert!(
                (z[i] - x[i]).abs() < 1e-10,
                "{side:?} {i}: {} vs {}",
                z[i],
                x[i]
            );
        }
    }
}

/// The same with `d = 2` and full `L_vv` blocks (the Woodbury term is a 2 × 2 system), at
/// successive linearisations of one system: `L_vv` unchanged (the correction kept), changed
/// (recomputed), and unchanged again.
#[test]
fn preconditioner_inverts_the_kinetic_part_with_blocks() {
    let n = 15;
    let grid = Grid::new(0.2, 1.5, n).unwrap();
    let shifted: Vec<Vector<2>> = curve(n)
        .iter()
        .map(|x| x * 1.3 + Vector::<2>::new(0.2, -0.1))
        .collect();
    for side in [Side::Backward, Side::Forward] {
        let embedding = Embedding::grunwald_letnikov(side, 0.6).unwrap();
        let disc = Discretisation::new(&Mixed, grid, embedding);
        let mut fft = FftOperator::new(disc.velocity_operator());
        let (mut system, _) = linearized(&disc, &mut fft, &curve(n));
        for q in [curve(n), shifted.clone(), shifted.clone()] {
            let mut eval = Evaluation::new(n);
            evaluate(&disc, &mut system, &q, 0, &mut eval).unwrap();
            system
                .linearize(&disc, &q, &eval.v, Location::Newton(0))
                .unwrap();
            assert!(system.preconditioner.correction.is_some());
            let m = n - 1;
            let mut p = DMatrix::<f64>::zeros(2 * m, 2 * m);
            let sigma = side.sign();
            for (i, k) in disc.velocity_operator().rows().enumerate() {
                let vv = *system.vv.get(i);
                let d = |j| {
                    disc.velocity_operator()
                        .row_entries(k)
                        .find(|&(jj, _)| jj == j)
                        .map_or(0.0, |(_, c)| -sigma * c)
                };
                for a in 1..n {
                    for b in 1..n {
                        let block = vv * (d(a) * d(b));
                        for (r, c) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                            p[(2 * (a - 1) + r, 2 * (b - 1) + c)] += block[(r, c)];
                        }
                    }
                }
            }
            let x: Vec<f64> = (0..2 * m).map(|i| (i as f64 * 0.37).cos()).collect();
            let px = &p * nalgebra::DVector::from_vec(x.clone());
            let mut z = vec![0.0; 2 * m];
            system.precondition(px.as_slice(), &mut z);
            for i in 0..2 * m {
                assert!(
                    (z[i] - x[i]).abs() < 1e-9,
                    "{side:?} {i}: {} vs {}",
                    z[i],
                    x[i]
                );
            }
        }
    }
}
