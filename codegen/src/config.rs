//! The build library (stage driver for a `build.rs`, prost-build style): [`compile`] generates the
//! solvers of a crate's own mechanism file into `OUT_DIR`, [`Config`] does the same with options
//! (runtime path, output file name, an environment override, the source-text file). Diagnostics
//! become `cargo::error=` / `cargo::warning=` lines with FILE:LINE:COLUMN; nothing panics and
//! nothing ends the process.

use std::path::{Path, PathBuf};

use crate::compile::analyze;
use crate::diagnostic::{Diagnostic, SourceFile, render};
use crate::emit::{DEFAULT_RUNTIME, emit_with};

/// Generates the solvers of `path` (relative to the crate's `CARGO_MANIFEST_DIR`) into
/// `OUT_DIR/mechanisms.rs`, for `mechgen::include_mechanisms!()`. Call it from `build.rs`:
///
/// ```no_run
/// fn main() { mechgen_codegen::compile("mechanism.toml"); }
/// ```
///
/// An edit to the file regenerates; a bad file prints every diagnostic once, as a cargo error
/// (`FILE:LINE:COLUMN: error: …`), and fails the build; warnings become cargo warnings.
// The doctest shows the whole `build.rs`, `fn main` included.
#[allow(clippy::needless_doctest_main)]
pub fn compile(path: impl AsRef<Path>) {
    Config::new().compile(path);
}

/// The Rust source of a mechanism file for the runtime at `::mechgen`, or its diagnostics when
/// any is an error (warnings come back with the code).
pub fn generate_source(file: &SourceFile) -> Result<(String, Vec<Diagnostic>), Vec<Diagnostic>> {
    Config::new().generate(file)
}

/// Options of [`compile`]: `Config::new().runtime_path("::mechgen").compile("mechanism.toml")`.
#[derive(Clone, Debug)]
pub struct Config {
    /// `None`: the runtime the crate depends on (see [`Config::runtime_path`]).
    runtime: Option<String>,
    out_file: String,
    source_file: Option<String>,
    env_override: Option<String>,
}

impl Default for Config {
    fn default() -> Self {
        Config::new()
    }
}

/// What a build wrote: the generated file's path and the rendered warnings.
#[derive(Debug)]
pub struct Generated {
    pub path: PathBuf,
    pub warnings: String,
}

impl Config {
    /// Runtime `::mechgen`, output `mechanisms.rs`, no source-text file, no override.
    pub fn new() -> Self {
        Config {
            runtime: None,
            out_file: "mechanisms.rs".to_string(),
            source_file: None,
            env_override: None,
        }
    }

    /// The path generated code reaches the runtime through (`{path}::__private::…`): `::mechgen`
    /// or `::mechgen_runtime`, or a re-export of either in the user's crate (`crate::rt`). By
    /// default [`Config::compile`] reads the crate's `Cargo.toml` and takes the crate it depends
    /// on (`mechgen`, else `mechgen-runtime`, under whatever name the manifest gives it), so that
    /// the one-call `compile` works for a crate that depends on either; `::mechgen` when it names
    /// neither and for [`Config::generate`].
    pub fn runtime_path(&mut self, path: &str) -> &mut Self {
        self.runtime = Some(path.to_string());
        self
    }

    /// The name of the generated file in `OUT_DIR` (default `mechanisms.rs`); include it with
    /// `mechgen::include_mechanisms!("NAME")`. Several calls with different files can share a crate.
    pub fn out_file(&mut self, name: &str) -> &mut Self {
        self.out_file = name.to_string();
        self
    }

    /// Also write `OUT_DIR/NAME` with two constants, `SOURCE_NAME` (the file's display name) and
    /// `SOURCE` (its text): what run-time engines need to load the same file (mechgen's
    /// `mechgen::source`).
    pub fn source_file(&mut self, name: &str) -> &mut Self {
        self.source_file = Some(name.to_string());
        self
    }

    /// When the environment variable `var` is set and not empty, the build reads the file it
    /// names (an absolute path) instead of the one given to [`Config::compile`]; a change of the
    /// variable reruns the build script. mechgen's own `build.rs` uses `MECHGEN_MECHANISM`.
    pub fn env_override(&mut self, var: &str) -> &mut Self {
        self.env_override = Some(var.to_string());
        self
    }

    /// The generated source of a file, or its diagnostics when any is an error.
    pub fn generate(
        &self,
        file: &SourceFile,
    ) -> Result<(String, Vec<Diagnostic>), Vec<Diagnostic>> {
        let (mechs, diags) = analyze(file);
        if diags.iter().any(Diagnostic::is_error) {
            return Err(diags);
        }
        let runtime = self.runtime.as_deref().unwrap_or(DEFAULT_RUNTIME);
        match emit_with(&mechs, &file.name, runtime) {
            Ok(code) => Ok((code, diags)),
            Err(msg) => Err(vec![Diagnostic::error(Default::default(), msg)]),
        }
    }

