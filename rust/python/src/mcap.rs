//! `read_mcap` and the read-only classes it returns; `read_mcap_messages` and its iterator.

use std::collections::{BTreeMap, HashSet};
use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::PyBytes;
use skillwright_core::mcap::{self, ReadMode};

use crate::errors;

/// A schema record: how messages of the channels that use it are laid out.
#[pyclass(frozen, module = "skillwright._core", name = "McapSchema")]
#[derive(Clone)]
pub struct PyMcapSchema {
    #[pyo3(get)]
    id: u16,
    #[pyo3(get)]
    name: String,
    #[pyo3(get)]
    encoding: String,
    data: Vec<u8>,
}

#[pymethods]
impl PyMcapSchema {
    /// The schema's bytes as stored (for `ros2msg`, the message definition text).
    #[getter]
    fn data<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        PyBytes::new(py, &self.data)
    }

    fn __repr__(&self) -> String {
        format!(
            "McapSchema(id={}, name={:?}, encoding={:?})",
            self.id, self.name, self.encoding
        )
    }
}

/// A channel record with its message count and log-time range.
#[pyclass(frozen, get_all, module = "skillwright._core", name = "McapChannel")]
#[derive(Clone)]
pub struct PyMcapChannel {
    id: u16,
    schema_id: u16,
    topic: String,
    message_encoding: String,
    metadata: BTreeMap<String, String>,
    message_count: u64,
    first_log_time: Option<u64>,
    last_log_time: Option<u64>,
    times_exact: bool,
}

#[pymethods]
impl PyMcapChannel {
    fn __repr__(&self) -> String {
        format!(
            "McapChannel(id={}, topic={:?}, message_count={})",
            self.id, self.topic, self.message_count
        )
    }
}

/// A place in the file where something was wrong: byte offset and explanation.
#[pyclass(frozen, get_all, module = "skillwright._core", name = "McapDamage")]
#[derive(Clone)]
pub struct PyMcapDamage {
    offset: u64,
    message: String,
}

#[pymethods]
impl PyMcapDamage {
    fn __repr__(&self) -> String {
        format!(
            "McapDamage(offset={}, message={:?})",
            self.offset, self.message
        )
    }
}

/// What one MCAP file holds, as `read_mcap` found it.
#[pyclass(frozen, get_all, module = "skillwright._core", name = "McapFile")]
pub struct PyMcapFile {
    path: PathBuf,
    file_size: u64,
    profile: Option<String>,
    library: Option<String>,
    method: &'static str,
    schemas: Vec<PyMcapSchema>,
    channels: Vec<PyMcapChannel>,
    message_count: u64,
    message_start_time: Option<u64>,
    message_end_time: Option<u64>,
    attachment_count: u64,
    metadata_count: u64,
    chunk_count: u64,
    compressions: Vec<String>,
    orphan_message_count: u64,
    stopped: Option<PyMcapDamage>,
    damaged: Vec<PyMcapDamage>,
    notes: Vec<String>,
}

#[pymethods]
impl PyMcapFile {
    /// True when part of the file could not be read (`stopped` or `damaged`).
    #[getter]
    fn partial(&self) -> bool {
        self.stopped.is_some() || !self.damaged.is_empty()
    }

    fn __repr__(&self) -> String {
        format!(
            "McapFile(path={:?}, method={:?}, channels={}, message_count={})",
            self.path,
            self.method,
            self.channels.len(),
            self.message_count
        )
    }
}

fn damage(d: mcap::Damage) -> PyMcapDamage {
    PyMcapDamage {
        offset: d.offset,
        message: d.message,
    }
}

impl From<mcap::McapSummary> for PyMcapFile {
    fn from(s: mcap::McapSummary) -> Self {
        Self {
            path: s.path,
            file_size: s.file_size,
            profile: s.profile,
            library: s.library,
            method: s.method.as_str(),
            schemas: s
                .schemas
                .into_iter()
                .map(|x| PyMcapSchema {
                    id: x.id,
                    name: x.name,
                    encoding: x.encoding,
                    data: x.data,
                })
                .collect(),
            channels: s
                .channels
                .into_iter()
                .map(|c| PyMcapChannel {
                    id: c.id,
                    schema_id: c.schema_id,
                    topic: c.topic,
                    message_encoding: c.message_encoding,
                    metadata: c.metadata,
                    message_count: c.message_count,
                    first_log_time: c.first_log_time,
                    last_log_time: c.last_log_time,
                    times_exact: c.times_exact,
                })
                .collect(),
            message_count: s.message_count,
            message_start_time: s.message_start_time,
            message_end_time: s.message_end_time,
            attachment_count: s.attachment_count,
            metadata_count: s.metadata_count,
            chunk_count: s.chunk_count,
            compressions: s.compressions,
            orphan_message_count: s.orphan_message_count,
            stopped: s.stopped.map(damage),
            damaged: s.damaged.into_iter().map(damage).collect(),
            notes: s.notes,
        }
    }
}

/// Reads what an MCAP file holds without holding the GIL; see `skillwright._core.pyi`.
#[pyfunction]
#[pyo3(signature = (path, mode = "auto"))]
fn read_mcap(py: Python<'_>, path: PathBuf, mode: &str) -> PyResult<PyMcapFile> {
    let mode = ReadMode::parse(mode).map_err(errors::to_py)?;
    py.detach(|| mcap::read_mcap(&path, mode))
        .map(PyMcapFile::from)
        .map_err(errors::to_py)
}

/// The messages of one MCAP file as `(log time in ns, topic, payload)`; see `_core.pyi`.
#[pyclass(module = "skillwright._core", name = "McapMessages")]
pub struct PyMcapMessages {
    reader: mcap::MessageReader,
}

#[pymethods]
impl PyMcapMessages {
    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    fn __next__<'py>(
        mut slf: PyRefMut<'py, Self>,
        py: Python<'py>,
    ) -> PyResult<Option<(u64, String, Bound<'py, PyBytes>)>> {
        let reader = &mut slf.reader;
        let next = py.detach(|| reader.next_message()).map_err(errors::to_py)?;
        Ok(next.map(|m| (m.log_time, m.topic.to_string(), PyBytes::new(py, &m.data))))
    }
}

/// Opens an MCAP file for reading its messages; see `skillwright._core.pyi`.
#[pyfunction]
#[pyo3(signature = (path, topics = None))]
fn read_mcap_messages(
    py: Python<'_>,
    path: PathBuf,
    topics: Option<HashSet<String>>,
) -> PyResult<PyMcapMessages> {
    py.detach(|| mcap::MessageReader::open(&path, topics))
        .map(|reader| PyMcapMessages { reader })
        .map_err(errors::to_py)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyMcapSchema>()?;
    m.add_class::<PyMcapChannel>()?;
    m.add_class::<PyMcapDamage>()?;
    m.add_class::<PyMcapFile>()?;
    m.add_class::<PyMcapMessages>()?;
    m.add_function(wrap_pyfunction!(read_mcap, m)?)?;
    m.add_function(wrap_pyfunction!(read_mcap_messages, m)?)?;
    Ok(())
}
