//! Scenes: meshes with tangent frames, bump maps (height fields and normal maps), lights,
//! camera and material. Knows nothing of hardware units.

pub mod atlas;
pub mod bake;
pub mod bumpmap;
pub mod camera;
pub mod centre_grads;
pub mod files;
pub mod lathe;
pub mod material;
pub mod mesh;
pub mod normals;
pub mod obj;
pub mod perturb;
pub mod ply;
pub mod shapes;

use glam::{DMat4, DVec3};
use serde::{Deserialize, Serialize};

pub use bumpmap::{BumpMap, BumpSpec, HeightField};
pub use camera::Camera;
pub use material::{Coord, EnvImage, Looks, Material, RegionRule, Regions, Shading};
pub use mesh::{Mesh, Vertex};
pub use normals::{NormalMap, NormalMethod};
pub use shapes::MeshSpec;

/// Largest magnitude of a coordinate in a config (positions, directions, camera, model
/// translation, clip distances): 1e12, so that squares and products of two coordinates
/// (normalisation, the view and projection matrices) stay far from the f64 range.
pub const MAX_COORD: f64 = 1e12;

/// Largest number of lights of a scene (each adds a clock to a light combiner's interval and a
/// term to every shaded sample).
pub const MAX_LIGHTS: usize = 16;

/// A reason a scene cannot be built. Each names the field or file and what was expected.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("{field}: {message}")]
    Invalid { field: String, message: String },
    #[error("{path}: {message}")]
    File { path: String, message: String },
}

impl SceneError {
    pub fn invalid(field: impl Into<String>, message: impl Into<String>) -> Self {
        SceneError::Invalid {
            field: field.into(),
            message: message.into(),
        }
    }
    pub fn file(path: impl std::fmt::Display, message: impl Into<String>) -> Self {
        SceneError::File {
            path: path.to_string(),
            message: message.into(),
        }
    }
}

/// A light. Directions point from the surface toward the light (OpenGL convention).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Light {
    pub kind: LightKind,
    /// Linear RGB colour, each component in [0, 1].
    pub color: [f64; 3],
    /// Whether the bump engine shades with this light. A light with `bump: false` only
    /// contributes to the per-vertex Gouraud colour (Gouraud bump paper §5.4.1, Fig. 6).
    #[serde(default = "yes")]
    pub bump: bool,
}

