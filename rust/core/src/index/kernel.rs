//! Scoring loops: dot products of stored rows with queries, fed into `TopK`.
//!
//! Two builds of the loops, chosen once per process after a CPU check, so a shipped
//! build stays portable and needs no `-C target-cpu`: plain Rust that LLVM vectorises
//! for the baseline target (16 lane accumulators, a scalar tail, a fixed-order sum), and
//! explicit AVX2 + FMA vectors (`avx2`). Within a build, every (row, query) pair is summed
//! in the same order in the single-query, four-row and four-query loops, so a batch
//! search returns bit-identical scores to the single searches it replaces, and identical
//! rows always tie exactly (then the lower id wins, see `TopK`). Single queries score four
//! rows per pass (one query load for four rows); batches score four queries per row.

use std::sync::OnceLock;

use super::topk::TopK;

const LANES: usize = 16;

/// How one multiply-add step is done: fused on CPUs that have FMA, two roundings otherwise.
trait Mac {
    fn mac(acc: f32, a: f32, b: f32) -> f32;
}

struct Plain;
impl Mac for Plain {
    #[inline(always)]
    fn mac(acc: f32, a: f32, b: f32) -> f32 {
        acc + a * b
    }
}

#[inline(always)]
fn reduce(acc: &[f32; LANES], tail: f32) -> f32 {
    // A left-to-right sum: a fixed order like any other, and a pairwise tree here led
    // LLVM's SLP vectoriser to narrow the whole loop to 128-bit vectors.
    acc.iter().sum::<f32>() + tail
}

/// Views a `chunks_exact(LANES)` item as an array: with a length known at compile time
/// LLVM emits full-width vector code (with plain slices it fell back to 4-wide or scalar).
#[inline(always)]
fn arr(chunk: &[f32]) -> Option<&[f32; LANES]> {
    chunk.try_into().ok()
}

#[inline(always)]
fn lanes<M: Mac>(acc: &mut [f32; LANES], x: &[f32; LANES], y: &[f32; LANES]) {
    for ((a, xv), yv) in acc.iter_mut().zip(x).zip(y) {
        *a = M::mac(*a, *xv, *yv);
    }
}

#[inline(always)]
fn dot<M: Mac>(a: &[f32], b: &[f32]) -> f32 {
    let mut acc = [0.0f32; LANES];
    let ca = a.chunks_exact(LANES);
    let cb = b.chunks_exact(LANES);
    let (ta, tb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        let (Some(x), Some(y)) = (arr(x), arr(y)) else {
            continue;
        };
        lanes::<M>(&mut acc, x, y);
    }
    let mut tail = 0.0f32;
    for (x, y) in ta.iter().zip(tb) {
        tail = M::mac(tail, *x, *y);
    }
    reduce(&acc, tail)
}

/// One row against four queries: the row is loaded once for all four.
#[inline(always)]
fn dot4<M: Mac>(row: &[f32], q: [&[f32]; 4]) -> [f32; 4] {
    let mut acc = [[0.0f32; LANES]; 4];
    let c = row.chunks_exact(LANES);
    let c0 = q[0].chunks_exact(LANES);
    let c1 = q[1].chunks_exact(LANES);
    let c2 = q[2].chunks_exact(LANES);
    let c3 = q[3].chunks_exact(LANES);
    let tails = [
        c.remainder(),
        c0.remainder(),
        c1.remainder(),
        c2.remainder(),
        c3.remainder(),
    ];
    for ((((x, y0), y1), y2), y3) in c.zip(c0).zip(c1).zip(c2).zip(c3) {
        let (Some(x), Some(y0), Some(y1), Some(y2), Some(y3)) =
            (arr(x), arr(y0), arr(y1), arr(y2), arr(y3))
        else {
            continue;
        };
        let [a0, a1, a2, a3] = &mut acc;
        lanes::<M>(a0, x, y0);
        lanes::<M>(a1, x, y1);
        lanes::<M>(a2, x, y2);
        lanes::<M>(a3, x, y3);
    }
    let mut out = [0.0f32; 4];
    for (j, o) in out.iter_mut().enumerate() {
        let mut tail = 0.0f32;
        for (x, y) in tails[0].iter().zip(tails[j + 1]) {
            tail = M::mac(tail, *x, *y);
        }
        *o = reduce(&acc[j], tail);
    }
    out
}

