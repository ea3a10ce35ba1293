//! The bit-accurate datapath of [`crate::arith::Acc`] as Verilog: every operation of `Acc`
//! (read a port word, exact product and sum, constant scale, clamp, rounding and the cast into
//! an output [`Encoding`]) has a twin here that emits a signed wire.
//!
//! An [`Fx`] is a signed wire holding `raw / 2^frac` (times its pending factors, below), with
//! the exact integer range `[lo, hi]` its raw value can take; widths are derived from the
//! ranges, so every wire is as wide as the exact intermediate needs (the `Acc` semantics: no
//! intermediate rounds or overflows) and no wider. The casts (rounding, overflow, codecs) are in [`super::cast`].
//!
//! The bit replication that reads a `c / (2^n - 1)` code (`c (2^n + 1)`) is kept as a
//! factor of the value rather than widening the wire ([`Fx::fac`]): products multiply the
//! codes and collect the factors, sums of terms with common factors add the codes, and a
//! factor becomes a shift-and-add only where a sum, a clamp or a cast needs the plain value.
//! The value is the same; the multipliers are as wide as the codes, as a designer would build
//! them. Products of signed words are split into an unsigned array and the sign rows
//! (Baugh-Wooley), since yosys 0.23 sign-extends both operands of a signed `*` to the product
//! width.

use super::verilog::{lit, signed_bits, Module};
use crate::format::{Codec, Encoding, Format};

pub use super::cast::{clamp_code, overflow, shift_round, to_code};

/// A signed fixed-point wire: value `raw prod_n (2^n + 1) / 2^frac`, `raw` in `[lo, hi]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Fx {
    pub name: String,
    pub lo: i128,
    pub hi: i128,
    pub frac: u32,
    /// Pending bit-replication factors `2^n + 1` (sorted).
    pub fac: Vec<u32>,
}

impl Fx {
    pub fn width(&self) -> u32 {
        signed_bits(self.lo, self.hi)
    }
}

fn corners(a: &Fx, b: &Fx) -> (i128, i128) {
    let c = [a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi];
    (*c.iter().min().unwrap(), *c.iter().max().unwrap())
}

/// `floor(v / 2^by)`.
pub(super) fn floor_shr(v: i128, by: u32) -> i128 {
    v >> by
}

/// Emit a signed wire for `expr` with range `[lo, hi]`.
pub(super) fn make(m: &mut Module, hint: &str, lo: i128, hi: i128, frac: u32, expr: &str) -> Fx {
    let name = m.swire(hint, signed_bits(lo, hi), expr);
    Fx {
        name,
        lo,
        hi,
        frac,
        fac: Vec::new(),
    }
}

pub(super) fn with_fac(mut a: Fx, fac: Vec<u32>) -> Fx {
    a.fac = fac;
    a.fac.sort_unstable();
    a
}

/// The factors of `a` not in `keep` (multiset difference).
pub(super) fn extra(a: &[u32], keep: &[u32]) -> Vec<u32> {
    let mut k = keep.to_vec();
    a.iter()
        .filter(|f| match k.iter().position(|x| x == *f) {
            Some(i) => {
                k.remove(i);
                false
            }
            None => true,
        })
        .copied()
        .collect()
}

/// The factors common to every term (multiset intersection).
fn common(terms: &[&Fx]) -> Vec<u32> {
    let mut c = terms[0].fac.clone();
    for t in &terms[1..] {
        let gone = extra(&c, &t.fac);
        c = extra(&c, &gone);
    }
    c
}

/// `a` with the factors not in `keep` applied (one shift-and-add network).
fn strip(m: &mut Module, a: &Fx, keep: &[u32]) -> Fx {
    let ex = extra(&a.fac, keep);
    if ex.is_empty() {
        return a.clone();
    }
    let k = ex.iter().fold(1i128, |k, &n| k * ((1i128 << n) + 1));
    let x = align_wire(m, &with_fac(a.clone(), Vec::new()), a.frac);
    let y = make(m, "rep", x.lo * k, x.hi * k, x.frac, &csd_expr(&x.name, k));
    with_fac(y, keep.to_vec())
}

/// `a` with every factor applied.
pub fn plain(m: &mut Module, a: &Fx) -> Fx {
    strip(m, a, &[])
}

/// A constant.
pub fn constant(raw: i128, frac: u32) -> Fx {
    Fx {
        name: lit(raw),
        lo: raw,
        hi: raw,
        frac,
        fac: Vec::new(),
    }
}

