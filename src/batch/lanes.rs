//! Param sets of a compiled-in mechanism swept in SIMD lanes by name ([`sweep_group`]): the
//! mechanism's concrete type found through the generated `visit_all`, a lane group of it made with
//! each set's params, and the sets swept together ([`crate::sweep::sweep_sets_in_lanes`]).

use mechgen_runtime::{StaticMechanism, StaticVisitor};

use crate::sweep::{Continuation, RowRef, sweep_sets_in_lanes};

/// The most sets one call of [`sweep_group`] sweeps, and how many to hand it at a time on this
/// CPU (eight with AVX-512, four otherwise and for a mechanism of many unknowns; or what the
/// environment variable `MECHGEN_LANES` says).
pub use crate::sweep::{LANES, LANES_VAR, lane_width, lane_width_for};

/// One lane group's sweep (see [`sweep_group`]).
pub struct Group<'a> {
    /// Each set's base params, in the order of the mechanism's `info().params`.
    pub params: &'a [Vec<f64>],
    pub index: usize,
    pub values: &'a [f64],
    pub rate: f64,
    pub held: &'a [(usize, f64)],
    pub continuation: &'a Continuation,
}

/// Sweeps up to [`LANES`] param sets of the compiled-in mechanism `name` in SIMD lanes, set `i`'s
/// row `r` (its index in the values) to `emit(i, r, row)` as solved (see
/// [`crate::sweep::sweep_sets_in_lanes`]), the rows [`crate::sweep::sweep_each_with`] gives each. `None` when no
/// compiled-in mechanism has that name or a set's params do not fit it; else the sets (a bit
/// each) that left the lanes: drop their rows and sweep them with the scalar sweep.
pub fn sweep_group(
    name: &str,
    group: &Group<'_>,
    emit: &mut dyn FnMut(usize, usize, RowRef<'_>),
) -> Option<u32> {
    let mut v = Visit {
        name,
        group,
        emit,
        left: None,
    };
    crate::visit_all::<f64, _>(&mut v);
    v.left
}

struct Visit<'a, 'g> {
    name: &'a str,
    group: &'a Group<'g>,
    emit: &'a mut dyn FnMut(usize, usize, RowRef<'_>),
    left: Option<u32>,
}

impl StaticVisitor<f64> for Visit<'_, '_> {
    fn visit<M: StaticMechanism<f64> + 'static>(&mut self, m: &M) {
        if self.left.is_some() || m.info().name != self.name {
            return;
        }
        let g = self.group;
        let Some(mechs) = g
            .params
            .iter()
            .map(|p| M::with_params(p))
            .collect::<Option<Vec<M>>>()
        else {
            return;
        };
        self.left = Some(sweep_sets_in_lanes(
            &mechs,
            g.index,
            g.values,
            g.rate,
            g.held,
            g.continuation,
            self.emit,
        ));
    }
}
