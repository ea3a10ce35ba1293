//! Study of NDF-based bump map synthesis (Kautz et al. 2001, issue 15): regenerates
//! `docs/studies/ndf-synthesis.md` and the pictures in `docs/studies/ndf/`:
//!
//! ```sh
//! cargo run --release --example study_ndf
//! ```
//!
//! Claims: C16 (4 stages: isotropic only; an extra stage for anisotropic NDFs), C17 (the
//! generated normals follow the NDF), C18 (8-bit noise indices ring when the object moves,
//! float does not), shading consistency across levels of detail, and cost. Every number comes
//! from the library: `ndf::*` for the tables, `config::load` + `run::run` of the bundled
//! `configs/ndf-*.ron` with `--set` overrides for the renderings.

use bumpsim_pipeline::config;
use bumpsim_pipeline::ndf::tables::{binned, fit, histogram};
use bumpsim_pipeline::ndf::{Distribution, NdfSpec, SynthesisSpec};
use bumpsim_pipeline::run::{run, RunResult};
use rayon::prelude::*;
use std::fmt::Write;
use std::path::Path;

mod common;
use common::root;

fn load(name: &str, sets: &[String]) -> Result<RunResult, String> {
    let path = root().join("configs").join(format!("{name}.ron"));
    let l = config::load(&path, sets).map_err(|e| e.to_string())?;
    run(&l, None).map_err(|e| e.to_string())
}

fn go(name: &str, sets: &[String]) -> RunResult {
    load(name, sets).unwrap_or_else(|e| panic!("{name} {sets:?}: {e}"))
}

const U8: &str = "(format: (signed: false, width: 8, frac: 0), codec: UnitUnsigned)";

fn c16(md: &mut String) {
    writeln!(md, "## C16: four stages allow isotropic NDFs only\n").unwrap();
    let iso = go("ndf-teapot-hw", &[]);
    let ward = "scene.bump=Ndf(ndf: Ward(alpha_x: 0.1, alpha_y: 0.4), octaves: 4, frequency: 8)";
    let e4 = load("ndf-teapot-hw", &[ward.into()])
        .err()
        .unwrap_or_default();
    let p5 = format!(
        "engine.units.shader.unit.programs=[(program: Texture2d, texture: Some((source: NdfNoise(size: 256, level: 0), texel: {U8}))), (program: DependentGb(prev: 0), texture: Some((source: NdfLookup(size: 256, entry: Rgb8), texel: {U8}, filter: Nearest, address: Clamp))), (program: DependentGb(prev: 0), texture: Some((source: NdfLookup(size: 256, entry: Tangent8), texel: {U8}, filter: Nearest, address: Clamp))), (program: DotProduct(prev: 1, mapping: Minus1To1Gl)), (program: DotProductTexture2d(prev: 2, mapping: Minus1To1Gl), texture: Some((source: NdfShading2d(size: 256, light: 0), texel: {U8}, address: Mirror)))]"
    );
    let ins = r#"engine.units.shader.inputs={"coord0": "uvq", "coord1": "uvq", "coord2": "uvq", "coord3": "cat(h0, uvq.q)", "coord4": "cat(h0, uvq.q)"}"#;
    let sets5 = vec![
        ward.to_string(),
        p5,
        ins.to_string(),
        r#"engine.output="shader.tex4.rgb""#.to_string(),
    ];
    let e5 = load("ndf-teapot-hw", &sets5).err().unwrap_or_default();
    let aniso = go("ndf-teapot-aniso-hw5", &[]);
    let sw = go("ndf-teapot-aniso-sw", &[]);
    let short = |e: &str| e.rsplit(": engine.").next().unwrap_or(e).to_string();
    writeln!(
        md,
        "| program | stages | result |\n|---|---:|---|\n\
         | isotropic Blinn-Phong cos^24 (`ndf-teapot-hw`) | 4 | runs: algorithm {:.1} dB, quantization {:.1} dB |\n\
         | Ward (0.1, 0.4) in the same program | 4 | rejected (exit 2): `engine.{}` |\n\
         | Ward, NV20-style 5-stage part: TEXTURE_2D, DEPENDENT_GB (L_n), DEPENDENT_GB (L_t), DOT_PRODUCT (prev 1), DOT_PRODUCT_TEXTURE_2D (prev 2) | 5 | rejected (exit 2): `engine.{}` |\n\
         | Ward, the fifth stage free to dot a second texel (`ndf-teapot-aniso-hw5`: 3 texture-shader stages, a Dot3 of H with n_m and t_m, the 2-D NDF fetch) | 5 | runs: algorithm {:.1} dB, quantization {:.1} dB |\n\
         | Ward, software path (`ndf-teapot-aniso-sw`: per-fragment turbulence, octaves by LOD, the same tables) | — | runs: algorithm {:.1} dB, quantization {:.1} dB, {:.0} GE |\n",
        iso.report.error.algorithm.psnr_db,
        iso.report.error.quantization.psnr_db,
        short(&e4),
        short(&e5),
        aniso.report.error.algorithm.psnr_db,
        aniso.report.error.quantization.psnr_db,
        sw.report.error.algorithm.psnr_db,
        sw.report.error.quantization.psnr_db,
        sw.report.gates.total,
    )
    .unwrap();
    save(&sw.image, "teapot-aniso-sw.png");
    save(&iso.image, "teapot-hw.png");
    save(&aniso.image, "teapot-aniso-hw5.png");
    save(
        &go("ndf-teapot-uniform-hw", &[]).image,
        "teapot-uniform-hw.png",
    );
    writeln!(
        md,
        "![isotropic, 4 stages](ndf/teapot-hw.png) ![anisotropic, 5 stages](ndf/teapot-aniso-hw5.png) \
         ![uniform normals (Fig. 4 right)](ndf/teapot-uniform-hw.png) \
         ![anisotropic, software path (Fig. 4)](ndf/teapot-aniso-sw.png)\n"
    )
    .unwrap();
}

