//! Quantized normal maps (Tarini, Cignoni, Rocchini, Scopigno 1999, "Real Time, Accurate,
//! Multi-Featured Rendering of Bump Mapped Surfaces"): the preprocessing library.
//!
//! Tarini §3: any normal map is quantized into one that uses only `s_N` different normals, an
//! index texture plus a lookup table `N`; at render time the table is shaded per frame into a
//! colour table `C` (§5.1) and applied as a paletted texture. This module builds `N` and the
//! indices (f64 throughout: this is preprocessing, not hardware):
//!
//! * [`quantize`]: the palette (§4), by Heckbert median cut ([`median_cut`]), NeuQuant
//!   (`color_quant`, on RGBA8 pixels exactly as §4 reuses image software, at most 256
//!   entries) or k-means ([`kmeans`], `linfa-clustering` on the f64 normals, any size), then
//!   every texel mapped to its nearest entry (largest dot product).
//! * [`dither()`]: Floyd–Steinberg error diffusion of normals (§4, Fig. 4);
//!   [`quantize_dithered`] builds the table and dithers without the plain mapping.
//! * [`search`]: the exact nearest-entry search ([`NearestIndex`], a k-d tree) behind every
//!   per-texel mapping here; [`nearest`] is its brute-force reference (the same answers).
//! * [`materials`]: several lighting models in one table, one contiguous interval of
//!   entries per material (§6).
//! * [`mipmap`]: index mipmaps (§5.2), where indices cannot be averaged.
//! * [`angular_error_deg`]: the error measure of all of the above; [`map_error`]: a map's
//!   and its index mipmaps' errors against the true (box-filtered) normals.
//!
//! Measured (`tests::mexican_hat_128_errors`, `BumpSpec::MexicanHat { cells: 4, sigma: 0.18,
//! depth: 0.02 }` baked analytically at 128x128, which holds 1024 distinct normals; mean /
//! max angular error per texel in degrees, plain | serpentine-dithered):
//!
//! | quantizer       | s_n = 16                  | s_n = 256               | s_n = 2048 |
//! |-----------------|---------------------------|-------------------------|------------|
//! | MedianCut       | 4.07/21.6 \| 7.02/31.6    | 0.685/1.59 \| 0.764/2.73 | 0 (exact) |
//! | NeuQuant (sf 1) | 3.70/20.7 \| 5.23/97.4    | 0.910/4.66 \| 1.07/6.94  | error     |
//! | KMeans (Random seed 1, 20 it) | 3.09/14.4 \| 3.78/19.1 | 0.756/5.56 \| 0.837/5.93 | 0.227/4.18 \| 0.272/5.36 (783 entries) |
//! | KMeans (MedianCut, 3 it) | 3.60/19.6 \| 4.81/30.8 | 0.640/1.58 \| 0.709/2.99 | 0 (exact) |
//!
//! KMeans from a random start loses entries to duplicate initial texels (783 of 2048 for
//! 1024 distinct normals). Timing (`tests::kmeans_256_to_16k_timing`, release, 2 cores),
//! 256x256 texels to 16384 entries: 4 cells (4096 distinct normals) 10.1 s random / 1.4 s
//! median-cut start; 3 cells 89 s random (20 iterations) / 12.7 s median-cut start
//! (3 iterations, mean error 0.052 deg): `linfa` assigns by brute force, about 2 s per
//! iteration.
//!
//! With 3 cells (16384 distinct normals) median cut gives 3.14 / 0.855 / 0.260 degrees mean
//! for 16 / 256 / 2048 entries (dithered 5.17 / 1.00 / 0.294) and NeuQuant 3.11 / 0.800.
//!
//! The fixed hemisphere palette of Gouraud bump mapping (Ernst et al. §6) is
//! [`crate::engine::palette`]; this module adapts the table to the map instead.

pub mod dither;
pub mod kmeans;
pub mod map_error;
pub mod materials;
pub mod median_cut;
mod memo;
pub mod mipmap;
pub mod search;

