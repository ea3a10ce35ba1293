//! Pipeline configs: RON files that name a scene and wire hardware units into an engine.
//!
//! Unknown keys are rejected everywhere (`deny_unknown_fields` on every struct and on every
//! enum with struct variants, where serde's derive applies it to each variant; the unit specs'
//! own structs in `engine/units/`); number formats and sizes are checked while parsing, so
//! their errors carry the file, line and column; checks that span several fields (wiring,
//! light indices) run after parsing and name the field, and every number must be finite
//! ([`finite`]). `--set` overrides are applied to the parsed config (see [`overrides`]). The
//! config hash is the SHA-256 of the canonical RON serialisation of the final config.
//!
//! A config file is read whole, at most [`MAX_CONFIG_BYTES`], as UTF-8 (a byte-order mark at
//! the start is skipped); ranges of every field are listed in `docs/configs.md`.

pub mod error;
pub mod finite;
pub mod frames;
pub mod limits;
pub mod overrides;

use crate::engine::units::UnitSpec;
use crate::raster::RasterConfig;
use crate::scene::perturb::Perturbation;
use crate::scene::{BumpSpec, Camera, Light, Material, MeshSpec, Regions};
use bumpsim_hw::units::RopParams;
use bumpsim_hw::{CostTable, Encoding};
pub use error::{locate, InputError};
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Path, PathBuf};

/// Largest image side.
pub const MAX_IMAGE_SIDE: u32 = 16384;

/// Largest config file read, in bytes (16 MiB; the bundled configs are a few KiB).
pub const MAX_CONFIG_BYTES: usize = 16 << 20;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// Short name of the config, used in reports.
    pub name: String,
    #[serde(default)]
    pub description: String,
    pub scene: SceneConfig,
    #[serde(default)]
    pub raster: RasterConfig,
    #[serde(default)]
    pub reference: ReferenceConfig,
    pub engine: EngineConfig,
    #[serde(default)]
    pub sim: SimConfig,
    /// Overrides of the primitive gate costs (see docs/gates.md).
    #[serde(default)]
    pub cost: CostTable,
    /// A short animation: each entry is one more frame after the config itself, given as
    /// `--set` overrides of its per-frame inputs (lights, camera, material, model; see
    /// [`frames`] and docs/configs.md, "Frames"). Left out of the config hash when empty.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub frames: Vec<Vec<String>>,
}

/// An image side: 1 to 16384 pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "u32", into = "u32")]
pub struct Side(pub u32);

impl TryFrom<u32> for Side {
    type Error = String;
    fn try_from(v: u32) -> Result<Self, String> {
        if (1..=MAX_IMAGE_SIDE).contains(&v) {
            Ok(Side(v))
        } else {
            Err(format!(
                "image side {v}: expected 1 to {MAX_IMAGE_SIDE} pixels"
            ))
        }
    }
}

impl From<Side> for u32 {
    fn from(s: Side) -> u32 {
        s.0
    }
}

/// Object placement: scale, then rotations about x, y, z (degrees), then translation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Transform {
    pub translate: [f64; 3],
    pub rotate_deg: [f64; 3],
    pub scale: f64,
}

impl Default for Transform {
    fn default() -> Self {
        Transform {
            translate: [0.0; 3],
            rotate_deg: [0.0; 3],
            scale: 1.0,
        }
    }
}

