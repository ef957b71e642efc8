//! CLI, `mechgen check`: validates a mechanism file through the generator's front end and prints
//! its structure, or every diagnostic as FILE:LINE:COLUMN.

use std::path::Path;

use mechgen::{CoordDesc, Kind, MechanismInfo, SceneDescription, generic};

/// `mechgen check [--file PATH] [-v]`: the file given, or the compiled-in one.
pub fn run(file: Option<&Path>, verbose: bool) -> Result<(), String> {
    match file {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
            check(&path.display().to_string(), &text, verbose)
        }
        None => check(
            mechgen::source::SOURCE_NAME,
            mechgen::source::SOURCE,
            verbose,
        ),
    }
}

/// Checks `name`/`text`; prints structure to stdout and diagnostics to stderr; `verbose`: the
/// JIT's compile time of each mechanism too.
pub fn check(name: &str, text: &str, verbose: bool) -> Result<(), String> {
    match generic::load_with_warnings(name, text) {
        Ok((mechs, warnings)) => {
            tell_raw!("{warnings}");
            for m in &mechs {
                print_structure(&mechgen::DynMechanism::<f64>::info(m), &m.block_kinds());
                if verbose {
                    print_jit(m);
                }
            }
            for m in &mechs {
                let info = mechgen::DynMechanism::<f64>::info(m);
                for s in m.scene_names().into_iter().filter_map(|n| m.scene(n)) {
                    print_scene(&mechgen::DynScene::<f64>::info(&s), &info);
                }
            }
            Ok(())
        }
        Err(e) => {
            tell_raw!("{}", e.rendered);
            let n = e.diagnostics.iter().filter(|d| d.is_error()).count();
            Err(format!("{name}: {n} error(s)"))
        }
    }
}

/// The JIT's line of `check -v`: the compile time of every tape of `m`, or why there is none.
fn print_jit(m: &generic::Generic) {
    match m.clone().compile() {
        Ok(took) => say!(
            "  jit:      compiled in {:.1} ms ({} tapes, {} instructions)",
            took.as_secs_f64() * 1e3,
            m.tape_count(),
            m.instruction_count()
        ),
        Err(e) => say!("  jit:      {e}; the interpreter runs it"),
    }
}

fn print_structure(info: &MechanismInfo, kinds: &[String]) {
    let names = |v: &[CoordDesc]| {
        v.iter()
            .map(
                |CoordDesc {
                     name: n, kind: k, ..
                 }| {
                    format!(
                        "{n} ({})",
                        if *k == Kind::Angle { "angle" } else { "length" }
                    )
                },
            )
            .collect::<Vec<_>>()
    };
    if info.description.is_empty() {
        say!("mechanism {}:", info.name);
    } else {
        say!("mechanism {}: {}", info.name, info.description);
    }
    say!("  inputs:   {}", names(&info.inputs).join(", "));
    say!("  unknowns: {}", names(&info.unknowns).join(", "));
    say!("  params:   {}", info.params.len());
    say!("  points:   {}", info.points.join(", "));
    if !info.bodies.is_empty() {
        say!(
            "  bodies:   {} (dynamics: `mechgen dynamics`, `mechgen simulate`)",
            info.bodies.join(", ")
        );
    }
    let blocks: Vec<String> = info
        .blocks
        .iter()
        .zip(kinds)
        .map(|(b, kind)| {
            let us: Vec<&str> = b.iter().map(|&u| info.unknowns[u].name.as_str()).collect();
            format!("{}x{} [{}] {kind}", b.len(), b.len(), us.join(", "))
        })
        .collect();
    say!("  blocks:   {}", blocks.join(" -> "));
}

/// A scene: what it keeps of its mechanism (blocks, order, points) and its columns.
fn print_scene(s: &SceneDescription, info: &MechanismInfo) {
    let block = |b: usize| {
        let us: Vec<&str> = info.blocks[b]
            .iter()
            .map(|&u| info.unknowns[u].name.as_str())
            .collect();
        format!("{b} [{}]", us.join(", "))
    };
    let kept: Vec<String> = s.blocks.iter().map(|&b| block(b)).collect();
    let skipped: Vec<String> = (0..info.blocks.len())
        .filter(|b| !s.blocks.contains(b))
        .map(block)
        .collect();
    let orders = [
        "positions",
        "positions, velocities",
        "positions, velocities, accelerations",
    ];
    let none = |v: &[String]| {
        if v.is_empty() {
            "none".to_string()
        } else {
            v.join(", ")
        }
    };
    say!("scene {} (mechanism {}):", s.name, s.mechanism);
    say!(
        "  order:    {} ({})",
        s.order,
        orders[usize::from(s.order.min(2))]
    );
    say!("  keeps:    {}", none(&kept));
    say!("  skipped:  {}", none(&skipped));
    say!("  points:   {}", none(&s.points));
    if !s.angles_skipped.is_empty() {
        let names: Vec<&str> = s
            .angles_skipped
            .iter()
            .map(|&u| info.unknowns[u].name.as_str())
            .collect();
        say!(
            "  sin/cos:  {} (read through their sines and cosines only: a tick skips the angles)",
            names.join(", ")
        );
    }
    say!("  columns:  {}", s.columns.join(", "));
}
