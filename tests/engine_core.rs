//! The engine core's means for texture-shader programs, end to end on the bundled configs:
//! wire expressions feeding a dependent lookup, and fragment kill with the depth test after
//! shading.

mod common;

use bumpsim_pipeline::config::{self, Loaded};
use bumpsim_pipeline::run::{self, RunResult, TraceRequest};
use common::*;

fn load(stem: &str, sets: &[&str]) -> Loaded {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    config::load(&config(stem), &sets).expect("the bundled config loads")
}

fn render(l: &Loaded) -> RunResult {
    run::run(l, None).expect("the config renders")
}

#[test]
fn a_concatenated_wire_carries_two_dot_products_into_the_dependent_lookup() {
    let l = load("dependent-dot-lookup", &[]);
    let req = TraceRequest {
        cycles: (0, 3000),
        units: None,
    };
    let r = run::run(&l, Some(&req)).unwrap();
    let t = r.trace.unwrap();
    let idx = |n: &str| t.units.iter().position(|u| u.name == n).unwrap();
    let (dot, light) = (idx("dot"), idx("light"));
    assert_eq!(t.units[light].inputs[0].lanes, 2);
    let mut dots = std::collections::BTreeMap::new();
    let mut checked = 0;
    for (u, p) in &t.records {
        if *u == dot {
            if let Some((id, w)) = &p.emitted {
                dots.insert(*id, (w[0].lanes[0], w[1].lanes[0]));
            }
        }
        if *u == light {
            if let Some((id, w)) = &p.accepted {
                let (d0, d1) = dots[id];
                assert_eq!((w[0].lanes[0], w[0].lanes[1]), (d0, d1), "fragment {id}");
                checked += 1;
            }
        }
    }
    assert!(checked > 100, "only {checked} fragments traced");
    // the table lookup is as good as the SGI engine's power table and combiner (one light):
    // quantization error below one LSB on average, the algorithm's above 29 dB
    let e = &r.report.error;
    assert!(e.quantization.mean_abs_lsb < 1.0, "{:?}", e.quantization);
    assert!(e.algorithm.psnr_db > 29.0, "{:?}", e.algorithm);
}

#[test]
fn a_cull_unit_that_never_kills_leaves_the_image_unchanged() {
    // uv is unsigned, so uv.x >= 0 always passes; back faces are drawn, so the depth test
    // in the ROP (late, with a cull unit) must give what the rasterizer's early test gives
    let l = load(
        "cull-fragment",
        &["engine.units.cull.inputs.v=\"uv.x\"", "raster.cull=None"],
    );
    let with = render(&l);
    let mut without = l.clone();
    without.config.engine.units.remove(0);
    let without = render(&without);
    assert_eq!(with.report.cycles.killed, 0);
    assert_eq!(with.image, without.image);
    // the late test shades every covered sample, the early one only those in front so far
    assert!(with.report.cycles.fragments > without.report.cycles.fragments);
}

#[test]
fn killed_fragments_are_not_written_and_reveal_what_is_behind() {
    let back = render(&load("cull-fragment", &[]));
    let c = &back.report.cycles;
    assert!(c.killed > 5_000 && c.killed < c.fragments, "{c:?}");
    // the ROP reads depth for every live fragment and writes colour and depth for those that
    // pass; with back faces culled the sphere covers each pixel about once
    let live = c.fragments - c.killed;
    let pass = &back.report.passes.passes[0];
    assert_eq!(pass.fb_read_bits, live * 24);
    let written = pass.fb_write_bits / (24 + 24);
    let covered = back.report.image.covered_pixels;
    assert!(
        covered <= written && written <= live,
        "{covered} {written} {live}"
    );
    assert!(live - covered < 10, "{covered} of {live}");
    // with back faces drawn, the inside of the far hemisphere shows where the front is killed
    let none = render(&load("cull-fragment", &["raster.cull=None"]));
    assert!(
        none.report.image.covered_pixels > back.report.image.covered_pixels + 1_000,
        "{} vs {}",
        none.report.image.covered_pixels,
        back.report.image.covered_pixels
    );
}

#[test]
fn a_prepared_frame_simulates_the_same_twice() {
    // the stages' timing state is reset per frame (the benchmark simulates one frame often)
    let l = load("gouraud-quad-bandwidth", &[]);
    let mut p = run::prepare(&l).unwrap();
    let (a, b) = (p.simulate(None), p.simulate(None));
    assert_eq!(a.cycles, b.cycles);
    assert_eq!(a.outputs, b.outputs);
}

