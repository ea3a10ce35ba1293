//! The float reference: Blinn bump mapping evaluated per pixel in f64, independent of any
//! engine code. Every engine in bumpsim approximates this image. See `docs/reference.md`.
//!
//! The pipeline of [`render_reference`]:
//!
//! 1. **Coverage and visibility** — clip positions `proj · view · model · pos`; the
//!    hardware rasterizer ([`crate::raster::rasterize`]) decides only *which triangle wins
//!    each pixel* ([`Coverage`]: a run passes the engine's own fragments, [`render_covered`],
//!    so the frame is rasterised once). The barycentrics are then recomputed exactly in f64
//!    at the pixel centre from the unsnapped clip-space vertices ([`pixel_barycentrics`]), so
//!    the reference does not inherit the rasterizer's sub-pixel snapping.
//! 2. **Surface point** — object-space `P`, `N`, `Pu`, `Pv`, `uv` interpolated with those
//!    barycentrics and taken to world space ([`surface_point`]).
//! 3. **Perturbed normal** — Blinn 1978 as given in Ernst et al. 1998 §2, optionally with
//!    Lingard 1995's scale-invariant `D'`; tangent-space normal maps in the `(T, B, N)` frame
//!    of Ernst et al. 1998 §3.4 ([`perturbed_normal`]).
//! 4. **Lighting** — ambient + per-light diffuse and Blinn–Phong specular, every vector
//!    exact per pixel ([`shade`]).
//! 5. **Assembly** — rows in parallel with rayon, each written in place into the image;
//!    each pixel is a pure function of the scene and its winner, so the image is
//!    bit-identical at any thread count.

mod coverage;
mod shade;
#[cfg(test)]
mod tests;

use glam::{DMat3, DMat4, DVec3, DVec4};
use rayon::prelude::*;

use crate::raster::{rasterize, Fragment, RasterConfig};
use crate::scene::{Mesh, Scene};

pub use coverage::Coverage;

// The perturbation is part of the scene (what the bump map does to the surface); the
// reference evaluates it exactly per pixel, the bakes per texel.
pub use crate::scene::perturb::{
    perturb_height, perturb_normal_map, perturbed_normal, tangent_frame, Perturbation, SurfacePoint,
};
pub use shade::{base_color, shade, shade_with_view, view_vector};

/// The reference image.
#[derive(Debug, Clone, PartialEq)]
pub struct ReferenceImage {
    /// Linear RGB per pixel, row-major, row 0 at the top; each channel clamped to [0, 1].
    /// Black where uncovered.
    pub image: crate::metrics::Rgb64,
    /// Whether a triangle covers the pixel.
    pub mask: Vec<bool>,
    /// World-space perturbed unit normal per pixel, zero where uncovered; empty unless asked
    /// for ([`Options::normals`]).
    pub normals: Vec<[f64; 3]>,
}

/// What [`render_covered`] computes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    pub perturbation: Perturbation,
    /// Shading samples per pixel side (`samples^2` per pixel, box filtered); 1 shades the
    /// pixel centre.
    pub samples: u32,
    /// Keep the normal of each pixel ([`ReferenceImage::normals`]); a run's report does not
    /// read them.
    pub normals: bool,
}

impl ReferenceImage {
    /// Index of pixel `(x, y)` (y = 0 the top row) in `px`, `mask` and `normals`.
    pub fn index(&self, x: u32, y: u32) -> usize {
        y as usize * self.image.width as usize + x as usize
    }
    /// Number of covered pixels.
    pub fn covered(&self) -> usize {
        self.mask.iter().filter(|&&m| m).count()
    }
}

/// The model transform split the three ways vectors transform.
#[derive(Debug, Clone, Copy)]
struct Transforms {
    /// Points.
    model: DMat4,
    /// Tangent vectors `Pu`, `Pv`: the upper-left 3x3.
    linear: DMat3,
    /// Normals: the inverse transpose of `linear`.
    normal: DMat3,
}

impl Transforms {
    fn new(model: DMat4) -> Self {
        let linear = DMat3::from_mat4(model);
        Transforms {
            model,
            linear,
            normal: linear.inverse().transpose(),
        }
    }
}

/// Largest distance outside `[0, 1]` accepted for an f64 barycentric at a pixel centre the
/// rasterizer covered (snapping may cover centres just outside the exact triangle); beyond
/// it the triangle is treated as degenerate in f64 and the fragment's barycentrics are used.
pub const BARY_SLACK: f64 = 0.5;

/// Clip-space positions `proj(width / height) · view · model · pos` of the scene's vertices
/// (step 1).
pub fn clip_positions(scene: &Scene) -> Vec<DVec4> {
    let aspect = f64::from(scene.width) / f64::from(scene.height.max(1));
    let m = scene.camera.proj(aspect) * scene.camera.view() * scene.model;
    scene
        .mesh
        .vertices
        .iter()
        .map(|v| m * v.pos.extend(1.0))
        .collect()
}

