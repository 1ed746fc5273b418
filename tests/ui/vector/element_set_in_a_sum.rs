use varembed::force;

const M: usize = 2;

#[force]
fn drag(x: [f64; 2], v: [f64; 2], c: f64) -> [f64; 2] {
    let mut f = [0.0; 2];
    for i in 0..M {
        f[i] = -c * v[i] + x[i];
    }
    f
}

fn main() {}
