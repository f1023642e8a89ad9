//! Exact top-k with a low-precision first pass: read a quarter of the bytes, then rescore.
//!
//! A single search over a large index is limited by memory bandwidth: each f32 vector is
//! 4 bytes per dimension. This module keeps an 8-bit copy of every vector, with, per row,
//! the step of its codes and an upper bound of its rounding error (`‖v - v̂‖`). A first
//! pass scores the query (quantised to 16 bits, again with a known error) against the
//! codes in integer arithmetic, which gives each row an interval that certainly contains
//! its f32 score (see `bound`). Any row whose upper end is below the k-th largest lower end
//! cannot be in the top k: at least k rows score at least that much. The rest, usually a
//! few dozen, are rescored with the same f32 kernel as a full scan, so the result, ties
//! included, is bit for bit the one a full scan returns: this is an exact search.
//!
//! The 8-bit copy (a quarter of the vectors' size) is built on the first search that needs
//! it, saved with the index (so an opened index maps it like the vectors) and kept up to
//! date by every change.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rayon::prelude::*;

use super::column::Column;

/// Largest dimension for which the integer dot products are guaranteed not to overflow
/// with a useful query precision; larger indexes always take the full scan.
pub(crate) const MAX_DIM: usize = 8192;

/// The 8-bit copy of the rows of an index (owned, or mapped from a saved index).
#[derive(Debug)]
pub(crate) struct Quantized {
    dim: usize,
    codes: Column<i8>,
    /// Per row: the value of one code step.
    step: Column<f32>,
    /// Per row: an upper bound of the Euclidean norm of `v - codes * step`.
    error: Column<f32>,
}

