//! Discovery of what an MCAP recording holds: schemas, channels and message counts; and
//! the messages themselves, for replay ([`MessageReader`]).
//!
//! Two ways to read a file, chosen per file by [`ReadMode`]:
//!
//! * **summary** — the footer points at the summary section, which repeats every schema
//!   and channel and carries statistics and chunk indexes. Reading it touches a few
//!   kilobytes at the end of the file, whatever the file's size.
//! * **scan** — for files without a usable summary (recorder killed, no statistics,
//!   cut short, damaged). Records are read front to back; a chunk's compressed body is
//!   skipped when the message indexes that follow it say everything needed (counts and
//!   log times of channels already known), and decompressed otherwise. Reading stops at
//!   the first broken record frame; everything intact before it is kept and the result
//!   says where the file broke. A chunk that fails to decompress is skipped and named.
//!   When the file ends inside an uncompressed chunk (a recorder killed while writing
//!   its first chunk: schemas and channels lie there), the records before the cut are
//!   read too, and the result says how many.
//!
//! Record bodies are decoded by our own bounded decoder ([`records`]) rather than the
//! `mcap` crate's reader (0.26), for three reasons found when trying it: its
//! `parse_record` panics on an attachment record of 32 to 35 bytes ("slice index starts
//! at 32 but ends at 28"), binrw reserves memory from unchecked `u32` string lengths
//! (up to 4 GiB per flipped length), and its readers cannot skip chunk bodies while
//! keeping the message indexes after them, which the scan path depends on. The `mcap`
//! crate still writes the files our tests read, and the upstream conformance suite
//! checks the decoder.
//!
//! One limit of the index-assisted scan: a channel declared in the middle of a chunk
//! whose message indexes suffice, and that never carries a message, is not seen (unless
//! the summary section after the data repeats it). `ReadMode::Full` sees it.

mod messages;
mod reader;
pub mod records;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::error::{CoreError, CoreResult};

pub use messages::{MessageReader, RecordedMessage};
pub use records::Schema;

/// How [`read_mcap`] reads a file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReadMode {
    /// The summary section when it is complete (statistics plus every schema and
    /// channel), otherwise a scan.
    Auto,
    /// Ignore the summary; scan records, using message indexes to skip chunk bodies.
    Scan,
    /// Ignore the summary and the message indexes; decompress every chunk.
    Full,
}

impl ReadMode {
    /// Parses `auto`, `scan` or `full`.
    pub fn parse(text: &str) -> CoreResult<Self> {
        match text {
            "auto" => Ok(Self::Auto),
            "scan" => Ok(Self::Scan),
            "full" => Ok(Self::Full),
            other => Err(CoreError::InvalidArgument(format!(
                "unknown MCAP read mode {other:?}: use \"auto\", \"scan\" or \"full\""
            ))),
        }
    }
}

/// How a file was actually read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReadMethod {
    Summary,
    Scan,
    Full,
}

impl ReadMethod {
    /// Lower-case name used in reports: `summary`, `scan` or `full`.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Summary => "summary",
            Self::Scan => "scan",
            Self::Full => "full",
        }
    }
}

/// A place in the file where something was wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Damage {
    /// Byte offset of the record (or field) at fault.
    pub offset: u64,
    /// What was wrong there.
    pub message: String,
}

/// One channel (a recorded topic) with what the file says about its messages.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ChannelInfo {
    pub id: u16,
    pub schema_id: u16,
    pub topic: String,
    pub message_encoding: String,
    pub metadata: BTreeMap<String, String>,
    /// Messages on this channel (from statistics, message indexes or the messages).
    pub message_count: u64,
    /// Earliest log time in nanoseconds, when known.
    pub first_log_time: Option<u64>,
    /// Latest log time in nanoseconds, when known.
    pub last_log_time: Option<u64>,
    /// False when the times are bounds taken from chunk indexes (summary reading):
    /// the channel's messages lie within them, but need not touch them.
    pub times_exact: bool,
}

/// Everything discovery needs from one MCAP file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct McapSummary {
    pub path: PathBuf,
    pub file_size: u64,
    /// Header profile (`ros2` for rosbag2), when the header record was readable.
    pub profile: Option<String>,
    /// Header library (the writer), when the header record was readable.
    pub library: Option<String>,
    pub method: ReadMethod,
    /// Schemas by ascending id.
    pub schemas: Vec<Schema>,
    /// Channels by ascending id.
    pub channels: Vec<ChannelInfo>,
    pub message_count: u64,
    pub message_start_time: Option<u64>,
    pub message_end_time: Option<u64>,
    pub attachment_count: u64,
    pub metadata_count: u64,
    pub chunk_count: u64,
    /// Distinct chunk compressions (`""` for uncompressed chunks), sorted.
    pub compressions: Vec<String>,
    /// Messages whose channel id has no channel record in the intact part of the file.
    pub orphan_message_count: u64,
    /// Where reading stopped before the end of the file, if it did.
    pub stopped: Option<Damage>,
    /// Records that were skipped because they were damaged (reading went on after them).
    pub damaged: Vec<Damage>,
    /// Remarks for the user, e.g. why the summary could not be used.
    pub notes: Vec<String>,
}

impl McapSummary {
    /// True when part of the file could not be read.
    pub fn is_partial(&self) -> bool {
        self.stopped.is_some() || !self.damaged.is_empty()
    }
}

/// Reads what the MCAP file at `path` holds (see the module documentation).
///
/// A damaged or truncated file gives a partial result ([`McapSummary::is_partial`]);
/// an error means the file cannot be read at all or is not an MCAP file.
pub fn read_mcap(path: &Path, mode: ReadMode) -> CoreResult<McapSummary> {
    // The decoder is written not to panic; this guard keeps a bug in it (or in a
    // decompression library) from ever unwinding into the caller, e.g. the Python binding.
    match std::panic::catch_unwind(|| reader::read(path, mode)) {
        Ok(result) => result,
        Err(_) => Err(CoreError::Format {
            path: path.to_path_buf(),
            offset: 0,
            message: "internal error while reading this MCAP file; please report it with \
                      the file"
                .to_string(),
        }),
    }
}

#[cfg(test)]
mod tests;
