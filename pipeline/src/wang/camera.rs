//! The orthographic views of the baking and the evaluation, and the item buffer one view of
//! a mesh leaves in the project's rasterizer (`crate::raster`, the hardware model's front
//! end: sub-pixel snapping, top-left fill rule, 24-bit depth, early LESS test).
//!
//! Choices: orthographic projection (the paper does not say; with it the depth difference
//! of §2 step 3 is a distance along the view direction in object units at every pixel),
//! the bounding sphere of the detailed mesh filling the square image with a 2% margin, the
//! camera's up the world axis least aligned with the view direction, orthogonalised.

use glam::{DVec3, DVec4};

use super::Surface;
use crate::raster::{rasterize, RasterConfig};

/// Margin of the bounding sphere in the image.
const MARGIN: f64 = 1.02;

/// One orthographic view of an object.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// Unit, from the object's centre towards the camera.
    pub dir: DVec3,
    pub right: DVec3,
    pub up: DVec3,
    pub centre: DVec3,
    /// Half the side of the view volume in object units.
    pub half: f64,
    /// Image side in pixels.
    pub size: u32,
}

/// Where a point falls in a view: its pixel (if inside the image) and window depth in [0, 1]
/// (0 nearest the camera).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projected {
    pub pixel: Option<(u32, u32)>,
    pub depth: f64,
}

impl View {
    /// The view along `dir` of the sphere `(centre, radius)` on a `size`-pixel image.
    pub fn new(dir: DVec3, centre: DVec3, radius: f64, size: u32) -> View {
        let dir = dir.normalize();
        let axes = [DVec3::X, DVec3::Y, DVec3::Z];
        let least = axes
            .iter()
            .copied()
            .min_by(|a, b| a.dot(dir).abs().total_cmp(&b.dot(dir).abs()))
            .unwrap_or(DVec3::Y);
        let right = least.cross(dir).normalize();
        let up = dir.cross(right);
        View {
            dir,
            right,
            up,
            centre,
            half: radius.max(f64::MIN_POSITIVE) * MARGIN,
            size,
        }
    }

    /// Clip coordinates of `p` (w = 1).
    pub fn clip(&self, p: DVec3) -> DVec4 {
        let d = (p - self.centre) / self.half;
        DVec4::new(d.dot(self.right), d.dot(self.up), -d.dot(self.dir), 1.0)
    }

    /// Where `p` falls (the rasterizer's viewport transform, rows from the top).
    pub fn project(&self, p: DVec3) -> Projected {
        let c = self.clip(p);
        let n = f64::from(self.size);
        let wx = (c.x + 1.0) * 0.5 * n;
        let wy = (c.y + 1.0) * 0.5 * n;
        let (col, row) = (wx.floor(), (n - wy).floor());
        let inside = (0.0..n).contains(&col) && (0.0..n).contains(&row);
        Projected {
            pixel: inside.then_some((col as u32, row as u32)),
            depth: (c.z + 1.0) * 0.5,
        }
    }

    /// Object-space length of a window-depth difference.
    pub fn depth_to_object(&self, dz: f64) -> f64 {
        dz * 2.0 * self.half
    }
}

/// What one view of a mesh leaves per pixel: the nearest triangle (or `u32::MAX`), its
/// window depth (quantised by the rasterizer, as a fraction of the largest code) and the
/// barycentrics there.
#[derive(Debug, Clone)]
pub struct ItemBuffer {
    pub size: u32,
    pub tri: Vec<u32>,
    pub depth: Vec<f64>,
    pub bary: Vec<[f64; 3]>,
}

/// The depth bits of the views' rasterizer.
const DEPTH_BITS: u32 = 24;

impl ItemBuffer {
    /// Rasterise `mesh` in `view`. Each pixel keeps the last fragment written to it, which
    /// the early LESS test makes the nearest.
    pub fn render(mesh: &Surface, view: &View) -> ItemBuffer {
        let clip: Vec<DVec4> = mesh.positions.iter().map(|&p| view.clip(p)).collect();
        let cfg = RasterConfig {
            depth_bits: DEPTH_BITS,
            ..RasterConfig::default()
        };
        let raster = rasterize(&clip, &mesh.triangles, view.size, view.size, &cfg);
        let px = view.size as usize * view.size as usize;
        let mut out = ItemBuffer {
            size: view.size,
            tri: vec![u32::MAX; px],
            depth: vec![1.0; px],
            bary: vec![[0.0; 3]; px],
        };
        let max = f64::from(crate::raster::scan::depth_max(DEPTH_BITS));
        for f in &raster.fragments {
            let k = f.y as usize * view.size as usize + f.x as usize;
            out.tri[k] = f.tri;
            out.depth[k] = f64::from(f.depth) / max;
            out.bary[k] = f.bary;
        }
        out
    }

    /// Index of pixel `(col, row)`.
    pub fn index(&self, (col, row): (u32, u32)) -> usize {
        row as usize * self.size as usize + col as usize
    }

    /// Pixels covered.
    pub fn covered(&self) -> usize {
        self.tri.iter().filter(|t| **t != u32::MAX).count()
    }
}
