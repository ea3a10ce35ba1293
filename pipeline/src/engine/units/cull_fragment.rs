//! Conditional fragment culling (NV_texture_shader CULL_FRAGMENT, `hw/src/units/cull.rs`).

use super::ports::input;
use super::{BuildCtx, Spec};
use bumpsim_hw::units::{CullFragment, CullTest};
use bumpsim_hw::{PortSpec, Unit};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The tested vector input.
const V: &str = "v";

/// Conditional fragment culling (NV_texture_shader CULL_FRAGMENT,
/// `hw/src/units/cull.rs`): one test per lane of `v` against zero; the fragment is killed
/// when any fails. An engine with this unit tests depth after shading.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CullFragmentSpec {
    pub tests: Vec<CullTest>,
}

impl Spec for CullFragmentSpec {
    fn input_names(&self, _: &BuildCtx) -> Vec<String> {
        vec![V.into()]
    }

    fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        _: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String> {
        Ok(Box::new(CullFragment::new(
            input(ins, V)?.enc,
            &self.tests,
        )?))
    }
}
