//! Messages of the shared code (the sweep plan, the simulation's row count) for Python: they name
//! the command line's options, here keyword arguments.

use pyo3::PyErr;
use pyo3::exceptions::PyValueError;

/// A `ValueError` with a message of the shared code, which names the command line's options
/// (`--step`, `--from/--to`, `--time`): here they are keyword arguments, named without the dashes.
pub fn keyword_error(message: String) -> PyErr {
    let mut out = String::with_capacity(message.len());
    let mut rest = message.as_str();
    while let Some(at) = rest.find("--") {
        out.push_str(&rest[..at]);
        let after = &rest[at + 2..];
        if !after.starts_with(|c: char| c.is_ascii_lowercase()) {
            out.push_str("--");
        }
        rest = after;
    }
    out.push_str(rest);
    PyValueError::new_err(out)
}
