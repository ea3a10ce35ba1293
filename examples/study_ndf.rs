//! Study of NDF-based bump map synthesis (Kautz et al. 2001, issue 15): regenerates
//! `docs/studies/ndf-synthesis.md` and everything under `docs/studies/ndf/`:
//!
//! ```sh
//! cargo run --release --example study_ndf
//! ```
//!
//! Claims: C16 (4 stages: isotropic only; an extra stage for anisotropic NDFs), C17 (the
//! generated normals follow the NDF), C18 (8-bit noise indices ring when the object moves,
//! float does not), shading consistency across levels of detail, Fig. 1 and cost.
//!
//! Every table is a sweep's, `docs/studies/sweeps/kautz-*.ron`, run into
//! `docs/studies/ndf/NAME/` exactly as `bumpsim sweep docs/studies/sweeps/kautz-NAME.ron --out
//! docs/studies/ndf/NAME` runs them (from the repository root, so that the error rows name the
//! configs by relative paths), quoted as they are written; the verdicts read the sweeps' rows
//! or quote their numbers. This program adds the prose and the pictures (Fig. 1's renders,
//! checked to be the sweep's points by their config hashes).

use bumpsim_pipeline::config;
use bumpsim_pipeline::run::{run, RunResult};
use bumpsim_pipeline::sweep::table::Row;
use std::fmt::Write;

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

use common::Swept;

/// Run `docs/studies/sweeps/kautz-{name}.ron` into `docs/studies/ndf/{name}/`, error rows kept
/// (C16's rejected programs are rows).
fn kautz(name: &str) -> Swept {
    Swept::run_keeping_errors(&format!("kautz-{name}"), &format!("ndf/{name}"))
}

/// A rejected row's reason: its error message from the field on (`engine....`), without the
/// config file and its overrides.
fn reason(s: &Swept, r: &Row) -> String {
    assert!(!r.is_ok(), "{}: row {} is not an error", s.file, r.index);
    let e = s.text(r, "error");
    format!("engine.{}", e.rsplit(": engine.").next().unwrap_or(&e))
}

