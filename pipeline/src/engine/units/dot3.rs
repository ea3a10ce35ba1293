//! Dot products of one vector with several (`hw/src/units/dot3.rs`).

use super::checks::check_parallel;
use super::defaults::one;
use super::ports::{input, seq};
use super::{BuildCtx, Spec};
use bumpsim_hw::units::{Clamp, Dot3};
use bumpsim_hw::{Encoding, PortSpec, Unit};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The vector dotted with every other.
const A: &str = "a";
/// The other vectors: `b0`, `b1`, ...
const B: &str = "b";

/// Dot products of `a` with `count` vectors `b0..` (`hw/src/units/dot3.rs`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Dot3Spec {
    pub count: u32,
    #[serde(default = "one")]
    pub parallel: u32,
    #[serde(default)]
    pub clamp: Clamp,
    pub out: Encoding,
}

impl Spec for Dot3Spec {
    fn input_names(&self, _: &BuildCtx) -> Vec<String> {
        std::iter::once(A.to_string())
            // at most 8 (the range checked with the config): a count of 2^31 must not
            // allocate its port names
            .chain(seq(B, self.count.min(8)))
            .collect()
    }

    fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        _: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String> {
        let count = self.count;
        if !(1..=8).contains(&count) {
            return Err(format!("count {count}: expected 1 to 8 vectors"));
        }
        check_parallel(self.parallel, count)?;
        let a = input(ins, A)?.enc;
        let b = input(ins, &format!("{B}0"))?.enc;
        Ok(Box::new(Dot3::new(
            a,
            b,
            count,
            self.parallel,
            self.clamp,
            self.out,
        )))
    }
}
