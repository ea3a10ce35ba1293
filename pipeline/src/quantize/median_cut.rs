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
//!
//! By selection (same entries as sorting, bit for bit; `tests::selection_equals_sorting`,
//! against `reference::median_cut_by_sorting`): each split finds the weighted median with
//! `select_nth_unstable_by` (a weighted quickselect) instead of sorting the box, and only the
//! final boxes of two or more normals are sorted, once, because their entry is a sum whose
//! f64 rounding depends on the order. That order, and which normals fall on either side of a
//! split, are those of the sort-every-box algorithm: its sorts are stable, so a box's order is
//! its split axis' comparison, ties broken by its parent's, and so on up to the histogram's
//! bit order (`Chain`); that chain is a total order, which the selections and the final sort
//! use. A box's range and axis do not depend on the order of its normals: the component-wise
//! min and max keep the *last* of equal values, so `hi - lo` is `+0` whenever the two are equal
//! (whatever the signs of zeros) and the same nonzero difference otherwise. Measured
//! (`benches/nearest.rs`, a 256x256 map of 65,536 distinct normals): 2,048 entries 36 ms
//! sorting, 19 ms by selection; 256 entries 27-44 ms sorting, 13 ms by selection (the
//! histogram's sort, about 5 ms, is common to both).

#[doc(hidden)]
pub mod reference;

use glam::DVec3;
use rayon::prelude::*;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// A box in the heap of the sequential algorithm: node `node` of the split tree, with its
/// range and the age `order` that break ties between equal ranges.
struct Cut {
    range: f64,
    order: usize,
    node: usize,
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

/// The orders of the boxes: link `k` is the split of node `k` of the split tree, along its
/// `axis`, of a box whose order was its `chain` (`None`: the histogram's). A box made by that
/// split is in the order [`Chain::order`] of `Some(k)` gives.
struct Chain<'a> {
    links: &'a [Node],
}

impl Chain<'_> {
    /// The order of a box whose chain is `at`: the stable sorts of its ancestors, nearest
    /// first (along the axis, then all components), then the histogram's bit order.
    fn order(
        &self,
        at: Option<usize>,
    ) -> impl Fn(&(DVec3, usize), &(DVec3, usize)) -> Ordering + '_ {
        let first = at.map(|k| (self.links[k].axis, self.links[k].chain));
        move |p, q| match first {
            Some((axis, up)) => match along(axis, p.0, q.0) {
                Ordering::Equal => self.tie(up, p.0, q.0),
                o => o,
            },
            None => bits(p.0).cmp(&bits(q.0)),
        }
    }

    /// [`Self::order`] of normals equal up to the signs of zeros (rare: not inlined).
    #[inline(never)]
    fn tie(&self, mut at: Option<usize>, p: DVec3, q: DVec3) -> Ordering {
        while let Some(k) = at {
            let Node {
                axis, chain: up, ..
            } = self.links[k];
            let o = along(axis, p, q);
            if o != Ordering::Equal {
                return o;
            }
            at = up;
        }
        bits(p).cmp(&bits(q))
    }
}

/// The comparison of one sort: along `axis`, then all components (`-0` and `+0` equal).
#[inline]
fn along(axis: usize, p: DVec3, q: DVec3) -> Ordering {
    match p[axis].total_cmp(&q[axis]) {
        Ordering::Equal => p
            .to_array()
            .partial_cmp(&q.to_array())
            .unwrap_or(Ordering::Equal),
        o => o,
    }
}

fn bits(v: DVec3) -> [u64; 3] {
    [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()]
}

