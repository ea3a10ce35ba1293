//! Co-simulation of the generated Verilog (`bumpsim_hw::rtl`) against the bit-accurate
//! model: for each unit, deterministic vectors from the model (`rtl::vectors`: random words,
//! plausible values, corner words, aligned vectors), replayed by an iverilog testbench that
//! compares every output word. Zero mismatches are required, and `done` must come at the
//! unit's RTL latency for every vector.
//!
//! iverilog (`iverilog` on `PATH`, or `$IVERILOG`) is required: the test **fails** without
//! it (`.ci/install-iverilog.sh` installs it). `BUMPSIM_SKIP_IVERILOG=1` skips it explicitly.

mod rtl_units;

use bumpsim_hw::rtl::{testbench, vectors};
use bumpsim_hw::{Mode, Word};
use rtl_units::Case;
use std::path::Path;
use std::process::Command;

/// Vectors per bundled unit, and per variant.
const BUNDLED_VECTORS: usize = 4000;
const VARIANT_VECTORS: usize = 1500;

fn skip_requested() -> bool {
    std::env::var_os("BUMPSIM_SKIP_IVERILOG").is_some_and(|v| !v.is_empty() && v != "0")
}

fn iverilog_available() -> bool {
    Command::new(testbench::iverilog_bin().0)
        .arg("-V")
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

fn cosim(cases: Vec<Case>, n: usize, seed: u64) {
    if skip_requested() {
        println!("rtl_cosim: skipped (BUMPSIM_SKIP_IVERILOG is set)");
        return;
    }
    assert!(
        iverilog_available(),
        "rtl_cosim: iverilog not found: install it (Debian package iverilog, \
         .ci/install-iverilog.sh), point $IVERILOG at it, or set BUMPSIM_SKIP_IVERILOG=1"
    );
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR")).join("rtl_cosim");
    let results: Vec<_> = std::thread::scope(|s| {
        let hs: Vec<_> = cases
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let tmp = &tmp;
                s.spawn(move || {
                    let (ins, outs) = vectors::vectors(c.unit.as_ref(), n, seed + i as u64);
                    let dir = tmp.join(c.name);
                    testbench::write(&dir, &c.rtl, &ins, &outs).unwrap();
                    testbench::run_iverilog(&dir)
                })
            })
            .collect();
        hs.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let mut bad = Vec::new();
    for (c, r) in cases.iter().zip(results) {
        match r {
            Ok(r) => {
                println!(
                    "{:<22} vectors {:>5}  mismatches {}  latency {} (model {}){}",
                    c.name,
                    r.vectors,
                    r.mismatches,
                    c.rtl.latency,
                    c.unit.latency(),
                    if r.latency_errors > 0 {
                        "  LATENCY ERRORS"
                    } else {
                        ""
                    }
                );
                for l in &r.first {
                    println!("    {l}");
                }
                if r.vectors != n || r.mismatches > 0 || r.latency_errors > 0 {
                    bad.push(format!("{}: {r:?}", c.name));
                }
            }
            Err(e) => bad.push(format!("{}: {e}", c.name)),
        }
    }
    assert!(bad.is_empty(), "co-simulation failed:\n{}", bad.join("\n"));
}

#[test]
fn bundled_units_match_the_model_word_for_word() {
    cosim(rtl_units::bundled(), BUNDLED_VECTORS, 0x13_0001);
}

#[test]
fn generator_variants_match_the_model_word_for_word() {
    cosim(rtl_units::variants(), VARIANT_VECTORS, 0x13_1001);
}

#[test]
fn vectors_are_deterministic() {
    let u = &rtl_units::bundled()[0];
    let a = vectors::vectors(u.unit.as_ref(), 64, 5);
    let b = vectors::vectors(u.unit.as_ref(), 64, 5);
    assert_eq!(a, b);
}

#[test]
fn a_wrong_expected_word_is_reported() {
    if skip_requested() {
        return;
    }
    assert!(iverilog_available(), "rtl_cosim: iverilog not found");
    let c = &rtl_units::bundled()[1]; // the power table: the fastest
    let (ins, mut outs) = vectors::vectors(c.unit.as_ref(), 200, 9);
    let w = &mut outs[17][1].lanes[0].raw;
    *w ^= 1;
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("rtl_cosim/corrupted");
    testbench::write(&dir, &c.rtl, &ins, &outs).unwrap();
    let r = testbench::run_iverilog(&dir).unwrap();
    assert_eq!(
        (r.vectors, r.mismatches, r.latency_errors),
        (200, 1, 0),
        "{r:?}"
    );
    assert!(r.first[0].contains("vector 17 lane y1"), "{:?}", r.first);
}

/// Co-simulate `c` on the vectors `ins` (expected: the model's outputs); every vector must
/// match.
fn cosim_on(c: &Case, ins: Vec<Vec<Word>>, dir: &str) {
    let outs: Vec<Vec<Word>> = ins
        .iter()
        .map(|w| {
            let mut o = vec![Word::default(); c.unit.outputs().len()];
            c.unit.eval(Mode::BitAccurate, w, &mut o);
            o
        })
        .collect();
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("rtl_cosim")
        .join(dir);
    testbench::write(&dir, &c.rtl, &ins, &outs).unwrap();
    let r = testbench::run_iverilog(&dir).unwrap();
    assert_eq!(
        (r.vectors, r.mismatches, r.latency_errors),
        (ins.len(), 0, 0),
        "{}: {r:?}",
        c.name
    );
}

/// The texture stage at the Gouraud orders' widths, exhaustively: all 65,536 pairs of 8-bit
/// codes (three per vector, one per channel) against the model.
#[test]
fn modulate_u8_matches_the_model_on_every_pair_of_codes() {
    if skip_requested() {
        return;
    }
    assert!(iverilog_available(), "rtl_cosim: iverilog not found");
    let c = rtl_units::bundled()
        .into_iter()
        .find(|c| c.name == "gouraud_texture")
        .expect("the texture stage is a bundled unit");
    let ports = c.unit.inputs().to_vec();
    let (ec, et) = (ports[0].enc, ports[1].enc);
    let n = (1usize << 16).div_ceil(3);
    let pair = |k: usize, l: usize| ((3 * k + l) % (1 << 16)) as i64;
    let ins = (0..n)
        .map(|k| {
            let p: [i64; 3] = std::array::from_fn(|l| pair(k, l));
            vec![
                Word::from_raw(&ec, &p.map(|v| v >> 8)),
                Word::from_raw(&et, &p.map(|v| v & 255)),
            ]
        })
        .collect();
    cosim_on(&c, ins, "modulate_exhaustive");
}

/// The normaliser on every input vector of a 5-bit signed format (32,768 vectors: the zero
/// vector, every length and so every branch of the leading-one detector and every shift).
#[test]
fn normalize_matches_the_model_on_every_5_bit_vector() {
    if skip_requested() {
        return;
    }
    assert!(iverilog_available(), "rtl_cosim: iverilog not found");
    let e = bumpsim_hw::Encoding::fixed(bumpsim_hw::Format::s(5, 2));
    let out = bumpsim_hw::Encoding::fixed(bumpsim_hw::Format::s(8, 6));
    let u = bumpsim_hw::units::Normalize::new(e, 4, 8, out).unwrap();
    let c = Case {
        name: "normalize_exhaustive",
        rtl: bumpsim_hw::rtl::normalize::rtl(&u, "normalize_exhaustive"),
        unit: Box::new(u),
    };
    let ins = (0..1i64 << 15)
        .map(|k| {
            let v: [i64; 3] = std::array::from_fn(|l| ((k >> (5 * l)) & 31) - 16);
            vec![Word::from_raw(&e, &v)]
        })
        .collect();
    cosim_on(&c, ins, "normalize_exhaustive");
}

/// The emboss filter at every texel of a 32 x 16 map (the variant with two ports and signed
/// coordinates), at the texel centres of the base period and of the periods on either side
/// (negative coordinates floor, then wrap): every neighbourhood, every wrapped edge.
#[test]
fn emboss_matches_the_model_at_every_texel() {
    if skip_requested() {
        return;
    }
    assert!(iverilog_available(), "rtl_cosim: iverilog not found");
    let c = rtl_units::variants()
        .into_iter()
        .find(|c| c.name == "emboss_ports2_signed")
        .expect("the emboss variant");
    let uv = c.unit.inputs()[0].enc;
    let (w, h) = (32i64, 16i64);
    let ins: Vec<Vec<Word>> = (-1..=1)
        .flat_map(|period| (0..w * h).map(move |k| (period, k)))
        .map(|(period, k)| {
            let (i, j) = (k % w + period * w, k / w - period * h);
            let at = |x: i64, n: i64| (x as f64 + 0.5) / n as f64;
            vec![Word::quantize(&uv, &[at(i, w), at(j, h)])]
        })
        .collect();
    cosim_on(&c, ins, "emboss_every_texel");
}

/// Every entry the builder writes, read back: one vector per texel centre of an index
/// texture that holds every index (`quantized_sphere`: 256 entries in 64 x 64 texels, one
/// Blinn-Phong material; `quantized_materials`: two materials over 200 entries, two lights;
/// `quantized_envmap`: 2048 sphere-map entries in 64 x 64; `quantized_envmap_two`: two
/// sphere maps over 150 entries in 16 x 16).
#[test]
fn quantized_builder_writes_every_entry_as_the_model() {
    if skip_requested() {
        return;
    }
    assert!(iverilog_available(), "rtl_cosim: iverilog not found");
    let names = [
        ("quantized_sphere", 64u32),
        ("quantized_materials", 32),
        ("quantized_envmap", 64),
        ("quantized_envmap_two", 16),
    ];
    let cases = rtl_units::quantized::bundled()
        .into_iter()
        .chain(rtl_units::quantized::variants())
        .filter_map(|c| {
            let size = names.iter().find(|n| n.0 == c.name)?.1;
            Some((c, size))
        })
        .collect::<Vec<_>>();
    assert_eq!(cases.len(), names.len());
    for (c, size) in cases {
        let uv = c.unit.inputs()[0].enc;
        let ins: Vec<Vec<Word>> = (0..size * size)
            .map(|k| {
                let (i, j) = (k % size, k / size);
                let at = |x: u32| (x as f64 + 0.5) / size as f64;
                vec![Word::quantize(&uv, &[at(i), at(j)])]
            })
            .collect();
        cosim_on(&c, ins, &format!("every_entry_{}", c.name));
    }
}

/// The NDF turbulence of the software path (`rtl::ndf_turbulence`): `octaves` octaves of two
/// improved-noise sums at `frequency` cells (permutations `seed`, `seed + 1`), index scale
/// `scale`, `frac` fraction bits.
#[allow(clippy::too_many_arguments)]
fn turbulence(
    name: &'static str,
    frequency: u32,
    seed: u64,
    octaves: u32,
    scale: f64,
    frac: u32,
    (uv, lod, out): (
        bumpsim_hw::Encoding,
        bumpsim_hw::Encoding,
        bumpsim_hw::Encoding,
    ),
) -> Case {
    use bumpsim_hw::units::{ndf_noise::Turbulence, TurbulenceIndex};
    let t = Turbulence::new(frequency, seed);
    let u = TurbulenceIndex::new(t, octaves, scale, frac, uv, lod, out).unwrap();
    let rtl = bumpsim_hw::rtl::ndf_turbulence::rtl(&u, name);
    Case::new(name, u, rtl)
}

/// `configs/ndf-teapot-aniso-sw.ron`'s noise: 4 octaves from 8 cells, seed 1, u16.16
/// coordinates, a u8.4 LOD, 16 fraction bits, the Ward NDF's index scale (code 0x6b15), u16.16
/// indices.
fn turbulence_bundled() -> Case {
    let fx = |w, f| bumpsim_hw::Encoding::fixed(bumpsim_hw::Format::u(w, f));
    turbulence(
        "ndf_turbulence",
        8,
        1,
        4,
        f64::from(0x6b15) / 65536.0,
        16,
        (fx(16, 16), fx(8, 4), fx(16, 16)),
    )
}

/// Other widths and lattices: fewer datapath bits than coordinate bits (the position
/// truncated), a LOD with fewer than 8 fraction bits; a period of 3 (not a power of two:
/// the constant multiply, the modular neighbour) with a signed LOD (negative: every octave)
/// and a scale above 1; a one-cell octave (no cell bits, the hash of cell 0) under a
/// `UnitUnsigned` LOD; periods of 200 and 400 (above the permutation: `i & 255`).
fn turbulence_variants() -> Vec<Case> {
    use bumpsim_hw::{Codec, Encoding, Format};
    let u = |w, f| Encoding::fixed(Format::u(w, f));
    vec![
        turbulence(
            "turb_f8_oct2",
            4,
            5,
            2,
            0.9,
            8,
            (
                u(12, 12),
                u(4, 2),
                Encoding::texel(Codec::UnitUnsigned, false, 8),
            ),
        ),
        turbulence(
            "turb_period3",
            3,
            9,
            3,
            2.5,
            12,
            (u(10, 10), Encoding::fixed(Format::s(6, 3)), u(10, 9)),
        ),
        turbulence(
            "turb_one_cell",
            1,
            0,
            2,
            0.3,
            6,
            (
                u(16, 16),
                Encoding::texel(Codec::UnitUnsigned, false, 8),
                u(16, 16),
            ),
        ),
        turbulence(
            "turb_period400",
            200,
            2,
            2,
            0.45,
            10,
            (u(16, 16), u(8, 4), u(12, 12)),
        ),
    ]
}

#[test]
fn ndf_turbulence_matches_the_model_word_for_word() {
    cosim(vec![turbulence_bundled()], BUNDLED_VECTORS, 0x13_2001);
    cosim(turbulence_variants(), VARIANT_VECTORS, 0x13_2101);
}

/// The bundled turbulence on uniform coordinates with LODs spread over every octave count
/// (0 to 4 octaves and the blends between; the generic vectors' uniform u8.4 LOD is mostly
/// above 4, which leaves no octave).
#[test]
fn ndf_turbulence_matches_the_model_over_every_octave_count() {
    if skip_requested() {
        return;
    }
    assert!(iverilog_available(), "rtl_cosim: iverilog not found");
    let c = turbulence_bundled();
    let (uv, lod) = (c.unit.inputs()[0].enc, c.unit.inputs()[1].enc);
    let mut r = vectors::SplitMix(0x13_2201);
    let ins = (0..3000)
        .map(|_| {
            let (a, b) = (r.range(0, 65535), r.range(0, 65535));
            vec![
                Word::from_raw(&uv, &[a, b]),
                Word::from_raw(&lod, &[r.range(0, 4 * 16 + 1)]),
            ]
        })
        .collect();
    cosim_on(&c, ins, "ndf_turbulence_octaves");
}

/// Vectors per texture-shader case.
const SHADER_VECTORS: usize = 1500;

/// Vectors per reflection case: with the six cube-map and depth cases at 1,500 vectors each
/// the suite's `rtl_cosim` went from 60 to 176 s (clean-clone CI); the reflections' 65- to
/// 99-bit products and divisions at s32.16 are the widest logic iverilog evaluates here.
const REFLECTION_VECTORS: usize = 500;

/// The texture shader, one case per program family (`rtl_units::texture_shader`): TEXTURE_2D
/// (projective, mip levels), PASS_THROUGH, DEPENDENT_AR / _GB, DOT_PRODUCT(_TEXTURE_2D) under
/// every mapping, OFFSET_TEXTURE_2D(_SCALE) (the specified and the NV2A luminance), a broken
/// stage run as NONE, the cube maps, the reflections and the depth.
#[test]
fn texture_shader_programs_match_the_model_word_for_word() {
    let (reflect, others): (Vec<_>, Vec<_>) = rtl_units::texture_shader::cases()
        .into_iter()
        .partition(|c| c.name.contains("reflect"));
    assert_eq!(reflect.len(), 3);
    cosim(others, SHADER_VECTORS, 0x13_2001);
    cosim(reflect, REFLECTION_VECTORS, 0x13_2301);
}

/// The `live` output of CULL_FRAGMENT as one more output lane, against `Unit::live`.
fn with_live(c: &Case, ins: &[Vec<Word>], outs: &mut [Vec<Word>]) -> bumpsim_hw::rtl::RtlUnit {
    let bit = bumpsim_hw::Encoding::fixed(bumpsim_hw::Format::u(1, 0));
    let mut r = c.rtl.clone();
    let port = c.unit.outputs().len();
    r.outputs.push(bumpsim_hw::rtl::Lane {
        name: "live".into(),
        port,
        lane: 0,
        enc: bit,
    });
    for (w, o) in ins.iter().zip(outs.iter_mut()) {
        let live = c.unit.live(Mode::BitAccurate, w, o);
        o.push(Word::from_raw(&bit, &[live as i64]));
    }
    r
}

#[test]
fn texture_shader_culls_as_the_model() {
    if skip_requested() {
        return;
    }
    assert!(iverilog_available(), "rtl_cosim: iverilog not found");
    let c = rtl_units::texture_shader::cull();
    let (ins, mut outs) = vectors::vectors(c.unit.as_ref(), SHADER_VECTORS, 0x13_2101);
    let r = with_live(&c, &ins, &mut outs);
    let killed = outs
        .iter()
        .filter(|o| o.last().unwrap().lanes[0].raw == 0)
        .count();
    // both outcomes occur (eight sign tests: few random fragments survive)
    assert!(killed > 100 && killed + 5 <= ins.len(), "killed {killed}");
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("rtl_cosim/ts_cull");
    testbench::write(&dir, &r, &ins, &outs).unwrap();
    let res = testbench::run_iverilog(&dir).unwrap();
    assert_eq!(
        (res.vectors, res.mismatches, res.latency_errors),
        (ins.len(), 0, 0),
        "{res:?}"
    );
    // one flipped live bit is one mismatch
    let last = outs[23].len() - 1;
    outs[23][last].lanes[0].raw ^= 1;
    testbench::write(&dir, &r, &ins, &outs).unwrap();
    let res = testbench::run_iverilog(&dir).unwrap();
    assert_eq!((res.mismatches, res.latency_errors), (1, 0), "{res:?}");
    assert!(
        res.first[0].contains("vector 23 lane live"),
        "{:?}",
        res.first
    );
}

#[test]
fn a_wrong_texture_shader_word_is_reported() {
    if skip_requested() {
        return;
    }
    assert!(iverilog_available(), "rtl_cosim: iverilog not found");
    let c = rtl_units::texture_shader::cases()
        .into_iter()
        .find(|c| c.name == "ts_dot_hilo")
        .unwrap();
    let (ins, mut outs) = vectors::vectors(c.unit.as_ref(), 300, 11);
    outs[41][2].lanes[1].raw ^= 4;
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("rtl_cosim/ts_corrupted");
    testbench::write(&dir, &c.rtl, &ins, &outs).unwrap();
    let r = testbench::run_iverilog(&dir).unwrap();
    assert_eq!(
        (r.vectors, r.mismatches, r.latency_errors),
        (300, 1, 0),
        "{r:?}"
    );
    assert!(
        r.first[0].contains("vector 41 lane tex2_1"),
        "{:?}",
        r.first
    );
}

/// Same config, same text.
#[test]
fn texture_shader_verilog_is_deterministic() {
    let a = rtl_units::texture_shader::cases();
    let b = rtl_units::texture_shader::cases();
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(x.rtl.verilog, y.rtl.verilog, "{}", x.name);
    }
}
