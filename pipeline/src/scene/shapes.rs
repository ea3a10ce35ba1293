//! The config's meshes (`MeshSpec`): the quad, sphere, torus and cylinder, Newell's teapot
//! from its Bézier patches, surfaces of revolution (`super::lathe`) and OBJ and PLY files
//! (`super::obj`, `super::ply`, built by `super::mesh`'s rule for scan defects, or laid out by
//! `super::atlas` for files without texture coordinates). Conventions
//! (y up, `u` around the axis, `Pu × Pv` outward) are `super::mesh`'s.

use std::f64::consts::{PI, TAU};
use std::path::Path;

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use super::mesh::{Defects, FileMesh, Mesh, Vertex};
use super::{check_count, SceneError};

/// A mesh as written in a scene config. Every `uv_repeat` is `[u, v]`, each finite and > 0:
/// how many times the period-1 bump map repeats across the surface in `u` and in `v`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum MeshSpec {
    /// A square in the z = 0 plane centred at the origin, normal +z, `u` along +x, `v` along
    /// +y; two triangles.
    Quad {
        /// Edge length (> 0).
        size: f64,
        uv_repeat: [f64; 2],
        /// Grid cells per side, 1..=2048 (default 1: two triangles). A finer grid gives
        /// per-triangle quantities (e.g. the `Lod` attribute) somewhere to vary.
        #[serde(default = "one_cell")]
        subdivisions: u32,
    },
    /// A sphere about the y axis. The poles get one vertex per slice (at the slice's centre
    /// `u`) and one triangle per pole quad.
    Sphere {
        /// Radius (> 0).
        radius: f64,
        /// Segments around the y axis (`u`), 3..=2048.
        slices: u32,
        /// Segments from the south (-y) to the north (+y) pole (`v`), 2..=2048.
        stacks: u32,
        uv_repeat: [f64; 2],
    },
    /// A ring torus about the y axis.
    Torus {
        /// Distance from the axis to the tube's centre circle (> `minor`).
        major: f64,
        /// Tube radius (> 0).
        minor: f64,
        /// Segments around the y axis (`u`), 3..=2048.
        slices: u32,
        /// Segments around the tube (`v`, starting on the outer equator and going up first),
        /// 3..=2048.
        rings: u32,
        uv_repeat: [f64; 2],
    },
    /// An open tube (no caps) about the y axis, from y = -height/2 to +height/2.
    Cylinder {
        /// Radius (> 0).
        radius: f64,
        /// Length along y (> 0).
        height: f64,
        /// Segments around the axis (`u`), 3..=2048.
        slices: u32,
        /// Segments along the axis (`v`), 1..=2048.
        stacks: u32,
        uv_repeat: [f64; 2],
    },
    /// Newell's teapot: 32 bicubic Bézier patches, each evaluated on a
    /// `subdivisions x subdivisions` grid with its own `(u, v)` in [0, 1]² (times
    /// `uv_repeat`).
    Teapot {
        /// Grid cells per patch side, 1..=64.
        subdivisions: u32,
        uv_repeat: [f64; 2],
    },
    /// A Wavefront OBJ file (all its objects merged). It must have texture coordinates on
    /// every face unless `atlas`; missing normals are computed (area-weighted, smooth across
    /// UV seams). Scan defects load by the rule of `docs/assets.md` ("Meshes from files").
    Obj {
        /// File path, relative to the scene's directory.
        path: String,
        uv_repeat: [f64; 2],
        /// Ignore the file's texture coordinates (they may be absent) and generate a grid
        /// atlas: two triangles per square cell with gutters, smooth normals
        /// (`super::atlas`). Default false.
        #[serde(default)]
        atlas: bool,
    },
    /// A PLY file (`super::ply`: ASCII or binary, either byte order), e.g. a scanned mesh. As
    /// `Obj`: texture coordinates (vertex `u v`, `s t`, ... or a face `texcoord` list) are
    /// needed unless `atlas` (scans usually have none: use `atlas: true`); missing normals
    /// are computed; scan defects load by the rule of `docs/assets.md`.
    Ply {
        /// File path, relative to the scene's directory.
        path: String,
        uv_repeat: [f64; 2],
        /// Ignore the file's texture coordinates and generate a grid atlas (as for `Obj`).
        /// Default false.
        #[serde(default)]
        atlas: bool,
    },
    /// A normal-mapped simplified mesh baked from a detailed OBJ or PLY mesh (Wang et al.;
    /// `crate::wang`): the file simplified to `faces` faces, each face a patch of a
    /// `map_size` map, the map baked from `views` views of the detailed mesh. The mesh has
    /// one vertex per face corner with the face's normal; `bump: Baked` shades it with the
    /// baked map in face space (any other bump map is allowed too).
    Baked {
        /// File path (`.obj` or `.ply`), relative to the scene's directory.
        path: String,
        /// Target face count, 4 to the file's face count.
        faces: usize,
        /// Map side in texels: a power of two, 16 to 4096. Default 1024 (the paper's).
        #[serde(default = "default_bake_map")]
        map_size: u32,
        /// Border texels of each patch, 0 to 2. Default 1.
        #[serde(default = "default_bake_widen")]
        widen: u32,
        /// Views, 0 (the initialisation alone: the simplified mesh's interpolated normals)
        /// to 64. Default 12 (the icosahedron's vertices).
        #[serde(default = "default_bake_views")]
        views: usize,
        /// Side of each view's image in pixels, 16 to 4096. Default 1024.
        #[serde(default = "default_bake_map")]
        view_size: u32,
        /// Largest depth difference accepted, as a fraction of the detailed mesh's
        /// bounding-sphere radius, above 0 and at most 1. Default 0.03.
        #[serde(default = "default_bake_threshold")]
        threshold: f64,
        /// `Item` (exact normals from the triangle id, default) or `Color8` (normals as
        /// 8-bit colours, the paper's first method).
        #[serde(default = "default_bake_buffer")]
        buffer: crate::wang::bake::Buffer,
        /// Two faces that share an edge share a square (the paper's packing; default true).
        /// False: one square per face, so that bilinear filtering near an edge never mixes
        /// the two faces' frames (see docs/studies/normal-map-baking.md).
        #[serde(default = "default_bake_pairs")]
        pairs: bool,
        /// `Some((size, bits))`: measure the bake against the detailed mesh (Wang et al. §5:
        /// 30 views; the report's `bake.evaluation`, `crate::wang::scene::Evaluate`). Default
        /// `None`: not measured.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        evaluate: Option<crate::wang::scene::Evaluate>,
    },
    /// A surface of revolution about the y axis (no caps): the smooth monotone cubic `r(y)`
    /// through `profile`, `u` around the axis, `v` along the profile's arc length
    /// (`super::lathe`).
    Lathe {
        /// Control points `(radius, y)`: at least 2, y strictly increasing, radius finite and
        /// > 0 (0 allowed at the first and last point: a pole).
        profile: Vec<[f64; 2]>,
        /// Segments around the y axis (`u`), 3..=2048.
        slices: u32,
        /// Rings along the profile (`v`), 1..=2048 (2..=2048 with both ends on the axis).
        stacks: u32,
        uv_repeat: [f64; 2],
    },
    /// A strip folded along its middle (the y axis) into a ridge: two flat panels, each
    /// `size` across and `2 size` along, whose normals differ by `angle_deg` (the dihedral angle between the
    /// triangles that meet at the crease, 0 to 170; 0 is a flat strip), `columns` cells per
    /// panel across and `2 columns` along. The crease vertices take the mean normal and
    /// tangent, so shading is smooth across it: the scene of the edge-discontinuity study
    /// (Ernst et al. §3.2; `docs/studies/perturbation-engines.md`). `u` runs across the
    /// crease, `v` along it.
    Fold {
        angle_deg: f64,
        /// Edge length of each panel (> 0).
        size: f64,
        /// Cells across each panel, 1..=2048.
        columns: u32,
        uv_repeat: [f64; 2],
    },
}

fn default_bake_map() -> u32 {
    1024
}
fn default_bake_widen() -> u32 {
    1
}
fn default_bake_views() -> usize {
    12
}
fn default_bake_threshold() -> f64 {
    0.03
}
fn default_bake_pairs() -> bool {
    true
}
fn default_bake_buffer() -> crate::wang::bake::Buffer {
    crate::wang::bake::Buffer::Item
}

/// Largest segment count accepted for parametric meshes.
const MAX_SEGMENTS: u32 = 2048;

fn check_positive(field: String, x: f64) -> Result<(), SceneError> {
    if x.is_finite() && x > 0.0 {
        Ok(())
    } else {
        Err(SceneError::invalid(
            field,
            format!("expected a finite value > 0, found {x}"),
        ))
    }
}

fn check_repeat(variant: &str, r: [f64; 2]) -> Result<DVec2, SceneError> {
    for (i, x) in r.iter().enumerate() {
        check_positive(format!("mesh.{variant}.uv_repeat[{i}]"), *x)?;
    }
    Ok(DVec2::from(r))
}

