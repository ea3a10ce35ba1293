//! Verilog of the ROP's datapath ([`crate::units::RopDatapath`], [`crate::units::Rop::resolve`]):
//! one fragment against the pixel it lands on, the framebuffer read (`dc`, `dz`) and write
//! (`wc`, `wz`, `oc`) outside the module, as the texture memories are outside the fetch units.
//!
//! * **Conversions**: the colour lanes into framebuffer codes and alpha into 8 bits,
//!   `clamp(round(num (2^b - 1) / den), 0, 2^b - 1)` of the word's exact rational `num / den`
//!   (a constant multiply, [`divide::div_round`], a clamp); a unit code of the framebuffer's
//!   own width is the code itself (no logic).
//! * **Tests**: the depth and alpha functions in host registers in GL's order (`Never` 0,
//!   `Less` 1, `Equal` 2, `LEqual` 3, `Greater` 4, `NotEqual` 5, `GEqual` 6, `Always` 7), whose
//!   bits are exactly "pass when less", "when equal", "when greater": the test is the OR of the
//!   function's bits ANDed with one comparator's three outcomes, no decoder. A ROP whose depth
//!   function is `Always` or `Never` has no comparator; without an alpha test no alpha one.
//! * **Blender** (when the ROP blends): the source and destination factors in host registers
//!   (GL's table order of [`crate::units::rop::Factor`], 0 to 7), each an 8-way select of 0,
//!   `2^b - 1`, the source, the destination, alpha and their complements (`2^b - 1 - x` of a
//!   `b`-bit code is its bitwise NOT); two `b x b` products a channel, their sum, the
//!   round-half-up division by `2^b - 1` and the clamp to `2^b - 1`. Alpha is scaled from 8
//!   bits to the framebuffer's codes (nothing at 8 bits).
//! * **Write**: `wc` = both tests passed, `wz` = `wc` and the depth-write register, `oc` the
//!   new codes when `wc`, else the stored ones.
//!
//! The host registers hold one pass's state; a multi-pass engine reloads them between passes
//! (co-simulation runs each pass's state). Clocking: one edge from `start` into the output
//! registers (latency 1, as the unit).

use super::divide;
use super::fixed::{add, clamp, make, mul, raw_word, scale, Fx};
use super::verilog::Module;
use super::{Plan, RtlUnit, Shell};
use crate::format::{Codec, Encoding, Format};
use crate::unit::Unit;
use crate::units::rop::{conversion_terms, Compare};
use crate::units::RopDatapath;

/// `clamp(round(num (2^bits - 1) / den), 0, 2^bits - 1)` of the word `w` of `enc` as a
/// `bits`-bit unsigned code (the model's `Rop::code_of`).
pub(crate) fn code(m: &mut Module, w: &str, enc: &Encoding, bits: u32) -> String {
    let n = enc.width();
    if enc.codec == Codec::UnitUnsigned && n == bits {
        return w.to_string();
    }
    let one = (1i128 << bits) - 1;
    let r = raw_word(m, w, &enc.format);
    let num = if enc.codec == Codec::UnitSymmetric {
        let expr = if enc.format.signed {
            format!("$signed({{{w}, 1'b1}})")
        } else {
            format!("$signed({{1'b0, {w}, 1'b1}})")
        };
        make(m, "odd", 2 * r.lo + 1, 2 * r.hi + 1, 0, &expr)
    } else {
        r
    };
    let (_, den) = conversion_terms(enc);
    let x = scale(m, &num, one);
    let q = divide::div_round(m, &x, den);
    let q = clamp(m, &q, Some((0, 0)), Some((one, 0)));
    low_bits(m, &q, bits)
}

/// The low `bits` bits of a non-negative wire (its range within `[0, 2^bits)`).
fn low_bits(m: &mut Module, a: &Fx, bits: u32) -> String {
    debug_assert!(a.lo >= 0 && a.hi < 1i128 << bits);
    if a.lo == a.hi {
        return format!("{bits}'d{}", a.lo);
    }
    m.uwire("code", bits, &format!("{}[{}:0]", a.name, bits - 1))
}

/// A test: the function register's bits against `a`'s comparison with `b` (GL's order), as
/// one magnitude comparator and an equality (greater is neither).
fn test(m: &mut Module, func: &str, a: &str, b: &str) -> String {
    let lt = m.uwire("lt", 1, &format!("{a} < {b}"));
    let eq = m.uwire("eq", 1, &format!("{a} == {b}"));
    m.uwire(
        "pass",
        1,
        &format!("|({func} & {{~({lt} | {eq}), {eq}, {lt}}})"),
    )
}

