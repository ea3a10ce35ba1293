//! The units of the RTL tests: the units at the bundled configs' widths
//! (`configs/sgi-teapot.ron`: dot, spec, shade; `configs/gouraud-teapot.ron`: diffuse,
//! specular), and variants that exercise the other parameters of the generators.

// shared by rtl_cosim.rs (both lists) and rtl_synth.rs (the bundled units only)
#![allow(dead_code)]

pub mod quantized;
pub mod texture_shader;

use bumpsim_hw::rtl::{self, Dot3Rtl, ModulateRtl, PowerTableRtl, RtlUnit, ShadeRtl};
use bumpsim_hw::units::rop::{Compare, Factor};
use bumpsim_hw::units::{
    Address, BlendEquation, CullFragment, CullTest, EmbossFilter, FbBlend, Filter, QuatFrame,
    TexFetch, Texels, TexramForm, TexramFrame,
};
use bumpsim_hw::units::{
    BlendKind, BumpBlend, BumpBlendParams, Clamp, LightState, Selective, ShadeInputs, ShadeParams,
    SpecGen, VecSource,
};
use bumpsim_hw::units::{Rop, RopDatapath, RopParams};
use bumpsim_hw::{Codec, Encoding, Format, Overflow, Quant, Sampler, Texture, Unit};

/// A unit under test: its name, the model and its Verilog.
pub struct Case {
    pub name: &'static str,
    pub unit: Box<dyn Unit>,
    pub rtl: RtlUnit,
}

impl Case {
    pub fn new(name: &'static str, unit: impl Unit + 'static, rtl: RtlUnit) -> Case {
        Case {
            name,
            unit: Box::new(unit),
            rtl,
        }
    }
}

pub(crate) fn fixed(signed: bool, w: u8, f: u8) -> Encoding {
    Encoding::fixed(if signed {
        Format::s(w, f)
    } else {
        Format::u(w, f)
    })
}
pub(crate) fn uu(w: u8) -> Encoding {
    Encoding::texel(Codec::UnitUnsigned, false, w)
}
fn us(w: u8) -> Encoding {
    Encoding::texel(Codec::UnitSigned, true, w)
}

fn dot3(name: &'static str, p: Dot3Rtl) -> Case {
    Case::new(name, p.unit(), p.rtl(name))
}
fn power(name: &'static str, p: PowerTableRtl) -> Case {
    Case::new(name, p.unit(), p.rtl(name))
}
fn shade(name: &'static str, p: ShadeRtl) -> Case {
    Case::new(name, p.unit(), p.rtl(name))
}
fn modulate(name: &'static str, p: ModulateRtl) -> Case {
    Case::new(name, p.unit(), p.rtl(name))
}
/// The register combiners at 9 bits with one general stage: RGB `A.B` and `C.D` of expanded
/// 8-bit codes into spare0 and spare1, alpha `A*B + C*D` of the constants into spare0; the
/// final combiner `A*B + (1 - A)*C + D` over the spares, the `E*F` product and the secondary
/// colour. Ports primary, secondary and tex0 (RGBA, 8-bit unit codes).
fn combiner(name: &'static str) -> Case {
    use bumpsim_hw::units::combiner::{
        Combiner, CombinerParams, FinalCombiner, FinalInput, GeneralStage, Input, Mapping,
        MuxSelect, OutputOp, Portion, Program, Source, Usage,
    };
    let expand = |s: Source| Input::new(s, Usage::Rgb, Mapping::ExpandNormal);
    let stage = GeneralStage {
        rgb: Portion {
            a: expand(Source::Texture0),
            b: expand(Source::Primary),
            c: expand(Source::Texture0),
            d: expand(Source::Secondary),
            ab_dot: true,
            cd_dot: true,
            op: OutputOp::default(),
            ab_out: Some(Source::Spare0),
            cd_out: Some(Source::Spare1),
            ..Portion::nop(false)
        },
        alpha: Portion {
            a: Input::of(Source::Constant0, Usage::Alpha),
            b: Input::of(Source::Primary, Usage::Alpha),
            c: Input::of(Source::Constant1, Usage::Alpha),
            d: Input::of(Source::Texture0, Usage::Alpha),
            sum_out: Some(Source::Spare0),
            ..Portion::nop(true)
        },
        c0: [204, 115, 77, 96],
        c1: [20, 20, 20, 160],
        ..GeneralStage::nop()
    };
    let fin = FinalCombiner {
        a: FinalInput::new(Source::Spare0, Usage::Rgb, false),
        b: FinalInput::new(Source::Constant0, Usage::Rgb, false),
        c: FinalInput::new(Source::EfProduct, Usage::Rgb, false),
        d: FinalInput::new(Source::Secondary, Usage::Rgb, false),
        e: FinalInput::new(Source::Spare1, Usage::Rgb, false),
        f: FinalInput::new(Source::Texture0, Usage::Rgb, false),
        g: FinalInput::new(Source::Spare0, Usage::Alpha, false),
        c0: [230, 200, 180, 255],
        ..FinalCombiner::default()
    };
    let program = Program {
        stages: vec![stage],
        final_combiner: fin,
        mux_select: MuxSelect::Lsb,
    };
    let params = CombinerParams {
        width: 9,
        stages: 1,
        ..CombinerParams::default()
    };
    let u = Combiner::new(params, program)
        .and_then(|u| u.with_ports(&[("primary", 4), ("secondary", 4), ("tex0", 4)]))
        .expect("a valid one-stage program");
    let rtl = rtl::combiner::rtl(&u, name);
    Case::new(name, u, rtl)
}

