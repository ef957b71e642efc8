//! Generic engine, solvers: a mechanism loaded at run time (through mechgen-codegen's parser,
//! checker, lowering and derivatives), its DAG compiled to tapes per diagonal block; `driver.rs`
//! solves them with the same block Newton, kernels and elimination as the generated code.

use mechgen_codegen::{Compiled, Diagnostic, SourceFile};

use super::closed::ClosedTape;
use super::tape::Tape;
use mechgen_runtime::{CoordDesc, Kind, MechanismInfo, ParamDesc};

/// A mechanism file that could not be loaded: every diagnostic, rendered as FILE:LINE:COLUMN.
#[derive(Clone, Debug)]
pub struct LoadError {
    pub rendered: String,
    pub diagnostics: Vec<Diagnostic>,
}

impl std::fmt::Display for LoadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.rendered.trim_end())
    }
}

impl std::error::Error for LoadError {}

/// The tapes of one diagonal block.
#[derive(Clone, Debug)]
pub(super) struct BlockTapes {
    pub equations: Vec<usize>,
    pub unknowns: Vec<usize>,
    pub length: Vec<bool>,
    /// k residuals, then the k×k Jacobian row-major.
    pub position: Tape,
    /// The k residuals alone (evaluated in double-word arithmetic to refine positions).
    pub residual: Tape,
    /// k velocity right-hand sides, then the Jacobian (factored once for both rates).
    pub velocity: Tape,
    /// k acceleration right-hand sides.
    pub acceleration: Tape,
    /// The kind and roots of a closed-form block (solved by its kernel); `None`: Newton.
    pub closed: Option<ClosedTape>,
}

/// A mechanism solved by interpreting its expression DAG.
#[derive(Clone, Debug)]
pub struct Generic {
    pub(super) info: MechanismInfo,
    pub(super) params: Vec<f64>,
    pub(super) length_param: Vec<bool>,
    /// The checked model, for recomputing derived params when a base param changes.
    pub(super) model: std::sync::Arc<mechgen_codegen::Model>,
    pub(super) blocks: Vec<BlockTapes>,
    /// Every block index, in solve order (the whole mechanism's plan).
    pub(super) order: Vec<usize>,
    /// Which unknowns are angles (their sines and cosines are kept in step through a solve).
    pub(super) angle: Vec<bool>,
    pub(super) residual: Tape,
    pub(super) jacobian: Tape,
    pub(super) input_jacobian: Tape,
    /// Φp (equations × params), then ∂P/∂q and ∂P/∂p (rows `P_x`, `P_y` per point), row-major.
    pub(super) sensitivity: Tape,
    pub(super) jacobian_dot: Tape,
    pub(super) acceleration_rhs: Tape,
    /// Per point: x, y, vx, vy, ax, ay.
    pub(super) points: Tape,
    /// Per body: its centre's x, y and angle, their velocities, their accelerations.
    pub(super) bodies: Tape,
    /// Gravity's x, y (when the file gives it), then per body: mass, inertia.
    pub(super) masses: Tape,
    pub(super) gravity: bool,
    /// Joint positions of the drawing chains, and each chain's (vertex count, ground segments).
    pub(super) chains: Tape,
    pub(super) chain_shape: Vec<(usize, usize)>,
    /// The drawing structure (terms classified by how they move).
    pub(super) linkage: std::sync::Arc<super::linkage::Linkage>,
    /// The file's scenes on this mechanism, each from its `ScenePlan`.
    pub(super) scenes: Vec<super::scene_tapes::SceneTapes>,
    /// The params-only values the program reads after the params, as a tape of the params.
    pub(super) prelude: Tape,
    /// The whole motion as one program (what the JIT compiles into one function); `None` when
    /// it could not be built.
    pub(super) program: Option<std::sync::Arc<super::program::Program>>,
    /// What the program reads besides the state (`None`: no program); kept with the params.
    pub(super) program_params: Option<ProgramParams>,
    /// That program compiled ([`Generic::compile`]).
    #[cfg(feature = "jit")]
    pub(super) fused: Option<super::jit::Fused>,
}

