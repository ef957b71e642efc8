//! Entry point for a `build.rs`: find the mechanism file, generate the solvers into `OUT_DIR`,
//! report every diagnostic as `cargo::error=` / `cargo::warning=` lines, never panic.

use std::path::{Path, PathBuf};

use crate::diagnostic::{SourceFile, render};

/// Name of the generated file in `OUT_DIR`.
pub const GENERATED_FILE: &str = "mechanisms.rs";
/// Name of the file in `OUT_DIR` holding the mechanism file's name and text as two constants,
/// `SOURCE_NAME` and `SOURCE` (for run-time engines, drawings and `check`).
pub const SOURCE_FILE: &str = "mechanism_source.rs";
/// Environment variable naming the mechanism file (an absolute path).
pub const ENV_VAR: &str = "MECHGEN_MECHANISM";

/// What a build produced: the generated file's path and rendered warnings.
#[derive(Debug)]
pub struct Generated {
    pub path: PathBuf,
    pub warnings: String,
}

/// Reads `input`, writes the generated code to `out_dir/mechanisms.rs`. Errors come back rendered
/// (FILE:LINE:COLUMN, all of them).
pub fn generate(input: &Path, display_name: &str, out_dir: &Path) -> Result<Generated, String> {
    let text = std::fs::read_to_string(input)
        .map_err(|e| format!("{display_name}: error: cannot read mechanism file: {e}"))?;
    let file = SourceFile::new(display_name, text);
    match crate::compile(&file) {
        Ok((code, warnings)) => {
            let path = out_dir.join(GENERATED_FILE);
            write_if_changed(&path, &code)?;
            let source = format!(
                "/// Name of the mechanism file the solvers were generated from.\n\
                 pub const SOURCE_NAME: &str = {:?};\n\
                 /// Its text.\n\
                 pub const SOURCE: &str = {:?};\n",
                file.name, file.text
            );
            write_if_changed(&out_dir.join(SOURCE_FILE), &source)?;
            Ok(Generated {
                path,
                warnings: render(&file, &warnings),
            })
        }
        Err(diags) => Err(render(&file, &diags)),
    }
}

/// Writes only on change, so an unchanged file does not rebuild dependents.
fn write_if_changed(path: &Path, text: &str) -> Result<(), String> {
    if std::fs::read_to_string(path).ok().as_deref() != Some(text) {
        std::fs::write(path, text)
            .map_err(|e| format!("{}: error: cannot write: {e}", path.display()))?;
    }
    Ok(())
}

/// The whole build script: `fn main() { mechgen_codegen::build_script::run() }`. Exits with status
/// 1 after printing the errors when the file is invalid.
pub fn run() {
    println!("cargo::rerun-if-env-changed={ENV_VAR}");
    let manifest = std::env::var_os("CARGO_MANIFEST_DIR")
        .map(PathBuf::from)
        .unwrap_or_default();
    let (input, display) = match std::env::var_os(ENV_VAR).filter(|v| !v.is_empty()) {
        Some(p) => {
            let p = PathBuf::from(p);
            let d = p.display().to_string();
            (p, d)
        }
        None => (
            manifest.join("mechanism.toml"),
            "mechanism.toml".to_string(),
        ),
    };
    println!("cargo::rerun-if-changed={}", input.display());
    let Some(out_dir) = std::env::var_os("OUT_DIR").map(PathBuf::from) else {
        println!("cargo::error=OUT_DIR is not set: run this from a build script");
        std::process::exit(1);
    };
    match generate(&input, &display, &out_dir) {
        Ok(g) => {
            for line in g.warnings.lines().filter(|l| !l.trim().is_empty()) {
                println!("cargo::warning={line}");
            }
        }
        Err(rendered) => {
            for line in rendered.lines() {
                println!("cargo::error={line}");
            }
            eprintln!("{rendered}");
            std::process::exit(1);
        }
    }
}
