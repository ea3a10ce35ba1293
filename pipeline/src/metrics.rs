//! Image error metrics: PSNR, RMSE and 8-bit LSB errors between two renderings, and an
//! error heatmap.
//!
//! Images are linear RGB in `f64`, nominally in [0, 1], each with a coverage mask (one
//! `bool` per pixel, row-major). Two images are compared over the pixels covered in both
//! masks, channel by channel, after clamping every channel to [0, 1] (what the 8-bit output
//! would show; a NaN channel counts as 0). So all statistics are finite:
//!
//! * `rmse` is on the [0, 1] scale, over `3 * pixels` channel values;
//! * `psnr_db = 20 log10(1 / rmse)`, capped at [`PSNR_CAP_DB`] (999 dB) for identical images
//!   (and for an empty comparison, `pixels == 0`);
//! * `max_abs_lsb` and `mean_abs_lsb` are in 8-bit LSBs (the error times 255).
//!
//! Images of different sizes are compared over the pixel positions they share (the top-left
//! `min(width) x min(height)` rectangle); a mask shorter than its image leaves the missing
//! pixels uncovered.

use serde::Serializer;

/// PSNR reported for a zero error: 999 dB, a finite stand-in for infinity.
pub const PSNR_CAP_DB: f64 = 999.0;

/// Dark grey of pixels that are not covered in both images in a [`heatmap`].
pub const UNCOVERED: [u8; 3] = [32, 32, 32];

/// Error statistics of one image against another.
///
/// Serialisation never writes NaN or infinity: `psnr_db` is clamped to ±999 dB and any
/// other non-finite field is written as `null`. [`compare`] only produces finite values.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ErrorStats {
    #[serde(serialize_with = "ser_psnr")]
    pub psnr_db: f64,
    #[serde(serialize_with = "ser_finite")]
    pub rmse: f64,
    #[serde(serialize_with = "ser_finite")]
    pub max_abs_lsb: f64,
    #[serde(serialize_with = "ser_finite")]
    pub mean_abs_lsb: f64,
    /// Pixels compared (covered in both images).
    pub pixels: u64,
}

pub(crate) fn ser_psnr<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
    if x.is_nan() {
        s.serialize_none()
    } else {
        s.serialize_f64(x.clamp(-PSNR_CAP_DB, PSNR_CAP_DB))
    }
}

pub(crate) fn ser_finite<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
    if x.is_finite() {
        s.serialize_f64(*x)
    } else {
        s.serialize_none()
    }
}

/// PSNR in dB of an RMSE on the [0, 1] scale, capped at [`PSNR_CAP_DB`].
pub fn psnr_db(rmse: f64) -> f64 {
    if rmse.is_nan() {
        return 0.0;
    }
    if rmse <= 0.0 {
        return PSNR_CAP_DB;
    }
    (20.0 * (1.0 / rmse).log10()).min(PSNR_CAP_DB)
}

/// A linear RGB image in `f64`, row-major, `px.len() == width * height`.
#[derive(Debug, Clone, PartialEq)]
pub struct Rgb64 {
    pub width: u32,
    pub height: u32,
    pub px: Vec<[f64; 3]>,
}

impl Rgb64 {
    /// A black image.
    pub fn new(width: u32, height: u32) -> Self {
        Rgb64 {
            width,
            height,
            px: vec![[0.0; 3]; width as usize * height as usize],
        }
    }

