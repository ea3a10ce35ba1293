//! Schlag's 3x3 emboss masks over the bump heights (`hw/src/units/emboss.rs`).

use super::checks::check_size;
use super::defaults::{mem_latency, ports};
use super::ports::input;
use super::textures::{height_range, heights, key, scene_heights, texels, TextureSource};
use super::{BuildCtx, Spec};
use crate::scene::Scene;
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

impl EmbossFilterSpec {
    /// Schlag's bevel width `w` the unit is built with: `bevel_w`, or `(F_max - F_min) *
    /// size` over the scene's heights baked at `size` (`bumpsim rtl` rebuilds the unit with it).
    pub fn bevel(&self, scene: &Scene) -> Result<f64, String> {
        check_size(self.size)?;
        Ok(self.bevel_of(&scene_heights(scene, self.size)?))
    }

    fn bevel_of(&self, heights: &[f64]) -> f64 {
        let (lo, hi) = height_range(heights);
        self.bevel_w.unwrap_or(if hi > lo {
            (hi - lo) * self.size as f64
        } else {
            1.0
        })
    }
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
        let w = self.bevel_of(&raw);
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
