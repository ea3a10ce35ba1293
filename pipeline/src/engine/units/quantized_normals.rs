//! Quantized normal maps (Tarini et al. §3–6, `hw/src/units/quantized_fetch.rs`).

use super::checks::check_size;
use super::defaults::{mem_latency, one};
use super::palette_lighting::lighting_fn;
use super::ports::input;
use super::{BuildCtx, Spec};
use crate::quantize::{self, MipMode, NormalMapError, Quantizer, Scan};
use bumpsim_hw::units::{BuilderFormats, PaletteBuilder, QuantizedFetch, SpecGen, SphereAddress};
use bumpsim_hw::{Codec, Encoding, Format, PortSpec, Unit};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The texture coordinate input.
const UV: &str = "uv";
/// The level of detail input (with `mipmap`).
const LOD: &str = "lod";

/// Quantized normal maps (Tarini et al. §3–6, `hw/src/units/quantized_fetch.rs`): the
/// object-space normals baked at `size` x `size` are quantized to `s_n` entries (median
/// cut, NeuQuant, k-means, or `Exact`: every distinct normal kept, the unquantized
/// baseline; optionally Floyd–Steinberg dithered; with several scene materials, one
/// interval of entries per material, §6) stored as `index_bits`-bit indices; per
/// frame the table is shaded by each material's lighting model in object space and
/// loaded into the colour LUT; per fragment the index under `uv` (nearest) reads its
/// colour. `split` (§7.1): alpha holds the Lambert intensity and RGB the specular colour,
/// for an `FbBlend` with a base colour (Phong and Lambert materials only). `mipmap`
/// (§5.2): index mipmap levels built by `NearestToAverage` (or the wrong
/// `NaiveIndexAverage`), chosen per fragment by a `lod` input (an `Lod` attribute).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QuantizedNormalsSpec {
    pub size: u32,
    pub s_n: u32,
    pub quantizer: Quantizer,
    #[serde(default)]
    pub dither: bool,
    pub index_bits: u32,
    #[serde(default)]
    pub split: bool,
    #[serde(default)]
    pub mipmap: Option<MipMode>,
    #[serde(default)]
    pub datapath: BuilderDatapath,
    pub entry: Encoding,
    #[serde(default = "one")]
    pub entries_per_clock: u32,
    #[serde(default = "one")]
    pub load_width: u32,
}

/// The palette builder's datapath words (`hw/src/units/palette_builder.rs`, "Bit-accurate
/// mode"): the normal table's components, the light / half-way / view vector registers, the
/// intensities after each dot product, the power generator, and the `EnvMap` function's
/// sphere-map reciprocal square root (default 1024 x 16).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BuilderDatapath {
    pub normal: Encoding,
    pub vector: Encoding,
    pub intensity: Encoding,
    pub power: SpecGen,
    #[serde(default)]
    pub sphere: SphereAddress,
}

impl Default for BuilderDatapath {
    /// s1.10 normals and vectors in 12-bit words, 10-bit intensities, a 1024 x 12 power table.
    fn default() -> Self {
        let s1_10 = Encoding::fixed(Format {
            signed: true,
            width: 12,
            frac: 10,
        });
        BuilderDatapath {
            normal: s1_10,
            vector: s1_10,
            intensity: Encoding::texel(Codec::UnitUnsigned, false, 10),
            power: SpecGen::Table {
                index_bits: 10,
                value_bits: 12,
            },
            sphere: SphereAddress::default(),
        }
    }
}

impl Spec for QuantizedNormalsSpec {
    fn input_names(&self, _: &BuildCtx) -> Vec<String> {
        match self.mipmap {
            Some(_) => vec![UV.into(), LOD.into()],
            None => vec![UV.into()],
        }
    }

    fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        ctx: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String> {
        Ok(Box::new(self.quantized_fetch(ins, ctx, false)?.0))
    }
}

impl QuantizedNormalsSpec {
    /// [`Spec::build`], and how far the map's normals and its mip levels stray from the true
    /// ones (the report's `normal_maps`, `quantize::map_error`).
    pub(crate) fn build_measured(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        ctx: &BuildCtx,
    ) -> Result<(Box<dyn Unit>, NormalMapError), String> {
        let (unit, err) = self.quantized_fetch(ins, ctx, true)?;
        Ok((Box::new(unit), err.expect("measured when asked")))
    }

