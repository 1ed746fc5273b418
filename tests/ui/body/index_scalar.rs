use varembed::lagrangian;

#[lagrangian]
fn line(x: f64, v: f64) -> f64 {
    0.5 * v[0] * v + x
}

fn main() {}
