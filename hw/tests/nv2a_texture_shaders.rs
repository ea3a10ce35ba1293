//! The texture-shader unit (with the register combiners) against frames rendered by real
//! NV2A hardware (`tests/nv2a/golden/Pixel_shader/*.png`, from
//! abaire/nxdk_pgraph_tests_golden_results at 902343e2, CC0; the scenes are
//! abaire/nxdk_pgraph_tests' `pixel_shader_tests.cpp` at 16c27827, MIT).
//!
//! Every reproduced scene draws screen-aligned quads (`SetScreenVertex` of integer pixel
//! corners, the XDK default camera: one w for the whole quad, so perspective correction is
//! the identity). The test rasterizes them itself: a quad is the two triangles (v0, v1, v2)
//! and (v0, v2, v3); a pixel's texture coordinates are the plane of its triangle through the
//! three vertices' float coordinates, evaluated in f64 at the sample point `(x + o, y + o)`
//! (`o` = 0 is the model, [`CORNER`]; other values are the alternatives), then truncated to the unit's s16.16 coordinate words. The
//! texture-shader unit and the register-combiner unit run in bit-accurate mode; the ROP
//! blends as the combiner test found (SRC_ALPHA, ONE_MINUS_SRC_ALPHA, round to nearest, all
//! four channels).
//!
//! Compared pixels: every pixel of `[left, right) x [top, bottom)` of each quad (the coverage
//! the combiner frames showed for such quads), minus the text cells the host prints
//! (`pb_printat` / `pb_print`: 10 x 16 px cells at x = 20 + 10 col, y = 25 + 25 row). All four
//! channels are compared; a pixel is exact when all four equal the frame's.
//!
//! A missing frame is a failure, not a skip.

mod nv2a;

use nv2a::{blend, in_text};

use bumpsim_hw::sampler::{Address, Filter, Sampler};
use bumpsim_hw::units::combiner::{
    Combiner, CombinerParams, FinalCombiner, FinalInput, GeneralStage, MuxSelect, Program as Cp,
    Source, Usage,
};
use bumpsim_hw::units::texture_shader::{Offset, Program, ShaderParams, StageSpec, TextureShader};
use bumpsim_hw::{Codec, Encoding, Mode, Texels, Texture, Unit, Word};
use std::path::PathBuf;
use std::sync::Arc;

const W: u32 = 640;
const H: u32 = 480;
const U8: Encoding = Encoding::texel(Codec::UnitUnsigned, false, 8);

// ---- the interpolation hypotheses --------------------------------------------------------

/// How a pixel's attributes are sampled.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Interp {
    /// Sample point inside the pixel, from its top-left corner (0.5: the centre).
    offset: f64,
    /// Quad split: false (v0, v1, v2) + (v0, v2, v3); true (v0, v1, v3) + (v1, v2, v3).
    other_diagonal: bool,
}

const CENTRE: Interp = Interp {
    offset: 0.5,
    other_diagonal: false,
};

/// The model: attributes at the pixel's top-left corner (see the docs: the viewport's 0.53125
/// offset truncated to the rasterizer's 4 fraction bits puts vertices half a pixel right and
/// down, so pixel centres see the attribute planes at integer distances from the vertices).
const CORNER: Interp = Interp {
    offset: 0.0,
    other_diagonal: false,
};

/// A screen quad: corners v0..v3 (clockwise from top-left) and each corner's texture
/// coordinates for every stage.
struct Quad {
    corners: [(f64, f64); 4],
    coords: [[[f64; 4]; 4]; 4], // [vertex][stage][s t r q]
}

