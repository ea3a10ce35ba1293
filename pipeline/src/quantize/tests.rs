//! Tests of the table builders, the nearest-entry property and the measurements quoted in
//! the module docs.

use super::*;
use crate::scene::{BumpSpec, NormalMethod};
use std::path::Path;

/// `BumpSpec::MexicanHat { cells: 4, sigma: 0.18, depth: 0.02 }` (configs/
/// gouraud-quad-bandwidth.ron) baked analytically at `n x n`.
pub(crate) fn mexican_hat(n: u32) -> Vec<DVec3> {
    mexican_hat_cells(n, 4)
}

/// The same with `cells` cells: with 4 cells at 128x128 every cell is 32x32 texels and the map
/// holds only 1024 distinct normals; 3 cells do not divide 128 and give 16384.
pub(crate) fn mexican_hat_cells(n: u32, cells: u32) -> Vec<DVec3> {
    BumpSpec::MexicanHat {
        cells,
        sigma: 0.18,
        depth: 0.02,
    }
    .build(Path::new("."))
    .expect("a valid bump")
    .bake_normals(n, n, NormalMethod::Analytic)
    .texels
}

/// No entry has a strictly larger dot product than the chosen one, and among equal ones the
/// chosen is the first (independent brute force).
fn assert_nearest(normals: &[DVec3], p: &Palette) {
    assert_eq!(p.indices.len(), normals.len());
    for (i, (n, &k)) in normals.iter().zip(&p.indices).enumerate() {
        let d = n.dot(p.entries[k as usize]);
        for (j, e) in p.entries.iter().enumerate() {
            let s = n.dot(*e);
            assert!(
                s < d || (s == d && j >= k as usize),
                "texel {i}: entry {j} beats {k}"
            );
        }
    }
}

#[test]
fn every_texel_maps_to_its_nearest_entry() {
    let map = mexican_hat(64);
    for (s_n, q) in [
        (1, Quantizer::MedianCut),
        (16, Quantizer::MedianCut),
        (333, Quantizer::MedianCut),
        (1, Quantizer::NeuQuant { sample_factor: 10 }),
        (2, Quantizer::NeuQuant { sample_factor: 10 }),
        (16, Quantizer::NeuQuant { sample_factor: 10 }),
        (256, Quantizer::NeuQuant { sample_factor: 1 }),
        (1, KM),
        (16, KM),
        (333, KM),
    ] {
        let p = quantize(&map, s_n, q).unwrap();
        assert!(
            !p.entries.is_empty() && p.entries.len() <= s_n,
            "{q:?} {s_n}"
        );
        for e in &p.entries {
            assert!((e.length() - 1.0).abs() < 1e-12);
        }
        assert_nearest(&map, &p);
    }
}

/// The k-means quantizer as the tests use it.
const KM: Quantizer = Quantizer::KMeans {
    start: KMeansStart::Random { seed: 1 },
    max_iterations: 20,
};
/// k-means refining median cut.
const KMC: Quantizer = Quantizer::KMeans {
    start: KMeansStart::MedianCut,
    max_iterations: 3,
};

#[test]
fn kmeans_maps_every_texel_to_its_nearest_entry_at_any_size() {
    let map = mexican_hat(128);
    let mut last = f64::INFINITY;
    for s_n in [16, 256, 2048, 16384] {
        let p = quantize(&map, s_n, KM).unwrap();
        let c = quantize(&map, s_n, KMC).unwrap();
        assert!(c.entries.len() <= s_n);
        assert_nearest(&map, &c);
        assert!(
            !p.entries.is_empty() && p.entries.len() <= s_n,
            "{s_n}: {}",
            p.entries.len()
        );
        for e in &p.entries {
            assert!((e.length() - 1.0).abs() < 1e-12);
        }
        assert_nearest(&map, &p);
        // more entries, smaller (or, once the table holds every distinct normal, equal) error
        let mean = angular_error_deg(&p.decode(), &map).0;
        assert!(mean <= last, "s_n {s_n}: mean {mean} > {last}");
        if s_n <= 256 {
            assert!(mean < last, "s_n {s_n}: mean {mean} not below {last}");
        }
        last = mean;
    }
}

#[test]
fn kmeans_is_deterministic_and_seeded() {
    let map = mexican_hat_cells(64, 3);
    for s_n in [16, 300] {
        let a = quantize(&map, s_n, KM).unwrap();
        // built again, not the kept table
        let b = super::build_table_now(&map, s_n, KM).unwrap();
        assert_eq!(a.entries, b, "s_n {s_n}");
        let other = Quantizer::KMeans {
            start: KMeansStart::Random { seed: 2 },
            max_iterations: 20,
        };
        assert_ne!(quantize(&map, s_n, other).unwrap().entries, a.entries);
    }
}

