//! The geometry engine's per-vertex attributes and the rasterizer's attribute interpolator.
//!
//! Attributes are computed per vertex in f64 (world space), sent to the rasterizer in their
//! configured encoding, and interpolated per fragment with the rasterizer's perspective-correct
//! barycentrics. In bit-accurate mode the vertex values are rounded to the encoding's grid
//! (what the triangle packet carries) and the interpolated value is encoded again (the
//! interpolator's output register); wrap-around (for repeating texture coordinates) applies
//! only to the interpolated value, so a triangle spanning a wrap boundary interpolates
//! correctly. In exact mode neither rounding happens.

use super::frames;
use crate::config::{AttrSource, AttributeConfig, VecFrame};
use crate::scene::{Light, Scene};
use bumpsim_hw::{Codec, Encoding, Mode, Word};
use glam::{DMat3, DVec2, DVec3, DVec4};

/// A vertex's tangent frame in world space: T along Pu, B completing a frame that follows the
/// parameterisation's handedness, N the shading normal.
#[derive(Debug, Clone, Copy)]
pub struct Frame {
    pub t: DVec3,
    pub b: DVec3,
    pub n: DVec3,
}

impl Frame {
    pub fn new(n: DVec3, pu: DVec3, pv: DVec3) -> Frame {
        let n = n.normalize();
        let t = pu - pu.dot(n) * n;
        let t = if t.length_squared() > 1e-24 {
            t.normalize()
        } else {
            n.any_orthonormal_vector()
        };
        let mut b = n.cross(t);
        if pu.cross(pv).dot(n) < 0.0 {
            b = -b;
        }
        Frame { t, b, n }
    }
    pub fn to_local(&self, v: DVec3) -> [f64; 3] {
        [v.dot(self.t), v.dot(self.b), v.dot(self.n)]
    }
}

/// Values of every attribute, and the clip-space positions.
pub struct VertexData {
    pub clip: Vec<DVec4>,
    /// `values[attribute][vertex]`, or `[triangle]` for per-triangle attributes; lanes beyond
    /// the attribute's count are 0.
    pub values: Vec<Vec<[f64; 4]>>,
    /// Whether each attribute is per triangle.
    pub flat: Vec<bool>,
}

