//! The paths as a render runs them against the forms the unit tests read: the stored lanes
//! are the words the ROP read before, the exact mode without raw words gives the same values,
//! and the concurrent paths give what each gives alone.

use super::*;
use std::path::Path;

/// Bundled configs at 64x64: plain, killing (late depth), alpha (four lanes) and two blend
/// passes.
fn small(name: &str) -> Prepared {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../configs/{name}.ron"));
    let sets = ["scene.width=64".to_string(), "scene.height=64".to_string()];
    let l = crate::config::load(&path, &sets).unwrap();
    prepare(&l).unwrap()
}

const CONFIGS: [&str; 4] = [
    "sgi-teapot",
    "cull-fragment",
    "rop-alpha-test",
    "quantized-bunny-wood-eq2",
];

#[test]
fn stored_lanes_are_the_words_the_rop_reads() {
    for name in CONFIGS {
        let mut p = small(name);
        let words = p.simulate(None);
        let lanes = p.simulate_lanes(None);
        assert_eq!(words.cycles, lanes.cycles, "{name}");
        assert_eq!(words.probes, lanes.probes, "{name}");
        let n = p.engine.output.spec.lanes as usize;
        assert_eq!(lanes.outputs.len(), words.outputs.len());
        for (f, w) in words.outputs.iter().enumerate() {
            let got = lanes.outputs.word(f);
            assert_eq!(got.is_some(), w.is_some(), "{name} fragment {f}");
            if let (Some(got), Some(w)) = (got, w) {
                assert_eq!(got.lanes[..n], w.lanes[..n], "{name} fragment {f}");
            }
        }
    }
}

#[test]
fn exact_mode_without_raw_words_has_the_same_values() {
    for name in CONFIGS {
        let p = small(name);
        let out = p.evaluate_exact();
        let n = p.engine.output.spec.lanes as usize;
        assert!(!out.is_empty(), "{name}");
        for f in 0..out.len() {
            let t = p.fragment_token(Mode::Exact, f);
            let want = t.live.then(|| p.engine.output.wire.read(&t.slots));
            let got = out.word(f);
            assert_eq!(got.is_some(), want.is_some(), "{name} fragment {f}");
            if let (Some(got), Some(want)) = (got, want) {
                let bits = |w: &Word| {
                    w.lanes[..n]
                        .iter()
                        .map(|s| s.x.to_bits())
                        .collect::<Vec<_>>()
                };
                assert_eq!(bits(&got), bits(&want), "{name} fragment {f}");
            }
        }
    }
}

#[test]
fn the_concurrent_paths_are_the_paths_one_after_another() {
    for name in CONFIGS {
        let p = small(name);
        let r = crate::config::ReferenceConfig::default();
        let all = p.paths(r, Some((0, 200)));
        let sim = p.simulate_lanes(Some((0, 200)));
        assert_eq!(all.sim.outputs, sim.outputs, "{name}");
        assert_eq!(all.sim.cycles, sim.cycles, "{name}");
        assert_eq!(all.sim.probes, sim.probes, "{name}");
        assert_eq!(all.exact, p.evaluate_exact(), "{name}");
        assert_eq!(all.reference, p.reference(r), "{name}");
        // the reference on the engine's coverage is the reference that rasterises again
        let again = reference::render_reference_sampled(
            &p.scene,
            &p.raster_config,
            r.perturbation,
            r.samples,
        );
        assert_eq!(
            (&all.reference.image.px, &all.reference.mask),
            (&again.image.px, &again.mask),
            "{name}"
        );
    }
}

#[test]
fn gates_without_rendering_are_the_reports() {
    let mut seen_interpolator = false;
    let fixed = "engine.interpolator=Fixed(weight_bits: 12)";
    for (name, more) in [
        ("sgi-teapot", None),
        ("sgi-teapot", Some(fixed)),
        ("gouraud-teapot", None),
        ("quantized-bunny-materials", None),
        ("nv20-combiner-bump", None),
        ("texram-teapot", None),
        ("rop-alpha-test", None),
    ] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../configs/{name}.ron"));
        let mut sets = vec!["scene.width=32".to_string(), "scene.height=32".to_string()];
        sets.extend(more.map(String::from));
        let l = crate::config::load(&path, &sets).unwrap();
        let g = serde_json::to_value(gates(&l).unwrap()).unwrap();
        let r = serde_json::to_value(run(&l, None).unwrap().report.gates).unwrap();
        assert_eq!(g, r, "{name}");
        assert!(g["total"].as_f64().unwrap() > 0.0, "{name}");
        seen_interpolator |= g["per_unit"].get("attribute interpolator").is_some();
    }
    assert!(
        seen_interpolator,
        "the fixed-point interpolator is not priced"
    );
}

