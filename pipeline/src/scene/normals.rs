//! Tangent-space normal maps and the ways of deriving them from a sampled height field.
//!
//! # Conventions
//!
//! * A normal map is `width x height` texels stored row-major; texel `(i, j)` has its centre at
//!   `u = (i + 0.5) / width`, `v = (j + 0.5) / height`. Row `j = 0` covers `v` in
//!   `[0, 1/height)`. When a map is read from or written to a PNG, PNG row 0 (the top row) is
//!   `j = 0`, so `v` increases *down* the image (as for `Scene::color_texture`).
//! * Texels are unit tangent-space normals `(x, y, z)`: `x` along `∂P/∂u`, `y` along `∂P/∂v`,
//!   `z` along the surface normal. A height field `F` gives `normalize(-F_u, -F_v, 1)`
//!   (Ernst 1998 Eq. 1 with k = 1).
//! * Maps wrap (period 1 in `u` and `v`) at the borders, for every method.

use std::path::Path;

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use super::SceneError;

/// How a normal map is derived from heights.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub enum NormalMethod {
    /// The exact gradient of the height field at each texel centre
    /// (`BumpMap::bake_normals`). From sampled heights alone
    /// (`NormalMap::from_heights`) no exact gradient exists, so there it falls back to
    /// `CentralDifference`.
    #[default]
    Analytic,
    /// `F_u ≈ (h[i+1] - h[i-1]) / (2 du)`, `F_v ≈ (h[j+1] - h[j-1]) / (2 dv)`, with
    /// `du = 1/width`, `dv = 1/height`.
    CentralDifference,
    /// John Schlag's embossing (Graphics Gems IV, "Fast Embossing Effects on Raster Image
    /// Data", as summarised by Lingard 1995): heights are quantised to 8-bit intensities
    /// over the map's own range, convolved with 3x3 masks, and
    /// `N = normalize(-i_u, -i_v, 6 * 255 / w)`.
    Schlag {
        /// Schlag's bevel width `w` (> 0, finite), in texels. A height ramp that rises by
        /// `a` intensity levels per texel gives the slope `a * w / 255` relative to `z`: a
        /// larger `w` makes the embossing steeper.
        w: f64,
    },
    /// Least-squares plane fit (Tarini et al. §4.1) through the texel and its `q` neighbours,
    /// in texture units.
    PlaneFit {
        /// Neighbourhood size: 4 (left, right, above, below) or 8 (the 3x3 ring).
        q: u32,
    },
}

impl NormalMethod {
    /// Check the parameters: Schlag's `w` finite and > 0, PlaneFit's `q` 4 or 8.
    pub fn validate(&self, field: &str) -> Result<(), SceneError> {
        match *self {
            NormalMethod::Schlag { w } if !(w.is_finite() && w > 0.0) => Err(SceneError::invalid(
                format!("{field}.Schlag.w"),
                format!("expected a finite bevel width > 0, found {w}"),
            )),
            NormalMethod::PlaneFit { q } if q != 4 && q != 8 => Err(SceneError::invalid(
                format!("{field}.PlaneFit.q"),
                format!("expected 4 or 8 neighbours, found {q}"),
            )),
            _ => Ok(()),
        }
    }
}

/// A tangent-space normal map (see the module docs for the layout).
#[derive(Debug, Clone, PartialEq)]
pub struct NormalMap {
    pub width: u32,
    pub height: u32,
    /// Unit tangent-space normals, row-major, `width * height` of them.
    pub texels: Vec<DVec3>,
}

/// The unperturbed tangent-space normal.
const FLAT: DVec3 = DVec3::Z;

fn normalize_or_flat(n: DVec3) -> DVec3 {
    let len = n.length();
    if len.is_finite() && len > 0.0 {
        n / len
    } else {
        FLAT
    }
}

fn wrap(i: i64, n: u32) -> usize {
    i.rem_euclid(i64::from(n)) as usize
}

