//! Files written by the `mcap` crate (an independent writer) read back in every mode,
//! and damaged copies of them never panic, hang or allocate what a length field says.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::collections::BTreeMap;
use std::io::Cursor;
use std::path::{Path, PathBuf};

use super::*;

const SCHEMA: &str = "string data\n";

struct Fixture {
    _dir: tempfile::TempDir,
    path: PathBuf,
}

fn write_bag(options: mcap::WriteOptions, messages_per_topic: u64) -> Vec<u8> {
    let mut out = Cursor::new(Vec::new());
    let mut writer = options.profile("ros2").create(&mut out).unwrap();
    let schema = writer
        .add_schema("std_msgs/msg/String", "ros2msg", SCHEMA.as_bytes())
        .unwrap();
    let mut meta = BTreeMap::new();
    meta.insert("offered_qos_profiles".to_string(), "- depth: 1".to_string());
    let chatter = writer
        .add_channel(schema, "/chatter", "cdr", &meta)
        .unwrap();
    let rosout = writer
        .add_channel(schema, "/rosout", "cdr", &BTreeMap::new())
        .unwrap();
    // A channel that never carries a message still has to be discovered.
    writer
        .add_channel(schema, "/silent", "cdr", &BTreeMap::new())
        .unwrap();
    for i in 0..messages_per_topic {
        for (channel_id, step) in [(chatter, 10), (rosout, 7)] {
            let header = mcap::records::MessageHeader {
                channel_id,
                sequence: i as u32,
                log_time: 1_000 + i * step,
                publish_time: 1_000 + i * step,
            };
            writer
                .write_to_known_channel(&header, &[i as u8; 64])
                .unwrap();
        }
    }
    writer
        .attach(&mcap::Attachment {
            log_time: 5,
            create_time: 5,
            name: "calibration.yaml".into(),
            media_type: "text/yaml".into(),
            data: std::borrow::Cow::Borrowed(b"k: v"),
        })
        .unwrap();
    writer
        .write_metadata(&mcap::records::Metadata {
            name: "rosbag2".into(),
            metadata: BTreeMap::new(),
        })
        .unwrap();
    writer.finish().unwrap();
    drop(writer);
    out.into_inner()
}

fn store(bytes: &[u8]) -> Fixture {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bag.mcap");
    std::fs::write(&path, bytes).unwrap();
    Fixture { _dir: dir, path }
}

fn chunked(compression: Option<mcap::Compression>) -> mcap::WriteOptions {
    mcap::WriteOptions::new()
        .compression(compression)
        .chunk_size(Some(2048))
}

fn topics(summary: &McapSummary) -> Vec<(String, u64)> {
    summary
        .channels
        .iter()
        .map(|c| (c.topic.clone(), c.message_count))
        .collect()
}

fn expected_topics(n: u64) -> Vec<(String, u64)> {
    vec![
        ("/chatter".into(), n),
        ("/rosout".into(), n),
        ("/silent".into(), 0),
    ]
}

#[test]
fn every_mode_reads_every_compression_alike() {
    for compression in [
        None,
        Some(mcap::Compression::Zstd),
        Some(mcap::Compression::Lz4),
    ] {
        let fixture = store(&write_bag(chunked(compression), 200));
        for mode in [ReadMode::Auto, ReadMode::Scan, ReadMode::Full] {
            let summary = read_mcap(&fixture.path, mode).unwrap();
            assert_eq!(
                topics(&summary),
                expected_topics(200),
                "{compression:?} {mode:?}"
            );
            assert_eq!(summary.message_count, 400);
            assert_eq!(summary.attachment_count, 1);
            assert_eq!(summary.metadata_count, 1);
            assert_eq!(summary.schemas.len(), 1);
            assert_eq!(summary.schemas[0].data, SCHEMA.as_bytes());
            assert_eq!(summary.profile.as_deref(), Some("ros2"));
            assert!(summary.chunk_count > 5, "{}", summary.chunk_count);
            assert!(!summary.is_partial(), "{:?}", summary.stopped);
            assert_eq!(summary.message_start_time, Some(1_000));
            assert_eq!(summary.message_end_time, Some(1_000 + 199 * 10));
            let chatter = &summary.channels[0];
            assert_eq!(
                chatter
                    .metadata
                    .get("offered_qos_profiles")
                    .map(String::as_str),
                Some("- depth: 1")
            );
            let expected_method = match mode {
                ReadMode::Auto => ReadMethod::Summary,
                ReadMode::Scan => ReadMethod::Scan,
                ReadMode::Full => ReadMethod::Full,
            };
            assert_eq!(summary.method, expected_method);
        }
    }
}

