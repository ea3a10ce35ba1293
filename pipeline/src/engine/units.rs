//! The unit catalogue: each config variant builds one hardware unit of `bumpsim-hw`.
//!
//! A unit takes the encodings of its inputs from the signals wired to them (so changing a width
//! upstream propagates), and states its own output encodings. Adding a unit to bumpsim means
//! writing it in `hw/src/units/` and adding a variant here; the simulator does not change.

use crate::scene::{NormalMethod, Scene};
use bumpsim_hw::units::{
    Address, BlendKind, BumpBlend, BumpBlendParams, Clamp, CullFragment, CullTest, Dot3,
    EmbossFilter, Filter, LightState, Modulate, Normalize, PowerTable, Selective, Shade,
    ShadeInputs, ShadeParams, SpecGen, TexFetch, Texels, VecSource,
};
use bumpsim_hw::units::{BuilderFormats, LightingFn, PaletteBuilder, QuantizedFetch};
use bumpsim_hw::{Codec, Encoding, Format, PortSpec, Unit};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// What a texel fetch unit reads.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum TextureSource {
    /// The scene's bump map as a tangent-space normal map of `size` x `size` texels, baked by
    /// `method` (from heights) or resampled (from a normal PNG).
    BumpNormals { size: u32, method: NormalMethod },
    /// The scene's bump map as heights in [0, 1] (normalised to the map's range).
    BumpHeights { size: u32 },
    /// The scene's colour texture (RGB in [0, 1]); its sides must be powers of two.
    ColorTexture,
    /// The mesh's perturbed normals in object space, baked by rasterising the mesh in uv space
    /// (`scene/bake.rs`): a bump map "containing the computed surface normals ... plus the
    /// bump-structure" (Ernst et al. §5.4.2, Fig. 8).
    ObjectNormals { size: u32 },
    /// A lighting table for a dependent lookup at (N·L, N·H) of light `light` (the
    /// DOT_PRODUCT_TEXTURE_2D use of NV20 texture shaders): texel (i, j) holds the scene
    /// material's Blinn-Phong colour at s = (i + 1/2) / size, t = (j + 1/2) / size,
    /// `ambient + color (diffuse s + specular t^shininess)` (no specular where s is 0), each
    /// channel clamped to [0, 1]. Read it with `address: Clamp` so that s = 1 reads the last
    /// column.
    LightingTable { size: u32, light: usize },
}

fn is_wrap(a: &Address) -> bool {
    *a == Address::Wrap
}
fn default_ports() -> u32 {
    4
}
fn default_latency() -> u32 {
    4
}
fn one() -> u32 {
    1
}
fn default_weight_bits() -> u32 {
    8
}
fn yes() -> bool {
    true
}
fn default_spec() -> SpecGen {
    SpecGen::Table {
        index_bits: 8,
        value_bits: 8,
    }
}

/// The palette builder's datapath words (`hw/src/units/palette_builder.rs`, "Bit-accurate
/// mode"): the normal table's components, the light / half-way / view vector registers, the
/// intensities after each dot product, and the power generator.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BuilderDatapath {
    pub normal: Encoding,
    pub vector: Encoding,
    pub intensity: Encoding,
    pub power: SpecGen,
}

impl Default for BuilderDatapath {
    /// s1.10 normals and vectors in 12-bit words, 10-bit intensities, a 1024 x 12 power table.
    fn default() -> Self {
        BuilderDatapath {
            normal: fixed(true, 12, 10),
            vector: fixed(true, 12, 10),
            intensity: Encoding::texel(Codec::UnitUnsigned, false, 10),
            power: SpecGen::Table {
                index_bits: 10,
                value_bits: 12,
            },
        }
    }
}

