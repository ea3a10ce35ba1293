//! Verilog of the texture-shader unit ([`crate::units::texture_shader::TextureShader`], the
//! NV20 / NV2A texture shaders of NV_texture_shader §3.8.13 "Texture Shaders"), bit-exact with
//! its bit-accurate mode (`FixedArith` in `units/texture_shader/eval.rs`, `vector_bits` in
//! `mapping.rs`).
//!
//! The generator is specialised to the configured program of each stage (the programs are
//! fixed by the config, like ROM contents): each stage gets the datapath of its program only.
//! Every program has a generator: NONE, TEXTURE_2D, PASS_THROUGH, CULL_FRAGMENT,
//! DEPENDENT_AR / _GB, DOT_PRODUCT, DOT_PRODUCT_TEXTURE_2D (every dot mapping),
//! OFFSET_TEXTURE_2D and OFFSET_TEXTURE_2D_SCALE (the specified clamp, and the NV2A luminance
//! reading with or without the colour converter), TEXTURE_CUBE_MAP,
//! DOT_PRODUCT_TEXTURE_CUBE_MAP, DOT_PRODUCT_DIFFUSE_CUBE_MAP, the two reflections
//! (DOT_PRODUCT_REFLECT_CUBE_MAP, _CONST_EYE_REFLECT_CUBE_MAP; `cube`) and
//! DOT_PRODUCT_DEPTH_REPLACE. A stage whose consistency rule is broken runs NONE, as the
//! model.
//!
//! Datapath per program (coordinates are the coordinate encoding's raw words, `f` fraction
//! bits):
//!
//! * **TEXTURE_2D**: `s/q`, `t/q` as the model's `div` (`p = s 2^f`, the divisor's sign moved
//!   into `p`, `floor((2p + |q|) / (2|q|))`, 0 when `q = 0`, then the coordinate overflow):
//!   one unsigned divider of the magnitudes per coordinate (`arith::divide`). With
//!   `ShaderParams::lod` the mip level `clamp(floor(lod + 1/2), 0, levels - 1)`.
//! * **DEPENDENT_AR / _GB**: the previous texel's lanes read by their codec and cast into the
//!   coordinate encoding.
//! * **DOT_PRODUCT(_TEXTURE_2D)**: the mapped vector N at `dot_frac` fraction bits (8-bit
//!   channels and 16-bit HI / LO codes divided by 127, 255, 32767 or 65535 with round half
//!   up through [`crate::rtl::divide::div_round`]; the hemisphere's `z` the integer square
//!   root of `2^(2 dot_frac) - hi^2 - lo^2` (`arith::isqrt`, digit by digit); other texel
//!   widths by value), three exact products with `(s, t, r)`, one cast.
//! * **OFFSET_TEXTURE_2D(_SCALE)**: `s + a1 ds + a3 dt`, `t + a2 ds + a4 dt` with the matrix
//!   as shift-and-add constants, one cast each; the scale `l = scale mag + bias` (constants),
//!   clamped, times each RGB lane and cast (or the NV2A's integer quotient, the divisions by
//!   constants as reciprocals).
//! * **The cube maps**: the direction (the inputs' `(s, t, r)`, the three dots, or the
//!   eye vector reflected about the dots, `2 N (N.E) / (N.N) - E` rounded into the coordinate)
//!   projected onto its cube face (`cube::face`); the face and the face coordinates
//!   (`f + 2` bits, in `[0, 1]`) are registered like a 2D stage's `(s, t)`, the six faces
//!   stored one after another in the stage's memory.
//! * **PASS_THROUGH**: the coordinate clamped to `[0, 1]` and the colour converter
//!   (`((floor(v 2^k) + 1) (2^n - 1)) >> k`) or the cast into `pass_through`.
//! * **CULL_FRAGMENT**: the `live` output (a register, 1 = kept; present only when a stage
//!   culls): the AND over the culling stages of each coordinate's sign bit against its mode.
//!   It is not an output lane of [`RtlUnit::outputs`] (the model kills through
//!   [`crate::unit::Unit::live`], not a port).
//!
//! **Texel fetch** (`sample`): each stage with a texture has its own texture memory
//! (`{top}_tex{i}`, one read port per tap, one clock); a TEXTURE_2D stage with `lod` stores
//! every mip level in that one memory, the levels one after the other (level `l` from its
//! base address), and selects the tap offsets, base and weights by the level. Addressing,
//! weights, lerps and the cast are the TexFetch generator's (`crate::rtl::fetch::axis`).
//!
//! **Clocking**: one fragment at a time (the `RtlUnit` contract: inputs held from `start`
//! until `done`, outputs registered and held until the next fragment's edges write them).
//! Stage `i` is scheduled after what it reads: a texture stage whose operands are valid
//! after edge `d` (0: the inputs) loads its coordinate registers (`s`, `t`, after the divide,
//! dot product or offset) on edge `d + 1`, the memory reads on edge `d + 2`, and the filtered
//! (and scaled) texel is written into the stage's output registers on edge `d + 3`; a
//! DOT_PRODUCT stage registers its dot on the edge after its texel; PASS_THROUGH and the cull
//! test are written on edge 1; NONE and the result of DOT_PRODUCT and CULL_FRAGMENT are
//! constant wires, as is `depth` without DEPTH_REPLACE (with it, a register loaded the edge
//! after the two dots, through the projective divider's module); a DIFFUSE_CUBE_MAP stage's
//! lookup is scheduled with the reflection after it, which supplies its third dot. The
//! latency is the last
//! edge: 3 for one texture stage, 6 for a dependent read of it, 10 for the NDF hardware
//! path (TEXTURE_2D, DEPENDENT_GB, DOT_PRODUCT, DOT_PRODUCT_TEXTURE_2D); the model's is one
//! clock per stage plus 3.

