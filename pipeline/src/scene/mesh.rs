//! Triangle meshes with per-vertex tangent frames, and their checks. They are built by
//! `super::shapes` (the config's `MeshSpec`: parametric surfaces, Newell's teapot),
//! `super::lathe` and `super::atlas`, and from files: `super::obj` and `super::ply` read a
//! [`FileMesh`], which [`FileMesh::keep`] cleans by the rule for scan defects
//! (`docs/assets.md`, "Meshes from files") and [`FileMesh::to_mesh`] builds.
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
pub(crate) fn degenerate3(a: DVec3, b: DVec3, c: DVec3) -> bool {
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

// ------------------------------------------------------------------ meshes read from files

/// No value: a corner without a texture coordinate or normal in its file.
pub const NONE: u32 = u32::MAX;

/// How a file names its faces in messages: by line (OBJ, ASCII PLY) or by element index
/// (binary PLY, counting from 0).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Place {
    #[default]
    Line,
    FaceElement,
}

impl Place {
    /// "line 12" or "face element 7".
    pub fn name(self, at: u64) -> String {
        match self {
            Place::Line => format!("line {at}"),
            Place::FaceElement => format!("face element {at}"),
        }
    }
}

/// A per-corner attribute of a [`FileMesh`]: the values, and per triangle the value index of
/// each corner ([`NONE`] where the file gives the corner none).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Corners<T> {
    pub values: Vec<T>,
    pub index: Vec<[u32; 3]>,
}

/// A mesh as read from a file (`super::obj`, `super::ply`), before the rule for scan defects
/// (`docs/assets.md`, "Meshes from files"): the file's positions, its faces fanned into
/// triangles in file order (`(c0, ci, ci+1)`), and the corners' texture coordinates and
/// normals. Readers check every index and number; `uv_repeat` is applied when building.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FileMesh {
    pub positions: Vec<DVec3>,
    /// Position indices, counter-clockwise as in the file.
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle, where its face is: a line or a face element index, as `place` says.
    pub places: Vec<u64>,
    pub place: Place,
    /// Texture coordinates, if the file has them.
    pub uvs: Option<Corners<DVec2>>,
    /// Normals, if the file has them (a corner may lack one: [`NONE`]).
    pub normals: Option<Corners<DVec3>>,
    /// Why the file's texture coordinates cannot be used (e.g. the line of the first face
    /// without them); `None` when every corner has one.
    pub no_uv: Option<String>,
    /// Faces of fewer than three corners (points, edges): ignored, counted.
    pub short_faces: usize,
}

/// What the rule for scan defects did to a [`FileMesh`] (`docs/assets.md`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Defects {
    /// Triangles read (polygons fanned), before the rule.
    pub triangles: usize,
    /// Faces of fewer than three corners, ignored.
    pub short_faces: usize,
    /// Zero-area triangles, dropped.
    pub zero_area: usize,
    /// Repeats of an earlier triangle on the same three positions (either winding), dropped.
    pub repeated: usize,
    /// File vertices that no kept triangle uses, left out.
    pub unreferenced: usize,
    /// Vertices whose area-weighted normal sum cancels: given a normal by the fallback.
    pub cancelled_normals: usize,
    /// Corners whose file normal has zero length: given the computed normal.
    pub zero_file_normals: usize,
}

/// The triangles a [`FileMesh`] keeps, with the smooth normal of each position.
#[derive(Debug, Clone, Default)]
pub struct Kept {
    /// Indices into [`FileMesh::triangles`], in file order.
    pub triangles: Vec<usize>,
    /// Per position: the smooth normal over the kept triangles ([`smooth_normals`]); zero
    /// for positions no kept triangle uses.
    pub normals: Vec<DVec3>,
    pub defects: Defects,
}

/// A fast hasher for the loaders' maps of integer keys (FxHash's step, as in rustc, and
/// MurmurHash3's finaliser so that the low bits the table indexes by are mixed): the default
/// SipHash took an eighth of the time of loading a 1M-triangle mesh.
#[derive(Default, Clone, Copy)]
pub struct FxHasher(u64);