fn c16(md: &mut String, stages: &Swept, nv20: &Swept, width: &Swept) {
    writeln!(
        md,
        "## C16: four stages allow isotropic NDFs only; an extra stage allows anisotropic ones\n"
    )
    .unwrap();
    // labels by their start (`Swept::holds`)
    let (gf3, hw5, sw) = ("GeForce3*", "5 stages*", "software*");
    let (iso, ward) = ("isotropic*", "anisotropic*");
    let s = stages;
    let it = s.any_row(&[("program", gf3), ("ndf", iso)]);
    let w4 = s.any_row(&[("program", gf3), ("ndf", ward)]);
    let a5 = s.any_row(&[("program", hw5), ("ndf", ward)]);
    let i5 = s.any_row(&[("program", hw5), ("ndf", iso)]);
    let aw = s.any_row(&[("program", sw), ("ndf", ward)]);
    let nv = &nv20.t.rows[0];
    let db = |r: &Row, c: &str| format!("{:.1}", s.n(r, c));
    writeln!(
        md,
        "Three programs, each with an isotropic and an anisotropic NDF, {} (a program that \
         cannot hold the NDF is an error row, the config refused with exit code 2; its reason \
         is quoted below the table):\n\n{}\n\n\
         The natural program of an NV20-style part with a fifth stage (Ward's NDF), {}:\n\n{}\n\n\
         The reasons (the error rows' messages from the field on): the 4-stage program with \
         Ward's NDF, `{}`; the NV20-style 5-stage program, `{}`.\n",
        s.cite(),
        s.table("stages"),
        nv20.cite(),
        nv20.table("nv20"),
        reason(s, w4),
        reason(nv20, nv),
    )
    .unwrap();
    let teapot = |name: &str| {
        let r = go(name, &[]);
        save(
            &r.image,
            &format!("{}.png", name.trim_start_matches("ndf-")),
        );
    };
    for name in [
        "ndf-teapot-hw",
        "ndf-teapot-aniso-hw5",
        "ndf-teapot-uniform-hw",
        "ndf-teapot-aniso-sw",
    ] {
        teapot(name);
    }
    writeln!(
        md,
        "![isotropic, 4 stages](ndf/teapot-hw.png) ![anisotropic, 5 stages](ndf/teapot-aniso-hw5.png) \
         ![uniform normals (Fig. 4 right)](ndf/teapot-uniform-hw.png) \
         ![anisotropic, software path (Fig. 4)](ndf/teapot-aniso-sw.png)\n"
    )
    .unwrap();
    writeln!(
        md,
        "**Verdict: the first half holds, the second needs more than a stage.** The isotropic program \
is exactly the paper's (TEXTURE_2D of the noise, DEPENDENT_GB into `L`, DOT_PRODUCT of `H`, \
DOT_PRODUCT_TEXTURE_2D into the 1-D NDF at `(n_m·H, 0)`) and runs on the NV20 stage rules \
(algorithm {} dB, quantization {} dB). An \
anisotropic NDF must be read at `(n_m·H, t_m·H)`: a second table `L_t` (a second \
DEPENDENT_GB of the same noise) and a second dot product against that other texel. Four \
stages cannot hold it, and the config is refused with that reason (exit 2). But on an \
NV20-style part with a fifth stage the natural program is refused too: NV_texture_shader's \
consistency rule makes DOT_PRODUCT_TEXTURE_2D's partner DOT_PRODUCT read the same previous \
texel, so the two dot products cannot take `n_m` and `t_m` from two stages. The fifth stage \
the paper asks for must also lift that rule (or be a stage that dots a second texel). bumpsim \
builds it from its own units (a `Dot3` of `H` with both texels and a `TexFetch` of the 2-D NDF), \
and it renders the anisotropic highlight: algorithm {} dB, quantization {} dB, as close \
to the reference as the isotropic program. (Until the reference took the \
surface's `u` as the microfacet tangent, as the engines do, it took world `x`, and this figure \
was 25.8 dB.) The same program also runs the isotropic NDF (quantization {} dB against the 4-stage \
program's {}: the datapath, not the program; see the table below). The software path (§5.1, Fig. 4) needs no \
stages: a per-fragment turbulence unit \
(octaves from the interpolated per-vertex LOD, the next one blended in) feeds the same tables. \
It renders the same streak and is as exact ({} dB quantization); its algorithm figure ({} \
dB) is lower because it drops octaves with the LOD where the reference evaluates all four, at \
the price of the noise datapath: 8 octave datapaths of improved noise, {:.0} GE of its {:.0}, \
where the texture shader reads a noise texture.\n",
        db(it, "algorithm_psnr_db"),
        db(it, "quantization_psnr_db"),
        db(a5, "algorithm_psnr_db"),
        db(a5, "quantization_psnr_db"),
        db(i5, "quantization_psnr_db"),
        db(it, "quantization_psnr_db"),
        db(aw, "quantization_psnr_db"),
        db(aw, "algorithm_psnr_db"),
        s.n(aw, "gates.noise"),
        s.n(aw, "gates_total"),
    )
    .unwrap();
    let (narrow, wide) = (
        width.row(&[("datapath", "as bundled*")]),
        width.row(&[("datapath", "16 bits*")]),
    );
    writeln!(
        md,
        "The 5-stage config's datapath is narrower than the 4-stage one's (chosen for Ward's \
         NDF). With the isotropic NDF, the same program at 16 bits throughout, {}:\n\n{}\n\n\
         At 16 bits the quantization PSNR is {:.1} dB, as good as the 4-stage program's {} dB, for \
         {:.0} GE more: the difference was the widths, not the fifth stage.\n",
        width.cite(),
        width.table("width"),
        width.n(wide, "quantization_psnr_db"),
        db(it, "quantization_psnr_db"),
        width.n(wide, "gates_total") - width.n(narrow, "gates_total"),
    )
    .unwrap();
}

