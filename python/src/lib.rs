//! The Python package `mechgen` (interfaces.md, "Python"): the mechanisms compiled into the
//! `mechgen` crate (generated solvers) and any file loaded at run time (the generic engine),
//! with `sweep`, `batch` and `sensitivity` returning numpy arrays under the CSV's column names.
//! Everything is the `mechgen` crate's: the sweep plan (`mechgen::sweep::plan`), the sweep core
//! (`sweep_each`), the row's numbers as the CSV writes them (`mechgen::report::row_numbers`), the
//! per-set solver (`mechgen::batch`); this crate converts ([`columns`]) and runs off the GIL
//! ([`run`]).

mod args;
mod columns;
mod dynamics;
mod mechanism;
mod messages;
mod run;
mod scene;

use mechanism::{FileEngine, Mechanism, Source};
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
/// `"jit"` (compiled to machine code by Cranelift: the default where the host has a back end),
/// or `"generic"` (the interpreter; the default elsewhere).
#[pyfunction]
#[pyo3(signature = (path, engine=None))]
fn load<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
    engine: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let engine = file_engine(engine)?;
    let name = path.display().to_string();
    let text = std::fs::read_to_string(&path).map_err(|e| {
        PyValueError::new_err(format!("{name}: error: cannot read mechanism file: {e}"))
    })?;
    into_dict(
        py,
        Mechanism::from_source(Source::File { name, text, engine })?,
    )
}

/// The engine `load` runs a file on: the one asked for, else `jit` where the host has it.
fn file_engine(engine: Option<&str>) -> PyResult<FileEngine> {
    match engine {
        None if mg::generic::jit::available() => Ok(FileEngine::Jit { asked: false }),
        None | Some("generic") => Ok(FileEngine::Generic),
        Some("jit") => Ok(FileEngine::Jit { asked: true }),
        Some(other) => Err(PyValueError::new_err(format!(
            "engine `{other}`: a loaded file runs on `jit` or `generic`"
        ))),
    }
}

/// A pickled Mechanism, made again: the compiled-in one of that name, or that mechanism of the
/// file text it was loaded from, on the same engine.
#[pyfunction]
#[pyo3(signature = (mechanism, file=None, text=None, engine=None, scene=None))]
fn _restore(
    py: Python<'_>,
    mechanism: &str,
    file: Option<String>,
    text: Option<String>,
    engine: Option<&str>,
    scene: Option<&str>,
) -> PyResult<Py<Mechanism>> {
    let all = match (file, text) {
        (Some(name), Some(text)) => {
            let engine = file_engine(engine)?;
            into_dict(
                py,
                Mechanism::from_source(Source::File { name, text, engine })?,
            )?
        }
        _ => mechanisms(py)?,
    };
    let m = all
        .get_item(mechanism)?
        .ok_or_else(|| PyValueError::new_err(format!("no mechanism `{mechanism}` to restore")))?;
    let m = m.cast_into::<Mechanism>()?;
    match scene {
        Some(name) => Py::new(py, m.get().scene(name)?),
        None => Ok(m.unbind()),
    }
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
