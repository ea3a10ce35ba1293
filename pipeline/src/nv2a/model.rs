//! The model of a frame: the host's textures, each pass's units built once, and the colour
//! each pass leaves at a pixel (the quad's interpolated texture coordinates through the
//! texture-shader unit, the register-combiner unit, the ROP's blend).

use super::frame::{Frame, Pass, Quad, Reading, Region, Sample, TextureDef, TextureSource};
use bumpsim_hw::sampler::Sampler;
use bumpsim_hw::units::combiner::{Combiner, CombinerParams};
use bumpsim_hw::units::texture_shader::{ShaderParams, StageSpec, TextureShader};
use bumpsim_hw::{Codec, Encoding, Format, Mode, Quant, Texels, Texture, Unit, Word};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

const U8: Encoding = Encoding::texel(Codec::UnitUnsigned, false, 8);

/// The ROP's blend of the NV2A frames: SRC_ALPHA, ONE_MINUS_SRC_ALPHA on all four channels,
/// `(s a + d (255 - a)) / 255` rounded to nearest (what the Combiner frames settle).
pub fn blend(s: [u8; 4], d: [u8; 4]) -> [u8; 4] {
    let a = s[3] as u32;
    std::array::from_fn(|c| {
        let t = s[c] as u32 * a + d[c] as u32 * (255 - a);
        ((2 * t + 255) / 510) as u8
    })
}

/// A 16-bit word read as an R5G6B5 texel: each field widened to 8 bits by repeating its top
/// bits; alpha 1.
fn r5g6b5(v: u32) -> [u8; 4] {
    let (r, g, b) = ((v >> 11) & 31, (v >> 5) & 63, v & 31);
    [
        (r << 3 | r >> 2) as u8,
        (g << 2 | g >> 4) as u8,
        (b << 3 | b >> 2) as u8,
        255,
    ]
}

/// The host's `GenerateRGBTestPattern` channel value of `v` in `0..n` (f32, truncated).
fn normal(v: u32, n: u32) -> u32 {
    (v as f32 * 255.0f32 / n as f32) as u32
}

/// The texture's codes at (x, y), of `bits` each.
fn texel(src: &TextureSource, x: u32, y: u32) -> [u32; 4] {
    match *src {
        TextureSource::RadialPattern { width, height } => {
            // four copies of the RGB pattern, alpha falling off from the centre; the host
            // measures dy from cx (its own slip, kept: the frames show it)
            let (hw, hh) = (width / 2, height / 2);
            let (yn, xn) = (normal(y % hh, hh), normal(x % hw, hw));
            let (cx, cy) = (hw as f32, hh as f32);
            let max = cx * cx + cy * cy;
            let (dx, dy) = (x as f32 - cx, y as f32 - cx);
            let a = (255.0f32 * (1.0f32 - (dx * dx + dy * dy) / max)) as u32;
            [yn, xn, 255 - yn, a & 0xff]
        }
        TextureSource::RgbaPattern { width, height } => {
            let (yn, xn) = (normal(y, height), normal(x, width));
            [yn, xn, 255 - yn, (xn + yn) & 0xff]
        }
        TextureSource::Checkerboard {
            cell,
            first,
            second,
            ..
        } => {
            let c = if (x / cell + y / cell).is_multiple_of(2) {
                first
            } else {
                second
            };
            [c & 0xff, (c >> 8) & 0xff, (c >> 16) & 0xff, c >> 24]
        }
        TextureSource::Quadrants {
            split,
            colours,
            reading,
            ..
        } => {
            let c = colours[(y >= split) as usize * 2 + (x >= split) as usize];
            let (r, g, b, a) = (c >> 24, (c >> 16) & 0xff, (c >> 8) & 0xff, c & 0xff);
            let (hi, lo) = (r * 257, b * 257);
            match reading {
                Reading::Rgba8 => [r, g, b, a],
                Reading::R16b16 => [hi, lo, 0, 0],
                Reading::R16b16Bytes => [hi & 0xff, lo >> 8, lo & 0xff, hi >> 8],
            }
        }
        TextureSource::Png(_) => unreachable!("a PNG is read, not generated"),
    }
}

