fn main() {
    mechgen_codegen::compile("mechanism.toml");
}
