//! Quantized normal maps units (Tarini et al.) for the RTL tests: the builder's datapath at
//! the bundled configs' widths (`configs/quantized-*.ron`: s1.10 normals and vectors,
//! 10-bit intensities, a 1024 x 12 power table, u8 entries) and variants.

use super::{fixed, uu, Case};
use bumpsim_hw::rtl;
use bumpsim_hw::units::{BuilderFormats, LightingFn, PaletteBuilder, QuantizedFetch, SpecGen};
use bumpsim_hw::{Encoding, Format};

fn formats(entry: Encoding) -> BuilderFormats {
    BuilderFormats {
        normal: fixed(true, 12, 10),
        vector: fixed(true, 12, 10),
        intensity: uu(10),
        power: SpecGen::Table {
            index_bits: 10,
            value_bits: 12,
        },
        entry,
        sphere: Default::default(),
    }
}

/// `n` normals spread over the sphere (a spiral), the upper half first.
fn normals(n: usize) -> Vec<[f64; 3]> {
    (0..n)
        .map(|k| {
            let a = k as f64 * 2.399963;
            let z = 1.0 - 2.0 * (k as f64 + 0.5) / n as f64;
            let r = (1.0 - z * z).sqrt();
            [r * a.cos(), r * a.sin(), z]
        })
        .collect()
}

fn lambert(lights: Vec<([f64; 3], [f64; 3])>) -> LightingFn {
    LightingFn::Lambert {
        ambient: [0.08, 0.1, 0.12],
        diffuse: [0.75, 0.5, 0.3],
        lights,
    }
}

fn specular(shininess: f64, lights: Vec<([f64; 3], [f64; 3])>) -> LightingFn {
    LightingFn::Specular {
        ambient: [0.08, 0.08, 0.08],
        diffuse: [0.75, 0.5, 0.3],
        specular: [0.4, 0.4, 0.4],
        shininess,
        view: [0.0, 0.24, 0.97],
        lights,
    }
}

/// Cartoon shading (`quantized-cartoon`: 4 bands, the light along (1, 1, 1)).
fn cartoon(bands: u32, lights: Vec<([f64; 3], [f64; 3])>) -> LightingFn {
    LightingFn::Cartoon {
        bands,
        ambient: [0.08, 0.08, 0.08],
        diffuse: [0.75, 0.5, 0.3],
        lights,
    }
}

/// Doubled-angle Phong (`quantized-doubled-angle`: the torus turned 55 degrees, so the
/// object-space light and view below).
fn doubled(shininess: f64, light: ([f64; 3], [f64; 3])) -> LightingFn {
    LightingFn::DoubledAnglePhong {
        ambient: [0.08, 0.08, 0.08],
        diffuse: [0.75, 0.5, 0.3],
        specular: [0.4, 0.4, 0.4],
        shininess,
        view: [0.0, 0.819, 0.574],
        light,
    }
}

/// Chrome (`quantized-chrome`: sky and ground colours, the viewer and up in object space).
fn chrome(view: [f64; 3], up: [f64; 3]) -> LightingFn {
    LightingFn::Chrome {
        view,
        up,
        sky: [0.35, 0.55, 0.95],
        ground: [0.45, 0.28, 0.12],
    }
}

/// A quantized unit over `indices` (`size` x `size`, row-major) into a builder of `n`
/// normals with `materials`.
#[allow(clippy::too_many_arguments)]
pub fn unit(
    name: &'static str,
    n: usize,
    materials: Vec<(std::ops::Range<usize>, LightingFn)>,
    entry: Encoding,
    size: u32,
    indices: Vec<u32>,
    index_bits: u32,
    mem_latency: u32,
) -> Case {
    unit_with(
        name,
        n,
        materials,
        formats(entry),
        size,
        indices,
        index_bits,
        mem_latency,
    )
}

/// [`unit`] with the builder's formats given.
#[allow(clippy::too_many_arguments)]
pub fn unit_with(
    name: &'static str,
    n: usize,
    materials: Vec<(std::ops::Range<usize>, LightingFn)>,
    formats: BuilderFormats,
    size: u32,
    indices: Vec<u32>,
    index_bits: u32,
    mem_latency: u32,
) -> Case {
    let b = PaletteBuilder::new(normals(n), materials, formats, 1).unwrap();
    let uv = fixed(false, 16, 12);
    let u = QuantizedFetch::new(
        "indices",
        uv,
        size,
        size,
        &indices,
        index_bits,
        b,
        1,
        mem_latency,
    )
    .unwrap();
    let rtl = rtl::quantized::rtl(&u, name).unwrap();
    Case::new(name, u, rtl)
}