fn texram(
    name: &'static str,
    (n, m): (Encoding, Encoding),
    form: TexramForm,
    (table_bits, value_bits): (u32, u32),
    out: Encoding,
) -> Case {
    let u = TexramFrame::new(n, m, form, table_bits, value_bits, out).unwrap();
    let rtl = rtl::texram::rtl(&u, name);
    Case::new(name, u, rtl)
}

fn quat(
    name: &'static str,
    q: Encoding,
    m: Option<Encoding>,
    (table_bits, value_bits): (u32, u32),
    out: Encoding,
) -> Case {
    let u = QuatFrame::new(q, m, table_bits, value_bits, out).unwrap();
    let rtl = rtl::quat::rtl(&u, name);
    Case::new(name, u, rtl)
}

fn normalize(name: &'static str, u: bumpsim_hw::units::Normalize) -> Case {
    let rtl = rtl::normalize::rtl(&u, name);
    Case::new(name, u, rtl)
}
fn blend(name: &'static str, p: BumpBlendParams, wire: impl Fn(&str) -> Option<Encoding>) -> Case {
    let u = BumpBlend::new(p, wire).unwrap();
    let rtl = rtl::blend::rtl(&u, name).unwrap();
    Case::new(name, u, rtl)
}

/// A texel fetch of a `w x h` texture of `lanes`-lane pseudo-random texels in the range of
/// `texel` (deterministic), read at coordinates `uv`.
#[allow(clippy::too_many_arguments)]
fn fetch(
    name: &'static str,
    uv: Encoding,
    (w, h, lanes): (u32, u32, u8),
    texel: Encoding,
    (filter, weight_bits, address): (Filter, u32, Address),
    ports: u32,
    mem_latency: u32,
    out: Encoding,
) -> Case {
    let (lo, hi) = (
        texel.decode(texel.format.min_raw()),
        texel.decode(texel.format.max_raw()),
    );
    let mut x = 0x9e37_79b9_7f4a_7c15u64 ^ name.len() as u64;
    let values = (0..w * h)
        .map(|_| {
            std::array::from_fn(|_| {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                lo + (hi - lo) * ((x >> 11) as f64 / (1u64 << 53) as f64)
            })
        })
        .collect();
    let tex = Texels {
        width: w,
        height: h,
        lanes,
        values,
    };
    let tex = std::sync::Arc::new(Texture::new(name, texel, tex).unwrap());
    let sampler = Sampler::new(filter, weight_bits)
        .unwrap()
        .with_address(address, address);
    let u = TexFetch::new(uv, tex, sampler, ports, mem_latency, out).unwrap();
    let rtl = rtl::fetch::rtl(&u, name).unwrap();
    Case::new(name, u, rtl)
}

