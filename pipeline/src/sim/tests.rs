//! The timing model on events against the clocked one: the same cycle report for random
//! pipelines (latencies, intervals, FIFO depths, frame work) and random workloads
//! (triangles with and without fragments, setup times), small values that make every
//! constraint bind: back-pressure, the in-flight limit, setup stalls, empty triangles.

use super::{clocked, events, timing_twins, TimingTwin, Workload};
use bumpsim_hw::{Stage, Token};
use proptest::prelude::*;

fn stage(k: usize, (latency, interval, frame_cycles): (u32, u32, u64)) -> Stage {
    let twin = TimingTwin {
        kind: "twin",
        latency,
        interval,
        frame_cycles,
        can_kill: false,
    };
    Stage::new(format!("u{k}"), Box::new(twin), Vec::new(), Vec::new())
}

fn workload<'a>(
    fill: &'a super::FillToken<'a>,
    sizes: &[usize],
    setup: Vec<u32>,
    fifo_depth: usize,
) -> Workload<'a> {
    let mut start = 0;
    let triangles = sizes
        .iter()
        .map(|&n| {
            start += n;
            start - n..start
        })
        .collect();
    Workload {
        triangles,
        setup,
        fill_token: fill,
        slots: 0,
        attributes: 0,
        fifo_depth,
        extra: Vec::new(),
    }
}

fn unit() -> impl Strategy<Value = (u32, u32, u64)> {
    (
        0u32..=7,
        0u32..=4,
        prop_oneof![3 => Just(0u64), 1 => 0u64..=20],
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn events_give_the_clocked_report(
        units in prop::collection::vec(unit(), 0..=5),
        tris in prop::collection::vec((0usize..=9, 0u32..=12), 0..=12),
        fifo_depth in 0usize..=4,
    ) {
        let stages: Vec<Stage> =
            units.into_iter().enumerate().map(|(k, u)| stage(k, u)).collect();
        let fill = |_: usize, _: &mut Token| {};
        let (sizes, setup): (Vec<usize>, Vec<u32>) = tris.into_iter().unzip();
        let w = workload(&fill, &sizes, setup, fifo_depth);
        let want = clocked(&stages, &w, None).0;
        let got = events::timing(&stages, &w).expect("no misses");
        prop_assert_eq!(got, want);
    }
}

/// A long frame through a unit of two clocks and a slower, deeper one behind a one-deep
/// FIFO: the recurrences' rings wrap many times.
#[test]
fn events_give_the_clocked_report_over_a_long_frame() {
    let stages = [(4, 2, 256), (9, 3, 0), (1, 1, 0)]
        .into_iter()
        .enumerate()
        .map(|(k, u)| stage(k, u))
        .collect::<Vec<_>>();
    let fill = |_: usize, _: &mut Token| {};
    let sizes: Vec<usize> = (0..500).map(|t| (t * 7919) % 23).collect();
    let setup: Vec<u32> = (0..500).map(|t| ((t * 104_729) % 17) as u32).collect();
    for depth in [1, 2, 5] {
        let w = workload(&fill, &sizes, setup.clone(), depth);
        let want = clocked(&stages, &w, None).0;
        assert_eq!(want.fragments, sizes.iter().sum::<usize>() as u64);
        assert_eq!(events::timing(&stages, &w), Some(want));
    }
}

/// Misses of two stages queued at one texture memory: the clocked model serves the queue in
/// its tick order within a clock, so the events give way to it.
#[test]
fn misses_sharing_a_memory_run_on_the_clocked_model() {
    let stages = timing_twins(&[stage(0, (2, 1, 0)), stage(1, (1, 1, 0))]);
    let fill = |_: usize, _: &mut Token| {};
    let mut w = workload(&fill, &[3], vec![1], 2);
    let m = bumpsim_hw::stage::MissTiming {
        misses: vec![0, 2, 0].into(),
        latency: 5,
        occupancy: 1,
        memory: 0,
        prefetch: None,
    };
    w.extra = vec![Some(m.clone()), Some(m)];
    assert_eq!(events::timing(&stages, &w), None);
}

/// A stage's texture-cache misses: each fragment's count (mostly none), the fill latency and
/// occupancy, the memory, and blocking or a prefetch FIFO's depth.
fn misses() -> impl Strategy<Value = Option<bumpsim_hw::stage::MissTiming>> {
    let m = (
        prop::collection::vec(prop_oneof![3 => Just(0u32), 1 => 0u32..=3], 0..=120),
        0u32..=9,
        1u32..=4,
        0usize..=5,
        prop_oneof![Just(None), (1u32..=4).prop_map(Some)],
    )
        .prop_map(|(misses, latency, occupancy, memory, prefetch)| {
            bumpsim_hw::stage::MissTiming {
                misses: misses.into(),
                latency,
                occupancy,
                memory,
                prefetch,
            }
        });
    prop_oneof![Just(None), m.prop_map(Some)]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    /// With misses, the events give the clocked report whenever no two stages' fills queue
    /// at one memory (an index beyond the memories is a memory of the fragment's own), and
    /// give way to the clocked model otherwise.
    #[test]
    fn events_with_misses_give_the_clocked_report(
        units in prop::collection::vec((unit(), misses()), 1..=4),
        tris in prop::collection::vec((0usize..=9, 0u32..=12), 0..=12),
        fifo_depth in 0usize..=4,
    ) {
        let (units, extra): (Vec<_>, Vec<_>) = units.into_iter().unzip();
        let stages: Vec<Stage> =
            units.into_iter().enumerate().map(|(k, u)| stage(k, u)).collect();
        let fill = |_: usize, _: &mut Token| {};
        let (sizes, setup): (Vec<usize>, Vec<u32>) = tris.into_iter().unzip();
        let mut w = workload(&fill, &sizes, setup, fifo_depth);
        w.extra = extra;
        let nmem = w.extra.iter().flatten().map(|m| m.memory + 1).max().unwrap_or(0);
        let nmem = nmem.min(w.extra.len());
        let shared = (0..nmem).any(|k| {
            w.extra.iter().flatten().filter(|m| m.memory == k).count() > 1
        });
        let want = clocked(&stages, &w, None).0;
        let got = events::timing(&stages, &w);
        if shared {
            prop_assert_eq!(got, None);
        } else {
            prop_assert_eq!(got, Some(want));
        }
    }
}
