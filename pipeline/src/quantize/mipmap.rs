//! Mipmaps of index textures (Tarini §5.2): the levels "cannot be computed by the renderer as
//! usual, since that texture consists of indexes, that cannot be directly averaged". The
//! "average" of 4 texels is "the index in N that best approximates the average of the 4
//! normals N(t1), ..., N(t4)".

use super::{NearestIndex, QuantizeError};
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// How 2x2 texels of indices become one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum MipMode {
    /// Tarini §5.2: the entry nearest (largest dot product, ties to the lower index) to the
    /// mean of the 4 normals.
    NearestToAverage,
    /// What a renderer does with an ordinary texture: the rounded mean of the 4 indices
    /// (`(a + b + c + d + 2) / 4`). Wrong: neighbouring indices need not be neighbouring
    /// normals. Kept to measure how wrong.
    NaiveIndexAverage,
}

/// The next level of a `w x h` row-major index map: `max(w/2, 1) x max(h/2, 1)`, texel
/// `(x, y)` from the 2x2 block at `(2x, 2y)` (an odd last row or column is dropped, as GL
/// does; a dimension of 1 repeats its texel). Returns `(indices, w', h')`.
/// Errors: `indices.len() != w * h`, an index outside `palette`.
pub fn mip_indices(
    indices: &[u32],
    w: usize,
    h: usize,
    palette: &[DVec3],
    mode: MipMode,
) -> Result<(Vec<u32>, usize, usize), QuantizeError> {
    if indices.len() != w * h {
        return Err(QuantizeError::Length {
            what: "indices",
            expected: w * h,
            found: indices.len(),
        });
    }
    if let Some(&index) = indices.iter().find(|&&i| i as usize >= palette.len()) {
        return Err(QuantizeError::Index {
            index,
            len: palette.len(),
        });
    }
    let (w2, h2) = ((w / 2).max(1), (h / 2).max(1));
    let mut out = Vec::with_capacity(w2 * h2);
    let search = NearestIndex::of(palette);
    for y in 0..h2 {
        for x in 0..w2 {
            let q = block(indices, w, h, x, y);
            out.push(match mode {
                MipMode::NearestToAverage => {
                    let avg = q.iter().fold(DVec3::ZERO, |s, &i| s + palette[i as usize]) / 4.0;
                    search.nearest(avg)
                }
                MipMode::NaiveIndexAverage => {
                    ((q.iter().map(|&i| u64::from(i)).sum::<u64>() + 2) / 4) as u32
                }
            });
        }
    }
    Ok((out, w2, h2))
}

/// The 4 indices under texel `(x, y)` of the next level.
pub fn block(indices: &[u32], w: usize, h: usize, x: usize, y: usize) -> [u32; 4] {
    let (x0, x1) = (2 * x, (2 * x + 1).min(w - 1));
    let (y0, y1) = (2 * y, (2 * y + 1).min(h - 1));
    [
        indices[y0 * w + x0],
        indices[y0 * w + x1],
        indices[y1 * w + x0],
        indices[y1 * w + x1],
    ]
}

#[cfg(test)]
mod tests {
    use super::super::{angular_error_deg, quantize, Quantizer};
    use super::*;
    use crate::quantize::tests::mexican_hat;

    /// The true level: the normalised mean of the 4 normals below.
    fn true_level(idx: &[u32], w: usize, h: usize, p: &[DVec3]) -> Vec<DVec3> {
        let mut v = Vec::new();
        for y in 0..h / 2 {
            for x in 0..w / 2 {
                let s = block(idx, w, h, x, y)
                    .iter()
                    .fold(DVec3::ZERO, |s, &i| s + p[i as usize]);
                v.push(s.normalize());
            }
        }
        v
    }

    #[test]
    fn nearest_to_average_matches_brute_force() {
        let map = mexican_hat(64);
        let p = quantize(&map, 64, Quantizer::MedianCut).unwrap();
        let (l1, w, h) =
            mip_indices(&p.indices, 64, 64, &p.entries, MipMode::NearestToAverage).unwrap();
        assert_eq!((w, h, l1.len()), (32, 32, 1024));
        // independent brute force: the first entry with the largest dot product with the mean
        let mut k = 0;
        for y in 0..32 {
            for x in 0..32 {
                let q = block(&p.indices, 64, 64, x, y);
                let avg = q
                    .iter()
                    .fold(DVec3::ZERO, |s, &i| s + p.entries[i as usize])
                    / 4.0;
                let dots: Vec<f64> = p.entries.iter().map(|e| avg.dot(*e)).collect();
                let best = dots.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                let first = dots.iter().position(|&d| d == best).unwrap();
                assert_eq!(l1[k] as usize, first, "texel ({x}, {y})");
                k += 1;
            }
        }
        // down to 1x1, shapes as GL's
        let mut cur = (l1, 32usize, 32usize);
        while cur.1 * cur.2 > 1 {
            cur = mip_indices(&cur.0, cur.1, cur.2, &p.entries, MipMode::NearestToAverage).unwrap();
        }
        assert_eq!(cur.0.len(), 1);
        let (l, w, h) =
            mip_indices(&[0, 1, 1], 3, 1, &p.entries, MipMode::NearestToAverage).unwrap();
        assert_eq!((l.len(), w, h), (1, 1, 1));
    }

    #[test]
    fn naive_index_average_is_much_worse() {
        let map = mexican_hat(64);
        let p = quantize(&map, 64, Quantizer::MedianCut).unwrap();
        let truth = true_level(&p.indices, 64, 64, &p.entries);
        let err = |mode| {
            let (l, _, _) = mip_indices(&p.indices, 64, 64, &p.entries, mode).unwrap();
            let v: Vec<DVec3> = l.iter().map(|&i| p.entries[i as usize]).collect();
            angular_error_deg(&v, &truth)
        };
        let (good, good_max) = err(MipMode::NearestToAverage);
        let (naive, naive_max) = err(MipMode::NaiveIndexAverage);
        eprintln!("mip level 1 of a 64-entry median-cut Mexican hat: nearest-to-average mean {good:.3} max {good_max:.3} deg, naive {naive:.3} max {naive_max:.3} deg");
        assert!(good < 5.0, "{good}");
        assert!(naive > 3.0 * good, "naive {naive} vs {good}");
        assert!(naive_max > good_max);
    }

    #[test]
    fn mip_errors() {
        let p = [DVec3::Z, DVec3::X];
        assert!(mip_indices(&[0, 1, 0], 2, 2, &p, MipMode::NearestToAverage).is_err());
        assert_eq!(
            mip_indices(&[0, 1, 2, 0], 2, 2, &p, MipMode::NaiveIndexAverage),
            Err(QuantizeError::Index { index: 2, len: 2 })
        );
        assert_eq!(
            mip_indices(&[0, 1, 1, 1], 2, 2, &p, MipMode::NaiveIndexAverage)
                .unwrap()
                .0,
            vec![1]
        );
    }
}
