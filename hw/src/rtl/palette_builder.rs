//! Verilog of the per-frame colour-table builder ([`crate::units::PaletteBuilder`], Tarini et
//! al. §5.1 `f(n) -> c`; §6 one function per material interval; §7.1 the split form), inside
//! the quantized normal maps unit ([`super::quantized`]): it shades every entry of the normal
//! table and writes the colour table, one dot product per clock.
//!
//! Functions with a generator: `Lambert`, `Specular` (Blinn-Phong) and `SpecularSplit`, any
//! number of lights and materials, a `Table` power generator, one pipeline
//! (`entries_per_clock` 1). Each material's entry takes `cycles_per_entry` slots (the model's
//! schedule): one diffuse slot `N.L_l` per light, then (specular) one `N.H_l` per light.
//!
//! * Per slot the host loads the vector (`L_l` or `H_l`, `vector` codes) and one coefficient
//!   per lane: the exact product of the two entry words that multiply the slot's intensity
//!   (`diffuse_i x colour_l,i`, `specular_i x colour_l,i`; the split form's alpha `diffuse x
//!   mean(colour_l)`), so that one multiplier per lane forms `coefficient x intensity`: the
//!   model's `a + d (sum_l c_l k_l)` is `a + sum_l (d c_l) k_l`, the same exact value.
//! * Pipeline: slot issue (the normal table read, address = entry), the dot product of the
//!   normal word and the slot's vector, clamp to [0, 1] and cast to `intensity` (registered;
//!   the power table is read at its nearest index in the same clock), the lane products
//!   accumulated per kind (diffuse intensities and power-table words carry different
//!   bit-replication factors: two accumulators where a lane has both), and after an entry's
//!   last slot the sum `ambient + diffuse + specular`, cast to the entry encoding, written
//!   into the colour table. Alpha is the constant `1` except in the split form.
//! * Materials: the interval bounds are constants of the generated unit (the index texture
//!   and the normal table are built together); the normal table and the power tables (one per
//!   distinct table: a material with another shininess has its own) are memories, loaded by
//!   the host (black boxes in synthesis, as the gate model prices them).
//!
//! Clocks per frame: `T + 4` for `T` slots in all (the model's builder cycles; the model
//! counts the colour-table load, `entries / load_width`, as a pass of its own, where this
//! datapath writes each entry as it is built).

use super::fixed::{
    clamp, constant, from_code, gate, mul, raw_word, scale, select, sum, sum_in_range, to_code, Fx,
};
use super::power::nearest_index;
use super::verilog::{signed_bits, unsigned_bits, Module};
use super::Shell;
use crate::format::{Codec, Encoding, Format};
use crate::units::palette_builder::{Light, LightingFn};
use crate::units::{PaletteBuilder, SpecGen};

/// The builder's write port into the colour table and its clocks per frame.
pub(crate) struct Writes {
    pub we: String,
    /// The entry address, `addr_bits` wide.
    pub addr: String,
    /// The entry word, lanes packed from bit 0 (`4 x entry` bits).
    pub data: String,
    pub cycles: u32,
}

#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Diffuse,
    Specular,
}

/// One slot of a material's schedule: its kind, vector codes, one coefficient per lane
/// (`None`: structurally zero) and the power table it reads.
struct Slot {
    kind: Kind,
    vector: [i64; 3],
    coef: [Option<i128>; 4],
    table: usize,
    first: bool,
    last: bool,
}

/// The raw integer [`from_code`] reads for `code` of `enc`.
fn read_raw(enc: &Encoding, code: i64) -> i128 {
    match enc.codec {
        Codec::UnitSymmetric => 2 * code as i128 + 1,
        _ => code as i128,
    }
}

/// Fraction bits and factors of a word of `enc` read into the datapath.
fn reading(enc: &Encoding) -> (u32, Vec<u32>) {
    let mut scratch = Module::new("scratch");
    let x = from_code(&mut scratch, "w", enc);
    (x.frac, x.fac)
}

/// The range of [`read_raw`] over every code of `enc`.
fn raw_range(enc: &Encoding) -> (i128, i128) {
    let f = enc.format;
    (read_raw(enc, f.min_raw()), read_raw(enc, f.max_raw()))
}

