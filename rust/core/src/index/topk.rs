//! Bounded selection of the best `k` hits, ordered by score (high first) then id (low first).

use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// One scored row. Its `Ord` puts the *worse* hit first, so a max-heap keeps the worst
/// of the current best `k` on top, where it is cheap to compare against and replace.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Hit {
    pub(crate) score: f32,
    pub(crate) id: i64,
}

impl Ord for Hit {
    fn cmp(&self, other: &Self) -> Ordering {
        // Lower score is worse; at equal score the higher id is worse, which makes the
        // order of ties deterministic and independent of row order or thread split.
        other
            .score
            .total_cmp(&self.score)
            .then_with(|| self.id.cmp(&other.id))
    }
}

impl PartialOrd for Hit {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for Hit {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Hit {}

/// The best `k` hits seen so far.
#[derive(Debug)]
pub(crate) struct TopK {
    k: usize,
    heap: BinaryHeap<Hit>,
    /// Score of the worst kept hit once `k` are kept: anything below it is rejected
    /// with one comparison, which is the common case in a long scan.
    floor: f32,
}

impl TopK {
    pub(crate) fn new(k: usize) -> Self {
        TopK {
            k,
            heap: BinaryHeap::with_capacity(k.saturating_add(1).min(1 << 16)),
            floor: f32::NEG_INFINITY,
        }
    }

    #[inline(always)]
    pub(crate) fn push(&mut self, score: f32, id: i64) {
        // `+ 0.0` turns -0.0 into +0.0 so that both zeros tie (and fall back to the id)
        // instead of ranking by sign bit, as `total_cmp` alone would.
        let score = score + 0.0;
        if self.heap.len() < self.k {
            self.heap.push(Hit { score, id });
            if self.heap.len() == self.k {
                self.floor = self.heap.peek().map_or(f32::NEG_INFINITY, |h| h.score);
            }
            return;
        }
        if score < self.floor {
            return;
        }
        let hit = Hit { score, id };
        if let Some(mut worst) = self.heap.peek_mut() {
            if hit < *worst {
                *worst = hit;
            }
        }
        self.floor = self.heap.peek().map_or(f32::NEG_INFINITY, |h| h.score);
    }

    /// Adds every hit of `other` (the result of another part of the same scan).
    pub(crate) fn merge(&mut self, other: TopK) {
        for hit in other.heap {
            self.push(hit.score, hit.id);
        }
    }

    /// The kept hits, best first.
    pub(crate) fn into_sorted(self) -> Vec<Hit> {
        // `into_sorted_vec` sorts ascending by `Ord`, and `Ord` ranks better hits lower.
        self.heap.into_sorted_vec()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ids(top: TopK) -> Vec<i64> {
        top.into_sorted().iter().map(|h| h.id).collect()
    }

    #[test]
    fn keeps_the_highest_scores_best_first() {
        let mut top = TopK::new(2);
        for (score, id) in [(0.1, 1), (0.9, 2), (0.5, 3), (0.7, 4)] {
            top.push(score, id);
        }
        assert_eq!(ids(top), vec![2, 4]);
    }

    #[test]
    fn ties_are_broken_by_lower_id_whatever_the_arrival_order() {
        let mut top = TopK::new(2);
        for id in [9, 3, 7, 1, 5] {
            top.push(0.5, id);
        }
        assert_eq!(ids(top), vec![1, 3]);
    }

    #[test]
    fn negative_zero_ties_with_positive_zero() {
        let mut top = TopK::new(1);
        top.push(0.0, 5);
        top.push(-0.0, 2);
        assert_eq!(ids(top), vec![2]);
    }

    #[test]
    fn merging_parts_equals_one_scan() {
        let scores: Vec<(f32, i64)> = (0..100).map(|i| (((i * 37) % 11) as f32, i)).collect();
        let mut whole = TopK::new(7);
        let mut a = TopK::new(7);
        let mut b = TopK::new(7);
        for (n, (s, id)) in scores.iter().enumerate() {
            whole.push(*s, *id);
            if n % 3 == 0 {
                a.push(*s, *id);
            } else {
                b.push(*s, *id);
            }
        }
        a.merge(b);
        assert_eq!(ids(a), ids(whole));
    }
}
