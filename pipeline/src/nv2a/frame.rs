//! The schema of an NV2A frame config (`configs/nv2a/`): what one frame of a hardware test
//! suite draws, written so that the model can render it and compare it with the frame the
//! hardware rendered. See [`super`] and `docs/nv2a.md`.

use bumpsim_hw::units::combiner::Program;
use bumpsim_hw::units::texture_shader::Program as StageProgram;
use bumpsim_hw::units::{Address, Filter};
use serde::{Deserialize, Serialize};

/// Frame size of every capture (the host's 640 x 480 A8R8G8B8 back buffer).
pub const WIDTH: u32 = 640;
pub const HEIGHT: u32 = 480;
/// Most quads in a frame (the suites draw at most a few dozen).
pub const MAX_QUADS: usize = 1024;
/// Most passes drawn over one quad.
pub const MAX_PASSES: usize = 16;
/// Largest text row and column of a `pb_printat` cell (the frame holds 18 rows, 62 columns).
pub const MAX_TEXT_CELL: u32 = 64;
/// Most text cells of a frame.
pub const MAX_TEXTS: usize = 256;
/// Most pixels times shaded passes a frame may ask for (about ten seconds of shading; the
/// bundled frames ask for at most 0.2 M).
pub const MAX_SHADED: u64 = 1 << 24;
/// Most textures of a frame, and their largest side.
pub const MAX_TEXTURES: usize = 16;
pub const MAX_TEXTURE_SIDE: u32 = 1024;

/// One frame of an NV2A test suite.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Frame {
    /// The test's name (the frame's file name without `.png`).
    pub name: String,
    #[serde(default)]
    pub description: String,
    /// The frame the hardware rendered: a 640 x 480 PNG, relative to this file.
    pub golden: String,
    /// Register width of the combiners in bits, 9 to 24 (the NV2A's: 9, `docs/nv2a.md`).
    #[serde(default = "nine")]
    pub combiner_width: u32,
    /// The text the host prints (`pb_printat(row, col, text)`): 10 x 16 pixel cells at
    /// x = 20 + 10 col, y = 25 + 25 row, left out of the comparison.
    #[serde(default)]
    pub text: Vec<Text>,
    /// Where in a pixel the interpolated texture coordinates are sampled (default the
    /// centre; see [`Sample`]).
    #[serde(default)]
    pub sample: Sample,
    /// The textures the passes' shader stages read, by name.
    #[serde(default)]
    pub textures: Vec<TextureDef>,
    /// The quads the test draws, each with the passes drawn over it in order.
    pub quads: Vec<Quad>,
}

/// Where a pixel's interpolated attributes are sampled: the plane of its triangle through the
/// three vertices' values (f64), evaluated at this point and truncated (toward minus
/// infinity) to the texture shader's s16.16 coordinate words.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Sample {
    /// The pixel centre (x + 1/2, y + 1/2): the `Bump_map` frames (the passthrough vertex
    /// shader; unit page, hypothesis 13).
    #[default]
    Centre,
    /// The pixel's top-left corner (x, y): the `Pixel_shader` frames (the XDK default
    /// viewport's 0.53125 offset truncated to the rasterizer's 4 fraction bits moves the
    /// vertices half a pixel; unit page, hypothesis 1).
    Corner,
}

/// A texture of the frame: its name and how the host makes it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextureDef {
    pub name: String,
    pub source: TextureSource,
    /// The codes are two's complement (the host's per-channel signed flags, set for the
    /// channels a quad reads signed: the filter interpolates signed values). Default false.
    #[serde(default)]
    pub signed: bool,
}