/// A block's unknowns as indices (what the run-time descriptions and tapes index by).
fn unknown_indices(b: &mechgen_codegen::Block) -> Vec<usize> {
    b.unknowns.iter().map(|u| u.index()).collect()
}

/// Loads every mechanism of a file's text. Warnings are dropped; see [`load_with_warnings`].
pub fn load(name: &str, text: &str) -> Result<Vec<Generic>, LoadError> {
    load_with_warnings(name, text).map(|(m, _)| m)
}

/// Loads every mechanism of a file's text; also returns the rendered warnings.
pub fn load_with_warnings(name: &str, text: &str) -> Result<(Vec<Generic>, String), LoadError> {
    let file = SourceFile::new(name, text);
    let (compiled, diagnostics) = mechgen_codegen::analyze(&file);
    let rendered = mechgen_codegen::diagnostic::render(&file, &diagnostics);
    if diagnostics.iter().any(Diagnostic::is_error) {
        return Err(LoadError {
            rendered,
            diagnostics,
        });
    }
    Ok((compiled.iter().map(Generic::new).collect(), rendered))
}

/// The start check's warning for mechanism `name`, rendered as `mechgen check` prints it, if the
/// file has one: its start did not close the loops and Newton converged somewhere, maybe on
/// another branch.
pub fn start_warning(file: &SourceFile, diagnostics: &[Diagnostic], name: &str) -> Option<String> {
    let prefix = format!("start configuration of `{name}`");
    let mine: Vec<Diagnostic> = diagnostics
        .iter()
        .filter(|d| d.severity == mechgen_codegen::diagnostic::Severity::Warning)
        .filter(|d| d.message.starts_with(&prefix))
        .cloned()
        .collect();
    (!mine.is_empty()).then(|| mechgen_codegen::diagnostic::render(file, &mine))
}

/// Loads every mechanism of a file's text, each with its start warning ([`start_warning`]).
pub fn load_with_start_warnings(
    name: &str,
    text: &str,
) -> Result<Vec<(Generic, Option<String>)>, LoadError> {
    let file = SourceFile::new(name, text);
    let (compiled, diagnostics) = mechgen_codegen::analyze(&file);
    if diagnostics.iter().any(Diagnostic::is_error) {
        let rendered = mechgen_codegen::diagnostic::render(&file, &diagnostics);
        return Err(LoadError {
            rendered,
            diagnostics,
        });
    }
    Ok(compiled
        .iter()
        .map(|c| {
            let g = Generic::new(c);
            let w = start_warning(&file, &diagnostics, g.name());
            (g, w)
        })
        .collect())
}

/// Reads and loads a mechanism file.
pub fn load_file(path: &std::path::Path) -> Result<Vec<Generic>, LoadError> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| LoadError {
        rendered: format!("{name}: error: cannot read mechanism file: {e}"),
        diagnostics: Vec::new(),
    })?;
    load(&name, &text)
}

