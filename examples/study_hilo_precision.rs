//! Wang et al. §3, Fig. 2 (issue 14, item 5): 8-bit against 16-bit precision of a normal map
//! rendered by texture shaders, outside (the type the application hands over) and inside (the
//! texture's internal format, its filtering and the dot products). Regenerates
//! `docs/studies/hilo-precision.md` and everything under `docs/studies/hilo-precision/`:
//!
//! ```sh
//! cargo run --release --example study_hilo_precision
//! ```
//!
//! The tables are those of the sweeps `docs/studies/sweeps/wang-hilo-*.ron`, run into
//! `docs/studies/hilo-precision/NAME/` exactly as `bumpsim sweep
//! docs/studies/sweeps/wang-hilo-NAME.ron --out docs/studies/hilo-precision/NAME` runs them,
//! quoted as they are written (issue 11); this program adds the prose, reading the sweeps'
//! rows for the verdicts, and the pictures (the bundled `configs/wang-bunny-hilo*.ron` and
//! `wang-bunny-rgb8.ron` rendered), which no sweep holds.

mod common;

use bumpsim_pipeline::highlight;
use bumpsim_pipeline::rop::Framebuffer;
use bumpsim_pipeline::sweep::table::Row;
use std::fmt::Write;

/// The reference luma at or above which a pixel is in the highlight, as the sweeps set it
/// (`reference.highlight_luma=Some(0.8)`): the material's diffuse and ambient reach at most
/// 0.73 (`diffuse` (0.75, 0.65, 0.45) + 0.08), so only the specular term gets past 0.8. The
/// pictures' crop is placed on this region.
const HIGHLIGHT: f64 = 0.8;
const CROP: u32 = 48;
const ZOOM: u32 = 4;
/// Gain of the pictures of |bit-accurate - exact|.
const GAIN: f64 = 16.0;

use common::Swept;

/// Run `docs/studies/sweeps/wang-hilo-{name}.ron` into `docs/studies/hilo-precision/{name}/`.
fn wang(name: &str) -> Swept {
    Swept::run(
        &format!("wang-hilo-{name}"),
        &format!("hilo-precision/{name}"),
    )
}

/// A highlight figure of the quantization comparison (`highlight.quantization.FIELD`).
fn hl(s: &Swept, r: &Row, field: &str) -> f64 {
    s.n(r, &format!("report.highlight.quantization.{field}"))
}

/// The row of `engine` (its label starts with it: "(c)") at `dot` fraction bits.
fn row<'a>(s: &'a Swept, engine: &str, dot: u32) -> &'a Row {
    s.row(&[
        ("engine", &format!("{engine}*")),
        ("dot_frac", &dot.to_string()),
    ])
}

/// The top-left corner of the `CROP` window holding the most highlight pixels (first in
/// raster order on ties).
fn densest(hl: &[bool], w: u32, h: u32) -> (u32, u32) {
    let mut best = (0, 0, 0);
    for y in (0..=h - CROP).step_by(4) {
        for x in (0..=w - CROP).step_by(4) {
            let n = (y..y + CROP)
                .flat_map(|j| (x..x + CROP).map(move |i| (j * w + i) as usize))
                .filter(|&k| hl[k])
                .count();
            if n > best.0 {
                best = (n, x, y);
            }
        }
    }
    (best.1, best.2)
}

/// The crop at `(x0, y0)` magnified `ZOOM` times (nearest), of `f(x, y)`.
fn crop(x0: u32, y0: u32, f: impl Fn(u32, u32) -> [u8; 3]) -> image::RgbImage {
    image::RgbImage::from_fn(CROP * ZOOM, CROP * ZOOM, |x, y| {
        image::Rgb(f(x0 + x / ZOOM, y0 + y / ZOOM))
    })
}

fn save(img: &image::RgbImage, name: &str) {
    let dir = common::root().join("docs/studies/hilo-precision");
    std::fs::create_dir_all(&dir).unwrap();
    img.save(dir.join(name)).unwrap();
}

/// The highlight region of the scene: the f64 reference of `wang-bunny-hilo` (the same scene
/// and raster as the two other configs) where its luma is at least `HIGHLIGHT`, as the
/// report's `highlight` section defines it.
fn highlight_region() -> Vec<bool> {
    let l = common::load("wang-bunny-hilo", &[]);
    let p = bumpsim_pipeline::run::prepare(&l).unwrap_or_else(|e| panic!("{e}"));
    let r = p.reference(l.config.reference);
    highlight::region(&r.image, &r.mask, HIGHLIGHT)
}