#[test]
fn scan_gives_exact_channel_times() {
    let fixture = store(&write_bag(chunked(Some(mcap::Compression::Zstd)), 50));
    let summary = read_mcap(&fixture.path, ReadMode::Scan).unwrap();
    let rosout = &summary.channels[1];
    assert!(rosout.times_exact);
    assert_eq!(
        (rosout.first_log_time, rosout.last_log_time),
        (Some(1_000), Some(1_000 + 49 * 7))
    );
}

#[test]
fn file_without_summary_falls_back_to_scan_and_says_why() {
    let options = chunked(Some(mcap::Compression::Zstd))
        .emit_statistics(false)
        .emit_summary_records(false)
        .emit_chunk_indexes(false);
    let fixture = store(&write_bag(options, 30));
    let summary = read_mcap(&fixture.path, ReadMode::Auto).unwrap();
    assert_eq!(summary.method, ReadMethod::Scan);
    assert_eq!(topics(&summary), expected_topics(30));
    assert_eq!(summary.notes, ["the file has no summary section"]);
}

#[test]
fn every_writer_option_combination_reads_alike() {
    let variants: Vec<(&str, mcap::WriteOptions)> = vec![
        (
            "no statistics",
            chunked(Some(mcap::Compression::Zstd)).emit_statistics(false),
        ),
        (
            "no message indexes",
            chunked(Some(mcap::Compression::Lz4)).emit_message_indexes(false),
        ),
        ("no chunk indexes", chunked(None).emit_chunk_indexes(false)),
        (
            "no summary offsets",
            chunked(None).emit_summary_offsets(false),
        ),
        (
            "no repeated channels",
            chunked(Some(mcap::Compression::Zstd)).repeat_channels(false),
        ),
        ("no repeated schemas", chunked(None).repeat_schemas(false)),
        (
            "no crcs",
            chunked(None)
                .calculate_chunk_crcs(false)
                .calculate_summary_section_crc(false),
        ),
        ("one big chunk", mcap::WriteOptions::new().chunk_size(None)),
    ];
    for (name, options) in variants {
        let fixture = store(&write_bag(options, 60));
        for mode in [ReadMode::Auto, ReadMode::Scan, ReadMode::Full] {
            let summary = read_mcap(&fixture.path, mode).unwrap();
            assert_eq!(topics(&summary), expected_topics(60), "{name} {mode:?}");
            assert_eq!(
                (summary.attachment_count, summary.metadata_count),
                (1, 1),
                "{name}"
            );
            assert!(
                !summary.is_partial(),
                "{name} {mode:?}: {:?}",
                summary.damaged
            );
        }
    }
}

#[test]
fn corrupt_summary_offset_falls_back_to_scan() {
    let mut bytes = write_bag(chunked(Some(mcap::Compression::Zstd)), 30);
    // summary_start is the first field of the footer body.
    let at = bytes.len() - 8 - 20;
    bytes[at..at + 8].copy_from_slice(&8u64.to_le_bytes());
    let fixture = store(&bytes);
    let summary = read_mcap(&fixture.path, ReadMode::Auto).unwrap();
    assert_eq!(summary.method, ReadMethod::Scan);
    assert!(
        summary.notes[0].contains("data end record"),
        "{:?}",
        summary.notes
    );
    assert_eq!(topics(&summary), expected_topics(30));
}

#[test]
fn unchunked_file_is_read() {
    let options = mcap::WriteOptions::new().use_chunks(false);
    let fixture = store(&write_bag(options, 20));
    for mode in [ReadMode::Auto, ReadMode::Scan] {
        let summary = read_mcap(&fixture.path, mode).unwrap();
        assert_eq!(topics(&summary), expected_topics(20));
        assert_eq!(summary.chunk_count, 0);
    }
}

#[test]
fn truncated_file_keeps_the_intact_chunks_and_names_the_break() {
    let bytes = write_bag(chunked(Some(mcap::Compression::Lz4)), 200);
    let cut = bytes.len() / 2;
    let fixture = store(&bytes[..cut]);
    let summary = read_mcap(&fixture.path, ReadMode::Auto).unwrap();
    assert!(summary.is_partial());
    let stopped = summary.stopped.clone().unwrap();
    assert!(stopped.offset < cut as u64);
    assert!(stopped.message.contains("cut short"), "{}", stopped.message);
    assert!(summary.message_count > 100, "{}", summary.message_count);
    assert!(summary.message_count < 400);
    assert_eq!(summary.channels.len(), 3);
}