fn save(img: &image::RgbImage, name: &str) {
    let dir = root().join("docs/studies/ndf");
    std::fs::create_dir_all(&dir).unwrap();
    img.save(dir.join(name)).unwrap();
}

/// KL and chi-square/dof of the generated normals (256² texture coordinates, 16² bins).
fn c17_fit(s: &SynthesisSpec, table: Option<u32>) -> (f64, f64) {
    let surf = s.build(Path::new(".")).unwrap();
    let lookup = table.map(|n| surf.lookup(n));
    let side = 256;
    let normals = (0..side * side).map(|k| {
        let (i, j) = (k % side, k / side);
        let u = (f64::from(i) + 0.5) / f64::from(side);
        let v = (f64::from(j) + 0.5) / f64::from(side);
        let r = surf.indices(u, v, f64::from(s.octaves));
        match &lookup {
            Some(l) => l.normals[l.nearest(r[0], r[1])],
            None => surf.normal_of(r),
        }
    });
    let bins = 16;
    let h = histogram(bins, normals);
    let fine = bins * 16;
    fit(
        &h,
        &binned(&surf.ndf.map(fine, Distribution::Ndf), fine, bins),
    )
}

fn c17(md: &mut String) {
    writeln!(md, "## C17: the generated normals follow the NDF\n").unwrap();
    writeln!(
        md,
        "Normals generated at 256² texture coordinates (turbulence of 4 octaves from 32 cells, \
         so 8 samples per first-octave cell), binned on a 16² hemispherical map, against the \
         NDF integrated over each bin. KL divergence in nats; chi-square per degree of freedom \
         (bins with at least 5 expected). Uniform: Fig. 4 right's normals.\n\n\
         | NDF | exact inverse CDFs | L 64² | L 256² | uniform normals |\n|---|---|---|---|---|"
    )
    .unwrap();
    let ndfs = [
        NdfSpec::BlinnPhong { exponent: 20.0 },
        NdfSpec::BlinnPhong { exponent: 200.0 },
        NdfSpec::Beckmann { roughness: 0.3 },
        NdfSpec::Beckmann { roughness: 0.6 },
        NdfSpec::Ward {
            alpha_x: 0.15,
            alpha_y: 0.5,
        },
    ];
    let rows: Vec<String> = ndfs
        .par_iter()
        .map(|ndf| {
            let s = SynthesisSpec {
                ndf: ndf.clone(),
                normals: Distribution::Ndf,
                octaves: 4,
                frequency: 32,
                seed: 1,
                map_size: 64,
            };
            let mut u = s.clone();
            u.normals = Distribution::Uniform;
            let cell = |(chi, kl): (f64, f64)| format!("KL {kl:.4}, χ²/dof {chi:.1}");
            format!(
                "| {ndf:?} | {} | {} | {} | {} |",
                cell(c17_fit(&s, None)),
                cell(c17_fit(&s, Some(64))),
                cell(c17_fit(&s, Some(256))),
                cell(c17_fit(&u, None))
            )
        })
        .collect();
    for r in rows {
        writeln!(md, "{r}").unwrap();
    }
    writeln!(md).unwrap();
}

