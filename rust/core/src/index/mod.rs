//! An exact vector index: cosine top-k over f32 vectors with ids and metadata.
//!
//! Vectors are normalised on insert, so a dot product is their cosine; every search
//! considers every (allowed) row, so results are exact and equal a brute-force reference.
//! Large single searches first score 8-bit copies of the rows and rescore in f32 only the
//! rows whose error bounds leave them a chance (`prefilter`): same result, a quarter of
//! the memory traffic.
//! Hits are ordered by score, high first, and ties by id, low first. Rows have no order
//! of their own: removal moves the last row into the gap.
//!
//! Each row carries a small metadata record, two tags: a *kind* (`topic`, `service`,
//! `action`, ...) and a *source* (the robot, bag or document set it came from). Tags are
//! interned, so a row stores two `u32` codes, and searches can be restricted to some kinds
//! and/or sources. See `file` for the on-disk format.

mod column;
mod file;
mod kernel;
mod prefilter;
mod topk;

use std::collections::hash_map::Entry;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

use rayon::prelude::*;
use rustc_hash::FxHashMap;

use crate::error::{CoreError, CoreResult};
use column::Column;
use topk::TopK;

pub use kernel::isa_name;

/// Largest vector dimension an index accepts.
pub const MAX_DIM: usize = 1 << 16;
/// Longest tag (kind or source) in bytes: the metadata record is meant to stay small.
pub const MAX_TAG_LEN: usize = 255;

/// Work (rows x dimension) from which one search is split across threads; below it the
/// cost of waking threads outweighs the gain, and the search stays on the caller's thread.
const PARALLEL_WORK: usize = 1 << 17;
/// Allowed rows from which a single search takes the 8-bit first pass (`prefilter`);
/// below it a full scan is as fast.
const PREFILTER_ROWS: usize = 2048;
/// Rows per tile in batch search: a tile (tens of KiB) stays in L2 while every query of a
/// task is scored against it, so rows are read from memory once per task, not per query.
const TILE_ROWS: usize = 64;
/// Queries per batch task.
const BATCH_QUERIES: usize = 32;

/// Tags for the rows of an `add` or `update`: one for all, or one per row.
#[derive(Clone, Copy, Debug)]
pub enum Tags<'a> {
    Same(&'a str),
    PerRow(&'a [String]),
}

impl Tags<'_> {
    fn get(&self, row: usize) -> &str {
        match self {
            Tags::Same(tag) => tag,
            Tags::PerRow(tags) => tags.get(row).map_or("", String::as_str),
        }
    }
}

/// Which rows a search may return: rows whose kind is in `kinds` (when given) and whose
/// source is in `sources` (when given). A tag the index has never seen matches nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Filter<'a> {
    pub kinds: Option<&'a [String]>,
    pub sources: Option<&'a [String]>,
}

/// Results of a search of `queries` queries: row-major `queries x k` ids and scores,
/// best first per query. `k` is the requested k, or fewer when fewer rows are allowed.
#[derive(Clone, Debug, PartialEq)]
pub struct Hits {
    pub queries: usize,
    pub k: usize,
    pub ids: Vec<i64>,
    pub scores: Vec<f32>,
}

/// A stored row, as returned by `VectorIndex::get`.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    pub vector: Vec<f32>,
    pub kind: String,
    pub source: String,
}

/// Interned tag names; a row stores the code (position) of its tag.
#[derive(Clone, Debug, Default)]
pub(crate) struct TagTable {
    names: Vec<String>,
    codes: FxHashMap<String, u32>,
}

impl TagTable {
    pub(crate) fn from_names(names: Vec<String>) -> Option<Self> {
        let mut codes = FxHashMap::default();
        for (i, name) in names.iter().enumerate() {
            if codes.insert(name.clone(), u32::try_from(i).ok()?).is_some() {
                return None;
            }
        }
        Some(TagTable { names, codes })
    }

    pub(crate) fn names(&self) -> &[String] {
        &self.names
    }

    fn code(&self, name: &str) -> Option<u32> {
        self.codes.get(name).copied()
    }

    fn intern(&mut self, name: &str) -> CoreResult<u32> {
        if let Some(code) = self.codes.get(name) {
            return Ok(*code);
        }
        let code = u32::try_from(self.names.len())
            .map_err(|_| CoreError::InvalidArgument("too many distinct tags".into()))?;
        self.names.push(name.to_owned());
        self.codes.insert(name.to_owned(), code);
        Ok(code)
    }

