use varembed::force;

const N: usize = 4;

#[force]
fn drag(x: [f64; N], v: [f64; N], c: f64) -> [f64; N] {
    let mut f = [0.0; N];
    for i in 0..N {
        f[i] = -c * v[i] * x[i];
    }
    f
}

fn main() {}