fn small_with(name: &str, more: &[&str]) -> Prepared {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../configs/{name}.ron"));
    let mut sets = vec!["scene.width=48".to_string(), "scene.height=48".to_string()];
    sets.extend(more.iter().map(|s| s.to_string()));
    let l = crate::config::load(&path, &sets).unwrap();
    prepare(&l).unwrap()
}

/// The keys under which runs share a reference and a bake: equal for two engines of one
/// scene, apart for another scene, and the bump key apart only where the bump map may be.
#[test]
fn frames_of_one_scene_share_their_keys_and_only_they() {
    let base = small_with("sgi-teapot", &[]);
    let engine = small_with("sgi-teapot", &["sim.fifo_depth=3"]);
    let light = small_with("sgi-teapot", &["scene.lights[0].color=(0.5, 0.5, 0.5)"]);
    let bump = small_with("sgi-teapot", &["scene.bump.MexicanHat.depth=0.02"]);
    let key = |p: &Prepared| p.scene.key.expect("a bundled scene has a key");
    assert_eq!(key(&base), key(&engine));
    assert_ne!(key(&base).scene, key(&light).scene);
    assert_eq!(
        key(&base).bump,
        key(&light).bump,
        "the lights do not touch the bump map"
    );
    assert_ne!(key(&base).bump, key(&bump).bump);
    assert_ne!(key(&base).scene, key(&bump).scene);
    let opts = reference::Options {
        perturbation: Default::default(),
        samples: 1,
        normals: false,
    };
    let frame = |p: &Prepared, o: reference::Options| {
        let frags = &p.raster.fragments;
        let c = reference::Coverage::of_fragments(frags, 48, 48, &p.raster_config);
        shared::key(key(p).scene, &c, frags, o)
    };
    assert_eq!(frame(&base, opts), frame(&engine, opts));
    assert_ne!(frame(&base, opts), frame(&light, opts));
    assert_ne!(
        frame(&base, opts),
        frame(&base, reference::Options { samples: 2, ..opts })
    );
    // a shared reference is the one rendered for the frame itself
    let r = crate::config::ReferenceConfig::default();
    for p in [&base, &engine, &light] {
        let frags = &p.raster.fragments;
        let c = reference::Coverage::of_fragments(frags, 48, 48, &p.raster_config);
        let fresh = reference::render_covered(&p.scene, &c, frags, opts);
        let got = p.reference(r);
        assert_eq!((&got.image.px, &got.mask), (&fresh.image.px, &fresh.mask));
    }
}

/// The front end's batches ([`front::Front::fill_batch`], lane by lane over up to
/// [`bumpsim_hw::BATCH`] fragments) fill the tokens that one call per fragment fills, bit for bit,
/// for every bundled config with its own interpolator and with the fixed-point one, in both
/// modes, from any first fragment.
#[test]
fn batched_fill_is_the_fill_of_every_fragment() {
    use crate::sim::Fill;
    let paths = bundled();
    let bits = |t: &Token| {
        let lanes = t.slots.iter().flat_map(|w| w.lanes.iter());
        let words: Vec<(i64, u64)> = lanes.map(|s| (s.raw, s.x.to_bits())).collect();
        (t.id, t.x, t.y, t.live, words)
    };
    let mut batched = 0;
    let mut weighted = 0;
    for (name, with_fixed, p) in small_variants(&paths) {
        weighted += usize::from(with_fixed && p.front(Mode::BitAccurate, true).fixed.is_some());
        for mode in [Mode::BitAccurate, Mode::Exact] {
            let front = p.front(mode, true);
            let fill = front::FrontFill {
                front: &front,
                attrs: &p.engine.attributes,
                mode,
            };
            let n = front.frags.len();
            let token = || Token {
                id: 0,
                x: 0,
                y: 0,
                live: true,
                slots: vec![Word::default(); p.engine.slots()],
            };
            let mut one = token();
            // all fragments at once, and batches that start and end anywhere
            for (first, len) in [(0, n), (n / 3, 5), (n / 2, 3 * bumpsim_hw::BATCH + 7)] {
                let len = len.min(n - first.min(n));
                let mut ts: Vec<Token> = (0..len).map(|_| token()).collect();
                fill.fill_batch(first, &mut ts);
                for (k, t) in ts.iter().enumerate() {
                    fill.fill(first + k, &mut one);
                    assert_eq!(
                        bits(t),
                        bits(&one),
                        "{name} {mode:?} fragment {}",
                        first + k
                    );
                }
                batched += len;
            }
        }
    }
    assert!(batched > 200_000, "{batched}");
    assert_eq!(weighted, paths.len());
}

