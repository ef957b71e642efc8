//! Generates the files of this crate with the build library: the one-call form, and the builder
//! with another output file and the runtime crate's own path.
fn main() {
    mechgen_codegen::compile("mechanism.toml");
    mechgen_codegen::Config::new()
        .runtime_path("::mechgen_runtime")
        .out_file("other.rs")
        .compile("other.toml");
    mechgen_codegen::Config::new()
        .out_file("derived.rs")
        .compile("derived.toml");
    mechgen_codegen::Config::new()
        .out_file("closed.rs")
        .compile("closed.toml");
    mechgen_codegen::Config::new()
        .out_file("unread.rs")
        .compile("unread.toml");
    mechgen_codegen::Config::new()
        .out_file("crossings.rs")
        .compile("crossings.toml");
    mechgen_codegen::Config::new()
        .out_file("weak.rs")
        .compile("weak.toml");
}