    fn name(&self, code: u32) -> &str {
        self.names.get(code as usize).map_or("", String::as_str)
    }

    /// `allowed[code]` for each code, or `None` when the filter allows every code.
    fn mask(&self, wanted: Option<&[String]>) -> Option<Vec<bool>> {
        let wanted = wanted?;
        let mut allowed = vec![false; self.names.len()];
        for name in wanted {
            if let Some(code) = self.code(name) {
                allowed[code as usize] = true;
            }
        }
        Some(allowed)
    }
}

/// Where a mapped index came from, and whether its vector payload has been checked.
#[derive(Debug)]
struct Backing {
    path: PathBuf,
    map: Arc<memmap2::Mmap>,
    /// Checksummed blocks of the vector payload not yet verified at open time.
    lazy_blocks: Vec<file::Block>,
    verified: OnceLock<Result<(), (u64, String)>>,
}

/// An exact cosine index over `dim`-dimensional f32 vectors.
#[derive(Debug)]
pub struct VectorIndex {
    dim: usize,
    vectors: Column<f32>,
    ids: Column<i64>,
    kinds: Column<u32>,
    sources: Column<u32>,
    kind_names: TagTable,
    source_names: TagTable,
    /// id -> row, built on first use: opening a large index should not pay for it.
    id_rows: OnceLock<Result<FxHashMap<i64, u32>, i64>>,
    /// 8-bit copy of the vectors for the first pass of large single searches, built on
    /// first use (or mapped from the file) and kept up to date by every change.
    quant: OnceLock<prefilter::Quantized>,
    backing: Option<Backing>,
}

fn normalise_into(src: &[f32], dst: &mut [f32], what: impl Fn() -> String) -> CoreResult<()> {
    // Sum in f64: squares of large finite f32 values would overflow in f32.
    let mut sum = 0.0f64;
    for (i, x) in src.iter().enumerate() {
        if !x.is_finite() {
            return Err(CoreError::InvalidArgument(format!(
                "{} has a NaN or infinite value at position {i}; embeddings must be finite",
                what()
            )));
        }
        sum += f64::from(*x) * f64::from(*x);
    }
    if sum == 0.0 {
        return Err(CoreError::InvalidArgument(format!(
            "{} is all zeros and has no direction, so it has no cosine with anything; \
             check the embedding step",
            what()
        )));
    }
    let inv = 1.0 / sum.sqrt();
    for (d, x) in dst.iter_mut().zip(src) {
        *d = (f64::from(*x) * inv) as f32;
    }
    Ok(())
}

fn check_tag(tag: &str, what: &str) -> CoreResult<()> {
    if tag.is_empty() || tag.len() > MAX_TAG_LEN {
        return Err(CoreError::InvalidArgument(format!(
            "{what} {tag:?} must be between 1 and {MAX_TAG_LEN} bytes long"
        )));
    }
    Ok(())
}

fn check_tags(tags: &Tags<'_>, rows: usize, what: &str) -> CoreResult<()> {
    match tags {
        Tags::Same(tag) => check_tag(tag, what),
        Tags::PerRow(list) => {
            if list.len() != rows {
                return Err(CoreError::InvalidArgument(format!(
                    "{} {what}s given for {rows} vectors; give one per vector or a single one for all",
                    list.len()
                )));
            }
            list.iter().try_for_each(|t| check_tag(t, what))
        }
    }
}

impl VectorIndex {
    /// An empty index for vectors of dimension `dim`.
    pub fn new(dim: usize) -> CoreResult<Self> {
        if dim == 0 || dim > MAX_DIM {
            return Err(CoreError::InvalidArgument(format!(
                "vector dimension must be between 1 and {MAX_DIM}, got {dim}"
            )));
        }
        Ok(VectorIndex {
            dim,
            vectors: Column::Owned(Vec::new()),
            ids: Column::Owned(Vec::new()),
            kinds: Column::Owned(Vec::new()),
            sources: Column::Owned(Vec::new()),
            kind_names: TagTable::default(),
            source_names: TagTable::default(),
            id_rows: OnceLock::new(),
            quant: OnceLock::new(),
            backing: None,
        })
    }

    /// Dimension of every vector in the index.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Number of stored vectors.
    pub fn len(&self) -> usize {
        self.ids.as_slice().len()
    }