/// Mean |ΔI_bit - ΔI_exact| over consecutive frames (8-bit LSB of the framebuffers, all
/// channels, samples lit in any of the four images), the share where it reaches 4 LSB, and
/// the bit-accurate path's own mean |ΔI|.
fn flicker(bits: &[image::RgbImage], refs: &[image::RgbImage]) -> (f64, f64, f64) {
    let (mut sum, mut big, mut n, mut own) = (0.0, 0.0, 0.0, 0.0);
    for t in 0..bits.len() - 1 {
        for ((a0, a1), (r0, r1)) in bits[t]
            .pixels()
            .zip(bits[t + 1].pixels())
            .zip(refs[t].pixels().zip(refs[t + 1].pixels()))
        {
            for c in 0..3 {
                if a0[c] == 0 && a1[c] == 0 && r0[c] == 0 && r1[c] == 0 {
                    continue;
                }
                let db = f64::from(a1[c]) - f64::from(a0[c]);
                let dr = f64::from(r1[c]) - f64::from(r0[c]);
                let x = (db - dr).abs();
                sum += x;
                own += db.abs();
                if x >= 4.0 {
                    big += 1.0;
                }
                n += 1.0;
            }
        }
    }
    (sum / n, big / n, own / n)
}

/// The framebuffers (8-bit) of a config in bit-accurate and exact mode.
fn both_modes(name: &str, sets: &[String]) -> (image::RgbImage, image::RgbImage) {
    let (b, e) = common::framebuffers(name, sets);
    (b.rgb8, e.rgb8)
}

fn c18(md: &mut String) {
    writeln!(
        md,
        "## C18: 8-bit noise indices ring when the object moves\n"
    )
    .unwrap();
    writeln!(
        md,
        "`ndf-sphere-hw` (Beckmann 0.35), 8 frames with the camera orbiting the sphere by 0.25° \
         a frame (about a pixel at the silhouette's centre). Temporal ringing: the frame-to-frame \
         change of the bit-accurate path minus that of the float path (the same program in exact \
         mode: unquantized indices, normals, dot products and NDF values), mean |ΔI_bit − \
         ΔI_float| in 8-bit LSB of the framebuffers, and the share of lit samples where it \
         reaches 4 LSB; 'own' is the bit-accurate path's mean |ΔI|. The noise texels are \
         `UnitUnsigned` of the width given (the index width); L is 256² (nearest, as the paper, \
         or bilinear; 'Wide': L as HILO16 and 16-bit NDF texels, nearest); the noise level bound is \
         `level` (0: 256², 4 octaves; 1: 128², 3).\n\n\
         | index bits | L filter | level | ringing LSB | ≥ 4 LSB | own LSB |\n|---:|---|---:|---:|---:|---:|"
    )
    .unwrap();
    let mut cases = Vec::new();
    for (filter, level) in [("Nearest", 0), ("Bilinear", 0), ("Nearest", 1), ("Wide", 0)] {
        for w in [8u32, 10, 12, 16] {
            cases.push((w, filter, level));
        }
    }
    let rows: Vec<String> = cases
        .par_iter()
        .map(|&(w, filter, level)| {
            let (mut bits, mut refs) = (Vec::new(), Vec::new());
            for k in 0..8 {
                let a = (k as f64 * 0.25).to_radians();
                let sets = vec![
                    format!(
                        "scene.camera.eye=({}, 0.6, {})",
                        3.2 * a.sin(),
                        3.2 * a.cos()
                    ),
                    format!(
                        "engine.units.shader.unit.programs[0].texture.texel=(format: (signed: false, width: {w}, frac: 0), codec: UnitUnsigned)"
                    ),
                    format!("engine.units.shader.unit.programs[0].texture.source=NdfNoise(size: 256, level: {level})"),
                ];
                let mut sets = sets;
                if filter == "Wide" {
                    // 16-bit tables: L as HILO16, the NDF texels 16 bits
                    let u16 = "(format: (signed: false, width: 16, frac: 0), codec: UnitUnsigned)";
                    sets.push(format!("engine.units.shader.unit.programs[1].texture=Some((source: NdfLookup(size: 256, entry: Hilo16), texel: {u16}, filter: Nearest, address: Clamp))"));
                    sets.push("engine.units.shader.unit.programs[2].program=DotProduct(prev: 1, mapping: HiloHemisphereGl)".into());
                    sets.push("engine.units.shader.unit.programs[3].program=DotProductTexture2d(prev: 1, mapping: HiloHemisphereGl)".into());
                    sets.push(format!("engine.units.shader.unit.programs[3].texture=Some((source: NdfShading(size: 256, light: 0), texel: {u16}, address: Clamp))"));
                } else {
                    sets.push(format!("engine.units.shader.unit.programs[1].texture.filter={filter}"));
                }
                let (b, e) = both_modes("ndf-sphere-hw", &sets);
                if k == 0 && w == 8 && filter == "Nearest" && level == 0 {
                    save(&b, "sphere-8bit.png");
                    save(&e, "sphere-float.png");
                }
                bits.push(b);
                refs.push(e);
            }
            let (m, big, own) = flicker(&bits, &refs);
            format!(
                "| {w} | {filter} | {level} | {m:.3} | {:.2} % | {own:.3} |",
                100.0 * big
            )
        })
        .collect();
    for r in rows {
        writeln!(md, "{r}").unwrap();
    }
    writeln!(md).unwrap();
}

