//! Triangle meshes with per-vertex tangent frames, and their checks. They are built by
//! `super::shapes` (the config's `MeshSpec`: parametric surfaces, Newell's teapot),
//! `super::obj`, `super::lathe` and `super::atlas`.
//!
//! # Conventions
//!
//! * Parametric surfaces are **y-up**: the sphere, torus and cylinder have the y axis as
//!   their axis, and the teapot's original z-up data is rotated by `(x, y, z) -> (x, z, -y)`
//!   (spout toward +x, lid toward +y). The quad lies in the z = 0 plane facing +z.
//! * `u` runs around the axis and `v` along it (from -y to +y for the sphere and cylinder),
//!   chosen so that `Pu × Pv` points *out* of the surface: on the side facing a viewer on +z,
//!   `u` increases toward +x and `v` toward +y, as on the quad.
//! * `pu`, `pv` are the analytic derivatives of the position with respect to the *final*
//!   texture coordinates (after `uv_repeat`), so `uv_repeat` divides them.
//! * Triangles are counter-clockwise seen from outside (`(b - a) × (c - a)` along the normal).

use glam::{DVec2, DVec3};

use super::SceneError;

/// A mesh vertex with its tangent frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Vertex {
    pub pos: DVec3,
    /// Unit surface normal.
    pub normal: DVec3,
    /// Texture coordinates (bump maps tile with period 1).
    pub uv: DVec2,
    /// ∂P/∂u, unnormalised.
    pub pu: DVec3,
    /// ∂P/∂v, unnormalised.
    pub pv: DVec3,
}

/// An indexed triangle mesh.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    pub vertices: Vec<Vertex>,
    pub triangles: Vec<[u32; 3]>,
}

/// Relative tolerance for degenerate triangles: twice the area at most this fraction of the
/// longest edge squared (an aspect ratio of 1e-12).
const DEGENERATE_REL: f64 = 1e-12;

/// Whether the triangle `abc` has (near) zero area.
pub(super) fn degenerate3(a: DVec3, b: DVec3, c: DVec3) -> bool {
    let (e1, e2, e3) = (b - a, c - a, c - b);
    let longest = e1
        .length_squared()
        .max(e2.length_squared())
        .max(e3.length_squared());
    let twice_area = e1.cross(e2).length();
    twice_area.is_nan() || twice_area <= DEGENERATE_REL * longest
}

/// Whether the texture-space triangle `abc` has (near) zero area.
pub(super) fn degenerate2(a: DVec2, b: DVec2, c: DVec2) -> bool {
    let (e1, e2, e3) = (b - a, c - a, c - b);
    let longest = e1
        .length_squared()
        .max(e2.length_squared())
        .max(e3.length_squared());
    let twice_area = e1.perp_dot(e2).abs();
    twice_area.is_nan() || twice_area <= DEGENERATE_REL * longest
}

impl Mesh {
    /// Check the mesh: every vertex finite with a unit normal (within 1e-6), at least one
    /// triangle, every index in range, no zero-area triangle and no triangle with zero
    /// texture-space area. Errors carry `field` and name the vertex or triangle.
    pub fn validate(&self, field: &str) -> Result<(), SceneError> {
        let bad = |message: String| Err(SceneError::invalid(field, message));
        for (i, v) in self.vertices.iter().enumerate() {
            for (name, ok) in [
                ("position", v.pos.is_finite()),
                ("normal", v.normal.is_finite()),
                ("uv", v.uv.is_finite()),
                ("pu", v.pu.is_finite()),
                ("pv", v.pv.is_finite()),
            ] {
                if !ok {
                    return bad(format!("vertex {i}: non-finite {name} in {v:?}"));
                }
            }
        }
        if self.triangles.is_empty() {
            return bad("expected at least one triangle, found none".into());
        }
        let n = self.vertices.len();
        for (t, tri) in self.triangles.iter().enumerate() {
            if let Some(&k) = tri.iter().find(|&&k| k as usize >= n) {
                return bad(format!(
                    "triangle {t}: vertex index {k} out of range (the mesh has {n} vertices)"
                ));
            }
            let [a, b, c] = tri.map(|k| self.vertices[k as usize]);
            if degenerate3(a.pos, b.pos, c.pos) {
                return bad(format!(
                    "triangle {t}: degenerate (zero area), positions {}, {}, {}",
                    a.pos, b.pos, c.pos
                ));
            }
            if degenerate2(a.uv, b.uv, c.uv) {
                return bad(format!(
                    "triangle {t}: degenerate texture coordinates (zero uv area), uv {}, {}, {}",
                    a.uv, b.uv, c.uv
                ));
            }
        }
        // Unit normals last, so that a zero normal computed from a degenerate triangle is
        // reported as that triangle.
        for (i, v) in self.vertices.iter().enumerate() {
            if (v.normal.length() - 1.0).abs() > 1e-6 {
                return bad(format!(
                    "vertex {i}: expected a unit normal, found {} (length {})",
                    v.normal,
                    v.normal.length()
                ));
            }
        }
        Ok(())
    }

    /// Axis-aligned bounds `(min, max)` of the vertex positions; `(0, 0)` for an empty mesh.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        if self.vertices.is_empty() {
            return (DVec3::ZERO, DVec3::ZERO);
        }
        self.vertices.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), v| (lo.min(v.pos), hi.max(v.pos)),
        )
    }

    /// Drop zero-area triangles and the vertices no triangle uses.
    pub(super) fn drop_degenerate(&mut self) {
        let verts = &self.vertices;
        self.triangles.retain(|t| {
            let [a, b, c] = t.map(|k| verts[k as usize].pos);
            !degenerate3(a, b, c)
        });
        let mut remap = vec![u32::MAX; self.vertices.len()];
        let mut kept = Vec::with_capacity(self.vertices.len());
        for t in &mut self.triangles {
            for k in t.iter_mut() {
                if remap[*k as usize] == u32::MAX {
                    remap[*k as usize] = kept.len() as u32;
                    kept.push(self.vertices[*k as usize]);
                }
                *k = remap[*k as usize];
            }
        }
        self.vertices = kept;
    }
}
