//! Specular intensity generators: `y = x^n` for `x` in [0, 1], three ways.
//!
//! Ernst et al. 1998 §4.2: "The material shininess is held constant over the triangle and is
//! implemented as a simple power table for one shininess at a time. The table can be loaded
//! similar to a color LUT and is equal in size to reduce costs", and the gate budget depends
//! on "the fidelity of the specular intensity generator". [`SpecGen::Table`] is that table;
//! [`SpecGen::TableLerp`] and [`SpecGen::Squaring`] are the alternatives a designer of the
//! period would weigh against it, so that cost ([`SpecularGenerator::gates`]) and error
//! ([`SpecularGenerator::error_bound`], measured in the tests) can be compared.
//!
//! * `Table { index_bits: b, value_bits: v }`: `2^b` entries of `v` bits, entry `i` the
//!   `UnitUnsigned` code of `(i / (2^b - 1))^n` (so 0 and 1 are exact, and the words are those
//!   of a colour LUT: all ones is 1.0). The input is rounded to the nearest index
//!   `round(x (2^b - 1))`. Loaded once per frame, one entry per clock.
//! * `TableLerp { index_bits: b, value_bits: v, frac_bits: f }`: the same table, addressed by
//!   `i = floor(x (2^b - 1))`, and the next `f` bits of `x (2^b - 1)` (truncated) interpolate
//!   linearly between entries `i` and `i + 1`. The table is split into even and odd banks so
//!   both neighbours are read in one clock without storing anything twice.
//! * `Squaring { width: w }`: for `n = 2^k`, the input rounded to `w` fraction bits and
//!   squared `k` times, each square rounded (to nearest) back to `w` fraction bits. A word
//!   holds `w` fraction bits and one integer bit so that 1.0 is exact (`1^2 = 1` bypasses the
//!   `w`-bit squarer). The `k` squarers are chained in one clock; no table, nothing to load.
//!
//! Bit-accurate results ([`SpecularGenerator::bits`]) are [`Acc`]s: table words are read the
//! way every unit reads a `UnitUnsigned` word (bit replication, `2v` fraction bits; `v + f`
//! bits of interpolated code give `2v + f`), squaring results have `w` fraction bits. Exact
//! mode is `clamp(x, 0, 1)^n` with `powf`.
//!
//! Error bounds (vs `x^n` of the decoded input, see [`SpecularGenerator::error_bound`]):
//! * Table: `e_v + n_s (1/2) h` with `h = 1/(2^b - 1)`, `e_v = 1/(2 (2^v - 1)) + 2^-2v` (entry
//!   rounding and the read), `n_s` the largest slope of `x^n` (`n` for `n >= 1`; for `n < 1`
//!   the Hölder bound `(h/2)^n` replaces the slope term).
//! * TableLerp: `e_v + n(n-1) h^2 / 8` (interpolation of a convex function, `n >= 2`) `+ n h
//!   2^-f` (fraction truncation times the largest step between entries).
//! * Squaring: `E_0 = 2^-(w+1)` (0 when the input is already on the `w`-bit grid),
//!   `E_{j+1} = 2 E_j + E_j^2 + 2^-(w+1)`: roughly `(n - 1) / 2` LSBs, not `k` LSBs; rounding
//!   errors made early are doubled by every later squaring near `x = 1` (measured: 11.6 LSB for
//!   `w = 12, n = 64`; the `k`-LSB rule of thumb holds for `n <= 64` only up to `w = 9`).

use crate::arith::{Acc, Reader, Writer};
use crate::format::{shift_round, Codec, Encoding, Format, Overflow, Quant};
use crate::gates::{CostTable, GateBudget, TableRole};

/// Which specular intensity generator, and its widths.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub enum SpecGen {
    /// `2^index_bits` entries of `value_bits`, entry `i = (i / (2^b - 1))^n`, input rounded to
    /// the nearest index (as [`crate::units::PowerTable`]).
    Table { index_bits: u32, value_bits: u32 },
    /// Coarse table plus linear interpolation between neighbouring entries with `frac_bits`
    /// of the input below the index.
    TableLerp {
        index_bits: u32,
        value_bits: u32,
        frac_bits: u32,
    },
    /// Repeated squaring for `n = 2^k`: `k` squarings of a `width`-bit value, each rounded
    /// back to `width` bits. `n` must be a power of two.
    Squaring { width: u32 },
}

