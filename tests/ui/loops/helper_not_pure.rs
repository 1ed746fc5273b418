use varembed::lagrangian;

static SCALE: f64 = 2.0;

#[lagrangian(helper)]
fn spring(d: f64) -> f64 {
    println!("{d}");
    SCALE * d * d
}

#[lagrangian]
fn oscillator(x: f64, v: f64) -> f64 {
    0.5 * v * v - spring(x)
}

fn main() {}