/// Every config of `paths` at 40x32, with its own interpolator and with the fixed-point one:
/// (a name for messages, whether the fixed-point one was set, the prepared frame).
fn small_variants(
    paths: &[std::path::PathBuf],
) -> impl Iterator<Item = (String, bool, Prepared)> + '_ {
    let variants = paths.iter().flat_map(|p| [(p, false), (p, true)]);
    variants.map(|(path, with_fixed)| {
        let name = format!(
            "{} (fixed-point interpolator: {with_fixed})",
            path.display()
        );
        let mut sets = vec!["scene.width=40".to_string(), "scene.height=32".to_string()];
        if with_fixed {
            sets.push("engine.interpolator=Fixed(weight_bits: 16)".to_string());
        }
        let l = crate::config::load(path, &sets).unwrap_or_else(|e| panic!("{name}: {e}"));
        let p = prepare(&l).unwrap_or_else(|e| panic!("{name}: {e}"));
        (name, with_fixed, p)
    })
}

/// The bundled top-level configs, sorted.
fn bundled() -> Vec<std::path::PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../configs");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    paths.sort();
    assert!(paths.len() >= 36, "{} configs", paths.len());
    paths
}

/// The bit-accurate function over batches of columns (`sim::evaluate_lanes`:
/// `Stage::eval_columns`, the units' batch datapaths) gives every output port's raw words and
/// live bits that the tokens give fragment by fragment (`sim::evaluate`: `Stage::eval_token`),
/// and their decodings are the tokens' values, bit for bit: every bundled config, every
/// pass, with its own interpolator and with the fixed-point one.
#[test]
fn columns_are_the_tokens_of_every_fragment() {
    let (mut compared, mut killed) = (0usize, 0usize);
    for (name, _, p) in small_variants(&bundled()) {
        let mode = Mode::BitAccurate;
        let front = p.front(mode, false);
        let fill = front::FrontFill {
            front: &front,
            attrs: &p.engine.attributes,
            mode,
        };
        let n = front.frags.len();
        let outputs =
            std::iter::once(&p.engine.output).chain(p.engine.passes.iter().map(|q| &q.output));
        for out in outputs {
            let stages = &p.engine.stages;
            let slots = p.engine.slots();
            let tokens = sim::evaluate(stages, mode, out.wire, n, slots, &fill);
            let cols = sim::evaluate_lanes(stages, mode, out.wire, &out.spec, n, slots, &fill);
            let lanes = out.spec.lanes as usize;
            for (f, t) in tokens.iter().enumerate() {
                let bits = |w: &Word| -> Vec<(i64, u64)> {
                    w.lanes[..lanes]
                        .iter()
                        .map(|s| (s.raw, s.x.to_bits()))
                        .collect()
                };
                let c = cols.word(f);
                assert_eq!(
                    t.as_ref().map(bits),
                    c.as_ref().map(bits),
                    "{name} fragment {f}"
                );
                killed += usize::from(t.is_none());
            }
            compared += n;
        }
    }
    assert!(compared > 80_000, "{compared}");
    assert!(killed > 0, "no config killed a fragment");
}

/// The fragment ranges by triangle from the rasterizer's counts are the scan's, on every
/// bundled config, and still when the fragments were edited after rasterization (the counts
/// no longer describe them: the scan is taken).
#[test]
fn raster_ranges_are_the_scan_of_the_fragments() {
    let sets = ["scene.width=40".to_string(), "scene.height=32".to_string()];
    let mut nonempty = 0;
    for path in bundled() {
        let l = crate::config::load(&path, &sets).unwrap();
        let mut p = prepare(&l).unwrap();
        let ntri = p.scene.mesh.triangles.len();
        let scan = front::triangle_ranges(&p.raster.fragments, ntri);
        assert_eq!(
            front::raster_ranges(&p.raster, ntri),
            scan,
            "{}",
            path.display()
        );
        nonempty += scan.iter().filter(|r| !r.is_empty()).count();
        let half = p.raster.fragments.len() / 2;
        p.raster.fragments.truncate(half);
        let scan = front::triangle_ranges(&p.raster.fragments, ntri);
        assert_eq!(
            front::raster_ranges(&p.raster, ntri),
            scan,
            "{} (half)",
            path.display()
        );
    }
    assert!(nonempty > 1000, "{nonempty}");
}
