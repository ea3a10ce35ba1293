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
        Ok(Box::new(BumpBlend::new(params, |n| {
            ins.get(n).map(|p| p.enc)
        })?))
    }
}

impl BumpBlendSpec {
    /// The blend unit's parameters: the scene's bump lights with their bump-state vectors in
    /// the object's frame (a parallel light and a parallel viewer taken at the object's origin).
    fn params(&self, ctx: &BuildCtx) -> Result<BumpBlendParams, String> {
        let scene = ctx.scene;
        let lights = some_bump_lights(ctx)?;
        check_parallel(self.parallel, lights.len() as u32)?;
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
                let w = match self.kind {
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
            kind: self.kind,
            lights,
            l_source: self.l_source,
            h_source: self.h_source,
            spec: self.spec,
            shininess: self.shininess.unwrap_or(scene.material.shininess),
            state: self.state,
            color: self.color,
            dot: self.dot,
            out: self.out,
            selective: self.selective,
            parallel: self.parallel,
        })
    }
}
