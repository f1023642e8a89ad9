#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use super::*;
use std::fs;

fn data(n: usize, seed: u64) -> Vec<f32> {
    let mut x = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15).wrapping_add(1);
    (0..n)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            ((x >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
        })
        .collect()
}

fn build(n: usize, dim: usize) -> VectorIndex {
    let mut index = VectorIndex::new(dim).unwrap();
    let ids: Vec<i64> = (0..n as i64).map(|i| i * 3 + 1).collect();
    let kinds: Vec<String> = (0..n)
        .map(|i| ["topic", "service", "action"][i % 3].to_owned())
        .collect();
    index
        .add(
            &ids,
            &data(n * dim, 7),
            Tags::PerRow(&kinds),
            Tags::Same("robot"),
        )
        .unwrap();
    index
}

/// Brute force in f64 over the stored vectors: (id, score) best first, ties by id.
fn reference(index: &VectorIndex, query: &[f32], k: usize, kind: Option<&str>) -> Vec<(i64, f64)> {
    let norm: f64 = query
        .iter()
        .map(|x| f64::from(*x).powi(2))
        .sum::<f64>()
        .sqrt();
    let mut all: Vec<(i64, f64)> = index
        .ids()
        .iter()
        .filter(|id| kind.is_none_or(|k| index.get(**id).unwrap().kind == k))
        .map(|id| {
            let v = index.get(*id).unwrap().vector;
            let s = v
                .iter()
                .zip(query)
                .map(|(a, b)| f64::from(*a) * f64::from(*b))
                .sum::<f64>();
            (*id, s / norm)
        })
        .collect();
    all.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    all.truncate(k);
    all
}

fn assert_close(hits: &Hits, expected: &[(i64, f64)]) {
    assert_eq!(hits.k, expected.len());
    for (i, (id, score)) in expected.iter().enumerate() {
        assert!(
            (f64::from(hits.scores[i]) - score).abs() < 1e-5,
            "{i}: {hits:?} {expected:?}"
        );
        // Scores this far apart cannot swap by rounding, so the ids must agree.
        let near = expected
            .iter()
            .any(|(other, s)| other != id && (s - score).abs() < 1e-5);
        if !near {
            assert_eq!(hits.ids[i], *id);
        }
    }
}

#[test]
fn search_equals_brute_force_small_and_parallel() {
    for (n, dim) in [(1, 3), (50, 17), (200, 384), (3000, 64)] {
        let index = build(n, dim);
        for seed in 0..3 {
            let q = data(dim, 100 + seed);
            let hits = index.search(&q, 10, &Filter::default()).unwrap();
            assert_close(&hits, &reference(&index, &q, 10, None));
        }
    }
}

#[test]
fn filter_restricts_to_matching_kinds() {
    let index = build(3000, 64);
    let q = data(64, 5);
    let kinds = vec!["action".to_owned()];
    let filter = Filter {
        kinds: Some(&kinds),
        sources: None,
    };
    let hits = index.search(&q, 7, &filter).unwrap();
    assert_close(&hits, &reference(&index, &q, 7, Some("action")));
    let unknown = vec!["parameter".to_owned()];
    let none = Filter {
        kinds: Some(&unknown),
        sources: None,
    };
    assert_eq!(index.search(&q, 7, &none).unwrap().k, 0);
}

#[test]
fn batch_scores_are_bit_identical_to_single_searches() {
    let index = build(2500, 40);
    let queries = data(40 * 37, 9);
    let kinds = vec!["topic".to_owned(), "action".to_owned()];
    for filter in [
        Filter::default(),
        Filter {
            kinds: Some(&kinds),
            sources: None,
        },
    ] {
        let batch = index.search_batch(&queries, 5, &filter).unwrap();
        assert_eq!((batch.queries, batch.k), (37, 5));
        for (i, q) in queries.chunks(40).enumerate() {
            let single = index.search(q, 5, &filter).unwrap();
            assert_eq!(single.ids, batch.ids[i * 5..i * 5 + 5]);
            let a: Vec<u32> = single.scores.iter().map(|s| s.to_bits()).collect();
            let b: Vec<u32> = batch.scores[i * 5..i * 5 + 5]
                .iter()
                .map(|s| s.to_bits())
                .collect();
            assert_eq!(a, b);
        }
    }
}