fn lod(md: &mut String) {
    writeln!(md, "## Shading consistency across levels of detail\n").unwrap();
    writeln!(
        md,
        "Mean NDF shading `D(h_m) / max D` of a patch (256² texture coordinates) at each mip \
         level of the noise (level k holds 4 − k octaves; level 4 holds none, the flat surface \
         seen from far away), against the NDF's closed-form shading of the flat surface, \
         `D(θ_h) / max D`, for half-way vectors tilted by θ_h from the macro normal, and the \
         flat level shaded with the far NDF (`NdfShading(far: true)`: the NDF averaged over \
         its own microfacets, read at `L(1/2, 1/2) · h`, as the texture shader reads it). \
         Beckmann 0.35, 8 cells.\n\n\
         | θ_h | closed form | level 0 (4 octaves) | level 1 | level 2 | level 3 | level 4 (flat) | level 4, far NDF |\n|---:|---:|---:|---:|---:|---:|---:|---:|"
    )
    .unwrap();
    let s = SynthesisSpec {
        ndf: NdfSpec::Beckmann { roughness: 0.35 },
        normals: Distribution::Ndf,
        octaves: 4,
        frequency: 8,
        seed: 1,
        map_size: 128,
    };
    let surf = s.build(Path::new(".")).unwrap();
    for deg in [0.0f64, 10.0, 20.0, 30.0, 45.0] {
        let closed = surf.ndf.relative_iso(deg.to_radians().cos());
        let mut row = format!("| {deg}° | {closed:.4} |");
        for level in 0..=4u32 {
            let m = surf.patch_shading(level, 256, deg.to_radians());
            write!(row, " {m:.4} |").unwrap();
        }
        let far = surf.far_shading(deg.to_radians());
        write!(row, " {far:.4} |").unwrap();
        writeln!(md, "{row}").unwrap();
    }
    writeln!(md).unwrap();
}

