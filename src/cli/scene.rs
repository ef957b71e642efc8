//! CLI, scenes: `mechgen sweep SCENE` (streamed) and the main job's scene sweeps. The scene's mechanism is
//! swept as usual (branch, options, statuses); the scene's solver (generated, or the generic
//! engine's on the same `ScenePlan`) gives the columns (interfaces.md, "Scenes on the command line").

use std::path::Path;

use mechgen::generic::Generic;
use std::io::Write as _;

use mechgen::sweep::scene::{
    SceneRow, SceneSolver, SceneTable, scene_csv, scene_csv_header, scene_csv_row, scene_rows,
    scene_table,
};
use mechgen::sweep::{Continuation, check_start};
use mechgen::{DynScene, MechanismInfo, SceneDescription, report};

use super::args::{Engine, SweepArgs};
use super::load::{Loaded, Swept, held_inputs, run_plan, select, stream_plan, write_plots};
use super::out::Out;
use mechgen::sweep::plan::{Plan, Range, plan};

/// The mechanism that scene `name` of `loaded` runs on, if `name` is a scene.
pub fn scene_mechanism<'a>(loaded: &'a Loaded, name: &str) -> Option<&'a Generic> {
    loaded
        .mechs
        .iter()
        .find(|m| m.scene_names().contains(&name))
}

/// Scene `name` of `mech` with the engine `select` chooses for its mechanism.
fn select_scene(
    mech: &Generic,
    name: &str,
    file: Option<&Path>,
    engine: Option<Engine>,
) -> Result<Box<dyn DynScene<f64>>, String> {
    let asked = engine.is_some();
    let engine = super::load::engine_for(file, engine);
    let scene: Option<Box<dyn DynScene<f64>>> = match engine {
        Engine::Generated => mechgen::lookup_scene::<f64>(name),
        Engine::Generic | Engine::Jit => {
            let mut mech = mech.clone();
            super::load::prepare(&mut mech, engine, asked)?;
            mech.scene(name)
                .map(|s| Box::new(s) as Box<dyn DynScene<f64>>)
        }
    };
    scene.ok_or_else(|| format!("no compiled-in scene `{name}`"))
}

/// A scene sweep held whole (the main job's): what ran, and the scene's rows.
struct SceneSweep {
    info: MechanismInfo,
    swept: Swept,
    scene: SceneDescription,
    rows: Vec<SceneRow>,
}

/// Sweeps scene `name` of `mech` whole: its mechanism's branch over the plan `plan_of` gives, then the
/// scene's solver at every row.
fn sweep_scene(
    loaded: &Loaded,
    mech: &Generic,
    name: &str,
    (file, engine): (Option<&Path>, Option<Engine>),
    plan_of: impl FnOnce(&MechanismInfo) -> Result<Plan, String>,
    rate: f64,
) -> Result<SceneSweep, String> {
    let sel = select(loaded, mech.name(), file, engine)?;
    let solver = select_scene(mech, name, file, engine)?;
    let info = sel.solver.info();
    let swept = run_plan(sel.solver.as_ref(), &info, plan_of(&info)?, rate)?;
    let index = swept.plan.index;
    let continuation = Continuation::for_input(info.inputs[index].kind, swept.plan.span);
    let x = swept.inputs(&info);
    let rows = scene_rows(
        solver.as_ref(),
        &x,
        index,
        &swept.rows,
        rate,
        &continuation.options,
    );
    Ok(SceneSweep {
        info,
        swept,
        scene: solver.info(),
        rows,
    })
}

impl SceneSweep {
    /// The table with the mechanism's preamble (units, rate, held inputs).
    fn table(&self) -> String {
        let index = self.swept.plan.index;
        let mut out = report::preamble(
            &self.info,
            index,
            self.swept.rate,
            &self.swept.inputs(&self.info),
        );
        out.push_str(&scene_table(&self.scene, &self.info, index, &self.rows));
        out
    }

    fn write_csv(&self, path: &Path) -> Result<(), String> {
        let input = &self.info.inputs[self.swept.plan.index].name;
        std::fs::write(path, scene_csv(&self.scene, input, &self.rows))
            .map_err(|e| format!("cannot write {}: {e}", path.display()))
    }
}

/// `mechgen sweep SCENE [options]`: rows printed and written as they are solved (only what
/// plots read is kept).
pub fn sweep(loaded: &Loaded, mech: &Generic, args: &SweepArgs) -> Result<(), String> {
    if let Some(w) = loaded.start_warning(mech.name()) {
        tell_raw!("{w}");
    }
    let range = Range {
        from: args.from,
        to: args.to,
        step: args.step,
    };
    let (file, engine) = (args.file.as_deref(), args.engine);
    let sel = select(loaded, mech.name(), file, engine)?;
    let solver = select_scene(mech, &args.name, file, engine)?;
    let info = sel.solver.info();
    let plan = plan(&info, args.input.as_deref(), &args.set, range)?;
    check_start(&info).map_err(|e| format!("{}: {e}", info.name))?;
    let (scene, index) = (solver.info(), plan.index);
    let continuation = Continuation::for_input(info.inputs[index].kind, plan.span);
    let x = held_inputs(&info, &plan);
    let mut rows = SceneSolver::new(solver.as_ref(), &x, index, args.rate, &continuation.options);
    let table = SceneTable::new(&scene, &info, index);
    let header = scene_csv_header(&scene, &info.inputs[index].name).join(",") + "\n";
    let mut csv = match &args.csv {
        Some(path) => Some(Out::create(path, &header)?),
        None => None,
    };
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::with_capacity(super::OUTPUT_BUFFER, stdout.lock());
    let _ = write!(
        out,
        "{} (scene of {}, order {}; {} rows)\n{}{}",
        scene.name,
        scene.mechanism,
        scene.order,
        plan.values.len(),
        report::preamble(&info, index, args.rate, &x),
        table.header()
    );
    let mut line = String::new();
    let swept = stream_plan(
        sel.solver.as_ref(),
        &info,
        plan,
        args.rate,
        None,
        &mut |r| {
            let row = rows.row(r);
            line.clear();
            table.row(&mut line, &row);
            // A closed stdout (`… | head`) ends the table, not the rows or their CSV.
            let _ = out.write_all(line.as_bytes());
            if let Some(csv) = &mut csv {
                line.clear();
                scene_csv_row(&mut line, scene.columns.len(), &row);
                csv.write(line.as_bytes());
            }
        },
    )?;
    let _ = out.flush();
    drop(out);
    if let Some(csv) = csv {
        csv.finish()?;
    }
    write_plots(
        &sel,
        &info,
        &swept,
        args.plot.as_deref(),
        args.animate.as_deref(),
        true,
    )
}

/// The main job's sweep of scene `name` over its mechanism's default range: table and
/// `DIR/NAME.csv`.
pub fn main_job_scene(
    loaded: &Loaded,
    name: &str,
    file: Option<&Path>,
    dir: &Path,
    range: impl FnOnce(&MechanismInfo) -> Range,
) -> Result<(), String> {
    let mech = scene_mechanism(loaded, name).ok_or_else(|| format!("no scene `{name}`"))?;
    let s = sweep_scene(
        loaded,
        mech,
        name,
        (file, None),
        |info| plan(info, None, &[], range(info)),
        1.0,
    )?;
    say!(
        "{} — scene of {}, order {}",
        name,
        s.scene.mechanism,
        s.scene.order
    );
    say!("{}", s.table());
    s.write_csv(&dir.join(format!("{name}.csv")))
}
