//! `Mechanism.dynamics` and `Mechanism.simulate`: a mechanism with bodies, its inverse dynamics
//! along a sweep (`mechgen::kinetics`) and its forward dynamics (`mechgen::simulation`), into the
//! columns of `mechgen dynamics` and `mechgen simulate`.

use std::collections::HashMap;

use mg::design::row_inputs;
use mg::dynamics::PointLoad;
use mg::kinetics;
use mg::sweep::plan::Plan;
use mg::sweep::{Continuation, sweep_each};
use mg::{DynMechanism, MechanismInfo};
use pyo3::exceptions::{PyKeyError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::columns::Buffers;

/// What the dynamics need of a `Mechanism` (implemented beside it, in `mechanism.rs`).
pub trait Source: Sync {
    fn info(&self) -> &MechanismInfo;
    /// The sweep the options ask for: (input rate, plan, base param values).
    #[allow(clippy::too_many_arguments)]
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
    ) -> PyResult<(f64, Plan, Vec<f64>)>;
    /// The solver with those params.
    fn solver(&self, values: &[f64]) -> Box<dyn DynMechanism<f64>>;
}

/// `Mechanism.dynamics` (its Python docstring says what it gives).
#[allow(clippy::too_many_arguments)]
pub fn dynamics<'py>(
    m: &impl Source,
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
    let info = m.info();
    kinetics::require_bodies(info, "use dynamics").map_err(PyValueError::new_err)?;
    if !acc.is_finite() {
        return Err(PyValueError::new_err(format!("acc is not finite: {acc}")));
    }
    let (rate, plan, values) = m.prepared(py, start, stop, step, rate, input, set, params)?;
    let angle = info.inputs[plan.index].kind == mg::Kind::Angle;
    let loads = ranged_loads(info, loads.unwrap_or_default(), angle)?;
    let mut header = vec![info.inputs[plan.index].name.clone()];
    header.extend(info.unknowns.iter().map(|u| u.name.clone()));
    header.extend(kinetics::column_names(&info.inputs[plan.index].name));
    let n = plan.values.len();
    let mut out = Buffers::new(py, header.len(), n, "dynamics")?;
    let mut b = out.block()?;
    py.detach(|| {
        let k = m.solver(&values);
        let cont = Continuation::for_input(info.inputs[plan.index].kind, plan.span);
        // Each row as the sweep hands it out: nothing allocated per row.
        let mut ws = kinetics::RowWork::new(info);
        let nu = info.unknowns.len();
        let mut x = row_inputs(info, plan.index, &plan.held, 0.0);
        let mut r = 0;
        let (index, motion) = (plan.index, (rate, acc));
        sweep_each(
            k.as_ref(),
            index,
            &plan.values,
            rate,
            &plan.held,
            &cont,
            &mut |row| {
                b.columns[0][r] = row.input;
                x[index] = row.input;
                let d = match &row.result {
                    Ok(s) => {
                        kinetics::row_dynamics(k.as_ref(), &x, index, s, motion, &loads, &mut ws)
                            .map(|d| (s.q, d))
                            .map_err(|e| e.status())
                    }
                    Err(_) => Err(row.status()),
                };
                let status = match d {
                    Ok((q, d)) => {
                        for (j, v) in q.iter().chain(&kinetics::values(&d)).enumerate() {
                            b.columns[j + 1][r] = *v;
                        }
                        "ok"
                    }
                    Err(status) => {
                        for c in b.columns[1..=nu + 7].iter_mut() {
                            c[r] = f64::NAN;
                        }
                        status
                    }
                };
                b.codes[r] = mg::report::status_code(status);
                r += 1;
            },
        );
    });
    out.into_dict(py, &crate::columns::keys(py, &header), &[n], &[])
}