fn mean(c: [f64; 3]) -> f64 {
    (c[0] + c[1] + c[2]) / 3.0
}

/// The schedule of every material: slots in issue order, and per material its ambient codes
/// (per lane; `None` zero) and its first slot.
struct Schedule {
    slots: Vec<Slot>,
    ambient: Vec<[Option<i64>; 4]>,
    base: Vec<usize>,
    tables: Vec<Vec<i64>>,
    split: bool,
}

fn schedule(b: &PaletteBuilder) -> Result<Schedule, String> {
    let e = b.formats().entry;
    let w = |x: f64| e.encode(x);
    let r = |x: f64| read_raw(&e, w(x));
    let mut s = Schedule {
        slots: Vec::new(),
        ambient: Vec::new(),
        base: Vec::new(),
        tables: Vec::new(),
        split: false,
    };
    for (k, ((_, f), gen)) in b.materials().iter().zip(b.generators()).enumerate() {
        let mut table = 0;
        if let Some(g) = gen {
            if !matches!(g.spec(), SpecGen::Table { .. }) {
                return Err(format!(
                    "material {k}: power generator {:?}: the generator builds the Table form only",
                    g.spec()
                ));
            }
            table = match s.tables.iter().position(|t| t == g.table()) {
                Some(i) => i,
                None => {
                    s.tables.push(g.table().to_vec());
                    s.tables.len() - 1
                }
            };
        }
        let mut slots = Vec::new();
        let diffuse_slot = |l: &Light, coef: [Option<i128>; 4]| Slot {
            kind: Kind::Diffuse,
            vector: b.vector_codes(l.0),
            coef,
            table,
            first: false,
            last: false,
        };
        let specular_slot = |l: &Light, view: [f64; 3], coef: [Option<i128>; 4]| Slot {
            kind: Kind::Specular,
            vector: b.halfway_codes(l.0, view),
            coef,
            table,
            first: false,
            last: false,
        };
        let rgb = |a: [f64; 3], c: [f64; 3]| -> [Option<i128>; 4] {
            [
                Some(r(a[0]) * r(c[0])),
                Some(r(a[1]) * r(c[1])),
                Some(r(a[2]) * r(c[2])),
                None,
            ]
        };
        let amb3 = |a: &[f64; 3]| [Some(w(a[0])), Some(w(a[1])), Some(w(a[2])), None];
        // the diffuse slots per function; the specular slots (view, specular colour) after
        let (ambient, spec) = match f {
            LightingFn::Lambert {
                ambient,
                diffuse,
                lights,
            } => {
                slots.extend(lights.iter().map(|l| diffuse_slot(l, rgb(*diffuse, l.1))));
                (amb3(ambient), None)
            }
            LightingFn::Specular {
                ambient,
                diffuse,
                specular,
                view,
                lights,
                ..
            } => {
                slots.extend(lights.iter().map(|l| diffuse_slot(l, rgb(*diffuse, l.1))));
                (amb3(ambient), Some((*view, *specular, lights)))
            }
            LightingFn::SpecularSplit {
                ambient,
                diffuse,
                specular,
                view,
                lights,
                ..
            } => {
                s.split = true;
                slots.extend(lights.iter().map(|l| {
                    diffuse_slot(l, [None, None, None, Some(r(*diffuse) * r(mean(l.1)))])
                }));
                (
                    [None, None, None, Some(w(*ambient))],
                    Some((*view, *specular, lights)),
                )
            }
            other => {
                let name = format!("{other:?}");
                let name = name.split([' ', '{']).next().unwrap_or("").to_string();
                return Err(format!(
                    "material {k}: the {name} function has no generator yet (Lambert, Specular \
                     and the split form have)"
                ));
            }
        };
        if let Some((view, specular, lights)) = spec {
            slots.extend(
                lights
                    .iter()
                    .map(|l| specular_slot(l, view, rgb(specular, l.1))),
            );
        }
        if slots.is_empty() {
            // no lights: one slot of nothing (the model's one clock per entry)
            slots.push(Slot {
                kind: Kind::Diffuse,
                vector: [0; 3],
                coef: [None; 4],
                table,
                first: false,
                last: false,
            });
        }
        slots[0].first = true;
        slots.last_mut().unwrap().last = true;
        s.base.push(s.slots.len());
        s.slots.extend(slots);
        s.ambient.push(ambient);
    }
    if s.split
        && b.materials()
            .iter()
            .any(|(_, f)| !matches!(f, LightingFn::SpecularSplit { .. }))
    {
        return Err("the split form and another function in one table: expected one form".into());
    }
    Ok(s)
}