/// `x` times `y`, as the prose writes a ratio.
fn times(x: f64, y: f64) -> String {
    format!("{:.1}x", x / y)
}

fn main() {
    // the sweeps (rayon inside) beside the pictures' renders
    let (fig2, dot, frames, hl) = std::thread::scope(|sc| {
        let sweeps = sc.spawn(|| (wang("fig2"), wang("dot-frac")));
        let frames: Vec<(Framebuffer, Framebuffer)> = common::par_map(
            &["wang-bunny-hilo", "wang-bunny-hilo-byte", "wang-bunny-rgb8"],
            |c| common::framebuffers(c, &[]),
        );
        let hl = highlight_region();
        let (fig2, dot) = sweeps.join().expect("the sweeps");
        (fig2, dot, frames, hl)
    });
    let (w, h) = (frames[0].1.image.width, frames[0].1.image.height);
    let hl_pixels = hl.iter().filter(|&&x| x).count();
    let c16 = row(&fig2, "(c)", 16);
    assert_eq!(
        fig2.n(c16, "report.highlight.pixels"),
        hl_pixels as f64,
        "the pictures' region is the sweep's"
    );
    let (x0, y0) = densest(&hl, w, h);

    // pictures: the whole of (c) with the crop outlined, then per figure variant the
    // bit-accurate crop and |bit-accurate - exact| x GAIN
    let mut whole = frames[0].0.rgb8.clone();
    for t in 0..CROP {
        for (x, y) in [
            (x0 + t, y0),
            (x0 + t, y0 + CROP - 1),
            (x0, y0 + t),
            (x0 + CROP - 1, y0 + t),
        ] {
            whole.put_pixel(x, y, image::Rgb([255, 0, 0]));
        }
    }
    save(&whole, "whole.png");
    let exact_c = &frames[0].1.rgb8;
    save(&crop(x0, y0, |x, y| exact_c.get_pixel(x, y).0), "exact.png");
    for (k, name) in ["c", "a", "b"].iter().enumerate() {
        let (b, e) = &frames[k];
        save(
            &crop(x0, y0, |x, y| b.rgb8.get_pixel(x, y).0),
            &format!("{name}.png"),
        );
        let diff = |x: u32, y: u32| {
            let (p, q) = (b.image.get(x, y), e.image.get(x, y));
            let d = (0..3).map(|c| (p[c] - q[c]).abs()).fold(0.0, f64::max);
            let v = (d * 255.0 * GAIN).round().min(255.0) as u8;
            [v, v, v]
        };
        save(&crop(x0, y0, diff), &format!("{name}-diff.png"));
    }

    let mut md = String::new();
    writeln!(
        md,
        "# Wang et al. Fig. 2: 8-bit against 16-bit normal-map precision\n"
    )
    .unwrap();
    writeln!(
        md,
        "Generated by `cargo run --release --example study_hilo_precision` (do not edit by hand). \
         Part of the normal-map study (`normal-map-baking.md`); the paper is \
         `wang-normal-map-generation-hilo.txt`, §3. Every table is a table of a sweep, \
         `docs/studies/sweeps/wang-hilo-*.ron`, written into `docs/studies/hilo-precision/NAME/` \
         (with the sweep's rows, `sweep.csv`) by the command each section names (`bumpsim \
         sweep`, docs/sweep.md); each sweep file's header says what it varies, what it holds \
         fixed and which claim it tests.\n"
    )
    .unwrap();
    writeln!(
        md,
        "**The claims.** \"An internal precision of 8 bits introduced visual artifacts in high \
         light areas, such as blocky appearance and mach banding. We had to resort to 16 bit \
         precision ... `GL_SIGNED_HILO_NV` ... the internal calculations such as dot products \
         are performed with 16 bits precision.\" And: \"the external precision of a normal map \
         is not very important. Normal maps with 8-bit or 16-bit precision lead to very similar \
         visual results if the internal type is set to 16-bit precision computation.\" Fig. 2: \
         (a) external `GL_SIGNED_BYTE`, internal `GL_SIGNED_HILO_NV`; (b) external and \
         internal `GL_RGB8`; (c) external `GL_SHORT`, internal `GL_SIGNED_HILO_NV`.\n"
    )
    .unwrap();
    writeln!(
        md,
        "**The set-up.** The bunny baked at 500 faces into a 512² face-space map (one square per \
         face, `configs/wang-bunny.ron`'s bake), rendered at {w}x{h} by three texture-shader \
         stages: TEXTURE_2D of the map, DOT_PRODUCT with L, DOT_PRODUCT_TEXTURE_2D with H into a \
         256² lighting table of (N·L, N·H) (bilinear). (c) is `configs/wang-bunny-hilo.ron`: the \
         map's (x, y) as SIGNED_HILO16 texels, z = sqrt(1 − x² − y²) by the hemisphere mapping, \
         the mapped vector at 16 fraction bits. (a) is `wang-bunny-hilo-byte.ron`: the same \
         texture, but its values handed over as GL_BYTE (OpenGL 1.x's (2c + 1) / 255) and \
         converted by the driver (`upload`). (b) is `wang-bunny-rgb8.ron`: (x, y, z) as 8-bit \
         signed RGB texels (GL_SIGNED_RGB8_NV rather than the paper's range-compressed GL_RGB8: \
         the same 8 bits a component, read without the expand), the vector at 8 fraction bits. \
         The sweep runs each engine with the dot products at 16 and at 8 fraction bits \
         (`dot_frac`): Fig. 2's own rows are (c) and (a) at 16 and (b) at 8; the other three \
         split the texel's precision from the dot products'.\n"
    )
    .unwrap();
    writeln!(
        md,
        "**The measure.** Precision is judged as each report judges quantization: the \
         bit-accurate framebuffer against the exact-mode framebuffer of the same config (the \
         same algorithm without rounding), so nothing but precision differs. Blocks are the \
         report's blockiness measure (steps per pixel between plateaus of the bit-accurate image \
         where the exact one is smooth: blocks of any size, `docs/metrics.md`), faceting the RMS \
         Laplacian difference after a 3x3 blur (the blockiness of flat-shaded cells), bands the \
         false-contour measure `banding` (the same steps in groups of 8 pixels or more). \"Highlight\" is the report's \
         `highlight` section (`reference.highlight_luma: Some({HIGHLIGHT})`, docs/metrics.md): \
         the {hl_pixels} pixels where the f64 reference has a Rec. 601 luma of at least \
         {HIGHLIGHT} (only the specular term gets there: diffuse and ambient reach 0.73), the \
         same pixels for every engine. Mean signed LSB is the mean of bit-accurate − exact over \
         the highlight (negative: darker); the algorithm columns are exact mode against the \
         reference (`error.algorithm`).\n"
    )
    .unwrap();
    writeln!(
        md,
        "## Fig. 2\n\n{}, errors (LSB: 8-bit steps):\n\n{}\n\nArtifacts:\n\n{}\n",
        fig2.cite(),
        fig2.table("error"),
        fig2.table("artifacts"),
    )
    .unwrap();
    findings(&mut md, &fig2);
    writeln!(
        md,
        "**Pictures.** The crop ({CROP}x{CROP} pixels at ({x0}, {y0}), the window holding the \
         most highlight pixels, outlined in the whole frame of (c); {ZOOM}x, nearest), and below \
         each crop |bit-accurate − exact| x {GAIN} (the largest channel). The exact column is \
         (c)'s exact image, the algorithm of (a) and (c); (b)'s own exact image, against which \
         its difference is taken, is brighter in the highlight (its filtered normals are not \
         renormalised).\n\n\
         ![whole frame of (c)](hilo-precision/whole.png)\n\n\
         | exact | (c) 16-bit | (a) 8-bit outside, 16 inside | (b) 8-bit |\n|---|---|---|---|\n\
         | ![exact](hilo-precision/exact.png) | ![c](hilo-precision/c.png) | ![a](hilo-precision/a.png) | ![b](hilo-precision/b.png) |\n\
         | | ![c diff](hilo-precision/c-diff.png) | ![a diff](hilo-precision/a-diff.png) | ![b diff](hilo-precision/b-diff.png) |"
    )
    .unwrap();
    dot_section(&mut md, &dot);
    let out = common::root().join("docs/studies/hilo-precision.md");
    std::fs::write(&out, md).unwrap();
    println!("wrote {}", out.display());
}

