//! Rows straight into column buffers: each sweep row's numbers (`mechgen::report::row_numbers`,
//! what the CSV writes) go to their place in one `f64` buffer per column and its status to one
//! byte, with nothing made per row; the buffers become numpy arrays without a copy, and the
//! statuses an object array of shared `str` (one per status kind).

use mg::MechanismInfo;
use mg::report::{STATUSES, row_numbers};
use mg::sweep::RowRef;
use mg::sweep::scene::SceneRowRef;
use numpy::{PyArray1, PyArrayMethods, PyReadwriteArray1};
use pyo3::exceptions::PyMemoryError;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyModule, PySlice, PyString};

/// A block of rows in column buffers: `columns[c][r]` is column `c` (the input, then the CSV's
/// numbers up to `cond`) of row `r`, `codes[r]` the index of its status in [`STATUSES`].
pub struct Block<'a> {
    pub columns: Vec<&'a mut [f64]>,
    pub codes: &'a mut [u8],
}

impl Block<'_> {
    /// Row `r` written: its input, its numbers (NaN where the CSV leaves a cell empty), its
    /// status code.
    pub fn put(&mut self, r: usize, row: &RowRef<'_>, info: &MechanismInfo) {
        let Some((first, mut rest)) = self.columns.split_first_mut() else {
            return;
        };
        first[r] = row.input;
        let status = row_numbers(row, info, |run| {
            // The run's columns split off once, then walked in registers (an iterator shared
            // with the closure's caller would be stored back at every number).
            let n = run.len().min(rest.len());
            let (now, later) = std::mem::take(&mut rest).split_at_mut(n);
            for (c, &v) in now.iter_mut().zip(run) {
                c[r] = v;
            }
            rest = later;
        });
        self.codes[r] = mg::report::status_code(status);
    }
}

impl Block<'_> {
    /// A scene's row into row `r`: the input, the scene's outputs and `cond` (NaN where the row
    /// has none: a failed row's numbers, the condition where it is not finite), the status code.
    pub fn put_scene(&mut self, r: usize, row: &SceneRowRef<'_>) {
        let Some((first, rest)) = self.columns.split_first_mut() else {
            return;
        };
        first[r] = row.input;
        let Some((cond, outputs)) = rest.split_last_mut() else {
            return;
        };
        match row.outputs {
            Ok(v) => {
                for (c, &v) in outputs.iter_mut().zip(v) {
                    c[r] = v;
                }
                cond[r] = row.condition.unwrap_or(f64::NAN);
            }
            Err(_) => {
                for c in outputs.iter_mut() {
                    c[r] = f64::NAN;
                }
                cond[r] = f64::NAN;
            }
        }
        self.codes[r] = mg::report::status_code(row.status);
    }
}

/// Columns (each as long as `codes`) and their status codes cut into blocks of `rows` rows
/// each (the last one shorter).
pub fn blocks<'a>(columns: Vec<&'a mut [f64]>, codes: &'a mut [u8], rows: usize) -> Vec<Block<'a>> {
    let rows = rows.max(1);
    let ncols = columns.len();
    let mut blocks: Vec<Block<'a>> = codes
        .chunks_mut(rows)
        .map(|codes| Block {
            columns: Vec::with_capacity(ncols),
            codes,
        })
        .collect();
    for column in columns {
        for (b, chunk) in blocks.iter_mut().zip(column.chunks_mut(rows)) {
            b.columns.push(chunk);
        }
    }
    blocks
}