/// (width, height, lanes, bits per code) of a generated texture.
fn shape(src: &TextureSource) -> (u32, u32, u8, u32) {
    match *src {
        TextureSource::RadialPattern { width, height }
        | TextureSource::RgbaPattern { width, height }
        | TextureSource::Checkerboard { width, height, .. } => (width, height, 4, 8),
        TextureSource::Quadrants { size, reading, .. } => match reading {
            Reading::R16b16 => (size, size, 2, 16),
            Reading::Rgba8 | Reading::R16b16Bytes => (size, size, 4, 8),
        },
        TextureSource::Png(_) => (0, 0, 4, 8),
    }
}

/// Build one texture: generated, or read from a PNG beside the frame config. Codes of `bits`
/// become values `c / (2^bits - 1)`, or as two's complement `c / 2^(bits-1)` when `signed`.
fn build_texture(def: &TextureDef, base: &Path) -> Result<Texture, String> {
    let (mut width, mut height, lanes, bits) = shape(&def.source);
    let codes: Vec<[u32; 4]> = match &def.source {
        TextureSource::Png(p) => {
            let path = base.join(p);
            let img = crate::scene::files::read_png(&path, super::frame::MAX_TEXTURE_SIDE)
                .map_err(|e| e.to_string())?
                .to_rgb8();
            (width, height) = img.dimensions();
            img.pixels()
                .map(|px| {
                    let [r, g, b] = px.0.map(u32::from);
                    [r, g, b, 255]
                })
                .collect()
        }
        src => (0..width as u64 * height as u64)
            .map(|k| texel(src, (k % width as u64) as u32, (k / width as u64) as u32))
            .collect(),
    };
    let half = (1u64 << (bits - 1)) as f64;
    let max = ((1u64 << bits) - 1) as f64;
    let value = |c: u32| {
        if def.signed && c as f64 >= half {
            (c as f64 - 2.0 * half) / half
        } else if def.signed {
            c as f64 / half
        } else {
            c as f64 / max
        }
    };
    let t = Texels {
        width,
        height,
        lanes,
        values: codes.into_iter().map(|c| c.map(value)).collect(),
    };
    let codec = if def.signed {
        Codec::UnitSigned
    } else {
        Codec::UnitUnsigned
    };
    Texture::new(&def.name, Encoding::texel(codec, def.signed, bits as u8), t)
}

/// The frame's textures by name.
pub fn textures(f: &Frame, base: &Path) -> Result<BTreeMap<String, Arc<Texture>>, String> {
    let mut out = BTreeMap::new();
    for (i, def) in f.textures.iter().enumerate() {
        let t = build_texture(def, base).map_err(|m| format!("textures[{i}].source: {m}"))?;
        out.insert(def.name.clone(), Arc::new(t));
    }
    Ok(out)
}

/// One pass as built.
enum PassModel {
    /// No shader: the same colour at every pixel.
    Flat([u8; 4]),
    /// A texture shader feeding the combiners, and the other registers' words; `show_depth`:
    /// the pixel shows the replaced depth ([`super::Pass::show_depth`]).
    Shaded {
        shader: Box<TextureShader>,
        combiner: Box<Combiner>,
        regs: Box<[Word; 3]>,
        show_depth: bool,
        /// The shader's mode ([`super::Shader::exact`], else the frame's).
        mode: Mode,
    },
}

/// A quad's passes as built, and the colours that may lie under it.
pub struct QuadModel<'a> {
    quad: &'a Quad,
    sample: Sample,
    mode: Mode,
    passes: Vec<PassModel>,
}

fn combiner_params(width: u32, shader: Option<&TextureShader>) -> CombinerParams {
    let mut p = CombinerParams {
        width,
        ..CombinerParams::default()
    };
    if let Some(u) = shader {
        for i in 0..4 {
            p.inputs[3 + i] = u.result_encoding(i).unwrap_or(U8);
        }
    }
    p
}

