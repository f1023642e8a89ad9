//! The on-disk format of a vector index, version 1.
//!
//! One file, little-endian, every section aligned to 64 bytes (so the memory map can be
//! read as `f32`/`i64`/`u32` slices in place), zero padding between sections:
//!
//! ```text
//! offset  size  field
//!      0     8  magic "SWVINDEX"
//!      8     4  format version (1)
//!     12     4  header length (128)
//!     16     4  dimension
//!     20     4  log2 of the checksum block size (22: 4 MiB)
//!     24     8  number of rows
//!     32     8  file length
//!     40     8  length of the tag section
//!     48    40  offsets of the id, kind, source, vector and checksum sections
//!     88     8  xxh3-64 of the checksum section
//!     96    24  offsets of the code, step and error sections
//!    120     8  xxh3-64 of bytes 0..120
//!    128        tags: kinds then sources, each u32 count + (u32 length + UTF-8) per tag
//!               ids: i64 per row; kinds: u32 code per row; sources: u32 code per row
//!               vectors: dimension f32 per row, normalised
//!               codes: dimension i8 per row, steps: f32 per row, errors: f32 per row
//!               (the 8-bit copy single searches start with, see `prefilter`)
//!               checksums: xxh3-64 of each block of the payload (bytes 128 up to the
//!               checksum section, cut into blocks of the size above; the last is shorter)
//! ```
//!
//! What is checked when: opening reads and checks the header (magic, version, header
//! checksum), that the file length and every section offset equal the layout computed
//! from the row count, dimension and tag length (so truncation and foreign files are
//! caught before anything is mapped as data), the checksum table, and the checksums of
//! every block holding tags, ids or tag codes, then the tags and codes themselves. That
//! is a few MB even for a million rows, so opening stays cheap. The vectors and their
//! 8-bit copy (1.9 GB for a million 384-d rows) are verified on first use instead: once,
//! in parallel, before the first search, `get`, save or change reads them
//! (`VectorIndex::verify` forces it). Hashing them on open would read the whole file and
//! defeat the memory map; deferring it keeps opening cheap at the price of one pass on
//! first use, and corruption is still reported (with the offset of the bad block) before
//! any result is computed from it.
//!
//! The format does not protect against another program rewriting the file in place while
//! it is mapped. `save` never does that: it writes a temporary file and renames it, so a
//! mapped older version stays intact.

use std::fs::{self, File};
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use bytemuck::Pod;
use memmap2::Mmap;
use rayon::prelude::*;
use xxhash_rust::xxh3::{xxh3_64, Xxh3};

use super::column::Column;
use super::TagTable;
use crate::error::{CoreError, CoreResult};

pub(crate) const MAGIC: [u8; 8] = *b"SWVINDEX";
pub(crate) const VERSION: u32 = 1;
const HEADER_LEN: usize = 128;
const ALIGN: usize = 64;
const BLOCK_LOG2: u32 = 22;

/// A checksummed byte range of the file.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Block {
    offset: usize,
    len: usize,
    hash: u64,
}

/// What `save` writes.
pub(crate) struct Parts<'a> {
    pub(crate) dim: usize,
    pub(crate) vectors: &'a [f32],
    pub(crate) ids: &'a [i64],
    pub(crate) kinds: &'a [u32],
    pub(crate) sources: &'a [u32],
    pub(crate) kind_names: &'a [String],
    pub(crate) source_names: &'a [String],
    pub(crate) codes: &'a [i8],
    pub(crate) steps: &'a [f32],
    pub(crate) errors: &'a [f32],
}

/// What `open` returns: columns borrowed from the map, and the blocks left to verify.
pub(crate) struct Opened {
    pub(crate) dim: usize,
    pub(crate) vectors: Column<f32>,
    pub(crate) ids: Column<i64>,
    pub(crate) kinds: Column<u32>,
    pub(crate) sources: Column<u32>,
    pub(crate) kind_names: TagTable,
    pub(crate) source_names: TagTable,
    pub(crate) codes: Column<i8>,
    pub(crate) steps: Column<f32>,
    pub(crate) errors: Column<f32>,
    pub(crate) map: Arc<Mmap>,
    pub(crate) lazy_blocks: Vec<Block>,
}

