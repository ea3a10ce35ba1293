//! Normal maps for simplified meshes, after Wang, Fröhlich and Göbel, "Fast Normal Map
//! Generation for Simplified Meshes" (`shared/seeds/wang-normal-map-generation-hilo.txt`).
//!
//! The method (§2, the `constructNormalMap` listing): simplify the detailed mesh
//! ([`simplify`], Garland-Heckbert quadrics through `meshopt`), scan-convert every face of the
//! simplified mesh into a right-angled triangle patch of a packed map ([`pack`]), initialise
//! each sample with the simplified mesh's interpolated vertex normal, then render the
//! detailed mesh from a set of views uniformly distributed around it ([`views`]) with the
//! project's own rasterizer and, per view, replace a sample's normal by the one the detailed
//! mesh shows at the sample's pixel where the depth difference is below a threshold and below
//! the best so far ([`bake`]). The error analysis of §5 ([`evaluate`]) compares renders of
//! the detailed mesh with renders of the normal-mapped simplified mesh from 30 other views.
//!
//! Nothing here needs a correspondence between the two meshes: the simplified mesh keeps
//! only its own vertices (§1: "it can be combined with any existing simplification method
//! even if the topology changed").

pub mod bake;
pub mod camera;
pub mod evaluate;
pub mod pack;
pub mod scene;
pub mod simplify;
pub mod views;

#[cfg(test)]
mod tests;

use glam::DVec3;
use std::path::Path;

use crate::scene::mesh::{smooth_normals, FileMesh};
use crate::scene::SceneError;

/// A triangle mesh with one smooth normal per position: what the method needs of the
/// detailed and of the simplified mesh (no texture coordinates).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Surface {
    pub positions: Vec<DVec3>,
    pub triangles: Vec<[u32; 3]>,
    /// Unit, per position (zero for a position no triangle uses).
    pub normals: Vec<DVec3>,
}

impl Surface {
    /// Load an OBJ or PLY file (by extension, `.obj` or `.ply`, any case) with the rule for
    /// scan defects of `docs/assets.md`: zero-area faces and repeats dropped, smooth normals
    /// with their fallbacks. Texture coordinates and file normals are ignored.
    pub fn load(path: &Path) -> Result<Surface, SceneError> {
        Surface::from_bytes(path, &Surface::read(path)?)
    }

    /// The bytes of a mesh file [`Surface::load`] reads (bounded as its kind is).
    pub fn read(path: &Path) -> Result<Vec<u8>, SceneError> {
        use crate::scene::files::{read_bounded, MAX_OBJ_BYTES, MAX_PLY_BYTES};
        match Surface::kind(path)? {
            "ply" => read_bounded(path, MAX_PLY_BYTES, "PLY"),
            _ => read_bounded(path, MAX_OBJ_BYTES, "OBJ"),
        }
    }

    /// `ply` or `obj`, by the extension of `path` (any case).
    fn kind(path: &Path) -> Result<&'static str, SceneError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("ply") => Ok("ply"),
            Some("obj") => Ok("obj"),
            _ => Err(SceneError::invalid(
                path.display().to_string(),
                "expected a mesh file ending in .obj or .ply",
            )),
        }
    }

    /// [`Surface::load`] of the bytes already read from `path` (named in the errors).
    pub fn from_bytes(path: &Path, bytes: &[u8]) -> Result<Surface, SceneError> {
        let file = match Surface::kind(path)? {
            "ply" => crate::scene::ply::parse(bytes).map_err(|m| {
                SceneError::file(path.display(), format!("could not load PLY: {m}"))
            })?,
            _ => crate::scene::obj::from_bytes(path, bytes)?,
        };
        Surface::from_file(&file).map_err(|m| SceneError::invalid(path.display().to_string(), m))
    }

    /// The kept triangles of a file mesh with their smooth normals.
    pub fn from_file(file: &FileMesh) -> Result<Surface, String> {
        let kept = file.keep()?;
        Ok(Surface {
            positions: file.positions.clone(),
            triangles: kept.triangles.iter().map(|&t| file.triangles[t]).collect(),
            normals: kept.normals,
        })
    }

    /// A surface from positions and triangles, normals area-weighted per position.
    pub fn with_smooth_normals(positions: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Surface {
        let faces: Vec<([usize; 3], DVec3)> = triangles
            .iter()
            .map(|t| (t.map(|k| k as usize), self::face_cross(&positions, *t)))
            .collect();
        let normals = smooth_normals(positions.len(), &faces);
        Surface {
            positions,
            triangles,
            normals,
        }
    }

    /// The corners of triangle `t`.
    pub fn corners(&self, t: usize) -> [DVec3; 3] {
        self.triangles[t].map(|k| self.positions[k as usize])
    }

    /// The unit normal of triangle `t` (zero if degenerate).
    pub fn face_normal(&self, t: usize) -> DVec3 {
        face_cross(&self.positions, self.triangles[t]).normalize_or_zero()
    }

    /// The normal interpolated at barycentrics `b` of triangle `t`, renormalised.
    pub fn normal_at(&self, t: usize, b: [f64; 3]) -> DVec3 {
        let n = self.triangles[t].map(|k| self.normals[k as usize]);
        (n[0] * b[0] + n[1] * b[1] + n[2] * b[2]).normalize_or_zero()
    }

    /// The point at barycentrics `b` of triangle `t`.
    pub fn point_at(&self, t: usize, b: [f64; 3]) -> DVec3 {
        let p = self.corners(t);
        p[0] * b[0] + p[1] * b[1] + p[2] * b[2]
    }

    /// The bounding sphere used for views: the centre of the bounding box of the positions
    /// triangles use, and the largest distance from it.
    pub fn bounding_sphere(&self) -> (DVec3, f64) {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for t in &self.triangles {
            for &k in t {
                let p = self.positions[k as usize];
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
        let c = (lo + hi) * 0.5;
        let r = self
            .triangles
            .iter()
            .flatten()
            .map(|&k| (self.positions[k as usize] - c).length())
            .fold(0.0f64, f64::max);
        (c, r)
    }
}

/// `(b - a) x (c - a)` of a triangle: twice its area times its normal.
fn face_cross(positions: &[DVec3], t: [u32; 3]) -> DVec3 {
    let [a, b, c] = t.map(|k| positions[k as usize]);
    (b - a).cross(c - a)
}