fn yes() -> bool {
    true
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum LightKind {
    /// A distant light; `dir` points toward the light, in world space.
    Directional { dir: [f64; 3] },
    /// A point light at `pos`, in world space.
    Point { pos: [f64; 3] },
    /// An OpenGL spot light at `pos` shining along `dir`: no light outside the cone of
    /// half-angle `cutoff_deg`, `cos^exponent` of the angle off the axis inside it.
    Spot {
        pos: [f64; 3],
        dir: [f64; 3],
        cutoff_deg: f64,
        exponent: f64,
    },
}

impl Light {
    /// Unit vector from `p` toward the light.
    pub fn dir_from(&self, p: DVec3) -> DVec3 {
        match self.kind {
            LightKind::Directional { dir } => DVec3::from(dir).normalize(),
            LightKind::Point { pos } | LightKind::Spot { pos, .. } => {
                (DVec3::from(pos) - p).normalize()
            }
        }
    }
    /// Spot attenuation at `p` (OpenGL's spot factor): 1 for directional and point lights.
    pub fn attenuation(&self, p: DVec3) -> f64 {
        match self.kind {
            LightKind::Spot {
                pos,
                dir,
                cutoff_deg,
                exponent,
            } => {
                let c = (p - DVec3::from(pos))
                    .normalize_or_zero()
                    .dot(DVec3::from(dir).normalize_or_zero());
                if c < cutoff_deg.to_radians().cos() {
                    0.0
                } else {
                    c.max(0.0).powf(exponent)
                }
            }
            _ => 1.0,
        }
    }
    pub fn color(&self) -> DVec3 {
        DVec3::from(self.color)
    }
    /// Check a light from a config: finite, non-zero direction, colour in [0, 1].
    pub fn validate(&self, field: &str) -> Result<(), SceneError> {
        match self.kind {
            LightKind::Directional { dir } => {
                check_dir(field, dir)?;
            }
            LightKind::Point { pos } => check_pos(field, pos)?,
            LightKind::Spot {
                pos,
                dir,
                cutoff_deg,
                exponent,
            } => {
                check_pos(field, pos)?;
                check_dir(field, dir)?;
                if !(cutoff_deg > 0.0 && cutoff_deg <= 90.0) {
                    return Err(SceneError::invalid(
                        format!("{field}.kind.cutoff_deg"),
                        format!("expected an angle in (0, 90] degrees, found {cutoff_deg}"),
                    ));
                }
                if !(exponent.is_finite() && exponent >= 0.0) {
                    return Err(SceneError::invalid(
                        format!("{field}.kind.exponent"),
                        format!("expected a finite number >= 0, found {exponent}"),
                    ));
                }
            }
        }
        for (i, c) in self.color.iter().enumerate() {
            if !(0.0..=1.0).contains(c) {
                return Err(SceneError::invalid(
                    format!("{field}.color[{i}]"),
                    format!("expected a value in [0, 1], found {c}"),
                ));
            }
        }
        Ok(())
    }
}

/// An integer parameter in `lo..=hi`, shared by the scene builders' checks.
pub(crate) fn check_count(field: String, x: u32, lo: u32, hi: u32) -> Result<(), SceneError> {
    if (lo..=hi).contains(&x) {
        Ok(())
    } else {
        Err(SceneError::invalid(
            field,
            format!("expected an integer in {lo}..={hi}, found {x}"),
        ))
    }
}

fn check_pos(field: &str, pos: [f64; 3]) -> Result<(), SceneError> {
    if !DVec3::from(pos).is_finite() {
        return Err(SceneError::invalid(
            format!("{field}.kind.pos"),
            format!("expected a finite position, found {pos:?}"),
        ));
    }
    check_coords(&format!("{field}.kind.pos"), pos)
}

/// Every coordinate within ±[`MAX_COORD`].
fn check_coords(field: &str, v: [f64; 3]) -> Result<(), SceneError> {
    match v.iter().find(|x| x.abs() > MAX_COORD) {
        Some(x) => Err(SceneError::invalid(
            field,
            format!(
                "coordinate {x:e} is out of range: expected each coordinate within ±{MAX_COORD:e} \
                 (larger values overflow when the vector is normalised)"
            ),
        )),
        None => Ok(()),
    }
}

/// A light direction: finite, each coordinate within ±[`MAX_COORD`], non-zero (length at
/// least 1e-12), so that normalising it neither overflows (a direction of 1e154 has an
/// infinite length and normalised to nothing) nor divides by zero.
fn check_dir(field: &str, dir: [f64; 3]) -> Result<(), SceneError> {
    let d = DVec3::from(dir);
    let f = format!("{field}.kind.dir");
    if !d.is_finite() {
        return Err(SceneError::invalid(
            f,
            format!("expected a finite non-zero direction, found {dir:?}"),
        ));
    }
    check_coords(&f, dir)?;
    if d.length() < 1e-12 {
        return Err(SceneError::invalid(
            f,
            format!("expected a finite non-zero direction (length at least 1e-12), found {dir:?}"),
        ));
    }
    Ok(())
}

/// A built scene, ready for the rasterizer, the engines and the float reference.
pub struct Scene {
    pub mesh: Mesh,
    /// Object-to-world transform.
    pub model: DMat4,
    pub camera: Camera,
    pub lights: Vec<Light>,
    /// Material 0.
    pub material: Material,
    /// Materials 1.. and their regions, and the environment maps of all materials.
    pub looks: Looks,
    pub bump: BumpMap,
    /// What the bake of a `MeshSpec::Baked` mesh did (Wang et al.; `None` for other meshes).
    pub bake: Option<crate::wang::scene::BakeStats>,
    /// Optional colour texture (linear RGB, rows top to bottom, u right, v down).
    pub color_texture: Option<image::RgbImage>,
    pub width: u32,
    pub height: u32,
    /// Digests of what the scene was built from, under which results computed from it are
    /// shared (`crate::memo`); None: never shared.
    pub key: Option<SceneKey>,
}

/// What a scene was built from (`run::build_scene`): digests of its config, the config's
/// directory and the bytes of every file read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SceneKey {
    /// The whole scene.
    pub scene: [u64; 2],
    /// What the bump map depends on: its spec and the mesh's (a `Baked` map is the mesh's).
    pub bump: [u64; 2],
}

impl Scene {
    /// Light `light`, or the error a texture source that names a light the scene lacks gives.
    pub fn light(&self, light: usize) -> Result<&Light, String> {
        self.lights.get(light).ok_or_else(|| {
            format!(
                "light {light}: the scene has {} lights: expected an index below that",
                self.lights.len()
            )
        })
    }
    /// The material id at a surface point: texture coordinates `uv`, world-space perturbed
    /// normal `n` (taken back to object space by the transpose of the model's 3x3 part).
    pub fn material_id(&self, uv: glam::DVec2, n: DVec3) -> u8 {
        match &self.looks.regions {
            None => 0,
            Some(r) => {
                let n_obj =
                    (glam::DMat3::from_mat4(self.model).transpose() * n).normalize_or_zero();
                r.material_at(uv, n_obj)
            }
        }
    }
    /// Material `id` (0 is `material`; ids past the regions' list give material 0).
    pub fn material(&self, id: u8) -> &Material {
        match (&self.looks.regions, id) {
            (Some(r), 1..) => r.materials.get(id as usize - 1).unwrap_or(&self.material),
            _ => &self.material,
        }
    }
    /// Number of materials (1 without regions).
    pub fn material_count(&self) -> usize {
        1 + self.looks.regions.as_ref().map_or(0, |r| r.materials.len())
    }
}
