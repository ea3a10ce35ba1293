//! Vector normalisation unit: `v / |v|` through a reciprocal-square-root table.
//!
//! Lambertian shading needs `N . L / (|N| |L|)` (Lingard, "An Example: Embossing"); the
//! Texram construction needs `N = N_i / |N_i|` (Gouraud bump paper §3.1). Hardware of the
//! period did this with a table: the squared length `s = x^2 + y^2 + z^2` is computed exactly
//! (three squarers, two adders), a leading-one detector shifts it by an even amount into a
//! mantissa `m` in [1/4, 1), a table of `2^table_bits` entries gives `1/sqrt(m)` (sampled at
//! the centre of each bin, `value_bits` wide, in u2.(value_bits-2)), and three multipliers and
//! a shifter scale the vector. The zero vector gives zero. Exact mode divides by `sqrt` in f64.

use crate::arith::{bit_length, Acc};
use crate::format::{Encoding, Format, Quant};
use crate::gates::{CostTable, GateBudget};
use crate::unit::{Mode, PortSpec, Unit, Word};

pub struct Normalize {
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
    rsqrt: Rsqrt,
}

/// The reciprocal-square-root table of [`Normalize`], shared by every unit that needs
/// `1 / sqrt(s)` of an exact squared length (`TexramFrame`'s `1 / |m x N|` and `|N_i|`,
/// `QuatFrame`'s `1 / |q|^2`), so that they all round the same way.
///
/// `2^table_bits` entries of `1 / sqrt(m)` at the bin centres, `value_bits` wide in
/// u2.(value_bits-2); [`Rsqrt::lookup`] shifts `s` by an even amount into `m` in `[1/4, 1)`.
#[derive(Debug, Clone)]
pub(crate) struct Rsqrt {
    table_bits: u32,
    value_bits: u32,
    table: Vec<i64>,
}

impl Rsqrt {
    /// The table; `table_bits` 2 to 16, `value_bits` 4 to 32 (the messages are the config's).
    pub(crate) fn new(table_bits: u32, value_bits: u32) -> Result<Self, String> {
        if !(2..=16).contains(&table_bits) {
            return Err(format!("table_bits {table_bits}: expected 2 to 16"));
        }
        if !(4..=32).contains(&value_bits) {
            return Err(format!("value_bits {value_bits}: expected 4 to 32"));
        }
        let vf = Format::u(value_bits as u8, value_bits as u8 - 2);
        let n = 1u64 << table_bits;
        // entry i covers m in [i / n, (i + 1) / n); entries below 1/4 are never read
        let table = (0..n)
            .map(|i| {
                let m = ((i as f64 + 0.5) / n as f64).max(0.25);
                vf.from_f64(1.0 / m.sqrt(), Quant::Rnd, crate::format::Overflow::Sat)
            })
            .collect();
        Ok(Rsqrt {
            table_bits,
            value_bits,
            table,
        })
    }

    /// Number of entries (`2^table_bits`).
    pub(crate) fn entries(&self) -> u64 {
        self.table.len() as u64
    }

    /// Width of an entry.
    pub(crate) fn value_bits(&self) -> u32 {
        self.value_bits
    }

    /// Index width (`table_bits`).
    pub(crate) fn index_bits(&self) -> u32 {
        self.table_bits
    }

    /// The entries (u2.(value_bits-2) codes), for the ROM of the generated Verilog.
    pub(crate) fn table(&self) -> &[i64] {
        &self.table
    }

    /// `1 / sqrt(s) ~ r 2^k` for an exact `s > 0`: the table value `r` (an [`Acc`] with
    /// `value_bits - 2` fraction bits) and the power of two `k`. `None` for `s <= 0` (the
    /// zero detect: the table is not read).
    /// Gates of one lookup of a `width`-bit squared length: the leading-one detector, the
    /// mantissa shifter of `levels` stages and the table, each item named after `label`.
    pub(crate) fn lookup_gates(
        &self,
        g: &mut GateBudget,
        t: &CostTable,
        label: &str,
        width: u32,
        levels: u32,
    ) {
        g.add(
            format!("{label}leading-one detector {width}"),
            1,
            t.mux(width, 2),
        );
        g.add(
            format!("{label}mantissa shifter {width}x{levels}"),
            1,
            t.mux(width, 2) * levels as f64,
        );
        let (entries, vb) = (self.entries(), self.value_bits());
        // priced by its contents: a smooth table, 2.5x smaller than random words
        g.add_rom(
            format!("{label}rsqrt table {entries}x{vb}"),
            1,
            t.rom_of(self.table(), vb),
        );
    }