/// Run the geometry engine over the scene's vertices and triangles.
pub fn compute(scene: &Scene, attrs: &[AttributeConfig]) -> VertexData {
    let m = scene.model;
    let m3 = DMat3::from_mat4(m);
    let nm = m3.inverse().transpose();
    let aspect = scene.width as f64 / scene.height as f64;
    let vp = scene.camera.proj(aspect) * scene.camera.view();
    let verts = &scene.mesh.vertices;
    let clip: Vec<DVec4> = verts.iter().map(|v| vp * m * v.pos.extend(1.0)).collect();
    // world position and tangent frame of every vertex
    let world: Vec<(DVec3, DVec3, DVec3, DVec3)> = verts
        .iter()
        .map(|v| {
            (
                m.transform_point3(v.pos),
                nm * v.normal,
                m3 * v.pu,
                m3 * v.pv,
            )
        })
        .collect();
    let to_object = m3.inverse();
    let view_rot = DMat3::from_mat4(scene.camera.view());
    let at = |src: AttrSource,
              (p, n, pu, pv): (DVec3, DVec3, DVec3, DVec3),
              uv: [f64; 2]|
     -> [f64; 4] {
        let frame = Frame::new(n, pu, pv);
        let view = scene.camera.view_dir(p);
        let local = |f: VecFrame, d: DVec3| -> [f64; 4] {
            let x = match f {
                VecFrame::Tangent => frame.to_local(d),
                VecFrame::Object => (to_object * d).normalize_or_zero().to_array(),
                VecFrame::World => d.to_array(),
            };
            [x[0], x[1], x[2], 0.0]
        };
        match src {
            AttrSource::Uv => [uv[0], uv[1], 0.0, 0.0],
            AttrSource::LightDir {
                light, frame: f, ..
            } => local(f, scene.lights[light].dir_from(p)),
            AttrSource::HalfVec {
                light, frame: f, ..
            } => {
                let l = scene.lights[light].dir_from(p);
                local(f, (l + view).normalize_or_zero())
            }
            AttrSource::BlendEnable { light } => {
                let faces = frame.n.dot(scene.lights[light].dir_from(p)) > 0.0;
                [f64::from(u8::from(faces)), 0.0, 0.0, 0.0]
            }
            // per triangle: see `lod` and `frames::alignment`; per vertex from the triangles
            // around it: `vertex_lods`
            AttrSource::Lod { .. }
            | AttrSource::Alignment { .. }
            | AttrSource::VertexLod { .. } => [0.0; 4],
            AttrSource::Normal => lanes3(frame.n),
            AttrSource::BlinnAxis { axis, rule } => {
                lanes3(frames::blinn_axis(axis, frame.n, pu, pv, rule))
            }
            AttrSource::MainDirection => lanes3(frames::main_direction(frame.n, pu, pv)),
            AttrSource::Quaternion => frames::quaternion_frame(frame.n, pu, pv, Default::default())
                .0
                .to_array(),
            AttrSource::QuatScale { rule } => frames::quaternion_frame(frame.n, pu, pv, rule).1,
            AttrSource::Uvq => [uv[0], uv[1], 0.0, 1.0],
            AttrSource::TangentRow { row } => {
                let r = usize::from(row).min(2);
                [frame.t[r], frame.b[r], frame.n[r], 0.0]
            }
            AttrSource::ViewDir { frame: f } => local(f, view),
            AttrSource::SphereMap => {
                let n = (view_rot * frame.n).normalize_or_zero();
                [n.x / 2.0 + 0.5, n.y / 2.0 + 0.5, 0.0, 1.0]
            }
            AttrSource::Gouraud {
                ambient,
                all_lights,
            } => {
                let a = if ambient {
                    DVec3::from(scene.material.ambient)
                } else {
                    DVec3::ZERO
                };
                let c = a + gouraud(scene, frame.n, p, view, all_lights);
                [c.x, c.y, c.z, 0.0]
            }
        }
    };
    let values = attrs
        .iter()
        .map(|a| {
            if let AttrSource::Lod { size } = a.source {
                let px = DVec2::new(f64::from(scene.width), f64::from(scene.height));
                scene
                    .mesh
                    .triangles
                    .iter()
                    .map(|t| {
                        [
                            lod(
                                t.map(|i| (&clip[i as usize], verts[i as usize].uv)),
                                px,
                                size,
                            ),
                            0.0,
                            0.0,
                            0.0,
                        ]
                    })
                    .collect()
            } else if let AttrSource::VertexLod { size } = a.source {
                let px = DVec2::new(f64::from(scene.width), f64::from(scene.height));
                vertex_lods(&scene.mesh, &clip, px, size)
                    .into_iter()
                    .map(|l| [l, 0.0, 0.0, 0.0])
                    .collect()
            } else if let AttrSource::Alignment { column, rule } = a.source {
                scene
                    .mesh
                    .triangles
                    .iter()
                    .map(|t| {
                        let w = t.map(|i| world[i as usize]);
                        let n = (w[0].1.normalize_or_zero()
                            + w[1].1.normalize_or_zero()
                            + w[2].1.normalize_or_zero())
                        .normalize_or_zero();
                        let mean = (
                            (w[0].2 + w[1].2 + w[2].2) / 3.0,
                            (w[0].3 + w[1].3 + w[2].3) / 3.0,
                        );
                        lanes3(frames::alignment(
                            column,
                            w.map(|x| x.0),
                            t.map(|i| verts[i as usize].uv),
                            n,
                            mean,
                            rule,
                        ))
                    })
                    .collect()
            } else if a.source.per_triangle() {
                scene
                    .mesh
                    .triangles
                    .iter()
                    .map(|t| {
                        let c = t.iter().fold(
                            (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO, DVec3::ZERO),
                            |s, &i| {
                                let w = world[i as usize];
                                (s.0 + w.0 / 3.0, s.1 + w.1, s.2 + w.2, s.3 + w.3)
                            },
                        );
                        at(a.source, c, [0.0; 2])
                    })
                    .collect()
            } else {
                verts
                    .iter()
                    .zip(&world)
                    .map(|(v, w)| at(a.source, *w, [v.uv.x, v.uv.y]))
                    .collect()
            }
        })
        .collect();
    let flat = attrs.iter().map(|a| a.source.per_triangle()).collect();
    VertexData { clip, values, flat }
}

