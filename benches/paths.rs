//! The three paths of one prepared frame (configs/sgi-teapot.ron at 256x256): the timed,
//! bit-accurate run (`simulate_lanes`: the timing model beside the function), exact mode
//! (`evaluate_exact`) and the float reference (`reference`), and the three together as a
//! render runs them (`paths`: concurrently, rayon). One criterion iteration is one round of
//! all four, in an order rotated each round, so the four see the same machine; every round's
//! times are kept and, after criterion's own figure for a round, the paired ratios are
//! printed: each path against the simulation, and the sum of the three against the
//! concurrent run (what running them concurrently saves). Medians and quartiles over rounds.

use bumpsim_pipeline::config;
use bumpsim_pipeline::run::{prepare, Prepared};
use criterion::{criterion_group, criterion_main, Criterion};
use std::path::Path;
use std::sync::Mutex;
use std::time::{Duration, Instant};

const PATHS: [&str; 4] = ["simulation", "exact mode", "reference", "concurrent"];

/// One path's wall time.
fn time_path(p: &Prepared, r: config::ReferenceConfig, which: usize) -> Duration {
    let t0 = Instant::now();
    match which {
        0 => drop(std::hint::black_box(p.simulate_lanes(None))),
        1 => drop(std::hint::black_box(p.evaluate_exact())),
        2 => drop(std::hint::black_box(p.reference(r))),
        _ => drop(std::hint::black_box(p.paths(r, None))),
    }
    t0.elapsed()
}

/// The median and the quartiles of `v`.
fn quartiles(mut v: Vec<f64>) -> (f64, f64, f64) {
    v.sort_by(f64::total_cmp);
    let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
    (at(0.5), at(0.25), at(0.75))
}

fn paths(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/sgi-teapot.ron");
    let loaded = config::load(&path, &[]).expect("the bundled config loads");
    let mut p = prepare(&loaded).expect("the bundled config prepares");
    // no key: every round renders the reference (a run would find it kept from the last)
    p.scene.key = None;
    let r = loaded.config.reference;
    let rounds: Mutex<Vec<[Duration; 4]>> = Mutex::new(Vec::new());
    let mut g = c.benchmark_group("sgi-teapot-256");
    g.sample_size(20);
    g.bench_function("one round of the four paths, interleaved", |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                let mut round = [Duration::ZERO; 4];
                let mut log = rounds.lock().unwrap();
                let first = log.len() % 4;
                for k in 0..4 {
                    let which = (first + k) % 4;
                    round[which] = time_path(&p, r, which);
                }
                total += round.iter().sum::<Duration>();
                log.push(round);
            }
            total
        })
    });
    g.finish();
    let rounds = rounds.into_inner().unwrap();
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    println!(
        "\npaired over {} rounds (median [quartiles]); fragments {}",
        rounds.len(),
        p.raster.fragments.len()
    );
    for (k, name) in PATHS.iter().enumerate() {
        let (m, lo, hi) = quartiles(rounds.iter().map(|t| ms(t[k])).collect());
        println!("  {name:<34} {m:>8.2} ms [{lo:.2}, {hi:.2}]");
    }
    let ratio = |name: &str, f: &dyn Fn(&[Duration; 4]) -> f64| {
        let (m, lo, hi) = quartiles(rounds.iter().map(f).collect());
        println!("  {name:<34} {m:>8.3}    [{lo:.3}, {hi:.3}]");
    };
    ratio("exact mode / simulation", &|t| ms(t[1]) / ms(t[0]));
    ratio("reference / simulation", &|t| ms(t[2]) / ms(t[0]));
    ratio("sum of the three / concurrent", &|t| {
        (ms(t[0]) + ms(t[1]) + ms(t[2])) / ms(t[3])
    });
}

criterion_group!(benches, paths);
criterion_main!(benches);