/// Buffers for `rows` rows of `ncols` columns and their status codes: `MemoryError` naming the
/// size when the machine cannot hold them (checked before anything is allocated).
///
/// The columns lie in one allocation, column `c` at `c · stride`, and become numpy views of it.
/// A row writes one number into each column, so `ncols` streams of writes advance together. As
/// separate allocations (each page-aligned) every stream sat at the same offset in its page and
/// so in the same set of the CPU's L1 cache, which holds 8–12 lines of a set; `stride` is a whole
/// number of 64-byte lines, an odd number of them modulo 4 KiB, so that the streams spread over
/// the sets. One batch on one thread (2000 sets × 360 rows, Intel Xeon VM, docs/python.md): a
/// four-bar row 205–208 ns as separate columns, 201–203 in one allocation without the odd stride,
/// 173 with it; a Strandbeest leg's (69 columns) 669–687, 651 and 566–596 ns.
///
/// The allocation is numpy's own (`numpy.zeros`), which asks Linux for transparent huge pages
/// on arrays of 4 MiB and more, as every large numpy array has them: fresh memory then costs a
/// page fault per 2 MiB, not per 4 KiB. On the AVX2 AMD EPYC VM (2026-11-29, docs/python.md),
/// 400 MB of fresh memory touched page by page took 56–65 ms so (280–340 ms the first time in a
/// process), 280–320 ms every time in 4 KiB pages (the allocation of a Rust `Vec`); the
/// compiled-in Strandbeest leg's batch on one thread 1112 ns a row in a `Vec` (against 408 into
/// an earlier result's arrays, `out=`), 637–694 ns in numpy's memory (against 437).
pub struct Buffers<'py> {
    /// The numbers, borrowed for writing (numpy's borrow check) until `into_dict`.
    data: PyReadwriteArray1<'py, f64>,
    stride: usize,
    ncols: usize,
    rows: usize,
    pub codes: Vec<u8>,
}

/// The distance in numbers between two columns of `rows` rows in [`Buffers`]: an odd number of
/// 64-byte lines (8 numbers each), so an odd one modulo the 64 lines of 4 KiB: column `c` starts
/// `c` times that many lines into the sets, all 64 sets visited before one comes again.
fn stride(rows: usize) -> usize {
    (rows.div_ceil(8) | 1) * 8
}

impl<'py> Buffers<'py> {
    pub fn new(py: Python<'py>, ncols: usize, rows: usize, what: &str) -> PyResult<Self> {
        let per_row = ncols * 8 + 1 + 8;
        let too_big = || {
            PyMemoryError::new_err(format!(
                "{what}: {rows} rows × {ncols} columns need {} of memory (numbers, statuses), more than this machine has ({} in all)",
                bytes(rows as f64 * per_row as f64),
                bytes(physical_memory() as f64)
            ))
        };
        let need = rows.checked_mul(per_row).ok_or_else(too_big)?;
        if need > physical_memory() {
            return Err(too_big());
        }
        let stride = stride(rows);
        let len = stride.checked_mul(ncols).ok_or_else(too_big)?;
        // Zeroed memory (fresh pages, not written here): every cell is written by its row.
        let data = numpy(py)?.call_method1("zeros", (len,))?;
        let data = data.cast_into::<PyArray1<f64>>()?.try_readwrite()?;
        Ok(Buffers {
            data,
            stride,
            ncols,
            rows,
            codes: vec![0; rows],
        })
    }

