use varembed::lagrangian;

const N: usize = 8;

#[lagrangian]
fn chain(x: [f64; N], v: [f64; N]) -> f64 {
    let mut l = 1.0;
    for i in 0..N {
        l *= x[i] + v[i];
    }
    l
}

fn main() {}