/// How the host makes a texture: RGBA 8-bit codes, or (`Quadrants` read as `R16b16`) HILO
/// 16-bit words.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum TextureSource {
    /// `GenerateCheckerboardSurface(width, height, first, second)`: cells of `cell` texels,
    /// the colours as ABGR8888 words (R in the low byte); texel (x, y) is `first` where
    /// x / cell + y / cell is even.
    Checkerboard {
        width: u32,
        height: u32,
        cell: u32,
        first: u32,
        second: u32,
    },
    /// The bump-map tests' surface: `size` x `size` texels of four RGBA8888 colours (SDL's,
    /// R in the high byte), split at texel `split` on both axes, in the order top-left,
    /// top-right, bottom-left, bottom-right; read as `reading`.
    Quadrants {
        size: u32,
        split: u32,
        colours: [u32; 4],
        reading: Reading,
    },
    /// `GenerateRGBRadialATestPattern(width, height)` of the host's texture generator.
    RadialPattern { width: u32, height: u32 },
    /// `GenerateRGBATestPattern(width, height)` (alpha wraps at 8 bits).
    RgbaPattern { width: u32, height: u32 },
    /// A host resource PNG (RGB) relative to this file, as `LoadPNG` uploads it: alpha 255.
    Png(String),
}

/// How the texture unit reads a [`TextureSource::Quadrants`] surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Reading {
    /// Four 8-bit lanes R, G, B, A (every 8-bit format the host converts the colours to).
    Rgba8,
    /// R16B16 as HILO: two 16-bit lanes, HI = R * 257 and LO = B * 257 (the host writes the
    /// bytes B, B, R, R; docs/units/texture-shader.md, hypothesis 10).
    R16b16,
    /// The R16B16 words read as A8R8G8B8 bytes: R = HI & 0xff, G = LO >> 8, B = LO & 0xff,
    /// A = HI >> 8 (what BUMPENVMAP reads of a 16-bit texel, hypothesis 22).
    R16b16Bytes,
}

fn nine() -> u32 {
    9
}

/// A line of text the host prints.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Text {
    pub row: u32,
    pub col: u32,
    pub text: String,
}

impl Text {
    /// Whether the pixel (x, y) lies in one of this text's cells.
    pub fn covers(&self, x: u32, y: u32) -> bool {
        let (x0, y0) = (20 + 10 * self.col, 25 + 25 * self.row);
        let n = self.text.chars().count() as u32;
        x >= x0 && x < x0 + 10 * n && y >= y0 && y < y0 + 16
    }
}

/// One quad: where it lies, what lies under it, and the passes drawn over it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Quad {
    pub label: String,
    pub region: Region,
    pub under: Under,
    /// Texture coordinates (s, t, r, q) per shader stage (at most 4), each at the vertices
    /// v0 to v3: top-left, top-right, bottom-right, bottom-left of a screen rectangle, drawn as
    /// the triangles (v0, v1, v2) and (v0, v2, v3). f32, as the host passes them. Stages
    /// left out read (0, 0, 0, 0).
    #[serde(default)]
    pub texcoords: Vec<[[f32; 4]; 4]>,
    pub passes: Vec<Pass>,
}

/// Where a quad lies.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Region {
    /// A quad placed in screen space (the host unprojects integer pixel corners): the pixels
    /// `[left, right) x [top, bottom)`, all compared.
    Screen {
        left: u32,
        top: u32,
        right: u32,
        bottom: u32,
    },
    /// An axis-aligned quad in world space (y up) at depth `z`, seen by the host's XDK default
    /// camera (eye (0, 0, -7) looking at the origin, 45 degree vertical field of view, aspect
    /// 4:3, the D3D viewport on 640 x 480). Covered: pixel centres inside the projected edges;
    /// compared: centres at least [`WORLD_INSET`] pixels inside them.
    World {
        left: f32,
        top: f32,
        right: f32,
        bottom: f32,
        z: f32,
    },
}

/// How far inside a world-space quad's projected edges a compared pixel centre lies: one
/// pixel beyond the viewport's 0.53125-pixel offset, whichever way the hardware applies it,
/// so that neither the rasterizer's edge rule nor that offset matters.
pub const WORLD_INSET: f64 = 1.53125;

