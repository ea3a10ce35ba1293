//! Candidate lists per direction cell: an exact shortcut of [`NearestIndex::nearest`] for
//! tables of unit entries queried texel after texel (the dither, whose serpentine order
//! cannot be split between threads, so every query's cost counts).
//!
//! The largest `v · e` over unit entries depends on the direction of `v` only. The sphere of
//! directions is cut into the cells of a cube map, `g x g` per face. For a cell with centre
//! direction `c` and angular radius `r` (the largest angle from `c` to a corner: the cell is a
//! spherical quadrilateral bounded by great circles, smaller than a hemisphere, so the cap
//! through its farthest corner holds all of it), let `θ_c` be the angle from `c` to its nearest
//! entry `e_c`. The cell's **candidates** are the entries within `A = θ_c + 2r + s` of `c`
//! (`s` = [`SLACK`]), found once, on the cell's first query, by a cap query on the k-d tree.
//! A query `v` is answered by the brute-force rule ([`super::super::nearest`]: largest
//! `v.dot(e)`, ties to the lowest index) over its cell's candidates, in index order.
//!
//! Why it is exact: let `w` be the direction of `v` (within `r` of `c`, up to the rounding of
//! the cell lookup, far below `s`). An entry `e` off the list has `∠(c, e) > θ_c + 2r + s`, so
//! `∠(w, e) ≥ ∠(c, e) - r > θ_c + r + s ≥ ∠(w, e_c) + s`, and `w · e_c - w · e > cos α -
//! cos(α + s) = 2 sin(α + s/2) sin(s/2) ≥ 2 sin²(s/2) ≈ 5e-11` (`α = ∠(w, e_c)`; when `α + s
//! > π` no entry is off the list). The entries are unit to `|e·e - 1| ≤ 1e-12` (checked; an
//! index over other entries has no cells), which moves an exact score by at most `1e-12 |v|`,
//! and a computed score `fl(v · e)` is within `γ_3 √3 |v| < 1e-15 |v|` of the exact one. So
//! `fl(v · e_c) > fl(v · e)` for every `e` off the list: neither the winner nor a tie with it
//! is off the list, and the list in index order gives the brute force's answer. The cap
//! query and the angles (`atan2(|a × b|, a · b)`, accurate at every angle) keep margins of
//! `1e-11` and `s` over their rounding. Queries that are not finite or whose largest
//! component lies outside `[1e-100, 1e100]` go to the tree.
//!
//! The cell size is chosen from the table: `g = ⌈K / d⌉` ([`K`], clamped to `1..=`[`MAX_G`]),
//! `d = sqrt(area / n)` the spacing of `n` entries spread over the cap (about their mean
//! direction) that holds them; so `r ≈ d / 2.7` and a list holds a few entries.

use super::NearestIndex;
use glam::DVec3;

/// Angular slack of the candidate cap, in radians (see the module docs).
pub const SLACK: f64 = 1e-5;
/// `g d`: cells per face side times the entries' spacing (`r ≈ 1.1 / g ≈ d / 2.7`).
/// Measured on quantized-sphere's dither (256 entries over the sphere, 65,536 queries):
/// `K` = 2, 3, 4.4, 6, 8 give g = 10, 14, 20, 28, 37, lists of 6.3, 4.0, 2.7, 2.0, 1.7
/// entries and 4.3-5.1, 4.2-4.4, 4.7-5.7, 5.5-6.1, 6.8-7.2 ms (the k-d tree alone: 9.5 ms):
/// finer cells cost more first queries than their shorter lists save.
pub const K: f64 = 3.0;
/// Most cells per face side (6 x 256^2 cells of 8 bytes: 3 MiB).
pub const MAX_G: usize = 256;
/// How far `e · e` may be from 1 for the table to have cells.
const UNIT: f64 = 1e-12;
/// A cell not built yet.
const UNBUILT: u32 = u32::MAX;

/// The lazily built candidate lists of one [`NearestIndex`] (see the module docs).
#[derive(Debug, Clone)]
pub struct Cells {
    g: usize,
    /// Per cell `(start, len)` into `lists`; `start == UNBUILT` until its first query.
    cell: Vec<(u32, u32)>,
    /// The candidates of the built cells (local indices, ascending per cell).
    lists: Vec<u32>,
}

