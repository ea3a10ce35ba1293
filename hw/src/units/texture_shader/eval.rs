//! One fragment through the stages, written once over the arithmetic of a mode ([`Arith`]):
//! [`ExactArith`] (f64, no quantization) and [`FixedArith`] (integers: the hardware).
//!
//! Bit-accurate number formats (see the module documentation of the unit):
//! * texture coordinates, dot products, offset and reflected coordinates: raw words of the
//!   coordinate encoding (`f` fraction bits); every result is computed exactly and rounded
//!   once into it (halves up, saturated);
//! * the mapped vector N: `dot_frac` fraction bits ([`super::mapping`]);
//! * the offset matrix, the luminance scale and bias: `offset_frac` fraction bits;
//! * texels: the texture's own codes; filtering and the cube-face projection are the
//!   sampler's ([`crate::sampler`]).

use super::mapping::{div_round, vector_bits, vector_exact};
use super::program::Program;
use super::{Compiled, TextureShader};
use crate::arith::Acc;
use crate::format::Encoding;
use crate::sampler::{cube_face, cube_face_bits};
use crate::texture::Texture;
use crate::unit::{Sample, Word, MAX_LANES};

/// The arithmetic of one mode. `V` is a coordinate-like scalar.
pub(crate) trait Arith {
    type V: Copy;
    fn coord(&self, s: &Sample) -> Self::V;
    fn zero(&self) -> Self::V;
    fn nonneg(&self, v: Self::V) -> bool;
    /// `a / b` (0 when b is 0).
    fn div(&self, a: Self::V, b: Self::V) -> Self::V;
    /// (s, t, r) . N of the previous texel, mapped.
    fn dot(&self, c: [Self::V; 3], prev: &Word, st: &Compiled, prev_st: &Compiled) -> Self::V;
    /// R = 2 N (N.E) / (N.N) - E.
    fn reflect(&self, n: [Self::V; 3], e: [Self::V; 3]) -> [Self::V; 3];
    /// A constant (the eye vector), as the stage holds it.
    fn konst(&self, x: f64) -> Self::V;
    /// Lane `lane` of the previous texel as a coordinate (DEPENDENT_AR / _GB).
    fn texel_coord(&self, prev: &Word, enc: &Encoding, lane: usize) -> Self::V;
    /// (s, t) offset by the matrix times (ds, dt) of the previous texel.
    fn offset(
        &self,
        s: Self::V,
        t: Self::V,
        prev: &Word,
        st: &Compiled,
        prev_st: &Compiled,
    ) -> (Self::V, Self::V);
    /// RGB of `texel` scaled by clamp(scale mag + bias, 0, 1).
    fn scale(&self, texel: &mut Word, prev: &Word, st: &Compiled, prev_st: &Compiled);
    fn sample2d(&self, st: &Compiled, level: usize, s: Self::V, t: Self::V) -> Word;
    /// The mip level of `tex` that level of detail `lod` selects (NEAREST_MIPMAP_NEAREST).
    fn level(&self, lod: &Sample, tex: &Texture) -> usize;
    fn sample_cube(&self, st: &Compiled, d: [Self::V; 3]) -> Word;
    /// PASS_THROUGH: clamp to [0, 1] into the pass-through encoding.
    fn pass(&self, c: [Self::V; 4], enc: &Encoding) -> Word;
}

/// The NV2A's reading of an offset lane ([`super::Offset::twos_complement`]): an unsigned
/// n-bit code `c` as two's complement, `c / 2^(n-1)`, minus 2 from `c >= 2^(n-1)`; a signed
/// encoding as it is. Exact mode reads the unquantized `c = x (2^n - 1)` the same way.
pub(super) fn twos_complement_exact(x: f64, enc: &Encoding) -> f64 {
    if enc.format.signed {
        return x;
    }
    let n = enc.format.width as i32;
    let half = 2f64.powi(n - 1);
    let c = x * (2f64.powi(n) - 1.0);
    if c >= half {
        (c - 2.0 * half) / half
    } else {
        c / half
    }
}

/// [`twos_complement_exact`] on the code, in integers.
pub(super) fn twos_complement_bits(raw: i64, enc: &Encoding) -> Acc {
    if enc.format.signed {
        return Acc::from_code(raw, enc);
    }
    let n = enc.format.width as u32;
    let c = raw as i128;
    let c = if c >= 1i128 << (n - 1) {
        c - (1i128 << n)
    } else {
        c
    };
    Acc::new(c, n - 1)
}

