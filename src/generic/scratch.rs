//! Generic engine, its workspace: every buffer a solve needs (registers, trial unknowns, kept
//! sines and cosines, per block size the Newton and rate matrices), one per thread and
//! precision, reused, so that a solve (a tick, a sweep row) allocates nothing once it has grown.

use std::cell::RefCell;

use mechgen_runtime::nalgebra::{DMatrix, DVector, Dyn};
use mechgen_runtime::scalar::Real;
use mechgen_runtime::solve::NewtonWork;

/// The matrices of one block size `k`.
pub(super) struct Sized<T: Real> {
    pub newton: NewtonWork<T, Dyn>,
    pub rhs: DVector<T>,
    pub jac: DMatrix<T>,
    pub scale: DVector<T>,
    pub swaps: Vec<usize>,
}

impl<T: Real> Sized<T> {
    fn new(k: usize) -> Self {
        Sized {
            newton: NewtonWork {
                residual: DVector::zeros(k),
                jacobian: DMatrix::zeros(k, k),
                scale: DVector::zeros(k),
            },
            rhs: DVector::zeros(k),
            jac: DMatrix::zeros(k, k),
            scale: DVector::zeros(k),
            swaps: vec![0; k],
        }
    }
}

/// Every buffer of a solve.
#[derive(Default)]
pub(super) struct Scratch<T: Real> {
    /// A tape's registers.
    pub regs: Vec<T>,
    /// A tape's outputs.
    pub out: Vec<T>,
    /// The unknowns being solved, and their sines and cosines (copied out on success).
    pub trial: Vec<T>,
    pub trial_sc: Vec<(T, T)>,
    /// The solved angles' sines and cosines.
    pub sc: Vec<(T, T)>,
    /// A whole solve's unknowns, velocities and accelerations (then copied to the state).
    pub state: Vec<T>,
    /// Point values (six per point).
    pub points: Vec<T>,
    /// By block size.
    pub by_size: Vec<Option<Sized<T>>>,
    /// A tick program's registers, and the values one of its call steps takes.
    pub program: Vec<T>,
    pub values: Vec<T>,
}

/// The matrices for block size `k` in `by_size`, made at first use.
pub(super) fn sized<T: Real>(by_size: &mut Vec<Option<Sized<T>>>, k: usize) -> &mut Sized<T> {
    if by_size.len() <= k {
        by_size.resize_with(k + 1, || None);
    }
    by_size[k].get_or_insert_with(|| Sized::new(k))
}

/// A precision with a workspace per thread.
pub(super) trait Scratched: Real {
    /// Runs `f` with this thread's workspace (a fresh one if it is in use further up the stack).
    fn with_scratch<R>(f: impl FnOnce(&mut Scratch<Self>) -> R) -> R;
}

macro_rules! scratched {
    ($t:ty, $cell:ident) => {
        thread_local! {
            static $cell: RefCell<Scratch<$t>> = RefCell::new(Scratch::default());
        }

        impl Scratched for $t {
            fn with_scratch<R>(f: impl FnOnce(&mut Scratch<Self>) -> R) -> R {
                $cell.with(|c| match c.try_borrow_mut() {
                    Ok(mut s) => f(&mut s),
                    Err(_) => f(&mut Scratch::default()),
                })
            }
        }
    };
}

scratched!(f64, SCRATCH_F64);
scratched!(f32, SCRATCH_F32);
