//! Texram's per-pixel orthonormal frame from the main direction (Ernst et al. 1998 §3.1).
//!
//! "Given the interpolated per vertex normal `N_i` and the main direction `m` the following
//! formulae lead to the final perturbation: `N = N_i / ||N_i||`; `e1 = m x N / ||m x N||`;
//! `e2 = N x e1`", and the simplification that "avoids the normalization by multiplying with
//! `||N_i||` and widening the vector formats": `N ||N_i|| = N_i`, `e1 ||N_i||`,
//! `e2 ||N_i|| = N_i x e1`.
//!
//! The unit outputs the two axes `u`, `v` that multiply the bump map's height gradient
//! `(Fu, Fv)` in a [`super::Perturb`] unit. With `m` along `T` (the `Pu` direction), `N` unit
//! and `B = N x T`: `e1 = T x N = -B` and `e2 = N x (T x N) = T`, so the outputs
//! `u = -e2 = -T`, `v = e1 = -B` give `N + Fu u + Fv v = N - Fu T - Fv B`, Blinn's perturbation
//! for an orthonormal frame (the scale-invariant form of §2's `N + D`).
//!
//! * [`TexramForm::Normalized`] (§3.1's first form): `n` is the unit `N`, normalised upstream.
//!   `c = m x n`, `e1 = c / |c|`, `u = -(n x e1)`, `v = e1`.
//! * [`TexramForm::Scaled`] (§3.1's simplification): `n` is `N_i`, not normalised.
//!   `c = m x N_i`, `e1 = c / |c|`, `l = |N_i|`, `u = -(N_i x e1) = -|N_i| e2`, `v = l e1`, so
//!   that `N_i + Fu u + Fv v = |N_i| (N - Fu T - Fv B)`: only the final normalisation of the
//!   perturbed normal (a [`super::Normalize`] downstream) remains.
//!
//! Degenerate inputs: `c = 0` (`m` parallel to `N`, `m = 0` or `n = 0`) gives zero axes, i.e.
//! no perturbation (a hardware zero detect; the table is not read).
//!
//! Bit-accurate mode: `c`, `c . c`, `n x c` and `N_i . N_i` are exact; `1 / |c|` and
//! `1 / |N_i|` come from the reciprocal-square-root table of [`super::Normalize`]
//! (`1 / sqrt(s) ~ r 2^k`), `|N_i| = (N_i . N_i) r_n 2^k_n`; `v = c r 2^k` (Scaled:
//! `c (r (N_i . N_i) r_n) 2^(k + k_n)`) and `u = -(n x c) r 2^k` are exact and each lane is cast
//! once into `out`. Exact mode is the same algebra in f64 with `sqrt`.

use crate::arith::{bit_length, Acc};
use crate::format::Encoding;
use crate::gates::{CostTable, GateBudget};
use crate::unit::{Mode, PortSpec, Unit, Word};

use super::normalize::{shift_pow2, Rsqrt};
use super::perturb::{accs, cast, cross_acc, cross_f64, Span};

/// Which of §3.1's two constructions a [`TexramFrame`] computes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum TexramForm {
    /// `n` is the unit normal `N`: `u = -e2`, `v = e1`.
    Normalized,
    /// `n` is the interpolated `N_i`: `u = -||N_i|| e2`, `v = ||N_i|| e1`.
    Scaled,
}

/// The Texram axes `u`, `v` from `n` and the main direction `m` (Ernst et al. 1998 §3.1,
/// `e1 = m x N / ||m x N||`, `e2 = N x e1`). Inputs `n` (3 lanes), `m` (3 lanes); outputs `u`,
/// `v` (3 lanes each). Latency 6, interval 1. See the module documentation.
pub struct TexramFrame {
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
    form: TexramForm,
    rsqrt: Rsqrt,
}

