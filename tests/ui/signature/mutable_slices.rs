use varembed::lagrangian;

#[lagrangian]
fn chain(x: &mut [f64], v: &mut [f64], n: usize) -> f64 {
    (0..n).map(|i| 0.5 * v[i] * v[i] - x[i] * x[i]).sum()
}

fn main() {}
