use varembed::lagrangian;

const N: usize = 8;

/// A chain with fixed ends `x_{-1} = x_N = 0`, the left neighbour guarded by a branch.
#[lagrangian]
fn fixed(x: [f64; N], v: [f64; N]) -> f64 {
    let mut l = 0.0;
    for i in 0..N {
        let left = if i == 0 { 0.0 } else { x[i - 1] };
        l += 0.5 * v[i] * v[i] - 0.5 * (x[i] - left).powi(2);
    }
    l - 0.5 * x[N - 1].powi(2)
}

fn main() {}