impl Region {
    /// The projected rectangle (x0, y0, x1, y1) in pixels.
    pub(super) fn projected(&self) -> (f64, f64, f64, f64) {
        match *self {
            Region::Screen {
                left,
                top,
                right,
                bottom,
            } => (left as f64, top as f64, right as f64, bottom as f64),
            Region::World {
                left,
                top,
                right,
                bottom,
                z,
            } => {
                let ys = 1.0 / (std::f64::consts::PI / 8.0).tan();
                let xs = ys / (4.0 / 3.0);
                let zv = z as f64 + 7.0;
                let sx = |wx: f32| 320.0 + 320.0 * wx as f64 * xs / zv;
                let sy = |wy: f32| 240.0 - 240.0 * wy as f64 * ys / zv;
                (sx(left), sy(top), sx(right), sy(bottom))
            }
        }
    }

    /// Whether the pixel (x, y) is compared: inside a screen rectangle, or its centre at
    /// least [`WORLD_INSET`] inside a world quad's projected edges.
    pub fn compares(&self, x: u32, y: u32) -> bool {
        self.inside(x, y, WORLD_INSET)
    }

    /// Whether the quad covers the pixel (x, y): what the model's picture paints.
    pub fn covers(&self, x: u32, y: u32) -> bool {
        self.inside(x, y, 0.0)
    }

    fn inside(&self, x: u32, y: u32, inset: f64) -> bool {
        let (x0, y0, x1, y1) = self.projected();
        if let Region::Screen { .. } = self {
            let (px, py) = (x as f64, y as f64);
            return px >= x0 && px < x1 && py >= y0 && py < y1;
        }
        let (cx, cy) = (x as f64 + 0.5, y as f64 + 0.5);
        cx >= x0 + inset && cx <= x1 - inset && cy >= y0 + inset && cy <= y1 - inset
    }

    /// The pixels to visit, clipped to the frame: (x0, y0, x1, y1), half-open.
    pub fn bounds(&self) -> (u32, u32, u32, u32) {
        let (x0, y0, x1, y1) = self.projected();
        let clip = |v: f64, max: u32| v.clamp(0.0, max as f64) as u32;
        (
            clip(x0.floor(), WIDTH),
            clip(y0.floor(), HEIGHT),
            clip(x1.ceil() + 1.0, WIDTH),
            clip(y1.ceil() + 1.0, HEIGHT),
        )
    }

    /// What is wrong with the region, if anything.
    pub(super) fn check(&self) -> Result<(), String> {
        match *self {
            Region::Screen {
                left,
                top,
                right,
                bottom,
            } => {
                if left >= right || right > WIDTH || top >= bottom || bottom > HEIGHT {
                    return Err(format!(
                        "Screen(left: {left}, top: {top}, right: {right}, bottom: {bottom}): \
                         expected left < right <= {WIDTH} and top < bottom <= {HEIGHT}"
                    ));
                }
            }
            Region::World {
                left,
                top,
                right,
                bottom,
                z,
            } => {
                let all = [left, top, right, bottom, z];
                if all.iter().any(|v| !v.is_finite() || v.abs() > 1e6) {
                    return Err(format!(
                        "World{all:?}: expected finite coordinates of at most 1e6"
                    ));
                }
                if left >= right || bottom >= top || z <= -6.0 {
                    return Err(format!(
                        "World(left: {left}, top: {top}, right: {right}, bottom: {bottom}, \
                         z: {z}): expected left < right, bottom < top (y is up) and z > -6 \
                         (in front of the camera at z = -7)"
                    ));
                }
            }
        }
        Ok(())
    }
}

/// What lies under a quad before its passes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Under {
    /// The cleared colour (RGBA codes).
    Clear([u8; 4]),
    /// A checkerboard of these two colours (the host's background texture; its texel edges
    /// are not modelled, so a pixel is exact when it matches the frame over either colour).
    Checker([u8; 4], [u8; 4]),
}

