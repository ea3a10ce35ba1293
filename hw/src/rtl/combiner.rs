//! Verilog of the NV20 / NV2A register combiners ([`crate::units::combiner::Combiner`],
//! NV_register_combiners 2.14): the programmable part, not one program. Every general stage
//! is the whole stage of the spec (for each portion four 12:1 operand selects with their
//! component usage and eight input mappings, the products or dot products read back into the
//! register format, the sum or the mux, the output scale and bias with the clamp, the
//! write-back into up to three registers and NV2A's blue-to-alpha copies) and one pipeline
//! stage of the register file (fog to spare1, 9 registers of 4 lanes); the final combiner is
//! two (the `spare0 + secondary` sum, `E * F` and the variables; then `A B + (1 - A) C + D`,
//! the clamps and the 8-bit codes). The program is host-loaded state, as the NV2A's
//! `NV097_SET_COMBINER_*` registers: the unit's program is written into it by the host port
//! (the stages the program leaves out hold a stage that writes nothing).
//!
//! Host words (the NV2A's fields; the register numbering is the model's register-file index,
//! ZERO 0 to SPARE1 11, not the NV2A's source codes):
//! * per general stage and portion (RGB, alpha), per variable A to D, 8 bits as NV2A's ICW
//!   byte: `[3:0]` register, `[4]` ALPHA usage (else RGB, or BLUE in the alpha portion),
//!   `[7:5]` the mapping in the order of [`Mapping::ALL`];
//! * per portion the OCW: `[3:0]` AB, `[7:4]` CD, `[11:8]` sum destination (0 discards),
//!   `[12]` AB dot, `[13]` CD dot, `[14]` mux, `[17:15]` the output op in the order of
//!   [`OutputOp::ALL`], `[18]` CD and `[19]` AB blue to alpha;
//! * per stage the constants 0 and 1 as RGBA codes (R in `[7:0]`);
//! * the final combiner's variables A to G, 6 bits: `[3:0]` register (12 `spare0 +
//!   secondary`, 13 `E * F`), `[4]` ALPHA usage (G: else BLUE), `[5]` invert; its flags
//!   (`[0]` invert spare0, `[1]` invert secondary, `[2]` clamp the sum) and constants;
//! * the mux select (1: MSB).
//!
//! The datapath is the model's ([`crate::units::combiner`]'s `FixedPath`): a register
//! is a signed word in units of `S = 255 2^(w - 9)`, a product or dot product is read back
//! by the round-half-up division by `S` ([`super::divide`]), the port words by the exact
//! reading of their codec. Every register holds a value in `[-S, S]` (ports, outputs and
//! constants are), so UNSIGNED_INVERT's clamp is `max(0, x)` and the final combiner's
//! `max(0, x)` needs no upper clamp.

use super::divide::div_round;
use super::fixed::{
    add, align_wire, clamp, constant, make, mul, raw_word, scale, select, shift_round, sum, Fx,
};
use super::normalize::stage;
use super::verilog::{lit, Module};
use super::{Plan, RtlUnit, Shell};
use crate::format::{Codec, Encoding, Quant};
use crate::unit::Unit;
use crate::units::combiner::{
    Combiner, FinalInput, GeneralStage, Input, Mapping, MuxSelect, OutputOp, Portion, Source,
    Usage, INPUT_PORTS,
};

/// The register file: 12 registers of 4 lanes.
type Regs = Vec<[Fx; 4]>;

/// The register format: 1.0 and one half as words, the extra fraction bits.
#[derive(Clone, Copy)]
struct Fmt {
    s: i128,
    h: i128,
    f: u32,
}

fn reg_index(s: Source) -> i64 {
    match s {
        Source::Spare0PlusSecondary => 12,
        Source::EfProduct => 13,
        s => s.index().map_or(0, |i| i as i64),
    }
}

fn icw(i: &Input) -> i64 {
    let m = Mapping::ALL
        .iter()
        .position(|x| *x == i.mapping)
        .unwrap_or(0) as i64;
    reg_index(i.source) | ((i.usage == Usage::Alpha) as i64) << 4 | m << 5
}

