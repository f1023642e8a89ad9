//! The messages of one MCAP file, front to back, for replaying a recording.
//!
//! Discovery ([`super::read_mcap`]) only counts messages; replay needs their payloads.
//! [`MessageReader`] walks the data section record by record and hands out each message's
//! log time, topic and serialised payload (CDR for rosbag2), of the wanted topics only.
//! Memory stays at about one chunk: a chunk is decompressed when it is reached, its
//! messages are handed out in log-time order (rosbag2 writes chunks one after the other in
//! time), and it is dropped before the next one is read.
//!
//! Unlike discovery, which keeps what is intact around a damaged record, replay stops at
//! the first broken record or chunk with an error naming its offset: the messages after it
//! are lost to the replay either way, and the caller decides whether what it got so far is
//! worth keeping.

use std::collections::{HashMap, HashSet, VecDeque};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::reader::{inflate, split_record, Input};
use super::records::{op, Channel, ChunkHeader, MessageHeader, MAGIC, RECORD_PREFIX_LEN};
use crate::error::{CoreError, CoreResult};

/// One recorded message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RecordedMessage {
    /// Log time in nanoseconds.
    pub log_time: u64,
    pub topic: Arc<str>,
    /// The payload as recorded (for rosbag2, CDR with its encapsulation header).
    pub data: Vec<u8>,
}

/// Iterates over the messages of one MCAP file; see the module documentation.
pub struct MessageReader {
    input: Input,
    path: PathBuf,
    offset: u64,
    topics: Option<HashSet<String>>,
    channels: HashMap<u16, Arc<str>>,
    pending: VecDeque<RecordedMessage>,
    done: bool,
}

impl MessageReader {
    /// Opens `path` and checks that it is an MCAP file; `topics` limits the messages
    /// handed out to those topics (`None`: every topic).
    pub fn open(path: &Path, topics: Option<HashSet<String>>) -> CoreResult<Self> {
        let mut input = Input::open(path)?;
        let head = input.read_at(0, input.size.min(MAGIC.len() as u64))?;
        if head.as_slice() != MAGIC {
            return Err(input.format_error(0, "not an MCAP file (wrong magic bytes)"));
        }
        Ok(Self {
            input,
            path: path.to_path_buf(),
            offset: MAGIC.len() as u64,
            topics,
            channels: HashMap::new(),
            pending: VecDeque::new(),
            done: false,
        })
    }

    /// The next message, `Ok(None)` at the end of the data section.
    pub fn next_message(&mut self) -> CoreResult<Option<RecordedMessage>> {
        // The decoders are written not to panic; this guard keeps a bug in them (or in a
        // decompression library) from unwinding into the caller, e.g. the Python binding.
        let path = self.path.clone();
        let offset = self.offset;
        match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| self.advance())) {
            Ok(Ok(found)) => Ok(found),
            Ok(Err(error)) => {
                self.done = true;
                Err(error)
            }
            Err(_) => {
                self.done = true;
                Err(CoreError::Format {
                    path,
                    offset,
                    message: "internal error while reading the messages of this MCAP file; \
                              please report it with the file"
                        .to_string(),
                })
            }
        }
    }

    fn advance(&mut self) -> CoreResult<Option<RecordedMessage>> {
        loop {
            if let Some(message) = self.pending.pop_front() {
                return Ok(Some(message));
            }
            if self.done {
                return Ok(None);
            }
            let offset = self.offset;
            let Some((opcode, len)) = self.input.record_prefix(offset)? else {
                self.done = true;
                continue;
            };
            if opcode == op::FOOTER || opcode == op::DATA_END {
                self.done = true;
                continue;
            }
            let body_offset = offset + RECORD_PREFIX_LEN;
            if len > self.input.size - body_offset {
                return Err(self.input.format_error(offset, "record is cut short"));
            }
            self.offset = body_offset + len;
            match opcode {
                op::CHANNEL => {
                    let body = self.input.read_at(body_offset, len)?;
                    self.channel(&body, offset)?;
                }
                op::MESSAGE => {
                    let body = self.input.read_at(body_offset, len)?;
                    if let Some(message) = self.message(&body, offset)? {
                        return Ok(Some(message));
                    }
                }
                op::CHUNK => {
                    let body = self.input.read_at(body_offset, len)?;
                    self.chunk(&body, offset)?;
                }
                _ => {}
            }
        }
    }

    fn channel(&mut self, body: &[u8], offset: u64) -> CoreResult<()> {
        let channel = Channel::decode(body).map_err(|e| {
            self.input
                .format_error(offset, &format!("broken channel record: {}", e.message))
        })?;
        self.channels.insert(channel.id, Arc::from(channel.topic));
        Ok(())
    }

    fn message(&self, body: &[u8], offset: u64) -> CoreResult<Option<RecordedMessage>> {
        let header = MessageHeader::decode(body).map_err(|e| {
            self.input
                .format_error(offset, &format!("broken message record: {}", e.message))
        })?;
        let Some(topic) = self.channels.get(&header.channel_id) else {
            return Ok(None);
        };
        if let Some(topics) = &self.topics {
            if !topics.contains(topic.as_ref()) {
                return Ok(None);
            }
        }
        Ok(Some(RecordedMessage {
            log_time: header.log_time,
            topic: Arc::clone(topic),
            data: body[MessageHeader::LEN as usize..].to_vec(),
        }))
    }

    fn chunk(&mut self, body: &[u8], offset: u64) -> CoreResult<()> {
        let broken = |what: &str| {
            self.input
                .format_error(offset, &format!("chunk is broken ({what})"))
        };
        let header = ChunkHeader::decode(body).map_err(|e| broken(&e.message))?;
        let start = usize::try_from(header.header_len).map_err(|_| broken("header length"))?;
        let compressed = usize::try_from(header.compressed_size)
            .ok()
            .and_then(|size| body.get(start..start.checked_add(size)?))
            .ok_or_else(|| broken("its records run past the chunk"))?;
        let records = inflate(&header, compressed).map_err(|message| {
            self.input
                .format_error(offset, &format!("chunk does not decompress ({message})"))
        })?;
        let mut messages = Vec::new();
        let mut rest: &[u8] = &records;
        while let Some((opcode, record)) = split_record(rest) {
            rest = &rest[RECORD_PREFIX_LEN as usize + record.len()..];
            match opcode {
                op::CHANNEL => self.channel(record, offset)?,
                op::MESSAGE => messages.extend(self.message(record, offset)?),
                _ => {}
            }
        }
        // A stable sort: messages logged at the same time keep the order they were written.
        messages.sort_by_key(|m| m.log_time);
        self.pending.extend(messages);
        Ok(())
    }
}

impl Iterator for MessageReader {
    type Item = CoreResult<RecordedMessage>;

    fn next(&mut self) -> Option<Self::Item> {
        self.next_message().transpose()
    }
}
