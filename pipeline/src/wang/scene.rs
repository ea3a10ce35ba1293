//! A baked mesh as a scene mesh (`MeshSpec::Baked` in a config): the detailed mesh loaded,
//! simplified, packed and baked (this module's parent), then given to the engines as the
//! simplified mesh with one vertex per face corner at its patch's texture coordinates and the
//! map as a tangent-space normal map (`bump: Baked`).
//!
//! **Face space** (Wang et al. §3): "we transform all normal vectors within a triangle patch of
//! the normal map into a local face space, whose z-axis is the same direction as normal
//! vector of the triangle", so that z >= 0 and a SIGNED_HILO16 texture can hold them. Here the
//! face's frame is the one every engine and the reference build from a vertex's normal, `Pu`
//! and `Pv` ([`tangent_frame`]): the vertices of a face carry the face's normal, and `Pu`,
//! `Pv` of its patch's texture mapping, so `x` lies along the patch's `u` edge; a texel `t`
//! holds `(n.T, n.B, n.N)` of the baked normal `n`, and the engines' `T t.x + B t.y + N t.z`
//! gives back `n` exactly at texel centres. Texels outside every square hold `(0, 0, 1)`.

use crate::memo::Memo;
use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::sync::Arc;

use super::bake::{BakeConfig, Baker, Buffer};
use super::simplify::simplify;
use super::views::{directions, MAX_VIEWS};
use super::Surface;
use crate::scene::mesh::{Mesh, Vertex};
use crate::scene::normals::NormalMap;
use crate::scene::perturb::tangent_frame;
use crate::scene::SceneError;

/// The parameters of `MeshSpec::Baked` (documented in docs/configs.md; the config's
/// variant is deserialised there).
#[derive(Debug, Clone, PartialEq)]
pub struct BakeSpec {
    pub path: String,
    pub faces: usize,
    pub map_size: u32,
    pub widen: u32,
    pub views: usize,
    pub view_size: u32,
    pub threshold: f64,
    pub buffer: Buffer,
    pub pairs: bool,
    /// Measure the bake against the detailed mesh (`BakeStats::evaluation`).
    pub evaluate: Option<Evaluate>,
}

/// The bake's measure of Wang et al. §5 (`MeshSpec::Baked`'s `evaluate`): 30 views on a
/// golden-angle spiral (none a baking view, `super::views::evaluation`), `size` pixels a
/// side, orthographic; per pixel covered by both meshes, the detailed mesh's interpolated
/// normal against the map's bilinear value on the simplified mesh, the map stored at `bits`
/// bits a component (`None`: f64).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Evaluate {
    /// Side of each evaluation view, 16 to 4096 pixels. Default 512.
    #[serde(default = "default_eval_size")]
    pub size: u32,
    /// Bits a component of the stored map, 2 to 16, or `None` (f64). Default `Some(16)`.
    #[serde(default = "default_eval_bits")]
    pub bits: Option<u32>,
}

fn default_eval_size() -> u32 {
    512
}

fn default_eval_bits() -> Option<u32> {
    Some(16)
}

/// The measure's figures (`super::evaluate::ViewError`, the mean over the views).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BakeEvaluation {
    pub views: usize,
    pub size: u32,
    /// Mean normal error in 8-bit colour steps, both normals quantised to 8 bits (the
    /// paper's "quantized to 8 bit, average vector difference"; 0 to 441).
    pub normal8: f64,
    /// The same, unquantised (`127.5 |n_o - n_m|`).
    pub normal: f64,
    /// Mean depth difference over the detailed mesh's bounding radius.
    pub distance: f64,
    /// Pixels covered by both meshes, over all views.
    pub pixels: usize,
}

/// What a bake did, for reports and studies.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct BakeStats {
    pub detailed_faces: usize,
    pub faces: usize,
    pub samples: usize,
    /// Samples some view replaced (the others keep the interpolated normal).
    pub updated: usize,
    /// `updated / samples`: the share of the map the views saw.
    pub updated_share: f64,
    /// Samples whose face-space normal points away from the face (z < 0).
    pub below: usize,
    /// With `evaluate`: the bake measured against the detailed mesh.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub evaluation: Option<BakeEvaluation>,
}

/// Largest map side of a baked mesh in a config.
pub const MAX_MAP: u32 = 4096;
/// Largest side of a baking view in a config.
pub const MAX_VIEW: u32 = 4096;