/// [`unit`] with index mipmaps: a `w` x `h` level 0 of `every` index, each coarser level
/// (halved, at least one texel a side) the top-left texel of each 2 x 2 of the one above (with
/// an offset, so that levels differ), down to 1 x 1; a 1-lane `lod` port.
#[allow(clippy::too_many_arguments)]
pub fn mip_unit(
    name: &'static str,
    n: usize,
    materials: Vec<(std::ops::Range<usize>, LightingFn)>,
    (w, h): (u32, u32),
    lod: Encoding,
    mem_latency: u32,
) -> Case {
    let b = PaletteBuilder::new(normals(n), materials, formats(uu(8)), 1).unwrap();
    let uv = fixed(false, 16, 12);
    let base: Vec<u32> = (0..w * h).map(|k| k % n as u32).collect();
    let mut levels = Vec::new();
    let (mut pw, mut ph, mut prev) = (w, h, base.clone());
    while pw > 1 || ph > 1 {
        let (nw, nh) = ((pw / 2).max(1), (ph / 2).max(1));
        let next: Vec<u32> = (0..nw * nh)
            .map(|k| {
                let (i, j) = (k % nw, k / nw);
                let (si, sj) = ((2 * i).min(pw - 1), (2 * j).min(ph - 1));
                (prev[(sj * pw + si) as usize] + 3 * levels.len() as u32 + 1) % n as u32
            })
            .collect();
        levels.push((nw, nh, next.clone()));
        (pw, ph, prev) = (nw, nh, next);
    }
    let u = QuantizedFetch::new("indices", uv, w, h, &base, 8, b, 1, mem_latency)
        .unwrap()
        .with_mipmaps(lod, levels)
        .unwrap();
    let rtl = rtl::quantized::rtl(&u, name).unwrap();
    Case::new(name, u, rtl)
}

/// An environment map (`quantized-vase-envmap`: the viewer and up in object space) on a
/// `w` x `h` image of smooth ramps and a fine pattern, so that neighbouring texels differ.
fn envmap(w: u32, h: u32, view: [f64; 3], up: [f64; 3]) -> LightingFn {
    let image = (0..w * h)
        .map(|k| {
            let (i, j) = ((k % w) as f64, (k / w) as f64);
            [
                i / w as f64,
                j / h as f64,
                ((k * 7 + (k / w) * 13) % 17) as f64 / 16.0,
            ]
        })
        .collect();
    LightingFn::EnvMap {
        view,
        up,
        image,
        width: w,
        height: h,
    }
}

/// Indices `0..n` in turn, so that every entry of the table is under some texel.
fn every(size: u32, n: usize) -> Vec<u32> {
    (0..size * size).map(|k| k % n as u32).collect()
}

/// The bundled configs' builder: Blinn-Phong with one light on 256 entries
/// (`quantized-sphere`), Lambert on 16 (`quantized-sn16`, `quantized-vase-sn*`), the
/// 256-entry cartoon (4 bands), doubled-angle Phong and chrome tables (`quantized-cartoon`,
/// `-doubled-angle`, `-chrome`), and index mipmaps at `quantized-plane-mipmap`'s words.
pub fn bundled() -> Vec<Case> {
    let light = ([0.577, 0.577, 0.577], [1.0; 3]);
    let turned = ([0.577, 0.804, -0.141], [1.0; 3]);
    vec![
        unit(
            "quantized_sphere",
            256,
            vec![(0..256, specular(24.0, vec![light]))],
            uu(8),
            64,
            every(64, 256),
            8,
            3,
        ),
        unit(
            "quantized_sn16",
            16,
            vec![(0..16, lambert(vec![light]))],
            uu(8),
            16,
            every(16, 16),
            8,
            3,
        ),
        unit(
            "quantized_cartoon",
            256,
            vec![(0..256, cartoon(4, vec![light]))],
            uu(8),
            64,
            every(64, 256),
            8,
            3,
        ),
        unit(
            "quantized_doubled_angle",
            256,
            vec![(0..256, doubled(24.0, turned))],
            uu(8),
            64,
            every(64, 256),
            8,
            3,
        ),
        unit(
            "quantized_chrome",
            256,
            vec![(0..256, chrome([0.0, 0.819, 0.574], [0.0, 0.574, -0.819]))],
            uu(8),
            64,
            every(64, 256),
            8,
            3,
        ),
        // quantized-vase-envmap: 2048 entries, a 256 x 256 sphere map, the default 1024 x 16
        // reciprocal-square-root table
        unit(
            "quantized_envmap",
            2048,
            vec![(
                0..2048,
                envmap(256, 256, [0.0, 0.196, 0.981], [0.0, 0.981, -0.196]),
            )],
            uu(8),
            64,
            every(64, 2048),
            11,
            3,
        ),
        // quantized-plane-mipmap's words (a u8.4 LOD, Lambert on 256 entries, u8 entries) on
        // a 64 x 64 index texture: 7 levels
        mip_unit(
            "quantized_mipmap",
            256,
            vec![(0..256, lambert(vec![light]))],
            (64, 64),
            fixed(false, 8, 4),
            3,
        ),
    ]
}