mod arith;
mod cube;
mod sample;

use super::fixed::{
    add, clamp, constant, from_code, make, mul, overflow, raw_word, scale, shift_round, sum,
    to_code, Fx,
};
use super::verilog::{unsigned_bits, Module};
use super::{Plan, RtlUnit, Shell};
use crate::format::{Codec, Encoding, Format, Overflow, Quant};
use crate::unit::Unit;
use crate::units::texture_shader::{DotMapping, Program, TextureShader};

/// The edges of each stage: its result (0: constant or none), its dot product, and for a
/// texture stage the edge that loads its coordinate registers.
struct Schedule {
    result: Vec<u32>,
    dot: Vec<u32>,
    coord: Vec<u32>,
    latency: u32,
}

fn schedule(progs: &[Program]) -> Schedule {
    let n = progs.len();
    let (mut result, mut dot, mut coord) = (vec![0; n], vec![0; n], vec![0; n]);
    let mut last = 1;
    for (i, p) in progs.iter().enumerate() {
        let prev = p.prev().map_or(0, |k| result[k]);
        if p.is_dot() {
            dot[i] = prev + 1;
        }
        let dep = match p {
            Program::Texture2d => Some(0),
            Program::DotProductTexture2d { .. } => Some(dot[i - 1].max(prev)),
            Program::DotProductTextureCube { .. }
            | Program::DotProductReflectCube { .. }
            | Program::DotProductConstEyeReflectCube { .. } => {
                Some(dot[i - 2].max(dot[i - 1]).max(prev))
            }
            // read with the next stage's dot: scheduled with it (below)
            Program::DotProductDiffuseCube { .. } => None,
            p if p.texture_kind().is_some() => Some(prev),
            _ => None,
        };
        if let Some(d) = dep {
            coord[i] = d + 1;
            result[i] = d + 3;
            if i > 0 && matches!(progs[i - 1], Program::DotProductDiffuseCube { .. }) {
                (coord[i - 1], result[i - 1]) = (coord[i], result[i]);
            }
        }
        if matches!(p, Program::PassThrough) {
            result[i] = 1;
        }
        if matches!(p, Program::DotProductDepthReplace { .. }) {
            // the depth register: after this dot and the previous stage's are valid
            result[i] = dot[i].max(dot[i - 1]) + 1;
        }
        last = last.max(result[i]).max(dot[i]);
    }
    Schedule {
        result,
        dot,
        coord,
        latency: last,
    }
}

/// The enable of edge `k` (1: the edge that samples `start`).
fn edge(k: u32, sb: u32) -> String {
    if k <= 1 {
        "start".into()
    } else {
        format!("step == {sb}'d{}", k - 1)
    }
}