/// A hardware unit and its parameters, as written in a config.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum UnitSpec {
    /// Texel fetch and filter (`hw/src/units/fetch.rs`).
    TexFetch {
        source: TextureSource,
        texel: Encoding,
        #[serde(default)]
        filter: Filter,
        #[serde(default = "default_weight_bits")]
        weight_bits: u32,
        #[serde(default = "default_ports")]
        ports: u32,
        #[serde(default = "default_latency")]
        mem_latency: u32,
        /// Store the texture as indices into a palette of this many entries (Ernst et al. §6),
        /// chosen as directions spread evenly over the hemisphere (bump normals) or the texture
        /// itself quantized to them; each texel takes the nearest entry.
        #[serde(default)]
        palette: Option<u32>,
        /// Addressing outside [0, 1) on both axes (default wrap; left out of the canonical
        /// config, and so of the config hash, when it is the default).
        #[serde(default, skip_serializing_if = "is_wrap")]
        address: Address,
        out: Encoding,
    },
    /// Conditional fragment culling (NV_texture_shader CULL_FRAGMENT,
    /// `hw/src/units/cull.rs`): one test per lane of `v` against zero; the fragment is killed
    /// when any fails. An engine with this unit tests depth after shading.
    CullFragment { tests: Vec<CullTest> },
    /// Dot products of `a` with `count` vectors `b0..` (`hw/src/units/dot3.rs`).
    Dot3 {
        count: u32,
        #[serde(default = "one")]
        parallel: u32,
        #[serde(default)]
        clamp: Clamp,
        out: Encoding,
    },
    /// `x^n` through a loadable table (`hw/src/units/power.rs`). `shininess` defaults to the
    /// scene material's.
    PowerTable {
        count: u32,
        index_bits: u32,
        value_bits: u32,
        #[serde(default)]
        shininess: Option<f64>,
        #[serde(default = "one")]
        parallel: u32,
    },
    /// `v / |v|` through a reciprocal square root table (`hw/src/units/normalize.rs`).
    Normalize {
        table_bits: u32,
        value_bits: u32,
        out: Encoding,
    },
    /// Light combiner (`hw/src/units/shade.rs`) over the scene's bump lights.
    Shade {
        #[serde(default = "yes")]
        specular: bool,
        /// Use a `base` colour input (a texel) instead of white.
        #[serde(default)]
        base: bool,
        /// Add a `src` colour input (the Gouraud colour).
        #[serde(default)]
        src: bool,
        #[serde(default = "one")]
        parallel: u32,
        coef: Encoding,
        out: Encoding,
    },
    /// Gouraud bump blend unit (`hw/src/units/blend.rs`, Ernst et al. 1998 §4.2) over the
    /// scene's bump lights. Bump-state vectors (`State`) are the lights' directions and the
    /// half vectors of a parallel viewer in the object's frame (the bump vector space),
    /// computed once per frame; `Port` vectors arrive as `l0..`, `h0..` inputs.
    BumpBlend {
        kind: BlendKind,
        #[serde(default)]
        l_source: VecSource,
        #[serde(default)]
        h_source: VecSource,
        #[serde(default = "default_spec")]
        spec: SpecGen,
        /// Defaults to the scene material's shininess.
        #[serde(default)]
        shininess: Option<f64>,
        state: Encoding,
        color: Encoding,
        dot: Encoding,
        out: Encoding,
        #[serde(default)]
        selective: Selective,
        #[serde(default = "one")]
        parallel: u32,
    },
    /// Texture stage: `c * t` per channel (`hw/src/units/modulate.rs`, Ernst et al. §5.1).
    Modulate { out: Encoding },
    /// Quantized normal maps (Tarini et al. §3–6, `hw/src/units/quantized_fetch.rs`): the
    /// object-space normals baked at `size` x `size` are quantized to `s_n` entries (median
    /// cut or NeuQuant, optionally Floyd–Steinberg dithered; with several scene materials,
    /// one interval of entries per material, §6) stored as `index_bits`-bit indices; per
    /// frame the table is shaded by each material's lighting model in object space and
    /// loaded into the colour LUT; per fragment the index under `uv` (nearest) reads its
    /// colour. `split` (§7.1): alpha holds the Lambert intensity and RGB the specular colour,
    /// for an `FbBlend` with a base colour (Phong and Lambert materials only). `mipmap`
    /// (§5.2): index mipmap levels built by `NearestToAverage` (or the wrong
    /// `NaiveIndexAverage`), chosen per fragment by a `lod` input (an `Lod` attribute).
    QuantizedNormals {
        size: u32,
        s_n: u32,
        quantizer: crate::quantize::Quantizer,
        #[serde(default)]
        dither: bool,
        index_bits: u32,
        #[serde(default)]
        split: bool,
        #[serde(default)]
        mipmap: Option<crate::quantize::MipMode>,
        #[serde(default)]
        datapath: BuilderDatapath,
        entry: Encoding,
        #[serde(default = "one")]
        entries_per_clock: u32,
        #[serde(default = "one")]
        load_width: u32,
    },
    /// Framebuffer blending of Tarini et al. §7 (`hw/src/units/fb_blend.rs`): the `base`
    /// colour (a colour texture fetch) with a split palette `entry` by equation (1), three
    /// passes, or (2), two passes, into framebuffer words of `fb`.
    FbBlend {
        equation: bumpsim_hw::units::BlendEquation,
        fb: Encoding,
    },
    /// Schlag's 3x3 emboss masks over the bump heights (`hw/src/units/emboss.rs`).
    EmbossFilter {
        size: u32,
        texel: Encoding,
        /// Schlag's bevel width `w` (N_z = 6 * 255 / w). Left out, it is chosen so that the
        /// filter reproduces the height field's true slope: `w = (F_max - F_min) * size`.
        #[serde(default)]
        bevel_w: Option<f64>,
        #[serde(default = "default_ports")]
        ports: u32,
        #[serde(default = "default_latency")]
        mem_latency: u32,
        out: Encoding,
    },
}

