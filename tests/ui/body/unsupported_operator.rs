use varembed::lagrangian;

#[lagrangian]
fn modulo(x: f64, v: f64) -> f64 {
    0.5 * v * v + x % 2.0
}

fn main() {}
