//! The Rust code of the README and the docs cannot rot: their `rust` and `rust,no_run` blocks are
//! doctests of the crate (`ReadmeDoctests`, `RustDocDoctests`, `CliDocDoctests` in `src/lib.rs`);
//! the one block that needs a crate of its own (`rust,ignore`: the downstream example's
//! `src/main.rs`, in docs/rust.md) must be that file's text, and the `build.rs` block must call
//! what the example's `build.rs` calls.

fn blocks(readme: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut lines = readme.lines();
    while let Some(line) = lines.next() {
        if let Some(tag) = line.strip_prefix("```").filter(|t| t.starts_with("rust")) {
            let body: Vec<&str> = lines.by_ref().take_while(|l| *l != "```").collect();
            out.push((tag.to_string(), body.join("\n") + "\n"));
        }
    }
    out
}

#[test]
fn every_rust_block_is_compiled() {
    let readme = include_str!("../README.md");
    let rust = include_str!("../docs/rust.md");
    let cli = include_str!("../docs/cli.md");
    let blocks: Vec<(String, String)> = [readme, rust, cli].into_iter().flat_map(blocks).collect();
    assert!(blocks.len() >= 5, "{} rust blocks", blocks.len());
    let main_rs = include_str!("../examples/simulator/src/main.rs");
    let mut ignored = 0;
    for (tag, body) in &blocks {
        match tag.as_str() {
            // Compiled by rustdoc as doctests.
            "rust" | "rust,no_run" => assert!(body.contains("fn main()"), "{body}"),
            "rust,ignore" => {
                ignored += 1;
                // The first two lines say where the block comes from; the rest is the file.
                let text: String = body.splitn(3, '\n').nth(2).unwrap_or("").to_string();
                assert_eq!(
                    text, main_rs,
                    "README block differs from examples/simulator/src/main.rs"
                );
            }
            other => panic!("README rust block tagged `{other}`: compile it or hold it to a file"),
        }
    }
    assert_eq!(ignored, 1);
    let build_rs = include_str!("../examples/simulator/build.rs");
    assert!(build_rs.contains("mechgen_codegen::compile(\"mechanism.toml\");"));
    assert!(rust.contains(build_rs.trim_end().lines().nth(1).unwrap()));
}
