//! The summary path and the scan path behind [`super::read_mcap`].

use std::borrow::Cow;
use std::collections::{BTreeMap, BTreeSet};
use std::fs::File;
use std::io::{self, BufReader, Read, Seek, SeekFrom};
use std::path::Path;

use super::records::{
    op, usize_from, Channel, ChunkHeader, ChunkIndex, DecodeError, Footer, Header, MessageHeader,
    MessageIndex, Schema, Statistics, MAGIC, RECORD_PREFIX_LEN,
};
use super::{ChannelInfo, Damage, McapSummary, ReadMethod, ReadMode};
use crate::error::{CoreError, CoreResult};

/// Largest uncompressed chunk we agree to inflate; a larger declared size is treated as
/// damage rather than trusted with an allocation.
const MAX_UNCOMPRESSED_CHUNK: u64 = 4 << 30;

/// How much of a chunk body we read to decode its header (the compression name is short).
const CHUNK_HEADER_PREFIX: u64 = 1024;

/// Footer record (prefix + body) plus the closing magic.
const FOOTER_AND_MAGIC: u64 = RECORD_PREFIX_LEN + Footer::BODY_LEN + 8;

pub(super) fn read(path: &Path, mode: ReadMode) -> CoreResult<McapSummary> {
    let mut input = Input::open(path)?;
    let size = input.size;
    if size == 0 {
        return Err(input.format_error(0, "empty file: not an MCAP recording"));
    }
    let mut magic = [0u8; 8];
    let head = input.read_prefix(0, &mut magic)?;
    if head < 8 && magic[..head] == MAGIC[..head] {
        return Err(input.format_error(
            head as u64,
            "file ends inside the MCAP magic: too short to hold any record",
        ));
    }
    if &magic != MAGIC {
        return Err(input.format_error(
            0,
            "not an MCAP file (it does not start with the MCAP magic bytes); \
             give an .mcap file or a rosbag2 folder recorded with MCAP storage",
        ));
    }

    let mut acc = Accumulator::new(path, size);
    read_header(&mut input, &mut acc)?;
    if mode == ReadMode::Auto {
        match read_summary(&mut input)? {
            SummaryOutcome::Complete(summary) => return Ok(acc.finish_from_summary(*summary)),
            SummaryOutcome::Unusable(reason) => acc.notes.push(reason),
        }
    }
    let method = if mode == ReadMode::Full {
        ReadMethod::Full
    } else {
        ReadMethod::Scan
    };
    let mut scanner = Scanner {
        input: &mut input,
        acc: &mut acc,
        use_indexes: method == ReadMethod::Scan,
    };
    scanner.scan()?;
    Ok(acc.finish(method))
}

/// Buffered positioned reading with a known file size.
pub(super) struct Input {
    path: std::path::PathBuf,
    reader: BufReader<File>,
    position: u64,
    pub(super) size: u64,
}

impl Input {
    pub(super) fn open(path: &Path) -> CoreResult<Self> {
        let file = File::open(path).map_err(|e| CoreError::io(path, e))?;
        let meta = file.metadata().map_err(|e| CoreError::io(path, e))?;
        if meta.is_dir() {
            return Err(CoreError::InvalidArgument(format!(
                "{}: is a folder, expected an .mcap file",
                path.display()
            )));
        }
        Ok(Self {
            path: path.to_path_buf(),
            reader: BufReader::with_capacity(1 << 16, file),
            position: 0,
            size: meta.len(),
        })
    }

    fn io_error(&self, error: io::Error) -> CoreError {
        CoreError::io(&self.path, error)
    }

    pub(super) fn format_error(&self, offset: u64, message: &str) -> CoreError {
        CoreError::Format {
            path: self.path.clone(),
            offset,
            message: message.to_string(),
        }
    }

