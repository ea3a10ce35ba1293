//! Artifact metrics: measures of what a reader of a render sees, beside PSNR. Each compares a
//! test image `a` with a reference `r` over the pixels covered in both (the top-left
//! `min(width) x min(height)` rectangle, as in [`crate::metrics::compare`]). Channel values
//! are clamped to [0, 1] (NaN as 0) and taken in 8-bit LSBs (times 255), without rounding.
//! The definitions and formulas are in `docs/metrics.md`:
//!
//! * `banding`: false-contour length, contour edges per covered pixel;
//! * `blockiness`: steps between plateaus per covered pixel, specks included;
//! * `faceting_lsb`: RMS difference of the discrete Laplacians of the two images after a
//!   3x3 box blur (gradient discontinuities such as triangle edges of Gouraud shading);
//! * `ringing_lsb`: mean overshoot beyond the reference's local range near strong edges;
//! * `lowpass_psnr_db`: PSNR after a 5x5 binomial blur of both images;
//! * `half_ssim`: mean SSIM of the luma at half resolution (2x2 box), 7x7 windows;
//! * `ms_ssim`: multi-scale SSIM of the luma (Wang, Simoncelli and Bovik 2003), five scales
//!   of 7x7 windows.
//!
//! Every sum runs in a fixed pixel order, so the figures are the same at any thread count.

use crate::metrics::{psnr_db, ser_finite, ser_psnr, unit, Rgb64, PSNR_CAP_DB};
use serde::Serialize;

/// A step of the reference of at most this many LSBs between neighbours is "smooth".
pub const SMOOTH_LSB: f64 = 1.0;
/// A step of the error larger than this (LSB) is more than rounding to 8 bits explains.
pub const FALSE_STEP_LSB: f64 = 1.0;
/// Neighbouring values closer than this (LSB) are equal (a plateau).
pub const FLAT_LSB: f64 = 0.5;
/// The smallest group of 8-connected pixels with a step that `banding` counts as a contour
/// (shorter groups are specks: the resolved steps of dither noise).
pub const MIN_CONTOUR_PX: usize = 8;
/// A reference step of at least this many LSBs between neighbours is a strong edge.
pub const STRONG_EDGE_LSB: f64 = 32.0;
/// Pixels within this Chebyshev distance of a strong edge are "near" it (ringing).
pub const RINGING_RADIUS: i64 = 2;
/// SSIM window side (at half resolution).
pub const SSIM_WINDOW: usize = 7;

/// The artifact figures of one image against another.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ArtifactStats {
    /// False-contour edges per covered pixel.
    #[serde(serialize_with = "ser_finite")]
    pub banding: f64,
    /// False-contour edges (pixel pairs).
    pub banding_edges: u64,
    /// Steps between plateaus per covered pixel, specks included: blocks of any size (the
    /// contour edges are those of them in groups of [`MIN_CONTOUR_PX`] or more).
    #[serde(serialize_with = "ser_finite")]
    pub blockiness: f64,
    /// Steps between plateaus (pixel pairs), specks included.
    pub blockiness_edges: u64,
    /// RMS Laplacian difference after a 3x3 box blur, in LSB.
    #[serde(serialize_with = "ser_finite")]
    pub faceting_lsb: f64,
    /// Mean overshoot near strong reference edges, in LSB.
    #[serde(serialize_with = "ser_finite")]
    pub ringing_lsb: f64,
    /// Pixels near strong reference edges (where ringing is measured).
    pub ringing_pixels: u64,
    /// PSNR after a 5x5 binomial blur of both images, capped at 999 dB.
    #[serde(serialize_with = "ser_psnr")]
    pub lowpass_psnr_db: f64,
    /// Mean SSIM of the luma at half resolution (1 for identical images or no window).
    #[serde(serialize_with = "ser_finite")]
    pub half_ssim: f64,
    /// Multi-scale SSIM of the luma over up to five scales (1 for identical images or no
    /// window).
    #[serde(serialize_with = "ser_finite")]
    pub ms_ssim: f64,
}

/// Two images on a common grid with the pixels covered in both. The values are read from
/// the images where they lie, in LSBs, as they are needed (no copy of either image is made:
/// the working memory of every measure is a few rows, and the masks).
struct Pair<'a> {
    w: usize,
    h: usize,
    a: &'a Rgb64,
    r: &'a Rgb64,
    cov: Vec<bool>,
}

impl<'a> Pair<'a> {
    fn new(a: &'a Rgb64, a_mask: &[bool], r: &'a Rgb64, r_mask: &[bool]) -> Pair<'a> {
        let (w, h) = (a.width.min(r.width), a.height.min(r.height));
        let n = w as usize * h as usize;
        let mut cov = vec![false; n];
        for y in 0..h {
            for x in 0..w {
                let i = y as usize * w as usize + x as usize;
                let (Some(ia), Some(ir)) = (a.index(x, y), r.index(x, y)) else {
                    continue;
                };
                cov[i] = a_mask.get(ia).copied().unwrap_or(false)
                    && r_mask.get(ir).copied().unwrap_or(false);
            }
        }
        Pair {
            w: w as usize,
            h: h as usize,
            a,
            r,
            cov,
        }
    }

    /// The index in `img` of grid pixel `i` (a covered pixel lies inside both images).
    #[inline]
    fn index_in(&self, img: &Rgb64, i: usize) -> usize {
        let iw = img.width as usize;
        if iw == self.w {
            i
        } else {
            i / self.w * iw + i % self.w
        }
    }

    /// The test image at covered grid pixel `i`, in LSBs.
    #[inline]
    fn pa(&self, i: usize) -> [f64; 3] {
        self.a.px[self.index_in(self.a, i)].map(|v| unit(v) * 255.0)
    }

    /// The reference at covered grid pixel `i`, in LSBs.
    #[inline]
    fn pr(&self, i: usize) -> [f64; 3] {
        self.r.px[self.index_in(self.r, i)].map(|v| unit(v) * 255.0)
    }

    /// Index of `(x, y)` if inside and covered.
    #[inline]
    fn at(&self, x: i64, y: i64) -> Option<usize> {
        if x < 0 || y < 0 || x >= self.w as i64 || y >= self.h as i64 {
            return None;
        }
        let i = y as usize * self.w + x as usize;
        self.cov[i].then_some(i)
    }

    fn covered(&self) -> u64 {
        self.cov.iter().filter(|&&c| c).count() as u64
    }
}

