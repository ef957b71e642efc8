//! Embedding the generated solvers in a simulation loop: no allocation, no panics, f64 or f32.
//! Run: `cargo run --release --example embed`

use mechgen::sixbar::{Inputs, Sixbar};
use mechgen::{InputMotion, SolveOptions};

fn main() {
    let mut mech = Sixbar::<f64>::default();
    mech.params.l1 = 26.5; // params can change at run time
    let options = SolveOptions::default();
    let (_, mut q) = Sixbar::<f64>::start();
    let omega = 1.0; // crank speed, rad/s
    for step in 0..=12 {
        let input = InputMotion {
            x: Inputs {
                q1: (step as f64 * 30.0).to_radians(),
            },
            xd: Inputs { q1: omega },
            xdd: Inputs { q1: 0.0 },
        };
        let x = input.x;
        match mech.solve(&input, &q, &options) {
            Ok(m) => {
                q = m.q; // the next guess: stays on this assembly branch
                let e = m.points.E;
                println!(
                    "q1 = {:5.1}°  q5 = {:8.3}°  E = ({:8.3}, {:8.3})  |E'| = {:7.3}  ({} Newton iterations)",
                    x.q1.to_degrees(),
                    m.q.q5.to_degrees().rem_euclid(360.0),
                    e.position[0],
                    e.position[1],
                    e.velocity[0].hypot(e.velocity[1]),
                    m.report.iterations
                );
            }
            Err(err) => println!("q1 = {:5.1}°: {err} ({})", x.q1.to_degrees(), err.status()),
        }
    }
}
