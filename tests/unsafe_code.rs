//! `unsafe` lives in one module: `src/generic/jit/code.rs`, the JIT's boundary (owning machine
//! code, turning an address into a function pointer, calling it). Every other source file of
//! every crate of the repository, read with `syn`, has no `unsafe` block, function, impl or trait
//! (this test file and `tests/alloc.rs`, whose counting allocator must be an `unsafe impl`, aside).

use std::path::{Path, PathBuf};

use syn::visit::Visit;

#[derive(Default)]
struct Unsafe(Vec<String>);

impl<'a> Visit<'a> for Unsafe {
    fn visit_expr_unsafe(&mut self, e: &'a syn::ExprUnsafe) {
        self.0.push("unsafe block".into());
        syn::visit::visit_expr_unsafe(self, e);
    }
    fn visit_signature(&mut self, s: &'a syn::Signature) {
        if matches!(s.safety, syn::Safety::Unsafe(_)) {
            self.0.push(format!("unsafe fn {}", s.ident));
        }
        syn::visit::visit_signature(self, s);
    }
    fn visit_item_impl(&mut self, i: &'a syn::ItemImpl) {
        if i.unsafety.is_some() {
            self.0.push("unsafe impl".into());
        }
        syn::visit::visit_item_impl(self, i);
    }
    fn visit_item_trait(&mut self, t: &'a syn::ItemTrait) {
        if t.unsafety.is_some() {
            self.0.push(format!("unsafe trait {}", t.ident));
        }
        syn::visit::visit_item_trait(self, t);
    }
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).expect("read dir").flatten() {
        let p = e.path();
        let name = p.file_name().map(|n| n.to_string_lossy().into_owned());
        if p.is_dir() {
            if !matches!(name.as_deref(), Some("target" | ".git")) {
                rust_files(&p, out);
            }
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The `unsafe` items of one source file.
fn unsafe_in(text: &str) -> Vec<String> {
    let file = syn::parse_file(text).expect("parses");
    let mut v = Unsafe::default();
    v.visit_file(&file);
    v.0
}

#[test]
fn unsafe_only_in_the_jit_boundary() {
    let allowed = [
        "src/generic/jit/code.rs",
        "tests/alloc.rs",
        "tests/unsafe_code.rs",
    ];
    let mut files = Vec::new();
    for dir in [
        "src",
        "runtime/src",
        "codegen/src",
        "python/src",
        "tests",
        "benches",
        "examples",
    ] {
        rust_files(Path::new(dir), &mut files);
    }
    assert!(files.len() > 100, "{} files", files.len());
    let mut found = Vec::new();
    let mut boundary = 0;
    for f in &files {
        let text = std::fs::read_to_string(f).expect("readable");
        // Snapshots of generated code and fixture outputs are not sources.
        if let Err(e) = syn::parse_file(&text) {
            eprintln!("{}: not parsed ({e})", f.display());
            continue;
        }
        let items = unsafe_in(&text);
        let rel = f.to_string_lossy().replace('\\', "/");
        if allowed.contains(&rel.as_str()) {
            if rel == allowed[0] {
                boundary = items.len();
            }
        } else if !items.is_empty() {
            found.push(format!("{rel}: {}", items.join(", ")));
        }
    }
    assert!(
        found.is_empty(),
        "unsafe outside the JIT boundary:\n{}",
        found.join("\n")
    );
    assert!(
        boundary >= 3,
        "the boundary module has {boundary} unsafe items"
    );
}

#[test]
fn the_check_finds_unsafe() {
    let items = unsafe_in("fn f(p: *const u8) -> u8 { unsafe { *p } } unsafe impl Send for X {}");
    assert_eq!(items, ["unsafe block", "unsafe impl"]);
}
