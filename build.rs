//! Reads the mechanism file (`mechanism.toml` or `$MECHGEN_MECHANISM`) and generates the solvers.
fn main() {
    mechgen_codegen::build_script::run();
}
