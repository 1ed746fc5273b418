//! `#[force]` with loops, over a named dimension `[f64; N]` and over slices: each force is
//! written three times, with loops over `N` (a `Force<N>` and a `DynForce`), on slices with a
//! run-time `n` (a `DynForce`), and over the literal dimension 7 with its loops unrolled (the
//! entry-by-entry path, which shares no code with the loop path after the parse). At 100
//! generated points each, the three give the same force and Jacobian, and the Jacobian
//! matches central differences of the generated force; the declared band holds every entry;
//! `jacobian_dependence` is the unrolled form's; `invalid_dimension` names a wrong dimension
//! and an index out of range.

#![allow(
    dead_code,
    reason = "the #[force] fns stay callable, but these tests use the generated structs"
)]
#![allow(
    clippy::needless_range_loop,
    reason = "the loop forms the macro accepts, written as the docs show them"
)]

use varembed::{DynForce, Force, SparseForceJacobian, Vector, force};
use varembed_tests::rng::Rng;

const N: usize = 7;

/// Points per force.
const POINTS: usize = 100;

// Dashpots and cubic springs between neighbours: the scatter form, each link adding to both
// of its ends; band 1.

#[force]
fn links(x: [f64; N], v: [f64; N], c: f64, k: f64) -> [f64; N] {
    let mut f = [0.0; N];
    for i in 0..N - 1 {
        let d = c * (v[i + 1] - v[i]) + k * (x[i + 1] - x[i]).powi(3);
        f[i] += d;
        f[i + 1] -= d;
    }
    f
}

#[force]
fn links_dyn(x: &[f64], v: &[f64], n: usize, c: f64, k: f64) -> Vec<f64> {
    let mut f = vec![0.0; n];
    for i in 0..n - 1 {
        let d = c * (v[i + 1] - v[i]) + k * (x[i + 1] - x[i]).powi(3);
        f[i] += d;
        f[i + 1] -= d;
    }
    f
}

#[force]
fn links_7(x: [f64; 7], v: [f64; 7], c: f64, k: f64) -> [f64; 7] {
    let mut f = [0.0; 7];
    for i in 0..6 {
        let d = c * (v[i + 1] - v[i]) + k * (x[i + 1] - x[i]).powi(3);
        f[i] += d;
        f[i + 1] -= d;
    }
    f
}

// A ring: drag against the next site's velocity (a periodic index), a drive in time on the
// first and last sites, quadratic drag on every site; no band.

#[force]
fn ring(x: [f64; N], v: [f64; N], t: f64, c: f64, a: f64) -> [f64; N] {
    let mut f = [0.0; N];
    for i in 0..N {
        f[i] -= c * (1.0 + x[i] * x[i]) * (v[i] - v[(i + 1) % N]);
        f[i] -= 0.3 * v[i] * v[i].abs();
    }
    f[0] += a * (2.0 * t).sin();
    f[N - 1] -= a * x[N - 1] * t.cos();
    f
}

#[force]
fn ring_dyn(x: &[f64], v: &[f64], t: f64, n: usize, c: f64, a: f64) -> Vec<f64> {
    let mut f = vec![0.0; n];
    for i in 0..n {
        f[i] -= c * (1.0 + x[i] * x[i]) * (v[i] - v[(i + 1) % n]);
        f[i] -= 0.3 * v[i] * v[i].abs();
    }
    f[0] += a * (2.0 * t).sin();
    f[n - 1] -= a * x[n - 1] * t.cos();
    f
}

#[force]
fn ring_7(x: [f64; 7], v: [f64; 7], t: f64, c: f64, a: f64) -> [f64; 7] {
    let mut f = [0.0; 7];
    for i in 0..7 {
        f[i] -= c * (1.0 + x[i] * x[i]) * (v[i] - v[(i + 1) % 7]);
        f[i] -= 0.3 * v[i] * v[i].abs();
    }
    f[0] += a * (2.0 * t).sin();
    f[6] -= a * x[6] * t.cos();
    f
}

// A guarded read (`x[i - 1]` where `i > 0`), a mean field (a sum bound to a local, divided by
// `N`: a dense Jacobian) and a pairwise coupling (a double loop).

