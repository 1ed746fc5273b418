use varembed::lagrangian;

const N: usize = 4;

#[lagrangian]
fn chain(x: [f64; N], v: [f64; N]) -> f64 {
    let mut l = 0.0;
    for i in 0..N {
        let a = [x[i], v[i]];
        l += a[i] * a[0];
    }
    l
}

fn main() {}