fn save(img: &image::RgbImage, name: &str) {
    let dir = root().join("docs/studies/ndf");
    std::fs::create_dir_all(&dir).unwrap();
    img.save(dir.join(name)).unwrap();
}

fn c17(md: &mut String, fit: &Swept) {
    writeln!(md, "## C17: the generated normals follow the NDF\n").unwrap();
    writeln!(
        md,
        "Normals generated at 256² texture coordinates (turbulence of 4 octaves from 32 cells, \
         so 8 samples per first-octave cell), binned on a 16² hemispherical map, against the \
         NDF integrated over each bin: the report's `synthesis` section (`reference.synthesis`, \
         docs/metrics.md), measured on the tables. KL divergence in nats; chi-square per degree \
         of freedom (bins with at least 5 expected); through the exact inverse CDFs and through \
         the engine's `L` (nearest entry), {}:\n\n{}\n\nUniform normals (Fig. 4 right's \
         counter-example), the same sweep:\n\n{}\n",
        fit.cite(),
        fit.table("fit"),
        fit.table("uniform")
    )
    .unwrap();
}

fn c18(md: &mut String) {
    let (ring, wide) = (kautz("ringing"), kautz("ringing-wide"));
    writeln!(
        md,
        "## C18: 8-bit noise indices cause ringing that float does not\n\n\
         `ndf-sphere-hw` (Beckmann 0.35), 8 frames with the camera orbiting the sphere by 0.25° \
         a frame (about a pixel at the silhouette's centre; `frames`, 7 camera positions after \
         the config's). Temporal ringing: the frame-to-frame change of the bit-accurate path \
         minus that of the float path (the same program in exact mode: unquantized indices, \
         normals, dot products and NDF values), mean |ΔI_bit − ΔI_float| in 8-bit LSB of the \
         framebuffers, and the share of lit samples where it reaches 4 LSB; 'own' is the \
         bit-accurate path's mean |ΔI|: the report's `animation.ringing` (`mean_lsb`, \
         `share_4lsb`, `change_lsb`, docs/metrics.md). The noise texels are `UnitUnsigned` of \
         the width given (the index width); L is 256² (nearest, as the paper, or bilinear); the \
         noise level bound is `level` (0: 256², 4 octaves; 1: 128², 3), {}:\n\n{}\n\n\
         With 16-bit tables (L as HILO16 read by the hemisphere mapping, 16-bit NDF texels, \
         nearest, level 0), {}:\n\n{}\n",
        ring.cite(),
        ring.table("ringing"),
        wide.cite(),
        wide.table("ringing-wide"),
    )
    .unwrap();
    let m = "report.animation.ringing.mean_lsb";
    let sh = "report.animation.ringing.share_4lsb";
    let at = |bits: &str, filter: &str, level: &str, c: &str| {
        let r = ring.row(&[("index_bits", bits), ("filter", filter), ("level", level)]);
        ring.n(r, c)
    };
    let w = |bits: &str, c: &str| wide.n(wide.row(&[("index_bits", bits)]), c);
    let (r8, r16) = (at("8", "Nearest", "0", m), at("16", "Nearest", "0", m));
    // the spread of every 8-bit-table row against the paper's case
    let rows8: Vec<f64> = ring.t.rows.iter().map(|r| ring.n(r, m)).collect();
    let spread = rows8.iter().fold(0.0f64, |a, x| a.max((x - r8).abs() / r8));
    let ws: Vec<f64> = ["8", "10", "12", "16"].iter().map(|b| w(b, m)).collect();
    let wsh: Vec<f64> = ["8", "10", "12", "16"]
        .iter()
        .map(|b| 100.0 * w(b, sh))
        .collect();
    let indices_main = (r8 - r16) / r8 < 0.5;
    let tenth = ws
        .iter()
        .position(|x| *x < 2.0 * ws[3])
        .map_or(16, |k| [8, 10, 12, 16][k]);
    writeln!(
        md,
        "**Verdict: {}.** With the paper's texel formats (8-bit `L` entries and NDF), the \
         moving sphere's frames differ from the float path's by {r8:.2} LSB on average ({:.1} % \
         of lit samples by 4 LSB or more). Widening only the noise indices to 16 bits removes \
         {:.0} % of that ({r16:.2} LSB){}. A bilinear `L` or a coarser noise level changes \
         little (every row within {:.0} % of the paper's case). With 16-bit tables the index \
         width decides: {:.3} LSB at 8 bits, {:.3} at 10, {:.3} at 12 and {:.3} at 16 ({:.2} %, \
         {:.2} %, {:.2} %, {:.2} % of samples at 4 LSB or more); 8-bit indices flicker {:.0} \
         times as much as 16-bit ones. The paper's guess (\"probably due to quantization errors \
         (e.g. the indices in the noise-texture are limited to 8 bits by the hardware)\") names \
         {}. From {tenth} bits the indices ring less than twice the 16-bit floor of a 16-bit \
         table path.\n\n\
         ![8-bit path, frame 0](ndf/sphere-8bit.png) ![float path, frame 0](ndf/sphere-float.png)\n",
        if indices_main {
            "holds, but on the GeForce3's 8-bit tables the indices are not the main cause"
        } else {
            "holds: the 8-bit indices are the main cause"
        },
        100.0 * at("8", "Nearest", "0", sh),
        100.0 * (r8 - r16) / r8,
        if indices_main {
            ": the 8-bit `L` entries and the 8-bit NDF values ring as much"
        } else {
            ""
        },
        100.0 * spread,
        ws[0],
        ws[1],
        ws[2],
        ws[3],
        wsh[0],
        wsh[1],
        wsh[2],
        wsh[3],
        ws[0] / ws[3],
        if indices_main {
            "one of three 8-bit sources, not the largest"
        } else {
            "the main source"
        },
    )
    .unwrap();
    // the pictures: frame 0 of the paper's case (8-bit indices, nearest L, level 0)
    let r = go(
        "ndf-sphere-hw",
        &[
            "engine.units.shader.unit.programs[0].texture.texel=(format: (signed: false, width: 8, frac: 0), codec: UnitUnsigned)".into(),
            "engine.units.shader.unit.programs[1].texture.filter=Nearest".into(),
            "engine.units.shader.unit.programs[0].texture.source=NdfNoise(size: 256, level: 0)".into(),
        ],
    );
    save(&r.image, "sphere-8bit.png");
    save(&r.exact, "sphere-float.png");
}