/// An emboss filter over a `w x h` map of pseudo-random codes of `texel` (deterministic),
/// read at coordinates `uv`, with bevel width `bevel`.
#[allow(clippy::too_many_arguments)]
fn emboss(
    name: &'static str,
    uv: Encoding,
    (w, h): (u32, u32),
    texel: Encoding,
    bevel: f64,
    ports: u32,
    mem_latency: u32,
    out: Encoding,
) -> Case {
    let f = texel.format;
    let mut x = 0x2545_f491_4f6c_dd1du64 ^ name.len() as u64;
    let values = (0..w * h)
        .map(|_| {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let c = f.min_raw() + ((x >> 33) % (f.max_raw() - f.min_raw() + 1) as u64) as i64;
            [texel.decode(c), 0.0, 0.0, 0.0]
        })
        .collect();
    let tex = Texels {
        width: w,
        height: h,
        lanes: 1,
        values,
    };
    let tex = std::sync::Arc::new(Texture::new(name, texel, tex).unwrap());
    let u = EmbossFilter::new(uv, tex, bevel, ports, mem_latency, out).unwrap();
    let rtl = rtl::emboss::rtl(&u, name).unwrap();
    Case::new(name, u, rtl)
}

fn fb_blend(
    name: &'static str,
    eq: BlendEquation,
    base: Encoding,
    entry: Encoding,
    fb: Encoding,
) -> Case {
    let u = FbBlend::new(eq, base, entry, fb).unwrap();
    let rtl = rtl::fb_blend::rtl(&u, name);
    Case::new(name, u, rtl)
}

fn cull(name: &'static str, v: Encoding, tests: &[CullTest]) -> Case {
    let u = CullFragment::new(v, tests).unwrap();
    let rtl = rtl::cull::rtl(&u, name);
    Case::new(name, u, rtl)
}

/// The ROP's datapath for colour `enc` (RGBA when `params` reads alpha) and `depth` bits.
fn rop(name: &'static str, params: RopParams, enc: Encoding, depth: u32) -> Case {
    let alpha = params.reads_alpha().then_some(enc);
    let r = Rop::new(params, enc, alpha, depth).unwrap();
    let u = RopDatapath::new(&r);
    let rtl = rtl::rop::rtl(&u, name);
    Case::new(name, u, rtl)
}

fn light(color: [f64; 3], l: [f64; 3], h: [f64; 3]) -> LightState {
    LightState {
        color,
        l,
        h,
        k: 1.0,
    }
}

fn sgi_shade() -> ShadeRtl {
    ShadeRtl {
        intensity: fixed(false, 9, 8),
        has: ShadeInputs {
            specular: Some(uu(8)),
            base: None,
            src: None,
        },
        params: ShadeParams {
            ambient: [0.08; 3],
            diffuse: [0.75, 0.65, 0.45],
            specular: [0.5; 3],
            light_colors: vec![[1.0, 1.0, 1.0], [0.6, 0.2, 0.6]],
        },
        coef: uu(8),
        parallel: 1,
        out: uu(8),
    }
}

fn gouraud(kind: BlendKind, color: [f64; 3]) -> BumpBlendParams {
    let mut p = BumpBlendParams::paper(kind, vec![light(color, [0.0, 0.6, 0.8], [0.0, 0.0, 1.0])]);
    p.state = us(10);
    p.l_source = VecSource::Port;
    p.h_source = VecSource::Port;
    p.spec = SpecGen::Table {
        index_bits: 8,
        value_bits: 8,
    };
    p.shininess = 16.0;
    p.selective = Selective::Off;
    p
}