/// The findings of Fig. 2, each verdict computed from the sweep's rows.
fn findings(md: &mut String, s: &Swept) {
    let (c, a, b) = (row(s, "(c)", 16), row(s, "(a)", 16), row(s, "(b)", 8));
    let (b16, c8, a8) = (row(s, "(b)", 16), row(s, "(c)", 8), row(s, "(a)", 8));
    let psnr = |r: &Row| s.n(r, "quantization_psnr_db");
    let block = |r: &Row| hl(s, r, "blockiness");
    let facet = |r: &Row| hl(s, r, "faceting_lsb");
    // 1. 8 bits inside: blocky in the highlight (twice the steps and the facets of (c) at least)
    let blocky = block(b) > 2.0 * block(c) && facet(b) > 2.0 * facet(c);
    let contour = s
        .rows()
        .flat_map(|r| [s.n(r, "quantization_banding"), hl(s, r, "banding")])
        .fold(0.0, f64::max);
    let bands = if contour < 0.1 * block(b) {
        format!(
            "The blocks are small: the false-contour measure (steps in groups of 8 pixels or \
             more) reads at most {contour:.4} per pixel in any row, so the paper's \"mach \
             banding\" shows here as blocks a few pixels wide, not as long bands."
        )
    } else {
        format!(
            "The false-contour measure (steps in groups of 8 pixels or more) reads up to \
             {contour:.4} per pixel: some of the steps line up into bands, the paper's \"mach \
             banding\"."
        )
    };
    // 2. external precision: (a) nearer (c) than (b) overall and in the highlight
    let (ca, ab) = (psnr(c) - psnr(a), psnr(a) - psnr(b));
    let (ca_hl, ab_hl) = (
        hl(s, c, "psnr_db") - hl(s, a, "psnr_db"),
        hl(s, a, "psnr_db") - hl(s, b, "psnr_db"),
    );
    let external = match (ca < ab && ca_hl < ab_hl, ca > 1.0 || ca_hl > 1.0) {
        (true, true) => "holds, with a measurable cost",
        (true, false) => "holds",
        (false, _) => "does not hold",
    };
    // 3. internal precision: the texel and the dot product
    let rgb_dot = psnr(b16) - psnr(b);
    let nothing = if rgb_dot.abs() < 0.5 {
        "change nothing"
    } else {
        "change the error"
    };
    let bias = hl(s, c8, "mean_signed_lsb");
    let biased = if bias.abs() > 0.5 * hl(s, c8, "mean_abs_lsb") {
        format!(
            "mostly as a bias: in the highlight the mean error is {:.2} LSB (against {:.2} for \
             (c)) and the mean signed error {bias:.2} LSB, {}",
            hl(s, c8, "mean_abs_lsb"),
            hl(s, c, "mean_abs_lsb"),
            if bias < 0.0 {
                "darker, as the hemisphere's z is the floor root of words of 8 fraction bits"
            } else {
                "brighter"
            }
        )
    } else {
        format!(
            "as noise more than bias: in the highlight the mean error is {:.2} LSB, the mean \
             signed error {bias:.2} LSB",
            hl(s, c8, "mean_abs_lsb")
        )
    };
    let below = if block(c8) < block(b) {
        "stays below"
    } else {
        "reaches"
    };
    // 4. the algorithm: (b) not renormalised
    let alg = |r: &Row| s.n(r, "algorithm_psnr_db");
    let alg_hl = |r: &Row| s.n(r, "report.highlight.algorithm.psnr_db");
    let larger = if alg(b) < alg(c).min(alg(a)) && alg_hl(b) < alg_hl(c).min(alg_hl(a)) {
        "larger than"
    } else {
        "not larger than"
    };
    writeln!(
        md,
        "**Findings.**\n\n\
         - *8 bits inside band and block the highlight* ({}). In the highlight, (b) has {} the \
         steps between plateaus of (c) and {} its faceting, with errors up to {:.1} LSB against \
         {:.1}. {bands}\n\
         - *The external precision matters little with 16 bits inside* ({external}). (a) is \
         {ca:.1} dB below (c) overall and {ca_hl:.1} dB below it in the highlight, but {ab:.1} dB \
         above (b) ({ab_hl:.1} dB in the highlight); its highlight blockiness is {} that of (c) \
         and {:.2}x that of (b). The 16-bit texture filters the 8-bit steps into 16-bit \
         gradients, and z comes from the hemisphere mapping at 16 bits. With 8-bit dot products \
         {}: (a) at 8 bits is {:.1} dB from (c) at 8 bits.\n\
         - *What \"internal precision\" is: both the texel and the dot product.* With an 8-bit \
         texel, 16-bit dot products {nothing} ({rgb_dot:+.1} dB): the texel's 8 bits (its 8-bit \
         filtered result and its quantized z) bound the error. With 16-bit texels, 8-bit dot \
         products lose {:.1} dB, {biased}; their highlight blockiness ({:.4}) {below} (b)'s \
         ({:.4}). SIGNED_HILO16 widens both, as the paper's \"internal type\" does.\n\
         - *Not precision, but visible*: the algorithm error of (b) against the reference is \
         {larger} that of (a) and (c) (`error.algorithm`: {:.1} dB against {:.1}, and {:.1} dB \
         against {:.1} in the highlight), because a filtered RGB normal is not renormalised, \
         while the hemisphere mapping of a HILO texel always gives a unit vector.\n",
        if blocky { "holds" } else { "does not hold" },
        times(block(b), block(c)),
        times(facet(b), facet(c)),
        hl(s, b, "max_abs_lsb"),
        hl(s, c, "max_abs_lsb"),
        times(block(a), block(c)),
        block(a) / block(b),
        if (psnr(c8) - psnr(a8)).abs() < 0.5 {
            "the outside no longer shows"
        } else {
            "the outside still shows"
        },
        (psnr(c8) - psnr(a8)).abs(),
        psnr(c) - psnr(c8),
        block(c8),
        block(b),
        alg(b),
        alg(c),
        alg_hl(b),
        alg_hl(c),
    )
    .unwrap();
}