impl Default for SpecGen {
    /// The paper's generator: a 256 x 8 power table, the size of a colour LUT.
    fn default() -> Self {
        SpecGen::Table {
            index_bits: 8,
            value_bits: 8,
        }
    }
}

/// Table words of `x^n` at `2^index_bits` evenly spaced points of [0, 1], as codes of `out`.
/// Shared with [`crate::units::PowerTable`].
pub fn power_table_codes(index_bits: u32, out: &Encoding, n: f64) -> Vec<i64> {
    let last = (1u64 << index_bits) - 1;
    (0..=last)
        .map(|i| out.encode((i as f64 / last as f64).powf(n)))
        .collect()
}

/// Nearest table index of an input word: `round(x (2^b - 1))` (half up), clamped to the
/// table. Shared with [`crate::units::PowerTable`].
pub fn nearest_index(raw: i64, enc: &Encoding, index_bits: u32) -> usize {
    let last = (1i128 << index_bits) - 1;
    let i = Acc::from_code(raw, enc).scale(last).round_int(Quant::Rnd);
    i.clamp(0, last) as usize
}

/// [`nearest_index`] planned once for one input encoding: the word read by its [`Reader`],
/// scaled by `2^b - 1`, and rounded and clamped by a [`Writer`] into `b` unsigned bits, in
/// `i64` where that fits (`tests::the_planned_index_is_nearest_index`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NearestIndex {
    enc: Encoding,
    index_bits: u32,
    fast: Option<(Reader, Writer)>,
}

impl NearestIndex {
    pub fn new(enc: &Encoding, index_bits: u32) -> NearestIndex {
        let index = Encoding {
            format: Format::u(index_bits.clamp(1, 60) as u8, 0),
            codec: Codec::Fixed,
            quant: Quant::Rnd,
            overflow: Overflow::Sat,
        };
        let fast = Reader::new(enc)
            .filter(|r| (1..=60).contains(&index_bits) && r.bits + index_bits <= 62)
            .map(|r| (r, Writer::new(r.frac, &index)));
        NearestIndex {
            enc: *enc,
            index_bits,
            fast,
        }
    }

    /// `nearest_index(raw, enc, index_bits)`.
    #[inline]
    pub fn index(&self, raw: i64) -> usize {
        match &self.fast {
            Some((r, w)) => w.write(r.read(raw) * ((1i64 << self.index_bits) - 1)) as usize,
            None => nearest_index(raw, &self.enc, self.index_bits),
        }
    }
}

/// Error of reading a word of `enc` into an [`Acc`] (bit replication of the `c / (2^n - 1)`
/// codecs, see [`Acc::from_code`]).
fn read_error(enc: &Encoding) -> f64 {
    match enc.codec {
        Codec::Fixed | Codec::UnitSigned => 0.0,
        Codec::UnitUnsigned | Codec::UnitSymmetric => (-2.0 * enc.width() as f64).exp2(),
    }
}

/// A configured specular intensity generator. See the module documentation.
#[derive(Debug, Clone, PartialEq)]
pub struct SpecularGenerator {
    spec: SpecGen,
    n: f64,
    input: Encoding,
    /// Table words (`UnitUnsigned` codes of `entry`); empty for squaring.
    table: Vec<i64>,
    entry: Encoding,
    /// Squarings (squaring only).
    k: u32,
}

fn check(name: &str, v: u32, lo: u32, hi: u32) -> Result<(), String> {
    if (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(format!("{name} {v}: expected {lo} to {hi}"))
    }
}

