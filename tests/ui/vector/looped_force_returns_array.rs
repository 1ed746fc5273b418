use varembed::force;

#[force]
fn drag(x: &[f64], v: &[f64], n: usize, c: f64) -> [f64; 3] {
    let mut f = vec![0.0; n];
    for i in 0..n {
        f[i] -= c * v[i] * x[i];
    }
    f
}

fn main() {}