    /// Reads `input` (shown as `display_name` in diagnostics) and writes the generated code
    /// into `out_dir`; every error comes back rendered (FILE:LINE:COLUMN, all of them).
    pub fn generate_into(
        &self,
        input: &Path,
        display_name: &str,
        out_dir: &Path,
    ) -> Result<Generated, String> {
        let text = std::fs::read_to_string(input)
            .map_err(|e| format!("{display_name}: error: cannot read mechanism file: {e}"))?;
        let file = SourceFile::new(display_name, text);
        let (code, warnings) = self.generate(&file).map_err(|d| render(&file, &d))?;
        let path = out_dir.join(&self.out_file);
        write_if_changed(&path, &code)?;
        if let Some(name) = &self.source_file {
            let source = format!(
                "/// Name of the mechanism file the solvers were generated from.\n\
                 pub const SOURCE_NAME: &str = {:?};\n\
                 /// Its text.\n\
                 pub const SOURCE: &str = {:?};\n",
                file.name, file.text
            );
            write_if_changed(&out_dir.join(name), &source)?;
        }
        Ok(Generated {
            path,
            warnings: render(&file, &warnings),
        })
    }

    /// The whole build step, for `build.rs`: `path` is relative to `CARGO_MANIFEST_DIR`. Prints
    /// `cargo::rerun-if-changed` (and `rerun-if-env-changed` for an override), warnings as
    /// `cargo::warning=` lines, and errors once, as `cargo::error=` lines: cargo shows each as
    /// `error: CRATE@VERSION: FILE:LINE:COLUMN: …` and fails the build (the script itself returns
    /// normally, so cargo does not print its output a second time). [`Config::try_compile`]
    /// returns the rendered errors instead.
    pub fn compile(&self, path: impl AsRef<Path>) {
        if let Err(rendered) = self.try_compile(path.as_ref()) {
            for line in rendered.lines() {
                println!("cargo::error={line}");
            }
        }
    }

    /// [`Config::compile`] that returns instead of ending the process: `Ok` with what it wrote
    /// (warnings already printed as `cargo::warning=` lines), or `Err` with every diagnostic
    /// rendered (FILE:LINE:COLUMN), printed nowhere, for the caller to report.
    pub fn try_compile(&self, path: impl AsRef<Path>) -> Result<Generated, String> {
        let path = path.as_ref();
        let manifest = std::env::var_os("CARGO_MANIFEST_DIR")
            .map(PathBuf::from)
            .unwrap_or_default();
        let mut config = self.clone();
        if config.runtime.is_none() {
            let toml = manifest.join("Cargo.toml");
            if let Ok(text) = std::fs::read_to_string(&toml) {
                println!("cargo::rerun-if-changed={}", toml.display());
                config.runtime = runtime_of_manifest(&text);
            }
        }
        if let Some(var) = &self.env_override {
            println!("cargo::rerun-if-env-changed={var}");
        }
        let overridden = self
            .env_override
            .as_ref()
            .and_then(std::env::var_os)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from);
        let (input, display) = match overridden {
            Some(p) => {
                let d = p.display().to_string();
                (p, d)
            }
            None => (manifest.join(path), path.display().to_string()),
        };
        println!("cargo::rerun-if-changed={}", input.display());
        let out_dir = std::env::var_os("OUT_DIR")
            .map(PathBuf::from)
            .ok_or_else(|| "OUT_DIR is not set: call this from a build script".to_string())?;
        let generated = config.generate_into(&input, &display, &out_dir)?;
        for line in generated.warnings.lines().filter(|l| !l.trim().is_empty()) {
            println!("cargo::warning={line}");
        }
        Ok(generated)
    }
}

/// The runtime path for a crate whose manifest is `text`: `::NAME` of its dependency on
/// `mechgen` (by package, under any key: `rt = { package = "mechgen", … }` gives `::rt`), else
/// of its dependency on `mechgen-runtime`; `None` when it has neither (or the text is no TOML).
/// Normal dependencies only, target-specific ones included.
pub fn runtime_of_manifest(text: &str) -> Option<String> {
    let table: toml::Table = text.parse().ok()?;
    let mut tables: Vec<&toml::Table> = Vec::new();
    if let Some(d) = table.get("dependencies").and_then(toml::Value::as_table) {
        tables.push(d);
    }
    if let Some(targets) = table.get("target").and_then(toml::Value::as_table) {
        for t in targets.values().filter_map(toml::Value::as_table) {
            if let Some(d) = t.get("dependencies").and_then(toml::Value::as_table) {
                tables.push(d);
            }
        }
    }
    let find = |package: &str| {
        tables
            .iter()
            .flat_map(|t| t.iter())
            .find_map(|(key, value)| {
                let named = value
                    .get("package")
                    .and_then(toml::Value::as_str)
                    .unwrap_or(key);
                (named == package).then(|| format!("::{}", key.replace('-', "_")))
            })
    };
    find("mechgen").or_else(|| find("mechgen-runtime"))
}

/// Writes only on change, so an unchanged file does not rebuild dependents.
fn write_if_changed(path: &Path, text: &str) -> Result<(), String> {
    if std::fs::read_to_string(path).ok().as_deref() != Some(text) {
        std::fs::write(path, text)
            .map_err(|e| format!("{}: error: cannot write: {e}", path.display()))?;
    }
    Ok(())
}
