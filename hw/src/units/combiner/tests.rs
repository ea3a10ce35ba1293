use super::datapath::{ExactPath, FixedPath, Path};
use super::*;
use proptest::prelude::*;

const U8: Encoding = Encoding::texel(Codec::UnitUnsigned, false, 8);

fn rgba(c: [u8; 4]) -> Word {
    Word::from_raw(&U8, &c.map(i64::from))
}

/// Inputs: primary, secondary, fog, tex0..3.
fn inputs(prim: [u8; 4], sec: [u8; 4], tex0: [u8; 4]) -> [Word; 7] {
    let z = rgba([0; 4]);
    [rgba(prim), rgba(sec), z, rgba(tex0), z, z, z]
}

fn eval(u: &Combiner, mode: Mode, ins: &[Word]) -> [i64; 4] {
    let mut o = [Word::default()];
    u.eval(mode, ins, &mut o);
    o[0].raws()
}

/// One stage: RGB `A*B (+ C*D)` into spare0 with `op`, alpha likewise; final RGB = spare0,
/// alpha = spare0 alpha.
fn one_stage(rgb: Portion, alpha: Portion, c0: [u8; 4], c1: [u8; 4]) -> Program {
    Program {
        stages: vec![GeneralStage {
            rgb,
            alpha,
            c0,
            c1,
            ..GeneralStage::nop()
        }],
        final_combiner: FinalCombiner::just(
            FinalInput::new(Source::Spare0, Usage::Rgb, false),
            FinalInput::new(Source::Spare0, Usage::Alpha, false),
        ),
        mux_select: MuxSelect::Lsb,
    }
}

fn c0_times_one(op: OutputOp, alpha: bool) -> Portion {
    let (a, b) = if alpha {
        (
            Input::of(Source::Constant0, Usage::Alpha),
            Input::one_alpha(),
        )
    } else {
        (Input::of(Source::Constant0, Usage::Rgb), Input::one())
    };
    Portion {
        a,
        b,
        op,
        ab_out: Some(Source::Spare0),
        ..Portion::nop(alpha)
    }
}

#[test]
fn the_combiner_ops_frame_values() {
    // shared/nv2a/README.md: c0 = (0.1, 0.25, 1.0, 0.5) held as 8-bit codes (25, 63, 255, 127)
    let c0 = [25, 63, 255, 127];
    let want = [
        (OutputOp::Identity, [25, 63, 255, 127]),
        (OutputOp::Bias, [0, 0, 127, 0]),
        (OutputOp::ShiftLeft1, [50, 126, 255, 254]),
        (OutputOp::ShiftLeft1Bias, [0, 0, 254, 0]),
        (OutputOp::ShiftLeft2, [100, 252, 255, 255]),
        (OutputOp::ShiftRight1, [13, 32, 128, 64]),
    ];
    for (op, rgba_want) in want {
        let p = one_stage(c0_times_one(op, false), c0_times_one(op, true), c0, [0; 4]);
        let u = Combiner::new(CombinerParams::default(), p).unwrap();
        let ins = inputs([0; 4], [0; 4], [0; 4]);
        assert_eq!(
            eval(&u, Mode::BitAccurate, &ins),
            rgba_want.map(i64::from),
            "{op:?}"
        );
    }
}

/// The spec's mapping formula on a real number.
fn spec_map(x: f64, m: Mapping, half: f64) -> f64 {
    let pos = x.max(0.0);
    match m {
        Mapping::UnsignedIdentity => pos,
        Mapping::UnsignedInvert => 1.0 - x.clamp(0.0, 1.0),
        Mapping::ExpandNormal => 2.0 * pos - 1.0,
        Mapping::ExpandNegate => -2.0 * pos + 1.0,
        Mapping::HalfBiasNormal => pos - half,
        Mapping::HalfBiasNegate => -pos + half,
        Mapping::SignedIdentity => x,
        Mapping::SignedNegate => -x,
    }
}