/// The signed reading of a raw port word `bits` (an unsigned vector of `fmt.width` bits).
pub fn raw_word(m: &mut Module, bits: &str, fmt: &Format) -> Fx {
    let w = fmt.width as u32;
    let (lo, hi) = (fmt.min_raw() as i128, fmt.max_raw() as i128);
    let expr = if fmt.signed {
        format!("$signed({bits})")
    } else {
        format!("$signed({{1'b0, {bits}}})")
    };
    debug_assert_eq!(signed_bits(lo, hi), w + !fmt.signed as u32);
    make(m, "raw", lo, hi, 0, &expr)
}

impl Fx {
    pub(super) fn at_frac(mut self, frac: u32) -> Fx {
        self.frac = frac;
        self
    }
}

/// [`crate::arith::Acc::from_code`]: read a port word into the datapath.
pub fn from_code(m: &mut Module, bits: &str, enc: &Encoding) -> Fx {
    let n = enc.format.width as u32;
    let r = raw_word(m, bits, &enc.format);
    match enc.codec {
        Codec::Fixed => r.at_frac(enc.format.frac as u32),
        Codec::UnitSigned => r.at_frac(n - 1),
        // c (2^n + 1): the code, with the replication as a factor
        Codec::UnitUnsigned => with_fac(r.at_frac(2 * n), vec![n]),
        // (2c + 1)(2^n + 1)
        Codec::UnitSymmetric => {
            let t = make(
                m,
                "odd",
                2 * r.lo + 1,
                2 * r.hi + 1,
                2 * n,
                &format!("$signed({{{bits}, 1'b1}})"),
            );
            with_fac(t, vec![n])
        }
    }
}

/// Exact product: an unsigned array of the magnitude bits and, for signed operands, the
/// sign rows `- s_a B 2^(n-1) - s_b A 2^(m-1) + s_a s_b 2^(n+m-2)`.
pub fn mul(m: &mut Module, a: &Fx, b: &Fx) -> Fx {
    let (lo, hi) = corners(a, b);
    let a = align_wire(m, a, a.frac);
    let b = align_wire(m, b, b.frac);
    let fac = [a.fac.clone(), b.fac.clone()].concat();
    let frac = a.frac + b.frac;
    // (magnitude bits, sign bit) of an operand
    let split = |x: &Fx| -> (u32, bool) {
        if x.lo >= 0 {
            (super::verilog::unsigned_bits(x.hi as u128), false)
        } else {
            (signed_bits(x.lo, x.hi) - 1, true)
        }
    };
    let ((na, sa), (nb, sb)) = (split(&a), split(&b));
    if na == 0 || nb == 0 {
        // a one-bit signed operand (-1 or 0): no array
        let p = make(m, "mul", lo, hi, frac, &format!("{} * {}", a.name, b.name));
        return with_fac(p, fac);
    }
    let bits = |x: &Fx, n: u32| format!("{}[{}:0]", x.name, n - 1);
    let (ab, bb) = (bits(&a, na), bits(&b, nb));
    let pp = m.uwire("pp", na + nb, &format!("{ab} * {bb}"));
    let mut e = format!("$signed({{1'b0, {pp}}})");
    if sa {
        let row = m.uwire("rowa", nb, &format!("{{{nb}{{{}[{na}]}}}} & {bb}", a.name));
        e += &format!(" - ($signed({{1'b0, {row}}}) <<< {na})");
    }
    if sb {
        let row = m.uwire("rowb", na, &format!("{{{na}{{{}[{nb}]}}}} & {ab}", b.name));
        e += &format!(" - ($signed({{1'b0, {row}}}) <<< {nb})");
    }
    if sa && sb {
        e += &format!(
            " + ($signed({{1'b0, {}[{na}] & {}[{nb}]}}) <<< {})",
            a.name,
            b.name,
            na + nb
        );
    }
    let p = make(m, "mul", lo, hi, frac, &e);
    with_fac(p, fac)
}

