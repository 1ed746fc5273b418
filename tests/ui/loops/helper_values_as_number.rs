use varembed::lagrangian;

#[lagrangian(helper)]
fn polar(r: f64, theta: f64) -> (f64, f64) {
    (r * theta.cos(), r * theta.sin())
}

#[lagrangian]
fn particle(x: [f64; 2], v: [f64; 2]) -> f64 {
    0.5 * (v[0] * v[0] + v[1] * v[1]) - polar(x[0], x[1]) * 2.0
}

fn main() {}
