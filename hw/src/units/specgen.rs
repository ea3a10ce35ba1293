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
//!   `w = 12, n = 64`; the `k`-LSB rule of thumb holds only up to `w = 8`).

use crate::arith::Acc;
use crate::format::{shift_round, Codec, Encoding, Quant};
use crate::gates::{CostTable, GateBudget};

/// Which specular intensity generator, and its widths.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
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
                g.add(
                    format!("power table {}x{value_bits} (loadable)", self.table.len()),
                    1,
                    t.sram(self.table.len() as u64, value_bits),
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
                g.add(
                    format!("power table {}x{v} (loadable, even/odd banks)", self.table.len()),
                    1,
                    t.sram(self.table.len() as u64, v),
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
                g.add(
                    format!("one bypass mux {}", w + 1),
                    self.k,
                    t.mux(w + 1, 2),
                );
            }
        }
        g
    }
}

fn entry_error(value_bits: u32) -> f64 {
    0.5 / ((1u64 << value_bits) - 1) as f64 + (-2.0 * value_bits as f64).exp2()
}