impl Quad {
    fn rect(left: f64, top: f64, size: f64, coords: [[[f64; 4]; 4]; 4]) -> Quad {
        Quad {
            corners: [
                (left, top),
                (left + size, top),
                (left + size, top + size),
                (left, top + size),
            ],
            coords,
        }
    }
    fn covers(&self, x: u32, y: u32) -> bool {
        let (l, t) = self.corners[0];
        let (r, b) = self.corners[2];
        (x as f64) >= l && (x as f64) < r && (y as f64) >= t && (y as f64) < b
    }
    /// The coordinates of every stage at pixel (x, y).
    fn at(&self, x: u32, y: u32, ip: Interp) -> [[f64; 4]; 4] {
        let (px, py) = (x as f64 + ip.offset, y as f64 + ip.offset);
        let c = &self.corners;
        let tri = if !ip.other_diagonal {
            // above the v0-v2 diagonal: (v0, v1, v2)
            let cross = (c[2].0 - c[0].0) * (py - c[0].1) - (c[2].1 - c[0].1) * (px - c[0].0);
            if cross <= 0.0 {
                [0, 1, 2]
            } else {
                [0, 2, 3]
            }
        } else {
            let cross = (c[3].0 - c[1].0) * (py - c[1].1) - (c[3].1 - c[1].1) * (px - c[1].0);
            if cross <= 0.0 {
                [0, 1, 3]
            } else {
                [1, 2, 3]
            }
        };
        let [a, b, d] = tri.map(|k| c[k]);
        let det = (b.0 - a.0) * (d.1 - a.1) - (d.0 - a.0) * (b.1 - a.1);
        let wb = ((px - a.0) * (d.1 - a.1) - (d.0 - a.0) * (py - a.1)) / det;
        let wd = ((b.0 - a.0) * (py - a.1) - (px - a.0) * (b.1 - a.1)) / det;
        let wa = 1.0 - wb - wd;
        std::array::from_fn(|s| {
            std::array::from_fn(|k| {
                wa * self.coords[tri[0]][s][k]
                    + wb * self.coords[tri[1]][s][k]
                    + wd * self.coords[tri[2]][s][k]
            })
        })
    }
}

// ---- the units ---------------------------------------------------------------------------

fn shader(stages: Vec<StageSpec>, params: ShaderParams) -> TextureShader {
    TextureShader::new(params, stages).expect("scene program")
}

fn fin(s: Source, alpha: bool) -> FinalInput {
    FinalInput::new(s, if alpha { Usage::Alpha } else { Usage::Rgb }, false)
}

/// The final combiner `RGB = rgb, alpha = alpha` with one idle general stage.
fn combiner(u: &TextureShader, rgb: FinalInput, alpha: FinalInput) -> Combiner {
    let mut params = CombinerParams::default();
    for i in 0..4 {
        params.inputs[3 + i] = u.result_encoding(i).unwrap_or(U8);
    }
    let prog = Cp {
        stages: vec![GeneralStage::nop()],
        final_combiner: FinalCombiner::just(rgb, alpha),
        mux_select: MuxSelect::Lsb,
    };
    Combiner::new(params, prog).expect("combiner program")
}

/// One pass over one pixel: (colour, live).
fn shade(
    u: &TextureShader,
    c: &Combiner,
    coords: &[[f64; 4]; 4],
    diffuse: [u8; 4],
    mode: Mode,
) -> ([u8; 4], bool) {
    let enc = u.params().coord;
    let ins: Vec<Word> = coords
        .iter()
        .map(|cs| Word::for_mode(mode, &enc, cs))
        .collect();
    let mut outs = vec![Word::default(); u.outputs().len()];
    u.eval(mode, &ins, &mut outs);
    let live = u.live(mode, &ins, &outs);
    let w = |k: [u8; 4]| Word::from_raw(&U8, &k.map(i64::from));
    let cins = [
        w(diffuse),
        w([0; 4]),
        w([0; 4]),
        outs[0],
        outs[1],
        outs[2],
        outs[3],
    ];
    let mut o = [Word::default()];
    c.eval(mode, &cins, &mut o);
    let rgba = o[0].raws::<4>().map(|r| r as u8);
    (rgba, live)
}

// ---- scenes ------------------------------------------------------------------------------

/// One draw: a quad, the units, the diffuse colour.
struct Draw {
    quad: usize,
    shader: TextureShader,
    combiner: Combiner,
    diffuse: [u8; 4],
}

struct Scene {
    name: &'static str,
    clear: [u8; 4],
    quads: Vec<Quad>,
    draws: Vec<Draw>,
    text: Vec<(u32, u32, u32)>,
}