/// A constant lane code as a named wire (so that lanes can be sliced).
fn code_wire(m: &mut Module, enc: &Encoding, raw: i64) -> String {
    let w = enc.width();
    m.uwire("kc", w, &format!("{w}'d{}", enc.format.bits(raw)))
}

/// A register of `w` bits loaded with `expr` on edge `k`.
fn reg_at(m: &mut Module, name: &str, w: u32, k: u32, sb: u32, expr: &str) -> String {
    m.reg(name, w);
    m.stmt(format!(
        "always @(posedge clk) if ({}) {name} <= {expr};",
        edge(k, sb)
    ));
    name.to_string()
}

/// `a / b` of two coordinate words as the model's `FixedArith::div`, into the coordinate
/// encoding: an instance of the one divider module `{top}_div` ([`arith::divide`], added to
/// `subs` with its first instance, so synthesised once).
fn divider(
    m: &mut Module,
    top: &str,
    coord: &Encoding,
    subs: &mut Vec<String>,
    a: &str,
    b: &str,
) -> String {
    let cw = coord.width();
    let name = format!("{top}_div");
    let mut dm = Module::new(&name);
    dm.input("a", cw);
    dm.input("b", cw);
    let q = arith::divide(&mut dm, "a", "b", &coord.format, coord.overflow);
    dm.output_wire("y", q.width(), &q.name);
    let text = dm.text();
    if !subs.contains(&text) {
        subs.push(text);
    }
    let net = m.net("quo", q.width());
    m.stmt(format!("{name} {net}_i (.a({a}), .b({b}), .y({net}));"));
    let r = make(m, "quo", q.lo, q.hi, 0, &format!("$signed({net})"));
    overflow(m, &r, &coord.format, coord.overflow)
}

/// An integer wire `v` (0 fraction bits) as a `w`-bit unsigned code (its low bits).
fn low(m: &mut Module, v: &Fx, w: u32) -> String {
    overflow(m, v, &Format::u(w as u8, 0), Overflow::Wrap)
}