#[inline(always)]
fn row(vectors: &[f32], dim: usize, r: usize) -> &[f32] {
    vectors.get(r * dim..(r + 1) * dim).unwrap_or(&[])
}

#[inline(always)]
fn id_of(ids: &[i64], r: usize) -> i64 {
    ids.get(r).copied().unwrap_or(i64::MAX)
}

#[inline(always)]
fn scan_impl<M: Mac, I: Iterator<Item = usize>>(
    vectors: &[f32],
    dim: usize,
    ids: &[i64],
    rows: I,
    query: &[f32],
    top: &mut TopK,
) {
    for r in rows {
        top.push(dot::<M>(row(vectors, dim, r), query), id_of(ids, r));
    }
}

#[inline(always)]
fn tile_impl<M: Mac, I: Iterator<Item = usize> + Clone>(
    vectors: &[f32],
    dim: usize,
    ids: &[i64],
    rows: I,
    queries: &[&[f32]],
    tops: &mut [TopK],
) {
    let mut qs = queries.chunks_exact(4);
    let mut ts = tops.chunks_exact_mut(4);
    for (q, t) in (&mut qs).zip(&mut ts) {
        let (q, [t0, t1, t2, t3]) = ([q[0], q[1], q[2], q[3]], t) else {
            continue;
        };
        for r in rows.clone() {
            let s = dot4::<M>(row(vectors, dim, r), q);
            let id = id_of(ids, r);
            t0.push(s[0], id);
            t1.push(s[1], id);
            t2.push(s[2], id);
            t3.push(s[3], id);
        }
    }
    for (q, t) in qs.remainder().iter().zip(ts.into_remainder()) {
        scan_impl::<M, I>(vectors, dim, ids, rows.clone(), q, t);
    }
}

/// The same loops with AVX2 + FMA, written with explicit 256-bit vectors: LLVM's
/// auto-vectoriser kept narrowing the multi-row and multi-query loops to 128 bits.
///
/// Per (row, query) pair the order of operations is the same in every function here:
/// two 8-lane accumulators over 16-float chunks (low and high half), a scalar fused tail,
/// then `finish`. So one row scored alone, with three other rows, or against four
/// queries gives the same bits.
#[cfg(target_arch = "x86_64")]
mod avx2 {
    use std::arch::x86_64::{__m256, _mm256_add_ps, _mm256_fmadd_ps, _mm256_setzero_ps};

    use super::{id_of, row, TopK, LANES};

    /// A 16-float chunk as two vectors (a plain unaligned load).
    #[inline(always)]
    fn halves(chunk: &[f32]) -> [__m256; 2] {
        let array: [f32; LANES] = chunk.try_into().unwrap_or([0.0; LANES]);
        bytemuck::cast(array)
    }

    #[target_feature(enable = "avx2,fma")]
    #[inline]
    fn tail(x: &[f32], y: &[f32]) -> f32 {
        let mut t = 0.0f32;
        for (a, b) in x.iter().zip(y) {
            t = a.mul_add(*b, t);
        }
        t
    }

    #[target_feature(enable = "avx2,fma")]
    #[inline]
    fn finish(acc: [__m256; 2], tail: f32) -> f32 {
        let lanes: [f32; 8] = bytemuck::cast(_mm256_add_ps(acc[0], acc[1]));
        lanes.iter().sum::<f32>() + tail
    }