impl SpecularGenerator {
    /// Build a generator for shininess `n` reading words of `input`. Errors name the parameter
    /// and what was expected.
    pub fn new(spec: SpecGen, n: f64, input: Encoding) -> Result<Self, String> {
        input.validate()?;
        if !(n.is_finite() && n >= 0.0) {
            return Err(format!("shininess {n}: expected a finite number >= 0"));
        }
        let unit = |v: u32| Encoding::texel(Codec::UnitUnsigned, false, v as u8);
        let (table, entry, k) = match spec {
            SpecGen::Table {
                index_bits,
                value_bits,
            } => {
                check("index_bits", index_bits, 1, 16)?;
                check("value_bits", value_bits, 1, 16)?;
                let e = unit(value_bits);
                (power_table_codes(index_bits, &e, n), e, 0)
            }
            SpecGen::TableLerp {
                index_bits,
                value_bits,
                frac_bits,
            } => {
                check("index_bits", index_bits, 1, 16)?;
                check("value_bits", value_bits, 1, 16)?;
                check("frac_bits", frac_bits, 1, 16)?;
                let e = unit(value_bits);
                (power_table_codes(index_bits, &e, n), e, 0)
            }
            SpecGen::Squaring { width } => {
                check("width", width, 1, 24)?;
                let ok = n >= 1.0 && n.fract() == 0.0 && n <= 65536.0 && {
                    let m = n as u64;
                    m.is_power_of_two()
                };
                if !ok {
                    return Err(format!(
                        "shininess {n}: repeated squaring needs a power of two from 1 to 65536"
                    ));
                }
                (Vec::new(), unit(1), (n as u64).trailing_zeros())
            }
        };
        Ok(SpecularGenerator {
            spec,
            n,
            input,
            table,
            entry,
            k,
        })
    }

    pub fn spec(&self) -> SpecGen {
        self.spec
    }
    pub fn shininess(&self) -> f64 {
        self.n
    }
    /// Encoding of the input words.
    pub fn input(&self) -> Encoding {
        self.input
    }
    /// The table words (`UnitUnsigned` codes of `value_bits`); empty for squaring.
    pub fn table(&self) -> &[i64] {
        &self.table
    }

    /// The algorithm: `clamp(x, 0, 1)^n`.
    pub fn exact(&self, x: f64) -> f64 {
        x.clamp(0.0, 1.0).powf(self.n)
    }

    /// The hardware's result for an input word: see the module documentation for the
    /// fraction bits of the returned value.
    pub fn bits(&self, raw: i64) -> Acc {
        match self.spec {
            SpecGen::Table { index_bits, .. } => {
                let i = nearest_index(raw, &self.input, index_bits);
                Acc::from_code(self.table[i], &self.entry)
            }
            SpecGen::TableLerp {
                index_bits,
                frac_bits,
                ..
            } => {
                let last = (1i128 << index_bits) - 1;
                let x = Acc::from_code(raw, &self.input).clamp(Acc::ZERO, Acc::new(1, 0));
                // s = x (2^b - 1) = x 2^b - x: a subtractor; x >= 0 so the shifts floor
                let s = x.scale(last);
                let i = (s.raw >> s.frac).min(last);
                let rem = s.raw - (i << s.frac);
                let f = if s.frac >= frac_bits {
                    rem >> (s.frac - frac_bits)
                } else {
                    rem << (frac_bits - s.frac)
                };
                let j = (i + 1).min(last);
                let a = Acc::from_code(self.table[i as usize], &self.entry);
                let b = Acc::from_code(self.table[j as usize], &self.entry);
                a.add(b.sub(a).mul(Acc::new(f, frac_bits)))
            }
            SpecGen::Squaring { width } => {
                let x = Acc::from_code(raw, &self.input).clamp(Acc::ZERO, Acc::new(1, 0));
                // round the input to `width` fraction bits (half up)
                let mut y = if x.frac >= width {
                    shift_round(x.raw, x.frac - width, Quant::Rnd)
                } else {
                    x.raw << (width - x.frac)
                };
                for _ in 0..self.k {
                    y = shift_round(y * y, width, Quant::Rnd);
                }
                Acc::new(y, width)
            }
        }
    }

    /// Width of the generator's result word (what the next multiplier sees): `value_bits`
    /// for a table, `value_bits + frac_bits` for the interpolated code, `width + 1` for
    /// squaring (the integer bit of 1.0).
    pub fn out_bits(&self) -> u32 {
        match self.spec {
            SpecGen::Table { value_bits, .. } => value_bits,
            SpecGen::TableLerp {
                value_bits,
                frac_bits,
                ..
            } => value_bits + frac_bits,
            SpecGen::Squaring { width } => width + 1,
        }
    }

    /// Clocks to load the table before a frame (one entry per clock, as a colour LUT); 0 for
    /// squaring.
    pub fn load_cycles(&self) -> u64 {
        self.table.len() as u64
    }