/// Load `base_dir/path`, simplify, pack and bake; the simplified mesh and the face-space map.
pub fn build(spec: &BakeSpec, base_dir: &Path) -> Result<(Mesh, NormalMap, BakeStats), SceneError> {
    let field = |f: &str| format!("mesh.Baked.{f}");
    let bad = |f: &str, m: String| SceneError::invalid(field(f), m);
    if spec.views > MAX_VIEWS.min(64) {
        return Err(bad(
            "views",
            format!(
                "expected 0 (the initialisation alone) to 64 views, found {}",
                spec.views
            ),
        ));
    }
    if let Some(e) = spec.evaluate {
        if !(16..=MAX_VIEW).contains(&e.size) {
            return Err(bad(
                "evaluate.size",
                format!("expected 16 to {MAX_VIEW} pixels, found {}", e.size),
            ));
        }
        if e.bits.is_some_and(|b| !(2..=16).contains(&b)) {
            return Err(bad(
                "evaluate.bits",
                format!("expected None or 2 to 16 bits, found {:?}", e.bits),
            ));
        }
    }
    if spec.map_size > MAX_MAP {
        return Err(bad(
            "map_size",
            format!("expected at most {MAX_MAP} texels, found {}", spec.map_size),
        ));
    }
    if spec.view_size > MAX_VIEW {
        return Err(bad(
            "view_size",
            format!(
                "expected at most {MAX_VIEW} pixels, found {}",
                spec.view_size
            ),
        ));
    }
    let cfg = BakeConfig {
        map_size: spec.map_size,
        widen: spec.widen,
        view_size: spec.view_size,
        threshold: spec.threshold,
        buffer: spec.buffer,
        pairs: spec.pairs,
    };
    cfg.validate().map_err(|m| {
        let (f, rest) = m.split_once(": ").unwrap_or(("", &m));
        bad(f, rest.to_string())
    })?;
    let full = base_dir.join(&spec.path);
    // the file is read once here (and so accounted once in the scene's key), whether the
    // bake is found or made
    let bytes = Surface::read(&full)?;
    let digest: [u64; 2] = std::array::from_fn(|pass| {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        (pass as u64, &bytes).hash(&mut h);
        h.finish()
    });
    let key = (format!("{spec:?} {}", full.display()), digest);
    let mut failed = None;
    let found = BAKES.get_or_build(key, || match bake(spec, cfg, &full, &bytes) {
        Ok(b) => Some(Arc::new(b)),
        Err(e) => {
            failed = Some(e);
            None
        }
    });
    match (found, failed) {
        (Some(b), _) => Ok((*b).clone()),
        (None, Some(e)) => Err(e),
        // a failed bake kept by an earlier call: make it again for its message
        (None, None) => bake(spec, cfg, &full, &bytes),
    }
}

type Baked = (Mesh, NormalMap, BakeStats);

/// The bakes of this process (`crate::memo`: a sweep's points that differ in their engine
/// only share one bake), by the spec, the mesh file's path and a digest of its bytes; at most
/// four, and only while their maps hold 64 M texels together. A failed bake is kept as None.
static BAKES: Memo<(String, [u64; 2]), Option<Arc<Baked>>> =
    Memo::weighed(4, 1 << 26, |b| b.as_ref().map_or(0, |b| b.1.texels.len()));

/// The mesh files baked so far (for the tests: a bake found is not made again).
#[cfg(test)]
static MADE: std::sync::Mutex<Vec<std::path::PathBuf>> = std::sync::Mutex::new(Vec::new());

/// [`build`] after the checks: load the bytes of `full`, simplify, pack and bake.
fn bake(spec: &BakeSpec, cfg: BakeConfig, full: &Path, bytes: &[u8]) -> Result<Baked, SceneError> {
    let field = |f: &str| format!("mesh.Baked.{f}");
    let bad = |f: &str, m: String| SceneError::invalid(field(f), m);
    // load, simplify, one step per view, and the face-space conversion
    let progress = crate::progress::bar(spec.views as u64 + 3, &format!("baking {}", spec.path));
    progress.set_message("loading");
    #[cfg(test)]
    MADE.lock()
        .unwrap_or_else(|p| p.into_inner())
        .push(full.to_path_buf());
    let detailed = Surface::from_bytes(full, bytes)?;
    progress.inc(1);
    progress.set_message(format!("simplifying {} faces", detailed.triangles.len()));
    let simple = simplify(&detailed, spec.faces).map_err(|m| bad("faces", m))?;
    progress.inc(1);
    let s = &simple.surface;
    let mut baker = Baker::new(&detailed, s, cfg).map_err(|m| {
        let f = if m.contains("widening") && !m.contains("map") {
            "widen"
        } else {
            "map_size"
        };
        bad(f, m)
    })?;
    for (k, d) in directions(spec.views).into_iter().enumerate() {
        progress.set_message(format!("view {} of {}", k + 1, spec.views));
        baker.add_view(d);
        progress.inc(1);
    }
    let evaluation = spec.evaluate.map(|e| {
        progress.set_message("evaluating");
        let dirs = super::views::evaluation();
        let ev = super::evaluate::Evaluation::new(&detailed, s, &dirs, e.size);
        let m = super::evaluate::mean(&ev.errors(&detailed, &baker.packing, &baker.map(e.bits)));
        BakeEvaluation {
            views: dirs.len(),
            size: e.size,
            normal8: m.normal8,
            normal: m.normal,
            distance: m.distance,
            pixels: m.pixels,
        }
    });
    progress.set_message("face space");
    let mesh = face_mesh(s, &baker.packing.uv);
    let (texels, below) = face_space(&baker, &mesh);
    let stats = BakeStats {
        detailed_faces: detailed.triangles.len(),
        faces: s.triangles.len(),
        samples: baker.sample_count(),
        updated: baker.updated(),
        updated_share: baker.updated() as f64 / baker.sample_count().max(1) as f64,
        below,
        evaluation,
    };
    let map = NormalMap {
        width: spec.map_size,
        height: spec.map_size,
        texels,
    };
    Ok((mesh, map, stats))
}