#[test]
fn a_fixed_point_interpolator_converges_on_the_exact_one_and_is_costed() {
    // quantization error of the whole engine (bit-accurate vs exact mode) against the weight
    // width of a fixed-point interpolator; the exact interpolator is the floor
    let psnr = |sets: &[&str]| {
        let r = render(&load("sgi-sphere-bricks", sets)).report;
        (r.error.quantization.psnr_db, r.gates)
    };
    let (exact, g_exact) = psnr(&[]);
    let (coarse, g_coarse) = psnr(&["engine.interpolator=Fixed(weight_bits: 6)"]);
    let (fine, g_fine) = psnr(&["engine.interpolator=Fixed(weight_bits: 20)"]);
    assert!(coarse < fine - 3.0, "6 bits {coarse} dB, 20 bits {fine} dB");
    assert!(
        (fine - exact).abs() < 0.5,
        "20 bits {fine} dB, exact {exact} dB"
    );
    let interp = |g: &bumpsim_pipeline::report::Gates| {
        g.per_unit.get("attribute interpolator").map(|u| u.total)
    };
    assert_eq!(interp(&g_exact), None);
    let (c, f) = (interp(&g_coarse).unwrap(), interp(&g_fine).unwrap());
    assert!(c > 1_000.0 && f > c, "{c} {f}");
}

#[test]
fn register_combiners_shade_the_bump_map_in_9_bit_registers() {
    let r = render(&load("nv20-combiner-bump", &[]));
    let e = &r.report.error;
    // the combiners' 9-bit registers and 8-bit constants against their own f64 program: less
    // than a third of an LSB on average; the program (power by squaring, no specular cut)
    // against the float Blinn reference: above 33 dB
    assert!(e.quantization.mean_abs_lsb < 0.35, "{:?}", e.quantization);
    assert!(e.quantization.psnr_db > 47.0, "{:?}", e.quantization);
    assert!(e.algorithm.psnr_db > 33.0, "{:?}", e.algorithm);
    let g = &r.report.gates.per_unit["rc"];
    assert_eq!(g.kind, "register_combiners");
    assert!(g.total > 150_000.0, "{}", g.total);
    // a killed-free engine writes every fragment the early depth test lets through
    assert_eq!(r.report.cycles.killed, 0);
}

#[test]
fn combiner_ports_and_programs_are_checked() {
    let cfg = config("nv20-combiner-bump");
    expect_rejected(
        &cfg,
        "engine.units.rc.unit.ports=[\"primary\", \"secondary\", \"tex9\"]",
        &["engine.units[1]", "tex9"],
    );
    expect_rejected(
        &cfg,
        "engine.units.rc.unit.stages=4",
        &["engine.units[1]", "stages"],
    );
    expect_rejected(
        &cfg,
        "engine.units.rc.unit.width=8",
        &["width", "expected 9 to 24"],
    );
}

/// The 8-bit RGB pixels of two images that differ, and the largest channel difference.
fn differing(a: &image::RgbImage, b: &image::RgbImage) -> (usize, u8) {
    let mut n = (0, 0);
    for (p, q) in a.pixels().zip(b.pixels()) {
        let d = (0..3).map(|c| p.0[c].abs_diff(q.0[c])).max().unwrap();
        if d > 0 {
            n = (n.0 + 1, n.1.max(d));
        }
    }
    n
}

#[test]
fn tarinis_blend_passes_go_through_the_rop_and_charge_what_it_read_and_wrote() {
    for (stem, names) in [
        (
            "quantized-bunny-wood-eq1",
            &[
                "tex.t",
                "eq. (1): dst = dst alpha",
                "eq. (1): dst = src (1 - dst) + dst",
            ][..],
        ),
        (
            "quantized-bunny-wood-eq2",
            &["tex.t", "eq. (2): dst = src (1 - dst) + dst alpha"][..],
        ),
    ] {
        let r = render(&load(stem, &[]));
        let p = &r.report.passes;
        let got: Vec<&str> = p.passes.iter().map(|q| q.name.as_str()).collect();
        assert_eq!(got, names, "{stem}");
        let c = &r.report.cycles;
        let stream = c.total - c.frame;
        assert_eq!(p.total_cycles, c.frame + names.len() as u64 * stream);
        // pass 1 (depth Less, written): the rasterizer's early test lets every fragment through
        // the ROP's, so it reads depth for each and writes colour and depth for each
        let (first, covered) = (&p.passes[0], r.report.image.covered_pixels);
        assert_eq!(first.fb_read_bits, c.fragments * 24, "{stem}");
        assert_eq!(first.fb_write_bits, c.fragments * 48, "{stem}");
        // a blend pass (depth Equal, no depth write) reads depth for every fragment and blends
        // only the one left on top at each pixel: colour read and written once per pixel
        for q in &p.passes[1..] {
            assert_eq!(q.fb_read_bits, c.fragments * 24 + covered * 24, "{stem}");
            assert_eq!(q.fb_write_bits, covered * 24, "{stem}");
        }
        // overdraw: 3,067 of the 18,724 fragments are hidden at 192 x 192
        assert_eq!((c.fragments, covered), (18_724, 15_657), "{stem}");
    }
}