use glam::DVec3;
use serde::{Deserialize, Serialize};

pub use dither::{dither, Scan};
pub use map_error::{level_errors, LevelError, NormalMapError};
pub use materials::{
    quantize_with_materials, quantize_with_materials_dithered, MaterialPalette, MAX_MATERIALS,
};
pub use mipmap::{mip_indices, MipMode};
pub use search::NearestIndex;

/// Largest table size: Tarini §4 finds `s_N = 16K` "in practice invisible".
pub const MAX_PALETTE: usize = 16384;
/// Largest table of [`Quantizer::Exact`]: every distinct normal of a 256 x 256 map.
pub const MAX_EXACT: usize = 65536;
/// NeuQuant (`color_quant`) builds at most 256 colours.
pub const MAX_NEUQUANT: usize = 256;
/// Most Lloyd iterations of [`Quantizer::KMeans`].
pub const MAX_KMEANS_ITERATIONS: u32 = 300;

/// How the table `N` is chosen (Tarini §4: "standard image processing software (RGB palette
/// quantization)").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Quantizer {
    /// Heckbert's median cut as ppmquant does it, on the f64 normals (see [`median_cut`]).
    MedianCut,
    /// Dekker's NeuQuant (the `color_quant` crate) on the normals as RGBA8 pixels
    /// (`[-1, 1]` mapped to `[0, 255]`, alpha 255). At most 256 entries.
    NeuQuant {
        /// Learning sample factor, 1 (every pixel, best) ..= 30 (fastest); 10 is NeuQuant's
        /// suggested compromise.
        sample_factor: u32,
    },
    /// k-means (Lloyd) by the `linfa-clustering` crate on the f64 normals (no RGB8 step), any
    /// `s_n` up to 16384 (see [`kmeans`]). RON:
    /// `KMeans(start: Random(seed: 1), max_iterations: 20)` or
    /// `KMeans(start: MedianCut, max_iterations: 3)`.
    KMeans {
        /// The initial centroids.
        start: KMeansStart,
        /// Most Lloyd iterations, `1..=300`; they stop earlier once the centroids move less
        /// than [`kmeans::TOLERANCE`] in total. Each costs `texels * min(s_n, distinct
        /// normals)` distance evaluations: about 2 s for 256x256 texels and 16384 entries on
        /// two cores (release).
        max_iterations: u32,
    },
    /// No quantization: every distinct normal of the map (bit for bit) is its own entry, in
    /// the order of first appearance, and every texel reads its own normal back exactly.
    /// The same engine with unquantized normals, the baseline against which the quantizers'
    /// loss is judged with everything else held fixed (Tarini §4's "16K in practice
    /// invisible", issue 11). `s_n` (up to 65536) must hold the map's distinct normals;
    /// dithering has no error to diffuse and changes nothing.
    Exact,
}

impl Quantizer {
    /// The largest `s_n` this quantizer accepts.
    pub fn max_entries(&self) -> usize {
        match self {
            Quantizer::Exact => MAX_EXACT,
            Quantizer::NeuQuant { .. } => MAX_NEUQUANT,
            _ => MAX_PALETTE,
        }
    }
}

/// Initial centroids of [`Quantizer::KMeans`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum KMeansStart {
    /// Forgy: `min(s_n, distinct normals)` texels drawn by a `Xoshiro256Plus` seeded with
    /// `seed` (any value; the same seed gives the same table).
    Random { seed: u64 },
    /// The [`median_cut`] table (k-means as a refinement of median cut, as ppmquant-style
    /// quantizers with a k-means optimizer do). Deterministic without a seed; needs far
    /// fewer iterations.
    MedianCut,
}