/// One vertex per face corner: the face's normal, its patch's texture coordinates, `Pu`,
/// `Pv` of the patch's mapping.
pub fn face_mesh(s: &Surface, uv: &[[DVec2; 3]]) -> Mesh {
    let mut mesh = Mesh::default();
    for (f, t) in uv.iter().enumerate() {
        let p = s.corners(f);
        let n = s.face_normal(f);
        let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
        let (d1, d2) = (t[1] - t[0], t[2] - t[0]);
        let det = d1.perp_dot(d2);
        let (pu, pv) = if det == 0.0 {
            (e1, e2)
        } else {
            ((e1 * d2.y - e2 * d1.y) / det, (e2 * d1.x - e1 * d2.x) / det)
        };
        let base = mesh.vertices.len() as u32;
        for i in 0..3 {
            mesh.vertices.push(Vertex {
                pos: p[i],
                normal: n,
                uv: t[i],
                pu,
                pv,
            });
        }
        mesh.triangles.push([base, base + 1, base + 2]);
    }
    mesh
}

/// The baked normals in each texel's face frame (see the module), and how many point below
/// their face.
pub(crate) fn face_space(baker: &Baker<'_>, mesh: &Mesh) -> (Vec<DVec3>, usize) {
    let mut below = 0;
    let texels = baker
        .samples
        .iter()
        .zip(&baker.normals)
        .map(|(s, &n)| {
            let Some((s, _)) = s else { return DVec3::Z };
            let v = mesh.vertices[3 * s.face as usize];
            let (t, b) = tangent_frame(v.normal, v.pu, v.pv);
            let local = DVec3::new(n.dot(t), n.dot(b), n.dot(v.normal)).normalize_or(DVec3::Z);
            below += usize::from(local.z < 0.0);
            local
        })
        .collect();
    (texels, below)
}

#[cfg(test)]
mod memo_tests {
    use super::*;

    /// A bake of the same spec and the same file's bytes is made once per process; a change
    /// of the bytes (a comment appended) or of the spec makes it again.
    #[test]
    fn a_bake_is_made_once_per_spec_and_mesh_bytes() {
        let dir = crate::scratch::Scratch::dir();
        let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("../configs/assets/bunny.obj");
        let mesh = dir.join("bunny.obj");
        std::fs::copy(&assets, &mesh).unwrap();
        let spec = BakeSpec {
            path: "bunny.obj".into(),
            faces: 200,
            map_size: 64,
            widen: 1,
            views: 2,
            view_size: 64,
            threshold: 0.8,
            buffer: Buffer::Item,
            pairs: true,
            evaluate: None,
        };
        let made = || {
            let m = MADE.lock().unwrap_or_else(|p| p.into_inner());
            m.iter().filter(|p| **p == mesh).count()
        };
        let first = build(&spec, &dir).unwrap();
        let again = build(&spec, &dir).unwrap();
        assert_eq!(made(), 1);
        assert_eq!(first.0.triangles, again.0.triangles);
        assert_eq!(first.1, again.1);
        assert_eq!(first.2, again.2);
        let mut bytes = std::fs::read(&mesh).unwrap();
        bytes.extend_from_slice(b"# a comment\n");
        std::fs::write(&mesh, bytes).unwrap();
        let changed = build(&spec, &dir).unwrap();
        assert_eq!(made(), 2);
        assert_eq!(changed.1, first.1, "the same mesh bakes the same map");
        let wider = BakeSpec {
            views: 3,
            ..spec.clone()
        };
        build(&wider, &dir).unwrap();
        assert_eq!(made(), 3);
        // a failed bake is an error each time, with its message
        let few = BakeSpec { faces: 1, ..spec };
        for _ in 0..2 {
            let e = build(&few, &dir).unwrap_err().to_string();
            assert!(e.contains("faces"), "{e}");
        }
    }
}