/// The texture-shader unit of a pass.
fn build_shader(
    pass: &Pass,
    textures: &BTreeMap<String, Arc<Texture>>,
) -> Result<Option<TextureShader>, String> {
    let Some(s) = &pass.shader else {
        return Ok(None);
    };
    let mut stages = Vec::with_capacity(s.stages.len());
    for (i, st) in s.stages.iter().enumerate() {
        let tex = match &st.texture {
            None => None,
            Some(n) => Some(textures.get(n).cloned().ok_or_else(|| {
                format!(
                    "shader.stages[{i}].texture: {n:?}: expected one of the frame's textures ({})",
                    textures.keys().cloned().collect::<Vec<_>>().join(", ")
                )
            })?),
        };
        let sampler = Sampler::new(st.filter, st.weight_bits)
            .map_err(|m| format!("shader.stages[{i}].weight_bits: {m}"))?
            .with_address(st.address, st.address);
        stages.push(StageSpec::new(st.program, tex).with_sampler(sampler));
    }
    let max = bumpsim_hw::format::MAX_WIDTH as u32;
    if !(24..=max).contains(&s.coord_width) {
        return Err(format!(
            "shader.coord_width: {}: expected 24 to {max} bits (16 of them fraction bits; \
             wider values: `exact: true`)",
            s.coord_width
        ));
    }
    let d = ShaderParams::default();
    let params = ShaderParams {
        coord: Encoding {
            quant: Quant::Trn,
            format: Format::s(s.coord_width as u8, 16),
            ..d.coord
        },
        dot_frac: s.dot_frac,
        offset_frac: s.offset_frac,
        convert_frac: s.convert_frac,
        ..d
    };
    TextureShader::new(params, stages)
        .map(Some)
        .map_err(|m| format!("shader.{m}"))
}

