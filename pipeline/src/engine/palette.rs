//! Bump-normal palettes (Ernst et al. 1998 §6, "palletized bumps"): a fixed table of surface
//! orientations and the nearest-entry quantization of a normal map to it.
//!
//! The paper gives no table; bumpsim spreads `n` unit vectors evenly over the upper hemisphere
//! with a Fibonacci spiral (equal-area rings, golden-angle turns), always including the
//! unperturbed normal (0, 0, 1) as entry 0 so that flat texels stay exact. Quantizers that
//! adapt the table to the map belong to the quantized-normal-map engine (Tarini et al.).

use crate::quantize::NearestIndex;
use glam::DVec3;

/// `n` unit vectors over the hemisphere z >= 0, entry 0 = (0, 0, 1).
pub fn hemisphere(n: usize) -> Vec<[f64; 4]> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut v = vec![[0.0, 0.0, 1.0, 0.0]];
    let m = n.saturating_sub(1);
    for i in 0..m {
        // z from just below 1 down to 0, equal area steps
        let z = 1.0 - (i as f64 + 0.5) / m as f64;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let a = golden * i as f64;
        v.push([r * a.cos(), r * a.sin(), z, 0.0]);
    }
    v.truncate(n);
    v
}

/// At most `n` unit entries fitted to the map's texels by Heckbert's median cut (the
/// quantized-normal engine's quantizer, [`crate::quantize::median_cut::median_cut`]): entries where the
/// map's normals are, none where it has none. Errors name a texel that is not a finite,
/// non-zero normal.
pub fn median_cut(texels: &[[f64; 4]], n: usize) -> Result<Vec<[f64; 4]>, String> {
    let normals: Vec<DVec3> = texels
        .iter()
        .map(|t| DVec3::new(t[0], t[1], t[2]))
        .collect();
    if let Some(i) = normals
        .iter()
        .position(|v| !v.is_finite() || v.length_squared() == 0.0)
    {
        return Err(format!(
            "palette_table MedianCut: texel {i} is not a finite, non-zero normal"
        ));
    }
    let unit: Vec<DVec3> = normals.iter().map(|v| v.normalize()).collect();
    Ok(crate::quantize::median_cut::median_cut(&unit, n)
        .into_iter()
        .map(|e| [e.x, e.y, e.z, 0.0])
        .collect())
}

/// Replace every texel by the palette entry with the largest dot product (the nearest
/// direction); ties go to the lower index. The search is the exact k-d tree of the quantized
/// normal maps ([`NearestIndex`]: the brute-force answer bit for bit), texels in parallel.
pub fn quantize(texels: &mut [[f64; 4]], palette: &[[f64; 4]]) {
    use rayon::prelude::*;
    let p: Vec<DVec3> = palette
        .iter()
        .map(|e| DVec3::new(e[0], e[1], e[2]))
        .collect();
    let index = NearestIndex::of(&p);
    texels.par_iter_mut().for_each(|t| {
        *t = palette[index.nearest(DVec3::new(t[0], t[1], t[2])) as usize];
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hemisphere_entries_are_unit_upper_and_spread() {
        let h = hemisphere(256);
        assert_eq!(h.len(), 256);
        assert_eq!(h[0], [0.0, 0.0, 1.0, 0.0]);
        for e in &h {
            let l = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
            assert!((l - 1.0).abs() < 1e-12 && e[2] >= 0.0);
        }
        // the largest gap: every direction of a fine sample is within 9 degrees of an entry
        let mut worst: f64 = 1.0;
        for i in 0..2000 {
            let z = (i as f64 + 0.5) / 2000.0;
            let a = i as f64 * 2.399;
            let d = DVec3::new(
                (1.0 - z * z).sqrt() * a.cos(),
                (1.0 - z * z).sqrt() * a.sin(),
                z,
            );
            let best = h
                .iter()
                .map(|e| d.dot(DVec3::new(e[0], e[1], e[2])))
                .fold(-1.0, f64::max);
            worst = worst.min(best);
        }
        assert!(
            worst > 9f64.to_radians().cos(),
            "largest gap {} degrees",
            worst.acos().to_degrees()
        );
    }

    #[test]
    fn quantize_is_the_brute_force_answer_on_every_texel() {
        for n in [1usize, 2, 16, 256, 4096] {
            let pal = hemisphere(n);
            // texels on a grid over the hemisphere and below it, some on entries exactly
            let mut t: Vec<[f64; 4]> = (0..4000)
                .map(|i| {
                    let (a, z) = (i as f64 * 0.7, (i % 97) as f64 / 48.0 - 1.0);
                    let r = (1.0 - z * z).max(0.0).sqrt();
                    [r * a.cos(), r * a.sin(), z, 0.0]
                })
                .chain(pal.iter().copied())
                .collect();
            let want: Vec<[f64; 4]> = t
                .iter()
                .map(|v| {
                    let d = DVec3::new(v[0], v[1], v[2]);
                    let mut best = (f64::NEG_INFINITY, 0);
                    for (i, e) in pal.iter().enumerate() {
                        let s = d.dot(DVec3::new(e[0], e[1], e[2]));
                        if s > best.0 {
                            best = (s, i);
                        }
                    }
                    pal[best.1]
                })
                .collect();
            quantize(&mut t, &pal);
            assert_eq!(t, want, "{n} entries");
        }
    }

    #[test]
    fn quantize_picks_the_nearest_entry() {
        let p = vec![
            [0.0, 0.0, 1.0, 0.0],
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
        ];
        let mut t = vec![
            [0.1, 0.0, 0.99, 0.0],
            [0.8, 0.1, 0.5, 0.0],
            [0.0, 0.9, 0.3, 0.0],
        ];
        quantize(&mut t, &p);
        assert_eq!(t, vec![p[0], p[1], p[2]]);
    }

    #[test]
    fn a_fitted_palette_holds_a_map_of_few_normals_exactly() {
        // three distinct normals, in unequal numbers: median cut with room for them keeps each
        // one (a box per normal), so every texel reads its own normal back; the fixed
        // hemisphere of the same size does not
        let n = [
            [0.0, 0.0, 1.0, 0.0],
            [0.6, 0.0, 0.8, 0.0],
            [0.0, -0.28, 0.96, 0.0],
        ];
        let map: Vec<[f64; 4]> = (0..60).map(|i| n[(i * i) % 7 % 3]).collect();
        let fitted = median_cut(&map, 4).unwrap();
        assert!(fitted.len() <= 4);
        let mut t = map.clone();
        quantize(&mut t, &fitted);
        for (q, want) in t.iter().zip(&map) {
            for c in 0..3 {
                assert!((q[c] - want[c]).abs() < 1e-12, "{q:?} for {want:?}");
            }
        }
        let mut h = map.clone();
        quantize(&mut h, &hemisphere(4));
        let off =
            |q: &[f64; 4], w: &[f64; 4]| (0..3).map(|c| (q[c] - w[c]).abs()).fold(0.0, f64::max);
        assert!(h.iter().zip(&map).any(|(q, w)| off(q, w) > 0.05));
        // a zero or non-finite texel is an error naming it
        let mut bad = map.clone();
        bad[7] = [0.0; 4];
        assert_eq!(
            median_cut(&bad, 4).unwrap_err(),
            "palette_table MedianCut: texel 7 is not a finite, non-zero normal"
        );
        bad[7] = [f64::NAN, 0.0, 1.0, 0.0];
        assert!(median_cut(&bad, 4).unwrap_err().contains("texel 7"));
    }
}
