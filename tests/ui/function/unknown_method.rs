use varembed::lagrangian;

#[lagrangian]
fn base2(x: f64, v: f64) -> f64 {
    0.5 * v * v + x.exp2()
}

fn main() {}