#[test]
fn kmeans_handles_tiny_inputs() {
    // fewer distinct normals than entries: one entry per distinct normal at most
    let one = quantize(&[DVec3::Z], 16384, KM).unwrap();
    assert_eq!(one.entries, vec![DVec3::Z]);
    let d = [DVec3::X, DVec3::Y, DVec3::Z];
    let n: Vec<DVec3> = (0..30).map(|i| d[i % 3]).collect();
    let p = quantize(&n, 16, KM).unwrap();
    assert!(p.entries.len() <= 3, "{:?}", p.entries);
    assert_nearest(&n, &p);
}

#[test]
fn median_cut_accepts_any_count_and_fills_the_table() {
    // 1000 distinct normals, not a power of two
    let map: Vec<DVec3> = (0..1000)
        .map(|i| {
            let t = f64::from(i);
            DVec3::new((t * 0.37).sin() * 0.5, (t * 0.11).cos() * 0.5, 1.0).normalize()
        })
        .collect();
    let p = quantize(&map, 100, Quantizer::MedianCut).unwrap();
    assert_eq!(p.entries.len(), 100);
    let one = quantize(&map[..1], 16384, Quantizer::MedianCut).unwrap();
    assert_eq!(one.entries, vec![map[0]]);
    assert_eq!(one.indices, vec![0]);
}

#[test]
fn neuquant_handles_tiny_inputs() {
    let one = quantize(&[DVec3::Z], 16, Quantizer::NeuQuant { sample_factor: 30 }).unwrap();
    assert_eq!(one.entries.len(), 16);
    // the only pixel's entry is its RGB8 code, remapped and renormalised
    let e = one.entries[one.indices[0] as usize];
    assert!(angular_error_deg(&[e], &[DVec3::Z]).0 < 0.5, "{e:?}");
}

#[test]
fn sixteen_k_entries_reproduce_a_map_with_as_many_distinct_normals() {
    // Tarini §4: "for s_N = 16K the approximation is in practice invisible"; here exact
    let map = mexican_hat_cells(128, 3);
    let p = quantize(&map, MAX_PALETTE, Quantizer::MedianCut).unwrap();
    assert_eq!(p.entries.len(), MAX_PALETTE);
    assert_eq!(p.decode(), map);
}

#[test]
fn rgb8_mapping_follows_tarini() {
    assert_eq!((to_u8(-1.0), to_u8(0.0), to_u8(1.0)), (0, 128, 255));
    assert_eq!((from_u8(0), from_u8(255)), (-1.0, 1.0));
    for c in 0..=255u8 {
        assert_eq!(to_u8(from_u8(c)), c);
    }
}

#[test]
fn quantize_errors_are_clear() {
    let n = vec![DVec3::Z; 4];
    assert_eq!(
        quantize(&n, 0, Quantizer::MedianCut),
        Err(QuantizeError::PaletteSize(0))
    );
    assert_eq!(
        quantize(&n, 16385, Quantizer::MedianCut),
        Err(QuantizeError::PaletteSize(16385))
    );
    let e = quantize(&n, 257, Quantizer::NeuQuant { sample_factor: 10 }).unwrap_err();
    assert_eq!(e, QuantizeError::NeuQuantTooLarge(257));
    assert!(e.to_string().contains("at most 256"), "{e}");
    assert_eq!(
        quantize(&n, 16, Quantizer::NeuQuant { sample_factor: 0 }),
        Err(QuantizeError::SampleFactor(0))
    );
    for bad in [0, MAX_KMEANS_ITERATIONS + 1] {
        let q = Quantizer::KMeans {
            start: KMeansStart::MedianCut,
            max_iterations: bad,
        };
        let e = quantize(&n, 16, q).unwrap_err();
        assert_eq!(e, QuantizeError::KMeansIterations(bad));
        assert!(e.to_string().contains("1..=300"), "{e}");
    }
    // KMeans takes the whole range of table sizes; only s_n itself is checked
    assert_eq!(
        quantize(&n, 16385, KM),
        Err(QuantizeError::PaletteSize(16385))
    );
    assert_eq!(
        quantize(&[], 16, Quantizer::MedianCut),
        Err(QuantizeError::Empty)
    );
    let bad = [DVec3::Z, DVec3::new(f64::NAN, 0.0, 1.0)];
    assert!(matches!(
        quantize(&bad, 16, Quantizer::MedianCut),
        Err(QuantizeError::BadNormal { index: 1, .. })
    ));
    assert!(matches!(
        quantize(&[DVec3::ZERO], 16, Quantizer::MedianCut),
        Err(QuantizeError::BadNormal { index: 0, .. })
    ));
}