/// Measure `a` against the reference `r` (see the module documentation).
pub fn measure(a: &Rgb64, a_mask: &[bool], r: &Rgb64, r_mask: &[bool]) -> ArtifactStats {
    let p = Pair::new(a, a_mask, r, r_mask);
    let mut steps = plateau_steps(&p);
    let per_px = |n: u64| {
        let cov = p.covered();
        if cov == 0 {
            0.0
        } else {
            n as f64 / cov as f64
        }
    };
    let blockiness_edges = steps
        .iter()
        .map(|&s| u64::from(s & 1) + u64::from((s >> 1) & 1))
        .sum::<u64>();
    let banding_edges = contour_steps(&mut steps, p.w, p.h);
    let (ringing_lsb, ringing_pixels) = ringing(&p);
    let (half_ssim, ms_ssim) = ssim_pair(&p);
    ArtifactStats {
        banding: per_px(banding_edges),
        banding_edges,
        blockiness: per_px(blockiness_edges),
        blockiness_edges,
        faceting_lsb: faceting(&p),
        ringing_lsb,
        ringing_pixels,
        lowpass_psnr_db: lowpass_psnr(&p),
        half_ssim,
        ms_ssim,
    }
}

/// False contours: neighbour pairs `(p, q)` (horizontal and vertical) where, in some channel,
/// the reference is smooth (`|r_q - r_p| <= SMOOTH_LSB`), the error steps by more than
/// rounding explains (`|(a_q - a_p) - (r_q - r_p)| > FALSE_STEP_LSB`), and the test image is
/// flat on both sides (`|a_p - a_{p-d}| < FLAT_LSB` and `|a_{q+d} - a_q| < FLAT_LSB`): a step
/// between two plateaus, marked at `p` (bit 0: to the right, bit 1: down), on a `w x h` grid.
/// All of them are `blockiness`; those whose pixel lies in an 8-connected group of at least
/// [`MIN_CONTOUR_PX`] pixels with a step are `banding`'s contour edges ([`contour_steps`]: a
/// band's boundary is a line across the image, the steps of a dither pattern resolved on
/// screen are specks).
fn plateau_steps(p: &Pair) -> Vec<u8> {
    let mut steps = vec![0u8; p.w * p.h];
    for (bit, (dx, dy)) in [(1u8, (1i64, 0i64)), (2, (0, 1))] {
        for y in 0..p.h as i64 {
            for x in 0..p.w as i64 {
                let (Some(i0), Some(i1), Some(i2), Some(i3)) = (
                    p.at(x - dx, y - dy),
                    p.at(x, y),
                    p.at(x + dx, y + dy),
                    p.at(x + 2 * dx, y + 2 * dy),
                ) else {
                    continue;
                };
                let (a0, a1, a2, a3) = (p.pa(i0), p.pa(i1), p.pa(i2), p.pa(i3));
                let (r1, r2) = (p.pr(i1), p.pr(i2));
                let hit = (0..3).any(|c| {
                    let dr = r2[c] - r1[c];
                    let da = a2[c] - a1[c];
                    dr.abs() <= SMOOTH_LSB
                        && (da - dr).abs() > FALSE_STEP_LSB
                        && (a1[c] - a0[c]).abs() < FLAT_LSB
                        && (a3[c] - a2[c]).abs() < FLAT_LSB
                });
                if hit {
                    steps[i1] |= bit;
                }
            }
        }
    }
    steps
}

/// The steps (bits 0 and 1 of `steps`, a `w x h` grid) whose pixel lies in an 8-connected
/// group of at least [`MIN_CONTOUR_PX`] pixels with a step. Groups are found in row-major
/// order of their first pixel with an explicit stack (bounded memory, any image size).
fn contour_steps(steps: &mut [u8], w: usize, h: usize) -> u64 {
    const VISITED: u8 = 4;
    let count = |s: u8| u64::from(s & 1) + u64::from((s >> 1) & 1);
    let mut total = 0u64;
    let mut stack = Vec::new();
    for start in 0..steps.len() {
        if steps[start] & 3 == 0 || steps[start] & VISITED != 0 {
            continue;
        }
        steps[start] |= VISITED;
        stack.push(start);
        let (mut pixels, mut edges) = (0usize, 0u64);
        while let Some(i) = stack.pop() {
            pixels += 1;
            edges += count(steps[i]);
            let (x, y) = ((i % w) as i64, (i / w) as i64);
            for (dx, dy) in NEIGHBOURS_8 {
                let (nx, ny) = (x + dx, y + dy);
                if nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                    continue;
                }
                let j = ny as usize * w + nx as usize;
                if steps[j] & 3 != 0 && steps[j] & VISITED == 0 {
                    steps[j] |= VISITED;
                    stack.push(j);
                }
            }
        }
        if pixels >= MIN_CONTOUR_PX {
            total += edges;
        }
    }
    total
}

const NEIGHBOURS_8: [(i64, i64); 8] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (-1, 0),
    (1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];

/// The values of both sides of a [`Pair`] in LSBs for a band of consecutive rows (row `y` in
/// slot `y mod rows`), each pixel converted once for all the taps that read it.
struct Band {
    w: usize,
    rows: usize,
    a: Vec<[f64; 3]>,
    r: Vec<[f64; 3]>,
    /// The row each slot holds (`i64::MIN`: none yet).
    held: Vec<i64>,
}

impl Band {
    fn new(p: &Pair, rows: usize) -> Band {
        let n = p.w * rows;
        Band {
            w: p.w,
            rows,
            a: vec![[0.0; 3]; n],
            r: vec![[0.0; 3]; n],
            held: vec![i64::MIN; rows],
        }
    }

