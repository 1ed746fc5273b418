use varembed::lagrangian;

#[lagrangian]
fn unit(x: f64, v: f64) -> f64 {
    let e = 0.5 * v * v - x;
    return e;
}

fn main() {}
