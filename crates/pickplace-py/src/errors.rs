//! The exceptions of the package and the mapping of Rust errors onto them.

use pyo3::exceptions::{PyException, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyList;

pyo3::create_exception!(
    pickplace,
    InputError,
    PyValueError,
    "Bad input: an unreadable or invalid file, or a value out of range. The message is the \
     one `pickplace` prints after `error: ` (it names the file and what is wrong)."
);

pyo3::create_exception!(
    pickplace,
    NoPlanError,
    PyException,
    "A well-formed scene with no solution. `reasons` (list of str) says why, one line per \
     reason; `stats` (dict, or None for a scene refused before the search: a start state in \
     collision, an object not resting, an unusable target) holds the counts per strategy and \
     stage (`stats[\"strategies\"][i][\"stages\"][stage][\"rejected\"]`)."
);

/// An error and its causes on one line: the line the CLI prints after `error: `.
pub use pickplace::error::message;

/// Bad input, with the CLI's message.
pub fn input(error: &(dyn std::error::Error + 'static)) -> PyErr {
    InputError::new_err(message(error))
}

/// An input error with a message of our own.
pub fn input_msg(text: impl Into<String>) -> PyErr {
    InputError::new_err(text.into())
}

/// A façade error: an infeasible scene is a [`NoPlanError`] (the CLI's exit status 1) with
/// the message as its only reason, a defect of a lower layer a `RuntimeError`, everything
/// else bad input.
pub fn facade(py: Python<'_>, error: &pickplace::Error) -> PyErr {
    if error.is_infeasible() {
        let text = message(error);
        no_plan(py, &text, std::slice::from_ref(&text), None)
    } else if matches!(error, pickplace::Error::Internal { .. }) {
        PyRuntimeError::new_err(message(error))
    } else {
        input(error)
    }
}

/// A [`NoPlanError`] with its `reasons` and `stats` attributes set.
pub fn no_plan(
    py: Python<'_>,
    text: &str,
    reasons: &[String],
    stats: Option<Bound<'_, PyAny>>,
) -> PyErr {
    let err = NoPlanError::new_err(text.to_owned());
    let value = err.value(py);
    let set = PyList::new(py, reasons)
        .and_then(|list| value.setattr("reasons", list))
        .and_then(|()| value.setattr("stats", stats.unwrap_or_else(|| py.None().into_bound(py))));
    match set {
        Ok(()) => err,
        Err(e) => e,
    }
}
