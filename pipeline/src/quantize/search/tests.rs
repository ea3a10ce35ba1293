//! [`NearestIndex`] against the brute force [`nearest`]: every answer equal, on seeded random
//! tables and queries (unit, non-unit, axis-aligned, equal to entries, near ties, exact
//! duplicates, signed zeros, sub-ranges, 1 ..= 16384 entries) and through dithering.

use super::super::dither::{dither_in, dither_with};
use super::super::tests::mexican_hat_cells;
use super::super::{dither, nearest, quantize, quantize_dithered, Quantizer, Scan};
use super::super::{quantize_with_materials, quantize_with_materials_dithered};
use super::cells::Cells;
use super::*;
use rand_xoshiro::rand_core::{RngCore, SeedableRng};
use rand_xoshiro::Xoshiro256Plus;

/// A uniform f64 in `[0, 1)`.
fn uniform(rng: &mut Xoshiro256Plus) -> f64 {
    (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}

/// A uniform unit vector (normalised Gaussian-free: rejection from the cube).
fn unit(rng: &mut Xoshiro256Plus) -> DVec3 {
    loop {
        let v = DVec3::new(uniform(rng), uniform(rng), uniform(rng)) * 2.0 - DVec3::ONE;
        let l = v.length_squared();
        if l > 1e-6 && l <= 1.0 {
            return v.normalize();
        }
    }
}

/// A unit vector in the upper cone of normal maps (`z >= 0.5`), as bakes produce.
fn bump(rng: &mut Xoshiro256Plus) -> DVec3 {
    loop {
        let v = unit(rng);
        if v.z >= 0.5 {
            return v;
        }
    }
}

/// Every query through the index equals the brute force over `entries[range]`.
fn check(entries: &[DVec3], range: Range<usize>, queries: &[DVec3], what: &str) {
    let ix = NearestIndex::new(entries, range.clone());
    for (k, &v) in queries.iter().enumerate() {
        let want = nearest(v, entries, range.clone());
        let got = ix.nearest(v);
        assert_eq!(
            got,
            want,
            "{what}: query {k} {v:?}, range {range:?}, {} entries",
            entries.len()
        );
    }
}

/// Queries of every kind for a table: unit (sphere and cone), scaled, the entries themselves
/// (and scaled), axis-aligned, zero, tiny, huge, non-finite.
fn queries(rng: &mut Xoshiro256Plus, entries: &[DVec3], n: usize) -> Vec<DVec3> {
    let mut q = Vec::new();
    for _ in 0..n {
        q.push(unit(rng));
        q.push(bump(rng));
        // dithering targets: a normal plus diffused error, not unit
        q.push(bump(rng) + (DVec3::new(uniform(rng), uniform(rng), uniform(rng)) - 0.5) * 0.3);
        let scale = 10f64.powf(uniform(rng) * 12.0 - 6.0);
        q.push(unit(rng) * scale);
    }
    for &e in entries.iter().take(n) {
        q.extend([e, e * 3.0, -e, e * 1e-200]);
    }
    for a in [DVec3::X, DVec3::Y, DVec3::Z] {
        q.extend([a, -a, a * 7.5, a * 1e-310]);
    }
    q.extend([
        DVec3::ZERO,
        DVec3::new(-0.0, 0.0, -0.0),
        DVec3::splat(1e-320),
        DVec3::new(1e305, -1e305, 1e305),
        DVec3::new(f64::NAN, 0.0, 1.0),
        DVec3::new(f64::INFINITY, 0.0, 1.0),
        DVec3::new(0.0, f64::NEG_INFINITY, 0.0),
    ]);
    q
}

#[test]
fn index_equals_brute_force_on_random_unit_tables_of_every_size() {
    let mut rng = Xoshiro256Plus::seed_from_u64(16);
    let sizes: Vec<usize> = (1..=70)
        .chain([100, 333, 1000, 2048, 4097, 16384])
        .collect();
    for n in sizes {
        let cone = n % 2 == 0;
        let entries: Vec<DVec3> = (0..n)
            .map(|_| if cone { bump(&mut rng) } else { unit(&mut rng) })
            .collect();
        let count = if n >= 4096 { 150 } else { 300 };
        let q = queries(&mut rng, &entries, count);
        check(&entries, 0..n, &q, "unit table");
        assert_eq!(NearestIndex::of(&entries).is_tree(), n >= BRUTE_FORCE_BELOW);
    }
}

#[test]
fn index_equals_brute_force_with_duplicates_and_near_ties() {
    let mut rng = Xoshiro256Plus::seed_from_u64(17);
    for n in [40, 257, 3000] {
        // a few distinct normals, each repeated, shuffled: exact ties at different indices
        let distinct: Vec<DVec3> = (0..n / 4).map(|_| bump(&mut rng)).collect();
        let mut entries: Vec<DVec3> = (0..n).map(|i| distinct[i % distinct.len()]).collect();
        for i in (1..n).rev() {
            entries.swap(i, rng.next_u64() as usize % (i + 1));
        }
        let q = queries(&mut rng, &entries, 300);
        check(&entries, 0..n, &q, "duplicates");
        // a tight cluster: neighbours a few ulps apart, so scores tie or differ in the last
        // bits and pruning has no room
        let c = bump(&mut rng);
        let cluster: Vec<DVec3> = (0..n)
            .map(|_| {
                let d = DVec3::new(uniform(&mut rng), uniform(&mut rng), uniform(&mut rng));
                c + (d - 0.5) * 1e-15
            })
            .collect();
        let mut q = queries(&mut rng, &cluster, 300);
        q.extend((0..300).map(|_| c + (unit(&mut rng) * 1e-15)));
        check(&cluster, 0..n, &q, "cluster");
    }
    // axis-aligned and signed-zero entries: many equal scores for axis-aligned queries
    let mut grid = Vec::new();
    for x in [-1.0, -0.6, -0.0, 0.0, 0.6, 1.0] {
        for y in [-0.8, -0.0, 0.0, 0.8] {
            for z in [-0.0, 0.0, 0.5, 1.0] {
                grid.push(DVec3::new(x, y, z));
            }
        }
    }
    let q = queries(&mut rng, &grid, grid.len());
    check(&grid, 0..grid.len(), &q, "grid");
}

#[test]
fn index_equals_brute_force_on_sub_ranges() {
    let mut rng = Xoshiro256Plus::seed_from_u64(18);
    let entries: Vec<DVec3> = (0..5000).map(|_| bump(&mut rng)).collect();
    let mut ranges = vec![0..0, 7..7, 0..1, 4999..5000, 0..5000, 100..131, 100..132];
    for _ in 0..20 {
        let a = rng.next_u64() as usize % 5000;
        let b = a + rng.next_u64() as usize % (5000 - a + 1);
        ranges.push(a..b);
    }
    for r in ranges {
        let q = queries(&mut rng, &entries[r.clone()], 100);
        check(&entries, r.clone(), &q, "sub-range");
    }
}

#[test]
fn index_equals_brute_force_on_a_quantized_map() {
    // the real case: a median-cut table and the map's own normals
    let map = mexican_hat_cells(64, 3);
    for s_n in [16, 333, 2048] {
        let p = quantize(&map, s_n, Quantizer::MedianCut).unwrap();
        check(&p.entries, 0..p.entries.len(), &map, "median cut");
        let brute: Vec<u32> = map
            .iter()
            .map(|&n| nearest(n, &p.entries, 0..p.entries.len()))
            .collect();
        assert_eq!(p.indices, brute, "s_n {s_n}");
    }
}

#[test]
fn dithering_through_the_index_equals_dithering_by_brute_force() {
    let map = mexican_hat_cells(64, 3);
    for s_n in [16, 256, 2048] {
        let p = quantize(&map, s_n, Quantizer::MedianCut).unwrap();
        let n = p.entries.len();
        for scan in [Scan::Raster, Scan::Serpentine] {
            let brute = dither_with(
                &map,
                64,
                64,
                &p.entries,
                scan,
                |_| 0..n,
                |v, r| nearest(v, &p.entries, r),
            );
            assert_eq!(dither(&map, 64, 64, &p.entries, scan), brute, "s_n {s_n}");
            // two candidate ranges, one per half of the map
            let half = |i: usize| if i % 64 < 32 { 0..n / 2 } else { n / 2..n };
            let brute = dither_with(&map, 64, 64, &p.entries, scan, half, |v, r| {
                nearest(v, &p.entries, r)
            });
            assert_eq!(dither_in(&map, 64, 64, &p.entries, scan, half), brute);
        }
    }
}

#[test]
fn quantize_dithered_equals_quantize_then_dither() {
    let map = mexican_hat_cells(64, 4);
    let mats: Vec<u8> = map
        .iter()
        .enumerate()
        .map(|(i, n)| if i % 64 < 8 { 5 } else { u8::from(n.x > 0.0) })
        .collect();
    for s_n in [16, 256] {
        for q in [
            Quantizer::MedianCut,
            Quantizer::NeuQuant { sample_factor: 10 },
        ] {
            let mut p = quantize(&map, s_n, q).unwrap();
            p.indices = dither(&map, 64, 64, &p.entries, Scan::Serpentine);
            let d = quantize_dithered(&map, 64, 64, s_n, q, Scan::Serpentine).unwrap();
            assert_eq!(d, p);
            let mut mp = quantize_with_materials(&map, &mats, s_n, q).unwrap();
            mp.palette.indices = mp.dither(&map, &mats, 64, 64, Scan::Serpentine);
            let md =
                quantize_with_materials_dithered(&map, &mats, 64, 64, s_n, q, Scan::Serpentine)
                    .unwrap();
            assert_eq!(md, mp);
        }
    }
    assert!(quantize_dithered(&map, 64, 63, 16, Quantizer::MedianCut, Scan::Raster).is_err());
    assert!(quantize_with_materials_dithered(
        &map,
        &mats,
        63,
        64,
        16,
        Quantizer::MedianCut,
        Scan::Raster
    )
    .is_err());
}

#[test]
fn index_equals_brute_force_on_non_unit_entries() {
    let mut rng = Xoshiro256Plus::seed_from_u64(19);
    // lengths over ten decades, then whole tables scaled: the ball bound on and (beyond
    // 1e100) off, the linear bound and the brute-force fallback for huge scores
    let base: Vec<DVec3> = (0..700)
        .map(|_| unit(&mut rng) * 10f64.powf(uniform(&mut rng) * 10.0 - 5.0))
        .collect();
    for scale in [1.0, 1e-150, 1e50, 1e120, 1e200] {
        let entries: Vec<DVec3> = base.iter().map(|&e| e * scale).collect();
        let q = queries(&mut rng, &entries, 300);
        check(&entries, 0..entries.len(), &q, "non-unit");
        // a cluster of near-equal long entries
        let c = bump(&mut rng) * 3.0 * scale;
        let cluster: Vec<DVec3> = (0..200)
            .map(|_| c + unit(&mut rng) * (3e-15 * scale))
            .collect();
        let mut q = queries(&mut rng, &cluster, 200);
        q.extend((0..200).map(|_| c * 1e-3 + unit(&mut rng) * 1e-18 * scale));
        check(&cluster, 0..cluster.len(), &q, "long cluster");
    }
    // non-finite entries: the whole index answers by brute force
    let mut bad = base.clone();
    bad[5] = DVec3::new(f64::NAN, 0.0, 1.0);
    bad[9] = DVec3::new(f64::INFINITY, 0.0, 0.0);
    assert!(!NearestIndex::of(&bad).is_tree());
    let q = queries(&mut rng, &base, 100);
    check(&bad, 0..bad.len(), &q, "non-finite entries");
}

/// Every query through [`Cells`] equals the brute force over `entries[range]`, asked twice
/// (the first query of a cell builds its list, the second reads it).
fn check_cells(entries: &[DVec3], range: Range<usize>, queries: &[DVec3], what: &str) -> Cells {
    let ix = NearestIndex::new(entries, range.clone());
    let mut cells = Cells::new(&ix).unwrap_or_else(|| panic!("{what}: no cells"));
    for round in 0..2 {
        for (k, &v) in queries.iter().enumerate() {
            let want = nearest(v, entries, range.clone());
            assert_eq!(
                cells.nearest(&ix, v),
                want,
                "{what}: query {k} {v:?} (round {round}), range {range:?}, g {}",
                cells.side()
            );
        }
    }
    cells
}

/// Directions on the cells' boundaries, corners and the cube's edges and corners, exactly
/// and a few ulps off, for `g` cells per face side.
fn boundary_queries(g: usize) -> Vec<DVec3> {
    let mut q = Vec::new();
    let step = |k: usize| -1.0 + 2.0 * k as f64 / g as f64;
    for f in 0..3 {
        for sign in [1.0, -1.0] {
            for a in (0..=g).step_by((g / 7).max(1)) {
                for b in (0..=g).step_by((g / 5).max(1)) {
                    for d in [0.0, 1e-16, -1e-16, 1e-9] {
                        let mut v = DVec3::ZERO;
                        v[f] = sign;
                        v[(f + 1) % 3] = step(a) + d;
                        v[(f + 2) % 3] = step(b) - d;
                        q.push(v);
                        q.push(v.normalize());
                    }
                }
            }
        }
    }
    for x in [-1.0, 1.0] {
        for y in [-1.0, 1.0] {
            q.extend([
                DVec3::new(x, y, 1.0),
                DVec3::new(x, y, -1.0),
                DVec3::new(x, y, 0.0),
            ]);
            q.extend([DVec3::new(x, 0.0, y), DVec3::new(0.0, x, y)]);
        }
    }
    q
}

#[test]
fn cells_equal_brute_force_on_unit_tables() {
    let mut rng = Xoshiro256Plus::seed_from_u64(20);
    for n in [32, 33, 64, 100, 256, 1000, 2048, 4097] {
        for cone in [false, true] {
            let entries: Vec<DVec3> = (0..n)
                .map(|_| if cone { bump(&mut rng) } else { unit(&mut rng) })
                .collect();
            let mut q = queries(&mut rng, &entries, if n > 2000 { 150 } else { 400 });
            let g = Cells::new(&NearestIndex::of(&entries)).unwrap().side();
            q.extend(boundary_queries(g));
            let what = format!("{n} entries, cone {cone}");
            let cells = check_cells(&entries, 0..n, &q, &what);
            assert!(cells.built() > 0, "{what}");
        }
    }
}

#[test]
fn cells_equal_brute_force_with_ties_ranges_and_quantized_maps() {
    let mut rng = Xoshiro256Plus::seed_from_u64(21);
    // repeated unit entries: exact ties, answered with the lowest index
    let distinct: Vec<DVec3> = (0..60).map(|_| bump(&mut rng)).collect();
    let mut entries: Vec<DVec3> = (0..300).map(|i| distinct[i % 60]).collect();
    for i in (1..300).rev() {
        entries.swap(i, rng.next_u64() as usize % (i + 1));
    }
    let q = queries(&mut rng, &entries, 300);
    check_cells(&entries, 0..300, &q, "ties");
    // the axes and their opposites (queries between them tie exactly)
    let mut axes = vec![
        DVec3::X,
        DVec3::Y,
        DVec3::Z,
        -DVec3::X,
        -DVec3::Y,
        -DVec3::Z,
    ];
    axes = axes.iter().cycle().take(36).copied().collect();
    let mut q = queries(&mut rng, &axes, 100);
    q.extend(boundary_queries(
        Cells::new(&NearestIndex::of(&axes)).unwrap().side(),
    ));
    check_cells(&axes, 0..36, &q, "axes");
    // sub-ranges, as the materials' intervals
    let entries: Vec<DVec3> = (0..3000).map(|_| unit(&mut rng)).collect();
    for r in [0..3000, 100..200, 2500..3000, 7..40] {
        let q = queries(&mut rng, &entries[r.clone()], 200);
        check_cells(&entries, r, &q, "sub-range");
    }
    // median-cut tables and their maps' own normals plus diffused error
    let map = mexican_hat_cells(64, 3);
    for s_n in [64, 256, 2048] {
        let p = quantize(&map, s_n, Quantizer::MedianCut).unwrap();
        let mut q = map.clone();
        q.extend(map.iter().map(|&n| n + (unit(&mut rng) * 0.05)));
        check_cells(
            &p.entries,
            0..p.entries.len(),
            &q,
            &format!("median cut {s_n}"),
        );
    }
}

#[test]
fn cells_only_for_unit_tables_with_a_tree() {
    let mut rng = Xoshiro256Plus::seed_from_u64(22);
    let unit_table: Vec<DVec3> = (0..500).map(|_| unit(&mut rng)).collect();
    assert!(Cells::new(&NearestIndex::of(&unit_table)).is_some());
    // too small for a tree: brute force, no cells
    assert!(Cells::new(&NearestIndex::of(&unit_table[..20])).is_none());
    // one entry off unit length by more than 1e-12
    let mut off = unit_table.clone();
    off[7] *= 1.0 + 1e-11;
    assert!(Cells::new(&NearestIndex::of(&off)).is_none());
    let scaled: Vec<DVec3> = unit_table.iter().map(|&e| e * 2.0).collect();
    assert!(Cells::new(&NearestIndex::of(&scaled)).is_none());
    // cells per side follow the spread: a tight cone gets finer cells than the sphere
    let cone: Vec<DVec3> = (0..500)
        .map(|_| (DVec3::Z + unit(&mut rng) * 0.05).normalize())
        .collect();
    let (gs, gc) = (
        Cells::new(&NearestIndex::of(&unit_table)).unwrap().side(),
        Cells::new(&NearestIndex::of(&cone)).unwrap().side(),
    );
    assert!(gc > 4 * gs, "sphere {gs}, cone {gc}");
}
