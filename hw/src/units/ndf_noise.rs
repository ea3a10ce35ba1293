//! Perlin's improved noise (Perlin 2002: fade `6t^5 - 15t^4 + 10t^3`, the 12 cube-edge
//! gradients padded to 16, a 256-entry permutation) on the plane `z = 0`, periodic, and its
//! fractal sum, the "turbulence function (i.e. fractal noise)" of Kautz et al. §4 that gives
//! the two random numbers `(r1, r2)`.
//!
//! Two modes behind one interface ([`Turbulence::eval`] with a [`NoiseMode`]):
//! * **exact**: f64;
//! * **bit-accurate**: integers. The position is a fixed-point word with `frac` fraction bits
//!   per lattice cell of the octave; the fade polynomial is evaluated exactly and rounded once
//!   to `frac` bits (halves up), the corner dot products are exact (gradients are 0, ±1), each
//!   of the three lerps is rounded once to `frac` bits, and octave `k`'s value is added
//!   scaled by `2^-k` (an exact shift of a word with `frac + octaves` fraction bits). The
//!   result is a word with `frac` fraction bits (the sum rounded once).
//!
//! The paper calls the fractal sum "Perlin turbulence"; Perlin's own `turbulence` sums
//! `|noise|`, whose distribution is one-sided, not the Gaussian-like one the paper measures.
//! bumpsim sums signed octaves (fBm), `Σ_k 2^-k n(2^k f u, 2^k f v)`: see
//! `docs/units/ndf.md`. The per-fragment generator of the software path is
//! [`super::ndf_turbulence::TurbulenceIndex`].

/// Ken Perlin's reference permutation (improved noise, 2002).
const PERM: [u8; 256] = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69,
    142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219,
    203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175,
    74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60, 211, 133, 230,
    220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216, 80, 73, 209, 76,
    132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173,
    186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206,
    59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163,
    70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232,
    178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162,
    241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184, 84, 204,
    176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141,
    128, 195, 78, 66, 215, 61, 156, 180,
];

/// Largest octave count of a turbulence.
pub const MAX_OCTAVES: u32 = 12;

/// Which arithmetic evaluates the noise.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoiseMode {
    Exact,
    /// Integers with this many fraction bits (4 to 24).
    Bits(u32),
}

/// Perlin's permutation for `seed` 0, else a Fisher-Yates shuffle of it driven by SplitMix64.
pub fn permutation(seed: u64) -> [u8; 256] {
    let mut p = PERM;
    if seed != 0 {
        let mut state = seed;
        let mut next = || {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        };
        for i in (1..256usize).rev() {
            let j = (next() % (i as u64 + 1)) as usize;
            p.swap(i, j);
        }
    }
    p
}

/// Perlin's 2002 `grad(hash, x, y, 0)` as `(gx, gy)`, each 0 or ±1 (only `hash & 15`
/// matters).
pub fn grad(hash: u8) -> (i64, i64) {
    let h = hash & 15;
    let u = if h & 1 == 0 { 1 } else { -1 };
    let v = if h & 2 == 0 { 1 } else { -1 };
    let (mut gx, mut gy) = (0, 0);
    if h < 8 {
        gx += u;
    } else {
        gy += u;
    }
    if h < 4 {
        gy += v;
    } else if h == 12 || h == 14 {
        gx += v;
    }
    (gx, gy)
}

/// Improved noise on one permutation, lattice wrapped at a period.
#[derive(Debug, Clone)]
pub struct Noise {
    perm: [u8; 256],
}

fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// round-half-up(p / 2^k).
fn shr_round(p: i128, k: u32) -> i128 {
    if k == 0 {
        p
    } else {
        (p + (1i128 << (k - 1))) >> k
    }
}

/// The fade of `t = raw / 2^f` in `[0, 1)` as a word with `f` fraction bits, exact then
/// rounded once.
pub fn fade_bits(t: i64, f: u32) -> i64 {
    let t = t as i128;
    let one = 1i128 << f;
    // t^3 (6 t^2 - 15 t + 10): 5f fraction bits
    let p = t * t * t * (6 * t * t - 15 * t * one + 10 * one * one);
    shr_round(p, 4 * f) as i64
}