fn lod(md: &mut String, lod: &Swept) {
    writeln!(md, "## Shading consistency across levels of detail\n").unwrap();
    writeln!(
        md,
        "Mean NDF shading `D(h_m) / max D` of a patch (256² texture coordinates) at each mip \
         level of the noise (level k holds 4 − k octaves; level 4 holds none, the flat surface \
         seen from far away), against the NDF's closed-form shading of the flat surface, \
         `D(θ_h) / max D`, for half-way vectors tilted by θ_h from the macro normal, and the \
         flat level shaded with the far NDF (`NdfShading(far: true)`: the NDF averaged over \
         its own microfacets, read at `L(1/2, 1/2) · h`, as the texture shader reads it): the \
         report's `synthesis` section. Beckmann 0.35, 8 cells, {}:\n\n{}\n",
        lod.cite(),
        lod.table("lod")
    )
    .unwrap();
}

/// Fig. 1: the sphere at three distances, each with the noise level its distance needs
/// (one level coarser per doubling), then with the level per fragment; the tables are the
/// sweeps', the pictures rendered here.
fn fig1(md: &mut String, near: &Swept, mip: &Swept) {
    writeln!(
        md,
        "## Fig. 1: the sphere at several distances\n\n\
         `ndf-sphere-hw` with the eye at 3.2, 6.4 and 12.8 along its direction and the noise \
         level 0, 1, 2 bound (4, 3, 2 octaves: one level per doubling of distance, each \
         distance paired with its level), {}:\n\n{}\n\n\
         Then `ndf-sphere-hw-mip`, whose stage 0 selects the level per fragment from the whole \
         mip chain (the interpolated per-vertex LOD of the 256-texel map, \
         NEAREST_MIPMAP_NEAREST), {}:\n\n{}\n\n\
         The mean lit intensity is the report's `image.mean_lit_level`: (R + G + B) / 3 over \
         the pixels that are not black.\n",
        near.cite(),
        near.table("distance"),
        mip.cite(),
        mip.table("distance")
    )
    .unwrap();
    let mut pics = String::new();
    for (k, d) in [3.2f64, 6.4, 12.8].into_iter().enumerate() {
        let f = d / 3.2;
        let sets = vec![
            format!("scene.camera.eye=(0.0, {}, {})", 0.6 * f, 3.2 * f),
            format!("scene.camera.far={}", 10.0 * f),
            format!(
                "engine.units.shader.unit.programs[0].texture.source=NdfNoise(size: 256, level: {k})"
            ),
        ];
        let r = go("ndf-sphere-hw", &sets);
        let row = near.row(&[("distance", &d.to_string())]);
        assert_eq!(
            near.text(row, "config_hash"),
            r.report.config_hash,
            "the picture is the sweep's point"
        );
        let name = format!("sphere-distance-{k}.png");
        save(&r.image, &name);
        write!(pics, "![distance {d}](ndf/{name}) ").unwrap();
    }
    save(&go("ndf-sphere-hw-mip", &[]).image, "sphere-mip.png");
    write!(
        pics,
        "![distance 3.2, mip level per fragment](ndf/sphere-mip.png) "
    )
    .unwrap();
    writeln!(md, "{pics}\n").unwrap();
}

