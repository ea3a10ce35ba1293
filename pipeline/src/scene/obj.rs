//! OBJ files (tobj): reading, and meshes with the file's texture coordinates.

use std::collections::HashMap;
use std::path::Path;

use glam::{DVec2, DVec3};

use super::mesh::{degenerate2, degenerate3, Mesh, Vertex};
use super::SceneError;

/// An OBJ file read by tobj, with what tobj does not keep: the file line of every triangle
/// (after triangulation, in file order) for error messages.
pub(crate) struct ObjFile {
    pub models: Vec<tobj::Model>,
    /// The 1-based line of each triangle's face, in the order of the models' triangles;
    /// empty when it could not be matched to tobj's triangles.
    pub lines: Vec<usize>,
    /// Whether every face gives every corner a texture coordinate (`f a/t ...`); else the
    /// line of the first face that does not.
    pub missing_vt: Option<usize>,
}

impl ObjFile {
    /// "line N" of triangle `t` (in the models' order), or "face t" if lines are unknown.
    pub fn line(&self, t: usize) -> String {
        match self.lines.get(t) {
            Some(l) => format!("line {l}"),
            None => format!("face {t}"),
        }
    }
}

/// Check the numbers of the `v`, `vt` and `vn` lines and find each face's line. tobj reads
/// coordinates as f32 (its `use_f64` feature is off), so a finite value beyond the f32 range
/// (3.4e38) would become infinite: it is reported here, with its line, as out of range.
fn scan(text: &str) -> Result<(Vec<usize>, Option<usize>), String> {
    let mut lines = Vec::new();
    let mut missing_vt = None;
    for (i, line) in text.lines().enumerate() {
        let n = i + 1;
        let mut it = line.split_whitespace();
        let Some(key) = it.next() else { continue };
        match key {
            "v" | "vt" | "vn" => {
                let mut len2 = 0.0;
                for (k, tok) in it.enumerate() {
                    let x: f64 = tok
                        .parse()
                        .map_err(|_| format!("line {n}: {key}: {tok:?} is not a number"))?;
                    if !x.is_finite() {
                        return Err(format!(
                            "line {n}: {key}: expected a finite number, found {tok}"
                        ));
                    }
                    if x.abs() > f64::from(f32::MAX) {
                        return Err(format!(
                            "line {n}: {key}: {tok} is out of range: OBJ coordinates are read \
                             as f32, expected at most {:e} in magnitude",
                            f32::MAX
                        ));
                    }
                    if k < 3 {
                        len2 += x * x;
                    }
                }
                if key == "vn" && len2 == 0.0 {
                    return Err(format!(
                        "line {n}: vn: a normal of zero length: expected a non-zero normal"
                    ));
                }
            }
            "f" => {
                let corners: Vec<&str> = it.collect();
                if corners.len() >= 3 {
                    let has_vt = corners
                        .iter()
                        .all(|c| c.split('/').nth(1).is_some_and(|t| !t.is_empty()));
                    if !has_vt && missing_vt.is_none() {
                        missing_vt = Some(n);
                    }
                    lines.extend(std::iter::repeat_n(n, corners.len() - 2));
                }
            }
            _ => {}
        }
    }
    Ok((lines, missing_vt))
}

/// Read an OBJ file: a regular file of at most [`super::files::MAX_OBJ_BYTES`], triangulated
/// (points and lines ignored); errors name the file and, where known, the line.
pub(crate) fn read_obj(path: &Path) -> Result<ObjFile, SceneError> {
    let fail = |message: String| SceneError::file(path.display(), message);
    let bytes = super::files::read_bounded(path, super::files::MAX_OBJ_BYTES, "OBJ")?;
    // `..Default::default()` covers the options of tobj's optional features.
    #[allow(clippy::needless_update)]
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let (lines, missing_vt) = match std::str::from_utf8(&bytes) {
        Ok(text) => scan(text).map_err(|m| fail(format!("could not load OBJ: {m}")))?,
        Err(_) => (Vec::new(), None),
    };
    let mut reader = std::io::BufReader::new(bytes.as_slice());
    let (models, _materials) = tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| fail(format!("could not load OBJ: {e}")))?;
    let triangles: usize = models.iter().map(|m| m.mesh.indices.len() / 3).sum();
    let lines = if lines.len() == triangles {
        lines
    } else {
        Vec::new()
    };
    Ok(ObjFile {
        models,
        lines,
        missing_vt,
    })
}

