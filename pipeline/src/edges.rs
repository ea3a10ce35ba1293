//! The edge-discontinuity measure (Ernst et al. 1998 §3.2: VISA+ "leads to minor visible
//! discontinuities at the edges of two adjacent triangles if the angle between the spanned
//! planes exceeds a certain threshold"): how much more the error steps between neighbouring
//! pixels that lie on two different triangles than between neighbours on one triangle.
//!
//! For every horizontal and vertical pair of pixels `(p, q)` covered in both images, the
//! error step is `max_c |(a_q - a_p) - (r_q - r_p)|` in 8-bit LSBs: zero where the test
//! image changes exactly as the reference does, whatever the shading. A pair is an **edge**
//! pair when the test image's triangles at `p` and `q` differ (the shared edge runs between
//! them), else an **interior** pair. The figures: the mean and the 99th percentile of the
//! step over each kind, and the **excess** `edge mean - interior mean`: what the triangle
//! edges add. An engine whose perturbation is continuous across edges (Harmony, Texram,
//! VISA+ with quaternions, the SGI and Blinn engines) has an excess near zero; VISA+ with a
//! per-triangle alignment matrix steps at every edge by what the dihedral angle turns its
//! perturbation.
//!
//! Every sum runs in a fixed pixel order, so the figures are the same at any thread count.

use crate::metrics::{ser_finite, Rgb64};
use serde::Serialize;

/// No triangle at a pixel.
pub const NO_TRIANGLE: u32 = u32::MAX;

/// The edge-discontinuity figures of one image against another.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EdgeStats {
    /// Neighbour pairs on two different triangles.
    pub edge_pairs: u64,
    /// Neighbour pairs on one triangle.
    pub interior_pairs: u64,
    /// Mean error step across edges, in LSB.
    #[serde(serialize_with = "ser_finite")]
    pub edge_step_lsb: f64,
    /// Mean error step inside triangles, in LSB.
    #[serde(serialize_with = "ser_finite")]
    pub interior_step_lsb: f64,
    /// `edge_step_lsb - interior_step_lsb`.
    #[serde(serialize_with = "ser_finite")]
    pub excess_lsb: f64,
    /// 99th percentile of the error step across edges, in LSB.
    #[serde(serialize_with = "ser_finite")]
    pub edge_p99_lsb: f64,
    /// 99th percentile of the error step inside triangles, in LSB.
    #[serde(serialize_with = "ser_finite")]
    pub interior_p99_lsb: f64,
    /// The worst single edge: the largest mean error step over the pairs between one two
    /// triangles (at least [`SEAM_MIN_PAIRS`] of them), less `interior_step_lsb`; 0 when no
    /// edge has that many pairs.
    #[serde(serialize_with = "ser_finite")]
    pub worst_seam_lsb: f64,
    /// Pixel pairs along that edge.
    pub worst_seam_pairs: u64,
}

/// Fewest pixel pairs an edge needs to count as a seam (shorter edges are noise).
pub const SEAM_MIN_PAIRS: u64 = 8;

