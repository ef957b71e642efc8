//! Design derivatives (dq/dp, dP/dp) of every compiled-in mechanism on both engines, against
//! each other and against Richardson-extrapolated differences of the position solve.

mod common;

use common::sensitivity::check_sensitivities;

#[test]
fn sensitivities_equal_differences_of_the_position_solve_on_both_engines() {
    let (fails, compared) = check_sensitivities();
    assert!(fails.is_empty(), "{}", fails.join("\n"));
    assert!(
        compared >= 2 * mechgen::MECHANISMS.len(),
        "only {compared} rows compared"
    );
}

/// A tick's sensitivities, from the sines and cosines it keeps, equal a fresh computation at its
/// state (1e-12 relative to each matrix's largest entry), every 7th of 200 ticks of every
/// compiled-in mechanism; after a change of params they are computed afresh.
#[test]
fn tick_sensitivities_equal_sensitivities_at_the_ticks_state() {
    use mechgen::{Array, InputMotion, RowMajor, SolveOptions, StaticMechanism, StaticVisitor};
    struct Ticks(Vec<String>, usize);
    impl StaticVisitor<f64> for Ticks {
        fn visit<M: StaticMechanism<f64> + 'static>(&mut self, m: &M) {
            let info = m.info();
            let x0: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
            let q0: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
            let mut x = M::X::zeros();
            x.as_mut().copy_from_slice(&x0);
            let mut q = M::Q::zeros();
            q.as_mut().copy_from_slice(&q0);
            let mut xd = M::X::zeros();
            xd.as_mut()[0] = 1.0;
            let input = |x: M::X| InputMotion::new(x, xd, M::X::zeros());
            let options = SolveOptions::default();
            let Ok(mut t) = m.tick_start(&input(x), &q, &options) else {
                self.0.push(format!("{}: no start", M::NAME));
                return;
            };
            for i in 1..200 {
                x.as_mut()[0] = x0[0] + f64::from(i) * 1e-3;
                if m.tick(&mut t, &input(x), &options).is_err() {
                    break;
                }
                if i % 7 != 0 {
                    continue;
                }
                let (a, b) = (m.tick_sensitivities(&t), m.sensitivities(&t.x, &t.q));
                let (Ok(a), Ok(b)) = (a, b) else {
                    self.0.push(format!("{} tick {i}: failed", M::NAME));
                    continue;
                };
                self.1 += 1;
                let npar = info.params.len();
                let sizes = [info.unknowns.len() * npar, 2 * info.points.len() * npar];
                let mut pairs = sizes.map(|n| (vec![0.0; n], vec![0.0; n]));
                a.unknowns.write_row_major(&mut pairs[0].0).unwrap();
                b.unknowns.write_row_major(&mut pairs[0].1).unwrap();
                a.points.write_row_major(&mut pairs[1].0).unwrap();
                b.points.write_row_major(&mut pairs[1].1).unwrap();
                for (u, v) in &pairs {
                    let big = v.iter().fold(1e-3f64, |m, e| m.max(e.abs()));
                    if u.iter().zip(v).any(|(a, b)| (a - b).abs() > 1e-12 * big) {
                        self.0.push(format!("{} tick {i}: {u:?} vs {v:?}", M::NAME));
                    }
                }
            }
        }
    }
    let mut v = Ticks(Vec::new(), 0);
    mechgen::visit_all(&mut v);
    assert!(v.0.is_empty(), "{}", v.0.join("\n"));
    assert!(v.1 >= 20, "only {} ticks compared", v.1);
}
