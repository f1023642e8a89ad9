//! Bounded decoding of MCAP record bodies (spec: <https://mcap.dev/spec>).
//!
//! Every length field is checked against the bytes actually present before anything
//! is allocated or sliced, so a flipped bit can produce an error but never a huge
//! allocation or a panic. Extra bytes at the end of a record body are ignored, as the
//! specification requires (records may grow new fields).

use std::collections::BTreeMap;

/// Record opcodes defined by the MCAP specification.
pub mod op {
    pub const HEADER: u8 = 0x01;
    pub const FOOTER: u8 = 0x02;
    pub const SCHEMA: u8 = 0x03;
    pub const CHANNEL: u8 = 0x04;
    pub const MESSAGE: u8 = 0x05;
    pub const CHUNK: u8 = 0x06;
    pub const MESSAGE_INDEX: u8 = 0x07;
    pub const CHUNK_INDEX: u8 = 0x08;
    pub const ATTACHMENT: u8 = 0x09;
    pub const ATTACHMENT_INDEX: u8 = 0x0A;
    pub const STATISTICS: u8 = 0x0B;
    pub const METADATA: u8 = 0x0C;
    pub const METADATA_INDEX: u8 = 0x0D;
    pub const SUMMARY_OFFSET: u8 = 0x0E;
    pub const DATA_END: u8 = 0x0F;
}

/// The eight bytes at the start and the end of every MCAP file.
pub const MAGIC: &[u8; 8] = b"\x89MCAP0\r\n";

/// Opcode (1 byte) plus body length (8 bytes).
pub const RECORD_PREFIX_LEN: u64 = 9;

/// A decoding failure inside one record body: what was wrong and the byte position
/// inside the body, which the caller turns into a file offset.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DecodeError {
    pub position: usize,
    pub message: String,
}

pub type DecodeResult<T> = Result<T, DecodeError>;

/// A little-endian reader over one record body that never reads past its end.
pub struct Cursor<'a> {
    bytes: &'a [u8],
    position: usize,
}

impl<'a> Cursor<'a> {
    pub fn new(bytes: &'a [u8]) -> Self {
        Self { bytes, position: 0 }
    }

    pub fn position(&self) -> usize {
        self.position
    }

    fn fail<T>(&self, what: &str) -> DecodeResult<T> {
        Err(DecodeError {
            position: self.position,
            message: what.to_string(),
        })
    }

