//! CLI, a mechanism file's analysis made once per process: every command that needs it (the
//! engines of a sweep, its branch analysis and default range, the main job's summaries and notes,
//! `batch`'s other-branch rows, `metrics`' links) shares the one analysis of its file.

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use mechgen_codegen::Compiled;
use mechgen_codegen::diagnostic::{Diagnostic, SourceFile};

/// A file as read and analysed: its text, its mechanisms and every diagnostic.
pub struct FileAnalysis {
    pub file: SourceFile,
    pub compiled: Vec<Compiled>,
    pub diagnostics: Vec<Diagnostic>,
}

thread_local! {
    /// The analyses made so far, by path (`None`: the compiled-in file).
    static ANALYSES: RefCell<Vec<(Option<PathBuf>, Rc<FileAnalysis>)>> = const { RefCell::new(Vec::new()) };
}

/// The analysis of the file at `path` (or of the compiled-in file), made on first use.
pub fn analysis(path: Option<&Path>) -> Result<Rc<FileAnalysis>, String> {
    let key = path.map(Path::to_path_buf);
    if let Some(hit) = ANALYSES.with(|a| {
        a.borrow()
            .iter()
            .find(|(k, _)| *k == key)
            .map(|(_, v)| Rc::clone(v))
    }) {
        return Ok(hit);
    }
    let (name, text) = match path {
        Some(p) => (
            p.display().to_string(),
            std::fs::read_to_string(p).map_err(|e| format!("cannot read {}: {e}", p.display()))?,
        ),
        None => (
            mechgen::source::SOURCE_NAME.to_string(),
            mechgen::source::SOURCE.to_string(),
        ),
    };
    let file = SourceFile::new(name, text);
    let (compiled, diagnostics) = mechgen_codegen::analyze(&file);
    let made = Rc::new(FileAnalysis {
        file,
        compiled,
        diagnostics,
    });
    ANALYSES.with(|a| a.borrow_mut().push((key, Rc::clone(&made))));
    Ok(made)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A second request for the same file is the first analysis, not a new one.
    #[test]
    fn a_file_is_analysed_once() {
        let a = analysis(None).expect("the compiled-in file");
        let b = analysis(None).expect("the compiled-in file");
        assert!(Rc::ptr_eq(&a, &b));
        assert!(!a.compiled.is_empty());
        let missing = Path::new("/nonexistent/mechanism.toml");
        assert!(analysis(Some(missing)).is_err());
    }
}
