use varembed::lagrangian;

#[lagrangian]
struct Pendulum {
    g: f64,
}

fn main() {}
