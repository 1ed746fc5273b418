use varembed::lagrangian;

const N: usize = 8;

/// A sum that reads the loop variable around it is one value per iteration: it may be added,
/// multiplied or raised to a small power, but not taken the root of.
#[lagrangian]
fn speeds(x: [f64; N], v: [f64; N]) -> f64 {
    let mut l = 0.0;
    for k in 0..N {
        let speed2: f64 = (0..=k).map(|i| v[i] * v[i]).sum();
        l += speed2.sqrt() - x[k] * x[k];
    }
    l
}

fn main() {}