#[inline(always)]
fn quantize_row(v: &[f32], codes: &mut [i8]) -> (f32, f32) {
    let max = v.iter().fold(0.0f64, |m, x| m.max(f64::from(x.abs())));
    if max == 0.0 {
        codes.fill(0);
        return (0.0, 0.0);
    }
    let step = (max / 127.0) as f32;
    let s = f64::from(step);
    let inv = 1.0 / s;
    // Four partial sums: one running sum made this loop wait on each addition.
    let mut err2 = [0.0f64; 4];
    for (cs, xs) in codes.chunks_mut(4).zip(v.chunks(4)) {
        for ((c, x), e) in cs.iter_mut().zip(xs).zip(err2.iter_mut()) {
            // Rounding by adding a half and truncating (`f64::round` is a library call on
            // the baseline target). An off-by-one code at an exact half would only loosen
            // the bound a little: the bound is measured from the codes actually chosen.
            let y = f64::from(*x) * inv;
            let code = ((y + 0.5f64.copysign(y)) as i32).clamp(-127, 127);
            *c = code as i8;
            let diff = f64::from(*x) - f64::from(code) * s;
            *e += diff * diff;
        }
    }
    let err2: f64 = err2.iter().sum();
    // Rounded up generously: the bound must hold, a slightly looser one costs nothing.
    (step, (err2.sqrt() * (1.0 + 1e-6) + 1e-12) as f32)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn quantize_row_avx2(v: &[f32], codes: &mut [i8]) -> (f32, f32) {
    quantize_row(v, codes)
}

/// `quantize_row`, compiled for AVX2 where the CPU has it (the same arithmetic, wider).
fn quantize_row_fast(v: &[f32], codes: &mut [i8]) -> (f32, f32) {
    #[cfg(target_arch = "x86_64")]
    {
        if super::kernel::has_avx2() {
            #[allow(unsafe_code)]
            // SAFETY: `has_avx2` returned true only after the CPU reported AVX2 and FMA.
            return unsafe { quantize_row_avx2(v, codes) };
        }
    }
    quantize_row(v, codes)
}

impl Quantized {
    pub(crate) fn build(vectors: &[f32], dim: usize) -> Self {
        let rows = vectors.len() / dim;
        let mut codes = vec![0i8; rows * dim];
        let per_row: Vec<(f32, f32)> = codes
            .par_chunks_mut(dim)
            .zip(vectors.par_chunks(dim))
            .with_min_len(256)
            .map(|(codes, v)| quantize_row_fast(v, codes))
            .collect();
        let (step, error) = per_row.into_iter().unzip();
        Quantized {
            dim,
            codes: Column::Owned(codes),
            step: Column::Owned(step),
            error: Column::Owned(error),
        }
    }

    /// The copy saved with an index (see `file`).
    pub(crate) fn from_columns(
        dim: usize,
        codes: Column<i8>,
        step: Column<f32>,
        error: Column<f32>,
    ) -> Self {
        Quantized {
            dim,
            codes,
            step,
            error,
        }
    }

    pub(crate) fn codes(&self) -> &[i8] {
        self.codes.as_slice()
    }

    pub(crate) fn steps(&self) -> &[f32] {
        self.step.as_slice()
    }

    pub(crate) fn errors(&self) -> &[f32] {
        self.error.as_slice()
    }

    pub(crate) fn push_rows(&mut self, vectors: &[f32]) {
        let dim = self.dim;
        for v in vectors.chunks_exact(dim) {
            let codes = self.codes.to_mut();
            let start = codes.len();
            codes.resize(start + dim, 0);
            let (step, error) = quantize_row(v, codes.get_mut(start..).unwrap_or(&mut []));
            self.step.to_mut().push(step);
            self.error.to_mut().push(error);
        }
    }

    pub(crate) fn set_row(&mut self, row: usize, v: &[f32]) {
        let dim = self.dim;
        if let Some(codes) = self.codes.to_mut().get_mut(row * dim..(row + 1) * dim) {
            let (step, error) = quantize_row(v, codes);
            if let Some(s) = self.step.to_mut().get_mut(row) {
                *s = step;
            }
            if let Some(e) = self.error.to_mut().get_mut(row) {
                *e = error;
            }
        }
    }

    /// Mirrors the index's removal: the last row moves into `row`.
    pub(crate) fn swap_remove(&mut self, row: usize) {
        let dim = self.dim;
        let Some(last) = self.step.as_slice().len().checked_sub(1) else {
            return;
        };
        let codes = self.codes.to_mut();
        if row != last {
            codes.copy_within(last * dim..(last + 1) * dim, row * dim);
        }
        codes.truncate(last * dim);
        self.step.to_mut().swap_remove(row);
        self.error.to_mut().swap_remove(row);
    }
}

/// The query in 16-bit codes, with the value of a step and the norm of its rounding error.
pub(crate) struct Query {
    codes: Vec<i16>,
    step: f64,
    error: f64,
    /// Bound of how far an f32 dot product of two unit vectors of this dimension can be
    /// from the real one: recursive summation error, `d * 2^-24` per unit of `Σ|q_i v_i|`
    /// (which is at most 1 here), doubled for margin.
    slack: f64,
}

impl Query {
    pub(crate) fn new(q: &[f32]) -> Self {
        let dim = q.len();
        // Largest code such that no partial sum of `dim` products with 8-bit codes can
        // overflow an i32.
        let limit = (f64::from(i32::MAX) / (dim.max(1) as f64 * 127.0))
            .min(32767.0)
            .floor();
        let max = q.iter().fold(0.0f64, |m, x| m.max(f64::from(x.abs())));
        let step = if max == 0.0 { 1.0 } else { max / limit };
        let mut err2 = 0.0f64;
        let codes = q
            .iter()
            .map(|x| {
                let code = (f64::from(*x) / step).round().clamp(-limit, limit);
                let diff = f64::from(*x) - code * step;
                err2 += diff * diff;
                code as i16
            })
            .collect();
        Query {
            codes,
            step,
            error: err2.sqrt() * (1.0 + 1e-9),
            slack: (dim as f64 + 8.0) * f64::from(f32::EPSILON),
        }
    }
}

/// What one part of the first pass found: the k largest lower bounds it saw and the rows
/// that may still belong to the top k.
pub(crate) struct Part {
    lowers: BinaryHeap<Reverse<Bound>>,
    candidates: Vec<(u32, f64)>,
}

/// A bound ordered by `total_cmp` (the values are finite).
#[derive(Clone, Copy)]
struct Bound(f64);
impl Ord for Bound {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}
impl PartialOrd for Bound {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl PartialEq for Bound {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other).is_eq()
    }
}
impl Eq for Bound {}