/// `Passthru`: PASS_THROUGH of texture coordinate 0, RGB = tex0, alpha = tex0 alpha.
fn passthru(params: ShaderParams) -> Scene {
    let z = [0.0; 4];
    let v = |c: [f64; 4]| [c, z, z, z];
    let (left, top) = (192.0, 112.0); // CenterX(256), CenterY(256)
    let q = Quad::rect(
        left,
        top,
        256.0,
        [
            v([0.0, 0.0, 1.0, 0.25]),
            v([0.0, 1.0, 0.0, 0.5]),
            v([1.0, 0.0, 0.0, 0.75]),
            v([1.0, 1.0, 0.4, 0.33]),
        ],
    );
    let u = shader(vec![StageSpec::new(Program::PassThrough, None)], params);
    let c = combiner(
        &u,
        fin(Source::Texture0, false),
        fin(Source::Texture0, true),
    );
    Scene {
        name: "Passthru",
        clear: [0x22, 0x22, 0x22, 0xff],
        quads: vec![q],
        draws: vec![Draw {
            quad: 0,
            shader: u,
            combiner: c,
            diffuse: [0x7f; 4],
        }],
        text: vec![(0, 0, 8), (1, 0, 30)],
    }
}

/// `ClipPlane`: 16 quads, each drawn four times: the background colour with NONE, then red,
/// green and blue with CULL_FRAGMENT on stage 0, 1 and 2 and the quad's comparator. The
/// host's comparator bit set means the coordinate passes when >= 0, clear when < 0
/// (`set_bit_passes_nonneg`; the frame settles it against the other reading).
fn clip_plane(params: ShaderParams, set_bit_passes_nonneg: bool) -> Scene {
    let corner = [
        [
            [0.0, 0.1, -0.02, -0.25],
            [-0.1, -0.1, 0.02, 0.25],
            [-0.1, -0.1, -0.1, 0.1],
            [0.0; 4],
        ],
        [
            [1.0, -0.3, 1.0, 0.0],
            [0.1, 0.3, -0.2, -0.01],
            [0.1, -0.1, -0.1, -0.1],
            [0.0; 4],
        ],
        [
            [-1.0, -0.1, -0.1, 0.5],
            [1.0, 0.1, 0.1, -0.25],
            [-0.1, 0.1, -0.1, -0.1],
            [0.0; 4],
        ],
        [
            [-0.1, 2.0, 3.0, 0.25],
            [0.1, -0.6, 1.1, -0.35],
            [-0.1, -0.1, 0.1, -0.1],
            [0.0; 4],
        ],
    ];
    // the host passes floats: the coordinates as f32
    let corner = corner.map(|v| v.map(|s| s.map(|x| x as f32 as f64)));
    // `SetDiffuse(0xAARRGGBB)` reaches the colour register with R in the low byte: the
    // frame shows 0xFF7F44DD as (0xDD, 0x44, 0x7F)
    let colours = [
        [0x33, 0x33, 0x33, 0xff],
        [0xdd, 0x44, 0x7f, 0xff],
        [0x44, 0xdd, 0x6e, 0xff],
        [0x55, 0x66, 0xee, 0xff],
    ];
    let mut quads = Vec::new();
    let mut draws = Vec::new();
    let mut text = vec![(0, 0, 9), (1, 0, 52), (2, 0, 25), (3, 0, 25), (4, 0, 23)];
    let (mut left, mut top, mut row, mut col) = (32.0, 208.0, 6u32, 2u32);
    for bits in 0..16u32 {
        // s is the outermost loop: bit 3 of the counter
        let ge = [bits & 8 != 0, bits & 4 != 0, bits & 2 != 0, bits & 1 != 0];
        let gequal = ge.map(|b| b != set_bit_passes_nonneg);
        quads.push(Quad::rect(left, top, 64.0, corner));
        for pass in 0..4 {
            let mut stages = vec![StageSpec::none(), StageSpec::none(), StageSpec::none()];
            if pass > 0 {
                stages[pass - 1] = StageSpec::new(Program::CullFragment { gequal }, None);
            }
            let u = shader(stages, params);
            let c = combiner(
                &u,
                fin(Source::Primary, false),
                FinalInput::new(Source::Zero, Usage::Alpha, true),
            );
            draws.push(Draw {
                quad: quads.len() - 1,
                shader: u,
                combiner: c,
                diffuse: colours[pass],
            });
        }
        text.push((row, col, 4));
        left += 80.0;
        col += 8;
        if left + 64.0 >= 640.0 {
            left = 32.0;
            top += 96.0;
            row += 4;
            col = 2;
        }
    }
    Scene {
        name: "ClipPlane",
        clear: [0, 0, 0, 0xff],
        quads,
        draws,
        text,
    }
}