/// The faces an OBJ mesh keeps (`docs/assets.md`, "Meshes from files"): a face of zero area
/// (its corners collinear or equal, [`degenerate3`]) is dropped, and of the faces on the same
/// three corner positions (equal coordinates, in either winding: exact duplicates and
/// back-to-back pairs) only the first in the file is kept. `corners` gives each triangle's
/// three positions in file order; returns whether each is kept.
pub(crate) fn kept_faces(corners: &[[DVec3; 3]]) -> Vec<bool> {
    let mut seen = std::collections::HashSet::new();
    corners
        .iter()
        .map(|&[a, b, c]| {
            if degenerate3(a, b, c) {
                return false;
            }
            let mut key = [a, b, c].map(|p| p.to_array().map(f64::to_bits));
            key.sort_unstable();
            seen.insert(key)
        })
        .collect()
}

/// Smooth vertex normals from faces: for each position the area-weighted sum of its faces'
/// normals, normalised. Where that sum vanishes (faces around the position cancel, e.g. a
/// fold), the sum of the faces' unit normals; where that vanishes too, the normal of the
/// first face that uses the position. `faces` are `(position indices, (b - a) x (c - a))`.
pub(crate) fn smooth_normals(positions: usize, faces: &[([usize; 3], DVec3)]) -> Vec<DVec3> {
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
        return out;
    }
    let mut unit = vec![DVec3::ZERO; positions];
    let mut first = vec![None; positions];
    for (tri, n) in faces {
        for &k in tri {
            unit[k] += n.normalize_or_zero();
            first[k].get_or_insert(n.normalize_or_zero());
        }
    }
    for k in bad {
        out[k] = if unit[k].length() > 1e-9 {
            unit[k].normalize()
        } else {
            first[k].unwrap_or(DVec3::ZERO)
        };
    }
    out
}

