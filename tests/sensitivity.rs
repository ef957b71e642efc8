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