/// The host's `GenerateRGBTestPattern` channel values at (x, y) of a `w x h` image
/// (float32 arithmetic, truncated).
fn normal(v: u32, n: u32) -> u32 {
    (v as f32 * 255.0f32 / n as f32) as u32
}

/// `GenerateRGBRadialATestPattern(256, 256)` as A8B8G8R8 texels (R, G, B, A codes).
fn radial(x: u32, y: u32) -> [u32; 4] {
    let (hw, hh) = (128u32, 128u32);
    let (qx, qy) = (x % hw, y % hh);
    let yn = normal(qy, hh);
    let xn = normal(qx, hw);
    let cx = hw as f32;
    let max = cx * cx + cx * cx;
    let (dx, dy) = (x as f32 - cx, y as f32 - cx);
    let a = (255.0f32 * (1.0f32 - (dx * dx + dy * dy) / max)) as u32;
    [yn, xn, 255 - yn, a & 0xff]
}

/// `GenerateRGBATestPattern(256, 256)` (R, G, B, A codes; A wraps at 8 bits).
fn rgba_pattern(x: u32, y: u32) -> [u32; 4] {
    let (yn, xn) = (normal(y, 256), normal(x, 256));
    [yn, xn, 255 - yn, (xn + yn) & 0xff]
}

fn texture(name: &str, f: impl Fn(u32, u32) -> [u32; 4]) -> Arc<Texture> {
    let values = (0..256 * 256)
        .map(|k| f(k % 256, k / 256).map(|c| c as f64 / 255.0))
        .collect();
    let t = Texels {
        width: 256,
        height: 256,
        lanes: 4,
        values,
    };
    Arc::new(Texture::new(name, U8, t).expect("texture"))
}

/// `StageDependentAlphaRed` / `...GreenBlue`: stage 0 TEXTURE_2D of the radial pattern,
/// stage 1 DEPENDENT_AR (GB) into the RGBA pattern; RGB = tex1, alpha = tex1 alpha. The
/// default filter (`0x1012000`: box min and mag) is nearest; the address mode clamp.
fn dependent(params: ShaderParams, gb: bool) -> Scene {
    let z = [0.0; 4];
    let v = |s: f64, t: f64| [[s, t, 0.0, 1.0], z, z, z];
    let q = Quad::rect(
        192.0,
        112.0,
        256.0,
        [v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)],
    );
    let near = Sampler::new(Filter::Nearest, 8)
        .expect("sampler")
        .with_address(Address::Clamp, Address::Clamp);
    let prog = if gb {
        Program::DependentGb { prev: 0 }
    } else {
        Program::DependentAr { prev: 0 }
    };
    let u = shader(
        vec![
            StageSpec::new(Program::Texture2d, Some(texture("radial", radial))).with_sampler(near),
            StageSpec::new(prog, Some(texture("rgba", rgba_pattern))).with_sampler(near),
        ],
        params,
    );
    let c = combiner(
        &u,
        fin(Source::Texture1, false),
        fin(Source::Texture1, true),
    );
    Scene {
        name: if gb {
            "StageDependentGreenBlue"
        } else {
            "StageDependentAlphaRed"
        },
        clear: [0x28, 0x28, 0x28, 0xff],
        quads: vec![q],
        draws: vec![Draw {
            quad: 0,
            shader: u,
            combiner: c,
            diffuse: [0; 4],
        }],
        text: vec![(0, 0, 23)],
    }
}

/// A 128 x 128 resource PNG of the host (`resources/pixel_shader/`, copied to
/// `tests/nv2a/resources/`) as the A8R8G8B8 texture `LoadPNG` makes of it: RGB, alpha 255.
fn resource(name: &str) -> Arc<Texture> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/nv2a/resources")
        .join(format!("{name}.png"));
    let img = image::open(&p)
        .unwrap_or_else(|e| panic!("the host resource {} is missing: {e}", p.display()))
        .to_rgb8();
    let (w, h) = img.dimensions();
    let values = img
        .pixels()
        .map(|px| {
            let [r, g, b] = px.0;
            [r, g, b, 255].map(|c| c as f64 / 255.0)
        })
        .collect();
    let t = Texels {
        width: w,
        height: h,
        lanes: 4,
        values,
    };
    Arc::new(Texture::new(name, U8, t).expect("texture"))
}