#[test]
fn identical_vectors_tie_and_come_back_by_id() {
    let mut index = VectorIndex::new(8).unwrap();
    let v = data(8, 1);
    let many: Vec<f32> = v.iter().cycle().take(8 * 5).copied().collect();
    index
        .add(
            &[50, 10, 40, 20, 30],
            &many,
            Tags::Same("topic"),
            Tags::Same("a"),
        )
        .unwrap();
    let hits = index.search(&v, 3, &Filter::default()).unwrap();
    assert_eq!(hits.ids, vec![10, 20, 30]);
}

#[test]
fn k_larger_than_the_index_returns_everything_and_empty_returns_nothing() {
    let index = build(4, 8);
    assert_eq!(
        index
            .search(&data(8, 2), 100, &Filter::default())
            .unwrap()
            .k,
        4
    );
    let empty = VectorIndex::new(8).unwrap();
    let hits = empty.search(&data(8, 2), 3, &Filter::default()).unwrap();
    assert_eq!((hits.k, hits.ids.len()), (0, 0));
    let batch = empty
        .search_batch(&data(16, 2), 3, &Filter::default())
        .unwrap();
    assert_eq!((batch.queries, batch.k), (2, 0));
}

#[test]
fn bad_arguments_are_refused_with_reasons() {
    let mut index = build(10, 8);
    let err = |r: CoreResult<Hits>| r.unwrap_err().to_string();
    assert!(err(index.search(&data(7, 1), 3, &Filter::default())).contains("dimension 7"));
    assert!(err(index.search(&data(8, 1), 0, &Filter::default())).contains("k must be"));
    assert!(err(index.search(&[0.0; 8], 1, &Filter::default())).contains("all zeros"));
    let mut nan = data(8, 1);
    nan[3] = f32::NAN;
    assert!(err(index.search(&nan, 1, &Filter::default())).contains("position 3"));
    let e = index
        .add(
            &[1000, 1001],
            &[nan.clone(), data(8, 2)].concat(),
            Tags::Same("t"),
            Tags::Same("s"),
        )
        .unwrap_err();
    assert!(e.to_string().contains("vector 0 (id 1000)"), "{e}");
    assert_eq!(index.len(), 10, "a failed add changes nothing");
    let e = index
        .add(&[1], &data(8, 2), Tags::Same("t"), Tags::Same("s"))
        .unwrap_err();
    assert!(e.to_string().contains("already in the index"));
    let e = index
        .add(
            &[7000, 7000],
            &data(16, 2),
            Tags::Same("t"),
            Tags::Same("s"),
        )
        .unwrap_err();
    assert!(e.to_string().contains("given twice"));
    assert!(index.remove(&[1, 99999]).is_err());
    assert_eq!(index.len(), 10, "a failed remove changes nothing");
    assert!(VectorIndex::new(0).is_err());
    let e = index
        .add(&[5000], &data(8, 1), Tags::Same(""), Tags::Same("s"))
        .unwrap_err();
    assert!(e.to_string().contains("kind"));
}

#[test]
fn remove_and_update_keep_search_consistent() {
    let mut index = build(100, 16);
    let removed: Vec<i64> = index.ids().iter().step_by(7).copied().collect();
    index.remove(&removed).unwrap();
    assert_eq!(index.len(), 100 - removed.len());
    for id in &removed {
        assert!(!index.contains(*id).unwrap());
    }
    let target = index.ids()[5];
    let q = data(16, 77);
    index
        .update(&[target], Some(&q), Some(Tags::Same("action")), None)
        .unwrap();
    let hits = index.search(&q, 3, &Filter::default()).unwrap();
    assert_eq!(hits.ids[0], target);
    assert!((hits.scores[0] - 1.0).abs() < 1e-6);
    assert_eq!(index.get(target).unwrap().kind, "action");
    assert_close(&hits, &reference(&index, &q, 3, None));
    assert!(index.update(&[-5], None, None, None).is_err());
}

#[test]
fn save_and_open_round_trip_mapped() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("index.swv");
    let index = build(777, 33);
    index.save(&path).unwrap();
    let opened = VectorIndex::open(&path).unwrap();
    assert!(opened.is_mapped());
    assert_eq!((opened.len(), opened.dim()), (777, 33));
    assert_eq!(opened.ids(), index.ids());
    assert_eq!(opened.kind_names(), index.kind_names());
    let q = data(33, 4);
    assert_eq!(
        opened.search(&q, 9, &Filter::default()).unwrap(),
        index.search(&q, 9, &Filter::default()).unwrap()
    );
    // A change copies the data out of the map; the file stays as it was.
    let mut changed = opened;
    changed.remove(&[1]).unwrap();
    assert!(!changed.is_mapped());
    assert_eq!(VectorIndex::open(&path).unwrap().len(), 777);
    let leftovers: Vec<_> = fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(leftovers.len(), 1, "no temporary file is left behind");
}

