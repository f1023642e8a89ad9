//! `skillwright._core`: the Python face of skillwright-core.
//!
//! Thin by design: argument conversion, releasing the GIL around real work, and
//! error mapping (see `errors`). All logic lives in the core crate.

mod errors;
mod index;
mod mcap;
#[cfg(target_os = "linux")]
mod sandbox;

use std::path::PathBuf;

use pyo3::prelude::*;

/// Lower-case hex SHA-256 of a file, computed without holding the GIL.
#[pyfunction]
fn sha256_file(py: Python<'_>, path: PathBuf) -> PyResult<String> {
    py.detach(|| skillwright_core::digest::sha256_file(&path))
        .map_err(errors::to_py)
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", skillwright_core::VERSION)?;
    m.add_function(wrap_pyfunction!(sha256_file, m)?)?;
    index::register(m)?;
    mcap::register(m)?;
    #[cfg(target_os = "linux")]
    sandbox::register(m)?;
    Ok(())
}