impl Generic {
    /// Compiles the tapes of an analysed mechanism.
    pub fn new(c: &Compiled) -> Generic {
        let m = &c.model;
        let mut dag = c.system.dag.clone();
        let chains = mechgen_codegen::chains(m, &mut dag);
        let d = &c.derivatives;
        let flat = |rows: &[Vec<_>]| rows.iter().flatten().copied().collect::<Vec<_>>();
        let coords = |cs: &[mechgen_codegen::Coord]| {
            cs.iter()
                .map(|c| CoordDesc {
                    name: c.name.text.clone(),
                    kind: c.kind,
                    start: c.start,
                })
                .collect::<Vec<_>>()
        };
        let info = MechanismInfo {
            name: m.name.text.clone(),
            description: m.description.clone(),
            inputs: coords(&m.inputs),
            unknowns: coords(&m.unknowns),
            params: m
                .params
                .iter()
                .map(|p| ParamDesc {
                    name: p.name.text.clone(),
                    kind: p.kind,
                    value: p.value,
                })
                .collect(),
            points: m.points.iter().map(|p| p.0.text.clone()).collect(),
            blocks: c.blocks.iter().map(|b| unknown_indices(&b.block)).collect(),
            closed: c.blocks.iter().map(|b| b.closed_form.is_some()).collect(),
            bodies: m.bodies.iter().map(|b| b.name.text.clone()).collect(),
        };
        let blocks: Vec<BlockTapes> = c
            .blocks
            .iter()
            .map(|b| {
                let with_jac = |head: &[_]| {
                    let mut roots = head.to_vec();
                    roots.extend(flat(&b.jacobian));
                    Tape::new(&dag, &roots)
                };
                BlockTapes {
                    equations: b.block.equations.iter().map(|e| e.index()).collect(),
                    unknowns: unknown_indices(&b.block),
                    length: b
                        .block
                        .unknowns
                        .iter()
                        .map(|&k| m.unknowns[k.index()].kind == Kind::Length)
                        .collect(),
                    position: with_jac(&b.residual),
                    residual: Tape::new(&dag, &b.residual),
                    velocity: with_jac(&b.velocity_rhs),
                    acceleration: Tape::new(&dag, &b.acceleration_rhs),
                    closed: b.closed_form.as_ref().map(|f| ClosedTape {
                        form: f.clone(),
                        roots: Tape::new(&dag, f.roots()),
                    }),
                }
            })
            .collect();
        let mut point_roots = Vec::new();
        for p in 0..m.points.len() {
            point_roots.extend(c.system.points[p]);
            point_roots.extend(d.point_velocity[p]);
            point_roots.extend(d.point_acceleration[p]);
        }
        let mut body_roots = Vec::new();
        for (b, n) in c.system.bodies.iter().enumerate() {
            body_roots.extend([n.com[0], n.com[1], n.angle]);
            body_roots.extend(d.body_velocity[b]);
            body_roots.extend(d.body_acceleration[b]);
        }
        let mut mass_roots: Vec<_> = c.system.gravity.into_iter().flatten().collect();
        mass_roots.extend(c.system.bodies.iter().flat_map(|n| [n.mass, n.inertia]));
        let chain_roots: Vec<_> = chains.iter().flat_map(|ch| ch.vertices.concat()).collect();
        let mut sensitivity_roots = flat(&d.param_jacobian);
        for per_point in [&d.point_jacobian, &d.point_param_jacobian] {
            sensitivity_roots.extend(per_point.iter().flat_map(|p| p.iter().flatten()));
        }
        let program = super::program::Program::motion(c, &mut dag);
        let prelude =
            (program.as_ref()).map_or_else(Tape::default, |p| Tape::new(&dag, &p.prelude));
        let mut g = Generic {
            params: m.params.iter().map(|p| p.value).collect(),
            length_param: m.params.iter().map(|p| p.kind == Kind::Length).collect(),
            order: (0..blocks.len()).collect(),
            angle: m.unknowns.iter().map(|u| u.kind == Kind::Angle).collect(),
            blocks,
            residual: Tape::new(&dag, &c.system.residuals),
            jacobian: Tape::new(&dag, &flat(&d.jacobian)),
            input_jacobian: Tape::new(&dag, &flat(&d.input_jacobian)),
            sensitivity: Tape::new(&dag, &sensitivity_roots),
            jacobian_dot: Tape::new(&dag, &flat(&d.jacobian_dot)),
            acceleration_rhs: Tape::new(&dag, &d.acceleration_rhs),
            points: Tape::new(&dag, &point_roots),
            bodies: Tape::new(&dag, &body_roots),
            masses: Tape::new(&dag, &mass_roots),
            gravity: c.system.gravity.is_some(),
            chains: Tape::new(&dag, &chain_roots),
            chain_shape: chains
                .iter()
                .map(|ch| (ch.vertices.len(), ch.ground_segments))
                .collect(),
            linkage: std::sync::Arc::new(super::linkage::Linkage::new(m)),
            scenes: c
                .scenes
                .iter()
                .map(|plan| super::scene_tapes::SceneTapes::new(c, &dag, plan))
                .collect(),
            prelude,
            program: program.map(std::sync::Arc::new),
            program_params: None,
            #[cfg(feature = "jit")]
            fused: None,
            info,
            model: std::sync::Arc::new(m.clone()),
        };
        g.program_params = ProgramParams::new(&g);
        g
    }

    pub fn name(&self) -> &str {
        &self.info.name
    }

