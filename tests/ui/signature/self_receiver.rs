use varembed::lagrangian;

struct Model;

impl Model {
    #[lagrangian]
    fn energy(&self, x: f64, v: f64) -> f64 {
        0.5 * v * v - x
    }
}

fn main() {}
