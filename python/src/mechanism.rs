//! `mechgen.Mechanism`: one mechanism (or one of its scenes) on its generated solvers (compiled
//! in) or a loaded file's engine, its description in file order, and `sweep`, `batch`,
//! `sensitivity`, `dynamics`, `simulate`.

use mg::branches::Assembly;
use std::collections::HashMap;
use std::sync::Arc;

use mg::batch::solver_with_params;
use mg::design::{self, outputs, row_inputs};
use mg::generic::Generic;
use mg::sweep::plan::Plan;
use mg::sweep::{Continuation, sweep_holding};
use mg::{DynMechanism, MechanismInfo};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString, PyTuple};

use crate::args::{options, param_columns, writable_columns};
use crate::columns::Buffers;
use crate::run::{SETS_PER_BLOCK, sweep_sets};
use crate::scene::SceneFace;

mod setup;

/// Where a mechanism's file came from (what a pickle carries to make it again).
#[derive(Clone)]
pub enum Source {
    /// The file compiled in (generated solvers).
    Compiled,
    /// A file loaded at run time: its name, its text and the engine it runs on.
    File {
        name: String,
        text: String,
        engine: FileEngine,
    },
}

/// How a loaded file runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileEngine {
    /// The interpreter.
    Generic,
    /// Compiled by the JIT (`asked`: a failure to compile is an error, else the interpreter runs).
    Jit { asked: bool },
}

/// One mechanism: its generated solvers (compiled in) or the generic engine (a loaded file).
#[pyclass(frozen, module = "mechgen")]
pub struct Mechanism {
    model: Generic,
    info: MechanismInfo,
    generated: bool,
    /// The start check's warning for this mechanism, said when it is swept.
    warning: Option<String>,
    source: Source,
    /// Where it assembles along each input swept so far (the branch analysis, made once per
    /// input): what tells `other-branch` rows from `unassemblable` ones.
    assembly: std::sync::Mutex<Vec<(usize, Option<std::sync::Arc<Assembly>>)>>,
    /// The scene this object runs (`Mechanism.scene`), if it is one.
    scene: Option<SceneFace>,
    /// The names of a sweep's columns as Python `str`, per input swept so far.
    keys: std::sync::Mutex<Keys>,
}

/// Column names by the index of the input swept.
type Keys = Vec<(usize, Arc<Vec<Py<PyString>>>)>;

#[pymethods]
impl Mechanism {
    /// The mechanism's name in its file.
    #[getter(name)]
    fn py_name(&self) -> &str {
        self.scene.as_ref().map_or(&self.info.name, |s| &s.name)
    }