fn ocw(p: &Portion, ab_b2a: bool, cd_b2a: bool) -> i64 {
    let dst = |o: Option<Source>| o.map_or(0, reg_index);
    let op = OutputOp::ALL.iter().position(|x| *x == p.op).unwrap_or(0) as i64;
    dst(p.ab_out)
        | dst(p.cd_out) << 4
        | dst(p.sum_out) << 8
        | (p.ab_dot as i64) << 12
        | (p.cd_dot as i64) << 13
        | (p.mux as i64) << 14
        | op << 15
        | (cd_b2a as i64) << 18
        | (ab_b2a as i64) << 19
}

fn fin_word(i: &FinalInput) -> i64 {
    reg_index(i.source) | ((i.usage == Usage::Alpha) as i64) << 4 | (i.invert as i64) << 5
}

fn rgba_word(c: &[u8; 4]) -> i64 {
    c.iter()
        .enumerate()
        .fold(0, |w, (l, &k)| w | (k as i64) << (8 * l))
}

/// The host words of one portion: the four variables and the OCW.
struct PortionCfg {
    vars: [String; 4],
    ocw: String,
}

struct StageCfg {
    rgb: PortionCfg,
    alpha: PortionCfg,
    c0: String,
    c1: String,
}

struct FinalCfg {
    /// A to G.
    vars: [String; 7],
    flags: String,
    c0: String,
    c1: String,
}

fn portion_cfg(sh: &mut Shell, at: &str, p: &Portion, b2a: (bool, bool)) -> PortionCfg {
    let vars = [&p.a, &p.b, &p.c, &p.d]
        .into_iter()
        .zip(["a", "b", "c", "d"])
        .map(|(i, n)| sh.config_raw(&format!("{at}.{n} (icw byte)"), 8, icw(i)))
        .collect::<Vec<_>>()
        .try_into()
        .unwrap();
    let ocw = sh.config_raw(&format!("{at} ocw"), 20, ocw(p, b2a.0, b2a.1));
    PortionCfg { vars, ocw }
}

/// A port word read into the register format (`FixedPath::port`), clamped to `[-S, S]`.
fn read(m: &mut Module, bits: &str, enc: &Encoding, fm: Fmt) -> Fx {
    let n = enc.width();
    let r = raw_word(m, bits, &enc.format);
    let v = match enc.codec {
        Codec::UnitUnsigned | Codec::UnitSymmetric => {
            // round-half-up(c S / (2^n - 1)), c the code (or 2 code + 1), the fraction reduced
            let c = if enc.codec == Codec::UnitSymmetric {
                make(
                    m,
                    "odd",
                    2 * r.lo + 1,
                    2 * r.hi + 1,
                    0,
                    &format!("$signed({{{bits}, 1'b1}})"),
                )
            } else {
                r
            };
            let d = (1i128 << n) - 1;
            let g = crate::arith::gcd(fm.s as u128, d as u128) as i128;
            let x = scale(m, &c, fm.s / g);
            if d == g {
                x
            } else {
                div_round(m, &x, d / g)
            }
        }
        Codec::Fixed | Codec::UnitSigned => {
            let f = if enc.codec == Codec::Fixed {
                enc.format.frac as u32
            } else {
                n - 1
            };
            let x = scale(m, &r, fm.s);
            shift_round(m, &x, f, Quant::Rnd)
        }
    };
    clamp(m, &v, Some((-fm.s, 0)), Some((fm.s, 0)))
}

/// The 8-bit RGBA constant word `w` as four register values `k 2^f`.
fn constants(m: &mut Module, w: &str, fm: Fmt) -> [Fx; 4] {
    std::array::from_fn(|l| {
        let code = format!("{w}[{}:{}]", 8 * l + 7, 8 * l);
        let e = if fm.f == 0 {
            format!("$signed({{1'b0, {code}}})")
        } else {
            format!("$signed({{1'b0, {code}, {}'d0}})", fm.f)
        };
        make(m, "k", 0, 255 << fm.f, 0, &e)
    })
}

/// The register file with the stage's (or final combiner's) constants in registers 1 and 2.
fn with_constants(m: &mut Module, regs: &[[Fx; 4]], c0: &str, c1: &str, fm: Fmt) -> Regs {
    let mut r = regs.to_vec();
    r[1] = constants(m, c0, fm);
    r[2] = constants(m, c1, fm);
    r
}