#[test]
fn every_input_mapping_of_every_9_bit_register_word() {
    let p = FixedPath::new(DEFAULT_WIDTH);
    assert_eq!((p.s, p.half), (255, 128));
    for r in -256i64..=255 {
        let x = r as f64 / 255.0;
        for m in Mapping::ALL {
            let got = p.map(r, m);
            // the hardware's half is 128/255: exact against the formula with that half
            let want = spec_map(x, m, 128.0 / 255.0) * 255.0;
            assert_eq!(got as f64, want.round(), "{m:?} {r}");
            assert!(
                (got as f64 - want).abs() < 1e-9,
                "{m:?} {r}: {got} vs {want}"
            );
            // and within 0.5/255 of the spec's 0.5, which exact mode uses
            let exact = ExactPath.map(x, m);
            assert_eq!(exact, spec_map(x, m, 0.5), "{m:?} {r}");
            let d = (got as f64 / 255.0 - exact).abs();
            let bound = if matches!(m, Mapping::HalfBiasNormal | Mapping::HalfBiasNegate) {
                0.5 / 255.0
            } else {
                0.0
            };
            assert!(d <= bound + 1e-12, "{m:?} {r}: {d}");
            // a mapped word fits the multiplier's width + 1 bits
            assert!((-256..=256).contains(&got), "{m:?} {r}: {got}");
        }
    }
}

#[test]
fn every_output_op_of_every_9_bit_word_and_of_every_dot_product_sum() {
    let p = FixedPath::new(DEFAULT_WIDTH);
    // all 2^9 register words, and every value AB + CD or a dot product can take (3 x 255)
    for x in -3 * 255i64..=3 * 255 {
        for op in OutputOp::ALL {
            let (bias, shift) = op.parts();
            let scale = if shift < 0 { 0.5 } else { (1 << shift) as f64 };
            let got = p.out(x, op);
            // reference: clamp(round-half-up((x - 128 bias) * scale), -255, 255)
            let v = (x as f64 - if bias { 128.0 } else { 0.0 }) * scale;
            let want = (v + 0.5).floor().clamp(-255.0, 255.0);
            assert_eq!(got as f64, want, "{op:?} {x}");
            // against exact mode: the bias differs by 0.5/255 (scaled), the shift rounds
            let exact = ExactPath.out(x as f64 / 255.0, op);
            let bound = if bias { 0.5 / 255.0 * scale } else { 0.0 }
                + if shift < 0 { 0.5 / 255.0 } else { 0.0 };
            let d = (got as f64 / 255.0 - exact).abs();
            assert!(d <= bound + 1e-12, "{op:?} {x}: {d} > {bound}");
        }
    }
}

#[test]
fn wider_registers_hold_8_bit_codes_exactly_and_half_is_exact() {
    for w in 10..=MAX_WIDTH {
        let p = FixedPath::new(w);
        assert_eq!(p.s, 255 << (w - 9));
        assert_eq!(2 * p.half, p.s);
        for k in 0..=255u8 {
            assert_eq!(p.code_of(p.code(k)), k as i64);
            let s = crate::unit::Sample {
                x: U8.decode(k as i64),
                raw: k as i64,
            };
            assert_eq!(p.port(&s, &U8), p.code(k));
        }
    }
}

#[test]
fn mux_tests_the_lsb_or_the_msb_of_spare0_alpha() {
    // the Mux frame: spare0 alpha 0x82, 0x81, 0x00; LSB mode picks CD (blue) for 0x81 only,
    // MSB mode for 0x82 and 0x81.
    for (alpha, sel, blue) in [
        (0x82u8, MuxSelect::Lsb, false),
        (0x82, MuxSelect::Msb, true),
        (0x81, MuxSelect::Lsb, true),
        (0x81, MuxSelect::Msb, true),
        (0x00, MuxSelect::Lsb, false),
        (0x00, MuxSelect::Msb, false),
        (0x80, MuxSelect::Msb, true),
        (0x7f, MuxSelect::Msb, false),
    ] {
        let set_r0 = GeneralStage {
            rgb: Portion {
                a: Input::one(),
                b: Input::one(),
                ab_out: Some(Source::Spare0),
                ..Portion::nop(false)
            },
            alpha: Portion {
                a: Input::of(Source::Constant0, Usage::Alpha),
                b: Input::one_alpha(),
                ab_out: Some(Source::Spare0),
                ..Portion::nop(true)
            },
            c0: [0, 0, 0, alpha],
            ..GeneralStage::nop()
        };
        let mux = GeneralStage {
            rgb: Portion {
                a: Input::of(Source::Constant0, Usage::Rgb),
                b: Input::one(),
                c: Input::of(Source::Constant1, Usage::Rgb),
                d: Input::one(),
                mux: true,
                sum_out: Some(Source::Primary),
                ..Portion::nop(false)
            },
            c0: [255, 0, 0, 255],
            c1: [0, 0, 255, 255],
            ..GeneralStage::nop()
        };
        let prog = Program {
            stages: vec![set_r0, mux],
            final_combiner: FinalCombiner::just(
                FinalInput::new(Source::Primary, Usage::Rgb, false),
                FinalInput::one(),
            ),
            mux_select: sel,
        };
        let prog = Program {
            final_combiner: FinalCombiner {
                g: FinalInput::new(Source::Zero, Usage::Alpha, true),
                ..prog.final_combiner
            },
            ..prog
        };
        let u = Combiner::new(CombinerParams::default(), prog).unwrap();
        let ins = inputs([9; 4], [0; 4], [0; 4]);
        let want = if blue {
            [0, 0, 255, 255]
        } else {
            [255, 0, 0, 255]
        };
        for mode in [Mode::BitAccurate, Mode::Exact] {
            assert_eq!(eval(&u, mode, &ins), want, "{alpha:#x} {sel:?} {mode:?}");
        }
    }
}

