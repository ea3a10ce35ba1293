//! The tables of Kautz et al. §4, all computed numerically: the noise distribution `g` and
//! its CDF `G`; the NDF's marginal density `m(x) = ∫ f(x, y) dy`, its CDF `M`, the
//! conditional `c(y | x_n) = f(x_n, y) / m(x_n)` and its CDF `C`, and their inverses; and the
//! lookup table `L(r1, r2) = expand(M^-1(G(r1)), C^-1(G(r2) | x_n))` with a deterministic
//! tangent frame per normal.
//!
//! Every density is piecewise constant over equal bins of [0, 1], so every CDF is piecewise
//! linear and its inverse exact (within f64): [`Cdf`].

use glam::DVec3;

/// A piecewise-linear CDF over [0, 1] from the weights of `n` equal bins.
#[derive(Debug, Clone)]
pub struct Cdf {
    /// `cum[k]` = the CDF at `k / n`, `cum[0] = 0`, `cum[n] = 1`.
    cum: Vec<f64>,
}

impl Cdf {
    /// From non-negative bin weights; all zero gives the uniform CDF.
    pub fn new(weights: &[f64]) -> Cdf {
        let total: f64 = weights.iter().sum();
        let n = weights.len();
        let mut cum = Vec::with_capacity(n + 1);
        cum.push(0.0);
        let mut s = 0.0;
        for (k, &w) in weights.iter().enumerate() {
            s += if total > 0.0 {
                w / total
            } else {
                1.0 / n as f64
            };
            cum.push(if k + 1 == n { 1.0 } else { s.min(1.0) });
        }
        Cdf { cum }
    }

    pub fn bins(&self) -> usize {
        self.cum.len() - 1
    }

    /// The CDF at `t` (clamped to [0, 1]).
    pub fn eval(&self, t: f64) -> f64 {
        let n = self.bins();
        let x = t.clamp(0.0, 1.0) * n as f64;
        let k = (x.floor() as usize).min(n - 1);
        let f = x - k as f64;
        self.cum[k] + f * (self.cum[k + 1] - self.cum[k])
    }

    /// The inverse CDF at `u` (clamped to [0, 1]): the smallest `t` with `eval(t) = u`,
    /// linear within the bin (empty bins are skipped).
    pub fn inverse(&self, u: f64) -> f64 {
        let n = self.bins();
        let u = u.clamp(0.0, 1.0);
        // first k with cum[k + 1] >= u and a non-empty bin
        let mut k = self.cum.partition_point(|&c| c < u).saturating_sub(1);
        k = k.min(n - 1);
        while k + 1 < n && self.cum[k + 1] <= self.cum[k] {
            k += 1;
        }
        let w = self.cum[k + 1] - self.cum[k];
        let f = if w > 0.0 {
            ((u - self.cum[k]) / w).clamp(0.0, 1.0)
        } else {
            0.5
        };
        (k as f64 + f) / n as f64
    }
}

/// Bins of the measured noise distribution `g`.
pub const NOISE_BINS: usize = 1024;

/// `g` and `G`: the distribution of the noise indices in [0, 1], measured from samples (§4:
/// "The actual distribution g(x) of the Perlin turbulence is also computed numerically").
#[derive(Debug, Clone)]
pub struct NoiseCdf {
    /// The density `g` per bin (integrates to 1 over [0, 1]).
    pub density: Vec<f64>,
    pub cdf: Cdf,
}

impl NoiseCdf {
    /// From index samples in [0, 1].
    pub fn measure(samples: impl Iterator<Item = f64>) -> NoiseCdf {
        let mut h = vec![0.0; NOISE_BINS];
        let mut count = 0.0;
        for t in samples {
            let k = ((t.clamp(0.0, 1.0) * NOISE_BINS as f64) as usize).min(NOISE_BINS - 1);
            h[k] += 1.0;
            count += 1.0;
        }
        let density = h
            .iter()
            .map(|c| {
                if count > 0.0 {
                    c / count * NOISE_BINS as f64
                } else {
                    1.0
                }
            })
            .collect();
        NoiseCdf {
            density,
            cdf: Cdf::new(&h),
        }
    }