/// Two materials with their own shininess and lights, the split form, fewer entries than
/// the index reaches, a 9-bit index, a one-clock index memory, other
/// entry words.
pub fn variants() -> Vec<Case> {
    let l1 = ([0.3, 0.8, 0.5], [1.0, 0.9, 0.8]);
    let l2 = ([-0.6, 0.2, 0.77], [0.4, 0.5, 0.9]);
    let split = LightingFn::SpecularSplit {
        ambient: 0.1,
        diffuse: 0.8,
        specular: [0.9, 0.85, 0.8],
        shininess: 40.0,
        view: [0.1, 0.0, 1.0],
        lights: vec![l1, l2],
        lambert: false,
    };
    // a 200-entry table behind an 8-bit index, read in a scattered order
    let scattered: Vec<u32> = (0..32 * 32u32).map(|k| (k * 7) % 200).collect();
    let l3 = ([0.5, -0.4, 0.6], [0.9, 0.7, 1.0]);
    // factor-carrying words: UnitSymmetric normals and vectors (read (2c + 1)(2^n + 1))
    let sym = Encoding::texel(bumpsim_hw::Codec::UnitSymmetric, true, 10);
    let reflect_sym = BuilderFormats {
        normal: sym,
        vector: sym,
        ..formats(uu(6))
    };
    // UnitSigned normals and vectors, 12-bit intensities into the 10-bit power index
    let doubled_signed = BuilderFormats {
        normal: Encoding::texel(bumpsim_hw::Codec::UnitSigned, true, 10),
        vector: Encoding::texel(bumpsim_hw::Codec::UnitSigned, true, 9),
        intensity: uu(12),
        ..formats(uu(8))
    };
    // an intensity word that holds 1.0 (the cartoon band reaches `bands`, clamped)
    let cartoon_fixed = BuilderFormats {
        intensity: fixed(false, 11, 10),
        ..formats(Encoding::fixed(Format::u(9, 8)))
    };
    vec![
        unit(
            "quantized_materials",
            200,
            vec![
                (0..70, lambert(vec![l1, l2])),
                (70..200, specular(60.0, vec![l2, l1])),
            ],
            uu(8),
            32,
            every(32, 200),
            8,
            1,
        ),
        unit(
            "quantized_split",
            64,
            vec![(0..64, split)],
            uu(8),
            16,
            every(16, 64),
            8,
            2,
        ),
        unit(
            "quantized_short",
            200,
            vec![(0..200, specular(8.0, vec![l1]))],
            uu(6),
            32,
            scattered,
            8,
            3,
        ),
        unit(
            "quantized_wide",
            300,
            vec![
                (0..120, specular(24.0, vec![l1])),
                (120..300, specular(5.0, vec![l2])),
            ],
            Encoding::fixed(Format::u(9, 8)),
            32,
            every(32, 300),
            9,
            2,
        ),
        // every function with a generator in one table: two cartoon materials (5 bands with
        // two lights, 3 bands with none), chrome, doubled-angle Phong, Lambert
        unit(
            "quantized_functions",
            230,
            vec![
                (0..40, cartoon(5, vec![l1, l2])),
                (40..90, chrome([0.1, 0.3, 0.95], [0.0, 1.0, 0.2])),
                (90..150, doubled(12.0, l3)),
                (150..200, lambert(vec![l2])),
                (200..230, cartoon(3, vec![])),
            ],
            uu(8),
            32,
            every(32, 230),
            8,
            1,
        ),
        unit_with(
            "quantized_reflect_sym",
            160,
            vec![
                (0..100, lambert(vec![l1, l3])),
                (100..160, chrome([0.3, -0.2, 0.9], [0.0, 0.0, 1.0])),
            ],
            reflect_sym,
            16,
            every(16, 160),
            8,
            2,
        ),
        unit_with(
            "quantized_doubled_signed",
            128,
            vec![(0..128, doubled(40.0, l1))],
            doubled_signed,
            16,
            every(16, 128),
            8,
            3,
        ),
        // a 32 x 8 index texture (levels down to 1 x 1, one axis first), a signed LOD
        mip_unit(
            "quantized_mipmap_rect",
            64,
            vec![(0..64, specular(16.0, vec![l1]))],
            (32, 8),
            fixed(true, 8, 2),
            1,
        ),
        // an integer LOD beyond the levels (clamped)
        mip_unit(
            "quantized_mipmap_int",
            100,
            vec![(0..100, cartoon(3, vec![l2]))],
            (16, 16),
            fixed(false, 3, 0),
            2,
        ),
        // two sphere maps of other sizes (one not a power of two) and viewers, factor-carrying
        // normals and vectors (symmetric 10-bit), s2.9 reflections, a 64 x 10 table, 6-bit
        // entries
        unit_with(
            "quantized_envmap_two",
            150,
            vec![
                (0..90, envmap(37, 20, [0.3, -0.2, 0.9], [0.0, 1.0, 0.0])),
                (90..150, envmap(16, 16, [-0.5, 0.1, 0.6], [0.2, 0.0, 1.0])),
            ],
            BuilderFormats {
                normal: sym,
                vector: sym,
                sphere: bumpsim_hw::units::SphereAddress {
                    r_frac: 9,
                    table_bits: 6,
                    value_bits: 10,
                },
                ..formats(uu(6))
            },
            16,
            every(16, 150),
            8,
            2,
        ),
        unit_with(
            "quantized_cartoon_fixed",
            100,
            vec![(0..100, cartoon(4, vec![l1, l3]))],
            cartoon_fixed,
            16,
            every(16, 100),
            8,
            2,
        ),
    ]
}