/// What a unit's build may read of the scene.
pub struct BuildCtx<'a> {
    pub scene: &'a Scene,
}

impl BuildCtx<'_> {
    /// Indices of the lights the bump engine shades with.
    pub fn bump_lights(&self) -> Vec<usize> {
        self.scene
            .lights
            .iter()
            .enumerate()
            .filter(|(_, l)| l.bump)
            .map(|(i, _)| i)
            .collect()
    }
}

fn seq(prefix: &str, n: u32) -> Vec<String> {
    (0..n).map(|i| format!("{prefix}{i}")).collect()
}

fn check_parallel(parallel: u32, count: u32) -> Result<(), String> {
    if (1..=count.max(1)).contains(&parallel) {
        Ok(())
    } else {
        Err(format!(
            "parallel {parallel}: expected 1 to {} datapaths",
            count.max(1)
        ))
    }
}

fn check_size(size: u32) -> Result<(), String> {
    if size.is_power_of_two() && (1..=4096).contains(&size) {
        Ok(())
    } else {
        Err(format!(
            "size {size}: expected a power of two from 1 to 4096"
        ))
    }
}

fn input<'a>(ins: &'a BTreeMap<String, PortSpec>, name: &str) -> Result<&'a PortSpec, String> {
    ins.get(name)
        .ok_or_else(|| format!("input {name:?} is not wired"))
}

impl UnitSpec {
    /// Names of the input ports this unit will have, for wiring before it is built.
    pub fn input_names(&self, ctx: &BuildCtx) -> Vec<String> {
        match self {
            UnitSpec::QuantizedNormals {
                mipmap: Some(_), ..
            } => vec!["uv".into(), "lod".into()],
            UnitSpec::TexFetch { .. }
            | UnitSpec::EmbossFilter { .. }
            | UnitSpec::QuantizedNormals { .. } => vec!["uv".into()],
            UnitSpec::BumpBlend { .. } => self
                .blend_params(ctx)
                .map_or_else(|_| vec!["c".into(), "b".into()], |p| p.input_names()),
            UnitSpec::Modulate { .. } => vec!["c".into(), "t".into()],
            UnitSpec::FbBlend { .. } => vec!["base".into(), "entry".into()],
            UnitSpec::Dot3 { count, .. } => std::iter::once("a".to_string())
                .chain(seq("b", *count))
                .collect(),
            UnitSpec::PowerTable { count, .. } => seq("x", *count),
            UnitSpec::Normalize { .. } | UnitSpec::CullFragment { .. } => vec!["v".into()],
            UnitSpec::Shade {
                specular,
                base,
                src,
                ..
            } => {
                let k = ctx.bump_lights().len() as u32;
                let mut v = seq("d", k);
                if *specular {
                    v.extend(seq("s", k));
                }
                if *base {
                    v.push("base".into());
                }
                if *src {
                    v.push("src".into());
                }
                v
            }
        }
    }