#[force]
fn field(x: [f64; N], v: [f64; N], c: f64, k: f64) -> [f64; N] {
    let mean = (0..N).map(|j| x[j]).sum::<f64>() / N as f64;
    let mut f = [0.0; N];
    for i in 0..N {
        f[i] += if i > 0 { c * x[i - 1] * v[i] } else { 0.0 };
        f[i] -= k * (x[i] - mean) * (x[i] - mean) * v[i];
        for j in 0..N {
            f[i] += 0.1 * k * (x[j] - x[i]).sin();
        }
    }
    f
}

#[force]
fn field_dyn(x: &[f64], v: &[f64], n: usize, c: f64, k: f64) -> Vec<f64> {
    let mean = (0..n).map(|j| x[j]).sum::<f64>() / n as f64;
    let mut f = vec![0.0; n];
    for i in 0..n {
        f[i] += if i > 0 { c * x[i - 1] * v[i] } else { 0.0 };
        f[i] -= k * (x[i] - mean) * (x[i] - mean) * v[i];
        for j in 0..n {
            f[i] += 0.1 * k * (x[j] - x[i]).sin();
        }
    }
    f
}

#[force]
fn field_7(x: [f64; 7], v: [f64; 7], c: f64, k: f64) -> [f64; 7] {
    let mean = (x[0] + x[1] + x[2] + x[3] + x[4] + x[5] + x[6]) / 7.0;
    let mut f = [0.0; 7];
    for i in 1..7 {
        f[i] += c * x[i - 1] * v[i];
    }
    for i in 0..7 {
        f[i] -= k * (x[i] - mean) * (x[i] - mean) * v[i];
        for j in 0..7 {
            f[i] += 0.1 * k * (x[j] - x[i]).sin();
        }
    }
    f
}

// Negated components inside branches and `max`: their zero derivatives are signed zeros,
// which once left a weight of the virtual work in the generated code (a compile-time panic).

#[force]
fn clipped(x: [f64; N], v: [f64; N], c: f64) -> [f64; N] {
    let mut f = [0.0; N];
    for i in 0..N {
        f[i] += if x[i] > 0.0 { -x[i] } else { 0.0 };
        f[i] += c * (-x[i]).max(0.2) * v[i];
    }
    f[0] += if x[0] > 0.0 { x[0] * -x[0] } else { -v[0] };
    f
}

#[force]
fn clipped_dyn(x: &[f64], v: &[f64], n: usize, c: f64) -> Vec<f64> {
    let mut f = vec![0.0; n];
    for i in 0..n {
        f[i] += if x[i] > 0.0 { -x[i] } else { 0.0 };
        f[i] += c * (-x[i]).max(0.2) * v[i];
    }
    f[0] += if x[0] > 0.0 { x[0] * -x[0] } else { -v[0] };
    f
}

#[force]
fn clipped_7(x: [f64; 7], v: [f64; 7], c: f64) -> [f64; 7] {
    let mut f = [0.0; 7];
    for i in 0..7 {
        f[i] += if x[i] > 0.0 { -x[i] } else { 0.0 };
        f[i] += c * (-x[i]).max(0.2) * v[i];
    }
    f[0] += if x[0] > 0.0 { x[0] * -x[0] } else { -v[0] };
    f
}

/// A force in its three forms, evaluated at one point.
struct Forms<'a> {
    name: &'static str,
    named: &'a dyn Force<N>,
    named_dyn: &'a dyn DynForce,
    slices: &'a dyn DynForce,
    unrolled: &'a dyn Force<7>,
}

/// The force and its Jacobian blocks of a `DynForce` at a point, as dense arrays.
fn run_time(
    f: &dyn DynForce,
    x: &[f64],
    v: &[f64],
    t: f64,
) -> (Vec<f64>, Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let mut force = vec![0.0; N];
    f.add_force(x, v, t, &mut force);
    let mut out = SparseForceJacobian::new(N);
    f.jacobian(x, v, t, &mut out);
    let dense = |b: &varembed::SparseBlock| {
        (0..N)
            .map(|i| (0..N).map(|j| b.get(i, j)).collect())
            .collect::<Vec<Vec<f64>>>()
    };
    (force, dense(&out.x), dense(&out.v))
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / (1.0 + a.abs().max(b.abs()))
}

