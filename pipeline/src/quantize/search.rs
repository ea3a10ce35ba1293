//! Exact nearest-entry search with a k-d tree: [`NearestIndex`] returns, for every query,
//! exactly what the brute-force [`super::nearest`] returns (the reference, kept for tests).
//!
//! The answer is the entry with the largest `v.dot(e)` (glam's `DVec3::dot`, f64), ties to the
//! lowest index. The tree only decides which entries are *scored*; every candidate's score is
//! that same `v.dot(e)` expression on the same bits, and candidates are compared with the same
//! rule (`s > best`, or `s == best` at a lower index), so the rounding of the winner's score and
//! the tie rule are the brute force's.
//!
//! Why it is exact: the tree splits the entries at the median of the axis of largest extent
//! down to leaves of [`LEAF`] entries; every node keeps the bounding box `[lo, hi]` of its
//! entries and `n2`, the largest `fl(e · e)` among them. A node is skipped only when its
//! bound is *strictly* below the best score found so far, and the bound is at least the
//! computed score `fl(v · e)` of every entry `e` of the node; so a skipped node holds no
//! entry whose score equals or beats the best, hence neither the winner nor a tie at a lower
//! index. The bounds (`u = 2^-53`, `γ_k = k u / (1 - k u)`; Higham, *Accuracy and Stability of
//! Numerical Algorithms*, §3.1):
//!
//! * The score margin: `fl(v · e) ≤ v · e + γ_3 Σ_i |v_i e_i| + 3·2^-1075` (the last term for
//!   gradual underflow) `≤ v · e + margin` with `margin = 2^-40 M + f64::MIN_POSITIVE` and
//!   `M = Σ_i |v_i| max_e |e_i|` over the whole table.
//! * The ball bound (used when `1e-100 ≤ |v| ≤ 1e100` and no entry component exceeds
//!   `1e100`): with `w = fl(v / |v|)` and `l = fl(|v|)`, `v_i = l w_i (1 + η_i)`, `|η_i| ≤ u`,
//!   and for `x` in the box with `|x|² ≤ n2_exact`, `w · x = (|w|² + |x|² - |w - x|²) / 2 ≤
//!   (|w|² + n2_exact - D²) / 2`, `D` the distance from `w` to the box. Computed as
//!   `l (ww + n2 - D2) / 2` it is off by at most about `10 u l (ww + n2 + D2 + 1)`; the bound
//!   adds `2^-36 l (ww + n2 + D2 + 1)` and the score margin. It is tight for unit entries (a
//!   box farther than the best entry's distance is skipped), where a bound that is linear in
//!   `v` over the box (below) is loose by the box's size and prunes far less.
//! * The linear bound (other queries): `B = Σ_i max(v_i lo_i, v_i hi_i)` with the products and
//!   the sum in the dot product's order (`x`, `y`, `z`), plus the score margin. Already `B`
//!   itself is at least `fl(v · e)`: IEEE rounding is monotone, so `fl(v_i e_i) ≤
//!   max(fl(v_i lo_i), fl(v_i hi_i))` for `lo_i ≤ e_i ≤ hi_i`, and a rounded sum does not
//!   decrease when its terms do.
//!
//! Both need every product and sum finite: queries with a non-finite component or with
//! `M > 1e300`, and indices over non-finite entries, are answered by the brute force itself;
//! so are tables of fewer than [`BRUTE_FORCE_BELOW`] entries, where the tree would not pay.
//! Tables of unit entries queried one texel after another (the dither) go through [`Cells`]
//! instead: candidate lists per direction cell, each built on its cell's first query with
//! a cap query on the tree, the same answers (proof in [`cells`]).
//! Measured (`benches/nearest.rs`, 262,144 Mexican-hat normals, median-cut tables, one
//! thread on a loaded 2-core machine): 2,048 entries 963 ms brute force, 75 ms index (build
//! 0.16 ms); 16,384 entries 8.2 s brute force, 117 ms index (build 2 ms).

pub mod cells;

use cells::Cells;
use glam::DVec3;
use std::ops::Range;

/// Entries per leaf at most.
pub const LEAF: usize = 16;
/// Tables (ranges) smaller than this are searched by brute force.
pub const BRUTE_FORCE_BELOW: usize = 32;
/// Relative part of the pruning margin (`2^-40`, far above `2 γ_3 + u ≈ 7.8e-16`).
const REL_MARGIN: f64 = 1.0 / (1u64 << 40) as f64;
/// Largest `M` (see the module docs) for which the tree is used: no score can overflow.
const MAX_SCALE: f64 = 1e300;
/// Relative part of the ball bound's margin (`2^-36`, far above its `~10 u` of rounding).
const REL_BALL: f64 = 1.0 / (1u64 << 36) as f64;
/// Largest entry component for which the ball bound is used (no square can overflow).
const MAX_BALL: f64 = 1e100;
/// Query lengths for which the ball bound is used (`v / |v|` and the products stay normal).
const MIN_LENGTH: f64 = 1e-100;
const MAX_LENGTH: f64 = 1e100;
/// Deepest stack a search needs: one pending sibling per level (median splits halve).
const STACK: usize = 32;

