//! A generated uv atlas for OBJ meshes without texture coordinates
//! ([`super::MeshSpec::Obj`] with `atlas: true`), e.g. the Stanford bunny of Tarini et al.
//! 1999 (Figs. 1, 4, 8, 9), whose normal map needs a one-to-one uv layout.
//!
//! # Layout
//!
//! * The file's texture coordinates are ignored (they may be absent). Triangles are taken in
//!   file order and paired: triangles `2k` and `2k + 1` share cell `k` of an `n x n` grid over
//!   [0, 1]², `n = ceil(sqrt(ceil(T / 2)))`, cell `k` at column `k mod n`, row `k div n` (row 0
//!   at `v = 0`).
//! * In a cell of side `c = 1/n`, with the gutter `g` ([`GUTTER`]), `m = g/2` and
//!   `d = g/√2`, triangle `2k` is the lower-left right triangle `(m, m)`, `(c - m - d, m)`,
//!   `(m, c - m - d)` and triangle `2k + 1` the upper-right one `(c - m, c - m)`,
//!   `(m + d, c - m)`, `(c - m, m + d)` (cell-relative; both counter-clockwise in uv, so
//!   `Pu × Pv` has the file's winding). The two hypotenuses are `g` apart, and triangles of
//!   neighbouring cells (also across the wrap at 0 / 1) are at least `2m = g` apart: **every
//!   two triangles are at least [`GUTTER_TEXELS`] = 2 texels apart at [`ATLAS_TEXELS`] = 1024
//!   texels (1 texel at 512, half a texel at 256)**, so nearest sampling anywhere in a triangle
//!   reads a texel whose centre is nearer to that triangle than to any other. Every leg is at
//!   least `g` long; meshes needing more than [`max_cells`]² cells are rejected.
//! * Every triangle gets its own three vertices. Normals are smooth across charts: the file's
//!   normals if every face has them, otherwise the area-weighted sum of the face normals
//!   around each *position* (computed before the split, so the split does not show).
//! * `Pu`, `Pv` come from the triangle's positions and uvs (`[e1 e2] = [Pu Pv] [Δuv1 Δuv2]`),
//!   as for OBJ files with texture coordinates; `uv_repeat` scales the uvs (keep it at
//!   `(1, 1)` for a normal map baked in uv space: larger values make the charts overlap).

use std::f64::consts::FRAC_1_SQRT_2;

use glam::{DVec2, DVec3};

use super::mesh::{Mesh, Vertex};

/// The texture resolution the gutter is stated at.
pub const ATLAS_TEXELS: u32 = 1024;
/// The smallest gap between two triangles, in texels at [`ATLAS_TEXELS`].
pub const GUTTER_TEXELS: f64 = 2.0;
/// The smallest gap between two triangles, in uv units.
pub const GUTTER: f64 = GUTTER_TEXELS / ATLAS_TEXELS as f64;

/// The largest grid side: cells of side `c` with legs `c - g (1 + 1/√2)` of at least `g`
/// (189 at 1024 texels and a 2-texel gutter: 71 442 triangles).
pub fn max_cells() -> u64 {
    (1.0 / (GUTTER * (2.0 + FRAC_1_SQRT_2))).floor() as u64
}

/// The grid side `n = ceil(sqrt(ceil(triangles / 2)))` (at least 1).
pub fn grid_side(triangles: usize) -> u64 {
    let cells = (triangles as u64).div_ceil(2).max(1);
    let mut n = (cells as f64).sqrt() as u64;
    while n * n < cells {
        n += 1;
    }
    while n > 1 && (n - 1) * (n - 1) >= cells {
        n -= 1;
    }
    n
}

/// The uv corners of triangle `t` in an `n x n` grid (before `uv_repeat`), counter-clockwise.
pub fn chart(t: usize, n: u64) -> [DVec2; 3] {
    let k = (t / 2) as u64;
    let c = 1.0 / n as f64;
    let origin = DVec2::new((k % n) as f64, (k / n) as f64) * c;
    let (m, d) = (0.5 * GUTTER, GUTTER * FRAC_1_SQRT_2);
    let corners = if t.is_multiple_of(2) {
        [
            DVec2::new(m, m),
            DVec2::new(c - m - d, m),
            DVec2::new(m, c - m - d),
        ]
    } else {
        [
            DVec2::new(c - m, c - m),
            DVec2::new(m + d, c - m),
            DVec2::new(c - m, m + d),
        ]
    };
    corners.map(|p| origin + p)
}