/// `BumpEnvMap`: eight 128 x 128 quads, stage 0 TEXTURE_2D of the water map, stage 1
/// OFFSET_TEXTURE_2D (BUMPENVMAP) of the test image, both 128 x 128 linear (texture-rectangle)
/// A8R8G8B8 read nearest (the default filter) with clamp, coordinates 0 to 128 texels; RGB =
/// tex1, alpha = tex1 alpha; one matrix per quad. As in the `Bump_map` frames
/// (`docs/units/texture-shader.md`, hypotheses 15 to 17): du = B, dv = G as two's complement
/// / 128 and the method's words (M00, M01, M11, M10). A texture rectangle's offset is in
/// **texels** (hypothesis 19): the unit's normalized matrix is the words / 128.
fn bump_env_map(params: ShaderParams) -> Scene {
    const MATS: [[f64; 4]; 8] = [
        [-1.0, 0.0, 1.0, 0.0],
        [1.0, 1.0, 1.0, 1.0],
        [0.0, 0.2, 0.0, 0.75],
        [0.5, -0.5, 0.5, -0.5],
        [0.3, 0.5, 0.7, 1.0],
        [0.0, 1.0, -1.0, 0.0],
        [0.0, 0.0, 1.0, 1.0],
        [0.5, 0.8, 0.0, 0.0],
    ];
    let env = BumpEnv::new(params);
    let (size, spacing, first_left, top0) = (128.0, 144.0, 152.0, 64.0);
    let (mut left, mut top) = (first_left, top0);
    let mut quads = Vec::new();
    let mut draws = Vec::new();
    for (k, w) in MATS.iter().enumerate() {
        quads.push(Quad::rect(left, top, size, env.corners()));
        left += spacing;
        if left + size > W as f64 {
            left = first_left;
            top += spacing;
        }
        draws.push(env.draw(k, *w, None));
    }
    Scene {
        name: "BumpEnvMap",
        clear: [0x22, 0x22, 0x22, 0xff],
        quads,
        draws,
        text: vec![(0, 0, 10)],
    }
}

/// What the two `TestBumpEnvMap` frames share: the water map read by stage 0, the test image
/// offset by stage 1, both 128 x 128 texture rectangles read nearest with clamp, RGB = tex1,
/// alpha = tex1 alpha.
struct BumpEnv {
    params: ShaderParams,
    water: Arc<Texture>,
    image: Arc<Texture>,
    near: Sampler,
    /// The NV2A's luminance (hypothesis 20); `false`: NV_texture_shader's.
    nv2a_luminance: bool,
}

impl BumpEnv {
    fn new(params: ShaderParams) -> Self {
        BumpEnv {
            params: ShaderParams {
                offset_frac: 16,
                ..params
            },
            water: resource("water_bump_map"),
            image: resource("bump_map_test_image"),
            near: Sampler::new(Filter::Nearest, 8)
                .expect("sampler")
                .with_address(Address::Clamp, Address::Clamp),
            nv2a_luminance: true,
        }
    }

    /// Both coordinate sets 0 to 1 (0 to 128 texels) over the quad.
    fn corners(&self) -> [[[f64; 4]; 4]; 4] {
        let z = [0.0; 4];
        let v = |s: f64, t: f64| [[s, t, 0.0, 1.0], [s, t, 0.0, 1.0], z, z];
        [v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)]
    }

    /// Quad `k` with the method's matrix words `w` (f32, / 128: a texture rectangle's offset
    /// is in texels) and, for BUMPENVMAPLUMINANCE, `(scale, offset)`: OFFSET_TEXTURE_2D_SCALE
    /// with the luminance R / 255 of the water map, clamped at 0 only (hypothesis 20).
    fn draw(&self, k: usize, w: [f64; 4], luminance: Option<(f64, f64)>) -> Draw {
        let w = w.map(|x| x as f32 as f64 / 128.0);
        let mut offset = Offset {
            matrix: [w[0], w[1], w[3], w[2]],
            lanes: [2, 1, 0],
            twos_complement: true,
            ..Offset::default()
        };
        let program = match luminance {
            None => Program::OffsetTexture2d { prev: 0, offset },
            Some((scale, bias)) => {
                offset.scale = scale as f32 as f64;
                offset.bias = bias as f32 as f64;
                offset.luminance_unclamped = self.nv2a_luminance;
                Program::OffsetTexture2dScale { prev: 0, offset }
            }
        };
        let u = shader(
            vec![
                StageSpec::new(Program::Texture2d, Some(self.water.clone()))
                    .with_sampler(self.near),
                StageSpec::new(program, Some(self.image.clone())).with_sampler(self.near),
            ],
            self.params,
        );
        let c = combiner(
            &u,
            fin(Source::Texture1, false),
            fin(Source::Texture1, true),
        );
        Draw {
            quad: k,
            shader: u,
            combiner: c,
            diffuse: [0; 4],
        }
    }
}