impl Noise {
    pub fn new(seed: u64) -> Noise {
        Noise {
            perm: permutation(seed),
        }
    }

    /// The permutation.
    pub fn perm(&self) -> &[u8; 256] {
        &self.perm
    }

    /// Perlin's `p[p[p[X] + Y] + Z]` at `Z = 0`.
    fn hash(&self, i: i64, j: i64) -> u8 {
        let a = self.perm[(i & 255) as usize] as usize + (j & 255) as usize;
        let b = self.perm[a & 255] as usize;
        self.perm[b & 255]
    }

    /// The four corner gradients of cell `(xi, yi)` wrapped at `period`.
    fn corners(&self, xi: i64, yi: i64, period: i64) -> [(i64, i64); 4] {
        let (xi, yi) = (xi.rem_euclid(period), yi.rem_euclid(period));
        let (x1, y1) = ((xi + 1) % period, (yi + 1) % period);
        [
            grad(self.hash(xi, yi)),
            grad(self.hash(x1, yi)),
            grad(self.hash(xi, y1)),
            grad(self.hash(x1, y1)),
        ]
    }

    /// Noise at `(x, y)` in lattice units, exact.
    pub fn exact(&self, x: f64, y: f64, period: u64) -> f64 {
        let (xf, yf) = (x.floor(), y.floor());
        let (fx, fy) = (x - xf, y - yf);
        let g = self.corners(xf as i64, yf as i64, period as i64);
        let d = |k: usize, dx: f64, dy: f64| g[k].0 as f64 * dx + g[k].1 as f64 * dy;
        let (n00, n10) = (d(0, fx, fy), d(1, fx - 1.0, fy));
        let (n01, n11) = (d(2, fx, fy - 1.0), d(3, fx - 1.0, fy - 1.0));
        let (a, b) = (fade(fx), fade(fy));
        let r0 = n00 + a * (n10 - n00);
        let r1 = n01 + a * (n11 - n01);
        r0 + b * (r1 - r0)
    }

    /// Noise at `(x, y) = (xr, yr) / 2^f` lattice units, bit-accurate: a word with `f`
    /// fraction bits.
    pub fn bits(&self, xr: i64, yr: i64, f: u32, period: u64) -> i64 {
        let one = 1i64 << f;
        let (xi, yi) = (xr >> f, yr >> f);
        let (fx, fy) = (xr & (one - 1), yr & (one - 1));
        let g = self.corners(xi, yi, period as i64);
        let d = |k: usize, dx: i64, dy: i64| g[k].0 * dx + g[k].1 * dy;
        let (n00, n10) = (d(0, fx, fy), d(1, fx - one, fy));
        let (n01, n11) = (d(2, fx, fy - one), d(3, fx - one, fy - one));
        let (a, b) = (fade_bits(fx, f) as i128, fade_bits(fy, f) as i128);
        let lerp = |t: i128, p: i64, q: i64| -> i64 {
            ((p as i128) + shr_round(t * (q as i128 - p as i128), f)) as i64
        };
        let r0 = lerp(a, n00, n10);
        let r1 = lerp(a, n01, n11);
        lerp(b, r0, r1)
    }
}

/// The fractal sum of `octaves` octaves of improved noise from `frequency` lattice cells per
/// unit of texture coordinate, each octave doubling the frequency and halving the amplitude,
/// wrapped so that it tiles with period 1; two of them (permutations `seed` and `seed + 1`)
/// give `(r1, r2)` ("the noise function has to be evaluated twice (with different
/// settings) to get two different random numbers", §5.1).
#[derive(Debug, Clone)]
pub struct Turbulence {
    pub frequency: u32,
    noise: [Noise; 2],
}

impl Turbulence {
    pub fn new(frequency: u32, seed: u64) -> Turbulence {
        Turbulence {
            frequency,
            noise: [Noise::new(seed), Noise::new(seed.wrapping_add(1))],
        }
    }