/// The Verilog of the texture shader `u` as configured (see the module documentation).
pub fn rtl(u: &TextureShader, top: &str) -> Result<RtlUnit, String> {
    let p = *u.params();
    let n = u.stages.len();
    let progs = u.programs();
    let coord = p.coord;
    let cw = coord.width();
    let f = coord.format.frac as u32;
    let sc = schedule(&progs);
    let plan = if sc.latency <= 1 {
        Plan::single()
    } else {
        Plan::pipeline(sc.latency)
    };
    let mut sh = Shell::new(top, plan);
    let sb = unsigned_bits(sc.latency as u128);
    let ins = u.inputs().to_vec();
    let outs = u.outputs().to_vec();
    let coords: Vec<Vec<String>> = (0..n).map(|i| sh.port(i, &ins[i], false)).collect();
    let lod = p.lod.map(|_| sh.port(n, &ins[n], false).remove(0));
    let culls: Vec<usize> = (0..n)
        .filter(|&i| matches!(progs[i], Program::CullFragment { .. }))
        .collect();
    if !culls.is_empty() {
        sh.m.output_reg("live", 1);
    }
    let mut results: Vec<Vec<String>> = Vec::with_capacity(n);
    let mut dots: Vec<Option<String>> = vec![None; n];
    let mut fails = Vec::new();
    let mut subs: Vec<String> = Vec::new();
    let mut mapped: Vec<((usize, DotMapping), [Fx; 3])> = Vec::new();
    let mut depth: Option<(u32, String, String)> = None;
    for i in 0..n {
        let st = &u.stages[i];
        let prog = progs[i];
        let enc = st.out_enc;
        sh.m.comment(&format!("stage {i}: {}", prog.name()));
        let prev = prog.prev();
        // the dot product of this stage, registered on its edge (DOT_PRODUCT) or used as
        // the t coordinate (DOT_PRODUCT_TEXTURE_2D)
        let own_dot = if let (Some(mp), Some(k)) = (prog.mapping(), prev) {
            let ps = &u.stages[k];
            let m = &mut sh.m;
            // one mapping per texel and mapping: a second dot product of the same texel
            // reads the first one's N (as the price assumes, `price.rs`)
            let nv = match mapped.iter().find(|(key, _)| *key == (k, mp)) {
                Some((_, nv)) => nv.clone(),
                None => {
                    let hemi = format!("{top}_hemi{i}");
                    let nv = arith::vector(
                        m,
                        mp,
                        &results[k],
                        &ps.out_enc,
                        ps.lanes,
                        p.dot_frac,
                        (&hemi, &mut subs),
                    );
                    mapped.push(((k, mp), nv.clone()));
                    nv
                }
            };
            let terms: Vec<Fx> = (0..3)
                .map(|c| {
                    let x = raw_word(m, &coords[i][c], &coord.format).at_frac(f);
                    mul(m, &x, &nv[c].clone().at_frac(p.dot_frac))
                })
                .collect();
            let s = sum(m, &terms.iter().collect::<Vec<_>>());
            Some(to_code(m, &s, &coord))
        } else {
            None
        };
        if let (Program::DotProductDepthReplace { .. }, Some(d)) = (prog, &own_dot) {
            let p = dots[i.saturating_sub(1)].clone().ok_or_else(|| {
                format!("texture shader: stage {i}: the previous stage has no dot product")
            })?;
            depth = Some((sc.result[i], p, d.clone()));
        }
        if let (Program::DotProduct { .. } | Program::DotProductDiffuseCube { .. }, Some(d)) =
            (prog, &own_dot)
        {
            let r = reg_at(&mut sh.m, &format!("dot{i}"), cw, sc.dot[i], sb, d);
            dots[i] = Some(r);
        }
        // texture coordinates (s, t) and the level; a cube map's face and face coordinates
        let mut face: Option<String> = None;
        // the DIFFUSE_CUBE_MAP stage before a reflection: its lookup at the three dots
        let mut diffuse: Option<(String, String, String)> = None;
        let st_expr: Option<(String, String)> = match prog {
            Program::TextureCube => {
                let m = &mut sh.m;
                let d = std::array::from_fn(|k| raw_word(m, &coords[i][k], &coord.format));
                let (fc, s, t) = cube::face(m, &d, f);
                face = Some(fc);
                Some((s, t))
            }
            Program::DotProductTextureCube { .. }
            | Program::DotProductReflectCube { .. }
            | Program::DotProductConstEyeReflectCube { .. } => {
                let missing =
                    || format!("texture shader: stage {i}: the stages before have no dot products");
                let ds = [
                    dots[i - 2].clone().ok_or_else(missing)?,
                    dots[i - 1].clone().ok_or_else(missing)?,
                    own_dot.clone().ok_or_else(missing)?,
                ];
                let m = &mut sh.m;
                let nv: [Fx; 3] = std::array::from_fn(|k| raw_word(m, &ds[k], &coord.format));
                if matches!(progs[i - 1], Program::DotProductDiffuseCube { .. }) {
                    diffuse = Some(cube::face(m, &nv, f));
                }
                let dir = match prog {
                    Program::DotProductTextureCube { .. } => nv,
                    _ => {
                        let e: [Fx; 3] = match prog {
                            Program::DotProductConstEyeReflectCube { eye, .. } => {
                                std::array::from_fn(|k| {
                                    let v = coord.encode(eye[k]) as i128;
                                    make(m, "eye", v, v, 0, &super::verilog::lit(v))
                                })
                            }
                            _ => std::array::from_fn(|k| {
                                raw_word(m, &coords[i + k - 2][3], &coord.format)
                            }),
                        };
                        let refl = format!("{top}_refl{i}");
                        let r = cube::reflect(m, &nv, &e, &coord, (&refl, &mut subs));
                        std::array::from_fn(|k| raw_word(m, &r[k], &coord.format))
                    }
                };
                let (fc, s, t) = cube::face(m, &dir, f);
                face = Some(fc);
                Some((s, t))
            }
            Program::Texture2d => {
                // s/q and t/q: one divider module (synthesised once), two instances
                let q = &coords[i][3];
                let s = divider(&mut sh.m, top, &coord, &mut subs, &coords[i][0], q);
                let t = divider(&mut sh.m, top, &coord, &mut subs, &coords[i][1], q);
                Some((s, t))
            }
            Program::DependentAr { prev } | Program::DependentGb { prev } => {
                let (ls, lt) = if matches!(prog, Program::DependentAr { .. }) {
                    (3, 0)
                } else {
                    (1, 2)
                };
                let pe = u.stages[prev].out_enc;
                let m = &mut sh.m;
                let mut rd = |l: usize| {
                    let x = from_code(m, &results[prev][l], &pe);
                    to_code(m, &x, &coord)
                };
                Some((rd(ls), rd(lt)))
            }
            Program::DotProductTexture2d { .. } => {
                let s = dots[i - 1].clone().ok_or_else(|| {
                    format!("texture shader: stage {i}: the previous stage has no dot product")
                })?;
                Some((s, own_dot.clone().unwrap_or_default()))
            }
            Program::OffsetTexture2d { prev, .. } | Program::OffsetTexture2dScale { prev, .. } => {
                let o = &st.offset;
                let pe = u.stages[prev].out_enc;
                let m = &mut sh.m;
                let mut rd = |l: usize| {
                    let bits = &results[prev][o.lanes[l]];
                    if o.twos_complement && !pe.format.signed {
                        let nb = pe.format.width;
                        raw_word(m, bits, &Format::s(nb, 0)).at_frac(nb as u32 - 1)
                    } else {
                        from_code(m, bits, &pe)
                    }
                };
                let (ds, dt) = (rd(0), rd(1));
                let of = p.offset_frac;
                let term = |m: &mut Module, k: usize, d: &Fx| {
                    let r = st.matrix_raw[k] as i128;
                    (r != 0).then(|| {
                        let fr = d.frac + of;
                        scale(m, d, r).at_frac(fr)
                    })
                };
                let s0 = raw_word(m, &coords[i][0], &coord.format).at_frac(f);
                let t0 = raw_word(m, &coords[i][1], &coord.format).at_frac(f);
                let ts: Vec<Fx> = [Some(s0), term(m, 0, &ds), term(m, 2, &dt)]
                    .into_iter()
                    .flatten()
                    .collect();
                let tt: Vec<Fx> = [Some(t0), term(m, 1, &ds), term(m, 3, &dt)]
                    .into_iter()
                    .flatten()
                    .collect();
                let s2 = sum(m, &ts.iter().collect::<Vec<_>>());
                let t2 = sum(m, &tt.iter().collect::<Vec<_>>());
                Some((to_code(m, &s2, &coord), to_code(m, &t2, &coord)))
            }
            _ => None,
        };
        if let Some((fc, ds, dt)) = diffuse {
            results[i - 1] = texture_stage(
                &mut sh,
                u,
                (i - 1, progs[i - 1]),
                (ds, dt, Some(fc)),
                None,
                &sc,
                sb,
                None,
            )?;
        }
        let word: Vec<String> = if let Some((se, te)) = st_expr {
            let mag = match prog {
                Program::OffsetTexture2dScale { prev, .. } => {
                    Some(results[prev][st.offset.lanes[2]].clone())
                }
                _ => None,
            };
            texture_stage(
                &mut sh,
                u,
                (i, prog),
                (se, te, face),
                lod.as_deref(),
                &sc,
                sb,
                mag.as_deref(),
            )?
        } else if matches!(prog, Program::PassThrough) {
            let m = &mut sh.m;
            let codes: Vec<String> = (0..4)
                .map(|l| {
                    let v = raw_word(m, &coords[i][l], &coord.format).at_frac(f);
                    let v = clamp(m, &v, Some((0, 0)), Some((1, 0)));
                    match p.convert_frac {
                        Some(k) => {
                            let vk = if k >= f {
                                scale(m, &v, 1i128 << (k - f)).at_frac(0)
                            } else {
                                shift_round(m, &v, f - k, Quant::Trn)
                            };
                            let w = enc.width();
                            let top = (1i128 << w) - 1;
                            let v1 = add(m, &vk, &constant(1, 0));
                            let c = scale(m, &v1, top);
                            let c = shift_round(m, &c.at_frac(k), k, Quant::Trn);
                            low(m, &c, w)
                        }
                        None => to_code(m, &v, &enc),
                    }
                })
                .collect();
            let o = sh.output(i, &outs[i]);
            let ek = edge(sc.result[i], sb);
            for (r, c) in o.iter().zip(&codes) {
                sh.m.stmt(format!("always @(posedge clk) if ({ek}) {r} <= {c};"));
            }
            o
        } else if matches!(prog, Program::DotProductDiffuseCube { .. }) {
            // written by the next stage (above)
            Vec::new()
        } else {
            if let Program::CullFragment { gequal } = prog {
                let m = &mut sh.m;
                for (k, ge) in gequal.iter().enumerate() {
                    // fails when (c >= 0) != gequal: the sign bit equals the GEQUAL mode
                    let sign = format!("{}[{}]", coords[i][k], cw - 1);
                    fails.push(m.uwire("cfail", 1, &if *ge { sign } else { format!("~{sign}") }));
                }
            }
            let m = &mut sh.m;
            let zeros: Vec<String> = (0..4).map(|_| code_wire(m, &enc, 0)).collect();
            sh.output_wires(i, &outs[i], &zeros);
            zeros
        };
        results.push(word);
    }
    // DEPTH_REPLACE: the previous stage's dot over this one's, registered the edge after
    // both are valid
    let z = match depth {
        Some((e, a, b)) => {
            let q = divider(&mut sh.m, top, &coord, &mut subs, &a, &b);
            reg_at(&mut sh.m, "depth_q", cw, e, sb, &q)
        }
        None => code_wire(&mut sh.m, &coord, 0),
    };
    sh.output_wires(n, &outs[n], &[z]);
    if !culls.is_empty() {
        sh.m.stmt(format!(
            "always @(posedge clk) if (start) live <= ~({});",
            fails.join(" | ")
        ));
    }
    let mut r = sh.finish();
    for text in subs {
        r.verilog += "\n";
        r.verilog += &text;
    }
    Ok(r)
}

