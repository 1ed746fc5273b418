use varembed::lagrangian;

struct Params {
    k: f64,
}

const P: Params = Params { k: 2.0 };

#[lagrangian]
fn spring(x: f64, v: f64) -> f64 {
    0.5 * v * v - 0.5 * P.k * x * x
}

fn main() {}