    /// Whether the index holds no vectors.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether the index still reads its data from the file it was opened from.
    pub fn is_mapped(&self) -> bool {
        self.vectors.is_mapped()
    }

    /// Ids of all rows, in row order.
    pub fn ids(&self) -> &[i64] {
        self.ids.as_slice()
    }

    /// Every kind tag the index knows (including tags of since-removed rows).
    pub fn kind_names(&self) -> &[String] {
        self.kind_names.names()
    }

    /// Every source tag the index knows (including tags of since-removed rows).
    pub fn source_names(&self) -> &[String] {
        self.source_names.names()
    }

    fn path_label(&self) -> String {
        self.backing
            .as_ref()
            .map_or_else(|| "the index".to_owned(), |b| b.path.display().to_string())
    }

    fn id_rows(&self) -> CoreResult<&FxHashMap<i64, u32>> {
        let built = self.id_rows.get_or_init(|| {
            let ids = self.ids.as_slice();
            let mut map = FxHashMap::default();
            map.reserve(ids.len());
            for (row, id) in ids.iter().enumerate() {
                if map.insert(*id, row as u32).is_some() {
                    return Err(*id);
                }
            }
            Ok(map)
        });
        built.as_ref().map_err(|id| {
            // Only a file written by something other than this crate can get here.
            CoreError::Format {
                path: self
                    .backing
                    .as_ref()
                    .map_or_else(PathBuf::new, |b| b.path.clone()),
                offset: 0,
                message: format!("id {id} appears more than once; rebuild the index"),
            }
        })
    }

    /// Whether a row with this id exists.
    pub fn contains(&self, id: i64) -> CoreResult<bool> {
        Ok(self.id_rows()?.contains_key(&id))
    }

    /// Verifies the checksums of the vector payload of a mapped index, once.
    ///
    /// Opening a file checks its header, layout, ids and tags; the vector payload (by far
    /// the largest part) is checked here, on first use, so that opening stays cheap.
    pub fn verify(&self) -> CoreResult<()> {
        let Some(backing) = &self.backing else {
            return Ok(());
        };
        let result = backing
            .verified
            .get_or_init(|| file::verify_blocks(&backing.map, &backing.lazy_blocks));
        result
            .clone()
            .map_err(|(offset, message)| CoreError::Format {
                path: backing.path.clone(),
                offset,
                message,
            })
    }

    /// The stored (normalised) vectors, verified first when they come from a file.
    fn vectors(&self) -> CoreResult<&[f32]> {
        self.verify()?;
        Ok(self.vectors.as_slice())
    }

    /// Turns a mapped index into an owned one before a change (verifying it first).
    fn make_owned(&mut self) -> CoreResult<()> {
        if self.backing.is_some() {
            self.verify()?;
            self.id_rows()?;
            self.vectors.to_mut();
            self.ids.to_mut();
            self.kinds.to_mut();
            self.sources.to_mut();
            self.backing = None;
        }
        Ok(())
    }

    fn check_matrix(&self, values: &[f32], rows: usize, what: &str) -> CoreResult<()> {
        if values.len() != rows * self.dim {
            return Err(CoreError::InvalidArgument(format!(
                "{what} have {} values for {rows} rows, but the index holds vectors of \
                 dimension {}; embed them with the same model as the index",
                values.len(),
                self.dim
            )));
        }
        Ok(())
    }