/// Load an OBJ file: positions, texture coordinates (required) and normals (computed if
/// absent, [`smooth_normals`]), with `pu`, `pv` per triangle from positions and uvs, averaged
/// per vertex weighted by triangle area. Faces are kept by [`kept_faces`]; errors name the
/// file's line.
pub(super) fn load_obj(path: &Path, rep: DVec2) -> Result<Mesh, SceneError> {
    let fail = |message: String| SceneError::file(path.display(), message);
    let file = read_obj(path)?;
    if let Some(line) = file.missing_vt {
        return Err(fail(format!(
            "line {line}: a face without texture coordinates (vt): expected `f v/vt ...` on \
             every face; bump mapping needs them (or use atlas: true)"
        )));
    }
    let models = &file.models;
    // the corner positions of every triangle, in file order, to choose the faces kept
    let mut corners_all = Vec::new();
    for model in models {
        let m = &model.mesh;
        for tri in m.indices.chunks_exact(3) {
            let p = |k: u32| {
                let k = k as usize * 3;
                m.positions.get(k..k + 3).map_or(DVec3::NAN, |c| {
                    DVec3::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2]))
                })
            };
            corners_all.push([p(tri[0]), p(tri[1]), p(tri[2])]);
        }
    }
    let kept = kept_faces(&corners_all);
    let mut mesh = Mesh::default();
    // the file triangle of each mesh triangle
    let mut source: Vec<usize> = Vec::new();
    let mut first_tri = 0usize;
    for model in models {
        let m = &model.mesh;
        let model_first = first_tri;
        first_tri += m.indices.len() / 3;
        if m.indices.is_empty() {
            continue;
        }
        let name = &model.name;
        let get3 = |data: &[f32], k: u32, what: &str| -> Result<DVec3, SceneError> {
            let k = k as usize * 3;
            match data.get(k..k + 3) {
                Some(c) => Ok(DVec3::new(
                    f64::from(c[0]),
                    f64::from(c[1]),
                    f64::from(c[2]),
                )),
                None => Err(fail(format!("object '{name}': {what} index out of range"))),
            }
        };
        if m.texcoords.is_empty() || m.texcoord_indices.len() != m.indices.len() {
            return Err(fail(format!(
                "object '{name}': expected texture coordinates (vt) on every face; bump mapping \
                 needs them (or use atlas: true)"
            )));
        }
        let has_normals = !m.normals.is_empty() && m.normal_indices.len() == m.indices.len();
        // Unique vertices per (position, uv, normal) index triple.
        let mut lookup: HashMap<(u32, u32, u32), u32> = HashMap::new();
        let mut pos_index: Vec<u32> = Vec::new(); // per new vertex: OBJ position index
        let base = mesh.vertices.len();
        let mut corners = Vec::with_capacity(m.indices.len());
        for (c, &pi) in m.indices.iter().enumerate() {
            if !kept[model_first + c / 3] {
                continue;
            }
            let ti = m.texcoord_indices[c];
            let ni = if has_normals {
                m.normal_indices[c]
            } else {
                u32::MAX
            };
            let id = *lookup.entry((pi, ti, ni)).or_insert_with(|| {
                pos_index.push(pi);
                (base + pos_index.len() - 1) as u32
            });
            if id as usize == mesh.vertices.len() {
                let pos = get3(&m.positions, pi, "position")?;
                let t = ti as usize * 2;
                let uv = match m.texcoords.get(t..t + 2) {
                    Some(c) => DVec2::new(f64::from(c[0]), f64::from(c[1])) * rep,
                    None => {
                        return Err(fail(format!(
                            "object '{name}': texcoord index out of range"
                        )))
                    }
                };
                let normal = if has_normals {
                    get3(&m.normals, ni, "normal")?.normalize_or_zero()
                } else {
                    DVec3::ZERO
                };
                mesh.vertices.push(Vertex {
                    pos,
                    normal,
                    uv,
                    pu: DVec3::ZERO,
                    pv: DVec3::ZERO,
                });
            }
            if c % 3 == 0 {
                source.push(model_first + c / 3);
            }
            corners.push(id);
        }
        for tri in corners.chunks_exact(3) {
            mesh.triangles.push([tri[0], tri[1], tri[2]]);
        }
        if !has_normals {
            // Area-weighted face normals summed per OBJ position, so that vertices split
            // only by a UV seam share one smooth normal.
            let faces: Vec<([usize; 3], DVec3)> = corners
                .chunks_exact(3)
                .map(|tri| {
                    let [a, b, c] = [tri[0], tri[1], tri[2]].map(|k| mesh.vertices[k as usize].pos);
                    let n = (b - a).cross(c - a); // |n| = 2 * area
                    (
                        [tri[0], tri[1], tri[2]].map(|k| pos_index[k as usize - base] as usize),
                        n,
                    )
                })
                .collect();
            let smooth = smooth_normals(m.positions.len() / 3, &faces);
            for (k, v) in mesh.vertices[base..].iter_mut().enumerate() {
                v.normal = smooth[pos_index[k] as usize];
            }
        }
    }
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let [a, b, c] = tri.map(|k| mesh.vertices[k as usize].uv);
        if degenerate2(a, b, c) {
            return Err(fail(format!(
                "{}: a face with degenerate texture coordinates (zero uv area), uv {a}, {b}, \
                 {c}: expected three distinct, non-collinear vt",
                file.line(source[t])
            )));
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
        if degenerate2(a.uv, b.uv, c.uv) || det == 0.0 {
            continue; // reported by validate
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
    if mesh.triangles.is_empty() {
        return Err(fail(if corners_all.is_empty() {
            "expected at least one face, found none".into()
        } else {
            format!(
                "expected at least one face of non-zero area, found none ({} faces, all of \
                 zero area or duplicates)",
                corners_all.len()
            )
        }));
    }
    Ok(mesh)
}
