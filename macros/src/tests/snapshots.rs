//! Expansion snapshots: the pretty-printed output for three models, a force and a constraint,
//! so that a change to the emitted code shows in review.

use proc_macro2::TokenStream;
use quote::quote;

use super::{double_pendulum_item, kepler_item, pendulum_item};
use crate::expand::expand_as;
use crate::ir::Attr;

fn pretty(ts: TokenStream) -> String {
    let file: syn::File = syn::parse2(ts).expect("the expansion is a valid file");
    prettyplease::unparse(&file)
}

/// Compares the pretty-printed expansion of `item` with `macros/tests/expand/<name>.expanded.rs`;
/// with `UPDATE_EXPAND=1` rewrites the file first (review the diff).
pub(super) fn check_snapshot(name: &str, item: TokenStream) {
    check_snapshot_as(name, Attr::Lagrangian, item);
}

/// [`check_snapshot`] of a fn under the attribute `attr`.
fn check_snapshot_as(name: &str, attr: Attr, item: TokenStream) {
    let out = pretty(expand_as(attr, quote!(), item).expect("the model expands"));
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(format!("tests/expand/{name}.expanded.rs"));
    if std::env::var_os("UPDATE_EXPAND").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, &out).unwrap();
    }
    let expected = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e}; run with UPDATE_EXPAND=1", path.display()));
    assert!(
        out == expected,
        "the expansion of {name} changed; run with UPDATE_EXPAND=1 and review the diff.\n{out}"
    );
}

/// The pendulum's generated code (d = 1, model constants as fields, a zero `xv` block).
#[test]
fn pendulum_expansion_snapshot() {
    check_snapshot("pendulum", pendulum_item());
}

/// The double pendulum's generated code (d = 2, shared temporaries, symmetric blocks).
#[test]
fn double_pendulum_expansion_snapshot() {
    check_snapshot("double_pendulum", double_pendulum_item());
}

/// Kepler's generated code: a unit struct, a constant `L_vv = I` (its `hessian_dependence`
/// depends on nothing, so core's variational steps are closed-form).
#[test]
fn kepler_expansion_snapshot() {
    check_snapshot("kepler", kepler_item());
}

/// A force's generated code: `∂f/∂x` not symmetric, `∂f/∂v` reading `v`, temporaries shared
/// by the entries of the Jacobian, a `jacobian_dependence` per block.
#[test]
fn force_expansion_snapshot() {
    check_snapshot_as(
        "drag_force",
        Attr::Force,
        quote! {
            /// Quadratic drag and a turning spring.
            fn drag(x: [f64; 2], v: [f64; 2], c: f64, w: f64) -> [f64; 2] {
                let speed = v[0].hypot(v[1]);
                [-c * speed * v[0] - w * x[1], -c * speed * v[1] + w * x[0]]
            }
        },
    );
}

/// A constraint's generated code: `G` row by row, `Σ_k λ_k ∂²g_k/∂x²` written once for
/// `i ≤ j` and mirrored.
#[test]
fn constraint_expansion_snapshot() {
    check_snapshot_as(
        "rods_constraint",
        Attr::Constraint,
        quote! {
            /// Two rods from the origin and between the points.
            fn rods(x: [f64; 4], a: f64, b: f64) -> [f64; 2] {
                let d = [x[2] - x[0], x[3] - x[1]];
                [x[0] * x[0] + x[1] * x[1] - a * a, d[0] * d[0] + d[1] * d[1] - b * b]
            }
        },
    );
}

/// A force over a named dimension: its virtual work's terms scattered by a loop into `f`,
/// `jx`, `jv` (`Force<N>`) and into a `SparseForceJacobian` (`DynForce`), with the declared
/// band.
#[test]
fn looped_force_expansion_snapshot() {
    check_snapshot_as(
        "dashpots_force",
        Attr::Force,
        quote! {
            /// Dashpots and cubic springs between neighbours.
            fn dashpots(x: [f64; N], v: [f64; N], c: f64, k: f64) -> [f64; N] {
                let mut f = [0.0; N];
                for i in 0..N - 1 {
                    let d = c * (v[i + 1] - v[i]) + k * (x[i + 1] - x[i]).powi(3);
                    f[i] += d;
                    f[i + 1] -= d;
                }
                f
            }
        },
    );
}

/// A force on slices: `DynForce` alone, with the run-time index checks of its dimension.
#[test]
fn slice_force_expansion_snapshot() {
    check_snapshot_as(
        "ring_drag_force",
        Attr::Force,
        quote! {
            /// Drag on each particle of a ring, against its next neighbour's velocity.
            fn ring_drag(x: &[f64], v: &[f64], n: usize, c: f64) -> Vec<f64> {
                let mut f = vec![0.0; n];
                for i in 0..n {
                    f[i] -= c * x[i] * (v[i] - v[(i + 1) % n]);
                }
                f
            }
        },
    );
}
