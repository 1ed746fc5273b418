use varembed::lagrangian;

#[lagrangian]
fn arity(x: f64, v: f64) -> f64 {
    0.5 * v * v - x.hypot()
}

fn main() {}