/// Offset and body length of the first chunk record.
fn first_chunk(bytes: &[u8]) -> (usize, usize) {
    let record_len = |at: usize| u64::from_le_bytes(bytes[at + 1..at + 9].try_into().unwrap());
    let mut at = 8 + 9 + record_len(8) as usize;
    while bytes[at] != records::op::CHUNK {
        at += 9 + record_len(at) as usize;
    }
    (at, record_len(at) as usize)
}

#[test]
fn a_cut_uncompressed_chunk_keeps_the_records_before_the_cut() {
    // One chunk for the whole recording: the schema, the channels and the messages.
    let options = mcap::WriteOptions::new().compression(None).chunk_size(None);
    let bytes = write_bag(options, 200);
    let (chunk, len) = first_chunk(&bytes);
    let mut counts = Vec::new();
    for share in [50, 90] {
        let cut = chunk + 9 + len * share / 100;
        let fixture = store(&bytes[..cut]);
        for mode in [ReadMode::Auto, ReadMode::Scan, ReadMode::Full] {
            let summary = read_mcap(&fixture.path, mode).unwrap();
            let names: Vec<&str> = summary.channels.iter().map(|c| c.topic.as_str()).collect();
            assert_eq!(
                names,
                ["/chatter", "/rosout", "/silent"],
                "{share}% {mode:?}"
            );
            assert_eq!(summary.schemas.len(), 1);
            let stopped = summary.stopped.clone().unwrap();
            // Reading stops where the first record the cut runs through begins.
            assert!(stopped.offset <= cut as u64 && stopped.offset + 200 > cut as u64);
            let recovered = format!(
                "{} records were recovered (1 schema, 3 channels, {} messages)",
                4 + summary.message_count,
                summary.message_count
            );
            assert!(
                stopped.message.contains("cut short") && stopped.message.contains(&recovered),
                "{}",
                stopped.message
            );
            assert_eq!(summary.chunk_count, 1);
            counts.push(summary.message_count);
        }
    }
    // The chunk is almost all messages of one size: a cut at half of it keeps about half
    // of its 400, one at 90 % about 360.
    assert!((190..=210).contains(&counts[0]), "{counts:?}");
    assert!((350..400).contains(&counts[3]), "{counts:?}");
}

#[test]
fn a_cut_compressed_chunk_says_its_records_are_not_read() {
    let options = mcap::WriteOptions::new()
        .compression(Some(mcap::Compression::Zstd))
        .chunk_size(None);
    let bytes = write_bag(options, 200);
    let (chunk, len) = first_chunk(&bytes);
    let fixture = store(&bytes[..chunk + 9 + len / 2]);
    let summary = read_mcap(&fixture.path, ReadMode::Auto).unwrap();
    assert!(summary.channels.is_empty());
    let stopped = summary.stopped.unwrap();
    assert_eq!(stopped.offset, chunk as u64);
    assert!(
        stopped
            .message
            .contains("zstd-compressed, so none of them is read"),
        "{}",
        stopped.message
    );
}

#[test]
fn file_cut_at_a_record_boundary_says_it_was_not_closed() {
    let bytes = write_bag(mcap::WriteOptions::new().use_chunks(false), 5);
    // Header record: magic + 9-byte prefix + body of two strings.
    let header_len = u64::from_le_bytes(bytes[9..17].try_into().unwrap());
    let cut = 8 + 9 + header_len as usize;
    let fixture = store(&bytes[..cut]);
    let summary = read_mcap(&fixture.path, ReadMode::Auto).unwrap();
    let stopped = summary.stopped.unwrap();
    assert_eq!(stopped.offset, cut as u64);
    assert!(stopped.message.contains("not closed"));
}

#[test]
fn empty_file_is_a_format_error_at_byte_zero() {
    let fixture = store(b"");
    let err = read_mcap(&fixture.path, ReadMode::Auto).unwrap_err();
    assert!(matches!(err, CoreError::Format { offset: 0, .. }), "{err}");
    assert!(err.to_string().contains("empty file"));
}

