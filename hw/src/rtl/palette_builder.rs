//! Verilog of the per-frame colour-table builder ([`crate::units::PaletteBuilder`], Tarini et
//! al. §5.1 `f(n) -> c`; §6 one function per material interval; §7.1 the split form), inside
//! the quantized normal maps unit ([`super::quantized`]): it shades every entry of the normal
//! table and writes the colour table, one dot product per clock.
//!
//! Functions with a generator: `Lambert`, `Specular` (Blinn-Phong), `SpecularSplit`,
//! `Cartoon`, `DoubledAnglePhong` and `Chrome`, any number of lights and materials (one table
//! may mix them, but the split form), a `Table` power generator, one pipeline
//! (`entries_per_clock` 1). Each material's entry takes `cycles_per_entry` slots (the model's
//! schedule):
//!
//! | function | slots |
//! |---|---|
//! | Lambert | `N.L_l` per light (one empty slot without lights) |
//! | Specular, split | `N.L_l` per light, then `N.H_l` per light |
//! | Cartoon | `N.L_l` per light into the cartoon sum, then the band slot |
//! | DoubledAnglePhong | `N.L`; `N.V`, forming `R.V`; `2 (R.V)^2 - 1` and the power word |
//! | Chrome | `N.V`; `N.up`, forming `R.up` and `t = (1 + R.up) / 2` |
//!
//! `EnvMap` has none: the model's sphere-map address is computed in f64 (the eye frame's
//! axes, `m = 2 sqrt(...)`, the divisions, the floor); an integer form that keeps the bundled
//! config's texels needs the axes to about 30 fraction bits and an exact floor of a quotient
//! by a square root (`docs/rtl.md`).
//!
//! * Per slot the host loads the vector (`L_l`, `H_l`, `V` or `up`, `vector` codes) and one
//!   coefficient per lane: the exact product of the two entry words that multiply the slot's
//!   intensity (`diffuse_i x colour_l,i`, `specular_i x colour_l,i`; the split form's alpha
//!   `diffuse x mean(colour_l)`), so that one multiplier per lane forms `coefficient x
//!   intensity`: the model's `a + d (sum_l c_l k_l)` is `a + sum_l (d c_l) k_l`, the same
//!   exact value; chrome's coefficient is the difference of two entry words, `sky_i -
//!   ground_i`, and its "ambient" the ground word (`g + (s - g) t`). A reflection slot also
//!   has the host constant `L.V` or `V.up` (the exact product of two vector registers).
//! * Pipeline: slot issue (the normal table read, address = entry), the dot product of the
//!   normal word and the slot's vector, clamp to [0, 1] and cast to `intensity` (registered;
//!   the power table is read at its nearest index in the same clock), the lane products
//!   accumulated (products of different readings, the intensity's and the power word's bit
//!   replications, a one- or two-word coefficient, first brought to one reading), and after
//!   an entry's last slot the sum with the ambient word, cast to the entry encoding, written
//!   into the colour table. Alpha is the constant `1` except in the split form.
//! * The other intensity sources, selected per slot before the intensity register: the
//!   cartoon sum (`sum_l clamp(N.L_l, 0, 1)`, a register accumulated over the light slots,
//!   then clamped and cast: the model's order); the reflections `2 (N.a)(N.b) - a.b` (the
//!   previous slot's dot product is registered every clock), chrome's `(1 + R.up) / 2`
//!   clamped and cast, and doubled-angle Phong's `R.V`, clamped to [0, 1] and registered,
//!   squared (`fixed::square`), `2 x^2 - 1` clamped and cast in the next slot. The clamp of
//!   `R.V` before the square is exact: `R.V <= 0` gives the intensity 0 and the power
//!   table's first word, 0 (the generator checks it), where the model takes 0; `R.V >= 1`
//!   gives `2 - 1 = 1`, where the model's `2 (R.V)^2 - 1 >= 1` is clamped to 1; so the square
//!   is as wide as `R.V`'s fraction (40 bits at s1.10), not its range.
//! * Cartoon: the band `min(floor(bands x), bands - 1)` of the intensity word `x` (stage 2,
//!   `x bands` by its digits), registered, selects the material's band word per lane (host
//!   registers, [`crate::units::palette_builder::band_codes`]: the words the host computes).
//! * Materials: the interval bounds are constants of the generated unit (the index texture
//!   and the normal table are built together); the normal table and the power tables (one per
//!   distinct table: a material with another shininess has its own) are memories, loaded by
//!   the host (black boxes in synthesis, as the gate model prices them).
//!
//! Clocks per frame: `T + 4` for `T` slots in all (the model's builder cycles; the model
//! counts the colour-table load, `entries / load_width`, as a pass of its own, where this
//! datapath writes each entry as it is built).