    /// `one` against each of `others` (four rows against a query, or a row against four
    /// queries); the query for one reuses its loads across the others.
    #[target_feature(enable = "avx2,fma")]
    #[inline]
    fn dot_n<const N: usize>(one: &[f32], others: [&[f32]; N]) -> [f32; N] {
        let mut acc = [[_mm256_setzero_ps(); 2]; N];
        let mut chunks = others.map(|o| o.chunks_exact(LANES));
        let ones = one.chunks_exact(LANES);
        let one_tail = ones.remainder();
        for y in ones {
            let [yl, yh] = halves(y);
            for (a, c) in acc.iter_mut().zip(chunks.iter_mut()) {
                let [xl, xh] = halves(c.next().unwrap_or(&[]));
                a[0] = _mm256_fmadd_ps(xl, yl, a[0]);
                a[1] = _mm256_fmadd_ps(xh, yh, a[1]);
            }
        }
        let mut out = [0.0f32; N];
        for ((o, a), c) in out.iter_mut().zip(acc).zip(&chunks) {
            *o = finish(a, tail(c.remainder(), one_tail));
        }
        out
    }

    #[target_feature(enable = "avx2,fma")]
    pub(super) fn scan<I: Iterator<Item = usize>>(
        vectors: &[f32],
        dim: usize,
        ids: &[i64],
        rows: I,
        query: &[f32],
        top: &mut TopK,
    ) {
        let mut group = [0usize; 4];
        let mut filled = 0;
        for r in rows {
            if let Some(slot) = group.get_mut(filled) {
                *slot = r;
            }
            filled += 1;
            if filled == 4 {
                let s = dot_n(query, group.map(|r| row(vectors, dim, r)));
                for (score, r) in s.into_iter().zip(group) {
                    top.push(score, id_of(ids, r));
                }
                filled = 0;
            }
        }
        for r in group.into_iter().take(filled) {
            let [score] = dot_n(query, [row(vectors, dim, r)]);
            top.push(score, id_of(ids, r));
        }
    }