/// A 3-vector as attribute lanes.
fn lanes3(v: DVec3) -> [f64; 4] {
    [v.x, v.y, v.z, 0.0]
}

/// Per-vertex level of detail of a `size` x `size` texture ([`AttrSource::VertexLod`]): at
/// each vertex `1/2 log2(Σ uv area size^2 / Σ screen area)` over the triangles that use it and
/// lie in front of the eye with area on screen and in uv, clamped to `[0, log2 size]`; 0 where
/// none does. `clip` holds every vertex's clip position, `px` the image size in pixels.
pub fn vertex_lods(mesh: &crate::scene::Mesh, clip: &[DVec4], px: DVec2, size: u32) -> Vec<f64> {
    let mut sums = vec![(0.0f64, 0.0f64); mesh.vertices.len()];
    for t in &mesh.triangles {
        let corners = t.map(|i| (&clip[i as usize], mesh.vertices[i as usize].uv));
        let Some((texels, screen)) = areas(corners, px, size) else {
            continue;
        };
        for &i in t {
            let e = &mut sums[i as usize];
            e.0 += texels;
            e.1 += screen;
        }
    }
    sums.into_iter()
        .map(|(texels, screen)| {
            if screen > 0.0 {
                lambda(texels, screen, size)
            } else {
                0.0
            }
        })
        .collect()
}

/// Per-triangle level of detail of a `size` x `size` texture ([`AttrSource::Lod`]): `1/2
/// log2(uv area size^2 / screen area)` clamped to `[0, log2 size]`; `tri` holds each vertex's
/// clip position and uv, `px` the image size in pixels. 0 if a vertex is at or behind the eye
/// (`w <= 0`) or the triangle has no area on screen or in uv.
pub fn lod(tri: [(&DVec4, DVec2); 3], px: DVec2, size: u32) -> f64 {
    areas(tri, px, size).map_or(0.0, |(texels, screen)| lambda(texels, screen, size))
}

/// A triangle's area in texels of a `size` x `size` map and on screen in pixels; `None` if a
/// vertex is at or behind the eye (`w <= 0`) or either area is zero or not finite.
fn areas(tri: [(&DVec4, DVec2); 3], px: DVec2, size: u32) -> Option<(f64, f64)> {
    if tri.iter().any(|(c, _)| c.w.is_nan() || c.w <= 0.0) {
        return None;
    }
    let s = tri.map(|(c, _)| (DVec2::new(c.x, c.y) / c.w + 1.0) * 0.5 * px);
    let area = |a: DVec2, b: DVec2, c: DVec2| ((b - a).perp_dot(c - a) / 2.0).abs();
    let screen = area(s[0], s[1], s[2]);
    let texels = area(tri[0].1, tri[1].1, tri[2].1) * f64::from(size) * f64::from(size);
    (screen > 0.0 && texels > 0.0 && screen.is_finite() && texels.is_finite())
        .then_some((texels, screen))
}

/// `1/2 log2(texels / screen)` clamped to `[0, log2 size]`.
fn lambda(texels: f64, screen: f64, size: u32) -> f64 {
    let max = f64::from(size.max(1)).log2();
    (0.5 * (texels / screen).log2()).clamp(0.0, max)
}

/// The Gouraud colour at a vertex: the lights that do not take part in bump mapping (or all
/// lights), evaluated with the vertex normal (Ernst et al. §5.4.1).
pub fn gouraud(scene: &Scene, n: DVec3, p: DVec3, view: DVec3, all_lights: bool) -> DVec3 {
    let mat = &scene.material;
    let mut c = DVec3::ZERO;
    for light in scene.lights.iter().filter(|l| all_lights || !l.bump) {
        c += light_term(
            light,
            n,
            p,
            view,
            mat.diffuse.into(),
            mat.specular.into(),
            mat.shininess,
        );
    }
    c
}