#[test]
fn the_rop_passes_and_the_fused_fbblend_unit_differ_only_in_the_blends_rounding() {
    // FbBlend computes the same equation inside the pipe in one pass; its framebuffer words
    // decode unit codes by bit replication (c * 257 / 2^16 for 8 bits), the ROP divides by
    // 255 exactly (GL): 2^-16 relative apart, so a blend within a hundredth of a code of a
    // half rounds apart
    for (stem, eq) in [
        ("quantized-bunny-wood-eq1", "Exact"),
        ("quantized-bunny-wood-eq2", "Approx"),
    ] {
        let l = load(stem, &[]);
        let passes = render(&l);
        let mut fused = l.clone();
        let unit = format!(
            "(name: \"blend\", unit: FbBlend(equation: {eq}, fb: (format: (signed: false, width: 8, frac: 0), codec: UnitUnsigned)), inputs: {{\"base\": \"tex.t\", \"entry\": \"qnm.c\"}})"
        );
        fused
            .config
            .engine
            .units
            .push(ron::from_str(&unit).unwrap());
        fused.config.engine.output = "blend.c".into();
        fused.config.engine.passes.clear();
        let fused = render(&fused);
        assert_eq!(fused.report.passes.passes.len(), 1, "{stem}: one pass");
        // exact mode: the same f64 equation, the same image
        assert_eq!(differing(&passes.exact, &fused.exact), (0, 0), "{stem}");
        assert_eq!(
            passes.report.error.algorithm, fused.report.error.algorithm,
            "{stem}"
        );
        // bit-accurate: 55 (eq. 1) or 54 (eq. 2) of 15,657 pixels one code apart
        let (n, d) = differing(&passes.image, &fused.image);
        assert_eq!((n, d), (if eq == "Exact" { 55 } else { 54 }, 1), "{stem}");
    }
}

#[test]
fn bad_passes_are_errors_naming_the_pass() {
    let err = |sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let l = config::load(&config("quantized-bunny-wood-eq2"), &sets).unwrap();
        match run::run(&l, None) {
            Ok(_) => panic!("{sets:?} rendered"),
            Err(e) => e.to_string(),
        }
    };
    // RGBA into a pass whose ROP reads no alpha
    let e = err(&["engine.passes.0.rop.blend=Some((One, One))"]);
    assert!(
        e.contains("engine.passes[0].output") && e.contains("4 lanes"),
        "{e}"
    );
    let e = err(&["engine.passes.0.output=\"nowhere.c\""]);
    assert!(e.contains("engine.passes[0].output"), "{e}");
    let e = err(&["engine.passes.0.rop.color_bits=10"]);
    assert!(
        e.contains("engine.passes[0].rop.color_bits") && e.contains("one framebuffer"),
        "{e}"
    );
    let e = err(&[
        "engine.passes.0.rop.alpha_test=Some((Greater, 0))",
        "engine.passes.0.output=\"tex.t\"",
    ]);
    assert!(e.contains("engine.passes[0].rop"), "{e}");
    let pass = "(name: \"p\", output: \"qnm.c\", rop: (depth: Equal, depth_write: false, blend: Some((Zero, SrcAlpha))))";
    let many = format!("engine.passes=[{}]", [pass; 8].join(", "));
    let e = err(&[&many]);
    assert!(
        e.contains("engine.passes") && e.contains("at most 7"),
        "{e}"
    );
}

