//! Specular power unit: `y_i = x_i^n` through a loadable table (a "power table").
//!
//! Ernst et al. 1998 §4.2: "The material shininess is held constant over the triangle and is
//! implemented as a simple power table for one shininess at a time. The table can be loaded
//! similar to a color LUT". The table has `2^index_bits` entries of `value_bits`; entry `i`
//! holds `(i / (2^index_bits - 1))^n` so that 0 and 1 are exact, and the input is rounded to the
//! nearest index. Loading it costs one clock per entry before the frame (when the material
//! changes). The same unit serves the SGI engine's specular term (§3.4).
//!
//! Exact mode evaluates `x^n` with `powf`. The table contents and the index rounding are
//! those of [`crate::units::SpecGen::Table`] (`specgen.rs`), which also offers interpolated
//! and repeated-squaring generators.

use crate::columns::{Column, ColumnIn};
use crate::format::{Codec, Encoding};
use crate::frame::FrameInputs;
use crate::gates::{CostTable, GateBudget, TableRole};
use crate::unit::{Mode, PortSpec, Unit, Word};
use crate::units::specgen::{nearest_index, power_table_codes, NearestIndex};

pub struct PowerTable {
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
    index_bits: u32,
    shininess: f64,
    parallel: u32,
    table: Vec<i64>,
    /// The shininess is the frame's material's ([`PowerTable::following_material`]).
    follows_material: bool,
    /// The index of an input word, planned for the inputs' encoding.
    indexer: NearestIndex,
}

impl PowerTable {
    /// `input` is the encoding of the incoming intensities; `k` how many per fragment.
    /// The output encoding is `UnitUnsigned` with `value_bits` (so 1.0 is all ones).
    pub fn new(
        input: Encoding,
        k: u32,
        index_bits: u32,
        value_bits: u32,
        shininess: f64,
        parallel: u32,
    ) -> Self {
        let out = Encoding::texel(Codec::UnitUnsigned, false, value_bits as u8);
        let inputs = (0..k)
            .map(|i| PortSpec::new(&format!("x{i}"), 1, input))
            .collect();
        let outputs = (0..k)
            .map(|i| PortSpec::new(&format!("y{i}"), 1, out))
            .collect();
        let table = power_table_codes(index_bits, &out, shininess);
        PowerTable {
            inputs,
            outputs,
            index_bits,
            shininess,
            parallel: parallel.clamp(1, k.max(1)),
            table,
            follows_material: false,
            indexer: NearestIndex::new(&input, index_bits),
        }
    }

    /// A table loaded with the shininess of material 0 each frame ([`Unit::begin_frame`]);
    /// otherwise the shininess given to [`PowerTable::new`] is kept in every frame.
    pub fn following_material(mut self) -> Self {
        self.follows_material = true;
        self
    }

    /// The table contents (raw output words), for tests and studies.
    pub fn table(&self) -> &[i64] {
        &self.table
    }

    /// Table index for an input word: `round(x (2^b - 1))`, clamped to the table.
    pub fn index(&self, raw: i64, enc: &Encoding) -> usize {
        nearest_index(raw, enc, self.index_bits)
    }
}