/// One light's diffuse and specular contribution (Blinn-Phong).
pub fn light_term(
    light: &Light,
    n: DVec3,
    p: DVec3,
    view: DVec3,
    kd: DVec3,
    ks: DVec3,
    shininess: f64,
) -> DVec3 {
    let l = light.dir_from(p);
    let nl = n.dot(l);
    if nl <= 0.0 {
        return DVec3::ZERO;
    }
    let h = (l + view).normalize_or_zero();
    light.color() * light.attenuation(p) * (kd * nl + ks * n.dot(h).max(0.0).powf(shininess))
}

/// Round a value to an encoding's grid without applying its overflow mode.
pub fn to_grid(enc: &Encoding, x: f64) -> f64 {
    match enc.codec {
        Codec::Fixed => {
            let s = enc.format.lsb();
            (x / s).round() * s
        }
        _ => enc.decode(enc.encode(x)),
    }
}

/// A per-triangle attribute at a fragment: the triangle's value, rounded to the encoding's
/// grid in bit-accurate mode.
pub fn flat(mode: Mode, enc: &Encoding, lanes: usize, v: &[f64; 4]) -> Word {
    Word::for_mode(mode, enc, &v[..lanes])
}

/// Interpolate one attribute at a fragment.
pub fn interpolate(
    mode: Mode,
    enc: &Encoding,
    lanes: usize,
    v: [&[f64; 4]; 3],
    bary: [f64; 3],
) -> Word {
    let snap = |x: &[f64; 4]| std::array::from_fn(|l| to_grid(enc, x[l]));
    match mode {
        Mode::Exact => interpolate_snapped(mode, enc, lanes, v, bary),
        Mode::BitAccurate => {
            let g: [[f64; 4]; 3] = v.map(snap);
            interpolate_snapped(mode, enc, lanes, [&g[0], &g[1], &g[2]], bary)
        }
    }
}

/// [`interpolate`] of vertex values already on the encoding's grid in bit-accurate mode
/// ([`VertexData::snapped`]): the interpolator's inputs are the vertex words.
#[inline]
pub fn interpolate_snapped(
    mode: Mode,
    enc: &Encoding,
    lanes: usize,
    v: [&[f64; 4]; 3],
    bary: [f64; 3],
) -> Word {
    let mut xs = [0.0; 4];
    // one sum in both modes: a fold of the three products from -0.0 (the bit-accurate
    // mode's former `sum()`) is this sum bit for bit
    for (l, x) in xs.iter_mut().enumerate().take(lanes) {
        *x = bary[0] * v[0][l] + bary[1] * v[1][l] + bary[2] * v[2][l];
    }
    Word::for_mode(mode, enc, &xs[..lanes])
}

/// The raw word of a vertex value that the fixed-point interpolator reads: for fixed point the
/// value on the grid as an integer of LSBs, without overflow (uv beyond [0, 1) stays
/// unwrapped until the interpolated sum is cast, as in [`interpolate`]); for the unit codecs
/// the encoded code (their values lie in range).
pub fn vertex_code(enc: &Encoding, x: f64) -> i64 {
    match enc.codec {
        Codec::Fixed => {
            let r = (x * bumpsim_hw::format::pow2(enc.format.frac as i32)).round();
            if r.is_finite() {
                r.clamp(-(2f64.powi(62)), 2f64.powi(62)) as i64
            } else {
                0
            }
        }
        _ => enc.encode(x),
    }
}

/// The fixed-point interpolator's weights of a fragment (`bits` 1 to 62): `q0`, `q1` its
/// first two barycentrics times `2^bits` rounded half away from zero and clamped to
/// `[0, 2^bits]` (NaN: 0), `q2 = 2^bits - q0 - q1`. The same words as
/// `(b 2^bits).round().clamp(0, 2^bits)`, without the library call `f64::round` is on the
/// baseline target: the truncation and the remainder, both exact.
#[inline]
pub fn fixed_weights(bary: [f64; 3], bits: u32) -> [i64; 3] {
    let one = 1i64 << bits;
    let q = |b: f64| {
        // beyond [-1, 2^bits + 1] the clamp below decides alone; NaN stays NaN
        let x = (b * one as f64).clamp(-1.0, one as f64 + 1.0);
        if x.is_nan() {
            return 0;
        }
        let t = x as i64; // toward zero
        let r = x - t as f64; // exact, in (-1, 1)
        let rounded = t + i64::from(r >= 0.5) - i64::from(r <= -0.5);
        rounded.clamp(0, one)
    };
    let (q0, q1) = (q(bary[0]), q(bary[1]));
    [q0, q1, one - q0 - q1]
}

