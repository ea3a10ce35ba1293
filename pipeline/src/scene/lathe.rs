//! Surfaces of revolution about the y axis ([`super::MeshSpec::Lathe`]): vases, amphorae,
//! bottles (the "vase" of Tarini et al. 1999, Figs. 5 and 10).
//!
//! # Construction
//!
//! * The profile is a radius function `r(y)` through the control points `(radius, y)` (`y`
//!   strictly increasing): a C¹ monotone piecewise cubic (PCHIP, Fritsch & Carlson 1980 with
//!   the Fritsch–Butland harmonic-mean slopes and the shape-preserving three-point end
//!   slopes, as in MATLAB's `pchip` and SciPy's `PchipInterpolator`). It passes through every
//!   point, never overshoots (a radius between two points stays between their radii, so it
//!   never becomes negative) and is flat at local extrema of the radius. Two points give a
//!   straight line (a cone or a cylinder).
//! * `v` follows the arc length of the profile curve `(r(y), y)`: ring `j` of `stacks` lies at
//!   arc length `j / stacks` of the total (5-point Gauss–Legendre on 32 sub-intervals per
//!   segment, inverted by safeguarded Newton), so texels are not stretched along steep
//!   parts. `u` runs around the axis as on the cylinder: `P = (r cos θ, y, -r sin θ)`,
//!   `θ = 2π u / uv_repeat[0]`, so `Pu × Pv` points out of the surface.
//! * `Pu`, `Pv` and the normal are analytic: with `r' = dr/dy` and `L` the arc length,
//!   `Pu = 2π r (-sin θ, 0, -cos θ) / rep_u`, `Pv = L (r' cos θ, 1, -r' sin θ) / (√(1 + r'²)
//!   rep_v)` and `N = (cos θ, -r', -sin θ) / √(1 + r'²)`.
//! * A first or last point with radius 0 is a pole: as on the sphere it gets one vertex per
//!   slice (at the slice's centre `u`, carrying `Pu` of the adjacent ring) and one triangle per
//!   slice. The tip is a cone point unless the profile meets the axis at a right angle.
//! * No caps: an open profile leaves the ends open.

use std::f64::consts::TAU;

use glam::{DVec2, DVec3};

use super::mesh::{Mesh, Vertex};
use super::{check_count, SceneError};

/// Largest segment count (`slices`, `stacks`), as for the other parametric meshes.
pub const MAX_SEGMENTS: u32 = 2048;
/// Largest number of profile points.
pub const MAX_PROFILE_POINTS: usize = 4096;

/// Sub-intervals per profile segment of the arc-length table.
const ARC_SUBDIVISIONS: usize = 32;

/// The profile `r(y)`: a monotone piecewise cubic Hermite interpolant (PCHIP).
#[derive(Debug, Clone)]
pub struct Profile {
    y: Vec<f64>,
    r: Vec<f64>,
    /// Slopes `dr/dy` at the points.
    m: Vec<f64>,
}

fn invalid(field: impl Into<String>, message: impl Into<String>) -> SceneError {
    SceneError::invalid(field, message)
}