    /// Index of pixel `(x, y)`, if it lies inside the image (and inside `px`).
    pub fn index(&self, x: u32, y: u32) -> Option<usize> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = y as usize * self.width as usize + x as usize;
        (i < self.px.len()).then_some(i)
    }

    /// Pixel `(x, y)`; black outside the image.
    pub fn get(&self, x: u32, y: u32) -> [f64; 3] {
        self.index(x, y).map_or([0.0; 3], |i| self.px[i])
    }

    /// Set pixel `(x, y)`; a pixel outside the image is ignored.
    pub fn set(&mut self, x: u32, y: u32, c: [f64; 3]) {
        if let Some(i) = self.index(x, y) {
            self.px[i] = c;
        }
    }

    /// The 8-bit image: each channel `round_half_up(clamp(x, 0, 1) * 255)`, NaN as 0.
    pub fn to_rgb8(&self) -> image::RgbImage {
        let mut img = image::RgbImage::new(self.width, self.height);
        for (x, y, p) in img.enumerate_pixels_mut() {
            p.0 = self.get(x, y).map(to_u8);
        }
        img
    }

    /// An image from 8-bit values, `c / 255` (no sRGB decoding: the values are taken as
    /// linear, as [`Rgb64::to_rgb8`] writes them).
    pub fn from_rgb8(img: &image::RgbImage) -> Self {
        let mut out = Rgb64::new(img.width(), img.height());
        for (x, y, p) in img.enumerate_pixels() {
            out.set(x, y, p.0.map(|c| c as f64 / 255.0));
        }
        out
    }
}

/// One channel in [0, 1] (NaN as 0).
/// A channel value clamped to [0, 1], NaN as 0.
pub(crate) fn unit(x: f64) -> f64 {
    if x.is_nan() {
        0.0
    } else {
        x.clamp(0.0, 1.0)
    }
}

/// One channel to 8 bits, rounding half up.
fn to_u8(x: f64) -> u8 {
    (unit(x) * 255.0 + 0.5).floor() as u8
}

fn covered(mask: &[bool], img: &Rgb64, x: u32, y: u32) -> Option<[f64; 3]> {
    let i = img.index(x, y)?;
    mask.get(i).copied().unwrap_or(false).then(|| img.px[i])
}

/// Per-channel absolute errors of pixel `(x, y)` when it is covered in both images.
fn pixel_error(
    a: &Rgb64,
    a_mask: &[bool],
    b: &Rgb64,
    b_mask: &[bool],
    x: u32,
    y: u32,
) -> Option<[f64; 3]> {
    let pa = covered(a_mask, a, x, y)?;
    let pb = covered(b_mask, b, x, y)?;
    Some([0, 1, 2].map(|c| (unit(pa[c]) - unit(pb[c])).abs()))
}

/// Compare two images over the pixels covered in both masks (see the module documentation).
pub fn compare(a: &Rgb64, a_mask: &[bool], b: &Rgb64, b_mask: &[bool]) -> ErrorStats {
    let (w, h) = (a.width.min(b.width), a.height.min(b.height));
    let (mut pixels, mut sum_sq, mut sum_abs, mut max_abs) = (0u64, 0.0f64, 0.0f64, 0.0f64);
    for y in 0..h {
        for x in 0..w {
            if let Some(e) = pixel_error(a, a_mask, b, b_mask, x, y) {
                pixels += 1;
                for d in e {
                    sum_sq += d * d;
                    sum_abs += d;
                    max_abs = max_abs.max(d);
                }
            }
        }
    }
    if pixels == 0 {
        return ErrorStats {
            psnr_db: PSNR_CAP_DB,
            rmse: 0.0,
            max_abs_lsb: 0.0,
            mean_abs_lsb: 0.0,
            pixels: 0,
        };
    }
    let n = 3.0 * pixels as f64;
    let rmse = (sum_sq / n).sqrt();
    ErrorStats {
        psnr_db: psnr_db(rmse),
        rmse,
        max_abs_lsb: max_abs * 255.0,
        mean_abs_lsb: sum_abs / n * 255.0,
        pixels,
    }
}

/// The heatmap colour ramp: five stops at 0, 1/4, 1/2, 3/4 and 1, after matplotlib's
/// "inferno" (with pure black at 0), interpolated linearly in 8-bit RGB.
pub const RAMP: [[u8; 3]; 5] = [
    [0, 0, 0],
    [87, 16, 110],
    [188, 55, 84],
    [249, 142, 9],
    [252, 255, 164],
];

/// Colour of `t` in [0, 1] on [`RAMP`] (clamped; NaN as 0), channels rounded half up.
pub fn ramp(t: f64) -> [u8; 3] {
    let t = unit(t) * (RAMP.len() - 1) as f64;
    let k = (t.floor() as usize).min(RAMP.len() - 2);
    let f = t - k as f64;
    let (a, b) = (RAMP[k], RAMP[k + 1]);
    [0, 1, 2].map(|c| (a[c] as f64 + (b[c] as f64 - a[c] as f64) * f + 0.5).floor() as u8)
}