#[test]
fn a_stage_reads_the_registers_as_they_were_before_it() {
    // the Independence frame: stage 1 writes c0 (red) to spare0 and spare0 (green) to spare1
    let s0 = GeneralStage {
        rgb: Portion {
            a: Input::of(Source::Constant0, Usage::Rgb),
            b: Input::one(),
            ab_out: Some(Source::Spare0),
            ..Portion::nop(false)
        },
        c0: [0, 255, 0, 255],
        ..GeneralStage::nop()
    };
    let s1 = GeneralStage {
        rgb: Portion {
            a: Input::of(Source::Constant0, Usage::Rgb),
            b: Input::one(),
            c: Input::of(Source::Spare0, Usage::Rgb),
            d: Input::one(),
            ab_out: Some(Source::Spare0),
            cd_out: Some(Source::Spare1),
            ..Portion::nop(false)
        },
        c0: [255, 0, 0, 255],
        ..GeneralStage::nop()
    };
    let prog = Program {
        stages: vec![s0, s1],
        final_combiner: FinalCombiner::just(
            FinalInput::new(Source::Spare1, Usage::Rgb, false),
            FinalInput::new(Source::Zero, Usage::Alpha, true),
        ),
        mux_select: MuxSelect::Lsb,
    };
    let u = Combiner::new(CombinerParams::default(), prog).unwrap();
    let ins = inputs([0; 4], [0; 4], [0; 4]);
    assert_eq!(eval(&u, Mode::BitAccurate, &ins), [0, 255, 0, 255]);
}

fn sum_program(invert_r0: bool, invert_v1: bool, clamp: bool, a: FinalInput) -> Program {
    let s0 = GeneralStage {
        rgb: Portion {
            a: Input::of(Source::Constant0, Usage::Rgb),
            b: Input::one(),
            c: Input::of(Source::Constant1, Usage::Rgb),
            d: Input::one(),
            ab_out: Some(Source::Spare0),
            cd_out: Some(Source::Secondary),
            ..Portion::nop(false)
        },
        c0: [63, 127, 191, 0],
        c1: [178, 127, 38, 127],
        ..GeneralStage::nop()
    };
    Program {
        stages: vec![s0],
        final_combiner: FinalCombiner {
            a,
            b: FinalInput::new(Source::Spare0PlusSecondary, Usage::Rgb, false),
            g: FinalInput::new(Source::Zero, Usage::Alpha, true),
            sum_invert_spare0: invert_r0,
            sum_invert_secondary: invert_v1,
            sum_clamp: clamp,
            c0: [127; 4],
            ..FinalCombiner::just(FinalInput::zero(), FinalInput::one())
        },
        mux_select: MuxSelect::Lsb,
    }
}