impl Profile {
    /// Check the points (errors name `mesh.Lathe.profile` or `mesh.Lathe.profile[i]`) and
    /// build the interpolant.
    pub fn new(points: &[[f64; 2]]) -> Result<Self, SceneError> {
        const FIELD: &str = "mesh.Lathe.profile";
        let n = points.len();
        if n < 2 {
            return Err(invalid(
                FIELD,
                format!("expected at least 2 points (radius, y), found {n}"),
            ));
        }
        if n > MAX_PROFILE_POINTS {
            return Err(invalid(
                FIELD,
                format!("expected at most {MAX_PROFILE_POINTS} points, found {n}"),
            ));
        }
        for (i, &[r, y]) in points.iter().enumerate() {
            let field = format!("{FIELD}[{i}]");
            if !(r.is_finite() && r >= 0.0) {
                return Err(invalid(
                    field,
                    format!("expected a finite radius >= 0, found {r}"),
                ));
            }
            if r == 0.0 && i != 0 && i != n - 1 {
                return Err(invalid(
                    field,
                    "expected a radius > 0, found 0: only the first and last points may lie on \
                     the axis",
                ));
            }
            if !y.is_finite() {
                return Err(invalid(field, format!("expected a finite y, found {y}")));
            }
            if i > 0 {
                let prev = points[i - 1][1];
                if y <= prev {
                    return Err(invalid(
                        field,
                        format!(
                            "expected y > {prev} (the y of profile[{}]): y must increase \
                             strictly along the profile, found {y}",
                            i - 1
                        ),
                    ));
                }
                if !(y - prev).is_finite() {
                    return Err(invalid(
                        field,
                        format!("expected a finite step in y from {prev}, found {y}"),
                    ));
                }
            }
        }
        if points.iter().all(|p| p[0] == 0.0) {
            return Err(invalid(
                FIELD,
                "expected a radius > 0 somewhere, found every point on the axis",
            ));
        }
        let y: Vec<f64> = points.iter().map(|p| p[1]).collect();
        let r: Vec<f64> = points.iter().map(|p| p[0]).collect();
        let m = pchip_slopes(&y, &r);
        if let Some(i) = m.iter().position(|s| !s.is_finite()) {
            return Err(invalid(
                format!("{FIELD}[{i}]"),
                "expected points whose slope dr/dy is finite (the points are too close in y \
                 for their radii)",
            ));
        }
        Ok(Profile { y, r, m })
    }

    /// The first and last y.
    pub fn range(&self) -> (f64, f64) {
        (self.y[0], self.y[self.y.len() - 1])
    }

    /// The segment containing `y` (clamped to the ends).
    fn segment(&self, y: f64) -> usize {
        let last = self.y.len() - 2;
        // Number of interior knots <= y.
        self.y[1..=last].partition_point(|&k| k <= y).min(last)
    }

    /// `(r, dr/dy)` at `y` (extrapolating the end cubics outside the range).
    pub fn eval(&self, y: f64) -> (f64, f64) {
        let k = self.segment(y);
        let (y0, y1) = (self.y[k], self.y[k + 1]);
        let h = y1 - y0;
        let t = (y - y0) / h;
        let (t2, t3) = (t * t, t * t * t);
        let dr = self.r[k + 1] - self.r[k];
        let (m0, m1) = (self.m[k] * h, self.m[k + 1] * h);
        // r = r0 + Δr h01 + h m0 h10 + h m1 h11, written so that a constant radius is exact.
        let h01 = 3.0 * t2 - 2.0 * t3;
        let h10 = t3 - 2.0 * t2 + t;
        let h11 = t3 - t2;
        let r = self.r[k] + dr * h01 + m0 * h10 + m1 * h11;
        let d01 = 6.0 * t - 6.0 * t2;
        let d10 = 3.0 * t2 - 4.0 * t + 1.0;
        let d11 = 3.0 * t2 - 2.0 * t;
        let slope = (dr * d01 + m0 * d10 + m1 * d11) / h;
        (r, slope)
    }

    /// `ds/dy`, the speed of the profile curve `(r(y), y)`.
    fn speed(&self, y: f64) -> f64 {
        self.eval(y).1.hypot(1.0)
    }

    /// Arc length from `a` to `b` (5-point Gauss–Legendre; `a`, `b` within one segment).
    fn arc(&self, a: f64, b: f64) -> f64 {
        const X: [f64; 5] = [
            0.0,
            -0.538_469_310_105_683_1,
            0.538_469_310_105_683_1,
            -0.906_179_845_938_664,
            0.906_179_845_938_664,
        ];
        const W: [f64; 5] = [
            0.568_888_888_888_888_9,
            0.478_628_670_499_366_5,
            0.478_628_670_499_366_5,
            0.236_926_885_056_189_1,
            0.236_926_885_056_189_1,
        ];
        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
        half * X
            .iter()
            .zip(W)
            .map(|(x, w)| w * self.speed(mid + half * x))
            .sum::<f64>()
    }
}

