//! Framebuffer blending of Tarini et al. §7 (`hw/src/units/fb_blend.rs`).

use super::ports::input;
use super::{BuildCtx, Spec};
use bumpsim_hw::units::{BlendEquation, FbBlend};
use bumpsim_hw::{Encoding, PortSpec, Unit};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The base colour input.
const BASE: &str = "base";
/// The split palette entry input.
const ENTRY: &str = "entry";

/// Framebuffer blending of Tarini et al. §7 (`hw/src/units/fb_blend.rs`): the `base`
/// colour (a colour texture fetch) with a split palette `entry` by equation (1), three
/// passes, or (2), two passes, into framebuffer words of `fb`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FbBlendSpec {
    pub equation: BlendEquation,
    pub fb: Encoding,
}

impl Spec for FbBlendSpec {
    fn input_names(&self, _: &BuildCtx) -> Vec<String> {
        vec![BASE.into(), ENTRY.into()]
    }

    fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        _: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String> {
        Ok(Box::new(FbBlend::new(
            self.equation,
            input(ins, BASE)?.enc,
            input(ins, ENTRY)?.enc,
            self.fb,
        )?))
    }
}