impl<'a> QuadModel<'a> {
    /// Build every pass of `quad`. Errors name the field under the pass.
    pub fn new(
        f: &Frame,
        quad: &'a Quad,
        textures: &BTreeMap<String, Arc<Texture>>,
        mode: Mode,
    ) -> Result<QuadModel<'a>, (usize, String)> {
        let w = |c: [u8; 4]| Word::from_raw(&U8, &c.map(i64::from));
        let mut passes = Vec::with_capacity(quad.passes.len());
        for (j, p) in quad.passes.iter().enumerate() {
            let shader = build_shader(p, textures).map_err(|m| (j, m))?;
            let params = combiner_params(f.combiner_width, shader.as_ref());
            let combiner = Combiner::new(params, p.program.clone())
                .map_err(|m| (j, format!("program.{m}")))?;
            let regs = [w(p.primary), w(p.secondary), w(p.fog)];
            passes.push(match shader {
                None => {
                    let t = w(p.texture);
                    let ins = [regs[0], regs[1], regs[2], t, t, t, t];
                    let mut o = [Word::default()];
                    combiner.eval(mode, &ins, &mut o);
                    PassModel::Flat(o[0].raws::<4>().map(|r| r.clamp(0, 255) as u8))
                }
                Some(u) => PassModel::Shaded {
                    shader: Box::new(u),
                    combiner: Box::new(combiner),
                    regs: Box::new(regs),
                    show_depth: p.show_depth,
                    mode: match &p.shader {
                        Some(s) if s.exact => Mode::Exact,
                        _ => mode,
                    },
                },
            });
        }
        Ok(QuadModel {
            quad,
            sample: f.sample,
            mode,
            passes,
        })
    }

    /// The colours the quad may end as at (x, y), one per colour that may lie under it.
    pub fn colours_at(&self, x: u32, y: u32) -> Vec<[u8; 4]> {
        // (colour, replaces what lies there) per pass that leaves one
        let mut shaded: Vec<Option<([u8; 4], bool)>> = Vec::with_capacity(self.passes.len());
        for p in &self.passes {
            shaded.push(match p {
                PassModel::Flat(c) => Some((*c, false)),
                PassModel::Shaded {
                    shader,
                    combiner,
                    regs,
                    show_depth,
                    mode,
                } => self
                    .shade((shader, *mode), combiner, regs, *show_depth, x, y)
                    .map(|c| (c, *show_depth)),
            });
        }
        self.quad
            .under
            .colours()
            .into_iter()
            .map(|mut d| {
                for &(s, replace) in shaded.iter().flatten() {
                    d = if replace { s } else { blend(s, d) };
                }
                d
            })
            .collect()
    }

    /// One shaded pass at (x, y): the colour (with `show_depth`, the depth as `DrawZBuffer`
    /// shows it), or `None` where the shader culls.
    fn shade(
        &self,
        (u, umode): (&TextureShader, Mode),
        c: &Combiner,
        regs: &[Word; 3],
        show_depth: bool,
        x: u32,
        y: u32,
    ) -> Option<[u8; 4]> {
        let enc = u.params().coord;
        let coords = self.coords_at(x, y);
        let ins: Vec<Word> = coords
            .iter()
            .map(|cs| Word::for_mode(umode, &enc, cs))
            .collect();
        let mut outs = vec![Word::default(); u.outputs().len()];
        u.eval(umode, &ins, &mut outs);
        if !u.live(umode, &ins, &outs) {
            return None;
        }
        if show_depth {
            let z = outs[outs.len() - 1].lanes[0].x.floor().clamp(0.0, 65535.0) as u32;
            return Some(r5g6b5(z));
        }
        let cins = [
            regs[0], regs[1], regs[2], outs[0], outs[1], outs[2], outs[3],
        ];
        let mut o = [Word::default()];
        c.eval(self.mode, &cins, &mut o);
        Some(o[0].raws::<4>().map(|r| r.clamp(0, 255) as u8))
    }

    /// Every stage's texture coordinates at (x, y), at the sample point: bilinear over the
    /// corners where a stage's coordinates are affine over the quad (both triangles in one
    /// plane), otherwise the plane of the pixel's triangle through its three vertices.
    fn coords_at(&self, x: u32, y: u32) -> [[f64; 4]; 4] {
        if !matches!(self.quad.region, Region::Screen { .. }) {
            return [[0.0; 4]; 4];
        }
        let (l, t, r, b) = self.quad.region.projected();
        let o = match self.sample {
            Sample::Centre => 0.5,
            Sample::Corner => 0.0,
        };
        let (px, py) = (x as f64 + o, y as f64 + o);
        let c = [(l, t), (r, t), (r, b), (l, b)];
        // above the v0-v2 diagonal: (v0, v1, v2); below: (v0, v2, v3)
        let cross = (c[2].0 - c[0].0) * (py - c[0].1) - (c[2].1 - c[0].1) * (px - c[0].0);
        let tri = if cross <= 0.0 { [0, 1, 2] } else { [0, 2, 3] };
        let [a, bb, d] = tri.map(|k| c[k]);
        let det = (bb.0 - a.0) * (d.1 - a.1) - (d.0 - a.0) * (bb.1 - a.1);
        let wb = ((px - a.0) * (d.1 - a.1) - (d.0 - a.0) * (py - a.1)) / det;
        let wd = ((bb.0 - a.0) * (py - a.1) - (px - a.0) * (bb.1 - a.1)) / det;
        let wa = 1.0 - wb - wd;
        let (u, v) = ((px - l) / (r - l), (py - t) / (b - t));
        let tc = &self.quad.texcoords;
        std::array::from_fn(|s| {
            let Some(cs) = tc.get(s) else {
                return [0.0; 4];
            };
            let cs = cs.map(|v| v.map(f64::from));
            let affine = (0..4).all(|k| cs[0][k] + cs[2][k] == cs[1][k] + cs[3][k]);
            std::array::from_fn(|k| {
                if affine {
                    let top = cs[0][k] + (cs[1][k] - cs[0][k]) * u;
                    let bot = cs[3][k] + (cs[2][k] - cs[3][k]) * u;
                    top + (bot - top) * v
                } else {
                    wa * cs[tri[0]][k] + wb * cs[tri[1]][k] + wd * cs[tri[2]][k]
                }
            })
        })
    }
}
