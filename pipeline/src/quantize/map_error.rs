//! How far a quantized normal map and its index mipmaps (§5.2) stray from the normals they
//! stand for, in texel space: the report's `normal_maps` (docs/metrics.md).
//!
//! Level 0: each texel's table normal against the unquantized normal. A coarser level: each
//! texel's table normal against the true box-filtered normal, the normalised mean of the
//! unquantized texels it covers (built level by level from the level below's unnormalised
//! sums, so a texel of level `k` is the mean of its `4^k` texels, not a mean of means).

use super::{angular_error_deg, decode};
use glam::DVec3;
use serde::Serialize;

/// One level's error: texels per side, mean and largest angle in degrees.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LevelError {
    pub size: u32,
    pub mean_deg: f64,
    pub max_deg: f64,
}

/// One quantized normal map of the engine (a `QuantizedNormals` unit).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NormalMapError {
    /// The unit that holds the map.
    pub unit: String,
    /// Entries of the table (at most `s_n`: median cut stops when every box holds one
    /// distinct normal).
    pub entries: u32,
    /// Texels per side of level 0.
    pub size: u32,
    /// Level 0, then each mip level, finest first.
    pub levels: Vec<LevelError>,
}

/// The errors of a `w x w` row-major map: `normals` the unquantized (unit) normals, `indices`
/// their entries of `table`, `mips` the coarser levels' indices, finest first, each
/// `max(w'/2, 1)` per side of the one before (as `mip_indices` builds them; an odd last
/// row or column is dropped, a side of 1 repeats its texel). Panics if a length is not
/// that (a programming error).
pub fn level_errors(
    normals: &[DVec3],
    w: usize,
    table: &[DVec3],
    indices: &[u32],
    mips: &[&[u32]],
) -> Vec<LevelError> {
    assert_eq!(normals.len(), w * w, "level_errors: normals");
    let level = |w: usize, truth: &[DVec3], idx: &[u32]| {
        let (mean_deg, max_deg) = angular_error_deg(truth, &decode(table, idx));
        LevelError {
            size: w as u32,
            // the mean of equal angles may round above them
            mean_deg: mean_deg.min(max_deg),
            max_deg,
        }
    };
    let mut out = vec![level(w, normals, indices)];
    let (mut sums, mut w) = (normals.to_vec(), w);
    for idx in mips {
        let w2 = (w / 2).max(1);
        let mut next = Vec::with_capacity(w2 * w2);
        for y in 0..w2 {
            let (y0, y1) = (2 * y, (2 * y + 1).min(w - 1));
            for x in 0..w2 {
                let (x0, x1) = (2 * x, (2 * x + 1).min(w - 1));
                next.push(
                    sums[y0 * w + x0] + sums[y0 * w + x1] + sums[y1 * w + x0] + sums[y1 * w + x1],
                );
            }
        }
        assert_eq!(idx.len(), w2 * w2, "level_errors: mip level of {w2} x {w2}");
        (sums, w) = (next, w2);
        let truth: Vec<DVec3> = sums.iter().map(|s| s.normalize()).collect();
        out.push(level(w, &truth, idx));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::{quantize, Quantizer};
    use super::*;

    /// A table that holds every normal of the map exactly: no error at level 0.
    #[test]
    fn exact_table_has_no_error_at_level_0() {
        let map: Vec<DVec3> = (0..16)
            .map(|k| DVec3::new((k % 4) as f64 - 1.5, (k / 4) as f64 - 1.5, 4.0).normalize())
            .collect();
        let p = quantize(&map, 16, Quantizer::Exact).unwrap();
        let l = level_errors(&map, 4, &p.entries, &p.indices, &[]);
        assert_eq!(
            l,
            vec![LevelError {
                size: 4,
                mean_deg: 0.0,
                max_deg: 0.0
            }]
        );
    }

    /// Hand-built 2 x 2 and 4 x 4 maps: the truth of level 1 is the normalised mean of the
    /// four normals, that of level 2 the normalised mean of all sixteen (not of the four
    /// means).
    #[test]
    fn box_filtered_truth() {
        let (x, y, z) = (DVec3::X, DVec3::Y, DVec3::Z);
        let xz = (x + z).normalize();
        let table = [x, y, z, xz];
        // 2 x 2: X Z / X Z, the mean is X + Z
        let map = [x, z, x, z];
        let l = level_errors(&map, 2, &table, &[0, 2, 0, 2], &[&[3]]);
        assert_eq!((l[0].size, l[0].mean_deg, l[0].max_deg), (2, 0.0, 0.0));
        assert_eq!(l[1].size, 1);
        assert!(l[1].max_deg.abs() < 1e-12, "{:?}", l[1]);
        let l = level_errors(&map, 2, &table, &[0, 2, 0, 2], &[&[2]]);
        assert!((l[1].mean_deg - 45.0).abs() < 1e-12, "{:?}", l[1]);
        let l = level_errors(&map, 2, &table, &[0, 2, 0, 2], &[&[1]]);
        assert!((l[1].max_deg - 90.0).abs() < 1e-12, "{:?}", l[1]);
        // 4 x 4: the top-right 2 x 2 block is X Z / X Z, the other three all Z; the sum is
        // 2 X + 14 Z
        let mut map = vec![z; 16];
        let mut idx = vec![2; 16];
        for k in [2, 6] {
            map[k] = x;
            idx[k] = 0;
        }
        let l1 = [2, 3, 2, 2];
        let l = level_errors(&map, 4, &table, &idx, &[&l1, &[2]]);
        assert_eq!(l.iter().map(|l| l.size).collect::<Vec<_>>(), [4, 2, 1]);
        assert_eq!((l[0].mean_deg, l[0].max_deg), (0.0, 0.0));
        assert!(l[1].max_deg < 1e-12, "{:?}", l[1]);
        let want = 2f64.atan2(14.0).to_degrees(); // 8.13, not 10.8 from the level-1 means
        assert!((l[2].mean_deg - want).abs() < 1e-12, "{:?}", l[2]);
        assert!((l[2].max_deg - want).abs() < 1e-12, "{:?}", l[2]);
    }
}