/// Per-pixel error heatmap of `a` against `b`, the size of `a`.
///
/// A pixel covered in both images shows its largest channel error `e` (in 8-bit LSBs) as
/// `ramp(e / full_scale_lsb)`: black for no error, saturating at the last stop (pale yellow)
/// at `full_scale_lsb` LSBs and above. A pixel not covered in both is dark grey
/// [`UNCOVERED`]. A `full_scale_lsb` that is not positive (or NaN) makes every nonzero error
/// saturate.
pub fn heatmap(
    a: &Rgb64,
    a_mask: &[bool],
    b: &Rgb64,
    b_mask: &[bool],
    full_scale_lsb: f64,
) -> image::RgbImage {
    let full = if full_scale_lsb > 0.0 {
        full_scale_lsb
    } else {
        f64::MIN_POSITIVE
    };
    let mut img = image::RgbImage::new(a.width, a.height);
    for (x, y, p) in img.enumerate_pixels_mut() {
        p.0 = match pixel_error(a, a_mask, b, b_mask, x, y) {
            None => UNCOVERED,
            Some(e) => {
                let lsb = e[0].max(e[1]).max(e[2]) * 255.0;
                if lsb == 0.0 {
                    RAMP[0]
                } else {
                    ramp(lsb / full)
                }
            }
        };
    }
    img
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    /// 2x2 grey images, all covered, pixel (1, 0) green differs by one 8-bit LSB.
    fn one_lsb_pair() -> (Rgb64, Rgb64, Vec<bool>) {
        let mut a = Rgb64::new(2, 2);
        for p in &mut a.px {
            *p = [0.5; 3];
        }
        let mut b = a.clone();
        b.set(1, 0, [0.5, 0.5 + 1.0 / 255.0, 0.5]);
        (a, b, vec![true; 4])
    }

    #[test]
    fn one_lsb_in_one_channel_of_one_pixel() {
        let (a, b, m) = one_lsb_pair();
        let s = compare(&a, &m, &b, &m);
        assert_eq!(s.pixels, 4);
        // 12 channel values, one of them off by 1/255
        let rmse = (1.0f64 / 255.0) / 12f64.sqrt();
        assert!(close(s.rmse, rmse, 1e-15), "{}", s.rmse);
        assert!(close(s.rmse, 0.0011320, 1e-7));
        // 20 log10(255 sqrt 12) = 48.1308 + 10.7918
        assert!(close(s.psnr_db, 58.92256, 1e-4), "{}", s.psnr_db);
        assert!(close(s.max_abs_lsb, 1.0, 1e-9));
        assert!(close(s.mean_abs_lsb, 1.0 / 12.0, 1e-9));
        // symmetric
        assert_eq!(compare(&b, &m, &a, &m), s);
    }

    #[test]
    fn only_pixels_covered_in_both_masks_count() {
        let (a, b, m) = one_lsb_pair();
        let mut ma = m.clone();
        ma[1] = false; // the differing pixel
        let s = compare(&a, &ma, &b, &m);
        assert_eq!(s.pixels, 3);
        assert_eq!(s.rmse, 0.0);
        assert_eq!(s.psnr_db, PSNR_CAP_DB);
        assert_eq!(s.max_abs_lsb, 0.0);
        let mut mb = m.clone();
        mb[0] = false;
        mb[3] = false;
        let s = compare(&a, &m, &b, &mb);
        assert_eq!(s.pixels, 2);
        assert!(close(s.mean_abs_lsb, 1.0 / 6.0, 1e-9));
        // short masks and mismatched sizes do not panic
        let s = compare(&a, &[true], &Rgb64::new(1, 5), &[true; 5]);
        assert_eq!(s.pixels, 1);
        assert!(close(s.max_abs_lsb, 127.5, 1e-9));
        let s = compare(&a, &[], &b, &m);
        assert_eq!((s.pixels, s.psnr_db, s.rmse), (0, PSNR_CAP_DB, 0.0));
    }

    #[test]
    fn values_are_clamped_and_nan_is_zero() {
        let mut a = Rgb64::new(1, 1);
        let mut b = Rgb64::new(1, 1);
        a.set(0, 0, [1.5, -0.2, f64::NAN]);
        b.set(0, 0, [1.0, 0.0, 0.0]);
        let s = compare(&a, &[true], &b, &[true]);
        assert_eq!(s.rmse, 0.0);
        b.set(0, 0, [0.0, 1.0, 0.0]);
        let s = compare(&a, &[true], &b, &[true]);
        assert!(close(s.rmse, (2.0f64 / 3.0).sqrt(), 1e-15));
        assert!(close(s.psnr_db, 1.760913, 1e-6));
        assert_eq!(s.max_abs_lsb, 255.0);
        assert!(close(s.mean_abs_lsb, 170.0, 1e-9));
    }

    #[test]
    fn psnr_of_rmse() {
        assert!(close(psnr_db(0.1), 20.0, 1e-12));
        assert!(close(psnr_db(1.0), 0.0, 1e-12));
        assert_eq!(psnr_db(0.0), PSNR_CAP_DB);
        assert_eq!(psnr_db(1e-300), PSNR_CAP_DB);
    }

    #[test]
    fn json_never_has_nan_or_infinity() {
        let (a, b, m) = one_lsb_pair();
        let same = compare(&a, &m, &a, &m);
        let j = serde_json::to_string(&same).unwrap();
        assert_eq!(
            j,
            r#"{"psnr_db":999.0,"rmse":0.0,"max_abs_lsb":0.0,"mean_abs_lsb":0.0,"pixels":4}"#
        );
        let bad = ErrorStats {
            psnr_db: f64::INFINITY,
            rmse: f64::NAN,
            max_abs_lsb: f64::NEG_INFINITY,
            mean_abs_lsb: 0.5,
            pixels: 1,
        };
        let j = serde_json::to_string(&bad).unwrap();
        assert_eq!(
            j,
            r#"{"psnr_db":999.0,"rmse":null,"max_abs_lsb":null,"mean_abs_lsb":0.5,"pixels":1}"#
        );
        let v: serde_json::Value = serde_json::from_str(&j).unwrap();
        assert_eq!(v["psnr_db"], 999.0);
        let s = compare(&a, &m, &b, &m);
        let v: serde_json::Value = serde_json::to_value(s).unwrap();
        assert!((v["psnr_db"].as_f64().unwrap() - 58.92256).abs() < 1e-4);
    }

    #[test]
    fn to_rgb8_rounds_half_up_and_clamps() {
        let mut img = Rgb64::new(2, 1);
        img.set(0, 0, [0.5, 0.25, 1.2]); // 127.5 -> 128, 63.75 -> 64, clamped -> 255
        img.set(1, 0, [-1.0, f64::NAN, 0.4999 / 255.0]);
        let out = img.to_rgb8();
        assert_eq!(out.get_pixel(0, 0).0, [128, 64, 255]);
        assert_eq!(out.get_pixel(1, 0).0, [0, 0, 0]);
        let back = Rgb64::from_rgb8(&out);
        assert_eq!(back.get(0, 0), [128.0 / 255.0, 64.0 / 255.0, 1.0]);
        assert_eq!(back.to_rgb8(), out);
        // out-of-range access is harmless
        img.set(5, 5, [1.0; 3]);
        assert_eq!(img.get(5, 5), [0.0; 3]);
    }

    #[test]
    fn ramp_stops_and_interpolation() {
        assert_eq!(ramp(0.0), [0, 0, 0]);
        assert_eq!(ramp(0.25), [87, 16, 110]);
        assert_eq!(ramp(0.5), [188, 55, 84]);
        assert_eq!(ramp(1.0), [252, 255, 164]);
        assert_eq!(ramp(7.0), [252, 255, 164]);
        assert_eq!(ramp(f64::NAN), [0, 0, 0]);
        // 1/8: halfway to the second stop: (43.5, 8, 55) rounded half up
        assert_eq!(ramp(0.125), [44, 8, 55]);
    }

    #[test]
    fn heatmap_colours() {
        let (a, mut b, m) = one_lsb_pair();
        b.set(0, 1, [0.5 - 8.0 / 255.0, 0.5, 0.5 + 2.0 / 255.0]); // max error 8 LSB
        let mut mb = m.clone();
        mb[3] = false;
        let h = heatmap(&a, &m, &b, &mb, 4.0);
        assert_eq!((h.width(), h.height()), (2, 2));
        assert_eq!(h.get_pixel(0, 0).0, [0, 0, 0]); // no error
        assert_eq!(h.get_pixel(1, 0).0, [87, 16, 110]); // 1 of 4 LSB: second stop
        assert_eq!(h.get_pixel(0, 1).0, [252, 255, 164]); // 8 >= 4: saturated
        assert_eq!(h.get_pixel(1, 1).0, UNCOVERED);
        let h = heatmap(&a, &m, &b, &mb, 2.0);
        assert_eq!(h.get_pixel(1, 0).0, [188, 55, 84]); // 1 of 2 LSB: middle stop
        let h = heatmap(&a, &m, &b, &mb, 0.0);
        assert_eq!(h.get_pixel(1, 0).0, [252, 255, 164]);
        assert_eq!(h.get_pixel(0, 0).0, [0, 0, 0]);
        // a smaller `b` leaves the missing pixels uncovered
        let h = heatmap(&a, &m, &Rgb64::new(1, 1), &[true], 4.0);
        assert_eq!(h.get_pixel(1, 1).0, UNCOVERED);
        assert_eq!(h.get_pixel(0, 0).0, [252, 255, 164]); // 0.5 vs 0: 127.5 LSB
    }
}

