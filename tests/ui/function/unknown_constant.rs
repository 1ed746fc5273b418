use varembed::lagrangian;

#[lagrangian]
fn golden(x: f64, v: f64) -> f64 {
    0.5 * v * v + std::f64::consts::PHI * x
}

fn main() {}