    /// The whole buffers as one block: each column's `rows` numbers, and the codes.
    pub fn block(&mut self) -> PyResult<Block<'_>> {
        let rows = self.rows;
        let data = self.data.as_slice_mut()?;
        let columns = data
            .chunks_mut(self.stride)
            .take(self.ncols)
            .map(|c| &mut c[..rows])
            .collect();
        Ok(Block {
            columns,
            codes: &mut self.codes,
        })
    }

    /// The buffers cut into blocks of `rows` rows each (the last one shorter).
    pub fn blocks(&mut self, rows: usize) -> PyResult<Vec<Block<'_>>> {
        let whole = self.block()?;
        Ok(blocks(whole.columns, whole.codes, rows))
    }

    /// The dict of numpy arrays: `header[c]` → column `c`, then `status`; each of `shape`
    /// (whose rows are the first of the buffers'; views of one array). The views are made by
    /// numpy in one pass (the buffers seen as `(columns, rows…)`, iterated): a view apiece made
    /// from Rust, by a slice and a reshape, cost a Strandbeest sweep of one row 160 µs.
    pub fn into_dict(
        self,
        py: Python<'py>,
        header: &[Py<PyString>],
        shape: &[usize],
        held: &[(String, f64)],
    ) -> PyResult<Bound<'py, PyDict>> {
        let out = PyDict::new(py);
        let n: usize = shape.iter().product();
        let Buffers {
            data,
            stride,
            ncols,
            mut codes,
            ..
        } = self;
        let all: Bound<'py, PyArray1<f64>> = (**data).clone();
        // The borrow for writing ends here.
        drop(data);
        let mut dims = vec![ncols];
        dims.extend_from_slice(shape);
        let grid = all
            .reshape([ncols, stride])?
            .get_item((PySlice::full(py), PySlice::new(py, 0, n as isize, 1)))?
            .call_method1("reshape", (dims,))?;
        let mut columns = grid.try_iter()?;
        for (k, name) in header.iter().enumerate() {
            let Some(column) = columns.next() else {
                break;
            };
            out.set_item(name.bind(py), column?)?;
            if k == 0 {
                // The inputs the sweep holds, each its value on every row, after the swept one
                // (as the CSV has them).
                for (name, v) in held {
                    let np = numpy(py)?;
                    out.set_item(name, np.call_method1("full", (shape.to_vec(), *v))?)?;
                }
            }
        }
        codes.truncate(n);
        set_statuses(&out, codes, shape)?;
        Ok(out)
    }
}

/// `names` as Python `str`, the keys of [`Buffers::into_dict`].
pub fn keys(py: Python<'_>, names: &[String]) -> Vec<Py<PyString>> {
    names
        .iter()
        .map(|n| PyString::new(py, n).unbind())
        .collect()
}

/// `out["status"]`: the statuses of `codes` (one per row) as an array of `shape`.
pub fn set_statuses(out: &Bound<'_, PyDict>, codes: Vec<u8>, shape: &[usize]) -> PyResult<()> {
    let py = out.py();
    let codes = PyArray1::from_vec(py, codes).reshape(shape.to_vec())?;
    out.set_item("status", statuses(py)?.get_item(codes)?)
}

/// The module `numpy`, imported once.
pub fn numpy(py: Python<'_>) -> PyResult<&Bound<'_, PyModule>> {
    static NUMPY: PyOnceLock<Py<PyModule>> = PyOnceLock::new();
    let np = NUMPY.get_or_try_init(py, || Ok::<_, PyErr>(py.import("numpy")?.unbind()))?;
    Ok(np.bind(py))
}

/// The statuses as a numpy object array, indexed by status code: one `str` object per status
/// kind, which every row's status refers to (8 bytes a row; `==` and pandas work as on strings).
/// Made once (never handed out: indexing it makes each result's own array).
fn statuses(py: Python<'_>) -> PyResult<&Bound<'_, PyAny>> {
    static STATUS_OBJECTS: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
    let made = STATUS_OBJECTS.get_or_try_init(py, || {
        let mut names: Vec<&str> = STATUSES.to_vec();
        names.push("unknown");
        let kw = PyDict::new(py);
        kw.set_item("dtype", "object")?;
        Ok::<_, PyErr>(
            numpy(py)?
                .call_method("array", (names,), Some(&kw))?
                .unbind(),
        )
    })?;
    Ok(made.bind(py))
}

/// The machine's physical memory in bytes (`usize::MAX` where it cannot be read), read once per
/// process (reading `/proc/meminfo` took a few microseconds of every call).
fn physical_memory() -> usize {
    static MEMORY: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    *MEMORY.get_or_init(|| {
        let meminfo = std::fs::read_to_string("/proc/meminfo").unwrap_or_default();
        meminfo
            .lines()
            .find_map(|l| l.strip_prefix("MemTotal:"))
            .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<usize>().ok())
            .map_or(usize::MAX, |kb| kb.saturating_mul(1024))
    })
}

/// A size in bytes, readable.
fn bytes(b: f64) -> String {
    if b >= 1e9 {
        format!("{:.1} GB", b / 1e9)
    } else {
        format!("{:.1} MB", b / 1e6)
    }
}
