use varembed::lagrangian;

fn spring(d: f64) -> f64 {
    0.5 * d * d
}

#[lagrangian]
fn oscillator(x: f64, v: f64) -> f64 {
    0.5 * v * v - spring(x)
}

fn main() {}
