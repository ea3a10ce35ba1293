//! Gouraud bump blend unit (`hw/src/units/blend.rs`, Ernst et al. 1998 §4.2).

use super::checks::{check_parallel, some_bump_lights};
use super::defaults::one;
use super::{BuildCtx, Spec};
use bumpsim_hw::units::{
    BlendKind, BumpBlend, BumpBlendParams, LightState, Selective, SpecGen, VecSource,
};
use bumpsim_hw::{Encoding, PortSpec, Unit};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Gouraud bump blend unit (`hw/src/units/blend.rs`, Ernst et al. 1998 §4.2) over the
/// scene's bump lights. Bump-state vectors (`State`) are the lights' directions and the
/// half vectors of a parallel viewer in the object's frame (the bump vector space),
/// computed once per frame; `Port` vectors arrive as `l0..`, `h0..` inputs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BumpBlendSpec {
    pub kind: BlendKind,
    #[serde(default)]
    pub l_source: VecSource,
    #[serde(default)]
    pub h_source: VecSource,
    #[serde(default = "spec")]
    pub spec: SpecGen,
    /// Defaults to the scene material's shininess.
    #[serde(default)]
    pub shininess: Option<f64>,
    pub state: Encoding,
    pub color: Encoding,
    pub dot: Encoding,
    pub out: Encoding,
    #[serde(default)]
    pub selective: Selective,
    #[serde(default = "one")]
    pub parallel: u32,
}

fn spec() -> SpecGen {
    SpecGen::Table {
        index_bits: 8,
        value_bits: 8,
    }
}

impl Spec for BumpBlendSpec {
    /// The unit's own names (`BumpBlendParams::input_names`); while its parameters do not
    /// build, the two inputs it always has, the colour `c` and the bump normal `b`.
    fn input_names(&self, ctx: &BuildCtx) -> Vec<String> {
        self.params(ctx)
            .map_or_else(|_| vec!["c".into(), "b".into()], |p| p.input_names())
    }

    fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        ctx: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String> {
        let params = self.params(ctx)?;
        let unit = BumpBlend::new(params, |n| ins.get(n).map(|p| p.enc))?;
        Ok(Box::new(match self.shininess {
            Some(_) => unit,
            None => unit.following_material(),
        }))
    }
}

impl BumpBlendSpec {
    /// The blend unit's parameters: the scene's bump lights with their bump-state vectors in
    /// the object's frame (a parallel light and a parallel viewer taken at the object's
    /// origin: [`LightState::from_frame`], which the unit takes again each frame).
    fn params(&self, ctx: &BuildCtx) -> Result<BumpBlendParams, String> {
        let lights = some_bump_lights(ctx)?;
        check_parallel(self.parallel, lights.len() as u32)?;
        Ok(BumpBlendParams {
            kind: self.kind,
            lights: LightState::from_frame(self.kind, ctx.frame)?,
            l_source: self.l_source,
            h_source: self.h_source,
            spec: self.spec,
            shininess: match self.shininess {
                Some(n) => n,
                None => ctx.frame.material(0)?.shininess,
            },
            state: self.state,
            color: self.color,
            dot: self.dot,
            out: self.out,
            selective: self.selective,
            parallel: self.parallel,
        })
    }
}