/// The lanes a texel has beyond the texture's: RGB 0, alpha 1.
fn fill_missing(w: &mut Word, lanes: u8, enc: &Encoding, exact: bool) {
    for l in lanes as usize..MAX_LANES {
        let x = if l == 3 { 1.0 } else { 0.0 };
        let raw = enc.encode(x);
        w.lanes[l] = Sample {
            x: if exact { x } else { enc.decode(raw) },
            raw,
        };
    }
}

pub(crate) struct ExactArith;

impl Arith for ExactArith {
    type V = f64;
    fn coord(&self, s: &Sample) -> f64 {
        s.x
    }
    fn zero(&self) -> f64 {
        0.0
    }
    fn nonneg(&self, v: f64) -> bool {
        v >= 0.0
    }
    fn div(&self, a: f64, b: f64) -> f64 {
        if b == 0.0 {
            0.0
        } else {
            a / b
        }
    }
    fn dot(&self, c: [f64; 3], prev: &Word, st: &Compiled, prev_st: &Compiled) -> f64 {
        let m = st.spec.program.mapping().unwrap_or_default();
        let n = vector_exact(m, &prev.xs::<4>(), &prev_st.out_enc, prev_st.lanes);
        c[0] * n[0] + c[1] * n[1] + c[2] * n[2]
    }
    fn reflect(&self, n: [f64; 3], e: [f64; 3]) -> [f64; 3] {
        let nn: f64 = n.iter().map(|v| v * v).sum();
        let ne: f64 = n.iter().zip(&e).map(|(a, b)| a * b).sum();
        if nn == 0.0 {
            return e.map(|v| -v);
        }
        std::array::from_fn(|k| 2.0 * n[k] * ne / nn - e[k])
    }
    fn konst(&self, x: f64) -> f64 {
        x
    }
    fn texel_coord(&self, prev: &Word, _: &Encoding, lane: usize) -> f64 {
        prev.lanes[lane].x
    }
    fn offset(&self, s: f64, t: f64, prev: &Word, st: &Compiled, p: &Compiled) -> (f64, f64) {
        let o = &st.offset;
        let read = |l: usize| {
            let x = prev.lanes[o.lanes[l]].x;
            if o.twos_complement {
                twos_complement_exact(x, &p.out_enc)
            } else {
                x
            }
        };
        let (ds, dt) = (read(0), read(1));
        let m = o.matrix;
        (s + m[0] * ds + m[2] * dt, t + m[1] * ds + m[3] * dt)
    }
    fn scale(&self, texel: &mut Word, prev: &Word, st: &Compiled, _: &Compiled) {
        let o = &st.offset;
        let hi = if o.luminance_unclamped {
            f64::INFINITY
        } else {
            1.0
        };
        let l = (o.scale * prev.lanes[o.lanes[2]].x + o.bias).clamp(0.0, hi);
        for s in texel.lanes.iter_mut().take(3) {
            s.x *= l;
            s.raw = st.out_enc.encode(s.x);
        }
    }
    fn sample2d(&self, st: &Compiled, level: usize, s: f64, t: f64) -> Word {
        let tex = st.spec.texture.as_ref().expect("checked: a 2D texture");
        let v = st.spec.sampler.sample_exact(tex, level, 0, s, t);
        let mut w = Word::from_exact(&st.out_enc, &v[..st.lanes as usize]);
        fill_missing(&mut w, st.lanes, &st.out_enc, true);
        w
    }
    fn sample_cube(&self, st: &Compiled, d: [f64; 3]) -> Word {
        let tex = st.spec.texture.as_ref().expect("checked: a cube map");
        let (f, s, t) = cube_face(d);
        let v = st.spec.sampler.sample_exact(tex, 0, f, s, t);
        let mut w = Word::from_exact(&st.out_enc, &v[..st.lanes as usize]);
        fill_missing(&mut w, st.lanes, &st.out_enc, true);
        w
    }
    fn pass(&self, c: [f64; 4], enc: &Encoding) -> Word {
        Word::from_exact(enc, &c.map(|v| v.clamp(0.0, 1.0)))
    }
    fn level(&self, lod: &Sample, tex: &Texture) -> usize {
        tex.nearest_level(lod.x)
    }
}

/// Bit-accurate arithmetic: raw coordinate words with `f` fraction bits.
pub(crate) struct FixedArith {
    pub coord: Encoding,
    pub dot_frac: u32,
    pub offset_frac: u32,
    /// Fraction bits of the level-of-detail input.
    pub lod_frac: u32,
    /// [`super::ShaderParams::convert_frac`].
    pub convert_frac: Option<u32>,
}

