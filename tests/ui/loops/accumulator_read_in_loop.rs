use varembed::lagrangian;

const N: usize = 8;

#[lagrangian]
fn chain(x: [f64; N], v: [f64; N]) -> f64 {
    let mut l = 0.0;
    for i in 0..N {
        l += l * x[i] + 0.5 * v[i] * v[i];
    }
    l
}

fn main() {}