/// The five units at the bundled configs' widths.
pub fn bundled() -> Vec<Case> {
    let s10 = fixed(true, 10, 8);
    let wire = |l: &'static str| {
        move |n: &str| match n {
            "c" => Some(uu(8)),
            "b" => Some(us(8)),
            x if x == l => Some(us(16)),
            _ => None,
        }
    };
    let mut cases = vec![
        dot3(
            "sgi_dot",
            Dot3Rtl {
                a: s10,
                b: s10,
                k: 4,
                parallel: 2,
                clamp: Clamp::Unit,
                out: fixed(false, 9, 8),
            },
        ),
        power(
            "sgi_spec",
            PowerTableRtl {
                input: fixed(false, 9, 8),
                k: 2,
                index_bits: 8,
                value_bits: 8,
                shininess: 32.0,
                parallel: 1,
            },
        ),
        // configs/reference.ron: 12-bit index from a u17.16 dot, 12-bit values
        power(
            "reference_spec",
            PowerTableRtl {
                input: fixed(false, 17, 16),
                k: 2,
                index_bits: 12,
                value_bits: 12,
                shininess: 32.0,
                parallel: 1,
            },
        ),
        shade("sgi_shade", sgi_shade()),
        blend(
            "gouraud_diffuse",
            gouraud(BlendKind::Diffuse, [0.75, 0.65, 0.45]),
            wire("l0"),
        ),
        blend(
            "gouraud_specular",
            gouraud(BlendKind::Specular, [0.5; 3]),
            wire("h0"),
        ),
        // configs/{visa,harmony,texram}-*.ron: N' = N + d0 u + d1 v, s2.8 in, s4.8 out
        {
            let u =
                bumpsim_hw::units::Perturb::new(s10, s10, s10, s10, fixed(true, 12, 8)).unwrap();
            let rtl = rtl::perturb::rtl(&u, "visa_perturb");
            Case {
                name: "visa_perturb",
                unit: Box::new(u),
                rtl,
            }
        },
        // configs/sgi-teapot.ron: the normal map, 256 x 256 (2c + 1) texels, bilinear
        fetch(
            "sgi_fetch",
            fixed(false, 16, 12),
            (256, 256, 3),
            Encoding::texel(Codec::UnitSymmetric, true, 8),
            (Filter::Bilinear, 8, Address::Wrap),
            4,
            4,
            s10,
        ),
        // configs/gouraud-teapot.ron: the bump map read as UnitSigned bytes
        fetch(
            "gouraud_fetch",
            fixed(false, 16, 12),
            (256, 256, 3),
            us(8),
            (Filter::Bilinear, 8, Address::Wrap),
            4,
            4,
            us(8),
        ),
        // configs/gouraud-torus-caps.ron and the other 64-texel maps: six weight bits
        fetch(
            "gouraud_fetch64",
            fixed(false, 16, 12),
            (64, 64, 3),
            us(8),
            (Filter::Bilinear, 8, Address::Wrap),
            4,
            4,
            us(8),
        ),
        // configs/ndf-teapot-aniso-hw5.ron: a 1-lane shading table, mirrored
        fetch(
            "ndf_fetch",
            fixed(false, 16, 12),
            (256, 256, 1),
            uu(8),
            (Filter::Bilinear, 8, Address::Mirror),
            4,
            4,
            uu(8),
        ),
        // configs/ndf-teapot-aniso-sw.ron: a nearest 2-lane lookup, clamped, u16.16
        fetch(
            "ndf_lookup",
            fixed(false, 16, 16),
            (256, 256, 2),
            us(8),
            (Filter::Nearest, 8, Address::Clamp),
            4,
            4,
            us(8),
        ),
        // configs/emboss.ron and emboss-sphere.ron: Schlag's masks over a 256 x 256 map of
        // u8 heights, u2.14 coordinates, 3 ports (a row a clock) behind a 4-clock memory, into
        // s12.4; the bricks' default bevel (w = 0.01 x 256)
        emboss(
            "emboss",
            fixed(false, 16, 14),
            (256, 256),
            uu(8),
            2.56,
            3,
            4,
            fixed(true, 16, 4),
        ),
        // configs/quantized-bunny-wood-eq{1,2}.ron: Tarini's framebuffer blends, u8 words
        fb_blend("tarini_eq1", BlendEquation::Exact, uu(8), uu(8), uu(8)),
        fb_blend("tarini_eq2", BlendEquation::Approx, uu(8), uu(8), uu(8)),
        // configs/cull-fragment.ron: one coordinate kept where it is >= 0
        cull("cull", fixed(true, 10, 8), &[CullTest::Gequal]),
        // configs/gouraud-order-{split,combined,multiplicative}.ron: the texture stage
        modulate(
            "gouraud_texture",
            ModulateRtl {
                c: uu(8),
                t: uu(8),
                out: uu(8),
            },
        ),
        // configs/phong-teapot.ron (and the texram, VISA configs): N_i / |N_i|, s10.8
        normalize(
            "phong_norm",
            bumpsim_hw::units::Normalize::new(fixed(true, 10, 8), 8, 12, fixed(true, 10, 8))
                .unwrap(),
        ),
        // configs/texram-teapot.ron: the normalised frame, s10.8 in and out
        texram(
            "texram_frame",
            (fixed(true, 10, 8), fixed(true, 10, 8)),
            TexramForm::Normalized,
            (8, 12),
            fixed(true, 10, 8),
        ),
        // configs/visa-quat-teapot.ron: the frame of an interpolated quaternion, s10.8
        quat(
            "quat_frame",
            fixed(true, 10, 8),
            None,
            (8, 12),
            fixed(true, 10, 8),
        ),
        // configs/nv20-combiner-bump.ron's part (width 9, its ports primary, secondary, tex0)
        // at one general stage instead of 8: the netlist depends on the stage count, not on
        // the program, and one stage and the final combiner synthesise in 40 s where the 8
        // stages take 5.5 minutes (docs/gates.md)
        combiner("nv20_rc1"),
        // every config's ROP: an 8-bit unit colour, depth Less and written, 24-bit depth
        rop("rop", RopParams::default(), uu(8), 24),
        // configs/quantized-bunny-wood-eq1.ron's blend passes (eq2: OneMinusDstColor,
        // SrcAlpha): depth Equal without writes
        rop(
            "rop_wood_modulate",
            RopParams {
                depth: Compare::Equal,
                depth_write: false,
                blend: Some((Factor::Zero, Factor::SrcAlpha)),
                ..RopParams::default()
            },
            uu(8),
            24,
        ),
        rop(
            "rop_wood_add",
            RopParams {
                depth: Compare::Equal,
                depth_write: false,
                blend: Some((Factor::OneMinusDstColor, Factor::One)),
                ..RopParams::default()
            },
            uu(8),
            24,
        ),
    ];
    cases.extend(quantized::bundled());
    cases
}

