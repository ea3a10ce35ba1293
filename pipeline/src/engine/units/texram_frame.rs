//! Texram's per-pixel orthonormal frame from the main direction (Ernst et al. §3.1,
//! `hw/src/units/texram.rs`).

use super::ports::input;
use super::{BuildCtx, Spec};
use bumpsim_hw::units::{TexramForm, TexramFrame};
use bumpsim_hw::{Encoding, PortSpec, Unit};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// `e1 = m × N / |m × N|`, `e2 = N × e1`, output as the axes `u = -e2`, `v = e1` that
/// multiply `(Fu, Fv)`; `form: Scaled` reads the unnormalised `N_i` and scales by `|N_i|`
/// instead (§3.1's simplification).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TexramFrameSpec {
    pub form: TexramForm,
    pub table_bits: u32,
    pub value_bits: u32,
    pub out: Encoding,
}

impl Spec for TexramFrameSpec {
    fn input_names(&self, _: &BuildCtx) -> Vec<String> {
        vec!["n".into(), "m".into()]
    }

    fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        _: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String> {
        Ok(Box::new(TexramFrame::new(
            input(ins, "n")?.enc,
            input(ins, "m")?.enc,
            self.form,
            self.table_bits,
            self.value_bits,
            self.out,
        )?))
    }
}
