//! VISA+ with quaternions at the vertices: the perturbation axes from an interpolated
//! quaternion (Ernst et al. 1998 §3.2, last paragraph).
//!
//! VISA+ perturbs by `N' = N + A . V` with the alignment matrix `A` per triangle, which "leads
//! to minor visible discontinuities at the edges of two adjacent triangles"; "Using
//! quaternions at the triangle vertices for A and interpolating them over the triangle removes
//! this artifact". The rasterizer interpolates the vertex quaternions `q = (x, y, z, w)`
//! linearly; this unit turns the interpolated (not unit) `q` into the first two columns of its
//! rotation matrix, normalised as nlerp does, by dividing the matrix built from the
//! unnormalised `q` by `s = |q|^2`:
//!
//! ```text
//! c0 = (w^2 + x^2 - y^2 - z^2, 2 (xy + wz), 2 (xz - wy)) / s      = R e_x = T
//! c1 = (2 (xy - wz), w^2 - x^2 + y^2 - z^2, 2 (yz + wx)) / s      = R e_y = B
//! ```
//!
//! Without `m` the outputs are `u = -c0`, `v = -c1`, so that a [`super::Perturb`] unit gives
//! `N - Fu T - Fv B` (the scale-invariant perturbation in an orthonormal frame). With `m`, a
//! per-vertex 2x2 matrix `(m00, m01, m10, m11)` interpolated alongside (the scale and shear of
//! Blinn's axes in the frame: "Full control (scaling, rotation etc.) over the bump map is given
//! through the matrix A"): `u = m00 c0 + m10 c1`, `v = m01 c0 + m11 c1`. `q = 0` gives zero
//! axes (a zero detect).
//!
//! Bit-accurate mode: the ten squares and products of `q`'s lanes and the matrix entries are
//! exact; `1 / s = (r 2^k)^2` from the reciprocal-square-root table of [`super::Normalize`]
//! (the same table; one multiplier squares `r`); the `m` combination is applied to the exact
//! entries, then each lane is scaled by `r^2 2^2k` exactly and cast once into `out`. Exact mode
//! divides by `s` in f64.

use crate::arith::{bit_length, Acc};
use crate::format::Encoding;
use crate::gates::{CostTable, GateBudget};
use crate::unit::{Mode, PortSpec, Unit, Word};

use super::normalize::{shift_pow2, Rsqrt};
use super::perturb::{accs, cast, Span};

/// The axes `u`, `v` of an interpolated quaternion (Ernst et al. 1998 §3.2). Inputs `q`
/// (4 lanes: x, y, z, w) and, when built with an `m` encoding, `m` (4 lanes: m00, m01, m10,
/// m11); outputs `u`, `v` (3 lanes each). Latency 6, interval 1. See the module documentation.
pub struct QuatFrame {
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
    rsqrt: Rsqrt,
}

impl QuatFrame {
    /// `table_bits` (2 to 16) and `value_bits` (4 to 32) size the reciprocal-square-root
    /// table as for [`super::Normalize`]; `m` adds the input `m`; `out` is the encoding of
    /// both outputs.
    pub fn new(
        q: Encoding,
        m: Option<Encoding>,
        table_bits: u32,
        value_bits: u32,
        out: Encoding,
    ) -> Result<Self, String> {
        let rsqrt = Rsqrt::new(table_bits, value_bits)?;
        let sq = Span::of(&q);
        let p = sq.mul(sq);
        let p2 = p.add(p);
        let a = p2.add(p2).check("quat_frame: rotation entries")?; // also s = q . q
        let (kmin, kmax) = Rsqrt::k_range(a.bits, a.frac);
        let r = Span {
            bits: value_bits,
            frac: value_bits - 2,
        };
        let rr = r.mul(r);
        let pre = match m {
            None => a,
            Some(me) => {
                let t = Span::of(&me).mul(a);
                t.add(t).check("quat_frame: m combination")?
            }
        };
        pre.mul(rr).check("quat_frame: scaled axes")?.check_cast(
            "quat_frame: u, v",
            (2 * kmin, 2 * kmax),
            &out,
        )?;
        let mut inputs = vec![PortSpec::new("q", 4, q)];
        if let Some(me) = m {
            inputs.push(PortSpec::new("m", 4, me));
        }
        Ok(QuatFrame {
            inputs,
            outputs: vec![PortSpec::new("u", 3, out), PortSpec::new("v", 3, out)],
            rsqrt,
        })
    }

