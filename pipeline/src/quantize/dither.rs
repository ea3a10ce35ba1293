//! Floyd–Steinberg dithering of normals (Tarini §4, Fig. 4: "Applying dithering to normals
//! produces as well an improved image quality").
//!
//! The error is the *vector* difference `target - entry`, where `target` is the texel's
//! normal plus the error diffused into it and `entry` the nearest table entry to `target`
//! (largest dot product; `target` is not renormalised, which does not change the choice
//! because the entries are unit). It is pushed to the unvisited neighbours with Floyd and
//! Steinberg's weights 7/16 (ahead), 3/16 (below behind), 5/16 (below), 1/16 (below ahead).
//! [`Scan::Serpentine`] alternates the row direction (ahead = the scan direction), which
//! avoids the diagonal "worms" of a raster scan; [`Scan::Raster`] scans every row left to
//! right. Error that would leave the map is dropped (no wrap-around).
//!
//! Measured (tests in this module and `quantize::tests`):
//! * On a smooth gradient (64x64, -5..25 degrees across x, median cut), dithering brings the
//!   mean of the quantized normals closer to the mean of the originals: `|mean - mean0|` =
//!   0.000703 plain, 0.000545 serpentine, 0.002377 raster (4 entries); 0.000174 / 0.000098 /
//!   0.000598 (8); 0.000041 / 0.000020 / 0.000103 (16). A raster scan is *worse* than no
//!   dithering (the 7/16 dropped at every row end all point the same way): use serpentine.
//! * Per texel, dithering always increases the angular error; what it buys is the error of
//!   local averages (what a minified map or the eye sees): on the Mexican hat at 128x128 with
//!   256 entries, the 4x4-block mean error falls from 0.185 to 0.118 degrees.
//! * With too few entries (16 on the Mexican hat) the steepest normals lie outside the cone of
//!   the table: their error can never be paid back and winds up (plain Floyd–Steinberg has no
//!   clamp), so the block error grows (2.68 to 3.23 degrees) and NeuQuant tables see outliers
//!   up to ~100 degrees. Tarini's own advice (§4) is `s_N >= 256` with dithering on.

use super::search::Indices;
use glam::DVec3;
use serde::{Deserialize, Serialize};
use std::ops::Range;

/// Row order of the error diffusion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Scan {
    /// Every row left to right.
    Raster,
    /// Even rows left to right, odd rows right to left (the usual choice).
    #[default]
    Serpentine,
}

/// Dithered indices of a `w x h` row-major map `normals` into `entries` (unit vectors).
/// Panics if `normals.len() != w * h` or `entries` is empty (programming errors).
pub fn dither(normals: &[DVec3], w: usize, h: usize, entries: &[DVec3], scan: Scan) -> Vec<u32> {
    let n = entries.len();
    dither_in(normals, w, h, entries, scan, |_| 0..n)
}

/// [`dither`] with the candidates of texel `i` restricted to `range(i)` (materials, §6).
/// Error is only diffused between texels with the same candidate range. Every texel is one
/// query of its range's [`super::NearestIndex`] (the answers of [`super::nearest`]).
pub(crate) fn dither_in(
    normals: &[DVec3],
    w: usize,
    h: usize,
    entries: &[DVec3],
    scan: Scan,
    range: impl Fn(usize) -> Range<usize>,
) -> Vec<u32> {
    let mut search = Indices::new(entries);
    dither_with(normals, w, h, entries, scan, range, |v, r| {
        search.nearest(v, r)
    })
}