impl Unit for PowerTable {
    fn kind(&self) -> &'static str {
        "power_table"
    }
    fn inputs(&self) -> &[PortSpec] {
        &self.inputs
    }
    fn outputs(&self) -> &[PortSpec] {
        &self.outputs
    }
    fn latency(&self) -> u32 {
        self.interval() + 1
    }
    fn interval(&self) -> u32 {
        (self.outputs.len() as u32).div_ceil(self.parallel).max(1)
    }
    fn frame_cycles(&self) -> u64 {
        self.table.len() as u64
    }
    /// Reloads the table for material 0's shininess when the unit follows the material.
    fn begin_frame(&mut self, f: &FrameInputs) -> Result<(), String> {
        if !self.follows_material {
            return Ok(());
        }
        let n = f.material(0)?.shininess;
        if !(n.is_finite() && n > 0.0) {
            return Err(format!("shininess {n}: expected a number above 0"));
        }
        if let Some(out) = self.outputs.first() {
            self.table = power_table_codes(self.index_bits, &out.enc, n);
        }
        self.shininess = n;
        Ok(())
    }
    fn gates(&self, t: &CostTable) -> GateBudget {
        let wi = self.inputs.first().map_or(8, |p| p.enc.width());
        let vb = self.outputs.first().map_or(8, |p| p.enc.width());
        let mut g = GateBudget::new();
        g.add_memory(
            format!("power table {}x{vb} (loadable)", self.table.len()),
            self.parallel,
            t.for_table(TableRole::Power).table_of(&self.table, vb),
        );
        // the index: `(x << n) - x` of the input word rounded to n bits (`rtl::power`): a
        // subtractor where the two copies overlap (the input bits beyond n), a borrow and
        // carry chain (a half adder a bit) over the other n
        let n = self.index_bits;
        g.add(
            format!("index rounding {wi}"),
            self.parallel,
            t.adder(wi.saturating_sub(n)) + t.half_adder * wi.min(n) as f64 + t.clamp(n),
        );
        // measured (yosys, the index alone at 10 (width, fraction, index bits) from (9, 8, 6)
        // to (20, 16, 12), docs/gates.md): where the input has more fraction bits than the
        // index (f > n), the rounding half lands in the bits the subtraction keeps only for
        // their carry, and the index takes a second carry, an incrementer over its n bits;
        // each integer bit beyond the first widens the borrow chain and the saturation test
        let f = self.inputs.first().map_or(8, |p| p.enc.format.frac as u32);
        let extra = if f > n { n } else { 0 } + wi.saturating_sub(f + 1);
        if extra > 0 {
            g.add(
                format!("index carry: {} bits", extra),
                self.parallel,
                t.half_adder * extra as f64,
            );
        }
        g.add(
            format!("sequencer counter {}", self.interval()),
            1,
            t.sequencer(self.interval()),
        );
        g.add(
            format!("result register {vb}"),
            self.outputs.len() as u32,
            t.register(vb),
        );
        if self.interval() > 1 {
            g.add(
                format!("input mux {}:1 x{wi}", self.interval()),
                self.parallel,
                t.mux(wi, self.interval()),
            );
        }
        g
    }
    fn eval_columns(&self, n: usize, ins: &[ColumnIn<'_>], outs: &mut [&mut Column]) -> bool {
        for (o, x) in outs.iter_mut().zip(ins) {
            for (o, &x) in o[0][..n].iter_mut().zip(&x.lanes[0][..n]) {
                *o = self.table[self.indexer.index(x)];
            }
        }
        true
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        let out = self.outputs[0].enc;
        for (i, o) in outs.iter_mut().enumerate() {
            let s = ins[i].lanes[0];
            *o = match mode {
                Mode::Exact => Word::from_exact(&out, &[s.x.clamp(0.0, 1.0).powf(self.shininess)]),
                Mode::BitAccurate => Word::from_raw(&out, &[self.table[self.indexer.index(s.raw)]]),
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::Format;

    #[test]
    fn table_endpoints_and_hand_values() {
        let input = Encoding::fixed(Format::u(9, 8));
        let u = PowerTable::new(input, 1, 4, 8, 2.0, 1);
        assert_eq!(u.table().len(), 16);
        assert_eq!(u.table()[0], 0);
        assert_eq!(u.table()[15], 255);
        // entry 5: (5/15)^2 = 0.1111 -> 28.33 -> 28
        assert_eq!(u.table()[5], 28);
        // x = 0.5 (raw 128): 0.5*15 = 7.5 -> rounds half up to 8
        assert_eq!(u.index(128, &input), 8);
        assert_eq!(u.index(511, &input), 15); // 1.996 clamps
        assert_eq!(u.frame_cycles(), 16);
    }

    #[test]
    fn every_index_width_to_12_bits_is_monotone_and_within_its_bound() {
        let input = Encoding::fixed(Format::u(16, 15));
        for bits in 1..=12u32 {
            let u = PowerTable::new(input, 1, bits, 12, 16.0, 1);
            let t = u.table().to_vec();
            assert!(t.windows(2).all(|w| w[0] <= w[1]), "bits {bits}");
            let last = (1u32 << bits) - 1;
            // the input reaches every entry, and the entry is the rounded power at its centre
            for (i, &v) in t.iter().enumerate() {
                let x = i as f64 / last as f64;
                let raw = (x * 32768.0).round() as i64;
                let mut o = [Word::default()];
                u.eval(Mode::BitAccurate, &[Word::from_raw(&input, &[raw])], &mut o);
                assert_eq!(o[0].lanes[0].raw, v, "bits {bits} entry {i}");
                assert!((o[0].lanes[0].x - x.powf(16.0)).abs() <= 0.5 / 4095.0 + 1e-12);
            }
        }
    }
}