/// The report's texture cache of `stem` with the cache `cache` (RON) and `sets`.
fn cache_of(stem: &str, cache: &str, sets: &[&str]) -> serde_json::Value {
    let set = format!("engine.texture_cache=Some({cache})");
    let mut all = vec![set.as_str()];
    all.extend(sets);
    let r = render(&load(stem, &all));
    serde_json::to_value(&r.report.bandwidth.texture_cache).unwrap()
}

#[test]
fn a_texture_cache_sees_every_texel_read_and_fills_a_block_per_miss() {
    let c = cache_of("sgi-teapot", "(lines: 64, ways: 4, block: 4)", &[]);
    let k = &c["caches"][0];
    assert_eq!(k["readers"], serde_json::json!(["fetch"]));
    // every bilinear tap of every fragment: 24,921 fragments x 4, the texture memory's count
    assert_eq!(k["reads"], 99_684);
    assert_eq!(k["uncached_bits"], 99_684 * 24);
    assert_eq!(k["misses"], 36_193);
    // a miss fills a 4 x 4 block of 24-bit texels
    assert_eq!(k["fill_bits"], 36_193 * 16 * 24);
    assert_eq!(c["data_bits"], serde_json::json!([64 * 16 * 24]));
    // the teapot minifies its 256 x 256 map (twice repeated) without mipmaps: blocks are
    // evicted before their texels are used, and the cache fills 5.8 times the bits the reads
    // take (the case for mipmaps, Hakura and Gupta 1997)
    let ratio = c["traffic_ratio"].as_f64().unwrap();
    assert!((ratio - 5.809).abs() < 1e-3, "{ratio}");
    // fully associative LRU caches of 1, 4, 16 and 64 lines: each holds what the smaller one
    // holds (LRU's inclusion), so misses never grow with the size
    let misses: Vec<u64> = [1, 4, 16, 64]
        .map(|n| {
            let c = cache_of(
                "sgi-teapot",
                &format!("(lines: {n}, ways: {n}, block: 4)"),
                &[],
            );
            c["caches"][0]["misses"].as_u64().unwrap()
        })
        .to_vec();
    assert_eq!(misses, [48_235, 36_708, 36_347, 36_170]);
    // at 512 x 512 the map is nearer one texel a pixel: more reuse. 99,614 fragments are
    // recorded in three windows of parallel chunks; the caches take the reads in fragment
    // order, so on one thread or two the figures are those of one thread recording every read
    // in order (the counts of the recorder before the windows, 2026-12-07)
    let big_on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build();
        pool.unwrap().install(|| {
            cache_of(
                "sgi-teapot",
                "(lines: 64, ways: 4, block: 4, miss_cycles: 20)",
                &["scene.width=512", "scene.height=512"],
            )
        })
    };
    let big = big_on(1);
    assert_eq!(big, big_on(2));
    assert_eq!(big["caches"][0]["reads"], 398_560);
    assert_eq!(big["caches"][0]["misses"], 92_456);
    let hit = big["caches"][0]["hit_rate"].as_f64().unwrap();
    assert!(
        hit > 0.75 && hit > k["hit_rate"].as_f64().unwrap() + 0.1,
        "{hit}"
    );
}

#[test]
fn a_row_of_blocks_that_the_tiled_index_crowds_into_few_sets_spreads_with_xor() {
    // emboss at 512 x 512: its 256 x 256 map twice magnified, read in scanlines; a block row
    // is 64 blocks, which the tiled index puts in 8 of the 32 two-way sets
    let misses = |index: &str| {
        let c = cache_of(
            "emboss",
            &format!("(lines: 64, ways: 2, block: 4, index: {index})"),
            &["scene.width=512", "scene.height=512"],
        );
        c["caches"][0]["misses"].as_u64().unwrap()
    };
    assert_eq!((misses("Tiled"), misses("Xor")), (47_662, 23_506));
}

#[test]
fn a_shared_texture_cache_takes_every_readers_reads_in_fragment_order() {
    let each = cache_of(
        "quantized-bunny-wood-eq2",
        "(lines: 64, ways: 4, block: 4)",
        &[],
    );
    let readers: Vec<(String, u64)> = each["caches"]
        .as_array()
        .unwrap()
        .iter()
        .map(|k| {
            (
                k["readers"][0].as_str().unwrap().to_string(),
                k["reads"].as_u64().unwrap(),
            )
        })
        .collect();
    // the palette index once a fragment (nearest), the wood texture's four bilinear taps
    assert_eq!(
        readers,
        [("qnm".to_string(), 18_724), ("tex".to_string(), 4 * 18_724)]
    );
    let shared = cache_of(
        "quantized-bunny-wood-eq2",
        "(lines: 64, ways: 4, block: 4, shared: true)",
        &[],
    );
    let k = &shared["caches"][0];
    assert_eq!(k["readers"], serde_json::json!(["qnm", "tex"]));
    assert_eq!(k["reads"], 5 * 18_724);
    assert_eq!(k["misses"], 13_029);
    assert_eq!(shared["uncached_bits"], each["uncached_bits"]);
}

