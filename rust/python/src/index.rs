//! `skillwright._core.VectorIndex`: the exact vector index of `skillwright_core::index`.
//!
//! Arrays arrive as NumPy float32 / int64 arrays and are read in place (the Python facade
//! converts other dtypes and layouts first). Work that scales with the index runs without
//! the GIL; tiny searches keep it, because releasing and re-taking it would cost more
//! than the search itself.

use std::path::PathBuf;

use numpy::ndarray::Array2;
use numpy::{PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use skillwright_core::index::{Filter, Hits, Tags, VectorIndex};
use skillwright_core::CoreError;

use crate::errors;

/// Rows x dimension below which a call keeps the GIL (a few microseconds of work).
const DETACH_WORK: usize = 1 << 17;

/// Ids and scores of a search, as NumPy arrays.
type HitArrays<'py, I, S> = (Bound<'py, I>, Bound<'py, S>);

/// A tag argument: one string for every row, or one per row.
#[derive(FromPyObject)]
enum TagArg {
    One(String),
    Many(Vec<String>),
}

impl TagArg {
    fn as_tags(&self) -> Tags<'_> {
        match self {
            TagArg::One(tag) => Tags::Same(tag),
            TagArg::Many(tags) => Tags::PerRow(tags),
        }
    }
}

fn invalid(message: String) -> PyErr {
    errors::to_py(CoreError::InvalidArgument(message))
}

fn slice<'a, T: numpy::Element>(
    array: &'a numpy::PyReadonlyArray<'_, T, impl numpy::ndarray::Dimension>,
    what: &str,
) -> PyResult<&'a [T]> {
    array.as_slice().map_err(|_| {
        invalid(format!(
            "{what} must be a C-contiguous array (use numpy.ascontiguousarray)"
        ))
    })
}

fn check_k(k: i64) -> PyResult<usize> {
    usize::try_from(k).ok().filter(|k| *k > 0).ok_or_else(|| {
        invalid(format!(
            "k must be at least 1 (the number of hits to return), got {k}"
        ))
    })
}

/// An exact cosine index over float32 vectors with int64 ids and (kind, source) tags.
#[pyclass(name = "VectorIndex", module = "skillwright._core")]
pub struct PyVectorIndex {
    inner: VectorIndex,
}

#[pymethods]
impl PyVectorIndex {
    #[new]
    fn new(dim: i64) -> PyResult<Self> {
        let dim = usize::try_from(dim)
            .map_err(|_| invalid(format!("vector dimension must be positive, got {dim}")))?;
        Ok(PyVectorIndex {
            inner: VectorIndex::new(dim).map_err(errors::to_py)?,
        })
    }

    /// Opens an index saved with `save`, memory-mapped.
    #[staticmethod]
    fn open(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let inner = py
            .detach(|| VectorIndex::open(&path))
            .map_err(errors::to_py)?;
        Ok(PyVectorIndex { inner })
    }