#[test]
fn quantizer_round_trips_through_ron() {
    for q in [
        Quantizer::MedianCut,
        Quantizer::NeuQuant { sample_factor: 7 },
        Quantizer::KMeans {
            start: KMeansStart::Random { seed: u64::MAX },
            max_iterations: 300,
        },
        KMC,
    ] {
        let s = ron::to_string(&q).unwrap();
        assert_eq!(ron::from_str::<Quantizer>(&s).unwrap(), q);
    }
    assert_eq!(
        ron::from_str::<Quantizer>("NeuQuant(sample_factor: 3)").unwrap(),
        Quantizer::NeuQuant { sample_factor: 3 }
    );
    assert!(ron::from_str::<Quantizer>("NeuQuant(sample_factor: 3, x: 1)").is_err());
    assert_eq!(
        ron::from_str::<Quantizer>("KMeans(start: Random(seed: 1), max_iterations: 20)").unwrap(),
        KM
    );
    assert_eq!(
        ron::from_str::<Quantizer>("KMeans(start: MedianCut, max_iterations: 3)").unwrap(),
        KMC
    );
    assert!(ron::from_str::<Quantizer>("KMeans(start: MedianCut)").is_err());
}

#[test]
fn angular_error_in_degrees() {
    let a = [DVec3::Z, DVec3::X, DVec3::new(1.0, 0.0, 1.0)];
    let b = [DVec3::Z, DVec3::Y * 2.0, DVec3::Z];
    let (mean, max) = angular_error_deg(&a, &b);
    assert!((max - 90.0).abs() < 1e-12);
    assert!((mean - 45.0).abs() < 1e-12);
    assert_eq!(angular_error_deg(&[], &[]), (0.0, 0.0));
    // accurate for tiny angles, where acos(dot) is not
    let t = 1e-9f64;
    let (m, _) = angular_error_deg(&[DVec3::Z], &[DVec3::new(t.sin(), 0.0, t.cos())]);
    assert!((m - t.to_degrees()).abs() < 1e-18);
}

/// Mean over `b x b` blocks, renormalised (the map seen minified).
pub(crate) fn block_means(v: &[DVec3], w: usize, b: usize) -> Vec<DVec3> {
    let h = v.len() / w;
    let mut out = Vec::new();
    for by in 0..h / b {
        for bx in 0..w / b {
            let mut s = DVec3::ZERO;
            for y in 0..b {
                for x in 0..b {
                    s += v[(by * b + y) * w + bx * b + x];
                }
            }
            out.push(s.normalize());
        }
    }
    out
}

