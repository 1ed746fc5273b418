use varembed::lagrangian;

#[lagrangian(helper)]
fn series(d: f64) -> f64 {
    1.0 + d * series(d)
}

#[lagrangian]
fn oscillator(x: f64, v: f64) -> f64 {
    0.5 * v * v - series(x)
}

fn main() {}
