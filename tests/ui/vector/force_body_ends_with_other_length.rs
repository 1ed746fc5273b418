use varembed::force;

#[force]
fn drag(x: [f64; 2], v: [f64; 2], c: f64) -> [f64; 2] {
    [-c * v[0], -c * v[1], x[0]]
}

fn main() {}
