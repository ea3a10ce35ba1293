//! VISA+ with quaternions at the vertices: the axes of the interpolated quaternion (Ernst et
//! al. §3.2 last paragraph, `hw/src/units/quat_frame.rs`).

use super::ports::input;
use super::{BuildCtx, Spec};
use bumpsim_hw::units::QuatFrame;
use bumpsim_hw::{Encoding, PortSpec, Unit};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The rotation of the interpolated quaternion `q` (normalised by `1 / |q|²`, as nlerp)
/// applied to the frame's first two axes; with `scaled: true` a per-vertex 2x2 matrix `m`
/// (an `AttrSource::QuatScale`) maps them to Blinn's axes, without it they are `-T`, `-B`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QuatFrameSpec {
    #[serde(default)]
    pub scaled: bool,
    pub table_bits: u32,
    pub value_bits: u32,
    pub out: Encoding,
}

impl Spec for QuatFrameSpec {
    fn input_names(&self, _: &BuildCtx) -> Vec<String> {
        let mut v = vec!["q".to_string()];
        if self.scaled {
            v.push("m".into());
        }
        v
    }

    fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        _: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String> {
        let m = if self.scaled {
            Some(input(ins, "m")?.enc)
        } else {
            None
        };
        Ok(Box::new(QuatFrame::new(
            input(ins, "q")?.enc,
            m,
            self.table_bits,
            self.value_bits,
            self.out,
        )?))
    }
}