    /// The params (base params: the derived ones follow from them), name → value, file order.
    #[getter]
    fn params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let out = PyDict::new(py);
        for p in &self.info.params {
            out.set_item(&p.name, p.value)?;
        }
        Ok(out)
    }

    /// The inputs, unknowns and points, by name, in file order. A scene has its mechanism's
    /// inputs (and params: its sweeps take them), and as unknowns and points the outputs it
    /// computes (its `outputs` in the file).
    #[getter]
    fn inputs(&self) -> Vec<String> {
        self.info.inputs.iter().map(|c| c.name.clone()).collect()
    }
    #[getter]
    fn unknowns(&self) -> Vec<String> {
        match &self.scene {
            Some(s) => s.description.unknowns.clone(),
            None => self.info.unknowns.iter().map(|c| c.name.clone()).collect(),
        }
    }
    #[getter]
    fn points(&self) -> Vec<String> {
        match &self.scene {
            Some(s) => s.description.points.clone(),
            None => self.info.points.clone(),
        }
    }

    /// The highest derivative the rows hold: 2 (positions, velocities, accelerations) for a
    /// mechanism, the scene's `order` for a scene.
    #[getter]
    fn order(&self) -> u8 {
        self.scene.as_ref().map_or(2, |s| s.description.order)
    }

    /// `"generated"` (compiled in), `"jit"` (a loaded file compiled at run time) or
    /// `"generic"` (a loaded file interpreted).
    #[getter]
    fn engine(&self) -> &str {
        if self.generated {
            "generated"
        } else if self.model.is_compiled() {
            "jit"
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
        let (o, plan, values) = self.prepare(py, start, stop, step, rate, input, set, params)?;
        let header = self.column_keys(py, &plan);
        let rows = plan.values.len();
        let mut out = Buffers::new(py, header.len(), rows, "sweep")?;
        let job = self.job(&plan, o.rate);
        sweep_sets(py, &job, &[values], vec![out.block()?], rows, None)?;
        out.into_dict(py, &header, &[rows], &self.held(&plan))
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
        self.whole("sensitivity")?;
        let (o, plan, values) = self.prepare(py, start, stop, step, rate, input, set, params)?;
        let info = &self.info;
        let mut header = vec![info.inputs[plan.index].name.clone()];
        for (out, _) in outputs(info) {
            header.extend(info.params.iter().map(|p| format!("{out}/{}", p.name)));
        }
        let n = plan.values.len();
        let mut out = Buffers::new(py, header.len(), n, "sensitivity")?;
        let mut b = out.block()?;
        py.detach(|| {
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
            for (r, row) in rows.iter().enumerate() {
                b.columns[0][r] = row.input;
                let s = match &row.result {
                    Ok(s) => {
                        let x = row_inputs(info, plan.index, &plan.held, row.input);
                        design::sensitivity(k.as_ref(), info, &x, &s.q).map_err(|e| e.status())
                    }
                    Err(_) => Err(row.status()),
                };
                let status = match s {
                    Ok(v) => {
                        for (j, v) in v.iter().enumerate() {
                            b.columns[j + 1][r] = *v;
                        }
                        "ok"
                    }
                    Err(status) => {
                        // A failed row's numbers are NaN (the CSV's empty cells).
                        for c in b.columns[1..].iter_mut() {
                            c[r] = f64::NAN;
                        }
                        status
                    }
                };
                b.codes[r] = mg::report::status_code(status);
            }
        });
        out.into_dict(py, &crate::columns::keys(py, &header), &[n], &[])
    }

    /// Inverse dynamics along a sweep, as `mechgen dynamics` gives it (same options and rows as
    /// `sweep`; a mechanism with bodies): the input at `rate` accelerating at `acc`, `loads` a
    /// list of `(point, fx, fy)` or `(point, fx, fy, (a, b))` acting only while the angle input
    /// lies in [a, b] degrees. Columns: the input, every unknown, `effort_X`, `inertia_X_X`,
    /// `kinetic_energy`, `potential_energy`, `shaking_fx`, `shaking_fy`, `shaking_moment`,
    /// `status`.
    #[pyo3(signature = (start=None, stop=None, step=None, rate=1.0, acc=0.0, loads=None, input=None, set=None, params=None))]
    #[allow(clippy::too_many_arguments)]
    fn dynamics<'py>(
        &self,
        py: Python<'py>,
        start: Option<f64>,
        stop: Option<f64>,
        step: Option<f64>,
        rate: f64,
        acc: f64,
        loads: Option<Vec<Bound<'py, PyTuple>>>,
        input: Option<String>,
        set: Option<HashMap<String, f64>>,
        params: Option<HashMap<String, f64>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        crate::dynamics::dynamics(
            self, py, start, stop, step, rate, acc, loads, input, set, params,
        )
    }

    /// Forward dynamics, as `mechgen simulate` gives it (a mechanism with bodies): the input
    /// (`input`, default the first; the others held at rest, `set` their values in degrees or
    /// file units) from the start configuration at `rate`, under gravity, `loads` (a list of
    /// `(point, fx, fy)`, or `(point, fx, fy, (a, b))` acting while an angle input lies in
    /// [a, b] degrees, as `dynamics`) and the constant driving effort `torque`, a row every `dt` seconds to
    /// `time`. Columns: `t`, the input, `X_vel`, `X_acc`, every unknown, `kinetic_energy`,
    /// `potential_energy`, `status` (a dead point stops it: its row is the last; `at-load-edge`
    /// where the forces on both sides of a load range's edge push into it and the input rests
    /// there).
    #[pyo3(signature = (time, dt, torque=0.0, rate=0.0, loads=None, input=None, set=None, params=None))]
    #[allow(clippy::too_many_arguments)]
    fn simulate<'py>(
        &self,
        py: Python<'py>,
        time: f64,
        dt: f64,
        torque: f64,
        rate: f64,
        loads: Option<Vec<Bound<'py, PyTuple>>>,
        input: Option<String>,
        set: Option<HashMap<String, f64>>,
        params: Option<HashMap<String, f64>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        crate::dynamics::simulate(self, py, time, dt, torque, rate, loads, input, set, params)
    }

    /// Many param sets, each swept as `sweep` sweeps it, on `threads` worker threads (default
    /// every core) with the GIL released. `params`: param name → 1-D array, one entry per set
    /// (all of one length); the params not named keep the file's values. Returns column name →
    /// 2-D array (sets, rows). `MemoryError` (naming the size) before anything is allocated when
    /// the result cannot fit; `Ctrl-C` stops the workers and raises `KeyboardInterrupt`.
    /// `out`: the dict an earlier `batch` of as many sets and rows returned (the same columns),
    /// its number arrays written in place and the dict returned (its `status` a new array), so
    /// that repeated batches reuse their memory.
    #[pyo3(signature = (params, start=None, stop=None, step=None, rate=1.0, input=None, set=None, threads=None, out=None))]
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
        threads: Option<usize>,
        out: Option<Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        if threads == Some(0) {
            return Err(PyValueError::new_err("threads must be at least 1"));
        }
        let o = options(start, stop, step, rate, input, set)?;
        let plan = self.plan(py, &o)?;
        let (columns, count) = param_columns(py, &params)?;
        let np = py.import("numpy")?;
        let rows = plan.values.len();
        let keys = self.column_keys(py, &plan);
        let ncols = keys.len();
        let what = format!("batch of {count} sets × {rows} rows");
        let total = count
            .checked_mul(rows)
            .ok_or_else(|| pyo3::exceptions::PyMemoryError::new_err(what.clone()))?;
        let shape = [count, rows];
        // Where the rows go: fresh buffers, or the arrays of `out` (checked before anything runs).
        let target = match &out {
            Some(dict) => {
                let header = self.columns(&plan);
                Err((dict, writable_columns(dict, &header, &shape)?, header))
            }
            None => Ok(Buffers::new(py, ncols, total, &what)?),
        };
        let sets: Vec<Vec<f64>> = (0..count)
            .map(|s| {
                let given: Vec<(String, f64)> =
                    columns.iter().map(|(n, c)| (n.clone(), c[s])).collect();
                self.params_with(&given)
            })
            .collect::<PyResult<_>>()?;
        let job = self.job(&plan, o.rate);
        let (dict, mut arrays, header) = match target {
            Ok(mut buffers) => {
                let blocks = buffers.blocks(SETS_PER_BLOCK * rows)?;
                sweep_sets(py, &job, &sets, blocks, rows, threads)?;
                return buffers.into_dict(py, &keys, &shape, &self.held(&plan));
            }
            Err(given) => given,
        };
        let mut slices = Vec::with_capacity(ncols);
        for (a, name) in arrays.iter_mut().zip(&header) {
            slices.push(a.as_slice_mut().map_err(|_| {
                PyValueError::new_err(format!("out[\"{name}\"] is not contiguous in memory"))
            })?);
        }
        let mut codes = vec![0u8; total];
        let blocks = crate::columns::blocks(slices, &mut codes, SETS_PER_BLOCK * rows);
        sweep_sets(py, &job, &sets, blocks, rows, threads)?;
        for (name, v) in self.held(&plan) {
            dict.set_item(name, np.call_method1("full", (shape.to_vec(), v))?)?;
        }
        crate::columns::set_statuses(dict, codes, &shape)?;
        Ok(dict.clone())
    }

    /// Pickling (so that `client.submit(m.batch, …)` works on Dask): the mechanism's name and
    /// the text of the file it was loaded from (nothing for a compiled-in one).
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let restore = py.import("mechgen")?.getattr("_restore")?;
        let scene = self.scene.as_ref().map(|s| s.name.clone());
        let args = match &self.source {
            Source::Compiled => (self.info.name.clone(), None, None, None, scene),
            Source::File { name, text, .. } => (
                self.info.name.clone(),
                Some(name.clone()),
                Some(text.clone()),
                Some(self.engine().to_string()),
                scene,
            ),
        };
        Ok((restore, args.into_pyobject(py)?))
    }

    fn __repr__(&self) -> String {
        match &self.scene {
            Some(s) => format!(
                "<mechgen.Mechanism {} (scene of {}, {})>",
                s.name,
                self.info.name,
                self.engine()
            ),
            None => format!("<mechgen.Mechanism {} ({})>", self.info.name, self.engine()),
        }
    }

    /// The names of the mechanism's scenes, in file order.
    #[getter]
    fn scenes(&self) -> Vec<String> {
        self.model
            .scene_names()
            .into_iter()
            .map(String::from)
            .collect()
    }

    /// Scene `name` of this mechanism: an object whose `sweep` and `batch` sweep the mechanism
    /// as they do (its branch rule, statuses, params) and at every row run the scene's solver,
    /// with the columns of `mechgen sweep SCENE` (the input, the scene's outputs, `cond`,
    /// `status`); `KeyError` naming the mechanism's scenes when it has no such scene.
    pub fn scene(&self, name: &str) -> PyResult<Mechanism> {
        Ok(Mechanism {
            model: self.model.clone(),
            info: self.info.clone(),
            generated: self.generated,
            warning: self.warning.clone(),
            source: self.source.clone(),
            assembly: Default::default(),
            keys: Default::default(),
            scene: Some(SceneFace::of(&self.model, name)?),
        })
    }

    /// For a scene, the name of its mechanism; `None` for a mechanism.
    #[getter]
    fn mechanism(&self) -> Option<String> {
        self.scene.as_ref().map(|_| self.info.name.clone())
    }
}

impl crate::dynamics::Source for Mechanism {
    fn info(&self) -> &MechanismInfo {
        &self.info
    }
    fn prepared(
        &self,
        py: Python<'_>,
        start: Option<f64>,
        stop: Option<f64>,
        step: Option<f64>,
        rate: f64,
        input: Option<String>,
        set: Option<HashMap<String, f64>>,
        params: Option<HashMap<String, f64>>,
    ) -> PyResult<(f64, Plan, Vec<f64>)> {
        self.whole("`dynamics` (and `simulate`)")?;
        let (o, plan, values) = self.prepare(py, start, stop, step, rate, input, set, params)?;
        Ok((o.rate, plan, values))
    }
    fn solver(&self, values: &[f64]) -> Box<dyn DynMechanism<f64>> {
        solver_with_params(&self.info.name, &self.model, self.generated, values)
    }
}
