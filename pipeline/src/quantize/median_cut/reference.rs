//! The first median cut, kept as the reference of [`super::median_cut`] (tests) and as the
//! baseline of `benches/nearest.rs`: it sorts every box in full (stable, along its longest
//! axis) before splitting it, so each box's order is the one its ancestors' sorts left.

use super::histogram;
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

/// [`super::median_cut`] as it was written first: every box sorted in full before its split.
/// The same entries, bit for bit (`median_cut::tests`), several times slower.
pub fn median_cut_by_sorting(normals: &[DVec3], s_n: usize) -> Vec<DVec3> {
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
            super::mean_entry(part)
        })
        .collect()
}