impl Transform {
    pub fn matrix(&self) -> glam::DMat4 {
        let [rx, ry, rz] = self.rotate_deg.map(f64::to_radians);
        glam::DMat4::from_translation(self.translate.into())
            * glam::DMat4::from_rotation_z(rz)
            * glam::DMat4::from_rotation_y(ry)
            * glam::DMat4::from_rotation_x(rx)
            * glam::DMat4::from_scale(glam::DVec3::splat(self.scale))
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneConfig {
    pub width: Side,
    pub height: Side,
    pub mesh: MeshSpec,
    #[serde(default)]
    pub model: Transform,
    pub camera: Camera,
    pub lights: Vec<Light>,
    #[serde(default)]
    pub material: Material,
    /// More materials and where they go (Tarini §6); none: `material` everywhere.
    #[serde(default)]
    pub regions: Option<Regions>,
    pub bump: BumpSpec,
    /// Optional colour texture.
    #[serde(default)]
    pub color_texture: Option<TextureSpec>,
}

/// A colour texture.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum TextureSpec {
    /// An RGB PNG file, relative to the config file (PNG values are taken as linear).
    Png(String),
    /// A `size` x `size` checkerboard of `cells` x `cells` squares of colours `a` and `b`
    /// (e.g. the black-and-white texture of Ernst et al. Figs. 2 and 3).
    Checker {
        size: u32,
        cells: u32,
        a: [f64; 3],
        b: [f64; 3],
    },
}

impl TextureSpec {
    /// Build the texture image; errors are (file, message).
    pub fn build(&self, base_dir: &Path) -> Result<image::RgbImage, (String, String)> {
        match self {
            TextureSpec::Png(p) => {
                let path = base_dir.join(p);
                let max = crate::scene::files::MAX_PNG_SIDE;
                let img = crate::scene::files::read_png(&path, max).map_err(|e| match e {
                    crate::scene::SceneError::File { path, message } => (path, message),
                    e => (path.display().to_string(), e.to_string()),
                })?;
                Ok(img.to_rgb8())
            }
            TextureSpec::Checker { size, cells, a, b } => {
                if !(1..=4096).contains(size) || *cells == 0 || cells > size {
                    return Err((String::new(), format!("checker size {size} and cells {cells}: expected 1 <= cells <= size <= 4096")));
                }
                if a.iter().chain(b).any(|x| !(0.0..=1.0).contains(x)) {
                    return Err((
                        String::new(),
                        "checker colours: expected values in [0, 1]".into(),
                    ));
                }
                let q = |c: &[f64; 3]| image::Rgb(c.map(|x| (x * 255.0).round() as u8));
                Ok(image::RgbImage::from_fn(*size, *size, |x, y| {
                    let odd = (x * cells / size + y * cells / size) % 2 == 1;
                    if odd {
                        q(b)
                    } else {
                        q(a)
                    }
                }))
            }
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ReferenceConfig {
    pub perturbation: Perturbation,
    /// Shading samples per pixel side, 1 to 16 (`samples^2` per pixel, box filtered). 1, the
    /// default, shades the pixel centre; more approximate the band-limited image that a
    /// minified bump map (and an index mipmap, Tarini §5.2) should approach.
    pub samples: u32,
    /// `Some(t)`, 0 < t <= 1: the report's `highlight` section, the error and artifact
    /// figures over the pixels where the reference's Rec. 601 luma is at least `t`
    /// (`crate::highlight`, docs/metrics.md). Left out of the config hash when `None`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub highlight_luma: Option<f64>,
    /// `Some((tilt_deg: θ))` with the scene's `bump: Ndf(...)`: the report's `synthesis`
    /// section (the generated normals' fit to the NDF and the patch shading per level of
    /// detail at a half-way vector tilted by θ degrees, `crate::ndf::statistics`,
    /// docs/metrics.md). Left out of the config hash when `None`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub synthesis: Option<crate::ndf::statistics::SynthesisStats>,
}

impl Default for ReferenceConfig {
    fn default() -> Self {
        ReferenceConfig {
            perturbation: Perturbation::default(),
            samples: 1,
            highlight_luma: None,
            synthesis: None,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SimConfig {
    /// Depth of the FIFO between two units (1 to 64).
    pub fifo_depth: u32,
}

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig { fifo_depth: 2 }
    }
}

/// The frame a direction attribute is expressed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum VecFrame {
    /// The surface's tangent frame (T along Pu, B, N) at the vertex or centroid: the SGI
    /// engine's frame (Gouraud bump paper §3.4).
    Tangent,
    /// The object's own frame (world directions taken through the inverse model transform):
    /// the "bump vector space" of Gouraud bump mapping (§4), in which a bump map's Eq. 2
    /// normals are read as directions of a surface facing +z.
    Object,
    /// World space as it is (the frame the per-pixel engines of Ernst et al. §3.1, §3.2 and
    /// §3.5 light in: interpolated world normals, world L and H).
    World,
}

/// Which of Blinn's three axes a [`AttrSource::BlinnAxis`] carries (Ernst et al. §3.5: `-Pv
/// × N`, `-N × Pu`, `Pu × Pv`, the components of §2's final equation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Axis {
    /// The axis that multiplies `Fu`: `s (n̂ × Pv) / |Pu × Pv|`.
    Du,
    /// The axis that multiplies `Fv`: `s (Pu × n̂) / |Pu × Pv|`.
    Dv,
    /// The unperturbed normal `n̂` (`Pu × Pv` scaled to unit length; the smooth normal).
    N,
}

/// Where an attribute comes from. The geometry engine computes it in f64 and sends it to the
/// rasterizer in the attribute's encoding (that is what the packet counts): per vertex and
/// interpolated, or once per triangle (`per_triangle: true`, at the centroid) and held
/// constant over the triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum AttrSource {
    /// Texture coordinates (u, v).
    Uv,
    /// Unit direction toward light `light`.
    LightDir {
        light: usize,
        frame: VecFrame,
        #[serde(default)]
        per_triangle: bool,
    },
    /// Unit half vector of light `light` and the viewer (Ernst et al. §4.2: "H is constant
    /// within at least one triangle" when sent per triangle; §6: interpolated per vertex).
    HalfVec {
        light: usize,
        frame: VecFrame,
        #[serde(default)]
        per_triangle: bool,
    },
    /// The Gouraud colour (§4.2 C_src): the lights with `bump: false` (every light if
    /// `all_lights`) evaluated per vertex with the vertex normal (§5.4.1, Fig. 6), plus the
    /// material's ambient colour if `ambient`.
    Gouraud {
        ambient: bool,
        #[serde(default)]
        all_lights: bool,
    },
    /// A 1-lane blend switch sent with the Gouraud colour (Ernst et al. §4.2: "Both blending
    /// units can selectively be turned off ... according to the color information given in
    /// the interpolated Gouraud color fragment"): 1 at a vertex whose normal faces `light`,
    /// 0 elsewhere, interpolated; a blend unit with `selective: Enable` passes `C_src` through
    /// where it reads 0, so bumps do not light up beyond the shadow terminator. Which colour
    /// information drives the switch is bumpsim's choice; the paper does not say.
    BlendEnable { light: usize },
    /// Texture level of detail for a `size` x `size` texture, one lane, once per triangle:
    /// `lambda = 1/2 log2(texel area / pixel area)` of the triangle (its uv area times
    /// `size^2` over its screen area in pixels), clamped to `[0, log2 size]`; 0 for a
    /// triangle that crosses the eye plane or has no screen area. Per-triangle LOD is the
    /// cheapest scheme of the period (one value from the geometry engine, no per-pixel
    /// derivatives); it selects index mipmap levels (Tarini §5.2).
    Lod { size: u32 },
    /// Texture level of detail for a `size` x `size` texture per vertex, interpolated: at
    /// each vertex `1/2 log2(texel area / pixel area)` of the triangles around it (their uv
    /// areas times `size^2` summed, over their screen areas summed; triangles crossing the
    /// eye plane left out), clamped to `[0, log2 size]`, 0 where no triangle counts. A
    /// per-fragment LOD that is continuous across shared edges (the per-triangle `Lod` jumps
    /// there), and cheap: one value per vertex from the geometry engine, no per-pixel
    /// derivatives. Kautz et al. §5.1: "we adjust the number of used octaves depending on the
    /// distance d ... Whenever a new octave is added, it should be blended in smoothly".
    VertexLod { size: u32 },
    /// The smooth unit normal `n̂` in world space, per vertex: the interpolated `N_i` of the
    /// per-pixel engines (Ernst et al. §3.1 "the interpolated per vertex normal", §3.2).
    Normal,
    /// One of Blinn's axes per vertex in world space (Harmony, Ernst et al. §3.5: "simply
    /// interpolates the per vertex coordinate systems across the triangle"), built by `rule`
    /// (Blinn's `Pu`, `Pv`; or, for the scale-invariant rule, `Pu`, `Pv` scaled to unit
    /// length, which equals Lingard's `D'` where `Pu ⟂ Pv`). See `docs/units/perturb.md`.
    BlinnAxis {
        axis: Axis,
        #[serde(default)]
        rule: Perturbation,
    },
    /// A column of VISA+'s alignment matrix `A` (Ernst et al. §3.2: `N' = N + A V`, "A is
    /// calculated based on a local orthogonal coordinate system constructed by the local
    /// surface normal N and the texture coordinates of the triangle"), once per triangle:
    /// Blinn's `Du` (`column: Du`) or `Dv` axis of the triangle's own plane (its face normal
    /// and its `Pu`, `Pv` solved from its positions and texture coordinates), by `rule` as
    /// [`AttrSource::BlinnAxis`]; `column: N` is the face normal. A triangle without uv area
    /// falls back to its vertices' mean normal, `Pu` and `Pv`.
    Alignment {
        column: Axis,
        #[serde(default)]
        rule: Perturbation,
    },
    /// Texram's main direction `m` per vertex (Ernst et al. §3.1: "a direction m, which is,
    /// for example homogeneously interpolated over the triangle"): `Pu / |Pu|` in world space
    /// (the tangent frame's `T` where `Pu` is degenerate).
    MainDirection,
    /// The vertex's tangent frame `(T, n̂ × T, n̂)` as a unit quaternion `(x, y, z, w)` (VISA+
    /// with quaternions at the vertices, §3.2 last paragraph). Vertex quaternions are shared
    /// by triangles, so triangle setup negates a vertex's quaternion whose dot product with
    /// the triangle's first vertex's is negative (`q` and `-q` are one rotation; without this
    /// the interpolation would pass through zero).
    Quaternion,
    /// The 2x2 matrix `M` (`m00, m01, m10, m11`) per vertex that takes the quaternion frame's
    /// `(T, n̂ × T)` to Blinn's axes by `rule`: `Du = m00 T + m10 B`, `Dv = m01 T + m11 B`.
    /// `(-1, 0, 0, -1)` for an orthonormal right-handed parameterisation under the
    /// scale-invariant rule (then a `QuatFrame` without `m` does the same).
    QuatScale {
        #[serde(default)]
        rule: Perturbation,
    },
    /// Texture coordinates as a texture-shader stage reads them, `(u, v, 0, 1)`.
    Uvq,
    /// Sphere-map coordinates of the vertex normal in view space, `(n_x / 2 + 1/2, n_y / 2 +
    /// 1/2, 0, 1)`: the environment-map coordinates of Direct3D 6 bump mapping with a diffuse
    /// and specular lighting map (Ernst et al. §3.3), read by a `SphereLighting` texture.
    SphereMap,
    /// Row `row` (0 to 2) of the matrix whose columns are the vertex's tangent frame `(T, B,
    /// N)` in world space (the frame of `LightDir(frame: Tangent)`): `(T[row], B[row],
    /// N[row])`, so that the three rows' dot products with a tangent-space normal give it in
    /// world space. NV_texture_shader's bump-reflect setup sends these rows as the `(s, t, r)`
    /// of texture coordinate sets 1 to 3 and the eye vector in their `q`
    /// (DOT_PRODUCT_REFLECT_CUBE_MAP; wire `cat(row0, eye.r)` with a `ViewDir(frame: World)`
    /// attribute `eye`).
    TangentRow { row: u8 },
    /// Unit direction from the vertex toward the eye in `frame` (the scene camera's eye: a
    /// local viewer).
    ViewDir { frame: VecFrame },
}

impl AttrSource {
    pub fn lanes(&self) -> u8 {
        match self {
            AttrSource::Uv => 2,
            AttrSource::BlendEnable { .. }
            | AttrSource::Lod { .. }
            | AttrSource::VertexLod { .. } => 1,
            AttrSource::Quaternion
            | AttrSource::QuatScale { .. }
            | AttrSource::Uvq
            | AttrSource::SphereMap => 4,
            _ => 3,
        }
    }
    /// Whether the attribute is sent once per triangle (flat) rather than per vertex.
    pub fn per_triangle(&self) -> bool {
        matches!(
            self,
            AttrSource::LightDir {
                per_triangle: true,
                ..
            } | AttrSource::HalfVec {
                per_triangle: true,
                ..
            } | AttrSource::Lod { .. }
                | AttrSource::Alignment { .. }
        )
    }
    /// The light the attribute is about, if any.
    pub fn light(&self) -> Option<usize> {
        match *self {
            AttrSource::LightDir { light, .. }
            | AttrSource::HalfVec { light, .. }
            | AttrSource::BlendEnable { light } => Some(light),
            _ => None,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AttributeConfig {
    pub name: String,
    pub source: AttrSource,
    /// Encoding of each lane, at the vertices and after interpolation.
    pub enc: Encoding,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UnitConfig {
    /// Instance name; outputs are referred to as `name.port`.
    pub name: String,
    pub unit: UnitSpec,
    /// Input port -> signal (`attribute` or `unit.port`).
    pub inputs: BTreeMap<String, String>,
    /// Optional declared bits per lane of inputs; a mismatch with the wired signal is an error.
    #[serde(default)]
    pub expect: BTreeMap<String, u32>,
    /// What this unit's loadable tables are built as (SRAM, latch RAM, flip-flop RAM or ROM),
    /// when not as the config's `cost.tables` says (docs/gates.md, "Memory"). Left out of the
    /// canonical config, and so of the config hash, when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tables: Option<bumpsim_hw::gates::MemoryKind>,
    /// Per table of the unit, what it is built as, over `tables` and `cost.tables`: e.g.
    /// `{Colours: LatchRam, Normals: Sram, Power: Rom}` (roles: `Power`, `Colours`,
    /// `Normals`, `EnvMap`, `BumpPalette`; a role the unit has no table of is an error).
    /// Left out of the canonical config, and so of the hash, when empty.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub table_kinds: BTreeMap<bumpsim_hw::gates::TableRole, bumpsim_hw::gates::MemoryKind>,
}

impl UnitConfig {
    /// The cost table this unit is priced with: the config's, its tables built as the unit's
    /// `tables` says when it says, and each role in `table_kinds` as it says.
    pub fn cost(&self, config: &CostTable) -> CostTable {
        let mut t = match self.tables {
            Some(tables) => CostTable { tables, ..*config },
            None => *config,
        };
        for (&role, &kind) in &self.table_kinds {
            t.by_role[role as usize] = Some(kind);
        }
        t
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EngineConfig {
    pub attributes: Vec<AttributeConfig>,
    pub units: Vec<UnitConfig>,
    /// The signal written to the frame buffer: RGB (3 lanes), or RGBA (4 lanes) for a ROP
    /// that tests or blends with alpha.
    pub output: String,
    /// How the bit-accurate attribute interpolator computes (default `Exact`; left out of the
    /// canonical config, and so of the hash, when it is the default).
    #[serde(default, skip_serializing_if = "Interpolator::is_exact")]
    pub interpolator: Interpolator,
    /// The raster operations at the end of the pipe: depth and alpha tests, blending, the
    /// framebuffer's channel width (`hw/src/units/rop.rs`; default: depth `Less`, no alpha
    /// test, no blending, 8 bits; left out of the canonical config when it is the default).
    #[serde(default, skip_serializing_if = "RopParams::is_default")]
    pub rop: RopParams,
    /// Rendering passes after the first (`output` through `rop`), in order: each re-sends the
    /// geometry, re-rasterises every triangle and writes its own output through its own ROP
    /// state into the same framebuffer (Tarini et al. §7's blend passes: `docs/units/rop.md`,
    /// "Passes"). Default none; left out of the canonical config, and so of the hash, when
    /// empty. At most [`MAX_PASSES`] in all.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub passes: Vec<PassConfig>,
    /// A texture cache on the units' texel reads (`pipeline/src/texcache.rs`): the report's
    /// `bandwidth.texture_cache` gives the texel bits the memory delivers through it. Default
    /// none; left out of the canonical config, and so of the hash, when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texture_cache: Option<TextureCacheConfig>,
}

/// A blocked texture cache (`pipeline/src/texcache.rs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextureCacheConfig {
    /// Lines of one cache: a power of two, 1 to 65,536.
    pub lines: u32,
    /// Lines of a set: a power of two, at most `lines` and 64 (`lines`: fully associative).
    pub ways: u32,
    /// Texels a side of a line's square block: 1, 2, 4, 8 or 16.
    pub block: u32,
    /// One cache for every reading unit instead of one each (default false).
    #[serde(default)]
    pub shared: bool,
    /// How a block's coordinates choose its set (default `Tiled`).
    #[serde(default)]
    pub index: SetIndex,
    /// Cycles from a fill's request to its data, 0 to 4096; default 0: the cache counts
    /// traffic only. A blocking unit (`prefetch: 0`) waits this long per miss and takes no
    /// other fragment meanwhile.
    #[serde(default)]
    pub miss_cycles: u32,
    /// Cycles the texture memory is busy with one fill (fills one after another), 1 to 4096
    /// (default 1): what a prefetching unit's misses queue for.
    #[serde(default = "one_u32")]
    pub fill_cycles: u32,
    /// The depth of a prefetching unit's fragment FIFO (Igehy, Eldridge and Proudfoot 1998:
    /// fills requested when the fragment arrives, the fragment waiting in the FIFO for its
    /// data while later ones go on), 1 to 1024; 0 (default): a blocking unit.
    #[serde(default)]
    pub prefetch: u32,
    /// Which fills wait for each other at the texture memory (default `Shared`).
    #[serde(default)]
    pub bus: TextureBus,
}

/// The texture memory behind the caches: whose fills queue for it (`engine.texture_cache.bus`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum TextureBus {
    /// One memory on one bus: every cache's fills go one after another (`fill_cycles` each),
    /// in the order the units request them (units requesting in the same clock: the one
    /// further down the pipe first, the simulator's tick order).
    #[default]
    Shared,
    /// A memory channel per cache: a cache's fills wait only for its own (the model before
    /// the bus; with `shared: true` there is one cache, hence one queue, either way).
    PerCache,
}

fn one_u32() -> u32 {
    1
}

/// The set of a texture cache's block `(bx, by)` among `a b` sets (`a = 2^ceil(log2(sets) / 2)`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum SetIndex {
    /// `(bx mod a) + a (by mod b)`: a square of `a x b` neighbouring blocks in distinct sets,
    /// but a row of blocks in only `a` of them.
    #[default]
    Tiled,
    /// `(bx xor (by * a)) mod sets`: the low bits of `bx` and `by` spread over every set, so a
    /// row of blocks, a column and a square all use them all.
    Xor,
}

impl TextureCacheConfig {
    /// `(field, message)` of the first value out of range.
    pub fn check(&self) -> Result<(), (&'static str, String)> {
        let pow2 = |x: u32| x.is_power_of_two();
        if !pow2(self.lines) || self.lines > 1 << 16 {
            return Err((
                "lines",
                format!("{}: expected a power of two from 1 to 65536", self.lines),
            ));
        }
        if !pow2(self.ways) || self.ways > self.lines.min(64) {
            return Err((
                "ways",
                format!(
                    "{}: expected a power of two from 1 to {} (at most lines and 64)",
                    self.ways,
                    self.lines.min(64)
                ),
            ));
        }
        if self.miss_cycles > 4096 {
            return Err((
                "miss_cycles",
                format!("{}: expected 0 to 4096", self.miss_cycles),
            ));
        }
        if !(1..=4096).contains(&self.fill_cycles) {
            return Err((
                "fill_cycles",
                format!("{}: expected 1 to 4096", self.fill_cycles),
            ));
        }
        if self.prefetch > 1024 {
            return Err((
                "prefetch",
                format!("{}: expected 0 (blocking) to 1024", self.prefetch),
            ));
        }
        if !pow2(self.block) || self.block > 16 {
            return Err((
                "block",
                format!("{}: expected 1, 2, 4, 8 or 16 texels", self.block),
            ));
        }
        Ok(())
    }
}

/// The most rendering passes of a frame (the first and `engine.passes`).
pub const MAX_PASSES: usize = 8;

/// A rendering pass after the first: what it writes and how the ROP writes it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PassConfig {
    /// The pass's name in the report.
    pub name: String,
    /// The signal (or wire expression) the pass writes: RGB, or RGBA when its ROP tests or
    /// blends with alpha.
    pub output: String,
    /// The ROP's state in this pass (default as `engine.rop`'s: depth `Less` with writes, no
    /// blending); a blend pass over the first pass's surface tests depth `Equal` without
    /// writing it.
    #[serde(default)]
    pub rop: RopParams,
}

/// The attribute interpolator of the bit-accurate engine (`engine/attributes.rs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Interpolator {
    /// The perspective-correct barycentrics in f64 weight the vertex words (the values on each
    /// attribute's grid), and the sum is rounded once into the attribute's encoding: an ideal
    /// interpolator whose only error is the final rounding.
    #[default]
    Exact,
    /// A fixed-point interpolator: the barycentrics rounded to `weight_bits` fraction bits (the
    /// third as `1 - b0 - b1`, so the weights sum to one exactly), integer products with the
    /// vertex codes, the sum rounded and saturated (or wrapped) by the attribute's encoding.
    /// 4 to 30 bits. Costed in the report's gates as `attribute interpolator`.
    Fixed { weight_bits: u32 },
}

impl Interpolator {
    pub fn is_exact(&self) -> bool {
        *self == Interpolator::Exact
    }
}

/// A loaded config with where it came from.
#[derive(Debug, Clone)]
pub struct Loaded {
    pub config: Config,
    pub path: PathBuf,
    /// Directory that relative file names in the config are resolved against.
    pub base_dir: PathBuf,
    pub text: String,
    pub hash: String,
    /// The `--set` overrides applied after parsing.
    pub sets: Vec<String>,
}

impl Loaded {
    /// An error about a field of this config, located at the first occurrence of `needle`
    /// outside comments. When `--set` overrides were applied, positions in the file may not
    /// hold the value checked, so the error names the overrides instead of a position.
    pub fn error(&self, field: &str, needle: &str, message: impl Into<String>) -> InputError {
        if self.sets.is_empty() {
            InputError::new(self.path.display().to_string(), field, message)
                .at(locate(&self.text, needle))
        } else {
            let file = format!(
                "{} with --set {}",
                self.path.display(),
                self.sets.join(" --set ")
            );
            InputError::new(file, field, message)
        }
    }