/// Exact square `a^2` as a designer folds it: the magnitude bits' partial products `u_i u_j`
/// (`i < j`) once, doubled by position, and the diagonal `u_i` (about half a multiplier's
/// array, what `CostTable::squarer` prices); a signed `a = u - s 2^n` adds the one row
/// `- s u 2^(n+1)` and the constant `s 2^(2n)`.
pub fn square(m: &mut Module, a: &Fx) -> Fx {
    let hi = a.lo.unsigned_abs().max(a.hi.unsigned_abs());
    let hi = (hi * hi) as i128;
    let a = align_wire(m, a, a.frac);
    let fac = [a.fac.clone(), a.fac.clone()].concat();
    let frac = 2 * a.frac;
    let (n, signed) = if a.lo >= 0 {
        (super::verilog::unsigned_bits(a.hi as u128), false)
    } else {
        (signed_bits(a.lo, a.hi) - 1, true)
    };
    if n == 0 {
        // a one-bit signed value (-1 or 0): its square is its sign bit
        let p = make(
            m,
            "sq",
            0,
            1,
            frac,
            &format!("$signed({{1'b0, {}[0]}})", a.name),
        );
        return with_fac(p, fac);
    }
    let u = m.uwire("u", n, &format!("{}[{}:0]", a.name, n - 1));
    let w = 2 * n;
    let mut terms = Vec::new();
    for i in 0..n {
        terms.push(format!("({{{}'d0, {u}[{i}]}} << {})", w - 1, 2 * i));
        if i + 1 < n {
            let k = n - i - 1;
            let row = m.uwire(
                "sqr",
                k,
                &format!("{u}[{}:{}] & {{{k}{{{u}[{i}]}}}}", n - 1, i + 1),
            );
            // u_i u_j (j > i) weighs 2^(i + j + 1): the row's low bit (j = i + 1) at 2i + 2
            terms.push(format!("({{{}'d0, {row}}} << {})", w - k, 2 * i + 2));
        }
    }
    let uu = m.uwire("uu", w, &terms.join(" + "));
    let mut e = format!("$signed({{1'b0, {uu}}})");
    if signed {
        let sb = format!("{}[{n}]", a.name);
        let row = m.uwire("sqs", n, &format!("{{{n}{{{sb}}}}} & {u}"));
        e += &format!(
            " - ($signed({{1'b0, {row}}}) <<< {}) + ($signed({{1'b0, {sb}}}) <<< {})",
            n + 1,
            2 * n
        );
    }
    with_fac(make(m, "sq", 0, hi, frac, &e), fac)
}

/// `a` at `frac` fraction bits (a shift left; `frac >= a.frac`).
pub(super) fn aligned(a: &Fx, frac: u32) -> (String, i128, i128) {
    let s = frac - a.frac;
    if s == 0 {
        (a.name.clone(), a.lo, a.hi)
    } else {
        (format!("({} <<< {s})", a.name), a.lo << s, a.hi << s)
    }
}

/// Exact sum of several terms, aligned to the largest number of fraction bits; factors
/// common to every term stay factors.
pub fn sum(m: &mut Module, terms: &[&Fx]) -> Fx {
    assert!(!terms.is_empty());
    if terms.len() == 1 {
        return terms[0].clone();
    }
    let c = common(terms);
    let terms: Vec<Fx> = terms.iter().map(|t| strip(m, t, &c)).collect();
    let f = terms.iter().map(|t| t.frac).max().unwrap();
    let (mut lo, mut hi, mut e) = (0i128, 0i128, Vec::new());
    for t in &terms {
        let (x, l, h) = aligned(t, f);
        lo += l;
        hi += h;
        e.push(x);
    }
    let s = make(m, "add", lo, hi, f, &e.join(" + "));
    with_fac(s, c)
}

pub fn add(m: &mut Module, a: &Fx, b: &Fx) -> Fx {
    sum(m, &[a, b])
}

/// `a - b`.
pub fn sub(m: &mut Module, a: &Fx, b: &Fx) -> Fx {
    let c = common(&[a, b]);
    let (a, b) = (strip(m, a, &c), strip(m, b, &c));
    let f = a.frac.max(b.frac);
    let (x, al, ah) = aligned(&a, f);
    let (y, bl, bh) = aligned(&b, f);
    let d = make(m, "sub", al - bh, ah - bl, f, &format!("{x} - {y}"));
    with_fac(d, c)
}

/// `x * k` for a constant `k != 0` as shifts and adds (canonical signed digits).
pub(super) fn csd_expr(x: &str, k: i128) -> String {
    let mut e = String::new();
    for (i, (sh, dg)) in crate::arith::csd(k.unsigned_abs())
        .into_iter()
        .rev()
        .enumerate()
    {
        let neg = (dg < 0) != (k < 0);
        let t = if sh == 0 {
            x.to_string()
        } else {
            format!("({x} <<< {sh})")
        };
        if i == 0 {
            e = if neg { format!("-{t}") } else { t };
        } else {
            e += if neg { " - " } else { " + " };
            e += &t;
        }
    }
    e
}

/// Multiply by an integer constant, the pending factors folded in: one shift-and-add
/// network for `k prod (2^n + 1)` (e.g. `255 * 257 = 2^16 - 1`, a subtractor).
pub fn scale(m: &mut Module, a: &Fx, k: i128) -> Fx {
    let k = a.fac.iter().fold(k, |k, &n| k * ((1i128 << n) + 1));
    let (lo, hi) = if k >= 0 {
        (a.lo * k, a.hi * k)
    } else {
        (a.hi * k, a.lo * k)
    };
    if k == 0 {
        return constant(0, a.frac);
    }
    let a = align_wire(m, a, a.frac);
    make(m, "scl", lo, hi, a.frac, &csd_expr(&a.name, k))
}

