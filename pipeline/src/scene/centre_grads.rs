//! Height-field gradients at the texel centres of a map, each distinct one evaluated once.
//!
//! The lattice fields (Mexican hats, sphere caps) depend on a point only through its
//! fractions within a cell, `fx = frac(u · cells)` and `fy = frac(v · cells)`. At the texel
//! centres `u = (i + 0.5) / w` of a map whose size is not a multiple of the cell count,
//! the centres of many columns fall at the same fraction (a 256-texel map over 6 cells has
//! 128 distinct ones), so the `w x h` gradients of a bake take only `|fx| x |fy|`
//! evaluations. Each is the field's own function of the same `(fx, fy)` bits, so the
//! gradients are bit for bit those of one `grad` per texel.

use glam::DVec2;

/// Gradients at the texel centres `((i + 0.5)/w, (j + 0.5)/h)` of a `w x h` map, stored as
/// a grid over the distinct column and row fractions.
#[derive(Debug, Clone, PartialEq)]
pub struct CentreGrads {
    /// Per column `i`, the index of its fraction among the distinct ones.
    col: Vec<u32>,
    /// Per row `j`, likewise.
    row: Vec<u32>,
    /// Distinct column fractions.
    nx: usize,
    /// `g[r * nx + c]`: the gradient at distinct fractions `(c, r)`.
    g: Vec<DVec2>,
}

impl CentreGrads {
    /// The gradient at the centre of texel `(i, j)`; None outside the map.
    pub fn at(&self, i: u32, j: u32) -> Option<DVec2> {
        let c = *self.col.get(i as usize)? as usize;
        let r = *self.row.get(j as usize)? as usize;
        self.g.get(r * self.nx + c).copied()
    }

    /// The grid for a field with `grad(u, v) = f(frac(u · cells), frac(v · cells))`, where
    /// `split` is the field's own split of a coordinate into its cell fraction; None when
    /// the grid would hold more than half as many gradients as the map (no saving worth the
    /// memory). Evaluated in parallel by rows, each entry a pure function of its fractions.
    pub fn lattice(
        w: u32,
        h: u32,
        split: impl Fn(f64) -> f64,
        f: impl Fn(f64, f64) -> DVec2 + Sync,
    ) -> Option<CentreGrads> {
        use rayon::prelude::*;
        let (xs, col) = distinct(w, &split);
        let (ys, row) = distinct(h, &split);
        if xs.len() * ys.len() > w as usize * h as usize / 2 {
            return None;
        }
        let g = ys
            .par_iter()
            .flat_map_iter(|&fy| xs.iter().map(move |&fx| (fx, fy)))
            .map(|(fx, fy)| f(fx, fy))
            .collect();
        Some(CentreGrads {
            col,
            row,
            nx: xs.len(),
            g,
        })
    }
}

/// The distinct fractions of the `n` texel centres `(k + 0.5) / n` (compared by their bits,
/// sorted) and, per texel, the index of its own.
fn distinct(n: u32, split: &impl Fn(f64) -> f64) -> (Vec<f64>, Vec<u32>) {
    let fr: Vec<f64> = (0..n)
        .map(|k| split((f64::from(k) + 0.5) / f64::from(n)))
        .collect();
    let mut bits: Vec<u64> = fr.iter().map(|x| x.to_bits()).collect();
    bits.sort_unstable();
    bits.dedup();
    let index = fr
        .iter()
        .map(|x| bits.binary_search(&x.to_bits()).unwrap_or(0) as u32)
        .collect();
    (bits.into_iter().map(f64::from_bits).collect(), index)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distinct_fractions_of_a_256_map_over_6_cells() {
        let split = |x: f64| (x * 6.0).fract();
        let (xs, idx) = distinct(256, &split);
        // (6 i + 3) mod 256 over 256: the 128 odd residues.
        assert_eq!(xs.len(), 128);
        for (k, &i) in idx.iter().enumerate() {
            assert_eq!(xs[i as usize], split((k as f64 + 0.5) / 256.0));
        }
    }

    #[test]
    fn lattice_matches_the_function_at_every_centre_and_declines_when_no_saving() {
        let split = |x: f64| (x * 6.0).fract();
        let f = |fx: f64, fy: f64| DVec2::new(fx.sin() * fy, fy.cos() - fx);
        let g = CentreGrads::lattice(256, 100, split, f).expect("a saving");
        for j in 0..100 {
            for i in 0..256 {
                let (u, v) = ((i as f64 + 0.5) / 256.0, (j as f64 + 0.5) / 100.0);
                let want = f(split(u), split(v));
                assert_eq!(
                    g.at(i, j).map(|x| x.to_array().map(f64::to_bits)),
                    Some(want.to_array().map(f64::to_bits)),
                    "texel ({i}, {j})"
                );
            }
        }
        assert_eq!(g.at(256, 0), None);
        assert_eq!(g.at(0, 100), None);
        // 7 texels over 6 cells: every fraction distinct, no grid.
        assert_eq!(CentreGrads::lattice(7, 7, split, f), None);
    }
}
