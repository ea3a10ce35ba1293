//! Verilog of the power table ([`crate::units::PowerTable`]): per datapath the nearest-index
//! rounding `round(x (2^b - 1))` clamped to the table, and the table as a ROM with the
//! contents the model computed for its shininess (the model's table is loadable; the ROM is
//! what synthesis can price, `docs/rtl.md`).
//!
//! Clocking: edges 1 to `interval` look up `parallel` inputs each (through the input mux, the
//! inputs held until `done`) into the result registers.

use super::fixed::{clamp, from_code, overflow, scale, shift_round, Fx};
use super::verilog::Module;
use super::{Plan, RtlUnit, Shell};
use crate::format::{Encoding, Format, Overflow, Quant};
use crate::unit::Unit;
use crate::units::PowerTable;

/// The parameters of [`PowerTable::new`]; builds both the unit and its Verilog.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PowerTableRtl {
    pub input: Encoding,
    pub k: u32,
    pub index_bits: u32,
    pub value_bits: u32,
    pub shininess: f64,
    pub parallel: u32,
}

/// [`crate::units::specgen::nearest_index`] of the word `bits` of `enc`: the index's bits.
pub fn nearest_index(m: &mut Module, bits: &str, enc: &Encoding, index_bits: u32) -> String {
    let last = (1i128 << index_bits) - 1;
    let x = from_code(m, bits, enc);
    let s = scale(m, &x, last);
    let i: Fx = shift_round(m, &s, s.frac, Quant::Rnd);
    let i = clamp(m, &i, Some((0, 0)), Some((last, 0)));
    overflow(m, &i, &Format::u(index_bits as u8, 0), Overflow::Wrap)
}

impl PowerTableRtl {
    pub fn unit(&self) -> PowerTable {
        PowerTable::new(
            self.input,
            self.k,
            self.index_bits,
            self.value_bits,
            self.shininess,
            self.parallel,
        )
    }

    pub fn rtl(&self, top: &str) -> RtlUnit {
        let u = self.unit();
        let k = self.k.max(1) as usize;
        let p = self.parallel.clamp(1, k as u32) as usize;
        let iv = u.interval();
        let plan = Plan {
            capture: false,
            interval: iv,
            finish: false,
        };
        let mut sh = Shell::new(top, plan);
        let ins = u.inputs().to_vec();
        let x: Vec<String> = (0..k)
            .map(|i| sh.port(i, &ins[i], false)[0].clone())
            .collect();
        let outs: Vec<String> = u
            .outputs()
            .iter()
            .enumerate()
            .map(|(i, o)| sh.output(i, o)[0].clone())
            .collect();
        let (t, tb, comp) = (sh.t.clone(), sh.t_bits, sh.comp.clone());
        let table = u.table().to_vec();
        let rom_name = format!("{top}_table");
        for j in 0..p {
            let items: Vec<usize> = (0..iv as usize)
                .map(|c| c * p + j)
                .filter(|&i| i < k)
                .collect();
            let m = &mut sh.m;
            m.comment(&format!("datapath {j}"));
            let names: Vec<String> = items.iter().map(|&i| x[i].clone()).collect();
            let xb = m.select_bits(&t, &names, self.input.width());
            let idx = nearest_index(m, &xb, &self.input, self.index_bits);
            let y = sh.rom(&rom_name, &table, self.value_bits, &idx);
            for (c, &i) in items.iter().enumerate() {
                sh.m.stmt(format!(
                    "always @(posedge clk) if ({comp} && {t} == {tb}'d{c}) {} <= {y};",
                    outs[i]
                ));
            }
        }
        sh.finish()
    }
}