/// Lane `lane` of the register the 4-bit `src` names (12:1; larger values read SPARE1).
fn pick(m: &mut Module, regs: &[[Fx; 4]], src: &str, lane: usize) -> Fx {
    let vals: Vec<Fx> = regs.iter().map(|r| r[lane].clone()).collect();
    select(m, src, &vals)
}

/// The eight input mappings of `x` (in `[-S, S]`), selected by the 3-bit `map`.
fn mapping(m: &mut Module, x: &Fx, map: &str, fm: Fmt) -> Fx {
    let (s, h) = (fm.s, fm.h);
    let pos = make(
        m,
        "pos",
        0,
        x.hi.max(0),
        0,
        &format!("{x} < {z} ? {z} : {x}", x = x.name, z = lit(0)),
    );
    let p = &pos.name;
    let (ls, lh) = (lit(s), lit(h));
    let vals = [
        pos.clone(),
        make(m, "inv", s - pos.hi, s, 0, &format!("{} - {p}", ls)),
        make(
            m,
            "exp",
            -s,
            2 * pos.hi - s,
            0,
            &format!("({p} <<< 1) - {}", ls),
        ),
        make(
            m,
            "exn",
            s - 2 * pos.hi,
            s,
            0,
            &format!("{} - ({p} <<< 1)", ls),
        ),
        make(m, "hbn", -h, pos.hi - h, 0, &format!("{p} - {}", lh)),
        make(m, "hbg", h - pos.hi, h, 0, &format!("{} - {p}", lh)),
        x.clone(),
        make(m, "neg", -x.hi, -x.lo, 0, &format!("-{}", x.name)),
    ];
    select(m, map, &vals)
}

/// One variable's lanes (3 in the RGB portion, 1 in the alpha portion) from its ICW byte.
fn variable(m: &mut Module, regs: &[[Fx; 4]], w: &str, lanes: usize, fm: Fmt) -> Vec<Fx> {
    let src = format!("{w}[3:0]");
    let alpha = format!("{w}[4]");
    let map = format!("{w}[7:5]");
    let a = pick(m, regs, &src, 3);
    let own: Vec<usize> = if lanes == 3 { vec![0, 1, 2] } else { vec![2] };
    own.into_iter()
        .map(|l| {
            let o = pick(m, regs, &src, l);
            let v = select(m, &alpha, &[o, a.clone()]);
            mapping(m, &v, &map, fm)
        })
        .collect()
}

/// `x * y` lane by lane, or the dot product broadcast when `dot`; read back by `/ S`.
fn products(m: &mut Module, x: &[Fx], y: &[Fx], dot: &str, fm: Fmt) -> Vec<Fx> {
    let p: Vec<Fx> = x.iter().zip(y).map(|(a, b)| mul(m, a, b)).collect();
    if p.len() == 1 {
        return vec![div_round(m, &p[0], fm.s)];
    }
    let d = sum(m, &p.iter().collect::<Vec<_>>());
    let first = select(m, dot, &[p[0].clone(), d]);
    let r0 = div_round(m, &first, fm.s);
    let mut out = vec![r0.clone()];
    for q in &p[1..] {
        let r = div_round(m, q, fm.s);
        out.push(select(m, dot, &[r, r0.clone()]));
    }
    out
}

/// The output scale and bias of the 3-bit `op`, then the clamp to `[-S, S]`.
fn output_op(m: &mut Module, x: &Fx, op: &str, fm: Fmt) -> Fx {
    let biased = make(
        m,
        "bs",
        x.lo - fm.h,
        x.hi - fm.h,
        0,
        &format!("{} - {}", x.name, lit(fm.h)),
    );
    let v = select(m, &format!("{op}[0]"), &[x.clone(), biased]);
    let up = add(m, &v, &constant(1, 0));
    let half = make(
        m,
        "hv",
        up.lo >> 1,
        up.hi >> 1,
        0,
        &format!("{} >>> 1", up.name),
    );
    let vals = [v.clone(), scale(m, &v, 2), scale(m, &v, 4), half];
    let r = select(m, &format!("{op}[2:1]"), &vals);
    clamp(m, &r, Some((-fm.s, 0)), Some((fm.s, 0)))
}