    /// Build the unit from the encodings of the signals wired to its inputs.
    pub fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        ctx: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String> {
        Ok(match self {
            UnitSpec::TexFetch {
                source,
                texel,
                filter,
                weight_bits,
                ports,
                mem_latency,
                palette,
                address,
                out,
            } => {
                let uv = input(ins, "uv")?.enc;
                let mut tex = texels(source, ctx)?;
                if let Some(n) = *palette {
                    if !(2..=65536).contains(&n) {
                        return Err(format!("palette {n}: expected 2 to 65536 entries"));
                    }
                    let entries = match source {
                        TextureSource::BumpNormals { .. } => super::palette::hemisphere(n as usize),
                        _ => return Err("palette: expected source BumpNormals (palettes of other textures are not modelled yet)".into()),
                    };
                    super::palette::quantize(&mut tex.values, &entries);
                }
                let unit = TexFetch::new(
                    uv,
                    tex,
                    *texel,
                    *filter,
                    *weight_bits,
                    *ports,
                    *mem_latency,
                    *out,
                )?
                .with_address(*address, *address);
                Box::new(match palette {
                    Some(n) => unit.with_palette(*n),
                    None => unit,
                })
            }
            UnitSpec::CullFragment { tests } => {
                Box::new(CullFragment::new(input(ins, "v")?.enc, tests)?)
            }
            UnitSpec::Dot3 {
                count,
                parallel,
                clamp,
                out,
            } => {
                if !(1..=8).contains(count) {
                    return Err(format!("count {count}: expected 1 to 8 vectors"));
                }
                check_parallel(*parallel, *count)?;
                let a = input(ins, "a")?.enc;
                let b = input(ins, "b0")?.enc;
                Box::new(Dot3::new(a, b, *count, *parallel, *clamp, *out))
            }
            UnitSpec::PowerTable {
                count,
                index_bits,
                value_bits,
                shininess,
                parallel,
            } => {
                if !(1..=8).contains(count) {
                    return Err(format!("count {count}: expected 1 to 8 inputs"));
                }
                check_parallel(*parallel, *count)?;
                if !(1..=16).contains(index_bits) {
                    return Err(format!("index_bits {index_bits}: expected 1 to 16"));
                }
                if !(1..=32).contains(value_bits) {
                    return Err(format!("value_bits {value_bits}: expected 1 to 32"));
                }
                let n = shininess.unwrap_or(ctx.scene.material.shininess);
                if !(n.is_finite() && n > 0.0) {
                    return Err(format!("shininess {n}: expected a number above 0"));
                }
                let x = input(ins, "x0")?.enc;
                Box::new(PowerTable::new(
                    x,
                    *count,
                    *index_bits,
                    *value_bits,
                    n,
                    *parallel,
                ))
            }
            UnitSpec::Normalize {
                table_bits,
                value_bits,
                out,
            } => Box::new(Normalize::new(
                input(ins, "v")?.enc,
                *table_bits,
                *value_bits,
                *out,
            )?),
            UnitSpec::Shade {
                specular,
                base,
                src,
                parallel,
                coef,
                out,
            } => {
                let lights = ctx.bump_lights();
                if lights.is_empty() {
                    return Err(
                        "the scene has no light with bump: true: expected at least one".into(),
                    );
                }
                check_parallel(*parallel, lights.len() as u32)?;
                let m = &ctx.scene.material;
                let params = ShadeParams {
                    ambient: m.ambient,
                    diffuse: m.diffuse,
                    specular: m.specular,
                    light_colors: lights.iter().map(|&i| ctx.scene.lights[i].color).collect(),
                };
                let has = ShadeInputs {
                    specular: if *specular {
                        Some(input(ins, "s0")?.enc)
                    } else {
                        None
                    },
                    base: if *base {
                        Some(input(ins, "base")?.enc)
                    } else {
                        None
                    },
                    src: if *src {
                        Some(input(ins, "src")?.enc)
                    } else {
                        None
                    },
                };
                Box::new(Shade::new(
                    input(ins, "d0")?.enc,
                    has,
                    params,
                    *coef,
                    *parallel,
                    *out,
                ))
            }
            UnitSpec::BumpBlend { .. } => {
                let params = self.blend_params(ctx)?;
                Box::new(BumpBlend::new(params, |n| ins.get(n).map(|p| p.enc))?)
            }
            UnitSpec::Modulate { out } => Box::new(Modulate::new(
                input(ins, "c")?.enc,
                input(ins, "t")?.enc,
                *out,
            )),
            UnitSpec::QuantizedNormals { .. } => Box::new(self.build_quantized(ins, ctx)?),
            UnitSpec::FbBlend { equation, fb } => Box::new(bumpsim_hw::units::FbBlend::new(
                *equation,
                input(ins, "base")?.enc,
                input(ins, "entry")?.enc,
                *fb,
            )?),
            UnitSpec::EmbossFilter {
                size,
                texel,
                bevel_w,
                ports,
                mem_latency,
                out,
            } => {
                check_size(*size)?;
                let raw = ctx.scene.bump.bake_heights(*size, *size).ok_or(
                    "the scene's bump map holds normals, not heights: expected a height map",
                )?;
                let (lo, hi) = height_range(&raw);
                let w = bevel_w.unwrap_or(if hi > lo {
                    (hi - lo) * *size as f64
                } else {
                    1.0
                });
                let h = normalise_heights(&raw);
                Box::new(EmbossFilter::new(
                    input(ins, "uv")?.enc,
                    h,
                    *size,
                    *size,
                    *texel,
                    w,
                    *ports,
                    *mem_latency,
                    *out,
                )?)
            }
        })
    }
}

