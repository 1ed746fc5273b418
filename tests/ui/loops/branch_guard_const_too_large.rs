use varembed::lagrangian;

const N: usize = 5;
const M: usize = 5;

/// `x[i + 1]` guarded by `i < M`: in range only if `M < N`, which the compiler checks.
#[lagrangian]
fn first_bonds(x: [f64; N], v: [f64; N]) -> f64 {
    let mut l = 0.0;
    for i in 0..N {
        let right = if i < M { x[i + 1] } else { x[i] };
        l += 0.5 * v[i] * v[i] - 0.5 * (right - x[i]).powi(2);
    }
    l
}

fn main() {}
