//! Derived params in generated code: `derived.toml`'s `Params` holds the base param `r` only; the
//! rod `l = 4 r`, the offset `off = r / 2`, and the point's `gamma = asin(off / l)` and
//! `k = hypot(l, off) / l` are computed by the solvers from it, so setting `r` at run time moves
//! everything. Checked against the offset slider-crank's closed form written here.

use mechgen::{DynMechanism, DynState, InputMotion, SolveOptions};
use mechgen_odd_files::derived::offset_slider::{OffsetSlider, Params};

/// (q2, s, P) of the offset slider-crank with crank `r` at `q1`, on the branch with the rod
/// pointing along +x.
fn closed_form(r: f64, q1: f64) -> (f64, f64, [f64; 2]) {
    let (l, off) = (4.0 * r, r / 2.0);
    let q2 = ((off - r * q1.sin()) / l).asin();
    let s = r * q1.cos() + l * q2.cos();
    let (gamma, k) = ((off / l).asin(), l.hypot(off) / l);
    let p = [
        r * q1.cos() + k * l * (q2 - gamma).cos(),
        r * q1.sin() + k * l * (q2 - gamma).sin(),
    ];
    (q2, s, p)
}

fn sweep_against_closed_form(m: &OffsetSlider<f64>, r: f64) {
    let start = InputMotion::new(&[0.0][..], &[1.0], &[0.0]);
    let mut state = DynState::new(start, &[0.1, 4.9 * r], 1);
    for i in 0..=36 {
        let q1 = f64::from(i) * 10f64.to_radians();
        state.x[0] = q1;
        DynMechanism::solve_in_place(m, &mut state, &SolveOptions::default())
            .unwrap_or_else(|e| panic!("r = {r}, q1 = {q1}: {e}"));
        let (q, points) = (&state.q, &state.points);
        let (q2, s, p) = closed_form(r, q1);
        let tol = 1e-14;
        assert!(
            (q[0] - q2).abs() < tol,
            "r = {r}, q1 = {q1}: q2 {} vs {q2}",
            q[0]
        );
        assert!(
            (q[1] - s).abs() < tol * r,
            "r = {r}, q1 = {q1}: s {} vs {s}",
            q[1]
        );
        for (got, want) in points[0].position.iter().zip(p) {
            assert!((got - want).abs() < tol * r, "r = {r}: P {got} vs {want}");
        }
    }
}

#[test]
fn params_hold_the_base_params_only() {
    let info = mechgen_odd_files::derived::offset_slider::INFO;
    let names: Vec<&str> = info.params.iter().map(|p| p.name).collect();
    assert_eq!(names, ["r"]);
}

#[test]
fn derived_params_follow_a_base_param_changed_at_run_time() {
    sweep_against_closed_form(&OffsetSlider::default(), 0.05);
    let mut m = OffsetSlider::new(Params { r: 0.08 });
    sweep_against_closed_form(&m, 0.08);
    m.params.r = 0.03;
    sweep_against_closed_form(&m, 0.03);
}