impl MeshSpec {
    /// Check the parameters and build the mesh; the result passes [`Mesh::validate`].
    /// Parameter errors name `mesh.<Variant>.<field>`; problems of OBJ and PLY files are file
    /// errors naming the path (`base_dir` joined with `path`) and the line or element.
    pub fn build(&self, base_dir: &Path) -> Result<Mesh, SceneError> {
        Ok(self.build_with_map(base_dir)?.0)
    }

    /// [`MeshSpec::build`], and for [`MeshSpec::Baked`] the baked face-space map and what
    /// the bake did.
    pub fn build_with_map(
        &self,
        base_dir: &Path,
    ) -> Result<
        (
            Mesh,
            Option<(super::NormalMap, crate::wang::scene::BakeStats)>,
        ),
        SceneError,
    > {
        let (mesh, variant) = match *self {
            MeshSpec::Baked {
                ref path,
                faces,
                map_size,
                widen,
                views,
                view_size,
                threshold,
                buffer,
                pairs,
                evaluate,
            } => {
                let spec = crate::wang::scene::BakeSpec {
                    path: path.clone(),
                    faces,
                    map_size,
                    widen,
                    views,
                    view_size,
                    threshold,
                    buffer,
                    pairs,
                    evaluate,
                };
                let (mesh, map, stats) = crate::wang::scene::build(&spec, base_dir)?;
                mesh.validate("mesh.Baked")?;
                return Ok((mesh, Some((map, stats))));
            }
            MeshSpec::Quad {
                size,
                uv_repeat,
                subdivisions,
            } => {
                check_positive("mesh.Quad.size".into(), size)?;
                check_count("mesh.Quad.subdivisions".into(), subdivisions, 1, 2048)?;
                let rep = check_repeat("Quad", uv_repeat)?;
                (quad(size, subdivisions, rep), "Quad")
            }
            MeshSpec::Sphere {
                radius,
                slices,
                stacks,
                uv_repeat,
            } => {
                check_positive("mesh.Sphere.radius".into(), radius)?;
                check_count("mesh.Sphere.slices".into(), slices, 3, MAX_SEGMENTS)?;
                check_count("mesh.Sphere.stacks".into(), stacks, 2, MAX_SEGMENTS)?;
                let rep = check_repeat("Sphere", uv_repeat)?;
                (sphere(radius, slices, stacks, rep), "Sphere")
            }
            MeshSpec::Torus {
                major,
                minor,
                slices,
                rings,
                uv_repeat,
            } => {
                check_positive("mesh.Torus.minor".into(), minor)?;
                check_positive("mesh.Torus.major".into(), major)?;
                if major <= minor {
                    return Err(SceneError::invalid(
                        "mesh.Torus.major",
                        format!("expected major > minor ({minor}) for a ring torus, found {major}"),
                    ));
                }
                check_count("mesh.Torus.slices".into(), slices, 3, MAX_SEGMENTS)?;
                check_count("mesh.Torus.rings".into(), rings, 3, MAX_SEGMENTS)?;
                let rep = check_repeat("Torus", uv_repeat)?;
                (torus(major, minor, slices, rings, rep), "Torus")
            }
            MeshSpec::Cylinder {
                radius,
                height,
                slices,
                stacks,
                uv_repeat,
            } => {
                check_positive("mesh.Cylinder.radius".into(), radius)?;
                check_positive("mesh.Cylinder.height".into(), height)?;
                check_count("mesh.Cylinder.slices".into(), slices, 3, MAX_SEGMENTS)?;
                check_count("mesh.Cylinder.stacks".into(), stacks, 1, MAX_SEGMENTS)?;
                let rep = check_repeat("Cylinder", uv_repeat)?;
                (cylinder(radius, height, slices, stacks, rep), "Cylinder")
            }
            MeshSpec::Fold {
                angle_deg,
                size,
                columns,
                uv_repeat,
            } => {
                if !(0.0..=170.0).contains(&angle_deg) {
                    return Err(SceneError::invalid(
                        "mesh.Fold.angle_deg",
                        format!("expected 0 to 170 degrees, found {angle_deg}"),
                    ));
                }
                check_positive("mesh.Fold.size".into(), size)?;
                check_count("mesh.Fold.columns".into(), columns, 1, MAX_SEGMENTS / 2)?;
                let rep = check_repeat("Fold", uv_repeat)?;
                (fold(angle_deg, size, columns, rep), "Fold")
            }
            MeshSpec::Teapot {
                subdivisions,
                uv_repeat,
            } => {
                check_count("mesh.Teapot.subdivisions".into(), subdivisions, 1, 64)?;
                let rep = check_repeat("Teapot", uv_repeat)?;
                (teapot(subdivisions, rep), "Teapot")
            }
            MeshSpec::Lathe {
                ref profile,
                slices,
                stacks,
                uv_repeat,
            } => {
                let rep = check_repeat("Lathe", uv_repeat)?;
                (super::lathe::lathe(profile, slices, stacks, rep)?, "Lathe")
            }
            MeshSpec::Obj {
                ref path,
                uv_repeat,
                atlas,
            } => {
                return Ok((
                    build_file(FileKind::Obj, base_dir, path, uv_repeat, atlas)?,
                    None,
                ))
            }
            MeshSpec::Ply {
                ref path,
                uv_repeat,
                atlas,
            } => {
                return Ok((
                    build_file(FileKind::Ply, base_dir, path, uv_repeat, atlas)?,
                    None,
                ))
            }
        };
        mesh.validate(&format!("mesh.{variant}"))?;
        Ok((mesh, None))
    }
}

/// The format of a mesh file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileKind {
    Obj,
    Ply,
}

/// [`MeshSpec::Obj`] and [`MeshSpec::Ply`]: [`load_file`], then [`Mesh::validate`], whose
/// errors become file errors too.
fn build_file(
    kind: FileKind,
    base_dir: &Path,
    path: &str,
    uv_repeat: [f64; 2],
    atlas: bool,
) -> Result<Mesh, SceneError> {
    let variant = match kind {
        FileKind::Obj => "Obj",
        FileKind::Ply => "Ply",
    };
    let rep = check_repeat(variant, uv_repeat)?;
    let full = base_dir.join(path);
    let (mesh, _) = load_file(kind, &full, rep, atlas)?;
    mesh.validate(&format!("mesh.{variant}"))
        .map_err(|e| match e {
            SceneError::Invalid { message, .. } => SceneError::file(full.display(), message),
            other => other,
        })?;
    Ok(mesh)
}

/// Read a mesh file (`super::obj` or `super::ply`) and build it by the rule for scan defects
/// (`docs/assets.md`, "Meshes from files"): with the file's texture coordinates times `rep`
/// ([`FileMesh::to_mesh`]), or laid out in a generated atlas (`super::atlas`) when `atlas`.
/// Returns the mesh (not yet [`Mesh::validate`]d) and what the rule did; errors are file
/// errors naming the path and the line (or, in binary PLY files, the element).
pub fn load_file(
    kind: FileKind,
    path: &Path,
    rep: DVec2,
    atlas: bool,
) -> Result<(Mesh, Defects), SceneError> {
    let file: FileMesh = match kind {
        FileKind::Obj => super::obj::read(path)?,
        FileKind::Ply => super::ply::read(path)?,
    };
    let fail = |message: String| SceneError::file(path.display(), message);
    if !atlas {
        return file.to_mesh(rep).map_err(fail);
    }
    let mut kept = file.keep().map_err(fail)?;
    let normals = file.corner_normals(&mut kept);
    let triangles: Vec<[u32; 3]> = kept.triangles.iter().map(|&t| file.triangles[t]).collect();
    let mesh = super::atlas::atlas_mesh(&file.positions, &triangles, normals.as_deref(), rep)
        .map_err(fail)?;
    Ok((mesh, kept.defects))
}

/// A `nu x nv` grid of quads over `(s, t)` in [0, 1]², two triangles per quad.
/// `f(s, t)` gives `(P, N, ∂P/∂s, ∂P/∂t)`; uv = `(s, t) * rep`, so `pu = ∂P/∂s / rep.x`.
fn grid(
    nu: u32,
    nv: u32,
    rep: DVec2,
    f: impl Fn(f64, f64) -> (DVec3, DVec3, DVec3, DVec3),
) -> Mesh {
    let mut mesh = Mesh::default();
    for j in 0..=nv {
        let t = f64::from(j) / f64::from(nv);
        for i in 0..=nu {
            let s = f64::from(i) / f64::from(nu);
            let (pos, normal, ps, pt) = f(s, t);
            mesh.vertices.push(Vertex {
                pos,
                normal: normal.normalize(),
                uv: DVec2::new(s, t) * rep,
                pu: ps / rep.x,
                pv: pt / rep.y,
            });
        }
    }
    let row = nu + 1;
    for j in 0..nv {
        for i in 0..nu {
            let a = j * row + i;
            let (b, c, d) = (a + 1, a + row + 1, a + row);
            mesh.triangles.push([a, b, c]);
            mesh.triangles.push([a, c, d]);
        }
    }
    mesh
}