use super::fixed::{
    add, clamp, clamp_code, constant, extra, from_code, gate, mul, overflow, raw_word, scale,
    select, shift_round, square, sub, sum, sum_in_range, to_code, Fx,
};
use super::power::nearest_index;
use super::verilog::{signed_bits, unsigned_bits, Module};
use super::Shell;
use crate::format::{Codec, Encoding, Format, Overflow, Quant};
use crate::units::palette_builder::{band_codes, eye_axes, Light, LightingFn};
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

#[derive(Clone, Copy, PartialEq, Debug)]
enum Kind {
    Diffuse,
    Specular,
}

/// Where a slot's intensity word comes from (stage 1, clamped to [0, 1] and cast).
#[derive(Clone, Copy, PartialEq, Debug)]
enum Src {
    /// The slot's dot product `N . vector`.
    Dot,
    /// Zero (a cartoon function without lights).
    Zero,
    /// The cartoon sum `sum_l clamp(N . L_l, 0, 1)`, accumulated over the entry's light slots.
    Cartoon,
    /// Chrome: `(1 + R.up) / 2`, `R.up = 2 (N.V)(N.up) - V.up` (the previous slot's dot
    /// product times this slot's).
    Chrome,
    /// Doubled-angle Phong: `2 (R.V)^2 - 1` for `R.V = 2 (N.L)(N.V) - L.V > 0`, else 0 (`R.V`
    /// formed in the previous slot, from its dot product and the one before, and registered).
    Doubled,
}

/// The reading of a slot's coefficient: the exact product of two entry words, or one entry
/// word (chrome's `sky - ground`).
#[derive(Clone, Copy, PartialEq, Debug)]
enum Form {
    Product,
    Word,
}

/// One slot of a material's schedule: its kind, vector codes (`None`: no vector, the dot
/// product unused), one coefficient per lane (`None`: structurally zero) and the power table
/// it reads.
pub(crate) struct Slot {
    kind: Kind,
    src: Src,
    vector: Option<[i64; 3]>,
    coef: [Option<i128>; 4],
    form: Form,
    /// The host constant of a reflection (`L.V`, `V.up`: the raw product of two vector
    /// readings) for the `Chrome` and `Doubled` sources.
    konst: Option<i128>,
    /// A cartoon light slot: its clamped dot product adds to the cartoon sum.
    csum: bool,
    /// A cartoon band slot: the band of its intensity word (`bands`) is taken in stage 2.
    bands: Option<u32>,
    /// An `EnvMap` slot: 0 the view's `N.V`, 1 to 3 the eye frame's axis `a` forming `R.a`
    /// ([`super::palette_envmap`]).
    pub(crate) env: Option<u8>,
    table: usize,
    first: bool,
    last: bool,
}

