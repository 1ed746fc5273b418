use varembed::lagrangian;

#[lagrangian]
fn base2(x: f64, v: f64) -> f64 {
    0.5 * v * v + f64::exp2(x)
}

fn main() {}