#[test]
fn the_final_combiner_sum_flags_and_ef_product() {
    let ins = inputs([0; 4], [0; 4], [0; 4]);
    let one = FinalInput::one();
    // SpecialInputs: no flags, 1 - R0, 1 - V1
    for (r0, v1, want) in [
        (false, false, [241, 254, 229]),
        (true, false, [255, 255, 102]),
        (false, true, [140, 255, 255]),
    ] {
        let u = Combiner::new(CombinerParams::default(), sum_program(r0, v1, false, one)).unwrap();
        let got = eval(&u, Mode::BitAccurate, &ins);
        assert_eq!(got[..3], want.map(i64::from), "{r0} {v1}");
    }
    // Flags: A = 127/255, B = 1 + 1 unclamped -> 254; clamped -> 127
    let mut p = sum_program(
        false,
        false,
        false,
        FinalInput::new(Source::Constant0, Usage::Rgb, false),
    );
    p.stages[0].c0 = [255; 4];
    p.stages[0].c1 = [255; 4];
    let u = Combiner::new(CombinerParams::default(), p.clone()).unwrap();
    assert_eq!(eval(&u, Mode::BitAccurate, &ins)[..3], [254; 3]);
    p.final_combiner.sum_clamp = true;
    let u = Combiner::new(CombinerParams::default(), p).unwrap();
    assert_eq!(eval(&u, Mode::BitAccurate, &ins)[..3], [127; 3]);
    // EFProd: E = (255, 191, 127), F = 127 -> (127, 95, 63)
    let prog = Program {
        stages: vec![GeneralStage::nop()],
        final_combiner: FinalCombiner {
            e: FinalInput::new(Source::Constant0, Usage::Rgb, false),
            f: FinalInput::new(Source::Constant1, Usage::Rgb, false),
            c0: [255, 191, 127, 255],
            c1: [127; 4],
            ..FinalCombiner::just(
                FinalInput::new(Source::EfProduct, Usage::Rgb, false),
                FinalInput::new(Source::Zero, Usage::Alpha, true),
            )
        },
        mux_select: MuxSelect::Lsb,
    };
    let u = Combiner::new(CombinerParams::default(), prog).unwrap();
    assert_eq!(eval(&u, Mode::BitAccurate, &ins), [127, 95, 63, 255]);
}

#[test]
fn bad_configurations_name_the_field() {
    let good = one_stage(
        c0_times_one(OutputOp::Identity, false),
        c0_times_one(OutputOp::Identity, true),
        [1; 4],
        [2; 4],
    );
    let d = CombinerParams::default();
    let err = |params: CombinerParams, p: Program| Combiner::new(params, p).err().unwrap();
    assert!(err(CombinerParams { width: 8, ..d }, good.clone()).starts_with("width: 8"));
    assert!(err(CombinerParams { width: 25, ..d }, good.clone()).starts_with("width: 25"));
    assert!(err(CombinerParams { stages: 0, ..d }, good.clone()).starts_with("stages: 0"));
    let nine = Program {
        stages: vec![GeneralStage::nop(); 9],
        ..good.clone()
    };
    assert!(err(d, nine).contains("expected 1 to 8"));
    let empty = Program {
        stages: vec![],
        ..good.clone()
    };
    assert!(err(d, empty).starts_with("stages: 0 given"));
    let mut p = good.clone();
    p.stages[0].alpha.ab_dot = true;
    assert!(err(d, p).starts_with("stages[0].alpha.ab_dot"));
    let mut p = good.clone();
    p.stages[0].alpha.c = Input::of(Source::Spare1, Usage::Rgb);
    assert!(err(d, p).starts_with("stages[0].alpha.c.usage"));
    let mut p = good.clone();
    p.stages[0].rgb.b = Input::of(Source::Spare1, Usage::Blue);
    assert!(err(d, p).starts_with("stages[0].rgb.b.usage"));
    let mut p = good.clone();
    p.stages[0].rgb.d = Input::of(Source::EfProduct, Usage::Rgb);
    assert!(err(d, p).starts_with("stages[0].rgb.d.source"));
    let mut p = good.clone();
    p.stages[0].rgb.cd_out = Some(Source::Constant0);
    assert!(err(d, p).starts_with("stages[0].rgb.cd_out"));
    let mut p = good.clone();
    p.stages[0].rgb.sum_out = Some(Source::Spare0);
    assert!(err(d, p).contains("is also ab_out"));
    let mut p = good.clone();
    p.final_combiner.g = FinalInput::new(Source::Spare0, Usage::Rgb, false);
    assert!(err(d, p).starts_with("final_combiner.g.usage"));
    let mut p = good.clone();
    p.final_combiner.e = FinalInput::new(Source::Spare0PlusSecondary, Usage::Rgb, false);
    assert!(err(d, p).starts_with("final_combiner.e.source"));
    let mut p = good.clone();
    p.final_combiner.a = FinalInput::new(Source::EfProduct, Usage::Alpha, false);
    assert!(err(d, p).starts_with("final_combiner.a.usage"));
    let mut bad_enc = d;
    bad_enc.inputs[3].format.width = 0;
    assert!(err(bad_enc, good.clone()).starts_with("inputs.tex0"));
    assert!(Combiner::new(d, good).is_ok());
}