    /// The noise of random number `which` (0: r1, 1: r2).
    pub fn noise(&self, which: usize) -> &Noise {
        &self.noise[which]
    }

    /// Octave `k` of random number `which` (0: r1, 1: r2) at `(u, v)`, exact.
    pub fn octave(&self, which: usize, k: u32, u: f64, v: f64) -> f64 {
        let period = u64::from(self.frequency) << k;
        let p = period as f64;
        let (u, v) = (u.rem_euclid(1.0), v.rem_euclid(1.0));
        self.noise[which].exact(u * p, v * p, period)
    }

    /// `Σ_k w_k 2^-k n_k(u, v)` with `w_k = clamp(octaves - k, 0, 1)`: whole octaves, and the
    /// next one blended in by the fractional part (§5.1: "whenever a new octave is added, it
    /// should be blended in smoothly to avoid popping"). Exact.
    pub fn exact(&self, which: usize, u: f64, v: f64, octaves: f64) -> f64 {
        let mut s = 0.0;
        let mut amp = 1.0;
        let mut k = 0;
        while (k as f64) < octaves && k < MAX_OCTAVES {
            let w = (octaves - k as f64).min(1.0);
            s += w * amp * self.octave(which, k, u, v);
            amp *= 0.5;
            k += 1;
        }
        s
    }

    /// The sum of `octaves` whole octaves at `(u, v) = (ur, vr) / 2^uv_frac`, bit-accurate:
    /// octave `k`'s lattice position is `u 2^k f` taken to `f` fraction bits (truncated), its
    /// noise word scaled by `2^-k` exactly; the sum is rounded once to `f` bits.
    pub fn bits(&self, which: usize, ur: i64, vr: i64, uv_frac: u32, octaves: u32, f: u32) -> i64 {
        let mut acc: i128 = 0;
        let one_uv = 1i64 << uv_frac;
        let (ur, vr) = (ur.rem_euclid(one_uv), vr.rem_euclid(one_uv));
        for k in 0..octaves.min(MAX_OCTAVES) {
            let period = u64::from(self.frequency) << k;
            let lat = |r: i64| -> i64 {
                // r / 2^uv_frac * period, to f fraction bits (truncated)
                let p = r as i128 * period as i128;
                if f >= uv_frac {
                    (p << (f - uv_frac)) as i64
                } else {
                    (p >> (uv_frac - f)) as i64
                }
            };
            let n = self.noise[which].bits(lat(ur), lat(vr), f, period);
            acc += (n as i128) << (MAX_OCTAVES - k);
        }
        shr_round(acc, MAX_OCTAVES) as i64
    }

    /// [`Turbulence::bits`] with a fractional octave count `octaves_q / 2^8`: octave `k`
    /// weighted by `clamp(octaves_q - 256 k, 0, 256) / 256` (the next octave blended in,
    /// §5.1), the weighted sum exact and rounded once to `f` bits.
    pub fn bits_blend(
        &self,
        which: usize,
        ur: i64,
        vr: i64,
        uv_frac: u32,
        octaves_q: i64,
        f: u32,
    ) -> i64 {
        let mut acc: i128 = 0;
        let one_uv = 1i64 << uv_frac;
        let (ur, vr) = (ur.rem_euclid(one_uv), vr.rem_euclid(one_uv));
        for k in 0..MAX_OCTAVES {
            let w = (octaves_q - 256 * i64::from(k)).clamp(0, 256) as i128;
            if w == 0 {
                break;
            }
            let period = u64::from(self.frequency) << k;
            let lat = |r: i64| -> i64 {
                let p = r as i128 * period as i128;
                if f >= uv_frac {
                    (p << (f - uv_frac)) as i64
                } else {
                    (p >> (uv_frac - f)) as i64
                }
            };
            let n = self.noise[which].bits(lat(ur), lat(vr), f, period);
            acc += (n as i128 * w) << (MAX_OCTAVES - k);
        }
        shr_round(acc, MAX_OCTAVES + 8) as i64
    }