/// `BumpEnvMapLuminance`: 24 quads of 64 x 64 pixels (the 128 x 128 textures minified by 2,
/// nearest), two matrices (0 and 0.5 in every word) by scale 0, 1, 2 by offset 0, 0.25,
/// 0.75, 1, in columns of four.
fn bump_env_map_luminance(params: ShaderParams) -> Scene {
    bump_env_map_luminance_as(params, true)
}

/// [`bump_env_map_luminance`] with the NV2A's luminance or NV_texture_shader's.
fn bump_env_map_luminance_as(params: ShaderParams, nv2a: bool) -> Scene {
    let env = BumpEnv {
        nv2a_luminance: nv2a,
        ..BumpEnv::new(params)
    };
    let (size, spacing, left0, top0) = (64.0, 80.0, 88.0, 96.0);
    let mut quads = Vec::new();
    let mut draws = Vec::new();
    let mut left = left0;
    for m in [0.0, 0.5] {
        for scale in [0.0, 1.0, 2.0] {
            let mut top = top0;
            for bias in [0.0, 0.25, 0.75, 1.0] {
                draws.push(env.draw(quads.len(), [m; 4], Some((scale, bias))));
                quads.push(Quad::rect(left, top, size, env.corners()));
                top += spacing;
            }
            left += spacing;
        }
        left += spacing * 0.5;
    }
    Scene {
        name: "BumpEnvMapLuminance",
        clear: [0x22, 0x22, 0x22, 0xff],
        quads,
        draws,
        text: vec![(0, 0, 19)],
    }
}

// ---- evaluation --------------------------------------------------------------------------

#[derive(Debug, Default, Clone)]
struct Tally {
    compared: u64,
    exact: u64,
    max_diff: u8,
    /// bounding box of the mismatches
    bad_box: Option<(u32, u32, u32, u32)>,
}

fn check(scene: &Scene, ip: Interp, mode: Mode) -> Tally {
    let img = nv2a::frame("Pixel_shader", scene.name);
    let mut t = Tally::default();
    let dump = std::env::var("NV2A_DUMP").ok();
    let mut diff_img = image::RgbaImage::new(W, H);
    for y in 0..H {
        for x in 0..W {
            let quads: Vec<usize> = (0..scene.quads.len())
                .filter(|&k| scene.quads[k].covers(x, y))
                .collect();
            if quads.is_empty() || in_text(&scene.text, x, y) {
                continue;
            }
            let mut px = scene.clear;
            for d in scene.draws.iter().filter(|d| quads.contains(&d.quad)) {
                let coords = scene.quads[d.quad].at(x, y, ip);
                let (c, live) = shade(&d.shader, &d.combiner, &coords, d.diffuse, mode);
                if live {
                    px = blend(c, px);
                }
            }
            let got = img.get_pixel(x, y).0;
            t.compared += 1;
            let diff = (0..4).map(|i| px[i].abs_diff(got[i])).max().unwrap_or(0);
            if dump.is_some() {
                diff_img.put_pixel(x, y, image::Rgba(px));
            }
            if diff == 0 {
                t.exact += 1;
            } else {
                t.max_diff = t.max_diff.max(diff);
                let b = t.bad_box.get_or_insert((x, y, x, y));
                *b = (b.0.min(x), b.1.min(y), b.2.max(x), b.3.max(y));
            }
        }
    }
    if let Some(d) = dump {
        let _ = diff_img.save(format!("{d}/{}-{:?}.png", scene.name, ip.offset));
    }
    t
}

/// The unit's parameters the frames were matched with: the defaults, with coordinates that
/// reach the unit truncated (toward minus infinity) to s16.16 by the interpolator.
fn params() -> ShaderParams {
    let p = ShaderParams::default();
    ShaderParams {
        coord: Encoding {
            quant: bumpsim_hw::Quant::Trn,
            ..p.coord
        },
        ..p
    }
}

