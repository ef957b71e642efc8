//! The JIT's unsafe boundary, the one module of the crate with `unsafe`: owning the machine
//! code Cranelift wrote, turning its entry addresses into function pointers, calling them, and
//! the callbacks compiled code calls that write through a pointer.
//!
//! Invariants (each `unsafe` below relies on them):
//! 1. A [`Function`]'s entry points into memory owned by its [`Code`], which it holds by `Arc`:
//!    the memory is freed (in `Code`'s `Drop`) only when no `Function` can call it any more.
//! 2. The entry was compiled by `lower.rs` with the signature `extern "C" fn(*const Args, *mut
//!    f64)`: it reads `Args`' pointers only at the indices its [`Reads`] counts (unknown `k`'s
//!    kept sine and cosine only when `k < sc_len`, input `i`'s only when `i < sx_len`), writes
//!    `out[..outputs]`, and nothing else.
//!    [`Function::call`] checks every slice length against [`Reads`] before the call.
//! 3. After `finalize_definitions` nothing touches the `JITModule` but `free_memory` in `Drop`;
//!    the code is immutable, so `Code` is shared between threads.
//! 4. A [`Fused`] entry was compiled by `fused.rs` with the signature `extern "C" fn(*mut
//!    Frame, *mut f64) -> i32`: it reads and writes as invariant 2 says (its `Reads`), also
//!    stores the velocities and accelerations of unknowns below its `writes`, writes
//!    `out[..outputs]`, reads the frame's tolerance and reads and writes its pivot ratio, writes
//!    the unknowns (and their pairs of `sc`) it reads, and calls [`stage`] with the frame it was
//!    given (directly, or through a `cold.rs` trampoline passing the same arguments, which stores
//!    the result in the frame's `status` and changes nothing else), a pointer to `count` f64 of
//!    its own stack frame and one to a slot of `abi::KEPT_BYTES` of it, used by one block's
//!    velocity then its acceleration: an acceleration's call step reads it right after a
//!    velocity's call step of the same block wrote it (one that does not write it fails, ending
//!    the run), else right after it was zeroed. While it runs, the slices of the frame are
//!    borrowed by [`Fused::call`] alone, and [`stage`] makes references of them only for the
//!    duration of one callback, during which compiled code does not run. With a tick's prelude (the frame's
//!    `tick` not 0) it first reads `x, xd, xdd` and the frame's `last` slices (inputs and their
//!    pairs below its `inputs`, unknowns and their pairs below its `unknowns`, as
//!    [`Fused::call`] checks), writes the pairs of `sx` below `inputs` (before any callback) and,
//!    when it carries the unknowns, `q` and `sc` below `unknowns`; on success it writes the
//!    frame's `to` slices below `inputs`.
//! 5. `PointMotion<f64>` is `repr(C)` of three `[f64; 2]`: six f64 in order, no padding (asserted
//!    at compile time in [`flat_points`]), so a slice of them is the f64 a fused program writes.

#![allow(unsafe_code)]

use std::mem::ManuallyDrop;
use std::sync::Arc;

use cranelift_jit::JITModule;

use mechgen_runtime::PointMotion;
use mechgen_runtime::elimination::Factored;
use mechgen_runtime::error::{SolveError, Stage};
use mechgen_runtime::twofold::Arith;

use super::abi::{FusedArgs, InputTrig, Positions, Reads, Stages};
use crate::generic::factors::{factor_small, solve_small};

/// What compiled code reads, one pointer-sized slot each, in this order (`lower.rs` reads slot
/// `i` at byte offset `i × pointer size`).
#[repr(C)]
pub(super) struct Args {
    pub x: *const f64,
    pub q: *const f64,
    pub p: *const f64,
    pub xd: *const f64,
    pub qd: *const f64,
    pub xdd: *const f64,
    pub qdd: *const f64,
    /// (sin, cos) pairs of the unknowns, `sc_len` of them.
    pub sc: *const f64,
    pub sc_len: usize,
    /// (sin, cos) pairs of the inputs, `sx_len` of them.
    pub sx: *const f64,
    pub sx_len: usize,
}