    /// Adds rows; fails without changing anything if an id is already present or
    /// repeated, a vector is not finite or zero, or the shapes do not match.
    pub fn add(
        &mut self,
        ids: &[i64],
        vectors: &[f32],
        kinds: Tags<'_>,
        sources: Tags<'_>,
    ) -> CoreResult<()> {
        let n = ids.len();
        self.check_matrix(vectors, n, "the vectors")?;
        check_tags(&kinds, n, "kind")?;
        check_tags(&sources, n, "source")?;
        if self.len() + n > u32::MAX as usize {
            return Err(CoreError::InvalidArgument(format!(
                "an index holds at most {} vectors",
                u32::MAX
            )));
        }
        {
            let existing = self.id_rows()?;
            let mut seen = FxHashMap::default();
            seen.reserve(n);
            for (i, id) in ids.iter().enumerate() {
                if existing.contains_key(id) {
                    return Err(CoreError::InvalidArgument(format!(
                        "id {id} is already in the index; use update to change it"
                    )));
                }
                if let Some(first) = seen.insert(*id, i) {
                    return Err(CoreError::InvalidArgument(format!(
                        "id {id} is given twice (rows {first} and {i})"
                    )));
                }
            }
        }
        let dim = self.dim;
        let mut normalised = vec![0.0f32; vectors.len()];
        normalised
            .par_chunks_mut(dim)
            .zip(vectors.par_chunks(dim))
            .enumerate()
            .with_min_len(1024)
            .try_for_each(|(i, (dst, src))| {
                normalise_into(src, dst, || format!("vector {i} (id {})", ids[i]))
            })?;

        self.make_owned()?;
        let start = self.len();
        let mut kind_codes = Vec::with_capacity(n);
        let mut source_codes = Vec::with_capacity(n);
        for row in 0..n {
            kind_codes.push(self.kind_names.intern(kinds.get(row))?);
            source_codes.push(self.source_names.intern(sources.get(row))?);
        }
        self.vectors.to_mut().extend_from_slice(&normalised);
        self.ids.to_mut().extend_from_slice(ids);
        self.kinds.to_mut().extend_from_slice(&kind_codes);
        self.sources.to_mut().extend_from_slice(&source_codes);
        if let Some(quant) = self.quant.get_mut() {
            quant.push_rows(&normalised);
        }
        if let Some(Ok(map)) = self.id_rows.get_mut() {
            for (i, id) in ids.iter().enumerate() {
                map.insert(*id, (start + i) as u32);
            }
        }
        Ok(())
    }

    fn rows_of(&self, ids: &[i64]) -> CoreResult<Vec<usize>> {
        let map = self.id_rows()?;
        ids.iter()
            .map(|id| {
                map.get(id).map(|row| *row as usize).ok_or_else(|| {
                    CoreError::InvalidArgument(format!("id {id} is not in {}", self.path_label()))
                })
            })
            .collect()
    }

    /// Replaces the vector and/or tags of existing rows; all-or-nothing like `add`.
    pub fn update(
        &mut self,
        ids: &[i64],
        vectors: Option<&[f32]>,
        kinds: Option<Tags<'_>>,
        sources: Option<Tags<'_>>,
    ) -> CoreResult<()> {
        let n = ids.len();
        let rows = self.rows_of(ids)?;
        let mut seen = FxHashMap::default();
        for (i, id) in ids.iter().enumerate() {
            if let Some(first) = seen.insert(*id, i) {
                return Err(CoreError::InvalidArgument(format!(
                    "id {id} is given twice (rows {first} and {i})"
                )));
            }
        }
        let mut normalised = Vec::new();
        if let Some(vectors) = vectors {
            self.check_matrix(vectors, n, "the vectors")?;
            normalised = vec![0.0f32; vectors.len()];
            for (i, (dst, src)) in normalised
                .chunks_exact_mut(self.dim)
                .zip(vectors.chunks_exact(self.dim))
                .enumerate()
            {
                normalise_into(src, dst, || format!("vector {i} (id {})", ids[i]))?;
            }
        }
        if let Some(kinds) = &kinds {
            check_tags(kinds, n, "kind")?;
        }
        if let Some(sources) = &sources {
            check_tags(sources, n, "source")?;
        }
        self.make_owned()?;
        let dim = self.dim;
        for (i, row) in rows.iter().enumerate() {
            if vectors.is_some() {
                let dst = self.vectors.to_mut();
                let src = normalised.get(i * dim..(i + 1) * dim).unwrap_or(&[]);
                if let Some(slot) = dst.get_mut(row * dim..(row + 1) * dim) {
                    slot.copy_from_slice(src);
                }
                if let Some(quant) = self.quant.get_mut() {
                    quant.set_row(*row, src);
                }
            }
            if let Some(kinds) = &kinds {
                let code = self.kind_names.intern(kinds.get(i))?;
                if let Some(slot) = self.kinds.to_mut().get_mut(*row) {
                    *slot = code;
                }
            }
            if let Some(sources) = &sources {
                let code = self.source_names.intern(sources.get(i))?;
                if let Some(slot) = self.sources.to_mut().get_mut(*row) {
                    *slot = code;
                }
            }
        }
        Ok(())
    }

