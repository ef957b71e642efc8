//! Batches (feature `sweep`): one mechanism swept for many param sets. The sets come from a CSV
//! whose header names params ([`ParamSets::parse`]); each set is swept exactly as a sweep of that
//! mechanism with those params would be, and summarised ([`SetSummary`]). [`for_each_ordered`]
//! runs the sets in chunks, each chunk across every core with the `parallel` feature (rayon),
//! handing the results back in set order: the output is the same whatever the threads, and memory
//! holds one chunk, however many sets. [`for_each_mut`] is the same for many instances held in
//! memory (a fleet of mechanisms each ticked once, say).

pub mod lanes;

use crate::MechanismInfo;
use crate::sweep::RowRef;

/// Param sets read from CSV: `names` (the header), one row of values per set, and a note for each
/// value that is a number but not finite (`nan`, `inf`): that set is swept all the same, and
/// every row of it gets the status `non-finite-input`, while the other sets go on.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamSets {
    pub names: Vec<String>,
    pub sets: Vec<Vec<f64>>,
    /// `FILE:LINE: set S: `nan` for `p` is not finite: …`, one per such value.
    pub notes: Vec<String>,
}

impl ParamSets {
    /// Parses `text` (named `file` in errors, which give `FILE:LINE`): a header of param names,
    /// then one row of numbers per set (a cell that is no number is an error; one that is not
    /// finite, a note). Blank lines are skipped.
    pub fn parse(file: &str, text: &str) -> Result<ParamSets, String> {
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty());
        let Some((_, head)) = lines.next() else {
            return Err(format!("{file}:1: empty: needs a header of param names"));
        };
        let names: Vec<String> = head.split(',').map(|s| s.trim().to_string()).collect();
        for (i, n) in names.iter().enumerate() {
            if n.is_empty() {
                return Err(format!("{file}:1: column {} has no param name", i + 1));
            }
            if names[..i].contains(n) {
                return Err(format!("{file}:1: param `{n}` is named twice"));
            }
        }
        let (mut sets, mut notes) = (Vec::new(), Vec::new());
        for (i, line) in lines {
            let fields: Vec<&str> = line.split(',').map(str::trim).collect();
            if fields.len() != names.len() {
                return Err(format!(
                    "{file}:{}: {} values for {} params",
                    i + 1,
                    fields.len(),
                    names.len()
                ));
            }
            let mut row = Vec::with_capacity(fields.len());
            for (f, n) in fields.iter().zip(&names) {
                match f.parse::<f64>() {
                    Ok(v) if v.is_finite() => row.push(v),
                    Ok(v) => {
                        notes.push(format!(
                            "{file}:{}: set {}: `{f}` for `{n}` is not finite: its rows are `non-finite-input`",
                            i + 1,
                            sets.len()
                        ));
                        row.push(v);
                    }
                    Err(_) => {
                        return Err(format!("{file}:{}: `{f}` for `{n}` is not a number", i + 1));
                    }
                }
            }
            sets.push(row);
        }
        Ok(ParamSets { names, sets, notes })
    }

    /// Each column's index among the mechanism's (base) params; a name it lacks is an error
    /// naming it, the file's header line and the params there are.
    pub fn indices(&self, file: &str, info: &MechanismInfo) -> Result<Vec<usize>, String> {
        self.names
            .iter()
            .map(|n| {
                info.params
                    .iter()
                    .position(|p| &p.name == n)
                    .ok_or_else(|| {
                        let have: Vec<&str> = info.params.iter().map(|p| p.name.as_str()).collect();
                        format!(
                            "{file}:1: `{}` has no param `{n}` (it has: {})",
                            info.name,
                            have.join(", ")
                        )
                    })
            })
            .collect()
    }

    /// Set `s`'s full base-param array: the file's values with this set's written in.
    pub fn params_of(&self, s: usize, indices: &[usize], info: &MechanismInfo) -> Vec<f64> {
        let mut p: Vec<f64> = info.params.iter().map(|p| p.value).collect();
        for (&i, &v) in indices.iter().zip(&self.sets[s]) {
            p[i] = v;
        }
        p
    }
}