fn check(forms: &Forms<'_>, seed: u64) {
    let mut rng = Rng(seed);
    for point in 0..POINTS {
        let (x, v): (Vector<N>, Vector<N>) = (rng.vector(1.5), rng.vector(1.5));
        let t = rng.uniform(-3.0, 3.0);
        let (x7, v7) = (
            Vector::<7>::from_fn(|i, _| x[i]),
            Vector::<7>::from_fn(|i, _| v[i]),
        );
        let name = forms.name;
        let f = forms.named.force(&x, &v, t);
        let j = forms.named.jacobian(&x, &v, t);
        let f7 = forms.unrolled.force(&x7, &v7, t);
        let j7 = forms.unrolled.jacobian(&x7, &v7, t);
        for i in 0..N {
            assert!(
                relative(f[i], f7[i]) <= 1e-13,
                "{name} point {point}: f[{i}] {} against {}",
                f[i],
                f7[i]
            );
            for k in 0..N {
                for (block, a, b) in [
                    ("x", j.x[(i, k)], j7.x[(i, k)]),
                    ("v", j.v[(i, k)], j7.v[(i, k)]),
                ] {
                    assert!(
                        relative(a, b) <= 1e-13,
                        "{name} point {point}: ∂f[{i}]/∂{block}[{k}] {a} against {b}"
                    );
                }
            }
        }
        // The run-time impls: the same loops on slices, bit for bit.
        for (which, dynamic) in [("named", forms.named_dyn), ("slices", forms.slices)] {
            let (fd, jx, jv) = run_time(dynamic, x.as_slice(), v.as_slice(), t);
            for i in 0..N {
                assert_eq!(fd[i], f[i], "{name} {which} point {point}: f[{i}]");
                for k in 0..N {
                    assert_eq!(
                        jx[i][k],
                        j.x[(i, k)],
                        "{name} {which} point {point}: ∂f[{i}]/∂x[{k}]"
                    );
                    assert_eq!(
                        jv[i][k],
                        j.v[(i, k)],
                        "{name} {which} point {point}: ∂f[{i}]/∂v[{k}]"
                    );
                }
            }
            if let Some(b) = dynamic.bandwidth() {
                for i in 0..N {
                    for k in 0..N {
                        if i.abs_diff(k) > b {
                            assert_eq!(
                                (jx[i][k], jv[i][k]),
                                (0.0, 0.0),
                                "{name} {which}: ({i}, {k}) outside band {b}"
                            );
                        }
                    }
                }
            }
        }
        // Central differences of the generated force, column by column.
        let h = 1e-6;
        for k in 0..N {
            for (block, dir) in [("x", 0), ("v", 1)] {
                let (mut xp, mut vp, mut xm, mut vm) = (x, v, x, v);
                if dir == 0 {
                    xp[k] += h;
                    xm[k] -= h;
                } else {
                    vp[k] += h;
                    vm[k] -= h;
                }
                let (fp, fm) = (
                    forms.named.force(&xp, &vp, t),
                    forms.named.force(&xm, &vm, t),
                );
                for i in 0..N {
                    let fd = (fp[i] - fm[i]) / (2.0 * h);
                    let exact = if dir == 0 { j.x[(i, k)] } else { j.v[(i, k)] };
                    // `|v|` is not differentiable at 0: no point lands within `h` of it.
                    assert!(
                        (fd - exact).abs() <= 1e-6 * (1.0 + exact.abs()),
                        "{name} point {point}: ∂f[{i}]/∂{block}[{k}] {exact} against differences {fd}"
                    );
                }
            }
        }
    }
    assert_eq!(
        forms.named.jacobian_dependence(),
        forms.unrolled.jacobian_dependence(),
        "{}",
        forms.name
    );
    assert_eq!(
        forms.named_dyn.jacobian_dependence(),
        forms.unrolled.jacobian_dependence(),
        "{}",
        forms.name
    );
    assert_eq!(
        forms.slices.jacobian_dependence(),
        forms.unrolled.jacobian_dependence(),
        "{}",
        forms.name
    );
}

