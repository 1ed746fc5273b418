use varembed::lagrangian;

const N: usize = 8;

/// The second neighbour to the left, guarded as if it were the first.
#[lagrangian]
fn fixed(x: [f64; N], v: [f64; N]) -> f64 {
    let mut l = 0.0;
    for i in 0..N {
        let left = if i == 0 { 0.0 } else { x[i - 2] };
        l += 0.5 * v[i] * v[i] - 0.5 * (x[i] - left).powi(2);
    }
    l - 0.5 * x[N - 1].powi(2)
}

fn main() {}