/// Build the atlased mesh: `triangles` index `positions`; `corner_normals`, if given, has one
/// normal per triangle corner (`3 t + i`). Errors are messages (the caller names the file).
pub fn atlas_mesh(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    corner_normals: Option<&[DVec3]>,
    rep: DVec2,
) -> Result<Mesh, String> {
    if triangles.is_empty() {
        return Err("expected at least one face, found none".into());
    }
    let n = grid_side(triangles.len());
    if n > max_cells() {
        return Err(format!(
            "atlas: {} triangles need a {n} x {n} grid; at most {m} x {m} cells ({} triangles) \
             fit with a {GUTTER_TEXELS}-texel gutter at {ATLAS_TEXELS} texels",
            triangles.len(),
            2 * max_cells() * max_cells(),
            m = max_cells(),
        ));
    }
    for (t, tri) in triangles.iter().enumerate() {
        if let Some(&k) = tri.iter().find(|&&k| k as usize >= positions.len()) {
            return Err(format!(
                "face {t}: position index {k} out of range ({} positions)",
                positions.len()
            ));
        }
    }
    if let Some(normals) = corner_normals {
        if normals.len() != 3 * triangles.len() {
            return Err(format!(
                "expected {} corner normals, found {}",
                3 * triangles.len(),
                normals.len()
            ));
        }
    }
    // Smooth normals per position, before the split.
    let smooth = match corner_normals {
        Some(_) => Vec::new(),
        None => {
            let faces: Vec<([usize; 3], DVec3)> = triangles
                .iter()
                .map(|tri| {
                    let [a, b, c] = tri.map(|k| positions[k as usize]);
                    (tri.map(|k| k as usize), (b - a).cross(c - a)) // |face| = 2 * area
                })
                .collect();
            super::obj::smooth_normals(positions.len(), &faces)
        }
    };
    let mut mesh = Mesh {
        vertices: Vec::with_capacity(3 * triangles.len()),
        triangles: Vec::with_capacity(triangles.len()),
    };
    for (t, tri) in triangles.iter().enumerate() {
        let pos = tri.map(|k| positions[k as usize]);
        let uv = chart(t, n).map(|p| p * rep);
        let (e1, e2) = (pos[1] - pos[0], pos[2] - pos[0]);
        let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
        let det = d1.perp_dot(d2);
        let pu = (e1 * d2.y - e2 * d1.y) / det;
        let pv = (e2 * d1.x - e1 * d2.x) / det;
        let base = mesh.vertices.len() as u32;
        for i in 0..3 {
            // smooth normals are unit already
            let normal = match corner_normals {
                Some(normals) => normals[3 * t + i].normalize_or_zero(),
                None => smooth[tri[i] as usize],
            };
            mesh.vertices.push(Vertex {
                pos: pos[i],
                normal,
                uv: uv[i],
                pu,
                pv,
            });
        }
        mesh.triangles.push([base, base + 1, base + 2]);
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;
    use std::path::Path;

    use super::*;
    use crate::scene::bake::{bake, BakeSpace};
    use crate::scene::perturb::Perturbation;
    use crate::scene::{BumpSpec, MeshSpec, SceneError};

    /// Distance from `p` to the segment `ab`.
    fn point_segment(p: DVec2, a: DVec2, b: DVec2) -> f64 {
        let ab = b - a;
        let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
        (a + ab * t - p).length()
    }

    /// Whether `p` is inside the counter-clockwise triangle (boundary included).
    fn inside(p: DVec2, [a, b, c]: [DVec2; 3]) -> bool {
        (b - a).perp_dot(p - a) >= 0.0
            && (c - b).perp_dot(p - b) >= 0.0
            && (a - c).perp_dot(p - c) >= 0.0
    }

    /// Distance between two disjoint triangles: the smallest vertex-to-edge distance.
    fn triangle_distance(s: [DVec2; 3], t: [DVec2; 3]) -> f64 {
        let mut best = f64::INFINITY;
        for (x, y) in [(s, t), (t, s)] {
            for p in x {
                for i in 0..3 {
                    best = best.min(point_segment(p, y[i], y[(i + 1) % 3]));
                }
            }
        }
        best
    }

    #[test]
    fn atlas_grid_side() {
        assert_eq!(grid_side(0), 1);
        assert_eq!(grid_side(1), 1);
        assert_eq!(grid_side(2), 1);
        assert_eq!(grid_side(3), 2);
        assert_eq!(grid_side(8), 2);
        assert_eq!(grid_side(9), 3);
        assert_eq!(grid_side(3674), 43);
        assert_eq!(max_cells(), 189);
    }

    #[test]
    fn atlas_charts_inside_disjoint_with_gutters() {
        for count in [1usize, 2, 7, 18, 50] {
            let n = grid_side(count);
            let charts: Vec<[DVec2; 3]> = (0..count).map(|t| chart(t, n)).collect();
            for (t, c) in charts.iter().enumerate() {
                for p in c {
                    assert!(
                        p.cmpge(DVec2::ZERO).all() && p.cmple(DVec2::ONE).all(),
                        "{t}"
                    );
                }
                // Counter-clockwise, legs of at least one gutter.
                assert!((c[1] - c[0]).perp_dot(c[2] - c[0]) > 0.0);
                assert!((c[1] - c[0]).length() >= GUTTER && (c[2] - c[0]).length() >= GUTTER);
            }
            // Gutters: every two triangles at least GUTTER apart, also across the wrap.
            for s in 0..count {
                for t in 0..count {
                    for du in [-1.0, 0.0, 1.0] {
                        for dv in [-1.0, 0.0, 1.0] {
                            if s == t && du == 0.0 && dv == 0.0 {
                                continue;
                            }
                            let shifted = charts[t].map(|p| p + DVec2::new(du, dv));
                            let d = triangle_distance(charts[s], shifted);
                            assert!(
                                d >= GUTTER * (1.0 - 1e-9),
                                "{count}: {s} and {t} ({du}, {dv}) {d} apart"
                            );
                        }
                    }
                }
            }
            // No overlap, by sampling [0, 1]² on a 512 x 512 grid (and the vertices).
            let samples = 512;
            for j in 0..samples {
                for i in 0..samples {
                    let p = DVec2::new(i as f64 + 0.5, j as f64 + 0.5) / samples as f64;
                    let hits = charts.iter().filter(|c| inside(p, **c)).count();
                    assert!(hits <= 1, "{count}: {p} in {hits} triangles");
                }
            }
            for (t, c) in charts.iter().enumerate() {
                for p in c {
                    let hits = charts.iter().filter(|d| inside(*p, **d)).count();
                    assert_eq!(hits, 1, "{count}: corner of {t}");
                }
            }
            // The gutter in texels at the stated resolution.
            assert!(GUTTER * f64::from(ATLAS_TEXELS) >= 1.0);
        }
    }

    /// A closed octahedron without texture coordinates, wound outward.
    const OCTAHEDRON: &str = "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n\
                              f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\n\
                              f 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";

    /// A fresh, empty directory (removed when dropped).
    fn temp_dir() -> crate::scratch::Scratch {
        crate::scratch::Scratch::dir()
    }

    #[test]
    fn atlas_obj_smooth_normals_and_frames() {
        let dir = temp_dir();
        std::fs::write(dir.join("octa.obj"), OCTAHEDRON).unwrap();
        let spec = |atlas| MeshSpec::Obj {
            path: "octa.obj".into(),
            uv_repeat: [1.0, 1.0],
            atlas,
        };
        let m = spec(true).build(&dir).unwrap();
        assert_eq!((m.vertices.len(), m.triangles.len()), (24, 8));
        for v in &m.vertices {
            // The smooth normal of a vertex of the octahedron is its position.
            assert!((v.normal - v.pos).length() < 1e-12, "{v:?}");
            assert!(v.pu.cross(v.pv).dot(v.normal) > 0.0, "{v:?}");
            assert!(v.uv.cmpgt(DVec2::ZERO).all() && v.uv.cmplt(DVec2::ONE).all());
        }
        // Pu, Pv reproduce the triangle's edges from its uv edges.
        for tri in &m.triangles {
            let [a, b, c] = tri.map(|k| m.vertices[k as usize]);
            for (p, q) in [(a, b), (a, c)] {
                let d = q.uv - p.uv;
                assert!((p.pu * d.x + p.pv * d.y - (q.pos - p.pos)).length() < 1e-12);
            }
        }
        // Without atlas the file is rejected (no texture coordinates).
        assert!(matches!(
            spec(false).build(&dir),
            Err(SceneError::File { .. })
        ));
        // File normals are kept when every face has them.
        let with_vn = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 3\nvt 0.5 0.5\nf 1/1/1 2/1/1 3/1/1\n";
        std::fs::write(dir.join("vn.obj"), with_vn).unwrap();
        let m = MeshSpec::Obj {
            path: "vn.obj".into(),
            uv_repeat: [1.0, 1.0],
            atlas: true,
        }
        .build(&dir)
        .unwrap();
        assert!(m.vertices.iter().all(|v| v.normal == DVec3::Z));
        // Errors name the file; no panics.
        for (name, text) in [
            ("empty.obj", "v 0 0 0\n"),
            ("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"),
            ("bad.obj", "v 0 0 0\nf 1 2 3\n"),
        ] {
            std::fs::write(dir.join(name), text).unwrap();
            let spec = MeshSpec::Obj {
                path: name.into(),
                uv_repeat: [1.0, 1.0],
                atlas: true,
            };
            match spec.build(&dir) {
                Err(SceneError::File { path, .. }) => assert!(path.ends_with(name)),
                other => panic!("{name}: expected a file error, got {other:?}"),
            }
        }
        assert!(atlas_mesh(&[DVec3::ZERO], &[[0, 0, 1]], None, DVec2::ONE).is_err());
        let too_many = vec![[0, 1, 2]; 2 * 190 * 190];
        let pos = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let err = atlas_mesh(&pos, &too_many, None, DVec2::ONE).unwrap_err();
        assert!(err.contains("at most 189 x 189"), "{err}");
    }

    fn bunny() -> Mesh {
        let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("../configs/assets");
        MeshSpec::Obj {
            path: "bunny.obj".into(),
            uv_repeat: [1.0, 1.0],
            atlas: true,
        }
        .build(&assets)
        .unwrap()
    }

    #[test]
    fn atlas_bunny_counts() {
        let m = bunny();
        // 3674 triangles of the npm `bunny` (1839 positions), three vertices each.
        assert_eq!(m.triangles.len(), 3674);
        assert_eq!(m.vertices.len(), 3 * 3674);
        m.validate("mesh.Obj").unwrap();
        let positions: std::collections::BTreeSet<[u64; 3]> = m
            .vertices
            .iter()
            .map(|v| v.pos.to_array().map(f64::to_bits))
            .collect();
        assert_eq!(positions.len(), 1839);
        // Smooth: every copy of a position has the same normal.
        let mut normal_of: HashMap<[u64; 3], DVec3> = HashMap::new();
        for v in &m.vertices {
            let n = *normal_of
                .entry(v.pos.to_array().map(f64::to_bits))
                .or_insert(v.normal);
            assert_eq!(n, v.normal);
        }
        let (lo, hi) = m.bounds();
        assert!(lo.y > -0.01 && hi.y > 9.6 && hi.y < 9.7, "{lo} {hi}");
    }

    /// Bake the bunny in object space with one distinct normal per triangle (a flat bump
    /// keeps it): nearest sampling at every triangle's corners and along its edges must read
    /// that triangle's own normal, never an unfilled texel or a neighbouring chart's.
    #[test]
    fn atlas_bunny_bake_fills_chart_borders() {
        let mut m = bunny();
        let count = m.triangles.len();
        // Fibonacci-sphere directions, one per triangle.
        let id = |t: usize| {
            let z = 1.0 - 2.0 * (t as f64 + 0.5) / count as f64;
            let phi = t as f64 * std::f64::consts::PI * (3.0 - 5f64.sqrt());
            let r = (1.0 - z * z).sqrt();
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        };
        for (t, tri) in m.triangles.iter().enumerate() {
            for &k in tri {
                m.vertices[k as usize].normal = id(t);
            }
        }
        let flat = BumpSpec::Flat.build(Path::new(".")).unwrap();
        let size = ATLAS_TEXELS;
        let out = bake(&m, &flat, size, BakeSpace::Object, Perturbation::Blinn);
        assert_eq!((out.overlaps, out.skipped), (0, 0));
        assert!(out
            .map
            .texels
            .iter()
            .all(|n| (n.length() - 1.0).abs() < 1e-9));
        let sz = f64::from(size);
        let mut bad = Vec::new();
        for (t, tri) in m.triangles.iter().enumerate() {
            let uv = tri.map(|k| m.vertices[k as usize].uv);
            let centroid = (uv[0] + uv[1] + uv[2]) / 3.0;
            for i in 0..3 {
                let (a, b) = (uv[i], uv[(i + 1) % 3]);
                for s in 0..=16 {
                    let p = a + (b - a) * (f64::from(s) / 16.0);
                    // Just inside the triangle.
                    let p = p + (centroid - p) * 1e-9;
                    let texel = (p * sz).floor();
                    let k = texel.y as usize * size as usize + texel.x as usize;
                    if (out.map.texels[k] - id(t)).length() > 1e-9 {
                        bad.push((t, p, out.covered[k]));
                    }
                }
            }
        }
        assert!(
            bad.is_empty(),
            "{} misses, e.g. {:?}",
            bad.len(),
            &bad[..bad.len().min(5)]
        );
    }
}