#[test]
fn neighbour_links_agree_in_their_three_forms_and_with_differences() {
    let (c, k) = (0.7, 1.3);
    check(
        &Forms {
            name: "links",
            named: &Links { c, k },
            named_dyn: &Links { c, k },
            slices: &LinksDyn { n: N, c, k },
            unrolled: &Links7 { c, k },
        },
        1,
    );
    assert_eq!(DynForce::bandwidth(&Links { c, k }), Some(1));
    assert_eq!(LinksDyn { n: N, c, k }.bandwidth(), Some(1));
}

#[test]
fn a_driven_ring_agrees_in_its_three_forms_and_with_differences() {
    let (c, a) = (0.4, 2.0);
    check(
        &Forms {
            name: "ring",
            named: &Ring { c, a },
            named_dyn: &Ring { c, a },
            slices: &RingDyn { n: N, c, a },
            unrolled: &Ring7 { c, a },
        },
        2,
    );
    // A periodic index claims no band.
    assert_eq!(RingDyn { n: N, c, a }.bandwidth(), None);
}

#[test]
fn a_mean_field_with_pairwise_coupling_agrees_in_its_three_forms_and_with_differences() {
    let (c, k) = (0.9, 0.6);
    check(
        &Forms {
            name: "field",
            named: &Field { c, k },
            named_dyn: &Field { c, k },
            slices: &FieldDyn { n: N, c, k },
            unrolled: &Field7 { c, k },
        },
        3,
    );
    // A double loop over two variables claims no band.
    assert_eq!(FieldDyn { n: N, c, k }.bandwidth(), None);
}

#[test]
fn negated_components_in_branches_agree_in_their_three_forms_and_with_differences() {
    let c = 0.8;
    check(
        &Forms {
            name: "clipped",
            named: &Clipped { c },
            named_dyn: &Clipped { c },
            slices: &ClippedDyn { n: N, c },
            unrolled: &Clipped7 { c },
        },
        4,
    );
    assert_eq!(ClippedDyn { n: N, c }.bandwidth(), Some(0));
}

#[test]
fn a_force_names_a_wrong_dimension_and_an_index_out_of_range() {
    let links = LinksDyn {
        n: 5,
        c: 1.0,
        k: 1.0,
    };
    assert_eq!(links.invalid_dimension(5), None);
    let wrong = links.invalid_dimension(6).expect("5 against 6");
    assert!(
        wrong.contains("dimension 5") && wrong.contains("6"),
        "{wrong}"
    );
    assert!(DynForce::invalid_dimension(&Links { c: 1.0, k: 1.0 }, N - 1).is_some());
    // `0..n - 1` does not exist at `n = 0`.
    let empty = LinksDyn {
        n: 0,
        c: 1.0,
        k: 1.0,
    }
    .invalid_dimension(0)
    .expect("n = 0");
    assert!(
        empty.contains("links_dyn") && empty.contains("n = 0"),
        "{empty}"
    );
    // The ring reads `f[n - 1]`, `x[n - 1]`: at `n = 0` there is no such component.
    let ring = RingDyn {
        n: 0,
        c: 1.0,
        a: 1.0,
    }
    .invalid_dimension(0)
    .expect("n = 0");
    assert!(ring.contains("ring_dyn"), "{ring}");
    assert_eq!(
        RingDyn {
            n: 1,
            c: 1.0,
            a: 1.0
        }
        .invalid_dimension(1),
        None
    );
}

#[test]
fn the_derivatives_text_lists_components_and_entries_by_loop() {
    let text = Links::DERIVATIVES;
    assert!(text.contains("for i in 0..N - 1: f[i + 1] += "), "{text}");
    assert!(text.contains("∂f[i]/∂v[i + 1] += c"), "{text}");
    assert_eq!(
        Force::constants(&Links { c: 2.0, k: 3.0 }),
        vec![("c", 2.0), ("k", 3.0)]
    );
    assert_eq!(
        DynForce::constants(&RingDyn {
            n: 4,
            c: 2.0,
            a: 3.0
        }),
        vec![("c", 2.0), ("a", 3.0)]
    );
}