    fn seek(&mut self, to: u64) -> CoreResult<()> {
        if to == self.position {
            return Ok(());
        }
        // Short forward and backward moves stay inside BufReader's buffer.
        let delta = i64::try_from(i128::from(to) - i128::from(self.position));
        match delta {
            Ok(delta) if delta.unsigned_abs() < (1 << 16) => self
                .reader
                .seek_relative(delta)
                .map_err(|e| self.io_error(e))?,
            _ => {
                self.reader
                    .seek(SeekFrom::Start(to))
                    .map_err(|e| self.io_error(e))?;
            }
        }
        self.position = to;
        Ok(())
    }

    /// Reads `len` bytes at `offset`; the caller has checked they lie inside the file.
    pub(super) fn read_at(&mut self, offset: u64, len: u64) -> CoreResult<Vec<u8>> {
        self.seek(offset)?;
        let mut out = vec![0u8; usize_from(len)];
        self.reader
            .read_exact(&mut out)
            .map_err(|e| self.io_error(e))?;
        self.position = offset + len;
        Ok(out)
    }

    /// Reads up to `out.len()` bytes at `offset`, returning how many were available.
    fn read_prefix(&mut self, offset: u64, out: &mut [u8]) -> CoreResult<usize> {
        let available = self.size.saturating_sub(offset).min(out.len() as u64);
        let bytes = self.read_at(offset, available)?;
        out[..bytes.len()].copy_from_slice(&bytes);
        Ok(bytes.len())
    }

    /// Reads the 9-byte record prefix at `offset`: opcode and body length. `None` when
    /// the file ends first.
    pub(super) fn record_prefix(&mut self, offset: u64) -> CoreResult<Option<(u8, u64)>> {
        if self.size.saturating_sub(offset) < RECORD_PREFIX_LEN {
            return Ok(None);
        }
        let bytes = self.read_at(offset, RECORD_PREFIX_LEN)?;
        let mut len = [0u8; 8];
        len.copy_from_slice(&bytes[1..9]);
        Ok(Some((bytes[0], u64::from_le_bytes(len))))
    }
}

/// What is being gathered, whichever path fills it.
struct Accumulator {
    summary: McapSummary,
    schemas: BTreeMap<u16, Schema>,
    channels: BTreeMap<u16, ChannelInfo>,
    /// Counts and times of messages seen for channel ids, known or not (yet).
    traffic: BTreeMap<u16, Traffic>,
    compressions: BTreeSet<String>,
    notes: Vec<String>,
}

#[derive(Default, Clone, Copy)]
struct Traffic {
    count: u64,
    first: Option<u64>,
    last: Option<u64>,
}

impl Traffic {
    fn add(&mut self, count: u64, first: u64, last: u64) {
        self.count += count;
        self.first = Some(self.first.map_or(first, |t| t.min(first)));
        self.last = Some(self.last.map_or(last, |t| t.max(last)));
    }
}

impl Accumulator {
    fn new(path: &Path, size: u64) -> Self {
        Self {
            summary: McapSummary {
                path: path.to_path_buf(),
                file_size: size,
                profile: None,
                library: None,
                method: ReadMethod::Scan,
                schemas: Vec::new(),
                channels: Vec::new(),
                message_count: 0,
                message_start_time: None,
                message_end_time: None,
                attachment_count: 0,
                metadata_count: 0,
                chunk_count: 0,
                compressions: Vec::new(),
                orphan_message_count: 0,
                stopped: None,
                damaged: Vec::new(),
                notes: Vec::new(),
            },
            schemas: BTreeMap::new(),
            channels: BTreeMap::new(),
            traffic: BTreeMap::new(),
            compressions: BTreeSet::new(),
            notes: Vec::new(),
        }
    }

    fn add_schema(&mut self, schema: Schema) {
        // id 0 means "no schema" and must not be defined; first definition wins.
        if schema.id != 0 {
            self.schemas.entry(schema.id).or_insert(schema);
        }
    }