/// One portion: (AB, CD, sum or mux) after the output op, `lanes` values each.
fn portion(
    m: &mut Module,
    regs: &[[Fx; 4]],
    c: &PortionCfg,
    lanes: usize,
    pass: &str,
    fm: Fmt,
) -> [Vec<Fx>; 3] {
    let v: Vec<Vec<Fx>> = c
        .vars
        .iter()
        .map(|w| variable(m, regs, w, lanes, fm))
        .collect();
    let o = &c.ocw;
    let ab = products(m, &v[0], &v[1], &format!("{o}[12]"), fm);
    let cd = products(m, &v[2], &v[3], &format!("{o}[13]"), fm);
    let sm: Vec<Fx> = ab
        .iter()
        .zip(&cd)
        .map(|(x, y)| {
            let s = add(m, x, y);
            let mx = select(m, pass, &[x.clone(), y.clone()]);
            select(m, &format!("{o}[14]"), &[s, mx])
        })
        .collect();
    let op = m.uwire("op", 3, &format!("{o}[17:15]"));
    [ab, cd, sm].map(|xs| xs.iter().map(|x| output_op(m, x, &op, fm)).collect())
}

/// `(destination field == r) ? value : ...` chains, the first pair winning.
fn write_back(m: &mut Module, old: &Fx, writes: &[(String, &Fx)], fm: Fmt) -> Fx {
    let mut e = old.name.clone();
    for (cond, v) in writes.iter().rev() {
        e = format!("({cond}) ? {} : ({e})", v.name);
    }
    make(m, "wb", -fm.s, fm.s, 0, &e)
}

/// One general stage: the register file after it.
fn general(m: &mut Module, regs: &[[Fx; 4]], c: &StageCfg, msb: &str, fm: Fmt) -> Regs {
    let r = with_constants(m, regs, &c.c0, &c.c1, fm);
    let a0 = &align_wire(m, &r[10][3], 0);
    let pass = if a0.lo == a0.hi {
        // a constant spare0 alpha (no texture 0 alpha lane): both tests are constants
        let v = a0.lo;
        let code = if fm.f == 0 {
            v
        } else {
            (v + (1 << (fm.f - 1))) >> fm.f
        };
        let (msb_pass, lsb_pass) = ((v >= fm.h) as u8, (code & 1) as u8);
        m.uwire("pass", 1, &format!("{msb} ? 1'b{msb_pass} : 1'b{lsb_pass}"))
    } else {
        let lsb = if fm.f == 0 {
            format!("{}[0]", a0.name)
        } else {
            let t = add(m, a0, &constant(1 << (fm.f - 1), 0));
            format!("{}[{}]", t.name, fm.f)
        };
        m.uwire(
            "pass",
            1,
            &format!("{msb} ? ({} >= {}) : {lsb}", a0.name, lit(fm.h)),
        )
    };
    let rgb = portion(m, &r, &c.rgb, 3, &pass, fm);
    let alpha = portion(m, &r, &c.alpha, 1, &pass, fm);
    let (ro, ao) = (&c.rgb.ocw, &c.alpha.ocw);
    let dst = |o: &str, k: usize, i: usize| format!("{o}[{}:{}] == 4'd{i}", 4 * k + 3, 4 * k);
    let mut next = regs.to_vec();
    for (i, reg) in next.iter_mut().enumerate().skip(4) {
        for l in 0..3 {
            let w: Vec<(String, &Fx)> = (0..3).rev().map(|k| (dst(ro, k, i), &rgb[k][l])).collect();
            reg[l] = write_back(m, &regs[i][l], &w, fm);
        }
        let mut w = vec![
            (format!("{ro}[18] && {}", dst(ro, 1, i)), &rgb[1][2]),
            (format!("{ro}[19] && {}", dst(ro, 0, i)), &rgb[0][2]),
        ];
        w.extend((0..3).rev().map(|k| (dst(ao, k, i), &alpha[k][0])));
        reg[3] = write_back(m, &regs[i][3], &w, fm);
    }
    next
}

/// `max(0, x)`, or `S - max(0, x)` inverted (`x <= S`), by the 1-bit `inv`.
fn fin_map(m: &mut Module, x: &Fx, inv: &str, fm: Fmt) -> Fx {
    let pos = make(
        m,
        "fp",
        0,
        x.hi.max(0),
        0,
        &format!("{x} < {z} ? {z} : {x}", x = x.name, z = lit(0)),
    );
    let clipped = clamp(m, &pos, None, Some((fm.s, 0)));
    let i = make(
        m,
        "fi",
        fm.s - clipped.hi,
        fm.s,
        0,
        &format!("{} - {}", lit(fm.s), clipped.name),
    );
    select(m, inv, &[pos, i])
}