fn scenes(params: ShaderParams) -> Vec<Scene> {
    vec![
        clip_plane(params, true),
        passthru(params),
        dependent(params, false),
        dependent(params, true),
        bump_env_map(params),
        bump_env_map_luminance(params),
    ]
}

fn share(t: &Tally) -> f64 {
    100.0 * t.exact as f64 / t.compared.max(1) as f64
}

#[test]
fn the_licence_of_the_frames_is_in_the_repository() {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/nv2a/golden/LICENSE-CC0");
    let text =
        std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{} is missing: {e}", p.display()));
    assert!(text.contains("CC0") || text.contains("Creative Commons"));
}

/// (frame, compared, exact) with [`params`], bit-accurate mode, attributes at [`CORNER`], as
/// measured. A drop fails the test.
const EXPECTED: [(&str, u64, u64); 6] = [
    ("ClipPlane", 65536, 65518),
    ("Passthru", 65536, 65536),
    ("StageDependentAlphaRed", 65536, 65536),
    ("StageDependentGreenBlue", 65536, 65536),
    ("BumpEnvMap", 131072, 131071),
    // hypotheses 20 and 21 (docs/units/texture-shader.md)
    ("BumpEnvMapLuminance", 98304, 98304),
];

#[test]
fn the_pixel_shader_frames_are_reproduced() {
    println!(
        "{:<26} {:>9} {:>9} {:>8} {:>5}  mismatches within",
        "frame", "compared", "exact", "share", "max"
    );
    let mut all = (0u64, 0u64);
    let mut results = Vec::new();
    for s in scenes(params()) {
        let t = check(&s, CORNER, Mode::BitAccurate);
        println!(
            "{:<26} {:>9} {:>9} {:>7.3}% {:>5}  {:?}",
            s.name,
            t.compared,
            t.exact,
            share(&t),
            t.max_diff,
            t.bad_box
        );
        all.0 += t.compared;
        all.1 += t.exact;
        results.push((s.name, t.compared, t.exact));
    }
    println!(
        "{:<26} {:>9} {:>9} {:>7.3}%",
        "all",
        all.0,
        all.1,
        100.0 * all.1 as f64 / all.0.max(1) as f64
    );
    assert_eq!(
        results.len(),
        EXPECTED.len(),
        "a frame without its expected counts"
    );
    for ((name, compared, exact), (ename, ec, ee)) in results.iter().zip(EXPECTED) {
        assert_eq!(*name, ename);
        assert_eq!((*compared, *exact), (ec, ee), "{name}: (compared, exact)");
    }
}

/// The coordinate precision and sample-offset sweep behind the docs' table (slow-ish: run
/// with `--ignored`).
#[test]
#[ignore]
fn sweep_interpolation_precision() {
    use bumpsim_hw::{Format, Quant};
    for frac in [8u8, 10, 12, 14, 16, 20, 24] {
        for off in [-0.03125, 0.0, 0.03125] {
            for q in [Quant::Trn, Quant::Rnd] {
                let p = ShaderParams {
                    coord: Encoding {
                        quant: q,
                        ..Encoding::fixed(Format::s(32, frac))
                    },
                    ..ShaderParams::default()
                };
                let s = passthru(p);
                let t = check(
                    &s,
                    Interp {
                        offset: off,
                        ..CENTRE
                    },
                    Mode::BitAccurate,
                );
                let c = clip_plane(p, true);
                let tc = check(
                    &c,
                    Interp {
                        offset: off,
                        ..CENTRE
                    },
                    Mode::BitAccurate,
                );
                println!(
                    "frac {frac} off {off} {q:?}: passthru {:.3}% clip {:.3}%",
                    share(&t),
                    share(&tc)
                );
            }
        }
    }
}