#[test]
fn empty_index_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("empty.swv");
    VectorIndex::new(5).unwrap().save(&path).unwrap();
    let opened = VectorIndex::open(&path).unwrap();
    assert_eq!((opened.len(), opened.dim()), (0, 5));
}

fn corrupt(path: &Path, offset: usize) {
    let mut bytes = fs::read(path).unwrap();
    bytes[offset] ^= 0x40;
    fs::write(path, bytes).unwrap();
}

fn format_error(result: CoreResult<impl std::fmt::Debug>) -> (u64, String) {
    match result {
        Err(CoreError::Format {
            offset, message, ..
        }) => (offset, message),
        other => panic!("expected a format error, got {other:?}"),
    }
}

#[test]
fn damaged_files_give_format_errors_naming_the_offset() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("i.swv");
    let index = build(300, 16);
    index.save(&path).unwrap();
    let pristine = fs::read(&path).unwrap();
    let layout = offsets(&index);

    // Foreign file.
    fs::write(&path, b"PK\x03\x04 a zip file, not an index ".repeat(10)).unwrap();
    assert_eq!(format_error(VectorIndex::open(&path)).0, 0);
    // Too short.
    fs::write(&path, b"SWV").unwrap();
    assert!(format_error(VectorIndex::open(&path))
        .1
        .contains("too short"));
    // Truncated.
    fs::write(&path, &pristine[..pristine.len() - 100]).unwrap();
    let (offset, message) = format_error(VectorIndex::open(&path));
    assert!(message.contains("truncated"), "{message}");
    assert_eq!(offset as usize, pristine.len() - 100);
    // A newer version.
    let mut newer = pristine.clone();
    newer[8] = 2;
    fs::write(&path, &newer).unwrap();
    assert!(format_error(VectorIndex::open(&path))
        .1
        .contains("version 2"));
    // A flipped header bit.
    fs::write(&path, &pristine).unwrap();
    corrupt(&path, 17);
    assert_eq!(format_error(VectorIndex::open(&path)).0, 120);
    // A flipped id: caught on open.
    fs::write(&path, &pristine).unwrap();
    corrupt(&path, layout.0 + 8);
    assert!(format_error(VectorIndex::open(&path))
        .1
        .contains("checksum mismatch"));
    // A flipped vector value in a block past the first 4 MiB: open succeeds (the vector
    // payload is verified lazily), but nothing is computed from it.
    let big = build(3000, 384);
    big.save(&path).unwrap();
    let at = offsets(&big).1 + 3000 * 384 * 4 - 100;
    corrupt(&path, at);
    let opened = VectorIndex::open(&path).unwrap();
    let (offset, message) = format_error(opened.search(&data(384, 1), 3, &Filter::default()));
    assert!(message.contains("checksum mismatch"), "{message}");
    assert!(offset as usize <= at && at < offset as usize + (1 << 22));
    assert!(opened.verify().is_err());
    assert!(opened.get(1).is_err());
    let mut opened = opened;
    assert!(
        opened.remove(&[1]).is_err(),
        "a corrupt index is not copied into memory either"
    );
}

/// (start of ids, start of vectors) in the file of `index`.
fn offsets(index: &VectorIndex) -> (usize, usize) {
    let tags = file::encode_tags(index.kind_names(), index.source_names()).unwrap();
    file::file_layout(index.dim(), index.len(), tags.len())
}

#[test]
fn missing_file_and_folder_are_told_apart() {
    assert!(matches!(
        VectorIndex::open(Path::new("/no/such/index.swv")),
        Err(CoreError::NotFound { .. })
    ));
    let dir = tempfile::tempdir().unwrap();
    assert!(matches!(
        VectorIndex::open(dir.path()),
        Err(CoreError::InvalidArgument(_))
    ));
}

/// Vectors in a tight cluster, with exact duplicates: many scores within the 8-bit error,
/// and exact ties, the hardest case for the first pass of single searches.
fn clustered(n: usize, dim: usize, seed: u64) -> Vec<f32> {
    let base = data(dim, seed);
    let noise = data(n * dim, seed + 1);
    let mut out: Vec<f32> = noise
        .chunks(dim)
        .flat_map(|row| base.iter().zip(row).map(|(b, e)| b + 0.01 * e))
        .collect();
    for r in (0..n).step_by(17) {
        let copy: Vec<f32> = out[..dim].to_vec();
        out[r * dim..(r + 1) * dim].copy_from_slice(&copy);
    }
    out
}