/// The fixed-point interpolator (`Interpolator::Fixed`): the fragment's weights `w`
/// ([`fixed_weights`]: barycentrics rounded to `bits` fraction bits, computed once per fragment
/// for all its attributes), `raw = cast(sum w_k c_k >> bits)` in the encoding's rounding and
/// overflow modes. The weights sum to one, so the codes' affine readings (every codec of the
/// project) interpolate correctly.
pub fn interpolate_weighted(
    enc: &Encoding,
    lanes: usize,
    codes: [&[i64; 4]; 3],
    w: [i64; 3],
    bits: u32,
) -> Word {
    let int = bumpsim_hw::Format {
        frac: 0,
        ..enc.format
    };
    let mut raws = [0i64; 4];
    for (l, r) in raws.iter_mut().enumerate().take(lanes) {
        *r = weighted_lane(enc, int, codes.map(|c| c[l]), w, bits);
    }
    Word::from_raw(enc, &raws[..lanes])
}

/// One lane of [`interpolate_weighted`]: the raw word of the vertex codes `c` under the
/// weights `w` of `bits` fraction bits, cast by `int` (the encoding's format without fraction
/// bits) in the encoding's rounding and overflow modes.
#[inline]
pub fn weighted_lane(
    enc: &Encoding,
    int: bumpsim_hw::Format,
    c: [i64; 3],
    w: [i64; 3],
    bits: u32,
) -> i64 {
    // in i64 when the products and their sum fit (the common case: codes within 31 bits),
    // else in i128; the same sum either way
    let narrow = (0..3).try_fold(0i64, |s, k| {
        w[k].checked_mul(c[k]).and_then(|p| s.checked_add(p))
    });
    let sum = narrow.map_or_else(
        || (0..3).map(|k| w[k] as i128 * c[k] as i128).sum(),
        i128::from,
    );
    int.cast(sum, bits, enc.quant, enc.overflow)
}

/// [`weighted_lane`] of one encoding and weight width, planned once: an `i64` sum is cast by a
/// [`bumpsim_hw::arith::Writer`] (a multiply, shifts and a range test where `Format::cast`
/// matches on the rounding and overflow modes per value); a sum beyond `i64` by
/// `weighted_lane` itself. The same words (`Writer::write` is `Acc::to_code`, which for a
/// fixed-point encoding is `Format::cast`).
pub struct WeightedCast {
    enc: Encoding,
    int: bumpsim_hw::Format,
    bits: u32,
    write: bumpsim_hw::arith::Writer,
}

impl WeightedCast {
    pub fn new(enc: &Encoding, bits: u32) -> Self {
        let int = bumpsim_hw::Format {
            frac: 0,
            ..enc.format
        };
        let int_enc = Encoding {
            format: int,
            codec: bumpsim_hw::Codec::Fixed,
            ..*enc
        };
        WeightedCast {
            enc: *enc,
            int,
            bits,
            write: bumpsim_hw::arith::Writer::new(bits, &int_enc),
        }
    }
    /// [`weighted_lane`] of the vertex codes `c` under the weights `w`.
    #[inline]
    pub fn lane(&self, c: [i64; 3], w: [i64; 3]) -> i64 {
        let narrow = (0..3).try_fold(0i64, |s, k| {
            w[k].checked_mul(c[k]).and_then(|p| s.checked_add(p))
        });
        match narrow {
            Some(sum) => self.write.write(sum),
            None => weighted_lane(&self.enc, self.int, c, w, self.bits),
        }
    }
}