/// The folded strip of [`MeshSpec::Fold`]: `P = (a cos h, t, -|a| sin h) size` for `a` in
/// [-1, 1] across, `t` in [-1, 1] along, `h` half the angle.
fn fold(angle_deg: f64, size: f64, columns: u32, rep: DVec2) -> Mesh {
    let (sh, ch) = (angle_deg.to_radians() / 2.0).sin_cos();
    grid(2 * columns, 2 * columns, rep, |s, t| {
        let (a, b) = (2.0 * s - 1.0, 2.0 * t - 1.0);
        let side = if a.abs() < 1e-12 { 0.0 } else { a.signum() };
        (
            DVec3::new(a * ch, b, -a.abs() * sh) * size,
            DVec3::new(side * sh, 0.0, ch),
            DVec3::new(ch, 0.0, -side * sh) * (2.0 * size),
            DVec3::new(0.0, 2.0 * size, 0.0),
        )
    })
}

fn one_cell() -> u32 {
    1
}

fn quad(size: f64, n: u32, rep: DVec2) -> Mesh {
    grid(n, n, rep, |s, t| {
        (
            DVec3::new(size * (s - 0.5), size * (t - 0.5), 0.0),
            DVec3::Z,
            DVec3::new(size, 0.0, 0.0),
            DVec3::new(0.0, size, 0.0),
        )
    })
}

/// Sphere point, normal, ∂/∂θ, ∂/∂φ at azimuth θ and polar angle φ from the south pole:
/// `P = r (sin φ cos θ, -cos φ, -sin φ sin θ)`.
fn sphere_frame(r: f64, theta: f64, phi: f64) -> (DVec3, DVec3, DVec3, DVec3) {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    let n = DVec3::new(sp * ct, -cp, -sp * st);
    let d_theta = DVec3::new(-st, 0.0, -ct) * (r * sp);
    let d_phi = DVec3::new(cp * ct, sp, -cp * st) * r;
    (n * r, n, d_theta, d_phi)
}

fn sphere(r: f64, slices: u32, stacks: u32, rep: DVec2) -> Mesh {
    let mut mesh = Mesh::default();
    let row = slices + 1;
    let d_phi = PI / f64::from(stacks);
    // Ring vertices for stacks 1..stacks-1.
    for j in 1..stacks {
        let t = f64::from(j) / f64::from(stacks);
        for i in 0..=slices {
            let s = f64::from(i) / f64::from(slices);
            let (pos, normal, dth, dph) = sphere_frame(r, TAU * s, PI * t);
            mesh.vertices.push(Vertex {
                pos,
                normal: normal.normalize(),
                uv: DVec2::new(s, t) * rep,
                pu: dth * TAU / rep.x,
                pv: dph * PI / rep.y,
            });
        }
    }
    let ring = |j: u32, i: u32| (j - 1) * row + i;
    // Pole vertices, one per slice at its centre u. ∂P/∂u vanishes at a pole; the pole
    // vertex carries ∂P/∂u of the adjacent ring at the same u (same direction, the limit
    // tangent), so the tangent frame stays defined. The normal is exact.
    let poles_start = mesh.vertices.len() as u32;
    for (t, phi_adj, y) in [(0.0, d_phi, -1.0), (1.0, PI - d_phi, 1.0)] {
        for i in 0..slices {
            let s = (f64::from(i) + 0.5) / f64::from(slices);
            let (_, _, dth_adj, _) = sphere_frame(r, TAU * s, phi_adj);
            let (_, _, _, dph) = sphere_frame(r, TAU * s, PI * t);
            mesh.vertices.push(Vertex {
                pos: DVec3::new(0.0, y * r, 0.0),
                normal: DVec3::new(0.0, y, 0.0),
                uv: DVec2::new(s, t) * rep,
                pu: dth_adj * TAU / rep.x,
                pv: dph * PI / rep.y,
            });
        }
    }
    let south = |i: u32| poles_start + i;
    let north = |i: u32| poles_start + slices + i;
    for i in 0..slices {
        // South band: the quad's bottom edge collapses to the pole.
        mesh.triangles.push([south(i), ring(1, i + 1), ring(1, i)]);
    }
    for j in 1..stacks - 1 {
        for i in 0..slices {
            let (a, b) = (ring(j, i), ring(j, i + 1));
            let (c, d) = (ring(j + 1, i + 1), ring(j + 1, i));
            mesh.triangles.push([a, b, c]);
            mesh.triangles.push([a, c, d]);
        }
    }
    for i in 0..slices {
        // North band: the quad's top edge collapses to the pole.
        mesh.triangles
            .push([ring(stacks - 1, i), ring(stacks - 1, i + 1), north(i)]);
    }
    mesh
}

fn torus(major: f64, minor: f64, slices: u32, rings: u32, rep: DVec2) -> Mesh {
    grid(slices, rings, rep, |s, t| {
        let (st, ct) = (TAU * s).sin_cos();
        let (sp, cp) = (TAU * t).sin_cos();
        let rho = major + minor * cp;
        (
            DVec3::new(rho * ct, minor * sp, -rho * st),
            DVec3::new(cp * ct, sp, -cp * st),
            DVec3::new(-st, 0.0, -ct) * (rho * TAU),
            DVec3::new(-sp * ct, cp, sp * st) * (minor * TAU),
        )
    })
}

fn cylinder(radius: f64, height: f64, slices: u32, stacks: u32, rep: DVec2) -> Mesh {
    grid(slices, stacks, rep, |s, t| {
        let (st, ct) = (TAU * s).sin_cos();
        (
            DVec3::new(radius * ct, height * (t - 0.5), -radius * st),
            DVec3::new(ct, 0.0, -st),
            DVec3::new(-st, 0.0, -ct) * (radius * TAU),
            DVec3::new(0.0, height, 0.0),
        )
    })
}

/// Cubic Bernstein polynomials and their derivatives at `t`.
fn bernstein(t: f64) -> ([f64; 4], [f64; 4]) {
    let s = 1.0 - t;
    (
        [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t],
        [
            -3.0 * s * s,
            3.0 * s * s - 6.0 * t * s,
            6.0 * t * s - 3.0 * t * t,
            3.0 * t * t,
        ],
    )
}

/// A bicubic Bézier patch; `cp[i][j]`: row `i` along `v`, column `j` along `u`.
struct Patch {
    cp: [[DVec3; 4]; 4],
}

impl Patch {
    /// `(P, ∂P/∂u, ∂P/∂v, ∂²P/∂u∂v)` at `(u, v)`.
    fn eval(&self, u: f64, v: f64) -> (DVec3, DVec3, DVec3, DVec3) {
        let (bu, du) = bernstein(u);
        let (bv, dv) = bernstein(v);
        let (mut p, mut pu, mut pv, mut puv) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
        for i in 0..4 {
            for j in 0..4 {
                let c = self.cp[i][j];
                p += c * (bv[i] * bu[j]);
                pu += c * (bv[i] * du[j]);
                pv += c * (dv[i] * bu[j]);
                puv += c * (dv[i] * du[j]);
            }
        }
        (p, pu, pv, puv)
    }

    /// Position, unit normal, ∂P/∂u, ∂P/∂v at grid point `(i, j)` of an `n x n` grid.
    ///
    /// Where an edge of the patch collapses to a point (the lid top and the bottom), one
    /// derivative vanishes. There the normal is the exact limit (`∂²P/∂u∂v × ∂P/∂v` for a
    /// collapsed row, `∂P/∂u × ∂²P/∂u∂v` for a collapsed column, signed toward the interior)
    /// and the vanished derivative is replaced by its value on the adjacent grid line, which
    /// has the limit direction. If that still fails, the normal is taken a small step
    /// (1e-4 of the patch) toward the patch centre.
    fn frame(&self, i: u32, j: u32, n: u32) -> (DVec3, DVec3, DVec3, DVec3) {
        let step = 1.0 / f64::from(n);
        let (u, v) = (f64::from(i) * step, f64::from(j) * step);
        let (p, mut pu, mut pv, puv) = self.eval(u, v);
        let scale = self
            .cp
            .iter()
            .flatten()
            .fold(0.0f64, |m, c| m.max((*c - self.cp[0][0]).length()));
        let tiny = 1e-9 * scale;
        let mut normal = pu.cross(pv);
        if pu.length() < tiny && pv.length() >= tiny {
            let toward = if v < 0.5 { 1.0 } else { -1.0 };
            normal = puv.cross(pv) * toward;
            pu = self.eval(u, v + toward * step).1;
        } else if pv.length() < tiny && pu.length() >= tiny {
            let toward = if u < 0.5 { 1.0 } else { -1.0 };
            normal = pu.cross(puv) * toward;
            pv = self.eval(u + toward * step, v).2;
        }
        if normal.length().is_nan() || normal.length() <= tiny * tiny {
            let (u2, v2) = (u + (0.5 - u) * 1e-4, v + (0.5 - v) * 1e-4);
            let (_, a, b, _) = self.eval(u2, v2);
            normal = a.cross(b);
        }
        let normal = normal.normalize_or(DVec3::Y);
        (p, normal, pu, pv)
    }
}

/// Teapot z-up data to y-up: `(x, y, z) -> (x, z, -y)` (a rotation about x).
fn teapot_rotate(p: DVec3) -> DVec3 {
    DVec3::new(p.x, p.z, -p.y)
}

