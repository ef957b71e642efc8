//! The JIT, what compiled code and the runtime exchange (safe types): what a function reads, the
//! call steps a fused program makes and the runtime's side of them ([`Stages`]), the slices of
//! one fused call. `code.rs` holds the unsafe side that passes them.

use mechgen_runtime::elimination::Factored;
use mechgen_runtime::error::SolveError;

/// How many values of each slice a function reads: one past the largest index of each of
/// `x, q, p, xd, qd, xdd, qdd` (the `Args` order).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct Reads(pub [usize; 7]);

/// What a fused program's call step asks of the runtime (`what` of `code::stage`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub(super) enum Call {
    Closed = 0,
    Newton = 1,
    Refine = 2,
    Velocity = 3,
    Acceleration = 4,
    /// A 1×1 or 2×2 block's velocity: factored and solved here, the factors kept in the
    /// caller's slot (`aux`, [`KEPT_BYTES`]).
    SmallVelocity = 5,
    /// A 1×1 or 2×2 block's acceleration by the factors in `aux` (its velocity's, or zeros).
    SmallAcceleration = 6,
}

/// The bytes of the slot a small block's factors are kept in between its two rates.
pub(super) const KEPT_BYTES: usize = {
    let (one, two) = (size_of::<Factored<f64, 1>>(), size_of::<Factored<f64, 2>>());
    if one > two { one } else { two }
};

/// The positions a call step may change: the inputs and their kept sines and cosines, the
/// unknowns being solved and theirs.
pub struct Positions<'a> {
    pub x: &'a [f64],
    pub sx: &'a [(f64, f64)],
    pub q: &'a mut [f64],
    pub sc: &'a mut [(f64, f64)],
}

/// The runtime's side of a fused program's call steps (safe code: `stages.rs`). Each returns
/// `false` on failure, having kept its error.
pub trait Stages {
    /// Solves a closed-form block from its roots.
    fn closed(&mut self, block: usize, roots: &[f64], at: Positions<'_>) -> bool;
    /// Solves a block by Newton.
    fn newton(&mut self, block: usize, at: Positions<'_>) -> bool;
    /// The refinement near a dead point, if the positions' report asks for it.
    fn refine(&mut self, at: Positions<'_>) -> bool;
    /// `values` (right-hand side k, Jacobian k×k): factors the Jacobian, keeps its factors,
    /// leaves the velocities in `values[..k]`.
    fn velocity(&mut self, block: usize, values: &mut [f64]) -> bool;
    /// `values[..k]` (right-hand side) becomes the accelerations, by the kept factors.
    fn acceleration(&mut self, block: usize, values: &mut [f64]) -> bool;
    /// The smallest pivot ratio of the positions so far.
    fn pivot_ratio(&self) -> f64;
    /// Sets it (to what compiled code found solving blocks inline).
    fn set_pivot_ratio(&mut self, ratio: f64);
    /// Keeps the error of a step run outside the stages.
    fn fail(&mut self, error: SolveError);
}

/// What a fused call returns when a tick's inputs are not all finite (having written nothing).
pub const NOT_FINITE: u32 = 3;

/// A tick's prelude (`program::TickShape`) in a fused call: what it reads of the last tick, where
/// it writes the inputs' sines and cosines (rotated, or computed afresh when `resync`; the
/// motion then reads them), and where the inputs go when the tick succeeds.
pub struct TickPrelude<'a> {
    pub x_last: &'a [f64],
    pub tx_last: &'a [(f64, f64)],
    pub q_last: &'a [f64],
    pub tq_last: &'a [(f64, f64)],
    pub sx: &'a mut [(f64, f64)],
    /// The inputs, their rates and accelerations, copied there on success.
    pub to: [&'a mut [f64]; 3],
    pub resync: bool,
}

/// The inputs' sines and cosines of a fused call.
pub enum InputTrig<'a> {
    /// Given (a whole solve's).
    Given(&'a [(f64, f64)]),
    /// A tick's, made by its prelude.
    Tick(TickPrelude<'a>),
}

/// The slices of one fused call: read (`x, p, xd, xdd`, the inputs' kept sines and cosines),
/// solved in place (`q` and its `sc`), written (`qd, qdd`).
pub struct FusedArgs<'a> {
    pub x: &'a [f64],
    pub p: &'a [f64],
    pub xd: &'a [f64],
    pub xdd: &'a [f64],
    pub sx: InputTrig<'a>,
    pub q: &'a mut [f64],
    pub sc: &'a mut [(f64, f64)],
    pub qd: &'a mut [f64],
    pub qdd: &'a mut [f64],
    /// The Newton tolerance.
    pub tolerance: f64,
}
