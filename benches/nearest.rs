//! Criterion benchmarks of the quantize preprocessing (issue 16): the exact nearest-entry
//! search (`quantize::NearestIndex`, a k-d tree) against the brute force `quantize::nearest`
//! for 262,144 texels (512x512) and 2,048 / 16,384 median-cut entries, Floyd–Steinberg
//! dithering through the index (and its direction cells, `quantize/search/cells.rs`), and
//! median cut by selection against the sort-every-box reference on a 65,536-texel (256x256)
//! map. Both sides of each pair give the same answers
//! bit for bit (`quantize` tests). The maps are the Mexican hat of `quantize::tests` with 3
//! cells (no repeated normals within a cell). Report ratios of medians measured in one run
//! (machines here are noisy); one thread throughout.

use bumpsim_pipeline::quantize::{self, median_cut, NearestIndex, Scan};
use bumpsim_pipeline::scene::{BumpSpec, NormalMap, NormalMethod};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

/// The analytic Mexican hat with 3 cells baked at `n x n`.
fn hat(n: u32) -> NormalMap {
    BumpSpec::MexicanHat {
        cells: 3,
        sigma: 0.18,
        depth: 0.02,
    }
    .build(Path::new("."))
    .expect("a valid bump")
    .bake_normals(n, n, NormalMethod::Analytic)
}

fn nearest(c: &mut Criterion) {
    let map = hat(512);
    let n = &map.texels;
    let mut g = c.benchmark_group("nearest-262144-texels");
    g.sample_size(10);
    g.warm_up_time(Duration::from_millis(500));
    g.measurement_time(Duration::from_secs(2));
    g.throughput(Throughput::Elements(n.len() as u64));
    for s_n in [2048, 16384] {
        let t = median_cut::median_cut(n, s_n);
        assert_eq!(t.len(), s_n);
        g.bench_function(format!("brute force, {s_n} entries"), |b| {
            b.iter(|| {
                n.iter()
                    .map(|&v| quantize::nearest(v, &t, 0..t.len()))
                    .fold(0u64, |s, i| s + u64::from(i))
            })
        });
        g.bench_function(format!("index (build + queries), {s_n} entries"), |b| {
            b.iter(|| {
                let ix = NearestIndex::of(&t);
                n.iter()
                    .map(|&v| ix.nearest(v))
                    .fold(0u64, |s, i| s + u64::from(i))
            })
        });
        g.bench_function(format!("index build alone, {s_n} entries"), |b| {
            b.iter(|| NearestIndex::of(black_box(&t)).len())
        });
        g.bench_function(format!("dither (index), {s_n} entries"), |b| {
            b.iter(|| quantize::dither(n, 512, 512, &t, Scan::Serpentine).len())
        });
    }
    g.finish();
}

fn median_cut_by_selection(c: &mut Criterion) {
    let map = hat(256);
    let n = &map.texels;
    let mut g = c.benchmark_group("median-cut-65536-texels");
    g.sample_size(10);
    g.warm_up_time(Duration::from_millis(500));
    g.measurement_time(Duration::from_secs(2));
    g.throughput(Throughput::Elements(n.len() as u64));
    for s_n in [256, 2048] {
        g.bench_function(format!("sorting every box (old), {s_n} entries"), |b| {
            b.iter(|| median_cut::reference::median_cut_by_sorting(black_box(n), s_n).len())
        });
        g.bench_function(format!("selection (new), {s_n} entries"), |b| {
            b.iter(|| median_cut::median_cut(black_box(n), s_n).len())
        });
    }
    g.finish();
}

criterion_group!(benches, nearest, median_cut_by_selection);
criterion_main!(benches);
