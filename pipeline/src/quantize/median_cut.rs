//! Heckbert's median cut (1982) as ppmquant does it, for normals (Tarini §4 quantizes the
//! normal map with "standard image processing software").
//!
//! Like ppmquant, the cut works on the *histogram* of the map: its distinct normals with
//! their texel counts. Starting from one box holding all of them, repeatedly take the box
//! with the largest range (the largest extent along any axis; ties to the older box) among
//! those holding at least two distinct normals, sort it along its longest axis and split it
//! at the median *by texel count* (the first position where the running count reaches half,
//! kept so that both halves are non-empty), until there are `s_n` boxes or no box can be
//! split. Each entry is the texel-weighted mean of its box, renormalised; a box holding a
//! single distinct normal keeps that normal bit for bit.
//!
//! Unlike ppmquant this works on the f64 normals, not on RGB8 (documented choice): 8-bit
//! channels would merge normals less than 1/127.5 apart, so a table with one entry per
//! distinct normal would not reproduce the map exactly. Consequences: with `s_n` at least
//! the number of distinct normals the table *is* the set of distinct normals (quantization
//! and dithering change nothing), and the table may have fewer than `s_n` entries.

use glam::DVec3;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// A box: a slice `start..end` of the histogram, with its range and longest axis.
struct Cut {
    start: usize,
    end: usize,
    range: f64,
    axis: usize,
    order: usize,
}

impl PartialEq for Cut {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Cut {}
impl PartialOrd for Cut {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Cut {
    /// Largest range first, then the older box (smaller `order`).
    fn cmp(&self, o: &Self) -> Ordering {
        self.range
            .total_cmp(&o.range)
            .then_with(|| o.order.cmp(&self.order))
    }
}

/// The histogram of `normals`: distinct vectors (bitwise) with counts, sorted.
pub(crate) fn histogram(normals: &[DVec3]) -> Vec<(DVec3, usize)> {
    let mut keys: Vec<[u64; 3]> = normals
        .iter()
        .map(|n| [n.x.to_bits(), n.y.to_bits(), n.z.to_bits()])
        .collect();
    keys.sort_unstable();
    let mut out: Vec<(DVec3, usize)> = Vec::new();
    let mut last: Option<[u64; 3]> = None;
    for k in keys {
        if last == Some(k) {
            out.last_mut().expect("a previous key").1 += 1;
        } else {
            let v = DVec3::new(
                f64::from_bits(k[0]),
                f64::from_bits(k[1]),
                f64::from_bits(k[2]),
            );
            out.push((v, 1));
            last = Some(k);
        }
    }
    out
}

fn make_cut(h: &[(DVec3, usize)], start: usize, end: usize, order: usize) -> Cut {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for (v, _) in &h[start..end] {
        lo = lo.min(*v);
        hi = hi.max(*v);
    }
    let ext = hi - lo;
    let axis = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    // a single distinct normal cannot be split: range 0 and never popped for splitting
    let range = if end - start >= 2 { ext[axis] } else { -1.0 };
    Cut {
        start,
        end,
        range,
        axis,
        order,
    }
}

/// At most `s_n` unit entries (`s_n >= 1`, `normals` non-empty, finite, non-zero).
pub fn median_cut(normals: &[DVec3], s_n: usize) -> Vec<DVec3> {
    let mut h = histogram(normals);
    let mut heap = BinaryHeap::new();
    let mut order = 0;
    heap.push(make_cut(&h, 0, h.len(), order));
    let mut done = Vec::new();
    while heap.len() + done.len() < s_n {
        let Some(c) = heap.pop() else { break };
        if c.range < 0.0 {
            done.push(c);
            continue;
        }
        let a = c.axis;
        h[c.start..c.end].sort_by(|p, q| {
            p.0[a].total_cmp(&q.0[a]).then(
                p.0.to_array()
                    .partial_cmp(&q.0.to_array())
                    .unwrap_or(Ordering::Equal),
            )
        });
        let total: usize = h[c.start..c.end].iter().map(|p| p.1).sum();
        let mut run = 0;
        let mut split = c.end - 1;
        for (i, p) in h[c.start..c.end].iter().enumerate() {
            run += p.1;
            if 2 * run >= total {
                split = c.start + i + 1;
                break;
            }
        }
        let split = split.clamp(c.start + 1, c.end - 1);
        order += 1;
        heap.push(make_cut(&h, c.start, split, order));
        order += 1;
        heap.push(make_cut(&h, split, c.end, order));
    }
    let mut cuts: Vec<Cut> = done.into_iter().chain(heap).collect();
    cuts.sort_by_key(|c| c.order);
    cuts.iter()
        .map(|c| {
            let part = &h[c.start..c.end];
            // a single distinct normal is kept as given (already unit), bit for bit
            if part.len() == 1 {
                return part[0].0;
            }
            let sum = part
                .iter()
                .fold(DVec3::ZERO, |s, (v, n)| s + *v * *n as f64);
            let m = sum.normalize_or_zero();
            // opposite normals can cancel: fall back to the most frequent one
            if m == DVec3::ZERO {
                part.iter()
                    .max_by_key(|p| p.1)
                    .expect("non-empty box")
                    .0
                    .normalize()
            } else {
                m
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn histogram_counts_distinct_normals() {
        let n = [DVec3::X, DVec3::Y, DVec3::X, DVec3::Z, DVec3::X];
        let h = histogram(&n);
        assert_eq!(h.len(), 3);
        assert_eq!(h.iter().map(|p| p.1).sum::<usize>(), 5);
        assert!(h.contains(&(DVec3::X, 3)));
    }

    #[test]
    fn median_cut_splits_at_the_weighted_median_of_the_longest_axis() {
        // x spans 0.8, y 0.2: two boxes split along x; the count-weighted median puts the
        // heavy cluster alone
        let a = DVec3::new(-0.4, 0.0, 1.0).normalize();
        let b = DVec3::new(-0.3, 0.1, 1.0).normalize();
        let c = DVec3::new(0.4, 0.2, 1.0).normalize();
        let mut n = vec![a; 10];
        n.push(b);
        n.push(c);
        let t = median_cut(&n, 2);
        assert_eq!(t.len(), 2);
        assert!((t[0] - a).length() < 1e-12, "{:?}", t[0]);
        // mean of b and c, renormalised
        assert!((t[1] - (b + c).normalize()).length() < 1e-12);
    }

    #[test]
    fn median_cut_reproduces_few_distinct_normals_exactly() {
        let d = [DVec3::X, DVec3::Y, DVec3::Z, DVec3::new(0.6, 0.0, 0.8)];
        let n: Vec<DVec3> = (0..50).map(|i| d[(i * 7) % 4]).collect();
        let mut t = median_cut(&n, 100);
        assert_eq!(t.len(), 4);
        t.sort_by(|p, q| p.to_array().partial_cmp(&q.to_array()).unwrap());
        let mut e = d.to_vec();
        e.sort_by(|p, q| p.to_array().partial_cmp(&q.to_array()).unwrap());
        assert_eq!(t, e);
        // one entry: the mean direction
        let one = median_cut(&n, 1);
        assert_eq!(one.len(), 1);
        assert!((one[0].length() - 1.0).abs() < 1e-12);
    }
}