/// [`dither_in`] with the nearest-entry search given (`nearest(v, range)`: the answer of
/// [`super::nearest`]; the tests pass the brute force itself).
pub(crate) fn dither_with(
    normals: &[DVec3],
    w: usize,
    h: usize,
    entries: &[DVec3],
    scan: Scan,
    range: impl Fn(usize) -> Range<usize>,
    mut nearest: impl FnMut(DVec3, Range<usize>) -> u32,
) -> Vec<u32> {
    assert_eq!(normals.len(), w * h, "dither: map size");
    assert!(!entries.is_empty(), "dither: empty table");
    let mut err = vec![DVec3::ZERO; w * h];
    let mut out = vec![0u32; w * h];
    for y in 0..h {
        let back = scan == Scan::Serpentine && y % 2 == 1;
        for k in 0..w {
            let x = if back { w - 1 - k } else { k };
            let i = y * w + x;
            let r = range(i);
            let target = normals[i] + err[i];
            let e = nearest(target, r.clone());
            out[i] = e;
            let d = target - entries[e as usize];
            let dir: isize = if back { -1 } else { 1 };
            let mut push = |dx: isize, dy: usize, wgt: f64| {
                let xx = x as isize + dx;
                let yy = y + dy;
                if xx < 0 || xx >= w as isize || yy >= h {
                    return;
                }
                let j = yy * w + xx as usize;
                if range(j) == r {
                    err[j] += d * wgt;
                }
            };
            push(dir, 0, 7.0 / 16.0);
            push(-dir, 1, 3.0 / 16.0);
            push(0, 1, 5.0 / 16.0);
            push(dir, 1, 1.0 / 16.0);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::tests::block_means;
    use super::super::{angular_error_deg, decode, quantize, Quantizer};
    use super::*;

    /// A smooth gradient: normals tilting from -5 to +25 degrees about y across x (the
    /// same in every row), 2 degrees about x.
    fn gradient(w: usize, h: usize) -> Vec<DVec3> {
        let b = 2f64.to_radians();
        let mut v = Vec::new();
        for _ in 0..h {
            for x in 0..w {
                let a = (-5.0 + 30.0 * (x as f64 + 0.5) / w as f64).to_radians();
                v.push(DVec3::new(a.sin(), b.sin(), a.cos() * b.cos()).normalize());
            }
        }
        v
    }

    fn mean(v: &[DVec3]) -> DVec3 {
        v.iter().fold(DVec3::ZERO, |s, n| s + *n) / v.len() as f64
    }

    #[test]
    fn dithering_keeps_the_mean_normal_of_a_smooth_gradient() {
        let (w, h) = (64, 64);
        let n = gradient(w, h);
        let m = mean(&n);
        for (s_n, ratio) in [(4, 0.85), (8, 0.7), (16, 0.7)] {
            let p = quantize(&n, s_n, Quantizer::MedianCut).unwrap();
            let plain = p.decode();
            let dith = decode(&p.entries, &dither(&n, w, h, &p.entries, Scan::Serpentine));
            let ras = decode(&p.entries, &dither(&n, w, h, &p.entries, Scan::Raster));
            let e_plain = (mean(&plain) - m).length();
            let e_dith = (mean(&dith) - m).length();
            let e_ras = (mean(&ras) - m).length();
            let (bp, _) = angular_error_deg(&block_means(&plain, w, 8), &block_means(&n, w, 8));
            let (bd, _) = angular_error_deg(&block_means(&dith, w, 8), &block_means(&n, w, 8));
            eprintln!(
                "gradient s_n={s_n}: |mean - mean0| plain {e_plain:.6}, serpentine {e_dith:.6}, \
                 raster {e_ras:.6}; 8x8 block error plain {bp:.4} deg, serpentine {bd:.4} deg"
            );
            assert!(e_plain > 1e-5, "plain {e_plain}");
            assert!(
                e_dith < ratio * e_plain,
                "s_n {s_n}: dithered {e_dith} vs plain {e_plain}"
            );
            // locally (8x8 blocks) the dithered map is closer as well; for s_n >= 8 the boxes
            // are 8 or 4 columns wide, aligned with the blocks, so plain is exact there
            if s_n == 4 {
                assert!(
                    bd < 0.5 * bp,
                    "s_n {s_n}: block errors: dithered {bd}, plain {bp}"
                );
            }
        }
    }

    #[test]
    fn dithering_changes_nothing_when_every_distinct_normal_has_an_entry() {
        let (w, h) = (32, 16);
        let g: Vec<DVec3> = (0..32)
            .map(|i| DVec3::new(0.02 * f64::from(i % 8), 0.03 * f64::from(i / 8), 1.0).normalize())
            .collect();
        // 32 distinct normals repeated over the map
        let n: Vec<DVec3> = (0..w * h).map(|i| g[(i * 13) % 32]).collect();
        for s_n in [32, 40, 16384] {
            let p = quantize(&n, s_n, Quantizer::MedianCut).unwrap();
            assert_eq!(p.entries.len(), 32);
            assert_eq!(angular_error_deg(&p.decode(), &n).1, 0.0);
            for scan in [Scan::Raster, Scan::Serpentine] {
                assert_eq!(dither(&n, w, h, &p.entries, scan), p.indices);
            }
        }
    }

    #[test]
    fn error_is_not_diffused_across_candidate_ranges() {
        // two halves with disjoint candidate sets: the right half only ever sees its own error
        let n = vec![DVec3::new(0.3, 0.0, 1.0).normalize(); 8];
        let e = vec![DVec3::Z, DVec3::X, DVec3::Z, DVec3::X];
        let a = dither_in(&n, 4, 2, &e, Scan::Raster, |i| {
            if i % 4 < 2 {
                0..2
            } else {
                2..4
            }
        });
        for (i, &k) in a.iter().enumerate() {
            let r = if i % 4 < 2 { 0..2 } else { 2..4 };
            assert!(r.contains(&(k as usize)));
        }
        // right half alone, dithered on its own, gives the same indices (offset by 2)
        let right: Vec<DVec3> = vec![n[0]; 4];
        let b = dither(&right, 2, 2, &e[2..], Scan::Raster);
        assert_eq!(vec![a[2] - 2, a[3] - 2, a[6] - 2, a[7] - 2], b);
    }
}