impl FixedArith {
    fn f(&self) -> u32 {
        self.coord.format.frac as u32
    }
    /// An exact intermediate rounded into the coordinate format.
    fn cast(&self, a: Acc) -> i64 {
        a.to_code(&self.coord)
    }
}

impl Arith for FixedArith {
    type V = i64;
    fn coord(&self, s: &Sample) -> i64 {
        s.raw
    }
    fn zero(&self) -> i64 {
        0
    }
    fn nonneg(&self, v: i64) -> bool {
        v >= 0
    }
    fn div(&self, a: i64, b: i64) -> i64 {
        if b == 0 {
            return 0;
        }
        let (mut p, mut d) = ((a as i128) << self.f(), b as i128);
        if d < 0 {
            p = -p;
            d = -d;
        }
        let q = div_round(p, d);
        self.coord.format.overflow(q, self.coord.overflow)
    }
    fn dot(&self, c: [i64; 3], prev: &Word, st: &Compiled, prev_st: &Compiled) -> i64 {
        let m = st.spec.program.mapping().unwrap_or_default();
        let n = vector_bits(
            m,
            &prev.raws::<4>(),
            &prev_st.out_enc,
            prev_st.lanes,
            self.dot_frac,
        );
        let p: i128 = (0..3).map(|k| c[k] as i128 * n[k] as i128).sum();
        self.cast(Acc::new(p, self.f() + self.dot_frac))
    }
    fn reflect(&self, n: [i64; 3], e: [i64; 3]) -> [i64; 3] {
        let f = self.f();
        let nn: i128 = n.iter().map(|&v| (v as i128).pow(2)).sum();
        let ne: i128 = n.iter().zip(&e).map(|(&a, &b)| a as i128 * b as i128).sum();
        if nn == 0 {
            return e.map(|v| self.cast(Acc::new(-(v as i128), f)));
        }
        std::array::from_fn(|k| {
            // 2 N_k (N.E) / (N.N): 3f fraction bits over 2f -> f, rounded once with - E
            let num = 2 * n[k] as i128 * ne - e[k] as i128 * nn;
            let q = div_round(num, nn);
            self.coord.format.overflow(q, self.coord.overflow)
        })
    }
    fn konst(&self, x: f64) -> i64 {
        self.coord.encode(x)
    }
    fn texel_coord(&self, prev: &Word, enc: &Encoding, lane: usize) -> i64 {
        self.cast(Acc::from_code(prev.lanes[lane].raw, enc))
    }
    fn offset(&self, s: i64, t: i64, prev: &Word, st: &Compiled, p: &Compiled) -> (i64, i64) {
        let o = &st.offset;
        let read = |l: usize| {
            let raw = prev.lanes[o.lanes[l]].raw;
            if o.twos_complement {
                twos_complement_bits(raw, &p.out_enc)
            } else {
                Acc::from_code(raw, &p.out_enc)
            }
        };
        let (ds, dt) = (read(0), read(1));
        let m = st.matrix_raw.map(|r| Acc::new(r as i128, self.offset_frac));
        let f = self.f();
        let s2 = Acc::new(s as i128, f).add(m[0].mul(ds)).add(m[2].mul(dt));
        let t2 = Acc::new(t as i128, f).add(m[1].mul(ds)).add(m[3].mul(dt));
        (self.cast(s2), self.cast(t2))
    }
    fn scale(&self, texel: &mut Word, prev: &Word, st: &Compiled, p: &Compiled) {
        let m = prev.lanes[st.offset.lanes[2]].raw;
        let of = self.offset_frac;
        if st.offset.luminance_unclamped {
            if let Some(()) = nv2a_luminance(texel, m, st, &p.out_enc, of, self.convert_frac) {
                return;
            }
        }
        let mag = Acc::from_code(m, &p.out_enc);
        let l = Acc::new(st.scale_raw[0] as i128, of)
            .mul(mag)
            .add(Acc::new(st.scale_raw[1] as i128, of));
        let l = if st.offset.luminance_unclamped {
            if l.lt(Acc::ZERO) {
                Acc::ZERO
            } else {
                l
            }
        } else {
            l.clamp(Acc::ZERO, Acc::new(1, 0))
        };
        for s in texel.lanes.iter_mut().take(3) {
            s.raw = Acc::from_code(s.raw, &st.out_enc)
                .mul(l)
                .to_code(&st.out_enc);
            s.x = st.out_enc.decode(s.raw);
        }
    }
    fn sample2d(&self, st: &Compiled, level: usize, s: i64, t: i64) -> Word {
        let tex = st.spec.texture.as_ref().expect("checked: a 2D texture");
        let plan = st.plan.as_ref().expect("planned with the texture");
        let r = st
            .spec
            .sampler
            .sample_bits(tex, level, 0, s, t, self.f(), plan);
        let mut w = Word::from_raw(&st.out_enc, &r[..st.lanes as usize]);
        fill_missing(&mut w, st.lanes, &st.out_enc, false);
        w
    }
    fn sample_cube(&self, st: &Compiled, d: [i64; 3]) -> Word {
        let tex = st.spec.texture.as_ref().expect("checked: a cube map");
        let f = self.f();
        let (face, s, t) = cube_face_bits(d, f);
        let plan = st.plan.as_ref().expect("planned with the texture");
        let r = st.spec.sampler.sample_bits(tex, 0, face, s, t, f, plan);
        let mut w = Word::from_raw(&st.out_enc, &r[..st.lanes as usize]);
        fill_missing(&mut w, st.lanes, &st.out_enc, false);
        w
    }
    fn level(&self, lod: &Sample, tex: &Texture) -> usize {
        // floor(lod + 1/2): add half a level and drop the fraction bits
        let f = self.lod_frac;
        let half = if f == 0 { 0 } else { 1i64 << (f - 1) };
        let k = (lod.raw + half) >> f;
        (k.max(0) as usize).min(tex.levels() - 1)
    }
    fn pass(&self, c: [i64; 4], enc: &Encoding) -> Word {
        let f = self.f();
        let r = c.map(|v| {
            let v = Acc::new(v as i128, f).clamp(Acc::ZERO, Acc::new(1, 0));
            match self.convert_frac {
                // v_k = floor(v 2^k); c = ((v_k + 1)(2^n - 1)) >> k: at most 2^n - 1
                // (v_k <= 2^k), so no clamp after it.
                Some(k) => {
                    let vk = if k >= v.frac {
                        v.raw << (k - v.frac)
                    } else {
                        v.raw >> (v.frac - k)
                    };
                    let top = (1i128 << enc.width()) - 1;
                    (((vk + 1) * top) >> k) as i64
                }
                None => v.to_code(enc),
            }
        });
        Word::from_raw(enc, &r)
    }
}