#[test]
fn the_frames_decide_the_hypotheses() {
    use bumpsim_hw::Quant;
    let p = params();
    let rnd_coords = ShaderParams {
        coord: ShaderParams::default().coord,
        ..p
    };
    let round = ShaderParams {
        pass_through: Encoding {
            quant: Quant::Rnd,
            ..p.pass_through
        },
        convert_frac: None,
        ..p
    };
    let truncate = ShaderParams {
        convert_frac: None,
        ..p
    };
    let pass = |k: u32| ShaderParams {
        convert_frac: Some(k),
        ..p
    };
    let variants: Vec<(&str, Interp, ShaderParams, Mode, bool)> = vec![
        (
            "corner, coords trn (model)",
            CORNER,
            p,
            Mode::BitAccurate,
            true,
        ),
        ("pixel centre (o = 1/2)", CENTRE, p, Mode::BitAccurate, true),
        (
            "o = -1/32",
            Interp {
                offset: -0.03125,
                ..CORNER
            },
            p,
            Mode::BitAccurate,
            true,
        ),
        (
            "o = 1/32",
            Interp {
                offset: 0.03125,
                ..CORNER
            },
            p,
            Mode::BitAccurate,
            true,
        ),
        (
            "other diagonal",
            Interp {
                other_diagonal: true,
                ..CORNER
            },
            p,
            Mode::BitAccurate,
            true,
        ),
        (
            "coords rounded",
            CORNER,
            rnd_coords,
            Mode::BitAccurate,
            true,
        ),
        (
            "pass-through rounds",
            CORNER,
            round,
            Mode::BitAccurate,
            true,
        ),
        (
            "pass-through truncates",
            CORNER,
            truncate,
            Mode::BitAccurate,
            true,
        ),
        ("convert_frac 11", CORNER, pass(11), Mode::BitAccurate, true),
        ("convert_frac 13", CORNER, pass(13), Mode::BitAccurate, true),
        (
            "clip bit set culls < 0",
            CORNER,
            p,
            Mode::BitAccurate,
            false,
        ),
        ("exact f64 mode", CORNER, p, Mode::Exact, true),
    ];
    println!(
        "{:<28} {:>10} {:>10} {:>10} {:>10} {:>10}",
        "model", "ClipPlane", "Passthru", "DepAR", "DepGB", "EnvMap"
    );
    let mut rows = Vec::new();
    for (name, ip, params, mode, bit) in variants {
        let mut ss = scenes(params);
        ss[0] = clip_plane(params, bit);
        let row: Vec<f64> = ss.iter().map(|s| share(&check(s, ip, mode))).collect();
        println!(
            "{name:<28} {}",
            row.iter().map(|v| format!("{v:>9.3}%")).collect::<String>()
        );
        rows.push(row);
    }
    // the model is best on ClipPlane and Passthru of every variant; the comparator reading,
    // the diagonal and the pass-through conversion are settled by large margins
    for r in &rows[1..] {
        assert!(
            r[0] <= rows[0][0] && r[1] <= rows[0][1],
            "{r:?} vs {:?}",
            rows[0]
        );
    }
    assert_eq!(
        (rows[0][1], rows[0][5]),
        (100.0, 100.0),
        "Passthru, luminance"
    );
    // the converter without its +1 or at another width loses both frames
    for r in &rows[6..10] {
        assert!(r[1] < 95.0 && r[5] < 99.5, "{r:?}");
    }
    assert!(rows[10][0] < 80.0 && rows[4][1] < 10.0, "{rows:?}");
    assert!(rows[6][1] < 30.0 && rows[7][1] < 90.0, "{rows:?}");
    assert!(rows[8][1] < 90.0 && rows[9][1] < 95.0, "{rows:?}");
}

/// Hypothesis 20 (`BumpEnvMapLuminance`): the NV2A clamps the luminance `scale R / 255 +
/// offset` at 0 only and converts each RGB product `(c / 255) l` with the colour converter
/// (12 fraction bits, the top of the step; saturating at 255); NV_texture_shader's reading
/// (clamp to [0, 1], the product rounded) loses every quad whose factor passes 1.
#[test]
fn the_luminance_frame_decides_its_clamp() {
    let p = params();
    let nv2a = share(&check(
        &bump_env_map_luminance_as(p, true),
        CORNER,
        Mode::BitAccurate,
    ));
    let spec = share(&check(
        &bump_env_map_luminance_as(p, false),
        CORNER,
        Mode::BitAccurate,
    ));
    println!("BumpEnvMapLuminance: NV2A reading {nv2a:.3} %, NV_texture_shader's {spec:.3} %");
    assert!(nv2a == 100.0 && spec < 60.0, "{nv2a} {spec}");
}