#[derive(Debug, PartialEq, Eq)]
struct Layout {
    tags: Range<usize>,
    ids: Range<usize>,
    kinds: Range<usize>,
    sources: Range<usize>,
    vectors: Range<usize>,
    codes: Range<usize>,
    steps: Range<usize>,
    errors: Range<usize>,
    checksums: Range<usize>,
}

fn align(x: usize) -> Option<usize> {
    x.checked_add(ALIGN - 1).map(|v| v / ALIGN * ALIGN)
}

fn section(start: usize, len: usize) -> Option<Range<usize>> {
    let start = align(start)?;
    Some(start..start.checked_add(len)?)
}

fn block_count(payload: usize) -> usize {
    payload.div_ceil(1 << BLOCK_LOG2)
}

impl Layout {
    fn new(dim: usize, count: usize, tags_len: usize) -> Option<Layout> {
        let tags = section(HEADER_LEN, tags_len)?;
        let ids = section(tags.end, count.checked_mul(8)?)?;
        let kinds = section(ids.end, count.checked_mul(4)?)?;
        let sources = section(kinds.end, count.checked_mul(4)?)?;
        let vectors = section(sources.end, count.checked_mul(dim)?.checked_mul(4)?)?;
        let codes = section(vectors.end, count.checked_mul(dim)?)?;
        let steps = section(codes.end, count.checked_mul(4)?)?;
        let errors = section(steps.end, count.checked_mul(4)?)?;
        let payload_end = align(errors.end)?;
        let blocks = block_count(payload_end - HEADER_LEN);
        let checksums = payload_end..payload_end.checked_add(blocks.checked_mul(8)?)?;
        Some(Layout {
            tags,
            ids,
            kinds,
            sources,
            vectors,
            codes,
            steps,
            errors,
            checksums,
        })
    }

    fn blocks(&self) -> impl Iterator<Item = Range<usize>> + '_ {
        let size = 1usize << BLOCK_LOG2;
        (HEADER_LEN..self.checksums.start)
            .step_by(size)
            .map(move |s| s..(s + size).min(self.checksums.start))
    }
}

pub(crate) fn encode_tags(kinds: &[String], sources: &[String]) -> CoreResult<Vec<u8>> {
    let mut out = Vec::new();
    for names in [kinds, sources] {
        let count = u32::try_from(names.len())
            .map_err(|_| CoreError::InvalidArgument("too many distinct tags".into()))?;
        out.extend_from_slice(&count.to_le_bytes());
        for name in names {
            let len = u32::try_from(name.len())
                .map_err(|_| CoreError::InvalidArgument("tag too long".into()))?;
            out.extend_from_slice(&len.to_le_bytes());
            out.extend_from_slice(name.as_bytes());
        }
    }
    Ok(out)
}

/// Hashes everything written through it in blocks of `1 << BLOCK_LOG2` bytes.
struct BlockWriter<W: Write> {
    inner: W,
    hasher: Xxh3,
    in_block: usize,
    pos: usize,
    hashes: Vec<u64>,
}

impl<W: Write> BlockWriter<W> {
    fn write(&mut self, mut bytes: &[u8]) -> std::io::Result<()> {
        let size = 1usize << BLOCK_LOG2;
        while !bytes.is_empty() {
            let take = (size - self.in_block).min(bytes.len());
            let (now, rest) = bytes.split_at(take);
            self.inner.write_all(now)?;
            self.hasher.update(now);
            self.in_block += take;
            self.pos += take;
            if self.in_block == size {
                self.hashes.push(self.hasher.digest());
                self.hasher.reset();
                self.in_block = 0;
            }
            bytes = rest;
        }
        Ok(())
    }

    fn pad_to(&mut self, offset: usize) -> std::io::Result<()> {
        const ZEROS: [u8; ALIGN] = [0; ALIGN];
        while self.pos < offset {
            let n = (offset - self.pos).min(ALIGN);
            self.write(&ZEROS[..n])?;
        }
        Ok(())
    }