    /// A bound on `|bits(raw) - exact(decode(raw))|` over every input word, derived in the
    /// module documentation.
    pub fn error_bound(&self) -> f64 {
        let n = self.n;
        let ein = read_error(&self.input);
        if n == 0.0 {
            // every entry is 1 (0^0 = 1 as in powf): only the entry rounding is left
            return match self.spec {
                SpecGen::Table { value_bits, .. } | SpecGen::TableLerp { value_bits, .. } => {
                    entry_error(value_bits)
                }
                SpecGen::Squaring { .. } => 0.0,
            };
        }
        match self.spec {
            SpecGen::Table {
                index_bits,
                value_bits,
            } => {
                let h = 1.0 / ((1u64 << index_bits) - 1) as f64;
                let ev = entry_error(value_bits);
                let d = 0.5 * h + ein;
                ev + if n >= 1.0 { n * d } else { d.powf(n) }
            }
            SpecGen::TableLerp {
                index_bits,
                value_bits,
                frac_bits,
            } => {
                let h = 1.0 / ((1u64 << index_bits) - 1) as f64;
                let ev = entry_error(value_bits);
                // largest step between neighbouring entries of x^n
                let step = if n >= 1.0 { n * h } else { h.powf(n) };
                // deviation of x^n from its chord over one interval
                let interp = if n >= 2.0 {
                    n * (n - 1.0) * h * h / 8.0
                } else if n == 1.0 || n == 0.0 {
                    0.0
                } else {
                    step
                };
                let read = if n >= 1.0 { n * ein } else { ein.powf(n) };
                ev + interp + step * (-(frac_bits as f64)).exp2() + read
            }
            SpecGen::Squaring { width } => {
                let r = (-(width as f64) - 1.0).exp2();
                let on_grid = self.input.codec == Codec::Fixed
                    && (self.input.format.frac as u32) <= width
                    || self.input.codec == Codec::UnitSigned && self.input.width() - 1 <= width;
                let mut e = if on_grid { 0.0 } else { r };
                for _ in 0..self.k {
                    e = 2.0 * e + e * e + r;
                }
                e
            }
        }
    }

    /// Gate estimate of one generator.
    pub fn gates(&self, t: &CostTable) -> GateBudget {
        let wi = self.input.width();
        let mut g = GateBudget::new();
        match self.spec {
            SpecGen::Table {
                index_bits,
                value_bits,
            } => {
                g.add_memory(
                    format!("power table {}x{value_bits} (loadable)", self.table.len()),
                    1,
                    t.for_table(TableRole::Power)
                        .table_of(&self.table, value_bits),
                );
                g.add(
                    format!("index rounding {wi}"),
                    1,
                    t.adder(wi) + t.clamp(index_bits),
                );
            }
            SpecGen::TableLerp {
                index_bits,
                value_bits,
                frac_bits,
            } => {
                let (b, v, f) = (index_bits, value_bits, frac_bits);
                g.add_memory(
                    format!(
                        "power table {}x{v} (loadable, even/odd banks)",
                        self.table.len()
                    ),
                    1,
                    t.for_table(TableRole::Power).table_of(&self.table, v),
                );
                g.add(
                    format!("index scaling x(2^{b}-1) {}", wi + b),
                    1,
                    t.adder(wi + b) + t.clamp(b + f),
                );
                g.add(
                    format!("bank address incrementer {}", b.saturating_sub(1).max(1)),
                    1,
                    t.half_adder * b.saturating_sub(1).max(1) as f64,
                );
                g.add(format!("bank swap mux 2x{v}"), 1, t.mux(2 * v, 2));
                g.add(format!("lerp subtractor {}", v + 1), 1, t.adder(v + 1));
                g.add(
                    format!("lerp multiplier {}x{f}", v + 1),
                    1,
                    t.multiplier(v + 1, f),
                );
                g.add(format!("lerp adder {}", v + f), 1, t.adder(v + f));
            }
            SpecGen::Squaring { width } => {
                let w = width;
                g.add(
                    format!("input rounding {}", w + 1),
                    1,
                    t.half_adder * (w + 1) as f64 + t.clamp(w + 1),
                );
                g.add(format!("squarer {w}"), self.k, t.squarer(w));
                g.add(
                    format!("square rounding incrementer {w}"),
                    self.k,
                    t.half_adder * w as f64,
                );
                g.add(format!("one bypass mux {}", w + 1), self.k, t.mux(w + 1, 2));
            }
        }
        g
    }
}

