//! `x^n` through a loadable table (`hw/src/units/power.rs`).

use super::checks::check_parallel;
use super::defaults::one;
use super::ports::{input, seq};
use super::{BuildCtx, Spec};
use bumpsim_hw::units::PowerTable;
use bumpsim_hw::{PortSpec, Unit};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The inputs: `x0`, `x1`, ...
const X: &str = "x";

/// `x^n` through a loadable table (`hw/src/units/power.rs`). `shininess` defaults to the
/// scene material's.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PowerTableSpec {
    pub count: u32,
    pub index_bits: u32,
    pub value_bits: u32,
    #[serde(default)]
    pub shininess: Option<f64>,
    #[serde(default = "one")]
    pub parallel: u32,
}

impl Spec for PowerTableSpec {
    fn input_names(&self, _: &BuildCtx) -> Vec<String> {
        // at most 8 (the range checked with the config), never 2^31 names
        seq(X, self.count.min(8))
    }

    fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        ctx: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String> {
        let PowerTableSpec {
            count,
            index_bits,
            value_bits,
            shininess,
            parallel,
        } = *self;
        if !(1..=8).contains(&count) {
            return Err(format!("count {count}: expected 1 to 8 inputs"));
        }
        check_parallel(parallel, count)?;
        if !(1..=16).contains(&index_bits) {
            return Err(format!("index_bits {index_bits}: expected 1 to 16"));
        }
        if !(1..=32).contains(&value_bits) {
            return Err(format!("value_bits {value_bits}: expected 1 to 32"));
        }
        let n = match shininess {
            Some(n) => n,
            None => ctx.frame.material(0)?.shininess,
        };
        if !(n.is_finite() && n > 0.0) {
            return Err(format!("shininess {n}: expected a number above 0"));
        }
        let x = input(ins, &format!("{X}0"))?.enc;
        let unit = PowerTable::new(x, count, index_bits, value_bits, n, parallel);
        Ok(Box::new(match shininess {
            Some(_) => unit,
            None => unit.following_material(),
        }))
    }
}
