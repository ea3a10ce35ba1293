//! The highlight measure (`reference.highlight_luma`, docs/metrics.md, "`highlight`"): the
//! error and artifact figures of the three comparisons of a run restricted to the pixels
//! where the f64 reference is bright, the highlights.
//!
//! The region is defined on the reference alone (covered pixels whose Rec. 601 luma
//! `0.299 R + 0.587 G + 0.114 B`, each channel clamped to [0, 1] as the 8-bit output shows
//! it, is at least the threshold), so it is the same set of pixels for every engine that
//! renders the same scene. Each comparison is then that of the whole frame (`error.*`,
//! `artifacts.*`) with the test image's coverage cut to the region: a pixel counts when it
//! is covered in both images and lies in the region, and the artifact measures' windows
//! (neighbours, blurs) only use such pixels.

use crate::artifacts::{self, ArtifactStats};
use crate::metrics::{self, ser_finite, unit, ErrorStats, Rgb64};
use serde::Serialize;

/// The report's `highlight` section.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Highlight {
    /// The threshold, `reference.highlight_luma`.
    pub luma: f64,
    /// Reference pixels in the region (covered, luma at least `luma`).
    pub pixels: u64,
    /// Bit-accurate mode against the reference.
    pub total: HighlightStats,
    /// Exact mode against the reference.
    pub algorithm: HighlightStats,
    /// Bit-accurate against exact mode.
    pub quantization: HighlightStats,
}

/// One comparison over the region: `error.*`'s figures, `artifacts.*`'s, and the mean
/// signed error.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct HighlightStats {
    #[serde(flatten)]
    pub error: ErrorStats,
    /// Mean of `test - reference` over the channels of the pixels compared, in LSB (each
    /// channel clamped to [0, 1] first): negative when the test image is darker. 0 when no
    /// pixel is compared.
    #[serde(serialize_with = "ser_finite")]
    pub mean_signed_lsb: f64,
    #[serde(flatten)]
    pub artifacts: ArtifactStats,
}

/// Rec. 601 luma of a pixel, its channels clamped to [0, 1] (NaN as 0).
pub fn luma(p: [f64; 3]) -> f64 {
    0.299 * unit(p[0]) + 0.587 * unit(p[1]) + 0.114 * unit(p[2])
}

/// The region: the pixels of `r` covered in `r_mask` whose [`luma`] is at least `threshold`
/// (one `bool` per pixel of `r`, row-major).
pub fn region(r: &Rgb64, r_mask: &[bool], threshold: f64) -> Vec<bool> {
    r.px.iter()
        .enumerate()
        .map(|(i, &p)| r_mask.get(i).copied().unwrap_or(false) && luma(p) >= threshold)
        .collect()
}

/// `mask` (of image `img`) cut to `region` (of image `r`), pixel by pixel position.
fn restrict(img: &Rgb64, mask: &[bool], r: &Rgb64, region: &[bool]) -> Vec<bool> {
    let mut out = vec![false; img.px.len()];
    for y in 0..img.height.min(r.height) {
        for x in 0..img.width.min(r.width) {
            let (Some(i), Some(j)) = (img.index(x, y), r.index(x, y)) else {
                continue;
            };
            out[i] =
                mask.get(i).copied().unwrap_or(false) && region.get(j).copied().unwrap_or(false);
        }
    }
    out
}

/// Mean of `a - b` in LSB over the channels of the pixels covered in both masks.
fn mean_signed_lsb(a: &Rgb64, a_mask: &[bool], b: &Rgb64, b_mask: &[bool]) -> f64 {
    let (mut sum, mut n) = (0.0, 0u64);
    for y in 0..a.height.min(b.height) {
        for x in 0..a.width.min(b.width) {
            let (Some(i), Some(j)) = (a.index(x, y), b.index(x, y)) else {
                continue;
            };
            if a_mask.get(i).copied().unwrap_or(false) && b_mask.get(j).copied().unwrap_or(false) {
                let (p, q) = (a.px[i], b.px[j]);
                sum += (0..3).map(|c| unit(p[c]) - unit(q[c])).sum::<f64>();
                n += 3;
            }
        }
    }
    if n == 0 {
        0.0
    } else {
        255.0 * sum / n as f64
    }
}

/// Compare `a` with `b` over the pixels of `a_mask` in the region `hl` (of `b`'s grid).
fn stats(a: &Rgb64, a_mask: &[bool], b: &Rgb64, b_mask: &[bool], hl: &[bool]) -> HighlightStats {
    let am = restrict(a, a_mask, b, hl);
    HighlightStats {
        error: metrics::compare(a, &am, b, b_mask),
        mean_signed_lsb: mean_signed_lsb(a, &am, b, b_mask),
        artifacts: artifacts::measure(a, &am, b, b_mask),
    }
}