    fn write_values<T: Pod + LeValue>(&mut self, values: &[T]) -> std::io::Result<()> {
        if cfg!(target_endian = "little") {
            self.write(bytemuck::cast_slice(values))
        } else {
            let mut buffer = Vec::with_capacity(64 * 1024);
            for chunk in values.chunks(8 * 1024) {
                buffer.clear();
                for v in chunk {
                    buffer.extend_from_slice(bytemuck::bytes_of(&v.to_le()));
                }
                self.write(&buffer)?;
            }
            Ok(())
        }
    }

    fn finish(mut self) -> (W, Vec<u64>) {
        if self.in_block > 0 {
            self.hashes.push(self.hasher.digest());
        }
        (self.inner, self.hashes)
    }
}

/// Values stored little-endian in the file.
pub(crate) trait LeValue: Copy {
    fn to_le(self) -> Self;
}
impl LeValue for f32 {
    fn to_le(self) -> Self {
        f32::from_bits(self.to_bits().to_le())
    }
}
impl LeValue for i64 {
    fn to_le(self) -> Self {
        i64::to_le(self)
    }
}
impl LeValue for i8 {
    fn to_le(self) -> Self {
        self
    }
}
impl LeValue for u32 {
    fn to_le(self) -> Self {
        u32::to_le(self)
    }
}

fn header(
    dim: usize,
    count: usize,
    tags_len: usize,
    layout: &Layout,
    sums_hash: u64,
) -> [u8; HEADER_LEN] {
    let mut h = [0u8; HEADER_LEN];
    let mut put = |at: usize, bytes: &[u8]| {
        if let Some(slot) = h.get_mut(at..at + bytes.len()) {
            slot.copy_from_slice(bytes);
        }
    };
    put(0, &MAGIC);
    put(8, &VERSION.to_le_bytes());
    put(12, &(HEADER_LEN as u32).to_le_bytes());
    put(16, &(dim as u32).to_le_bytes());
    put(20, &BLOCK_LOG2.to_le_bytes());
    put(24, &(count as u64).to_le_bytes());
    put(32, &(layout.checksums.end as u64).to_le_bytes());
    put(40, &(tags_len as u64).to_le_bytes());
    put(48, &(layout.ids.start as u64).to_le_bytes());
    put(56, &(layout.kinds.start as u64).to_le_bytes());
    put(64, &(layout.sources.start as u64).to_le_bytes());
    put(72, &(layout.vectors.start as u64).to_le_bytes());
    put(80, &(layout.checksums.start as u64).to_le_bytes());
    put(88, &sums_hash.to_le_bytes());
    put(96, &(layout.codes.start as u64).to_le_bytes());
    put(104, &(layout.steps.start as u64).to_le_bytes());
    put(112, &(layout.errors.start as u64).to_le_bytes());
    let hash = xxh3_64(h.get(..120).unwrap_or(&[]));
    if let Some(slot) = h.get_mut(120..128) {
        slot.copy_from_slice(&hash.to_le_bytes());
    }
    h
}

fn temp_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(format!(".tmp-{}", std::process::id()));
    path.with_file_name(name)
}

/// Writes `parts` to `path` through a temporary file in the same folder and a rename,
/// so a reader never sees a partial file.
pub(crate) fn save(path: &Path, parts: &Parts<'_>) -> CoreResult<()> {
    let tags = encode_tags(parts.kind_names, parts.source_names)?;
    let count = parts.ids.len();
    let layout = Layout::new(parts.dim, count, tags.len())
        .ok_or_else(|| CoreError::InvalidArgument("the index is too large to save".into()))?;
    let tmp = temp_path(path);
    let written = write_file(&tmp, parts, &tags, &layout)
        .and_then(|()| fs::rename(&tmp, path).map_err(|e| CoreError::io(path, e)));
    if written.is_err() {
        // Best effort: the temporary file is ours and useless now.
        let _ = fs::remove_file(&tmp);
    }
    written
}