/// The caches' gates beside the total: storage by the memory model (SRAM, 1.5 GE a bit), the
/// logic apart; one per reader or one shared.
#[test]
fn texture_caches_are_priced_beside_the_total() {
    let cache = |c: &str, sets: &[&str]| {
        let mut all = vec![format!("engine.texture_cache=Some({c})")];
        all.extend(sets.iter().map(|s| s.to_string()));
        let all: Vec<&str> = all.iter().map(String::as_str).collect();
        run::gates(&load("sgi-teapot", &all)).expect("gates")
    };
    let g = cache("(lines: 64, ways: 4, block: 4)", &[]);
    let c = g.texture_cache.as_ref().expect("a cache budget");
    // the 256x256 24-bit map: 4,096 blocks, 12 address bits, 8 tag bits above 16 sets; data
    // 64 x 16 texels of 24 bits, tags 64 x 9, LRU 16 sets x 4 ways x 2 bits
    let bits = 1024.0 * 24.0 + 64.0 * 9.0 + 16.0 * 8.0;
    assert!((c.memory - 1.5 * bits).abs() < 0.01, "{}", c.memory);
    assert!(c.items.iter().all(|i| i.what.starts_with("fetch: ")));
    assert!(
        c.total > c.memory && c.total < c.memory + 1000.0,
        "{}",
        c.total
    );
    // not in the engine's total; none without a cache
    let plain = run::gates(&load("sgi-teapot", &[])).unwrap();
    assert_eq!(g.total, plain.total);
    assert!(plain.texture_cache.is_none());
    // latch RAM storage, a prefetching unit's FIFO
    let latch = cache("(lines: 64, ways: 4, block: 4)", &["cost.tables=LatchRam"]);
    let l = latch.texture_cache.unwrap();
    assert!(
        (l.memory / c.memory - 5.66 / 1.5).abs() < 1e-3,
        "{}",
        l.memory
    );
    let pf = cache(
        "(lines: 64, ways: 4, block: 4, prefetch: 64, miss_cycles: 16)",
        &[],
    );
    let fifo = pf.texture_cache.unwrap().memory - c.memory;
    assert!((fifo - 1.5 * 64.0 * (12.0 + 4.0)).abs() < 0.01, "{fifo}");
}

/// A texture bus shared by the caches (`bus: Shared`, the default): the dependent lookup's two
/// readers (the normal map's stage and the dependent texture's, a cache each) queue their fills
/// at one memory, against a memory channel per cache (`PerCache`).
#[test]
fn caches_on_one_texture_bus_wait_for_each_others_fills() {
    let run_with = |c: &str| {
        let set = format!("engine.texture_cache=Some((lines: 64, ways: 4, block: 4, {c}))");
        render(&load("dependent-dot-lookup", &[&set]))
    };
    let total = |r: &RunResult| r.report.cycles.total;
    let pre = "miss_cycles: 64, prefetch: 64, fill_cycles: 2";
    let (own, one) = (run_with(&format!("{pre}, bus: PerCache")), run_with(pre));
    // the function does not change, nor do the caches' misses: 27,436 and 17,588
    assert_eq!(own.image, one.image);
    let cache = |r: &RunResult| {
        let c = r.report.bandwidth.texture_cache.as_ref();
        c.expect("a cache report").clone()
    };
    let misses = |r: &RunResult| cache(r).caches.iter().map(|k| k.misses).collect::<Vec<_>>();
    assert_eq!(misses(&own), [27_436, 17_588]);
    assert_eq!(misses(&one), misses(&own));
    // a channel each: the busier memory holds 54,872 cycles of fills; one bus: 90,048 cycles
    // of fills, more than the frame took with a channel each, and the frame is bound by them
    assert_eq!([total(&own), total(&one)], [82_350, 98_696]);
    assert!(total(&one) >= 90_048 && total(&own) < 90_048);
    let busy = |r: &RunResult| cache(r).memory_busy_cycles;
    assert_eq!(busy(&own), [54_872, 35_176]);
    assert_eq!(busy(&one), [90_048]);
    // blocking units wait for the other's fills too
    let blocking = |bus: &str| total(&run_with(&format!("miss_cycles: 16, bus: {bus}")));
    assert_eq!(
        [blocking("PerCache"), blocking("Shared")],
        [606_853, 624_537]
    );
}

