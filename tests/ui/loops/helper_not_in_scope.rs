use varembed::lagrangian;

mod springs {
    use varembed::lagrangian;

    #[lagrangian(helper)]
    pub fn spring(d: f64) -> f64 {
        0.5 * d * d
    }
}

// The fn is imported, its relay is not: `use springs::*;` would bring both.
use springs::spring;

#[lagrangian]
fn oscillator(x: f64, v: f64) -> f64 {
    0.5 * v * v - spring(x)
}

fn main() {}