impl Under {
    /// The colours that may lie under a pixel.
    pub fn colours(&self) -> Vec<[u8; 4]> {
        match *self {
            Under::Clear(c) => vec![c],
            Under::Checker(a, b) => vec![a, b],
        }
    }
}

/// One draw over a quad: the texture-shader program if any, the combiner program and the
/// registers it reads (constant over the quad). The result is blended over what lies there
/// (SRC_ALPHA, ONE_MINUS_SRC_ALPHA, the host's default); a fragment the shader culls leaves
/// it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Pass {
    /// The texture-shader stages (none: every texture register reads `texture`).
    #[serde(default)]
    pub shader: Option<Shader>,
    pub program: Program,
    /// PRIMARY_COLOR (the vertex diffuse colour), RGBA codes.
    #[serde(default)]
    pub primary: [u8; 4],
    /// SECONDARY_COLOR (the vertex specular colour).
    #[serde(default)]
    pub secondary: [u8; 4],
    /// FOG.
    #[serde(default)]
    pub fog: [u8; 4],
    /// What TEXTURE0 to TEXTURE3 read without a shader (an unbound stage's value).
    #[serde(default)]
    pub texture: [u8; 4],
    /// The host's `DrawZBuffer` after this pass: the pixel shows the depth the shader
    /// replaced (DOT_PRODUCT_DEPTH_REPLACE) as the Z16 buffer holds it, `clamp(floor(z), 0,
    /// 65535)`, read back as an R5G6B5 texel one to one and drawn without blending (each
    /// field widened to 8 bits by repeating its top bits). Default false.
    #[serde(default)]
    pub show_depth: bool,
}

/// A pass's texture-shader program: 1 to 4 stages (the rest NONE) and the unit's precision
/// (`docs/units/texture-shader.md`; the defaults are the NV2A's).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Shader {
    pub stages: Vec<ShaderStage>,
    /// Fraction bits of the mapped dot-product vector (1 to 24).
    #[serde(default = "dot_frac")]
    pub dot_frac: u32,
    /// Fraction bits of the offset matrix, luminance scale and bias (1 to 16).
    #[serde(default = "offset_frac")]
    pub offset_frac: u32,
    /// The colour converter's fraction bits (`None`: rounding; the NV2A's 12).
    #[serde(default = "convert_frac")]
    pub convert_frac: Option<u32>,
    /// Width of the coordinate words, 24 to 32 bits with 16 fraction bits (default 32:
    /// s16.16); the dot products and the depth divide are held in the same format.
    #[serde(default = "coord_width")]
    pub coord_width: u32,
    /// Run this pass's texture shader in the unit's exact (f64) mode whatever the command's
    /// mode: for values beyond any fixed-point coordinate format of the unit (at most 32
    /// bits), e.g. DotZW's dot products of 40,000 and depths up to 65,535, which the NV2A
    /// computes in floating point. Default false.
    #[serde(default)]
    pub exact: bool,
}

fn coord_width() -> u32 {
    32
}

fn dot_frac() -> u32 {
    16
}
fn offset_frac() -> u32 {
    8
}
fn convert_frac() -> Option<u32> {
    Some(12)
}

/// One texture-shader stage: its program, the texture it reads (a name of the frame's
/// `textures`) and its sampler (default nearest, the host's default filter, 8-bit weights,
/// wrap).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShaderStage {
    pub program: StageProgram,
    #[serde(default)]
    pub texture: Option<String>,
    #[serde(default = "nearest")]
    pub filter: Filter,
    #[serde(default = "weight_bits")]
    pub weight_bits: u32,
    #[serde(default)]
    pub address: Address,
}

fn nearest() -> Filter {
    Filter::Nearest
}
fn weight_bits() -> u32 {
    8
}