/// PCHIP slopes: harmonic means of the adjacent secants in the interior (0 at local extrema),
/// the shape-preserving three-point formula at the ends.
fn pchip_slopes(y: &[f64], r: &[f64]) -> Vec<f64> {
    let n = y.len();
    let h: Vec<f64> = y.windows(2).map(|w| w[1] - w[0]).collect();
    let d: Vec<f64> = (0..n - 1).map(|k| (r[k + 1] - r[k]) / h[k]).collect();
    if n == 2 {
        return vec![d[0], d[0]];
    }
    let mut m = vec![0.0; n];
    for k in 1..n - 1 {
        if d[k - 1] * d[k] > 0.0 {
            let w1 = 2.0 * h[k] + h[k - 1];
            let w2 = h[k] + 2.0 * h[k - 1];
            m[k] = (w1 + w2) / (w1 / d[k - 1] + w2 / d[k]);
        }
    }
    let end = |h0: f64, h1: f64, d0: f64, d1: f64| {
        let s = ((2.0 * h0 + h1) * d0 - h0 * d1) / (h0 + h1);
        if s * d0 <= 0.0 {
            0.0
        } else if d0 * d1 <= 0.0 && s.abs() > 3.0 * d0.abs() {
            3.0 * d0
        } else {
            s
        }
    };
    m[0] = end(h[0], h[1], d[0], d[1]);
    m[n - 1] = end(h[n - 2], h[n - 3], d[n - 2], d[n - 3]);
    m
}

/// The arc-length table of a profile: knots `(y, s)` with `s` the arc length from the start.
struct ArcTable {
    knots: Vec<(f64, f64)>,
}

impl ArcTable {
    fn new(p: &Profile) -> Self {
        let mut knots = vec![(p.y[0], 0.0)];
        let mut s = 0.0;
        for k in 0..p.y.len() - 1 {
            let (y0, y1) = (p.y[k], p.y[k + 1]);
            for i in 0..ARC_SUBDIVISIONS {
                let a = y0 + (y1 - y0) * i as f64 / ARC_SUBDIVISIONS as f64;
                let b = if i + 1 == ARC_SUBDIVISIONS {
                    y1
                } else {
                    y0 + (y1 - y0) * (i + 1) as f64 / ARC_SUBDIVISIONS as f64
                };
                s += p.arc(a, b);
                knots.push((b, s));
            }
        }
        ArcTable { knots }
    }

    fn length(&self) -> f64 {
        self.knots[self.knots.len() - 1].1
    }

    /// The y at arc length `target` (in [0, length]).
    fn y_at(&self, p: &Profile, target: f64) -> f64 {
        let last = self.knots.len() - 1;
        if target <= 0.0 {
            return self.knots[0].0;
        }
        if target >= self.knots[last].1 {
            return self.knots[last].0;
        }
        // The sub-interval [knots[i], knots[i + 1]] containing the target.
        let i = self.knots.partition_point(|k| k.1 <= target).clamp(1, last) - 1;
        let ((ya, sa), (yb, _)) = (self.knots[i], self.knots[i + 1]);
        let (mut lo, mut hi) = (ya, yb);
        let mut y = ya + (yb - ya) * 0.5;
        for _ in 0..100 {
            let f = sa + p.arc(ya, y) - target;
            if f.abs() <= 1e-15 * self.length().max(f64::MIN_POSITIVE) {
                break;
            }
            if f > 0.0 {
                hi = y;
            } else {
                lo = y;
            }
            let next = y - f / p.speed(y);
            y = if next > lo && next < hi && next.is_finite() {
                next
            } else {
                0.5 * (lo + hi)
            };
            if hi - lo <= f64::EPSILON * y.abs().max(f64::MIN_POSITIVE) {
                break;
            }
        }
        y
    }
}