    fn take(&mut self, len: usize, what: &str) -> DecodeResult<&'a [u8]> {
        let remaining = self.bytes.len() - self.position;
        if len > remaining {
            return Err(DecodeError {
                position: self.position,
                message: format!("{what}: needs {len} bytes but the record has {remaining} left"),
            });
        }
        let slice = &self.bytes[self.position..self.position + len];
        self.position += len;
        Ok(slice)
    }

    fn array<const N: usize>(&mut self, what: &str) -> DecodeResult<[u8; N]> {
        let slice = self.take(N, what)?;
        let mut out = [0u8; N];
        out.copy_from_slice(slice);
        Ok(out)
    }

    pub fn u8(&mut self, what: &str) -> DecodeResult<u8> {
        Ok(self.array::<1>(what)?[0])
    }

    pub fn u16(&mut self, what: &str) -> DecodeResult<u16> {
        Ok(u16::from_le_bytes(self.array(what)?))
    }

    pub fn u32(&mut self, what: &str) -> DecodeResult<u32> {
        Ok(u32::from_le_bytes(self.array(what)?))
    }

    pub fn u64(&mut self, what: &str) -> DecodeResult<u64> {
        Ok(u64::from_le_bytes(self.array(what)?))
    }

    /// A `uint32` length followed by that many bytes.
    /// Errors point at the length field.
    pub fn bytes32(&mut self, what: &str) -> DecodeResult<&'a [u8]> {
        let start = self.position;
        let len = self.u32(what)?;
        self.take(usize_from(u64::from(len)), what)
            .map_err(|e| DecodeError {
                position: start,
                ..e
            })
    }

    /// A `uint32` length followed by UTF-8 text.
    pub fn string(&mut self, what: &str) -> DecodeResult<String> {
        let start = self.position;
        let bytes = self.bytes32(what)?;
        match std::str::from_utf8(bytes) {
            Ok(text) => Ok(text.to_string()),
            Err(_) => Err(DecodeError {
                position: start,
                message: format!("{what} is not valid UTF-8"),
            }),
        }
    }

    /// A `uint32` byte length followed by string keys and string values.
    pub fn string_map(&mut self, what: &str) -> DecodeResult<BTreeMap<String, String>> {
        let body = self.bytes32(what)?;
        let base = self.position - body.len();
        let mut inner = Cursor::new(body);
        let mut map = BTreeMap::new();
        while inner.position < body.len() {
            let key = inner.string(what).map_err(|e| e.shifted(base))?;
            let value = inner.string(what).map_err(|e| e.shifted(base))?;
            map.insert(key, value);
        }
        Ok(map)
    }

    /// A `uint32` byte length followed by `uint16` keys and `uint64` values.
    pub fn u16_u64_map(&mut self, what: &str) -> DecodeResult<BTreeMap<u16, u64>> {
        let body = self.bytes32(what)?;
        let base = self.position - body.len();
        if body.len() % 10 != 0 {
            return self.fail(&format!(
                "{what}: map length {} is not a multiple of 10",
                body.len()
            ));
        }
        let mut inner = Cursor::new(body);
        let mut map = BTreeMap::new();
        while inner.position < body.len() {
            let key = inner.u16(what).map_err(|e| e.shifted(base))?;
            let value = inner.u64(what).map_err(|e| e.shifted(base))?;
            map.insert(key, value);
        }
        Ok(map)
    }
}

impl DecodeError {
    fn shifted(mut self, base: usize) -> Self {
        self.position += base;
        self
    }
}