/// A node: the bounding box of its entries; a leaf holds `points[start..end]`, an inner node
/// has its children at `left` and `left + 1` (`left == 0` marks a leaf: the root is node 0).
#[derive(Debug, Clone, Default)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    /// The largest `fl(e · e)` of its entries.
    n2: f64,
    left: u32,
    start: u32,
    end: u32,
}

/// The entries of `entries[range]` in a k-d tree, for exact nearest-entry queries (see the
/// module docs). Built once per table (or per material interval), then queried per texel.
#[derive(Debug, Clone)]
pub struct NearestIndex {
    /// `range.start`: added to every local index.
    offset: usize,
    /// The entries of the range in their original order (the brute-force fallback).
    entries: Vec<DVec3>,
    /// The entries in tree order, with their local indices.
    points: Vec<(DVec3, u32)>,
    /// Empty when the index searches by brute force.
    nodes: Vec<Node>,
    /// Per axis, the largest magnitude of any entry (the root box's `max(|lo|, |hi|)`).
    amax: DVec3,
    /// Whether the ball bound may be used: every entry component at most `1e100` in magnitude.
    ball: bool,
}

/// A query with what its bounds need (see the module docs).
struct Query {
    v: DVec3,
    /// `v / |v|` (computed).
    w: DVec3,
    /// `|v|` (computed).
    l: f64,
    /// `fl(w · w)`.
    ww: f64,
    /// `2^-36 |v|`: the relative margin of the ball bound.
    lr: f64,
    /// The margin of the scores: `2^-40 M_root + f64::MIN_POSITIVE`.
    margin: f64,
    ball: bool,
}

impl NearestIndex {
    /// The index of `entries[range]`. Panics if the range is out of bounds (as slicing does).
    pub fn new(entries: &[DVec3], range: Range<usize>) -> Self {
        let mine = entries[range.clone()].to_vec();
        let mut ix = NearestIndex {
            offset: range.start,
            points: Vec::new(),
            nodes: Vec::new(),
            amax: DVec3::ZERO,
            ball: false,
            entries: mine,
        };
        let n = ix.entries.len();
        if n < BRUTE_FORCE_BELOW
            || n > u32::MAX as usize
            || !ix.entries.iter().all(|e| e.is_finite())
        {
            return ix;
        }
        ix.points = ix
            .entries
            .iter()
            .enumerate()
            .map(|(i, &e)| (e, i as u32))
            .collect();
        ix.nodes.push(Node::default());
        ix.build(0, 0, n, 1);
        ix.amax = ix.nodes[0].lo.abs().max(ix.nodes[0].hi.abs());
        ix.ball = ix.amax.max_element() <= MAX_BALL;
        ix
    }

    /// The whole table: `NearestIndex::new(entries, 0..entries.len())`.
    pub fn of(entries: &[DVec3]) -> Self {
        Self::new(entries, 0..entries.len())
    }

    /// Fills node `k` with `points[start..end]` (`depth`: of node `k`, root 1).
    fn build(&mut self, k: usize, start: usize, end: usize, depth: usize) {
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        let mut n2 = 0f64;
        for (p, _) in &self.points[start..end] {
            lo = lo.min(*p);
            hi = hi.max(*p);
            n2 = n2.max(p.dot(*p));
        }
        self.nodes[k] = Node {
            lo,
            hi,
            n2,
            left: 0,
            start: start as u32,
            end: end as u32,
        };
        if end - start <= LEAF || depth + 1 >= STACK {
            return;
        }
        let ext = hi - lo;
        let axis = if ext.x >= ext.y && ext.x >= ext.z {
            0
        } else if ext.y >= ext.z {
            1
        } else {
            2
        };
        let mid = start + (end - start) / 2;
        self.points[start..end]
            .select_nth_unstable_by(mid - start, |p, q| p.0[axis].total_cmp(&q.0[axis]));
        let left = self.nodes.len();
        self.nodes.push(Node::default());
        self.nodes.push(Node::default());
        self.nodes[k].left = left as u32;
        self.build(left, start, mid, depth + 1);
        self.build(left + 1, mid, end, depth + 1);
    }

    /// Number of entries indexed.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether the range is empty ([`Self::nearest`] then answers `range.start`, as
    /// [`super::nearest`] does).
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Whether queries go through the tree (false: brute force, see the module docs).
    pub fn is_tree(&self) -> bool {
        !self.nodes.is_empty()
    }

