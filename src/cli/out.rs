//! CLI: a file a command writes row by row (`batch`'s, `simulate`'s CSV), buffered, its first
//! error kept and reported with its name when it is finished.

use std::io::Write as _;

/// A file opened for writing, with its name for errors.
pub struct Out {
    path: std::path::PathBuf,
    w: std::io::BufWriter<std::fs::File>,
    error: Option<std::io::Error>,
}

impl Out {
    /// `path` created (or truncated), with `header` written first.
    pub fn create(path: &std::path::Path, header: &str) -> Result<Out, String> {
        let f = std::fs::File::create(path)
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        let mut out = Out {
            path: path.to_path_buf(),
            w: std::io::BufWriter::with_capacity(super::OUTPUT_BUFFER, f),
            error: None,
        };
        out.write(header.as_bytes());
        Ok(out)
    }

    /// `s` appended, unless an earlier write failed.
    pub fn write(&mut self, s: &[u8]) {
        if self.error.is_none() {
            self.error = self.w.write_all(s).err();
        }
    }

    /// Flushed; the first error of any write or of the flush, naming the file.
    pub fn finish(mut self) -> Result<(), String> {
        match self.error.take().or_else(|| self.w.flush().err()) {
            Some(e) => Err(format!("cannot write {}: {e}", self.path.display())),
            None => Ok(()),
        }
    }
}
