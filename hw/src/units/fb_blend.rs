//! Framebuffer blending of a base colour with a shaded palette entry: Tarini, Cignoni,
//! Rocchini, Scopigno 1999, §7 ("Blending color").
//!
//! The base (pictorial) colour `(r_o, g_o, b_o)` is drawn by a first pass from a colour
//! texture; the quantized normal map's entry `c_i = (r_i, g_i, b_i, alpha_i)` holds the
//! Lambert intensity in alpha and the specular colour in RGB (§7.1; the
//! [`crate::units::LightingFn::SpecularSplit`] form). The framebuffer's blend stage then
//! combines them per channel:
//!
//! * **Equation (1), exact specular** (§7.1): `r = r_o alpha_i + (1 - r_o alpha_i) r_i`, in
//!   two extra passes: "one to multiply the original color with alpha_i" (`dst = dst .
//!   src_alpha`, OpenGL `glBlendFunc(GL_ZERO, GL_SRC_ALPHA)`) "and another one to add the
//!   second term" (`dst = src (1 - dst) + dst`, `glBlendFunc(GL_ONE_MINUS_DST_COLOR,
//!   GL_ONE)`). Three passes in all.
//! * **Equation (2), approximate specular** (§7.2): `r = r_o alpha_i + (1 - r_o) r_i`, "in a
//!   single extra pass" (`dst = src (1 - dst) + dst . src_alpha`,
//!   `glBlendFunc(GL_ONE_MINUS_DST_COLOR, GL_SRC_ALPHA)`). Two passes in all.
//!
//! Colour as a material attribute (§7.3) needs no blending and no unit: the palette entry
//! is the final colour.
//!
//! # The model
//! Ports: `base` (3 lanes) and `entry` (4 lanes, RGBA) in, `c` (3 lanes, the framebuffer
//! encoding) out. The passes run one after another over the whole frame; the pipeline
//! simulator streams one fragment through all of them at once (interval 1, latency 2) and
//! the report charges every pass its own cycles and framebuffer traffic
//! ([`FbBlend::passes`]). Exact mode: the equations in f64, clamped to [0, 1]. Bit-accurate
//! mode: the framebuffer holds words of `fb` between passes, so each pass ends in a cast to
//! `fb` (the base colour written by pass 1, `r_o alpha_i` after pass 2 of equation (1), the
//! result); within a pass the blend is exact ([`Acc`]) and `1 - dst` is exact (OpenGL's
//! `ONE_MINUS_DST_COLOR`).
//!
//! Gates: one generic blend stage `src f_s + dst f_d` per channel (two multipliers `fb x
//! entry`, one adder, the clamp and cast), shared by all passes, and the output register.
//! The framebuffer memory is not counted.

use crate::arith::Acc;
use crate::format::{Codec, Encoding};
use crate::gates::{CostTable, GateBudget};
use crate::unit::{Mode, PortSpec, Unit, Word};

/// Which of Tarini's blending equations.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum BlendEquation {
    /// Equation (1): `r_o alpha + (1 - r_o alpha) r_i`, two extra passes.
    Exact,
    /// Equation (2): `r_o alpha + (1 - r_o) r_i`, one extra pass.
    Approx,
}

impl BlendEquation {
    /// Rendering passes including the base colour pass (§7: "three, two and one").
    pub fn passes(self) -> u32 {
        match self {
            BlendEquation::Exact => 3,
            BlendEquation::Approx => 2,
        }
    }
}

pub struct FbBlend {
    eq: BlendEquation,
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
}

impl FbBlend {
    /// `base`, `entry`: the encodings of the wires in; `fb`: the framebuffer's colour words.
    pub fn new(
        eq: BlendEquation,
        base: Encoding,
        entry: Encoding,
        fb: Encoding,
    ) -> Result<Self, String> {
        fb.validate()?;
        if fb.format.signed {
            return Err(format!(
                "framebuffer encoding {fb}: expected an unsigned one"
            ));
        }
        if fb.decode(fb.format.max_raw()) < 1.0 {
            return Err(format!(
                "framebuffer encoding {fb}: expected one that holds 1.0"
            ));
        }
        Ok(FbBlend {
            eq,
            inputs: vec![
                PortSpec::new("base", 3, base),
                PortSpec::new("entry", 4, entry),
            ],
            outputs: vec![PortSpec::new("c", 3, fb)],
        })
    }
    pub fn equation(&self) -> BlendEquation {
        self.eq
    }
    /// Rendering passes including the base colour pass.
    pub fn passes(&self) -> u32 {
        self.eq.passes()
    }
    /// Bits of one framebuffer colour word (three channels).
    pub fn fb_bits(&self) -> u32 {
        3 * self.outputs[0].enc.width()
    }
    fn fb(&self) -> Encoding {
        self.outputs[0].enc
    }
}

/// Equation (1) or (2) on one channel, in f64.
pub fn blend_exact(eq: BlendEquation, ro: f64, alpha: f64, ri: f64) -> f64 {
    let v = match eq {
        BlendEquation::Exact => {
            let d = (ro * alpha).clamp(0.0, 1.0);
            d + (1.0 - d) * ri
        }
        BlendEquation::Approx => ro * alpha + (1.0 - ro) * ri,
    };
    v.clamp(0.0, 1.0)
}

