//! Normal density functions (Kautz et al. §3.1: "the distribution of the orientation of
//! microfacets, given as a probability density function p(n_m), also called the normal
//! density function (NDF)") and their "2D hemispherical map (directly using the x- and
//! y-component of the normals, see right side of Figure 2)" (§4).
//!
//! Densities are over the map's coordinates `(x, y) = (m_x, m_y)` of a unit microfacet normal
//! `m` with `m_z > 0`. For an NDF `D` normalised as `∫ D(m) m_z dω = 1` (the projected-area
//! convention of microfacet models) and `dω = dx dy / m_z`, the density of the normals of a
//! bump map's texels (equal areas of the macro surface) over the disk is `D(m)` itself, so
//! the map stores `D` at texel centres and 0 outside the unit disk. Only shapes matter: every
//! table is normalised numerically.

use glam::DVec3;
use serde::{Deserialize, Serialize};
use std::path::Path;

use crate::scene::SceneError;

/// Largest side of an NDF map (and of an NDF PNG).
pub const MAX_MAP_SIDE: u32 = 1024;
/// Smallest side of an NDF map.
pub const MIN_MAP_SIDE: u32 = 8;

/// An NDF as written in a config.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum NdfSpec {
    /// Blinn's `cos^n` distribution (Blinn 1977; §3.1 "as it is done for example by the
    /// Blinn-Phong model"): `D ∝ m_z^exponent`, exponent in (0, 10000].
    BlinnPhong { exponent: f64 },
    /// Beckmann's Gaussian slope distribution (Cook-Torrance): `D ∝ exp(-tan²θ / m²) /
    /// cos⁴θ`, roughness `m` in [0.02, 2].
    Beckmann { roughness: f64 },
    /// Ward's anisotropic Gaussian (Ward 1992): `D ∝ exp(-tan²θ (cos²φ / αx² + sin²φ / αy²))
    /// / cos⁴θ` (the slope form of his elliptical Gaussian), φ measured from the microfacet
    /// tangent; each α in [0.02, 2]. Isotropic when αx = αy.
    Ward { alpha_x: f64, alpha_y: f64 },
    /// A density over the hemispherical map from a grey PNG (8 or 16 bits; RGB is read as its
    /// mean): square, a power of two from 8 to 1024 texels a side, texel `(i, j)` at `x = 2
    /// (i + 1/2) / n - 1`, `y = 1 - 2 (j + 1/2) / n` (PNG row 0 at the top, +y); texels
    /// outside the unit disk are ignored; the texels inside must not all be 0. `isotropic`:
    /// the hardware path's 1-D texture uses the average over each ring of the map.
    Png {
        path: String,
        #[serde(default)]
        isotropic: bool,
    },
}

/// A built NDF.
#[derive(Debug, Clone)]
pub struct Ndf {
    pub spec: NdfSpec,
    /// The PNG's densities (row-major, row 0 at +y), side.
    image: Option<(u32, Vec<f64>)>,
    /// Largest value of the unnormalised density (for [`Ndf::relative`]).
    peak: f64,
}

fn bad(field: &str, msg: String) -> SceneError {
    SceneError::invalid(field.to_string(), msg)
}

fn in_range(field: &str, x: f64, lo: f64, hi: f64) -> Result<(), SceneError> {
    if x.is_finite() && x >= lo && x <= hi {
        Ok(())
    } else {
        Err(bad(
            field,
            format!("{x}: expected a number from {lo} to {hi}"),
        ))
    }
}

