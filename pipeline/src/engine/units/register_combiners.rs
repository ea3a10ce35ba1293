//! NV20 / NV2A register combiners (`hw/src/units/combiner/`).

use super::ports::input;
use super::{BuildCtx, Spec};
use bumpsim_hw::units::combiner::{Combiner, CombinerParams, Program, DEFAULT_WIDTH, NV2A_STAGES};
use bumpsim_hw::{PortSpec, Unit};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// NV20 / NV2A register combiners (`hw/src/units/combiner/`, `docs/units/register-combiners.md`):
/// `program` (general stages and the final combiner, as the NV_register_combiners state) over
/// the registers wired in `ports` (`primary`, `secondary`, `fog`, `tex0` .. `tex3`; each 1 to 4
/// lanes of any encoding, read rounded to nearest into the registers; a register without a port
/// reads 0); output `rgba`, 8-bit unsigned. `width`: register bits (9, the NV2A's, to 24);
/// `stages`: general combiners of the part (8, the NV2A's).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegisterCombinersSpec {
    pub ports: Vec<String>,
    #[serde(default = "width")]
    pub width: u32,
    #[serde(default = "stages")]
    pub stages: usize,
    pub program: Program,
}

fn width() -> u32 {
    DEFAULT_WIDTH
}
fn stages() -> usize {
    NV2A_STAGES
}

impl Spec for RegisterCombinersSpec {
    fn input_names(&self, _: &BuildCtx) -> Vec<String> {
        self.ports.clone()
    }

    fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        _: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String> {
        let mut params = CombinerParams {
            width: self.width,
            stages: self.stages,
            ..CombinerParams::default()
        };
        let mut ports = Vec::new();
        for name in &self.ports {
            let k = bumpsim_hw::units::combiner::INPUT_PORTS
                .iter()
                .position(|p| p == name)
                .ok_or_else(|| {
                    format!(
                        "ports: {name:?}: expected one of {}",
                        bumpsim_hw::units::combiner::INPUT_PORTS.join(", ")
                    )
                })?;
            let p = input(ins, name)?;
            params.inputs[k] = p.enc;
            ports.push((name.as_str(), p.lanes));
        }
        let unit = Combiner::new(params, self.program.clone())?.with_ports(&ports)?;
        Ok(Box::new(unit))
    }
}