/// Converts a length read from the file to `usize`, saturating on 32-bit targets; the
/// saturated value then fails the bounds check instead of wrapping.
pub fn usize_from(value: u64) -> usize {
    usize::try_from(value).unwrap_or(usize::MAX)
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Header {
    pub profile: String,
    pub library: String,
}

impl Header {
    pub fn decode(body: &[u8]) -> DecodeResult<Self> {
        let mut c = Cursor::new(body);
        Ok(Self {
            profile: c.string("header profile")?,
            library: c.string("header library")?,
        })
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Footer {
    pub summary_start: u64,
    pub summary_offset_start: u64,
    pub summary_crc: u32,
}

impl Footer {
    /// Body length of a footer record.
    pub const BODY_LEN: u64 = 20;

    pub fn decode(body: &[u8]) -> DecodeResult<Self> {
        let mut c = Cursor::new(body);
        Ok(Self {
            summary_start: c.u64("footer summary_start")?,
            summary_offset_start: c.u64("footer summary_offset_start")?,
            summary_crc: c.u32("footer summary_crc")?,
        })
    }
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Schema {
    pub id: u16,
    pub name: String,
    pub encoding: String,
    pub data: Vec<u8>,
}

impl Schema {
    pub fn decode(body: &[u8]) -> DecodeResult<Self> {
        let mut c = Cursor::new(body);
        Ok(Self {
            id: c.u16("schema id")?,
            name: c.string("schema name")?,
            encoding: c.string("schema encoding")?,
            data: c.bytes32("schema data")?.to_vec(),
        })
    }
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Channel {
    pub id: u16,
    pub schema_id: u16,
    pub topic: String,
    pub message_encoding: String,
    pub metadata: BTreeMap<String, String>,
}

impl Channel {
    pub fn decode(body: &[u8]) -> DecodeResult<Self> {
        let mut c = Cursor::new(body);
        Ok(Self {
            id: c.u16("channel id")?,
            schema_id: c.u16("channel schema_id")?,
            topic: c.string("channel topic")?,
            message_encoding: c.string("channel message_encoding")?,
            metadata: c.string_map("channel metadata")?,
        })
    }
}

/// The fixed part of a message record; the payload is never needed for discovery.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MessageHeader {
    pub channel_id: u16,
    pub sequence: u32,
    pub log_time: u64,
    pub publish_time: u64,
}

impl MessageHeader {
    /// Bytes of the fixed part.
    pub const LEN: u64 = 22;

    pub fn decode(body: &[u8]) -> DecodeResult<Self> {
        let mut c = Cursor::new(body);
        Ok(Self {
            channel_id: c.u16("message channel_id")?,
            sequence: c.u32("message sequence")?,
            log_time: c.u64("message log_time")?,
            publish_time: c.u64("message publish_time")?,
        })
    }
}

/// A chunk's header: everything before its compressed records.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ChunkHeader {
    pub message_start_time: u64,
    pub message_end_time: u64,
    pub uncompressed_size: u64,
    pub uncompressed_crc: u32,
    pub compression: String,
    pub compressed_size: u64,
    /// Bytes from the start of the chunk body to the first compressed byte.
    pub header_len: u64,
}

impl ChunkHeader {
    /// Decodes the header from a prefix of the chunk body (the compressed bytes may be
    /// absent from `prefix`).
    pub fn decode(prefix: &[u8]) -> DecodeResult<Self> {
        let mut c = Cursor::new(prefix);
        let message_start_time = c.u64("chunk message_start_time")?;
        let message_end_time = c.u64("chunk message_end_time")?;
        let uncompressed_size = c.u64("chunk uncompressed_size")?;
        let uncompressed_crc = c.u32("chunk uncompressed_crc")?;
        let compression = c.string("chunk compression")?;
        let compressed_size = c.u64("chunk records length")?;
        Ok(Self {
            message_start_time,
            message_end_time,
            uncompressed_size,
            uncompressed_crc,
            compression,
            compressed_size,
            header_len: c.position() as u64,
        })
    }
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MessageIndex {
    pub channel_id: u16,
    /// `(log_time, offset into the uncompressed chunk)` per message.
    pub entries: Vec<(u64, u64)>,
}

impl MessageIndex {
    pub fn decode(body: &[u8]) -> DecodeResult<Self> {
        let mut c = Cursor::new(body);
        let channel_id = c.u16("message index channel_id")?;
        let records = c.bytes32("message index records")?;
        if records.len() % 16 != 0 {
            return c.fail(&format!(
                "message index records length {} is not a multiple of 16",
                records.len()
            ));
        }
        let mut inner = Cursor::new(records);
        let mut entries = Vec::with_capacity(records.len() / 16);
        while inner.position() < records.len() {
            let log_time = inner.u64("message index log_time")?;
            let offset = inner.u64("message index offset")?;
            entries.push((log_time, offset));
        }
        Ok(Self {
            channel_id,
            entries,
        })
    }
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ChunkIndex {
    pub message_start_time: u64,
    pub message_end_time: u64,
    pub chunk_start_offset: u64,
    pub chunk_length: u64,
    pub message_index_offsets: BTreeMap<u16, u64>,
    pub message_index_length: u64,
    pub compression: String,
    pub compressed_size: u64,
    pub uncompressed_size: u64,
}

impl ChunkIndex {
    pub fn decode(body: &[u8]) -> DecodeResult<Self> {
        let mut c = Cursor::new(body);
        Ok(Self {
            message_start_time: c.u64("chunk index message_start_time")?,
            message_end_time: c.u64("chunk index message_end_time")?,
            chunk_start_offset: c.u64("chunk index chunk_start_offset")?,
            chunk_length: c.u64("chunk index chunk_length")?,
            message_index_offsets: c.u16_u64_map("chunk index message_index_offsets")?,
            message_index_length: c.u64("chunk index message_index_length")?,
            compression: c.string("chunk index compression")?,
            compressed_size: c.u64("chunk index compressed_size")?,
            uncompressed_size: c.u64("chunk index uncompressed_size")?,
        })
    }
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Statistics {
    pub message_count: u64,
    pub schema_count: u16,
    pub channel_count: u32,
    pub attachment_count: u32,
    pub metadata_count: u32,
    pub chunk_count: u32,
    pub message_start_time: u64,
    pub message_end_time: u64,
    pub channel_message_counts: BTreeMap<u16, u64>,
}

impl Statistics {
    pub fn decode(body: &[u8]) -> DecodeResult<Self> {
        let mut c = Cursor::new(body);
        Ok(Self {
            message_count: c.u64("statistics message_count")?,
            schema_count: c.u16("statistics schema_count")?,
            channel_count: c.u32("statistics channel_count")?,
            attachment_count: c.u32("statistics attachment_count")?,
            metadata_count: c.u32("statistics metadata_count")?,
            chunk_count: c.u32("statistics chunk_count")?,
            message_start_time: c.u64("statistics message_start_time")?,
            message_end_time: c.u64("statistics message_end_time")?,
            channel_message_counts: c.u16_u64_map("statistics channel_message_counts")?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn string(text: &str) -> Vec<u8> {
        let mut out = (text.len() as u32).to_le_bytes().to_vec();
        out.extend_from_slice(text.as_bytes());
        out
    }

    #[test]
    fn header_decodes_profile_and_library() {
        let mut body = string("ros2");
        body.extend(string("lib"));
        assert_eq!(
            Header::decode(&body),
            Ok(Header {
                profile: "ros2".into(),
                library: "lib".into()
            })
        );
    }

    #[test]
    fn huge_string_length_is_an_error_not_an_allocation() {
        let mut body = 7u16.to_le_bytes().to_vec();
        body.extend_from_slice(&u32::MAX.to_le_bytes());
        body.extend_from_slice(b"abc");
        let err = Schema::decode(&body).err();
        assert!(
            matches!(err, Some(DecodeError { position: 2, .. })),
            "{err:?}"
        );
    }

    #[test]
    fn channel_metadata_map_is_decoded() {
        let mut body = 1u16.to_le_bytes().to_vec();
        body.extend_from_slice(&2u16.to_le_bytes());
        body.extend(string("/chatter"));
        body.extend(string("cdr"));
        let mut map = string("k");
        map.extend(string("v"));
        body.extend_from_slice(&(map.len() as u32).to_le_bytes());
        body.extend(map);
        body.extend_from_slice(b"padding is ignored");
        let channel = Channel::decode(&body);
        assert_eq!(
            channel.map(|c| (c.topic, c.metadata.get("k").cloned())),
            Ok(("/chatter".to_string(), Some("v".to_string())))
        );
    }

    #[test]
    fn truncated_map_entry_reports_its_position() {
        let mut body = 1u16.to_le_bytes().to_vec();
        body.extend_from_slice(&2u16.to_le_bytes());
        body.extend(string("t"));
        body.extend(string("e"));
        body.extend_from_slice(&9u32.to_le_bytes());
        body.extend(string("key"));
        body.extend_from_slice(&[0, 0]); // half of the value's length field
        let err = Channel::decode(&body).err();
        assert!(matches!(err, Some(DecodeError { position, .. }) if position == 18 + 7));
    }

    #[test]
    fn message_index_with_odd_length_is_rejected() {
        let mut body = 1u16.to_le_bytes().to_vec();
        body.extend_from_slice(&3u32.to_le_bytes());
        body.extend_from_slice(&[1, 2, 3]);
        assert!(MessageIndex::decode(&body).is_err());
    }

    #[test]
    fn invalid_utf8_is_an_error() {
        let mut body = 2u32.to_le_bytes().to_vec();
        body.extend_from_slice(&[0xff, 0xfe]);
        body.extend(string("lib"));
        assert!(Header::decode(&body).is_err());
    }
}
