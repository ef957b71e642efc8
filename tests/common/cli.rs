//! Shared helpers of the command-line tests: run the `mechgen` binary, a per-process temporary
//! directory, and output as text.
#![allow(dead_code)]

use std::path::PathBuf;
use std::process::{Command, Output};

/// Runs the `mechgen` binary from the repository root.
pub fn mechgen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mechgen"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("mechgen runs")
}

/// `name` inside a temporary directory of this test process, named by `suite`.
pub fn temp(suite: &str, name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("mechgen-{suite}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}
