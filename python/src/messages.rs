//! Messages of the shared code (the sweep plan, the simulation's row count) for Python: they name
//! the command line's options, here keyword arguments.

use pyo3::PyErr;
use pyo3::exceptions::PyValueError;

/// Where a param given as an input changes from Python (the shared code names the command line's).
const PARAM_HINT: &str = "give its value with `params=`, or several sets with `batch`";

/// A `ValueError` with a message of the shared code ([`python_words`]).
pub fn keyword_error(message: String) -> PyErr {
    PyValueError::new_err(python_words(&message))
}

/// A message of the shared code, which names the command line's options (`--step`,
/// `--from/--to`, `--time`) and where params change there, in Python's words: keyword arguments,
/// named without the dashes, and `params=`.
pub fn python_words(message: &str) -> String {
    let message = message.replace(mg::sweep::plan::PARAM_HINT, PARAM_HINT);
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
    out
}
