//! Texel fetch and filter (`hw/src/units/fetch.rs`).

use super::defaults::{mem_latency, ports};
use super::ports::input;
use super::textures::{key, texels, TextureSource};
use super::{recipe, BuildCtx, Spec};
use crate::engine::palette;
use bumpsim_hw::units::{Address, Filter, TexFetch};
use bumpsim_hw::{Encoding, PortSpec, Unit};
use bumpsim_hw::{Sampler, Texture};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The texture coordinate input.
const UV: &str = "uv";

/// Texel fetch and filter (`hw/src/units/fetch.rs`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TexFetchSpec {
    pub source: TextureSource,
    pub texel: Encoding,
    #[serde(default)]
    pub filter: Filter,
    #[serde(default = "weight_bits")]
    pub weight_bits: u32,
    #[serde(default = "ports")]
    pub ports: u32,
    #[serde(default = "mem_latency")]
    pub mem_latency: u32,
    /// Store the texture as indices into a palette of this many entries (Ernst et al. §6),
    /// chosen as directions spread evenly over the hemisphere (bump normals) or the texture
    /// itself quantized to them; each texel takes the nearest entry.
    #[serde(default)]
    pub palette: Option<u32>,
    /// How the palette's entries are chosen (default `Hemisphere`, left out of the canonical
    /// config, and so of the config hash, when it is the default).
    #[serde(default, skip_serializing_if = "is_hemisphere")]
    pub palette_table: PaletteTable,
    /// Addressing outside [0, 1) on both axes (default wrap; left out of the canonical
    /// config, and so of the config hash, when it is the default).
    #[serde(default, skip_serializing_if = "is_wrap")]
    pub address: Address,
    pub out: Encoding,
}

/// The entries of a bump-normal palette (Ernst et al. §6 names no table).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum PaletteTable {
    /// Fixed: directions spread evenly over the hemisphere, the same for every map
    /// ([`palette::hemisphere`]); a chip could hold it in ROM.
    #[default]
    Hemisphere,
    /// Fitted to the map: Heckbert's median cut of its normals, as the quantized-normal
    /// engine builds its tables (`crate::quantize::median_cut::median_cut`); a loadable table.
    MedianCut,
}

fn is_hemisphere(t: &PaletteTable) -> bool {
    *t == PaletteTable::Hemisphere
}

fn weight_bits() -> u32 {
    8
}

fn is_wrap(a: &Address) -> bool {
    *a == Address::Wrap
}

impl TexFetchSpec {
    /// The texture the unit reads, named `name`: its source's texels, as palette indices
    /// when the unit has a palette.
    fn texture(&self, ctx: &BuildCtx, name: &str) -> Result<Texture, String> {
        let mut tex = texels(&self.source, ctx)?;
        let table = match self.palette {
            Some(n) => {
                let table = match self.palette_table {
                    PaletteTable::Hemisphere => palette::hemisphere(n as usize),
                    PaletteTable::MedianCut => palette::median_cut(&tex.values, n as usize)?,
                };
                palette::quantize(&mut tex.values, &table);
                Some((n, table))
            }
            None => None,
        };
        let t = Texture::new(name, self.texel, tex)?;
        Ok(match table {
            Some((n, table)) => t.with_palette_table(n, &table),
            None => t,
        })
    }
}

impl Spec for TexFetchSpec {
    fn input_names(&self, _: &BuildCtx) -> Vec<String> {
        vec![UV.into()]
    }

    fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        ctx: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String> {
        let uv = input(ins, UV)?.enc;
        if let Some(n) = self.palette {
            if !(2..=65536).contains(&n) {
                return Err(format!("palette {n}: expected 2 to 65536 entries"));
            }
            if !matches!(self.source, TextureSource::BumpNormals { .. }) {
                return Err("palette: expected source BumpNormals (palettes of other textures are not modelled yet)".into());
            }
        }
        let mut key = key(&self.source, &self.texel, self.palette);
        if self.palette.is_some() && self.palette_table != PaletteTable::Hemisphere {
            key += &format!(" {:?}", self.palette_table);
        }
        let tex = ctx
            .memory
            .get_or_build(&key, ctx.unit, |name| self.texture(ctx, name))?;
        if self.source.per_frame() {
            let spec = self.clone();
            let build = move |ctx: &BuildCtx, name: &str| spec.texture(ctx, name);
            ctx.memory.each_frame(&tex, recipe(build));
        }
        let sampler =
            Sampler::new(self.filter, self.weight_bits)?.with_address(self.address, self.address);
        let unit = TexFetch::new(uv, tex, sampler, self.ports, self.mem_latency, self.out)?;
        Ok(Box::new(unit))
    }
}