/// The numbers quoted in the report: Mexican hat at 128x128 (4 cells as in configs/, and 3
/// cells, which has no repeated normals), both quantizers, with and without Floyd–Steinberg
/// (serpentine). Per texel, and over 4x4 blocks (what dithering is for). Run with
/// `--nocapture` to see the table.
#[test]
fn mexican_hat_128_errors() {
    for cells in [4, 3] {
        let map = mexican_hat_cells(128, cells);
        let distinct = median_cut::median_cut(&map, MAX_PALETTE).len();
        eprintln!("Mexican hat, {cells} cells, 128x128: {distinct} distinct normals");
        assert_eq!(distinct, if cells == 4 { 1024 } else { 16384 });
        let blocks = block_means(&map, 128, 4);
        let mut rows = Vec::new();
        for (name, q) in [
            ("MedianCut", Quantizer::MedianCut),
            ("NeuQuant(1)", Quantizer::NeuQuant { sample_factor: 1 }),
            ("KMeans(1,20)", KM),
            ("KMeans(MC,3)", KMC),
        ] {
            for s_n in [16, 256, 2048] {
                let p = match quantize(&map, s_n, q) {
                    Ok(p) => p,
                    Err(e) => {
                        assert_eq!(e, QuantizeError::NeuQuantTooLarge(s_n));
                        eprintln!("{name:12} s_n={s_n:5} {e}");
                        continue;
                    }
                };
                let plain = p.decode();
                let dith = decode(
                    &p.entries,
                    &dither(&map, 128, 128, &p.entries, Scan::Serpentine),
                );
                let e = angular_error_deg(&plain, &map);
                let d = angular_error_deg(&dith, &map);
                let eb = angular_error_deg(&block_means(&plain, 128, 4), &blocks).0;
                let db = angular_error_deg(&block_means(&dith, 128, 4), &blocks).0;
                eprintln!(
                    "{name:12} s_n={s_n:5} entries={:5} plain mean {:.3} max {:.3} | dithered mean {:.3} max {:.3} | 4x4 blocks plain {:.3} dithered {:.3} (deg)",
                    p.entries.len(), e.0, e.1, d.0, d.1, eb, db
                );
                rows.push((name, s_n, e, d, eb, db));
            }
        }
        let mc: Vec<_> = rows.iter().filter(|r| r.0 == "MedianCut").collect();
        // more entries, smaller error
        assert!(mc[0].2 .0 > mc[1].2 .0 && mc[1].2 .0 > mc[2].2 .0);
        let km: Vec<_> = rows.iter().filter(|r| r.0 == "KMeans(1,20)").collect();
        assert!(km[0].2 .0 > km[1].2 .0 && km[1].2 .0 > km[2].2 .0, "{km:?}");
        // refining median cut never does worse than median cut on the mean
        let kmc: Vec<_> = rows.iter().filter(|r| r.0 == "KMeans(MC,3)").collect();
        for (a, b) in kmc.iter().zip(&mc) {
            assert!(a.2 .0 <= b.2 .0 + 1e-9, "{a:?} vs {b:?}");
        }
        // median cut, 256 entries: under a degree on average
        assert!(mc[1].2 .0 < 1.0, "{:?}", mc[1]);
        for r in &rows {
            // dithering trades per-texel error for block error, once the table covers the
            // map (s_n >= 256); with 16 entries the extreme normals lie outside the table's
            // hull and the diffused error winds up
            assert!(r.3 .0 >= r.2 .0, "{r:?}");
            if r.1 >= 256 && r.4 > 0.0 {
                assert!(r.5 < r.4, "{r:?}");
            }
        }
    }
}

/// 256x256 normals (3 cells: no repeated normals within a cell) to 16384 entries by k-means:
/// the timing quoted in the module docs. Slow in debug builds; run with
/// `cargo test --release -p bumpsim-pipeline --lib kmeans_256_to_16k -- --ignored --nocapture`.
#[test]
#[ignore = "timing, run in release"]
fn kmeans_256_to_16k_timing() {
    for cells in [4, 3] {
        let map = mexican_hat_cells(256, cells);
        for (name, q) in [("KMeans(1,20)", KM), ("KMeans(MC,3)", KMC)] {
            let t = std::time::Instant::now();
            let p = quantize(&map, MAX_PALETTE, q).unwrap();
            let dt = t.elapsed();
            let (mean, max) = angular_error_deg(&p.decode(), &map);
            eprintln!(
                "{name} 256x256 {cells} cells -> {} entries in {dt:?}: mean {mean:.4} max {max:.3} deg",
                p.entries.len()
            );
            assert!(p.entries.len() <= MAX_PALETTE);
        }
    }
}

#[test]
fn exact_keeps_every_distinct_normal_bit_for_bit() {
    // 4 cells at 128x128: 1024 distinct normals
    let n = mexican_hat(128);
    let distinct: std::collections::HashSet<[u64; 3]> =
        n.iter().map(|v| v.to_array().map(f64::to_bits)).collect();
    assert_eq!(distinct.len(), 1024);
    let p = quantize(&n, 1024, Quantizer::Exact).unwrap();
    assert_eq!(p.entries.len(), 1024);
    // every texel reads its own normal back, bit for bit
    assert!(p
        .decode()
        .iter()
        .zip(&n)
        .all(|(a, b)| a.to_array() == b.to_array()));
    assert_eq!(angular_error_deg(&p.decode(), &n), (0.0, 0.0));
    // entries in order of first appearance
    assert_eq!(p.entries[0].to_array(), n[0].to_array());
    assert_eq!(p.indices[0], 0);
    // dithering has nothing to diffuse
    let d = quantize_dithered(&n, 128, 128, 4096, Quantizer::Exact, Scan::Serpentine).unwrap();
    assert_eq!(d, p);
    // a table too small for the map, and one above 65536 entries
    assert_eq!(
        quantize(&n, 1023, Quantizer::Exact),
        Err(QuantizeError::ExactTooSmall {
            distinct: 1024,
            s_n: 1023
        })
    );
    assert_eq!(
        quantize(&n, 65537, Quantizer::Exact),
        Err(QuantizeError::PaletteSize(65537))
    );
    // the other quantizers keep their 16384 limit
    assert_eq!(
        quantize(&n, 16385, Quantizer::MedianCut),
        Err(QuantizeError::PaletteSize(16385))
    );
}
