use varembed::lagrangian;

#[lagrangian]
fn free<T>(x: f64, v: f64) -> f64 {
    x * v
}

fn main() {}
