//! No import cycle between the modules of any crate of the repository (the library, the build
//! library, the runtime, the Python extension, the odd-files fixture crate): a module depends on
//! another when its code names it or an item in it (a `use`, or a path in code: `crate::a::f`,
//! `super::T`), `pub use` re-exports and `mod` declarations aside, code under `#[cfg(test)]`
//! aside. Read with `syn`, so paths inside macros' token streams (the emitter's `quote!`) are not
//! counted. The graph's strongly connected components must all be single modules. A synthetic
//! crate with a cycle checks that the check finds one.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use syn::visit::Visit;

type Module = Vec<String>;

/// Every module of the crate rooted at `src` (`lib.rs`/`main.rs` is the root, `a/mod.rs` and
/// `a.rs` are `a`), with its file.
fn modules(src: &Path) -> BTreeMap<Module, PathBuf> {
    let mut out = BTreeMap::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).expect("read dir").flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                let rel = p.strip_prefix(src).expect("inside").with_extension("");
                let mut m: Module = rel
                    .components()
                    .map(|c| c.as_os_str().to_string_lossy().into_owned())
                    .collect();
                if matches!(m.last().map(String::as_str), Some("mod" | "lib" | "main")) {
                    m.pop();
                }
                out.insert(m, p);
            }
        }
    }
    out
}

/// The modules one file's code refers to.
struct Refs<'a> {
    current: &'a Module,
    known: &'a BTreeMap<Module, PathBuf>,
    found: BTreeSet<Module>,
}

impl Refs<'_> {
    /// The deepest module a path names (`crate::a::b::f` → `a::b` when `a::b` is a module);
    /// `None` for a path into another crate or to a local item.
    fn resolve(&mut self, segments: &[String]) {
        let Some(first) = segments.first() else {
            return;
        };
        let (mut at, rest): (Module, &[String]) = match first.as_str() {
            "crate" => (Vec::new(), &segments[1..]),
            "self" => (self.current.clone(), &segments[1..]),
            "super" => {
                let mut m = self.current.clone();
                let mut i = 0;
                while segments.get(i).is_some_and(|s| s == "super") {
                    m.pop();
                    i += 1;
                }
                (m, &segments[i..])
            }
            _ => {
                let mut child = self.current.clone();
                child.push(first.clone());
                if !self.known.contains_key(&child) {
                    return;
                }
                (self.current.clone(), segments)
            }
        };
        for s in rest {
            at.push(s.clone());
            if !self.known.contains_key(&at) {
                at.pop();
                break;
            }
        }
        if &at != self.current {
            self.found.insert(at);
        }
    }

    fn use_tree(&mut self, prefix: &mut Vec<String>, tree: &syn::UseTree) {
        match tree {
            syn::UseTree::Path(p) => {
                prefix.push(p.ident.to_string());
                self.use_tree(prefix, &p.tree);
                prefix.pop();
            }
            syn::UseTree::Name(n) => {
                prefix.push(n.ident.to_string());
                let path = prefix.clone();
                self.resolve(&path);
                prefix.pop();
            }
            syn::UseTree::Rename(r) => {
                prefix.push(r.ident.to_string());
                let path = prefix.clone();
                self.resolve(&path);
                prefix.pop();
            }
            syn::UseTree::Glob(_) => {
                let path = prefix.clone();
                self.resolve(&path);
            }
            syn::UseTree::Group(g) => {
                for t in &g.items {
                    self.use_tree(prefix, t);
                }
            }
        }
    }
}

/// Whether `attrs` hold `#[cfg(test)]`.
fn test_only(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|a| {
        a.path().is_ident("cfg") && a.parse_args::<syn::Ident>().is_ok_and(|i| i == "test")
    })
}

impl<'ast> Visit<'ast> for Refs<'_> {
    fn visit_item_use(&mut self, u: &'ast syn::ItemUse) {
        // A re-export only names the item for the module's users.
        if matches!(u.vis, syn::Visibility::Inherited) && !test_only(&u.attrs) {
            self.use_tree(&mut Vec::new(), &u.tree);
        }
    }
    fn visit_item_mod(&mut self, m: &'ast syn::ItemMod) {
        if !test_only(&m.attrs) {
            syn::visit::visit_item_mod(self, m);
        }
    }
    fn visit_item_fn(&mut self, f: &'ast syn::ItemFn) {
        if !test_only(&f.attrs) {
            syn::visit::visit_item_fn(self, f);
        }
    }
    fn visit_item_impl(&mut self, i: &'ast syn::ItemImpl) {
        if !test_only(&i.attrs) {
            syn::visit::visit_item_impl(self, i);
        }
    }
    fn visit_path(&mut self, p: &'ast syn::Path) {
        if p.segments.len() > 1 {
            let segments: Vec<String> = p.segments.iter().map(|s| s.ident.to_string()).collect();
            self.resolve(&segments);
        }
        syn::visit::visit_path(self, p);
    }
}

