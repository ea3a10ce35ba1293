//! Verilog of the software path's per-fragment noise of NDF bump synthesis
//! ([`crate::units::TurbulenceIndex`], Kautz et al. 2001 §5.1): two fractal sums of Perlin's
//! improved noise (one permutation each) over `octaves` octaves, the last one blended in by
//! the fraction of the octave count `octaves - lod`, each scaled into an index `1/2 + n
//! scale`, clamped and cast. The datapath is [`crate::units::ndf_noise::Turbulence::bits_blend`]
//! and the unit's bit-accurate `eval`, operation for operation:
//!
//! * **Lattice** (per octave `k`, per axis; [`TurbulenceIndex::lattice`]): the coordinate's
//!   low bits `r` times the period `f 2^k` (a shift for a power-of-two frequency), the cell
//!   index `P >> uv_frac` and the position in the cell, of which only the bits that can be
//!   non-zero are built (`fb`: 13 bits for octave 0 of `ndf-teapot-aniso-sw`, a 16-bit
//!   coordinate over 8 cells), the neighbour cell `(i + 1) mod period`.
//! * **Hash** per corner, `P[P[P[i] + j]] & 15`: the first read is a ROM of the period's
//!   entries (`P[i]` for the cell and its neighbour, shared by two corners each), an 8-bit
//!   add, a 256 x 8 ROM, and a 256 x 4 ROM of the permutation's low four bits (the gradient
//!   index). One set of ROM modules per permutation.
//! * **Fade** `t^3 (6 t^2 - 15 t + 10)` exact (folded square, `t^2 t`, the quadratic by
//!   shifts and adds, one product) and rounded once, halves up, to `frac` bits: per octave
//!   and axis, shared by the two noises (they read the same position).
//! * **Corner dots** `g . (dx, dy)` with `g` in `{0, +-1}^2`: a negation and a mux per term.
//! * **Lerps** `p + round(t (q - p))` (one multiplier each), three per noise and octave.
//! * **Octave sum**: weights `w_k = clamp(256 (octaves - k) - floor(256 lod), 0, 256)` (the
//!   model's `clamp(o_q - 256 k, 0, 256)` with `o_q = clamp(256 octaves - floor(256 lod), 0,
//!   256 octaves)`: the same integer for every `lod`), one `n x w` product per octave, the
//!   sum `sum_k n_k w_k 2^-k` exact and rounded once to `frac` bits.
//! * **Index**: `n scale + 1/2` (the scale a host-loaded register, `cfg` address 0, holding
//!   the model's code with 16 fraction bits: the NDF's spread is a parameter of the image, not
//!   of the netlist), the clamp into `[0, 1]` fused with the cast ([`clamp_code`]).
//!
//! Clocking: three stages, every stage register loaded on every edge (the model's interval
//! of 1): (1) lattice, hash and fades into the gradient indices, the fades, the positions
//! in the cells and the LOD word; (2) corner dots, lerps and the weighted octave sum into the
//! two noise words; (3) the index, clamp and cast into the outputs. RTL latency 3 (the
//! model's `octaves + 3` counts one clock per octave: here the octaves are parallel).
//!
//! The fade of each position width (`{top}_fade{fb}`) and each octave's noise datapath
//! (`{top}_noise{k}`: dots and lerps) are submodules, instantiated per axis and per noise, so
//! that yosys synthesises each distinct one once (the flat module took ABC over 13 minutes;
//! with them the bundled unit takes 8 minutes of CPU).

use super::fixed::{
    add, align_wire, aligned, clamp, clamp_code, constant, make, mul, plain, scale, shift_round,
    square, sub, sum, Fx,
};
use super::normalize::{stage, stage_bits};
use super::verilog::{lit, Module};
use super::{Plan, RtlUnit, Shell};
use crate::format::Quant;
use crate::unit::Unit;
use crate::units::ndf_noise::{fade_bits, grad};
use crate::units::ndf_turbulence::{Lattice, SCALE_FRAC};
use crate::units::TurbulenceIndex;

/// The RTL latency: three pipeline stages.
pub const LATENCY: u32 = 3;

/// One axis of octave `k` from the coordinate word: the cell index, its neighbour (each
/// `Lattice::index_bits` unsigned bits, or `None` for a one-cell period) and the position
/// in the cell (`fb` unsigned bits, or `None` when it is always 0).
struct Axis {
    cell: Option<(String, String)>,
    pos: Option<String>,
}