impl TexramFrame {
    /// `table_bits` (2 to 16) and `value_bits` (4 to 32) size the reciprocal-square-root
    /// table as for [`super::Normalize`]; `out` is the encoding of both outputs.
    pub fn new(
        n: Encoding,
        m: Encoding,
        form: TexramForm,
        table_bits: u32,
        value_bits: u32,
        out: Encoding,
    ) -> Result<Self, String> {
        let rsqrt = Rsqrt::new(table_bits, value_bits)?;
        let (sn, sm) = (Span::of(&n), Span::of(&m));
        let r = Span {
            bits: value_bits,
            frac: value_bits - 2,
        };
        let c = sm.cross(sn).check("texram: m x n")?;
        let c2 = c.mul(c);
        let s = c2.add(c2).add(c2).check("texram: (m x n) . (m x n)")?;
        let k = Rsqrt::k_range(s.bits, s.frac);
        let p = sn.cross(c).check("texram: n x (m x n)")?;
        p.mul(r)
            .check("texram: u")?
            .check_cast("texram: u", k, &out)?;
        match form {
            TexramForm::Normalized => {
                c.mul(r)
                    .check("texram: v")?
                    .check_cast("texram: v", k, &out)?
            }
            TexramForm::Scaled => {
                let n2 = sn.mul(sn);
                let sl = n2.add(n2).add(n2).check("texram: N_i . N_i")?;
                let kl = Rsqrt::k_range(sl.bits, sl.frac);
                let g = r.mul(sl).mul(r).check("texram: |N_i| / |m x N_i|")?;
                c.mul(g).check("texram: v")?.check_cast(
                    "texram: v",
                    (k.0 + kl.0, k.1 + kl.1),
                    &out,
                )?;
            }
        }
        Ok(TexramFrame {
            inputs: vec![PortSpec::new("n", 3, n), PortSpec::new("m", 3, m)],
            outputs: vec![PortSpec::new("u", 3, out), PortSpec::new("v", 3, out)],
            form,
            rsqrt,
        })
    }

    /// The form the unit computes.
    pub fn form(&self) -> TexramForm {
        self.form
    }
    /// The reciprocal-square-root table (for the Verilog generator).
    pub(crate) fn rsqrt(&self) -> &Rsqrt {
        &self.rsqrt
    }
}