    /// Removes rows by id; fails without changing anything if an id is missing.
    pub fn remove(&mut self, ids: &[i64]) -> CoreResult<()> {
        self.rows_of(ids)?;
        let mut seen = FxHashMap::default();
        for id in ids {
            if seen.insert(*id, ()).is_some() {
                return Err(CoreError::InvalidArgument(format!(
                    "id {id} is given twice"
                )));
            }
        }
        self.make_owned()?;
        let dim = self.dim;
        for id in ids {
            let Some(Ok(map)) = self.id_rows.get_mut() else {
                break;
            };
            let Some(row) = map.remove(id).map(|r| r as usize) else {
                continue;
            };
            let Some(last) = self.ids.as_slice().len().checked_sub(1) else {
                break;
            };
            let vectors = self.vectors.to_mut();
            let ids_col = self.ids.to_mut();
            if row != last {
                vectors.copy_within(last * dim..(last + 1) * dim, row * dim);
                ids_col.swap(row, last);
                self.kinds.to_mut().swap(row, last);
                self.sources.to_mut().swap(row, last);
                if let Some(moved) = ids_col.get(row) {
                    if let Entry::Occupied(mut e) = map.entry(*moved) {
                        e.insert(row as u32);
                    }
                }
            }
            vectors.truncate(last * dim);
            if let Some(quant) = self.quant.get_mut() {
                quant.swap_remove(row);
            }
            ids_col.truncate(last);
            self.kinds.to_mut().truncate(last);
            self.sources.to_mut().truncate(last);
        }
        Ok(())
    }

    /// The stored (normalised) vector and the tags of the row with this id.
    pub fn get(&self, id: i64) -> CoreResult<Record> {
        let row = *self.rows_of(&[id])?.first().unwrap_or(&0);
        let dim = self.dim;
        let vector = self
            .vectors()?
            .get(row * dim..(row + 1) * dim)
            .unwrap_or(&[])
            .to_vec();
        let kind = self
            .kind_names
            .name(self.kinds.as_slice().get(row).copied().unwrap_or(0));
        let source = self
            .source_names
            .name(self.sources.as_slice().get(row).copied().unwrap_or(0));
        Ok(Record {
            vector,
            kind: kind.to_owned(),
            source: source.to_owned(),
        })
    }

    /// Rows a filter allows, or `None` when it allows all of them.
    fn allowed_rows(&self, filter: &Filter<'_>) -> Option<Vec<u32>> {
        let kinds = self.kind_names.mask(filter.kinds);
        let sources = self.source_names.mask(filter.sources);
        if kinds.is_none() && sources.is_none() {
            return None;
        }
        let allowed = |mask: &Option<Vec<bool>>, code: u32| {
            mask.as_ref()
                .is_none_or(|m| m.get(code as usize).copied().unwrap_or(false))
        };
        let rows = self
            .kinds
            .as_slice()
            .iter()
            .zip(self.sources.as_slice())
            .enumerate()
            .filter(|(_, (k, s))| allowed(&kinds, **k) && allowed(&sources, **s))
            .map(|(row, _)| row as u32)
            .collect();
        Some(rows)
    }

    fn check_k(k: usize) -> CoreResult<()> {
        if k == 0 {
            return Err(CoreError::InvalidArgument(
                "k must be at least 1 (the number of hits to return)".into(),
            ));
        }
        Ok(())
    }

    fn check_query_dim(&self, len: usize) -> CoreResult<()> {
        if len != self.dim {
            return Err(CoreError::InvalidArgument(format!(
                "the query has dimension {len}, but the index holds vectors of dimension {}; \
                 embed the query with the same model as the index",
                self.dim
            )));
        }
        Ok(())
    }

