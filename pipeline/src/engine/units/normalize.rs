//! `v / |v|` through a reciprocal square root table (`hw/src/units/normalize.rs`).

use super::ports::input;
use super::{BuildCtx, Spec};
use bumpsim_hw::units::Normalize;
use bumpsim_hw::{Encoding, PortSpec, Unit};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The vector input.
const V: &str = "v";

/// `v / |v|` through a reciprocal square root table (`hw/src/units/normalize.rs`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NormalizeSpec {
    pub table_bits: u32,
    pub value_bits: u32,
    pub out: Encoding,
}

impl Spec for NormalizeSpec {
    fn input_names(&self, _: &BuildCtx) -> Vec<String> {
        vec![V.into()]
    }

    fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        _: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String> {
        Ok(Box::new(Normalize::new(
            input(ins, V)?.enc,
            self.table_bits,
            self.value_bits,
            self.out,
        )?))
    }
}
