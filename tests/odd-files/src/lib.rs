//! Fixture crate: odd but valid mechanism files (no points, no params, two inputs, 1×1 blocks,
//! unknowns named like a naive emitter's locals, mechanisms named like generated items, runtime
//! functions, mechgen's modules and std crates), generated in this crate's own build and included
//! at its root; `tests/solve.rs` solves every one against an independent reference.

// `::mechgen`: this file has a mechanism named `mechgen`, whose module at this crate's root would
// make the plain `mechgen::` path ambiguous.
::mechgen::include_mechanisms!();

/// `other.toml`, generated for the runtime path `::mechgen_runtime` into `OUT_DIR/other.rs`.
pub mod other {
    ::mechgen::include_mechanisms!("other.rs");
}

/// `derived.toml`: derived params (expressions of other params) follow their bases at run time.
pub mod derived {
    ::mechgen::include_mechanisms!("derived.rs");
}

/// `closed.toml`: closed-form blocks no other file has, an offset slot (RPR, `h != 0`), an
/// inclined slide (RRP) and a cross slide (two lengths), in generated code (`tests/closed.rs`,
/// in lanes `tests/lanes.rs`).
pub mod closed {
    ::mechgen::include_mechanisms!("closed.rs");
}

/// `unread.toml`: a scene whose mechanism has a length param (1e12) the scene does not read
/// (`tests/unread.rs`).
pub mod unread {
    ::mechgen::include_mechanisms!("unread.rs");
}

/// `crossings.toml`: linkages whose branches cross (a parallelogram, a kite, a deltoid, an
/// isosceles slider-crank), swept through their crossings in `tests/crossings.rs`.
pub mod crossings {
    ::mechgen::include_mechanisms!("crossings.rs");
}

/// `weak.toml`: a mechanism, an input, an unknown, params and a point named after Rust's weak
/// keywords (`union`, `raw`, `safe`, `macro_rules`), which are identifiers (`tests/weak.rs`).
pub mod weak {
    ::mechgen::include_mechanisms!("weak.rs");
}
