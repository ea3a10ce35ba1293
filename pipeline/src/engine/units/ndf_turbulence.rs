//! The software path's per-fragment noise of NDF bump map synthesis (Kautz et al. §5.1) as
//! a config unit: `hw/src/units/ndf_turbulence.rs`, `docs/units/ndf.md`.

use super::ports::input;
use super::{BuildCtx, Spec};
use bumpsim_hw::units::TurbulenceIndex;
use bumpsim_hw::{Encoding, PortSpec, Unit};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Turbulence of the scene's `bump: Ndf(...)` (its octaves, frequency, seed and index
/// spread) per fragment: in `uv` (2 lanes, unsigned) and `lod` (1 lane; the octave count is
/// `octaves - lod`, the last octave blended by the fraction), out `r` (2 lanes, `out`, an
/// unsigned encoding): the indices `(r1, r2)` that read `L`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TurbulenceSpec {
    pub out: Encoding,
    /// Fraction bits of the noise datapath (4 to 24; 16 by default).
    #[serde(default = "frac")]
    pub frac: u32,
}

fn frac() -> u32 {
    16
}

impl Spec for TurbulenceSpec {
    fn input_names(&self, _: &BuildCtx) -> Vec<String> {
        vec!["uv".into(), "lod".into()]
    }

    fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        ctx: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String> {
        let s = crate::ndf::sources::surface(ctx.scene, "Turbulence")?;
        let t = bumpsim_hw::units::ndf_noise::Turbulence::new(s.spec.frequency, s.spec.seed);
        Ok(Box::new(TurbulenceIndex::new(
            t,
            s.spec.octaves,
            1.0 / (2.0 * s.spread),
            self.frac,
            input(ins, "uv")?.enc,
            input(ins, "lod")?.enc,
            self.out,
        )?))
    }
}
