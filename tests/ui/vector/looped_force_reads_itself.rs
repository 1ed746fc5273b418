use varembed::force;

const N: usize = 4;

#[force]
fn chain(x: [f64; N], v: [f64; N], c: f64) -> [f64; N] {
    let mut f = [0.0; N];
    for i in 1..N {
        f[i] += c * x[i] * v[i] + f[i - 1];
    }
    f
}

fn main() {}
