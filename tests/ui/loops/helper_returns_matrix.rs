use varembed::lagrangian;

#[lagrangian(helper)]
fn rotation(theta: f64) -> [[f64; 2]; 2] {
    let (s, c) = theta.sin_cos();
    [[c, -s], [s, c]]
}

fn main() {}
