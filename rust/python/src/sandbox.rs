//! `skillwright._core.seccomp_programs` and `confine_child`: the kernel layers of the skill
//! sandbox (`skillwright_core::sandbox`).
//!
//! `confine_child` runs inside the sandboxed child, which has none of skillwright's Python
//! package: its errors are plain `OSError`s, never `skillwright.errors` classes.

use std::path::PathBuf;

use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use skillwright_core::sandbox;
use skillwright_core::CoreError;

fn os_error(error: CoreError) -> PyErr {
    PyOSError::new_err(format!("the sandbox could not confine the skill: {error}"))
}

/// The base allow-list and its fallbacks, as bubblewrap's `--seccomp` reads them.
#[pyfunction]
fn seccomp_programs(py: Python<'_>) -> PyResult<(Bound<'_, PyBytes>, Bound<'_, PyBytes>)> {
    let base = sandbox::base_program().map_err(os_error)?;
    let fallbacks = sandbox::fallback_program().map_err(os_error)?;
    Ok((
        PyBytes::new(py, &sandbox::program_bytes(&base)),
        PyBytes::new(py, &sandbox::program_bytes(&fallbacks)),
    ))
}

/// Confines the calling (just forked, single-threaded) process for good; returns what the
/// kernel enforced: ``{"landlock": ..., "seccomp": [...]}``.
#[pyfunction]
#[pyo3(signature = (pid, readable, writable, with_base))]
fn confine_child<'py>(
    py: Python<'py>,
    pid: i32,
    readable: Vec<PathBuf>,
    writable: Vec<PathBuf>,
    with_base: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let done = sandbox::confine_child(pid, &readable, &writable, with_base).map_err(os_error)?;
    let result = PyDict::new(py);
    result.set_item("landlock", done.landlock)?;
    result.set_item("seccomp", done.seccomp)?;
    Ok(result)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(seccomp_programs, m)?)?;
    m.add_function(wrap_pyfunction!(confine_child, m)?)?;
    Ok(())
}