    fn add_channel(&mut self, channel: Channel) {
        self.channels.entry(channel.id).or_insert(ChannelInfo {
            id: channel.id,
            schema_id: channel.schema_id,
            topic: channel.topic,
            message_encoding: channel.message_encoding,
            metadata: channel.metadata,
            message_count: 0,
            first_log_time: None,
            last_log_time: None,
            times_exact: true,
        });
    }

    fn add_messages(&mut self, channel_id: u16, count: u64, first: u64, last: u64) {
        self.traffic
            .entry(channel_id)
            .or_default()
            .add(count, first, last);
    }

    fn damaged(&mut self, offset: u64, message: String) {
        self.summary.damaged.push(Damage { offset, message });
    }

    fn finish(mut self, method: ReadMethod) -> McapSummary {
        let mut total = Traffic::default();
        for (id, traffic) in &self.traffic {
            if let (Some(first), Some(last)) = (traffic.first, traffic.last) {
                total.add(traffic.count, first, last);
            }
            match self.channels.get_mut(id) {
                Some(channel) => {
                    channel.message_count = traffic.count;
                    channel.first_log_time = traffic.first;
                    channel.last_log_time = traffic.last;
                }
                None => self.summary.orphan_message_count += traffic.count,
            }
        }
        if self.summary.orphan_message_count > 0 {
            self.notes.push(format!(
                "{} messages belong to channels whose definition is missing from the \
                 readable part of the file; they are counted in the total only",
                self.summary.orphan_message_count
            ));
        }
        self.summary.message_count = total.count;
        self.summary.message_start_time = total.first;
        self.summary.message_end_time = total.last;
        self.summary.method = method;
        self.summary.schemas = self.schemas.into_values().collect();
        self.summary.channels = self.channels.into_values().collect();
        self.summary.compressions = self.compressions.into_iter().collect();
        self.summary.notes = self.notes;
        self.summary
    }

    fn finish_from_summary(mut self, summary: SummarySection) -> McapSummary {
        let stats = summary.statistics;
        for schema in summary.schemas {
            self.add_schema(schema);
        }
        for channel in summary.channels {
            self.add_channel(channel);
        }
        // Per-channel times are not in the summary; each chunk index bounds the times
        // of the channels it indexes.
        let mut bounds: BTreeMap<u16, (u64, u64)> = BTreeMap::new();
        for index in &summary.chunk_indexes {
            self.compressions.insert(index.compression.clone());
            for id in index.message_index_offsets.keys() {
                let entry = bounds
                    .entry(*id)
                    .or_insert((index.message_start_time, index.message_end_time));
                entry.0 = entry.0.min(index.message_start_time);
                entry.1 = entry.1.max(index.message_end_time);
            }
        }
        for channel in self.channels.values_mut() {
            channel.message_count = stats
                .channel_message_counts
                .get(&channel.id)
                .copied()
                .unwrap_or(0);
            channel.times_exact = false;
            if channel.message_count > 0 {
                if let Some((first, last)) = bounds.get(&channel.id) {
                    channel.first_log_time = Some(*first);
                    channel.last_log_time = Some(*last);
                }
            }
        }
        let known: u64 = self.channels.values().map(|c| c.message_count).sum();
        self.summary.orphan_message_count = stats.message_count.saturating_sub(known);
        let has_messages = stats.message_count > 0;
        self.summary.method = ReadMethod::Summary;
        self.summary.message_count = stats.message_count;
        self.summary.message_start_time = has_messages.then_some(stats.message_start_time);
        self.summary.message_end_time = has_messages.then_some(stats.message_end_time);
        self.summary.attachment_count = u64::from(stats.attachment_count);
        self.summary.metadata_count = u64::from(stats.metadata_count);
        self.summary.chunk_count = u64::from(stats.chunk_count);
        self.summary.schemas = self.schemas.into_values().collect();
        self.summary.channels = self.channels.into_values().collect();
        self.summary.compressions = self.compressions.into_iter().collect();
        self.summary.notes = self.notes;
        self.summary
    }
}

