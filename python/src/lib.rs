//! The Python package `mechgen` (interfaces.md, "Python"): the mechanisms compiled into the
//! `mechgen` crate (generated solvers) and any file loaded at run time (the generic engine),
//! with `sweep`, `batch` and `sensitivity` returning numpy arrays under the CSV's column names. Everything is the
//! `mechgen` crate's: the sweep plan (`mechgen::sweep::plan`), the continuation, the row cells of
//! the CSV (`mechgen::report::row_cells`), the per-set solver and the ordered parallel batch
//! (`mechgen::batch`); this file only converts.

use std::collections::HashMap;

use mg::batch::{for_each_ordered, solver_with_params};
use mg::design::{self, outputs, row_inputs};
use mg::generic::Generic;
use mg::report::{csv_header, row_cells};
use mg::sweep::plan::{Plan, Range, plan};
use mg::sweep::{Continuation, Row, check_start, sweep_holding};
use mg::{DynMechanism, MechanismInfo};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1};
use pyo3::exceptions::{PyKeyError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// One mechanism: its generated solvers (compiled in) or the generic engine (a loaded file).
#[pyclass(frozen, module = "mechgen")]
struct Mechanism {
    model: Generic,
    info: MechanismInfo,
    generated: bool,
}

/// The sweep options every method takes.
struct Options {
    range: Range,
    rate: f64,
    input: Option<String>,
    set: Vec<(String, f64)>,
}

/// A sweep's rows as cells, column by column: `numbers[c·rows + r]` is column `c` of row `r`
/// (NaN where the CSV leaves the cell empty), and each row's status.
struct Cells {
    numbers: Vec<f64>,
    statuses: Vec<&'static str>,
}

fn cells(rows: &[Row], columns: usize) -> Cells {
    let n = rows.len();
    let mut numbers = vec![f64::NAN; columns * n];
    let mut statuses = Vec::with_capacity(n);
    for (r, row) in rows.iter().enumerate() {
        let (c, status) = row_cells(row);
        numbers[r] = row.input;
        for (k, v) in c.into_iter().flatten().enumerate().take(columns - 1) {
            numbers[(k + 1) * n + r] = v.unwrap_or(f64::NAN);
        }
        statuses.push(status);
    }
    Cells { numbers, statuses }
}

/// One sweep's cells as the dict `sweep` and `sensitivity` return: `header[k]` → column `k`,
/// then `status`.
fn columns<'py>(py: Python<'py>, header: &[String], c: Cells) -> PyResult<Bound<'py, PyDict>> {
    let n = c.statuses.len();
    let out = PyDict::new(py);
    for (k, name) in header.iter().enumerate() {
        out.set_item(
            name,
            PyArray1::from_slice(py, &c.numbers[k * n..(k + 1) * n]),
        )?;
    }
    out.set_item("status", statuses(py, &[c], n, true)?)?;
    Ok(out)
}

/// The statuses of `sets` (each a list of rows) as one numpy string array of shape (sets, rows),
/// or flat when `flat`: the distinct statuses (a handful) indexed by one integer per row, so that
/// no Python string is made per row.
fn statuses<'py>(
    py: Python<'py>,
    sets: &[Cells],
    rows: usize,
    flat: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let mut names: Vec<&'static str> = Vec::new();
    let mut codes: Vec<i64> = Vec::with_capacity(sets.len() * rows);
    for s in sets.iter().flat_map(|c| &c.statuses) {
        let i = match names.iter().position(|n| n == s) {
            Some(i) => i,
            None => {
                names.push(s);
                names.len() - 1
            }
        };
        codes.push(i as i64);
    }
    let np = py.import("numpy")?;
    let names = np.call_method1("array", (names, "U"))?;
    let codes = PyArray1::from_vec(py, codes);
    let codes = if flat {
        codes.into_any()
    } else {
        codes.reshape([sets.len(), rows])?.into_any()
    };
    names.get_item(codes)
}

impl Mechanism {
    fn plan(&self, o: &Options) -> PyResult<Plan> {
        let p =
            plan(&self.info, o.input.as_deref(), &o.set, o.range).map_err(PyValueError::new_err)?;
        check_start(&self.info)
            .map_err(|e| PyValueError::new_err(format!("{}: {e}", self.info.name)))?;
        Ok(p)
    }

    /// A one-sweep call's options, its plan and its params (`params`: name → value in place of
    /// the file's).
    fn prepare(
        &self,
        o: Options,
        params: Option<HashMap<String, f64>>,
    ) -> PyResult<(Options, Plan, Vec<f64>)> {
        let plan = self.plan(&o)?;
        let given: Vec<(String, f64)> = params.unwrap_or_default().into_iter().collect();
        let values = self.params_with(&given)?;
        Ok((o, plan, values))
    }