/// Per-fragment state: each stage's coordinates, dot product and result.
pub(crate) struct Fragment<V> {
    pub results: Vec<Word>,
    pub live: bool,
    pub depth: Option<V>,
}

/// Run every stage on one fragment: `ins[i]` are stage i's (s, t, r, q).
pub(crate) fn run<A: Arith>(a: &A, u: &TextureShader, ins: &[Word]) -> Fragment<A::V> {
    let n = u.stages.len();
    let coords: Vec<[A::V; 4]> = (0..n)
        .map(|i| std::array::from_fn(|k| a.coord(&ins[i].lanes[k])))
        .collect();
    let lod = u.params().lod.map(|_| &ins[n].lanes[0]);
    let mut dots: Vec<A::V> = vec![a.zero(); n];
    let mut results: Vec<Word> = Vec::with_capacity(n);
    let mut live = true;
    let mut depth = None;
    // a DIFFUSE_CUBE_MAP stage's lookup needs the dot of the stage after it: deferred
    let mut diffuse: Option<usize> = None;
    for i in 0..n {
        let st = &u.stages[i];
        let c = coords[i];
        let zero = Word::from_raw(&st.out_enc, &[0; 4]);
        let prog = if st.broken.is_some() {
            Program::None
        } else {
            st.spec.program
        };
        let prev = prog.prev().map(|p| (&results[p], &u.stages[p]));
        if prog.is_dot() {
            let (pw, ps) = prev.expect("checked: a dot product reads an earlier stage");
            dots[i] = a.dot([c[0], c[1], c[2]], pw, st, ps);
        }
        let out = match prog {
            Program::None | Program::DotProduct { .. } => zero,
            Program::Texture2d => {
                let level = match (lod, &st.spec.texture) {
                    (Some(l), Some(t)) => a.level(l, t),
                    _ => 0,
                };
                a.sample2d(st, level, a.div(c[0], c[3]), a.div(c[1], c[3]))
            }
            Program::TextureCube => a.sample_cube(st, [c[0], c[1], c[2]]),
            Program::PassThrough => a.pass(c, &st.out_enc),
            Program::CullFragment { gequal } => {
                for k in 0..4 {
                    if a.nonneg(c[k]) != gequal[k] {
                        live = false;
                    }
                }
                zero
            }
            Program::OffsetTexture2d { .. } | Program::OffsetTexture2dScale { .. } => {
                let (pw, ps) = prev.expect("checked");
                let (s, t) = a.offset(c[0], c[1], pw, st, ps);
                let mut w = a.sample2d(st, 0, s, t);
                if matches!(prog, Program::OffsetTexture2dScale { .. }) {
                    a.scale(&mut w, pw, st, ps);
                }
                w
            }
            Program::DependentAr { .. } | Program::DependentGb { .. } => {
                let (pw, ps) = prev.expect("checked");
                let (ls, lt) = if matches!(prog, Program::DependentAr { .. }) {
                    (3, 0)
                } else {
                    (1, 2)
                };
                let s = a.texel_coord(pw, &ps.out_enc, ls);
                let t = a.texel_coord(pw, &ps.out_enc, lt);
                a.sample2d(st, 0, s, t)
            }
            Program::DotProductTexture2d { .. } => a.sample2d(st, 0, dots[i - 1], dots[i]),
            Program::DotProductTextureCube { .. } => {
                a.sample_cube(st, [dots[i - 2], dots[i - 1], dots[i]])
            }
            Program::DotProductDiffuseCube { .. } => {
                diffuse = Some(i);
                zero
            }
            Program::DotProductReflectCube { .. }
            | Program::DotProductConstEyeReflectCube { .. } => {
                let nv = [dots[i - 2], dots[i - 1], dots[i]];
                let e = match prog {
                    Program::DotProductConstEyeReflectCube { eye, .. } => eye.map(|x| a.konst(x)),
                    _ => [coords[i - 2][3], coords[i - 1][3], c[3]],
                };
                if let Some(d) = diffuse.take() {
                    if d == i - 1 {
                        results[d] = a.sample_cube(&u.stages[d], nv);
                    }
                }
                a.sample_cube(st, a.reflect(nv, e))
            }
            Program::DotProductDepthReplace { .. } => {
                depth = Some(a.div(dots[i - 1], dots[i]));
                zero
            }
        };
        results.push(out);
    }
    Fragment {
        results,
        live,
        depth,
    }
}

