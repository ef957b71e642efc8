//! The keyword arguments `Mechanism`'s methods take, checked: the sweep options, a batch's
//! param arrays and the result arrays it may write into (`out=`).

use std::collections::HashMap;

use mg::sweep::plan::Range;
use numpy::{PyReadonlyArray1, PyReadwriteArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The sweep options every method takes.
pub struct Options {
    pub range: Range,
    pub rate: f64,
    pub input: Option<String>,
    pub set: Vec<(String, f64)>,
}

/// The sweep options of a call, each number checked finite (`ValueError` naming it).
pub fn options(
    start: Option<f64>,
    stop: Option<f64>,
    step: Option<f64>,
    rate: f64,
    input: Option<String>,
    set: Option<HashMap<String, f64>>,
) -> PyResult<Options> {
    for (name, v) in [
        ("start", start),
        ("stop", stop),
        ("step", step),
        ("rate", Some(rate)),
    ] {
        if let Some(v) = v
            && !v.is_finite()
        {
            return Err(PyValueError::new_err(format!(
                "`{name}` is not finite: {v}"
            )));
        }
    }
    let mut set: Vec<(String, f64)> = set.unwrap_or_default().into_iter().collect();
    set.sort_by(|a, b| a.0.cmp(&b.0));
    if let Some((name, v)) = set.iter().find(|(_, v)| !v.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "set: the value of input `{name}` is not finite: {v}"
        )));
    }
    Ok(Options {
        range: Range {
            from: start,
            to: stop,
            step,
        },
        rate,
        input,
        set,
    })
}

/// Named columns of numbers: (name, values).
pub type Columns = Vec<(String, Vec<f64>)>;

/// A batch's `params` (param name → one value per set, any array-like) as columns of f64 in
/// name order, and the number of sets; `ValueError` for an array that is not 1-D or not as long
/// as the others.
pub fn param_columns<'py>(
    py: Python<'py>,
    params: &HashMap<String, Bound<'py, PyAny>>,
) -> PyResult<(Columns, usize)> {
    let mut names: Vec<&String> = params.keys().collect();
    names.sort();
    let np = py.import("numpy")?;
    let mut columns: Columns = Vec::new();
    for name in names {
        // Any array-like of numbers, one per set, in any memory layout; aligned (an array
        // unpickled from a Dask message may start at any byte: read as f64 it would not be).
        let a = np.call_method1("require", (&params[name], "float64", "A"))?;
        let shape: Vec<usize> = a.getattr("shape")?.extract()?;
        if shape.len() != 1 {
            return Err(PyValueError::new_err(format!(
                "param `{name}` has shape {shape:?}: it needs a 1-D array, one value per set"
            )));
        }
        let a: PyReadonlyArray1<'py, f64> = a.extract()?;
        columns.push((name.clone(), a.as_array().to_vec()));
    }
    let count = columns.first().map_or(0, |c| c.1.len());
    if let Some((name, c)) = columns.iter().find(|c| c.1.len() != count) {
        return Err(PyValueError::new_err(format!(
            "param `{name}` has {} values, `{}` has {count}: every array needs one per set",
            c.len(),
            columns[0].0
        )));
    }
    Ok((columns, count))
}

/// The number columns `names` of `out` (what an earlier `batch` returned), each a writable
/// float64 array of `shape`, borrowed for writing; `ValueError` naming the first that is not.
pub fn writable_columns<'py>(
    out: &Bound<'py, PyDict>,
    names: &[String],
    shape: &[usize],
) -> PyResult<Vec<PyReadwriteArray2<'py, f64>>> {
    let mut arrays = Vec::with_capacity(names.len());
    for name in names {
        let a = out.get_item(name)?.ok_or_else(|| {
            PyValueError::new_err(format!(
                "out has no column \"{name}\": pass the dict an earlier batch of as many sets and rows returned"
            ))
        })?;
        let a: PyReadwriteArray2<'py, f64> = a.extract().map_err(|e| {
            PyValueError::new_err(format!(
                "out[\"{name}\"] is not a writable float64 array of two dimensions: {e}"
            ))
        })?;
        if a.shape() != shape {
            return Err(PyValueError::new_err(format!(
                "out[\"{name}\"] has shape {:?}, this batch {shape:?} (sets, rows)",
                a.shape()
            )));
        }
        // Written as f64 slices: the data must start on an f64's alignment.
        if !a
            .as_any()
            .getattr("flags")?
            .getattr("aligned")?
            .extract::<bool>()?
        {
            return Err(PyValueError::new_err(format!(
                "out[\"{name}\"] is not aligned in memory (its data starts inside an f64)"
            )));
        }
        arrays.push(a);
    }
    Ok(arrays)
}