#[test]
fn timing_and_gate_budget() {
    let p = one_stage(
        c0_times_one(OutputOp::Identity, false),
        c0_times_one(OutputOp::Identity, true),
        [0; 4],
        [0; 4],
    );
    let u = Combiner::new(CombinerParams::default(), p.clone()).unwrap();
    assert_eq!((u.latency(), u.interval()), (10, 1));
    let g = u.gates(&CostTable::default());
    assert!(g.items.len() > 20);
    let four = Combiner::new(
        CombinerParams {
            stages: 4,
            ..CombinerParams::default()
        },
        p,
    )
    .unwrap();
    let g4 = four.gates(&CostTable::default());
    assert!(g4.total() < g.total() && g4.total() > 0.4 * g.total());
}

/// A small deterministic generator for random programs.
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 33
    }
    fn pick<T: Copy>(&mut self, xs: &[T]) -> T {
        xs[self.next() as usize % xs.len()]
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    fn bit(&mut self) -> bool {
        self.next() & 1 == 1
    }
}

const READABLE: [Source; 12] = [
    Source::Zero,
    Source::Constant0,
    Source::Constant1,
    Source::Fog,
    Source::Primary,
    Source::Secondary,
    Source::Texture0,
    Source::Texture1,
    Source::Texture2,
    Source::Texture3,
    Source::Spare0,
    Source::Spare1,
];
const WRITABLE: [Source; 8] = [
    Source::Primary,
    Source::Secondary,
    Source::Texture0,
    Source::Texture1,
    Source::Texture2,
    Source::Texture3,
    Source::Spare0,
    Source::Spare1,
];

fn random_portion(r: &mut Lcg, alpha: bool, tame: bool) -> Portion {
    let usages: &[Usage] = if alpha {
        &[Usage::Alpha, Usage::Blue]
    } else {
        &[Usage::Rgb, Usage::Alpha]
    };
    let input = |r: &mut Lcg| Input::new(r.pick(&READABLE), r.pick(usages), r.pick(&Mapping::ALL));
    let (a, b, c, d) = (input(r), input(r), input(r), input(r));
    let mut outs: Vec<Option<Source>> = Vec::new();
    for _ in 0..3 {
        let o = if r.bit() {
            None
        } else {
            Some(r.pick(&WRITABLE))
        };
        outs.push(if o.is_some() && outs.contains(&o) {
            None
        } else {
            o
        });
    }
    Portion {
        a,
        b,
        c,
        d,
        ab_dot: !alpha && r.bit(),
        cd_dot: !alpha && r.bit(),
        mux: !tame && r.below(4) == 0,
        op: if tame {
            r.pick(&[OutputOp::Identity, OutputOp::Bias, OutputOp::ShiftRight1])
        } else {
            r.pick(&OutputOp::ALL)
        },
        ab_out: outs[0],
        cd_out: outs[1],
        sum_out: outs[2],
    }
}

fn random_final_input(r: &mut Lcg, special: bool) -> FinalInput {
    if special && r.below(3) == 0 {
        let s = r.pick(&[Source::Spare0PlusSecondary, Source::EfProduct]);
        return FinalInput::new(s, Usage::Rgb, r.bit());
    }
    FinalInput::new(
        r.pick(&READABLE),
        r.pick(&[Usage::Rgb, Usage::Alpha]),
        r.bit(),
    )
}

