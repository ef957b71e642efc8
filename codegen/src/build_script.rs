//! mechgen's own build step (the root `build.rs` is an ordinary user of [`crate::Config`]): the
//! default file and the `MECHGEN_MECHANISM` override, plus [`generate`], the entry point the
//! diagnostics tests drive without a build.

use std::path::Path;

use crate::config::Config;
pub use crate::config::Generated;

/// Name of the generated file in `OUT_DIR`.
pub const GENERATED_FILE: &str = "mechanisms.rs";
/// Name of the file in `OUT_DIR` holding the mechanism file's name and text as two constants,
/// `SOURCE_NAME` and `SOURCE` (for run-time engines, drawings and `check`).
pub const SOURCE_FILE: &str = "mechanism_source.rs";
/// Environment variable naming the mechanism file (an absolute path).
pub const ENV_VAR: &str = "MECHGEN_MECHANISM";

/// The configuration of mechgen's own build: `mechanism.toml`, or `$MECHGEN_MECHANISM` when set,
/// into `mechanisms.rs`, with the source text in `mechanism_source.rs`.
pub fn mechgen_config() -> Config {
    let mut c = Config::new();
    c.env_override(ENV_VAR).source_file(SOURCE_FILE);
    c
}

/// Reads `input`, writes the generated code to `out_dir/mechanisms.rs` (and the source text to
/// `out_dir/mechanism_source.rs`). Errors come back rendered (FILE:LINE:COLUMN, all of them).
pub fn generate(input: &Path, display_name: &str, out_dir: &Path) -> Result<Generated, String> {
    mechgen_config().generate_into(input, display_name, out_dir)
}

/// mechgen's whole build script. Exits with status 1 after printing the errors when the file is
/// invalid.
pub fn run() {
    mechgen_config().compile("mechanism.toml");
}