impl NormalMap {
    /// A `w x h` map of unperturbed normals `(0, 0, 1)`.
    pub fn flat(w: u32, h: u32) -> NormalMap {
        NormalMap {
            width: w,
            height: h,
            texels: vec![FLAT; w as usize * h as usize],
        }
    }

    /// Derive a normal map from `w x h` heights (row-major, texel centres, texture-space
    /// units), wrapping periodically at the borders; texel spacing `du = 1/w`, `dv = 1/h`.
    ///
    /// * `Analytic` and `CentralDifference`: central differences.
    /// * `Schlag { w }`: intensities `i = round(255 (F - Fmin) / (Fmax - Fmin))` (a constant map
    ///   gives all `(0, 0, 1)`), then
    ///   `i_u = Σ_{dj=-1..1} (i[i+1, j+dj] - i[i-1, j+dj])` (Lingard's mask `[-1 0 1]` in every
    ///   row) and `i_v = Σ_{di=-1..1} (i[i+di, j+1] - i[i+di, j-1])`. This is Lingard's `i_v`
    ///   mask (top row `+1`, bottom row `-1`) with its *top row applied to row `j + 1`* (the
    ///   larger `v`, i.e. `v` pointing up as in Schlag's `P(u, v) = [u v i(u,v)]`), so that a
    ///   ramp `F = a v` gives a normal tilting toward `-v`, consistent with `(-F_u, -F_v, 1)`.
    ///   The normal is `normalize(-i_u, -i_v, 6 * 255 / w)`.
    /// * `PlaneFit { q }`: least-squares plane `z = a0 x + a1 y + a2` through the centre texel
    ///   *and* its `q` neighbours (Tarini: "the points corresponding to t and to other q
    ///   texels"), at offsets in texture units; normal `normalize(-a0, -a1, 1)`. Because the
    ///   stencils are symmetric, `q = 4` equals central differences and `q = 8` equals the
    ///   Prewitt operator `(Σ right column - Σ left column) / (6 du)`; the centre only moves
    ///   `a2`.
    ///
    /// Parameters failing [`NormalMethod::validate`] give an all-flat map (callers validate
    /// configs first). Missing heights (`heights.len() < w * h`) count as 0.
    pub fn from_heights(heights: &[f64], w: u32, h: u32, method: NormalMethod) -> NormalMap {
        if w == 0 || h == 0 || method.validate("method").is_err() {
            return NormalMap::flat(w, h);
        }
        let hv = |i: i64, j: i64| -> f64 {
            heights
                .get(wrap(j, h) * w as usize + wrap(i, w))
                .copied()
                .unwrap_or(0.0)
        };
        let du = 1.0 / f64::from(w);
        let dv = 1.0 / f64::from(h);
        let mut texels = Vec::with_capacity(w as usize * h as usize);
        match method {
            NormalMethod::Analytic | NormalMethod::CentralDifference => {
                for j in 0..i64::from(h) {
                    for i in 0..i64::from(w) {
                        let fu = (hv(i + 1, j) - hv(i - 1, j)) / (2.0 * du);
                        let fv = (hv(i, j + 1) - hv(i, j - 1)) / (2.0 * dv);
                        texels.push(normalize_or_flat(DVec3::new(-fu, -fv, 1.0)));
                    }
                }
            }
            NormalMethod::Schlag { w: bevel } => {
                let n = w as usize * h as usize;
                let vals: Vec<f64> = (0..n)
                    .map(|k| heights.get(k).copied().unwrap_or(0.0))
                    .collect();
                let (lo, hi) = vals
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
                        (lo.min(x), hi.max(x))
                    });
                let range = hi - lo;
                if !(range.is_finite() && range > 0.0) {
                    return NormalMap::flat(w, h);
                }
                let q: Vec<f64> = vals
                    .iter()
                    .map(|&x| (255.0 * (x - lo) / range).round())
                    .collect();
                let iv = |i: i64, j: i64| q[wrap(j, h) * w as usize + wrap(i, w)];
                let nz = 6.0 * 255.0 / bevel;
                for j in 0..i64::from(h) {
                    for i in 0..i64::from(w) {
                        let mut gu = 0.0;
                        let mut gv = 0.0;
                        for d in -1..=1 {
                            gu += iv(i + 1, j + d) - iv(i - 1, j + d);
                            gv += iv(i + d, j + 1) - iv(i + d, j - 1);
                        }
                        texels.push(normalize_or_flat(DVec3::new(-gu, -gv, nz)));
                    }
                }
            }
            NormalMethod::PlaneFit { q } => {
                let offsets: &[(i64, i64)] = if q == 8 {
                    &[
                        (0, 0),
                        (-1, -1),
                        (0, -1),
                        (1, -1),
                        (-1, 0),
                        (1, 0),
                        (-1, 1),
                        (0, 1),
                        (1, 1),
                    ]
                } else {
                    &[(0, 0), (-1, 0), (1, 0), (0, -1), (0, 1)]
                };
                for j in 0..i64::from(h) {
                    for i in 0..i64::from(w) {
                        let pts = offsets
                            .iter()
                            .map(|&(di, dj)| (di as f64 * du, dj as f64 * dv, hv(i + di, j + dj)));
                        let a = plane_fit(pts);
                        texels.push(normalize_or_flat(DVec3::new(-a.x, -a.y, 1.0)));
                    }
                }
            }
        }
        NormalMap {
            width: w,
            height: h,
            texels,
        }
    }

    /// Texel `(i, j)`, wrapped into the map. An empty map gives `(0, 0, 1)`.
    pub fn texel(&self, i: i64, j: i64) -> DVec3 {
        if self.width == 0 || self.height == 0 {
            return FLAT;
        }
        self.texels
            .get(wrap(j, self.height) * self.width as usize + wrap(i, self.width))
            .copied()
            .unwrap_or(FLAT)
    }

    /// Bilinear sample at `(u, v)` with wrap (texel centres at `((i + 0.5)/w, (j + 0.5)/h)`),
    /// renormalised. Non-finite coordinates give `(0, 0, 1)`.
    pub fn sample_bilinear(&self, u: f64, v: f64) -> DVec3 {
        if self.width == 0 || self.height == 0 || !u.is_finite() || !v.is_finite() {
            return FLAT;
        }
        let x = u.rem_euclid(1.0) * f64::from(self.width) - 0.5;
        let y = v.rem_euclid(1.0) * f64::from(self.height) - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (i, j) = (x0 as i64, y0 as i64);
        let top = self.texel(i, j).lerp(self.texel(i + 1, j), fx);
        let bottom = self.texel(i, j + 1).lerp(self.texel(i + 1, j + 1), fx);
        normalize_or_flat(top.lerp(bottom, fy))
    }

    /// Read a tangent-space normal map from a PNG: RGB (8 or 16 bit; grey and alpha are
    /// converted) mapped `c / max * 2 - 1` per channel and renormalised. Red is `x` (along
    /// `∂P/∂u`), green is `y` (along `∂P/∂v`, i.e. *down* the image, the DirectX "Y-"
    /// convention; OpenGL "green up" maps need their green channel inverted), blue is `z`.
    pub fn from_png(path: &Path) -> Result<NormalMap, SceneError> {
        let img = read_png(path)?;
        let (w, h) = (img.width(), img.height());
        let mut texels = Vec::with_capacity(w as usize * h as usize);
        let expand = |c: f64, max: f64| c / max * 2.0 - 1.0;
        if is_16bit(&img) {
            let rgb = img.to_rgb16();
            for p in rgb.pixels() {
                let n = DVec3::new(
                    expand(f64::from(p[0]), 65535.0),
                    expand(f64::from(p[1]), 65535.0),
                    expand(f64::from(p[2]), 65535.0),
                );
                texels.push(normalize_or_flat(n));
            }
        } else {
            let rgb = img.to_rgb8();
            for p in rgb.pixels() {
                let n = DVec3::new(
                    expand(f64::from(p[0]), 255.0),
                    expand(f64::from(p[1]), 255.0),
                    expand(f64::from(p[2]), 255.0),
                );
                texels.push(normalize_or_flat(n));
            }
        }
        Ok(NormalMap {
            width: w,
            height: h,
            texels,
        })
    }
}