#[test]
fn non_mcap_file_is_a_format_error() {
    let fixture = store(b"rosbag2_bagfile_information:\n  version: 8\n");
    let err = read_mcap(&fixture.path, ReadMode::Auto).unwrap_err();
    assert!(err.to_string().contains("not an MCAP file"), "{err}");
}

#[test]
fn missing_file_and_folder_are_told_apart() {
    let dir = tempfile::tempdir().unwrap();
    assert!(matches!(
        read_mcap(&dir.path().join("nope.mcap"), ReadMode::Auto),
        Err(CoreError::NotFound { .. })
    ));
    assert!(matches!(
        read_mcap(dir.path(), ReadMode::Auto),
        Err(CoreError::InvalidArgument(_))
    ));
}

#[test]
fn read_mode_names_parse() {
    assert_eq!(ReadMode::parse("scan").unwrap(), ReadMode::Scan);
    assert!(matches!(
        ReadMode::parse("fast"),
        Err(CoreError::InvalidArgument(_))
    ));
}

/// Reads a damaged copy with the unguarded reader, so a panic fails the test.
fn read_damaged(path: &Path, mode: ReadMode) {
    match reader::read(path, mode) {
        Ok(summary) => {
            // A flipped id or count can invent a channel or messages; what must hold is
            // that every channel read is complete enough to report.
            for channel in &summary.channels {
                assert!(channel.first_log_time.is_some() || channel.message_count == 0);
            }
        }
        Err(CoreError::Format { .. }) => {}
        Err(other) => panic!("unexpected error kind: {other}"),
    }
}

#[test]
fn truncation_at_every_offset_never_panics() {
    let bytes = write_bag(chunked(Some(mcap::Compression::Zstd)), 40);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cut.mcap");
    // Every offset near the ends (magic, header, footer), every 7th byte elsewhere.
    let offsets = (0..bytes.len()).filter(|&i| i < 200 || i + 200 > bytes.len() || i % 7 == 0);
    for cut in offsets {
        std::fs::write(&path, &bytes[..cut]).unwrap();
        for mode in [ReadMode::Auto, ReadMode::Scan, ReadMode::Full] {
            read_damaged(&path, mode);
        }
    }
}

#[test]
fn flipped_bytes_never_panic() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("flipped.mcap");
    for compression in [
        None,
        Some(mcap::Compression::Zstd),
        Some(mcap::Compression::Lz4),
    ] {
        let original = write_bag(chunked(compression), 40);
        // A fixed xorshift sequence: reproducible, no extra dependency.
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        for _ in 0..400 {
            let mut bytes = original.clone();
            for _ in 0..3 {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                let at = (state % bytes.len() as u64) as usize;
                bytes[at] ^= 1 << (state >> 61);
            }
            std::fs::write(&path, &bytes).unwrap();
            for mode in [ReadMode::Auto, ReadMode::Scan, ReadMode::Full] {
                read_damaged(&path, mode);
            }
        }
    }
}

#[test]
fn huge_length_fields_are_rejected_without_allocating() {
    let mut bytes = write_bag(chunked(Some(mcap::Compression::Zstd)), 10);
    // The first record after the header: make its length 2^63.
    let header_len = u64::from_le_bytes(bytes[9..17].try_into().unwrap()) as usize;
    let second = 8 + 9 + header_len;
    bytes[second + 1..second + 9].copy_from_slice(&(1u64 << 63).to_le_bytes());
    let fixture = store(&bytes);
    let summary = read_mcap(&fixture.path, ReadMode::Scan).unwrap();
    let stopped = summary.stopped.unwrap();
    assert_eq!(stopped.offset, second as u64);
    assert!(
        stopped.message.contains("9223372036854775808"),
        "{}",
        stopped.message
    );
}

#[test]
fn chunk_declaring_a_huge_uncompressed_size_is_skipped_as_damaged() {
    let bytes = write_bag(chunked(Some(mcap::Compression::Zstd)), 10);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bomb.mcap");
    // Find the first chunk record and set its uncompressed_size to u64::MAX.
    let header_len = u64::from_le_bytes(bytes[9..17].try_into().unwrap()) as usize;
    let mut at = 8 + 9 + header_len;
    while bytes[at] != records::op::CHUNK {
        at += 9 + u64::from_le_bytes(bytes[at + 1..at + 9].try_into().unwrap()) as usize;
    }
    let mut damaged = bytes.clone();
    damaged[at + 9 + 16..at + 9 + 24].copy_from_slice(&u64::MAX.to_le_bytes());
    std::fs::write(&path, &damaged).unwrap();
    let summary = read_mcap(&path, ReadMode::Full).unwrap();
    assert_eq!(summary.damaged.len(), 1, "{:?}", summary.damaged);
    assert_eq!(summary.damaged[0].offset, at as u64);
    assert!(summary.message_count < 20);
}