    /// The reciprocal-square-root table (for the Verilog generator).
    pub(crate) fn rsqrt(&self) -> &Rsqrt {
        &self.rsqrt
    }
    /// Whether the unit reads the 2x2 matrix `m`.
    pub fn has_m(&self) -> bool {
        self.inputs.len() == 2
    }
}

/// The first two columns of the rotation matrix of `q = (x, y, z, w)`, not divided by `|q|^2`,
/// and `|q|^2`, in f64.
fn columns_f64(q: [f64; 4]) -> ([f64; 3], [f64; 3], f64) {
    let [x, y, z, w] = q;
    let (xx, yy, zz, ww) = (x * x, y * y, z * z, w * w);
    let c0 = [
        ww + xx - yy - zz,
        2.0 * (x * y + w * z),
        2.0 * (x * z - w * y),
    ];
    let c1 = [
        2.0 * (x * y - w * z),
        ww - xx + yy - zz,
        2.0 * (y * z + w * x),
    ];
    (c0, c1, xx + yy + zz + ww)
}

impl Unit for QuatFrame {
    fn kind(&self) -> &'static str {
        "quat_frame"
    }
    fn inputs(&self) -> &[PortSpec] {
        &self.inputs
    }
    fn outputs(&self) -> &[PortSpec] {
        &self.outputs
    }
    /// (1) squares and products of `q`; (2) the sums `s` and the matrix entries; (3)
    /// leading-one detect and mantissa shift (the `m` combination alongside); (4) table read
    /// and `r^2`; (5) scaling multipliers; (6) output shift, saturate, register.
    fn latency(&self) -> u32 {
        6
    }
    fn interval(&self) -> u32 {
        1
    }
    fn gates(&self, t: &CostTable) -> GateBudget {
        let wq = self.inputs[0].enc.width();
        let wo = self.outputs[0].enc.width();
        let vb = self.rsqrt.value_bits();
        let wa = 2 * wq + 2; // a matrix entry, and s = q . q
        let levels = bit_length(wa as u128);
        let mut g = GateBudget::new();
        g.add(format!("squarer {wq}"), 4, t.squarer(wq));
        g.add(format!("multiplier {wq}x{wq}"), 6, t.multiplier(wq, wq));
        g.add(format!("q . q: adder {wa}"), 3, t.adder(wa));
        // w^2 - z^2 and x^2 - y^2, their sum and difference, and the four off-diagonal sums
        g.add(format!("matrix entries: adder {wa}"), 8, t.adder(wa));
        self.rsqrt.lookup_gates(&mut g, t, "", wa, levels);
        g.add(format!("r^2 squarer {vb}"), 1, t.squarer(vb));
        let (wpre, hold) = match self.inputs.get(1) {
            None => (wa, 6 * wa),
            Some(pm) => {
                let wm = pm.enc.width();
                let wc = wm + wa + 1;
                g.add(
                    format!("m combination: multiplier {wm}x{wa}"),
                    12,
                    t.multiplier(wm, wa),
                );
                g.add(format!("m combination: adder {wc}"), 6, t.adder(wc));
                (wc, 6 * wa + 4 * wm + 6 * wc)
            }
        };
        g.add(
            format!("column scaling: multiplier {wpre}x{}", 2 * vb),
            6,
            t.multiplier(wpre, 2 * vb),
        );
        g.add(
            format!("output shifter {}x{levels}", wpre + 2 * vb),
            6,
            t.mux(wpre + 2 * vb, 2) * levels as f64,
        );
        g.add(format!("output saturation {wo}"), 6, t.clamp(wo));
        // the ten products, the entries held through the table stages, s, r^2, outputs
        let regs = 10 * 2 * wq + 2 * hold + wa + 2 * vb + 6 * wo;
        g.add(format!("pipeline registers {regs}"), 1, t.register(regs));
        g
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        let out = self.outputs[0].enc;
        match mode {
            Mode::Exact => {
                let (c0, c1, s) = columns_f64(ins[0].xs::<4>());
                if s == 0.0 {
                    outs[0] = Word::from_exact(&out, &[0.0; 3]);
                    outs[1] = Word::from_exact(&out, &[0.0; 3]);
                    return;
                }
                let (c0, c1) = (c0.map(|x| x / s), c1.map(|x| x / s));
                let (u, v) = if self.has_m() {
                    let [m00, m01, m10, m11] = ins[1].xs::<4>();
                    (
                        std::array::from_fn(|j| m00 * c0[j] + m10 * c1[j]),
                        std::array::from_fn(|j| m01 * c0[j] + m11 * c1[j]),
                    )
                } else {
                    (c0.map(|x| -x), c1.map(|x| -x))
                };
                outs[0] = Word::from_exact(&out, &u);
                outs[1] = Word::from_exact(&out, &v);
            }
            Mode::BitAccurate => {
                let [x, y, z, w] = accs::<4>(&ins[0], &self.inputs[0].enc);
                let (xx, yy, zz, ww) = (x.mul(x), y.mul(y), z.mul(z), w.mul(w));
                let s = xx.add(yy).add(zz.add(ww));
                // 1 / |q| = r 2^k, so 1 / s = r^2 2^2k; q = 0 gives zero axes
                let Some((r, k)) = self.rsqrt.lookup(s) else {
                    outs[0] = Word::from_raw(&out, &[0; 3]);
                    outs[1] = Word::from_raw(&out, &[0; 3]);
                    return;
                };
                let (wz, xy) = (ww.sub(zz), xx.sub(yy));
                let a0 = [
                    wz.add(xy),
                    x.mul(y).add(w.mul(z)).scale(2),
                    x.mul(z).sub(w.mul(y)).scale(2),
                ];
                let a1 = [
                    x.mul(y).sub(w.mul(z)).scale(2),
                    wz.sub(xy),
                    y.mul(z).add(w.mul(x)).scale(2),
                ];
                let (pu, pv) = if self.has_m() {
                    let [m00, m01, m10, m11] = accs::<4>(&ins[1], &self.inputs[1].enc);
                    (
                        std::array::from_fn(|j| m00.mul(a0[j]).add(m10.mul(a1[j]))),
                        std::array::from_fn(|j| m01.mul(a0[j]).add(m11.mul(a1[j]))),
                    )
                } else {
                    (a0.map(Acc::neg), a1.map(Acc::neg))
                };
                let rr = r.mul(r);
                let fin = |a: [Acc; 3]| a.map(|e| cast(shift_pow2(e.mul(rr), 2 * k), &out));
                outs[0] = Word::from_raw(&out, &fin(pu));
                outs[1] = Word::from_raw(&out, &fin(pv));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::{Codec, Format};
    use proptest::prelude::*;

    const WIDE: Encoding = Encoding::fixed(Format::s(24, 20));

    fn eval(u: &QuatFrame, mode: Mode, ins: &[Word]) -> [[f64; 3]; 2] {
        let mut o = [Word::default(); 2];
        u.eval(mode, ins, &mut o);
        o.map(|w| w.xs::<3>())
    }

    fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
    }

    /// A deterministic spread of quaternions.
    fn quat(i: u32) -> [f64; 4] {
        let a = i as f64;
        [
            (a * 0.71).sin(),
            (a * 1.37).cos() * 0.8,
            (a * 0.23).sin() - 0.3,
            (a * 2.11).cos() + 0.1,
        ]
    }

    /// The identity gives `-x`, `-y`: exactly in exact mode, within the table's error in
    /// bit-accurate mode (`|q|^2 = 1` falls in the first bin read, whose entry is
    /// `1 / sqrt(1/4 + 2^-9)`, not 2: 0.9922 rather than 1 for a 256-entry table).
    #[test]
    fn identity_gives_minus_x_and_minus_y() {
        let u = QuatFrame::new(WIDE, None, 8, 12, WIDE).unwrap();
        for scale in [1.0, 0.7, 3.0] {
            let q = Word::from_exact(&WIDE, &[0.0, 0.0, 0.0, scale]);
            let [a, b] = eval(&u, Mode::Exact, &[q]);
            assert_eq!((a, b), ([-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]), "{scale}");
            let q = Word::quantize(&WIDE, &[0.0, 0.0, 0.0, scale]);
            let [a, b] = eval(&u, Mode::BitAccurate, &[q]);
            assert!(
                close(a, [-1.0, 0.0, 0.0], rel(&u)) && a[1..] == [0.0; 2],
                "{a:?}"
            );
            assert!(
                close(b, [0.0, -1.0, 0.0], rel(&u)) && b[0] == 0.0 && b[2] == 0.0,
                "{b:?}"
            );
        }
    }

    /// Exact mode against the formulas; the columns are orthonormal, right-handed with the
    /// third column `R e_z`, and do not depend on the scale of `q` (0.7 q or a normalised q).
    #[test]
    fn exact_mode_is_the_normalised_rotation() {
        let u = QuatFrame::new(WIDE, None, 8, 12, WIDE).unwrap();
        for i in 0..200 {
            let q = quat(i);
            let [a, b] = eval(&u, Mode::Exact, &[Word::from_exact(&WIDE, &q)]);
            let (c0, c1, s) = columns_f64(q);
            assert!(close(a, c0.map(|x| -x / s), 1e-15));
            assert!(close(b, c1.map(|x| -x / s), 1e-15));
            let (c0, c1) = (a.map(|x| -x), b.map(|x| -x));
            assert!((dot(c0, c0) - 1.0).abs() < 1e-12 && (dot(c1, c1) - 1.0).abs() < 1e-12);
            assert!(dot(c0, c1).abs() < 1e-12);
            // R e_z = (2 (xz + wy), 2 (yz - wx), w^2 - x^2 - y^2 + z^2) / s
            let [x, y, z, w] = q;
            let c2 = [
                2.0 * (x * z + w * y) / s,
                2.0 * (y * z - w * x) / s,
                (w * w - x * x - y * y + z * z) / s,
            ];
            assert!(close(super::super::perturb::cross_f64(c0, c1), c2, 1e-12));
            let l = s.sqrt();
            for k in [0.7, 1.0 / l] {
                let [a2, b2] = eval(
                    &u,
                    Mode::Exact,
                    &[Word::from_exact(&WIDE, &q.map(|x| x * k))],
                );
                assert!(close(a2, a, 1e-12) && close(b2, b, 1e-12), "{i} {k}");
            }
        }
    }

    #[test]
    fn the_m_combination() {
        let um = QuatFrame::new(WIDE, Some(WIDE), 8, 12, WIDE).unwrap();
        let u = QuatFrame::new(WIDE, None, 8, 12, WIDE).unwrap();
        assert_eq!(um.inputs().len(), 2);
        assert_eq!(um.inputs()[1].name, "m");
        for i in 0..100 {
            let q = Word::from_exact(&WIDE, &quat(i));
            let [a, b] = eval(&u, Mode::Exact, &[q]);
            let (c0, c1) = (a.map(|x| -x), b.map(|x| -x));
            // (-1, 0, 0, -1) is the unit without m
            let minus = Word::from_exact(&WIDE, &[-1.0, 0.0, 0.0, -1.0]);
            assert_eq!(eval(&um, Mode::Exact, &[q, minus]), [a, b]);
            let mm = [0.5, -1.25, 0.75, 2.0];
            let [mu, mv] = eval(&um, Mode::Exact, &[q, Word::from_exact(&WIDE, &mm)]);
            let want_u: [f64; 3] = std::array::from_fn(|j| mm[0] * c0[j] + mm[2] * c1[j]);
            let want_v: [f64; 3] = std::array::from_fn(|j| mm[1] * c0[j] + mm[3] * c1[j]);
            assert!(close(mu, want_u, 1e-12) && close(mv, want_v, 1e-12));
        }
    }

    #[test]
    fn zero_quaternion_gives_zero_axes() {
        for m in [None, Some(WIDE)] {
            let u = QuatFrame::new(WIDE, m, 8, 12, WIDE).unwrap();
            for mode in [Mode::Exact, Mode::BitAccurate] {
                let mut ins = vec![Word::for_mode(mode, &WIDE, &[0.0; 4])];
                if m.is_some() {
                    ins.push(Word::for_mode(mode, &WIDE, &[1.0, 0.5, -0.5, 1.0]));
                }
                let mut o = [Word::default(); 2];
                u.eval(mode, &ins, &mut o);
                assert_eq!(o.map(|w| w.raws::<3>()), [[0; 3]; 2]);
                assert_eq!(o.map(|w| w.xs::<3>()), [[0.0; 3]; 2]);
            }
        }
    }

    #[test]
    fn new_rejects_table_and_value_bits_out_of_range_and_too_wide_inputs() {
        let e = Encoding::fixed(Format::s(10, 8));
        let err = |t, v| QuatFrame::new(e, None, t, v, e).err().unwrap();
        assert_eq!(err(1, 12), "table_bits 1: expected 2 to 16");
        assert_eq!(err(17, 12), "table_bits 17: expected 2 to 16");
        assert_eq!(err(8, 3), "value_bits 3: expected 4 to 32");
        assert_eq!(err(8, 33), "value_bits 33: expected 4 to 32");
        assert!(QuatFrame::new(e, Some(e), 16, 32, e).is_ok());
        let w = Encoding::fixed(Format::s(32, 30));
        let msg = QuatFrame::new(w, Some(w), 8, 32, e).err().unwrap();
        assert!(msg.contains("more than the 126 bits"), "{msg}");
    }

    #[test]
    fn gates_with_m_cost_more() {
        let e = Encoding::fixed(Format::s(10, 8));
        let t = CostTable::default();
        let g0 = QuatFrame::new(e, None, 8, 12, e).unwrap().gates(&t).total();
        let g1 = QuatFrame::new(e, Some(e), 8, 12, e)
            .unwrap()
            .gates(&t)
            .total();
        for m in [None, Some(e)] {
            let u = QuatFrame::new(e, m, 8, 12, e).unwrap();
            for i in &u.gates(&t).items {
                println!(
                    "quat_frame m={} gates: {:>10.1}  {}",
                    m.is_some(),
                    i.ge,
                    i.what
                );
            }
        }
        println!("quat_frame gates at s2.8, 256x12 table: without m {g0:.1}, with m {g1:.1}");
        assert!(g0 > 0.0 && g1 > g0, "{g0} {g1}");
    }

    /// Relative error of `1 / s = (r 2^k)^2`: one lookup's `eps` squared through.
    fn rel(u: &QuatFrame) -> f64 {
        let e =
            2f64.powi(-(u.rsqrt.index_bits() as i32)) + 2f64.powi(1 - u.rsqrt.value_bits() as i32);
        (1.0 + e) * (1.0 + e) - 1.0
    }

    /// The bound per lane: the exact lane times the relative error of `1 / s` (the entries and
    /// the `m` combination are exact before the scaling), plus the output rounding. Lanes the
    /// output cannot hold are left out. Updates (worst error, worst error / bound, worst
    /// excess over the bound).
    fn check(u: &QuatFrame, ins: &[Word], acc: &mut (f64, f64, f64)) {
        let out = u.outputs[0].enc;
        let rel = rel(u);
        let got = eval(u, Mode::BitAccurate, ins);
        let want = eval(u, Mode::Exact, ins);
        for k in 0..2 {
            for (g, w) in got[k].iter().zip(want[k]) {
                if w > out.decode(out.format.max_raw()) || w < out.decode(out.format.min_raw()) {
                    continue;
                }
                let err = (g - w).abs();
                let bound = w.abs() * rel + out.max_error() + 1e-12;
                acc.0 = acc.0.max(err);
                acc.1 = acc.1.max(err / bound);
                acc.2 = acc.2.max(err - bound);
            }
        }
    }

    /// Every 4-bit quaternion (s2.2 lanes, 65,536), without `m` and with every 3-bit `m`
    /// (s1.2 lanes) for a sample of quaternions: within the bound, and the table's error is
    /// visible (many output LSBs).
    #[test]
    fn exhaustive_small_widths_within_the_table_bound() {
        let eq = Encoding::fixed(Format::s(4, 2));
        let em = Encoding::fixed(Format::s(3, 2));
        let out = Encoding::fixed(Format::s(14, 11));
        let qword = |a: i64| {
            Word::from_raw(
                &eq,
                &[
                    (a & 15) - 8,
                    ((a >> 4) & 15) - 8,
                    ((a >> 8) & 15) - 8,
                    (a >> 12) - 8,
                ],
            )
        };
        let u = QuatFrame::new(eq, None, 4, 8, out).unwrap();
        let mut acc = (0.0, 0.0, f64::NEG_INFINITY);
        for a in 0..1i64 << 16 {
            check(&u, &[qword(a)], &mut acc);
        }
        println!(
            "quat_frame t=4 vb=8 exhaustive: worst {:.5}, {:.3} of the bound",
            acc.0, acc.1
        );
        assert!(acc.2 <= 0.0, "bound exceeded by {}", acc.2);
        assert!(acc.0 > 16.0 * out.max_error() && acc.1 > 0.5, "{acc:?}");
        let um = QuatFrame::new(eq, Some(em), 4, 8, out).unwrap();
        let mut acc = (0.0, 0.0, f64::NEG_INFINITY);
        for a in (0..1i64 << 16).step_by(61) {
            for b in 0..1i64 << 12 {
                let m = Word::from_raw(
                    &em,
                    &[
                        (b & 7) - 4,
                        ((b >> 3) & 7) - 4,
                        ((b >> 6) & 7) - 4,
                        (b >> 9) - 4,
                    ],
                );
                check(&um, &[qword(a), m], &mut acc);
            }
        }
        println!(
            "quat_frame with m t=4 vb=8: worst {:.5}, {:.3} of the bound",
            acc.0, acc.1
        );
        assert!(acc.2 <= 0.0, "bound exceeded by {}", acc.2);
        assert!(acc.0 > 16.0 * out.max_error() && acc.1 > 0.5, "{acc:?}");
    }

    /// Unit codecs on `q` (bit replication scales every lane alike, which `1 / |q|^2` cancels)
    /// and a `UnitSigned` output.
    #[test]
    fn unit_codecs_within_the_table_bound() {
        let eq = Encoding::texel(Codec::UnitSymmetric, true, 4);
        let out = Encoding::texel(Codec::UnitSigned, true, 10);
        let u = QuatFrame::new(eq, None, 6, 10, out).unwrap();
        let mut acc = (0.0, 0.0, f64::NEG_INFINITY);
        for a in 0..1i64 << 16 {
            let q = Word::from_raw(
                &eq,
                &[
                    (a & 15) - 8,
                    ((a >> 4) & 15) - 8,
                    ((a >> 8) & 15) - 8,
                    (a >> 12) - 8,
                ],
            );
            check(&u, &[q], &mut acc);
        }
        assert!(acc.2 <= 0.0, "bound exceeded by {}", acc.2);
    }

    /// At the widths of the quaternion config (s2.8 lanes, a 256 x 12 table, s2.8 axes).
    #[test]
    fn measured_error_at_config_widths() {
        let e = Encoding::fixed(Format::s(10, 8));
        for m in [None, Some(e)] {
            let u = QuatFrame::new(e, m, 8, 12, e).unwrap();
            let mut acc = (0.0, 0.0, f64::NEG_INFINITY);
            for i in 0..20000 {
                let q = quat(i);
                let l = q.iter().map(|x| x * x).sum::<f64>().sqrt();
                // interpolated unit quaternions are a little shorter than 1
                let k = (0.75 + 0.25 * (i as f64 * 0.01).cos().abs()) / l;
                let mut ins = vec![Word::quantize(&e, &q.map(|x| x * k))];
                if m.is_some() {
                    let a = i as f64 * 0.3;
                    ins.push(Word::quantize(
                        &e,
                        &[a.cos(), -0.5 * a.sin(), 0.4 * a.sin(), a.cos()],
                    ));
                }
                check(&u, &ins, &mut acc);
            }
            println!(
                "quat_frame m={} t=8 vb=12 s2.8 -> s2.8: worst {:.5}, {:.3} of the bound",
                m.is_some(),
                acc.0,
                acc.1
            );
            assert!(acc.2 <= 0.0, "bound exceeded by {}", acc.2);
            assert!(acc.0 > 2.0 * e.max_error(), "{}", acc.0);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]
        /// Wide widths: random 16-bit `q` and `m`, tables of 6 to 12 index bits and 10 to 16
        /// value bits; within the bound of `check`.
        #[test]
        fn wide_widths_within_the_table_bound(
            with_m in any::<bool>(), t in 6u32..=12, vb in 10u32..=16, fq in 8u8..=15,
            raws in proptest::collection::vec(-32768i64..32768, 8),
        ) {
            let eq = Encoding::fixed(Format::s(16, fq));
            let em = Encoding::fixed(Format::s(16, 14));
            let out = Encoding::fixed(Format::s(16, 12));
            let u = QuatFrame::new(eq, with_m.then_some(em), t, vb, out).unwrap();
            let mut ins = vec![Word::from_raw(&eq, &raws[0..4])];
            if with_m {
                ins.push(Word::from_raw(&em, &raws[4..8]));
            }
            let mut acc = (0.0, 0.0, f64::NEG_INFINITY);
            check(&u, &ins, &mut acc);
            prop_assert!(acc.2 <= 0.0, "bound exceeded by {}", acc.2);
        }
    }
}
