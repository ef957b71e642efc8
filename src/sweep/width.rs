//! How many param sets a batch sweeps side by side in SIMD lanes ([`lane_width_for`]): the
//! CPU's widest vectors (`Isa::f64_lanes_for`: eight f64 lanes with AVX-512, four otherwise, and
//! four for a mechanism of many unknowns), or what the environment variable `MECHGEN_LANES`
//! asks for (`1`: no lanes, every set by the scalar sweep; `4`; `8`). Every width gives the same
//! rows bit for bit (a lane's rows are its scalar sweep's); only the time differs. Part of
//! [`crate::sweep`].

use std::sync::OnceLock;

use mechgen_runtime::simd::Isa;

/// The environment variable that sets the lane width of every batch of the process, read once.
pub const LANES_VAR: &str = "MECHGEN_LANES";

/// The sets a batch should hand [`super::sweep_sets_in_lanes`] at a time on this CPU for a
/// mechanism of few unknowns ([`Isa::f64_lanes`]: eight with AVX-512, four with AVX2 or less,
/// where eight lanes take two or four registers each and run slower per set than four), unless
/// `MECHGEN_LANES` says otherwise.
pub fn lane_width() -> usize {
    lane_width_for(0)
}

/// The sets a batch of a mechanism with `unknowns` unknowns should hand
/// [`super::sweep_sets_in_lanes`] at a time on this CPU ([`Isa::f64_lanes_for`]), or the width
/// `MECHGEN_LANES` names (1, 4 or 8; any other value is ignored). 1: no lanes.
pub fn lane_width_for(unknowns: usize) -> usize {
    static CHOSEN: OnceLock<Option<usize>> = OnceLock::new();
    let chosen = CHOSEN.get_or_init(|| std::env::var(LANES_VAR).ok().and_then(|v| parse(&v)));
    chosen.unwrap_or_else(|| Isa::widest().f64_lanes_for(unknowns))
}

/// A lane width as `MECHGEN_LANES` gives it: `1`, `4` or `8` (spaces around it allowed).
fn parse(value: &str) -> Option<usize> {
    match value.trim() {
        "1" => Some(1),
        "4" => Some(4),
        "8" => Some(8),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mechgen_runtime::simd::EIGHT_LANES_UP_TO;

    #[test]
    fn the_variable_names_one_of_the_widths_a_batch_runs() {
        assert_eq!(parse("1"), Some(1));
        assert_eq!(parse(" 4\n"), Some(4));
        assert_eq!(parse("8"), Some(8));
        for bad in ["", "0", "2", "16", "eight", "-4", "4.0"] {
            assert_eq!(parse(bad), None, "{bad:?}");
        }
    }

    #[test]
    fn many_unknowns_take_four_lanes_few_the_widest() {
        assert_eq!(Isa::Avx512.f64_lanes_for(2), 8);
        assert_eq!(Isa::Avx512.f64_lanes_for(EIGHT_LANES_UP_TO), 8);
        assert_eq!(Isa::Avx512.f64_lanes_for(EIGHT_LANES_UP_TO + 1), 4);
        assert_eq!(Isa::Avx512.f64_lanes_for(10), 4);
        for isa in [Isa::Avx2, Isa::Baseline] {
            assert_eq!(isa.f64_lanes_for(2), 4);
            assert_eq!(isa.f64_lanes_for(10), 4);
        }
    }

    #[test]
    fn a_width_is_one_a_batch_can_run() {
        for unknowns in [0, 2, 4, 10, 100] {
            assert!([1, 4, 8].contains(&lane_width_for(unknowns)));
        }
    }
}