    /// Writes the index to `path` (temporary file + rename).
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let inner = &self.inner;
        py.detach(|| inner.save(&path)).map_err(errors::to_py)
    }

    /// Checks the checksums of a mapped index's vector data now rather than on first use.
    fn verify(&self, py: Python<'_>) -> PyResult<()> {
        let inner = &self.inner;
        py.detach(|| inner.verify()).map_err(errors::to_py)
    }

    #[getter]
    fn dim(&self) -> usize {
        self.inner.dim()
    }

    #[getter]
    fn mapped(&self) -> bool {
        self.inner.is_mapped()
    }

    fn __len__(&self) -> usize {
        self.inner.len()
    }

    fn __contains__(&self, id: i64) -> PyResult<bool> {
        self.inner.contains(id).map_err(errors::to_py)
    }

    /// Ids of all rows, in storage order.
    fn ids<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        PyArray1::from_slice(py, self.inner.ids())
    }

    /// Every kind tag the index knows.
    fn kinds(&self) -> Vec<String> {
        self.inner.kind_names().to_vec()
    }

    /// Every source tag the index knows.
    fn sources(&self) -> Vec<String> {
        self.inner.source_names().to_vec()
    }

    /// The stored (normalised) vector, kind and source of one id.
    fn get<'py>(
        &self,
        py: Python<'py>,
        id: i64,
    ) -> PyResult<(Bound<'py, PyArray1<f32>>, String, String)> {
        let record = self.inner.get(id).map_err(errors::to_py)?;
        Ok((
            PyArray1::from_vec(py, record.vector),
            record.kind,
            record.source,
        ))
    }

    fn add(
        &mut self,
        py: Python<'_>,
        ids: PyReadonlyArray1<'_, i64>,
        vectors: PyReadonlyArray2<'_, f32>,
        kind: TagArg,
        source: TagArg,
    ) -> PyResult<()> {
        let ids = slice(&ids, "ids")?;
        let data = slice(&vectors, "vectors")?;
        let shape = vectors.shape();
        if shape.get(1).copied() != Some(self.inner.dim())
            || shape.first().copied() != Some(ids.len())
        {
            return Err(invalid(format!(
                "vectors have shape {shape:?}, expected ({}, {}) for {} ids in an index of \
                 dimension {}; embed them with the same model as the index",
                ids.len(),
                self.inner.dim(),
                ids.len(),
                self.inner.dim()
            )));
        }
        let (kind, source) = (kind.as_tags(), source.as_tags());
        let inner = &mut self.inner;
        if data.len() >= DETACH_WORK {
            py.detach(|| inner.add(ids, data, kind, source))
        } else {
            inner.add(ids, data, kind, source)
        }
        .map_err(errors::to_py)
    }

    #[pyo3(signature = (ids, vectors=None, kind=None, source=None))]
    fn update(
        &mut self,
        ids: PyReadonlyArray1<'_, i64>,
        vectors: Option<PyReadonlyArray2<'_, f32>>,
        kind: Option<TagArg>,
        source: Option<TagArg>,
    ) -> PyResult<()> {
        let ids = slice(&ids, "ids")?;
        let data = match &vectors {
            Some(v) => {
                if v.shape().get(1).copied() != Some(self.inner.dim()) {
                    return Err(invalid(format!(
                        "vectors have shape {:?}, but the index holds vectors of dimension {}",
                        v.shape(),
                        self.inner.dim()
                    )));
                }
                Some(slice(v, "vectors")?)
            }
            None => None,
        };
        self.inner
            .update(
                ids,
                data,
                kind.as_ref().map(TagArg::as_tags),
                source.as_ref().map(TagArg::as_tags),
            )
            .map_err(errors::to_py)
    }

    fn remove(&mut self, ids: PyReadonlyArray1<'_, i64>) -> PyResult<()> {
        let ids = slice(&ids, "ids")?;
        self.inner.remove(ids).map_err(errors::to_py)
    }

    #[pyo3(signature = (query, k, kinds=None, sources=None))]
    fn search<'py>(
        &self,
        py: Python<'py>,
        query: PyReadonlyArray1<'py, f32>,
        k: i64,
        kinds: Option<Vec<String>>,
        sources: Option<Vec<String>>,
    ) -> PyResult<HitArrays<'py, PyArray1<i64>, PyArray1<f32>>> {
        let k = check_k(k)?;
        let q = slice(&query, "query")?;
        let filter = Filter {
            kinds: kinds.as_deref(),
            sources: sources.as_deref(),
        };
        let inner = &self.inner;
        let hits = if inner.len() * inner.dim() >= DETACH_WORK {
            py.detach(|| inner.search(q, k, &filter))
        } else {
            inner.search(q, k, &filter)
        }
        .map_err(errors::to_py)?;
        Ok((
            PyArray1::from_vec(py, hits.ids),
            PyArray1::from_vec(py, hits.scores),
        ))
    }

    #[pyo3(signature = (queries, k, kinds=None, sources=None))]
    fn search_batch<'py>(
        &self,
        py: Python<'py>,
        queries: PyReadonlyArray2<'py, f32>,
        k: i64,
        kinds: Option<Vec<String>>,
        sources: Option<Vec<String>>,
    ) -> PyResult<HitArrays<'py, PyArray2<i64>, PyArray2<f32>>> {
        let k = check_k(k)?;
        let shape = queries.shape();
        if shape.get(1).copied() != Some(self.inner.dim()) {
            return Err(invalid(format!(
                "queries have shape {shape:?}, but the index holds vectors of dimension {}; \
                 embed them with the same model as the index",
                self.inner.dim()
            )));
        }
        let q = slice(&queries, "queries")?;
        let filter = Filter {
            kinds: kinds.as_deref(),
            sources: sources.as_deref(),
        };
        let inner = &self.inner;
        let hits: Hits = if inner.len() * q.len() >= DETACH_WORK {
            py.detach(|| inner.search_batch(q, k, &filter))
        } else {
            inner.search_batch(q, k, &filter)
        }
        .map_err(errors::to_py)?;
        let shape = (hits.queries, hits.k);
        let ids = Array2::from_shape_vec(shape, hits.ids)
            .map_err(|e| invalid(format!("internal shape error: {e}")))?;
        let scores = Array2::from_shape_vec(shape, hits.scores)
            .map_err(|e| invalid(format!("internal shape error: {e}")))?;
        Ok((
            PyArray2::from_owned_array(py, ids),
            PyArray2::from_owned_array(py, scores),
        ))
    }

    fn __repr__(&self) -> String {
        format!(
            "VectorIndex(dim={}, len={}, mapped={})",
            self.inner.dim(),
            self.inner.len(),
            self.inner.is_mapped()
        )
    }
}

/// Name of the instruction set the index's scoring loops use on this CPU.
#[pyfunction]
fn index_isa() -> &'static str {
    skillwright_core::index::isa_name()
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyVectorIndex>()?;
    m.add_function(wrap_pyfunction!(index_isa, m)?)?;
    Ok(())
}