fn axis(m: &mut Module, r: &Fx, uf: u32, l: &Lattice) -> Axis {
    let p = scale(m, r, l.period as i128);
    let xb = l.index_bits();
    // P = r period < 2^uf period: its index bits end at uf + xb
    let p = m.uwire("lat", uf + xb.max(1), &p.name);
    let cell = (xb > 0).then(|| {
        let i = m.uwire("ci", xb, &format!("{p}[{}:{uf}]", uf + xb - 1));
        let next = if l.period.is_power_of_two() {
            format!("{i} + {xb}'d1")
        } else {
            format!("({i} == {xb}'d{}) ? {xb}'d0 : {i} + {xb}'d1", l.period - 1)
        };
        let n = m.uwire("cn", xb, &next);
        (i, n)
    });
    let pos = (l.fb > 0).then(|| m.uwire("fx", l.fb, &format!("{p}[{}:{}]", uf - 1, l.low)));
    Axis { cell, pos }
}

/// The fade of a position of `fb` bits (`fx = pos 2^(f - fb)`) at `f` fraction bits, exact
/// then rounded once (halves up): [`fade_bits`].
fn fade(m: &mut Module, pos: &Fx, fb: u32, f: u32) -> Fx {
    let t2 = square(m, pos);
    let t3 = mul(m, &t2, pos);
    // 6 t^2 - 15 t + 10 at 2 fb fraction bits
    let a = scale(m, &t2, 6);
    let b = scale(m, pos, 15);
    let ab = sub(m, &a, &b);
    let q = add(m, &ab, &constant(10, 0));
    // 6 x^2 - 15 x + 10 falls from 10 at x = 0 to above 1 at x = 1 - 2^-fb: unsigned
    let q = make(m, "q", 1 << (2 * fb), 10 << (2 * fb), q.frac, &q.name);
    let p = mul(m, &t3, &q);
    debug_assert_eq!(p.frac, 5 * fb);
    let r = if 5 * fb >= f {
        shift_round(m, &p, 5 * fb - f, Quant::Rnd).at_frac(f)
    } else {
        align_wire(m, &p, f)
    };
    // the range of the model's fade over the positions (monotonic)
    let hi = fade_bits(((1i64 << fb) - 1) << (f - fb), f) as i128;
    make(m, "fade", 0, hi, f, &r.name)
}

/// `p + round(t (q - p))` at `t.frac` fraction bits (`Noise::bits`' lerp).
fn lerp(m: &mut Module, t: &Fx, p: &Fx, q: &Fx) -> Fx {
    let d = sub(m, q, p);
    let prod = mul(m, t, &d);
    let r = shift_round(m, &prod, d.frac, Quant::Rnd).at_frac(t.frac);
    let s = add(m, p, &r);
    // with t in [0, 1] the result lies between p and q
    let (_, pl, ph) = aligned(p, s.frac);
    let (_, ql, qh) = aligned(q, s.frac);
    make(m, "lerp", pl.min(ql), ph.max(qh), s.frac, &s.name)
}

/// `g . (dx, dy)` for the gradient of the 4-bit index `h` ([`grad`]): per axis the term
/// `d`, `-d` or 0 by the index.
fn dot(m: &mut Module, h: &str, d: [&Fx; 2]) -> Fx {
    let terms: Vec<Fx> = (0..2)
        .map(|a| {
            let x = d[a];
            let set = |s: i64| -> Vec<String> {
                (0u8..16)
                    .filter(|&c| {
                        let g = grad(c);
                        (if a == 0 { g.0 } else { g.1 }) == s
                    })
                    .map(|c| format!("({h} == 4'd{c})"))
                    .collect()
            };
            let (pos, neg) = (set(1), set(-1));
            let mag = x.lo.unsigned_abs().max(x.hi.unsigned_abs()) as i128;
            let e = format!(
                "({}) ? {} : (({}) ? -{} : {})",
                pos.join(" || "),
                x.name,
                neg.join(" || "),
                x.name,
                lit(0)
            );
            make(m, "gd", -mag, mag, x.frac, &e)
        })
        .collect();
    add(m, &terms[0], &terms[1])
}

