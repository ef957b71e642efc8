//! The condition estimate where a walk stopped (what tells a dead point from any other failure):
//! the position solve's own, from its blocks' pivot ratios, and the whole Jacobian's, from its
//! elimination with its columns equilibrated. The blocks' estimate cannot see every dead
//! point (a 1×1 block solved by Newton has an elimination pivot ratio of 1 whatever its
//! derivative); the whole Jacobian is singular at each. Evaluated at stops only, never per row.
//! Part of [`crate::sweep`].

use mechgen_runtime::DynMechanism;
use mechgen_runtime::elimination::lu_in_place;
use mechgen_runtime::nalgebra::{DMatrix, DVector};

use super::Continuation;

/// The workspace of [`Conditioner::at`], made once per walk.
pub(super) struct Conditioner {
    settled: Vec<f64>,
    jac: Vec<f64>,
    m: DMatrix<f64>,
    scale: DVector<f64>,
}

impl Conditioner {
    pub(super) fn new(unknowns: usize) -> Self {
        Conditioner {
            settled: vec![0.0; unknowns],
            jac: vec![0.0; unknowns * unknowns],
            m: DMatrix::zeros(unknowns, unknowns),
            scale: DVector::zeros(unknowns),
        }
    }

    /// The condition estimate at `(x, q)` (a converged state of `k`): the larger of the position
    /// solve's and the whole Jacobian's at the state it settles to; infinite when that solve
    /// fails or the Jacobian has a zero, infinite or NaN column.
    pub(super) fn at(
        &mut self,
        k: &dyn DynMechanism<f64>,
        x: &[f64],
        q: &[f64],
        c: &Continuation,
    ) -> f64 {
        let n = self.settled.len();
        if q.len() != n {
            return f64::INFINITY;
        }
        self.settled.copy_from_slice(q);
        let Ok(report) = k.solve_position(x, &mut self.settled, &c.options) else {
            return f64::INFINITY;
        };
        if k.jacobian(x, &self.settled, &mut self.jac).is_err() {
            return f64::INFINITY;
        }
        // Columns equilibrated by the elimination, rows as they are: each row is one loop
        // component, in the file's length unit, and a 1×1 block's row is small exactly where its
        // derivative vanishes (scaling it up would hide the dead point).
        // `jac` holds n rows of n (made so in `new`), `m` is n × n: every index is in range.
        for (i, row) in self.jac.chunks_exact(n.max(1)).enumerate() {
            for (j, v) in row.iter().enumerate() {
                self.m[(i, j)] = *v;
            }
        }
        let ratio = match lu_in_place(&mut self.m, &mut self.scale, |_, _| {}) {
            Ok(r) | Err(r) => r,
        };
        let whole = if ratio > 0.0 {
            1.0 / ratio
        } else {
            f64::INFINITY
        };
        report.condition().max(whole)
    }
}