    /// Exactly `super::nearest(v, entries, range)` for the `entries` and `range` given to
    /// [`Self::new`]: the index of the largest `v.dot(e)`, ties to the lower index.
    pub fn nearest(&self, v: DVec3) -> u32 {
        let scale = v.abs().dot(self.amax);
        if self.nodes.is_empty() || !(v.is_finite() && scale <= MAX_SCALE) {
            return (super::nearest(v, &self.entries, 0..self.entries.len()) as usize + self.offset)
                as u32;
        }
        let l = v.length();
        let ball = self.ball && (MIN_LENGTH..=MAX_LENGTH).contains(&l);
        let w = if ball { v / l } else { v };
        let q = Query {
            v,
            w,
            l,
            ww: w.dot(w),
            lr: REL_BALL * l,
            margin: REL_MARGIN * scale + f64::MIN_POSITIVE,
            ball,
        };
        let mut best = (f64::NEG_INFINITY, u32::MAX);
        let mut stack = [(0u32, 0f64); STACK];
        stack[0] = (0, f64::INFINITY);
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let (k, bound) = stack[top];
            if bound < best.0 {
                continue;
            }
            let node = &self.nodes[k as usize];
            if node.left == 0 {
                for &(e, i) in &self.points[node.start as usize..node.end as usize] {
                    let s = v.dot(e);
                    if s > best.0 || (s == best.0 && i < best.1) {
                        best = (s, i);
                    }
                }
                continue;
            }
            let (l, r) = (node.left, node.left + 1);
            let bl = bound_of(&q, &self.nodes[l as usize]);
            let br = bound_of(&q, &self.nodes[r as usize]);
            // the more promising child is popped first
            let (near, far) = if bl >= br {
                ((l, bl), (r, br))
            } else {
                ((r, br), (l, bl))
            };
            if far.1 >= best.0 {
                stack[top] = far;
                top += 1;
            }
            if near.1 >= best.0 {
                stack[top] = near;
                top += 1;
            }
        }
        (best.1 as usize + self.offset) as u32
    }

    /// [`Self::nearest`] of every vector.
    pub fn nearest_all(&self, vs: &[DVec3]) -> Vec<u32> {
        vs.iter().map(|&v| self.nearest(v)).collect()
    }

    /// Appends the local indices of the entries with `fl(c · e) >= t` (in tree order; the
    /// index must have a tree). A node is skipped when the linear bound of the module docs,
    /// itself at least every `fl(c · e)` of its entries, is below `t`.
    fn within(&self, c: DVec3, t: f64, out: &mut Vec<u32>) {
        let mut stack = [0u32; STACK];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = &self.nodes[stack[top] as usize];
            if max_dot(c, node) < t {
                continue;
            }
            if node.left == 0 {
                let pts = &self.points[node.start as usize..node.end as usize];
                out.extend(pts.iter().filter(|p| c.dot(p.0) >= t).map(|p| p.1));
                continue;
            }
            stack[top] = node.left;
            stack[top + 1] = node.left + 1;
            top += 2;
        }
    }
}

/// A bound at least the computed score `v.dot(e)` of every entry of the node (see the module
/// docs): the ball bound with its margins, or the linear bound with the score margin for
/// queries the ball bound does not take.
#[inline]
fn bound_of(q: &Query, n: &Node) -> f64 {
    if !q.ball {
        return max_dot(q.v, n) + q.margin;
    }
    let d = (n.lo - q.w).max(q.w - n.hi).max(DVec3::ZERO);
    let d2 = d.dot(d);
    q.l * ((q.ww + n.n2 - d2) * 0.5) + q.lr * (q.ww + n.n2 + d2 + 1.0) + q.margin
}

/// `Σ_i max(v_i lo_i, v_i hi_i)`: the largest `v · x` over the node's box (before rounding).
#[inline]
fn max_dot(v: DVec3, n: &Node) -> f64 {
    let (a, b) = (v * n.lo, v * n.hi);
    // `DVec3::max`: a plain comparison (no NaN can occur here)
    let m = a.max(b);
    m.x + m.y + m.z
}

/// One index per distinct candidate range, with its [`Cells`] where the entries are unit,
/// built on first use (dithering and materials ask for the few ranges of the material
/// intervals, texel after texel).
pub(crate) struct Indices<'a> {
    entries: &'a [DVec3],
    built: Vec<(Range<usize>, NearestIndex, Option<Cells>)>,
}

impl<'a> Indices<'a> {
    pub(crate) fn new(entries: &'a [DVec3]) -> Self {
        Indices {
            entries,
            built: Vec::new(),
        }
    }

    /// `super::nearest(v, entries, range)`, through the range's cells or index.
    pub(crate) fn nearest(&mut self, v: DVec3, range: Range<usize>) -> u32 {
        let k = match self.built.iter().position(|(r, ..)| *r == range) {
            Some(k) => k,
            None => {
                let ix = NearestIndex::new(self.entries, range.clone());
                let cells = Cells::new(&ix);
                self.built.push((range, ix, cells));
                self.built.len() - 1
            }
        };
        let (_, ix, cells) = &mut self.built[k];
        match cells {
            Some(c) => c.nearest(ix, v),
            None => ix.nearest(v),
        }
    }
}

#[cfg(test)]
mod tests;