    /// A scene error about this config: a file problem names the file, a value problem the
    /// field (found at `needle`).
    pub fn scene_error(
        &self,
        field: &str,
        needle: &str,
        e: crate::scene::SceneError,
    ) -> InputError {
        match e {
            crate::scene::SceneError::File { path, message } => {
                InputError::new(path, field, message)
            }
            crate::scene::SceneError::Invalid { field, message } => {
                let field = if field.starts_with("scene.") {
                    field
                } else {
                    format!("scene.{field}")
                };
                self.error(&field, needle, message)
            }
        }
    }
}

fn ron_options() -> ron::Options {
    ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
}

/// Parse RON text into a config, with the path of the failing field and its position. A
/// byte-order mark at the start is skipped.
pub fn parse(text: &str, file: &str) -> Result<Config, InputError> {
    parse_as(text, file)
}

/// [`parse`] for any schema read from RON (e.g. an NV2A frame, `crate::nv2a`).
pub fn parse_as<T: serde::de::DeserializeOwned>(text: &str, file: &str) -> Result<T, InputError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let opts = ron_options();
    let mut de = ron::Deserializer::from_str_with_options(text, &opts).map_err(|e| {
        InputError::new(file, "", e.code.to_string())
            .at(Some((e.span.start.line, e.span.start.col)))
    })?;
    let result: Result<T, _> = serde_path_to_error::deserialize(&mut de);
    match result {
        Ok(c) => {
            de.end().map_err(|e| {
                let s = de.span_error(e);
                InputError::new(file, "", s.code.to_string())
                    .at(Some((s.span.start.line, s.span.start.col)))
            })?;
            Ok(c)
        }
        Err(e) => {
            let field = e.path().to_string();
            let s = de.span_error(e.into_inner());
            let field = if field == "." { String::new() } else { field };
            let pos = (s.span.start.line, s.span.start.col);
            if let Some((field, message)) = not_an_integer(text, pos, &field) {
                return Err(InputError::new(file, field, message).at(Some(pos)));
            }
            Err(InputError::new(file, field, s.code.to_string()).at(Some(pos)))
        }
    }
}

/// A number with a fraction or an exponent where an integer was expected: RON reads the
/// integer part and then stops at the `.5` ("Expected comma", at the next field, `?`) or at
/// the `e` ("Invalid digit"). When the error at `pos` is inside such a literal, the path of
/// its field (the name before the `:`) and "expected an integer, found 256.5".
fn not_an_integer(text: &str, pos: (usize, usize), path: &str) -> Option<(String, String)> {
    let line = text.split('\n').nth(pos.0.checked_sub(1)?)?;
    let line_start = line.as_ptr() as usize - text.as_ptr() as usize;
    let at = line_start
        + line
            .char_indices()
            .nth(pos.1.checked_sub(1)?)
            .map_or(line.len(), |(i, _)| i);
    let b = text.as_bytes();
    let numeric = |c: u8| c.is_ascii_digit() || b"+-.eE".contains(&c);
    let mut start = at;
    while start > 0 && numeric(b[start - 1]) {
        start -= 1;
    }
    let mut end = at;
    while end < b.len() && numeric(b[end]) {
        end += 1;
    }
    let lit = &text[start..end];
    let digit_first = lit
        .trim_start_matches(['+', '-'])
        .starts_with(|c: char| c.is_ascii_digit());
    if !digit_first || !lit.contains(['.', 'e', 'E']) || lit.parse::<f64>().is_err() {
        return None;
    }
    // the field name before `:`, when the literal is a field's value
    let before = text[..start].trim_end();
    let name = before.strip_suffix(':').map(|b| {
        let b = b.trim_end();
        let from = b
            .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .map_or(0, |i| i + 1);
        &b[from..]
    });
    let field = match name {
        Some(n) if !n.is_empty() && path == "?" => n.to_string(),
        Some(n) if !n.is_empty() && path.ends_with(".?") => {
            format!("{}{n}", &path[..path.len() - 1])
        }
        _ => path
            .trim_end_matches(".?")
            .trim_end_matches('?')
            .to_string(),
    };
    Some((field, format!("expected an integer, found {lit}")))
}

/// Read a config file: a regular file of at most [`MAX_CONFIG_BYTES`] of UTF-8 text; a
/// byte-order mark at the start is skipped.
pub fn read_config(path: &Path, file: &str) -> Result<String, InputError> {
    let cannot = |m: String| InputError::new(file, "", format!("cannot read the config: {m}"));
    let meta = std::fs::metadata(path).map_err(|e| cannot(e.to_string()))?;
    if meta.is_dir() {
        return Err(cannot("it is a directory (expected a RON file)".into()));
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(MAX_CONFIG_BYTES as u64 + 1).read_to_end(&mut bytes))
        .map_err(|e| cannot(e.to_string()))?;
    if bytes.len() > MAX_CONFIG_BYTES {
        return Err(cannot(format!(
            "it is larger than {} MiB (expected a RON file of at most {} bytes)",
            MAX_CONFIG_BYTES >> 20,
            MAX_CONFIG_BYTES
        )));
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        cannot(format!(
            "it is not UTF-8 text (invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        ))
    })?;
    Ok(match text.strip_prefix('\u{feff}') {
        Some(t) => t.to_string(),
        None => text,
    })
}

/// The field name of a path (`dir` of `scene.lights[0].kind.Directional.dir[1]`), to find
/// it in the text.
fn last_name(path: &str) -> &str {
    let name = path.rsplit('.').next().unwrap_or(path);
    name.split('[').next().unwrap_or(name)
}

/// "expected a finite number" for the first NaN or infinity in `c`, if any: (field, message).
fn non_finite(c: &Config) -> Option<(String, String)> {
    finite::first_non_finite(c)
        .map(|(field, x)| (field, format!("expected a finite number, found {x}")))
}

/// Canonical RON text of a config (used for the hash).
pub fn canonical(config: &Config) -> String {
    ron::ser::to_string(config).expect("a parsed config serialises")
}

/// How a config is loaded.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LoadOptions {
    /// Run past the up-front estimate of work and memory ([`limits::check_budget`]); the
    /// hard limits still apply. `bumpsim --force`.
    pub force: bool,
}

/// Load a config file, apply `--set` overrides and validate it, within the budget of
/// [`limits::estimate`].
pub fn load(path: &Path, sets: &[String]) -> Result<Loaded, InputError> {
    load_with(path, sets, LoadOptions::default())
}

/// [`load`] with options (`force`: past the estimate's budget).
pub fn load_with(path: &Path, sets: &[String], opts: LoadOptions) -> Result<Loaded, InputError> {
    let file = path.display().to_string();
    let text = read_config(path, &file)?;
    let mut config = parse(&text, &file)?;
    if !sets.is_empty() {
        // the overrides go through JSON, which has no NaN or infinity: name the field here
        // (in the file) rather than let it arrive as a `null` blamed on --set
        if let Some((field, message)) = non_finite(&config) {
            let needle = format!("{}:", last_name(&field));
            return Err(InputError::new(&file, field, message).at(locate(&text, &needle)));
        }
        config = overrides::apply(&config, sets)?;
    }
    let hash = hash_of(&config);
    let base_dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let loaded = Loaded {
        config,
        path: path.to_path_buf(),
        base_dir,
        text,
        hash,
        sets: sets.to_vec(),
    };
    validate(&loaded)?;
    frames::check(&loaded)?;
    limits::check_budget(&loaded, opts.force)?;
    Ok(loaded)
}

/// The config hash of a config (SHA-256 of its canonical text, as in [`Loaded::hash`]).
fn hash_of(config: &Config) -> String {
    hex(&Sha256::digest(canonical(config).as_bytes()))
}

/// The hash [`load_with`] would give the config at `path` with `sets` applied, without
/// validating it or pricing its run (a sweep's `--resume` checks earlier rows with it).
pub fn hash_with(path: &Path, sets: &[String]) -> Result<String, InputError> {
    let file = path.display().to_string();
    let text = read_config(path, &file)?;
    let mut config = parse(&text, &file)?;
    if !sets.is_empty() {
        config = overrides::apply(&config, sets)?;
    }
    Ok(hash_of(&config))
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Checks that span fields: lights, FIFO depth, attribute names and light indices, gate
/// prices; last, that every number is finite (for the fields no check above covers).
fn validate(l: &Loaded) -> Result<(), InputError> {
    let c = &l.config;
    if let Err((name, message)) = c.cost.validate() {
        return Err(l.error(&format!("cost.{name}"), &format!("{name}:"), message));
    }
    if let Interpolator::Fixed { weight_bits } = c.engine.interpolator {
        if !(4..=30).contains(&weight_bits) {
            return Err(l.error(
                "engine.interpolator.weight_bits",
                "interpolator:",
                format!("weight_bits {weight_bits}: expected 4 to 30"),
            ));
        }
    }
    for (i, light) in c.scene.lights.iter().enumerate() {
        light
            .validate(&format!("scene.lights[{i}]"))
            .map_err(|e| l.scene_error("scene.lights", "lights:", e))?;
    }
    c.scene
        .camera
        .validate("scene.camera")
        .map_err(|e| l.scene_error("scene.camera", "camera:", e))?;
    let t = &c.scene.model;
    if !(t.scale.is_finite() && t.scale.abs() > 1e-12 && t.scale.abs() <= 1e12) {
        return Err(l.error(
            "scene.model.scale",
            "scale:",
            format!(
                "expected a finite number with 1e-12 < abs(scale) <= 1e12, found {}",
                t.scale
            ),
        ));
    }
    if t.translate
        .iter()
        .chain(&t.rotate_deg)
        .any(|x| !x.is_finite())
    {
        return Err(l.error(
            "scene.model",
            "model:",
            "expected finite translate and rotate_deg values",
        ));
    }
    if let Some(x) = t
        .translate
        .iter()
        .find(|x| x.abs() > crate::scene::MAX_COORD)
    {
        return Err(l.error(
            "scene.model.translate",
            "translate:",
            format!(
                "coordinate {x:e} is out of range: expected each within ±{:e}",
                crate::scene::MAX_COORD
            ),
        ));
    }
    c.scene
        .material
        .validate("scene.material")
        .map_err(|e| l.scene_error("scene.material", "material:", e))?;
    if let Some(r) = &c.scene.regions {
        r.validate("scene.regions")
            .map_err(|e| l.scene_error("scene.regions", "regions:", e))?;
    }
    if !(1..=16).contains(&c.reference.samples) {
        return Err(l.error(
            "reference.samples",
            "samples:",
            format!("expected 1 to 16, found {}", c.reference.samples),
        ));
    }
    if let Some(t) = c.reference.highlight_luma {
        if !(t > 0.0 && t <= 1.0) {
            return Err(l.error(
                "reference.highlight_luma",
                "highlight_luma:",
                format!("expected a luma with 0 < highlight_luma <= 1, found {t}"),
            ));
        }
    }
    if let Some(st) = c.reference.synthesis {
        let t = st.tilt_deg;
        if !(0.0..=90.0).contains(&t) {
            return Err(l.error(
                "reference.synthesis.tilt_deg",
                "tilt_deg:",
                format!("expected degrees from 0 to 90, found {t}"),
            ));
        }
        if !matches!(c.scene.bump, BumpSpec::Ndf { .. }) {
            return Err(l.error(
                "reference.synthesis",
                "synthesis:",
                "expected a scene with bump: Ndf(...) (it measures the NDF bump synthesis)",
            ));
        }
    }
    if !(1..=64).contains(&c.sim.fifo_depth) {
        return Err(l.error(
            "sim.fifo_depth",
            "fifo_depth:",
            format!("expected 1 to 64, found {}", c.sim.fifo_depth),
        ));
    }
    c.raster
        .validate("raster")
        .map_err(|e| l.error("raster", "raster:", e))?;
    let n = c.scene.lights.len();
    let mut seen = std::collections::BTreeSet::new();
    for (i, a) in c.engine.attributes.iter().enumerate() {
        let field = format!("engine.attributes[{i}]");
        if !seen.insert(a.name.as_str()) || a.name.contains('.') {
            return Err(l.error(
                &format!("{field}.name"),
                &format!("\"{}\"", a.name),
                format!(
                    "attribute name {:?}: expected a unique name without '.'",
                    a.name
                ),
            ));
        }
        if let AttrSource::Lod { size } | AttrSource::VertexLod { size } = a.source {
            if !size.is_power_of_two() || size > 1 << 14 {
                return Err(l.error(
                    &format!("{field}.source.size"),
                    &format!("\"{}\"", a.name),
                    format!("Lod size {size}: expected a power of two from 1 to 16384"),
                ));
            }
        }
        if let AttrSource::TangentRow { row } = a.source {
            if row > 2 {
                return Err(l.error(
                    &format!("{field}.source.row"),
                    &format!("\"{}\"", a.name),
                    format!("TangentRow row {row}: expected 0, 1 or 2"),
                ));
            }
        }
        if let Some(k) = a.source.light() {
            if k >= n {
                return Err(l.error(
                    &format!("{field}.source"),
                    &format!("\"{}\"", a.name),
                    match n {
                        0 => format!("light index {k}: the scene has 0 lights (expected a light in scene.lights)"),
                        _ => format!("light index {k}: the scene has {n} lights (expected 0 to {})", n - 1),
                    },
                ));
            }
        }
    }
    if let Some((field, message)) = non_finite(c) {
        let needle = format!("{}:", last_name(&field));
        return Err(l.error(&field, &needle, message));
    }
    limits::check_units(l)
}