impl Cells {
    /// Cells for `ix`, or `None` when its entries are not all unit or it has no tree (small
    /// tables are searched by brute force anyway).
    pub fn new(ix: &NearestIndex) -> Option<Self> {
        let e = &ix.entries;
        if !ix.is_tree() || !e.iter().all(|v| (v.dot(*v) - 1.0).abs() <= UNIT) {
            return None;
        }
        let g = side(e);
        Some(Cells {
            g,
            cell: vec![(UNBUILT, 0); 6 * g * g],
            lists: Vec::new(),
        })
    }

    /// Cells per face side.
    pub fn side(&self) -> usize {
        self.g
    }

    /// Cells built so far.
    pub fn built(&self) -> usize {
        self.cell.iter().filter(|c| c.0 != UNBUILT).count()
    }

    /// Exactly `ix.nearest(v)` (`ix` the index these cells were made for).
    pub fn nearest(&mut self, ix: &NearestIndex, v: DVec3) -> u32 {
        let a = v.abs();
        let m = a.max_element();
        if !v.is_finite() || !(1e-100..=1e100).contains(&m) {
            return ix.nearest(v);
        }
        let k = self.cell_of(v, a);
        if self.cell[k].0 == UNBUILT {
            self.build(ix, k);
        }
        let (start, len) = self.cell[k];
        let mut best = (f64::NEG_INFINITY, 0u32);
        for &i in &self.lists[start as usize..(start + len) as usize] {
            let s = v.dot(ix.entries[i as usize]);
            if s > best.0 {
                best = (s, i);
            }
        }
        (best.1 as usize + ix.offset) as u32
    }

    /// The cell of `v` (`a = |v|` component-wise, largest component finite and non-zero).
    fn cell_of(&self, v: DVec3, a: DVec3) -> usize {
        let f = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let (p, q) = others(f);
        let face = 2 * f + usize::from(v[f] < 0.0);
        let g = self.g as f64;
        let at = |c: f64| (((c / a[f] + 1.0) * 0.5 * g) as usize).min(self.g - 1);
        (face * self.g + at(v[q])) * self.g + at(v[p])
    }

    /// The candidates of cell `k`, appended to `lists`.
    fn build(&mut self, ix: &NearestIndex, k: usize) {
        let g = self.g;
        let (face, j, i) = (k / (g * g), (k / g) % g, k % g);
        let (f, neg) = (face / 2, face % 2 == 1);
        let dir = |u: f64, t: f64| {
            let (p, q) = others(f);
            let mut d = DVec3::ZERO;
            d[f] = if neg { -1.0 } else { 1.0 };
            d[p] = u;
            d[q] = t;
            d.normalize()
        };
        let coord = |n: usize| -1.0 + 2.0 * n as f64 / g as f64;
        let mid = |n: usize| -1.0 + (2 * n + 1) as f64 / g as f64;
        let c = dir(mid(i), mid(j));
        let r = [(i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)]
            .into_iter()
            .map(|(u, t)| angle(c, dir(coord(u), coord(t))))
            .fold(0.0, f64::max);
        let near = ix.entries[(ix.nearest(c) as usize) - ix.offset];
        let reach = angle(c, near) + 2.0 * r + SLACK;
        let start = self.lists.len();
        if reach >= std::f64::consts::PI {
            self.lists.extend(0..ix.entries.len() as u32);
        } else {
            ix.within(c, reach.cos() - 1e-11, &mut self.lists);
            self.lists[start..].sort_unstable();
        }
        self.cell[k] = (start as u32, (self.lists.len() - start) as u32);
    }
}

/// The two axes of a cube face other than its own, in a fixed order.
fn others(f: usize) -> (usize, usize) {
    match f {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    }
}

/// The angle between two vectors, accurate near 0 and near π.
fn angle(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

/// Cells per face side for unit entries `e` (see the module docs).
fn side(e: &[DVec3]) -> usize {
    let n = e.len() as f64;
    let m = e.iter().fold(DVec3::ZERO, |s, v| s + *v);
    let spread = if m.length() > 1e-6 * n {
        let m = m.normalize();
        e.iter().map(|v| angle(m, *v)).fold(0.0, f64::max)
    } else {
        std::f64::consts::PI
    };
    let area = (2.0 * std::f64::consts::PI * (1.0 - spread.cos())).max(1e-9);
    let d = (area / n).sqrt();
    ((K / d).ceil() as usize).clamp(1, MAX_G)
}