/// Least-squares plane `z = a0 x + a1 y + a2` through the points: solves the 3x3 normal
/// equations `(XᵀX) a = Xᵀd` by Cramer's rule. Returns `(a0, a1)`; a singular system gives 0.
fn plane_fit(points: impl Iterator<Item = (f64, f64, f64)>) -> DVec2 {
    // Sums for the symmetric matrix [[Sxx Sxy Sx] [Sxy Syy Sy] [Sx Sy n]] and the right side.
    let (mut sxx, mut sxy, mut sx, mut syy, mut sy, mut n) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let (mut sxz, mut syz, mut sz) = (0.0, 0.0, 0.0);
    for (x, y, z) in points {
        sxx += x * x;
        sxy += x * y;
        sx += x;
        syy += y * y;
        sy += y;
        n += 1.0;
        sxz += x * z;
        syz += y * z;
        sz += z;
    }
    let m = glam::DMat3::from_cols(
        DVec3::new(sxx, sxy, sx),
        DVec3::new(sxy, syy, sy),
        DVec3::new(sx, sy, n),
    );
    let det = m.determinant();
    if !(det.is_finite() && det.abs() > 0.0) {
        return DVec2::ZERO;
    }
    let rhs = DVec3::new(sxz, syz, sz);
    let a0 = glam::DMat3::from_cols(rhs, m.y_axis, m.z_axis).determinant() / det;
    let a1 = glam::DMat3::from_cols(m.x_axis, rhs, m.z_axis).determinant() / det;
    DVec2::new(a0, a1)
}