    pub(crate) fn lookup(&self, s: Acc) -> Option<(Acc, i64)> {
        if s.raw <= 0 {
            return None;
        }
        let len = bit_length(s.raw as u128) as i64; // s.raw in [2^(len-1), 2^len)
        let f = s.frac as i64;
        // s in [2^(e-1), 2^e) with e = len - f; m = s 4^k in [1/4, 1) for
        // k = -ceil(e / 2), and 1/sqrt(s) = rsqrt(m) 2^k.
        let e = len - f;
        let k = -(e.div_euclid(2) + e.rem_euclid(2));
        let mbits = f - 2 * k; // m = raw / 2^mbits
        let tb = self.table_bits as i64;
        let idx = if mbits >= tb {
            s.raw >> (mbits - tb)
        } else {
            s.raw << (tb - mbits)
        };
        let r = Acc::new(self.table[idx as usize] as i128, self.value_bits - 2);
        Some((r, k))
    }

    /// The range `(k_min, k_max)` of the shift [`Rsqrt::lookup`] returns for any `s` with
    /// `1 <= s.raw <= 2^raw_bits` at `frac` fraction bits (for width checks).
    pub(crate) fn k_range(raw_bits: u32, frac: u32) -> (i64, i64) {
        let k = |e: i64| -(e.div_euclid(2) + e.rem_euclid(2));
        let f = frac as i64;
        (k(raw_bits as i64 + 1 - f), k(1 - f))
    }
}

/// `a 2^k` exactly: a wire shift. Negative `k` adds fraction bits; positive `k` removes
/// fraction bits while there are any (the raw word does not grow), then multiplies.
pub(crate) fn shift_pow2(a: Acc, k: i64) -> Acc {
    if k < 0 {
        a.shr((-k) as u32)
    } else if a.frac as i64 >= k {
        Acc::new(a.raw, a.frac - k as u32)
    } else {
        Acc::new(a.raw << (k - a.frac as i64), 0)
    }
}

impl Normalize {
    pub fn new(
        input: Encoding,
        table_bits: u32,
        value_bits: u32,
        out: Encoding,
    ) -> Result<Self, String> {
        let rsqrt = Rsqrt::new(table_bits, value_bits)?;
        Ok(Normalize {
            inputs: vec![PortSpec::new("v", 3, input)],
            outputs: vec![PortSpec::new("n", 3, out)],
            rsqrt,
        })
    }
}

impl Normalize {
    /// The reciprocal-square-root table (for the generated Verilog, `rtl::normalize`).
    pub(crate) fn rsqrt(&self) -> &Rsqrt {
        &self.rsqrt
    }
    /// The reciprocal-square-root table's words (u2.(value_bits-2) codes, `2^table_bits` of
    /// them), as its ROM holds them.
    pub fn rsqrt_table(&self) -> &[i64] {
        self.rsqrt.table()
    }
}

