use varembed::lagrangian;

#[lagrangian]
fn power(x: f64, v: f64, n: f64) -> f64 {
    0.5 * v * v - x.powi(n as i32)
}

fn main() {}
