//! Shared helpers of the command-line tests: run the `mechgen` binary, temporary directories
//! removed after their test, and output as text.
#![allow(dead_code)]

use std::ffi::OsStr;
use std::ops::Deref;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Runs the `mechgen` binary from the repository root.
pub fn mechgen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mechgen"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("mechgen runs")
}

/// `name` in a fresh directory of its own ([`TempDir`] named by `suite`): the directory and
/// everything in it (the file, and whatever a command wrote beside it) go when the path is
/// dropped.
pub fn temp(suite: &str, name: &str) -> Temp {
    let dir = TempDir::new(suite);
    Temp {
        path: dir.join(name),
        _dir: dir,
    }
}

/// A path in a directory of its own ([`temp`]), removed with it on drop.
pub struct Temp {
    path: PathBuf,
    _dir: TempDir,
}

impl Deref for Temp {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.path
    }
}

impl AsRef<Path> for Temp {
    fn as_ref(&self) -> &Path {
        &self.path
    }
}

impl AsRef<OsStr> for Temp {
    fn as_ref(&self) -> &OsStr {
        self.path.as_os_str()
    }
}

/// A fresh temporary directory, `mechgen-{name}-{process}-{n}` (unique per call), removed with
/// everything in it on drop, but kept when its test fails (a panic), to be looked at.
pub struct TempDir(PathBuf);

impl TempDir {
    pub fn new(name: &str) -> Self {
        static NEXT: AtomicUsize = AtomicUsize::new(0);
        let n = NEXT.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("mechgen-{name}-{}-{n}", std::process::id()));
        // Left by an earlier process of the same id: its files must not pass for this test's.
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("temp dir");
        TempDir(dir)
    }
}

impl Deref for TempDir {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for TempDir {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        if std::thread::panicking() {
            eprintln!("kept for a look: {}", self.0.display());
        } else {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}