/// Smallest and largest height.
fn height_range(h: &[f64]) -> (f64, f64) {
    h.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        })
}

impl UnitSpec {
    /// The blend unit's parameters: the scene's bump lights with their bump-state vectors in
    /// the object's frame (a parallel light and a parallel viewer taken at the object's origin).
    fn blend_params(&self, ctx: &BuildCtx) -> Result<BumpBlendParams, String> {
        let UnitSpec::BumpBlend {
            kind,
            l_source,
            h_source,
            spec,
            shininess,
            state,
            color,
            dot,
            out,
            selective,
            parallel,
        } = self
        else {
            return Err("not a blend unit".into());
        };
        let scene = ctx.scene;
        let lights = ctx.bump_lights();
        if lights.is_empty() {
            return Err("the scene has no light with bump: true: expected at least one".into());
        }
        check_parallel(*parallel, lights.len() as u32)?;
        let m3 = glam::DMat3::from_mat4(scene.model);
        let to_object = m3.inverse();
        let origin = scene.model.transform_point3(glam::DVec3::ZERO);
        let v = (to_object * scene.camera.view_dir(origin)).normalize_or_zero();
        let lights = lights
            .iter()
            .map(|&i| {
                let light = &scene.lights[i];
                let l = (to_object * light.dir_from(origin)).normalize_or_zero();
                // The colour register holds the light colour weighted by the material term the
                // unit adds (kd for diffuse, ks for specular), as a host would load it; `Both`
                // adds both terms with one register, so it takes the plain light colour
                // (kd = ks = 1, the paper's equation).
                let w = match kind {
                    BlendKind::Diffuse => scene.material.diffuse,
                    BlendKind::Specular => scene.material.specular,
                    BlendKind::Both => [1.0; 3],
                };
                let color = std::array::from_fn(|c| light.color[c] * w[c]);
                LightState {
                    color,
                    l: l.to_array(),
                    h: (l + v).normalize_or_zero().to_array(),
                    k: 1.0,
                }
            })
            .collect();
        Ok(BumpBlendParams {
            kind: *kind,
            lights,
            l_source: *l_source,
            h_source: *h_source,
            spec: *spec,
            shininess: shininess.unwrap_or(scene.material.shininess),
            state: *state,
            color: *color,
            dot: *dot,
            out: *out,
            selective: *selective,
            parallel: *parallel,
        })
    }
}