#[test]
fn bad_texture_caches_are_errors_naming_the_field() {
    for (cache, field) in [
        ("(lines: 48, ways: 4, block: 4)", "lines"),
        ("(lines: 131072, ways: 4, block: 4)", "lines"),
        ("(lines: 64, ways: 128, block: 4)", "ways"),
        ("(lines: 8, ways: 16, block: 4)", "ways"),
        ("(lines: 64, ways: 4, block: 3)", "block"),
        ("(lines: 64, ways: 4, block: 32)", "block"),
    ] {
        let set = vec![format!("engine.texture_cache=Some({cache})")];
        let l = config::load(&config("sgi-teapot"), &set).unwrap();
        let e = run::run(&l, None).err().expect("an error").to_string();
        assert!(
            e.contains(&format!("engine.texture_cache.{field}")),
            "{cache}: {e}"
        );
    }
    let set = vec!["engine.texture_cache=Some((lines: 64, ways: 4, block: 4, size: 1))".into()];
    let e = config::load(&config("sgi-teapot"), &set)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("size"), "{e}");
}

#[test]
fn a_blocking_texture_caches_misses_stall_the_reader_and_leave_the_image() {
    let run_with = |m: u32| {
        let set =
            format!("engine.texture_cache=Some((lines: 64, ways: 4, block: 4, miss_cycles: {m}))");
        render(&load("sgi-teapot", &[&set]))
    };
    let plain = render(&load("sgi-teapot", &[]));
    let (r0, r4, r16) = (run_with(0), run_with(4), run_with(16));
    // traffic only: the timing of the engine without a cache
    assert_eq!(r0.report.cycles, plain.report.cycles);
    // the function does not change
    assert_eq!(r16.image, plain.image);
    let total = |r: &RunResult| r.report.cycles.total;
    assert_eq!(
        [total(&r0), total(&r4), total(&r16)],
        [68_186, 183_515, 613_721]
    );
    // 36,193 misses: the fetch unit is busy at least their stalls, and the frame grows by at
    // most them (it overlapped some with the scan's gaps)
    for (r, m) in [(&r4, 4u64), (&r16, 16)] {
        let busy = r.report.cycles.per_unit["fetch"].busy;
        assert!(busy >= 36_193 * m, "{busy}");
        assert!(total(r) - total(&r0) <= 36_193 * m);
    }
    // a prefetching unit (Igehy et al. 1998) with a FIFO as deep as the latency hides 64-cycle
    // misses: the frame takes what it takes without them (68,186 cycles; the FIFO's buffering
    // even absorbs some of the downstream stalls)
    let pre = |c: &str| {
        let set = format!("engine.texture_cache=Some((lines: 64, ways: 4, block: 4, {c}))");
        render(&load("sgi-teapot", &[&set])).report.cycles.total
    };
    assert_eq!(pre("miss_cycles: 64, prefetch: 64"), 66_897);
    // a shallow FIFO does not cover the latency
    assert_eq!(pre("miss_cycles: 64, prefetch: 8"), 216_377);
    // two memory cycles a fill: 36,193 fills take 72,386 cycles of memory, more than the frame
    let bound = pre("miss_cycles: 64, prefetch: 64, fill_cycles: 2");
    assert!((72_386..=90_000).contains(&bound), "{bound}");
    let e = config::load(
        &config("sgi-teapot"),
        &["engine.texture_cache=Some((lines: 64, ways: 4, block: 4, miss_cycles: 5000))".into()],
    )
    .and_then(|l| run::run(&l, None).map(|_| ()))
    .err()
    .unwrap()
    .to_string();
    assert!(e.contains("engine.texture_cache.miss_cycles"), "{e}");
    for (c, field) in [
        ("prefetch: 2000", "prefetch"),
        ("fill_cycles: 0", "fill_cycles"),
    ] {
        let set = format!("engine.texture_cache=Some((lines: 64, ways: 4, block: 4, {c}))");
        let e = run::run(&load("sgi-teapot", &[&set]), None)
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains(&format!("engine.texture_cache.{field}")), "{e}");
    }
}
