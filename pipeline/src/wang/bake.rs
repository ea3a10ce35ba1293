//! Multi-view baking (Wang et al. §2, the `constructNormalMap` listing and its four steps):
//! the normal map starts as the simplified mesh's interpolated vertex normals with an
//! infinite distance ("Filling invisible parts"); each view renders the detailed mesh, and
//! every sample whose pixel shows the detailed mesh at a depth difference below the
//! threshold and below the sample's best so far takes that pixel's normal.
//!
//! Two buffers (§2, "Improving normal vector precision"):
//! * [`Buffer::Color8`], the paper's first method: the detailed mesh rendered with its vertex
//!   normals as 8-bit colours, `c = round(255 (n + 1) / 2)`, interpolated and rounded to 8
//!   bits per pixel, and read back as `normalize(2 c / 255 - 1)`;
//! * [`Buffer::Item`]: the triangle id per pixel (the rasterizer's fragment), and the normal
//!   interpolated exactly (f64) on that triangle at the pixel's barycentrics.
//!
//! Either way the map is quantised only at the end ([`Baker::map`]), to 8 or 16 bits signed
//! per component, or kept in f64.
//!
//! Determinism: views are added in order; within a view every sample is independent
//! (rayon over samples, results stored by index), so the map is bit-identical at any thread
//! count.

use glam::DVec3;
use rayon::prelude::*;

use super::camera::{ItemBuffer, View};
use super::pack::{pack, Packing, Sample};
use super::Surface;

/// How the detailed mesh's normals reach the samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Buffer {
    Color8,
    Item,
}

/// The parameters of a bake.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BakeConfig {
    /// Normal map side in texels (power of two, 16..=16384; the paper: 1024).
    pub map_size: u32,
    /// Border texels of each patch (0..=2).
    pub widen: u32,
    /// Side of the views' images in pixels (16..=8192).
    pub view_size: u32,
    /// Largest accepted depth difference, as a fraction of the detailed mesh's
    /// bounding-sphere radius (0 < t <= 1).
    pub threshold: f64,
    pub buffer: Buffer,
    /// Two faces that share an edge share a square (the paper); false: a square per face.
    pub pairs: bool,
}

impl Default for BakeConfig {
    fn default() -> Self {
        BakeConfig {
            map_size: 1024,
            widen: 1,
            view_size: 1024,
            threshold: 0.03,
            buffer: Buffer::Item,
            pairs: true,
        }
    }
}

impl BakeConfig {
    /// Check the ranges: "field: expected ..., found ...".
    pub fn validate(&self) -> Result<(), String> {
        if !(16..=8192).contains(&self.view_size) {
            return Err(format!(
                "view_size: expected 16 to 8192 pixels, found {}",
                self.view_size
            ));
        }
        if !(self.threshold > 0.0 && self.threshold <= 1.0) {
            return Err(format!(
                "threshold: expected a fraction of the bounding radius above 0 and at most 1, \
                 found {}",
                self.threshold
            ));
        }
        Ok(())
    }
}

/// A normal map being baked.
pub struct Baker<'a> {
    pub detailed: &'a Surface,
    pub simplified: &'a Surface,
    pub config: BakeConfig,
    pub packing: Packing,
    /// Per texel (row-major), its sample and its point on the simplified mesh.
    pub samples: Vec<Option<(Sample, DVec3)>>,
    /// Per texel, the current normal (object space; zero outside every square).
    pub normals: Vec<DVec3>,
    /// Per texel, the best depth difference so far (object units; infinite if none).
    pub dist: Vec<f64>,
    /// Views added.
    pub views: usize,
    centre: DVec3,
    radius: f64,
    colours: Vec<[u8; 3]>,
}

/// A normal as an 8-bit colour, `round(255 (n + 1) / 2)` per component.
pub fn to_colour(n: DVec3) -> [u8; 3] {
    n.to_array()
        .map(|c| (((c.clamp(-1.0, 1.0) + 1.0) * 0.5 * 255.0) + 0.5).floor() as u8)
}

/// The normal of an 8-bit colour, `normalize(2 c / 255 - 1)`.
pub fn from_colour(c: [f64; 3]) -> DVec3 {
    DVec3::from_array(c.map(|c| c / 255.0 * 2.0 - 1.0)).normalize_or_zero()
}