/// The colour converter ([`super::ShaderParams::convert_frac`]): `xk = floor(x 2^k)` of a
/// value `x >= 0` read as the top of its step, `((min(xk, 2^k) + 1) top) >> k`, at most `top`.
pub(super) fn top_of_step(xk: i128, k: u32, top: i128) -> i128 {
    ((xk.clamp(0, 1i128 << k) + 1) * top) >> k
}

/// The NV2A's BUMPENVMAPLUMINANCE product (hypothesis 20, frame `BumpEnvMapLuminance`) on
/// unsigned unit codes: `l = scale m / (2^wm - 1) + bias` with the magnitude code `m` read
/// exactly, clamped at 0 only, and each RGB code `c` of the texel becomes, with the colour
/// converter (`conv = Some(k)`), `top_of_step(floor(c l 2^k / (2^w - 1)), k)` (the product
/// `x = (c / (2^w - 1)) l` exact, truncated to k fraction bits); without it
/// `min(floor(c l), 2^w - 1)`. Each an integer quotient. `None` (the generic path) for
/// other codecs.
fn nv2a_luminance(
    texel: &mut Word,
    m: i64,
    st: &Compiled,
    mag_enc: &crate::Encoding,
    of: u32,
    conv: Option<u32>,
) -> Option<()> {
    use crate::Codec;
    let unit = |e: &crate::Encoding| e.codec == Codec::UnitUnsigned && !e.format.signed;
    if !(unit(mag_enc) && unit(&st.out_enc)) {
        return None;
    }
    let nm = (1i128 << mag_enc.format.width) - 1;
    let top = (1i128 << st.out_enc.format.width) - 1;
    // l = num / (nm 2^of)
    let num = (st.scale_raw[0] as i128 * m as i128 + st.scale_raw[1] as i128 * nm).max(0);
    let den = nm << of;
    for s in texel.lanes.iter_mut().take(3) {
        let c = s.raw as i128;
        s.raw = match conv {
            Some(k) => top_of_step(
                c.saturating_mul(num).saturating_mul(1 << k) / (top * den),
                k,
                top,
            ),
            None => (c.saturating_mul(num) / den).clamp(0, top),
        } as i64;
        s.x = st.out_enc.decode(s.raw);
    }
    Some(())
}