fn all_messages(path: &Path, wanted: Option<&[&str]>) -> CoreResult<Vec<RecordedMessage>> {
    let topics = wanted.map(|w| w.iter().map(|t| (*t).to_string()).collect());
    MessageReader::open(path, topics)?.collect()
}

#[test]
fn messages_of_every_layout_come_with_their_topics_times_and_payloads() {
    let layouts = [
        chunked(None),
        chunked(Some(mcap::Compression::Zstd)),
        chunked(Some(mcap::Compression::Lz4)),
        mcap::WriteOptions::new().use_chunks(false),
    ];
    for options in layouts {
        let fixture = store(&write_bag(options, 50));
        let messages = all_messages(&fixture.path, None).unwrap();
        assert_eq!(messages.len(), 100);
        let chatter: Vec<_> = messages
            .iter()
            .filter(|m| &*m.topic == "/chatter")
            .collect();
        assert_eq!(chatter.len(), 50);
        for (i, message) in chatter.iter().enumerate() {
            assert_eq!(message.log_time, 1_000 + i as u64 * 10);
            assert_eq!(message.data, vec![i as u8; 64]);
        }
    }
}

#[test]
fn messages_within_a_chunk_come_in_log_time_order() {
    let fixture = store(&write_bag(mcap::WriteOptions::new().chunk_size(None), 40));
    let times: Vec<u64> = all_messages(&fixture.path, None)
        .unwrap()
        .iter()
        .map(|m| m.log_time)
        .collect();
    let mut sorted = times.clone();
    sorted.sort_unstable();
    assert_eq!(times, sorted);
}

#[test]
fn a_topic_filter_keeps_only_its_topics() {
    let fixture = store(&write_bag(chunked(Some(mcap::Compression::Zstd)), 30));
    let messages = all_messages(&fixture.path, Some(&["/rosout", "/absent"])).unwrap();
    assert_eq!(messages.len(), 30);
    assert!(messages.iter().all(|m| &*m.topic == "/rosout"));
}

#[test]
fn a_cut_recording_gives_its_messages_then_an_error_naming_the_break() {
    let bytes = write_bag(chunked(Some(mcap::Compression::Lz4)), 200);
    let fixture = store(&bytes[..bytes.len() / 2]);
    let mut reader = MessageReader::open(&fixture.path, None).unwrap();
    let mut read = 0;
    let error = loop {
        match reader.next() {
            Some(Ok(_)) => read += 1,
            Some(Err(error)) => break error,
            None => panic!("a cut file ended without an error"),
        }
    };
    assert!(read > 100, "{read}");
    assert!(error.to_string().contains("cut short"), "{error}");
    assert!(reader.next().is_none());
}

#[test]
fn messages_of_a_file_that_is_not_mcap_are_a_format_error() {
    let fixture = store(b"not an mcap file at all");
    let error = MessageReader::open(&fixture.path, None).err().unwrap();
    assert!(
        matches!(error, CoreError::Format { offset: 0, .. }),
        "{error}"
    );
    assert!(matches!(
        MessageReader::open(Path::new("/no/such.mcap"), None),
        Err(CoreError::NotFound { .. })
    ));
}

#[test]
fn messages_of_cut_or_flipped_files_never_panic() {
    let bytes = write_bag(chunked(Some(mcap::Compression::Zstd)), 40);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("damaged.mcap");
    for cut in (0..bytes.len()).step_by(5) {
        std::fs::write(&path, &bytes[..cut]).unwrap();
        if let Ok(reader) = MessageReader::open(&path, None) {
            for message in reader {
                if let Err(error) = message {
                    assert!(matches!(error, CoreError::Format { .. }), "{error}");
                }
            }
        }
    }
    for at in (8..bytes.len()).step_by(11) {
        let mut flipped = bytes.clone();
        flipped[at] ^= 0x5a;
        std::fs::write(&path, &flipped).unwrap();
        if let Ok(reader) = MessageReader::open(&path, None) {
            for message in reader {
                if let Err(error) = message {
                    assert!(matches!(error, CoreError::Format { .. }), "{error}");
                }
            }
        }
    }
}