/// [`crate::arith::Acc::clamp`] into `[lo, hi]` (each `(raw, frac)`, optional).
pub fn clamp(m: &mut Module, a: &Fx, lo: Option<(i128, u32)>, hi: Option<(i128, u32)>) -> Fx {
    let f = [Some(a.frac), lo.map(|l| l.1), hi.map(|h| h.1)]
        .into_iter()
        .flatten()
        .max()
        .unwrap();
    let up = |(r, fr): (i128, u32)| r << (f - fr);
    let a = plain(m, a);
    let a = align_wire(m, &a, f);
    let lo = lo.map(up).filter(|&l| l > a.lo);
    let hi = hi.map(up).filter(|&h| h < a.hi);
    if lo.is_none() && hi.is_none() {
        return a;
    }
    let lim = |v: i128| {
        let v = lo.map_or(v, |l| v.max(l));
        hi.map_or(v, |h| v.min(h))
    };
    let x = &a.name;
    let mut e = x.clone();
    if let Some(h) = hi {
        e = format!("({x} > {}) ? {} : {e}", lit(h), lit(h));
    }
    if let Some(l) = lo {
        e = format!("({x} < {}) ? {} : ({e})", lit(l), lit(l));
    }
    make(m, "clp", lim(a.lo), lim(a.hi), f, &e)
}

/// `a` as a wire at `frac` fraction bits (`frac >= a.frac`): a named wire, so that bit
/// selects and comparisons see the full width.
pub fn align_wire(m: &mut Module, a: &Fx, frac: u32) -> Fx {
    let is_name = a
        .name
        .chars()
        .all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !a.name.starts_with(|c: char| c.is_ascii_digit());
    if frac == a.frac && is_name {
        return a.clone();
    }
    let (x, lo, hi) = aligned(a, frac);
    with_fac(make(m, "al", lo, hi, frac, &x), a.fac.clone())
}

/// A `k`-way selection of `vals` by the unsigned select `sel` (value `i` picks `vals[i]`;
/// values beyond pick the last). Ranges and fraction bits are merged.
pub fn select(m: &mut Module, sel: &str, vals: &[Fx]) -> Fx {
    if vals.len() == 1 {
        return vals[0].clone();
    }
    let same = vals.iter().all(|v| v.fac == vals[0].fac);
    let fac = if same {
        vals[0].fac.clone()
    } else {
        Vec::new()
    };
    let vals: Vec<Fx> = vals.iter().map(|v| strip(m, v, &fac)).collect();
    let f = vals.iter().map(|v| v.frac).max().unwrap();
    let mut lo = i128::MAX;
    let mut hi = i128::MIN;
    let mut parts = Vec::new();
    for v in &vals {
        let (x, l, h) = aligned(v, f);
        lo = lo.min(l);
        hi = hi.max(h);
        parts.push(x);
    }
    let mut e = parts.last().unwrap().clone();
    for (i, p) in parts.iter().enumerate().rev().skip(1) {
        e = format!("({sel} == {i}) ? {p} : ({e})");
    }
    with_fac(make(m, "sel", lo, hi, f, &e), fac)
}

/// A sum of terms whose exact result is known to lie in `[lo, hi]` (an accumulator's
/// update): the adder is only as wide as that range.
pub fn sum_in_range(m: &mut Module, terms: &[&Fx], lo: i128, hi: i128) -> Fx {
    let s = sum(m, terms);
    with_fac(make(m, "acc", lo, hi, s.frac, &s.name), s.fac)
}

/// A register holding an [`Fx`] of range `[lo, hi]` at `frac` fraction bits, loaded with
/// `next` when `en`; returns the register as an [`Fx`].
pub fn register(m: &mut Module, name: &str, en: &str, next: &Fx, lo: i128, hi: i128) -> Fx {
    let w = signed_bits(lo, hi);
    m.sreg(name, w);
    m.stmt(format!(
        "always @(posedge clk) if ({en}) {name} <= {};",
        next.name
    ));
    Fx {
        name: name.to_string(),
        lo,
        hi,
        frac: next.frac,
        fac: next.fac.clone(),
    }
}

/// `value` when the 1-bit `keep` is set, else 0.
pub fn gate(m: &mut Module, keep: &str, v: &Fx) -> Fx {
    let g = make(
        m,
        "gt",
        v.lo.min(0),
        v.hi.max(0),
        v.frac,
        &format!("{keep} ? {} : {}", v.name, lit(0)),
    );
    with_fac(g, v.fac.clone())
}