/// The highlight section of a run: the bit-accurate image `a`, the exact-mode image `e` and
/// the reference `r` (with their masks), the region where `r`'s luma is at least
/// `threshold`.
pub fn measure(
    a: &Rgb64,
    a_mask: &[bool],
    e: &Rgb64,
    e_mask: &[bool],
    r: &Rgb64,
    r_mask: &[bool],
    threshold: f64,
) -> Highlight {
    let hl = region(r, r_mask, threshold);
    // the region on the exact image's grid (the same grid in a run), for `quantization`
    let hl_e = restrict(e, &vec![true; e.px.len()], r, &hl);
    let ((total, algorithm), quantization) = rayon::join(
        || {
            rayon::join(
                || stats(a, a_mask, r, r_mask, &hl),
                || stats(e, e_mask, r, r_mask, &hl),
            )
        },
        || stats(a, a_mask, e, e_mask, &hl_e),
    );
    Highlight {
        luma: threshold,
        pixels: hl.iter().filter(|&&h| h).count() as u64,
        total,
        algorithm,
        quantization,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `w x h` image of grey `v` everywhere, all covered.
    fn grey(w: u32, h: u32, v: f64) -> (Rgb64, Vec<bool>) {
        let mut img = Rgb64::new(w, h);
        img.px.iter_mut().for_each(|p| *p = [v; 3]);
        (img, vec![true; (w * h) as usize])
    }

    #[test]
    fn luma_is_rec601_of_the_clamped_channels() {
        assert!((luma([1.0, 0.0, 0.0]) - 0.299).abs() < 1e-15);
        assert!((luma([0.0, 1.0, 0.0]) - 0.587).abs() < 1e-15);
        assert!((luma([0.0, 0.0, 1.0]) - 0.114).abs() < 1e-15);
        assert!((luma([2.0, 2.0, 2.0]) - 1.0).abs() < 1e-12);
        assert_eq!(luma([f64::NAN, -1.0, 0.0]), 0.0);
    }

    #[test]
    fn the_region_is_the_bright_covered_reference_pixels() {
        let (mut r, mut m) = grey(4, 2, 0.5);
        r.px[1] = [0.9; 3];
        r.px[2] = [0.8; 3];
        r.px[5] = [1.0; 3];
        m[5] = false;
        let hl = region(&r, &m, 0.8);
        assert_eq!(
            hl,
            vec![false, true, true, false, false, false, false, false]
        );
    }

    /// A 16x16 frame: the reference is 0.5 grey with a bright 4x4 square (0.9) at (6, 6);
    /// the bit-accurate image is the reference plus 4 LSB inside the square only, plus 8 LSB
    /// on one pixel outside; the exact image is the reference.
    #[test]
    fn only_the_region_counts() {
        let (w, h) = (16u32, 16u32);
        let (mut r, m) = grey(w, h, 0.5);
        let inside = |x: u32, y: u32| (6..10).contains(&x) && (6..10).contains(&y);
        for y in 0..h {
            for x in 0..w {
                if inside(x, y) {
                    r.set(x, y, [0.9; 3]);
                }
            }
        }
        let e = r.clone();
        let mut a = r.clone();
        for y in 0..h {
            for x in 0..w {
                if inside(x, y) {
                    a.set(x, y, [0.9 + 4.0 / 255.0; 3]);
                }
            }
        }
        a.set(1, 1, [0.5 - 8.0 / 255.0; 3]);
        let hl = measure(&a, &m, &e, &m, &r, &m, 0.8);
        assert_eq!(hl.luma, 0.8);
        assert_eq!(hl.pixels, 16);
        for s in [&hl.total, &hl.quantization] {
            assert_eq!(s.error.pixels, 16);
            // 4 LSB everywhere in the region: the pixel 8 LSB off outside it is not seen
            assert!((s.error.max_abs_lsb - 4.0).abs() < 1e-9, "{s:?}");
            assert!((s.error.mean_abs_lsb - 4.0).abs() < 1e-9, "{s:?}");
            assert!((s.mean_signed_lsb - 4.0).abs() < 1e-9, "{s:?}");
            let psnr = 20.0 * (255.0f64 / 4.0).log10();
            assert!((s.error.psnr_db - psnr).abs() < 1e-9, "{s:?}");
            // a uniform offset over the region: no step, no facet
            assert_eq!(s.artifacts.blockiness_edges, 0);
            assert!(s.artifacts.faceting_lsb.abs() < 1e-9, "{s:?}");
        }
        // the exact image is the reference
        assert_eq!(hl.algorithm.error.pixels, 16);
        assert_eq!(hl.algorithm.error.max_abs_lsb, 0.0);
        assert_eq!(hl.algorithm.error.psnr_db, metrics::PSNR_CAP_DB);
        assert_eq!(hl.algorithm.mean_signed_lsb, 0.0);
        // over the whole frame the outside pixel is the worst
        let all = metrics::compare(&a, &m, &r, &m);
        assert!((all.max_abs_lsb - 8.0).abs() < 1e-9);
    }

    /// A step between two plateaus inside the region is seen; the same step outside is not.
    #[test]
    fn blockiness_in_the_region_only() {
        let (w, h) = (12u32, 6u32);
        // reference: a smooth bright left half (0.9) and a dull right half (0.3)
        let mut r = Rgb64::new(w, h);
        for y in 0..h {
            for x in 0..w {
                r.set(x, y, [if x < 6 { 0.9 } else { 0.3 }; 3]);
            }
        }
        let m = vec![true; (w * h) as usize];
        // the test image steps by 3 LSB between columns 2 and 3 (bright) and 8 and 9 (dull)
        let mut a = r.clone();
        for y in 0..h {
            for x in 0..w {
                let step = if (3..6).contains(&x) || x >= 9 {
                    3.0 / 255.0
                } else {
                    0.0
                };
                a.set(x, y, [r.get(x, y)[0] + step; 3]);
            }
        }
        let whole = artifacts::measure(&a, &m, &r, &m);
        let hl = measure(&a, &m, &r, &m, &r, &m, 0.8);
        assert_eq!(hl.pixels, 36);
        // one vertical line of steps in each half over the whole frame, one in the region
        assert_eq!(whole.blockiness_edges, 2 * h as u64);
        assert_eq!(hl.total.artifacts.blockiness_edges, h as u64);
        assert!((hl.total.artifacts.blockiness - 1.0 / 6.0).abs() < 1e-12);
    }

    #[test]
    fn an_empty_region_compares_nothing() {
        let (r, m) = grey(4, 4, 0.5);
        let hl = measure(&r, &m, &r, &m, &r, &m, 0.8);
        assert_eq!(hl.pixels, 0);
        assert_eq!(hl.total.error.pixels, 0);
        assert_eq!(hl.total.mean_signed_lsb, 0.0);
        assert_eq!(hl.quantization.artifacts.blockiness, 0.0);
    }

    /// `reference.highlight_luma`: optional (no change to the hash when absent), in (0, 1].
    #[test]
    fn the_config_field_is_checked() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../configs/wang-bunny-hilo.ron");
        let load = |sets: &[&str]| {
            let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
            crate::config::load(&path, &sets)
        };
        let plain = load(&[]).unwrap();
        assert_eq!(plain.config.reference.highlight_luma, None);
        assert!(!crate::config::canonical(&plain.config).contains("highlight_luma"));
        assert_eq!(
            load(&["reference.highlight_luma=None"]).unwrap().hash,
            plain.hash
        );
        let set = load(&["reference.highlight_luma=Some(0.8)"]).unwrap();
        assert_eq!(set.config.reference.highlight_luma, Some(0.8));
        assert_ne!(set.hash, plain.hash);
        assert!(load(&["reference.highlight_luma=Some(1.0)"]).is_ok());
        for bad in ["0.0", "-0.5", "1.5"] {
            let e = load(&[&format!("reference.highlight_luma=Some({bad})")])
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("reference.highlight_luma") && e.contains("0 < highlight_luma <= 1"),
                "{e}"
            );
        }
        let e = load(&["reference.highlight_lum=Some(0.8)"])
            .unwrap_err()
            .to_string();
        assert!(e.contains("highlight_lum"), "{e}");
        // in a file: unknown keys stay errors, the field parses
        let text = std::fs::read_to_string(&path).unwrap();
        let at = |field: &str| {
            let t = text.replacen(
                "    raster:",
                &format!("    reference: ({field}),\n    raster:"),
                1,
            );
            crate::config::parse(&t, "wang-bunny-hilo.ron")
        };
        let ok = at("highlight_luma: Some(0.9)").unwrap();
        assert_eq!(ok.reference.highlight_luma, Some(0.9));
        let e = at("highlight_lumaa: Some(0.9)").unwrap_err().to_string();
        assert!(e.contains("highlight_lumaa"), "{e}");
    }

    #[test]
    fn the_section_serialises_flat() {
        let (r, m) = grey(4, 4, 0.9);
        let v = serde_json::to_value(measure(&r, &m, &r, &m, &r, &m, 0.8)).unwrap();
        assert_eq!(v["pixels"], 16);
        for k in [
            "psnr_db",
            "max_abs_lsb",
            "mean_abs_lsb",
            "mean_signed_lsb",
            "blockiness",
            "faceting_lsb",
            "banding",
        ] {
            assert!(v["quantization"].get(k).is_some(), "{k}: {v}");
        }
    }
}
