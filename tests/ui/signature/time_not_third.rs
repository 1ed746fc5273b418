use varembed::lagrangian;

#[lagrangian]
fn driven(x: f64, v: f64, k: f64, t: f64) -> f64 {
    0.5 * v * v - k * x * t.cos()
}

fn main() {}