/// The histogram of `normals`: distinct vectors (bitwise) with counts, sorted.
pub(crate) fn histogram(normals: &[DVec3]) -> Vec<(DVec3, usize)> {
    let mut keys: Vec<[u64; 3]> = normals.par_iter().map(|&n| bits(n)).collect();
    // equal keys are equal bits: any sort gives the same list
    keys.par_sort_unstable();
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

/// The range and longest axis of the box `part`; the range is `-1` for a single distinct
/// normal (it cannot be split). They do not depend on the order of `part` (see the module
/// docs).
fn extent(part: &[(DVec3, usize)]) -> (f64, usize) {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for (v, _) in part {
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
    // a single distinct normal cannot be split: range -1, never popped for splitting
    let range = if part.len() >= 2 { ext[axis] } else { -1.0 };
    (range, axis)
}

/// Rearranges `part` (at least 2 normals) so that its first `j + 1` are the smallest in the
/// order `cmp` and returns `j`: the first position (in that order) where the running texel
/// count reaches half the total. A weighted quickselect: each step places one element with
/// `select_nth_unstable_by` where the count would reach half if the counts still in play were
/// equal (one step when they are, as for a map without repeated normals), and keeps the side
/// that holds `j`.
fn weighted_median(
    part: &mut [(DVec3, usize)],
    cmp: impl Fn(&(DVec3, usize), &(DVec3, usize)) -> Ordering,
) -> usize {
    let total: usize = part.iter().map(|p| p.1).sum();
    // the running count must reach `half`: `2 * run >= total`
    let half = total.div_ceil(2);
    // `j` lies in `l..r`, which holds `within` texels; `part[..l]` are the `l` smallest
    // (`before` texels, fewer than `half`) and `part[r..]` the largest
    let (mut l, mut r, mut before, mut within) = (0, part.len(), 0, total);
    loop {
        let need = half - before;
        let n = r - l;
        let guess = (need as u128 * n as u128).div_ceil(within as u128) as usize;
        let k = l + guess.clamp(1, n) - 1;
        part[l..r].select_nth_unstable_by(k - l, &cmp);
        let upto = before + part[l..=k].iter().map(|p| p.1).sum::<usize>();
        if upto < half {
            within -= upto - before;
            (l, before) = (k + 1, upto);
        } else if upto - part[k].1 >= half {
            within = upto - part[k].1 - before;
            r = k;
        } else {
            return k;
        }
    }
}

/// A box of the split tree: its slice of the histogram, range and axis, its chain (the node
/// whose split made it; `None` for the root) and, once split, its two halves.
#[derive(Clone, Copy)]
struct Node {
    start: usize,
    end: usize,
    range: f64,
    axis: usize,
    chain: Option<usize>,
    kids: Option<(usize, usize)>,
}

/// The split tree over the histogram `h`: node `k`'s split is chain link `k` (its axis and
/// its own chain), so a box's order is [`Chain::order`] of the node that made it.
struct Tree {
    nodes: Vec<Node>,
}

impl Tree {
    fn chain(&self) -> Chain<'_> {
        Chain { links: &self.nodes }
    }

    /// A node for the box `part` at `start`, made by the split of `chain`.
    fn node(part: &[(DVec3, usize)], start: usize, chain: Option<usize>) -> Node {
        let (range, axis) = extent(part);
        Node {
            start,
            end: start + part.len(),
            range,
            axis,
            chain,
            kids: None,
        }
    }

    /// Where node `k`'s box (`part`, at least 2 normals, its slice of the histogram) splits:
    /// the weighted median in its order, which also rearranges `part`.
    fn split_at(chain: &Chain, k: usize, part: &mut [(DVec3, usize)]) -> usize {
        let j = weighted_median(part, chain.order(Some(k)));
        (j + 1).clamp(1, part.len() - 1)
    }

    /// Adds the halves of node `k` split `at` (relative to its start).
    fn add_kids(&mut self, h: &[(DVec3, usize)], k: usize, at: usize) -> (usize, usize) {
        let Node { start, end, .. } = self.nodes[k];
        let split = start + at;
        let l = self.nodes.len();
        self.nodes
            .push(Self::node(&h[start..split], start, Some(k)));
        self.nodes.push(Self::node(&h[split..end], split, Some(k)));
        self.nodes[k].kids = Some((l, l + 1));
        (l, l + 1)
    }
}

/// At most `s_n` unit entries (`s_n >= 1`, `normals` non-empty, finite, non-zero).
///
/// The splits are worked out ahead, in parallel (rayon, one level of the tree at a time, each
/// box its own slice of the histogram), for every splittable box down to the depth
/// `floor(log2 s_n)`; then the heap of the sequential algorithm is replayed over that tree,
/// splitting a box it reaches that was not worked out ahead. A split depends only on its
/// box's normals and order, so the replay makes the boxes the sequential algorithm makes, in
/// its order; the boxes split ahead that the replay does not split only rearranged normals
/// within a box whose entry is summed after a sort in its own order (bit-identical,
/// `tests::selection_equals_sorting`).
pub fn median_cut(normals: &[DVec3], s_n: usize) -> Vec<DVec3> {
    let mut h = histogram(normals);
    let mut tree = Tree {
        nodes: vec![Tree::node(&h, 0, None)],
    };
    let depth = s_n.max(1).ilog2();
    let mut level = vec![0usize];
    for _ in 0..depth {
        level.retain(|&k| tree.nodes[k].range >= 0.0);
        if level.is_empty() {
            break;
        }
        let chain = tree.chain();
        let mut parts = Vec::with_capacity(level.len());
        let mut rest = &mut h[..];
        let mut at = 0;
        for &k in &level {
            let n = tree.nodes[k];
            let (_, r) = std::mem::take(&mut rest).split_at_mut(n.start - at);
            let (part, r) = r.split_at_mut(n.end - n.start);
            parts.push(part);
            rest = r;
            at = n.end;
        }
        let splits: Vec<usize> = level
            .par_iter()
            .zip(parts)
            .map(|(&k, part)| Tree::split_at(&chain, k, part))
            .collect();
        let mut next = Vec::with_capacity(2 * level.len());
        for (&k, at) in level.iter().zip(splits) {
            let (l, r) = tree.add_kids(&h, k, at);
            next.extend([l, r]);
        }
        level = next;
    }
    // the sequential algorithm's heap, over the tree
    let cut = |tree: &Tree, node: usize, order: usize| Cut {
        range: tree.nodes[node].range,
        order,
        node,
    };
    let mut heap = BinaryHeap::new();
    let mut order = 0;
    heap.push(cut(&tree, 0, order));
    let mut done = Vec::new();
    while heap.len() + done.len() < s_n {
        let Some(c) = heap.pop() else { break };
        if c.range < 0.0 {
            done.push(c);
            continue;
        }
        let k = c.node;
        let (l, r) = match tree.nodes[k].kids {
            Some(kids) => kids,
            None => {
                let Node { start, end, .. } = tree.nodes[k];
                let at = Tree::split_at(&tree.chain(), k, &mut h[start..end]);
                tree.add_kids(&h, k, at)
            }
        };
        order += 1;
        heap.push(cut(&tree, l, order));
        order += 1;
        heap.push(cut(&tree, r, order));
    }
    // the boxes tile the histogram: their entries are computed at once (rayon, each from
    // its own slice, in the order of the node that made it), then listed in the order the
    // boxes were made
    let chains = tree.chain();
    let mut cuts: Vec<Cut> = done.into_iter().chain(heap).collect();
    cuts.sort_by_key(|c| tree.nodes[c.node].start);
    let mut parts = Vec::with_capacity(cuts.len());
    let mut rest = &mut h[..];
    for c in &cuts {
        let n = &tree.nodes[c.node];
        let (part, r) = std::mem::take(&mut rest).split_at_mut(n.end - n.start);
        parts.push(part);
        rest = r;
    }
    let mut entries: Vec<(usize, DVec3)> = cuts
        .par_iter()
        .zip(parts)
        .map(|(c, part)| (c.order, entry(part, chains.order(tree.nodes[c.node].chain))))
        .collect();
    entries.sort_by_key(|e| e.0);
    entries.into_iter().map(|e| e.1).collect()
}

/// The entry of a box: the texel-weighted mean of its normals, summed in the order `order`
/// (the sum's rounding depends on it), renormalised.
fn entry(
    part: &mut [(DVec3, usize)],
    order: impl Fn(&(DVec3, usize), &(DVec3, usize)) -> Ordering,
) -> DVec3 {
    // a single distinct normal is kept as given (already unit), bit for bit
    if part.len() == 1 {
        return part[0].0;
    }
    // the sum's rounding depends on the order: the sort-every-box algorithm's
    part.sort_unstable_by(order);
    mean_entry(part)
}

/// The texel-weighted mean of a box of two or more normals, in the order given, renormalised
/// (shared with the sorting reference).
pub(crate) fn mean_entry(part: &[(DVec3, usize)]) -> DVec3 {
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
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bits of every entry (`==` would take `-0` for `+0`).
    fn bits_of(t: &[DVec3]) -> Vec<[u64; 3]> {
        t.iter().map(|&v| bits(v)).collect()
    }

    /// Maps that stress the order: shared coordinates, signed zeros, skewed counts.
    fn awkward_maps() -> Vec<(&'static str, Vec<DVec3>)> {
        let mut maps = Vec::new();
        // components on a coarse grid: many equal coordinates along every axis
        let mut grid = Vec::new();
        for i in 0..4000u32 {
            let f = |k: u32| f64::from((i * k) % 9) / 8.0 - 0.5;
            grid.push(DVec3::new(f(7), f(13), 1.0 + f(5)).normalize());
        }
        maps.push(("grid", grid));
        // signed zeros: numerically equal normals with different bits, in boxes of their own
        let z = [0.0, -0.0];
        let mut zeros = Vec::new();
        for (k, &a) in z.iter().enumerate() {
            for (l, &b) in z.iter().enumerate() {
                let reps = 1 + 3 * k + l;
                for _ in 0..reps {
                    zeros.push(DVec3::new(a, b, 1.0));
                    zeros.push(DVec3::new(a, 0.6, 0.8));
                    zeros.push(DVec3::new(0.6, b, 0.8));
                    zeros.push(DVec3::new(0.8, -0.6, a));
                }
            }
        }
        zeros.extend([DVec3::X, -DVec3::X, DVec3::Y, DVec3::new(0.6, 0.0, -0.8)]);
        maps.push(("signed zeros", zeros));
        // skewed counts: a few heavy normals among many light ones
        let mut skew = Vec::new();
        for i in 0..3000u32 {
            let t = f64::from(i);
            let v = DVec3::new((t * 0.37).sin() * 0.6, (t * 0.11).cos() * 0.6, 1.0).normalize();
            let reps = if i % 97 == 0 {
                200
            } else {
                1 + (i % 3) as usize
            };
            skew.resize(skew.len() + reps, v);
        }
        maps.push(("skewed", skew));
        // cancelling opposite normals
        maps.push(("opposite", vec![DVec3::X, -DVec3::X, DVec3::X, -DVec3::X]));
        maps
    }

    #[test]
    fn selection_equals_sorting() {
        use crate::quantize::tests::mexican_hat_cells;
        let mut maps = awkward_maps();
        maps.push(("hat 64 4 cells", mexican_hat_cells(64, 4)));
        maps.push(("hat 64 3 cells", mexican_hat_cells(64, 3)));
        maps.push(("hat 128 3 cells", mexican_hat_cells(128, 3)));
        for (name, map) in &maps {
            for s_n in [1, 2, 3, 5, 16, 100, 255, 256, 1000, 2048, 4000, 16384] {
                let new = median_cut(map, s_n);
                let old = reference::median_cut_by_sorting(map, s_n);
                assert_eq!(bits_of(&new), bits_of(&old), "{name}, s_n {s_n}");
            }
        }
    }

    #[test]
    fn weighted_median_is_the_first_position_reaching_half() {
        let cases = [
            vec![1, 1],
            vec![5, 1, 1],
            vec![1, 1, 5],
            vec![2, 2, 2, 2],
            vec![1; 9],
            vec![100, 1, 1, 1],
            vec![1, 1, 1, 100],
            vec![3, 1, 4, 1, 5, 9, 2, 6, 5, 3, 5],
            vec![1, 50, 1, 1, 1, 1, 1, 1, 1, 1, 40, 1],
        ];
        for counts in cases {
            let mut part: Vec<(DVec3, usize)> = counts
                .iter()
                .enumerate()
                .rev()
                .map(|(i, &c)| (DVec3::new(i as f64, 0.0, 1.0), c))
                .collect();
            let j = weighted_median(&mut part, |p, q| along(0, p.0, q.0));
            let total: usize = counts.iter().sum();
            let mut run = 0;
            let want = counts
                .iter()
                .position(|&c| {
                    run += c;
                    2 * run >= total
                })
                .unwrap();
            assert_eq!(j, want, "{counts:?}");
            for (i, p) in part.iter().enumerate() {
                assert_eq!(i <= j, p.0.x <= j as f64, "{counts:?}");
            }
        }
    }

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
