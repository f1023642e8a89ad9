//! The real rosbag2 recordings in `../shared/data/mcap/rosbag2` (written by the C++
//! rosbag2 MCAP plugin): every read mode agrees, and cut or bit-flipped copies never
//! panic. Skipped with a message when the shared data is not beside the repository.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::fs::{self, OpenOptions};
use std::path::{Path, PathBuf};

use skillwright_core::mcap::{read_mcap, McapSummary, ReadMode};
use skillwright_core::CoreError;

fn recordings() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/mcap/rosbag2");
    let mut found = Vec::new();
    let mut pending = vec![root];
    while let Some(dir) = pending.pop() {
        let Ok(entries) = fs::read_dir(&dir) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "mcap") {
                found.push(path);
            }
        }
    }
    found.sort();
    if found.is_empty() {
        eprintln!("skipped: no rosbag2 recordings beside the repository (CI has them)");
    }
    found
}

fn digest(summary: &McapSummary) -> Vec<(String, u64)> {
    summary
        .channels
        .iter()
        .map(|c| (c.topic.clone(), c.message_count))
        .collect()
}

/// Reading must end in a result or a format error; "internal error" means the guard
/// in `read_mcap` caught a panic.
fn read_damaged(path: &Path, mode: ReadMode) -> Option<McapSummary> {
    match read_mcap(path, mode) {
        Ok(summary) => Some(summary),
        Err(CoreError::Format { message, .. }) => {
            assert!(!message.contains("internal error"), "{message}");
            None
        }
        Err(other) => panic!("unexpected error: {other}"),
    }
}

#[test]
fn every_mode_agrees_on_every_recording() {
    for path in recordings() {
        let auto = read_mcap(&path, ReadMode::Auto).unwrap();
        let scan = read_mcap(&path, ReadMode::Scan).unwrap();
        let full = read_mcap(&path, ReadMode::Full).unwrap();
        assert_eq!(digest(&auto), digest(&scan), "{}", path.display());
        assert_eq!(digest(&auto), digest(&full), "{}", path.display());
        assert_eq!(auto.profile.as_deref(), Some("ros2"), "{}", path.display());
        assert!(!auto.is_partial() && !scan.is_partial() && !full.is_partial());
    }
}

#[test]
fn cut_copies_keep_a_prefix_of_the_recording() {
    let dir = tempfile::tempdir().unwrap();
    let cut = dir.path().join("cut.mcap");
    for path in recordings() {
        let whole = read_mcap(&path, ReadMode::Full).unwrap();
        let data = fs::read(&path).unwrap();
        fs::write(&cut, &data).unwrap();
        let file = OpenOptions::new().write(true).open(&cut).unwrap();
        let len = data.len() as u64;
        // Longest first: each cut is a truncate of the previous copy.
        // About 60 cuts spread over the file plus every byte of its last 24 (footer and
        // magic); the Python suite and the in-crate tests cut more densely.
        let step = (len / 60).max(1);
        let mut offsets: Vec<u64> = (0..len).filter(|o| o % step == 0 || o + 24 > len).collect();
        offsets.reverse();
        for offset in offsets {
            file.set_len(offset).unwrap();
            for mode in [ReadMode::Auto, ReadMode::Scan] {
                let Some(summary) = read_damaged(&cut, mode) else {
                    assert!(offset < 8, "only a cut inside the magic is an error");
                    continue;
                };
                let stopped = summary.stopped.as_ref().expect("a cut file is partial");
                assert!(stopped.offset <= offset);
                assert!(summary.message_count <= whole.message_count);
            }
        }
    }
}

#[test]
fn flipped_bits_never_panic() {
    let dir = tempfile::tempdir().unwrap();
    let flipped = dir.path().join("flipped.mcap");
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    for path in recordings() {
        let original = fs::read(&path).unwrap();
        for _ in 0..25 {
            let mut bytes = original.clone();
            for _ in 0..2 {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                let at = (state % bytes.len() as u64) as usize;
                bytes[at] ^= 1 << (state >> 61);
            }
            fs::write(&flipped, &bytes).unwrap();
            for mode in [ReadMode::Auto, ReadMode::Scan, ReadMode::Full] {
                read_damaged(&flipped, mode);
            }
        }
    }
}
