//! OBJ files (tobj): reading, and meshes with the file's texture coordinates.

use std::collections::HashMap;
use std::path::Path;

use glam::{DVec2, DVec3};

use super::mesh::{degenerate2, Mesh, Vertex};
use super::SceneError;

/// The models of an OBJ file, triangulated (points and lines ignored); errors name the file.
pub(crate) fn read_obj(path: &Path) -> Result<Vec<tobj::Model>, SceneError> {
    let fail = |message: String| SceneError::file(path.display(), message);
    if !path.is_file() {
        return Err(fail("could not read OBJ: no such file".into()));
    }
    // `..Default::default()` covers the options of tobj's optional features.
    #[allow(clippy::needless_update)]
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let (models, _materials) =
        tobj::load_obj(path, &options).map_err(|e| fail(format!("could not load OBJ: {e}")))?;
    Ok(models)
}

/// Load an OBJ file: positions, texture coordinates (required) and normals (computed if
/// absent), with `pu`, `pv` per triangle from positions and uvs, averaged per vertex weighted
/// by triangle area.
pub(super) fn load_obj(path: &Path, rep: DVec2) -> Result<Mesh, SceneError> {
    let fail = |message: String| SceneError::file(path.display(), message);
    let models = read_obj(path)?;
    let mut mesh = Mesh::default();
    for model in &models {
        let m = &model.mesh;
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
                 needs them"
            )));
        }
        let has_normals = !m.normals.is_empty() && m.normal_indices.len() == m.indices.len();
        // Unique vertices per (position, uv, normal) index triple.
        let mut lookup: HashMap<(u32, u32, u32), u32> = HashMap::new();
        let mut pos_index: Vec<u32> = Vec::new(); // per new vertex: OBJ position index
        let base = mesh.vertices.len();
        let mut corners = Vec::with_capacity(m.indices.len());
        for (c, &pi) in m.indices.iter().enumerate() {
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
            corners.push(id);
        }
        for tri in corners.chunks_exact(3) {
            mesh.triangles.push([tri[0], tri[1], tri[2]]);
        }
        if !has_normals {
            // Area-weighted face normals summed per OBJ position, so that vertices split
            // only by a UV seam share one smooth normal.
            let mut acc: HashMap<u32, DVec3> = HashMap::new();
            for tri in corners.chunks_exact(3) {
                let [a, b, c] = [tri[0], tri[1], tri[2]].map(|k| mesh.vertices[k as usize].pos);
                let n = (b - a).cross(c - a); // |n| = 2 * area
                for &k in tri {
                    *acc.entry(pos_index[k as usize - base]).or_default() += n;
                }
            }
            for (k, v) in mesh.vertices[base..].iter_mut().enumerate() {
                v.normal = acc[&pos_index[k]].normalize_or_zero();
            }
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
        return Err(fail("expected at least one face, found none".into()));
    }
    Ok(mesh)
}
