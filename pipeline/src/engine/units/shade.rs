//! Light combiner (`hw/src/units/shade.rs`) over the scene's bump lights.

use super::checks::{check_parallel, some_bump_lights};
use super::defaults::one;
use super::ports::{input, seq};
use super::{BuildCtx, Spec};
use bumpsim_hw::units::{Shade, ShadeInputs, ShadeParams};
use bumpsim_hw::{Encoding, PortSpec, Unit};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The diffuse intensities, one per bump light: `d0`, `d1`, ...
const D: &str = "d";
/// The specular intensities, one per bump light: `s0`, `s1`, ...
const S: &str = "s";
/// The base colour input.
const BASE: &str = "base";
/// The source colour input.
const SRC: &str = "src";

/// Light combiner (`hw/src/units/shade.rs`) over the scene's bump lights.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShadeSpec {
    #[serde(default = "yes")]
    pub specular: bool,
    /// Use a `base` colour input (a texel) instead of white.
    #[serde(default)]
    pub base: bool,
    /// Add a `src` colour input (the Gouraud colour).
    #[serde(default)]
    pub src: bool,
    #[serde(default = "one")]
    pub parallel: u32,
    pub coef: Encoding,
    pub out: Encoding,
}

fn yes() -> bool {
    true
}

impl Spec for ShadeSpec {
    fn input_names(&self, ctx: &BuildCtx) -> Vec<String> {
        let k = ctx.bump_lights().len() as u32;
        let mut v = seq(D, k);
        if self.specular {
            v.extend(seq(S, k));
        }
        if self.base {
            v.push(BASE.into());
        }
        if self.src {
            v.push(SRC.into());
        }
        v
    }

    fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        ctx: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String> {
        let lights = some_bump_lights(ctx)?;
        check_parallel(self.parallel, lights.len() as u32)?;
        let params = ShadeParams::from_frame(ctx.frame)?;
        let optional = |on: bool, name: &str| -> Result<Option<Encoding>, String> {
            Ok(if on {
                Some(input(ins, name)?.enc)
            } else {
                None
            })
        };
        let has = ShadeInputs {
            specular: optional(self.specular, &format!("{S}0"))?,
            base: optional(self.base, BASE)?,
            src: optional(self.src, SRC)?,
        };
        Ok(Box::new(Shade::new(
            input(ins, &format!("{D}0"))?.enc,
            has,
            params,
            self.coef,
            self.parallel,
            self.out,
        )))
    }
}