impl std::hash::Hasher for FxHasher {
    fn write(&mut self, bytes: &[u8]) {
        let mut chunks = bytes.chunks_exact(8);
        for c in &mut chunks {
            self.write_u64(u64::from_le_bytes(c.try_into().unwrap()));
        }
        let rest = chunks.remainder();
        if !rest.is_empty() {
            let mut word = [0u8; 8];
            word[..rest.len()].copy_from_slice(rest);
            self.write_u64(u64::from_le_bytes(word));
        }
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn write_u32(&mut self, x: u32) {
        self.write_u64(u64::from(x));
    }
    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }
    fn finish(&self) -> u64 {
        let mut h = self.0;
        h ^= h >> 33;
        h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
        h ^= h >> 33;
        h = h.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
        h ^ (h >> 33)
    }
}

/// The [`FxHasher`] builder.
pub type FxBuild = std::hash::BuildHasherDefault<FxHasher>;

/// The key of a position for "equal coordinates": its bits, with -0 as +0.
fn position_key(p: DVec3) -> [u64; 3] {
    (p + DVec3::ZERO).to_array().map(f64::to_bits)
}

/// The rule's first two steps over triangles given by their corner positions, in file order:
/// a zero-area triangle (`degenerate3`) is dropped, and of the triangles on the same three
/// positions (equal coordinates, in either winding: exact duplicates and back-to-back pairs)
/// only the first is kept. Returns whether each is kept, and the zero-area and repeat counts.
pub fn kept_faces_counted(
    count: usize,
    corners: impl Fn(usize) -> [DVec3; 3],
) -> (Vec<bool>, usize, usize) {
    let mut seen = std::collections::HashSet::with_capacity_and_hasher(count, FxBuild::default());
    let (mut zero, mut repeated) = (0, 0);
    let kept = (0..count)
        .map(|t| {
            let [a, b, c] = corners(t);
            if degenerate3(a, b, c) {
                zero += 1;
                return false;
            }
            let mut key = [a, b, c].map(position_key);
            key.sort_unstable();
            let new = seen.insert(key);
            repeated += usize::from(!new);
            new
        })
        .collect();
    (kept, zero, repeated)
}

/// Per position, the first position with equal coordinates (-0 as +0): equal ids, equal
/// coordinates.
fn weld(positions: &[DVec3]) -> Vec<u32> {
    let mut first =
        std::collections::HashMap::with_capacity_and_hasher(positions.len(), FxBuild::default());
    (0..positions.len() as u32)
        .map(|k| {
            *first
                .entry(position_key(positions[k as usize]))
                .or_insert(k)
        })
        .collect()
}

/// Three numbers in increasing order.
fn sort3([a, b, c]: [u32; 3]) -> [u32; 3] {
    let (a, b) = (a.min(b), a.max(b));
    let (b, c) = (b.min(c), b.max(c));
    let (a, b) = (a.min(b), a.max(b));
    [a, b, c]
}

/// Smooth vertex normals from faces: for each position the area-weighted sum of its faces'
/// normals, normalised. Where that sum cancels (its length at most 1e-9 of the sum of the
/// face normals' lengths, e.g. a fold), the sum of the faces' unit normals; where that
/// cancels too, the normal of the first face that uses the position. `faces` are
/// `(position indices, (b - a) x (c - a))`. Also returns how many positions took a fallback.
pub fn smooth_normals_counted(
    positions: usize,
    faces: &[([usize; 3], DVec3)],
) -> (Vec<DVec3>, usize) {
    let mut area = vec![DVec3::ZERO; positions];
    let mut scale = vec![0.0f64; positions];
    for (tri, n) in faces {
        for &k in tri {
            area[k] += *n;
            scale[k] += n.length();
        }
    }
    let cancelled = |k: usize, v: DVec3| v.length() <= 1e-9 * scale[k];
    let mut out: Vec<DVec3> = area.iter().map(|v| v.normalize_or_zero()).collect();
    let bad: Vec<usize> = (0..positions)
        .filter(|&k| scale[k] > 0.0 && cancelled(k, area[k]))
        .collect();
    if bad.is_empty() {
        return (out, 0);
    }
    let mut unit = vec![DVec3::ZERO; positions];
    let mut first = vec![None; positions];
    for (tri, n) in faces {
        for &k in tri {
            unit[k] += n.normalize_or_zero();
            first[k].get_or_insert(n.normalize_or_zero());
        }
    }
    for &k in &bad {
        out[k] = if unit[k].length() > 1e-9 {
            unit[k].normalize()
        } else {
            first[k].unwrap_or(DVec3::ZERO)
        };
    }
    (out, bad.len())
}