fn write_file(tmp: &Path, parts: &Parts<'_>, tags: &[u8], layout: &Layout) -> CoreResult<()> {
    let io = |e| CoreError::io(tmp, e);
    let file = File::create(tmp).map_err(io)?;
    let mut out = BufWriter::with_capacity(1 << 20, file);
    out.write_all(&[0u8; HEADER_LEN]).map_err(io)?;
    let mut w = BlockWriter {
        inner: out,
        hasher: Xxh3::new(),
        in_block: 0,
        pos: HEADER_LEN,
        hashes: Vec::new(),
    };
    w.write(tags).map_err(io)?;
    w.pad_to(layout.ids.start).map_err(io)?;
    w.write_values(parts.ids).map_err(io)?;
    w.pad_to(layout.kinds.start).map_err(io)?;
    w.write_values(parts.kinds).map_err(io)?;
    w.pad_to(layout.sources.start).map_err(io)?;
    w.write_values(parts.sources).map_err(io)?;
    w.pad_to(layout.vectors.start).map_err(io)?;
    w.write_values(parts.vectors).map_err(io)?;
    w.pad_to(layout.codes.start).map_err(io)?;
    w.write_values(parts.codes).map_err(io)?;
    w.pad_to(layout.steps.start).map_err(io)?;
    w.write_values(parts.steps).map_err(io)?;
    w.pad_to(layout.errors.start).map_err(io)?;
    w.write_values(parts.errors).map_err(io)?;
    w.pad_to(layout.checksums.start).map_err(io)?;
    let (mut out, hashes) = w.finish();
    let sums: Vec<u8> = hashes.iter().flat_map(|h| h.to_le_bytes()).collect();
    out.write_all(&sums).map_err(io)?;
    let head = header(
        parts.dim,
        parts.ids.len(),
        tags.len(),
        layout,
        xxh3_64(&sums),
    );
    let mut file = out.into_inner().map_err(|e| io(e.into_error()))?;
    file.seek(SeekFrom::Start(0)).map_err(io)?;
    file.write_all(&head).map_err(io)?;
    file.sync_all().map_err(io)?;
    Ok(())
}

#[allow(unsafe_code)]
fn map_file(file: &File, path: &Path) -> CoreResult<Mmap> {
    // SAFETY: the map is only read. It stays valid as long as no one truncates or
    // rewrites this file in place; skillwright replaces index files by rename (see the
    // module documentation), which leaves an existing map of the old file intact.
    unsafe { Mmap::map(file) }.map_err(|e| CoreError::io(path, e))
}

fn u32_at(bytes: &[u8], at: usize) -> u32 {
    let mut b = [0u8; 4];
    if let Some(s) = bytes.get(at..at + 4) {
        b.copy_from_slice(s);
    }
    u32::from_le_bytes(b)
}

fn u64_at(bytes: &[u8], at: usize) -> u64 {
    let mut b = [0u8; 8];
    if let Some(s) = bytes.get(at..at + 8) {
        b.copy_from_slice(s);
    }
    u64::from_le_bytes(b)
}

fn column<T: Pod + LeValue>(map: &Arc<Mmap>, range: &Range<usize>) -> Column<T> {
    let len = range.len() / size_of::<T>();
    if cfg!(target_endian = "little") {
        Column::Mapped {
            map: Arc::clone(map),
            start: range.start,
            len,
        }
    } else {
        let bytes = map.get(range.clone()).unwrap_or(&[]);
        Column::Owned(
            bytes
                .chunks_exact(size_of::<T>())
                .map(|c| bytemuck::pod_read_unaligned::<T>(c).to_le())
                .collect(),
        )
    }
}

/// Checks `blocks` against their checksums, in parallel; the error holds the offset of
/// the first bad block.
pub(crate) fn verify_blocks(map: &Mmap, blocks: &[Block]) -> Result<(), (u64, String)> {
    let bad = blocks.par_iter().find_first(|b| {
        map.get(b.offset..b.offset + b.len)
            .is_none_or(|bytes| xxh3_64(bytes) != b.hash)
    });
    match bad {
        None => Ok(()),
        Some(b) => Err((
            b.offset as u64,
            format!(
                "checksum mismatch in bytes {}..{}: the file is corrupt; rebuild the index \
                 or restore the file",
                b.offset,
                b.offset + b.len
            ),
        )),
    }
}