impl UnitSpec {
    /// Bake, quantize, build the colour table and the unit (Tarini et al. §3–6).
    fn build_quantized(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        ctx: &BuildCtx,
    ) -> Result<QuantizedFetch, String> {
        let UnitSpec::QuantizedNormals {
            size,
            s_n,
            quantizer,
            dither,
            index_bits,
            split,
            mipmap,
            datapath,
            entry,
            entries_per_clock,
            load_width,
        } = self
        else {
            return Err("not a quantized normals unit".into());
        };
        check_size(*size)?;
        if !(8..=14).contains(index_bits) {
            return Err(format!("index_bits {index_bits}: expected 8 to 14"));
        }
        if *s_n < 1 || *s_n > 1 << index_bits {
            return Err(format!(
                "s_n {s_n}: expected 1 to 2^index_bits = {}",
                1u32 << index_bits
            ));
        }
        let uv = input(ins, "uv")?.enc;
        let scene = ctx.scene;
        let b = crate::scene::bake::bake(
            &scene.mesh,
            &scene.bump,
            *size,
            crate::scene::bake::BakeSpace::Object,
            crate::reference::Perturbation::ScaleInvariant,
        );
        let normals = &b.map.texels;
        let (w, n) = (*size as usize, *s_n as usize);
        let (pal, intervals) = match &scene.looks.regions {
            None => {
                let mut pal =
                    crate::quantize::quantize(normals, n, *quantizer).map_err(|e| e.to_string())?;
                if *dither {
                    pal.indices = crate::quantize::dither(
                        normals,
                        w,
                        w,
                        &pal.entries,
                        crate::quantize::Scan::Serpentine,
                    );
                }
                let len = pal.entries.len();
                (pal, std::iter::once(0..len).collect())
            }
            Some(r) => {
                // Tarini §6: the material is a fourth, discrete component of each texel
                let ids: Vec<u8> = normals
                    .iter()
                    .enumerate()
                    .map(|(k, nrm)| {
                        let uv = glam::DVec2::new(
                            ((k % w) as f64 + 0.5) / w as f64,
                            ((k / w) as f64 + 0.5) / w as f64,
                        );
                        r.material_at(uv, *nrm)
                    })
                    .collect();
                let mut mp = crate::quantize::quantize_with_materials(normals, &ids, n, *quantizer)
                    .map_err(|e| e.to_string())?;
                if *dither {
                    mp.palette.indices =
                        mp.dither(normals, &ids, w, w, crate::quantize::Scan::Serpentine);
                }
                (mp.palette, mp.intervals)
            }
        };
        let materials = intervals
            .into_iter()
            .enumerate()
            .filter(|(_, r)| !r.is_empty())
            .map(|(id, r)| Ok((r, lighting_fn(ctx, id as u8, *split)?)))
            .collect::<Result<Vec<_>, String>>()?;
        let formats = BuilderFormats {
            normal: datapath.normal,
            vector: datapath.vector,
            intensity: datapath.intensity,
            power: datapath.power,
            entry: *entry,
        };
        let table = pal.entries.iter().map(|n| n.to_array()).collect();
        let builder = PaletteBuilder::new(table, materials, formats, *entries_per_clock)?;
        let unit = QuantizedFetch::new(
            uv,
            *size,
            *size,
            &pal.indices,
            *index_bits,
            builder,
            *load_width,
            default_latency(),
        )?;
        let Some(mode) = mipmap else {
            return Ok(unit);
        };
        // Tarini §5.2: every coarser level from the one below, down to 1 x 1
        let mut levels = Vec::new();
        let (mut idx, mut w) = (pal.indices, *size as usize);
        while w > 1 {
            let (next, w2, _) = crate::quantize::mip_indices(&idx, w, w, &pal.entries, *mode)
                .map_err(|e| e.to_string())?;
            levels.push((w2 as u32, w2 as u32, next.clone()));
            (idx, w) = (next, w2);
        }
        unit.with_mipmaps(input(ins, "lod")?.enc, levels)
    }
}

