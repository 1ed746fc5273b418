use varembed::force;

const N: usize = 2;

#[force]
fn drag(x: [f64; N], v: [f64; N], c: f64) -> [f64; N] {
    [-c * v[0] + x[1], -c * v[1]]
}

fn main() {}