/// One set's rows summarised: counts, the first failure, and each unknown's and point
/// coordinate's min and max over the `ok` rows (unknowns, then `P_x`, `P_y` per point).
#[derive(Clone, Debug, PartialEq)]
pub struct SetSummary {
    pub ok_rows: usize,
    pub failed_rows: usize,
    /// The input of the first row that is not `ok`.
    pub first_failure: Option<f64>,
    pub min: Vec<f64>,
    pub max: Vec<f64>,
}

impl SetSummary {
    pub fn new(info: &MechanismInfo) -> SetSummary {
        let n = info.unknowns.len() + 2 * info.points.len();
        SetSummary {
            ok_rows: 0,
            failed_rows: 0,
            first_failure: None,
            min: vec![f64::INFINITY; n],
            max: vec![f64::NEG_INFINITY; n],
        }
    }

    /// Counts `r` in.
    pub fn add(&mut self, r: &RowRef<'_>) {
        match &r.result {
            Ok(s) => {
                self.ok_rows += 1;
                let n = s.q.len();
                let (min, max) = (&mut self.min[..], &mut self.max[..]);
                if min.len() != n + 2 * s.points.len() || max.len() != min.len() {
                    return;
                }
                let mut take = |k: usize, v: f64| {
                    min[k] = min[k].min(v);
                    max[k] = max[k].max(v);
                };
                for (k, &v) in s.q.iter().enumerate() {
                    take(k, v);
                }
                for (j, p) in s.points.iter().enumerate() {
                    take(n + 2 * j, p.position[0]);
                    take(n + 2 * j + 1, p.position[1]);
                }
            }
            Err(_) => {
                self.failed_rows += 1;
                self.first_failure.get_or_insert(r.input);
            }
        }
    }

    /// Counts in, instead of [`SetSummary::add`], a failed row at `input` whose mechanism solved
    /// (a row of `mechgen batch SCENE` where the scene's solver did not).
    pub fn fail(&mut self, input: f64) {
        self.failed_rows += 1;
        self.first_failure.get_or_insert(input);
    }

    /// The summary CSV's header: `set,ok_rows,failed_rows,first_failure`, then `<c>_min,<c>_max`.
    pub fn header(info: &MechanismInfo) -> String {
        let mut cols: Vec<String> = ["set", "ok_rows", "failed_rows", "first_failure"]
            .map(String::from)
            .to_vec();
        let names = info.unknowns.iter().map(|u| u.name.clone()).chain(
            info.points
                .iter()
                .flat_map(|p| [format!("{p}_x"), format!("{p}_y")]),
        );
        for n in names {
            cols.push(format!("{n}_min"));
            cols.push(format!("{n}_max"));
        }
        cols.join(",") + "\n"
    }

    /// Set `set`'s summary row (min and max empty when no row is `ok`).
    pub fn row(&self, set: usize) -> String {
        let mut out = format!("{set},{},{},", self.ok_rows, self.failed_rows);
        if let Some(x) = self.first_failure {
            out.push_str(&format!("{x:?}"));
        }
        for (lo, hi) in self.min.iter().zip(&self.max) {
            if self.ok_rows > 0 {
                out.push_str(&format!(",{lo:?},{hi:?}"));
            } else {
                out.push_str(",,");
            }
        }
        out.push('\n');
        out
    }
}

/// Sets handed out per chunk: each chunk is solved (in parallel) before any of it is written.
pub const CHUNK: usize = 256;