fn read_header(input: &mut Input, acc: &mut Accumulator) -> CoreResult<()> {
    if let Some((op::HEADER, len)) = input.record_prefix(8)? {
        if len <= input.size.saturating_sub(8 + RECORD_PREFIX_LEN) {
            let body = input.read_at(8 + RECORD_PREFIX_LEN, len)?;
            if let Ok(header) = Header::decode(&body) {
                acc.summary.profile = Some(header.profile);
                acc.summary.library = Some(header.library);
            }
        }
    }
    Ok(())
}

struct SummarySection {
    schemas: Vec<Schema>,
    channels: Vec<Channel>,
    statistics: Statistics,
    chunk_indexes: Vec<ChunkIndex>,
}

enum SummaryOutcome {
    Complete(Box<SummarySection>),
    /// Why the scan path is needed.
    Unusable(String),
}

fn read_summary(input: &mut Input) -> CoreResult<SummaryOutcome> {
    use SummaryOutcome::Unusable;
    let size = input.size;
    let closed = "the file was not closed cleanly (recorder stopped early?)";
    if size < 8 + FOOTER_AND_MAGIC {
        return Ok(Unusable(format!("no footer: {closed}")));
    }
    let footer_offset = size - FOOTER_AND_MAGIC;
    let tail = input.read_at(footer_offset, FOOTER_AND_MAGIC)?;
    let prefix_ok = tail[0] == op::FOOTER && tail[1..9] == Footer::BODY_LEN.to_le_bytes();
    if !prefix_ok || &tail[29..37] != MAGIC {
        return Ok(Unusable(format!("no footer: {closed}")));
    }
    let footer = match Footer::decode(&tail[9..29]) {
        Ok(footer) => footer,
        Err(e) => return Ok(Unusable(format!("unreadable footer: {}", e.message))),
    };
    if footer.summary_start == 0 {
        return Ok(Unusable("the file has no summary section".to_string()));
    }
    if footer.summary_start < 8 || footer.summary_start > footer_offset {
        return Ok(Unusable(format!(
            "the footer points at a summary outside the file (byte {})",
            footer.summary_start
        )));
    }
    // The summary starts right after the data end record. Checking that record first
    // keeps a corrupt summary_start from making us load most of the file as "summary".
    let data_end_len = RECORD_PREFIX_LEN + 4;
    let data_end_ok = footer.summary_start >= 8 + data_end_len
        && input.record_prefix(footer.summary_start - data_end_len)? == Some((op::DATA_END, 4));
    if !data_end_ok {
        return Ok(Unusable(format!(
            "the footer's summary offset (byte {}) does not follow a data end record",
            footer.summary_start
        )));
    }
    let section = input.read_at(footer.summary_start, footer_offset - footer.summary_start)?;
    if footer.summary_crc != 0 {
        let mut hasher = crc32fast::Hasher::new();
        hasher.update(&section);
        hasher.update(&tail[..25]);
        if hasher.finalize() != footer.summary_crc {
            return Ok(Unusable(
                "the summary section fails its CRC check".to_string(),
            ));
        }
    }

    let mut schemas = Vec::new();
    let mut channels = Vec::new();
    let mut statistics = None;
    let mut chunk_indexes = Vec::new();
    let mut position = 0usize;
    while position < section.len() {
        let offset = footer.summary_start + position as u64;
        let Some((opcode, body)) = split_record(&section[position..]) else {
            return Ok(Unusable(format!("broken summary record at byte {offset}")));
        };
        position += RECORD_PREFIX_LEN as usize + body.len();
        let decoded: Result<(), DecodeError> = match opcode {
            op::SCHEMA => Schema::decode(body).map(|s| schemas.push(s)),
            op::CHANNEL => Channel::decode(body).map(|c| channels.push(c)),
            op::STATISTICS => Statistics::decode(body).map(|s| statistics = Some(s)),
            op::CHUNK_INDEX => ChunkIndex::decode(body).map(|c| chunk_indexes.push(c)),
            _ => Ok(()),
        };
        if let Err(e) = decoded {
            return Ok(Unusable(format!(
                "unreadable summary record at byte {offset}: {}",
                e.message
            )));
        }
    }
    let Some(statistics) = statistics else {
        return Ok(Unusable("the summary has no statistics record".to_string()));
    };
    let schema_ids: BTreeSet<u16> = schemas.iter().map(|s| s.id).filter(|id| *id != 0).collect();
    let channel_ids: BTreeSet<u16> = channels.iter().map(|c| c.id).collect();
    // Statistics count what the data section holds; some writers (rosbag2's) repeat
    // more in the summary, e.g. channels that never carried a message.
    if schema_ids.len() < usize::from(statistics.schema_count)
        || (channel_ids.len() as u64) < u64::from(statistics.channel_count)
    {
        return Ok(Unusable(
            "the summary does not repeat every schema and channel".to_string(),
        ));
    }
    Ok(SummaryOutcome::Complete(Box::new(SummarySection {
        schemas,
        channels,
        statistics,
        chunk_indexes,
    })))
}