/// A submodule `name` with unsigned inputs `ins` (name, bits) and one output `y`, the
/// signed value `build` returns; `inst` instantiates it in `m` on the wires `args` and
/// returns the output as an [`Fx`] (the same range). Its text is appended to `subs` once.
fn submodule(
    subs: &mut Vec<(String, String)>,
    name: &str,
    ins: &[(&str, u32)],
    build: impl FnOnce(&mut Module) -> Fx,
) -> (String, Fx) {
    let mut sm = Module::new(name);
    for (n, w) in ins {
        sm.input(n, *w);
    }
    let y = build(&mut sm);
    sm.output_wire("y", y.width(), &y.name);
    if !subs.iter().any(|(n, _)| n == name) {
        subs.push((name.to_string(), sm.text()));
    }
    (name.to_string(), y)
}

/// Instantiate submodule `name` (output `y` of the range of `y`) on `args` (port, wire).
fn instance(m: &mut Module, name: &str, y: &Fx, args: &[(&str, String)]) -> Fx {
    let net = m.net("sub", y.width());
    let mut conns: Vec<String> = args.iter().map(|(p, w)| format!(".{p}({w})")).collect();
    conns.push(format!(".y({net})"));
    let inst = format!("{net}_i");
    m.stmt(format!("{name} {inst} ({});", conns.join(", ")));
    let mut r = make(m, "sub", y.lo, y.hi, y.frac, &format!("$signed({net})"));
    r.fac = y.fac.clone();
    r
}

/// The unsigned bits of a non-negative signed wire `x` (range `[0, hi]`), without its sign.
fn ubits(x: &Fx) -> u32 {
    super::verilog::unsigned_bits(x.hi.max(1) as u128)
}