impl Slot {
    fn new(kind: Kind, src: Src, vector: Option<[i64; 3]>, table: usize) -> Slot {
        Slot {
            kind,
            src,
            vector,
            coef: [None; 4],
            form: Form::Product,
            konst: None,
            csum: false,
            bands: None,
            env: None,
            table,
            first: false,
            last: false,
        }
    }
    fn with_coef(mut self, coef: [Option<i128>; 4], form: Form) -> Slot {
        self.coef = coef;
        self.form = form;
        self
    }
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
/// (per lane; `None` zero), its first slot and (cartoon) its band words.
struct Schedule {
    slots: Vec<Slot>,
    ambient: Vec<[Option<i64>; 4]>,
    base: Vec<usize>,
    tables: Vec<Vec<i64>>,
    /// Per material: the cartoon band words (RGB entry codes), `None` for other functions.
    bands: Vec<Option<Vec<[i64; 3]>>>,
    split: bool,
    /// Every material is `EnvMap` ([`super::palette_envmap`]).
    env: bool,
}

fn schedule(b: &PaletteBuilder) -> Result<Schedule, String> {
    let e = b.formats().entry;
    let ve = b.formats().vector;
    let w = |x: f64| e.encode(x);
    let r = |x: f64| read_raw(&e, w(x));
    // the exact product of two host vectors' readings: `L.V`, `V.up`
    let vdot = |a: [i64; 3], c: [i64; 3]| -> i128 {
        (0..3)
            .map(|j| read_raw(&ve, a[j]) * read_raw(&ve, c[j]))
            .sum()
    };
    let mut s = Schedule {
        slots: Vec::new(),
        ambient: Vec::new(),
        base: Vec::new(),
        tables: Vec::new(),
        bands: Vec::new(),
        split: false,
        env: false,
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
        let diffuse_slot = |l: &Light, coef: [Option<i128>; 4]| {
            Slot::new(Kind::Diffuse, Src::Dot, Some(b.vector_codes(l.0)), table)
                .with_coef(coef, Form::Product)
        };
        let specular_slot = |l: &Light, view: [f64; 3], coef: [Option<i128>; 4]| {
            Slot::new(
                Kind::Specular,
                Src::Dot,
                Some(b.halfway_codes(l.0, view)),
                table,
            )
            .with_coef(coef, Form::Product)
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
        let mut band_words = None;
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
            LightingFn::Cartoon {
                bands,
                ambient,
                diffuse,
                lights,
            } => {
                // one slot per light into the cartoon sum, then the band slot
                slots.extend(lights.iter().map(|l| {
                    let mut x =
                        Slot::new(Kind::Diffuse, Src::Dot, Some(b.vector_codes(l.0)), table);
                    x.csum = true;
                    x
                }));
                let src = if lights.is_empty() {
                    Src::Zero
                } else {
                    Src::Cartoon
                };
                let mut band = Slot::new(Kind::Diffuse, src, None, table);
                band.bands = Some(*bands);
                slots.push(band);
                band_words = Some(band_codes(&e, *ambient, *diffuse, *bands));
                ([None; 4], None)
            }
            LightingFn::DoubledAnglePhong {
                ambient,
                diffuse,
                specular,
                view,
                light,
                ..
            } => {
                // N.L (the diffuse term); N.V, with R.V = 2 (N.L)(N.V) - L.V registered;
                // then 2 (R.V)^2 - 1 and the power word (the model's three clocks)
                let (lq, vq) = (b.vector_codes(light.0), b.vector_codes(*view));
                let tab = &s.tables[table];
                if tab.first().copied().unwrap_or(0) != 0 {
                    return Err(format!(
                        "material {k}: the power table's first word is {}: the doubled-angle \
                         generator reads it for R.V <= 0 (expected 0, a shininess above 0)",
                        tab[0]
                    ));
                }
                slots.push(diffuse_slot(light, rgb(*diffuse, light.1)));
                let mut x = Slot::new(Kind::Diffuse, Src::Dot, Some(vq), table);
                x.konst = Some(vdot(lq, vq));
                slots.push(x);
                slots.push(
                    Slot::new(Kind::Specular, Src::Doubled, None, table)
                        .with_coef(rgb(*specular, light.1), Form::Product),
                );
                (amb3(ambient), None)
            }
            LightingFn::Chrome {
                view,
                up,
                sky,
                ground,
            } => {
                // N.V, then N.up with R.up and t = (1 + R.up) / 2 in its stage: the lane
                // adds (sky - ground) t to the ground word
                let (vq, uq) = (b.vector_codes(*view), b.vector_codes(*up));
                slots.push(Slot::new(Kind::Diffuse, Src::Dot, Some(vq), table));
                let d = |i: usize| Some(r(sky[i]) - r(ground[i]));
                let mut x = Slot::new(Kind::Diffuse, Src::Chrome, Some(uq), table)
                    .with_coef([d(0), d(1), d(2), None], Form::Word);
                x.konst = Some(vdot(vq, uq));
                slots.push(x);
                (amb3(ground), None)
            }
            LightingFn::EnvMap { view, up, .. } => {
                // N.V, then per axis a of the eye frame N.a with R.a = 2 (N.V)(N.a) - V.a
                let vq = b.vector_codes(*view);
                let mut x = Slot::new(Kind::Diffuse, Src::Dot, Some(vq), table);
                x.env = Some(0);
                slots.push(x);
                for (a, axis) in eye_axes(*view, *up).into_iter().enumerate() {
                    let aq = b.vector_codes(axis);
                    let mut x = Slot::new(Kind::Diffuse, Src::Dot, Some(aq), table);
                    x.konst = Some(vdot(vq, aq));
                    x.env = Some(a as u8 + 1);
                    slots.push(x);
                }
                s.env = true;
                ([None; 4], None)
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
            slots.push(Slot::new(Kind::Diffuse, Src::Dot, None, table));
        }
        debug_assert_eq!(slots.len() as u64, f.cycles_per_entry());
        slots[0].first = true;
        slots.last_mut().unwrap().last = true;
        s.base.push(s.slots.len());
        s.slots.extend(slots);
        s.ambient.push(ambient);
        s.bands.push(band_words);
    }
    if s.env
        && b.materials()
            .iter()
            .any(|(_, f)| !matches!(f, LightingFn::EnvMap { .. }))
    {
        return Err(
            "EnvMap and another function in one table: the generator builds a table of \
             EnvMap materials only (their entries are written later in the pipeline)"
                .into(),
        );
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

/// The reflection `2 a b - k` of two dot products `a = N.u`, `b = N.w` and the constant `k =
/// u.w`: `R.w` for `R = 2 (N.u) N - u`.
pub(crate) fn reflection(m: &mut Module, a: &Fx, b: &Fx, k: &Fx) -> Fx {
    let p = mul(m, a, b);
    let p2 = twice(m, p);
    sub(m, &p2, k)
}

/// `2 x`: the same raw word read with one fraction bit less, or scaled when it has none.
fn twice(m: &mut Module, x: Fx) -> Fx {
    if x.frac > 0 {
        Fx {
            frac: x.frac - 1,
            ..x
        }
    } else {
        scale(m, &x, 2)
    }
}

/// The slot's reflection constant (`L.V`, `V.up`, `V.a`: a host register of the exact
/// product of two vector readings), selected by the slot `f1` among the slots that have one.
fn slot_konst(
    m: &mut Module,
    kregs: &[Option<String>],
    konst_fmt: &Format,
    vector: &Encoding,
    f1: &str,
) -> Fx {
    let (fv, facv) = reading(vector);
    let kslots: Vec<usize> = (0..kregs.len()).filter(|&i| kregs[i].is_some()).collect();
    let kvals: Vec<Fx> = kslots
        .iter()
        .map(|&i| {
            let r = raw_word(m, kregs[i].as_ref().unwrap(), konst_fmt);
            let mut fac = [facv.clone(), facv.clone()].concat();
            fac.sort_unstable();
            Fx {
                frac: 2 * fv,
                fac,
                ..r
            }
        })
        .collect();
    if kvals.len() == 1 {
        return kvals[0].clone();
    }
    let kb = unsigned_bits(kvals.len() as u128 - 1);
    let ids: Vec<String> = (0..kregs.len())
        .map(|i| {
            let at = kslots.iter().position(|&x| x == i).unwrap_or(0);
            format!("{kb}'d{at}")
        })
        .collect();
    let ksel = m.select_bits(f1, &ids, kb);
    select(m, &ksel, &kvals)
}

/// `1` when the unsigned `x` equals one of `values`, as an expression.
pub(crate) fn any_eq(x: &str, bits: u32, values: impl Iterator<Item = usize>) -> String {
    let terms: Vec<String> = values.map(|v| format!("({x} == {bits}'d{v})")).collect();
    if terms.is_empty() {
        "1'b0".into()
    } else {
        terms.join(" || ")
    }
}

/// The material of entry `e` (`eb` bits): the count of interval starts at or below it.
pub(crate) fn material_of(m: &mut Module, b: &PaletteBuilder, e: &str, eb: u32) -> String {
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
    // the write is stage 3 (an EnvMap table's stage 5) after the last slot's issue
    let cycles = b.cycles_per_frame() as u32 + if s.env { 6 } else { 4 };
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
    // a difference of two entry words (chrome's sky - ground)
    let word_fmt = Format::s(signed_bits(er_lo - er_hi, er_hi - er_lo) as u8, 0);
    let fmt_of = |form: Form| match form {
        Form::Product => coef_fmt,
        Form::Word => word_fmt,
    };
    // a reflection constant: three products of two vector readings
    let (vr_lo, vr_hi) = raw_range(&f.vector);
    let vc = [vr_lo * vr_lo, vr_lo * vr_hi, vr_hi * vr_hi];
    let (k_lo, k_hi) = (
        3 * vc.into_iter().min().unwrap(),
        3 * vc.into_iter().max().unwrap(),
    );
    let konst_fmt = Format::s(signed_bits(k_lo, k_hi) as u8, 0);
    let wv = f.vector.width();
    let we_w = f.entry.width();
    let mut vregs = Vec::new();
    let mut cregs: Vec<[Option<String>; 4]> = Vec::new();
    let mut kregs: Vec<Option<String>> = Vec::new();
    for (k, sl) in s.slots.iter().enumerate() {
        match sl.vector {
            Some(vector) => {
                let v: Vec<String> = (0..3)
                    .map(|j| sh.config_raw(&format!("slot {k} vector {j}"), wv, vector[j]))
                    .collect();
                let word = sh.m.uwire(
                    "b_vec",
                    3 * wv,
                    &format!("{{{}, {}, {}}}", v[2], v[1], v[0]),
                );
                vregs.push(word);
            }
            None => vregs.push(format!("{}'d0", 3 * wv)),
        }
        let cfmt = fmt_of(sl.form);
        cregs.push(std::array::from_fn(|j| {
            sl.coef[j].map(|c| {
                sh.config_raw(
                    &format!("slot {k} coefficient {j}"),
                    cfmt.width as u32,
                    c as i64,
                )
            })
        }));
        kregs.push(sl.konst.map(|c| {
            sh.config_raw(
                &format!("slot {k} reflection constant"),
                konst_fmt.width as u32,
                c as i64,
            )
        }));
    }
    let mut aregs: Vec<[Option<String>; 4]> = Vec::new();
    for (k, a) in s.ambient.iter().enumerate() {
        aregs.push(std::array::from_fn(|j| {
            a[j].map(|c| sh.config_raw(&format!("material {k} ambient {j}"), we_w, c))
        }));
    }
    // per cartoon material, per lane, the band words
    let mut bregs: Vec<Option<[Vec<String>; 3]>> = Vec::new();
    for (k, bw) in s.bands.iter().enumerate() {
        bregs.push(bw.as_ref().map(|words| {
            std::array::from_fn(|j| {
                words
                    .iter()
                    .enumerate()
                    .map(|(i, w)| {
                        sh.config_raw(&format!("material {k} band {i} lane {j}"), we_w, w[j])
                    })
                    .collect()
            })
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
    if s.env {
        let konst = slot_konst(m, &kregs, &konst_fmt, &f.vector, &f1);
        let s1 = super::palette_envmap::Stage1 {
            dot: &dot,
            konst: &konst,
            f1: &f1,
            e1: &e1,
            v1: &v1,
            fb,
            eb,
        };
        return super::palette_envmap::finish(
            sh,
            b,
            &s.slots,
            s1,
            (&frame, &done, cycles),
            addr_bits,
        );
    }
    let sat = clamp(m, &dot, Some((0, 0)), Some((1, 0)));
    let wi = f.intensity.width();
    let ik_dot = to_code(m, &sat, &f.intensity);
    let slots_where = |pick: &dyn Fn(&Slot) -> bool| -> Vec<usize> {
        s.slots
            .iter()
            .enumerate()
            .filter(|(_, x)| pick(x))
            .map(|(i, _)| i)
            .collect()
    };
    let has = |pick: &dyn Fn(&Slot) -> bool| s.slots.iter().any(pick);
    // the other sources of the slot's intensity word: (flag, code)
    let mut sources: Vec<(String, String)> = Vec::new();
    if has(&|x| matches!(x.src, Src::Chrome | Src::Doubled)) {
        m.comment("builder: the reflection, 2 (N.a)(N.b) - a.b (the previous slot's dot product)");
        let dp = m.sreg("b_dp", dot.width());
        m.stmt(format!("always @(posedge clk) {dp} <= {};", dot.name));
        let dpx = Fx {
            name: dp,
            ..dot.clone()
        };
        let kx = slot_konst(m, &kregs, &konst_fmt, &f.vector, &f1);
        let r = reflection(m, &dpx, &dot, &kx);
        if has(&|x| x.src == Src::Chrome) {
            // t = (1 + R.up) / 2
            let t = add(m, &constant(1, 0), &r);
            let t = Fx {
                frac: t.frac + 1,
                ..t
            };
            let code = clamp_code(m, &t, Some((0, 0)), Some((1, 0)), &f.intensity);
            let flag = any_eq(&f1, fb, slots_where(&|x| x.src == Src::Chrome).into_iter());
            sources.push((m.uwire("b_chrome", 1, &flag), code));
        }
        if has(&|x| x.src == Src::Doubled) {
            // 2 (R.V)^2 - 1 for R.V > 0, of R.V clamped to [0, 1] first: R.V <= 0 gives -1,
            // the intensity 0 and the power table's first word, 0 (checked), as the model's
            // zero; R.V >= 1 gives 1, the clamp's limit, as the model's 2 (R.V)^2 - 1 >= 1
            // (the square is as wide as R.V's fraction, not its range)
            let plain = r
                .fac
                .iter()
                .try_fold(r.lo.unsigned_abs().max(r.hi.unsigned_abs()), |a, &n| {
                    a.checked_mul((1u128 << n) + 1)
                });
            if plain.is_none_or(|v| v > 1u128 << 62) {
                return Err(
                    "doubled-angle Phong: R.V's square overflows the model's 128-bit \
                     intermediate (narrower normal and vector words, or words without \
                     bit-replication factors)"
                        .into(),
                );
            }
            let rp = clamp(m, &r, Some((0, 0)), Some((1, 0)));
            // registered: the square and the cast in the next slot
            let rv = m.sreg("b_rv", rp.width());
            m.stmt(format!("always @(posedge clk) {rv} <= {};", rp.name));
            let rp = Fx { name: rv, ..rp };
            let sq = square(m, &rp);
            let sq2 = twice(m, sq);
            let x = sub(m, &sq2, &constant(1, 0));
            let code = clamp_code(m, &x, Some((0, 0)), Some((1, 0)), &f.intensity);
            let flag = any_eq(&f1, fb, slots_where(&|x| x.src == Src::Doubled).into_iter());
            sources.push((m.uwire("b_doubled", 1, &flag), code));
        }
    }
    if has(&|x| x.csum) {
        m.comment("builder: the cartoon sum of the clamped dot products");
        let most = b
            .materials()
            .iter()
            .map(|(_, f)| match f {
                LightingFn::Cartoon { lights, .. } => lights.len() as i128,
                _ => 0,
            })
            .max()
            .unwrap_or(0);
        let hi = most * sat.hi.max(0);
        let cs = m.sreg("b_cs", signed_bits(0, hi));
        let csx = Fx {
            name: cs.clone(),
            lo: 0,
            hi,
            frac: sat.frac,
            fac: sat.fac.clone(),
        };
        let first1 = any_eq(&f1, fb, slots_where(&|x| x.first).into_iter());
        let keep = m.uwire("b_cs_keep", 1, &format!("!({first1})"));
        let old = gate(m, &keep, &csx);
        let next = sum_in_range(m, &[&old, &sat], 0, hi);
        let en = any_eq(&f1, fb, slots_where(&|x| x.csum).into_iter());
        m.stmt(format!(
            "always @(posedge clk) if ({en}) {cs} <= {};",
            next.name
        ));
        let code = clamp_code(m, &csx, Some((0, 0)), Some((1, 0)), &f.intensity);
        let flag = any_eq(&f1, fb, slots_where(&|x| x.src == Src::Cartoon).into_iter());
        sources.push((m.uwire("b_band", 1, &flag), code));
    }
    if has(&|x| x.src == Src::Zero) {
        let flag = any_eq(&f1, fb, slots_where(&|x| x.src == Src::Zero).into_iter());
        sources.push((m.uwire("b_zero", 1, &flag), format!("{wi}'d0")));
    }
    let ik1 = if sources.is_empty() {
        ik_dot
    } else {
        let mut e = ik_dot;
        for (flag, code) in sources.iter().rev() {
            e = format!("{flag} ? {code} : ({e})");
        }
        m.uwire("b_ik", wi, &e)
    };
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
    // the cartoon band of the intensity word: floor(bands x), at most bands - 1
    let mut band_counts: Vec<u32> = s.slots.iter().filter_map(|x| x.bands).collect();
    band_counts.sort_unstable();
    band_counts.dedup();
    let k3 = if let Some(&most) = band_counts.last() {
        let kb = unsigned_bits(most as u128 - 1);
        let kx = from_code(m, &ik2, &f.intensity);
        let ks: Vec<String> = band_counts
            .iter()
            .map(|&bands| {
                let sx = scale(m, &kx, bands as i128);
                let fl = shift_round(m, &sx, sx.frac, Quant::Trn);
                let cl = clamp(m, &fl, Some((0, 0)), Some((bands as i128 - 1, 0)));
                overflow(m, &cl, &Format::u(kb as u8, 0), Overflow::Wrap)
            })
            .collect();
        let k2 = if ks.len() == 1 {
            ks[0].clone()
        } else {
            let bb = unsigned_bits(ks.len() as u128 - 1);
            let ids: Vec<String> = s
                .slots
                .iter()
                .map(|x| {
                    let at = x
                        .bands
                        .and_then(|c| band_counts.iter().position(|&y| y == c))
                        .unwrap_or(0);
                    format!("{bb}'d{at}")
                })
                .collect();
            let bsel = m.select_bits(&f2, &ids, bb);
            m.select_bits(&bsel, &ks, kb)
        };
        let k3 = m.reg("b_k3", kb);
        m.stmt(format!("always @(posedge clk) {k3} <= {k2};"));
        Some(k3)
    } else {
        None
    };
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
    // the reading of a product `coefficient x value` of a class (form, kind)
    let class_reading = |(form, kind): (Form, Kind)| -> (u32, Vec<u32>) {
        let (cf, cfac) = match form {
            Form::Product => (2 * fe, [face.clone(), face.clone()].concat()),
            Form::Word => (fe, face.clone()),
        };
        let (xf, xfac) = match kind {
            Kind::Diffuse => (fi, faci.clone()),
            Kind::Specular => (fp, facp.clone()),
        };
        let mut fac = [cfac, xfac].concat();
        fac.sort_unstable();
        (cf + xf, fac)
    };
    let all_classes = [
        (Form::Product, Kind::Diffuse),
        (Form::Product, Kind::Specular),
        (Form::Word, Kind::Diffuse),
        (Form::Word, Kind::Specular),
    ];
    let v2e = v2.clone();
    let mut accs: Vec<Vec<Fx>> = Vec::new();
    for j in 0..lanes {
        m.comment(&format!("builder: lane {j}"));
        let in_lane = |x: &Slot| x.coef[j].is_some();
        // the classes of slot with a coefficient in this lane, and per class the most slots
        // of one material that add to it
        let classes: Vec<(Form, Kind)> = all_classes
            .iter()
            .copied()
            .filter(|&(fo, k)| has(&|x| in_lane(x) && x.form == fo && x.kind == k))
            .collect();
        if classes.is_empty() {
            accs.push(Vec::new());
            continue;
        }
        let coefs: Vec<Fx> = cregs
            .iter()
            .zip(&s.slots)
            .map(|(c, sl)| match &c[j] {
                Some(r) => raw_word(m, r, &fmt_of(sl.form)),
                None => constant(0, 0),
            })
            .collect();
        let coef = select(m, &f2, &coefs);
        let prod = mul(m, &coef, &x_raw);
        let mut most = 0;
        for &(fo, k) in &classes {
            let mut c = 0;
            for (mi, &start) in s.base.iter().enumerate() {
                let end = s.base.get(mi + 1).copied().unwrap_or(total);
                let n = s.slots[start..end]
                    .iter()
                    .filter(|x| in_lane(x) && x.form == fo && x.kind == k)
                    .count();
                c = c.max(n);
            }
            most += c;
        }
        // one accumulator: with several classes, each product is first brought to the
        // common reading (its own factors applied, aligned to the finest fraction)
        let (term, frac, fac) = if classes.len() == 1 {
            let (fr, fac) = class_reading(classes[0]);
            (prod, fr, fac)
        } else {
            let readings: Vec<(u32, Vec<u32>)> =
                classes.iter().map(|&c| class_reading(c)).collect();
            let mut common = readings[0].1.clone();
            for (_, fac) in &readings[1..] {
                let gone = extra(&common, fac);
                common = extra(&common, &gone);
            }
            let top = readings.iter().map(|r| r.0).max().unwrap();
            let vals: Vec<Fx> = readings
                .iter()
                .map(|(fr, fac)| {
                    scale(
                        m,
                        &Fx {
                            fac: extra(fac, &common),
                            ..prod.clone()
                        },
                        1 << (top - fr),
                    )
                })
                .collect();
            let csel = if classes
                == [
                    (Form::Product, Kind::Diffuse),
                    (Form::Product, Kind::Specular),
                ] {
                spec2.clone()
            } else {
                let cb = unsigned_bits(classes.len() as u128 - 1);
                let ids: Vec<String> = s
                    .slots
                    .iter()
                    .map(|x| {
                        let at = classes
                            .iter()
                            .position(|&(fo, k)| x.form == fo && x.kind == k)
                            .unwrap_or(0);
                        format!("{cb}'d{at}")
                    })
                    .collect();
                m.select_bits(&f2, &ids, cb)
            };
            (select(m, &csel, &vals), top, common)
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
    let cartoon: Vec<usize> = (0..s.bands.len())
        .filter(|&k| s.bands[k].is_some())
        .collect();
    let all_cartoon = cartoon.len() == s.bands.len();
    let is_cartoon3 = if !cartoon.is_empty() && !all_cartoon {
        let mb = unsigned_bits(s.bands.len().saturating_sub(1) as u128);
        let e = any_eq(&mat3, mb, cartoon.iter().copied());
        Some(m.uwire("b_cartoon", 1, &e))
    } else {
        None
    };
    let mut lane_codes = Vec::new();
    for j in 0..4 {
        if j >= lanes {
            let one = f.entry.encode(1.0);
            lane_codes.push(format!("{we_w}'d{}", f.entry.format.bits(one)));
            continue;
        }
        // the cartoon band word: by the band, then by the material
        let band = k3.as_ref().map(|k3| {
            let per: Vec<String> = bregs
                .iter()
                .map(|r| {
                    let words = r.as_ref().or(bregs[cartoon[0]].as_ref()).unwrap();
                    m.select_bits(k3, &words[j], we_w)
                })
                .collect();
            if all_cartoon && per.len() == 1 {
                per[0].clone()
            } else {
                m.select_bits(&mat3, &per, we_w)
            }
        });
        if all_cartoon {
            lane_codes.push(band.unwrap());
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
        let code = match (&band, &is_cartoon3) {
            (Some(bw), Some(c)) => m.uwire("b_lane", we_w, &format!("{c} ? {bw} : {code}")),
            _ => code,
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
    Ok(write_port(
        m,
        (w3, e3, eb),
        data,
        addr_bits,
        (&frame, &done, cycles),
        n,
    ))
}

/// The colour table's write port of the builder's last stage: enable `we` and entry `e`
/// (`eb` bits, widened to `addr_bits`), the entry word `data`; `done` rises on the write of
/// entry `n - 1` and falls on `frame`.
pub(crate) fn write_port(
    m: &mut Module,
    (we, e, eb): (String, String, u32),
    data: String,
    addr_bits: u32,
    (frame, done, cycles): (&str, &str, u32),
    n: usize,
) -> Writes {
    let addr = if eb < addr_bits {
        m.uwire(
            "b_addr",
            addr_bits,
            &format!("{{{}'d0, {e}}}", addr_bits - eb),
        )
    } else {
        e.clone()
    };
    m.stmt(format!(
        "always @(posedge clk) begin\n    if (rst || {frame}) {done} <= 1'b0;\n    \
         else if ({we} && {e} == {eb}'d{}) {done} <= 1'b1;\nend",
        n - 1
    ));
    Writes {
        we,
        addr,
        data,
        cycles,
    }
}