/// `1` when the unsigned `x` equals one of `values`, as an expression.
fn any_eq(x: &str, bits: u32, values: impl Iterator<Item = usize>) -> String {
    let terms: Vec<String> = values.map(|v| format!("({x} == {bits}'d{v})")).collect();
    if terms.is_empty() {
        "1'b0".into()
    } else {
        terms.join(" || ")
    }
}

/// The material of entry `e` (`eb` bits): the count of interval starts at or below it.
fn material_of(m: &mut Module, b: &PaletteBuilder, e: &str, eb: u32) -> String {
    let mats = b.materials();
    let mb = unsigned_bits(mats.len().saturating_sub(1) as u128);
    if mats.len() == 1 {
        return m.uwire("mat", 1, "1'b0");
    }
    let terms: Vec<String> = mats[1..]
        .iter()
        .map(|(r, _)| {
            let c = format!("({e} >= {eb}'d{})", r.start);
            if mb > 1 {
                format!("{{{}'d0, {c}}}", mb - 1)
            } else {
                c
            }
        })
        .collect();
    m.uwire("mat", mb, &terms.join(" + "))
}

/// The builder in `sh`: its registers, memories and pipeline; returns its write port into
/// the colour table (addresses of `addr_bits`).
pub(crate) fn builder(
    sh: &mut Shell,
    b: &PaletteBuilder,
    addr_bits: u32,
) -> Result<Writes, String> {
    if b.entries_per_clock() != 1 {
        return Err(format!(
            "entries_per_clock {}: the generator builds one entry at a time",
            b.entries_per_clock()
        ));
    }
    let s = schedule(b)?;
    let f = *b.formats();
    let n = b.entries();
    let total = s.slots.len();
    let cycles = b.cycles_per_frame() as u32 + 4;
    let (frame, done) = sh.frame(cycles);
    // host-loaded registers: each slot's vector and coefficients, each material's ambient
    let (er_lo, er_hi) = raw_range(&f.entry);
    let coef_lo = [er_lo * er_lo, er_lo * er_hi, er_hi * er_hi]
        .into_iter()
        .min()
        .unwrap();
    let coef_hi = [er_lo * er_lo, er_lo * er_hi, er_hi * er_hi]
        .into_iter()
        .max()
        .unwrap();
    // the coefficient registers: unsigned words when no product can be negative
    let coef_fmt = if coef_lo >= 0 {
        Format::u(unsigned_bits(coef_hi as u128) as u8, 0)
    } else {
        Format::s(signed_bits(coef_lo, coef_hi) as u8, 0)
    };
    let cw = coef_fmt.width as u32;
    let wv = f.vector.width();
    let mut vregs = Vec::new();
    let mut cregs: Vec<[Option<String>; 4]> = Vec::new();
    for (k, sl) in s.slots.iter().enumerate() {
        let v: Vec<String> = (0..3)
            .map(|j| sh.config_raw(&format!("slot {k} vector {j}"), wv, sl.vector[j]))
            .collect();
        let word = sh.m.uwire(
            "b_vec",
            3 * wv,
            &format!("{{{}, {}, {}}}", v[2], v[1], v[0]),
        );
        vregs.push(word);
        cregs.push(std::array::from_fn(|j| {
            sl.coef[j].map(|c| sh.config_raw(&format!("slot {k} coefficient {j}"), cw, c as i64))
        }));
    }
    let mut aregs: Vec<[Option<String>; 4]> = Vec::new();
    for (k, a) in s.ambient.iter().enumerate() {
        aregs.push(std::array::from_fn(|j| {
            a[j].map(|c| sh.config_raw(&format!("material {k} ambient {j}"), f.entry.width(), c))
        }));
    }
    let eb = unsigned_bits(n.saturating_sub(1) as u128);
    let fb = unsigned_bits(total.saturating_sub(1) as u128);
    let m = &mut sh.m;
    m.comment("builder: slot issue");
    let busy = m.reg("b_busy", 1);
    let e0 = m.reg("b_e0", eb);
    let f0 = m.reg("b_f0", fb);
    let last0 = m.uwire(
        "b_last",
        1,
        &any_eq(
            &f0,
            fb,
            s.slots
                .iter()
                .enumerate()
                .filter(|(_, x)| x.last)
                .map(|(i, _)| i),
        ),
    );
    let e_next = m.uwire("b_enext", eb, &format!("{e0} + {eb}'d1"));
    let mat_next = material_of(m, b, &e_next, eb);
    let bases: Vec<String> = s.base.iter().map(|&x| format!("{fb}'d{x}")).collect();
    let base_next = m.select_bits(&mat_next, &bases, fb);
    m.stmt(format!(
        "always @(posedge clk) begin\n    if (rst) {busy} <= 1'b0;\n    else if ({frame}) begin\n        \
         {busy} <= 1'b1; {e0} <= {eb}'d0; {f0} <= {fb}'d0;\n    end else if ({busy}) begin\n        \
         if ({last0}) begin\n            if ({e0} == {eb}'d{}) {busy} <= 1'b0;\n            \
         {e0} <= {e_next}; {f0} <= {base_next};\n        end else {f0} <= {f0} + {fb}'d1;\n    end\nend",
        n - 1
    ));
    // the normal table: address e0, the word one clock later (stage 1)
    let wn = f.normal.width();
    let normals: Vec<u128> = (0..n)
        .map(|k| {
            let c = b.normal_codes(k);
            (0..3).fold(0u128, |acc, j| {
                acc | (f.normal.format.bits(c[j]) as u128) << (j as u32 * wn)
            })
        })
        .collect();
    let nword = sh
        .memory("normals", normals, 3 * wn, &[(e0.clone(), eb)], 1)
        .remove(0);
    let m = &mut sh.m;
    m.comment("builder: stage 1, the dot product and the intensity");
    let v1 = m.reg("b_v1", 1);
    let e1 = m.reg("b_e1", eb);
    let f1 = m.reg("b_f1", fb);
    m.stmt(format!(
        "always @(posedge clk) begin\n    {v1} <= {busy} && !rst;\n    {e1} <= {e0};\n    {f1} <= {f0};\nend"
    ));
    let vsel = m.select_bits(&f1, &vregs, 3 * wv);
    let mut dot_terms = Vec::new();
    for j in 0..3u32 {
        let nb = m.uwire(
            "b_n",
            wn,
            &format!("{nword}[{}:{}]", (j + 1) * wn - 1, j * wn),
        );
        let vb = m.uwire(
            "b_v",
            wv,
            &format!("{vsel}[{}:{}]", (j + 1) * wv - 1, j * wv),
        );
        let nx = from_code(m, &nb, &f.normal);
        let vx = from_code(m, &vb, &f.vector);
        dot_terms.push(mul(m, &nx, &vx));
    }
    let dot = sum(m, &dot_terms.iter().collect::<Vec<_>>());
    let sat = clamp(m, &dot, Some((0, 0)), Some((1, 0)));
    let wi = f.intensity.width();
    let ik1 = to_code(m, &sat, &f.intensity);
    let pw_addr = match f.power {
        SpecGen::Table { index_bits, .. } if !s.tables.is_empty() => {
            Some((nearest_index(m, &ik1, &f.intensity, index_bits), index_bits))
        }
        _ => None,
    };
    let value_bits = match f.power {
        SpecGen::Table { value_bits, .. } => value_bits,
        _ => 1,
    };
    let mut power = Vec::new();
    if let Some((addr, ib)) = pw_addr {
        for (t, words) in s.tables.iter().enumerate() {
            let words: Vec<u128> = words.iter().map(|&w| w as u128).collect();
            let d = sh.memory(
                &format!("power{t}"),
                words,
                value_bits,
                &[(addr.clone(), ib)],
                1,
            );
            power.push(d[0].clone());
        }
    }
    let m = &mut sh.m;
    m.comment("builder: stage 2, the lane products and accumulators");
    let v2 = m.reg("b_v2", 1);
    let e2 = m.reg("b_e2", eb);
    let f2 = m.reg("b_f2", fb);
    let ik2 = m.reg("b_ik2", wi);
    m.stmt(format!(
        "always @(posedge clk) begin\n    {v2} <= {v1} && !rst;\n    {e2} <= {e1};\n    {f2} <= {f1};\n    {ik2} <= {ik1};\nend"
    ));
    let slot_flag = |m: &mut Module, hint: &str, pick: &dyn Fn(&Slot) -> bool| {
        let e = any_eq(
            &f2,
            fb,
            s.slots
                .iter()
                .enumerate()
                .filter(|(_, x)| pick(x))
                .map(|(i, _)| i),
        );
        m.uwire(hint, 1, &e)
    };
    let first2 = slot_flag(m, "b_first", &|x| x.first);
    let last2 = slot_flag(m, "b_last2", &|x| x.last);
    let spec2 = slot_flag(m, "b_spec", &|x| x.kind == Kind::Specular);
    // the slot's value as a raw integer: the intensity code or the power-table word
    let ik_fx = from_code(m, &ik2, &f.intensity);
    let ik_raw = Fx {
        frac: 0,
        fac: Vec::new(),
        ..ik_fx
    };
    let x_raw = if power.is_empty() {
        ik_raw
    } else {
        let pw = if power.len() == 1 {
            power[0].clone()
        } else {
            let tb = unsigned_bits(s.tables.len().saturating_sub(1) as u128);
            let ids: Vec<String> = s
                .slots
                .iter()
                .map(|x| format!("{tb}'d{}", x.table))
                .collect();
            let tsel = m.select_bits(&f2, &ids, tb);
            m.select_bits(&tsel, &power, value_bits)
        };
        let pe = Encoding::texel(Codec::UnitUnsigned, false, value_bits as u8);
        let p_fx = from_code(m, &pw, &pe);
        let p_raw = Fx {
            frac: 0,
            fac: Vec::new(),
            ..p_fx
        };
        select(m, &spec2, &[ik_raw, p_raw])
    };
    let (fe, face) = reading(&f.entry);
    let (fi, faci) = reading(&f.intensity);
    let pe = Encoding::texel(Codec::UnitUnsigned, false, value_bits as u8);
    let (fp, facp) = reading(&pe);
    let lanes = if s.split { 4 } else { 3 };
    let count = |kind: Kind, j: usize| -> (usize, bool) {
        // most slots of `kind` with a coefficient in lane j in one material
        let mut most = 0;
        for (k, &start) in s.base.iter().enumerate() {
            let end = s.base.get(k + 1).copied().unwrap_or(total);
            let c = s.slots[start..end]
                .iter()
                .filter(|x| x.kind == kind && x.coef[j].is_some())
                .count();
            most = most.max(c);
        }
        (most, most > 0)
    };
    let v2e = v2.clone();
    let mut accs: Vec<Vec<Fx>> = Vec::new();
    for j in 0..lanes {
        m.comment(&format!("builder: lane {j}"));
        let coefs: Vec<Fx> = cregs
            .iter()
            .map(|c| match &c[j] {
                Some(r) => raw_word(m, r, &coef_fmt),
                None => constant(0, 0),
            })
            .collect();
        let coef = select(m, &f2, &coefs);
        let prod = mul(m, &coef, &x_raw);
        // the kinds of slot with a coefficient in this lane, and the most slots of one
        // material that add to it
        let kinds: Vec<(u32, &Vec<u32>)> =
            [(Kind::Diffuse, fi, &faci), (Kind::Specular, fp, &facp)]
                .into_iter()
                .filter(|(k, _, _)| count(*k, j).1)
                .map(|(_, fr, fac)| (fr, fac))
                .collect();
        let most = count(Kind::Diffuse, j).0 + count(Kind::Specular, j).0;
        if kinds.is_empty() {
            accs.push(Vec::new());
            continue;
        }
        // one accumulator: with both kinds, each product is first brought to the common
        // reading (its own bit replication applied, aligned to the finer fraction)
        let (term, frac, fac) = if kinds.len() == 1 {
            let (fr, fac) = kinds[0];
            (
                prod,
                2 * fe + fr,
                [face.clone(), face.clone(), fac.clone()].concat(),
            )
        } else {
            let top = fi.max(fp);
            let pd = scale(
                m,
                &Fx {
                    fac: faci.clone(),
                    ..prod.clone()
                },
                1 << (top - fi),
            );
            let ps = scale(
                m,
                &Fx {
                    fac: facp.clone(),
                    ..prod.clone()
                },
                1 << (top - fp),
            );
            (
                select(m, &spec2, &[pd, ps]),
                2 * fe + top,
                [face.clone(), face.clone()].concat(),
            )
        };
        let (lo, hi) = (term.lo.min(0) * most as i128, term.hi.max(0) * most as i128);
        let name = format!("b_acc_{j}");
        m.sreg(&name, signed_bits(lo, hi));
        let me = Fx {
            name: name.clone(),
            lo,
            hi,
            frac: 0,
            fac: Vec::new(),
        };
        let keep = m.uwire("b_keep", 1, &format!("!{first2}"));
        let old = gate(m, &keep, &me);
        let next = sum_in_range(m, &[&old, &term], lo, hi);
        m.stmt(format!(
            "always @(posedge clk) if ({v2e}) {name} <= {};",
            next.name
        ));
        let mut fac = fac;
        fac.sort_unstable();
        accs.push(vec![Fx { frac, fac, ..me }]);
    }
    m.comment("builder: stage 3, the entry word into the colour table");
    let w3 = m.reg("b_w3", 1);
    let e3 = m.reg("b_e3", eb);
    m.stmt(format!(
        "always @(posedge clk) begin\n    {w3} <= {v2} && {last2} && !rst;\n    {e3} <= {e2};\nend"
    ));
    let mat3 = material_of(m, b, &e3, eb);
    let we_w = f.entry.width();
    let mut lane_codes = Vec::new();
    for j in 0..4 {
        if j >= lanes {
            let one = f.entry.encode(1.0);
            lane_codes.push(format!("{we_w}'d{}", f.entry.format.bits(one)));
            continue;
        }
        let mut terms = accs[j].clone();
        let amb: Vec<Fx> = aregs
            .iter()
            .map(|a| match &a[j] {
                Some(r) => from_code(m, r, &f.entry),
                None => Fx {
                    fac: face.clone(),
                    ..constant(0, fe)
                },
            })
            .collect();
        let amb = select(m, &mat3, &amb);
        if amb.lo != 0 || amb.hi != 0 {
            terms.push(amb);
        }
        let code = if terms.is_empty() {
            to_code(m, &constant(0, 0), &f.entry)
        } else {
            let total = sum(m, &terms.iter().collect::<Vec<_>>());
            to_code(m, &total, &f.entry)
        };
        lane_codes.push(code);
    }
    let data = m.uwire(
        "b_entry",
        4 * we_w,
        &format!(
            "{{{}, {}, {}, {}}}",
            lane_codes[3], lane_codes[2], lane_codes[1], lane_codes[0]
        ),
    );
    let addr = if eb < addr_bits {
        m.uwire(
            "b_addr",
            addr_bits,
            &format!("{{{}'d0, {e3}}}", addr_bits - eb),
        )
    } else {
        e3.clone()
    };
    m.stmt(format!(
        "always @(posedge clk) begin\n    if (rst || {frame}) {done} <= 1'b0;\n    \
         else if ({w3} && {e3} == {eb}'d{}) {done} <= 1'b1;\nend",
        n - 1
    ));
    Ok(Writes {
        we: w3,
        addr,
        data,
        cycles,
    })
}