/// The Verilog of a [`RopDatapath`].
pub fn rtl(u: &RopDatapath, top: &str) -> RtlUnit {
    let rop = u.rop();
    let p = *rop.params();
    let b = p.color_bits;
    let mut sh = Shell::new(top, Plan::single());
    let ins = u.inputs().to_vec();
    let outs = u.outputs().to_vec();
    let c = sh.port(0, &ins[0], false);
    let z = sh.port(1, &ins[1], false).remove(0);
    let dc = sh.port(2, &ins[2], false);
    let dz = sh.port(3, &ins[3], false).remove(0);
    let wc = sh.output(0, &outs[0]).remove(0);
    let wz = sh.output(1, &outs[1]).remove(0);
    let oc = sh.output(2, &outs[2]);
    let depth_test = !matches!(p.depth, Compare::Always | Compare::Never);
    let dfunc = depth_test.then(|| {
        sh.config_raw(
            "depth function (GL order: bit 0 less, 1 equal, 2 greater)",
            3,
            p.depth as i64,
        )
    });
    let dwrite = sh.config_raw("depth write", 1, i64::from(p.depth_write));
    let atest = p.alpha_test.map(|(f, r)| {
        (
            sh.config_raw("alpha function (GL order)", 3, f as i64),
            sh.config_raw("alpha reference", 8, i64::from(r)),
        )
    });
    let factors = p.blend.map(|(s, d)| {
        (
            sh.config_raw(
                "source factor (0 zero, 1 one, 2 src, 3 1-src, 4 dst, 5 1-dst, 6 alpha, 7 1-alpha)",
                3,
                s as i64,
            ),
            sh.config_raw("destination factor", 3, d as i64),
        )
    });
    let comp = sh.comp.clone();
    let m = &mut sh.m;
    let enc = rop.color();
    let one = (1i128 << b) - 1;
    m.comment("alpha in 8 bits, the tests");
    let a8 = rop.alpha().map(|ae| code(m, &c[3], &ae, 8));
    let alpha_ok = match (&atest, &a8) {
        (Some((f, r)), Some(a)) => test(m, f, a, r),
        _ => "1'b1".to_string(),
    };
    let depth_ok = match &dfunc {
        Some(f) => test(m, f, &z, &dz),
        None => format!("1'b{}", u8::from(p.depth == Compare::Always)),
    };
    let write = m.uwire("write", 1, &format!("{alpha_ok} & {depth_ok}"));
    let ubits = Format::u(b as u8, 0);
    // alpha in framebuffer codes
    let a_fb = match (&factors, &a8) {
        (Some(_), Some(a)) if b == 8 => a.clone(),
        (Some(_), Some(a)) => {
            let r = raw_word(m, a, &Format::u(8, 0));
            let x = scale(m, &r, one);
            let q = divide::div_round(m, &x, 255);
            low_bits(m, &q, b)
        }
        _ => format!("{b}'d{one}"),
    };
    let mut codes = Vec::new();
    for l in 0..3 {
        m.comment(&format!("channel {l}"));
        let s = code(m, &c[l], &enc, b);
        let Some((fs, fd)) = &factors else {
            codes.push(s);
            continue;
        };
        let d = &dc[l];
        let choices = [
            format!("{b}'d0"),
            format!("{b}'d{one}"),
            s.clone(),
            format!("~{s}"),
            d.clone(),
            format!("~{d}"),
            a_fb.clone(),
            format!("~{a_fb}"),
        ];
        let factor = |m: &mut Module, sel: &str| -> Fx {
            let mut e = choices[7].clone();
            for (i, ch) in choices.iter().enumerate().rev().skip(1) {
                e = format!("({sel} == 3'd{i}) ? {ch} : ({e})");
            }
            let f = m.uwire("factor", b, &e);
            raw_word(m, &f, &ubits)
        };
        let (f_s, f_d) = (factor(m, fs), factor(m, fd));
        let (sv, dv) = (raw_word(m, &s, &ubits), raw_word(m, d, &ubits));
        let ps = mul(m, &f_s, &sv);
        let pd = mul(m, &f_d, &dv);
        let sum = add(m, &ps, &pd);
        let q = divide::div_round(m, &sum, one);
        let q = clamp(m, &q, None, Some((one, 0)));
        codes.push(low_bits(m, &q, b));
    }
    m.stmt(format!(
        "always @(posedge clk) if ({comp}) begin\n    {wc} <= {write};\n    {wz} <= {write} & {dwrite};"
    ));
    for l in 0..3 {
        m.stmt(format!(
            "    {} <= {write} ? {} : {};",
            oc[l], codes[l], dc[l]
        ));
    }
    m.stmt("end");
    sh.finish()
}