/// [`smooth_normals_counted`] without the count.
pub fn smooth_normals(positions: usize, faces: &[([usize; 3], DVec3)]) -> Vec<DVec3> {
    smooth_normals_counted(positions, faces).0
}

impl FileMesh {
    /// The rule for scan defects (`docs/assets.md`): zero-area triangles and repeats dropped,
    /// smooth normals per position over the triangles kept (with their fallbacks), the
    /// positions no kept triangle uses counted. An error if no triangle is kept.
    pub fn keep(&self) -> Result<Kept, String> {
        let pos = |k: u32| self.positions[k as usize];
        // [`kept_faces_counted`] on welded positions, by sorting instead of a set: the same
        // faces (of equal keys the first in the file), with sequential memory access
        let ids = weld(&self.positions);
        let mut flags = vec![false; self.triangles.len()];
        let mut keys: Vec<([u32; 3], u32)> = Vec::with_capacity(self.triangles.len());
        for (t, tri) in self.triangles.iter().enumerate() {
            let [a, b, c] = tri.map(pos);
            if !degenerate3(a, b, c) {
                keys.push((sort3(tri.map(|k| ids[k as usize])), t as u32));
            }
        }
        let zero_area = self.triangles.len() - keys.len();
        keys.sort_unstable();
        for (i, (key, t)) in keys.iter().enumerate() {
            if i == 0 || keys[i - 1].0 != *key {
                flags[*t as usize] = true;
            }
        }
        let repeated = keys.len() - flags.iter().filter(|f| **f).count();
        let triangles: Vec<usize> = (0..flags.len()).filter(|&t| flags[t]).collect();
        if triangles.is_empty() {
            return Err(if self.triangles.is_empty() {
                "expected at least one face, found none".into()
            } else {
                format!(
                    "expected at least one face of non-zero area, found none ({} faces, all \
                     of zero area or duplicates)",
                    self.triangles.len()
                )
            });
        }
        let faces: Vec<([usize; 3], DVec3)> = triangles
            .iter()
            .map(|&t| {
                let tri = self.triangles[t];
                let [a, b, c] = tri.map(pos);
                (tri.map(|k| k as usize), (b - a).cross(c - a)) // |n| = 2 * area
            })
            .collect();
        let (normals, cancelled_normals) = smooth_normals_counted(self.positions.len(), &faces);
        let mut used = vec![false; self.positions.len()];
        for (tri, _) in &faces {
            for &k in tri {
                used[k] = true;
            }
        }
        let unreferenced = used.iter().filter(|u| !**u).count();
        Ok(Kept {
            triangles,
            normals,
            defects: Defects {
                triangles: self.triangles.len(),
                short_faces: self.short_faces,
                zero_area,
                repeated,
                unreferenced,
                cancelled_normals,
                zero_file_normals: 0,
            },
        })
    }

    /// The normal of corner `i` of triangle `t`: the file's (normalised) if it has one of
    /// non-zero length, else the smooth normal of the position; and whether a file normal
    /// of zero length was replaced.
    fn corner_normal(&self, kept: &Kept, t: usize, i: usize) -> (DVec3, bool) {
        let smooth = kept.normals[self.triangles[t][i] as usize];
        match &self.normals {
            Some(n) if n.index[t][i] != NONE => {
                let v = n.values[n.index[t][i] as usize].normalize_or_zero();
                if v == DVec3::ZERO {
                    (smooth, true)
                } else {
                    (v, false)
                }
            }
            _ => (smooth, false),
        }
    }