/// Splits one record off the front of an in-memory buffer: opcode and body. `None`
/// when the buffer ends inside it.
pub(super) fn split_record(bytes: &[u8]) -> Option<(u8, &[u8])> {
    let prefix = bytes.get(..RECORD_PREFIX_LEN as usize)?;
    let mut len = [0u8; 8];
    len.copy_from_slice(&prefix[1..9]);
    let len = usize::try_from(u64::from_le_bytes(len)).ok()?;
    let start = RECORD_PREFIX_LEN as usize;
    let body = bytes.get(start..start.checked_add(len)?)?;
    Some((prefix[0], body))
}

struct Scanner<'a> {
    input: &'a mut Input,
    acc: &'a mut Accumulator,
    use_indexes: bool,
}

impl Scanner<'_> {
    fn scan(&mut self) -> CoreResult<()> {
        let size = self.input.size;
        let mut offset = 8u64;
        loop {
            if offset == size {
                self.stop(
                    offset,
                    "the file ends without a footer: the recording was not closed",
                );
                return Ok(());
            }
            let Some((opcode, len)) = self.input.record_prefix(offset)? else {
                self.stop(offset, "the file ends inside a record header");
                return Ok(());
            };
            let body_offset = offset + RECORD_PREFIX_LEN;
            let available = size - body_offset;
            if len > available {
                let cut = format!(
                    "record (opcode 0x{opcode:02x}) claims {len} bytes but only \
                     {available} remain: the file is cut short or damaged here"
                );
                if opcode == op::CHUNK {
                    self.cut_chunk(offset, available, &cut)?;
                } else {
                    self.stop(offset, &cut);
                }
                return Ok(());
            }
            let next = body_offset + len;
            match opcode {
                op::FOOTER => {
                    let mut magic = [0u8; 8];
                    let read = self.input.read_prefix(next, &mut magic)?;
                    if read < 8 || &magic != MAGIC {
                        self.stop(
                            next,
                            "the closing magic after the footer is missing or damaged: \
                             the file is cut short or was altered",
                        );
                    }
                    return Ok(());
                }
                op::HEADER => {}
                op::SCHEMA => {
                    let body = self.input.read_at(body_offset, len)?;
                    match Schema::decode(&body) {
                        Ok(schema) => self.acc.add_schema(schema),
                        Err(e) => self.damaged_record(body_offset, "schema", &e),
                    }
                }
                op::CHANNEL => {
                    let body = self.input.read_at(body_offset, len)?;
                    match Channel::decode(&body) {
                        Ok(channel) => self.acc.add_channel(channel),
                        Err(e) => self.damaged_record(body_offset, "channel", &e),
                    }
                }
                op::MESSAGE => {
                    let body = self
                        .input
                        .read_at(body_offset, len.min(MessageHeader::LEN))?;
                    match MessageHeader::decode(&body) {
                        Ok(m) => self
                            .acc
                            .add_messages(m.channel_id, 1, m.log_time, m.log_time),
                        Err(e) => self.damaged_record(body_offset, "message", &e),
                    }
                }
                op::CHUNK => {
                    let resume = self.chunk(offset, len)?;
                    offset = resume;
                    continue;
                }
                op::ATTACHMENT => self.acc.summary.attachment_count += 1,
                op::METADATA => self.acc.summary.metadata_count += 1,
                _ => {}
            }
            offset = next;
        }
    }

    fn stop(&mut self, offset: u64, message: &str) {
        self.acc.summary.stopped = Some(Damage {
            offset,
            message: message.to_string(),
        });
    }

    fn damaged_record(&mut self, body_offset: u64, what: &str, e: &DecodeError) {
        self.acc.damaged(
            body_offset + e.position as u64,
            format!("damaged {what} record skipped: {}", e.message),
        );
    }

    /// Reads the chunk whose record starts at `offset`, and the message indexes after
    /// it; returns where reading goes on.
    fn chunk(&mut self, offset: u64, len: u64) -> CoreResult<u64> {
        let body_offset = offset + RECORD_PREFIX_LEN;
        let next = body_offset + len;
        let prefix = self
            .input
            .read_at(body_offset, len.min(CHUNK_HEADER_PREFIX))?;
        let header = match ChunkHeader::decode(&prefix) {
            Ok(header) if header.compressed_size <= len - header.header_len => header,
            Ok(header) => {
                self.acc.damaged(
                    offset,
                    format!(
                        "damaged chunk skipped: it claims {} compressed bytes in a record of {len}",
                        header.compressed_size
                    ),
                );
                return Ok(next);
            }
            Err(e) => {
                self.damaged_record(body_offset, "chunk", &e);
                return Ok(next);
            }
        };
        self.acc.summary.chunk_count += 1;
        self.acc.compressions.insert(header.compression.clone());

        if self.use_indexes {
            let (indexes, after) = self.message_indexes(next)?;
            if let Some(indexes) = indexes {
                if self.indexes_suffice(&indexes, &header) {
                    for index in indexes {
                        let first = index.entries.iter().map(|e| e.0).min();
                        let last = index.entries.iter().map(|e| e.0).max();
                        if let (Some(first), Some(last)) = (first, last) {
                            let count = index.entries.len() as u64;
                            self.acc.add_messages(index.channel_id, count, first, last);
                        }
                    }
                    return Ok(after);
                }
            }
        }
        let data_offset = body_offset + header.header_len;
        let compressed = self.input.read_at(data_offset, header.compressed_size)?;
        match inflate(&header, &compressed) {
            Ok(records) => self.chunk_records(&records, data_offset),
            Err(message) => self
                .acc
                .damaged(offset, format!("damaged chunk skipped: {message}")),
        }
        Ok(next)
    }

    /// Reads the message index records that start at `offset`. Returns them (`None` when
    /// one is damaged or cut short) and the offset after the last intact one.
    fn message_indexes(&mut self, mut offset: u64) -> CoreResult<(Option<Vec<MessageIndex>>, u64)> {
        let mut indexes = Vec::new();
        loop {
            let Some((opcode, len)) = self.input.record_prefix(offset)? else {
                return Ok((None, offset));
            };
            if opcode != op::MESSAGE_INDEX {
                return Ok((Some(indexes), offset));
            }
            let body_offset = offset + RECORD_PREFIX_LEN;
            if len > self.input.size - body_offset {
                return Ok((None, offset));
            }
            let body = self.input.read_at(body_offset, len)?;
            match MessageIndex::decode(&body) {
                Ok(index) => indexes.push(index),
                Err(_) => return Ok((None, offset)),
            }
            offset = body_offset + len;
        }
    }

    /// Whether a chunk's message indexes tell all discovery needs, so that its body can
    /// stay compressed: there are some, they name only channels already defined, and
    /// the chunk starts with a message (otherwise schema or channel records may precede
    /// it in the chunk).
    fn indexes_suffice(&self, indexes: &[MessageIndex], header: &ChunkHeader) -> bool {
        let mut starts_with_message = false;
        for index in indexes {
            if !self.acc.channels.contains_key(&index.channel_id) {
                return false;
            }
            for &(_, offset) in &index.entries {
                if offset >= header.uncompressed_size {
                    return false;
                }
                starts_with_message |= offset == 0;
            }
        }
        starts_with_message
    }

    /// The chunk whose record starts at `offset` is cut short (`cut` says how): the file
    /// ends `available` bytes into its body. An uncompressed chunk's records are plain
    /// bytes, so every record that lies wholly before the cut is read, as `mcap recover`
    /// does; reading stops where the first incomplete one begins. A compressed chunk is
    /// not read: that would take decoding a cut compression stream, and its records could
    /// not be checked against the chunk's CRC either way.
    fn cut_chunk(&mut self, offset: u64, available: u64, cut: &str) -> CoreResult<()> {
        let body_offset = offset + RECORD_PREFIX_LEN;
        let prefix = self
            .input
            .read_at(body_offset, available.min(CHUNK_HEADER_PREFIX))?;
        let header = match ChunkHeader::decode(&prefix) {
            Ok(header) if header.header_len <= available => header,
            _ => {
                self.stop(offset, &format!("{cut} (inside the chunk's header)"));
                return Ok(());
            }
        };
        if !header.compression.is_empty() {
            self.stop(
                offset,
                &format!(
                    "{cut}; the chunk's records are {}-compressed, so none of them is read",
                    header.compression
                ),
            );
            return Ok(());
        }
        let data_offset = body_offset + header.header_len;
        let intact = (available - header.header_len)
            .min(header.compressed_size)
            .min(MAX_UNCOMPRESSED_CHUNK);
        let records = self.input.read_at(data_offset, intact)?;
        let (read, end) = self.walk_chunk_records(&records, data_offset);
        self.acc.summary.chunk_count += 1;
        self.acc.compressions.insert(header.compression);
        let end = end.unwrap_or(records.len()) as u64;
        self.stop(
            data_offset + end,
            &format!(
                "{cut}; from the intact start of this uncompressed chunk (byte {offset}) \
                 {} records were recovered ({}), the rest of it is lost",
                read.total(),
                read.describe()
            ),
        );
        Ok(())
    }

    /// Walks the records of an inflated chunk; `data_offset` locates damage in the file.
    fn chunk_records(&mut self, records: &[u8], data_offset: u64) {
        if let (_, Some(position)) = self.walk_chunk_records(records, data_offset) {
            self.acc.damaged(
                data_offset,
                format!(
                    "chunk content broken at byte {position} of its uncompressed records; \
                     the rest of this chunk is skipped"
                ),
            );
        }
    }

    /// Reads the records at the front of a chunk's uncompressed `records`; returns how
    /// many of each kind were read and the position of the first one that does not fit
    /// in what is left, if one does not. `data_offset` locates damage in the file.
    fn walk_chunk_records(
        &mut self,
        records: &[u8],
        data_offset: u64,
    ) -> (RecordCounts, Option<usize>) {
        let mut read = RecordCounts::default();
        let mut position = 0usize;
        while position < records.len() {
            let Some((opcode, body)) = split_record(&records[position..]) else {
                return (read, Some(position));
            };
            let decoded = match opcode {
                op::SCHEMA => Schema::decode(body).map(|s| self.acc.add_schema(s)),
                op::CHANNEL => Channel::decode(body).map(|c| self.acc.add_channel(c)),
                op::MESSAGE => MessageHeader::decode(body).map(|m| {
                    self.acc
                        .add_messages(m.channel_id, 1, m.log_time, m.log_time)
                }),
                _ => Ok(()),
            };
            match decoded {
                Ok(()) => read.add(opcode),
                Err(e) => self.acc.damaged(
                    data_offset,
                    format!(
                        "damaged record (opcode 0x{opcode:02x}) inside a chunk at byte \
                         {position} of its uncompressed records: {}",
                        e.message
                    ),
                ),
            }
            position += RECORD_PREFIX_LEN as usize + body.len();
        }
        (read, None)
    }
}