fn parse_tags(bytes: &[u8], base: usize) -> Result<(TagTable, TagTable), (u64, String)> {
    let mut at = 0usize;
    let mut tables = Vec::with_capacity(2);
    for what in ["kind", "source"] {
        let bad = |at: usize, m: String| ((base + at) as u64, m);
        if at + 4 > bytes.len() {
            return Err(bad(at, format!("{what} tag table is cut short")));
        }
        let count = u32_at(bytes, at) as usize;
        at += 4;
        let mut names = Vec::with_capacity(count.min(1 << 16));
        for _ in 0..count {
            if at + 4 > bytes.len() {
                return Err(bad(at, format!("{what} tag table is cut short")));
            }
            let len = u32_at(bytes, at) as usize;
            at += 4;
            let text = bytes
                .get(at..at.saturating_add(len))
                .ok_or_else(|| bad(at, format!("{what} tag runs past its section")))?;
            let name = std::str::from_utf8(text)
                .map_err(|_| bad(at, format!("{what} tag is not valid UTF-8")))?;
            names.push(name.to_owned());
            at += len;
        }
        let table = TagTable::from_names(names)
            .ok_or_else(|| bad(at, format!("{what} tag table repeats a tag")))?;
        tables.push(table);
    }
    if at != bytes.len() {
        return Err((
            (base + at) as u64,
            "unexpected bytes after the tag tables".into(),
        ));
    }
    let sources = tables.pop().unwrap_or_default();
    let kinds = tables.pop().unwrap_or_default();
    Ok((kinds, sources))
}

/// Opens and checks a saved index (see the module documentation for what is checked).
pub(crate) fn open(path: &Path) -> CoreResult<Opened> {
    let fail = |offset: u64, message: String| CoreError::Format {
        path: path.to_path_buf(),
        offset,
        message,
    };
    let file = File::open(path).map_err(|e| CoreError::io(path, e))?;
    let meta = file.metadata().map_err(|e| CoreError::io(path, e))?;
    if meta.is_dir() {
        return Err(CoreError::InvalidArgument(format!(
            "{}: is a folder, expected a vector index file",
            path.display()
        )));
    }
    let file_len = meta.len();
    if file_len < HEADER_LEN as u64 {
        return Err(fail(
            file_len,
            format!(
                "only {file_len} bytes, too short for a skillwright vector index \
                 (its header alone is {HEADER_LEN} bytes); the file is truncated or not an index"
            ),
        ));
    }
    let map = Arc::new(map_file(&file, path)?);
    let head = map.get(..HEADER_LEN).unwrap_or(&[]);
    if head.get(..8) != Some(&MAGIC[..]) {
        return Err(fail(
            0,
            "not a skillwright vector index (wrong magic bytes); give the path of a file \
             written by VectorIndex.save"
                .into(),
        ));
    }
    let version = u32_at(head, 8);
    if version != VERSION {
        return Err(fail(
            8,
            format!(
                "index format version {version} is not supported (this skillwright reads \
                 version {VERSION}); rebuild the index with this version"
            ),
        ));
    }
    if xxh3_64(head.get(..120).unwrap_or(&[])) != u64_at(head, 120) {
        return Err(fail(
            120,
            "header checksum mismatch: the file is corrupt".into(),
        ));
    }
    let dim = u32_at(head, 16) as usize;
    let count = u64_at(head, 24);
    let tags_len = u64_at(head, 40);
    if u32_at(head, 12) as usize != HEADER_LEN || u32_at(head, 20) != BLOCK_LOG2 {
        return Err(fail(12, "unexpected header or block size".into()));
    }
    if dim == 0 || dim > super::MAX_DIM {
        return Err(fail(16, format!("dimension {dim} is out of range")));
    }
    let layout = usize::try_from(count)
        .ok()
        .zip(usize::try_from(tags_len).ok())
        .and_then(|(count, tags_len)| Layout::new(dim, count, tags_len))
        .ok_or_else(|| fail(24, "row count or tag length out of range".into()))?;
    let declared_len = u64_at(head, 32);
    if declared_len != layout.checksums.end as u64 {
        return Err(fail(
            32,
            "file length field does not match the layout".into(),
        ));
    }
    if file_len != declared_len {
        let what = if file_len < declared_len {
            "truncated"
        } else {
            "longer than its header says (trailing bytes)"
        };
        return Err(fail(
            file_len.min(declared_len),
            format!("the file is {what}: header says {declared_len} bytes, file has {file_len}"),
        ));
    }
    for (at, expected) in [
        (48, layout.ids.start),
        (56, layout.kinds.start),
        (64, layout.sources.start),
        (72, layout.vectors.start),
        (80, layout.checksums.start),
        (96, layout.codes.start),
        (104, layout.steps.start),
        (112, layout.errors.start),
    ] {
        if u64_at(head, at) != expected as u64 {
            return Err(fail(
                at as u64,
                "section offset does not match the layout".into(),
            ));
        }
    }
    let sums = map.get(layout.checksums.clone()).unwrap_or(&[]);
    if xxh3_64(sums) != u64_at(head, 88) {
        return Err(fail(
            layout.checksums.start as u64,
            "checksum table is corrupt".into(),
        ));
    }
    let blocks: Vec<Block> = layout
        .blocks()
        .zip(sums.chunks_exact(8))
        .map(|(r, h)| Block {
            offset: r.start,
            len: r.len(),
            hash: u64_at(h, 0),
        })
        .collect();
    // Blocks that hold anything before the vectors are checked now; the rest lazily.
    let (now, later): (Vec<Block>, Vec<Block>) = blocks
        .into_iter()
        .partition(|b| b.offset < layout.vectors.start);
    verify_blocks(&map, &now).map_err(|(offset, message)| fail(offset, message))?;

    let tag_bytes = map.get(layout.tags.clone()).unwrap_or(&[]);
    let (kind_names, source_names) =
        parse_tags(tag_bytes, layout.tags.start).map_err(|(o, m)| fail(o, m))?;
    let ids = column::<i64>(&map, &layout.ids);
    let kinds = column::<u32>(&map, &layout.kinds);
    let sources = column::<u32>(&map, &layout.sources);
    for (col, names, range, what) in [
        (&kinds, kind_names.names().len(), &layout.kinds, "kind"),
        (
            &sources,
            source_names.names().len(),
            &layout.sources,
            "source",
        ),
    ] {
        if let Some(row) = col.as_slice().iter().position(|c| *c as usize >= names) {
            return Err(fail(
                (range.start + row * 4) as u64,
                format!("row {row} refers to a {what} tag that does not exist"),
            ));
        }
    }
    Ok(Opened {
        dim,
        vectors: column::<f32>(&map, &layout.vectors),
        ids,
        kinds,
        sources,
        kind_names,
        source_names,
        codes: column::<i8>(&map, &layout.codes),
        steps: column::<f32>(&map, &layout.steps),
        errors: column::<f32>(&map, &layout.errors),
        map,
        lazy_blocks: later,
    })
}

