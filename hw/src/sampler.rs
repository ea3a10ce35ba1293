//! Texel addressing shared by the units that read textures: from a fixed-point texture
//! coordinate to a texel index and filter weight on one axis, and what happens to an index
//! outside the texture ([`Address`]). Texture sizes are powers of two, so the texel address
//! is a shift of the coordinate (an arithmetic shift: negative coordinates floor, as the
//! hardware's two's-complement shifter does).

/// What happens to a texel address outside the texture, per axis (OpenGL's texture wrap
/// modes: REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize, Default)]
pub enum Address {
    /// The texture repeats: texel `i mod n`.
    #[default]
    Wrap,
    /// The edge texel repeats: texel `clamp(i, 0, n - 1)`; a coordinate of exactly 1 reads
    /// the last texel (as lookup tables indexed by a dot product need).
    Clamp,
    /// The texture repeats mirrored every other period.
    Mirror,
}

impl Address {
    /// Texel index along an axis of `n` texels.
    #[inline]
    pub fn apply(self, i: i64, n: i64) -> i64 {
        match self {
            Address::Wrap => i.rem_euclid(n),
            Address::Clamp => i.clamp(0, n - 1),
            Address::Mirror => {
                let m = i.rem_euclid(2 * n);
                if m >= n {
                    2 * n - 1 - m
                } else {
                    m
                }
            }
        }
    }
}

/// Texel position along one axis of `2^log` texels for a coordinate `raw` with `frac`
/// fraction bits (`frac >= log`, and `frac > log` when `centered`): `s = c * size - 1/2` when `centered` (bilinear filtering: the
/// taps around the sample point), `c * size` otherwise (nearest, or a filter over whole texels);
/// returns (integer part, fraction raw with `frac - log` bits).
#[inline]
pub fn texel_axis(raw: i64, frac: u32, log: u32, centered: bool) -> (i64, i64) {
    let f = frac - log; // fraction bits left after multiplying by 2^log
    let mut s = raw as i128;
    if centered {
        s -= 1i128 << (f - 1);
    }
    ((s >> f) as i64, (s & ((1i128 << f) - 1)) as i64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn address_modes_fold_every_index_of_three_periods() {
        for n in [1i64, 2, 4, 8] {
            for i in -3 * n..3 * n {
                let w = Address::Wrap.apply(i, n);
                assert_eq!(w, ((i % n) + n) % n);
                assert_eq!(Address::Clamp.apply(i, n), i.max(0).min(n - 1));
                // mirrored repeat: 0 1 .. n-1 n-1 .. 1 0 0 1 ..
                let period = i.div_euclid(n);
                let m = Address::Mirror.apply(i, n);
                assert_eq!(
                    m,
                    if period % 2 == 0 { w } else { n - 1 - w },
                    "n {n} i {i}"
                );
            }
        }
    }

    #[test]
    fn the_axis_floors_negative_coordinates_and_keeps_the_fraction() {
        // 4 fraction bits, 2 texels (log 1): one texel = 8 raw steps
        for raw in -40i64..40 {
            let (i, f) = texel_axis(raw, 4, 1, false);
            assert_eq!((i, f), (raw.div_euclid(8), raw.rem_euclid(8)), "raw {raw}");
            let (i, f) = texel_axis(raw, 4, 1, true);
            assert_eq!(
                (i, f),
                ((raw - 4).div_euclid(8), (raw - 4).rem_euclid(8)),
                "raw {raw}"
            );
        }
    }
}