// The pairs of kept sines and cosines are read as two f64 at offsets 0 and 8.
const _: () = assert!(
    size_of::<(f64, f64)>() == 16
        && std::mem::offset_of!((f64, f64), 0) == 0
        && std::mem::offset_of!((f64, f64), 1) == 8
);

/// The machine code of one loaded mechanism (invariant 3).
pub(super) struct Code {
    module: ManuallyDrop<JITModule>,
}

// Invariant 3: the module is only read again by `Drop`.
unsafe impl Send for Code {}
unsafe impl Sync for Code {}

impl Code {
    pub(super) fn new(module: JITModule) -> Arc<Code> {
        Arc::new(Code {
            module: ManuallyDrop::new(module),
        })
    }
}

impl Drop for Code {
    fn drop(&mut self) {
        // SAFETY: invariant 1: no `Function` of this code is left to call it.
        unsafe { ManuallyDrop::take(&mut self.module).free_memory() }
    }
}

type Entry = extern "C" fn(*const Args, *mut f64);

/// One compiled tape.
#[derive(Clone)]
pub struct Function {
    code: Arc<Code>,
    entry: Entry,
    reads: Reads,
    outputs: usize,
}

impl std::fmt::Debug for Function {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Function")
            .field("reads", &self.reads)
            .field("outputs", &self.outputs)
            .finish_non_exhaustive()
    }
}

impl Function {
    /// `address` is the finalized entry of a function `lower.rs` compiled into `code`'s module
    /// reading `reads` and writing `outputs` values (invariant 2).
    pub(super) fn new(code: &Arc<Code>, address: *const u8, reads: Reads, outputs: usize) -> Self {
        // SAFETY: invariant 2 (the signature) and 1 (the address lives as long as `code`).
        let entry = unsafe { std::mem::transmute::<*const u8, Entry>(address) };
        Function {
            code: Arc::clone(code),
            entry,
            reads,
            outputs,
        }
    }

    /// Runs the compiled code on `vars` (`x, q, p, xd, qd, xdd, qdd`) and the kept sines and
    /// cosines of the unknowns and inputs `[sc, sx]`, writing `out`. `false` (nothing run) when a
    /// slice is shorter than what the code reads or `out` shorter than its outputs.
    pub fn call(&self, vars: [&[f64]; 7], [sc, sx]: [&[(f64, f64)]; 2], out: &mut [f64]) -> bool {
        let short = vars.iter().zip(self.reads.0).any(|(v, n)| v.len() < n);
        if short || out.len() < self.outputs {
            return false;
        }
        let [x, q, p, xd, qd, xdd, qdd] = vars.map(<[f64]>::as_ptr);
        let args = Args {
            x,
            q,
            p,
            xd,
            qd,
            xdd,
            qdd,
            sc: sc.as_ptr().cast::<f64>(),
            sc_len: sc.len(),
            sx: sx.as_ptr().cast::<f64>(),
            sx_len: sx.len(),
        };
        // Invariant 2: every read is within the slices checked above, every write within `out`.
        (self.entry)(&args, out.as_mut_ptr());
        let _ = &self.code;
        true
    }
}

/// Where compiled code reads the positions' pivot ratio in a [`Frame`] (to call the refinement
/// only when it is below `REFINE_BELOW`).
pub(super) const PIVOT_AT: usize = std::mem::offset_of!(Frame, pivot_ratio);

/// Where a call step's trampoline (`cold.rs`) leaves the status of `stage` in a [`Frame`].
pub(super) const STATUS_AT: usize = std::mem::offset_of!(Frame, status);

/// Where compiled code reads the Newton tolerance in a [`Frame`].
pub(super) const TOLERANCE_AT: usize = std::mem::offset_of!(Frame, tolerance);