impl NdfSpec {
    /// Check the parameters, load a PNG (relative to `base_dir`), and find the peak. `field`
    /// names this spec in errors (`scene.bump.Ndf.ndf`).
    pub fn build(&self, field: &str, base_dir: &Path) -> Result<Ndf, SceneError> {
        let mut image = None;
        match self {
            NdfSpec::BlinnPhong { exponent } => {
                if !(exponent.is_finite() && *exponent > 0.0 && *exponent <= 10000.0) {
                    return Err(bad(
                        &format!("{field}.BlinnPhong.exponent"),
                        format!("{exponent}: expected a number in (0, 10000]"),
                    ));
                }
            }
            NdfSpec::Beckmann { roughness } => in_range(
                &format!("{field}.Beckmann.roughness"),
                *roughness,
                0.02,
                2.0,
            )?,
            NdfSpec::Ward { alpha_x, alpha_y } => {
                in_range(&format!("{field}.Ward.alpha_x"), *alpha_x, 0.02, 2.0)?;
                in_range(&format!("{field}.Ward.alpha_y"), *alpha_y, 0.02, 2.0)?;
            }
            NdfSpec::Png { path, .. } => {
                image = Some(load_png(
                    &format!("{field}.Png.path"),
                    &base_dir.join(path),
                )?);
            }
        }
        let mut ndf = Ndf {
            spec: self.clone(),
            image,
            peak: 1.0,
        };
        ndf.peak = ndf.find_peak();
        Ok(ndf)
    }
}

/// A PNG's densities: square, power of two, some density inside the disk.
fn load_png(field: &str, path: &Path) -> Result<(u32, Vec<f64>), SceneError> {
    let img = crate::scene::files::read_png(path, MAX_MAP_SIDE)?;
    let (w, h) = (img.width(), img.height());
    if w != h || !w.is_power_of_two() || !(MIN_MAP_SIDE..=MAX_MAP_SIDE).contains(&w) {
        return Err(bad(
            field,
            format!(
                "{}: the NDF image is {w} x {h}: expected a square power of two from {MIN_MAP_SIDE} to {MAX_MAP_SIDE} texels a side",
                path.display()
            ),
        ));
    }
    let rgb = img.to_rgb32f();
    let values: Vec<f64> = rgb
        .pixels()
        .map(|p| f64::from(p.0[0] + p.0[1] + p.0[2]) / 3.0)
        .collect();
    let inside: f64 = (0..w * w)
        .filter(|&k| {
            let (x, y) = map_xy(w, k % w, k / w);
            x * x + y * y < 1.0
        })
        .map(|k| values[k as usize])
        .sum();
    if inside <= 0.0 {
        return Err(bad(
            field,
            format!(
                "{}: every texel inside the unit disk is 0: not a density (expected some positive texels)",
                path.display()
            ),
        ));
    }
    Ok((w, values))
}

/// Centre `(x, y)` of texel `(i, j)` of an `n x n` map, row 0 at +y.
pub fn map_xy(n: u32, i: u32, j: u32) -> (f64, f64) {
    let s = f64::from(n);
    (
        2.0 * (f64::from(i) + 0.5) / s - 1.0,
        1.0 - 2.0 * (f64::from(j) + 0.5) / s,
    )
}

impl Ndf {
    /// The side of a PNG NDF's map.
    pub fn image_side(&self) -> Option<u32> {
        self.image.as_ref().map(|(n, _)| *n)
    }

    /// Whether the density depends on the polar angle only (the hardware path's 1-D texture).
    pub fn is_isotropic(&self) -> bool {
        match &self.spec {
            NdfSpec::BlinnPhong { .. } | NdfSpec::Beckmann { .. } => true,
            NdfSpec::Ward { alpha_x, alpha_y } => alpha_x == alpha_y,
            NdfSpec::Png { isotropic, .. } => *isotropic,
        }
    }

    /// The unnormalised density at the unit normal `m` given in the microfacet's frame
    /// (x along its tangent); 0 where `m_z <= 0`.
    pub fn density(&self, m: DVec3) -> f64 {
        let z = m.z;
        if z <= 0.0 {
            return 0.0;
        }
        let z2 = z * z;
        match &self.spec {
            NdfSpec::BlinnPhong { exponent } => z.powf(*exponent),
            NdfSpec::Beckmann { roughness } => {
                let a2 = roughness * roughness;
                (-(m.x * m.x + m.y * m.y) / (z2 * a2)).exp() / (z2 * z2)
            }
            NdfSpec::Ward { alpha_x, alpha_y } => {
                let e = (m.x * m.x) / (alpha_x * alpha_x) + (m.y * m.y) / (alpha_y * alpha_y);
                (-e / z2).exp() / (z2 * z2)
            }
            NdfSpec::Png { .. } => self.image_density(m.x, m.y),
        }
    }