impl<'a> Baker<'a> {
    /// Pack `simplified` and initialise every sample with its interpolated vertex normal.
    pub fn new(
        detailed: &'a Surface,
        simplified: &'a Surface,
        config: BakeConfig,
    ) -> Result<Baker<'a>, String> {
        config.validate()?;
        let packing = pack(simplified, config.map_size, config.widen, config.pairs)?;
        let samples: Vec<Option<(Sample, DVec3)>> = packing
            .samples()
            .into_iter()
            .map(|s| s.map(|s| (s, simplified.point_at(s.face as usize, s.bary))))
            .collect();
        let normals = samples
            .iter()
            .map(|s| s.map_or(DVec3::ZERO, |(s, _)| phong(simplified, s)))
            .collect();
        let (centre, radius) = detailed.bounding_sphere();
        let colours = detailed.normals.iter().map(|&n| to_colour(n)).collect();
        Ok(Baker {
            detailed,
            simplified,
            config,
            packing,
            dist: vec![f64::INFINITY; samples.len()],
            samples,
            normals,
            views: 0,
            centre,
            radius,
            colours,
        })
    }

    /// The view along `dir` at the bake's image size.
    pub fn view(&self, dir: DVec3) -> View {
        View::new(dir, self.centre, self.radius, self.config.view_size)
    }

    /// Render the detailed mesh along `dir` and update the samples (steps 1 to 3).
    pub fn add_view(&mut self, dir: DVec3) {
        let view = self.view(dir);
        let buffer = ItemBuffer::render(self.detailed, &view);
        let limit = self.config.threshold * self.radius;
        let (detailed, colours, kind) = (self.detailed, &self.colours, self.config.buffer);
        self.samples
            .par_iter()
            .zip(self.normals.par_iter_mut())
            .zip(self.dist.par_iter_mut())
            .for_each(|((s, n), best)| {
                let Some((_, p)) = s else { return };
                let at = view.project(*p);
                let Some(pixel) = at.pixel else { return };
                let k = buffer.index(pixel);
                let tri = buffer.tri[k];
                if tri == u32::MAX {
                    return;
                }
                let d = view.depth_to_object((buffer.depth[k] - at.depth).abs());
                if d < limit && d < *best {
                    *best = d;
                    *n = match kind {
                        Buffer::Item => detailed.normal_at(tri as usize, buffer.bary[k]),
                        Buffer::Color8 => {
                            colour_normal(detailed, colours, tri as usize, buffer.bary[k])
                        }
                    };
                }
            });
        self.views += 1;
    }

    /// The map as stored: each component quantised to `bits` (2..=16) signed bits,
    /// `round(c (2^(bits-1) - 1))`, and read back (not renormalised), or exact for `None`.
    pub fn map(&self, bits: Option<u32>) -> Vec<DVec3> {
        match bits {
            None => self.normals.clone(),
            Some(b) => self.normals.iter().map(|&n| quantize(n, b)).collect(),
        }
    }

    /// Samples that some view updated.
    pub fn updated(&self) -> usize {
        self.dist.iter().filter(|d| d.is_finite()).count()
    }

    /// Samples of the map (texels in a square).
    pub fn sample_count(&self) -> usize {
        self.samples.iter().filter(|s| s.is_some()).count()
    }
}

/// `n` with each component quantised to `bits` signed bits and read back.
pub fn quantize(n: DVec3, bits: u32) -> DVec3 {
    let m = f64::from((1u32 << (bits.clamp(2, 16) - 1)) - 1);
    DVec3::from_array(n.to_array().map(|c| (c.clamp(-1.0, 1.0) * m).round() / m))
}

/// The simplified mesh's interpolated vertex normal at a sample (Phong's, the
/// initialisation).
fn phong(s: &Surface, sample: Sample) -> DVec3 {
    let n = s.normal_at(sample.face as usize, sample.bary);
    if n == DVec3::ZERO {
        s.face_normal(sample.face as usize)
    } else {
        n
    }
}

/// The colour buffer's normal: the vertex colours interpolated at `b`, rounded to 8 bits.
fn colour_normal(s: &Surface, colours: &[[u8; 3]], t: usize, b: [f64; 3]) -> DVec3 {
    let c = s.triangles[t].map(|k| colours[k as usize].map(f64::from));
    let mix = |i: usize| (c[0][i] * b[0] + c[1][i] * b[1] + c[2][i] * b[2] + 0.5).floor();
    from_colour([mix(0), mix(1), mix(2)])
}