fn cost(md: &mut String, cost: &Swept) {
    writeln!(md, "## Cost\n").unwrap();
    let s = cost;
    let teapot = s.row(&[("config", "ndf-teapot-hw")]);
    let sphere = s.row(&[("config", "ndf-sphere-hw")]);
    writeln!(
        md,
        "The three hardware configs as bundled (256²), {}:\n\n{}\n",
        s.cite(),
        s.table("cost")
    )
    .unwrap();
    let mip = s.row(&[("config", "ndf-sphere-hw-mip")]);
    let chain = "report.bandwidth.texture_memory[shader.tex0].stored_bits";
    writeln!(
        md,
        "The bits stored per texture (the reports' `bandwidth.texture_memory`: the noise \
         `shader.tex0`, `L` `shader.tex1`, the 1-D NDF `shader.tex3`; 24 bits a texel), the same \
         sweep:\n\n{}\n\nThe whole noise mip chain (256² down to 1²) is {} bits: what \
         `ndf-sphere-hw-mip` stores to select the level per fragment; the other configs bind \
         one level per draw (see `docs/units/ndf.md`).\n",
        s.table("memory"),
        s.text(mip, chain)
    )
    .unwrap();
    writeln!(
        md,
        "The texture shader's {:.0} GE are the whole four-stage part (every stage has the full \
datapath, `docs/units/texture-shader.md`). The synthesis itself adds only tables: the noise \
level bound (1.57 Mbit at 256², or 2.10 Mbit for the whole chain), `L` at 256² RGB8 (1.57 Mbit) \
and the 1-D NDF (6 kbit). A fragment reads 4 noise texels (bilinear), 1 `L` entry (nearest) and 4 NDF \
texels (bilinear, in a 1-texel-high texture). The {:.2} cycles per fragment of the teapot are its \
{} small triangles: triangle setup, not the shader, bounds the frame (the sphere of \
`ndf-sphere-hw`, {} triangles, runs at {:.2} cycles per fragment).\n",
        s.n(teapot, "gates.shader"),
        s.n(teapot, "report.cycles.per_fragment"),
        s.text(teapot, "report.cycles.triangles"),
        s.text(sphere, "report.cycles.triangles"),
        s.n(sphere, "report.cycles.per_fragment"),
    )
    .unwrap();
}