/// `Mechanism.simulate` (its Python docstring says what it gives).
#[allow(clippy::too_many_arguments)]
pub fn simulate<'py>(
    m: &impl Source,
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
    let info = m.info();
    kinetics::require_bodies(info, "simulate it").map_err(PyValueError::new_err)?;
    if !torque.is_finite() || !rate.is_finite() {
        return Err(PyValueError::new_err("torque and rate must be finite"));
    }
    let rows =
        mg::simulation::row_count(time, dt, 100_000_000).map_err(crate::messages::keyword_error)?;
    let index = match &input {
        Some(n) => mg::sweep::plan::input_index(info, n)
            .map_err(|e| PyKeyError::new_err(crate::messages::python_words(&e)))?,
        None => 0,
    };
    let start = info.inputs[index].start;
    let deg = info.inputs[index].kind == mg::Kind::Angle;
    let from = if deg { start.to_degrees() } else { start };
    let (_, plan, values) =
        m.prepared(py, Some(from), Some(from), None, rate, input, set, params)?;
    let loads = ranged_loads(info, loads.unwrap_or_default(), deg)?;
    let name = &info.inputs[index].name;
    let mut header = vec![
        "t".to_string(),
        name.clone(),
        format!("{name}_vel"),
        format!("{name}_acc"),
    ];
    header.extend(info.unknowns.iter().map(|u| u.name.clone()));
    header.extend(["kinetic_energy".to_string(), "potential_energy".to_string()]);
    let mut out = Buffers::new(py, header.len(), rows, "simulate")?;
    let mut x: Vec<f64> = info.inputs.iter().map(|i| i.start).collect();
    for &(i, v) in &plan.held {
        x[i] = v;
    }
    let guess: Vec<f64> = info.unknowns.iter().map(|u| u.start).collect();
    let mut b = out.block()?;
    let written = py.detach(|| {
        let k = m.solver(&values);
        let setup = mg::simulation::Setup {
            index,
            x: &x,
            rate,
            effort: torque,
            loads: &loads,
            time,
            dt,
        };
        let mut r = 0;
        let run = mg::simulation::simulate(k.as_ref(), &setup, &guess, &mut |row| {
            b.columns[0][r] = row.t;
            let values = row
                .input
                .iter()
                .chain(&row.q)
                .chain([&row.kinetic, &row.potential]);
            for (c, v) in values.enumerate() {
                b.columns[c + 1][r] = if row.status.is_ok() { *v } else { f64::NAN };
            }
            let status = row.status();
            b.codes[r] = mg::report::status_code(status);
            r += 1;
        });
        run.map(|()| r)
    });
    let written = written.map_err(PyValueError::new_err)?;
    // The rows written (a run stopped early writes fewer than it had room for).
    out.into_dict(py, &crate::columns::keys(py, &header), &[written], &[])
}

/// `(point, fx, fy)` or `(point, fx, fy, (a, b))` (degrees) → loads by point index.
fn ranged_loads(
    info: &MechanismInfo,
    loads: Vec<Bound<'_, PyTuple>>,
    angle: bool,
) -> PyResult<Vec<PointLoad<f64>>> {
    loads
        .into_iter()
        .map(|t| {
            let bad = || {
                PyValueError::new_err(
                    "a load is (point, fx, fy) or (point, fx, fy, (a, b)) with finite numbers",
                )
            };
            let (name, fx, fy, range): (String, f64, f64, Option<(f64, f64)>) = match t.len() {
                3 => {
                    let (n, fx, fy) = t.extract()?;
                    (n, fx, fy, None)
                }
                4 => {
                    let (n, fx, fy, r) = t.extract()?;
                    (n, fx, fy, Some(r))
                }
                _ => return Err(bad()),
            };
            let finite = [fx, fy]
                .into_iter()
                .chain(range.map(|r| [r.0, r.1]).into_iter().flatten());
            if !finite.into_iter().all(f64::is_finite) {
                return Err(bad());
            }
            let point = info.points.iter().position(|p| p == &name).ok_or_else(|| {
                PyKeyError::new_err(format!("`{}` has no point `{name}`", info.name))
            })?;
            if range.is_some() && !angle {
                return Err(PyValueError::new_err(
                    "a load's range of degrees needs an angle input",
                ));
            }
            Ok(PointLoad {
                point,
                force: [fx, fy],
                range: range.map(|(a, b)| [a.to_radians(), b.to_radians()]),
            })
        })
        .collect()
}