    /// Bilinear density of the PNG at `(x, y)` (texel centres; 0 outside the disk).
    fn image_density(&self, x: f64, y: f64) -> f64 {
        let Some((n, v)) = &self.image else {
            return 0.0;
        };
        if x * x + y * y >= 1.0 {
            return 0.0;
        }
        let s = f64::from(*n);
        let fi = (x + 1.0) / 2.0 * s - 0.5;
        let fj = (1.0 - y) / 2.0 * s - 0.5;
        let (i0, j0) = (fi.floor(), fj.floor());
        let (a, b) = (fi - i0, fj - j0);
        let at = |i: f64, j: f64| {
            let i = (i as i64).clamp(0, *n as i64 - 1) as usize;
            let j = (j as i64).clamp(0, *n as i64 - 1) as usize;
            v[j * *n as usize + i]
        };
        let top = at(i0, j0) * (1.0 - a) + at(i0 + 1.0, j0) * a;
        let bot = at(i0, j0 + 1.0) * (1.0 - a) + at(i0 + 1.0, j0 + 1.0) * a;
        top * (1.0 - b) + bot * b
    }

    /// `D(m) / max D` in [0, 1]: the value the shading uses (§5.2.2: "The result from this
    /// lookup is p(n_m · h), which is then directly used to texture the surface").
    pub fn relative(&self, m: DVec3) -> f64 {
        (self.density(m) / self.peak).clamp(0.0, 1.0)
    }

    /// The isotropic profile `D(θ) / max D` at `cos θ = c` (c <= 0: 0): the analytic density
    /// at `(sin θ, 0, cos θ)`, or a PNG's mean over the ring (64 azimuths).
    pub fn relative_iso(&self, c: f64) -> f64 {
        if c <= 0.0 {
            return 0.0;
        }
        let s = (1.0 - c * c).max(0.0).sqrt();
        match &self.spec {
            NdfSpec::Png { .. } => {
                let k = 64;
                let sum: f64 = (0..k)
                    .map(|a| {
                        let phi = std::f64::consts::TAU * (a as f64 + 0.5) / k as f64;
                        self.density(DVec3::new(s * phi.cos(), s * phi.sin(), c))
                    })
                    .sum();
                (sum / k as f64 / self.peak).clamp(0.0, 1.0)
            }
            _ => self.relative(DVec3::new(s, 0.0, c)),
        }
    }

    /// The largest density over a 512 x 512 grid of the disk and the pole.
    fn find_peak(&self) -> f64 {
        let n = 512;
        let mut p = self.density(DVec3::Z);
        for j in 0..n {
            for i in 0..n {
                let (x, y) = map_xy(n, i, j);
                let r2 = x * x + y * y;
                if r2 < 1.0 {
                    p = p.max(self.density(DVec3::new(x, y, (1.0 - r2).sqrt())));
                }
            }
        }
        if p > 0.0 {
            p
        } else {
            1.0
        }
    }

    /// The hemispherical map at `n x n` texel centres, row 0 at +y: the density of the
    /// normals over the disk (0 outside it).
    pub fn map(&self, n: u32, dist: Distribution) -> Vec<f64> {
        let mut out = Vec::with_capacity((n * n) as usize);
        for j in 0..n {
            for i in 0..n {
                let (x, y) = map_xy(n, i, j);
                let r2 = x * x + y * y;
                out.push(if r2 >= 1.0 {
                    0.0
                } else {
                    let z = (1.0 - r2).sqrt();
                    match dist {
                        Distribution::Ndf => self.density(DVec3::new(x, y, z)),
                        // uniform in solid angle: dω = dx dy / z
                        Distribution::Uniform => 1.0 / z.max(1.0 / f64::from(n)),
                    }
                });
            }
        }
        out
    }
}

/// How the synthesised normals are distributed: by the NDF (the method), or uniformly over
/// the hemisphere (Fig. 4 right: "what happens if the normals are distributed uniformly and
/// not according to the NDF").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Distribution {
    #[default]
    Ndf,
    Uniform,
}