    /// Make rows `y0..=y1` (those inside the grid) held; rows must be asked for in
    /// increasing order, at most `rows` at a time.
    fn hold(&mut self, p: &Pair, y0: i64, y1: i64) {
        for y in y0.max(0)..=y1.min(p.h as i64 - 1) {
            let slot = y as usize % self.rows;
            if self.held[slot] == y {
                continue;
            }
            self.held[slot] = y;
            for x in 0..p.w {
                if let Some(i) = p.at(x as i64, y) {
                    self.a[slot * self.w + x] = p.pa(i);
                    self.r[slot * self.w + x] = p.pr(i);
                }
            }
        }
    }

    /// Both sides at held, covered `(x, y)`.
    #[inline]
    fn at(&self, x: usize, y: usize) -> ([f64; 3], [f64; 3]) {
        let k = (y % self.rows) * self.w + x;
        (self.a[k], self.r[k])
    }
}

/// The masked blur of both sides of `p` at covered pixel `(x, y)`: for each, the weighted
/// mean over covered pixels with the separable kernel `k` (odd length), renormalised over the
/// covered taps. The two sides share the taps (and their weight sum); each side's sum runs
/// in the same order as alone. `band` holds rows `y - k.len() / 2 ..= y + k.len() / 2`.
#[inline]
fn blur_at(p: &Pair, band: &Band, k: &[f64], x: i64, y: i64) -> ([f64; 3], [f64; 3]) {
    let rad = (k.len() / 2) as i64;
    let (mut sa, mut sr, mut wsum) = ([0.0; 3], [0.0; 3], 0.0);
    for (ky, wy) in k.iter().enumerate() {
        for (kx, wx) in k.iter().enumerate() {
            let (u, v) = (x + kx as i64 - rad, y + ky as i64 - rad);
            if p.at(u, v).is_some() {
                let wgt = wx * wy;
                wsum += wgt;
                let (va, vr) = band.at(u as usize, v as usize);
                for c in 0..3 {
                    sa[c] += wgt * va[c];
                    sr[c] += wgt * vr[c];
                }
            }
        }
    }
    (sa.map(|v| v / wsum), sr.map(|v| v / wsum))
}

/// Row `y` of the masked blur of both sides of `p` into `a` and `r` (0 where not covered;
/// nothing outside the grid), holding the rows it reads in `band`.
fn blur_row(p: &Pair, band: &mut Band, k: &[f64], y: i64, a: &mut [[f64; 3]], r: &mut [[f64; 3]]) {
    if y < 0 || y >= p.h as i64 {
        a.fill([0.0; 3]);
        r.fill([0.0; 3]);
        return;
    }
    let rad = (k.len() / 2) as i64;
    band.hold(p, y - rad, y + rad);
    for (x, (oa, or)) in a.iter_mut().zip(r.iter_mut()).enumerate() {
        (*oa, *or) = if p.at(x as i64, y).is_some() {
            blur_at(p, band, k, x as i64, y)
        } else {
            ([0.0; 3], [0.0; 3])
        };
    }
}

/// Faceting: `sqrt(mean((L(Ba) - L(Br))^2))` over the pixels whose 4 neighbours are covered
/// and every channel, where `B` is the masked 3x3 box blur and `L` the 5-point Laplacian.
/// The blurred images are kept as three rows each (above, at and below the pixel).
fn faceting(p: &Pair) -> f64 {
    let k = [1.0, 1.0, 1.0];
    let row = || vec![[0.0; 3]; p.w];
    // [above, at, below] for the test image and the reference
    let (mut ba, mut br) = ([row(), row(), row()], [row(), row(), row()]);
    let mut band = Band::new(p, k.len());
    blur_row(p, &mut band, &k, 0, &mut ba[1], &mut br[1]);
    blur_row(p, &mut band, &k, 1, &mut ba[2], &mut br[2]);
    let (mut sum, mut n) = (0.0, 0u64);
    for y in 0..p.h as i64 {
        if y > 0 {
            ba.rotate_left(1);
            br.rotate_left(1);
            blur_row(p, &mut band, &k, y + 1, &mut ba[2], &mut br[2]);
        }
        for x in 0..p.w as i64 {
            if p.at(x, y).is_none() {
                continue;
            }
            let nb = [(x - 1, y), (x + 1, y), (x, y - 1), (x, y + 1)].map(|(u, v)| p.at(u, v));
            if nb.iter().any(Option::is_none) {
                continue;
            }
            let xu = x as usize;
            for c in 0..3 {
                let lap = |img: &[Vec<[f64; 3]>; 3]| {
                    [img[1][xu - 1], img[1][xu + 1], img[0][xu], img[2][xu]]
                        .iter()
                        .map(|v| v[c])
                        .sum::<f64>()
                        - 4.0 * img[1][xu][c]
                };
                let d = lap(&ba) - lap(&br);
                sum += d * d;
                n += 1;
            }
        }
    }
    if n == 0 {
        0.0
    } else {
        (sum / n as f64).sqrt()
    }
}