/// The section's verdict, written from the numbers the program prints above it.
const C17_VERDICT: &str =
    "**Verdict: holds.** Through the exact inverse CDFs and through `L` at 256², the histogram of
the generated normals is within KL 0.001 to 0.005 nats of the target for every NDF tried. The
uniform counter-example is 7 to 105 nats away. At 64² entries `L` is coarse for broad NDFs
(Beckmann 0.6: 0.026). The χ² per degree of freedom is 4 to 6, not 1, because the normals of
neighbouring texture coordinates come from correlated noise, not independent draws. Fed
independent uniform numbers instead (`tests/ndf.rs`, `inverse_cdfs_sample_the_map`, 200,000
draws), the same tables give χ²/dof 0.76 and KL 0.0004: the tables are an exact sampler of the
map, and the residual comes from the noise. The suite asserts KL < 0.02 for three NDFs at
three table settings, and the uniform case 100 times worse.
";

const LOD_VERDICT: &str =
    "**Verdict: consistent between bump levels, not at the switch to the flat surface.** Once
bumps exist (levels 0 to 3, 4 down to 1 octave), the patch's mean shading changes little: the
peak goes from 0.56 to 0.63 as octaves are dropped, because one `G` serves every level and the
turbulence's spread shrinks only a little with fewer octaves (the paper's \"valid
approximation\"). The coarsest level has no octaves: the flat surface shaded with the NDF, as
§5.1 prescribes beyond the distance threshold. That is the closed form, and it is 1.8 times
brighter at the highlight's centre and narrower: 0.11 against 0.19 at 30°, 0.001 against 0.04 at
45°. Shading microfacets that are distributed by `D` with `D` itself averages to the
convolution of `D` with itself, not `D`. A far level consistent with the near ones would shade
with that self-convolution. The paper's consistency assumes fractal (self-similar)
microfacets, but its far level stays the plain NDF. So the transition pops unless it is
blended, which §5.1's smooth blending of new octaves does not cover at the last octave.

**The fix: a far NDF.** `NdfShading(far: true)` stores, for each `n·h`, the NDF averaged
over microfacets distributed by the NDF itself (the tables' samples of a stratified 64² grid;
`NdfSurface::far_relative`). The flat level shaded with it is the last column: 0.5652 at 0°
against 0.5645 at 4 octaves, and within 3 % of level 0 up to 30° (0.1813 against 0.1865),
where the plain NDF is 77 % too bright at 0° and 40 % too dark at 30°. At 45° the far NDF
gives 0.038 against 0.041 (the tails of the 64² grid). A draw of the far level binds it in
place of the plain NDF, and the switch keeps the mean shading (`tests/ndf.rs`,
`far_level_keeps_the_bump_levels_shading`). Within one draw whose stage 0 selects the mip
level per fragment (`ndf-sphere-hw-mip`, below), the flat levels share stage 3's texture
with the bump levels, so there the plain NDF remains.
";

const FIG1_PROSE: &str =
    "The hardware path keeps the sphere's mean lit intensity within 6 % over a fourfold distance
(36.5, 35.3, 34.4 of 255) while the bound level drops an octave per doubling. The algorithm
figure falls with distance (43.3 → 27.0 dB) because the reference evaluates every octave at
each pixel centre, so it aliases where the mip level does not. The quantization error stays
at 43 dB.

With the level selected per fragment (`ndf-sphere-hw-mip`: the whole chain in texture memory,
2.10 Mbit against 1.57 for one level, stage 0 reading the NEAREST_MIPMAP_NEAREST level of the
interpolated per-vertex LOD), the mean lit intensity stays within 7 % over an eightfold
distance (36.4, 35.1, 33.8, 34.3). The LOD drops octaves sooner than the per-draw binding
(levels 0 to 3 show at 3.2), so the algorithm figure is lower (36.1 dB at 3.2, 16.7 dB at
25.6): the reference keeps every octave. Quantization stays at 40 to 42 dB.
";