    /// The corner normals of the kept triangles (`3 k + i` for the `k`-th kept triangle) when
    /// the file has normals (the others take the smooth normal), for the generated atlas;
    /// `None` when it has none. Counts the zero file normals replaced in `kept.defects`.
    pub fn corner_normals(&self, kept: &mut Kept) -> Option<Vec<DVec3>> {
        self.normals.as_ref()?;
        let mut out = Vec::with_capacity(3 * kept.triangles.len());
        let mut replaced = 0;
        for &t in &kept.triangles {
            for i in 0..3 {
                let (n, r) = self.corner_normal(kept, t, i);
                out.push(n);
                replaced += usize::from(r);
            }
        }
        kept.defects.zero_file_normals = replaced;
        Some(out)
    }

    /// The mesh with the file's texture coordinates (times `rep`): the kept triangles, one
    /// vertex per distinct (position, uv, normal) of their corners in order of first use,
    /// normals by `FileMesh::corner_normal`, `Pu`, `Pv` per triangle from positions and
    /// uvs, averaged per vertex weighted by area. A kept face of zero uv area is an error
    /// naming its place.
    pub fn to_mesh(&self, rep: DVec2) -> Result<(Mesh, Defects), String> {
        if let Some(why) = &self.no_uv {
            return Err(why.clone());
        }
        let Some(uvs) = &self.uvs else {
            return Err(
                "no texture coordinates: bump mapping needs them (or use atlas: true)".into(),
            );
        };
        let mut kept = self.keep()?;
        // Per position when every attribute is indexed like the positions (PLY), else per
        // (position, uv, normal) index triple (OBJ).
        let normal_index = self.normals.as_ref().map(|n| &n.index);
        let per_position =
            uvs.index == self.triangles && normal_index.is_none_or(|n| *n == self.triangles);
        let mut by_position = vec![
            NONE;
            if per_position {
                self.positions.len()
            } else {
                0
            }
        ];
        let mut by_triple: std::collections::HashMap<(u32, u32, u32), u32, FxBuild> =
            std::collections::HashMap::default();
        let mut mesh = Mesh {
            vertices: Vec::new(),
            triangles: Vec::with_capacity(kept.triangles.len()),
        };
        let mut replaced = 0;
        for &t in &kept.triangles {
            let mut tri = [0u32; 3];
            for (i, slot) in tri.iter_mut().enumerate() {
                let p = self.triangles[t][i];
                let next = mesh.vertices.len() as u32;
                let id = if per_position {
                    let e = &mut by_position[p as usize];
                    if *e == NONE {
                        *e = next;
                    }
                    *e
                } else {
                    let n = normal_index.map_or(NONE, |n| n[t][i]);
                    *by_triple.entry((p, uvs.index[t][i], n)).or_insert(next)
                };
                if id == next {
                    let (normal, r) = self.corner_normal(&kept, t, i);
                    replaced += usize::from(r);
                    mesh.vertices.push(Vertex {
                        pos: self.positions[p as usize],
                        normal,
                        uv: uvs.values[uvs.index[t][i] as usize] * rep,
                        pu: DVec3::ZERO,
                        pv: DVec3::ZERO,
                    });
                }
                *slot = id;
            }
            mesh.triangles.push(tri);
        }
        kept.defects.zero_file_normals = replaced;
        for (k, tri) in mesh.triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|k| mesh.vertices[k as usize].uv);
            if degenerate2(a, b, c) {
                return Err(format!(
                    "{}: a face with degenerate texture coordinates (zero uv area), uv {a}, \
                     {b}, {c}: expected three distinct, non-collinear texture coordinates",
                    self.place.name(self.places[kept.triangles[k]])
                ));
            }
        }
        // Tangents: per triangle solve [e1 e2] = [Pu Pv] [duv1 duv2], average weighted by area.
        let mut sum_u = vec![DVec3::ZERO; mesh.vertices.len()];
        let mut sum_v = vec![DVec3::ZERO; mesh.vertices.len()];
        let mut weight = vec![0.0; mesh.vertices.len()];
        for tri in &mesh.triangles {
            let [a, b, c] = tri.map(|k| mesh.vertices[k as usize]);
            let (e1, e2) = (b.pos - a.pos, c.pos - a.pos);
            let (d1, d2) = (b.uv - a.uv, c.uv - a.uv);
            let det = d1.perp_dot(d2);
            if det == 0.0 {
                continue; // not degenerate2, so not reached
            }
            let pu = (e1 * d2.y - e2 * d1.y) / det;
            let pv = (e2 * d1.x - e1 * d2.x) / det;
            let area = 0.5 * e1.cross(e2).length();
            for &k in tri {
                sum_u[k as usize] += pu * area;
                sum_v[k as usize] += pv * area;
                weight[k as usize] += area;
            }
        }
        for (k, v) in mesh.vertices.iter_mut().enumerate() {
            if weight[k] > 0.0 {
                v.pu = sum_u[k] / weight[k];
                v.pv = sum_v[k] / weight[k];
            }
        }
        Ok((mesh, kept.defects))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file mesh of `positions` and `triangles`, uvs per position (`uv = (x, y)`), faces on
    /// lines 10, 11, ...
    fn file(positions: &[[f64; 3]], triangles: &[[u32; 3]]) -> FileMesh {
        let positions: Vec<DVec3> = positions.iter().map(|&p| DVec3::from(p)).collect();
        FileMesh {
            uvs: Some(Corners {
                values: positions.iter().map(|p| p.truncate()).collect(),
                index: triangles.to_vec(),
            }),
            positions,
            triangles: triangles.to_vec(),
            places: (10..10 + triangles.len() as u64).collect(),
            ..FileMesh::default()
        }
    }

    /// The unit square as two triangles, counter-clockwise seen from +z.
    const SQUARE: [[f64; 3]; 4] = [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]];

    #[test]
    fn zero_area_faces_are_dropped_and_counted() {
        // a collinear triangle and one with two equal corners, between two good ones
        let mut p = SQUARE.to_vec();
        p.push([2.0, 0.0, 0.0]);
        let f = file(&p, &[[0, 1, 2], [0, 1, 4], [1, 1, 3], [0, 2, 3]]);
        let (m, d) = f.to_mesh(DVec2::ONE).unwrap();
        assert_eq!(m.triangles, [[0, 1, 2], [0, 2, 3]]);
        assert_eq!((d.triangles, d.zero_area, d.repeated), (4, 2, 0));
        // the vertex only the dropped face used is left out
        assert_eq!((m.vertices.len(), d.unreferenced), (4, 1));
        m.validate("mesh").unwrap();
        // a file of zero-area faces only is an error
        let e = file(&p, &[[0, 1, 4]]).to_mesh(DVec2::ONE).unwrap_err();
        assert!(e.contains("non-zero area") && e.contains("1 faces"), "{e}");
        let e = file(&p, &[]).to_mesh(DVec2::ONE).unwrap_err();
        assert!(e.contains("at least one face"), "{e}");
    }

    #[test]
    fn back_to_back_duplicates_keep_the_first() {
        // the square's first triangle again wound the other way, then an exact copy of the
        // second on separate vertices at the same coordinates (with -0 for 0)
        let mut p = SQUARE.to_vec();
        p.extend([[-0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, -0.0]]);
        let f = file(&p, &[[0, 1, 2], [0, 2, 1], [0, 2, 3], [4, 5, 6]]);
        let (m, d) = f.to_mesh(DVec2::ONE).unwrap();
        assert_eq!((d.repeated, d.zero_area, d.unreferenced), (2, 0, 3));
        assert_eq!(m.triangles, [[0, 1, 2], [0, 2, 3]]);
        // the side written first: facing +z
        assert!(m.vertices.iter().all(|v| v.normal == DVec3::Z));
        // the same pair with the other winding first faces -z
        let f = file(&SQUARE, &[[0, 2, 1], [0, 1, 2]]);
        let (m, d) = f.to_mesh(DVec2::ONE).unwrap(); // clockwise in uv: accepted
        assert_eq!((m.triangles.len(), d.repeated), (1, 1));
        assert!(m.vertices.iter().all(|v| v.normal == -DVec3::Z));
    }

    #[test]
    fn unreferenced_vertices_are_left_out() {
        let mut p = vec![[9.0, 9.0, 9.0]];
        p.extend(SQUARE);
        p.push([5.0, 5.0, 5.0]);
        let f = file(&p, &[[1, 2, 3], [1, 3, 4]]);
        let (m, d) = f.to_mesh(DVec2::ONE).unwrap();
        assert_eq!((m.vertices.len(), d.unreferenced), (4, 2));
        assert_eq!(m.vertices[0].pos, DVec3::ZERO);
        assert_eq!(m.triangles, [[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn cancelled_normal_sums_fall_back_by_the_rule() {
        // vertex 4 is the tip of two faces of equal area folded onto each other (a fin):
        // both sums cancel, so it takes the first face's normal (+z); so does vertex 2,
        // shared by one face up and one of the same area down
        let p = [
            [0., 0., 0.],
            [1., 0., 0.],
            [0., 1., 0.],
            [1., 1., 0.],
            [2., 2., 0.],
        ];
        let f = file(&p, &[[0, 1, 3], [0, 3, 2], [1, 4, 3], [2, 4, 3]]);
        let (m, d) = f.to_mesh(DVec2::ONE).unwrap();
        assert_eq!(d.cancelled_normals, 2);
        for at in [DVec3::new(2., 2., 0.), DVec3::Y] {
            let v = m.vertices.iter().find(|v| v.pos == at);
            assert_eq!(v.unwrap().normal, DVec3::Z);
        }
        m.validate("mesh").unwrap();
        // the area-weighted sum cancels but not the unit sum: +z with area 2 against two
        // faces of area 1 facing -z, all sharing vertices 0 and 2: they take -z
        let p = [[0., 0., 0.], [2., 0., 0.], [0., 2., 0.], [1., 0., 0.]];
        let faces: Vec<([usize; 3], DVec3)> = [[0, 1, 2], [0, 2, 3], [0, 2, 3]]
            .iter()
            .map(|t: &[usize; 3]| {
                let [a, b, c] = t.map(|k| DVec3::from(p[k]));
                (*t, (b - a).cross(c - a))
            })
            .collect();
        let (n, count) = smooth_normals_counted(4, &faces);
        assert_eq!((n[0], n[2], count), (-DVec3::Z, -DVec3::Z, 2));
    }

    #[test]
    fn file_normals_of_zero_length_take_the_computed_normal() {
        let mut f = file(&SQUARE, &[[0, 1, 2], [0, 2, 3]]);
        f.normals = Some(Corners {
            values: vec![DVec3::ZERO, DVec3::new(0.0, 0.0, 2.0)],
            index: vec![[0, 1, 1], [0, 1, 1]],
        });
        let (m, d) = f.to_mesh(DVec2::ONE).unwrap();
        assert_eq!(d.zero_file_normals, 1); // corner 0 of the first triangle (one vertex)
        assert!(m.vertices.iter().all(|v| v.normal == DVec3::Z));
        let mut kept = f.keep().unwrap();
        let corners = f.corner_normals(&mut kept).unwrap();
        assert_eq!((corners.len(), kept.defects.zero_file_normals), (6, 2));
        assert!(corners.iter().all(|&n| n == DVec3::Z));
    }

    #[test]
    fn zero_uv_area_is_an_error_naming_the_place() {
        let mut f = file(&SQUARE, &[[0, 1, 2], [0, 2, 3]]);
        f.uvs.as_mut().unwrap().values[3] = DVec2::new(0.5, 0.5); // on the diagonal 0-2
        let e = f.to_mesh(DVec2::ONE).unwrap_err();
        assert!(
            e.starts_with("line 11: a face with degenerate texture coordinates"),
            "{e}"
        );
        f.place = Place::FaceElement;
        let e = f.to_mesh(DVec2::ONE).unwrap_err();
        assert!(e.starts_with("face element 11:"), "{e}");
        // missing texture coordinates: the reader's reason
        f.no_uv = Some("line 3: no vt".into());
        assert_eq!(f.to_mesh(DVec2::ONE).unwrap_err(), "line 3: no vt");
    }
}