fn teapot(n: u32, rep: DVec2) -> Mesh {
    let mut mesh = Mesh::default();
    for indices in TEAPOT_PATCHES.iter() {
        let mut cp = [[DVec3::ZERO; 4]; 4];
        for (k, &idx) in indices.iter().enumerate() {
            cp[k / 4][k % 4] = teapot_rotate(DVec3::from(TEAPOT_VERTICES[idx as usize]));
        }
        let patch = Patch { cp };
        let base = mesh.vertices.len() as u32;
        for j in 0..=n {
            for i in 0..=n {
                let (pos, normal, pu, pv) = patch.frame(i, j, n);
                let uv = DVec2::new(f64::from(i), f64::from(j)) / f64::from(n);
                mesh.vertices.push(Vertex {
                    pos,
                    normal,
                    uv: uv * rep,
                    pu: pu / rep.x,
                    pv: pv / rep.y,
                });
            }
        }
        let row = n + 1;
        for j in 0..n {
            for i in 0..n {
                let a = base + j * row + i;
                let (b, c, d) = (a + 1, a + row + 1, a + row);
                mesh.triangles.push([a, b, c]);
                mesh.triangles.push([a, c, d]);
            }
        }
    }
    // The collapsed edges give zero-area triangles (one per grid cell along the edge).
    mesh.drop_degenerate();
    mesh
}

/// Newell's teapot: 32 bicubic Bézier patches (16 zero-based indices each, row-major: row i
/// along v, column j along u) over 306 control points, z up. Public-domain data by Martin
/// Newell (1975), as distributed in Steve Baker's `teaset.tgz` (sjbaker.org) and copied from
/// markkilgard/opengl4_examples `tessellation/teapot.cpp`. The four lid-top patches start
/// with the repeated point 203 and the four bottom patches with 269 (collapsed edges).
const TEAPOT_PATCHES: [[u16; 16]; 32] = [
    [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15],
    [3, 16, 17, 18, 7, 19, 20, 21, 11, 22, 23, 24, 15, 25, 26, 27],
    [
        18, 28, 29, 30, 21, 31, 32, 33, 24, 34, 35, 36, 27, 37, 38, 39,
    ],
    [30, 40, 41, 0, 33, 42, 43, 4, 36, 44, 45, 8, 39, 46, 47, 12],
    [
        12, 13, 14, 15, 48, 49, 50, 51, 52, 53, 54, 55, 56, 57, 58, 59,
    ],
    [
        15, 25, 26, 27, 51, 60, 61, 62, 55, 63, 64, 65, 59, 66, 67, 68,
    ],
    [
        27, 37, 38, 39, 62, 69, 70, 71, 65, 72, 73, 74, 68, 75, 76, 77,
    ],
    [
        39, 46, 47, 12, 71, 78, 79, 48, 74, 80, 81, 52, 77, 82, 83, 56,
    ],
    [
        56, 57, 58, 59, 84, 85, 86, 87, 88, 89, 90, 91, 92, 93, 94, 95,
    ],
    [
        59, 66, 67, 68, 87, 96, 97, 98, 91, 99, 100, 101, 95, 102, 103, 104,
    ],
    [
        68, 75, 76, 77, 98, 105, 106, 107, 101, 108, 109, 110, 104, 111, 112, 113,
    ],
    [
        77, 82, 83, 56, 107, 114, 115, 84, 110, 116, 117, 88, 113, 118, 119, 92,
    ],
    [
        120, 121, 122, 123, 124, 125, 126, 127, 128, 129, 130, 131, 132, 133, 134, 135,
    ],
    [
        123, 136, 137, 120, 127, 138, 139, 124, 131, 140, 141, 128, 135, 142, 143, 132,
    ],
    [
        132, 133, 134, 135, 144, 145, 146, 147, 148, 149, 150, 151, 68, 152, 153, 154,
    ],
    [
        135, 142, 143, 132, 147, 155, 156, 144, 151, 157, 158, 148, 154, 159, 160, 68,
    ],
    [
        161, 162, 163, 164, 165, 166, 167, 168, 169, 170, 171, 172, 173, 174, 175, 176,
    ],
    [
        164, 177, 178, 161, 168, 179, 180, 165, 172, 181, 182, 169, 176, 183, 184, 173,
    ],
    [
        173, 174, 175, 176, 185, 186, 187, 188, 189, 190, 191, 192, 193, 194, 195, 196,
    ],
    [
        176, 183, 184, 173, 188, 197, 198, 185, 192, 199, 200, 189, 196, 201, 202, 193,
    ],
    [
        203, 203, 203, 203, 206, 207, 208, 209, 210, 210, 210, 210, 211, 212, 213, 214,
    ],
    [
        203, 203, 203, 203, 209, 216, 217, 218, 210, 210, 210, 210, 214, 219, 220, 221,
    ],
    [
        203, 203, 203, 203, 218, 223, 224, 225, 210, 210, 210, 210, 221, 226, 227, 228,
    ],
    [
        203, 203, 203, 203, 225, 229, 230, 206, 210, 210, 210, 210, 228, 231, 232, 211,
    ],
    [
        211, 212, 213, 214, 233, 234, 235, 236, 237, 238, 239, 240, 241, 242, 243, 244,
    ],
    [
        214, 219, 220, 221, 236, 245, 246, 247, 240, 248, 249, 250, 244, 251, 252, 253,
    ],
    [
        221, 226, 227, 228, 247, 254, 255, 256, 250, 257, 258, 259, 253, 260, 261, 262,
    ],
    [
        228, 231, 232, 211, 256, 263, 264, 233, 259, 265, 266, 237, 262, 267, 268, 241,
    ],
    [
        269, 269, 269, 269, 278, 279, 280, 281, 274, 275, 276, 277, 270, 271, 272, 273,
    ],
    [
        269, 269, 269, 269, 281, 288, 289, 290, 277, 285, 286, 287, 273, 282, 283, 284,
    ],
    [
        269, 269, 269, 269, 290, 297, 298, 299, 287, 294, 295, 296, 284, 291, 292, 293,
    ],
    [
        269, 269, 269, 269, 299, 304, 305, 278, 296, 302, 303, 274, 293, 300, 301, 270,
    ],
];