/// (start of ids, start of vectors) for an index of this shape; for the tests of the
/// parent module, which corrupt chosen bytes.
#[cfg(test)]
pub(crate) fn file_layout(dim: usize, count: usize, tags_len: usize) -> (usize, usize) {
    Layout::new(dim, count, tags_len).map_or((0, 0), |l| (l.ids.start, l.vectors.start))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_aligns_every_section() {
        let layout = Layout::new(384, 1000, 37).unwrap_or_else(|| unreachable!());
        for r in [
            &layout.tags,
            &layout.ids,
            &layout.kinds,
            &layout.sources,
            &layout.vectors,
            &layout.codes,
            &layout.steps,
            &layout.errors,
            &layout.checksums,
        ] {
            assert_eq!(r.start % ALIGN, 0);
        }
        assert_eq!(layout.vectors.len(), 1000 * 384 * 4);
    }

    #[test]
    fn layout_of_absurd_sizes_is_refused() {
        assert!(Layout::new(65536, usize::MAX / 8, 0).is_none());
    }

    #[test]
    fn blocks_cover_the_payload_exactly() {
        let layout = Layout::new(384, 20_000, 10).unwrap_or_else(|| unreachable!());
        let blocks: Vec<Range<usize>> = layout.blocks().collect();
        assert_eq!(
            blocks.len(),
            block_count(layout.checksums.start - HEADER_LEN)
        );
        assert_eq!(blocks.first().map(|b| b.start), Some(HEADER_LEN));
        assert_eq!(blocks.last().map(|b| b.end), Some(layout.checksums.start));
        assert_eq!(layout.checksums.len(), blocks.len() * 8);
    }
}
