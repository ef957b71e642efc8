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

#![allow(unsafe_code)]

use std::mem::ManuallyDrop;
use std::sync::Arc;

use cranelift_jit::JITModule;

use mechgen_runtime::twofold::Arith;

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

/// How many values of each slice a function reads: one past the largest index of each of
/// `x, q, p, xd, qd, xdd, qdd` (the `Args` order).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct Reads(pub [usize; 7]);

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