/// Control points of [`TEAPOT_PATCHES`] (z up; same source).
const TEAPOT_VERTICES: [[f64; 3]; 306] = [
    [1.4, 0.0, 2.4],
    [1.4, -0.784, 2.4],
    [0.784, -1.4, 2.4],
    [0.0, -1.4, 2.4],
    [1.3375, 0.0, 2.53125],
    [1.3375, -0.749, 2.53125],
    [0.749, -1.3375, 2.53125],
    [0.0, -1.3375, 2.53125],
    [1.4375, 0.0, 2.53125],
    [1.4375, -0.805, 2.53125],
    [0.805, -1.4375, 2.53125],
    [0.0, -1.4375, 2.53125],
    [1.5, 0.0, 2.4],
    [1.5, -0.84, 2.4],
    [0.84, -1.5, 2.4],
    [0.0, -1.5, 2.4],
    [-0.784, -1.4, 2.4],
    [-1.4, -0.784, 2.4],
    [-1.4, 0.0, 2.4],
    [-0.749, -1.3375, 2.53125],
    [-1.3375, -0.749, 2.53125],
    [-1.3375, 0.0, 2.53125],
    [-0.805, -1.4375, 2.53125],
    [-1.4375, -0.805, 2.53125],
    [-1.4375, 0.0, 2.53125],
    [-0.84, -1.5, 2.4],
    [-1.5, -0.84, 2.4],
    [-1.5, 0.0, 2.4],
    [-1.4, 0.784, 2.4],
    [-0.784, 1.4, 2.4],
    [0.0, 1.4, 2.4],
    [-1.3375, 0.749, 2.53125],
    [-0.749, 1.3375, 2.53125],
    [0.0, 1.3375, 2.53125],
    [-1.4375, 0.805, 2.53125],
    [-0.805, 1.4375, 2.53125],
    [0.0, 1.4375, 2.53125],
    [-1.5, 0.84, 2.4],
    [-0.84, 1.5, 2.4],
    [0.0, 1.5, 2.4],
    [0.784, 1.4, 2.4],
    [1.4, 0.784, 2.4],
    [0.749, 1.3375, 2.53125],
    [1.3375, 0.749, 2.53125],
    [0.805, 1.4375, 2.53125],
    [1.4375, 0.805, 2.53125],
    [0.84, 1.5, 2.4],
    [1.5, 0.84, 2.4],
    [1.75, 0.0, 1.875],
    [1.75, -0.98, 1.875],
    [0.98, -1.75, 1.875],
    [0.0, -1.75, 1.875],
    [2.0, 0.0, 1.35],
    [2.0, -1.12, 1.35],
    [1.12, -2.0, 1.35],
    [0.0, -2.0, 1.35],
    [2.0, 0.0, 0.9],
    [2.0, -1.12, 0.9],
    [1.12, -2.0, 0.9],
    [0.0, -2.0, 0.9],
    [-0.98, -1.75, 1.875],
    [-1.75, -0.98, 1.875],
    [-1.75, 0.0, 1.875],
    [-1.12, -2.0, 1.35],
    [-2.0, -1.12, 1.35],
    [-2.0, 0.0, 1.35],
    [-1.12, -2.0, 0.9],
    [-2.0, -1.12, 0.9],
    [-2.0, 0.0, 0.9],
    [-1.75, 0.98, 1.875],
    [-0.98, 1.75, 1.875],
    [0.0, 1.75, 1.875],
    [-2.0, 1.12, 1.35],
    [-1.12, 2.0, 1.35],
    [0.0, 2.0, 1.35],
    [-2.0, 1.12, 0.9],
    [-1.12, 2.0, 0.9],
    [0.0, 2.0, 0.9],
    [0.98, 1.75, 1.875],
    [1.75, 0.98, 1.875],
    [1.12, 2.0, 1.35],
    [2.0, 1.12, 1.35],
    [1.12, 2.0, 0.9],
    [2.0, 1.12, 0.9],
    [2.0, 0.0, 0.45],
    [2.0, -1.12, 0.45],
    [1.12, -2.0, 0.45],
    [0.0, -2.0, 0.45],
    [1.5, 0.0, 0.225],
    [1.5, -0.84, 0.225],
    [0.84, -1.5, 0.225],
    [0.0, -1.5, 0.225],
    [1.5, 0.0, 0.15],
    [1.5, -0.84, 0.15],
    [0.84, -1.5, 0.15],
    [0.0, -1.5, 0.15],
    [-1.12, -2.0, 0.45],
    [-2.0, -1.12, 0.45],
    [-2.0, 0.0, 0.45],
    [-0.84, -1.5, 0.225],
    [-1.5, -0.84, 0.225],
    [-1.5, 0.0, 0.225],
    [-0.84, -1.5, 0.15],
    [-1.5, -0.84, 0.15],
    [-1.5, 0.0, 0.15],
    [-2.0, 1.12, 0.45],
    [-1.12, 2.0, 0.45],
    [0.0, 2.0, 0.45],
    [-1.5, 0.84, 0.225],
    [-0.84, 1.5, 0.225],
    [0.0, 1.5, 0.225],
    [-1.5, 0.84, 0.15],
    [-0.84, 1.5, 0.15],
    [0.0, 1.5, 0.15],
    [1.12, 2.0, 0.45],
    [2.0, 1.12, 0.45],
    [0.84, 1.5, 0.225],
    [1.5, 0.84, 0.225],
    [0.84, 1.5, 0.15],
    [1.5, 0.84, 0.15],
    [-1.6, 0.0, 2.025],
    [-1.6, -0.3, 2.025],
    [-1.5, -0.3, 2.25],
    [-1.5, 0.0, 2.25],
    [-2.3, 0.0, 2.025],
    [-2.3, -0.3, 2.025],
    [-2.5, -0.3, 2.25],
    [-2.5, 0.0, 2.25],
    [-2.7, 0.0, 2.025],
    [-2.7, -0.3, 2.025],
    [-3.0, -0.3, 2.25],
    [-3.0, 0.0, 2.25],
    [-2.7, 0.0, 1.8],
    [-2.7, -0.3, 1.8],
    [-3.0, -0.3, 1.8],
    [-3.0, 0.0, 1.8],
    [-1.5, 0.3, 2.25],
    [-1.6, 0.3, 2.025],
    [-2.5, 0.3, 2.25],
    [-2.3, 0.3, 2.025],
    [-3.0, 0.3, 2.25],
    [-2.7, 0.3, 2.025],
    [-3.0, 0.3, 1.8],
    [-2.7, 0.3, 1.8],
    [-2.7, 0.0, 1.575],
    [-2.7, -0.3, 1.575],
    [-3.0, -0.3, 1.35],
    [-3.0, 0.0, 1.35],
    [-2.5, 0.0, 1.125],
    [-2.5, -0.3, 1.125],
    [-2.65, -0.3, 0.9375],
    [-2.65, 0.0, 0.9375],
    [-2.0, -0.3, 0.9],
    [-1.9, -0.3, 0.6],
    [-1.9, 0.0, 0.6],
    [-3.0, 0.3, 1.35],
    [-2.7, 0.3, 1.575],
    [-2.65, 0.3, 0.9375],
    [-2.5, 0.3, 1.125],
    [-1.9, 0.3, 0.6],
    [-2.0, 0.3, 0.9],
    [1.7, 0.0, 1.425],
    [1.7, -0.66, 1.425],
    [1.7, -0.66, 0.6],
    [1.7, 0.0, 0.6],
    [2.6, 0.0, 1.425],
    [2.6, -0.66, 1.425],
    [3.1, -0.66, 0.825],
    [3.1, 0.0, 0.825],
    [2.3, 0.0, 2.1],
    [2.3, -0.25, 2.1],
    [2.4, -0.25, 2.025],
    [2.4, 0.0, 2.025],
    [2.7, 0.0, 2.4],
    [2.7, -0.25, 2.4],
    [3.3, -0.25, 2.4],
    [3.3, 0.0, 2.4],
    [1.7, 0.66, 0.6],
    [1.7, 0.66, 1.425],
    [3.1, 0.66, 0.825],
    [2.6, 0.66, 1.425],
    [2.4, 0.25, 2.025],
    [2.3, 0.25, 2.1],
    [3.3, 0.25, 2.4],
    [2.7, 0.25, 2.4],
    [2.8, 0.0, 2.475],
    [2.8, -0.25, 2.475],
    [3.525, -0.25, 2.49375],
    [3.525, 0.0, 2.49375],
    [2.9, 0.0, 2.475],
    [2.9, -0.15, 2.475],
    [3.45, -0.15, 2.5125],
    [3.45, 0.0, 2.5125],
    [2.8, 0.0, 2.4],
    [2.8, -0.15, 2.4],
    [3.2, -0.15, 2.4],
    [3.2, 0.0, 2.4],
    [3.525, 0.25, 2.49375],
    [2.8, 0.25, 2.475],
    [3.45, 0.15, 2.5125],
    [2.9, 0.15, 2.475],
    [3.2, 0.15, 2.4],
    [2.8, 0.15, 2.4],
    [0.0, 0.0, 3.15],
    [0.0, -0.002, 3.15],
    [0.002, 0.0, 3.15],
    [0.8, 0.0, 3.15],
    [0.8, -0.45, 3.15],
    [0.45, -0.8, 3.15],
    [0.0, -0.8, 3.15],
    [0.0, 0.0, 2.85],
    [0.2, 0.0, 2.7],
    [0.2, -0.112, 2.7],
    [0.112, -0.2, 2.7],
    [0.0, -0.2, 2.7],
    [-0.002, 0.0, 3.15],
    [-0.45, -0.8, 3.15],
    [-0.8, -0.45, 3.15],
    [-0.8, 0.0, 3.15],
    [-0.112, -0.2, 2.7],
    [-0.2, -0.112, 2.7],
    [-0.2, 0.0, 2.7],
    [0.0, 0.002, 3.15],
    [-0.8, 0.45, 3.15],
    [-0.45, 0.8, 3.15],
    [0.0, 0.8, 3.15],
    [-0.2, 0.112, 2.7],
    [-0.112, 0.2, 2.7],
    [0.0, 0.2, 2.7],
    [0.45, 0.8, 3.15],
    [0.8, 0.45, 3.15],
    [0.112, 0.2, 2.7],
    [0.2, 0.112, 2.7],
    [0.4, 0.0, 2.55],
    [0.4, -0.224, 2.55],
    [0.224, -0.4, 2.55],
    [0.0, -0.4, 2.55],
    [1.3, 0.0, 2.55],
    [1.3, -0.728, 2.55],
    [0.728, -1.3, 2.55],
    [0.0, -1.3, 2.55],
    [1.3, 0.0, 2.4],
    [1.3, -0.728, 2.4],
    [0.728, -1.3, 2.4],
    [0.0, -1.3, 2.4],
    [-0.224, -0.4, 2.55],
    [-0.4, -0.224, 2.55],
    [-0.4, 0.0, 2.55],
    [-0.728, -1.3, 2.55],
    [-1.3, -0.728, 2.55],
    [-1.3, 0.0, 2.55],
    [-0.728, -1.3, 2.4],
    [-1.3, -0.728, 2.4],
    [-1.3, 0.0, 2.4],
    [-0.4, 0.224, 2.55],
    [-0.224, 0.4, 2.55],
    [0.0, 0.4, 2.55],
    [-1.3, 0.728, 2.55],
    [-0.728, 1.3, 2.55],
    [0.0, 1.3, 2.55],
    [-1.3, 0.728, 2.4],
    [-0.728, 1.3, 2.4],
    [0.0, 1.3, 2.4],
    [0.224, 0.4, 2.55],
    [0.4, 0.224, 2.55],
    [0.728, 1.3, 2.55],
    [1.3, 0.728, 2.55],
    [0.728, 1.3, 2.4],
    [1.3, 0.728, 2.4],
    [0.0, 0.0, 0.0],
    [1.5, 0.0, 0.15],
    [1.5, 0.84, 0.15],
    [0.84, 1.5, 0.15],
    [0.0, 1.5, 0.15],
    [1.5, 0.0, 0.075],
    [1.5, 0.84, 0.075],
    [0.84, 1.5, 0.075],
    [0.0, 1.5, 0.075],
    [1.425, 0.0, 0.0],
    [1.425, 0.798, 0.0],
    [0.798, 1.425, 0.0],
    [0.0, 1.425, 0.0],
    [-0.84, 1.5, 0.15],
    [-1.5, 0.84, 0.15],
    [-1.5, 0.0, 0.15],
    [-0.84, 1.5, 0.075],
    [-1.5, 0.84, 0.075],
    [-1.5, 0.0, 0.075],
    [-0.798, 1.425, 0.0],
    [-1.425, 0.798, 0.0],
    [-1.425, 0.0, 0.0],
    [-1.5, -0.84, 0.15],
    [-0.84, -1.5, 0.15],
    [0.0, -1.5, 0.15],
    [-1.5, -0.84, 0.075],
    [-0.84, -1.5, 0.075],
    [0.0, -1.5, 0.075],
    [-1.425, -0.798, 0.0],
    [-0.798, -1.425, 0.0],
    [0.0, -1.425, 0.0],
    [0.84, -1.5, 0.15],
    [1.5, -0.84, 0.15],
    [0.84, -1.5, 0.075],
    [1.5, -0.84, 0.075],
    [0.798, -1.425, 0.0],
    [1.425, -0.798, 0.0],
];