/// How many records of each kind a chunk gave.
#[derive(Default)]
struct RecordCounts {
    schemas: u64,
    channels: u64,
    messages: u64,
    others: u64,
}

impl RecordCounts {
    fn add(&mut self, opcode: u8) {
        match opcode {
            op::SCHEMA => self.schemas += 1,
            op::CHANNEL => self.channels += 1,
            op::MESSAGE => self.messages += 1,
            _ => self.others += 1,
        }
    }

    fn total(&self) -> u64 {
        self.schemas + self.channels + self.messages + self.others
    }

    /// `2 schemas, 9 channels, 130 messages` (kinds with none left out).
    fn describe(&self) -> String {
        let parts: Vec<String> = [
            (self.schemas, "schema"),
            (self.channels, "channel"),
            (self.messages, "message"),
            (self.others, "other"),
        ]
        .iter()
        .filter(|(count, _)| *count > 0)
        .map(|(count, what)| format!("{count} {what}{}", if *count == 1 { "" } else { "s" }))
        .collect();
        if parts.is_empty() {
            "none".to_string()
        } else {
            parts.join(", ")
        }
    }
}

/// Decompresses a chunk's records and checks their CRC when the writer stored one.
pub(super) fn inflate<'a>(
    header: &ChunkHeader,
    compressed: &'a [u8],
) -> Result<Cow<'a, [u8]>, String> {
    let expected = header.uncompressed_size;
    if expected > MAX_UNCOMPRESSED_CHUNK {
        return Err(format!(
            "it declares {expected} uncompressed bytes, more than the {MAX_UNCOMPRESSED_CHUNK} \
             this reader accepts"
        ));
    }
    let data: Cow<'a, [u8]> = match header.compression.as_str() {
        "" => Cow::Borrowed(compressed),
        "zstd" => {
            let decoder = zstd::stream::read::Decoder::with_buffer(compressed)
                .map_err(|e| format!("zstd: {e}"))?;
            Cow::Owned(
                read_bounded(decoder, expected, compressed.len())
                    .map_err(|e| format!("zstd: {e}"))?,
            )
        }
        "lz4" => {
            let decoder = lz4::Decoder::new(compressed).map_err(|e| format!("lz4: {e}"))?;
            Cow::Owned(
                read_bounded(decoder, expected, compressed.len())
                    .map_err(|e| format!("lz4: {e}"))?,
            )
        }
        other => return Err(format!("unsupported compression {other:?}")),
    };
    if data.len() as u64 != expected {
        return Err(format!(
            "it holds {} uncompressed bytes, not the {expected} its header declares",
            data.len()
        ));
    }
    if header.uncompressed_crc != 0 {
        let actual = crc32fast::hash(&data);
        if actual != header.uncompressed_crc {
            return Err(format!(
                "CRC mismatch (stored {:08x}, computed {actual:08x})",
                header.uncompressed_crc
            ));
        }
    }
    Ok(data)
}

/// Reads at most `expected + 1` bytes, so an over-long stream is noticed without
/// inflating all of it; the buffer grows with real output, not with the declared size.
fn read_bounded(reader: impl Read, expected: u64, compressed_len: usize) -> io::Result<Vec<u8>> {
    let initial = usize_from(expected)
        .min(compressed_len.saturating_mul(8))
        .min(64 << 20);
    let mut out = Vec::with_capacity(initial);
    reader.take(expected + 1).read_to_end(&mut out)?;
    Ok(out)
}