/// Where compiled code reads whether it runs a tick's prelude ([`TICK`], [`RESYNC`]).
pub(super) const TICK_AT: usize = std::mem::offset_of!(Frame, tick);

/// Where the pointers to the last tick's inputs, their pairs, unknowns and theirs are, in that
/// order.
pub(super) const LAST_AT: usize = std::mem::offset_of!(Frame, last);

/// Where the pointers to a tick's inputs, rates and accelerations' destinations are.
pub(super) const TO_AT: usize = std::mem::offset_of!(Frame, to);

/// The frame's `tick`: a tick's prelude runs first.
pub(super) const TICK: u64 = 1;

/// With [`TICK`]: the inputs' sines and cosines computed afresh.
pub(super) const RESYNC: u64 = 2;

/// What a fused entry is called with: the `Args` it reads (first, so that its slots are at
/// the same offsets), the lengths of the slices a call step views, the stages.
#[repr(C)]
pub(super) struct Frame {
    args: Args,
    x_len: usize,
    q_len: usize,
    /// A `*mut &mut dyn Stages`, as an address.
    stages: *mut std::ffi::c_void,
    /// The positions' smallest pivot ratio so far (of the blocks solved inline and of the
    /// stages').
    pivot_ratio: f64,
    /// The Newton tolerance (the closed forms' test of an angle too large to hold).
    tolerance: f64,
    /// The status of the last call of [`stage`], stored there by its trampoline.
    status: u32,
    /// 0: the motion alone; else a tick's prelude first ([`TICK`], [`RESYNC`]).
    tick: u64,
    /// A tick's: the last tick's inputs, their pairs, unknowns and theirs.
    last: [*const f64; 4],
    /// A tick's: where its inputs, rates and accelerations go on success.
    to: [*mut f64; 3],
}

/// The callback of every call step (invariant 4): rebuilds the frame's views and runs the step
/// on the stages (a small block's rates here, by the runtime's `factor_block`, with its factors in
/// the caller's slot `aux`); 0 on success, 1 on failure (the stages keep the error), 2 for a
/// call compiled code cannot make.
pub(super) extern "C" fn stage(
    frame: *mut Frame,
    what: u32,
    block: u32,
    values: *mut f64,
    count: usize,
    aux: *mut u8,
) -> u32 {
    // SAFETY: invariant 4: `frame` is the frame `Fused::call` made, alive for the call, its
    // slices not otherwise referenced while this callback runs; `values` is `count` f64 of the
    // caller's stack.
    let (f, values) = unsafe { (&mut *frame, std::slice::from_raw_parts_mut(values, count)) };
    let stages = unsafe { &mut *f.stages.cast::<&mut dyn Stages>() };
    let at = || unsafe {
        Positions {
            x: std::slice::from_raw_parts(f.args.x, f.x_len),
            sx: std::slice::from_raw_parts(f.args.sx.cast::<(f64, f64)>(), f.args.sx_len),
            q: std::slice::from_raw_parts_mut(f.args.q.cast_mut(), f.q_len),
            sc: std::slice::from_raw_parts_mut(f.args.sc.cast::<(f64, f64)>().cast_mut(), f.q_len),
        }
    };
    let block = block as usize;
    if what <= 2 {
        stages.set_pivot_ratio(f.pivot_ratio);
    }
    let done = match what {
        0 => stages.closed(block, values, at()),
        1 => stages.newton(block, at()),
        2 => stages.refine(at()),
        3 => stages.velocity(block, values),
        4 => stages.acceleration(block, values),
        5 | 6 => {
            let velocity = what == 5;
            // A 1×1 block's values are 1 + 1 (velocity) or 1; a 2×2's 2 + 4 or 2.
            let r = match (velocity, count) {
                (true, 2) | (false, 1) => small::<1>(block, values, aux, velocity),
                (true, 6) | (false, 2) => small::<2>(block, values, aux, velocity),
                _ => return 2,
            };
            r.map_err(|e| stages.fail(e)).is_ok()
        }
        _ => return 2,
    };
    if what <= 2 {
        f.pivot_ratio = stages.pivot_ratio();
    }
    u32::from(!done)
}

