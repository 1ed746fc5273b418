use varembed::lagrangian;

#[lagrangian]
fn mutable(x: f64, v: f64) -> f64 {
    let mut e = 0.5 * v * v;
    e - x
}

fn main() {}