/// Whether a decoded image has 16-bit channels.
pub(crate) fn is_16bit(img: &image::DynamicImage) -> bool {
    matches!(
        img,
        image::DynamicImage::ImageLuma16(_)
            | image::DynamicImage::ImageLumaA16(_)
            | image::DynamicImage::ImageRgb16(_)
            | image::DynamicImage::ImageRgba16(_)
    )
}

/// Read and decode a PNG file of at most [`super::files::MAX_PNG_SIDE`] pixels a side (checked
/// from the header before decoding); errors name the path.
pub(crate) fn read_png(path: &Path) -> Result<image::DynamicImage, SceneError> {
    super::files::read_png(path, super::files::MAX_PNG_SIDE)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Heights of `f` at texel centres of a `w x h` map.
    fn bake(w: u32, h: u32, f: impl Fn(f64, f64) -> f64) -> Vec<f64> {
        let mut out = Vec::new();
        for j in 0..h {
            for i in 0..w {
                out.push(f(
                    (f64::from(i) + 0.5) / f64::from(w),
                    (f64::from(j) + 0.5) / f64::from(h),
                ));
            }
        }
        out
    }

    fn assert_close(a: DVec3, b: DVec3, tol: f64, what: &str) {
        assert!(
            (a - b).abs().max_element() <= tol,
            "{what}: {a} vs {b} (tol {tol})"
        );
    }

    /// `name` in a fresh, empty directory (removed when dropped).
    fn temp_path(name: &str) -> crate::scratch::Scratch {
        crate::scratch::Scratch::file(name)
    }

    #[test]
    fn ramp_in_u_central_difference_and_plane_fit_exact() {
        let (w, h) = (32, 16);
        let a = 0.37;
        let heights = bake(w, h, |u, _| a * u);
        let want = DVec3::new(-a, 0.0, 1.0).normalize();
        for method in [
            NormalMethod::CentralDifference,
            NormalMethod::Analytic,
            NormalMethod::PlaneFit { q: 4 },
            NormalMethod::PlaneFit { q: 8 },
        ] {
            let m = NormalMap::from_heights(&heights, w, h, method);
            assert_eq!(m.texels.len(), 32 * 16);
            // Away from the wrap seam at i = 0 and i = w - 1 (a ramp is not periodic).
            for j in 0..16 {
                for i in 1..31 {
                    assert_close(m.texel(i, j), want, 1e-9, &format!("{method:?} ({i},{j})"));
                }
            }
            // At the seam the ramp drops by a * (w - 1) / w: the normal tilts the other way.
            assert!(m.texel(0, 3).x > 0.0, "{method:?} seam");
        }
    }

    #[test]
    fn ramp_in_v_tilts_toward_minus_v_for_every_method() {
        let (w, h) = (16, 256);
        let a = 2.0;
        let heights = bake(w, h, |_, v| a * v);
        let want = DVec3::new(0.0, -a, 1.0).normalize();
        for method in [
            NormalMethod::CentralDifference,
            NormalMethod::PlaneFit { q: 4 },
            NormalMethod::PlaneFit { q: 8 },
        ] {
            let m = NormalMap::from_heights(&heights, w, h, method);
            assert_close(m.texel(5, 100), want, 1e-9, &format!("{method:?}"));
        }
        // Schlag: 256 rows over the range give exactly 1 intensity level per texel; the
        // matching bevel width is w = (Fmax - Fmin) / dv = a * 255 / 256 * 256 = 255 a.
        let m = NormalMap::from_heights(&heights, w, h, NormalMethod::Schlag { w: 255.0 * a });
        assert_close(m.texel(5, 100), want, 1e-12, "Schlag v ramp");
        assert!(m.texel(5, 100).y < -0.8);
    }

    #[test]
    fn schlag_matches_ramp_within_quantisation() {
        // Exact case: 256 texels, one intensity level per texel.
        let a = 0.5;
        let heights = bake(256, 4, |u, _| a * u);
        let m = NormalMap::from_heights(&heights, 256, 4, NormalMethod::Schlag { w: 255.0 * a });
        let want = DVec3::new(-a, 0.0, 1.0).normalize();
        for i in 1..255 {
            assert_close(m.texel(i, 2), want, 1e-12, &format!("texel {i}"));
        }
        // Inexact case: 100 texels, 255/99 levels per texel, rounded. w = (Fmax - Fmin) / du.
        let w = 100;
        let heights = bake(w, 4, |u, _| a * u);
        let range = a * 99.0 / 100.0;
        let bevel = range * 100.0;
        let m = NormalMap::from_heights(&heights, w, 4, NormalMethod::Schlag { w: bevel });
        // Each intensity is rounded by at most half a level, so the 2-texel difference is off
        // by at most one level; the recovered slope -x/z = diff * per_level / 2 is then off by
        // at most per_level / 2 (≈ 0.19 a here), where per_level is the slope of a ramp rising
        // one level per texel.
        let per_level = range / 255.0 * f64::from(w);
        for i in 1..(w as i64 - 1) {
            let n = m.texel(i, 1);
            let slope = -n.x / n.z;
            assert!(
                (slope - a).abs() <= per_level / 2.0 + 1e-12,
                "texel {i}: slope {slope}, want {a} ± {}",
                per_level / 2.0
            );
        }
        // A constant map is all flat.
        let flat = NormalMap::from_heights(&[0.25; 64], 8, 8, NormalMethod::Schlag { w: 3.0 });
        assert!(flat.texels.iter().all(|&n| n == DVec3::Z));
    }

    #[test]
    fn sine_central_difference_has_known_error() {
        // F = A sin(2πu): central difference gives A cos(2πu) sin(2π du) / du instead of
        // 2πA cos(2πu).
        let (w, amp) = (64u32, 0.01);
        let heights = bake(w, 8, |u, _| amp * (std::f64::consts::TAU * u).sin());
        let m = NormalMap::from_heights(&heights, w, 8, NormalMethod::CentralDifference);
        let du = 1.0 / f64::from(w);
        for i in 0..i64::from(w) {
            let u = (i as f64 + 0.5) * du;
            let fu =
                amp * (std::f64::consts::TAU * u).cos() * (std::f64::consts::TAU * du).sin() / du;
            let want = DVec3::new(-fu, 0.0, 1.0).normalize();
            assert_close(
                m.texel(i, 0),
                want,
                1e-12,
                &format!("texel {i} (incl. seam)"),
            );
        }
        // And the discrete result differs from the exact derivative by the predicted factor.
        let exact = amp * std::f64::consts::TAU;
        let n0 = m.texel(0, 0);
        let ratio = (-n0.x / n0.z) / (exact * (std::f64::consts::TAU * 0.5 * du).cos());
        let predicted = (std::f64::consts::TAU * du).sin() / (std::f64::consts::TAU * du);
        assert!((ratio - predicted).abs() < 1e-12, "{ratio} vs {predicted}");
        assert!(predicted < 0.9985 && predicted > 0.998);
    }

    #[test]
    fn plane_fit_8_is_prewitt_and_matches_generic_least_squares() {
        let (w, h) = (8u32, 8u32);
        // Pseudo-random heights.
        let heights: Vec<f64> = (0..64).map(|k| ((k * 37 % 11) as f64) * 0.01).collect();
        let m = NormalMap::from_heights(&heights, w, h, NormalMethod::PlaneFit { q: 8 });
        let hv = |i: i64, j: i64| heights[wrap(j, h) * 8 + wrap(i, w)];
        let du = 1.0 / 8.0;
        for (i, j) in [(0i64, 0i64), (3, 4), (7, 7)] {
            let fu = ((hv(i + 1, j - 1) + hv(i + 1, j) + hv(i + 1, j + 1))
                - (hv(i - 1, j - 1) + hv(i - 1, j) + hv(i - 1, j + 1)))
                / (6.0 * du);
            let fv = ((hv(i - 1, j + 1) + hv(i, j + 1) + hv(i + 1, j + 1))
                - (hv(i - 1, j - 1) + hv(i, j - 1) + hv(i + 1, j - 1)))
                / (6.0 * du);
            let want = DVec3::new(-fu, -fv, 1.0).normalize();
            assert_close(m.texel(i, j), want, 1e-12, &format!("({i},{j})"));
        }
        // An asymmetric point set: the plane through 3 points is exact.
        let a = plane_fit([(0.0, 0.0, 1.0), (1.0, 0.0, 3.0), (0.0, 2.0, 0.0)].into_iter());
        assert!((a - DVec2::new(2.0, -0.5)).length() < 1e-12, "{a}");
    }

    #[test]
    fn texel_wraps_and_bilinear_interpolates() {
        let mut m = NormalMap::flat(2, 2);
        m.texels[1] = DVec3::X; // (1, 0)
        assert_eq!(m.texel(-1, 0), DVec3::X);
        assert_eq!(m.texel(3, 2), DVec3::X);
        assert_eq!(m.texel(0, 0), DVec3::Z);
        // At the texel centre exactly.
        assert_close(m.sample_bilinear(0.75, 0.25), DVec3::X, 1e-15, "centre");
        // Half way between texels (0,0) and (1,0) on row 0: normalize(0.5, 0, 0.5).
        let half = DVec3::new(1.0, 0.0, 1.0).normalize();
        assert_close(m.sample_bilinear(0.5, 0.25), half, 1e-15, "midpoint");
        // Wrap: u = 1.0 is the seam between texel 1 and texel 0 again.
        assert_close(m.sample_bilinear(1.0, 0.25), half, 1e-15, "seam");
        assert_close(
            m.sample_bilinear(-0.25, 1.25),
            DVec3::X,
            1e-15,
            "negative wrap",
        );
        assert_eq!(m.sample_bilinear(f64::NAN, 0.0), DVec3::Z);
    }

    #[test]
    fn invalid_methods_are_rejected_and_give_flat_maps() {
        assert!(NormalMethod::PlaneFit { q: 5 }.validate("bake").is_err());
        assert!(NormalMethod::Schlag { w: 0.0 }.validate("bake").is_err());
        assert!(NormalMethod::Schlag { w: f64::NAN }
            .validate("bake")
            .is_err());
        assert!(NormalMethod::PlaneFit { q: 8 }.validate("bake").is_ok());
        let err = NormalMethod::PlaneFit { q: 5 }
            .validate("bake.method")
            .unwrap_err();
        assert!(err.to_string().contains("bake.method.PlaneFit.q"), "{err}");
        let heights = bake(4, 4, |u, _| u);
        let m = NormalMap::from_heights(&heights, 4, 4, NormalMethod::PlaneFit { q: 3 });
        assert!(m.texels.iter().all(|&n| n == DVec3::Z));
        assert_eq!(
            NormalMap::from_heights(&[], 0, 0, NormalMethod::Analytic)
                .texels
                .len(),
            0
        );
    }

    #[test]
    fn normal_png_round_trip_and_errors() {
        let path = temp_path("normals.png");
        // Texel (0,0) flat, (1,0) tilted toward +x, row 1 toward +v (green high).
        let mut img = image::RgbImage::new(2, 2);
        img.put_pixel(0, 0, image::Rgb([128, 128, 255]));
        img.put_pixel(1, 0, image::Rgb([255, 128, 128]));
        img.put_pixel(0, 1, image::Rgb([128, 255, 128]));
        img.put_pixel(1, 1, image::Rgb([0, 0, 0]));
        img.save(&path).unwrap();
        let m = NormalMap::from_png(&path).unwrap();
        assert_eq!((m.width, m.height), (2, 2));
        let e = |c: f64| c / 255.0 * 2.0 - 1.0;
        assert_close(
            m.texel(0, 0),
            DVec3::new(e(128.0), e(128.0), 1.0).normalize(),
            1e-15,
            "flat",
        );
        assert_close(
            m.texel(1, 0),
            DVec3::new(1.0, e(128.0), e(128.0)).normalize(),
            1e-15,
            "+x",
        );
        assert_close(
            m.texel(0, 1),
            DVec3::new(e(128.0), 1.0, e(128.0)).normalize(),
            1e-15,
            "+v",
        );
        assert_close(
            m.texel(1, 1),
            DVec3::splat(-1.0).normalize(),
            1e-15,
            "black",
        );
        for n in &m.texels {
            assert!((n.length() - 1.0).abs() < 1e-12);
        }

        // 16-bit.
        let path16 = temp_path("normals16.png");
        let img16: image::ImageBuffer<image::Rgb<u16>, Vec<u16>> =
            image::ImageBuffer::from_pixel(1, 1, image::Rgb([65535, 32768, 32768]));
        img16.save(&path16).unwrap();
        let m16 = NormalMap::from_png(&path16).unwrap();
        let e16 = 32768.0 / 65535.0 * 2.0 - 1.0;
        assert_close(
            m16.texel(0, 0),
            DVec3::new(1.0, e16, e16).normalize(),
            1e-15,
            "16-bit",
        );

        // Corrupt and missing files name the path.
        let bad = temp_path("corrupt.png");
        std::fs::write(&bad, b"\x89PNG\r\n\x1a\nthis is not really a png").unwrap();
        match NormalMap::from_png(&bad) {
            Err(SceneError::File { path, message }) => {
                assert_eq!(path, bad.display().to_string());
                assert!(message.contains("could not decode PNG"), "{message}");
            }
            other => panic!("expected a file error, got {other:?}"),
        }
        let missing = temp_path("does-not-exist.png");
        match NormalMap::from_png(&missing) {
            Err(SceneError::File { path, .. }) => assert_eq!(path, missing.display().to_string()),
            other => panic!("expected a file error, got {other:?}"),
        }
    }
}