/// The texture read of stage `i` running `prog` at the coordinate words `se`, `te` (and the
/// cube face `face`): the coordinate registers, the level from `lod`, the fetch, the missing
/// lanes, the luminance scale of OFFSET_TEXTURE_2D_SCALE by the magnitude code `mag`, and the
/// stage's output registers written on its result edge. Returns the output registers.
#[allow(clippy::too_many_arguments)]
fn texture_stage(
    sh: &mut Shell,
    u: &TextureShader,
    (i, prog): (usize, Program),
    (se, te, face): (String, String, Option<String>),
    lod: Option<&str>,
    sc: &Schedule,
    sb: u32,
    mag: Option<&str>,
) -> Result<Vec<String>, String> {
    let st = &u.stages[i];
    let enc = st.out_enc;
    let p = *u.params();
    let coord = p.coord;
    let cw = coord.width();
    let f = coord.format.frac as u32;
    let tex = st.spec.texture.as_ref().ok_or_else(|| {
        format!(
            "texture shader: stage {i}: {} without a texture",
            prog.name()
        )
    })?;
    let levels = if matches!(prog, Program::Texture2d) && lod.is_some() {
        tex.levels()
    } else {
        1
    };
    let ce = sc.coord[i];
    // a cube face's coordinates lie in [0, 1] at f fraction bits
    let (scoord, rw) = match face {
        Some(_) => (Encoding::fixed(Format::s(f as u8 + 2, f as u8)), f + 2),
        None => (coord, cw),
    };
    let sr = reg_at(&mut sh.m, &format!("s{i}"), rw, ce, sb, &se);
    let tr = reg_at(&mut sh.m, &format!("t{i}"), rw, ce, sb, &te);
    let fr = face
        .as_ref()
        .map(|fc| reg_at(&mut sh.m, &format!("f{i}"), 3, ce, sb, fc));
    let level = match (lod, levels > 1) {
        (Some(l), true) => {
            let le = p.lod.unwrap_or(coord);
            if le.codec != Codec::Fixed {
                return Err(format!(
                    "texture shader: a LOD of codec {:?}: the generator reads a fixed-point LOD",
                    le.codec
                ));
            }
            let m = &mut sh.m;
            m.comment("the mip level: floor(lod + 1/2), clamped to the levels");
            let lf = le.format.frac as u32;
            let lx = raw_word(m, l, &le.format).at_frac(lf);
            let r = shift_round(m, &lx, lf, Quant::Rnd);
            let c = clamp(m, &r, Some((0, 0)), Some((levels as i128 - 1, 0)));
            let lb = unsigned_bits(levels as u128 - 1);
            Some(overflow(m, &c, &Format::u(lb as u8, 0), Overflow::Wrap))
        }
        _ => None,
    };
    let fe = sample::Fetch {
        tex,
        sampler: &st.spec.sampler,
        levels,
        faces: if fr.is_some() { 6 } else { 1 },
        coord: scoord,
        out: enc,
    };
    let codes = sample::fetch(
        sh,
        &fe,
        &sr,
        &tr,
        level.as_deref(),
        fr.as_deref(),
        &format!("tex{i}"),
    )
    .map_err(|e| format!("texture shader: stage {i}: {e}"))?;
    let m = &mut sh.m;
    let mut w: Vec<String> = codes;
    for l in st.lanes as usize..4 {
        let x = if l == 3 { 1.0 } else { 0.0 };
        w.push(code_wire(m, &enc, enc.encode(x)));
    }
    if let (Program::OffsetTexture2dScale { prev, .. }, Some(mag)) = (prog, mag) {
        w = luminance(m, &w, mag, u, i, prev)?;
    }
    let o = sh.output(i, &u.outputs()[i]);
    let ek = edge(sc.result[i], sb);
    for (r, c) in o.iter().zip(&w) {
        sh.m.stmt(format!("always @(posedge clk) if ({ek}) {r} <= {c};"));
    }
    Ok(o)
}