/// A quantized normal map: the table `N` and one index per texel.
#[derive(Debug, Clone, PartialEq)]
pub struct Palette {
    /// Unit normals (renormalised, Tarini §4). At most `s_n` of them: median cut stops early
    /// when every box holds a single distinct normal.
    pub entries: Vec<DVec3>,
    /// Per texel, the index of its entry: the nearest one (largest dot product, ties to the
    /// lower index) unless the indices were dithered.
    pub indices: Vec<u32>,
}

impl Palette {
    /// The normals the indices stand for.
    pub fn decode(&self) -> Vec<DVec3> {
        decode(&self.entries, &self.indices)
    }
}

/// Errors of the preprocessing (bad sizes, parameters or inputs).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum QuantizeError {
    #[error("palette size s_n = {0} out of range 1..={MAX_PALETTE} (Exact: 1..={MAX_EXACT})")]
    PaletteSize(usize),
    #[error("Exact keeps every distinct normal: the map holds {distinct}, more than s_n = {s_n}")]
    ExactTooSmall { distinct: usize, s_n: usize },
    #[error(
        "NeuQuant builds at most {MAX_NEUQUANT} entries (color_quant), s_n = {0} requested; \
         use MedianCut for larger tables"
    )]
    NeuQuantTooLarge(usize),
    #[error("NeuQuant sample_factor = {0} out of range 1..=30")]
    SampleFactor(u32),
    #[error("KMeans max_iterations = {0} out of range 1..={MAX_KMEANS_ITERATIONS}")]
    KMeansIterations(u32),
    #[error("no normals to quantize")]
    Empty,
    #[error("normal {index} is not finite or has zero length: {value:?}")]
    BadNormal { index: usize, value: [f64; 3] },
    #[error("{what}: expected {expected} values, found {found}")]
    Length {
        what: &'static str,
        expected: usize,
        found: usize,
    },
    #[error(
        "material {0} out of range: at most {MAX_MATERIALS} materials (ids 0..{MAX_MATERIALS})"
    )]
    Material(u8),
    #[error("s_n = {s_n} is smaller than the number of materials present ({materials})")]
    TooFewEntries { s_n: usize, materials: usize },
    #[error("index {index} out of range for a table of {len} entries")]
    Index { index: u32, len: usize },
}

/// Quantize `normals` (unit vectors, any count) to a table of at most `s_n` entries
/// (Tarini §3–4) and map every texel to its nearest entry ([`nearest`]).
///
/// Errors: `s_n` outside `1..=16384`, NeuQuant with `s_n > 256` or a sample factor outside
/// `1..=30`, KMeans with `max_iterations` outside `1..=300`, no normals, a non-finite or zero
/// normal.
pub fn quantize(normals: &[DVec3], s_n: usize, q: Quantizer) -> Result<Palette, QuantizeError> {
    if q == Quantizer::Exact {
        return exact(normals, s_n);
    }
    let entries = build_table(normals, s_n, q)?;
    let indices = nearest_all(normals, &entries, 0..entries.len());
    Ok(Palette { entries, indices })
}

/// [`quantize`] with Floyd–Steinberg dithered indices ([`dither()`], scan `scan`) of the
/// `w x h` row-major map `normals`: the same result as `quantize` followed by
/// `pal.indices = dither(normals, w, h, &pal.entries, scan)`, without the nearest-entry
/// mapping that dithering replaces (every texel is searched once).
///
/// Errors as [`quantize`], plus `normals.len() != w * h`.
pub fn quantize_dithered(
    normals: &[DVec3],
    w: usize,
    h: usize,
    s_n: usize,
    q: Quantizer,
    scan: Scan,
) -> Result<Palette, QuantizeError> {
    check_map(normals.len(), w, h)?;
    if q == Quantizer::Exact {
        // every texel has its own normal: no error to diffuse
        return exact(normals, s_n);
    }
    let entries = build_table(normals, s_n, q)?;
    let indices = dither(normals, w, h, &entries, scan);
    Ok(Palette { entries, indices })
}