    /// How each block's positions are solved, in solve order: `closed form (KIND)` with the
    /// kind's `ClosedForm::name()` (`RRR`, `RPR`, `one angle`, …), or `newton`.
    pub fn block_kinds(&self) -> Vec<String> {
        self.blocks
            .iter()
            .map(|b| match &b.closed {
                Some(c) => format!("closed form ({})", c.form.name()),
                None => "newton".to_string(),
            })
            .collect()
    }

    /// Current param values, in the file's order.
    pub fn params(&self) -> &[f64] {
        &self.params
    }

    /// Sets a param by name. Derived params (defined by expressions of other params) are not
    /// free values: they are computed inside the solvers' expressions from the base params, so
    /// they follow every change; setting one is an error that names its bases.
    pub fn set_param(&mut self, name: &str, value: f64) -> Result<(), String> {
        if let Some(d) = self.model.derived.iter().find(|d| d.name.text == name) {
            let bases: Vec<String> = d
                .uses
                .iter()
                .filter_map(|s| match *s {
                    mechgen_codegen::Symbol::Param(k) => {
                        Some(&self.model.params[k.index()].name.text)
                    }
                    mechgen_codegen::Symbol::Derived(k) => {
                        Some(&self.model.derived[k.index()].name.text)
                    }
                    _ => None,
                })
                .map(|n| format!("`{n}`"))
                .collect();
            return Err(format!(
                "param `{name}` is derived from {}: set those instead",
                bases.join(", ")
            ));
        }
        let i = self
            .info
            .params
            .iter()
            .position(|p| p.name == name)
            .ok_or_else(|| format!("no param `{name}` in `{}`", self.info.name))?;
        self.params[i] = value;
        self.info.params[i].value = value;
        self.program_params = ProgramParams::new(self);
        Ok(())
    }

    /// Sets the base params in the file's order, `values[i]` the `i`-th (fewer values leave the
    /// rest as they are, more are ignored): what a batch does for each of its param sets, with
    /// the program's params-only values computed once instead of once per param.
    pub fn set_params(&mut self, values: &[f64]) {
        for ((p, d), &v) in self
            .params
            .iter_mut()
            .zip(&mut self.info.params)
            .zip(values)
        {
            *p = v;
            d.value = v;
        }
        self.program_params = ProgramParams::new(self);
    }

    /// The values of the derived params at the current base params, in file order.
    pub fn derived_params(&self) -> Result<Vec<(String, f64)>, String> {
        let values = mechgen_codegen::derived_values(&self.model, &self.params)?;
        Ok(self
            .model
            .derived
            .iter()
            .map(|d| d.name.text.clone())
            .zip(values)
            .collect())
    }

    /// Largest length param (or 1): what relative length tolerances are relative to.
    pub fn length_scale(&self) -> f64 {
        self.length_scale_of(None)
    }

    /// Largest length param among those `read` marks (all of them for `None`), or 1: a scene's
    /// tolerances are relative to the length params it reads, as its generated code's are.
    pub(super) fn length_scale_of(&self, read: Option<&[bool]>) -> f64 {
        let s = self
            .params
            .iter()
            .zip(&self.length_param)
            .enumerate()
            .filter(|(i, (_, l))| **l && read.is_none_or(|r| r.get(*i).copied().unwrap_or(false)))
            .fold(0.0f64, |m, (_, (p, _))| m.max(p.abs()));
        if s > 0.0 { s } else { 1.0 }
    }
}

/// What a tick's program reads besides the state, computed when the params change: the params
/// followed by the values of the program's prelude, and the length scale.
#[derive(Clone, Debug)]
pub(crate) struct ProgramParams {
    pub values: Vec<f64>,
    pub scale: f64,
}

impl ProgramParams {
    /// `None` when `g` has no program or its prelude cannot be evaluated.
    fn new(g: &Generic) -> Option<Self> {
        g.program.as_ref()?;
        let mut values = vec![0.0; g.prelude.outputs()];
        let env = super::tape::Env::position(&[], &[], &g.params);
        g.prelude.eval(&env, &mut Vec::new(), &mut values).ok()?;
        let mut all = g.params.clone();
        all.extend(values);
        Some(ProgramParams {
            values: all,
            scale: g.length_scale(),
        })
    }
}
