//! Schlag's 3x3 emboss masks over the bump heights (`hw/src/units/emboss.rs`).

use super::checks::check_size;
use super::defaults::{mem_latency, ports};
use super::ports::input;
use super::textures::{height_range, heights, key, texels, TextureSource};
use super::{BuildCtx, Spec};
use bumpsim_hw::units::EmbossFilter;
use bumpsim_hw::{Encoding, PortSpec, Texture, Unit};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The texture coordinate input.
const UV: &str = "uv";

/// Schlag's 3x3 emboss masks over the bump heights (`hw/src/units/emboss.rs`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EmbossFilterSpec {
    pub size: u32,
    pub texel: Encoding,
    /// Schlag's bevel width `w` (N_z = 6 * 255 / w). Left out, it is chosen so that the
    /// filter reproduces the height field's true slope: `w = (F_max - F_min) * size`.
    #[serde(default)]
    pub bevel_w: Option<f64>,
    #[serde(default = "ports")]
    pub ports: u32,
    #[serde(default = "mem_latency")]
    pub mem_latency: u32,
    pub out: Encoding,
}

impl Spec for EmbossFilterSpec {
    fn input_names(&self, _: &BuildCtx) -> Vec<String> {
        vec![UV.into()]
    }

    fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        ctx: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String> {
        let size = self.size;
        check_size(size)?;
        let raw = heights(ctx, size)?;
        let (lo, hi) = height_range(&raw);
        let w = self.bevel_w.unwrap_or(if hi > lo {
            (hi - lo) * size as f64
        } else {
            1.0
        });
        // the same texture a TexFetch of BumpHeights at this texel encoding reads
        let source = TextureSource::BumpHeights { size };
        let tex = ctx
            .memory
            .get_or_build(&key(&source, &self.texel, None), ctx.unit, |name| {
                Texture::new(name, self.texel, texels(&source, ctx)?)
            })?;
        Ok(Box::new(EmbossFilter::new(
            input(ins, UV)?.enc,
            tex,
            w,
            self.ports,
            self.mem_latency,
            self.out,
        )?))
    }
}