    /// `G(t)`: the fraction of noise indices below `t`.
    pub fn g(&self, t: f64) -> f64 {
        self.cdf.eval(t)
    }
}

/// The marginal and conditional CDFs of an `n x n` hemispherical map (row 0 at +y, column 0
/// at -x): `M` over the columns (x ascending), `C(· | column)` over the rows (y ascending).
#[derive(Debug, Clone)]
pub struct NdfTables {
    pub n: u32,
    pub marginal: Cdf,
    pub conditional: Vec<Cdf>,
}

impl NdfTables {
    /// From the map's densities; the map must hold some positive density.
    pub fn new(n: u32, map: &[f64]) -> NdfTables {
        let nu = n as usize;
        let column = |i: usize| -> Vec<f64> {
            // y ascending: row nu - 1 first
            (0..nu).map(|j| map[(nu - 1 - j) * nu + i]).collect()
        };
        let cols: Vec<Vec<f64>> = (0..nu).map(column).collect();
        let m: Vec<f64> = cols.iter().map(|c| c.iter().sum()).collect();
        NdfTables {
            n,
            marginal: Cdf::new(&m),
            conditional: cols.iter().map(|c| Cdf::new(c)).collect(),
        }
    }

    /// `(x_n, y_n) = (M^-1(u1), C^-1(u2 | x_n))` in [0, 1]² for uniform `(u1, u2)`.
    pub fn sample_xy(&self, u1: f64, u2: f64) -> (f64, f64) {
        let x = self.marginal.inverse(u1);
        let i = ((x * f64::from(self.n)) as usize).min(self.n as usize - 1);
        (x, self.conditional[i].inverse(u2))
    }

    /// The microfacet normal `(2 x_n - 1, 2 y_n - 1, sqrt(1 - (2 x_n - 1)² - (2 y_n - 1)²))`
    /// (§4); a point of an edge texel outside the disk is moved onto its rim (z = 0).
    pub fn sample(&self, u1: f64, u2: f64) -> DVec3 {
        let (x, y) = self.sample_xy(u1, u2);
        expand(x, y)
    }
}

/// §4's expansion of `(x_n, y_n)` to a unit normal.
pub fn expand(xn: f64, yn: f64) -> DVec3 {
    let (mut x, mut y) = (2.0 * xn - 1.0, 2.0 * yn - 1.0);
    let r2 = x * x + y * y;
    if r2 > 1.0 {
        let r = r2.sqrt();
        x /= r;
        y /= r;
    }
    DVec3::new(x, y, (1.0 - x * x - y * y).max(0.0).sqrt())
}

/// The deterministic tangent frame of a microfacet normal `n` (§4: "we are deterministically
/// generating a tangent frame for every normal"): the macro surface's tangent `x` made
/// orthogonal to `n` (Gram-Schmidt; `y` where `n` is along `x`), and `b = n × t`. The choice
/// keeps an anisotropic NDF's axes along the surface's `u` direction on every microfacet.
pub fn tangent_frame(n: DVec3) -> (DVec3, DVec3) {
    let mut t = DVec3::X - n * n.x;
    if t.length_squared() < 1e-12 {
        t = DVec3::Y - n * n.y;
    }
    let t = t.normalize();
    (t, n.cross(t))
}

/// `L(r1, r2)`: `size x size` entries at `r = (k + 1/2) / size`, row `j` for `r2`, column `i`
/// for `r1` (the DEPENDENT_GB lookup reads `s` from G = r1, `t` from B = r2).
#[derive(Debug, Clone)]
pub struct Lookup {
    pub size: u32,
    pub normals: Vec<DVec3>,
    pub tangents: Vec<DVec3>,
}

impl Lookup {
    pub fn new(size: u32, g: &NoiseCdf, t: &NdfTables) -> Lookup {
        let s = f64::from(size);
        let mut normals = Vec::with_capacity((size * size) as usize);
        let mut tangents = Vec::with_capacity((size * size) as usize);
        for j in 0..size {
            for i in 0..size {
                let r1 = (f64::from(i) + 0.5) / s;
                let r2 = (f64::from(j) + 0.5) / s;
                let n = t.sample(g.g(r1), g.g(r2));
                normals.push(n);
                tangents.push(tangent_frame(n).0);
            }
        }
        Lookup {
            size,
            normals,
            tangents,
        }
    }