    /// Both random numbers `(r1, r2)` at `(u, v)` over `octaves` whole octaves, in one mode
    /// (bit-accurate mode truncates `(u, v)` to 24 fraction bits first). Noise units.
    pub fn eval(&self, mode: NoiseMode, u: f64, v: f64, octaves: u32) -> [f64; 2] {
        match mode {
            NoiseMode::Exact => [0, 1].map(|w| self.exact(w, u, v, f64::from(octaves))),
            NoiseMode::Bits(f) => {
                const UV: u32 = 24;
                let q = |x: f64| (x.rem_euclid(1.0) * f64::from(1u32 << UV)).floor() as i64;
                let (ur, vr) = (q(u), q(v));
                [0, 1].map(|w| self.bits(w, ur, vr, UV, octaves, f) as f64 / f64::from(1u32 << f))
            }
        }
    }
}

/// The largest |value| a sum of `octaves` octaves can reach: one octave of 2-D improved noise
/// on the plane stays within [-1, 1] (corner dot products are at most 1 in the cell's
/// interior), so `Σ 2^-k < 2`.
pub fn bound(octaves: u32) -> f64 {
    2.0 - 2f64.powi(1 - octaves as i32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn reference_permutation_and_lattice_zero() {
        let n = Noise::new(0);
        assert_eq!(permutation(0), PERM);
        for i in 0..8 {
            for j in 0..8 {
                assert_eq!(n.exact(i as f64, j as f64, 256), 0.0);
                assert_eq!(n.bits(i << 8, j << 8, 8, 256), 0);
            }
        }
    }

    #[test]
    fn fade_bits_exhaustive_within_half_lsb() {
        for f in [4u32, 6, 8, 10] {
            for t in 0..(1i64 << f) {
                let x = t as f64 / f64::from(1u32 << f);
                let e = fade(x) * f64::from(1u32 << f);
                assert!(
                    (fade_bits(t, f) as f64 - e).abs() <= 0.5 + 1e-9,
                    "f {f} t {t}"
                );
            }
        }
    }

    /// Bit-accurate noise against exact over every lattice position of a 4 x 4-cell block at
    /// 6 fraction bits: each lerp rounds once and the fade is off by half an LSB, so the
    /// error is at most 2 LSB.
    #[test]
    fn noise_bits_exhaustive_small_width() {
        let n = Noise::new(7);
        let f = 6;
        let s = f64::from(1u32 << f);
        for x in 0..(4 << f) {
            for y in 0..(4 << f) {
                let e = n.exact(x as f64 / s, y as f64 / s, 16);
                let b = n.bits(x, y, f, 16) as f64 / s;
                assert!((e - b).abs() <= 2.0 / s, "({x}, {y}): {e} vs {b}");
            }
        }
    }

    #[test]
    fn turbulence_tiles_and_stays_bounded() {
        let t = Turbulence::new(4, 3);
        for k in 0..50 {
            let (u, v) = (k as f64 * 0.0731, k as f64 * 0.1137);
            let a = t.exact(0, u, v, 5.0);
            assert!((a - t.exact(0, u + 1.0, v - 1.0, 5.0)).abs() < 1e-12);
            assert!(a.abs() <= bound(5));
        }
    }

    proptest! {
        /// Wide words: 16 fraction bits, octaves 1..6: the bit-accurate sum is within
        /// 2 LSB per octave weight of the exact one (plus the position's truncation to 24 bits,
        /// whose effect is below 2^-24 * 2^k f cells times the slope bound 4).
        #[test]
        fn turbulence_bits_close_to_exact(u in 0.0f64..1.0, v in 0.0f64..1.0, oct in 1u32..6) {
            let t = Turbulence::new(4, 11);
            let f = 16;
            let e = t.eval(NoiseMode::Exact, u, v, oct);
            let b = t.eval(NoiseMode::Bits(f), u, v, oct);
            let lsb = 1.0 / f64::from(1u32 << f);
            let pos = 4.0 * f64::from(4u32 << oct) / f64::from(1u32 << 24) * 2.0;
            for w in 0..2 {
                prop_assert!((e[w] - b[w]).abs() <= 4.0 * lsb + pos, "{} vs {}", e[w], b[w]);
            }
        }
    }
}
