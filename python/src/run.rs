//! Running sweeps off the GIL: every set of a batch (or the one set of a sweep) swept by the
//! library's sweep core straight into its block of the column buffers, across the worker threads
//! asked for; the calling thread meanwhile checks for signals every few milliseconds, so that
//! `Ctrl-C` stops the work (each worker stops at its next set) and raises `KeyboardInterrupt`.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use mg::MechanismInfo;
use mg::batch::lanes::{Group, lane_width_for, sweep_group};
use mg::batch::{scene_with_params, solver_with_params};
use mg::branches::Assembly;
use mg::design::row_inputs;
use mg::generic::Generic;
use mg::sweep::plan::Plan;
use mg::sweep::scene::SceneSolver;
use mg::sweep::{Continuation, sweep_each_indexed};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::columns::Block;

/// What every set of one call shares: the mechanism, its plan and rate.
pub struct Job<'a> {
    pub name: &'a str,
    pub model: &'a Generic,
    pub info: &'a MechanismInfo,
    pub generated: bool,
    pub plan: &'a Plan,
    pub rate: f64,
    /// Where the mechanism assembles (its file's branch analysis), when it could be made.
    pub assembly: Option<std::sync::Arc<Assembly>>,
    /// The scene whose solver runs at every row (its columns into the blocks), if any.
    pub scene: Option<&'a str>,
}

impl Job<'_> {
    /// The set with base params `params` swept into `block` from its row `at`.
    fn sweep_into(&self, params: &[f64], block: &mut Block<'_>, at: usize) {
        let k = solver_with_params(self.name, self.model, self.generated, params);
        let c = Continuation::for_input(self.info.inputs[self.plan.index].kind, self.plan.span);
        // Made for this set when a row past the dead point that ends its branch asks.
        let setup = std::cell::OnceCell::new();
        let assembles = |x: &[f64]| {
            setup
                .get_or_init(|| self.assembly.as_ref()?.with_params(params))
                .as_ref()
                .and_then(|s| s.assembles(x))
        };
        let oracle: Option<mg::sweep::Assembles<'_>> =
            self.assembly.is_some().then_some(&assembles);
        let scene = self
            .scene
            .and_then(|name| scene_with_params(name, self.model, self.generated, params));
        let mut scene = scene.as_deref().map(|s| {
            let x = row_inputs(self.info, self.plan.index, &self.plan.held, 0.0);
            SceneSolver::new(s, &x, self.plan.index, self.rate, &c.options)
        });
        // Each row straight to its place, as the walk solves it.
        sweep_each_indexed(
            k.as_ref(),
            self.plan.index,
            &self.plan.values,
            self.rate,
            &self.plan.held,
            &c,
            oracle,
            &mut |i, row| match &mut scene {
                Some(s) => block.put_scene(at + i, &s.row(&row)),
                None => block.put(at + i, &row, self.info),
            },
        );
    }
}

impl Job<'_> {
    /// The sets `chunk` (at most [`lane_width_for`]`(unknowns)`) swept side by side in SIMD
    /// lanes into `block`, set `i` from its row `at + i·rows`; the sets (a bit each) that left the
    /// lanes, to be swept by [`Job::sweep_into`].
    fn sweep_lanes_into(
        &self,
        chunk: &[Vec<f64>],
        block: &mut Block<'_>,
        at: usize,
        rows: usize,
    ) -> u32 {
        let c = Continuation::for_input(self.info.inputs[self.plan.index].kind, self.plan.span);
        let group = Group {
            params: chunk,
            index: self.plan.index,
            values: &self.plan.values,
            rate: self.rate,
            held: &self.plan.held,
            continuation: &c,
        };
        sweep_group(self.name, &group, &mut |i, r, row| {
            block.put(at + i * rows + r, &row, self.info);
        })
        .unwrap_or(u32::MAX)
    }
}

/// Sets per block of the buffers: what one worker sweeps before it takes the next block.
pub const SETS_PER_BLOCK: usize = 16;

/// Rows below which a call runs on the calling thread (the GIL released, no worker threads):
/// it ends within a fraction of a second (0.3 s at the interpreter's 1.5 µs a row), so a signal
/// is seen soon enough when it returns.
const INLINE_ROWS: usize = 200_000;

/// Every set `sets[s]` (base params) swept into `blocks` (block `b` holds sets
/// `b·SETS_PER_BLOCK …`, each `rows` rows), the GIL released: a small job on the calling thread,
/// a larger one on `threads` workers (default every core; the pools are made once per process)
/// while the calling thread checks for signals; `KeyboardInterrupt` (or whatever a signal handler
/// raises) when a signal arrives.
pub fn sweep_sets(
    py: Python<'_>,
    job: &Job<'_>,
    sets: &[Vec<f64>],
    blocks: Vec<Block<'_>>,
    rows: usize,
    threads: Option<usize>,
) -> PyResult<()> {
    let stop = AtomicBool::new(false);
    let sweep_block = |b: usize, block: &mut Block<'_>| {
        let mine = &sets[(b * SETS_PER_BLOCK).min(sets.len())..];
        let mine = &mine[..mine.len().min(SETS_PER_BLOCK)];
        // A compiled-in mechanism's sets in lane groups, each set that leaves the lanes swept
        // again by the scalar sweep (its rows overwrite the lane's).
        let group = if job.generated && job.scene.is_none() {
            lane_width_for(job.info.unknowns.len())
        } else {
            1
        };
        for (g, chunk) in mine.chunks(group).enumerate() {
            if stop.load(Ordering::Relaxed) {
                return;
            }
            let at = g * group * rows;
            let left = if group > 1 {
                job.sweep_lanes_into(chunk, block, at, rows)
            } else {
                u32::MAX
            };
            for (i, params) in chunk.iter().enumerate() {
                if left >> i & 1 == 1 {
                    job.sweep_into(params, block, at + i * rows);
                }
            }
        }
    };
    if sets.len().saturating_mul(rows) <= INLINE_ROWS {
        py.detach(|| {
            for (b, mut block) in blocks.into_iter().enumerate() {
                sweep_block(b, &mut block);
            }
        });
        return py.check_signals();
    }
    let pool = pool(threads)?;
    let work = || {
        use rayon::prelude::*;
        pool.install(|| {
            blocks
                .into_par_iter()
                .enumerate()
                .for_each(|(b, mut block)| sweep_block(b, &mut block))
        })
    };
    py.detach(|| {
        std::thread::scope(|scope| {
            let worker = scope.spawn(work);
            let mut signal = Ok(());
            while !worker.is_finished() {
                std::thread::sleep(Duration::from_millis(20));
                if signal.is_ok() {
                    signal = Python::attach(|py| py.check_signals());
                    if signal.is_err() {
                        stop.store(true, Ordering::Relaxed);
                    }
                }
            }
            let _ = worker.join();
            signal
        })
    })
}

/// The worker pool of `threads` threads (every core for `None`), made at its first use.
fn pool(threads: Option<usize>) -> PyResult<Arc<rayon::ThreadPool>> {
    static POOLS: Mutex<Vec<(Option<usize>, Arc<rayon::ThreadPool>)>> = Mutex::new(Vec::new());
    let mut pools = POOLS.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, p)) = pools.iter().find(|(t, _)| *t == threads) {
        return Ok(p.clone());
    }
    let p = Arc::new(mg::batch::workers(threads).map_err(PyValueError::new_err)?);
    pools.push((threads, p.clone()));
    Ok(p)
}