/// Check the parameters (errors name `mesh.Lathe.<field>`) and build the mesh. The caller
/// checks `uv_repeat` and validates the result.
pub fn lathe(
    profile: &[[f64; 2]],
    slices: u32,
    stacks: u32,
    rep: DVec2,
) -> Result<Mesh, SceneError> {
    let p = Profile::new(profile)?;
    check_count("mesh.Lathe.slices".into(), slices, 3, MAX_SEGMENTS)?;
    let first_pole = profile[0][0] == 0.0;
    let last_pole = profile[profile.len() - 1][0] == 0.0;
    let min_stacks = if first_pole && last_pole { 2 } else { 1 };
    check_count("mesh.Lathe.stacks".into(), stacks, min_stacks, MAX_SEGMENTS)?;
    let table = ArcTable::new(&p);
    let length = table.length();
    if !(length.is_finite() && length > 0.0) {
        return Err(invalid(
            "mesh.Lathe.profile",
            format!("expected a profile of finite, positive arc length, found {length}"),
        ));
    }
    let (y_first, y_last) = p.range();
    let ring_y: Vec<f64> = (0..=stacks)
        .map(|j| match j {
            0 => y_first,
            j if j == stacks => y_last,
            j => table.y_at(&p, length * f64::from(j) / f64::from(stacks)),
        })
        .collect();
    // Position, normal, Pu, Pv at parameter s in [0, 1] around the axis, height y.
    let frame = |s: f64, y: f64| {
        let (r, dr) = p.eval(y);
        let (st, ct) = (TAU * s).sin_cos();
        let speed = dr.hypot(1.0);
        (
            DVec3::new(r * ct, y, -r * st),
            DVec3::new(ct, -dr, -st) / speed,
            DVec3::new(-st, 0.0, -ct) * (r * TAU / rep.x),
            DVec3::new(dr * ct, 1.0, -dr * st) * (length / (speed * rep.y)),
        )
    };
    let pole = |j: u32| (j == 0 && first_pole) || (j == stacks && last_pole);
    let mut mesh = Mesh::default();
    let mut row_start = Vec::with_capacity(stacks as usize + 1);
    for j in 0..=stacks {
        row_start.push(mesh.vertices.len() as u32);
        let t = f64::from(j) / f64::from(stacks);
        let y = ring_y[j as usize];
        if pole(j) {
            // The adjacent ring carries the limit direction of Pu.
            let y_adj = ring_y[if j == 0 { 1 } else { j as usize - 1 }];
            for i in 0..slices {
                let s = (f64::from(i) + 0.5) / f64::from(slices);
                let (_, normal, _, pv) = frame(s, y);
                let (_, _, pu, _) = frame(s, y_adj);
                mesh.vertices.push(Vertex {
                    pos: DVec3::new(0.0, y, 0.0),
                    normal: normal.normalize_or_zero(),
                    uv: DVec2::new(s, t) * rep,
                    pu,
                    pv,
                });
            }
        } else {
            for i in 0..=slices {
                let s = f64::from(i) / f64::from(slices);
                let (pos, normal, pu, pv) = frame(s, y);
                mesh.vertices.push(Vertex {
                    pos,
                    normal: normal.normalize_or_zero(),
                    uv: DVec2::new(s, t) * rep,
                    pu,
                    pv,
                });
            }
        }
    }
    for j in 0..stacks {
        let (lo, hi) = (row_start[j as usize], row_start[j as usize + 1]);
        for i in 0..slices {
            match (pole(j), pole(j + 1)) {
                (false, false) => {
                    let (a, b) = (lo + i, lo + i + 1);
                    let (c, d) = (hi + i + 1, hi + i);
                    mesh.triangles.push([a, b, c]);
                    mesh.triangles.push([a, c, d]);
                }
                // Bottom pole: the quad's bottom edge collapses.
                (true, false) => mesh.triangles.push([lo + i, hi + i + 1, hi + i]),
                // Top pole: the quad's top edge collapses.
                (false, true) => mesh.triangles.push([lo + i, lo + i + 1, hi + i]),
                // Not reached: stacks >= 2 when both ends are poles.
                (true, true) => {}
            }
        }
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::scene::MeshSpec;

    fn spec(profile: Vec<[f64; 2]>, slices: u32, stacks: u32) -> MeshSpec {
        MeshSpec::Lathe {
            profile,
            slices,
            stacks,
            uv_repeat: [2.0, 3.0],
        }
    }

    /// A Greek vase (amphora-like): foot, body, shoulder, neck, lip.
    fn vase_profile() -> Vec<[f64; 2]> {
        vec![
            [0.55, 0.0],
            [0.45, 0.15],
            [0.6, 0.45],
            [1.0, 1.1],
            [1.05, 1.4],
            [0.85, 1.9],
            [0.42, 2.3],
            [0.38, 2.65],
            [0.55, 2.9],
            [0.6, 3.0],
        ]
    }

    #[test]
    fn lathe_constant_radius_is_the_cylinder() {
        let (radius, height) = (0.7, 2.5);
        for (slices, stacks) in [(16, 3), (37, 11)] {
            let lathe = spec(
                vec![[radius, -height / 2.0], [radius, height / 2.0]],
                slices,
                stacks,
            )
            .build(Path::new("."))
            .unwrap();
            // Several points on the line: still the cylinder.
            let many = spec(
                vec![
                    [radius, -height / 2.0],
                    [radius, -0.3],
                    [radius, 0.1],
                    [radius, height / 2.0],
                ],
                slices,
                stacks,
            )
            .build(Path::new("."))
            .unwrap();
            let cyl = MeshSpec::Cylinder {
                radius,
                height,
                slices,
                stacks,
                uv_repeat: [2.0, 3.0],
            }
            .build(Path::new("."))
            .unwrap();
            for m in [&lathe, &many] {
                assert_eq!(m.triangles, cyl.triangles);
                assert_eq!(m.vertices.len(), cyl.vertices.len());
                for (a, b) in m.vertices.iter().zip(&cyl.vertices) {
                    assert!((a.pos - b.pos).length() < 1e-9, "{a:?} vs {b:?}");
                    assert!((a.normal - b.normal).length() < 1e-9, "{a:?} vs {b:?}");
                    assert!((a.pu - b.pu).length() < 1e-9, "{a:?} vs {b:?}");
                    assert!((a.pv - b.pv).length() < 1e-9, "{a:?} vs {b:?}");
                    assert!((a.uv - b.uv).length() < 1e-12, "{a:?} vs {b:?}");
                }
            }
        }
    }

    #[test]
    fn lathe_frames_are_orthonormal_and_outward() {
        let mut poles = vase_profile();
        poles[0][0] = 0.0;
        let last = poles.len() - 1;
        poles[last][0] = 0.0;
        for profile in [vase_profile(), poles] {
            let m = spec(profile.clone(), 24, 40).build(Path::new(".")).unwrap();
            m.validate("mesh.Lathe").unwrap();
            for (k, v) in m.vertices.iter().enumerate() {
                assert!((v.normal.length() - 1.0).abs() < 1e-12, "{k}: {v:?}");
                let (pu, pv) = (v.pu.normalize(), v.pv.normalize());
                assert!(v.normal.dot(pu).abs() < 1e-12, "{k}: {v:?}");
                assert!(v.normal.dot(pv).abs() < 1e-12, "{k}: {v:?}");
                // Pu × Pv points along the normal (outward).
                assert!(pu.cross(pv).dot(v.normal) > 1.0 - 1e-12, "{k}: {v:?}");
                // Outward: away from the axis unless the profile is steep.
                let radial = DVec3::new(v.normal.x, 0.0, v.normal.z);
                assert!(radial.dot(DVec3::new(v.pos.x, 0.0, v.pos.z)) >= 0.0);
            }
            for tri in &m.triangles {
                let [a, b, c] = tri.map(|k| m.vertices[k as usize]);
                let face = (b.pos - a.pos).cross(c.pos - a.pos);
                assert!(face.dot(a.normal + b.normal + c.normal) > 0.0);
            }
            // The profile points are interpolated: the rings at the ends hit them exactly.
            let (lo, hi) = m.bounds();
            assert_eq!((lo.y, hi.y), (0.0, 3.0));
        }
    }

    #[test]
    fn lathe_derivatives_match_finite_differences() {
        let profile = vase_profile();
        let p = Profile::new(&profile).unwrap();
        let table = ArcTable::new(&p);
        let rep = DVec2::new(2.0, 3.0);
        let pos = |u: f64, v: f64| {
            let y = table.y_at(&p, table.length() * v / rep.y);
            let (r, _) = p.eval(y);
            let (st, ct) = (TAU * u / rep.x).sin_cos();
            DVec3::new(r * ct, y, -r * st)
        };
        let m = spec(profile.clone(), 12, 30).build(Path::new(".")).unwrap();
        let h = 1e-5;
        for k in (13..m.vertices.len() - 13).step_by(11) {
            let v = m.vertices[k];
            let du = (pos(v.uv.x + h, v.uv.y) - pos(v.uv.x - h, v.uv.y)) / (2.0 * h);
            let dv = (pos(v.uv.x, v.uv.y + h) - pos(v.uv.x, v.uv.y - h)) / (2.0 * h);
            assert!((du - v.pu).length() < 1e-6 * v.pu.length().max(1.0), "{k}");
            assert!((dv - v.pv).length() < 1e-6 * v.pv.length().max(1.0), "{k}");
            assert!((pos(v.uv.x, v.uv.y) - v.pos).length() < 1e-9, "{k}");
        }
        // Equal arc length between rings: |Pv| = L / rep_v everywhere.
        for v in &m.vertices {
            assert!((v.pv.length() - table.length() / rep.y).abs() < 1e-9);
        }
        // The interpolant passes through the points and stays within the radii.
        for w in profile.windows(2) {
            assert!((p.eval(w[0][1]).0 - w[0][0]).abs() < 1e-12);
            for i in 0..=20 {
                let y = w[0][1] + (w[1][1] - w[0][1]) * f64::from(i) / 20.0;
                let r = p.eval(y).0;
                let (lo, hi) = (w[0][0].min(w[1][0]), w[0][0].max(w[1][0]));
                assert!(r >= lo - 1e-12 && r <= hi + 1e-12, "{y}: {r}");
            }
        }
    }

    #[test]
    fn lathe_poles_and_counts() {
        // A closed egg: both ends on the axis.
        let egg = vec![[0.0, -1.0], [0.6, -0.7], [0.8, 0.0], [0.5, 0.8], [0.0, 1.0]];
        let m = spec(egg, 10, 6).build(Path::new(".")).unwrap();
        // Rings 1..=5 of 11 vertices, 10 per pole; 10 triangles per pole band, 20 per band.
        assert_eq!(m.vertices.len(), 5 * 11 + 2 * 10);
        assert_eq!(m.triangles.len(), 2 * 10 + 4 * 20);
        let bottom: Vec<_> = m.vertices.iter().filter(|v| v.pos.y == -1.0).collect();
        assert_eq!(bottom.len(), 10);
        assert!(bottom.iter().all(|v| v.pos == DVec3::new(0.0, -1.0, 0.0)));
        assert!(bottom
            .iter()
            .all(|v| v.normal.y < 0.0 && v.pu.length() > 0.0));
        // One pole, one stack: a cone.
        let cone = spec(vec![[0.0, 0.0], [1.0, 1.0]], 8, 1)
            .build(Path::new("."))
            .unwrap();
        assert_eq!((cone.vertices.len(), cone.triangles.len()), (8 + 9, 8));
        let s = 0.5f64.sqrt();
        assert!(cone.vertices.iter().all(|v| (v.normal.y + s).abs() < 1e-12));
    }

    #[test]
    fn lathe_bad_profiles_name_the_field() {
        let nan = f64::NAN;
        let cases: Vec<(Vec<[f64; 2]>, u32, &str, &str)> = vec![
            (
                vec![[1.0, 0.0]],
                4,
                "mesh.Lathe.profile",
                "at least 2 points",
            ),
            (vec![], 4, "mesh.Lathe.profile", "at least 2 points"),
            (
                vec![[1.0, 0.0], [1.0, 1.0], [1.0, 1.0]],
                4,
                "mesh.Lathe.profile[2]",
                "increase strictly",
            ),
            (
                vec![[1.0, 0.0], [1.0, 2.0], [1.0, 1.0], [1.0, 3.0]],
                4,
                "mesh.Lathe.profile[2]",
                "expected y > 2",
            ),
            (
                vec![[1.0, 0.0], [-0.5, 1.0], [1.0, 2.0]],
                4,
                "mesh.Lathe.profile[1]",
                "radius >= 0",
            ),
            (
                vec![[1.0, 0.0], [1.0, 1.0], [1.0, 2.0], [nan, 3.0]],
                4,
                "mesh.Lathe.profile[3]",
                "radius >= 0, found NaN",
            ),
            (
                vec![[1.0, nan], [1.0, 1.0]],
                4,
                "mesh.Lathe.profile[0]",
                "finite y",
            ),
            (
                vec![[1.0, 0.0], [f64::INFINITY, 1.0]],
                4,
                "mesh.Lathe.profile[1]",
                "finite radius",
            ),
            (
                vec![[1.0, 0.0], [0.0, 1.0], [1.0, 2.0]],
                4,
                "mesh.Lathe.profile[1]",
                "only the first and last",
            ),
            (
                vec![[0.0, 0.0], [0.0, 1.0]],
                4,
                "mesh.Lathe.profile",
                "radius > 0 somewhere",
            ),
            (
                vec![[1.0, -1e308], [1.0, 1e308]],
                4,
                "mesh.Lathe.profile[1]",
                "finite step",
            ),
            (
                vec![[1e300, 0.0], [0.0, 1e-300]],
                4,
                "mesh.Lathe.profile[0]",
                "slope",
            ),
            (
                vec![[0.0, 0.0], [1.0, 1.0], [0.0, 2.0]],
                1,
                "mesh.Lathe.stacks",
                "2..=2048",
            ),
            (
                vec![[1.0, 0.0], [1.0, 1.0]],
                0,
                "mesh.Lathe.stacks",
                "1..=2048",
            ),
        ];
        for (profile, stacks, field, needle) in cases {
            match spec(profile.clone(), 8, stacks).build(Path::new(".")) {
                Err(SceneError::Invalid { field: f, message }) => {
                    assert_eq!(f, field, "{profile:?}: {message}");
                    assert!(message.contains(needle), "{profile:?}: {message}");
                }
                other => panic!("{profile:?}: expected an error on {field}, got {other:?}"),
            }
        }
        let bad_slices = spec(vec![[1.0, 0.0], [1.0, 1.0]], 2, 1);
        assert!(matches!(
            bad_slices.build(Path::new(".")),
            Err(SceneError::Invalid { field, .. }) if field == "mesh.Lathe.slices"
        ));
        let bad_repeat = MeshSpec::Lathe {
            profile: vec![[1.0, 0.0], [1.0, 1.0]],
            slices: 8,
            stacks: 1,
            uv_repeat: [1.0, 0.0],
        };
        assert!(matches!(
            bad_repeat.build(Path::new(".")),
            Err(SceneError::Invalid { field, .. }) if field == "mesh.Lathe.uv_repeat[1]"
        ));
    }

    #[test]
    fn lathe_never_panics_on_extreme_profiles() {
        // Huge or tiny values: an error or a valid mesh, never a panic.
        let cases = [
            vec![[1e300, 0.0], [1e300, 1.0]],
            vec![[1e-300, 0.0], [1e-300, 1e-300]],
            vec![[1.0, 0.0], [1e200, 1e-100], [1.0, 1.0]],
            vec![[1.0, -1e300], [2.0, 1e300]],
            vec![[0.0, 0.0], [1e-320, 1.0], [0.0, 2.0]],
        ];
        for profile in cases {
            let _ = spec(profile, 5, 3).build(Path::new("."));
        }
    }

    #[test]
    fn lathe_serde_shape() {
        let ron = "Lathe(profile: [(0.5, 0.0), (1.0, 1.0), (0.4, 2.0)], slices: 32, stacks: 24, \
                   uv_repeat: (4.0, 2.0))";
        let spec: MeshSpec = ron::from_str(ron).unwrap();
        assert_eq!(
            spec,
            MeshSpec::Lathe {
                profile: vec![[0.5, 0.0], [1.0, 1.0], [0.4, 2.0]],
                slices: 32,
                stacks: 24,
                uv_repeat: [4.0, 2.0],
            }
        );
        // Existing OBJ entries still parse: `atlas` defaults to false.
        let obj: MeshSpec = ron::from_str(r#"Obj(path: "b.obj", uv_repeat: (1.0, 1.0))"#).unwrap();
        assert!(matches!(obj, MeshSpec::Obj { atlas: false, .. }));
        let obj: MeshSpec =
            ron::from_str(r#"Obj(path: "b.obj", uv_repeat: (1.0, 1.0), atlas: true)"#).unwrap();
        assert!(matches!(obj, MeshSpec::Obj { atlas: true, .. }));
    }
}