    /// The `k` rows most similar (by cosine) to `query`, best first; ties by id.
    pub fn search(&self, query: &[f32], k: usize, filter: &Filter<'_>) -> CoreResult<Hits> {
        Self::check_k(k)?;
        self.check_query_dim(query.len())?;
        // The query is normalised like the rows, so a score is a cosine; on the stack for
        // common dimensions to keep the small-index path free of allocations.
        let mut stack = [0.0f32; 1024];
        let mut heap = Vec::new();
        let q: &mut [f32] = if self.dim <= stack.len() {
            &mut stack[..self.dim]
        } else {
            heap.resize(self.dim, 0.0);
            &mut heap
        };
        normalise_into(query, q, || "the query".to_owned())?;
        let vectors = self.vectors()?;
        let ids = self.ids.as_slice();
        let dim = self.dim;
        let allowed = self.allowed_rows(filter);
        let total = allowed.as_ref().map_or(self.len(), Vec::len);
        let q: &[f32] = q;

        let scan_part = |part: Range<usize>| {
            let mut top = TopK::new(k.min(part.len()));
            match &allowed {
                None => kernel::scan(vectors, dim, ids, part, q, &mut top),
                Some(rows) => {
                    let rows = rows.get(part).unwrap_or(&[]).iter().map(|r| *r as usize);
                    kernel::scan(vectors, dim, ids, rows, q, &mut top);
                }
            }
            top
        };
        let threads = rayon::current_num_threads();
        let top = if total >= PREFILTER_ROWS
            && dim <= prefilter::MAX_DIM
            && k.saturating_mul(16) <= total
        {
            // Large index, small k: an 8-bit first pass, then exact rescoring of the rows
            // it cannot rule out; same result as the full scan below (see `prefilter`).
            let quant = self
                .quant
                .get_or_init(|| prefilter::Quantized::build(vectors, dim));
            let query = prefilter::Query::new(q);
            let first = |part: Range<usize>| match &allowed {
                None => prefilter::first_pass(quant, &query, part, k),
                Some(rows) => {
                    let rows = rows.get(part).unwrap_or(&[]).iter().map(|r| *r as usize);
                    prefilter::first_pass(quant, &query, rows, k)
                }
            };
            // The first pass reads a quarter of the bytes, so it splits later.
            let parts = if threads > 1 && total * dim >= 4 * PARALLEL_WORK {
                split(total, threads * 2, 4 * PARALLEL_WORK / dim)
                    .into_par_iter()
                    .map(first)
                    .collect()
            } else {
                vec![first(0..total)]
            };
            let rows = prefilter::survivors(parts, k);
            let mut top = TopK::new(k.min(total));
            kernel::scan(vectors, dim, ids, rows.into_iter(), q, &mut top);
            top
        } else if threads > 1 && total * dim >= PARALLEL_WORK {
            let parts = split(total, threads * 2, PARALLEL_WORK / dim);
            let tops: Vec<TopK> = parts.into_par_iter().map(scan_part).collect();
            let mut merged = TopK::new(k.min(total));
            for top in tops {
                merged.merge(top);
            }
            merged
        } else {
            scan_part(0..total)
        };
        let hits = top.into_sorted();
        Ok(Hits {
            queries: 1,
            k: hits.len(),
            ids: hits.iter().map(|h| h.id).collect(),
            scores: hits.iter().map(|h| h.score).collect(),
        })
    }