/// `len == w * h`, or the error that says it is not.
pub(crate) fn check_map(len: usize, w: usize, h: usize) -> Result<(), QuantizeError> {
    match w.checked_mul(h) {
        Some(n) if n == len => Ok(()),
        n => Err(QuantizeError::Length {
            what: "normals (w * h)",
            expected: n.unwrap_or(usize::MAX),
            found: len,
        }),
    }
}

/// The table alone (checks as [`quantize`]), built once per distinct input in this process
/// ([`memo`]: a later call with the same normals, `s_n` and quantizer gets a copy).
pub(crate) fn build_table(
    normals: &[DVec3],
    s_n: usize,
    q: Quantizer,
) -> Result<Vec<DVec3>, QuantizeError> {
    if q == Quantizer::Exact {
        // a hash pass over the map: as cheap as the key
        return build_table_now(normals, s_n, q);
    }
    memo::table(normals, s_n, q, || build_table_now(normals, s_n, q))
}

/// [`build_table`] without the kept tables: always built now.
pub(crate) fn build_table_now(
    normals: &[DVec3],
    s_n: usize,
    q: Quantizer,
) -> Result<Vec<DVec3>, QuantizeError> {
    if !(1..=q.max_entries().max(MAX_PALETTE)).contains(&s_n) {
        return Err(QuantizeError::PaletteSize(s_n));
    }
    check_normals(normals)?;
    match q {
        Quantizer::Exact => exact(normals, s_n).map(|p| p.entries),
        Quantizer::MedianCut => Ok(median_cut::median_cut(normals, s_n)),
        Quantizer::NeuQuant { sample_factor } => {
            if s_n > MAX_NEUQUANT {
                return Err(QuantizeError::NeuQuantTooLarge(s_n));
            }
            if !(1..=30).contains(&sample_factor) {
                return Err(QuantizeError::SampleFactor(sample_factor));
            }
            Ok(neuquant(normals, s_n, sample_factor))
        }
        Quantizer::KMeans {
            start,
            max_iterations,
        } => {
            if !(1..=MAX_KMEANS_ITERATIONS).contains(&max_iterations) {
                return Err(QuantizeError::KMeansIterations(max_iterations));
            }
            Ok(kmeans::kmeans(normals, s_n, start, max_iterations))
        }
    }
}

/// [`Quantizer::Exact`]: the distinct normals (by their bits) in order of first appearance,
/// each texel's index that of its own normal.
fn exact(normals: &[DVec3], s_n: usize) -> Result<Palette, QuantizeError> {
    if !(1..=MAX_EXACT).contains(&s_n) {
        return Err(QuantizeError::PaletteSize(s_n));
    }
    check_normals(normals)?;
    let mut seen = std::collections::HashMap::new();
    let mut entries = Vec::new();
    let mut indices = Vec::with_capacity(normals.len());
    for n in normals {
        let key = n.to_array().map(f64::to_bits);
        let i = *seen.entry(key).or_insert_with(|| {
            entries.push(*n);
            entries.len() - 1
        });
        if entries.len() > s_n {
            let distinct = normals
                .iter()
                .map(|n| n.to_array().map(f64::to_bits))
                .collect::<std::collections::HashSet<_>>()
                .len();
            return Err(QuantizeError::ExactTooSmall { distinct, s_n });
        }
        indices.push(i as u32);
    }
    Ok(Palette { entries, indices })
}

fn check_normals(normals: &[DVec3]) -> Result<(), QuantizeError> {
    if normals.is_empty() {
        return Err(QuantizeError::Empty);
    }
    for (index, n) in normals.iter().enumerate() {
        let l = n.length();
        if !(n.is_finite() && l > 0.0) {
            return Err(QuantizeError::BadNormal {
                index,
                value: n.to_array(),
            });
        }
    }
    Ok(())
}

/// A normal as an 8-bit channel: `[-1, 1]` to `[0, 255]`, rounded (Tarini §4).
pub fn to_u8(c: f64) -> u8 {
    ((c.clamp(-1.0, 1.0) + 1.0) * 127.5).round() as u8
}

