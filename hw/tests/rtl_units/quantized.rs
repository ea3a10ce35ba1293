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
    let b = PaletteBuilder::new(normals(n), materials, formats(entry), 1).unwrap();
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

/// Indices `0..n` in turn, so that every entry of the table is under some texel.
fn every(size: u32, n: usize) -> Vec<u32> {
    (0..size * size).map(|k| k % n as u32).collect()
}

/// The bundled configs' builder: Blinn-Phong with one light on 256 entries
/// (`quantized-sphere`), Lambert on 16 (`quantized-sn16`, `quantized-vase-sn*`).
pub fn bundled() -> Vec<Case> {
    let light = ([0.577, 0.577, 0.577], [1.0; 3]);
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
    };
    // a 200-entry table behind an 8-bit index, read in a scattered order
    let scattered: Vec<u32> = (0..32 * 32u32).map(|k| (k * 7) % 200).collect();
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
    ]
}
