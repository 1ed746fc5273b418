use varembed::lagrangian;

const N: usize = 8;

/// A condition on the loop variable as a number: it does not say which iterations read the
/// neighbour.
#[lagrangian]
fn fixed(x: [f64; N], v: [f64; N]) -> f64 {
    let mut l = 0.0;
    for i in 0..N {
        let left = if (i as f64) > 0.5 { x[i - 1] } else { 0.0 };
        l += 0.5 * v[i] * v[i] - 0.5 * (x[i] - left).powi(2);
    }
    l
}

fn main() {}