/// A small block's velocity (factors written to `kept`) or acceleration (factors read from it).
fn small<const K: usize>(
    block: usize,
    values: &mut [f64],
    kept: *mut u8,
    velocity: bool,
) -> Result<(), SolveError> {
    let kept = kept.cast::<Factored<f64, K>>();
    if velocity {
        let f = factor_small::<f64, K>(block, Stage::Velocity, values)?;
        solve_small(&f, block, Stage::Velocity, values)?;
        // SAFETY: invariant 4: `aux` is a slot of `KEPT_BYTES` of the caller's frame.
        unsafe { kept.write_unaligned(f) };
        Ok(())
    } else {
        // SAFETY: invariant 4: the slot was written by this block's velocity step in this run,
        // or zeroed just before (all-zero bytes are a `Factored`: zeros and index 0).
        let f = unsafe { kept.read_unaligned() };
        solve_small(&f, block, Stage::Acceleration, values)
    }
}

type FusedEntry = extern "C" fn(*mut Frame, *mut f64) -> u32;

/// A whole motion compiled into one function (`fused.rs`).
#[derive(Clone)]
pub struct Fused {
    code: Arc<Code>,
    entry: FusedEntry,
    reads: Reads,
    writes: usize,
    outputs: usize,
    work: bool,
    /// The inputs and unknowns a tick's prelude reads (`None`: compiled without one).
    prelude: Option<(usize, usize)>,
}

impl std::fmt::Debug for Fused {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Fused")
            .field("reads", &self.reads)
            .field("writes", &self.writes)
            .finish_non_exhaustive()
    }
}

impl Fused {
    /// `address` is the finalized entry `fused.rs` compiled into `code`'s module (invariant 4).
    pub(super) fn new(
        code: &Arc<Code>,
        address: *const u8,
        reads: Reads,
        writes: usize,
        outputs: usize,
        work: bool,
        prelude: Option<(usize, usize)>,
    ) -> Self {
        // SAFETY: invariant 4 (the signature) and 1 (the address lives as long as `code`).
        let entry = unsafe { std::mem::transmute::<*const u8, FusedEntry>(address) };
        Fused {
            code: Arc::clone(code),
            entry,
            reads,
            writes,
            outputs,
            work,
            prelude,
        }
    }

    /// Whether a call step may need the stages' block work (a Newton block, the rates of a
    /// block larger than 2×2); without, the stages are only called back for closed forms, the
    /// refinement and small blocks' rates, which work in no buffer of theirs.
    pub fn uses_work(&self) -> bool {
        self.work
    }