    /// Bake, quantize, build the colour table and the unit (Tarini et al. §3–6); with
    /// `measure`, also the map's error.
    fn quantized_fetch(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        ctx: &BuildCtx,
        measure: bool,
    ) -> Result<(QuantizedFetch, Option<NormalMapError>), String> {
        let (size, s_n, index_bits) = (self.size, self.s_n, self.index_bits);
        check_size(size)?;
        let max_bits = bumpsim_hw::units::MAX_INDEX_BITS;
        if !(8..=max_bits).contains(&index_bits) {
            return Err(format!("index_bits {index_bits}: expected 8 to {max_bits}"));
        }
        if s_n < 1 || s_n > 1 << index_bits {
            return Err(format!(
                "s_n {s_n}: expected 1 to 2^index_bits = {}",
                1u32 << index_bits
            ));
        }
        let uv = input(ins, UV)?.enc;
        let scene = ctx.scene;
        let normals = &super::baked::object_normals(ctx, size)[..];
        let (w, n) = (size as usize, s_n as usize);
        let (pal, intervals) = match &scene.looks.regions {
            None => {
                // each texel is searched once: dithered, or mapped to its nearest entry
                let pal = if self.dither {
                    quantize::quantize_dithered(normals, w, w, n, self.quantizer, Scan::Serpentine)
                } else {
                    quantize::quantize(normals, n, self.quantizer)
                }
                .map_err(|e| e.to_string())?;
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
                let mp = if self.dither {
                    quantize::quantize_with_materials_dithered(
                        normals,
                        &ids,
                        w,
                        w,
                        n,
                        self.quantizer,
                        Scan::Serpentine,
                    )
                } else {
                    quantize::quantize_with_materials(normals, &ids, n, self.quantizer)
                }
                .map_err(|e| e.to_string())?;
                (mp.palette, mp.intervals)
            }
        };
        let materials = intervals
            .into_iter()
            .enumerate()
            .filter(|(_, r)| !r.is_empty())
            .map(|(id, r)| Ok((id, r, lighting_fn(ctx, id as u8, self.split)?)))
            .collect::<Result<Vec<_>, String>>()?;
        let dp = &self.datapath;
        let formats = BuilderFormats {
            normal: dp.normal,
            vector: dp.vector,
            intensity: dp.intensity,
            power: dp.power,
            entry: self.entry,
            sphere: dp.sphere,
        };
        let table = pal.entries.iter().map(|n| n.to_array()).collect();
        let ids = materials.iter().map(|m| m.0).collect();
        let materials = materials.into_iter().map(|(_, r, f)| (r, f)).collect();
        let builder = PaletteBuilder::new(table, materials, formats, self.entries_per_clock)?
            .with_material_ids(ids)?;
        let unit = QuantizedFetch::new(
            ctx.unit,
            uv,
            size,
            size,
            &pal.indices,
            index_bits,
            builder,
            self.load_width,
            mem_latency(),
        )?;
        // Tarini §5.2: every coarser level from the one below, down to 1 x 1
        let mut levels = Vec::new();
        if let Some(mode) = self.mipmap {
            let mut w = size as usize;
            while w > 1 {
                let below = levels
                    .last()
                    .map_or(&pal.indices[..], |l: &(_, _, Vec<u32>)| &l.2);
                let (next, w2, _) = quantize::mip_indices(below, w, w, &pal.entries, mode)
                    .map_err(|e| e.to_string())?;
                levels.push((w2 as u32, w2 as u32, next));
                w = w2;
            }
        }
        let measured = measure.then(|| {
            let mips: Vec<&[u32]> = levels.iter().map(|l| &l.2[..]).collect();
            NormalMapError {
                unit: ctx.unit.to_string(),
                entries: pal.entries.len() as u32,
                size,
                levels: quantize::level_errors(
                    normals,
                    size as usize,
                    &pal.entries,
                    &pal.indices,
                    &mips,
                ),
            }
        });
        let unit = match self.mipmap {
            Some(_) => unit.with_mipmaps(input(ins, LOD)?.enc, levels)?,
            None => unit,
        };
        Ok((unit, measured))
    }
}
