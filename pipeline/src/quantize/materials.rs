//! Multiple lighting models in one table (Tarini §6): the (material, normal) pairs are sorted
//! by material once, in preprocessing, and the material field is thrown away "keeping record
//! only of the intervals", so that the colour table `C` is evaluated per interval without a
//! per-entry branch.
//!
//! bumpsim gives every material its own palette: the present materials share `s_n` entries in
//! proportion to their texel counts (largest remainder, at least one each), each material's
//! normals are quantized with its share, and the tables are concatenated in material order.
//! A texel maps to the nearest entry *of its material's interval*. This is the effect Tarini
//! asks for when treating the material as "a fourth, discrete component of the normal": a
//! normal that is mostly metal gets its entries in the metal interval. A material's
//! interval may be shorter than its share (median cut stops at one entry per distinct normal).

use super::{build_table, check_map, check_normals, dither::dither_in, Palette, Quantizer};
use super::{NearestIndex, QuantizeError, Scan, MAX_PALETTE};
use glam::DVec3;
use std::ops::Range;

// Material ids are `0..MAX_MATERIALS`, a number the scene defines (Tarini §6).
pub use crate::scene::material::MAX_MATERIALS;

/// A table sorted by material.
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialPalette {
    /// Entries of all materials; `indices` index it.
    pub palette: Palette,
    /// `intervals[m]`: the entries of material `m`, for `m` up to the largest id present;
    /// contiguous, disjoint, in material order, covering `0..palette.entries.len()`. An
    /// absent material has an empty interval.
    pub intervals: Vec<Range<usize>>,
}

impl MaterialPalette {
    /// Floyd–Steinberg dithered indices ([`super::dither()`]) with every texel kept in its
    /// material's interval; error is not diffused across materials. Panics on size
    /// mismatches (programming errors).
    pub fn dither(
        &self,
        normals: &[DVec3],
        materials: &[u8],
        w: usize,
        h: usize,
        scan: Scan,
    ) -> Vec<u32> {
        assert_eq!(materials.len(), normals.len(), "materials per texel");
        dither_in(normals, w, h, &self.palette.entries, scan, |i| {
            self.intervals[materials[i] as usize].clone()
        })
    }
}

/// Shares of `s_n` proportional to `counts` (largest remainder, ties to the lower material),
/// at least 1 for every non-zero count, 0 for zero counts; they sum to `s_n`
/// (`s_n >= number of non-zero counts`).
pub fn shares(counts: &[usize], s_n: usize) -> Vec<usize> {
    let present = counts.iter().filter(|&&c| c > 0).count();
    let total: usize = counts.iter().sum();
    let mut out: Vec<usize> = counts.iter().map(|&c| usize::from(c > 0)).collect();
    if present == 0 {
        return out;
    }
    let spare = s_n - present;
    // proportional split of the spare entries
    let mut rem: Vec<(u128, usize)> = Vec::new();
    let mut given = 0;
    for (m, &c) in counts.iter().enumerate() {
        if c == 0 {
            continue;
        }
        let num = spare as u128 * c as u128;
        out[m] += (num / total as u128) as usize;
        given += (num / total as u128) as usize;
        rem.push((num % total as u128, m));
    }
    rem.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
    for &(_, m) in rem.iter().take(spare - given) {
        out[m] += 1;
    }
    out
}

/// Quantize `normals` with one material id per texel (`materials[i] < 8`) to at most `s_n`
/// entries, one contiguous interval per material (Tarini §6). Errors as [`super::quantize`],
/// plus: lengths differ, a material id >= 8, fewer entries than materials present.
pub fn quantize_with_materials(
    normals: &[DVec3],
    materials: &[u8],
    s_n: usize,
    q: Quantizer,
) -> Result<MaterialPalette, QuantizeError> {
    let (entries, intervals) = tables(normals, materials, s_n, q)?;
    let search: Vec<NearestIndex> = intervals
        .iter()
        .map(|r| NearestIndex::new(&entries, r.clone()))
        .collect();
    let indices = normals
        .iter()
        .zip(materials)
        .map(|(&n, &m)| search[m as usize].nearest(n))
        .collect();
    Ok(MaterialPalette {
        palette: Palette { entries, indices },
        intervals,
    })
}

/// [`quantize_with_materials`] with the indices dithered ([`MaterialPalette::dither`]) of the
/// `w x h` row-major maps `normals` and `materials`: the same result as
/// `quantize_with_materials` followed by `mp.palette.indices = mp.dither(normals, materials,
/// w, h, scan)`, without the nearest-entry mapping that dithering replaces (every texel is
/// searched once). Errors as [`quantize_with_materials`], plus `normals.len() != w * h`.
pub fn quantize_with_materials_dithered(
    normals: &[DVec3],
    materials: &[u8],
    w: usize,
    h: usize,
    s_n: usize,
    q: Quantizer,
    scan: Scan,
) -> Result<MaterialPalette, QuantizeError> {
    check_map(normals.len(), w, h)?;
    let (entries, intervals) = tables(normals, materials, s_n, q)?;
    let mut mp = MaterialPalette {
        palette: Palette {
            entries,
            indices: Vec::new(),
        },
        intervals,
    };
    mp.palette.indices = mp.dither(normals, materials, w, h, scan);
    Ok(mp)
}

