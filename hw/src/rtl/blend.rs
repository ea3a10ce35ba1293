//! Verilog of the bump blend unit ([`crate::units::BumpBlend`], Ernst et al. 1998 §4.2):
//! per datapath the dot products `B . L_i` and `B . H_i` clamped and cast into the intensity
//! register encoding `dot`, the power table as a ROM with the model's contents, the colour
//! multipliers by the light-colour registers `k_i L_i` (host-loaded, quantized as the model
//! does), an exact accumulator per channel, then `C_src + acc` clamped to [0, 1] and cast
//! once into `out`.
//!
//! Clocking as the model's latency (`interval + 2`): edge 1 loads the input registers, edges
//! 2 to `interval + 1` accumulate one light per datapath, the last edge writes the output
//! registers. Selective blending passes `C_src` through as the model does (`skip`); the
//! `Table` generator only (the others are an error: not yet generated).

use super::fixed::raw_word;
use super::fixed::{clamp_code, from_code, gate, mul, register, sum, sum_in_range, Fx};
use super::power::nearest_index;
use super::verilog::{lit, Module};
use super::{Plan, RtlUnit, Shell};
use crate::format::{Codec, Encoding};
use crate::unit::Unit;
use crate::units::{BumpBlend, Selective, SpecGen};

/// The Verilog of a built bump blend unit.
pub fn rtl(u: &BumpBlend, top: &str) -> Result<RtlUnit, String> {
    let p = u.params();
    let gen = u.generator();
    let table = match (gen, p.spec) {
        (None, _) => None,
        (Some(g), SpecGen::Table { value_bits, .. }) => Some((g.table().to_vec(), value_bits)),
        (Some(_), s) => return Err(format!("bump blend: generator {s:?} is not generated yet")),
    };
    let n = p.lights.len();
    let par = (p.parallel as usize).clamp(1, n);
    let iv = u.interval();
    let plan = Plan {
        capture: true,
        interval: iv,
        finish: true,
    };
    let mut sh = Shell::new(top, plan);
    let ins = u.inputs().to_vec();
    let regs: Vec<Vec<String>> = ins
        .iter()
        .enumerate()
        .map(|(i, s)| sh.port(i, s, true))
        .collect();
    let idx = |name: &str| crate::unit::port_index(&ins, name);
    let out = sh.output(0, &u.outputs()[0]);
    // bump-state and colour registers, quantized as BumpBlend::new quantizes them
    let kc: Vec<Vec<String>> = p
        .lights
        .iter()
        .enumerate()
        .map(|(i, l)| {
            (0..3)
                .map(|c| {
                    sh.config_reg(
                        &format!("k{i}*L{i}[{c}]"),
                        &p.color,
                        p.color.encode(l.color[c] * l.k),
                    )
                })
                .collect()
        })
        .collect();
    let state = |sh: &mut Shell,
                 what: &str,
                 on: bool,
                 pick: &dyn Fn(usize) -> [f64; 3]|
     -> Option<Vec<Vec<String>>> {
        on.then(|| {
            (0..n)
                .map(|i| {
                    (0..3)
                        .map(|j| {
                            sh.config_reg(
                                &format!("{what}{i}[{j}]"),
                                &p.state,
                                p.state.encode(pick(i)[j]),
                            )
                        })
                        .collect()
                })
                .collect()
        })
    };
    let (il, ih) = (idx("l0"), idx("h0"));
    let l_state = state(&mut sh, "L", p.kind.diffuse() && il.is_none(), &|i| {
        p.lights[i].l
    });
    let h_state = state(&mut sh, "H", p.kind.specular() && ih.is_none(), &|i| {
        p.lights[i].h
    });
    // per light, the lane names of L and H and their encodings
    let vecs = |port: Option<usize>,
                st: &Option<Vec<Vec<String>>>|
     -> Option<(Vec<Vec<String>>, Encoding)> {
        match (port, st) {
            (Some(k), _) => Some(((0..n).map(|i| regs[k + i].clone()).collect(), ins[k].enc)),
            (None, Some(s)) => Some((s.clone(), p.state)),
            (None, None) => None,
        }
    };
    let lv = if p.kind.diffuse() {
        vecs(il, &l_state)
    } else {
        None
    };
    let hv = if p.kind.specular() {
        vecs(ih, &h_state)
    } else {
        None
    };
    let (t, tb, comp, fin) = (sh.t.clone(), sh.t_bits, sh.comp.clone(), sh.fin.clone());
    let be = ins[1].enc;
    let b: Vec<Fx> = (0..3)
        .map(|j| from_code(&mut sh.m, &regs[1][j], &be))
        .collect();
    let de = p.dot;
    let rom_name = format!("{top}_table");
    let mut cycle: Vec<Vec<Fx>> = vec![Vec::new(); 3];
    for j in 0..par {
        sh.m.comment(&format!("datapath {j}"));
        let slots: Vec<usize> = (0..iv as usize).map(|c| c * par + j).collect();
        let items: Vec<usize> = slots.iter().map(|&i| i.min(n - 1)).collect();
        // the intensity register's word for one vector set: clamp(B . V) cast into `dot`
        let intensity = |sh: &mut Shell, (v, e): &(Vec<Vec<String>>, Encoding)| -> String {
            let m = &mut sh.m;
            let prods: Vec<Fx> = (0..3)
                .map(|l| {
                    let names: Vec<String> = items.iter().map(|&i| v[i][l].clone()).collect();
                    let bits = m.select_bits(&t, &names, e.width());
                    let x = from_code(m, &bits, e);
                    mul(m, &b[l], &x)
                })
                .collect();
            let s = sum(m, &[&prods[0], &prods[1], &prods[2]]);
            clamp_code(m, &s, Some((0, 0)), Some((1, 0)), &de)
        };
        let mut f: Vec<Fx> = Vec::new();
        if let Some(lv) = &lv {
            let d = intensity(&mut sh, lv);
            f.push(from_code(&mut sh.m, &d, &de));
        }
        if let (Some(hv), Some((words, vb))) = (&hv, &table) {
            let d = intensity(&mut sh, hv);
            let ib = gen.map_or(8, |g| match g.spec() {
                SpecGen::Table { index_bits, .. } => index_bits,
                _ => unreachable!(),
            });
            let i = nearest_index(&mut sh.m, &d, &de, ib);
            let y = sh.rom(&rom_name, words, *vb, &i);
            let entry = Encoding::texel(Codec::UnitUnsigned, false, *vb as u8);
            f.push(from_code(&mut sh.m, &y, &entry));
        }
        let m = &mut sh.m;
        let refs: Vec<&Fx> = f.iter().collect();
        let f = sum(m, &refs);
        let valid = if slots.iter().any(|&i| i >= n) {
            let last = (n - 1 - j) / par;
            Some(m.uwire("valid", 1, &format!("{t} <= {tb}'d{last}")))
        } else {
            None
        };
        for c in 0..3 {
            let names: Vec<String> = items.iter().map(|&i| kc[i][c].clone()).collect();
            let kj = m.select_bits(&t, &names, p.color.width());
            let kv = from_code(m, &kj, &p.color);
            let mut term = mul(m, &f, &kv);
            if let Some(v) = &valid {
                term = gate(m, v, &term);
            }
            cycle[c].push(term);
        }
    }
    let ce = ins[0].enc;
    let m = &mut sh.m;
    let skip = skip_flag(m, p.selective, &ins, &regs, idx("enable"));
    for (c, terms) in cycle.iter().enumerate() {
        m.comment(&format!("channel {c}: accumulator, C_src, clamp, cast"));
        let refs: Vec<&Fx> = terms.iter().collect();
        let per = sum(m, &refs);
        let k = iv as i128;
        let (lo, hi) = (per.lo.min(0) * k, per.hi.max(0) * k);
        let acc_name = format!("acc_{c}");
        let w = super::verilog::signed_bits(lo, hi);
        let prev = m.swire("accin", w, &format!("({t} == {tb}'d0) ? 0 : {acc_name}"));
        let prev = Fx {
            name: prev,
            lo,
            hi,
            frac: per.frac,
            fac: per.fac.clone(),
        };
        let next = sum_in_range(m, &[&prev, &per], lo, hi);
        let acc = register(m, &acc_name, &comp, &next, lo, hi);
        let cv = from_code(m, &regs[0][c], &ce);
        let v = sum(m, &[&cv, &acc]);
        let mut code = clamp_code(m, &v, Some((0, 0)), Some((1, 0)), &p.out);
        if let Some(skip) = &skip {
            let pass = pass_code(m, &regs[0][c], &ce, &p.out);
            code = m.uwire("sel", p.out.width(), &format!("{skip} ? {pass} : {code}"));
        }
        m.stmt(format!(
            "always @(posedge clk) if ({fin}) {} <= {code};",
            out[c]
        ));
    }
    Ok(sh.finish())
}