    /// Runs the motion, after a tick's prelude when `a.sx` is a tick's; `None` (nothing run)
    /// when a slice is shorter than what the code reads or writes (or a tick's is asked of code
    /// compiled without its prelude), else `Some((status, pivot ratio))`: status 0 done,
    /// [`super::abi::NOT_FINITE`] a tick's inputs not finite, otherwise a call step failed (its
    /// error is kept by `stages`); the positions' smallest pivot ratio. Inlined, so that the
    /// frame is built from the caller's slices in place.
    #[inline(always)]
    pub fn call(
        &self,
        a: FusedArgs<'_>,
        stages: &mut dyn Stages,
        out: &mut [f64],
    ) -> Option<(u32, f64)> {
        let have = [
            a.x.len(),
            a.q.len(),
            a.p.len(),
            a.xd.len(),
            a.qd.len(),
            a.xdd.len(),
            a.qdd.len(),
        ];
        let short = have.iter().zip(self.reads.0).any(|(&h, n)| h < n);
        let rates = a.qd.len().min(a.qdd.len()) < self.writes;
        if short || rates || a.sc.len() != a.q.len() || out.len() < self.outputs {
            return None;
        }
        let null = std::ptr::null_mut::<f64>();
        let (sx, sx_len, tick, last, to) = match a.sx {
            InputTrig::Given(sx) => (
                sx.as_ptr().cast::<f64>(),
                sx.len(),
                0,
                [null.cast_const(); 4],
                [null; 3],
            ),
            InputTrig::Tick(t) => {
                let (ni, nu) = self.prelude?;
                let inputs = (a.x.len().min(a.xd.len()).min(a.xdd.len()))
                    .min(t.x_last.len().min(t.tx_last.len()).min(t.sx.len()))
                    .min(t.to[0].len().min(t.to[1].len()).min(t.to[2].len()));
                let unknowns = t.q_last.len().min(t.tq_last.len()).min(a.q.len());
                if inputs < ni || unknowns < nu {
                    return None;
                }
                let last = [
                    t.x_last.as_ptr(),
                    t.tx_last.as_ptr().cast::<f64>(),
                    t.q_last.as_ptr(),
                    t.tq_last.as_ptr().cast::<f64>(),
                ];
                let [x, xd, xdd] = t.to;
                let flags = if t.resync { TICK | RESYNC } else { TICK };
                let sx = t.sx.as_mut_ptr().cast::<f64>().cast_const();
                (
                    sx,
                    t.sx.len(),
                    flags,
                    last,
                    [x.as_mut_ptr(), xd.as_mut_ptr(), xdd.as_mut_ptr()],
                )
            }
        };
        let mut stages: &mut dyn Stages = stages;
        let mut frame = Frame {
            args: Args {
                x: a.x.as_ptr(),
                q: a.q.as_mut_ptr(),
                p: a.p.as_ptr(),
                xd: a.xd.as_ptr(),
                qd: a.qd.as_mut_ptr(),
                xdd: a.xdd.as_ptr(),
                qdd: a.qdd.as_mut_ptr(),
                sc: a.sc.as_mut_ptr().cast::<f64>(),
                sc_len: a.sc.len(),
                sx,
                sx_len,
            },
            x_len: a.x.len(),
            q_len: a.q.len(),
            stages: (&raw mut stages).cast(),
            pivot_ratio: 1.0,
            tolerance: a.tolerance,
            status: 0,
            tick,
            last,
            to,
        };
        // Invariant 4: every slice checked above; `stages` and the slices outlive the call.
        let status = (self.entry)(&mut frame, out.as_mut_ptr());
        let _ = &self.code;
        Some((status, frame.pivot_ratio))
    }
}

/// The points' motions as the six values each that compiled code writes (a point's position,
/// velocity and acceleration in that order: `PointMotion` is `repr(C)`, of six f64 and no
/// padding, as checked below).
pub fn flat_points(points: &mut [PointMotion<f64>]) -> &mut [f64] {
    const _: () = assert!(
        size_of::<PointMotion<f64>>() == 6 * size_of::<f64>()
            && align_of::<PointMotion<f64>>() == align_of::<f64>()
    );
    let n = 6 * points.len();
    // SAFETY: invariant 5 (the size and alignment asserted above): `points` is `n` initialized
    // f64, borrowed mutably for the result's lifetime.
    unsafe { std::slice::from_raw_parts_mut(points.as_mut_ptr().cast::<f64>(), n) }
}

/// `sin` and `cos` of `x` into `out[0]` and `out[1]`: the interpreter's `sin_cos_of`, called by
/// compiled code with a 16-byte stack slot.
pub(super) extern "C" fn sin_cos(x: f64, out: *mut f64) {
    let (s, c) = x.sin_cos_of();
    // SAFETY: `lower.rs` passes the address of a 16-byte slot of its own frame.
    unsafe {
        out.write(s);
        out.add(1).write(c);
    }
}
