//! The one place where core errors become Python exceptions.
//!
//! The exception classes live in `skillwright.errors` (one hierarchy, with
//! docstrings, used by pure-Python code as well); they are imported lazily here.

use pyo3::PyErr;
use skillwright_core::CoreError;

pyo3::import_exception!(skillwright.errors, InputFileNotFoundError);
pyo3::import_exception!(skillwright.errors, InputFileError);
pyo3::import_exception!(skillwright.errors, FileFormatError);
pyo3::import_exception!(skillwright.errors, InvalidArgumentError);

/// Converts a core error into the matching `skillwright.errors` exception.
pub fn to_py(err: CoreError) -> PyErr {
    let message = err.to_string();
    match err {
        CoreError::NotFound { .. } => InputFileNotFoundError::new_err(message),
        CoreError::Io { .. } => InputFileError::new_err(message),
        CoreError::Format { .. } => FileFormatError::new_err(message),
        CoreError::InvalidArgument(_) => InvalidArgumentError::new_err(message),
    }
}