/// Back from `[0, 255]` to `[-1, 1]` (Tarini §4: "remap back each entry of the palette").
pub fn from_u8(c: u8) -> f64 {
    f64::from(c) / 127.5 - 1.0
}

/// Fewest learning samples NeuQuant is given (see [`neuquant`]).
const NEUQUANT_MIN_SAMPLES: usize = 1024;

/// NeuQuant on RGBA8 pixels; the colour map remapped to `[-1, 1]` and renormalised. No byte
/// triple maps to the zero vector (`c / 127.5 - 1 = 0` needs `c = 127.5`).
fn neuquant(normals: &[DVec3], s_n: usize, sample_factor: u32) -> Vec<DVec3> {
    let mut pixels = Vec::with_capacity(normals.len() * 4);
    for n in normals {
        pixels.extend_from_slice(&[to_u8(n.x), to_u8(n.y), to_u8(n.z), 255]);
    }
    // NeuQuant learns from `len / sample_factor` samples; a tiny map (fewer than
    // `sample_factor * NEUQUANT_MIN_SAMPLES` pixels) would leave its network at the initial
    // grey ramp, so it is repeated whole (the distribution of colours is unchanged)
    let min = sample_factor as usize * NEUQUANT_MIN_SAMPLES;
    if normals.len() < min {
        let one = pixels.clone();
        while pixels.len() < min * 4 {
            pixels.extend_from_slice(&one);
        }
    }
    let nq = color_quant::NeuQuant::new(sample_factor as i32, s_n, &pixels);
    nq.color_map_rgba()
        .chunks_exact(4)
        .map(|c| DVec3::new(from_u8(c[0]), from_u8(c[1]), from_u8(c[2])).normalize())
        .collect()
}

/// Index of the entry of `entries[range]` with the largest dot product with `v` (the nearest
/// direction; for unit entries also the nearest point, `|v - e|² = |v|² - 2 v·e + 1`), ties
/// to the lower index. `v` need not be unit. Brute force: exact by construction, and the
/// reference of [`NearestIndex`], which every per-texel search of this module uses (the same
/// answers, bit for bit; `search::tests`).
pub fn nearest(v: DVec3, entries: &[DVec3], range: std::ops::Range<usize>) -> u32 {
    let mut best = (f64::NEG_INFINITY, range.start);
    for i in range {
        let s = v.dot(entries[i]);
        if s > best.0 {
            best = (s, i);
        }
    }
    best.1 as u32
}

/// [`nearest`] of every normal, through one [`NearestIndex`].
fn nearest_all(normals: &[DVec3], entries: &[DVec3], range: std::ops::Range<usize>) -> Vec<u32> {
    NearestIndex::new(entries, range).nearest_all(normals)
}

/// `entries[indices[i]]` for every texel.
pub fn decode(entries: &[DVec3], indices: &[u32]) -> Vec<DVec3> {
    indices.iter().map(|&i| entries[i as usize]).collect()
}

/// Angles between corresponding vectors of `a` and `b`, in degrees: `(mean, max)`, computed as
/// `atan2(|a × b|, a · b)` (accurate near 0, independent of the lengths). `(0, 0)` when
/// empty. Panics if the lengths differ (a programming error, not an input error).
pub fn angular_error_deg(a: &[DVec3], b: &[DVec3]) -> (f64, f64) {
    assert_eq!(a.len(), b.len(), "angular_error_deg: lengths differ");
    if a.is_empty() {
        return (0.0, 0.0);
    }
    let mut sum = 0.0;
    let mut max: f64 = 0.0;
    for (x, y) in a.iter().zip(b) {
        let d = x.cross(*y).length().atan2(x.dot(*y)).to_degrees();
        sum += d;
        max = max.max(d);
    }
    (sum / a.len() as f64, max)
}

#[cfg(test)]
pub(crate) mod tests;
