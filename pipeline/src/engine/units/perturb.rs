//! The per-pixel perturbation `N' = base + Fu u + Fv v` (`hw/src/units/perturb.rs`): VISA+'s
//! `N + A V`, Harmony's interpolated axes and Texram's `e1`, `e2` (Ernst et al. §3.1, §3.2,
//! §3.5).

use super::ports::input;
use super::{BuildCtx, Spec};
use bumpsim_hw::units::Perturb;
use bumpsim_hw::{Encoding, PortSpec, Unit};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The input ports: the base normal, the two axes and the bump map's offsets `(Fu, Fv)`.
const INPUTS: [&str; 4] = ["base", "u", "v", "d"];

/// `N' = base + d0 u + d1 v`, computed exactly and cast once into `out`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PerturbSpec {
    pub out: Encoding,
}

impl Spec for PerturbSpec {
    fn input_names(&self, _: &BuildCtx) -> Vec<String> {
        INPUTS.iter().map(|s| s.to_string()).collect()
    }

    fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        _: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String> {
        let [base, u, v, d] = INPUTS.map(|n| input(ins, n).map(|p| p.enc));
        Ok(Box::new(Perturb::new(base?, u?, v?, d?, self.out)?))
    }
}