/// Measure test image `a` (covered where `a_mask`, triangle `tri[i]` at pixel `i`) against
/// `r` (covered where `r_mask`). Images of different sizes are compared on their common
/// top-left rectangle.
pub fn measure(a: &Rgb64, a_mask: &[bool], tri: &[u32], r: &Rgb64, r_mask: &[bool]) -> EdgeStats {
    let (w, h) = (
        a.width.min(r.width) as usize,
        a.height.min(r.height) as usize,
    );
    let at = |img: &Rgb64, x: usize, y: usize| y * img.width as usize + x;
    let covered = |x: usize, y: usize| {
        let (i, j) = (at(a, x, y), at(r, x, y));
        a_mask.get(i).copied().unwrap_or(false)
            && r_mask.get(j).copied().unwrap_or(false)
            && tri.get(i).is_some_and(|&t| t != NO_TRIANGLE)
    };
    // the pairs of each kind, counted first so each list is allocated once at its size
    let pairs = |x: usize, y: usize| {
        [(x + 1, y), (x, y + 1)]
            .into_iter()
            .filter(move |&(qx, qy)| qx < w && qy < h && covered(x, y) && covered(qx, qy))
    };
    let (mut n_edge, mut n_interior) = (0usize, 0usize);
    for y in 0..h {
        for x in 0..w {
            for (qx, qy) in pairs(x, y) {
                if tri[at(a, x, y)] == tri[at(a, qx, qy)] {
                    n_interior += 1;
                } else {
                    n_edge += 1;
                }
            }
        }
    }
    let (mut edge, mut interior) = (Vec::with_capacity(n_edge), Vec::with_capacity(n_interior));
    let mut seams: std::collections::BTreeMap<(u32, u32), (f64, u64)> = Default::default();
    for y in 0..h {
        for x in 0..w {
            for (qx, qy) in pairs(x, y) {
                let (ap, aq) = (a.px[at(a, x, y)], a.px[at(a, qx, qy)]);
                let (rp, rq) = (r.px[at(r, x, y)], r.px[at(r, qx, qy)]);
                let step = (0..3)
                    .map(|c| ((aq[c] - ap[c]) - (rq[c] - rp[c])).abs() * 255.0)
                    .fold(0.0, f64::max);
                let (tp, tq) = (tri[at(a, x, y)], tri[at(a, qx, qy)]);
                if tp == tq {
                    interior.push(step);
                } else {
                    edge.push(step);
                    let e = seams.entry((tp.min(tq), tp.max(tq))).or_default();
                    *e = (e.0 + step, e.1 + 1);
                }
            }
        }
    }
    let (edge_step_lsb, edge_p99_lsb) = mean_p99(&mut edge);
    let (interior_step_lsb, interior_p99_lsb) = mean_p99(&mut interior);
    let (worst_seam_lsb, worst_seam_pairs) = seams
        .values()
        .filter(|&&(_, n)| n >= SEAM_MIN_PAIRS)
        .map(|&(sum, n)| (sum / n as f64 - interior_step_lsb, n))
        .fold((0.0, 0), |best, s| if s.0 > best.0 { s } else { best });
    EdgeStats {
        edge_pairs: edge.len() as u64,
        interior_pairs: interior.len() as u64,
        edge_step_lsb,
        interior_step_lsb,
        excess_lsb: edge_step_lsb - interior_step_lsb,
        edge_p99_lsb,
        interior_p99_lsb,
        worst_seam_lsb,
        worst_seam_pairs,
    }
}

