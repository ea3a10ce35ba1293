//! Study of the per-pixel perturbation engines of Ernst et al. 1998 §3 (Texram, VISA+, VISA+
//! with quaternions, Harmony) against SGI's tangent-space engine and Gouraud bump mapping:
//! regenerates `docs/studies/perturbation-engines.md` and everything under
//! `docs/studies/perturbation/` with one command:
//!
//! ```sh
//! cargo run --release --example study_perturbation
//! ```
//!
//! The tables are those of the sweeps `docs/studies/sweeps/perturb-*.ron`, run into
//! `docs/studies/perturbation/NAME/` exactly as `bumpsim sweep
//! docs/studies/sweeps/perturb-NAME.ron --out docs/studies/perturbation/NAME` runs them, quoted
//! as they are written; this program adds the prose, reading the sweeps' rows for the
//! verdicts (the angle from which a seam is visible, interpolated between the rows), and the
//! pictures (VISA+ and its quaternion variant on the fold at 45 degrees).

use bumpsim_pipeline::sweep;
use std::fmt::Write;

mod common;

/// A seam is counted visible from this mean step (8-bit LSB) along one edge beyond the
/// interior's: two codes along a long straight line of a highlight, about 1 % of the
/// highlight's level (Weber's edge threshold).
const VISIBLE_LSB: f64 = 2.0;

use common::Swept;

/// Run `docs/studies/sweeps/perturb-{name}.ron` into `docs/studies/perturbation/{name}/`.
fn perturb(name: &str) -> Swept {
    Swept::run(&format!("perturb-{name}"), &format!("perturbation/{name}"))
}

/// (angle, column `c`) of the rows of `s` whose column `k` reads `v`, in row order.
fn curve(s: &Swept, k: &str, v: &str, c: &str) -> Vec<(f64, f64)> {
    s.rows()
        .filter(|r| s.text(r, k) == v)
        .map(|r| (s.n(r, "angle"), s.n(r, c)))
        .collect()
}

/// The first angle at which the seam reaches [`VISIBLE_LSB`], linearly interpolated between
/// rows, as the prose writes it.
fn visible_from(curve: &[(f64, f64)]) -> String {
    curve
        .windows(2)
        .find_map(|w| {
            let ((a0, s0), (a1, s1)) = (w[0], w[1]);
            (s0 < VISIBLE_LSB && s1 >= VISIBLE_LSB)
                .then(|| a0 + (VISIBLE_LSB - s0) / (s1 - s0) * (a1 - a0))
        })
        .map_or("not below 90°".into(), |t| format!("from {t:.0}°"))
}

/// Lowest and highest value of `curves` from angle `from` on.
fn range(curves: &[Vec<(f64, f64)>], from: f64) -> (f64, f64) {
    curves
        .iter()
        .flatten()
        .filter(|(a, _)| *a >= from)
        .fold((f64::INFINITY, 0.0), |(lo, hi), &(_, v)| {
            (lo.min(v), hi.max(v))
        })
}