fn random_program(r: &mut Lcg, stages: usize, tame: bool) -> Program {
    let code = |r: &mut Lcg| -> [u8; 4] { std::array::from_fn(|_| r.next() as u8) };
    let stages = (0..stages)
        .map(|_| GeneralStage {
            rgb: random_portion(r, false, tame),
            alpha: random_portion(r, true, tame),
            ab_blue_to_alpha: r.below(4) == 0,
            cd_blue_to_alpha: r.below(4) == 0,
            c0: code(r),
            c1: code(r),
        })
        .collect();
    let final_combiner = FinalCombiner {
        a: random_final_input(r, true),
        b: random_final_input(r, true),
        c: random_final_input(r, true),
        d: random_final_input(r, true),
        e: random_final_input(r, false),
        f: random_final_input(r, false),
        g: FinalInput::new(
            r.pick(&READABLE),
            r.pick(&[Usage::Alpha, Usage::Blue]),
            r.bit(),
        ),
        sum_invert_spare0: r.bit(),
        sum_invert_secondary: r.bit(),
        sum_clamp: r.bit(),
        c0: code(r),
        c1: code(r),
    };
    Program {
        stages,
        final_combiner,
        mux_select: r.pick(&[MuxSelect::Lsb, MuxSelect::Msb]),
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    #[test]
    fn exact_and_bit_accurate_agree_within_the_propagated_bound(
        seed in any::<u64>(), stages in 1usize..=8, width in 9u32..=16, signed_tex in any::<bool>(),
        tame in any::<bool>(),
    ) {
        let mut r = Lcg(seed);
        // tame programs (no mux, no x2 / x4 scales, at most 2 stages) have a small bound: at
        // most 0.5 (0.30 seen at 9 bits, 2 stages: hw/proptest-regressions), where wild ones
        // reach several units
        let stages = if tame { stages.min(2) } else { stages };
        let prog = random_program(&mut r, stages, tame);
        let mut params = CombinerParams { width, ..CombinerParams::default() };
        let s8 = Encoding::texel(Codec::UnitSigned, true, 8);
        if signed_tex {
            params.inputs[3] = s8; // a signed texture result on tex0
        }
        let u = Combiner::new(params, prog).unwrap();
        let bound = u.mode_error_bound();
        if tame {
            prop_assert!(bound.iter().all(|&b| b <= 0.5), "{:?}", bound);
        }
        for _ in 0..16 {
            let ins: Vec<Word> = (0..7)
                .map(|k| {
                    let enc = params.inputs[k];
                    let raws: Vec<i64> = (0..4)
                        .map(|_| {
                            let f = enc.format;
                            f.min_raw() + (r.next() as i64).rem_euclid(f.max_raw() - f.min_raw() + 1)
                        })
                        .collect();
                    Word::from_raw(&enc, &raws)
                })
                .collect();
            let mut ob = [Word::default()];
            let mut oe = [Word::default()];
            u.eval(Mode::BitAccurate, &ins, &mut ob);
            u.eval(Mode::Exact, &ins, &mut oe);
            for (l, &bl) in bound.iter().enumerate() {
                let (b, e) = (ob[0].lanes[l], oe[0].lanes[l]);
                prop_assert_eq!(b.x, U8.decode(b.raw));
                prop_assert!((0.0..=1.0).contains(&e.x));
                prop_assert!(
                    (b.x - e.x).abs() <= bl + 1e-9,
                    "lane {}: bit {} exact {} bound {}", l, b.x, e.x, bl
                );
            }
        }
    }
}

#[test]
fn the_bound_is_tight_for_8_bit_programs_without_arithmetic() {
    // a pass-through of 8-bit inputs is exact in both modes: the bound is 0
    let prog = Program {
        stages: vec![GeneralStage::nop()],
        final_combiner: FinalCombiner::just(
            FinalInput::new(Source::Texture0, Usage::Rgb, false),
            FinalInput::new(Source::Texture0, Usage::Alpha, true),
        ),
        mux_select: MuxSelect::Lsb,
    };
    let u = Combiner::new(CombinerParams::default(), prog).unwrap();
    assert_eq!(u.mode_error_bound(), [0.0; 4]);
    // a single product: half an LSB
    let p = one_stage(
        Portion {
            a: Input::of(Source::Primary, Usage::Rgb),
            b: Input::of(Source::Texture0, Usage::Rgb),
            ab_out: Some(Source::Spare0),
            ..Portion::nop(false)
        },
        Portion::nop(true),
        [0; 4],
        [0; 4],
    );
    let u = Combiner::new(CombinerParams::default(), p).unwrap();
    let b = u.mode_error_bound();
    assert!((b[0] - 0.5 / 255.0).abs() < 1e-15, "{b:?}");
}

#[test]
fn gate_budget_of_the_default_8_stage_part() {
    let p = one_stage(Portion::nop(false), Portion::nop(true), [0; 4], [0; 4]);
    let u = Combiner::new(CombinerParams::default(), p).unwrap();
    let g = u.gates(&CostTable::default());
    for i in &g.items {
        println!("{:>10.0}  {}", i.ge, i.what);
    }
    println!("{:>10.0}  total", g.total());
    assert!(g.total() > 0.0);
}
