//! Criterion benchmarks: the SGI engine's timed, bit-accurate simulation against the float
//! reference on the same 512x512 scene (configs/sgi-teapot.ron at 512x512), on one and on two
//! threads (rayon pools built here). Report ratios of medians measured in one run (machines
//! here are noisy), and fragments per second. The simulated run is the one `render` takes
//! (`Prepared::simulate_lanes`: the timing model beside the function, the outputs stored as
//! the ROP reads them).

use bumpsim_pipeline::config;
use bumpsim_pipeline::run::prepare;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::path::Path;

fn engines(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/sgi-teapot.ron");
    let sets = [
        "scene.width=512".to_string(),
        "scene.height=512".to_string(),
    ];
    let loaded = config::load(&path, &sets).expect("the bundled config loads");
    let mut p = prepare(&loaded).expect("the bundled config prepares");
    // no key: every iteration renders the reference (a run would find it kept from the last)
    p.scene.key = None;
    let fragments = p.raster.fragments.len() as u64;
    let reference = loaded.config.reference;
    let mut g = c.benchmark_group("sgi-teapot-512");
    g.sample_size(10);
    g.throughput(Throughput::Elements(fragments));
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a rayon pool");
        g.bench_function(
            format!("simulated (bit-accurate, timed), {threads} threads"),
            |b| b.iter(|| pool.install(|| p.simulate_lanes(None).cycles.total)),
        );
        g.bench_function(format!("exact mode (untimed), {threads} threads"), |b| {
            b.iter(|| pool.install(|| p.evaluate_exact().len()))
        });
        g.bench_function(format!("float reference, {threads} threads"), |b| {
            b.iter(|| pool.install(|| p.reference(reference).covered()))
        });
    }
    // the same engine with the fixed-point attribute interpolator (integer weights and vertex
    // words) in place of the exact one: what interpolation costs in integers (its images are
    // not the default's, so it is measured beside it, not instead)
    let sets = [
        sets.as_slice(),
        &["engine.interpolator=Fixed(weight_bits: 16)".to_string()],
    ]
    .concat();
    let loaded = config::load(&path, &sets).expect("the bundled config loads");
    let mut p = prepare(&loaded).expect("the bundled config prepares");
    p.scene.key = None;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a rayon pool");
    g.bench_function(
        "simulated (bit-accurate, timed, fixed-point interpolator), 1 threads",
        |b| b.iter(|| pool.install(|| p.simulate_lanes(None).cycles.total)),
    );
    g.finish();
}

criterion_group!(benches, engines);
criterion_main!(benches);