#[test]
fn prefiltered_single_search_equals_full_scan_bit_for_bit() {
    let (n, dim) = (5000, 48);
    let mut index = VectorIndex::new(dim).unwrap();
    let ids: Vec<i64> = (0..n as i64).map(|i| (i * 7919) % 100_003).collect();
    let kinds: Vec<String> = (0..n)
        .map(|i| ["topic", "action"][i % 2].to_owned())
        .collect();
    index
        .add(
            &ids,
            &clustered(n, dim, 3),
            Tags::PerRow(&kinds),
            Tags::Same("s"),
        )
        .unwrap();
    let topics = vec!["topic".to_owned()];
    let check = |index: &VectorIndex| {
        for (seed, k) in [(10, 1), (11, 10), (12, 100)] {
            let mut q = clustered(1, dim, 3);
            for (x, e) in q.iter_mut().zip(data(dim, seed)) {
                *x += 0.02 * e;
            }
            for filter in [
                Filter::default(),
                Filter {
                    kinds: Some(&topics),
                    sources: None,
                },
            ] {
                // A batch of one query always takes the full scan.
                let single = index.search(&q, k, &filter).unwrap();
                let full = index.search_batch(&q, k, &filter).unwrap();
                assert_eq!(single.ids, full.ids);
                let a: Vec<u32> = single.scores.iter().map(|s| s.to_bits()).collect();
                let b: Vec<u32> = full.scores.iter().map(|s| s.to_bits()).collect();
                assert_eq!(a, b);
            }
            // The exact duplicate of row 0 at the query's position ties and sorts by id.
            let v0 = index.get(ids[0]).unwrap().vector;
            let hits = index.search(&v0, 5, &Filter::default()).unwrap();
            let mut dups: Vec<i64> = (0..n)
                .step_by(17)
                .map(|r| ids[r])
                .filter(|id| index.contains(*id).unwrap())
                .collect();
            dups.push(ids[0]);
            dups.sort_unstable();
            dups.dedup();
            assert_eq!(hits.ids, dups[..5]);
        }
    };
    check(&index);
    // The 8-bit copy follows every change.
    let gone: Vec<i64> = ids.iter().skip(1).step_by(3).copied().collect();
    index.remove(&gone).unwrap();
    let moved = ids[2];
    index
        .update(&[moved], Some(&data(dim, 99)), None, None)
        .unwrap();
    index
        .add(
            &[1_000_000],
            &clustered(1, dim, 3),
            Tags::Same("topic"),
            Tags::Same("s"),
        )
        .unwrap();
    check(&index);
}

#[test]
fn wide_vectors_beyond_the_stack_buffer_search_correctly() {
    // Queries wider than 1024 are normalised on the heap; 2100 rows take the first pass.
    let index = build(2100, 1500);
    let q = data(1500, 8);
    let single = index.search(&q, 5, &Filter::default()).unwrap();
    assert_close(&single, &reference(&index, &q, 5, None));
    let full = index.search_batch(&q, 5, &Filter::default()).unwrap();
    assert_eq!(single, Hits { queries: 1, ..full });
}

#[test]
fn opened_index_uses_the_saved_8_bit_copy_and_keeps_it_current() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("big.swv");
    let index = build(3000, 24);
    index.save(&path).unwrap();
    let mut opened = VectorIndex::open(&path).unwrap();
    for seed in 0..5 {
        let q = data(24, 300 + seed);
        let hits = opened.search(&q, 7, &Filter::default()).unwrap();
        assert_eq!(hits, index.search(&q, 7, &Filter::default()).unwrap());
    }
    let first: Vec<i64> = opened.ids().iter().take(500).copied().collect();
    opened.remove(&first).unwrap();
    opened
        .add(
            &[-1, -2],
            &data(48, 5),
            Tags::Same("action"),
            Tags::Same("s"),
        )
        .unwrap();
    let update_id = opened.ids()[10];
    opened
        .update(&[update_id], Some(&data(24, 6)), None, None)
        .unwrap();
    for seed in 0..5 {
        let q = data(24, 400 + seed);
        let single = opened.search(&q, 7, &Filter::default()).unwrap();
        let full = opened.search_batch(&q, 7, &Filter::default()).unwrap();
        assert_eq!(single, full);
        assert_close(&single, &reference(&opened, &q, 7, None));
    }
}
