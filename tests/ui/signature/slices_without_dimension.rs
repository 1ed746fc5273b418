use varembed::lagrangian;

#[lagrangian]
fn chain(x: &[f64], v: &[f64], k: f64) -> f64 {
    0.5 * v[0] * v[0] - k * x[0] * x[0]
}

fn main() {}