/// Mean and 99th percentile (nearest rank) of `v`; zeros when empty. The percentile is the
/// element of that rank in `f64::total_cmp` order, found by selection (in place, linear
/// time): the value a full sort would put there, since elements that compare equal under
/// `total_cmp` are the same value. `v` is left permuted.
fn mean_p99(v: &mut [f64]) -> (f64, f64) {
    if v.is_empty() {
        return (0.0, 0.0);
    }
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    let rank = ((0.99 * v.len() as f64).ceil() as usize).clamp(1, v.len());
    let (_, p99, _) = v.select_nth_unstable_by(rank - 1, f64::total_cmp);
    (mean, *p99)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn img(w: u32, h: u32, f: impl Fn(u32, u32) -> f64) -> Rgb64 {
        Rgb64 {
            width: w,
            height: h,
            px: (0..h)
                .flat_map(|y| (0..w).map(move |x| (x, y)))
                .map(|(x, y)| [f(x, y); 3])
                .collect(),
        }
    }

    #[test]
    fn a_step_at_the_triangle_edge_is_an_excess_and_a_smooth_ramp_is_not() {
        let (w, h) = (8, 4);
        let mask = vec![true; 32];
        // two triangles: the left half and the right half
        let tri: Vec<u32> = (0..32).map(|i| u32::from(i % 8 >= 4)).collect();
        let r = img(w, h, |x, _| x as f64 * 10.0 / 255.0);
        // the same ramp, plus a 5 LSB step where the triangles meet
        let a = img(w, h, |x, _| {
            (x as f64 * 10.0 + if x >= 4 { 5.0 } else { 0.0 }) / 255.0
        });
        let s = measure(&a, &mask, &tri, &r, &mask);
        assert_eq!(s.edge_pairs, 4);
        assert_eq!(s.interior_pairs, 24 + 24);
        assert!((s.edge_step_lsb - 5.0).abs() < 1e-9, "{s:?}");
        assert!(s.interior_step_lsb.abs() < 1e-9);
        assert!((s.excess_lsb - 5.0).abs() < 1e-9);
        assert!((s.edge_p99_lsb - 5.0).abs() < 1e-9);
        // four pairs along the one edge: too few for a seam
        assert_eq!((s.worst_seam_lsb, s.worst_seam_pairs), (0.0, 0));
        let tall = |x, _| (x as f64 * 10.0 + if x >= 4 { 5.0 } else { 0.0 }) / 255.0;
        let (a8, r8) = (img(w, 8, tall), img(w, 8, |x, _| x as f64 * 10.0 / 255.0));
        let (m8, t8): (Vec<bool>, Vec<u32>) =
            (0..64).map(|i| (true, u32::from(i % 8 >= 4))).unzip();
        let s8 = measure(&a8, &m8, &t8, &r8, &m8);
        assert_eq!(s8.worst_seam_pairs, 8);
        assert!((s8.worst_seam_lsb - 5.0).abs() < 1e-9, "{s8:?}");
        // the reference against itself: nothing
        let z = measure(&r, &mask, &tri, &r, &mask);
        assert_eq!(z.excess_lsb, 0.0);
        // uncovered pixels and pixels without a triangle take no part
        let mut m = mask.clone();
        m[4] = false;
        let mut t = tri.clone();
        t[12] = NO_TRIANGLE;
        let s = measure(&a, &m, &t, &r, &mask);
        assert_eq!(s.edge_pairs, 2);
    }

    #[test]
    fn percentiles_use_the_nearest_rank() {
        let mut v: Vec<f64> = (1..=200).map(f64::from).collect();
        assert_eq!(mean_p99(&mut v), (100.5, 198.0));
        assert_eq!(mean_p99(&mut []), (0.0, 0.0));
        // shuffled, with repeats, zeros of both signs and an infinity
        let mut v: Vec<f64> = (0..1000u64)
            .map(|i| ((i * 7919) % 1000) as f64 / 8.0)
            .collect();
        v.extend([0.0, -0.0, f64::INFINITY, 3.0, 3.0]);
        let mut sorted = v.clone();
        sorted.sort_by(f64::total_cmp);
        let rank = (0.99 * v.len() as f64).ceil() as usize;
        let in_order = v.iter().sum::<f64>() / v.len() as f64;
        let (mean, p99) = mean_p99(&mut v);
        assert_eq!(p99.to_bits(), sorted[rank - 1].to_bits());
        assert_eq!(p99, 123.75);
        assert_eq!(mean, in_order);
    }

    /// Selection gives the value the full sort gave, for every length up to 300 and lists
    /// full of ties (the rank is where a percentile could silently move).
    #[test]
    fn selection_matches_the_sorted_percentile() {
        for n in 1..=300u64 {
            for modulus in [1, 2, 5, 97] {
                let mut v: Vec<f64> = (0..n).map(|i| ((i * 31 + 7) % modulus) as f64).collect();
                let mut sorted = v.clone();
                sorted.sort_by(f64::total_cmp);
                let rank = ((0.99 * n as f64).ceil() as usize).clamp(1, n as usize);
                assert_eq!(mean_p99(&mut v).1, sorted[rank - 1], "n {n} mod {modulus}");
            }
        }
    }
}