/// Exact perspective-correct barycentrics of the centre of pixel `(x, y)` (`y = 0` the top
/// row) w.r.t. the clip-space triangle `clip`, in f64, from the *unsnapped* vertices (step 1).
///
/// The pixel centre in window coordinates (y up, OpenGL viewport) is
/// `(x + 0.5, height - y - 0.5)`, in NDC `(px, py)`. Screen-space barycentrics `λ_i`
/// perspective-corrected with `1 / w_i` give `b_i ∝ λ_i / w_i`; the same `b` solves
/// `Σ b_i (X_i - px W_i) = 0`, `Σ b_i (Y_i - py W_i) = 0`, `Σ b_i = 1` (the clip-space point
/// `Σ b_i C_i` projects onto the pixel centre), i.e. `b ∝ r_x × r_y` with
/// `r_x = (X_i - px W_i)_i`, `r_y = (Y_i - py W_i)_i`. This homogeneous form needs no
/// division by `w` and stays exact for triangles that cross `w = 0` (near-clipped).
///
/// `None` if the triangle is degenerate in f64 (the normalising sum vanishes relative to
/// `|r_x| |r_y|`, or is not finite) or the centre lies more than [`BARY_SLACK`] outside it.
pub fn pixel_barycentrics(
    clip: [DVec4; 3],
    x: u32,
    y: u32,
    width: u32,
    height: u32,
) -> Option<DVec3> {
    sample_barycentrics(clip, f64::from(x) + 0.5, f64::from(y) + 0.5, width, height)
}

/// [`pixel_barycentrics`] at any point `(sx, sy)` of the image, in pixels from its top left
/// corner (the centre of pixel `(x, y)` is `(x + 1/2, y + 1/2)`).
pub fn sample_barycentrics(
    clip: [DVec4; 3],
    sx: f64,
    sy: f64,
    width: u32,
    height: u32,
) -> Option<DVec3> {
    if width == 0 || height == 0 {
        return None;
    }
    let wx = sx;
    let wy = f64::from(height) - sy;
    let px = 2.0 * wx / f64::from(width) - 1.0;
    let py = 2.0 * wy / f64::from(height) - 1.0;
    let rx = DVec3::new(
        clip[0].x - px * clip[0].w,
        clip[1].x - px * clip[1].w,
        clip[2].x - px * clip[2].w,
    );
    let ry = DVec3::new(
        clip[0].y - py * clip[0].w,
        clip[1].y - py * clip[1].w,
        clip[2].y - py * clip[2].w,
    );
    let c = rx.cross(ry);
    let s = c.x + c.y + c.z;
    let scale = rx.length() * ry.length();
    if !(s.is_finite() && scale.is_finite()) || s.abs() <= 1e-12 * scale {
        return None;
    }
    let b = c / s;
    let ok = |t: f64| (-BARY_SLACK..=1.0 + BARY_SLACK).contains(&t);
    (b.is_finite() && ok(b.x) && ok(b.y) && ok(b.z)).then_some(b)
}

fn interpolate(mesh: &Mesh, xf: &Transforms, tri: [u32; 3], b: DVec3) -> SurfacePoint {
    let v = tri.map(|i| mesh.vertices[i as usize]);
    let mix3 =
        |f: fn(&crate::scene::Vertex) -> DVec3| f(&v[0]) * b.x + f(&v[1]) * b.y + f(&v[2]) * b.z;
    let p = mix3(|v| v.pos);
    let n = mix3(|v| v.normal).normalize_or_zero();
    let pu = mix3(|v| v.pu);
    let pv = mix3(|v| v.pv);
    let uv = v[0].uv * b.x + v[1].uv * b.y + v[2].uv * b.z;
    SurfacePoint {
        p: xf.model.transform_point3(p),
        n: (xf.normal * n).normalize_or_zero(),
        pu: xf.linear * pu,
        pv: xf.linear * pv,
        uv,
    }
}

/// The world-space surface point of triangle `tri` (an index into `scene.mesh.triangles`)
/// at barycentrics `bary` (step 2): object-space `P`, `N` (then normalised), `Pu`, `Pv`, `uv`
/// interpolated linearly; `P` transformed by `model`, `N` by the inverse transpose of its
/// 3x3 part (then normalised), `Pu`, `Pv` by the 3x3 part.
pub fn surface_point(scene: &Scene, tri: u32, bary: DVec3) -> SurfacePoint {
    let xf = Transforms::new(scene.model);
    interpolate(&scene.mesh, &xf, scene.mesh.triangles[tri as usize], bary)
}