/// Material `id`'s lighting model as a palette-builder function, every vector taken into
/// object space with the inverse model matrix (Tarini §5: a parallel light and viewer taken
/// at the object's origin). `split`: the §7.1 form for blending with a base colour.
fn lighting_fn(ctx: &BuildCtx, id: u8, split: bool) -> Result<LightingFn, String> {
    use crate::scene::Shading;
    let scene = ctx.scene;
    let m = scene.material(id);
    let to_object = glam::DMat3::from_mat4(scene.model).inverse();
    let origin = scene.model.transform_point3(glam::DVec3::ZERO);
    let obj = |v: glam::DVec3| (to_object * v).normalize_or_zero().to_array();
    let view = obj(scene.camera.view_dir(origin));
    let lights: Vec<([f64; 3], [f64; 3])> = ctx
        .bump_lights()
        .iter()
        .map(|&i| (obj(scene.lights[i].dir_from(origin)), scene.lights[i].color))
        .collect();
    let lit = !matches!(m.model, Shading::Chrome { .. } | Shading::EnvMap { .. });
    if lit && lights.is_empty() {
        return Err("the scene has no light with bump: true: expected at least one".into());
    }
    let mean = |c: [f64; 3]| (c[0] + c[1] + c[2]) / 3.0;
    if split {
        let specular = match m.model {
            Shading::Phong => m.specular,
            Shading::Lambert => [0.0; 3],
            _ => {
                return Err(format!(
                    "split: material {id} uses the {} model: expected Phong or Lambert (Tarini \
                     §7 blends the specular and diffuse terms)",
                    m.model.name()
                ))
            }
        };
        return Ok(LightingFn::SpecularSplit {
            ambient: mean(m.ambient),
            diffuse: mean(m.diffuse),
            specular,
            shininess: m.shininess,
            view,
            lights,
        });
    }
    Ok(match &m.model {
        Shading::Phong => LightingFn::Specular {
            ambient: m.ambient,
            diffuse: m.diffuse,
            specular: m.specular,
            shininess: m.shininess,
            view,
            lights,
        },
        Shading::Lambert => LightingFn::Lambert {
            ambient: m.ambient,
            diffuse: m.diffuse,
            lights,
        },
        Shading::Cartoon { bands } => LightingFn::Cartoon {
            bands: *bands,
            ambient: m.ambient,
            diffuse: m.diffuse,
            lights,
        },
        Shading::DoubledAnglePhong => LightingFn::DoubledAnglePhong {
            ambient: m.ambient,
            diffuse: m.diffuse,
            specular: m.specular,
            shininess: m.shininess,
            view,
            light: lights[0],
        },
        Shading::Chrome { sky, ground } => LightingFn::Chrome {
            view,
            up: obj(glam::DVec3::Y),
            sky: *sky,
            ground: *ground,
        },
        Shading::EnvMap { .. } => {
            let img = scene
                .looks
                .env_maps
                .get(id as usize)
                .and_then(Option::as_ref)
                .ok_or_else(|| format!("material {id}: its environment map is not loaded"))?;
            LightingFn::EnvMap {
                view,
                up: obj(glam::DVec3::from(scene.camera.up)),
                image: img.rows_bottom_up(),
                width: img.width,
                height: img.height,
            }
        }
    })
}

