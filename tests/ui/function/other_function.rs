use varembed::lagrangian;

fn potential(x: f64) -> f64 {
    x * x
}

#[lagrangian]
fn oscillator(x: f64, v: f64) -> f64 {
    0.5 * v * v - potential(x)
}

fn main() {}