/// A final-combiner variable's three lanes from its word: registers 0 to 11, then the
/// `extra` inputs (`spare0 + secondary`, `E * F`; their usage bit is 0, the model's rule).
fn fin_variable(m: &mut Module, regs: &[[Fx; 4]], w: &str, extra: &[&[Fx]], fm: Fmt) -> Vec<Fx> {
    let src = format!("{w}[3:0]");
    let a = pick(m, regs, &src, 3);
    (0..3)
        .map(|l| {
            let mut vals: Vec<Fx> = regs.iter().map(|r| r[l].clone()).collect();
            vals.extend(extra.iter().map(|e| e[l].clone()));
            let o = select(m, &src, &vals);
            let v = select(m, &format!("{w}[4]"), &[o, a.clone()]);
            fin_map(m, &v, &format!("{w}[5]"), fm)
        })
        .collect()
}

/// The Verilog of a built [`Combiner`] (its width, stages, ports and encodings are the part;
/// its program is the host-loaded state).
pub fn rtl(u: &Combiner, top: &str) -> RtlUnit {
    let params = *u.params();
    let prog = u.program();
    let n = params.stages;
    let f = params.width - 9;
    let s = 255i128 << f;
    let fm = Fmt {
        s,
        h: (s + 1) >> 1,
        f,
    };
    let mut sh = Shell::new(top, Plan::pipeline(n as u32 + 2));
    let ins = u.inputs().to_vec();
    let mut lanes: Vec<Vec<String>> = vec![Vec::new(); INPUT_PORTS.len()];
    for (i, p) in ins.iter().enumerate() {
        let names = sh.port(i, p, false);
        let k = INPUT_PORTS.iter().position(|q| *q == p.name).unwrap_or(0);
        lanes[k] = names;
    }
    let outs = sh.output(0, &u.outputs()[0]);
    let msb = sh.config_raw(
        "mux_select (1: MSB)",
        1,
        (prog.mux_select == MuxSelect::Msb) as i64,
    );
    let stages: Vec<StageCfg> = (0..n)
        .map(|k| {
            let st = prog.stages.get(k).copied().unwrap_or(GeneralStage::nop());
            let at = format!("stages[{k}]");
            StageCfg {
                rgb: portion_cfg(
                    &mut sh,
                    &format!("{at}.rgb"),
                    &st.rgb,
                    (st.ab_blue_to_alpha, st.cd_blue_to_alpha),
                ),
                alpha: portion_cfg(&mut sh, &format!("{at}.alpha"), &st.alpha, (false, false)),
                c0: sh.config_raw(&format!("{at}.c0 (rgba)"), 32, rgba_word(&st.c0)),
                c1: sh.config_raw(&format!("{at}.c1 (rgba)"), 32, rgba_word(&st.c1)),
            }
        })
        .collect();
    let fc = &prog.final_combiner;
    let fin_cfg = FinalCfg {
        vars: [&fc.a, &fc.b, &fc.c, &fc.d, &fc.e, &fc.f, &fc.g]
            .into_iter()
            .zip("abcdefg".chars())
            .map(|(i, c)| sh.config_raw(&format!("final_combiner.{c}"), 6, fin_word(i)))
            .collect::<Vec<_>>()
            .try_into()
            .unwrap(),
        flags: sh.config_raw(
            "final_combiner flags (invert spare0, invert secondary, clamp)",
            3,
            fc.sum_invert_spare0 as i64
                | (fc.sum_invert_secondary as i64) << 1
                | (fc.sum_clamp as i64) << 2,
        ),
        c0: sh.config_raw("final_combiner.c0 (rgba)", 32, rgba_word(&fc.c0)),
        c1: sh.config_raw("final_combiner.c1 (rgba)", 32, rgba_word(&fc.c1)),
    };
    let fin = sh.fin.clone();
    let m = &mut sh.m;

    m.comment("the ports read into the registers (fog, primary, secondary, tex0..3)");
    const PORT_OF: [usize; 7] = [2, 0, 1, 3, 4, 5, 6];
    let zero = constant(0, 0);
    let mut regs: Regs = vec![std::array::from_fn(|_| zero.clone()); 12];
    for (k, &port) in PORT_OF.iter().enumerate() {
        let enc = params.inputs[port];
        for (l, bits) in lanes[port].iter().enumerate() {
            regs[3 + k][l] = read(m, bits, &enc, fm);
        }
    }
    regs[10][3] = regs[6][3].clone(); // spare0 alpha = texture 0 alpha
    for (k, c) in stages.iter().enumerate() {
        m.comment(&format!("general combiner stage {k}"));
        let next = general(m, &regs, c, &msb, fm);
        for (i, r) in next.iter().enumerate().skip(3) {
            for l in 0..4 {
                regs[i][l] = stage(m, &format!("g{k}_r{i}_{l}"), &r[l]);
            }
        }
    }

    m.comment("final combiner, first stage: spare0 + secondary, E * F, the variables");
    let fcfg = &fin_cfg;
    let r = with_constants(m, &regs, &fcfg.c0, &fcfg.c1, fm);
    let fl = &fcfg.flags;
    let sum_l: Vec<Fx> = (0..3)
        .map(|l| {
            let r0 = fin_map(m, &r[10][l], &format!("{fl}[0]"), fm);
            let v1 = fin_map(m, &r[5][l], &format!("{fl}[1]"), fm);
            let t = add(m, &r0, &v1);
            let c = clamp(m, &t, None, Some((fm.s, 0)));
            select(m, &format!("{fl}[2]"), &[t, c])
        })
        .collect();
    let e = fin_variable(m, &r, &fcfg.vars[4], &[], fm);
    let fv = fin_variable(m, &r, &fcfg.vars[5], &[], fm);
    let ef: Vec<Fx> = e
        .iter()
        .zip(&fv)
        .map(|(x, y)| {
            let p = mul(m, x, y);
            div_round(m, &p, fm.s)
        })
        .collect();
    let abcd: Vec<Vec<Fx>> = fcfg.vars[..4]
        .iter()
        .map(|w| fin_variable(m, &r, w, &[&sum_l, &ef], fm))
        .collect();
    let gw = &fcfg.vars[6];
    let g_src = format!("{gw}[3:0]");
    let g_a = pick(m, &r, &g_src, 3);
    let g_b = pick(m, &r, &g_src, 2);
    let g = select(m, &format!("{gw}[4]"), &[g_b, g_a]);
    let g = fin_map(m, &g, &format!("{gw}[5]"), fm);
    let abcd: Vec<Vec<Fx>> = abcd
        .iter()
        .enumerate()
        .map(|(v, lanes)| {
            lanes
                .iter()
                .enumerate()
                .map(|(l, x)| stage(m, &format!("f_{}{l}", "abcd".as_bytes()[v] as char), x))
                .collect()
        })
        .collect();
    let g = stage(m, "f_g", &g);

    m.comment("final combiner, second stage: A B + (1 - A) C + D, the clamps, the codes");
    let code = |m: &mut Module, x: &Fx| -> String {
        let c = clamp(m, x, Some((0, 0)), Some((fm.s, 0)));
        let k = if fm.f == 0 {
            c
        } else {
            shift_round(m, &c, fm.f, Quant::Rnd)
        };
        format!("{}[7:0]", k.name)
    };
    for l in 0..3 {
        let (a, b, c, d) = (&abcd[0][l], &abcd[1][l], &abcd[2][l], &abcd[3][l]);
        let one_a = make(
            m,
            "oa",
            fm.s - a.hi,
            fm.s - a.lo,
            0,
            &format!("{} - {}", lit(fm.s), a.name),
        );
        let p = mul(m, a, b);
        let q = mul(m, &one_a, c);
        let t = add(m, &p, &q);
        let lerp = div_round(m, &t, fm.s);
        let y = add(m, &lerp, d);
        let k = code(m, &y);
        m.stmt(format!(
            "always @(posedge clk) if ({fin}) {} <= {k};",
            outs[l]
        ));
    }
    let k = code(m, &g);
    m.stmt(format!(
        "always @(posedge clk) if ({fin}) {} <= {k};",
        outs[3]
    ));
    sh.finish()
}