/// Ringing: the pixels within `RINGING_RADIUS` (Chebyshev) of a strong edge pixel (one with a
/// 4-neighbour whose reference differs by at least `STRONG_EDGE_LSB` in some channel); for
/// each, the largest over channels of the test value's distance outside the reference's range
/// over the covered pixels of the 5x5 window around it; the mean of that over those pixels.
///
/// The window's nearness and range are separable (a dilation and a min / max, exact in any
/// order): each row's horizontal pass is kept for the window's rows, and the vertical pass
/// reads those. The same figures as the direct 5x5 scan (`tests::ringing_direct`).
fn ringing(p: &Pair) -> (f64, u64) {
    let (w, h) = (p.w, p.h);
    let strong = strong_edges(p);
    let rad = RINGING_RADIUS;
    let rows = 2 * rad as usize + 1;
    // per held row: whether a strong pixel lies within `rad` columns, and the reference's
    // range over the covered pixels within `rad` columns (infinite where there is none)
    let mut near_h = vec![false; w * rows];
    let mut lo_h = vec![[f64::INFINITY; 3]; w * rows];
    let mut hi_h = vec![[f64::NEG_INFINITY; 3]; w * rows];
    let mut held = vec![i64::MIN; rows];
    let mut vals = vec![None; w];
    let mut hold = |v: i64, near_h: &mut [bool], lo_h: &mut [[f64; 3]], hi_h: &mut [[f64; 3]]| {
        let slot = v as usize % rows;
        if held[slot] == v {
            return;
        }
        held[slot] = v;
        for (x, c) in vals.iter_mut().enumerate() {
            *c = p.at(x as i64, v).map(|j| (strong[j], p.pr(j)));
        }
        for x in 0..w {
            let (mut near, mut lo, mut hi) = (false, [f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            let x0 = (x as i64 - rad).max(0) as usize;
            let x1 = (x + rad as usize).min(w - 1);
            for (s, rj) in vals[x0..=x1].iter().flatten() {
                near |= *s;
                for c in 0..3 {
                    lo[c] = lo[c].min(rj[c]);
                    hi[c] = hi[c].max(rj[c]);
                }
            }
            let k = slot * w + x;
            (near_h[k], lo_h[k], hi_h[k]) = (near, lo, hi);
        }
    };
    let (mut sum, mut count) = (0.0, 0u64);
    for y in 0..h as i64 {
        let window = (y - rad).max(0)..=(y + rad).min(h as i64 - 1);
        for v in window.clone() {
            hold(v, &mut near_h, &mut lo_h, &mut hi_h);
        }
        for x in 0..w {
            let Some(i) = p.at(x as i64, y) else { continue };
            // a window without a strong pixel is skipped before any value is read
            let slots = || window.clone().map(|v| v as usize % rows * w + x);
            if !slots().any(|k| near_h[k]) {
                continue;
            }
            let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            for k in slots() {
                for c in 0..3 {
                    lo[c] = lo[c].min(lo_h[k][c]);
                    hi[c] = hi[c].max(hi_h[k][c]);
                }
            }
            sum += overshoot(p.pa(i), lo, hi);
            count += 1;
        }
    }
    (if count == 0 { 0.0 } else { sum / count as f64 }, count)
}

/// The largest over channels of `a`'s distance outside `[lo, hi]` (ringing).
fn overshoot(a: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> f64 {
    (0..3)
        .map(|c| (a[c] - hi[c]).max(0.0) + (lo[c] - a[c]).max(0.0))
        .fold(0.0, f64::max)
}

/// The strong edge pixels of the reference (see [`ringing`]), per grid pixel.
fn strong_edges(p: &Pair) -> Vec<bool> {
    let mut strong = vec![false; p.w * p.h];
    for y in 0..p.h as i64 {
        for x in 0..p.w as i64 {
            let Some(i) = p.at(x, y) else { continue };
            let ri = p.pr(i);
            for (u, v) in [(x + 1, y), (x, y + 1)] {
                if let Some(j) = p.at(u, v) {
                    let rj = p.pr(j);
                    if (0..3).any(|c| (rj[c] - ri[c]).abs() >= STRONG_EDGE_LSB) {
                        strong[i] = true;
                        strong[j] = true;
                    }
                }
            }
        }
    }
    strong
}

/// PSNR (on the [0, 1] scale) of the two images after the masked 5x5 binomial blur
/// `[1, 4, 6, 4, 1] / 16` in x and y (each blurred pixel computed where it is summed).
fn lowpass_psnr(p: &Pair) -> f64 {
    let k = [1.0, 4.0, 6.0, 4.0, 1.0].map(|v| v / 16.0);
    let (mut sum, mut n) = (0.0, 0u64);
    let mut band = Band::new(p, k.len());
    let rad = (k.len() / 2) as i64;
    for y in 0..p.h as i64 {
        band.hold(p, y - rad, y + rad);
        for x in 0..p.w as i64 {
            if p.at(x, y).is_none() {
                continue;
            }
            let (ba, br) = blur_at(p, &band, &k, x, y);
            for c in 0..3 {
                let d = (ba[c] - br[c]) / 255.0;
                sum += d * d;
                n += 1;
            }
        }
    }
    if n == 0 {
        return PSNR_CAP_DB;
    }
    psnr_db((sum / n as f64).sqrt())
}

/// Lumas `(test, reference)` of a row, `None` where a pixel is not defined.
type LumaRow = Vec<Option<(f64, f64)>>;

/// One scale of the SSIM pyramid: its rows, made as the windows need them.
trait Scale {
    fn w(&self) -> usize;
    fn h(&self) -> usize;
    /// Row `y` into `out` (`w` long).
    fn row(&self, y: usize, out: &mut [Option<(f64, f64)>]);
}

/// The full-resolution luma `Y = 0.299 R + 0.587 G + 0.114 B` (on [0, 1]) of the covered
/// pixels, read from the images as it is needed.
struct FullScale<'a, 'b>(&'b Pair<'a>);

impl Scale for FullScale<'_, '_> {
    fn w(&self) -> usize {
        self.0.w
    }
    fn h(&self) -> usize {
        self.0.h
    }
    fn row(&self, y: usize, out: &mut [Option<(f64, f64)>]) {
        let p = self.0;
        for (x, o) in out.iter_mut().enumerate() {
            *o = p
                .at(x as i64, y as i64)
                .map(|j| (luma(p.pa(j)), luma(p.pr(j))));
        }
    }
}

fn luma(c: [f64; 3]) -> f64 {
    (0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2]) / 255.0
}

/// A coarser scale, kept: each pixel the mean of a 2x2 block of the finer scale whose four
/// pixels are all defined (summed in the order (0,0), (1,0), (0,1), (1,1)).
struct HalfScale {
    w: usize,
    h: usize,
    px: LumaRow,
}

impl HalfScale {
    fn of(fine: &dyn Scale) -> HalfScale {
        let (w, h) = (fine.w() / 2, fine.h() / 2);
        let mut px = Vec::with_capacity(w * h);
        let (mut r0, mut r1) = (vec![None; fine.w()], vec![None; fine.w()]);
        for y in 0..h {
            fine.row(2 * y, &mut r0);
            fine.row(2 * y + 1, &mut r1);
            px.extend((0..w).map(|x| {
                let q = [r0[2 * x]?, r0[2 * x + 1]?, r1[2 * x]?, r1[2 * x + 1]?];
                Some((
                    q.iter().map(|v| v.0).sum::<f64>() / 4.0,
                    q.iter().map(|v| v.1).sum::<f64>() / 4.0,
                ))
            }));
        }
        HalfScale { w, h, px }
    }
}

impl Scale for HalfScale {
    fn w(&self) -> usize {
        self.w
    }
    fn h(&self) -> usize {
        self.h
    }
    fn row(&self, y: usize, out: &mut [Option<(f64, f64)>]) {
        out.copy_from_slice(&self.px[y * self.w..(y + 1) * self.w]);
    }
}

/// Over every 7x7 window of defined pixels of a scale (stride 1): the means of SSIM
/// `(2 mu_a mu_r + C1)(2 cov + C2) / ((mu_a^2 + mu_r^2 + C1)(var_a + var_r + C2))` and of its
/// contrast-structure term `(2 cov + C2) / (var_a + var_r + C2)`, with sample (co)variances
/// (divisor 48), `C1 = 0.01^2`, `C2 = 0.03^2`; `None` when there is no window. The window's 7
/// rows are kept.
fn window_means(sc: &dyn Scale) -> Option<(f64, f64)> {
    let (w, h) = (sc.w(), sc.h());
    let win = SSIM_WINDOW;
    if w < win || h < win {
        return None;
    }
    // row y of the scale lives in rows[y % win]
    let mut rows = vec![vec![None; w]; win];
    for (y, row) in rows.iter_mut().enumerate() {
        sc.row(y, row);
    }
    let (c1, c2) = (0.01f64.powi(2), 0.03f64.powi(2));
    let nwin = (win * win) as f64;
    let (mut sum, mut sum_cs, mut count) = (0.0, 0.0, 0u64);
    for y0 in 0..=h - win {
        if y0 > 0 {
            // the window moved down one row: the row above it makes room for the new one
            sc.row(y0 + win - 1, &mut rows[(y0 + win - 1) % win]);
        }
        'win: for x0 in 0..=w - win {
            let (mut sa, mut sr, mut saa, mut srr, mut sar) = (0.0, 0.0, 0.0, 0.0, 0.0);
            for y in y0..y0 + win {
                let row = &rows[y % win];
                for v in &row[x0..x0 + win] {
                    let Some((va, vr)) = *v else {
                        continue 'win;
                    };
                    sa += va;
                    sr += vr;
                    saa += va * va;
                    srr += vr * vr;
                    sar += va * vr;
                }
            }
            let (ma, mr) = (sa / nwin, sr / nwin);
            let va = (saa - nwin * ma * ma) / (nwin - 1.0);
            let vr = (srr - nwin * mr * mr) / (nwin - 1.0);
            let cov = (sar - nwin * ma * mr) / (nwin - 1.0);
            sum += (2.0 * ma * mr + c1) * (2.0 * cov + c2)
                / ((ma * ma + mr * mr + c1) * (va + vr + c2));
            sum_cs += (2.0 * cov + c2) / (va + vr + c2);
            count += 1;
        }
    }
    (count > 0).then(|| (sum / count as f64, sum_cs / count as f64))
}

/// The weights of the five scales of MS-SSIM (Wang, Simoncelli and Bovik 2003, Table 1's
/// fit), finest first.
pub const MS_SSIM_WEIGHTS: [f64; 5] = [0.0448, 0.2856, 0.3001, 0.2363, 0.1333];

/// `half_ssim` and `ms_ssim` of the luma (the module documentation; `docs/metrics.md`).
///
/// `half_ssim`: the mean SSIM at half resolution ([`HalfScale`] of the full scale), 1 when
/// there is no window. `ms_ssim`: multi-scale SSIM over the scales 1, 1/2, 1/4, ... (each a
/// [`HalfScale`] of the one before) that have a window, at most five:
/// `prod_{j < M} cs_j^{w_j} * ssim_M^{w_M}`, `cs_j` the scale's mean contrast-structure term,
/// `ssim_M` the coarsest scale's mean SSIM, each clamped at 0 (a negative correlation is no
/// similarity), the weights [`MS_SSIM_WEIGHTS`] of the scales used, normalised to sum 1. 1
/// when the full scale has no window.
fn ssim_pair(p: &Pair) -> (f64, f64) {
    let full = FullScale(p);
    let mut stats = vec![window_means(&full)];
    let mut scale = HalfScale::of(&full);
    let half = window_means(&scale);
    stats.push(half);
    while stats.len() < MS_SSIM_WEIGHTS.len() && stats.last().is_some_and(|s| s.is_some()) {
        scale = HalfScale::of(&scale);
        stats.push(window_means(&scale));
    }
    let used: Vec<(f64, f64)> = stats.into_iter().map_while(|s| s).collect();
    let ms = match used.len() {
        0 => 1.0,
        m => {
            let wsum: f64 = MS_SSIM_WEIGHTS[..m].iter().sum();
            used.iter()
                .zip(MS_SSIM_WEIGHTS)
                .enumerate()
                .map(|(j, (&(ssim, cs), wj))| {
                    let v = if j + 1 == m { ssim } else { cs };
                    v.max(0.0).powf(wj / wsum)
                })
                .product()
        }
    };
    (half.map_or(1.0, |s| s.0), ms)
}

#[cfg(test)]
mod tests {
    use super::*;

    const W: u32 = 64;
    const H: u32 = 32;

    /// A grey image from a function of (x, y) in LSBs.
    fn img(f: impl Fn(u32, u32) -> f64) -> Rgb64 {
        let mut m = Rgb64::new(W, H);
        for y in 0..H {
            for x in 0..W {
                m.set(x, y, [f(x, y) / 255.0; 3]);
            }
        }
        m
    }

    fn all() -> Vec<bool> {
        vec![true; (W * H) as usize]
    }

    fn m(a: &Rgb64, r: &Rgb64) -> ArtifactStats {
        measure(a, &all(), r, &all())
    }

    /// A slow ramp, 0.25 LSB per pixel in x.
    fn ramp(x: u32, _: u32) -> f64 {
        50.0 + 0.25 * x as f64
    }

    #[test]
    fn identical_images_have_no_artifacts() {
        let r = img(ramp);
        let s = m(&r, &r);
        assert_eq!(s.banding_edges, 0);
        assert_eq!(s.faceting_lsb, 0.0);
        assert_eq!(s.ringing_lsb, 0.0);
        assert_eq!(s.lowpass_psnr_db, PSNR_CAP_DB);
        assert!((s.half_ssim - 1.0).abs() < 1e-12, "{}", s.half_ssim);
    }

    #[test]
    fn a_quantized_ramp_has_exactly_its_band_boundaries_as_contours() {
        let r = img(ramp);
        // 4-LSB steps: r goes 50 .. 65.75, bands [48,52) [52,56) [56,60) [60,64) [64,68):
        // boundaries where r crosses 52, 56, 60, 64: x = 8, 24, 40, 56: 4 boundaries
        let banded = img(|x, y| 4.0 * (ramp(x, y) / 4.0).floor());
        let s = m(&banded, &r);
        assert_eq!(s.banding_edges, 4 * H as u64);
        assert!((s.banding - 4.0 / W as f64).abs() < 1e-15);
        // the smooth ramp rounded to 8 bits: its 1-LSB steps are rounding, not contours
        let rounded = img(|x, y| ramp(x, y).round());
        assert_eq!(m(&rounded, &r).banding_edges, 0);
        // nor is a smooth offset of the ramp a contour
        assert_eq!(m(&img(|x, y| ramp(x, y) + 3.0), &r).banding_edges, 0);
        // a real edge of the reference is not a false contour
        let step = img(|x, _| if x < 32 { 50.0 } else { 60.0 });
        assert_eq!(m(&step, &step).banding_edges, 0);
    }

    #[test]
    fn contours_are_groups_of_at_least_eight_pixels() {
        let (w, h) = (16usize, 12usize);
        let grid = |cells: &[(usize, usize, u8)]| {
            let mut g = vec![0u8; w * h];
            for &(x, y, b) in cells {
                g[y * w + x] |= b;
            }
            g
        };
        let line = |n: usize, b: u8| (0..n).map(|i| (3, i, b)).collect::<Vec<_>>();
        assert_eq!(contour_steps(&mut grid(&line(8, 1)), w, h), 8);
        assert_eq!(contour_steps(&mut grid(&line(7, 1)), w, h), 0);
        // both steps of a pixel count; the group is its pixels
        assert_eq!(contour_steps(&mut grid(&line(8, 3)), w, h), 16);
        assert_eq!(contour_steps(&mut grid(&line(7, 3)), w, h), 0);
        // a diagonal is connected
        let diag: Vec<_> = (0..8).map(|i| (i, i, 2)).collect();
        assert_eq!(contour_steps(&mut grid(&diag), w, h), 8);
        // two groups of 4 apart are two specks
        let mut two: Vec<_> = (0..4).map(|i| (1, i, 1)).collect();
        two.extend((0..4).map(|i| (9, i + 6, 1)));
        assert_eq!(contour_steps(&mut grid(&two), w, h), 0);
        // a group touching the image's last column and row
        let corner: Vec<_> = (0..8).map(|i| (w - 1, h - 1 - i, 1)).collect();
        assert_eq!(contour_steps(&mut grid(&corner), w, h), 8);
    }

    #[test]
    fn specks_of_a_resolved_dither_are_not_contours() {
        let r = img(ramp);
        // 2 x 2 pixel blocks raised by 4 LSB, 6 pixels apart, on the rounded ramp: each block
        // is a step between plateaus on its four sides (7 pixels, 8 steps), a speck
        let specks = img(|x, y| {
            let raised = x % 6 >= 2 && x % 6 < 4 && y % 6 >= 2 && y % 6 < 4;
            ramp(x, y).round() + if raised { 4.0 } else { 0.0 }
        });
        assert_eq!(m(&specks, &r).banding_edges, 0);
        // every block's steps are blockiness: 8 a block, 11 x 5 blocks (x = 2, 8, .., 62;
        // y = 2, 8, .., 26), less the 10 steps at the image's right border (no x + 2 there)
        assert_eq!(m(&specks, &r).blockiness_edges, 430);
        // the same blocks joined into bars 20 pixels long are contours
        let bars = img(|x, y| {
            let raised = (4..24).contains(&x) && y % 6 >= 2 && y % 6 < 4;
            ramp(x, y).round() + if raised { 4.0 } else { 0.0 }
        });
        assert!(
            m(&bars, &r).banding_edges >= 5 * 40,
            "{}",
            m(&bars, &r).banding_edges
        );
    }

    /// 4x4 Bayer thresholds in [0, 1).
    fn bayer(x: u32, y: u32) -> f64 {
        const B: [[f64; 4]; 4] = [
            [0.0, 8.0, 2.0, 10.0],
            [12.0, 4.0, 14.0, 6.0],
            [3.0, 11.0, 1.0, 9.0],
            [15.0, 7.0, 13.0, 5.0],
        ];
        (B[(y % 4) as usize][(x % 4) as usize] + 0.5) / 16.0
    }

    #[test]
    fn dithering_trades_psnr_for_less_banding_and_better_lowpass_psnr() {
        let r = img(ramp);
        let banded = img(|x, y| 4.0 * (ramp(x, y) / 4.0).round());
        let dithered = img(|x, y| 4.0 * (ramp(x, y) / 4.0 + bayer(x, y) - 0.5).round());
        let (b, d) = (m(&banded, &r), m(&dithered, &r));
        let psnr = |a: &Rgb64| crate::metrics::compare(a, &all(), &r, &all()).psnr_db;
        assert!(psnr(&dithered) < psnr(&banded) + 1.0);
        assert!(
            d.banding < b.banding / 2.0,
            "{} vs {}",
            d.banding,
            b.banding
        );
        assert!(
            d.lowpass_psnr_db > b.lowpass_psnr_db + 3.0,
            "{} vs {}",
            d.lowpass_psnr_db,
            b.lowpass_psnr_db
        );
        assert!(d.lowpass_psnr_db > psnr(&dithered));
    }

    #[test]
    fn faceting_sees_gradient_breaks_not_offsets() {
        // a parabola in x, and its piecewise-linear interpolation between knots 16 px apart
        let f = |x: f64| 0.2 * (x - 32.0).powi(2);
        let r = img(|x, _| f(x as f64));
        let faceted = img(|x, _| {
            let k0 = (x / 16 * 16) as f64;
            let t = (x as f64 - k0) / 16.0;
            f(k0) * (1.0 - t) + f(k0 + 16.0) * t
        });
        let s = m(&faceted, &r);
        assert!(s.faceting_lsb > 0.5, "{}", s.faceting_lsb);
        // a constant offset has a large error but no faceting
        let offset = img(|x, _| f(x as f64) + 10.0);
        assert!(m(&offset, &r).faceting_lsb < 1e-9);
        assert!(crate::metrics::compare(&offset, &all(), &r, &all()).psnr_db < 30.0);
    }

    /// Faceting in closed form: one gradient break of `s` LSB per pixel (the image is the
    /// reference plus `s max(0, x - x0)`, constant in y). The masked 3x3 blur of the hinge is
    /// 0, s/3, s, 2s, ... at x0 - 1, x0, x0 + 1, x0 + 2, so its Laplacian is s/3 at x0 - 1,
    /// x0 and x0 + 1 and 0 elsewhere, but for the last counted column, W - 2, where the blur
    /// of the border column averages two pixels of the slope: -s/2. Over the (W - 2)(H - 2)
    /// counted pixels, RMS = s sqrt((3 (s/3)^2 + (s/2)^2) / s^2 / (W - 2)) = s sqrt(7 / (12
    /// (W - 2))), whatever the reference (the measure is linear in the difference).
    #[test]
    fn one_gradient_break_has_the_faceting_of_its_closed_form() {
        for (s, x0) in [(2.0, 20u32), (0.5, 40)] {
            for r in [
                img(|_, _| 100.0),
                img(|x, y| 60.0 + 0.01 * (x * x + 3 * y) as f64),
            ] {
                let a = img(|x, y| r.get(x, y)[0] * 255.0 + s * (x as f64 - x0 as f64).max(0.0));
                let want = s * (7.0 / (12.0 * (W - 2) as f64)).sqrt();
                let got = m(&a, &r).faceting_lsb;
                assert!((got - want).abs() < 1e-9, "s {s}, x0 {x0}: {got} vs {want}");
            }
        }
    }

    /// [`ringing`] as first written, with direct 5x5 windows: the oracle of the separable one.
    fn ringing_direct(p: &Pair) -> (f64, u64) {
        // the strong edges are not what changed: the windows are
        let strong = strong_edges(p);
        let rad = RINGING_RADIUS;
        let (mut sum, mut count) = (0.0, 0u64);
        for y in 0..p.h as i64 {
            for x in 0..p.w as i64 {
                let Some(i) = p.at(x, y) else { continue };
                // a window without a strong pixel is skipped before any value is read
                let near = (y - rad..=y + rad)
                    .any(|v| (x - rad..=x + rad).any(|u| p.at(u, v).is_some_and(|j| strong[j])));
                if !near {
                    continue;
                }
                let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
                for v in y - rad..=y + rad {
                    for u in x - rad..=x + rad {
                        if let Some(j) = p.at(u, v) {
                            let rj = p.pr(j);
                            for c in 0..3 {
                                lo[c] = lo[c].min(rj[c]);
                                hi[c] = hi[c].max(rj[c]);
                            }
                        }
                    }
                }
                sum += overshoot(p.pa(i), lo, hi);
                count += 1;
            }
        }
        (if count == 0 { 0.0 } else { sum / count as f64 }, count)
    }

    /// The separable ringing against the direct scans: images of random values with sharp
    /// steps, random holes in either mask, sizes from 1x1 up (windows cut by every border).
    #[test]
    fn separable_ringing_is_the_direct_scan() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let mut near = 0;
        for case in 0..300 {
            let (w, h) = (1 + (next() % 23) as u32, 1 + (next() % 19) as u32);
            let n = (w * h) as usize;
            let mut pick = |k: u64| -> Rgb64 {
                let mut m = Rgb64::new(w, h);
                for v in m.px.iter_mut() {
                    // a few levels far apart (strong edges) plus noise
                    *v = [0, 1, 2]
                        .map(|_| ((next() % k) as f64 * 40.0 + (next() % 9) as f64) / 255.0);
                }
                m
            };
            let (a, r) = (pick(6), pick(4));
            let hole = (case % 4) as u64;
            let mut mask = || (0..n).map(|_| next() % 8 >= hole).collect::<Vec<bool>>();
            let (am, rm) = (mask(), mask());
            let p = Pair::new(&a, &am, &r, &rm);
            let (fast, slow) = (ringing(&p), ringing_direct(&p));
            assert_eq!(fast.1, slow.1, "case {case}: {w}x{h}");
            assert_eq!(fast.0.to_bits(), slow.0.to_bits(), "case {case}: {w}x{h}");
            near += fast.1;
        }
        assert!(near > 10_000, "{near} pixels near strong edges");
    }

    #[test]
    fn ringing_is_overshoot_beside_strong_edges() {
        let r = img(|x, _| if x < 32 { 50.0 } else { 200.0 });
        // 10 LSB of under- and overshoot in the two columns each side of the edge
        let rings = img(|x, _| match x {
            30 | 31 => 40.0,
            32 | 33 => 210.0,
            x if x < 32 => 50.0,
            _ => 200.0,
        });
        let s = m(&rings, &r);
        // near the edge: columns 29..=34 (the edge pixels 31, 32 and two either side)
        assert_eq!(s.ringing_pixels, 6 * H as u64);
        assert!(
            (s.ringing_lsb - 10.0 * 4.0 / 6.0).abs() < 1e-9,
            "{}",
            s.ringing_lsb
        );
        // a softened edge stays inside the local range: no ringing
        let soft = img(|x, _| match x {
            31 => 100.0,
            32 => 150.0,
            x if x < 32 => 50.0,
            _ => 200.0,
        });
        assert_eq!(m(&soft, &r).ringing_lsb, 0.0);
        // no strong edge, nothing measured
        assert_eq!(m(&img(ramp), &img(ramp)).ringing_pixels, 0);
    }

    #[test]
    fn half_resolution_ssim_drops_with_structure_loss() {
        let r = img(|x, y| 128.0 + 40.0 * ((x as f64) / 5.0).sin() * ((y as f64) / 7.0).cos());
        let flat = img(|_, _| 128.0);
        let noisy = img(|x, y| {
            128.0
                + 40.0 * ((x as f64) / 5.0).sin() * ((y as f64) / 7.0).cos()
                + if (x + y) % 2 == 0 { 4.0 } else { -4.0 }
        });
        let (sf, sn) = (m(&flat, &r).half_ssim, m(&noisy, &r).half_ssim);
        assert!(sf < 0.3, "{sf}");
        // a 1-pixel checkerboard averages out at half resolution
        assert!(sn > 0.999, "{sn}");
    }

    #[test]
    fn lowpass_psnr_of_a_constant_offset_is_its_closed_form() {
        // the blur of a constant difference is that constant, at the borders too (the
        // masked blur is normalised): PSNR = 20 log10(255 / d) for an offset of d LSB
        let r = img(|x, y| 60.0 + 1.5 * x as f64 + 0.5 * y as f64);
        for d in [0.5, 3.0, 17.0] {
            let a = img(|x, y| 60.0 + 1.5 * x as f64 + 0.5 * y as f64 + d);
            let want = 20.0 * (255.0 / d).log10();
            let got = m(&a, &r).lowpass_psnr_db;
            assert!((got - want).abs() < 1e-9, "{d}: {got} {want}");
        }
    }

    /// A `w x h` grey image of constant value `v` (LSB).
    fn flat(w: u32, h: u32, v: f64) -> Rgb64 {
        let mut m = Rgb64::new(w, h);
        for y in 0..h {
            for x in 0..w {
                m.set(x, y, [v / 255.0; 3]);
            }
        }
        m
    }

    #[test]
    fn ms_ssim_of_flat_images_is_the_coarsest_luminance_term_to_its_weight() {
        // flat images: every window's contrast-structure term is C2 / C2 = 1, so MS-SSIM is
        // the luminance term l = (2 a r + C1) / (a^2 + r^2 + C1) to the coarsest scale's
        // normalised weight: five scales at 128 (128, 64, 32, 16, 8), 0.1333 / 1.0001
        let (a, r): (f64, f64) = (100.0 / 255.0, 140.0 / 255.0);
        let l = (2.0 * a * r + 1e-4) / (a * a + r * r + 1e-4);
        let sq = |n: u32| {
            let mask = vec![true; (n * n) as usize];
            measure(&flat(n, n, 100.0), &mask, &flat(n, n, 140.0), &mask)
        };
        let s = sq(128);
        // (the published weights sum to 1.0001)
        let w5 = 0.1333 / MS_SSIM_WEIGHTS.iter().sum::<f64>();
        assert!((s.ms_ssim - l.powf(w5)).abs() < 1e-12, "{} {l}", s.ms_ssim);
        assert!((s.half_ssim - l).abs() < 1e-12, "{}", s.half_ssim);
        // three scales at 32 (32, 16, 8): the weights of the three used, normalised
        let s3 = sq(32);
        let w3: f64 = 0.3001 / (0.0448 + 0.2856 + 0.3001);
        assert!(
            (s3.ms_ssim - l.powf(w3)).abs() < 1e-12,
            "{} {}",
            s3.ms_ssim,
            l.powf(w3)
        );
        // no window at all: 1
        assert_eq!(sq(6).ms_ssim, 1.0);
        // identical images: 1
        let t = img(|x, y| 128.0 + 40.0 * ((x as f64) / 5.0).sin() * ((y as f64) / 7.0).cos());
        assert!((m(&t, &t).ms_ssim - 1.0).abs() < 1e-12);
    }

    #[test]
    fn ms_ssim_sees_what_half_resolution_ssim_averages_away() {
        // a 1-pixel checkerboard of +-4 LSB on a textured image: invisible at half resolution
        // (SSIM/2 above 0.999), but the full scale's structure term falls, and with it MS-SSIM
        let r = img(|x, y| 128.0 + 40.0 * ((x as f64) / 5.0).sin() * ((y as f64) / 7.0).cos());
        let noisy = img(|x, y| {
            128.0
                + 40.0 * ((x as f64) / 5.0).sin() * ((y as f64) / 7.0).cos()
                + if (x + y) % 2 == 0 { 12.0 } else { -12.0 }
        });
        let s = m(&noisy, &r);
        assert!(s.half_ssim > 0.999, "{}", s.half_ssim);
        assert!(
            s.ms_ssim < s.half_ssim - 0.005,
            "{} {}",
            s.ms_ssim,
            s.half_ssim
        );
        // a contrast-reversed image: negative correlation at every scale, clamped: 0
        let inv = img(|x, y| 128.0 - 40.0 * ((x as f64) / 5.0).sin() * ((y as f64) / 7.0).cos());
        assert_eq!(m(&inv, &r).ms_ssim, 0.0);
    }

    #[test]
    fn only_pixels_covered_in_both_count() {
        let r = img(ramp);
        let banded = img(|x, y| 4.0 * (ramp(x, y) / 4.0).floor());
        let mut mask = all();
        for y in 0..H {
            for x in 0..W / 2 {
                mask[(y * W + x) as usize] = false;
            }
        }
        let s = measure(&banded, &mask, &r, &all());
        // boundaries at x = 40, 56 remain (x = 24 lost: its left plateau pixel is uncovered)
        assert_eq!(s.banding_edges, 2 * H as u64);
        let empty = measure(&banded, &[], &r, &all());
        assert_eq!(empty.banding, 0.0);
        assert_eq!(empty.lowpass_psnr_db, PSNR_CAP_DB);
        assert_eq!(empty.half_ssim, 1.0);
        assert_eq!(empty.ms_ssim, 1.0);
    }
}
