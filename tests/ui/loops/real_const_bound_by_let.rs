use varembed::lagrangian;

/// A real constant written as a module const: the macro reads `UPPER_CASE` names as `usize`
/// consts, so it must be a parameter of the fn instead.
const G: f64 = 9.81;

#[lagrangian]
fn pendulum(x: f64, v: f64) -> f64 {
    let g = G;
    0.5 * v * v + g * x.cos()
}

fn main() {}