/// Mechanism `name` with the base params `params` (in `model`'s order): its generated solvers
/// when `generated` and it is compiled in, else the generic engine `model` with those params.
#[cfg(feature = "runtime")]
pub fn solver_with_params(
    name: &str,
    model: &crate::generic::Generic,
    generated: bool,
    params: &[f64],
) -> Box<dyn mechgen_runtime::DynMechanism<f64>> {
    if generated && let Some(k) = crate::lookup_with_params::<f64>(name, params) {
        return k;
    }
    // A clone shares the model's tapes and compiled code; only the params are its own.
    let mut g = model.clone();
    g.set_params(params);
    Box::new(g)
}

/// Scene `name` (of `model`'s mechanism) with `params` (its mechanism's base params, as
/// [`solver_with_params`] takes them): the compiled-in scene when `generated`, else the scene of
/// `model` with those params (sharing its compiled code); `None` when it has no such scene.
pub fn scene_with_params(
    name: &str,
    model: &crate::generic::Generic,
    generated: bool,
    params: &[f64],
) -> Option<Box<dyn mechgen_runtime::DynScene<f64>>> {
    if generated && let Some(s) = crate::lookup_scene_with_params::<f64>(name, params) {
        return Some(s);
    }
    let mut g = model.clone();
    g.set_params(params);
    g.scene(name)
        .map(|s| Box::new(s) as Box<dyn mechgen_runtime::DynScene<f64>>)
}

/// Runs `solve` for every set `0..count`, chunk by chunk (with the `parallel` feature on up to
/// `threads` threads, default every core), and hands each result to `emit` in set order.
pub fn for_each_ordered<T: Send>(
    count: usize,
    threads: Option<usize>,
    solve: impl Fn(usize) -> T + Sync,
    emit: impl FnMut(usize, T),
) -> Result<(), String> {
    for_each_ordered_by(count, CHUNK, threads, solve, emit)
}

/// [`for_each_ordered`] in chunks of `chunk` items (at least one): for items that are groups of
/// sets (a lane group's, say), so that a chunk still holds about [`CHUNK`] sets.
pub fn for_each_ordered_by<T: Send>(
    count: usize,
    chunk: usize,
    threads: Option<usize>,
    solve: impl Fn(usize) -> T + Sync,
    mut emit: impl FnMut(usize, T),
) -> Result<(), String> {
    let chunk = chunk.max(1);
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads.unwrap_or(0))
            .build()
            .map_err(|e| format!("cannot start worker threads: {e}"))?;
        for start in (0..count).step_by(chunk) {
            let end = (start + chunk).min(count);
            let done: Vec<T> = pool.install(|| (start..end).into_par_iter().map(&solve).collect());
            for (s, t) in (start..end).zip(done) {
                emit(s, t);
            }
        }
        Ok(())
    }
    #[cfg(not(feature = "parallel"))]
    {
        let _ = (threads, chunk);
        for s in 0..count {
            emit(s, solve(s));
        }
        Ok(())
    }
}

/// A pool of `threads` worker threads (default every core) to run a loop of batch calls on:
/// inside `pool.install(|| …)` the loop itself runs on a worker, so that consecutive calls of
/// [`for_each_mut`] (the ticks of a fleet) are not each a hand-over to sleeping threads and back
/// (measured: a fifth of a 4096-instance six-bar tick on this 2-core machine).
#[cfg(feature = "parallel")]
pub fn workers(threads: Option<usize>) -> Result<rayon::ThreadPool, String> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .map_err(|e| format!("cannot start worker threads: {e}"))
}

/// Calls `f(i, &mut items[i])` for every item, across every core with the `parallel` feature
/// (rayon's pool: the one installed, see [`workers`], else the global one; at least 64 items per
/// task), in order on one thread without it. Each call sees
/// its own item only, so the results do not depend on the threads.
pub fn for_each_mut<S: Send>(items: &mut [S], f: impl Fn(usize, &mut S) + Sync) {
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        items
            .par_iter_mut()
            .enumerate()
            .with_min_len(64)
            .for_each(|(i, s)| f(i, s));
    }
    #[cfg(not(feature = "parallel"))]
    for (i, s) in items.iter_mut().enumerate() {
        f(i, s);
    }
}