fn trn_wrap_s9_2() -> Encoding {
    let mut e = fixed(true, 9, 2);
    e.quant = Quant::Trn;
    e.overflow = Overflow::Wrap;
    e
}

/// Other parameters of the generators: clamps, codecs, rounding and overflow modes,
/// parallel datapaths with idle slots, optional shade inputs, state vectors.
pub fn variants() -> Vec<Case> {
    let sym = Encoding::texel(Codec::UnitSymmetric, true, 8);
    let mut trn = fixed(true, 10, 6);
    trn.quant = Quant::RndConv;
    trn.overflow = Overflow::Wrap;
    let mut odd = fixed(true, 7, 4);
    odd.quant = Quant::TrnZero;
    odd.overflow = Overflow::SatSym;
    let mut inf = uu(6);
    inf.quant = Quant::RndInf;
    inf.overflow = Overflow::SatZero;
    let mut zero = us(9);
    zero.quant = Quant::RndZero;
    let mut shade3 = sgi_shade();
    shade3.params.light_colors.push([0.3, 0.9, 0.1]);
    shade3.parallel = 2;
    shade3.has.base = Some(uu(8));
    shade3.has.src = Some(uu(8));
    shade3.out = inf;
    let mut both = BumpBlendParams::paper(
        BlendKind::Both,
        vec![
            light([0.9, 0.5, 0.2], [0.0, 0.6, 0.8], [0.1, 0.2, 0.97]),
            light([0.2, 0.6, 1.0], [0.6, 0.0, 0.8], [0.3, 0.0, 0.95]),
            light([0.5, 0.5, 0.5], [-0.48, 0.6, 0.64], [0.0, 0.0, 1.0]),
        ],
    );
    both.parallel = 2;
    both.out = zero;
    let mut cases = vec![
        // configs/phong-teapot.ron and emboss.ron: s2.8 normals, 256 x 12-bit rsqrt table
        normalize(
            "var_normalize_phong",
            bumpsim_hw::units::Normalize::new(fixed(true, 10, 8), 8, 12, fixed(true, 10, 8))
                .unwrap(),
        ),
        // a wide integer-heavy input (lengths from 2^-4 to 2^11), a small table, a code out
        normalize(
            "var_normalize_wide",
            bumpsim_hw::units::Normalize::new(fixed(true, 16, 4), 5, 9, us(8)).unwrap(),
        ),
        // a fixed-point colour above 1 times a 6-bit texel, into a 6-bit RndInf code
        modulate(
            "var_modulate_wide",
            ModulateRtl {
                c: fixed(false, 10, 8),
                t: uu(6),
                out: inf,
            },
        ),
        // signed operands (the clamp at 0 and at 1), into a wrapping fixed-point code
        modulate(
            "var_modulate_signed",
            ModulateRtl {
                c: us(9),
                t: fixed(true, 10, 8),
                out: trn,
            },
        ),
        dot3(
            "var_dot_none_sym",
            Dot3Rtl {
                a: fixed(true, 12, 10),
                b: sym,
                k: 3,
                parallel: 2,
                clamp: Clamp::None,
                out: trn,
            },
        ),
        dot3(
            "var_dot_positive",
            Dot3Rtl {
                a: us(8),
                b: fixed(true, 10, 8),
                k: 2,
                parallel: 1,
                clamp: Clamp::Positive,
                out: odd,
            },
        ),
        dot3(
            "var_dot_symmetric_out",
            Dot3Rtl {
                a: us(9),
                b: uu(7),
                k: 1,
                parallel: 1,
                clamp: Clamp::None,
                out: {
                    let mut e = sym;
                    e.quant = Quant::Trn;
                    e
                },
            },
        ),
        dot3(
            "var_dot_coarse_into_signed",
            Dot3Rtl {
                a: fixed(true, 4, 1),
                b: fixed(true, 5, 1),
                k: 2,
                parallel: 2,
                clamp: Clamp::None,
                out: us(8),
            },
        ),
        power(
            "var_power_par",
            PowerTableRtl {
                input: uu(8),
                k: 3,
                index_bits: 6,
                value_bits: 10,
                shininess: 8.0,
                parallel: 2,
            },
        ),
        shade("var_shade_base_src", shade3),
        blend(
            "var_blend_unperturbed",
            {
                let mut p = gouraud(BlendKind::Specular, [0.5; 3]);
                p.selective = Selective::Unperturbed;
                p
            },
            |n: &str| match n {
                "c" => Some(uu(8)),
                "b" => Some(us(8)),
                "h0" => Some(us(16)),
                _ => None,
            },
        ),
        blend(
            "var_blend_enable_fixed_c",
            {
                let mut p = gouraud(BlendKind::Diffuse, [0.75, 0.65, 0.45]);
                p.selective = Selective::UnperturbedAndEnable;
                p.out = fixed(false, 9, 8);
                p
            },
            |n: &str| match n {
                "c" => Some(fixed(false, 9, 8)),
                "b" => Some(Encoding::texel(Codec::UnitSymmetric, true, 8)),
                "l0" => Some(us(16)),
                "enable" => Some(bumpsim_hw::units::blend::ENABLE_ENCODING),
                _ => None,
            },
        ),
        blend("var_blend_both_state", both, |n: &str| match n {
            "c" => Some(uu(8)),
            "b" => Some(us(8)),
            _ => None,
        }),
        // configs/reference.ron: 1024 x 1024 16-bit texels, 12-bit weights
        fetch(
            "reference_fetch",
            fixed(false, 24, 20),
            (1024, 1024, 3),
            Encoding::texel(Codec::UnitSymmetric, true, 16),
            (Filter::Bilinear, 12, Address::Wrap),
            4,
            4,
            fixed(true, 18, 16),
        ),
        // two ports: two tap groups through the tap registers and the port address muxes;
        // signed coordinates, clamped, fixed-point texels into a narrower rounding code
        fetch(
            "fetch_ports2_clamp",
            fixed(true, 14, 10),
            (16, 8, 3),
            fixed(true, 8, 6),
            (Filter::Bilinear, 6, Address::Clamp),
            2,
            3,
            trn,
        ),
        // one port (four groups), mirrored signed coordinates, weights wider than the
        // fraction, a 1-lane UnitUnsigned texel into a 6-bit RndInf code
        fetch(
            "fetch_port1_mirror",
            fixed(true, 12, 9),
            (32, 64, 1),
            uu(8),
            (Filter::Bilinear, 8, Address::Mirror),
            1,
            1,
            inf,
        ),
        // nearest, wrap, a one-texel-high (1D) texture of 4 lanes, signed coordinates
        fetch(
            "fetch_nearest_1d",
            fixed(true, 16, 12),
            (64, 1, 4),
            sym,
            (Filter::Nearest, 8, Address::Wrap),
            1,
            2,
            fixed(true, 10, 8),
        ),
        // bilinear on a 1D texture (the t axis has one texel), 3 ports, clamp
        fetch(
            "fetch_1d_ports3",
            fixed(false, 12, 12),
            (128, 1, 2),
            us(8),
            (Filter::Bilinear, 4, Address::Clamp),
            3,
            2,
            zero,
        ),
        // emboss: two ports (address muxes on both axes), signed 5-bit texels (the rescale
        // x17), signed coordinates, into a saturating SatSym code on a 32 x 16 map
        emboss(
            "emboss_ports2_signed",
            fixed(true, 12, 8),
            (32, 16),
            fixed(true, 5, 0),
            3.0,
            2,
            3,
            {
                let mut e = fixed(true, 9, 2);
                e.overflow = Overflow::SatSym;
                e
            },
        ),
        // one port (nine clocks), u4 texels (x17), into a RndConv UnitSymmetric code
        emboss(
            "emboss_port1_sym",
            fixed(false, 10, 8),
            (16, 64),
            uu(4),
            7.0,
            1,
            1,
            {
                let mut e = Encoding::texel(Codec::UnitSymmetric, true, 12);
                e.quant = Quant::RndConv;
                e
            },
        ),
        // nine ports (one clock) on a 1D map (no t address bits), into a wrapping s9.2
        emboss(
            "emboss_ports9_1d",
            fixed(true, 16, 12),
            (128, 1),
            uu(8),
            1.5,
            9,
            2,
            trn_wrap_s9_2(),
        ),
        // four ports, a 2 x 2 map (every neighbour wraps), into a 10-bit unit code
        emboss(
            "emboss_ports4_tiny",
            fixed(false, 8, 6),
            (2, 2),
            fixed(false, 8, 0),
            0.25,
            4,
            2,
            uu(10),
        ),
        // texel widths whose largest code does not divide 255: the rational rescale 255 s / 31
        // truncated into s12.4 (u5 texels), 255 s / 63 into a RndConvOdd s10.2
        // (u6), 255 s / 127 into a TrnZero s9.3 (s8 texels), 255 s / 1023 into a RndZero
        // symmetric 9-bit code (u10 texels)
        emboss(
            "emboss_u5_rational",
            fixed(false, 10, 8),
            (16, 16),
            fixed(false, 5, 0),
            3.0,
            3,
            1,
            {
                let mut e = fixed(true, 16, 4);
                e.quant = Quant::Trn;
                e
            },
        ),
        emboss(
            "emboss_u6_rational",
            fixed(false, 10, 8),
            (16, 16),
            uu(6),
            2.0,
            9,
            1,
            {
                let mut e = fixed(true, 12, 2);
                e.quant = Quant::RndConvOdd;
                e
            },
        ),
        emboss(
            "emboss_s8_rational",
            fixed(true, 12, 8),
            (16, 16),
            fixed(true, 8, 0),
            4.0,
            3,
            2,
            {
                let mut e = fixed(true, 12, 3);
                e.quant = Quant::TrnZero;
                e
            },
        ),
        emboss(
            "emboss_u10_rational",
            fixed(false, 10, 8),
            (16, 16),
            uu(10),
            1.0,
            3,
            1,
            {
                let mut e = Encoding::texel(Codec::UnitSymmetric, true, 9);
                e.quant = Quant::RndZero;
                e
            },
        ),
        // four lanes, mixed tests (a clip plane on each side)
        cull(
            "cull_mixed",
            sym,
            &[
                CullTest::Less,
                CullTest::Gequal,
                CullTest::Less,
                CullTest::Gequal,
            ],
        ),
        // an unsigned lane is never negative: Gequal always passes, Less always fails
        cull("cull_unsigned", uu(8), &[CullTest::Gequal, CullTest::Less]),
        // a 10-bit framebuffer, 6-bit entries, a fixed-point base above 1 (pass 1 clamps it)
        fb_blend(
            "fb_eq1_wide",
            BlendEquation::Exact,
            fixed(false, 10, 8),
            uu(6),
            uu(10),
        ),
        fb_blend(
            "fb_eq2_fixed",
            BlendEquation::Approx,
            uu(8),
            us(8),
            fixed(false, 9, 8),
        ),
        // unsigned lanes (the squares without their sign row)
        normalize(
            "var_normalize_unsigned",
            bumpsim_hw::units::Normalize::new(uu(6), 6, 10, fixed(true, 10, 8)).unwrap(),
        ),
        // configs/texram-teapot-scaled.ron: N_i not normalised, v = |N_i| e1
        texram(
            "texram_scaled",
            (fixed(true, 10, 8), fixed(true, 10, 8)),
            TexramForm::Scaled,
            (8, 12),
            fixed(true, 10, 8),
        ),
        // unit codes in, a small table, a wider output
        texram(
            "texram_unit_codes",
            (us(8), sym),
            TexramForm::Normalized,
            (5, 9),
            fixed(true, 12, 9),
        ),
        // the 2x2 matrix m (scale and shear), unit-code quaternions into a wider output
        quat(
            "quat_scaled",
            fixed(true, 10, 8),
            Some(fixed(true, 8, 6)),
            (8, 12),
            fixed(true, 12, 8),
        ),
        quat("quat_unit_codes", sym, None, (5, 9), us(9)),
        // the ROP at other encodings and widths: a fixed-point colour into 5-bit codes with
        // an alpha test; a symmetric unit colour into 10 bits blending with alpha (the 8-bit
        // alpha scaled to 10-bit codes); a signed unit colour, no depth test, 16-bit depth
        rop(
            "rop_fixed_u5",
            RopParams {
                depth: Compare::GEqual,
                alpha_test: Some((Compare::NotEqual, 77)),
                color_bits: 5,
                ..RopParams::default()
            },
            fixed(false, 10, 9),
            16,
        ),
        rop(
            "rop_sym_10",
            RopParams {
                depth: Compare::LEqual,
                blend: Some((Factor::SrcAlpha, Factor::OneMinusSrcAlpha)),
                color_bits: 10,
                ..RopParams::default()
            },
            sym,
            20,
        ),
        rop(
            "rop_signed_always",
            RopParams {
                depth: Compare::Always,
                depth_write: false,
                blend: Some((Factor::DstColor, Factor::OneMinusSrcColor)),
                ..RopParams::default()
            },
            us(9),
            16,
        ),
    ];
    cases.extend(quantized::variants());
    cases
}