/// Colour and world normal of one covered pixel.
fn pixel(
    scene: &Scene,
    xf: &Transforms,
    clip: &[DVec4],
    (x, y): (u32, u32),
    (tri, frag_bary): (u32, [f64; 3]),
    perturbation: Perturbation,
    samples: u32,
) -> (DVec3, DVec3) {
    let t = scene.mesh.triangles[tri as usize];
    let cl = t.map(|i| clip[i as usize]);
    let shade_at = |b: DVec3| {
        let sp = interpolate(&scene.mesh, xf, t, b);
        let n = perturbed_normal(&scene.bump, &sp, perturbation);
        let v = view_vector(&scene.camera, sp.p);
        (shade_with_view(n, &sp, v, scene), n)
    };
    let (w, h) = (scene.width, scene.height);
    let centre = shade_at(pixel_barycentrics(cl, x, y, w, h).unwrap_or(DVec3::from(frag_bary)));
    if samples <= 1 {
        return centre;
    }
    // a box filter: s x s samples on a regular grid, all on the pixel's winning triangle
    // (its parameterisation extended past its edges by at most BARY_SLACK)
    let k = f64::from(samples);
    let mut sum = DVec3::ZERO;
    for j in 0..samples {
        for i in 0..samples {
            let sx = f64::from(x) + (f64::from(i) + 0.5) / k;
            let sy = f64::from(y) + (f64::from(j) + 0.5) / k;
            sum += match sample_barycentrics(cl, sx, sy, w, h) {
                Some(b) => shade_at(b).0,
                None => centre.0,
            };
        }
    }
    (sum / (k * k), centre.1)
}

/// Blinn bump mapping per pixel in f64, independent of any engine code (steps 1–5 of the
/// module docs). `raster` is used only for coverage and visibility (the last fragment that
/// passes the early depth test at a pixel wins).
pub fn render_reference(
    scene: &Scene,
    raster: &RasterConfig,
    perturbation: Perturbation,
) -> ReferenceImage {
    render_reference_sampled(scene, raster, perturbation, 1)
}

/// [`render_reference`] with `samples x samples` shading samples per pixel, box filtered:
/// the band-limited image a minified bump map should approach (what mipmaps aim at). Each
/// sample is taken on the triangle that wins the pixel centre; the normals reported are
/// the centre's.
pub fn render_reference_sampled(
    scene: &Scene,
    raster: &RasterConfig,
    perturbation: Perturbation,
    samples: u32,
) -> ReferenceImage {
    let (w, h) = (scene.width, scene.height);
    let out = rasterize(&clip_positions(scene), &scene.mesh.triangles, w, h, raster);
    let coverage = Coverage::of_fragments(&out.fragments, w, h, raster);
    let opts = Options {
        perturbation,
        samples,
        normals: true,
    };
    render_covered(scene, &coverage, &out.fragments, opts)
}

/// The reference of `scene` on the winners `coverage` of the fragments `frags` (rasterised
/// from [`clip_positions`] of `scene`, as the engine's geometry computes them): steps 2–5 of
/// the module docs for every covered pixel, rows in parallel, written in place.
pub fn render_covered(
    scene: &Scene,
    coverage: &Coverage,
    frags: &[Fragment],
    opts: Options,
) -> ReferenceImage {
    let (w, h) = (coverage.width, coverage.height);
    let n_px = w as usize * h as usize;
    let mut img = ReferenceImage {
        image: crate::metrics::Rgb64 {
            width: w,
            height: h,
            px: vec![[0.0; 3]; n_px],
        },
        mask: vec![false; n_px],
        normals: if opts.normals {
            vec![[0.0; 3]; n_px]
        } else {
            Vec::new()
        },
    };
    if n_px == 0 {
        return img;
    }
    let clip = clip_positions(scene);
    let xf = Transforms::new(scene.model);
    let wu = w as usize;
    let mut normal_rows: Vec<Option<&mut [[f64; 3]]>> = if opts.normals {
        img.normals.chunks_mut(wu).map(Some).collect()
    } else {
        (0..h).map(|_| None).collect()
    };
    // Each pixel depends only on the scene and its own winner: rows are computed
    // independently into their own slices, so the result does not depend on the pool size.
    img.image
        .px
        .par_chunks_mut(wu)
        .zip(img.mask.par_chunks_mut(wu))
        .zip(normal_rows.par_iter_mut())
        .enumerate()
        .for_each(|(y, ((px, mask), normals))| {
            let y = y as u32;
            for (x, &k) in coverage.row(y).iter().enumerate() {
                if k == Coverage::NONE {
                    continue;
                }
                let f = &frags[k as usize];
                let (c, n) = pixel(
                    scene,
                    &xf,
                    &clip,
                    (x as u32, y),
                    (f.tri, f.bary),
                    opts.perturbation,
                    opts.samples,
                );
                px[x] = c.to_array();
                mask[x] = true;
                if let Some(normals) = normals {
                    normals[x] = n.to_array();
                }
            }
        });
    img
}