    /// `search` for each of the row-major `queries` (`queries.len() / dim` of them).
    ///
    /// Scores equal those of single searches bit for bit; the work is split over
    /// queries and rows, and rows are read in cache-sized tiles shared by many queries.
    pub fn search_batch(&self, queries: &[f32], k: usize, filter: &Filter<'_>) -> CoreResult<Hits> {
        Self::check_k(k)?;
        let dim = self.dim;
        if !queries.len().is_multiple_of(dim) {
            return Err(CoreError::InvalidArgument(format!(
                "the queries have {} values, not a whole number of vectors of dimension {dim}; \
                 embed them with the same model as the index",
                queries.len()
            )));
        }
        let m = queries.len() / dim;
        let mut normalised = vec![0.0f32; queries.len()];
        for (i, (dst, src)) in normalised
            .chunks_exact_mut(dim)
            .zip(queries.chunks_exact(dim))
            .enumerate()
        {
            normalise_into(src, dst, || format!("query {i}"))?;
        }
        let vectors = self.vectors()?;
        let ids = self.ids.as_slice();
        let allowed = self.allowed_rows(filter);
        let total = allowed.as_ref().map_or(self.len(), Vec::len);
        let kk = k.min(total);
        if m == 0 || kk == 0 {
            return Ok(Hits {
                queries: m,
                k: 0,
                ids: Vec::new(),
                scores: Vec::new(),
            });
        }
        let refs: Vec<&[f32]> = normalised.chunks_exact(dim).collect();
        let query_chunks: Vec<Range<usize>> = (0..m)
            .step_by(BATCH_QUERIES)
            .map(|s| s..(s + BATCH_QUERIES).min(m))
            .collect();
        let threads = rayon::current_num_threads();
        // Enough tasks to keep every thread busy; with few queries, split the rows too.
        let row_parts = if total * dim * m < PARALLEL_WORK {
            std::iter::once(0..total).collect()
        } else {
            let wanted = (threads * 2).div_ceil(query_chunks.len());
            split(total, wanted, (PARALLEL_WORK / dim).max(TILE_ROWS))
        };
        let tasks: Vec<(usize, Range<usize>)> = (0..query_chunks.len())
            .flat_map(|c| row_parts.iter().map(move |r| (c, r.clone())))
            .collect();
        let run = |(chunk, part): (usize, Range<usize>)| {
            let qrange = query_chunks.get(chunk).cloned().unwrap_or(0..0);
            let qs = refs.get(qrange).unwrap_or(&[]);
            let mut tops: Vec<TopK> = qs.iter().map(|_| TopK::new(kk)).collect();
            let mut start = part.start;
            while start < part.end {
                let end = (start + TILE_ROWS).min(part.end);
                match &allowed {
                    None => kernel::tile(vectors, dim, ids, start..end, qs, &mut tops),
                    Some(rows) => {
                        let rows = rows
                            .get(start..end)
                            .unwrap_or(&[])
                            .iter()
                            .map(|r| *r as usize);
                        kernel::tile(vectors, dim, ids, rows, qs, &mut tops);
                    }
                }
                start = end;
            }
            (chunk, tops)
        };
        let results: Vec<(usize, Vec<TopK>)> = if tasks.len() > 1 {
            tasks.into_par_iter().map(run).collect()
        } else {
            tasks.into_iter().map(run).collect()
        };
        let mut merged: Vec<TopK> = (0..m).map(|_| TopK::new(kk)).collect();
        for (chunk, tops) in results {
            let first = query_chunks.get(chunk).map_or(0, |r| r.start);
            for (i, top) in tops.into_iter().enumerate() {
                if let Some(slot) = merged.get_mut(first + i) {
                    slot.merge(top);
                }
            }
        }
        let mut out_ids = Vec::with_capacity(m * kk);
        let mut out_scores = Vec::with_capacity(m * kk);
        for top in merged {
            for hit in top.into_sorted() {
                out_ids.push(hit.id);
                out_scores.push(hit.score);
            }
        }
        Ok(Hits {
            queries: m,
            k: kk,
            ids: out_ids,
            scores: out_scores,
        })
    }

    /// Writes the index to `path` atomically (a temporary file, then a rename).
    pub fn save(&self, path: &Path) -> CoreResult<()> {
        let vectors = self.vectors()?;
        let quant = self
            .quant
            .get_or_init(|| prefilter::Quantized::build(vectors, self.dim));
        file::save(
            path,
            &file::Parts {
                dim: self.dim,
                vectors,
                ids: self.ids.as_slice(),
                kinds: self.kinds.as_slice(),
                sources: self.sources.as_slice(),
                kind_names: self.kind_names.names(),
                source_names: self.source_names.names(),
                codes: quant.codes(),
                steps: quant.steps(),
                errors: quant.errors(),
            },
        )
    }

    /// Opens a saved index, memory-mapped: see `file` for what is checked now and later.
    pub fn open(path: &Path) -> CoreResult<Self> {
        let opened = file::open(path)?;
        Ok(VectorIndex {
            dim: opened.dim,
            vectors: opened.vectors,
            ids: opened.ids,
            kinds: opened.kinds,
            sources: opened.sources,
            kind_names: opened.kind_names,
            source_names: opened.source_names,
            id_rows: OnceLock::new(),
            quant: OnceLock::from(prefilter::Quantized::from_columns(
                opened.dim,
                opened.codes,
                opened.steps,
                opened.errors,
            )),
            backing: Some(Backing {
                path: path.to_path_buf(),
                map: opened.map,
                lazy_blocks: opened.lazy_blocks,
                verified: OnceLock::new(),
            }),
        })
    }
}

/// Splits `0..total` into at most `parts` ranges of at least `min_len` (except when
/// `total` is smaller).
fn split(total: usize, parts: usize, min_len: usize) -> Vec<Range<usize>> {
    let parts = parts.min(total / min_len.max(1)).max(1);
    let size = total.div_ceil(parts);
    (0..parts)
        .map(|p| (p * size).min(total)..((p + 1) * size).min(total))
        .filter(|r| !r.is_empty())
        .collect()
}

#[cfg(test)]
mod tests;