/// Gates of the fixed-point interpolator for `attrs` (per-vertex ones): per lane, two
/// multipliers and adders in the form `c0 + q1 (c1 - c0) + q2 (c2 - c0)` and an output
/// register.
pub fn interpolator_gates(
    attrs: &[AttributeConfig],
    bits: u32,
    t: &bumpsim_hw::CostTable,
) -> bumpsim_hw::GateBudget {
    let mut g = bumpsim_hw::GateBudget::new();
    for a in attrs.iter().filter(|a| !a.source.per_triangle()) {
        let (n, w) = (a.source.lanes() as u32, a.enc.width());
        g.add(
            format!("{} difference adders {}", a.name, w + 1),
            2 * n,
            t.adder(w + 1),
        );
        g.add(
            format!("{} weight multipliers {}x{bits}", a.name, w + 1),
            2 * n,
            t.multiplier(w + 1, bits),
        );
        g.add(
            format!("{} sum adders {}", a.name, w + bits + 2),
            2 * n,
            t.adder(w + bits + 2),
        );
        g.add(
            format!("{} output register {}", a.name, n * w),
            1,
            t.register(n * w),
        );
    }
    g
}

impl VertexData {
    /// The per-vertex values as the fixed-point interpolator's vertex words
    /// ([`vertex_code`]).
    pub fn codes(&self, attrs: &[AttributeConfig]) -> Vec<Vec<[i64; 4]>> {
        self.per_vertex(attrs, vertex_code)
    }

    /// The per-vertex values on each attribute's grid (what bit-accurate interpolation reads).
    pub fn snapped(&self, attrs: &[AttributeConfig]) -> Vec<Vec<[f64; 4]>> {
        self.per_vertex(attrs, to_grid)
    }

