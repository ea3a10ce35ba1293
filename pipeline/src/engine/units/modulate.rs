//! Texture stage: `c * t` per channel (`hw/src/units/modulate.rs`, Ernst et al. §5.1).

use super::ports::input;
use super::{BuildCtx, Spec};
use bumpsim_hw::units::Modulate;
use bumpsim_hw::{Encoding, PortSpec, Unit};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The colour input.
const C: &str = "c";
/// The texel input.
const T: &str = "t";

/// Texture stage: `c * t` per channel (`hw/src/units/modulate.rs`, Ernst et al. §5.1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModulateSpec {
    pub out: Encoding,
}

impl Spec for ModulateSpec {
    fn input_names(&self, _: &BuildCtx) -> Vec<String> {
        vec![C.into(), T.into()]
    }

    fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        _: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String> {
        Ok(Box::new(Modulate::new(
            input(ins, C)?.enc,
            input(ins, T)?.enc,
            self.out,
        )))
    }
}
