//! Forward dynamics as rows, what `mechgen simulate` and Python's `Mechanism.simulate` print: the
//! runtime's [`Simulation`] from the start configuration, a row every `dt` (time, the input with
//! its rate and acceleration, every unknown, the energies), until the time asked for or the
//! first failure (a dead point), which is the last row's status.

use mechgen_runtime::dynamics::{DynamicsWork, PointLoad, dynamics};
use mechgen_runtime::simulate::{Simulation, SimulationOptions};
use mechgen_runtime::{DynMechanism, SolveError};

/// One row of a simulation.
#[derive(Clone, Debug, PartialEq)]
pub struct SimRow {
    pub t: f64,
    /// The input, its rate and its acceleration.
    pub input: [f64; 3],
    pub q: Vec<f64>,
    pub kinetic: f64,
    pub potential: f64,
    /// `Err`: the simulation stopped here (the other numbers are the last good state's).
    pub status: Result<(), SolveError>,
    /// The input rests on the edge of a load's range, the forces on both sides pushing into it
    /// (status `at-load-edge`: the load there holds it with a value between off and on).
    pub held: bool,
}

impl SimRow {
    /// The CSV status: `ok`, `at-load-edge` ([`SimRow::held`]) or the error's.
    pub fn status(&self) -> &'static str {
        match self.status {
            Err(e) => e.status(),
            Ok(()) if self.held => "at-load-edge",
            Ok(()) => "ok",
        }
    }
}

/// What to simulate: the input (`index`) and the held inputs' values (every input, the
/// simulated one at its start), its start rate, the constant driving effort, the loads, the
/// length of time and the rows' spacing.
#[derive(Clone, Debug)]
pub struct Setup<'a> {
    pub index: usize,
    pub x: &'a [f64],
    pub rate: f64,
    pub effort: f64,
    pub loads: &'a [PointLoad<f64>],
    pub time: f64,
    pub dt: f64,
}

/// How many rows `setup` asks for (the start row included): an error where `time` and `dt`
/// are not positive or give more than `max` rows.
pub fn row_count(time: f64, dt: f64, max: usize) -> Result<usize, String> {
    if dt.is_nan() || dt <= 0.0 || time.is_nan() || time < 0.0 {
        return Err("--time needs a value ≥ 0 and --dt one > 0".into());
    }
    let n = (time / dt * (1.0 + 1e-12)).floor() + 1.0;
    if n > max as f64 {
        return Err(format!(
            "--time {time} with --dt {dt} gives {n} rows, more than {max}: take a larger --dt"
        ));
    }
    Ok(n as usize)
}

/// Runs `setup` on `k` from the start configuration `guess`, handing out each row; stops after
/// the first failed row.
pub fn simulate(
    k: &dyn DynMechanism<f64>,
    setup: &Setup<'_>,
    guess: &[f64],
    emit: &mut dyn FnMut(&SimRow),
) -> Result<(), String> {
    let rows = row_count(setup.time, setup.dt, usize::MAX)?;
    let info = k.info();
    let q_effort = setup.effort;
    let mut effort = move |_: f64, _: f64, _: f64| q_effort;
    let mut sim = Simulation::new(
        k,
        setup.index,
        setup.x,
        setup.rate,
        guess,
        setup.loads,
        SimulationOptions {
            max_step: setup.dt.min(1e-2),
            ..SimulationOptions::default()
        },
        &mut effort,
    )
    .map_err(|e| format!("the start does not solve: {e}"))?;
    let mut ws = DynamicsWork::new(&info);
    let mut row = SimRow {
        t: 0.0,
        input: [0.0; 3],
        q: vec![0.0; info.unknowns.len()],
        kinetic: 0.0,
        potential: 0.0,
        status: Ok(()),
        held: false,
    };
    for i in 0..rows {
        let t = i as f64 * setup.dt;
        let moved = sim.advance_to(t, &mut effort);
        row.t = t;
        match moved {
            Ok(()) => {
                row.input = [sim.position(), sim.rate(), sim.acceleration_now()];
                row.held = sim.held();
                let state = sim.tick().state().ok_or("no state")?;
                row.q.copy_from_slice(state.q);
                let d = dynamics(k, &state, setup.index, setup.loads, &mut ws)
                    .map_err(|e| e.to_string())?;
                row.kinetic = d.kinetic;
                row.potential = d.potential;
            }
            Err(e) => {
                row.status = Err(e);
                emit(&row);
                return Ok(());
            }
        }
        emit(&row);
    }
    Ok(())
}