impl Unit for FbBlend {
    fn kind(&self) -> &'static str {
        "fb_blend"
    }
    fn inputs(&self) -> &[PortSpec] {
        &self.inputs
    }
    fn outputs(&self) -> &[PortSpec] {
        &self.outputs
    }
    fn latency(&self) -> u32 {
        2
    }
    fn interval(&self) -> u32 {
        1
    }
    /// Priced as `rtl::fb_blend` builds it (`docs/units/fb_blend.md`), per channel: the two
    /// products (`r_o alpha` on the codes; `(1 - dst) r_i` on the plain `1 - dst`, which a
    /// unit framebuffer word makes `2n + 1` bits wide), the `1 - dst` subtractor and the sum,
    /// each framebuffer word's cast by its folded constant's digits (`shift_add` over the
    /// word's `n` bits: the rounding keeps only them, so the lower copies reach it as carries;
    /// the pass-1 base word where the encodings differ, equation (1)'s `d`, the result), the
    /// output register and the sequencer.
    fn gates(&self, t: &CostTable) -> GateBudget {
        let fb = self.fb();
        let wf = fb.width();
        let (be, ee) = (self.inputs[0].enc, self.inputs[1].enc);
        let we = ee.width();
        let rep = |e: &Encoding| match e.codec {
            Codec::UnitUnsigned | Codec::UnitSymmetric => (1u128 << e.width()) + 1,
            _ => 1,
        };
        let unit_out = matches!(fb.codec, Codec::UnitUnsigned | Codec::UnitSymmetric);
        let out_k = if unit_out { (1u128 << wf) - 1 } else { 1 };
        // the plain value of a framebuffer word read back (the replication applied)
        let pw = if rep(&fb) > 1 { 2 * wf } else { wf } + 1;
        let mut g = GateBudget::new();
        if be != fb {
            let k = rep(&be) * out_k;
            g.add(format!("base word cast x{k} {wf}"), 3, t.shift_add(wf, k));
            g.add(format!("base word clamp {wf}"), 3, t.clamp(wf));
        }
        g.add(
            format!("alpha multiplier {wf}x{we}"),
            3,
            t.multiplier(wf, we),
        );
        g.add(format!("1 - dst subtractor {pw}"), 3, t.adder(pw));
        g.add(
            format!("(1 - dst) multiplier {pw}x{we}"),
            3,
            t.multiplier(pw, we),
        );
        if self.eq == BlendEquation::Exact {
            let k = rep(&fb) * rep(&ee) * out_k;
            g.add(format!("d word cast x{k} {wf}"), 3, t.shift_add(wf, k));
        }
        let ws = pw + we + 1;
        g.add(format!("blend adder {ws}"), 3, t.adder(ws));
        let k = rep(&ee) * out_k;
        g.add(format!("result cast x{k} {wf}"), 3, t.shift_add(wf, k));
        g.add(format!("result clamp {wf}"), 3, t.clamp(wf));
        g.add(format!("output register {}", 3 * wf), 1, t.register(3 * wf));
        g.add("sequencer", 1, t.sequencer(1));
        g
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        let fb = self.fb();
        let (base, entry) = (&ins[0], &ins[1]);
        outs[0] = match mode {
            Mode::Exact => {
                let a = entry.lanes[3].x;
                let v: [f64; 3] = std::array::from_fn(|i| {
                    blend_exact(self.eq, base.lanes[i].x, a, entry.lanes[i].x)
                });
                Word::from_exact(&fb, &v)
            }
            Mode::BitAccurate => {
                let (be, ee) = (&self.inputs[0].enc, &self.inputs[1].enc);
                let one = Acc::new(1, 0);
                let word = |x: Acc| x.clamp(Acc::ZERO, one).to_code(&fb);
                let read = |raw: i64| Acc::from_code(raw, &fb);
                let alpha = Acc::from_code(entry.lanes[3].raw, ee);
                let v: [i64; 3] = std::array::from_fn(|i| {
                    // pass 1: the base colour lands in the framebuffer
                    let ro = read(word(Acc::from_code(base.lanes[i].raw, be)));
                    let ri = Acc::from_code(entry.lanes[i].raw, ee);
                    match self.eq {
                        BlendEquation::Exact => {
                            // pass 2: dst = dst alpha; pass 3: dst = src (1 - dst) + dst
                            let d = read(word(ro.mul(alpha)));
                            word(one.sub(d).mul(ri).add(d))
                        }
                        // pass 2: dst = src (1 - dst) + dst alpha
                        BlendEquation::Approx => word(one.sub(ro).mul(ri).add(ro.mul(alpha))),
                    }
                });
                Word::from_raw(&fb, &v)
            }
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::Codec;

    fn u8e() -> Encoding {
        Encoding::texel(Codec::UnitUnsigned, false, 8)
    }
    fn run(u: &mut FbBlend, mode: Mode, base: [i64; 3], entry: [i64; 4]) -> Word {
        let e = u8e();
        let mut o = [Word::default()];
        u.eval(
            mode,
            &[Word::from_raw(&e, &base), Word::from_raw(&e, &entry)],
            &mut o,
        );
        o[0]
    }

    #[test]
    fn equations_by_hand() {
        // r_o = 0.5, alpha = 0.5, r_i = 0.5: (1) 0.25 + 0.75 * 0.5 = 0.625; (2) 0.25 + 0.25
        assert_eq!(blend_exact(BlendEquation::Exact, 0.5, 0.5, 0.5), 0.625);
        assert_eq!(blend_exact(BlendEquation::Approx, 0.5, 0.5, 0.5), 0.5);
        // no specular: both are r_o alpha
        for eq in [BlendEquation::Exact, BlendEquation::Approx] {
            assert_eq!(blend_exact(eq, 0.8, 0.25, 0.0), 0.2);
        }
        // white base: (2) loses the highlight entirely, (1) keeps it
        assert_eq!(blend_exact(BlendEquation::Approx, 1.0, 0.5, 0.8), 0.5);
        assert!((blend_exact(BlendEquation::Exact, 1.0, 0.5, 0.8) - 0.9).abs() < 1e-15);
        assert_eq!(BlendEquation::Exact.passes(), 3);
        assert_eq!(BlendEquation::Approx.passes(), 2);
    }

    #[test]
    fn bit_accurate_8_bit_values_by_hand() {
        let e = u8e();
        let mut u1 = FbBlend::new(BlendEquation::Exact, e, e, e).unwrap();
        let mut u2 = FbBlend::new(BlendEquation::Approx, e, e, e).unwrap();
        // r_o = 200, alpha = 128, r_i = 64 (codes / 255)
        // (1): d = round(200 * 128 / 255) = round(100.39) = 100; r = 100 + (155/255) * 64
        //      = 100 + 38.90 -> 139
        // (2): 200 * 128 / 255 + 55 * 64 / 255 = 100.39 + 13.80 = 114.20 -> 114
        assert_eq!(
            run(&mut u1, Mode::BitAccurate, [200; 3], [64, 64, 64, 128]).raws::<3>(),
            [139; 3]
        );
        assert_eq!(
            run(&mut u2, Mode::BitAccurate, [200; 3], [64, 64, 64, 128]).raws::<3>(),
            [114; 3]
        );
    }

    #[test]
    fn bit_accurate_is_within_two_framebuffer_steps_of_exact_exhaustively_on_a_grid() {
        let e = u8e();
        for eq in [BlendEquation::Exact, BlendEquation::Approx] {
            let mut u = FbBlend::new(eq, e, e, e).unwrap();
            for ro in (0..=255).step_by(5) {
                for a in (0..=255).step_by(3) {
                    for ri in (0..=255).step_by(7) {
                        let bits = run(&mut u, Mode::BitAccurate, [ro; 3], [ri, ri, ri, a]);
                        let exact = run(&mut u, Mode::Exact, [ro; 3], [ri, ri, ri, a]);
                        let d = (bits.xs::<3>()[0] - exact.xs::<3>()[0]).abs();
                        // one rounding per pass: half a step each, plus read-back slack
                        let bound = match eq {
                            BlendEquation::Exact => 1.0 / 255.0 + 1e-9,
                            BlendEquation::Approx => 0.5 / 255.0 + 1e-9,
                        };
                        assert!(d <= bound, "{eq:?} {ro} {a} {ri}: {d}");
                    }
                }
            }
        }
    }

    #[test]
    fn rejects_a_signed_or_short_framebuffer() {
        let e = u8e();
        let signed = Encoding::texel(Codec::UnitSigned, true, 8);
        assert!(FbBlend::new(BlendEquation::Exact, e, e, signed).is_err());
        let frac = Encoding::fixed(crate::format::Format {
            signed: false,
            width: 8,
            frac: 8,
        });
        let err = FbBlend::new(BlendEquation::Exact, e, e, frac)
            .err()
            .unwrap();
        assert!(err.contains("holds 1.0"), "{err}");
    }

    #[test]
    fn gates_are_one_blend_stage_and_equation_1_adds_a_cast() {
        let t = CostTable::default();
        let e = u8e();
        let g = FbBlend::new(BlendEquation::Exact, e, e, e)
            .unwrap()
            .gates(&t);
        let item =
            |g: &GateBudget, what: &str| g.items.iter().find(|i| i.what == what).map(|i| i.ge);
        // r_o alpha on the codes, (1 - dst) r_i on the plain 17-bit 1 - dst
        assert_eq!(
            item(&g, "alpha multiplier 8x8"),
            Some(3.0 * t.multiplier(8, 8))
        );
        assert_eq!(
            item(&g, "(1 - dst) multiplier 17x8"),
            Some(3.0 * t.multiplier(17, 8))
        );
        let g2 = FbBlend::new(BlendEquation::Approx, e, e, e)
            .unwrap()
            .gates(&t);
        // equation (1)'s extra pass is one more framebuffer word: d = r_o alpha
        let d = 3.0 * t.shift_add(8, 257 * 257 * 255);
        assert!((g.total() - g2.total() - d).abs() < 1e-9);
    }
}