fn entry_error(value_bits: u32) -> f64 {
    0.5 / ((1u64 << value_bits) - 1) as f64 + (-2.0 * value_bits as f64).exp2()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    #[test]
    fn the_planned_index_is_nearest_index() {
        // every code of every codec to 9 bits, both signs (fixed formats at three
        // fractions), into every index width to 14 bits
        let mut encs = Vec::new();
        for width in 1..=9u8 {
            for signed in [false, true] {
                for codec in [Codec::UnitUnsigned, Codec::UnitSigned, Codec::UnitSymmetric] {
                    encs.push(Encoding::texel(codec, signed, width));
                }
                for frac in [0, width / 2, width] {
                    encs.push(Encoding::fixed(Format {
                        signed,
                        width,
                        frac,
                    }));
                }
            }
        }
        let mut checks = 0;
        for enc in &encs {
            for bits in 1..=14 {
                let n = NearestIndex::new(enc, bits);
                assert!(n.fast.is_some());
                for raw in enc.format.min_raw()..=enc.format.max_raw() {
                    assert_eq!(
                        n.index(raw),
                        nearest_index(raw, enc, bits),
                        "{enc:?} {bits} {raw}"
                    );
                    checks += 1;
                }
            }
        }
        assert!(checks > 100_000, "{checks}");
    }

    /// A fine input: u1.14, every value of [0, 1] on a 2^-14 grid.
    fn fine() -> Encoding {
        Encoding::fixed(Format::u(15, 14))
    }

    /// Largest |bits - x^n| over every input word of `fine()` in [0, 1].
    fn max_error(g: &SpecularGenerator) -> f64 {
        let e = g.input();
        (0..=1i64 << 14)
            .map(|r| (g.bits(r).to_f64() - g.exact(e.decode(r))).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn hand_values_of_each_generator() {
        let input = Encoding::fixed(Format::u(9, 8));
        let t = SpecularGenerator::new(
            SpecGen::Table {
                index_bits: 4,
                value_bits: 8,
            },
            2.0,
            input,
        )
        .unwrap();
        // entry 5: (5/15)^2 = 0.1111 -> 28.33 -> 28; entry 8: (8/15)^2 -> 72.53 -> 73
        assert_eq!((t.table()[0], t.table()[5], t.table()[15]), (0, 28, 255));
        // x = 0.5: 7.5 rounds half up to index 8; read by bit replication (73 * 257 / 2^16)
        assert_eq!(t.bits(128), Acc::new(73 * 257, 16));
        assert_eq!((t.load_cycles(), t.out_bits()), (16, 8));

        let l = SpecularGenerator::new(
            SpecGen::TableLerp {
                index_bits: 4,
                value_bits: 8,
                frac_bits: 4,
            },
            2.0,
            input,
        )
        .unwrap();
        // x = 0.5: s = 7.5, entries 7 (0.2178 -> 56) and 8 (73), f = 8/16:
        // code 56 + 17 * 0.5 = 64.5, read as 64.5 * 257 / 2^16
        assert_eq!(l.table()[7], 56);
        assert_eq!(l.bits(128).to_f64(), 64.5 * 257.0 / 65536.0);
        assert_eq!((l.load_cycles(), l.out_bits()), (16, 12));
        // x = 1 (raw 256) and beyond read the last entry exactly
        assert_eq!(l.bits(256).to_f64(), 255.0 * 257.0 / 65536.0);
        assert_eq!(l.bits(511).to_f64(), 255.0 * 257.0 / 65536.0);

        let s = SpecularGenerator::new(SpecGen::Squaring { width: 8 }, 4.0, input).unwrap();
        // 0.5^4 = 1/16 exactly; 0.75^2 = 0.5625, ^2 = 0.31640625 = 81/256 exactly
        assert_eq!(s.bits(128), Acc::new(16, 8));
        assert_eq!(s.bits(192), Acc::new(81, 8));
        assert_eq!(s.bits(256), Acc::new(256, 8)); // 1.0 is exact
        assert_eq!(s.bits(300), Acc::new(256, 8)); // clamped
        assert_eq!((s.load_cycles(), s.out_bits()), (0, 9));
    }

    #[test]
    fn table_every_index_width_to_12_bits_reaches_every_entry_monotone_within_bound() {
        for bits in 1..=12u32 {
            for n in [16.0, 2.5, 0.5] {
                let spec = SpecGen::Table {
                    index_bits: bits,
                    value_bits: 12,
                };
                let g = SpecularGenerator::new(spec, n, fine()).unwrap();
                let bound = g.error_bound();
                let mut reached = BTreeSet::new();
                let mut prev = Acc::ZERO;
                for r in 0..1i64 << 15 {
                    reached.insert(nearest_index(r, &fine(), bits));
                    let y = g.bits(r);
                    assert!(!y.lt(prev), "bits {bits} n {n}: not monotone at {r}");
                    prev = y;
                    let x = fine().decode(r);
                    let err = (y.to_f64() - g.exact(x)).abs();
                    assert!(err <= bound, "bits {bits} n {n} raw {r}: {err} > {bound}");
                }
                assert_eq!(
                    reached.len(),
                    1 << bits,
                    "bits {bits}: entries not all reached"
                );
            }
        }
    }

    #[test]
    fn lerp_every_index_width_to_12_bits_reaches_every_entry_monotone_within_bound() {
        for bits in 1..=12u32 {
            for n in [16.0, 2.0] {
                let spec = SpecGen::TableLerp {
                    index_bits: bits,
                    value_bits: 12,
                    frac_bits: 6,
                };
                let g = SpecularGenerator::new(spec, n, fine()).unwrap();
                let bound = g.error_bound();
                let last = (1i64 << bits) - 1;
                let mut reached = BTreeSet::new();
                let mut prev = Acc::ZERO;
                for r in 0..1i64 << 15 {
                    // the floor index the lerp reads first
                    let x = fine().decode(r).min(1.0);
                    reached.insert((x * last as f64).floor() as i64);
                    let y = g.bits(r);
                    assert!(!y.lt(prev), "bits {bits} n {n}: not monotone at {r}");
                    prev = y;
                    let err = (y.to_f64() - g.exact(x)).abs();
                    assert!(err <= bound, "bits {bits} n {n} raw {r}: {err} > {bound}");
                }
                assert_eq!(reached.len() as i64, last + 1, "bits {bits}");
            }
        }
    }

    #[test]
    fn lerp_beats_table_at_equal_entries_for_n_32() {
        let mut rows = Vec::new();
        for (bits, vb) in [(5u32, 8u32), (6, 8), (8, 8), (8, 12)] {
            let t = SpecularGenerator::new(
                SpecGen::Table {
                    index_bits: bits,
                    value_bits: vb,
                },
                32.0,
                fine(),
            )
            .unwrap();
            let l = SpecularGenerator::new(
                SpecGen::TableLerp {
                    index_bits: bits,
                    value_bits: vb,
                    frac_bits: 8,
                },
                32.0,
                fine(),
            )
            .unwrap();
            let (et, el) = (max_error(&t), max_error(&l));
            println!("n=32 {}x{vb}: table {et:.5}, lerp {el:.5}", 1 << bits);
            assert!(et <= t.error_bound() && el <= l.error_bound());
            rows.push((et, el));
        }
        // measured maxima over the 2^14 + 1 inputs of [0, 1]
        let expect = [
            (0.40536, 0.08053), // 32 x 8
            (0.22501, 0.02508), // 64 x 8
            (0.06063, 0.00238), // 256 x 8
            (0.06064, 0.00156), // 256 x 12
        ];
        for ((et, el), (xt, xl)) in rows.iter().zip(expect) {
            assert!(el < et);
            assert!(
                (et - xt).abs() < 5e-5 && (el - xl).abs() < 5e-5,
                "{et} {el}"
            );
        }
    }

    #[test]
    fn squaring_is_within_its_derived_bound_for_n_2_to_64() {
        for w in 4..=12u32 {
            let grid = Encoding::fixed(Format::u(w as u8 + 1, w as u8));
            for k in 1..=6u32 {
                let n = (1u32 << k) as f64;
                let g = SpecularGenerator::new(SpecGen::Squaring { width: w }, n, grid).unwrap();
                let lsb = (-(w as f64)).exp2();
                let bound = g.error_bound();
                let mut worst = 0.0f64;
                let mut prev = Acc::ZERO;
                for r in 0..=1i64 << w {
                    let y = g.bits(r);
                    assert_eq!(y.frac, w);
                    assert!(!y.lt(prev), "w {w} n {n}: not monotone at {r}");
                    prev = y;
                    worst = worst.max((y.to_f64() - g.exact(grid.decode(r))).abs());
                }
                assert!(worst <= bound, "w {w} n {n}: {worst} > {bound}");
                println!(
                    "squaring w {w} n {n}: measured {:.3} LSB, bound {:.3} LSB",
                    worst / lsb,
                    bound / lsb
                );
                // the bound is about (n - 1) / 2 LSBs once the words are wide
                if w == 12 {
                    assert!(bound <= (n - 1.0) / 2.0 * 1.01 * lsb, "w {w} n {n}");
                }
                // k LSBs holds up to 9 bits
                if w <= 9 {
                    assert!(worst <= k as f64 * lsb, "w {w} n {n}: {} LSB", worst / lsb);
                }
                if w == 12 && k == 6 {
                    // ... but not beyond: 11.6 LSB at x = 4059/4096
                    assert!((worst / lsb - 11.62).abs() < 0.01, "{}", worst / lsb);
                }
            }
        }
    }

    #[test]
    fn squaring_rounds_an_off_grid_input_first() {
        // a 16-bit input into an 8-bit squarer: the input rounding is amplified by n
        let input = Encoding::fixed(Format::u(17, 16));
        let g = SpecularGenerator::new(SpecGen::Squaring { width: 8 }, 8.0, input).unwrap();
        let bound = g.error_bound();
        for r in 0..=1i64 << 16 {
            let err = (g.bits(r).to_f64() - g.exact(input.decode(r))).abs();
            assert!(err <= bound, "{r}: {err} > {bound}");
        }
    }

    #[test]
    fn bad_parameters_are_rejected() {
        let e = fine();
        let sq = SpecGen::Squaring { width: 8 };
        for n in [3.0, 0.5, 6.0, 0.0] {
            let err = SpecularGenerator::new(sq, n, e).unwrap_err();
            assert!(err.contains("power of two"), "{err}");
        }
        assert!(SpecularGenerator::new(sq, 64.0, e).is_ok());
        let t = |b, v| SpecGen::Table {
            index_bits: b,
            value_bits: v,
        };
        assert!(SpecularGenerator::new(t(0, 8), 8.0, e)
            .unwrap_err()
            .contains("index_bits 0"));
        assert!(SpecularGenerator::new(t(8, 17), 8.0, e)
            .unwrap_err()
            .contains("value_bits 17"));
        assert!(SpecularGenerator::new(t(8, 8), f64::NAN, e).is_err());
        assert!(SpecularGenerator::new(t(8, 8), -1.0, e).is_err());
        let l = SpecGen::TableLerp {
            index_bits: 8,
            value_bits: 8,
            frac_bits: 0,
        };
        assert!(SpecularGenerator::new(l, 8.0, e)
            .unwrap_err()
            .contains("frac_bits 0"));
    }

    #[test]
    fn gates_grow_with_the_table_and_the_squarings() {
        let t = CostTable::default();
        let ge = |spec, n| {
            SpecularGenerator::new(spec, n, fine())
                .unwrap()
                .gates(&t)
                .total()
        };
        let table = |b| SpecGen::Table {
            index_bits: b,
            value_bits: 8,
        };
        assert!(ge(table(6), 32.0) < ge(table(8), 32.0));
        let lerp = SpecGen::TableLerp {
            index_bits: 6,
            value_bits: 8,
            frac_bits: 8,
        };
        // a 64-entry lerp costs less than the 256-entry table
        assert!(ge(lerp, 32.0) < ge(table(8), 32.0));
        let sq = SpecGen::Squaring { width: 10 };
        assert!(ge(sq, 8.0) < ge(sq, 64.0));
        println!(
            "GE: table 256x8 {:.0}, lerp 64x8+8 {:.0}, squaring w10 n=32 {:.0}",
            ge(table(8), 32.0),
            ge(lerp, 32.0),
            ge(sq, 32.0)
        );
    }
}