    /// The nearest entry to indices `(r1, r2)` in [0, 1].
    pub fn nearest(&self, r1: f64, r2: f64) -> usize {
        let k = |r: f64| ((r * f64::from(self.size)) as i64).clamp(0, self.size as i64 - 1);
        (k(r2) * self.size as i64 + k(r1)) as usize
    }
}

/// Histogram of unit normals over an `n x n` hemispherical map (row 0 at +y): counts per
/// texel (normals with `z < 0` are dropped).
pub fn histogram(n: u32, normals: impl Iterator<Item = DVec3>) -> Vec<f64> {
    let mut h = vec![0.0; (n * n) as usize];
    let s = f64::from(n);
    for m in normals {
        if m.z < 0.0 {
            continue;
        }
        let i = (((m.x + 1.0) / 2.0 * s) as i64).clamp(0, n as i64 - 1);
        let j = (((1.0 - m.y) / 2.0 * s) as i64).clamp(0, n as i64 - 1);
        h[(j * n as i64 + i) as usize] += 1.0;
    }
    h
}

/// A fine `fine x fine` map summed into `bins x bins` bins (`fine` a multiple of `bins`): the
/// expected counts of a histogram, integrated over each bin rather than taken at its centre.
pub fn binned(map: &[f64], fine: u32, bins: u32) -> Vec<f64> {
    let k = (fine / bins) as usize;
    let (f, b) = (fine as usize, bins as usize);
    let mut out = vec![0.0; b * b];
    for j in 0..f {
        for i in 0..f {
            out[(j / k) * b + i / k] += map[j * f + i];
        }
    }
    out
}

/// Goodness of fit of `counts` to the density `expected` (same bins, any scale): Pearson's
/// chi-square over the bins whose expected count is at least 5 (the others pooled into one),
/// divided by its degrees of freedom (about 1 for a fit, far above for a misfit), and the
/// Kullback-Leibler divergence `Σ p log(p / q)` of the observed from the expected (nats).
pub fn fit(counts: &[f64], expected: &[f64]) -> (f64, f64) {
    let total: f64 = counts.iter().sum();
    let esum: f64 = expected.iter().sum();
    let (mut chi, mut dof, mut pool_o, mut pool_e, mut kl) = (0.0f64, 0.0f64, 0.0, 0.0, 0.0);
    for (&o, &e) in counts.iter().zip(expected) {
        let e = e / esum * total;
        if e >= 5.0 {
            chi += (o - e).powi(2) / e;
            dof += 1.0;
        } else {
            pool_o += o;
            pool_e += e;
        }
        if o > 0.0 {
            kl += o / total * ((o / total) / (e / total).max(1e-300)).ln();
        }
    }
    if pool_e >= 5.0 {
        chi += (pool_o - pool_e).powi(2) / pool_e;
        dof += 1.0;
    }
    (chi / (dof - 1.0).max(1.0), kl)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cdf_inverse_round_trips() {
        let c = Cdf::new(&[1.0, 0.0, 3.0, 4.0]);
        for k in 0..=100 {
            let u = k as f64 / 100.0;
            let t = c.inverse(u);
            assert!((c.eval(t) - u).abs() < 1e-12, "u {u}");
            assert!(
                !(0.25..0.5).contains(&t) || u == 0.125,
                "t {t} in the empty bin"
            );
        }
        assert_eq!(Cdf::new(&[0.0, 0.0]).inverse(0.25), 0.25);
    }

    #[test]
    fn tangent_frames_are_orthonormal() {
        for n in [DVec3::Z, DVec3::X, DVec3::new(0.3, -0.4, 0.866).normalize()] {
            let (t, b) = tangent_frame(n);
            assert!(t.dot(n).abs() < 1e-12 && b.dot(n).abs() < 1e-12 && t.dot(b).abs() < 1e-12);
            assert!((t.length() - 1.0).abs() < 1e-12 && (b.length() - 1.0).abs() < 1e-12);
        }
    }
}