#[cfg(test)]
mod tests {
    use super::*;

    fn build(spec: &MeshSpec) -> Mesh {
        spec.build(Path::new(".")).unwrap()
    }

    /// Angle between two vectors, accurate near 0.
    fn angle_between(a: DVec3, b: DVec3) -> f64 {
        a.cross(b).length().atan2(a.dot(b))
    }

    /// Every vertex has a unit normal; `pu × pv` is parallel to the normal (same direction)
    /// to within `angle_tol` radians; every triangle winds counter-clockwise seen from
    /// outside.
    fn check_frames(mesh: &Mesh, angle_tol: f64, what: &str) {
        for (i, v) in mesh.vertices.iter().enumerate() {
            assert!(
                (v.normal.length() - 1.0).abs() < 1e-12,
                "{what} vertex {i}: {v:?}"
            );
            let c = v.pu.cross(v.pv);
            assert!(
                c.length() > 0.0,
                "{what} vertex {i}: degenerate frame {v:?}"
            );
            let angle = angle_between(c, v.normal);
            assert!(
                angle <= angle_tol,
                "{what} vertex {i}: pu×pv at {angle} rad from N, {v:?}"
            );
        }
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|k| mesh.vertices[k as usize]);
            let face = (b.pos - a.pos).cross(c.pos - a.pos);
            let avg = a.normal + b.normal + c.normal;
            assert!(face.dot(avg) > 0.0, "{what} triangle {t} winds inward");
        }
    }

    /// Analytic `pu` / `pv` against finite differences of the parametric position.
    fn check_derivatives(
        mesh: &Mesh,
        pos: impl Fn(f64, f64) -> DVec3,
        verts: &[usize],
        tol: f64,
        what: &str,
    ) {
        let h = 1e-6;
        for &k in verts {
            let v = mesh.vertices[k];
            let (u, w) = (v.uv.x, v.uv.y);
            let du = (pos(u + h, w) - pos(u - h, w)) / (2.0 * h);
            let dv = (pos(u, w + h) - pos(u, w - h)) / (2.0 * h);
            assert!(
                (du - v.pu).length() <= tol * v.pu.length().max(1.0),
                "{what} {k}: pu {} vs {du}",
                v.pu
            );
            assert!(
                (dv - v.pv).length() <= tol * v.pv.length().max(1.0),
                "{what} {k}: pv {} vs {dv}",
                v.pv
            );
            assert!((pos(u, w) - v.pos).length() < 1e-12, "{what} {k}: position");
        }
    }

    #[test]
    fn quad_geometry() {
        let m = build(&MeshSpec::Quad {
            size: 2.0,
            uv_repeat: [4.0, 2.0],
            subdivisions: 1,
        });
        assert_eq!((m.vertices.len(), m.triangles.len()), (4, 2));
        check_frames(&m, 1e-12, "quad");
        let (lo, hi) = m.bounds();
        assert_eq!(
            (lo, hi),
            (DVec3::new(-1.0, -1.0, 0.0), DVec3::new(1.0, 1.0, 0.0))
        );
        // u = 4 across 2 units of x: ∂P/∂u = 0.5 x; v = 2 across 2 units of y.
        for v in &m.vertices {
            assert_eq!(v.pu, DVec3::new(0.5, 0.0, 0.0));
            assert_eq!(v.pv, DVec3::new(0.0, 1.0, 0.0));
            assert_eq!(v.normal, DVec3::Z);
            assert_eq!(v.uv, DVec2::new((v.pos.x + 1.0) * 2.0, v.pos.y + 1.0));
        }
    }

    #[test]
    fn subdivided_quad_is_the_same_plane() {
        let m = build(&MeshSpec::Quad {
            size: 2.0,
            uv_repeat: [4.0, 2.0],
            subdivisions: 8,
        });
        assert_eq!((m.vertices.len(), m.triangles.len()), (81, 128));
        check_frames(&m, 1e-12, "quad 8");
        for v in &m.vertices {
            assert!(v.pos.x.abs() <= 1.0 && v.pos.y.abs() <= 1.0 && v.pos.z == 0.0);
            assert!((v.uv - DVec2::new((v.pos.x + 1.0) * 2.0, v.pos.y + 1.0)).length() < 1e-12);
        }
    }

    #[test]
    fn sphere_geometry_and_poles() {
        let (r, slices, stacks) = (2.0, 12, 7);
        let rep = [3.0, 2.0];
        let m = build(&MeshSpec::Sphere {
            radius: r,
            slices,
            stacks,
            uv_repeat: rep,
        });
        // Rings 1..stacks-1 of slices + 1 vertices, plus one pole vertex per slice per pole.
        assert_eq!(m.vertices.len(), 13 * 6 + 2 * 12);
        assert_eq!(m.triangles.len(), 2 * 12 * (7 - 1));
        check_frames(&m, 1e-9, "sphere");
        for v in &m.vertices {
            assert!((v.pos.length() - r).abs() < 1e-12);
            assert!((v.normal - v.pos / r).length() < 1e-12);
        }
        // Poles: exact normals and positions.
        let south: Vec<_> = m.vertices.iter().filter(|v| v.uv.y == 0.0).collect();
        let north: Vec<_> = m.vertices.iter().filter(|v| v.uv.y == 2.0).collect();
        assert_eq!((south.len(), north.len()), (12, 12));
        for v in &south {
            assert_eq!(v.normal, DVec3::new(0.0, -1.0, 0.0));
            assert_eq!(v.pos, DVec3::new(0.0, -2.0, 0.0));
        }
        for v in &north {
            assert_eq!(v.normal, DVec3::Y);
        }
        let pos = |u: f64, v: f64| sphere_frame(r, TAU * u / rep[0], PI * v / rep[1]).0;
        let rings: Vec<usize> = (0..m.vertices.len())
            .filter(|&k| m.vertices[k].uv.y > 0.0 && m.vertices[k].uv.y < 2.0)
            .step_by(7)
            .collect();
        check_derivatives(&m, pos, &rings, 1e-7, "sphere");
        // Orientation: on the +z side, u increases toward +x and v toward +y.
        let front = m
            .vertices
            .iter()
            .find(|v| v.pos.z > 1.9 && v.pos.y.abs() < 0.5)
            .unwrap();
        assert!(front.pu.x > 0.0 && front.pv.y > 0.0, "{front:?}");
        // |∂P/∂u| = 2π r sin φ / 3 (the latitude circle, u repeated 3 times) and
        // |∂P/∂v| = π r / 2 everywhere, poles included (pu there is the first ring's).
        let ring1 = TAU * r * (PI / 7.0).sin() / 3.0;
        for v in &m.vertices {
            assert!((v.pv.length() - PI * r / 2.0).abs() < 1e-12, "{v:?}");
            let phi = PI * v.uv.y / 2.0;
            let want = if v.uv.y == 0.0 || v.uv.y == 2.0 {
                ring1
            } else {
                TAU * r * phi.sin() / 3.0
            };
            assert!((v.pu.length() - want).abs() < 1e-12, "{v:?}");
        }
        m.validate("mesh.Sphere").unwrap();
    }

    #[test]
    fn torus_and_cylinder_geometry() {
        let (major, minor) = (3.0, 1.0);
        let rep = [8.0, 2.0];
        let m = build(&MeshSpec::Torus {
            major,
            minor,
            slices: 24,
            rings: 10,
            uv_repeat: rep,
        });
        assert_eq!(
            (m.vertices.len(), m.triangles.len()),
            (25 * 11, 2 * 24 * 10)
        );
        check_frames(&m, 1e-9, "torus");
        let pos = |u: f64, v: f64| {
            let (st, ct) = (TAU * u / rep[0]).sin_cos();
            let (sp, cp) = (TAU * v / rep[1]).sin_cos();
            DVec3::new(
                (major + minor * cp) * ct,
                minor * sp,
                -(major + minor * cp) * st,
            )
        };
        check_derivatives(&m, pos, &[0, 5, 30, 77, 140, 274], 1e-7, "torus");
        let (lo, hi) = m.bounds();
        assert!(
            (hi.x - 4.0).abs() < 1e-12 && (lo.x + 4.0).abs() < 0.1 && (hi.y - 1.0).abs() < 0.05
        );
        // Outer equator (v = 0): |pu| = 2π (R + r) / 8 = π.
        assert!((m.vertices[0].pu.length() - PI).abs() < 1e-12);

        let (radius, height) = (0.5, 3.0);
        let rep = [2.0, 1.0];
        let c = build(&MeshSpec::Cylinder {
            radius,
            height,
            slices: 16,
            stacks: 3,
            uv_repeat: rep,
        });
        assert_eq!((c.vertices.len(), c.triangles.len()), (17 * 4, 2 * 16 * 3));
        check_frames(&c, 1e-9, "cylinder");
        let pos = |u: f64, v: f64| {
            let (st, ct) = (TAU * u / rep[0]).sin_cos();
            DVec3::new(radius * ct, height * (v / rep[1] - 0.5), -radius * st)
        };
        check_derivatives(&c, pos, &[0, 3, 20, 41, 67], 1e-7, "cylinder");
        for v in &c.vertices {
            assert!((v.pu.length() - TAU * radius / 2.0).abs() < 1e-12);
            assert_eq!(v.pv, DVec3::new(0.0, 3.0, 0.0));
            assert_eq!(v.normal.y, 0.0);
        }
        let (lo, hi) = c.bounds();
        assert_eq!((lo.y, hi.y), (-1.5, 1.5));
    }

    #[test]
    fn teapot_data_and_mesh() {
        assert_eq!(TEAPOT_PATCHES.len(), 32);
        assert_eq!(TEAPOT_VERTICES.len(), 306);
        let max = TEAPOT_PATCHES.iter().flatten().max().copied().unwrap();
        assert_eq!(max, 305);
        let m = build(&MeshSpec::Teapot {
            subdivisions: 4,
            uv_repeat: [1.0, 1.0],
        });
        // 32 patches x 5 x 5 vertices and 32 x 4 x 4 x 2 triangles, minus the 8 patches
        // (lid top 4, bottom 4) whose v = 0 edge collapses: 4 triangles and 1 unused vertex
        // each.
        assert_eq!(m.vertices.len(), 32 * 25 - 8);
        assert_eq!(m.triangles.len(), 32 * 32 - 8 * 4);
        assert_eq!((m.vertices.len(), m.triangles.len()), (792, 992));
        m.validate("mesh.Teapot").unwrap();
        // pu × pv follows the normal everywhere, including the collapsed poles (where pu
        // comes from the adjacent grid line, which has the limit direction).
        check_frames(&m, 1e-9, "teapot");
        // The body (away from the handle and spout, which lie near z = 0) faces outward.
        let mut body = 0;
        for v in &m.vertices {
            let radial = DVec3::new(v.pos.x, 0.0, v.pos.z);
            if radial.length() > 1.45 && v.pos.z.abs() > 0.7 && (0.2..2.3).contains(&v.pos.y) {
                assert!(v.normal.dot(radial) > 0.5 * radial.length(), "{v:?}");
                body += 1;
            }
        }
        assert!(body > 50, "{body}");
        // The lid top and the bottom centre have vertical normals.
        let top = m
            .vertices
            .iter()
            .filter(|v| (v.pos - DVec3::new(0.0, 3.15, 0.0)).length() < 1e-9);
        let mut n_top = 0;
        for v in top {
            assert!((v.normal - DVec3::Y).length() < 1e-9, "{v:?}");
            n_top += 1;
        }
        assert_eq!(n_top, 4 * 4);
        let bottom = m.vertices.iter().filter(|v| v.pos.length() < 1e-9);
        let mut n_bottom = 0;
        for v in bottom {
            assert!((v.normal + DVec3::Y).length() < 1e-9, "{v:?}");
            n_bottom += 1;
        }
        assert_eq!(n_bottom, 4 * 4);
        // Bounds (y-up): the handle reaches x = -3 at a patch corner; the spout tip's true
        // maximum is about 3.434, which the 4 x 4 grid samples to within 0.02.
        let (lo, hi) = m.bounds();
        assert!((lo.x + 3.0).abs() < 1e-12, "{lo}");
        assert!(hi.x > 3.41 && hi.x < 3.435, "{hi}");
        assert!(
            lo.y.abs() < 1e-12 && (hi.y - 3.15).abs() < 1e-12,
            "{lo} {hi}"
        );
        assert!(
            (lo.z + 2.0).abs() < 1e-12 && (hi.z - 2.0).abs() < 1e-12,
            "{lo} {hi}"
        );
        let fine = build(&MeshSpec::Teapot {
            subdivisions: 16,
            uv_repeat: [2.0, 3.0],
        });
        fine.validate("mesh.Teapot").unwrap();
        check_frames(&fine, 1e-9, "teapot 16");
        let (_, hi) = fine.bounds();
        assert!(hi.x > 3.43 && hi.x < 3.435, "{hi}");
        assert_eq!(fine.triangles.len(), 32 * 16 * 16 * 2 - 8 * 16);
        // uv_repeat divides the derivatives: compare with the unit-repeat build.
        let unit = build(&MeshSpec::Teapot {
            subdivisions: 16,
            uv_repeat: [1.0, 1.0],
        });
        for (a, b) in unit.vertices.iter().zip(&fine.vertices).step_by(97) {
            assert_eq!(a.pos, b.pos);
            assert!((a.pu / 2.0 - b.pu).length() < 1e-12 && (a.pv / 3.0 - b.pv).length() < 1e-12);
            assert_eq!(a.uv * DVec2::new(2.0, 3.0), b.uv);
        }
    }

    #[test]
    fn teapot_derivatives_match_finite_differences() {
        for (k, indices) in TEAPOT_PATCHES.iter().enumerate().step_by(5) {
            let mut cp = [[DVec3::ZERO; 4]; 4];
            for (c, &idx) in indices.iter().enumerate() {
                cp[c / 4][c % 4] = DVec3::from(TEAPOT_VERTICES[idx as usize]);
            }
            let p = Patch { cp };
            let h = 1e-6;
            for (u, v) in [(0.3, 0.6), (0.9, 0.1), (0.5, 0.5)] {
                let (_, pu, pv, puv) = p.eval(u, v);
                let du = (p.eval(u + h, v).0 - p.eval(u - h, v).0) / (2.0 * h);
                let dv = (p.eval(u, v + h).0 - p.eval(u, v - h).0) / (2.0 * h);
                let duv = (p.eval(u + h, v).2 - p.eval(u - h, v).2) / (2.0 * h);
                assert!((du - pu).length() < 1e-7, "patch {k}");
                assert!((dv - pv).length() < 1e-7, "patch {k}");
                assert!((duv - puv).length() < 1e-7, "patch {k}");
            }
        }
    }

    fn vertex(pos: DVec3, uv: DVec2) -> Vertex {
        Vertex {
            pos,
            normal: DVec3::Z,
            uv,
            pu: DVec3::X,
            pv: DVec3::Y,
        }
    }

    fn triangle_mesh() -> Mesh {
        Mesh {
            vertices: vec![
                vertex(DVec3::ZERO, DVec2::ZERO),
                vertex(DVec3::X, DVec2::X),
                vertex(DVec3::Y, DVec2::Y),
            ],
            triangles: vec![[0, 1, 2]],
        }
    }

    fn expect_invalid(m: &Mesh, needle: &str) {
        match m.validate("mesh.test") {
            Err(SceneError::Invalid { field, message }) => {
                assert_eq!(field, "mesh.test");
                assert!(
                    message.contains(needle),
                    "{message:?} should mention {needle:?}"
                );
            }
            other => panic!("expected an error mentioning {needle:?}, got {other:?}"),
        }
    }

    #[test]
    fn validate_rejects_bad_meshes() {
        assert!(triangle_mesh().validate("mesh.test").is_ok());
        let mut m = triangle_mesh();
        m.vertices[1].pos.y = f64::NAN;
        expect_invalid(&m, "vertex 1: non-finite position");
        let mut m = triangle_mesh();
        m.vertices[2].pv.x = f64::INFINITY;
        expect_invalid(&m, "vertex 2: non-finite pv");
        let mut m = triangle_mesh();
        m.vertices[0].normal = DVec3::ZERO;
        expect_invalid(&m, "vertex 0: expected a unit normal");
        let mut m = triangle_mesh();
        m.vertices[2].pos = DVec3::new(2.0, 0.0, 0.0); // collinear
        expect_invalid(&m, "triangle 0: degenerate (zero area)");
        let mut m = triangle_mesh();
        m.vertices[2].uv = DVec2::new(2.0, 0.0); // collinear in uv
        expect_invalid(&m, "triangle 0: degenerate texture coordinates");
        let mut m = triangle_mesh();
        m.triangles.push([0, 2, 3]);
        expect_invalid(&m, "triangle 1: vertex index 3 out of range");
        let mut m = triangle_mesh();
        m.triangles.clear();
        expect_invalid(&m, "at least one triangle");
        assert_eq!(Mesh::default().bounds(), (DVec3::ZERO, DVec3::ZERO));
    }

    #[test]
    fn invalid_parameters_name_the_field() {
        let cases = [
            (
                MeshSpec::Quad {
                    size: 0.0,
                    uv_repeat: [1.0, 1.0],
                    subdivisions: 1,
                },
                "mesh.Quad.size",
            ),
            (
                MeshSpec::Quad {
                    size: 1.0,
                    uv_repeat: [1.0, 1.0],
                    subdivisions: 0,
                },
                "mesh.Quad.subdivisions",
            ),
            (
                MeshSpec::Quad {
                    size: 1.0,
                    uv_repeat: [1.0, f64::NAN],
                    subdivisions: 1,
                },
                "mesh.Quad.uv_repeat[1]",
            ),
            (
                MeshSpec::Sphere {
                    radius: 1.0,
                    slices: 2,
                    stacks: 4,
                    uv_repeat: [1.0, 1.0],
                },
                "mesh.Sphere.slices",
            ),
            (
                MeshSpec::Sphere {
                    radius: 1.0,
                    slices: 8,
                    stacks: 1,
                    uv_repeat: [1.0, 1.0],
                },
                "mesh.Sphere.stacks",
            ),
            (
                MeshSpec::Sphere {
                    radius: -1.0,
                    slices: 8,
                    stacks: 4,
                    uv_repeat: [1.0, 1.0],
                },
                "mesh.Sphere.radius",
            ),
            (
                MeshSpec::Torus {
                    major: 1.0,
                    minor: 1.0,
                    slices: 8,
                    rings: 8,
                    uv_repeat: [1.0, 1.0],
                },
                "mesh.Torus.major",
            ),
            (
                MeshSpec::Torus {
                    major: 2.0,
                    minor: 1.0,
                    slices: 8,
                    rings: 0,
                    uv_repeat: [1.0, 1.0],
                },
                "mesh.Torus.rings",
            ),
            (
                MeshSpec::Cylinder {
                    radius: 1.0,
                    height: 0.0,
                    slices: 8,
                    stacks: 1,
                    uv_repeat: [1.0, 1.0],
                },
                "mesh.Cylinder.height",
            ),
            (
                MeshSpec::Cylinder {
                    radius: 1.0,
                    height: 1.0,
                    slices: 8,
                    stacks: 0,
                    uv_repeat: [1.0, 1.0],
                },
                "mesh.Cylinder.stacks",
            ),
            (
                MeshSpec::Teapot {
                    subdivisions: 0,
                    uv_repeat: [1.0, 1.0],
                },
                "mesh.Teapot.subdivisions",
            ),
            (
                MeshSpec::Teapot {
                    subdivisions: 65,
                    uv_repeat: [1.0, 1.0],
                },
                "mesh.Teapot.subdivisions",
            ),
            (
                MeshSpec::Teapot {
                    subdivisions: 4,
                    uv_repeat: [-1.0, 1.0],
                },
                "mesh.Teapot.uv_repeat[0]",
            ),
        ];
        for (spec, field) in cases {
            match spec.build(Path::new(".")) {
                Err(SceneError::Invalid { field: f, message }) => {
                    assert_eq!(f, field, "{spec:?}: {message}")
                }
                other => panic!("{spec:?}: expected an error on {field}, got {other:?}"),
            }
        }
    }

    /// A fresh, empty directory (removed when dropped).
    fn temp_dir() -> crate::scratch::Scratch {
        crate::scratch::Scratch::dir()
    }

    #[test]
    fn obj_loading() {
        let dir = temp_dir();
        // A unit square in z = 0 made of two triangles, no normals; u along +x, v along +y
        // scaled by 2 in the file (vt runs 0..2 in v over 1 unit of y).
        let obj = "o square\n\
                   v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
                   vt 0 0\nvt 1 0\nvt 1 2\nvt 0 2\n\
                   f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
        std::fs::write(dir.join("square.obj"), obj).unwrap();
        let m = MeshSpec::Obj {
            path: "square.obj".into(),
            uv_repeat: [3.0, 1.0],
            atlas: false,
        }
        .build(&dir)
        .unwrap();
        assert_eq!((m.vertices.len(), m.triangles.len()), (4, 2));
        for v in &m.vertices {
            assert_eq!(v.normal, DVec3::Z);
            // u = 3x: ∂P/∂u = x/3; v = 2y: ∂P/∂v = y/2.
            assert!(
                (v.pu - DVec3::new(1.0 / 3.0, 0.0, 0.0)).length() < 1e-12,
                "{v:?}"
            );
            assert!((v.pv - DVec3::new(0.0, 0.5, 0.0)).length() < 1e-12, "{v:?}");
            assert_eq!(v.uv, DVec2::new(3.0 * v.pos.x, 2.0 * v.pos.y));
        }

        // A quad face with normals (triangulated), and a UV seam sharing positions.
        let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 1\n\
                   vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0\nvt 1 0.5\n\
                   vn 0 0 2\n\
                   f 1/1/1 2/2/1 3/3/1 4/4/1\n";
        std::fs::write(dir.join("quad.obj"), obj).unwrap();
        let m = MeshSpec::Obj {
            path: "quad.obj".into(),
            uv_repeat: [1.0, 1.0],
            atlas: false,
        }
        .build(&dir)
        .unwrap();
        assert_eq!((m.vertices.len(), m.triangles.len()), (4, 2));
        assert!(m.vertices.iter().all(|v| v.normal == DVec3::Z));

        // Bent strip without normals: two faces meeting at an edge; the shared vertices get
        // the normalised sum of the area-weighted face normals.
        let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 2 0 1\n\
                   vt 0 0\nvt 1 0\nvt 1 1\nvt 2 0\n\
                   f 1/1 2/2 3/3\nf 2/2 4/4 3/3\n";
        std::fs::write(dir.join("bent.obj"), obj).unwrap();
        let m = MeshSpec::Obj {
            path: "bent.obj".into(),
            uv_repeat: [1.0, 1.0],
            atlas: false,
        }
        .build(&dir)
        .unwrap();
        let n1 = DVec3::new(0.0, 0.0, 1.0); // face 1, area 0.5, 2A n = (0,0,1)
        let n2 = (DVec3::new(1.0, 0.0, 1.0)).cross(DVec3::new(0.0, 1.0, 0.0)); // face 2
        let shared = (n1 + n2).normalize();
        let v2 = m.vertices.iter().find(|v| v.pos == DVec3::X).unwrap();
        assert!((v2.normal - shared).length() < 1e-12, "{v2:?} vs {shared}");
    }

    #[test]
    fn obj_errors_name_the_path() {
        let dir = temp_dir();
        let missing = dir.join("nope.obj");
        let spec = |p: &str| MeshSpec::Obj {
            path: p.into(),
            uv_repeat: [1.0, 1.0],
            atlas: false,
        };
        match spec("nope.obj").build(&dir) {
            Err(SceneError::File { path, .. }) => assert_eq!(path, missing.display().to_string()),
            other => panic!("expected a file error, got {other:?}"),
        }
        std::fs::write(
            dir.join("garbage.obj"),
            [0xffu8, 0xfe, 0x00, 0x13, 0x80, 0x81],
        )
        .unwrap();
        match spec("garbage.obj").build(&dir) {
            Err(SceneError::File { path, message }) => {
                assert_eq!(
                    path,
                    dir.join("garbage.obj").display().to_string(),
                    "{message}"
                )
            }
            other => panic!("expected a file error, got {other:?}"),
        }
        std::fs::write(dir.join("text.obj"), "this is not\nan obj file\n").unwrap();
        assert!(matches!(
            spec("text.obj").build(&dir),
            Err(SceneError::File { .. })
        ));
        // No texture coordinates.
        std::fs::write(dir.join("nouv.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        match spec("nouv.obj").build(&dir) {
            Err(SceneError::File { message, .. }) => {
                assert!(message.contains("texture"), "{message}")
            }
            other => panic!("expected a file error, got {other:?}"),
        }
        // A file of only degenerate triangles is reported against the file (they are dropped:
        // docs/assets.md).
        std::fs::write(
            dir.join("flat.obj"),
            "v 0 0 0\nv 1 0 0\nv 2 0 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n",
        )
        .unwrap();
        match spec("flat.obj").build(&dir) {
            Err(SceneError::File { path, message }) => {
                assert!(path.ends_with("flat.obj"));
                assert!(message.contains("non-zero area"), "{message}");
            }
            other => panic!("expected a file error, got {other:?}"),
        }
    }

    #[test]
    fn serde_shape() {
        let spec = MeshSpec::Sphere {
            radius: 1.0,
            slices: 16,
            stacks: 8,
            uv_repeat: [4.0, 2.0],
        };
        let json = serde_json::to_string(&spec).unwrap();
        assert_eq!(
            json,
            r#"{"Sphere":{"radius":1.0,"slices":16,"stacks":8,"uv_repeat":[4.0,2.0]}}"#
        );
        assert_eq!(serde_json::from_str::<MeshSpec>(&json).unwrap(), spec);
        let bad = r#"{"Sphere":{"radius":1.0,"slices":16,"stacks":8,"uv_repeat":[4.0,2.0],"r":1}}"#;
        assert!(serde_json::from_str::<MeshSpec>(bad).is_err());
    }
}