/// The light an engine keeps where the texture is one colour, against the reference: the
/// sum of `image`'s 8-bit channels over the pixels where `texture` (the texels the engine
/// fetched, e.g. a render whose output is the texture unit) is exactly `texel` and the
/// reference is not black, over the reference's sum there; `None` if the reference has no
/// light there. Ernst et al. 1998 §5.1's claim that the combined order "has no effect on black
/// texture color due to the multiplication" is this share on the black texels
/// (`tests/gouraud_order.rs`, `docs/studies/gouraud-bump.md`).
pub fn light_share(
    image: &image::RgbImage,
    reference: &image::RgbImage,
    texture: &image::RgbImage,
    texel: [u8; 3],
) -> Option<f64> {
    let (mut kept, mut want) = (0u64, 0u64);
    for (x, y, t) in texture.enumerate_pixels() {
        let (Some(i), Some(r)) = (
            image.get_pixel_checked(x, y),
            reference.get_pixel_checked(x, y),
        ) else {
            continue;
        };
        if t.0 != texel || r.0 == [0, 0, 0] {
            continue;
        }
        kept += i.0.iter().map(|&c| u64::from(c)).sum::<u64>();
        want += r.0.iter().map(|&c| u64::from(c)).sum::<u64>();
    }
    (want > 0).then(|| kept as f64 / want as f64)
}

#[cfg(test)]
mod light_share_tests {
    use super::light_share;
    use image::{Rgb, RgbImage};

    #[test]
    fn light_share_counts_only_the_texels_asked_for() {
        // a 2x1 texture: black, white; the reference lights both; the image keeps half of
        // the black texel's light and all of the white one's
        let tex = RgbImage::from_fn(2, 1, |x, _| Rgb([255 * x as u8; 3]));
        let reference = RgbImage::from_pixel(2, 1, Rgb([100, 100, 100]));
        let img = RgbImage::from_fn(2, 1, |x, _| Rgb(if x == 0 { [50; 3] } else { [100; 3] }));
        assert_eq!(light_share(&img, &reference, &tex, [0; 3]), Some(0.5));
        assert_eq!(light_share(&img, &reference, &tex, [255; 3]), Some(1.0));
        assert_eq!(light_share(&img, &reference, &tex, [7; 3]), None);
        let dark = RgbImage::new(2, 1);
        assert_eq!(light_share(&img, &dark, &tex, [0; 3]), None);
    }
}