fn main() {
    let pics = common::root().join("docs/studies/perturbation");
    std::fs::create_dir_all(&pics).expect("create docs/studies/perturbation");
    let [teapot, fold, finer, shiny, prisms] =
        ["teapot", "fold", "finer", "shininess", "prisms"].map(perturb);

    // pictures: VISA+ and its quaternion variant on the fold at 45 degrees, with the finer
    // widths of perturb-finer.ron (its `sets`)
    let mut sets = sweep::load(&common::root().join("docs/studies/sweeps/perturb-finer.ron"))
        .unwrap_or_else(|e| panic!("{e}"))
        .file
        .sets;
    sets.push("scene.mesh.angle_deg=45".into());
    let jobs = [("visa-teapot", sets.clone()), ("visa-quat-teapot", sets)];
    let runs = common::go_all(&jobs);
    for (r, tag) in runs.iter().zip(["visa", "visa-quat"]) {
        r.image
            .save(pics.join(format!("fold45-{tag}.png")))
            .unwrap();
        r.error
            .save(pics.join(format!("fold45-{tag}-error.png")))
            .unwrap();
    }
    // the two engines differ only in the frame: their signed difference (green channel), 32x,
    // red where VISA+ is brighter, blue where it is darker
    let mut diff = runs[0].image.clone();
    for (d, q) in diff.pixels_mut().zip(runs[1].image.pixels()) {
        let g = (i32::from(d.0[1]) - i32::from(q.0[1])) * 32;
        d.0 = [g.clamp(0, 255) as u8, 0, (-g).clamp(0, 255) as u8];
    }
    diff.save(pics.join("fold45-visa-minus-quat.png")).unwrap();

    // the verdicts, from the rows
    let tp = |cfg: &str, c: &str| teapot.at(&[("engine", &format!("*`{cfg}`"))], c);
    let per_pixel = [
        "texram-teapot",
        "texram-teapot-scaled",
        "visa-teapot",
        "visa-quat-teapot",
        "harmony-teapot",
    ];
    let spread = |c: &str| {
        let v: Vec<f64> = per_pixel.iter().map(|e| tp(e, c)).collect();
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    };
    let (alg_lo, alg_hi) = spread("algorithm_psnr_db");
    let (q_lo, q_hi) = spread("quantization_psnr_db");
    let q_sgi = tp("sgi-teapot", "quantization_psnr_db");
    let q_off = (q_sgi - q_lo).abs().max((q_hi - q_sgi).abs());
    let (tot_lo, _) = spread("total_psnr_db");
    let beats = tot_lo > tp("sgi-teapot", "total_psnr_db")
        && tot_lo > tp("gouraud-teapot", "total_psnr_db");
    let cpf = |cfg: &str| tp(cfg, "cycles") / tp(cfg, "fragments");
    let cpf_pp: Vec<f64> = per_pixel.iter().map(|e| cpf(e)).collect();
    let cpf_lo = cpf_pp.iter().copied().fold(f64::INFINITY, f64::min);
    let cpf_hi = cpf_pp.iter().copied().fold(0.0, f64::max);

    let engines = [
        "VISA+",
        "VISA+ quat.",
        "Harmony",
        "Texram",
        "Texram scaled",
        "SGI",
    ];
    let alg = |e: &str| curve(&fold, "engine", e, "algorithm_worst_seam_lsb");
    let total = |e: &str| curve(&fold, "engine", e, "total_worst_seam_lsb");
    let seam = |e: &str, a: f64| alg(e).iter().find(|p| p.0 == a).unwrap().1;
    let continuous: Vec<_> = engines[1..5].iter().map(|e| alg(e)).collect();
    let (_, cont_max) = range(&continuous, 0.0);
    let visible: Vec<String> = engines
        .iter()
        .map(|e| format!("{e} {}", visible_from(&alg(e))))
        .collect();
    let shiny_curve = |n: &str| curve(&shiny, "shininess", n, "algorithm_worst_seam_lsb");
    let (visa_lo, visa_hi) = range(&[total("VISA+")], 15.0);
    let (cont_lo, cont_hi) = range(&[total("VISA+ quat."), total("Harmony")], 15.0);
    let (_, finer_visa) = range(
        &[curve(&finer, "engine", "VISA+", "total_worst_seam_lsb")],
        0.0,
    );
    let (_, alg_visa) = range(&[alg("VISA+")], 0.0);

    let mut s = String::new();
    let _ = writeln!(
        s,
        "# The per-pixel perturbation engines (Ernst et al. 1998 §3)\n\n\
         Generated by `cargo run --release --example study_perturbation` \
         (`examples/study_perturbation.rs`; do not edit by hand). Every table is a table of a \
         sweep, `docs/studies/sweeps/perturb-*.ron`, written into \
         `docs/studies/perturbation/NAME/` (with the sweep's rows, `sweep.csv`) by the command \
         each section names (`bumpsim sweep`, docs/sweep.md); each sweep file's header says \
         what it varies, what it holds fixed and which claim of the paper it tests. The \
         engines, their units and their geometry attributes are described in \
         `docs/units/perturb.md`, `docs/units/texram_frame.md`, `docs/units/quat_frame.md` and \
         `docs/configs.md`; the edge measure in `docs/metrics.md`.\n"
    );
    let _ = writeln!(s, "## Findings\n");
    let _ = writeln!(
        s,
        "- **The 30-degree claim holds.** On the folded strip at shininess 128 with the light \
         mirrored towards the viewer, VISA+'s seam (its alignment matrix is held per triangle, \
         so the perturbation turns by the dihedral angle at the crease) grows from {:.1} LSB \
         at 5 degrees to about {:.1} LSB at 30 and is visible ({VISIBLE_LSB} LSB) {}; at \
         shininess 512 {}, at shininess 32 {}: a threshold \"around 30 degrees for extreme \
         lighting situations\". Quaternions at the vertices remove it (at most {:.2} LSB at \
         any angle up to 90 degrees, with Harmony and both forms of Texram, whose frames are \
         continuous too).",
        seam("VISA+", 5.0),
        seam("VISA+", 30.0),
        visible_from(&alg("VISA+")),
        visible_from(&shiny_curve("512")),
        visible_from(&shiny_curve("32")),
        cont_max
    );
    let _ = writeln!(
        s,
        "- **In hardware the seam is worse than the algorithm's.** At the bundled widths the \
         renormalisation of `N'` (a 256-entry rsqrt table, 8 fraction bits) and the 8-bit \
         power-table index quantise the highlight at shininess 128 into contours tens of LSB \
         apart, and the contours break where VISA+'s frame turns: its bit-accurate seam is \
         {visa_lo:.0} to {visa_hi:.0} LSB from 15 degrees on, against {cont_lo:.1} to \
         {cont_hi:.0} for the continuous frames of VISA+ with quaternions and Harmony. A finer \
         renormalisation and index bring it back near the algorithm's (at most {finer_visa:.1} \
         LSB, against the algorithm's {alg_visa:.1}): for highlights this sharp, the widths \
         and the frame must be chosen together."
    );
    let _ = writeln!(
        s,
        "- **Cost.** The frame units dominate: Texram's `TexramFrame` ({:.0} GE) and the \
         quaternion variant's `QuatFrame` ({:.0} GE) each cost more than a whole SGI engine \
         ({:.0} GE), priced at the exact widths their bit-accurate datapaths compute in (no \
         internal rounding; `docs/units/texram_frame.md`). Harmony needs no frame unit \
         ({:.0} GE in all) but sends nine interpolated lanes per vertex: the most bits per \
         triangle. VISA+ ({:.0} GE) sends its matrix once per triangle. Texram's scaled form \
         costs more than its normalised form in this model ({:.0} against {:.0} GE): it saves \
         the normalisation of `N_i` but needs `|N_i|` (a second table read and three \
         multipliers) to scale `e1`; the paper's saving needs the widened formats it mentions \
         and a cheaper `|N_i|`, which it does not give.",
        tp("texram-teapot", "gates.frame"),
        tp("visa-quat-teapot", "gates.qframe"),
        tp("sgi-teapot", "gates_total"),
        tp("harmony-teapot", "gates_total"),
        tp("visa-teapot", "gates_total"),
        tp("texram-teapot-scaled", "gates_total"),
        tp("texram-teapot", "gates_total"),
    );
    let _ = writeln!(
        s,
        "- **Error.** Every per-pixel engine follows the reference within {:.2} dB of the \
         others (algorithm PSNR {alg_lo:.2} to {alg_hi:.2} dB): the texture of offsets and \
         the per-vertex light and half vectors are common to all of them and dominate; the \
         frame construction differs only where the fold or a coarse mesh bends it. {}\n",
        alg_hi - alg_lo,
        if beats {
            "They beat the SGI engine (tangent-space light vectors interpolated) and Gouraud \
             bump mapping (half vector per triangle, Gouraud colour) on the teapot."
        } else {
            "Not all of them beat the SGI engine and Gouraud bump mapping on the teapot."
        }
    );
    let _ = writeln!(
        s,
        "## What each engine costs and gets wrong, on the teapot\n\n\
         The teapot of `configs/sgi-teapot.ron` (256x256, mexican-hat bumps, two lights) through \
         each engine's bundled config, {}. The per-pixel engines share one set of widths \
         (10-bit s2.8 vectors, two 8-bit offsets per texel, the SGI engine's dot products, \
         power table and light combiner), so their quantization errors land within {q_off:.1} \
         dB of the SGI engine's; `gouraud-teapot` renders its own teapot scene (the same mesh \
         and bumps, its own lights). Bits per triangle count the whole packet (the \
         textured-Gouraud baseline is 1,056); the bump extras are what the engine adds to it. \
         Cycles per fragment (cycles / fragments): {cpf_lo:.2} to {cpf_hi:.2} for the \
         per-pixel engines, {:.2} for SGI's, {:.2} for Phong, {:.2} for Gouraud bump mapping. \
         The seam of each engine on the fold of `configs/visa-fold.ron` is in the next \
         section (its 30° row).\n\n{}\n\n\
         The reference itself (Blinn's perturbation per pixel in f64, `configs/reference.ron`) \
         is the zero of every error column. Quantized normal maps (Tarini et al.) are not in the \
         table: they store object-space normals and need a unique parameterisation, and the \
         teapot's 32 patches share theirs (`docs/studies/quantized-normals.md` measures them on \
         the sphere, the vase and the bunny).\n",
        teapot.cite(),
        cpf("sgi-teapot"),
        cpf("phong-teapot"),
        cpf("gouraud-teapot"),
        teapot.table("engines"),
    );
    let _ = writeln!(
        s,
        "## The 30-degree claim (§3.2)\n\n\
         \"This leads to minor visible discontinuities at the edges of two adjacent triangles \
         if the angle between the spanned planes exceeds a certain threshold. This threshold is \
         around 30 degrees for extreme lighting situations (high material shininess and mirror \
         reflection of the light)\".\n\n\
         The scene (`configs/visa-fold.ron`, given to every engine as one `scene=...` set): a \
         strip folded into a ridge whose two panels meet at a dihedral angle (the `Fold` mesh, \
         one quad per panel), smooth vertex normals across the crease, a one-octave noise bump \
         map whose slopes cross the crease, shininess 128, the light mirrored towards a nearly \
         parallel viewer (so that no interpolated vector but the engine's own frame differs \
         from the reference). The figure is the worst single edge's mean error step beyond the \
         interior's (`algorithm_worst_seam_lsb`, exact mode against the reference: the \
         algorithm's own discontinuity, no rounding in it), {} (table `algorithm`). A seam is \
         counted visible from {VISIBLE_LSB} LSB (two codes along a straight line in a \
         highlight, about Weber's 1 % edge threshold at the highlight's level).\n\n{}\n\n\
         Visible (the angle where the seam reaches {VISIBLE_LSB} LSB, interpolated between \
         the rows): {}.\n",
        fold.cite(),
        fold.table("algorithm"),
        visible.join("; "),
    );
    let _ = writeln!(
        s,
        "The same seam in the bit-accurate image (`total_worst_seam_lsb`) at the bundled \
         widths (the same sweep, table `total`). At shininess 128 the bundled 256-entry rsqrt \
         table (up to 0.4 % off), 8 fraction bits of `N'` and an 8-bit index each move \
         `x^128` near its peak by tens of LSB, in contours that follow `N'.H`; where VISA+'s \
         frame turns at the crease the contours break, and the mean step along the crease is \
         many LSB:\n\n{}\n\n\
         With a finer renormalisation and lighting (`renorm`: a 16,384-entry rsqrt table of \
         18-bit values, `N'` in s2.14; 12-bit dot products; a 12-bit power-table index), {}:\
         \n\n{}\n",
        fold.table("total"),
        finer.cite(),
        finer.table("total"),
    );
    let _ = writeln!(
        s,
        "VISA+ against the shininess (\"for extreme lighting situations\"), {} (the \
         shininess-128 column is the VISA+ column of the fold's table `algorithm`):\n\n{}\n\n\
         Visible: at shininess 32 {}, at 128 {}, at 512 {}.\n",
        shiny.cite(),
        shiny.table("algorithm"),
        visible_from(&shiny_curve("32")),
        visible_from(&shiny_curve("128")),
        visible_from(&shiny_curve("512")),
    );
    let _ = writeln!(
        s,
        "Prisms (a cylinder of k slices and one stack: faces meet at 360/k degrees, so 4, 8, \
         12, 16 and 24 slices are 90, 45, 30, 22.5 and 15 degrees), the fold's lights and \
         bumps, exact mode, {}:\n\n{}\n",
        prisms.cite(),
        prisms.table("algorithm"),
    );
    let _ = writeln!(
        s,
        "| VISA+, 45° | VISA+ with quaternions, 45° |\n|---|---|\n\
         | ![](perturbation/fold45-visa.png) | ![](perturbation/fold45-visa-quat.png) |\n\
         | ![](perturbation/fold45-visa-error.png) | ![](perturbation/fold45-visa-quat-error.png) |\n\n\
         ![](perturbation/fold45-visa-minus-quat.png)\n\n\
         (VISA+ minus VISA+ with quaternions, green channel, 32x: red where VISA+ is brighter, \
         blue where darker. The two share everything but the frame; VISA+'s is turned over \
         each whole triangle, one way left of the crease and the other way right of it, so the \
         difference changes sign at the crease, in the middle)\n\n\
         (bit-accurate images with the finer renormalisation and lighting of \
         `perturb-finer.ron`, its `sets` at 45 degrees; below, the error against the \
         reference, black 0, full scale 32 LSB)"
    );
    let page = common::root().join("docs/studies/perturbation-engines.md");
    std::fs::write(&page, s).expect("write the page");
    println!("wrote docs/studies/perturbation-engines.md and docs/studies/perturbation/");
}
