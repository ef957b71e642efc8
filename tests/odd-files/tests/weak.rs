//! `weak.toml`: names that are Rust's weak keywords build and solve. The slider-crank
//! `macro_rules·e(raw) + union_rod·e(safe) = s` against its closed form
//! s = r cos θ + √(l² − r² sin² θ), sin(safe) = −r sin θ / l, and the point at the crank's end.

use mechgen::{DynMechanism, DynState, InputMotion, SolveOptions};
use mechgen_odd_files::weak::union::{Params, Union};

#[test]
fn weak_keywords_are_names_that_solve() {
    let m = Union::<f64>::new(Params {
        macro_rules: 0.1,
        union_rod: 0.35,
    });
    let (r, l) = (0.1f64, 0.35f64);
    let start = InputMotion::new(&[0.0][..], &[1.0], &[0.0]);
    let mut state = DynState::new(start, &[0.0, 0.45], 1);
    for i in 0..=36 {
        let th = f64::from(i) * 10f64.to_radians();
        state.x[0] = th;
        DynMechanism::solve_in_place(&m, &mut state, &SolveOptions::default())
            .unwrap_or_else(|e| panic!("at {th}: {e}"));
        let s = r * th.cos() + (l * l - r * r * th.sin().powi(2)).sqrt();
        let safe = (-r * th.sin() / l).asin();
        assert!((state.q[1] - s).abs() < 1e-15, "s {} vs {s}", state.q[1]);
        assert!(
            (state.q[0] - safe).abs() < 1e-14,
            "safe {} vs {safe}",
            state.q[0]
        );
        let p = state.points[0].position;
        assert!((p[0] - r * th.cos()).abs() < 1e-16 && (p[1] - r * th.sin()).abs() < 1e-16);
    }
}
