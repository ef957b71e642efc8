//! `mechgen.Mechanism`'s setup: every mechanism of a source made, and what a call makes before
//! it runs (its plan, its params, its columns' names, kept as `str` per input swept, its job, the
//! branch analysis kept per input).

use std::collections::HashMap;
use std::sync::Arc;

use mg::DynMechanism;
use mg::branches::Assembly;
use mg::report::csv_header;
use mg::sweep::check_start;
use mg::sweep::plan::{Plan, plan};
use pyo3::exceptions::{PyKeyError, PyUserWarning, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyString;

use super::{FileEngine, Keys, Mechanism, Source};
use crate::args::{Options, options};
use crate::run::Job;

impl Mechanism {
    /// Every mechanism of `source`, in file order.
    pub fn from_source(source: Source) -> PyResult<Vec<Mechanism>> {
        let (name, text, generated, engine) = match &source {
            Source::Compiled => (mg::source::SOURCE_NAME, mg::source::SOURCE, true, None),
            Source::File { name, text, engine } => {
                (name.as_str(), text.as_str(), false, Some(*engine))
            }
        };
        let loaded = mg::generic::load_with_start_warnings(name, text)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        loaded
            .into_iter()
            .map(|(mut g, warning)| {
                if let Some(FileEngine::Jit { asked }) = engine {
                    match g.compile() {
                        Ok(_) => {}
                        Err(e) if asked => {
                            return Err(PyValueError::new_err(format!("{}: {e}", g.name())));
                        }
                        Err(_) => {}
                    }
                }
                Ok(Mechanism {
                    info: DynMechanism::<f64>::info(&g),
                    model: g,
                    generated,
                    warning,
                    source: source.clone(),
                    assembly: Default::default(),
                    keys: Default::default(),
                    scene: None,
                })
            })
            .collect()
    }

    pub fn name(&self) -> &str {
        &self.info.name
    }

    pub(super) fn plan(&self, py: Python<'_>, o: &Options) -> PyResult<Plan> {
        let p = plan(&self.info, o.input.as_deref(), &o.set, o.range)
            .map_err(crate::messages::keyword_error)?;
        check_start(&self.info)
            .map_err(|e| PyValueError::new_err(format!("{}: {e}", self.info.name)))?;
        if let Some(w) = &self.warning {
            PyErr::warn(
                py,
                &py.get_type::<PyUserWarning>(),
                &std::ffi::CString::new(w.trim_end()).unwrap_or_default(),
                1,
            )?;
        }
        Ok(p)
    }

    /// A one-sweep call's options, its plan and its base params (`params`: name → value in place
    /// of the file's).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn prepare(
        &self,
        py: Python<'_>,
        start: Option<f64>,
        stop: Option<f64>,
        step: Option<f64>,
        rate: f64,
        input: Option<String>,
        set: Option<HashMap<String, f64>>,
        params: Option<HashMap<String, f64>>,
    ) -> PyResult<(Options, Plan, Vec<f64>)> {
        let o = options(start, stop, step, rate, input, set)?;
        let plan = self.plan(py, &o)?;
        let given: Vec<(String, f64)> = params.unwrap_or_default().into_iter().collect();
        let values = self.params_with(&given)?;
        Ok((o, plan, values))
    }

    /// The base params with `given` (name → value) in place of the file's.
    pub(super) fn params_with(&self, given: &[(String, f64)]) -> PyResult<Vec<f64>> {
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

    /// The number columns of a sweep of `plan` (the CSV's, `status` aside): the mechanism's, or
    /// the scene's.
    pub(super) fn columns(&self, plan: &Plan) -> Vec<String> {
        match &self.scene {
            Some(s) => s.columns(&self.info.inputs[plan.index].name),
            None => {
                let mut header = csv_header(&self.info, plan.index);
                header.pop();
                header
            }
        }
    }

    /// [`Mechanism::columns`] as Python `str`, made at the first sweep along `plan`'s input and
    /// kept (a sweep of a few rows spent a tenth of its call making them).
    pub(super) fn column_keys(&self, py: Python<'_>, plan: &Plan) -> Arc<Vec<Py<PyString>>> {
        let kept = |made: &Keys| {
            let found = made.iter().find(|(i, _)| *i == plan.index);
            found.map(|(_, k)| Arc::clone(k))
        };
        if let Some(k) = kept(&self.keys.lock().unwrap_or_else(|e| e.into_inner())) {
            return k;
        }
        let keys = Arc::new(crate::columns::keys(py, &self.columns(plan)));
        let mut made = self.keys.lock().unwrap_or_else(|e| e.into_inner());
        made.push((plan.index, Arc::clone(&keys)));
        keys
    }

    /// `Err` for a scene: what `what` (a method that runs whole mechanisms) says of it.
    pub(super) fn whole(&self, what: &str) -> PyResult<()> {
        match &self.scene {
            Some(s) => Err(s.refuse(what)),
            None => Ok(()),
        }
    }

    /// The inputs a sweep of `plan` holds, by name, with their values (file units: radians for
    /// an angle), as the CSV records them (a scene's CSV has none).
    pub(super) fn held(&self, plan: &Plan) -> Vec<(String, f64)> {
        if self.scene.is_some() {
            return Vec::new();
        }
        mg::report::held_inputs(&self.info, plan.index, &plan.held)
            .into_iter()
            .map(|(i, v)| (self.info.inputs[i].name.clone(), v))
            .collect()
    }

    pub(super) fn job<'a>(&'a self, plan: &'a Plan, rate: f64) -> Job<'a> {
        Job {
            name: &self.info.name,
            model: &self.model,
            info: &self.info,
            generated: self.generated,
            plan,
            rate,
            assembly: self.assembly(plan.index),
            scene: self.scene.as_ref().map(|s| s.name.as_str()),
        }
    }

    /// The branch analysis along input `index`, made at its first use.
    pub(super) fn assembly(&self, index: usize) -> Option<std::sync::Arc<Assembly>> {
        let mut made = self.assembly.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, a)) = made.iter().find(|(i, _)| *i == index) {
            return a.clone();
        }
        let (file, text) = match &self.source {
            Source::Compiled => (mg::source::SOURCE_NAME, mg::source::SOURCE),
            Source::File { name, text, .. } => (name.as_str(), text.as_str()),
        };
        let a = Assembly::from_text(file, text, &self.info.name, index).map(std::sync::Arc::new);
        made.push((index, a.clone()));
        a
    }
}