impl Unit for Normalize {
    fn kind(&self) -> &'static str {
        "normalize"
    }
    fn inputs(&self) -> &[PortSpec] {
        &self.inputs
    }
    fn outputs(&self) -> &[PortSpec] {
        &self.outputs
    }
    fn latency(&self) -> u32 {
        4
    }
    fn interval(&self) -> u32 {
        1
    }
    fn gates(&self, t: &CostTable) -> GateBudget {
        let w = self.inputs[0].enc.width();
        let wo = self.outputs[0].enc.width();
        let vb = self.rsqrt.value_bits();
        let levels = bit_length(2 * w as u128);
        let mut g = GateBudget::new();
        g.add(format!("squarer {w}"), 3, t.squarer(w));
        g.add(format!("adder {}", 2 * w + 1), 2, t.adder(2 * w + 1));
        self.rsqrt.lookup_gates(&mut g, t, "", 2 * w + 2, levels);
        g.add(format!("multiplier {w}x{vb}"), 3, t.multiplier(w, vb));
        g.add(
            format!("output shifter {}x{levels}", w + vb),
            3,
            t.mux(w + vb, 2) * levels as f64,
        );
        // the four stages as `rtl::normalize` builds them, loaded on every edge (no load
        // enable): the squared length, the vector through three stages, the detector's shift,
        // index and zero flag (twice the shift and the flag), the table value; then the
        // output registers
        let kb = bit_length(w as u128 + 1);
        let stages = (2 * w + 2) + 9 * w + (2 * kb + self.rsqrt.index_bits() + 2) + (vb + 1);
        g.add(
            format!("stage registers {stages}"),
            1,
            t.dff * stages as f64,
        );
        g.add(
            format!("output registers {}", 3 * wo),
            1,
            t.register(3 * wo),
        );
        g
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        let out = self.outputs[0].enc;
        let v = &ins[0];
        match mode {
            Mode::Exact => {
                let x: [f64; 3] = v.xs();
                let len = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
                let n = if len > 0.0 {
                    x.map(|c| c / len)
                } else {
                    [0.0; 3]
                };
                outs[0] = Word::from_exact(&out, &n);
            }
            Mode::BitAccurate => {
                let enc = &self.inputs[0].enc;
                let c: [Acc; 3] = std::array::from_fn(|i| Acc::from_code(v.lanes[i].raw, enc));
                let s = c.iter().fold(Acc::ZERO, |s, a| s.add(a.mul(*a)));
                // 1/|v| = r 2^k; the zero vector gives zero
                let Some((r, k)) = self.rsqrt.lookup(s) else {
                    outs[0] = Word::from_raw(&out, &[0, 0, 0]);
                    return;
                };
                let scale = |a: Acc| {
                    let p = a.mul(r);
                    if k >= 0 {
                        p.scale(1i128 << k)
                    } else {
                        p.shr((-k) as u32)
                    }
                };
                let n: Vec<i64> = c.iter().map(|a| scale(*a).to_code(&out)).collect();
                outs[0] = Word::from_raw(&out, &n);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_vectors_within_the_table_bound_over_a_wide_range_of_lengths() {
        let input = Encoding::fixed(Format::s(16, 4));
        let out = Encoding::fixed(Format::s(12, 10));
        let u = Normalize::new(input, 8, 12, out).unwrap();
        let mut o = [Word::default()];
        let mut worst: f64 = 0.0;
        for k in 1..3000i64 {
            let raw = [
                (k * 7919) % 30000 - 15000,
                (k * 104729) % 20000 - 10000,
                (k * 31) % 900 + 1,
            ];
            let w = Word::from_raw(&input, &raw);
            u.eval(Mode::BitAccurate, &[w], &mut o);
            let x: [f64; 3] = w.xs();
            let len = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
            for (got, want) in o[0].lanes.iter().zip(x) {
                worst = worst.max((got.x - want / len).abs());
            }
        }
        // table step: m bins of 1/256 over [1/4,1): relative rsqrt error <= 0.5 * (1/256) / (2 * 0.25)
        // = 0.39 %, plus value and output rounding
        assert!(
            worst < 0.004 + out.max_error() + 2f64.powi(-10),
            "worst {worst}"
        );
        assert!(worst > 1e-4, "the table must show some error: {worst}");
    }

    /// The shared table: every `k` that `lookup` returns lies in `k_range` (the width checks
    /// of the units that share it rely on this), and `r 2^k` is within the table's relative
    /// bound of `1 / sqrt(s)`; `shift_pow2` keeps the value.
    #[test]
    fn shared_rsqrt_shift_range_and_error() {
        let rs = Rsqrt::new(6, 10).unwrap();
        let bound = 2f64.powi(-6) + 2f64.powi(-9);
        for frac in [0u32, 1, 7, 20, 40] {
            for bits in [1u32, 2, 9, 30, 60] {
                let (kmin, kmax) = Rsqrt::k_range(bits, frac);
                for raw in [
                    1i128,
                    2,
                    3,
                    (1i128 << bits) - 1,
                    1i128 << bits,
                    12345 % (1 << bits) + 1,
                ] {
                    let s = Acc::new(raw, frac);
                    let (r, k) = rs.lookup(s).unwrap();
                    assert!(
                        (kmin..=kmax).contains(&k),
                        "{raw} {frac}: {k} not in {kmin}..={kmax}"
                    );
                    let got = shift_pow2(r, k).to_f64();
                    let want = 1.0 / s.to_f64().sqrt();
                    assert!((got / want - 1.0).abs() <= bound, "{raw} {frac}");
                }
            }
        }
        assert_eq!(rs.lookup(Acc::ZERO), None);
        for k in [-5i64, 0, 3, 9] {
            let a = Acc::new(-77, 4);
            assert_eq!(
                shift_pow2(a, k).to_f64(),
                -77.0 / 16.0 * 2f64.powi(k as i32)
            );
        }
    }

    #[test]
    fn zero_stays_zero_and_exact_mode_is_exact() {
        let e = Encoding::fixed(Format::s(10, 4));
        let u = Normalize::new(e, 6, 10, Encoding::fixed(Format::s(10, 8))).unwrap();
        let mut o = [Word::default()];
        u.eval(Mode::BitAccurate, &[Word::from_raw(&e, &[0, 0, 0])], &mut o);
        assert_eq!(o[0].raws::<3>(), [0, 0, 0]);
        u.eval(
            Mode::Exact,
            &[Word::from_exact(&e, &[3.0, 0.0, 4.0])],
            &mut o,
        );
        assert_eq!(o[0].xs::<3>(), [0.6, 0.0, 0.8]);
    }
}