    #[target_feature(enable = "avx2,fma")]
    pub(super) fn tile<I: Iterator<Item = usize> + Clone>(
        vectors: &[f32],
        dim: usize,
        ids: &[i64],
        rows: I,
        queries: &[&[f32]],
        tops: &mut [TopK],
    ) {
        let mut qs = queries.chunks_exact(4);
        let mut ts = tops.chunks_exact_mut(4);
        for (q, t) in (&mut qs).zip(&mut ts) {
            let (Ok(q), [t0, t1, t2, t3]) = (<[&[f32]; 4]>::try_from(q), t) else {
                continue;
            };
            for r in rows.clone() {
                let s = dot_n(row(vectors, dim, r), q);
                let id = id_of(ids, r);
                t0.push(s[0], id);
                t1.push(s[1], id);
                t2.push(s[2], id);
                t3.push(s[3], id);
            }
        }
        for (q, t) in qs.remainder().iter().zip(ts.into_remainder()) {
            scan(vectors, dim, ids, rows.clone(), q, t);
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Isa {
    Baseline,
    #[cfg(target_arch = "x86_64")]
    Avx2Fma,
}

fn isa() -> Isa {
    static ISA: OnceLock<Isa> = OnceLock::new();
    *ISA.get_or_init(|| {
        #[cfg(target_arch = "x86_64")]
        {
            if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
                return Isa::Avx2Fma;
            }
        }
        Isa::Baseline
    })
}

/// Whether the AVX2 + FMA loops are in use (for other modules' own AVX2 builds).
#[cfg(target_arch = "x86_64")]
pub(crate) fn has_avx2() -> bool {
    isa() == Isa::Avx2Fma
}

/// Name of the instruction set the scoring loops run with on this CPU (for benchmarks).
pub fn isa_name() -> &'static str {
    match isa() {
        Isa::Baseline => "baseline",
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2Fma => "avx2+fma",
    }
}

/// Scores `query` against `rows` of the row-major `vectors` (each `dim` long) into `top`.
pub(crate) fn scan<I: Iterator<Item = usize>>(
    vectors: &[f32],
    dim: usize,
    ids: &[i64],
    rows: I,
    query: &[f32],
    top: &mut TopK,
) {
    match isa() {
        #[cfg(target_arch = "x86_64")]
        #[allow(unsafe_code)]
        // SAFETY: `isa()` returns Avx2Fma only after the CPU reported AVX2 and FMA.
        Isa::Avx2Fma => unsafe { avx2::scan(vectors, dim, ids, rows, query, top) },
        Isa::Baseline => scan_impl::<Plain, I>(vectors, dim, ids, rows, query, top),
    }
}

/// Scores several queries against the same `rows`; `tops[i]` collects the hits of
/// `queries[i]`. Rows are read once per four queries.
pub(crate) fn tile<I: Iterator<Item = usize> + Clone>(
    vectors: &[f32],
    dim: usize,
    ids: &[i64],
    rows: I,
    queries: &[&[f32]],
    tops: &mut [TopK],
) {
    match isa() {
        #[cfg(target_arch = "x86_64")]
        #[allow(unsafe_code)]
        // SAFETY: `isa()` returns Avx2Fma only after the CPU reported AVX2 and FMA.
        Isa::Avx2Fma => unsafe { avx2::tile(vectors, dim, ids, rows, queries, tops) },
        Isa::Baseline => tile_impl::<Plain, I>(vectors, dim, ids, rows, queries, tops),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn data(n: usize, seed: u32) -> Vec<f32> {
        // A small deterministic generator is enough to exercise the loops.
        let mut x = seed.wrapping_mul(2654435761).wrapping_add(1);
        (0..n)
            .map(|_| {
                x ^= x << 13;
                x ^= x >> 17;
                x ^= x << 5;
                (x % 2001) as f32 / 1000.0 - 1.0
            })
            .collect()
    }

    #[test]
    fn dot_matches_f64_reference_for_awkward_lengths() {
        for len in [0, 1, 7, 15, 16, 17, 33, 384, 385] {
            let a = data(len, 1);
            let b = data(len, 2);
            let exact: f64 = a.iter().zip(&b).map(|(x, y)| *x as f64 * *y as f64).sum();
            let got = dot::<Plain>(&a, &b) as f64;
            assert!((got - exact).abs() < 1e-4 * (1.0 + exact.abs()), "{len}");
        }
    }

    #[test]
    fn four_query_kernel_is_bit_identical_to_single_dot() {
        for dim in [1, 5, 16, 31, 64, 100] {
            let r = data(dim, 3);
            let qs: Vec<Vec<f32>> = (0..4).map(|i| data(dim, 10 + i)).collect();
            let four = dot4::<Plain>(&r, [&qs[0], &qs[1], &qs[2], &qs[3]]);
            for j in 0..4 {
                assert_eq!(four[j].to_bits(), dot::<Plain>(&r, &qs[j]).to_bits());
            }
        }
    }

    #[test]
    fn tile_and_scan_agree_on_every_query() {
        let dim = 37;
        let n = 50;
        let vectors = data(n * dim, 4);
        let ids: Vec<i64> = (0..n as i64).rev().collect();
        let queries: Vec<Vec<f32>> = (0..7).map(|i| data(dim, 20 + i)).collect();
        let refs: Vec<&[f32]> = queries.iter().map(|q| q.as_slice()).collect();
        let mut tops: Vec<TopK> = (0..7).map(|_| TopK::new(5)).collect();
        tile(&vectors, dim, &ids, 0..n, &refs, &mut tops);
        for (q, t) in queries.iter().zip(tops) {
            let mut single = TopK::new(5);
            scan(&vectors, dim, &ids, 0..n, q, &mut single);
            let a: Vec<(u32, i64)> = t
                .into_sorted()
                .iter()
                .map(|h| (h.score.to_bits(), h.id))
                .collect();
            let b: Vec<(u32, i64)> = single
                .into_sorted()
                .iter()
                .map(|h| (h.score.to_bits(), h.id))
                .collect();
            assert_eq!(a, b);
        }
    }
}