    /// The base params with `given` (name → value) in place of the file's.
    fn params_with(&self, given: &[(String, f64)]) -> PyResult<Vec<f64>> {
        let mut values: Vec<f64> = self.info.params.iter().map(|p| p.value).collect();
        for (name, v) in given {
            let Some(i) = self.info.params.iter().position(|p| &p.name == name) else {
                // A derived param is named with what it is derived from.
                return Err(match self.model.clone().set_param(name, 0.0) {
                    Err(e) if e.contains("derived") => PyValueError::new_err(e),
                    _ => PyKeyError::new_err(format!("`{}` has no param `{name}`", self.info.name)),
                });
            };
            if !v.is_finite() {
                return Err(PyValueError::new_err(format!(
                    "param `{name}` is not finite: {v}"
                )));
            }
            values[i] = *v;
        }
        Ok(values)
    }

    fn sweep_rows(&self, plan: &Plan, params: &[f64], rate: f64) -> Vec<Row> {
        let k = solver_with_params(&self.info.name, &self.model, self.generated, params);
        let c = Continuation::for_input(self.info.inputs[plan.index].kind, plan.span);
        sweep_holding(k.as_ref(), plan.index, &plan.values, rate, &plan.held, &c)
    }
}

fn options(
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

#[pymethods]
impl Mechanism {
    /// The mechanism's name in its file.
    #[getter]
    fn name(&self) -> &str {
        &self.info.name
    }

    /// The params (base params: the derived ones follow from them), name → value.
    #[getter]
    fn params(&self) -> HashMap<String, f64> {
        self.info
            .params
            .iter()
            .map(|p| (p.name.clone(), p.value))
            .collect()
    }

    /// The inputs, unknowns and points, by name, in file order.
    #[getter]
    fn inputs(&self) -> Vec<String> {
        self.info.inputs.iter().map(|c| c.name.clone()).collect()
    }
    #[getter]
    fn unknowns(&self) -> Vec<String> {
        self.info.unknowns.iter().map(|c| c.name.clone()).collect()
    }
    #[getter]
    fn points(&self) -> Vec<String> {
        self.info.points.clone()
    }

    /// `"generated"` (compiled in) or `"generic"` (a file loaded at run time).
    #[getter]
    fn engine(&self) -> &str {
        if self.generated {
            "generated"
        } else {
            "generic"
        }
    }

    /// One sweep, exactly as `mechgen sweep` sweeps it (start/stop/step in degrees for an angle
    /// input, file units for a length input; `rate` rad/s or units/s; `set` holds other inputs).
    /// Returns column name → numpy array: the CSV's columns (radians), `status` as str; the
    /// numbers of a row that is not `ok` are NaN.
    #[pyo3(signature = (start=None, stop=None, step=None, rate=1.0, input=None, set=None, params=None))]
    #[allow(clippy::too_many_arguments)]
    fn sweep<'py>(
        &self,
        py: Python<'py>,
        start: Option<f64>,
        stop: Option<f64>,
        step: Option<f64>,
        rate: f64,
        input: Option<String>,
        set: Option<HashMap<String, f64>>,
        params: Option<HashMap<String, f64>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (o, plan, values) =
            self.prepare(options(start, stop, step, rate, input, set)?, params)?;
        let header = csv_header(&self.info, plan.index);
        let ncols = header.len() - 1;
        let c = py.detach(|| cells(&self.sweep_rows(&plan, &values, o.rate), ncols));
        columns(py, &header[..ncols], c)
    }

    /// The design derivatives along a sweep, as `mechgen sensitivity` gives them (same options
    /// and rows as `sweep`): the input, then for each unknown `u` and param `p` the column `u/p`,
    /// for each point `P` the columns `P_x/p`, `P_y/p` (radians per param unit for angles), then
    /// `status` (a row whose sensitivities fail, at a dead point, has that status, NaN numbers).
    #[pyo3(signature = (start=None, stop=None, step=None, rate=1.0, input=None, set=None, params=None))]
    #[allow(clippy::too_many_arguments)]
    fn sensitivity<'py>(
        &self,
        py: Python<'py>,
        start: Option<f64>,
        stop: Option<f64>,
        step: Option<f64>,
        rate: f64,
        input: Option<String>,
        set: Option<HashMap<String, f64>>,
        params: Option<HashMap<String, f64>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (o, plan, values) =
            self.prepare(options(start, stop, step, rate, input, set)?, params)?;
        let info = &self.info;
        let mut header = vec![info.inputs[plan.index].name.clone()];
        for (out, _) in outputs(info) {
            header.extend(info.params.iter().map(|p| format!("{out}/{}", p.name)));
        }
        let c = py.detach(|| {
            let k = solver_with_params(&info.name, &self.model, self.generated, &values);
            let cont = Continuation::for_input(info.inputs[plan.index].kind, plan.span);
            let rows = sweep_holding(
                k.as_ref(),
                plan.index,
                &plan.values,
                o.rate,
                &plan.held,
                &cont,
            );
            let n = rows.len();
            let mut numbers = vec![f64::NAN; header.len() * n];
            let mut statuses = Vec::with_capacity(n);
            for (r, row) in rows.iter().enumerate() {
                numbers[r] = row.input;
                let s = match &row.result {
                    Ok(s) => {
                        let x = row_inputs(info, plan.index, &plan.held, row.input);
                        design::sensitivity(k.as_ref(), info, &x, &s.q).map_err(|e| e.status())
                    }
                    Err(_) => Err(row.status()),
                };
                match s {
                    Ok(v) => {
                        for (j, v) in v.iter().enumerate() {
                            numbers[(j + 1) * n + r] = *v;
                        }
                        statuses.push("ok");
                    }
                    Err(status) => statuses.push(status),
                }
            }
            Cells { numbers, statuses }
        });
        columns(py, &header, c)
    }

    /// Many param sets, each swept as `sweep` sweeps it, across every core with the GIL
    /// released. `params`: param name → 1-D array, one entry per set (all of one length); the
    /// params not named keep the file's values. Returns column name → 2-D array (sets, rows).
    #[pyo3(signature = (params, start=None, stop=None, step=None, rate=1.0, input=None, set=None))]
    #[allow(clippy::too_many_arguments)]
    fn batch<'py>(
        &self,
        py: Python<'py>,
        params: HashMap<String, Bound<'py, PyAny>>,
        start: Option<f64>,
        stop: Option<f64>,
        step: Option<f64>,
        rate: f64,
        input: Option<String>,
        set: Option<HashMap<String, f64>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let o = options(start, stop, step, rate, input, set)?;
        let plan = self.plan(&o)?;
        let mut names: Vec<&String> = params.keys().collect();
        names.sort();
        let np = py.import("numpy")?;
        let mut columns: Vec<(String, Vec<f64>)> = Vec::new();
        for name in names {
            // Any array-like of numbers, one per set, in any memory layout.
            let a = np.call_method1("asarray", (&params[name], "float64"))?;
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
        let sets: Vec<Vec<f64>> = (0..count)
            .map(|s| {
                let given: Vec<(String, f64)> =
                    columns.iter().map(|(n, c)| (n.clone(), c[s])).collect();
                self.params_with(&given)
            })
            .collect::<PyResult<_>>()?;
        let header = csv_header(&self.info, plan.index);
        let ncols = header.len() - 1;
        let mut all: Vec<Cells> = Vec::with_capacity(count);
        py.detach(|| {
            for_each_ordered(
                count,
                None,
                |s| cells(&self.sweep_rows(&plan, &sets[s], o.rate), ncols),
                |_, c| all.push(c),
            )
        })
        .map_err(PyValueError::new_err)?;
        let nrows = plan.values.len();
        let out = PyDict::new(py);
        for (k, name) in header.iter().take(ncols).enumerate() {
            let mut flat: Vec<f64> = Vec::with_capacity(count * nrows);
            for c in &all {
                flat.extend_from_slice(&c.numbers[k * nrows..(k + 1) * nrows]);
            }
            let a = PyArray1::from_vec(py, flat).reshape([count, nrows])?;
            out.set_item(name, a)?;
        }
        let s = if count == 0 {
            PyArray2::<f64>::zeros(py, [0, nrows], false).into_any()
        } else {
            statuses(py, &all, nrows, false)?
        };
        out.set_item("status", s)?;
        Ok(out)
    }

    fn __repr__(&self) -> String {
        format!("<mechgen.Mechanism {} ({})>", self.info.name, self.engine())
    }
}