/// The sweep of the dot products' width, `wang-hilo-dot-frac.ron`.
fn dot_section(md: &mut String, s: &Swept) {
    writeln!(
        md,
        "\n\n## The dot products' width, swept\n\n{}: (c) with the mapped vector at 8 to 16 \
         fraction bits (`dot_frac`), the texels SIGNED_HILO16 throughout; quantization against \
         exact mode of the same config, over the whole frame and over the highlight. Errors:\n\n\
         {}\n\nArtifacts:\n\n{}\n",
        s.cite(),
        s.table("error"),
        s.table("artifacts"),
    )
    .unwrap();
    let rows: Vec<&Row> = s.rows().collect();
    let last = *rows.last().expect("rows");
    let dot = |r: &Row| s.n(r, "dot_frac");
    // the first width from which on every wider one satisfies `ok`
    let from = |ok: &dyn Fn(&Row) -> bool| {
        let k = rows.iter().rposition(|r| !ok(r)).map_or(0, |k| k + 1);
        rows.get(k).map_or(f64::NAN, |r| dot(r))
    };
    let whole = from(&|r| s.n(r, "quantization_psnr_db") > s.n(last, "quantization_psnr_db") - 0.5);
    let hl_psnr = from(&|r| hl(s, r, "psnr_db") > hl(s, last, "psnr_db") - 0.5);
    let floor = hl(s, last, "blockiness");
    let hl_block = from(&|r| hl(s, r, "blockiness") <= 2.0 * floor);
    let first = rows[0];
    let more = |x: f64| if x > whole { "more" } else { "no more" };
    let bias = hl(s, first, "mean_signed_lsb");
    let biased = if bias.abs() > 0.5 * hl(s, first, "mean_abs_lsb") {
        "mostly the bias of the hemisphere's z"
    } else {
        "noise more than bias"
    };
    writeln!(
        md,
        "From {whole} fraction bits on, the whole frame's error is within 0.5 dB of 16 bits: \
         the rest is the texels' own 16 bits and the 8-bit lighting table. The highlight needs \
         {}: its error comes within 0.5 dB of 16 bits from {hl_psnr} bits on, and its \
         blockiness within twice its 16-bit floor ({floor:.4}) from {hl_block} bits on \
         ({:.4} at {} bits, {} the whole frame's {:.4} there). So the answer to \"how many bits \
         before the highlight stops banding\" is {hl_block} here, {} than the whole-frame PSNR \
         suggests; at the narrow widths the highlight's error is {biased} (mean signed {bias:.2} \
         LSB of a mean {:.2} at {} bits).",
        more(hl_psnr.max(hl_block)),
        hl(s, first, "blockiness"),
        dot(first),
        if hl(s, first, "blockiness") > s.n(first, "quantization_blockiness") {
            "above"
        } else {
            "not above"
        },
        s.n(first, "quantization_blockiness"),
        more(hl_block),
        hl(s, first, "mean_abs_lsb"),
        dot(first),
    )
    .unwrap();
}