/// OFFSET_TEXTURE_2D_SCALE: the RGB lanes of `w` scaled by the luminance of the magnitude
/// code `mag` (the previous stage's lane), as the model's `FixedArith::scale`.
fn luminance(
    m: &mut Module,
    w: &[String],
    mag: &str,
    u: &TextureShader,
    i: usize,
    prev: usize,
) -> Result<Vec<String>, String> {
    let st = &u.stages[i];
    let me = u.stages[prev].out_enc;
    let enc = st.out_enc;
    let of = u.params().offset_frac;
    let unit = |e: &Encoding| e.codec == Codec::UnitUnsigned && !e.format.signed;
    let mut out = w.to_vec();
    m.comment("luminance scale");
    if st.offset.luminance_unclamped && unit(&me) && unit(&enc) {
        // the NV2A reading: num = max(0, scale m + bias nm), each code an integer quotient
        let nm = (1i128 << me.format.width) - 1;
        let top = (1i128 << enc.format.width) - 1;
        let den = nm << of;
        let mc = raw_word(m, mag, &me.format);
        let a = scale(m, &mc, st.scale_raw[0] as i128);
        let num = add(m, &a, &constant(st.scale_raw[1] as i128 * nm, 0));
        let num = clamp(m, &num, Some((0, 0)), None);
        let kk = u.params().convert_frac.unwrap_or(0);
        let bits = |x: i128| super::verilog::signed_bits(0, x);
        let wide = bits(top) + bits(num.hi) + kk + bits(top * den);
        if wide > 120 {
            return Err(format!(
                "texture shader: stage {i}: the NV2A luminance quotient needs {wide} bits: \
                 the generator's constant divider takes at most 120"
            ));
        }
        for o in out.iter_mut().take(3) {
            let c = raw_word(m, o, &enc.format);
            let x = mul(m, &c, &num);
            *o = match u.params().convert_frac {
                Some(k) => {
                    let x = scale(m, &x, 1i128 << k);
                    let xk = super::divide::floor_div(m, &x, top * den);
                    let xk = clamp(m, &xk, Some((0, 0)), Some((1i128 << k, 0)));
                    let v1 = add(m, &xk, &constant(1, 0));
                    let c = scale(m, &v1, top);
                    let c = shift_round(m, &c.at_frac(k), k, Quant::Trn);
                    low(m, &c, enc.width())
                }
                None => {
                    let q = super::divide::floor_div(m, &x, den);
                    let q = clamp(m, &q, Some((0, 0)), Some((top, 0)));
                    low(m, &q, enc.width())
                }
            };
        }
        return Ok(out);
    }
    let mg = from_code(m, mag, &me);
    let mf = mg.frac;
    let a = scale(m, &mg, st.scale_raw[0] as i128).at_frac(mf + of);
    let l = add(m, &a, &constant(st.scale_raw[1] as i128, of));
    let l = if st.offset.luminance_unclamped {
        clamp(m, &l, Some((0, 0)), None)
    } else {
        clamp(m, &l, Some((0, 0)), Some((1, 0)))
    };
    for o in out.iter_mut().take(3) {
        let x = from_code(m, o, &enc);
        let y = mul(m, &x, &l);
        *o = to_code(m, &y, &enc);
    }
    Ok(out)
}