#[inline(always)]
fn int_dot(a: &[i8], b: &[i16]) -> i32 {
    // Integer sums may be reordered freely, so LLVM vectorises this with wide multiply-adds.
    a.iter()
        .zip(b)
        .map(|(x, y)| i32::from(*x) * i32::from(*y))
        .sum()
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use std::arch::x86_64::{
        __m128i, __m256i, _mm256_add_epi32, _mm256_cvtepi8_epi16, _mm256_madd_epi16,
        _mm256_setzero_si256,
    };

    /// `int_dot` with explicit 256-bit multiply-adds (LLVM chose 128-bit ones).
    #[target_feature(enable = "avx2,fma")]
    #[inline]
    pub(super) fn int_dot(a: &[i8], b: &[i16]) -> i32 {
        let mut acc = _mm256_setzero_si256();
        let ca = a.chunks_exact(16);
        let cb = b.chunks_exact(16);
        let tail = super::int_dot(ca.remainder(), cb.remainder());
        for (x, y) in ca.zip(cb) {
            let x: [i8; 16] = x.try_into().unwrap_or([0; 16]);
            let y: [i16; 16] = y.try_into().unwrap_or([0; 16]);
            let x: __m128i = bytemuck::cast(x);
            let y: __m256i = bytemuck::cast(y);
            acc = _mm256_add_epi32(acc, _mm256_madd_epi16(_mm256_cvtepi8_epi16(x), y));
        }
        let lanes: [i32; 8] = bytemuck::cast(acc);
        lanes.iter().fold(tail, |s, x| s.wrapping_add(*x))
    }
}