/// The mechanisms compiled into this build (`mechanism.toml`, or the file `MECHGEN_MECHANISM`
/// named at build time), name → Mechanism, on their generated solvers.
#[pyfunction]
fn mechanisms() -> PyResult<HashMap<String, Mechanism>> {
    let loaded = mg::generic::load(mg::source::SOURCE_NAME, mg::source::SOURCE)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(into_map(loaded, true))
}

/// Every mechanism of the file at `path`, loaded at run time on the generic engine. A file with
/// errors raises ValueError with every diagnostic (FILE:LINE:COLUMN).
#[pyfunction]
fn load(path: std::path::PathBuf) -> PyResult<HashMap<String, Mechanism>> {
    let loaded = mg::generic::load_file(&path).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(into_map(loaded, false))
}

fn into_map(loaded: Vec<Generic>, generated: bool) -> HashMap<String, Mechanism> {
    loaded
        .into_iter()
        .map(|g| {
            let info = DynMechanism::<f64>::info(&g);
            let m = Mechanism {
                model: g,
                info,
                generated,
            };
            (m.info.name.clone(), m)
        })
        .collect()
}

/// Planar linkage kinematics from loop equations: the generated solvers of the compiled-in
/// mechanism file and the generic engine for any file, sweeps and batches to numpy.
#[pymodule]
fn mechgen(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Mechanism>()?;
    m.add_function(wrap_pyfunction!(mechanisms, m)?)?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    Ok(())
}