    /// `f` of every lane of every per-vertex value, by attribute; per-triangle attributes are
    /// left empty ([`flat`] reads their values).
    fn per_vertex<T>(
        &self,
        attrs: &[AttributeConfig],
        f: impl Fn(&Encoding, f64) -> T,
    ) -> Vec<Vec<[T; 4]>> {
        self.values
            .iter()
            .zip(attrs)
            .zip(&self.flat)
            .map(|((vals, a), &flat)| {
                if flat {
                    Vec::new()
                } else {
                    vals.iter()
                        .map(|x| std::array::from_fn(|l| f(&a.enc, x[l])))
                        .collect()
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Mesh, Vertex};
    use bumpsim_hw::{Format, Overflow, Quant};
    use proptest::prelude::*;

    /// [`fixed_weights`]'s first weight as the interpolator first computed it.
    fn weight_by_round(b: f64, bits: u32) -> i64 {
        let one = 1i64 << bits;
        (b * one as f64).round().clamp(0.0, one as f64) as i64
    }

    /// The planned cast is `weighted_lane`: every rounding and overflow mode, signed and
    /// unsigned widths 1 to 40, weights of 1 to 62 bits, codes over the format's range and
    /// beyond it (sums past every range, and past `i64`).
    #[test]
    fn the_planned_weighted_cast_is_weighted_lane() {
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        let mut checked = 0;
        for quant in Quant::ALL {
            for overflow in Overflow::ALL {
                for width in 1..=40u8 {
                    for signed in [false, true] {
                        let enc = Encoding {
                            format: Format {
                                signed,
                                width,
                                frac: width / 2,
                            },
                            codec: Codec::Fixed,
                            quant,
                            overflow,
                        };
                        let int = Format {
                            frac: 0,
                            ..enc.format
                        };
                        for bits in [1u32, 4, 8, 16, 24, 31, 47, 62] {
                            let cast = WeightedCast::new(&enc, bits);
                            let one = 1i64 << bits;
                            for _ in 0..40 {
                                let r = next();
                                let span = 1i64 << (width as u32 + 1 + (r % 4) as u32 * 6).min(62);
                                let c: [i64; 3] = std::array::from_fn(|_| {
                                    (next() % (2 * span as u64)) as i64 - span
                                });
                                let q0 = (next() % (one as u64 + 1)) as i64;
                                let q1 = (next() % ((one - q0) as u64 + 1)) as i64;
                                let w = [q0, q1, one - q0 - q1];
                                assert_eq!(
                                    cast.lane(c, w),
                                    weighted_lane(&enc, int, c, w, bits),
                                    "{enc:?} bits {bits} codes {c:?} weights {w:?}"
                                );
                                checked += 1;
                            }
                        }
                    }
                }
            }
        }
        assert_eq!(checked, 8 * 4 * 40 * 2 * 8 * 40);
    }

    #[test]
    fn fixed_weights_round_half_away_and_clamp_as_f64_round_does() {
        for bits in [1, 4, 8, 16, 30, 52, 62] {
            let one = (1u64 << bits) as f64;
            let mut xs = vec![
                0.0,
                -0.0,
                1.0,
                -1.0,
                2.0,
                f64::NAN,
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::MIN_POSITIVE,
                f64::EPSILON,
                1e300,
                -1e300,
            ];
            // every half and its neighbours, near 0, near 1 and inside
            for k in [-3i64, -2, -1, 0, 1, 2, 3, 1 << bits.min(20)] {
                let h = (k as f64 + 0.5) / one;
                xs.extend([h, h.next_up(), h.next_down(), 1.0 + h, -h]);
            }
            for b in xs {
                let w = fixed_weights([b, b, 0.0], bits);
                assert_eq!(w[0], weight_by_round(b, bits), "{b:e} at {bits} bits");
                assert_eq!(w[2], (1i64 << bits) - w[0] - w[1]);
            }
        }
    }

    proptest! {
        #[test]
        fn fixed_weights_are_the_rounded_ones(b0 in -2.0f64..3.0, b1 in any::<f64>(), bits in 1u32..=62) {
            let w = fixed_weights([b0, b1, 0.0], bits);
            prop_assert_eq!(w[0], weight_by_round(b0, bits));
            prop_assert_eq!(w[1], weight_by_round(b1, bits));
        }

        /// The fixed-point interpolator's sum, in i64 where it fits, is the i128 sum cast.
        #[test]
        fn interpolate_weighted_is_the_wide_sum_cast(
            codes in prop::array::uniform3(prop::array::uniform4(prop_oneof![
                -(1i64 << 20)..(1i64 << 20), -(1i64 << 62)..(1i64 << 62)])),
            q0 in 0i64..=1 << 30, q1 in 0i64..=1 << 30, bits in 4u32..=30,
            signed in any::<bool>(), width in 2u32..=32,
        ) {
            let one = 1i64 << bits;
            let (q0, q1) = (q0 % (one + 1), q1 % (one + 1));
            let w = [q0, q1, one - q0 - q1];
            let enc = Encoding::fixed(Format::new(signed, width, width / 2).unwrap());
            let word = interpolate_weighted(&enc, 4, [&codes[0], &codes[1], &codes[2]], w, bits);
            let int = Format { frac: 0, ..enc.format };
            for (l, lane) in word.lanes.iter().enumerate() {
                let sum: i128 = (0..3).map(|k| w[k] as i128 * codes[k][l] as i128).sum();
                prop_assert_eq!(lane.raw, int.cast(sum, bits, enc.quant, enc.overflow));
            }
        }
    }

    #[test]
    fn lod_is_half_the_log2_of_texel_over_pixel_area() {
        // clip = NDC (w = 1) on a 100 x 100 image: the triangle (0,0) (0.5,0) (0,0.5) in NDC
        // covers 25 x 25 / 2 pixels; uv (0,0) (0.5,0) (0,0.5) on a 200-texel map covers
        // 100 x 100 / 2 texels: 16x the area, LOD 2
        let c = [
            DVec4::new(0.0, 0.0, 0.5, 1.0),
            DVec4::new(0.5, 0.0, 0.5, 1.0),
            DVec4::new(0.0, 0.5, 0.5, 1.0),
        ];
        let px = DVec2::splat(100.0);
        fn tri(c: &[DVec4; 3]) -> [(&DVec4, DVec2); 3] {
            let uv = [DVec2::ZERO, DVec2::new(0.5, 0.0), DVec2::new(0.0, 0.5)];
            [(&c[0], uv[0]), (&c[1], uv[1]), (&c[2], uv[2])]
        }
        assert!((lod(tri(&c), px, 200) - 2.0).abs() < 1e-12);
        // magnified: clamped to 0; at most log2(size)
        assert_eq!(lod(tri(&c), px, 10), 0.0);
        assert!((lod(tri(&c), DVec2::splat(1.0), 256) - 8.0).abs() < 1e-12);
        // the same triangle twice as far (w = 2) covers a quarter of the pixels: LOD 3
        let far = c.map(|v| DVec4::new(v.x, v.y, v.z, 2.0));
        assert!((lod(tri(&far), px, 200) - 3.0).abs() < 1e-12);
        // a vertex behind the eye, or no area: 0
        let mut behind = c;
        behind[1].w = -1.0;
        assert_eq!(lod(tri(&behind), px, 200), 0.0);
        let flat = [c[0], c[0], c[2]];
        assert_eq!(lod(tri(&flat), px, 200), 0.0);
    }

    /// The per-vertex LOD pools the areas of the triangles around each vertex: a vertex of two
    /// triangles at LOD 2 and 3 (16x and 64x texels per pixel, equal screen areas) gets
    /// `1/2 log2(40)`, one of only the first 2; a vertex of no triangle, or only of one behind
    /// the eye, 0.
    #[test]
    fn vertex_lod_pools_the_triangles_around_the_vertex() {
        let v = |x: f64, y: f64, u: f64, w: f64| Vertex {
            pos: DVec3::new(x, y, 0.0),
            normal: DVec3::Z,
            uv: DVec2::new(u, w),
            pu: DVec3::X,
            pv: DVec3::Y,
        };
        // vertices 0..3 in NDC on a 100 x 100 image; triangle A (0, 1, 2) maps uv 1:1 at
        // 200 texels (LOD 2: see the test above); triangle B (1, 3, 2) has 4x the uv area
        // (LOD 3); vertex 4 is used by no triangle, vertex 5 only by one behind the eye
        let mesh = Mesh {
            vertices: vec![
                v(0.0, 0.0, 0.0, 0.0),
                v(0.5, 0.0, 0.5, 0.0),
                v(0.0, 0.5, 0.0, 0.5),
                v(0.5, 0.5, 1.0, 1.5),
                v(0.0, 0.0, 0.0, 0.0),
                v(0.0, 0.0, 0.0, 0.0),
            ],
            triangles: vec![[0, 1, 2], [1, 3, 2], [5, 1, 2]],
        };
        let mut clip: Vec<DVec4> = mesh
            .vertices
            .iter()
            .map(|v| DVec4::new(v.pos.x, v.pos.y, 0.5, 1.0))
            .collect();
        clip[5].w = -1.0;
        let l = vertex_lods(&mesh, &clip, DVec2::splat(100.0), 200);
        let pooled = 0.5 * 40f64.log2();
        let want = [2.0, pooled, pooled, 3.0, 0.0, 0.0];
        for (k, (a, b)) in l.iter().zip(want).enumerate() {
            assert!((a - b).abs() < 1e-12, "vertex {k}: {a} vs {b}");
        }
    }

    #[test]
    fn frames_are_orthonormal_and_follow_handedness() {
        let f = Frame::new(DVec3::Z, DVec3::new(2.0, 0.0, 0.3), DVec3::Y);
        assert!((f.t - DVec3::X).length() < 1e-12);
        assert!((f.b - DVec3::Y).length() < 1e-12);
        let g = Frame::new(DVec3::Z, DVec3::X, -DVec3::Y);
        assert!((g.b + DVec3::Y).length() < 1e-12);
        assert_eq!(f.to_local(DVec3::new(0.0, 0.6, 0.8)), [0.0, 0.6, 0.8]);
    }

    #[test]
    fn bit_accurate_interpolation_wraps_only_the_result() {
        let enc = Encoding {
            format: Format::u(8, 4),
            codec: Codec::Fixed,
            quant: Quant::Rnd,
            overflow: Overflow::Wrap,
        };
        // vertices at u = 15.5 and 16.5 (the second is beyond the 4 integer bits)
        let (a, b) = ([15.5, 0.0, 0.0, 0.0], [16.5, 0.0, 0.0, 0.0]);
        let w = interpolate(Mode::BitAccurate, &enc, 1, [&a, &b, &b], [0.25, 0.75, 0.0]);
        // 16.25 wraps to 0.25
        assert_eq!(w.lanes[0].raw, 4);
        assert_eq!(w.lanes[0].x, 0.25);
        let e = interpolate(Mode::Exact, &enc, 1, [&a, &b, &b], [0.25, 0.75, 0.0]);
        assert_eq!(e.lanes[0].x, 16.25);
    }
}
