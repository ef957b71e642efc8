//! mechgen's build: an ordinary user of the build library. It generates the solvers of
//! `mechanism.toml`, or of the file named by `MECHGEN_MECHANISM` (an absolute path) when that is
//! set, into `OUT_DIR/mechanisms.rs`, and the file's text into `OUT_DIR/mechanism_source.rs`
//! (`mechgen::source`, for the generic engine and `mechgen check`).
fn main() {
    mechgen_codegen::Config::new()
        .runtime_path("::mechgen")
        .env_override("MECHGEN_MECHANISM")
        .source_file("mechanism_source.rs")
        .compile("mechanism.toml");
}