impl Unit for TexramFrame {
    fn kind(&self) -> &'static str {
        "texram_frame"
    }
    fn inputs(&self) -> &[PortSpec] {
        &self.inputs
    }
    fn outputs(&self) -> &[PortSpec] {
        &self.outputs
    }
    /// (1) `c = m x n`; (2) `c . c`; (3) leading-one detect and mantissa shift; (4) table
    /// read, `n x c` alongside; (5) scaling multipliers; (6) output shift, saturate, register.
    fn latency(&self) -> u32 {
        6
    }
    fn interval(&self) -> u32 {
        1
    }
    fn gates(&self, t: &CostTable) -> GateBudget {
        let wn = self.inputs[0].enc.width();
        let wm = self.inputs[1].enc.width();
        let wo = self.outputs[0].enc.width();
        let vb = self.rsqrt.value_bits();
        let wc = wm + wn + 1; // a component of m x n
        let wp = wn + wc + 1; // a component of n x c
        let ws = 2 * wc + 2; // c . c
        let levels = bit_length(ws as u128);
        let mut g = GateBudget::new();
        g.add(
            format!("cross product m x n: multiplier {wm}x{wn}"),
            6,
            t.multiplier(wm, wn),
        );
        g.add(format!("cross product m x n: adder {wc}"), 3, t.adder(wc));
        g.add(format!("c . c: squarer {wc}"), 3, t.squarer(wc));
        g.add(
            format!("c . c: adder {}", 2 * wc + 1),
            2,
            t.adder(2 * wc + 1),
        );
        self.rsqrt.lookup_gates(&mut g, t, "", ws, levels);
        g.add(
            format!("cross product n x c: multiplier {wn}x{wc}"),
            6,
            t.multiplier(wn, wc),
        );
        g.add(format!("cross product n x c: adder {wp}"), 3, t.adder(wp));
        g.add(
            format!("u scaling: multiplier {wp}x{vb}"),
            3,
            t.multiplier(wp, vb),
        );
        g.add(
            format!("u output shifter {}x{levels}", wp + vb),
            3,
            t.mux(wp + vb, 2) * levels as f64,
        );
        let wv = match self.form {
            TexramForm::Normalized => {
                g.add(
                    format!("v scaling: multiplier {wc}x{vb}"),
                    3,
                    t.multiplier(wc, vb),
                );
                wc + vb
            }
            TexramForm::Scaled => {
                let wl = 2 * wn + 2; // N_i . N_i
                let ll = bit_length(wl as u128);
                g.add(format!("N_i . N_i: squarer {wn}"), 3, t.squarer(wn));
                g.add(
                    format!("N_i . N_i: adder {}", 2 * wn + 1),
                    2,
                    t.adder(2 * wn + 1),
                );
                // a second copy of the table: two reads per clock at interval 1
                self.rsqrt.lookup_gates(&mut g, t, "|N_i| ", wl, ll);
                g.add(
                    format!("|N_i|: multiplier {wl}x{vb}"),
                    1,
                    t.multiplier(wl, vb),
                );
                g.add(
                    format!("|N_i| / |c|: multiplier {}x{vb}", wl + vb),
                    1,
                    t.multiplier(wl + vb, vb),
                );
                let wg = wl + 2 * vb;
                g.add(
                    format!("v scaling: multiplier {wc}x{wg}"),
                    3,
                    t.multiplier(wc, wg),
                );
                wc + wg
            }
        };
        g.add(
            format!("v output shifter {wv}x{levels}"),
            3,
            t.mux(wv, 2) * levels as f64,
        );
        g.add(format!("output saturation {wo}"), 6, t.clamp(wo));
        // n and c held through the three table stages, c . c, the table value, n x c, outputs
        let regs = 3 * (3 * wn + 3 * wc) + ws + vb + 3 * wp + 6 * wo;
        g.add(format!("pipeline registers {regs}"), 1, t.register(regs));
        g
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        let out = self.outputs[0].enc;
        match mode {
            Mode::Exact => {
                let (n, m) = (ins[0].xs::<3>(), ins[1].xs::<3>());
                let c = cross_f64(m, n);
                let cc = c.iter().map(|x| x * x).sum::<f64>();
                if cc == 0.0 {
                    outs[0] = Word::from_exact(&out, &[0.0; 3]);
                    outs[1] = Word::from_exact(&out, &[0.0; 3]);
                    return;
                }
                let e1 = c.map(|x| x / cc.sqrt());
                let u = cross_f64(n, e1).map(|x| -x);
                let v = match self.form {
                    TexramForm::Normalized => e1,
                    TexramForm::Scaled => {
                        let l = n.iter().map(|x| x * x).sum::<f64>().sqrt();
                        e1.map(|x| l * x)
                    }
                };
                outs[0] = Word::from_exact(&out, &u);
                outs[1] = Word::from_exact(&out, &v);
            }
            Mode::BitAccurate => {
                let n = accs::<3>(&ins[0], &self.inputs[0].enc);
                let m = accs::<3>(&ins[1], &self.inputs[1].enc);
                let c = cross_acc(m, n);
                let dot = |a: &[Acc; 3]| a.iter().fold(Acc::ZERO, |s, x| s.add(x.mul(*x)));
                // 1 / |c| = r 2^k; c = 0 gives zero axes
                let Some((r, k)) = self.rsqrt.lookup(dot(&c)) else {
                    outs[0] = Word::from_raw(&out, &[0; 3]);
                    outs[1] = Word::from_raw(&out, &[0; 3]);
                    return;
                };
                let p = cross_acc(n, c);
                let u = p.map(|x| cast(shift_pow2(x.mul(r), k).neg(), &out));
                let v = match self.form {
                    TexramForm::Normalized => c.map(|x| cast(shift_pow2(x.mul(r), k), &out)),
                    TexramForm::Scaled => {
                        // |N_i| = s r_n 2^k_n; c != 0 implies N_i != 0
                        let s = dot(&n);
                        let (rn, kn) = self.rsqrt.lookup(s).expect("N_i is not zero");
                        let g = r.mul(s).mul(rn);
                        c.map(|x| cast(shift_pow2(x.mul(g), k + kn), &out))
                    }
                };
                outs[0] = Word::from_raw(&out, &u);
                outs[1] = Word::from_raw(&out, &v);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::{Codec, Format};
    use proptest::prelude::*;

    fn eval(u: &TexramFrame, mode: Mode, n: Word, m: Word) -> [Word; 2] {
        let mut o = [Word::default(); 2];
        u.eval(mode, &[n, m], &mut o);
        o
    }

    fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    fn unit(a: [f64; 3]) -> [f64; 3] {
        let l = dot(a, a).sqrt();
        a.map(|x| x / l)
    }

    fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
    }

    const WIDE: Encoding = Encoding::fixed(Format::s(24, 20));

    fn frame(form: TexramForm) -> TexramFrame {
        TexramFrame::new(WIDE, WIDE, form, 8, 12, WIDE).unwrap()
    }

    /// The exact mode of both forms against the formulas of §3.1 in f64.
    #[test]
    fn exact_mode_follows_the_formulas() {
        let n = [0.3, -0.5, 0.8];
        let m = [0.9, 0.2, -0.1];
        let c = cross_f64(m, n);
        let e1 = unit(c);
        let nn = unit(n);
        let e2 = cross_f64(nn, e1);
        for (form, u_want, v_want) in [
            (TexramForm::Normalized, cross_f64(n, e1).map(|x| -x), e1),
            (
                TexramForm::Scaled,
                e2.map(|x| -x * dot(n, n).sqrt()),
                e1.map(|x| x * dot(n, n).sqrt()),
            ),
        ] {
            let [u, v] = eval(
                &frame(form),
                Mode::Exact,
                Word::from_exact(&WIDE, &n),
                Word::from_exact(&WIDE, &m),
            );
            assert!(close(u.xs(), u_want, 1e-15), "{form:?} {:?}", u.xs::<3>());
            assert!(close(v.xs(), v_want, 1e-15), "{form:?} {:?}", v.xs::<3>());
            assert_eq!(u.raws::<3>(), u_want.map(|x| WIDE.encode(x)));
        }
    }

    /// `m = T`, `N = Z`: `u = -T`, `v = -B`; for any orthonormal frame (and `m` anywhere in the
    /// `N`-`T` half plane) the perturbation is `N - Fu T - Fv B`; Scaled with `N_i = 0.8 N`
    /// gives 0.8 times the Normalized axes.
    #[test]
    fn geometry_of_the_frame() {
        let norm = frame(TexramForm::Normalized);
        let scaled = frame(TexramForm::Scaled);
        let ex = |u: &TexramFrame, n: [f64; 3], m: [f64; 3]| {
            let [a, b] = eval(
                u,
                Mode::Exact,
                Word::from_exact(&WIDE, &n),
                Word::from_exact(&WIDE, &m),
            );
            (a.xs::<3>(), b.xs::<3>())
        };
        let (u, v) = ex(&norm, [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
        assert_eq!((u, v), ([-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]));
        for i in 0..50 {
            let a = i as f64 * 0.37;
            let nv = unit([a.cos() * 0.6, a.sin() * 0.6, 0.5 + (a * 1.3).cos() * 0.3]);
            let t = unit(cross_f64([0.3, 1.0, (a * 0.7).sin()], nv));
            let b = cross_f64(nv, t);
            let m = std::array::from_fn(|j| 1.7 * t[j] + (a * 2.0).sin() * nv[j]);
            let (u, v) = ex(&norm, nv, m);
            assert!(close(u, t.map(|x| -x), 1e-12), "{i}: {u:?}");
            assert!(close(v, b.map(|x| -x), 1e-12), "{i}: {v:?}");
            let (fu, fv) = (0.3 - a.sin(), 0.2 * a.cos());
            let got: [f64; 3] = std::array::from_fn(|j| nv[j] + fu * u[j] + fv * v[j]);
            let want: [f64; 3] = std::array::from_fn(|j| nv[j] - fu * t[j] - fv * b[j]);
            assert!(close(got, want, 1e-12));
            let (su, sv) = ex(&scaled, nv.map(|x| 0.8 * x), m);
            assert!(close(su, u.map(|x| 0.8 * x), 1e-12), "{i}: {su:?}");
            assert!(close(sv, v.map(|x| 0.8 * x), 1e-12), "{i}: {sv:?}");
        }
    }

    #[test]
    fn degenerate_inputs_give_zero_axes() {
        for form in [TexramForm::Normalized, TexramForm::Scaled] {
            let u = frame(form);
            for (n, m) in [
                ([0.0, 0.0, 1.0], [0.0, 0.0, 0.5]), // m parallel to N
                ([0.0, 0.0, 1.0], [0.0, 0.0, -2.0]),
                ([0.0, 0.6, 0.8], [0.0; 3]), // m = 0
                ([0.0; 3], [1.0, 0.0, 0.0]), // n = 0
            ] {
                for mode in [Mode::Exact, Mode::BitAccurate] {
                    let o = eval(
                        &u,
                        mode,
                        Word::for_mode(mode, &WIDE, &n),
                        Word::for_mode(mode, &WIDE, &m),
                    );
                    assert_eq!(o.map(|w| w.raws::<3>()), [[0; 3]; 2], "{form:?} {mode:?}");
                    assert_eq!(o.map(|w| w.xs::<3>()), [[0.0; 3]; 2], "{form:?} {mode:?}");
                }
            }
        }
    }

    #[test]
    fn new_rejects_table_and_value_bits_out_of_range_and_too_wide_inputs() {
        let e = Encoding::fixed(Format::s(10, 8));
        let f = TexramForm::Normalized;
        let err = |t, v| TexramFrame::new(e, e, f, t, v, e).err().unwrap();
        assert_eq!(err(1, 12), "table_bits 1: expected 2 to 16");
        assert_eq!(err(17, 12), "table_bits 17: expected 2 to 16");
        assert_eq!(err(8, 3), "value_bits 3: expected 4 to 32");
        assert_eq!(err(8, 33), "value_bits 33: expected 4 to 32");
        assert!(TexramFrame::new(e, e, f, 2, 4, e).is_ok());
        assert!(TexramFrame::new(e, e, f, 16, 32, e).is_ok());
        let w = Encoding::fixed(Format::s(32, 30));
        let msg = TexramFrame::new(w, w, f, 8, 12, e).err().unwrap();
        assert!(msg.contains("more than the 126 bits"), "{msg}");
        let msg = TexramFrame::new(
            Encoding::fixed(Format::s(22, 20)),
            e,
            TexramForm::Scaled,
            8,
            32,
            e,
        )
        .err()
        .unwrap();
        assert!(msg.starts_with("texram: v"), "{msg}");
    }

    #[test]
    fn gates_scaled_costs_more_than_normalized() {
        let e = Encoding::fixed(Format::s(10, 8)); // the configs' s2.8
        let t = CostTable::default();
        let g = |f| {
            TexramFrame::new(e, e, f, 8, 12, e)
                .unwrap()
                .gates(&t)
                .total()
        };
        for f in [TexramForm::Normalized, TexramForm::Scaled] {
            let u = TexramFrame::new(e, e, f, 8, 12, e).unwrap();
            for i in &u.gates(&t).items {
                println!("texram {f:?} gates: {:>10.1}  {}", i.ge, i.what);
            }
        }
        let (n, s) = (g(TexramForm::Normalized), g(TexramForm::Scaled));
        println!("texram gates at s2.8, 256x12 table: Normalized {n:.1}, Scaled {s:.1}");
        assert!(n > 0.0 && s > n, "{n} {s}");
    }

    /// Relative error bound of one table lookup (bin half-width plus entry rounding).
    fn eps(t: u32, vb: u32) -> f64 {
        2f64.powi(-(t as i32)) + 2f64.powi(1 - vb as i32)
    }

    /// Worst `|bit-accurate - exact|` over the lanes of both outputs, minus the lane's bound
    /// `|exact| * rel + out.max_error()`: `rel` is one lookup's `eps` for `u` (and `v` in the
    /// Normalized form), `(1 + eps)^2 - 1` for the Scaled form's `v = |N_i| e1` (two lookups).
    /// Lanes whose exact value the output cannot hold (they saturate) are left out. Updates
    /// (worst error, worst error / bound, worst excess over the bound).
    fn check(u: &TexramFrame, n: Word, m: Word, acc: &mut (f64, f64, f64)) {
        let (t, vb) = (u.rsqrt.index_bits(), u.rsqrt.value_bits());
        let out = u.outputs[0].enc;
        let e = eps(t, vb);
        let rel_v = match u.form {
            TexramForm::Normalized => e,
            TexramForm::Scaled => (1.0 + e) * (1.0 + e) - 1.0,
        };
        let got = eval(u, Mode::BitAccurate, n, m);
        let want = eval(u, Mode::Exact, n, m);
        let c = cross_f64(m.xs(), n.xs());
        if dot(c, c) < 1e-20 {
            // m parallel to n in the decoded values (e.g. a UnitSymmetric m = 16/15 n): the
            // datapath reads both exactly (up to a common scale) and gives zero axes, f64's
            // rounding leaves a tiny c of arbitrary direction; not a comparison of the table
            assert_eq!(got.map(|w| w.raws::<3>()), [[0; 3]; 2]);
            return;
        }
        for (k, rel) in [(0, e), (1, rel_v)] {
            for (g, w) in got[k].xs::<3>().iter().zip(want[k].xs::<3>()) {
                if w > out.decode(out.format.max_raw()) || w < out.decode(out.format.min_raw()) {
                    continue; // saturates
                }
                let err = (g - w).abs();
                let bound = w.abs() * rel + out.max_error() + 1e-12;
                acc.0 = acc.0.max(err);
                acc.1 = acc.1.max(err / bound);
                acc.2 = acc.2.max(err - bound);
            }
        }
    }

    /// Every pair of a 4-bit `n` (s1.3 lanes) and a 3-bit `m` (s2.1 lanes): 2^21 inputs per
    /// form. The bound (see `check`) holds everywhere, and the table's error is visible: the
    /// worst error is many output LSBs.
    #[test]
    fn exhaustive_small_widths_within_the_table_bound() {
        let en = Encoding::fixed(Format::s(4, 3));
        let em = Encoding::fixed(Format::s(3, 1));
        let out = Encoding::fixed(Format::s(14, 11));
        for form in [TexramForm::Normalized, TexramForm::Scaled] {
            let u = TexramFrame::new(en, em, form, 4, 8, out).unwrap();
            let mut acc = (0.0, 0.0, f64::NEG_INFINITY);
            for a in 0..1i64 << 12 {
                let n = Word::from_raw(&en, &[(a & 15) - 8, ((a >> 4) & 15) - 8, (a >> 8) - 8]);
                for b in 0..1i64 << 9 {
                    let m = Word::from_raw(&em, &[(b & 7) - 4, ((b >> 3) & 7) - 4, (b >> 6) - 4]);
                    check(&u, n, m, &mut acc);
                }
            }
            println!(
                "texram {form:?} t=4 vb=8 exhaustive: worst {:.5}, {:.3} of the bound",
                acc.0, acc.1
            );
            assert!(acc.2 <= 0.0, "{form:?}: bound exceeded by {}", acc.2);
            assert!(
                acc.0 > 16.0 * out.max_error(),
                "{form:?}: the table must show: {}",
                acc.0
            );
            assert!(acc.1 > 0.5, "{form:?}: the bound is loose: {}", acc.1);
        }
    }

    /// A `UnitSigned` normal (texel-style) and a `UnitSymmetric` main direction: the
    /// replicated codes are read as the datapath reads them in both modes, so the same bound
    /// holds.
    #[test]
    fn unit_codecs_within_the_table_bound() {
        let en = Encoding::texel(Codec::UnitSigned, true, 5);
        let em = Encoding::texel(Codec::UnitSymmetric, true, 4);
        let out = Encoding::texel(Codec::UnitSigned, true, 10);
        for form in [TexramForm::Normalized, TexramForm::Scaled] {
            let u = TexramFrame::new(en, em, form, 6, 10, out).unwrap();
            let mut acc = (0.0, 0.0, f64::NEG_INFINITY);
            for a in 0..1i64 << 15 {
                let n = Word::from_raw(&en, &[(a & 31) - 16, ((a >> 5) & 31) - 16, (a >> 10) - 16]);
                let m = Word::from_raw(&em, &[(a * 7 % 16) - 8, (a * 3 % 16) - 8, (a % 13) - 6]);
                check(&u, n, m, &mut acc);
            }
            assert!(acc.2 <= 0.0, "{form:?}: bound exceeded by {}", acc.2);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]
        /// Wide widths: random 16-bit `n` and `m`, tables of 6 to 12 index bits and 10 to 16
        /// value bits, a 16-bit output; within the bound of `check`.
        #[test]
        fn wide_widths_within_the_table_bound(
            scaled in any::<bool>(), t in 6u32..=12, vb in 10u32..=16,
            fn_ in 12u8..=15, fm in 10u8..=15,
            raws in proptest::collection::vec(-32768i64..32768, 6),
        ) {
            let form = if scaled { TexramForm::Scaled } else { TexramForm::Normalized };
            let en = Encoding::fixed(Format::s(16, fn_));
            let em = Encoding::fixed(Format::s(16, fm));
            let out = Encoding::fixed(Format::s(16, 12));
            let u = TexramFrame::new(en, em, form, t, vb, out).unwrap();
            let mut acc = (0.0, 0.0, f64::NEG_INFINITY);
            check(&u, Word::from_raw(&en, &raws[0..3]), Word::from_raw(&em, &raws[3..6]), &mut acc);
            prop_assert!(acc.2 <= 0.0, "bound exceeded by {}", acc.2);
        }
    }

    /// The worst error at the widths of the Texram configs (s2.8 vectors, a 256 x 12 table,
    /// s2.8 axes) over a deterministic sweep of unit normals and main directions.
    #[test]
    fn measured_error_at_config_widths() {
        let e = Encoding::fixed(Format::s(10, 8));
        let out = e;
        for form in [TexramForm::Normalized, TexramForm::Scaled] {
            let u = TexramFrame::new(e, e, form, 8, 12, out).unwrap();
            let mut acc = (0.0, 0.0, f64::NEG_INFINITY);
            for i in 0..20000 {
                let a = i as f64 * 0.618;
                let len = if form == TexramForm::Scaled {
                    0.6 + 0.4 * (a * 0.3).sin().abs()
                } else {
                    1.0
                };
                let n = unit([a.cos(), a.sin() * (a * 0.1).cos(), (a * 0.1).sin() + 0.2])
                    .map(|x| x * len);
                let m = [(a * 1.7).sin(), (a * 2.3).cos(), (a * 0.9).sin()];
                check(&u, Word::quantize(&e, &n), Word::quantize(&e, &m), &mut acc);
            }
            println!(
                "texram {form:?} t=8 vb=12 s2.8 -> s2.8: worst {:.5}, {:.3} of the bound",
                acc.0, acc.1
            );
            assert!(acc.2 <= 0.0, "{form:?}: bound exceeded by {}", acc.2);
            assert!(acc.0 > 2.0 * out.max_error(), "{form:?}: {}", acc.0);
        }
    }
}