const LEFT_OPEN: &str = "## Left open

- A reference that follows the engines' level of detail: it evaluates every octave at each
  pixel centre, so the algorithm figures of the paths that drop octaves (the software path,
  the per-fragment mip level, the far distances) measure the octaves dropped as error.
- The far NDF within a single draw: where stage 0 selects the mip level per fragment, the flat
  levels read stage 3's plain NDF; a consistent transition inside one draw would need the NDF
  texture itself to change with the level (a second 1-D texture blended by the LOD). The far
  NDF is built for isotropic NDFs only (the 1-D texture).
- Per-stage LOD from each stage's own coordinate derivatives, as the GeForce3 computes it:
  bumpsim takes one LOD per fragment from the engine.
";

fn main() {
    // the sweeps run from the repository root, as `bumpsim sweep` from there (relative paths)
    std::env::set_current_dir(root()).unwrap();
    let mut md = String::new();
    writeln!(
        md,
        "# Study: NDF-based bump map synthesis (Kautz et al. 2001)\n\n\
Kautz, Heidrich and Seidel synthesise a bump map from nothing but a normal density function
(NDF) and shade it with the same NDF: turbulence gives two random numbers per texel, a
precomputed table `L(r1, r2)` turns them into a microfacet normal distributed by the NDF
(§4), and on a GeForce3 four texture-shader stages look the normal up and shade it with the
NDF (§5.2). This study tests the paper's hardware claims on bumpsim's model
(`pipeline/src/ndf/`, `docs/units/ndf.md`). The page is generated by
`cargo run --release --example study_ndf` (`examples/study_ndf.rs`; do not edit by hand),
with the pictures in `docs/studies/ndf/`. Every table is a sweep's,
`docs/studies/sweeps/kautz-*.ron`, written into `docs/studies/ndf/NAME/` (with the sweep's
rows, `sweep.csv`) by the command each section names (`bumpsim sweep`, docs/sweep.md, run
from the repository root); each sweep file's header says what it varies, what it holds fixed
and which claim it tests. C17 and the levels of detail are measured on the synthesis tables
themselves (the report's `synthesis` section, `reference.synthesis`); Fig. 1 pairs each
distance with its noise level (`paired` paths of an axis). The verdicts are written from
those numbers.

Configs: `configs/ndf-sphere-hw.ron` (Fig. 1's sphere, Beckmann), `configs/ndf-teapot-hw.ron`
(Fig. 5: isotropic, hardware, 16,384 triangles), `configs/ndf-teapot-uniform-hw.ron` (Fig. 4
right: uniform normals), `configs/ndf-teapot-aniso-hw5.ron` (the anisotropic 5-stage
variant), `configs/ndf-teapot-aniso-sw.ron` (Fig. 4: the software path, anisotropic).
"
    )
    .unwrap();
    let (stages, nv20, cost_sw) = (kautz("stages"), kautz("nv20"), kautz("cost"));
    c16(&mut md, &stages, &nv20, &kautz("hw5-width"));
    c17(&mut md, &kautz("fit"));
    writeln!(md, "{C17_VERDICT}").unwrap();
    c18(&mut md);
    lod(&mut md, &kautz("lod"));
    writeln!(md, "{LOD_VERDICT}").unwrap();
    fig1(&mut md, &kautz("distance"), &kautz("distance-mip"));
    writeln!(md, "{FIG1_PROSE}").unwrap();
    cost(&mut md, &cost_sw);
    md.push_str(LEFT_OPEN);
    let out = root().join("docs/studies/ndf-synthesis.md");
    std::fs::write(&out, &md).unwrap();
    // the old copy of the tables (the page is generated now)
    let _ = std::fs::remove_file(root().join("docs/studies/ndf/tables.md"));
    eprintln!("wrote {}", out.display());
}