/// The concatenated tables and the intervals of [`quantize_with_materials`] (its checks).
fn tables(
    normals: &[DVec3],
    materials: &[u8],
    s_n: usize,
    q: Quantizer,
) -> Result<(Vec<DVec3>, Vec<Range<usize>>), QuantizeError> {
    if materials.len() != normals.len() {
        return Err(QuantizeError::Length {
            what: "materials",
            expected: normals.len(),
            found: materials.len(),
        });
    }
    if !(1..=q.max_entries().max(MAX_PALETTE)).contains(&s_n) {
        return Err(QuantizeError::PaletteSize(s_n));
    }
    check_normals(normals)?;
    if let Some(&m) = materials.iter().find(|&&m| m as usize >= MAX_MATERIALS) {
        return Err(QuantizeError::Material(m));
    }
    let top = *materials.iter().max().expect("non-empty") as usize;
    let mut counts = vec![0usize; top + 1];
    for &m in materials {
        counts[m as usize] += 1;
    }
    let present = counts.iter().filter(|&&c| c > 0).count();
    if s_n < present {
        return Err(QuantizeError::TooFewEntries {
            s_n,
            materials: present,
        });
    }
    let share = shares(&counts, s_n);
    let mut entries = Vec::new();
    let mut intervals = Vec::new();
    for (m, &k) in share.iter().enumerate() {
        let start = entries.len();
        if k > 0 {
            let mine: Vec<DVec3> = normals
                .iter()
                .zip(materials)
                .filter(|p| *p.1 as usize == m)
                .map(|p| *p.0)
                .collect();
            entries.extend(build_table(&mine, k, q)?);
        }
        intervals.push(start..entries.len());
    }
    Ok((entries, intervals))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quantize::tests::mexican_hat;

    #[test]
    fn shares_are_proportional_at_least_one_and_sum_to_s_n() {
        assert_eq!(shares(&[300, 100], 4), vec![3, 1]);
        assert_eq!(shares(&[1000, 1, 0, 1], 8), vec![6, 1, 0, 1]);
        assert_eq!(shares(&[0, 5], 3), vec![0, 3]);
        for s in [4, 7, 100, 16384] {
            let c = [17, 0, 4000, 3, 999];
            let v = shares(&c, s);
            assert_eq!(v.iter().sum::<usize>(), s);
            assert!(v.iter().zip(&c).all(|(&k, &n)| (n > 0) == (k > 0)));
        }
    }

    #[test]
    fn material_intervals_are_contiguous_and_hold_their_texels() {
        let map = mexican_hat(64);
        // material by orientation (Tarini Fig. 8: metal up, plastic down) plus a band of 5
        let mats: Vec<u8> = map
            .iter()
            .enumerate()
            .map(|(i, n)| if i % 64 < 8 { 5 } else { u8::from(n.x > 0.0) })
            .collect();
        for q in [
            Quantizer::MedianCut,
            Quantizer::NeuQuant { sample_factor: 10 },
        ] {
            let mp = quantize_with_materials(&map, &mats, 64, q).unwrap();
            let n = mp.palette.entries.len();
            assert!(n <= 64);
            assert_eq!(mp.intervals.len(), 6);
            // contiguous, disjoint, in order, covering the table
            let mut next = 0;
            for r in &mp.intervals {
                assert_eq!(r.start, next);
                next = r.end;
            }
            assert_eq!(next, n);
            for m in [2, 3, 4] {
                assert!(mp.intervals[m].is_empty());
            }
            for m in [0, 1, 5] {
                assert!(!mp.intervals[m].is_empty());
            }
            // every texel's entry in its material's interval, and the nearest one there
            for (i, (&k, &m)) in mp.palette.indices.iter().zip(&mats).enumerate() {
                let r = mp.intervals[m as usize].clone();
                assert!(r.contains(&(k as usize)), "texel {i}");
                let best = r
                    .clone()
                    .map(|j| map[i].dot(mp.palette.entries[j]))
                    .fold(f64::MIN, f64::max);
                assert_eq!(map[i].dot(mp.palette.entries[k as usize]), best);
            }
            let d = mp.dither(&map, &mats, 64, 64, Scan::Serpentine);
            for (&k, &m) in d.iter().zip(&mats) {
                assert!(mp.intervals[m as usize].contains(&(k as usize)));
            }
        }
        // shares follow the texel counts: material 5 has 1/8 of the texels
        let mp = quantize_with_materials(&map, &mats, 64, Quantizer::MedianCut).unwrap();
        let k = mp.intervals[5].len();
        assert!((8..=9).contains(&k), "{k}");
    }

    #[test]
    fn material_errors() {
        let n = vec![DVec3::Z; 4];
        let e = quantize_with_materials(&n, &[0, 1, 8, 0], 4, Quantizer::MedianCut);
        assert_eq!(e, Err(QuantizeError::Material(8)));
        let e = quantize_with_materials(&n, &[0, 1, 2, 3], 3, Quantizer::MedianCut);
        assert_eq!(
            e,
            Err(QuantizeError::TooFewEntries {
                s_n: 3,
                materials: 4
            })
        );
        assert!(quantize_with_materials(&n, &[0, 1], 4, Quantizer::MedianCut).is_err());
        let e = quantize_with_materials(&n, &[0; 4], 300, Quantizer::NeuQuant { sample_factor: 1 });
        assert_eq!(e, Err(QuantizeError::NeuQuantTooLarge(300)));
    }
}