/// The Verilog of a built [`TurbulenceIndex`].
pub fn rtl(u: &TurbulenceIndex, top: &str) -> RtlUnit {
    let mut sh = Shell::new(top, Plan::pipeline(LATENCY));
    let ins = u.inputs().to_vec();
    let out = u.outputs()[0].enc;
    let uvp = sh.port(0, &ins[0], false);
    let lodp = sh.port(1, &ins[1], false);
    let outs = sh.output(0, &u.outputs()[0]);
    let sb = u.scale_bits();
    let scale_reg = sh.config_raw(
        &format!("index scale (u{sb}.{SCALE_FRAC}: 1 / (2 spread))"),
        sb,
        u.scale_raw(),
    );
    let (f, oct) = (u.frac(), u.octaves());
    let uf = ins[0].enc.format.frac as u32;
    let lats: Vec<Lattice> = (0..oct).map(|k| u.lattice(k)).collect();
    let turb = u.turbulence().clone();
    let fin = sh.fin.clone();
    let mut subs: Vec<(String, String)> = Vec::new();

    // stage 1: lattice, hashes and fades
    let m = &mut sh.m;
    m.comment("stage 1: the coordinates wrapped to [0, 1)");
    let r: Vec<Fx> = uvp
        .iter()
        .map(|w| {
            let ub = lats[0].ubits;
            if ub == 0 {
                constant(0, 0)
            } else {
                make(
                    m,
                    "r",
                    0,
                    (1i128 << ub) - 1,
                    0,
                    &format!("$signed({{1'b0, {w}[{}:0]}})", ub - 1),
                )
            }
        })
        .collect();
    // per octave: per axis the cell, its neighbour and the position
    let mut axes: Vec<[Axis; 2]> = Vec::new();
    for (k, l) in lats.iter().enumerate() {
        m.comment(&format!(
            "octave {k}: period {}, {} position bits",
            l.period, l.fb
        ));
        axes.push([axis(m, &r[0], uf, l), axis(m, &r[1], uf, l)]);
    }
    // fades and positions, registered
    let mut fades: Vec<[Fx; 2]> = Vec::new();
    let mut pos1: Vec<[Option<Fx>; 2]> = Vec::new();
    for (k, l) in lats.iter().enumerate() {
        let m = &mut sh.m;
        m.comment(&format!("octave {k}: fades"));
        let mut fs = Vec::new();
        let mut ps = Vec::new();
        for (a, ax) in axes[k].iter().enumerate() {
            match &ax.pos {
                None => {
                    fs.push(constant(0, f));
                    ps.push(None);
                }
                Some(p) => {
                    let fb = l.fb;
                    let pf = make(
                        m,
                        "t",
                        0,
                        (1i128 << fb) - 1,
                        fb,
                        &format!("$signed({{1'b0, {p}}})"),
                    );
                    let (name, y) =
                        submodule(&mut subs, &format!("{top}_fade{fb}"), &[("t", fb)], |sm| {
                            let t = make(sm, "t", 0, (1i128 << fb) - 1, fb, "$signed({1'b0, t})");
                            fade(sm, &t, fb, f)
                        });
                    let fd = instance(m, &name, &y, &[("t", p.clone())]);
                    fs.push(stage(m, &format!("fade_{k}_{a}"), &fd));
                    ps.push(Some(stage(m, &format!("pos_{k}_{a}"), &pf)));
                }
            }
        }
        fades.push([fs[0].clone(), fs[1].clone()]);
        pos1.push([ps[0].clone(), ps[1].clone()]);
    }
    // hashes: gradient indices per noise, octave, corner (00, 10, 01, 11), registered
    let mut grads: Vec<Vec<[String; 4]>> = Vec::new();
    for w in 0..2 {
        let perm: Vec<i64> = turb.noise(w).perm().iter().map(|&x| i64::from(x)).collect();
        let low4: Vec<i64> = perm.iter().map(|&x| x & 15).collect();
        let mut per = Vec::new();
        for (k, l) in lats.iter().enumerate() {
            sh.m.comment(&format!("noise {w}, octave {k}: the corners' hashes"));
            let cells = |a: usize| -> [String; 2] {
                match &axes[k][a].cell {
                    None => ["0".to_string(), "0".to_string()],
                    Some((i, n)) => [i.clone(), n.clone()],
                }
            };
            let (xs, ys) = (cells(0), cells(1));
            let xb = l.index_bits();
            // P[i & 255] for the cell and its neighbour
            let first: Vec<String> = xs
                .iter()
                .map(|x| {
                    if xb == 0 {
                        return format!("8'd{}", perm[0]);
                    }
                    let n = l.period.min(256) as usize;
                    let ab = 64 - ((n - 1) as u64).leading_zeros();
                    let addr = if xb > ab {
                        format!("{x}[{}:0]", ab - 1)
                    } else {
                        x.clone()
                    };
                    let name = if n == 256 {
                        format!("{top}_perm{w}")
                    } else {
                        format!("{top}_perm{w}_{n}")
                    };
                    sh.rom(&name, &perm[..n], 8, &addr)
                })
                .collect();
            let y8 = |y: &String| -> String {
                if xb == 0 {
                    "8'd0".to_string()
                } else if xb >= 8 {
                    format!("{y}[7:0]")
                } else {
                    format!("{{{}'d0, {y}}}", 8 - xb)
                }
            };
            let mut hs = Vec::new();
            for (cx, cy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let a =
                    sh.m.uwire("ha", 8, &format!("{} + {}", first[cx], y8(&ys[cy])));
                let b = sh.rom(&format!("{top}_perm{w}"), &perm, 8, &a);
                let h = sh.rom(&format!("{top}_grad{w}"), &low4, 4, &b);
                hs.push(stage_bits(&mut sh.m, &format!("g_{w}_{k}_{cx}{cy}"), 4, &h));
            }
            per.push([hs[0].clone(), hs[1].clone(), hs[2].clone(), hs[3].clone()]);
        }
        grads.push(per);
    }
    let m = &mut sh.m;
    let lod_enc = ins[1].enc;
    let lw = lod_enc.width();
    let lod1 = stage_bits(m, "lod1", lw, &lodp[0]);

    // stage 2: dots, lerps, the weighted octave sum
    m.comment("stage 2: octave weights clamp(256 (octaves - k) - floor(256 lod), 0, 256)");
    let lod = super::fixed::from_code(m, &lod1, &lod_enc);
    let lod = plain(m, &lod);
    let lq = if lod.frac >= 8 {
        shift_round(m, &lod, lod.frac - 8, Quant::Trn)
    } else {
        align_wire(m, &lod, 8).at_frac(0)
    };
    let weights: Vec<Fx> = (0..oct)
        .map(|k| {
            let d = sub(m, &constant(256 * i128::from(oct - k), 0), &lq);
            clamp(m, &d, Some((0, 0)), Some((256, 0)))
        })
        .collect();
    let mut noise2 = Vec::new();
    for (w, grads_w) in grads.iter().enumerate() {
        let mut terms = Vec::new();
        for k in 0..oct as usize {
            m.comment(&format!("noise {w}, octave {k}: dots and lerps"));
            let fb = lats[k].fb;
            let (fa, fbb) = (&fades[k][0], &fades[k][1]);
            let mut ports: Vec<(&str, u32)> = vec![("g00", 4), ("g10", 4), ("g01", 4), ("g11", 4)];
            let mut args: Vec<(&str, String)> = ["g00", "g10", "g01", "g11"]
                .into_iter()
                .zip(grads_w[k].iter().cloned())
                .collect();
            if let [Some(px), Some(py)] = &pos1[k] {
                ports.extend([("a", ubits(fa)), ("b", ubits(fbb)), ("px", fb), ("py", fb)]);
                let low = |x: &Fx| format!("{}[{}:0]", x.name, ubits(x) - 1);
                args.extend([
                    ("a", low(fa)),
                    ("b", low(fbb)),
                    ("px", low(px)),
                    ("py", low(py)),
                ]);
            }
            let has_pos = pos1[k][0].is_some();
            let (fah, fbh) = (fa.hi, fbb.hi);
            let (name, y) = submodule(&mut subs, &format!("{top}_noise{k}"), &ports, |sm| {
                let inp = |sm: &mut Module, n: &str, hi: i128, fr: u32| {
                    make(sm, n, 0, hi, fr, &format!("$signed({{1'b0, {n}}})"))
                };
                let (a, b, d) = if has_pos {
                    let one = 1i128 << fb;
                    let d: Vec<[Fx; 2]> = ["px", "py"]
                        .iter()
                        .map(|n| {
                            let p = inp(sm, n, one - 1, fb);
                            let m1 = make(
                                sm,
                                "dm",
                                p.lo - one,
                                p.hi - one,
                                fb,
                                &format!("{} - {}", p.name, lit(one)),
                            );
                            [p, m1]
                        })
                        .collect();
                    (inp(sm, "a", fah, f), inp(sm, "b", fbh, f), d)
                } else {
                    let d = vec![[constant(0, 0), constant(-1, 0)]; 2];
                    (constant(0, f), constant(0, f), d)
                };
                let n00 = dot(sm, "g00", [&d[0][0], &d[1][0]]);
                let n10 = dot(sm, "g10", [&d[0][1], &d[1][0]]);
                let n01 = dot(sm, "g01", [&d[0][0], &d[1][1]]);
                let n11 = dot(sm, "g11", [&d[0][1], &d[1][1]]);
                let r0 = lerp(sm, &a, &n00, &n10);
                let r1 = lerp(sm, &a, &n01, &n11);
                let n = lerp(sm, &b, &r0, &r1);
                align_wire(sm, &n, f)
            });
            let n = instance(m, &name, &y, &args);
            // n w_k 2^-k / 2^8
            let p = mul(m, &n, &weights[k]);
            terms.push(p.at_frac(f + 8 + k as u32));
        }
        let s = sum(m, &terms.iter().collect::<Vec<_>>());
        let nsum = shift_round(m, &s, s.frac - f, Quant::Rnd).at_frac(f);
        noise2.push(stage(m, &format!("n_{w}"), &nsum));
    }

    // stage 3: the index
    m.comment("stage 3: 1/2 + n scale, clamped to [0, 1] and cast");
    let sc = make(
        m,
        "scale",
        0,
        (1i128 << sb) - 1,
        SCALE_FRAC,
        &format!("$signed({{1'b0, {scale_reg}}})"),
    );
    for (w, n) in noise2.iter().enumerate() {
        let p = mul(m, n, &sc);
        let y = add(m, &p, &constant(1, 1));
        let code = clamp_code(m, &y, Some((0, 0)), Some((1, 0)), &out);
        m.stmt(format!(
            "always @(posedge clk) if ({fin}) {} <= {code};",
            outs[w]
        ));
    }
    let mut u = sh.finish();
    for (_, text) in subs {
        u.verilog += "\n";
        u.verilog += &text;
    }
    u
}