/// Heights rescaled to [0, 1] over the map's range (a constant map becomes 0.5).
fn normalise_heights(h: &[f64]) -> Vec<f64> {
    let (lo, hi) = height_range(h);
    if hi - lo < 1e-300 {
        return vec![0.5; h.len()];
    }
    h.iter().map(|x| (x - lo) / (hi - lo)).collect()
}

fn texels(source: &TextureSource, ctx: &BuildCtx) -> Result<Texels, String> {
    match *source {
        TextureSource::BumpNormals { size, method } => {
            check_size(size)?;
            let nm = ctx.scene.bump.bake_normals(size, size, method);
            let values = nm.texels.iter().map(|n| [n.x, n.y, n.z, 0.0]).collect();
            Ok(Texels {
                width: size,
                height: size,
                lanes: 3,
                values,
            })
        }
        TextureSource::BumpHeights { size } => {
            check_size(size)?;
            let h =
                ctx.scene.bump.bake_heights(size, size).ok_or(
                    "the scene's bump map holds normals, not heights: expected a height map",
                )?;
            let values = normalise_heights(&h)
                .into_iter()
                .map(|x| [x, 0.0, 0.0, 0.0])
                .collect();
            Ok(Texels {
                width: size,
                height: size,
                lanes: 1,
                values,
            })
        }
        TextureSource::ObjectNormals { size } => {
            check_size(size)?;
            let b = crate::scene::bake::bake(
                &ctx.scene.mesh,
                &ctx.scene.bump,
                size,
                crate::scene::bake::BakeSpace::Object,
                crate::reference::Perturbation::ScaleInvariant,
            );
            let values = b.map.texels.iter().map(|n| [n.x, n.y, n.z, 0.0]).collect();
            Ok(Texels {
                width: size,
                height: size,
                lanes: 3,
                values,
            })
        }
        TextureSource::LightingTable { size, light } => {
            check_size(size)?;
            let scene = ctx.scene;
            let l = scene.lights.get(light).ok_or_else(|| {
                format!(
                    "light {light}: the scene has {} lights: expected an index below that",
                    scene.lights.len()
                )
            })?;
            let m = &scene.material;
            let color = l.color();
            let n = f64::from(size);
            let values = (0..size)
                .flat_map(|j| (0..size).map(move |i| (i, j)))
                .map(|(i, j)| {
                    let (s, t) = ((f64::from(i) + 0.5) / n, (f64::from(j) + 0.5) / n);
                    let spec = if s > 0.0 { t.powf(m.shininess) } else { 0.0 };
                    let mut v = [0.0; 4];
                    for c in 0..3 {
                        v[c] = (m.ambient[c]
                            + color[c] * (m.diffuse[c] * s + m.specular[c] * spec))
                            .clamp(0.0, 1.0);
                    }
                    v
                })
                .collect();
            Ok(Texels {
                width: size,
                height: size,
                lanes: 3,
                values,
            })
        }
        TextureSource::ColorTexture => {
            let img =
                ctx.scene.color_texture.as_ref().ok_or(
                    "the scene has no color_texture: expected one for source ColorTexture",
                )?;
            let values = img
                .pixels()
                .map(|p| {
                    [
                        p.0[0] as f64 / 255.0,
                        p.0[1] as f64 / 255.0,
                        p.0[2] as f64 / 255.0,
                        0.0,
                    ]
                })
                .collect();
            Ok(Texels {
                width: img.width(),
                height: img.height(),
                lanes: 3,
                values,
            })
        }
    }
}

/// A plain fixed-point encoding.
fn fixed(signed: bool, width: u8, frac: u8) -> Encoding {
    Encoding::fixed(Format {
        signed,
        width,
        frac,
    })
}