#[inline(always)]
fn first_pass_impl<I: Iterator<Item = usize>, D: Fn(&[i8], &[i16]) -> i32>(
    quant: &Quantized,
    query: &Query,
    rows: I,
    k: usize,
    int_dot: D,
) -> Part {
    let dim = quant.dim;
    let (all_codes, steps, errors) = (quant.codes(), quant.steps(), quant.errors());
    let mut lowers: BinaryHeap<Reverse<Bound>> = BinaryHeap::with_capacity(k + 1);
    let mut threshold = f64::NEG_INFINITY;
    let mut candidates = Vec::new();
    for r in rows {
        let codes = all_codes.get(r * dim..(r + 1) * dim).unwrap_or(&[]);
        let step = f64::from(steps.get(r).copied().unwrap_or(0.0));
        let error = f64::from(errors.get(r).copied().unwrap_or(f32::INFINITY));
        let approx = f64::from(int_dot(codes, &query.codes)) * step * query.step;
        // |q·v - approx| <= |q·(v - v̂)| + |(q - q̂)·v̂| <= ‖v - v̂‖·‖q‖ + ‖q - q̂‖·‖v̂‖,
        // with ‖q‖, ‖v‖ = 1 (to f32 rounding) and ‖v̂‖ <= 1 + ‖v - v̂‖; plus the f32 slack.
        let bound = error * (1.0 + 1e-6) + query.error * (1.0 + error) + query.slack;
        // A bound that is not a number (only a damaged file could hold one) rules nothing out.
        let (low, high) = if bound.is_finite() && approx.is_finite() {
            (approx - bound, approx + bound)
        } else {
            (f64::NEG_INFINITY, f64::INFINITY)
        };
        if lowers.len() < k {
            lowers.push(Reverse(Bound(low)));
            if lowers.len() == k {
                threshold = lowers.peek().map_or(f64::NEG_INFINITY, |b| b.0 .0);
            }
        } else if low > threshold {
            if let Some(mut top) = lowers.peek_mut() {
                *top = Reverse(Bound(low));
            }
            threshold = lowers.peek().map_or(f64::NEG_INFINITY, |b| b.0 .0);
        }
        if high >= threshold {
            candidates.push((r as u32, high));
            if candidates.len() > 4 * k + 4096 {
                candidates.retain(|c| c.1 >= threshold);
            }
        }
    }
    Part { lowers, candidates }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn first_pass_avx2<I: Iterator<Item = usize>>(
    quant: &Quantized,
    query: &Query,
    rows: I,
    k: usize,
) -> Part {
    first_pass_impl(quant, query, rows, k, |a, b| avx2::int_dot(a, b))
}

/// Scores `rows` in 8 bits; see the module documentation.
pub(crate) fn first_pass<I: Iterator<Item = usize>>(
    quant: &Quantized,
    query: &Query,
    rows: I,
    k: usize,
) -> Part {
    #[cfg(target_arch = "x86_64")]
    {
        if super::kernel::has_avx2() {
            #[allow(unsafe_code)]
            // SAFETY: `has_avx2` returned true only after the CPU reported AVX2 and FMA.
            return unsafe { first_pass_avx2(quant, query, rows, k) };
        }
    }
    first_pass_impl(quant, query, rows, k, int_dot)
}

/// Rows that may belong to the top k, in ascending order, given every part's findings.
pub(crate) fn survivors(parts: Vec<Part>, k: usize) -> Vec<usize> {
    let mut all_lowers: Vec<f64> = parts
        .iter()
        .flat_map(|p| p.lowers.iter().map(|b| b.0 .0))
        .collect();
    all_lowers.sort_unstable_by(|a, b| b.total_cmp(a));
    let threshold = if all_lowers.len() >= k {
        all_lowers.get(k - 1).copied().unwrap_or(f64::NEG_INFINITY)
    } else {
        f64::NEG_INFINITY
    };
    let mut rows: Vec<usize> = parts
        .into_iter()
        .flat_map(|p| p.candidates)
        .filter(|c| c.1 >= threshold)
        .map(|c| c.0 as usize)
        .collect();
    rows.sort_unstable();
    rows
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn row_error_bound_holds_and_is_small() {
        let v: Vec<f32> = (0..384)
            .map(|i| ((i * 37 % 101) as f32 - 50.0) / 290.0)
            .collect();
        let norm = v.iter().map(|x| x * x).sum::<f32>().sqrt();
        let v: Vec<f32> = v.iter().map(|x| x / norm).collect();
        let mut codes = vec![0i8; 384];
        let (step, error) = quantize_row(&v, &mut codes);
        let real: f64 = v
            .iter()
            .zip(&codes)
            .map(|(x, c)| (f64::from(*x) - f64::from(*c) * f64::from(step)).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(real <= f64::from(error));
        assert!(error < 0.02, "{error}");
    }

    #[test]
    fn query_codes_cannot_overflow_for_the_largest_dimension() {
        let q = vec![1.0f32; MAX_DIM];
        let query = Query::new(&q);
        let codes = vec![127i8; MAX_DIM];
        let exact: i64 = codes
            .iter()
            .zip(&query.codes)
            .map(|(a, b)| i64::from(*a) * i64::from(*b))
            .sum();
        assert!(exact <= i64::from(i32::MAX));
        assert_eq!(i64::from(int_dot(&codes, &query.codes)), exact);
    }

    #[test]
    fn vector_integer_dot_equals_the_plain_one() {
        #[cfg(target_arch = "x86_64")]
        if super::super::kernel::has_avx2() {
            for len in [0, 5, 16, 31, 384, 1000] {
                let a: Vec<i8> = (0..len).map(|i| ((i * 73) % 255) as i8).collect();
                let b: Vec<i16> = (0..len)
                    .map(|i| ((i * 7919) % 20000) as i16 - 10000)
                    .collect();
                #[allow(unsafe_code)]
                // SAFETY: the CPU reported AVX2 and FMA.
                let fast = unsafe { avx2::int_dot(&a, &b) };
                assert_eq!(fast, int_dot(&a, &b), "{len}");
            }
        }
    }
}