/// The model's `skip`: the `enable` input is 0, or every lane of `B` is within one code of the
/// unperturbed `[0, 0, 1]`. `None` for `Selective::Off`.
fn skip_flag(
    m: &mut Module,
    sel: Selective,
    ins: &[crate::unit::PortSpec],
    regs: &[Vec<String>],
    enable: Option<usize>,
) -> Option<String> {
    let mut terms = Vec::new();
    if matches!(sel, Selective::Enable | Selective::UnperturbedAndEnable) {
        let e = &regs[enable?][0];
        terms.push(format!("({e} == 0)"));
    }
    if matches!(
        sel,
        Selective::Unperturbed | Selective::UnperturbedAndEnable
    ) {
        let be = ins[1].enc;
        let target = [0.0, 0.0, 1.0].map(|t| be.encode(t) as i128);
        let near: Vec<String> = (0..3)
            .map(|j| {
                let b = raw_word(m, &regs[1][j], &be.format);
                let (lo, hi) = (target[j] - 1, target[j] + 1);
                format!(
                    "(({} >= {}) && ({} <= {}))",
                    b.name,
                    lit(lo),
                    b.name,
                    lit(hi)
                )
            })
            .collect();
        terms.push(format!("({})", near.join(" && ")));
    }
    if terms.is_empty() {
        return None;
    }
    Some(m.uwire("skip", 1, &terms.join(" || ")))
}

