//! The Python package `mechgen` (interfaces.md, "Python"): the mechanisms compiled into the
//! `mechgen` crate (generated solvers) and any file loaded at run time (the generic engine),
//! with `sweep`, `batch` and `sensitivity` returning numpy arrays under the CSV's column names.
//! Everything is the `mechgen` crate's: the sweep plan (`mechgen::sweep::plan`), the sweep core
//! (`sweep_each`), the row's numbers as the CSV writes them (`mechgen::report::row_numbers`), the
//! per-set solver (`mechgen::batch`); this crate converts ([`columns`]) and runs off the GIL
//! ([`run`]).

mod columns;
mod mechanism;
mod run;

use mechanism::{Mechanism, Source};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::PyDict;

/// The compiled-in mechanisms, made once per interpreter, in file order.
static COMPILED: PyOnceLock<Vec<(String, Py<Mechanism>)>> = PyOnceLock::new();

/// The mechanisms compiled into this build (`mechanism.toml`, or the file `MECHGEN_MECHANISM`
/// named at build time), name → Mechanism in file order, on their generated solvers.
#[pyfunction]
fn mechanisms(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let compiled = COMPILED.get_or_try_init(py, || {
        let loaded = Mechanism::from_source(Source::Compiled)?;
        loaded
            .into_iter()
            .map(|m| Ok((m.name().to_string(), Py::new(py, m)?)))
            .collect::<PyResult<Vec<_>>>()
    })?;
    let out = PyDict::new(py);
    for (name, m) in compiled {
        out.set_item(name, m.clone_ref(py))?;
    }
    Ok(out)
}

/// Every mechanism of the file at `path`, loaded at run time, name → Mechanism in file order. A
/// file with errors raises ValueError with every diagnostic (FILE:LINE:COLUMN). `engine`:
/// `"generic"` (the interpreter; the default, as no run-time compiler is built in yet).
#[pyfunction]
#[pyo3(signature = (path, engine=None))]
fn load<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
    engine: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    match engine {
        None | Some("generic") => {}
        Some(other) => {
            return Err(PyValueError::new_err(format!(
                "engine `{other}` is not available here: this build runs loaded files on `generic`"
            )));
        }
    }
    let name = path.display().to_string();
    let text = std::fs::read_to_string(&path).map_err(|e| {
        PyValueError::new_err(format!("{name}: error: cannot read mechanism file: {e}"))
    })?;
    into_dict(py, Mechanism::from_source(Source::File { name, text })?)
}

/// A pickled Mechanism, made again: the compiled-in one of that name, or that mechanism of the
/// file text it was loaded from.
#[pyfunction]
#[pyo3(signature = (mechanism, file=None, text=None))]
fn _restore(
    py: Python<'_>,
    mechanism: &str,
    file: Option<String>,
    text: Option<String>,
) -> PyResult<Py<Mechanism>> {
    let all = match (file, text) {
        (Some(name), Some(text)) => {
            into_dict(py, Mechanism::from_source(Source::File { name, text })?)?
        }
        _ => mechanisms(py)?,
    };
    let m = all
        .get_item(mechanism)?
        .ok_or_else(|| PyValueError::new_err(format!("no mechanism `{mechanism}` to restore")))?;
    Ok(m.cast_into::<Mechanism>()?.unbind())
}

fn into_dict(py: Python<'_>, loaded: Vec<Mechanism>) -> PyResult<Bound<'_, PyDict>> {
    let out = PyDict::new(py);
    for m in loaded {
        out.set_item(m.name().to_string(), Py::new(py, m)?)?;
    }
    Ok(out)
}

/// Planar linkage kinematics from loop equations: the generated solvers of the compiled-in
/// mechanism file and the generic engine for any file, sweeps and batches to numpy.
#[pymodule]
fn mechgen(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Mechanism>()?;
    m.add_function(wrap_pyfunction!(mechanisms, m)?)?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(_restore, m)?)?;
    Ok(())
}