/// Fig. 1: the sphere at three distances, each with the noise level its distance needs
/// (one level coarser per doubling).
fn fig1(md: &mut String) {
    writeln!(
        md,
        "## Fig. 1: the sphere at several distances
"
    )
    .unwrap();
    writeln!(
        md,
        "`ndf-sphere-hw` with the eye at 3.2, 6.4 and 12.8 along its direction and the noise \
         level 0, 1, 2 bound (4, 3, 2 octaves: one level per doubling of distance); then \
         `ndf-sphere-hw-mip`, whose stage 0 selects the level per fragment from the whole mip \
         chain (the interpolated per-vertex LOD of the 256-texel map, NEAREST_MIPMAP_NEAREST).\n\n\
         | distance | level | algorithm dB | quantization dB | mean lit intensity |\n|---:|---:|---:|---:|---:|"
    )
    .unwrap();
    let mut pics = String::new();
    let rows = [3.2f64, 6.4, 12.8]
        .iter()
        .enumerate()
        .map(|(k, &d)| (d, Some(k)))
        .chain([3.2f64, 6.4, 12.8, 25.6].map(|d| (d, None)));
    for (d, k) in rows {
        let f = d / 3.2;
        let mut sets = vec![
            format!("scene.camera.eye=(0.0, {}, {})", 0.6 * f, 3.2 * f),
            format!("scene.camera.far={}", 10.0 * f),
        ];
        let name = match k {
            Some(k) => {
                sets.push(format!(
                    "engine.units.shader.unit.programs[0].texture.source=NdfNoise(size: 256, level: {k})"
                ));
                "ndf-sphere-hw"
            }
            None => "ndf-sphere-hw-mip",
        };
        let r = go(name, &sets);
        let (mut sum, mut n) = (0.0f64, 0.0f64);
        for p in r.image.pixels() {
            let v = f64::from(p[0]) + f64::from(p[1]) + f64::from(p[2]);
            if v > 0.0 {
                sum += v / 3.0;
                n += 1.0;
            }
        }
        let level = k.map_or("per fragment".to_string(), |k| k.to_string());
        writeln!(
            md,
            "| {d} | {level} | {:.1} | {:.1} | {:.1} |",
            r.report.error.algorithm.psnr_db,
            r.report.error.quantization.psnr_db,
            sum / n.max(1.0)
        )
        .unwrap();
        if let Some(k) = k {
            let name = format!("sphere-distance-{k}.png");
            save(&r.image, &name);
            write!(pics, "![distance {d}](ndf/{name}) ").unwrap();
        } else if d == 3.2 {
            save(&r.image, "sphere-mip.png");
            write!(
                pics,
                "![distance 3.2, mip level per fragment](ndf/sphere-mip.png) "
            )
            .unwrap();
        }
    }
    writeln!(md, "\n{pics}\n").unwrap();
}

fn cost(md: &mut String) {
    writeln!(md, "## Cost\n").unwrap();
    let r = go("ndf-teapot-hw", &[]).report;
    writeln!(
        md,
        "`ndf-teapot-hw` at 256² (16,384 triangles): {:.0} GE in all ({}), {:.2} cycles per \
         fragment ({} fragments, {} cycles).\n\n| texture | size | bits/texel | bits stored |\n|---|---|---:|---:|",
        r.gates.total,
        r.gates
            .per_unit
            .iter()
            .map(|(k, v)| format!("{k} {:.0}", v.total))
            .collect::<Vec<_>>()
            .join(", "),
        r.cycles.per_fragment,
        r.cycles.fragments,
        r.cycles.total,
    )
    .unwrap();
    for (name, t) in &r.bandwidth.texture_memory {
        writeln!(
            md,
            "| {name} | {}x{}, {} level(s) | {} | {} |",
            t.size[0], t.size[1], t.levels, t.bits_per_texel, t.stored_bits
        )
        .unwrap();
    }
    let chain: u64 = (0..=8).map(|k| (256u64 >> k).pow(2) * 24).sum();
    writeln!(
        md,
        "\nThe whole noise mip chain (256² down to 1², 24 bits a texel) is {chain} bits: what \
         `ndf-sphere-hw-mip` stores to select the level per fragment; the other configs bind \
         one level per draw (see `docs/units/ndf.md`).\n"
    )
    .unwrap();
}

fn main() {
    let mut md = String::new();
    writeln!(
        md,
        "# Study: NDF-based bump map synthesis (Kautz et al. 2001)\n\n\
         Generated by `cargo run --release --example study_ndf` (`examples/study_ndf.rs`); \
         the discussion is in the sections' last paragraphs, written from these numbers. \
         Units: `docs/units/ndf.md`.\n"
    )
    .unwrap();
    c16(&mut md);
    c17(&mut md);
    c18(&mut md);
    lod(&mut md);
    fig1(&mut md);
    cost(&mut md);
    print!("{md}");
    let out = root().join("docs/studies/ndf/tables.md");
    std::fs::create_dir_all(out.parent().unwrap()).unwrap();
    std::fs::write(&out, md).unwrap();
    eprintln!("wrote {}", out.display());
}
