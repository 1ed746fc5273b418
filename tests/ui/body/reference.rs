use varembed::lagrangian;

#[lagrangian]
fn borrowed(x: f64, v: f64) -> f64 {
    0.5 * v * v - (&x).cos()
}

fn main() {}
