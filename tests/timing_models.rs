//! The timing model on events (`pipeline/src/sim/events.rs`) against the clocked model that
//! traces run on: the same cycle report (total, frame work, every unit's busy, idle and stall
//! clocks) for every bundled config.

mod common;

use bumpsim_pipeline::{config, run};
use common::*;

/// The cycle reports of a run without a trace (on events, unless texture-cache misses stall
/// the units) and of one traced (clock by clock).
fn both(path: &std::path::Path, sets: &[String]) -> [bumpsim_pipeline::sim::CycleReport; 2] {
    let l = config::load(path, sets).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let p = run::prepare(&l).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    [None, Some((0, 1))].map(|trace| p.simulate_lanes(trace).cycles)
}

#[test]
fn events_and_clocks_give_every_config_the_same_cycle_report() {
    let sets = ["scene.width=48", "scene.height=40"].map(String::from);
    let configs = configs();
    assert!(configs.len() >= 36, "{} configs", configs.len());
    for path in &configs {
        let [events, clocked] = both(path, &sets);
        assert_eq!(events, clocked, "{}", stem(path));
        assert!(events.fragments > 0, "{}", stem(path));
    }
}

#[test]
fn events_and_clocks_agree_on_the_default_config_at_full_size() {
    let [events, clocked] = both(&config("sgi-teapot"), &[]);
    assert_eq!(events, clocked);
    // two clocks per fragment (the dot-product unit's interval), stalls upstream of it
    assert!(events.per_fragment >= 2.0, "{}", events.per_fragment);
    assert!(events.per_unit["fetch"].stall > 0);
}

#[test]
fn events_and_clocks_agree_with_texture_cache_misses() {
    // the misses of the one reading unit queue at its memory alone: the events model takes
    // them (blocking or prefetching, either bus); the clocked model is the reference
    let plain = both(&config("sgi-teapot"), &[])[0].total;
    for cache in [
        "(lines: 64, ways: 4, block: 4, miss_cycles: 20)",
        "(lines: 16, ways: 2, block: 2, miss_cycles: 7, fill_cycles: 3, bus: PerCache)",
        "(lines: 64, ways: 4, block: 4, miss_cycles: 30, fill_cycles: 4, prefetch: 8)",
        "(lines: 8, ways: 8, block: 4, miss_cycles: 50, fill_cycles: 2, prefetch: 2, bus: PerCache)",
    ] {
        let sets = [format!("engine.texture_cache=Some({cache})")];
        let [events, clocked] = both(&config("sgi-teapot"), &sets);
        assert_eq!(events, clocked, "{cache}");
        assert!(events.total > plain, "{cache}: {} <= {plain}", events.total);
    }
}