/// The model's pass-through word of `C_src`: the word itself when `C_src` and the output
/// share an encoding and it decodes into [0, 1], else `C_src` clamped and cast.
fn pass_code(m: &mut Module, bits: &str, ce: &Encoding, out: &Encoding) -> String {
    let v = from_code(m, bits, ce);
    let cast = clamp_code(m, &v, Some((0, 0)), Some((1, 0)), out);
    if ce != out {
        return cast;
    }
    // the codes that decode into [0, 1]: decode is monotone, find the ends by bisection
    let f = ce.format;
    let first = |pred: &dyn Fn(i64) -> bool| {
        let (mut lo, mut hi) = (f.min_raw(), f.max_raw() + 1);
        while lo < hi {
            let mid = lo + (hi - lo) / 2;
            if pred(mid) {
                hi = mid;
            } else {
                lo = mid + 1;
            }
        }
        lo
    };
    let lo = first(&|c| ce.decode(c) >= 0.0);
    let hi = first(&|c| ce.decode(c) > 1.0) - 1;
    let r = raw_word(m, bits, &f);
    let cond = format!(
        "({} >= {}) && ({} <= {})",
        r.name,
        lit(lo as i128),
        r.name,
        lit(hi as i128)
    );
    m.uwire("pass", out.width(), &format!("({cond}) ? {bits} : {cast}"))
}