/// The import graph of the crate rooted at `src`.
fn graph(src: &Path) -> BTreeMap<Module, BTreeSet<Module>> {
    let known = modules(src);
    let mut g = BTreeMap::new();
    for (m, file) in &known {
        let text = std::fs::read_to_string(file).expect("read");
        let parsed = syn::parse_file(&text)
            .unwrap_or_else(|e| panic!("{} does not parse: {e}", file.display()));
        let mut refs = Refs {
            current: m,
            known: &known,
            found: BTreeSet::new(),
        };
        refs.visit_file(&parsed);
        g.insert(m.clone(), refs.found);
    }
    g
}

/// The strongly connected components of more than one module (Tarjan).
fn cycles(g: &BTreeMap<Module, BTreeSet<Module>>) -> Vec<Vec<String>> {
    struct T<'g> {
        g: &'g BTreeMap<Module, BTreeSet<Module>>,
        index: BTreeMap<&'g Module, (usize, usize)>,
        stack: Vec<&'g Module>,
        on: BTreeSet<&'g Module>,
        next: usize,
        out: Vec<Vec<String>>,
    }
    impl<'g> T<'g> {
        fn visit(&mut self, v: &'g Module) {
            self.index.insert(v, (self.next, self.next));
            self.next += 1;
            self.stack.push(v);
            self.on.insert(v);
            for w in self.g.get(v).into_iter().flatten() {
                if !self.g.contains_key(w) {
                    continue;
                }
                if !self.index.contains_key(w) {
                    self.visit(w);
                    let lw = self.index[w].1;
                    let e = self.index.get_mut(v).expect("visited");
                    e.1 = e.1.min(lw);
                } else if self.on.contains(w) {
                    let iw = self.index[w].0;
                    let e = self.index.get_mut(v).expect("visited");
                    e.1 = e.1.min(iw);
                }
            }
            let (i, low) = self.index[v];
            if i == low {
                let mut comp = Vec::new();
                while let Some(w) = self.stack.pop() {
                    self.on.remove(w);
                    comp.push(if w.is_empty() {
                        "(root)".to_string()
                    } else {
                        w.join("::")
                    });
                    if w == v {
                        break;
                    }
                }
                if comp.len() > 1 {
                    comp.sort();
                    self.out.push(comp);
                }
            }
        }
    }
    let mut t = T {
        g,
        index: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        next: 0,
        out: Vec::new(),
    };
    for v in g.keys() {
        if !t.index.contains_key(v) {
            t.visit(v);
        }
    }
    t.out
}

#[test]
fn no_crate_has_an_import_cycle() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut found = Vec::new();
    for src in [
        "src",
        "codegen/src",
        "runtime/src",
        "python/src",
        "tests/odd-files/src",
    ] {
        let g = graph(&root.join(src));
        assert!(
            g.len() > 1 || src.starts_with("tests"),
            "{src}: no modules read"
        );
        for c in cycles(&g) {
            found.push(format!("{src}: {}", c.join(" ↔ ")));
        }
    }
    assert!(found.is_empty(), "import cycles:\n{}", found.join("\n"));
}

/// The check finds a cycle through a parent and its child (`super::T` one way, a path the other)
/// and one between siblings, and none where a child is only re-exported.
#[test]
fn the_check_finds_cycles() {
    let dir = std::env::temp_dir().join(format!("mechgen-cycles-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("a")).expect("dir");
    let write = |p: &str, t: &str| std::fs::write(dir.join(p), t).expect("write");
    write("lib.rs", "mod a;\nmod b;\nmod c;\npub use c::C;\n");
    write(
        "a/mod.rs",
        "mod child;\npub struct T;\nfn f() { child::g(); }\n",
    );
    write("a/child.rs", "use super::T;\npub fn g() {}\n");
    write("b.rs", "use crate::c::C;\npub struct B;\n");
    write(
        "c.rs",
        "pub struct C;\n#[cfg(test)]\nmod tests { use crate::b::B; }\nfn h() -> crate::b::B { crate::b::B }\n",
    );
    let found = cycles(&graph(&dir));
    assert_eq!(
        found,
        vec![
            vec!["a".to_string(), "a::child".to_string()],
            vec!["b".to_string(), "c".to_string()],
        ]
    );
    // Without the path back, no cycle (the test module does not count).
    write(
        "c.rs",
        "pub struct C;\n#[cfg(test)]\nmod tests { use crate::b::B; }\n",
    );
    write("a/mod.rs", "mod child;\npub use child::g;\npub struct T;\n");
    assert!(cycles(&graph(&dir)).is_empty());
    std::fs::remove_dir_all(&dir).expect("clean up");
}
